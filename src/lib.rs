//! # vibrissa
//!
//! Whisker-inspired tactile sensing: a tapered, pre-curved elastica in an elastic follicle
//! [3.25], swept past an obstacle under a flow (thesis ch. 5), with the flow identified and
//! the contour reconstructed from the base observables (ch. 6).
//!
//! The library a Rust program adds to its `Cargo.toml`: the command line (`vibrissa`) and
//! the Python package are thin layers on it. The contract (`spec/rust.md`):
//!
//! - [`Scene`]: [`Scene::load`] a scene file (`scenes/*.ron`, units included),
//!   [`Scene::from_ron`], build one in code ([`SceneFile`]), [`Scene::to_ron`];
//! - [`Scene::solve`] -> [`Solution`], [`Scene::sweep`] -> [`Sweep`] (its [`SweepRow`]s,
//!   [`Sweep::first_contact`], [`Sweep::separation`], [`Sweep::events`]),
//!   [`Scene::reconstruct`] -> [`Reconstruction`] from a [`Sweep`] or
//!   [`io::read_observables`]; all in the scene's units, the numbers the CLI writes;
//! - [`Error`]: invalid input, solver failure, no contact (the CLI's exit codes 2, 1, 3).
//!
//! ```no_run
//! let scene = vibrissa::Scene::load("scenes/physical-beta-g1.ron")?;
//! let sweep = scene.sweep()?;
//! for row in sweep.rows() {
//!     println!("x0 = {} mm: Ax = {} N, MA = {} N mm, phase {}", row.x0, row.ax, row.ma, row.phase);
//! }
//! let rec = scene.reconstruct(&sweep)?;
//! println!("q = {} N/m identified, {} contact points", rec.q, rec.rows.len());
//! # Ok::<(), vibrissa::Error>(())
//! ```
//!
//! The layers below are re-exported:
//!
//! | crate | concept |
//! |---|---|
//! | [`bvp_solvers`] | generic non-linear two-point BVP toolkit (FDM, shooting, integrators, roots) |
//! | [`beam_model`] | the whisker elastica [3.25] and its solution methods |
//! | [`contact_sim`] | quasi-static sweep past a convex obstacle (thesis ch. 5) |
//! | [`profile_recon`] | fluid-load identification and contour reconstruction (thesis ch. 6) |
//! | [`vibrissa_io`] | scene files, units, CSV files, output folders |

pub mod error;
pub mod io;
pub mod reconstruct;
pub mod scene;
pub mod solve;
pub mod sweep;

pub use beam_model;
pub use bvp_solvers;
pub use contact_sim;
pub use profile_recon;
pub use vibrissa_io;

pub use contact_sim::{FirstContact, Phase, Separation};
pub use error::Error;
pub use reconstruct::{Log, ReconRow, Reconstruction};
pub use scene::Scene;
pub use solve::{Elastica, Solution};
pub use sweep::{Event, Sweep};
pub use vibrissa_io::observables::SweepRow;
pub use vibrissa_io::scene_file::{
    LoadKind, LoadSpec, MethodSpec, SceneFile, SweepSpec, Units, WhiskerSpec,
};
pub use vibrissa_io::units::UnitSystem;

/// The small records of a result, serialisable (serde): what `solve --json`, `sweep --json`
/// and `calibrate --json` print and the Python package returns as dicts.
pub mod records {
    pub use vibrissa_io::calibration::CalibrationReport;
    pub use vibrissa_io::summary::{ReconSummary, SolveSummary, SweepSummary};
}
