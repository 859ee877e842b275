//! The `vibrissa` command line: input/output, figures and scene files.
//!
//! - [`error`]: [`CliError`], the one-line errors of the binary and their exit codes;
//! - [`printer`]: standard output that returns its errors (a closed pipe, a full disk) as
//!   [`CliError::Stdout`], exit [`error::EXIT_OUTPUT`];
//! - [`cli`]: the command-line grammar;
//! - [`commands`]: `solve`, `sweep`, `reconstruct`, `calibrate`, `demo`, one module per
//!   concept of their outputs.
//!
//! The library layers it prints are re-exported under their former paths: [`atomic`],
//! [`csvio`], [`units`], [`scene_file`], [`resolve`] (crate `vibrissa-io`) and [`plot`]
//! (crate `vibrissa-plot`).

pub mod cli;
pub mod commands;
pub mod error;
pub mod printer;

pub use vibrissa_io::{atomic, csvio, resolve, scene_file, units};
pub use vibrissa_plot as plot;

pub use error::CliError;
