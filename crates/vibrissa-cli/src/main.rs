//! The `vibrissa` binary: parses the command line and runs a command; every failure is one
//! line on stderr and a non-zero exit code ([`vibrissa_cli::CliError::exit_code`]).

use clap::error::ErrorKind;
use clap::Parser;

use vibrissa_cli::cli::Cli;
use vibrissa_cli::commands;

fn main() {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match e.kind() {
            ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                let _ = e.print();
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
    vibrissa_cli::plot::set_figure_formats(cli.figures);
    vibrissa_cli::plot::set_figure_size(cli.size);
    if let Err(e) = commands::run(cli.command) {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
