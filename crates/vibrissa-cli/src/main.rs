//! The `vibrissa` binary (placeholder: the commands are being implemented).

use clap::{Parser, Subcommand};

/// Whisker-inspired tactile sensing: elastica, contact sweeps and contour reconstruction.
#[derive(Debug, Parser)]
#[command(name = "vibrissa", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Solve one whisker configuration.
    Solve,
    /// Sweep the whisker past an obstacle.
    Sweep,
    /// Reconstruct a contour from an observables log.
    Reconstruct,
    /// Run the whole chain on a built-in scene.
    Demo,
}

fn main() {
    let cli = Cli::parse();
    let name = match cli.command {
        Command::Solve => "solve",
        Command::Sweep => "sweep",
        Command::Reconstruct => "reconstruct",
        Command::Demo => "demo",
    };
    eprintln!("vibrissa {name}: not implemented yet");
    std::process::exit(2);
}
