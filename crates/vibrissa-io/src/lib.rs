//! The library layer of vibrissa's inputs and outputs, without a command line: what the CLI,
//! the Python package and `cargo xtask` share.
//!
//! - [`error`]: [`IoError`], the typed errors of this crate (each names its culprit);
//! - [`calibration`]: a calibration's values, logs, fit and report (serialisable);
//! - [`atomic`]: atomic file writes and staged output folders (an OS lock, a manifest of
//!   what vibrissa wrote, symbolic links followed, an atomic swap);
//! - [`csvio`]: round-trip exact CSV writing and lenient, precise CSV reading (`csv` crate);
//! - [`units`]: the units of every output (dimensionless or mm, N, N mm) and their sidecars;
//! - [`scene_file`]: the RON scene format;
//! - [`resolve`]: scene file + overrides -> model values (physical units included), and a
//!   sweep's settings ([`resolve::sweep`]);
//! - [`observables`]: `observables.csv`, a sweep's rows ([`observables::SweepRow`]);
//! - [`sweep_events`]: a sweep's events and row counts;
//! - [`recon`]: a reconstruction's values, options, whisker and compute (culprits named);
//! - [`recon_friction`]: a reconstruction asked with `--mu` (frictional logs), its `ft`
//!   column and the `mu` of its JSON;
//! - [`recon_io`]: a reconstruction's inputs (logs, units) and `reconstruction.csv`;
//! - [`summary`]: the small records of a result (`solve`, `sweep`) as serialisable values;
//! - [`outputs`]: units sidecars and the `scene.ron` of an output folder.

pub mod atomic;
pub mod calibration;
pub mod csvio;
pub mod error;
pub mod observables;
pub mod outputs;
pub mod recon;
pub mod recon_friction;
pub mod recon_io;
pub mod resolve;
pub mod scene_file;
pub mod summary;
pub mod sweep_events;
pub mod units;

pub use error::IoError;
