//! The `vibrissa` command line: input/output, figures and scene files.
//!
//! - [`error`]: [`CliError`], the one-line errors of the binary and their exit codes;
//! - [`atomic`]: atomic file writes and staged output directories;
//! - [`csvio`]: round-trip exact CSV writing and lenient, precise CSV reading (`csv` crate);
//! - [`printer`]: standard output that returns its errors (a closed pipe, a full disk);
//! - [`plot`]: declarative charts, panels and categorical maps rendered to SVG and PNG;
//! - [`units`]: the units of every output (dimensionless or mm, N, N mm) and their sidecars;
//! - [`scene_file`]: the RON scene format;
//! - [`cli`]: the command-line grammar;
//! - [`resolve`]: scene file + flags -> model values (physical units included);
//! - [`commands`]: `solve`, `sweep`, `reconstruct`, `calibrate`, `demo`, one module per
//!   concept of their outputs.

pub mod atomic;
pub mod cli;
pub mod commands;
pub mod csvio;
pub mod error;
pub mod plot;
pub mod printer;
pub mod resolve;
pub mod scene_file;
pub mod units;

pub use error::CliError;
