//! The `vibrissa` binary: parses the command line and runs a command; every failure is one
//! line on stderr and a non-zero exit code ([`vibrissa_cli::CliError::exit_code`]).
//!
//! Output that cannot be delivered (standard output closed by its reader, or full) ends
//! the command with exit 4 ([`vibrissa_cli::printer::EXIT_OUTPUT`]): the commands write
//! through a [`vibrissa_cli::printer::Printer`], and a panic of `println!` anywhere else is
//! turned into the same one line by the panic hook below (no backtrace).

use std::io::Write;

use clap::error::ErrorKind;
use clap::Parser;

use vibrissa_cli::cli::Cli;
use vibrissa_cli::commands;
use vibrissa_cli::printer::EXIT_OUTPUT;
use vibrissa_cli::CliError;

/// The message of a panic's payload (`panic!` with a literal or a formatted message).
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".to_string())
}

/// The operating system's error in std's "failed printing to stdout: MESSAGE (os error N)".
fn os_error_of(message: &str) -> std::io::Error {
    let code = message
        .rsplit_once("(os error ")
        .and_then(|(_, rest)| rest.trim_end_matches(')').parse::<i32>().ok());
    match code {
        Some(c) => std::io::Error::from_raw_os_error(c),
        None => std::io::Error::other(message.to_string()),
    }
}

/// A panic ends the process with one line on stderr, no backtrace (`RUST_BACKTRACE` set
/// shows std's message and backtrace as well): a failed `println!` (standard output
/// closed or full) as [`CliError::Stdout`] with exit 4, a failed `eprintln!` silently with
/// exit 4, anything else as an internal error (a bug) with Rust's exit code 101.
fn install_panic_hook() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = panic_message(info.payload());
        if let Some(rest) = message.strip_prefix("failed printing to stdout: ") {
            let e = CliError::Stdout {
                source: os_error_of(rest),
                published: None,
            };
            let _ = writeln!(std::io::stderr(), "error: {e}");
            std::process::exit(EXIT_OUTPUT);
        }
        if message.starts_with("failed printing to stderr") {
            std::process::exit(EXIT_OUTPUT);
        }
        if std::env::var_os("RUST_BACKTRACE").is_some_and(|v| v != "0") {
            default(info);
            return;
        }
        let place = info
            .location()
            .map(|l| format!(" ({}:{})", l.file(), l.line()))
            .unwrap_or_default();
        let line = message.lines().next().unwrap_or_default();
        let _ = writeln!(
            std::io::stderr(),
            "error: internal error, a bug of vibrissa (please report it with the command \
             line): {line}{place}"
        );
    }));
}

fn main() {
    install_panic_hook();
    // rayon's pool, or the main thread alone where no thread can be started
    bvp_solvers::parallel::start_pool();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match e.kind() {
            ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                if let Err(source) = e.print().and_then(|()| std::io::stdout().flush()) {
                    let e = CliError::Stdout {
                        source,
                        published: None,
                    };
                    eprintln!("error: {e}");
                    std::process::exit(EXIT_OUTPUT);
                }
                std::process::exit(
                    if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                        2
                    } else {
                        0
                    },
                );
            }
            _ => {
                // clap's message spans several lines (usage, tips): keep the first.
                // Its first paragraph (the error and, indented, the arguments concerned)
                // is joined into one line.
                let text = e.render().to_string();
                let line = text
                    .trim_start()
                    .lines()
                    .map(str::trim)
                    .take_while(|l| !l.is_empty())
                    .collect::<Vec<_>>()
                    .join(" ");
                let line = if line.is_empty() {
                    "error: invalid command line".to_string()
                } else {
                    line
                };
                eprintln!("{line} (see --help)");
                std::process::exit(2);
            }
        },
    };
    let style = cli.figure_style();
    if let Err(e) = commands::run(cli.command, style) {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
