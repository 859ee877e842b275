//! # profile-recon
//!
//! Fluid-load identification and obstacle contour reconstruction from the base observables
//! (thesis ch. 6):
//!
//! | module | concept |
//! |---|---|
//! | [`observables`] | the measured rows `(x0, Ax, Ay, MA, phi0)` |
//! | [`identify`](mod@identify) | fluid load from the pre-contact rows [6.1], contact start (Table 6.1) |
//! | [`reconstruct`](mod@reconstruct) | contact point, force, s1 and phase per row; quality measure [6.11] |
//! | [`noise`] | seeded sensor noise and the error-against-noise study |
//! | [`thesis`] | the thesis's five-equation method [6.5-6.10] |
//!
//! ```
//! use beam_model::Whisker;
//! use contact_sim::{sweep, Profile, SweepSettings};
//! use profile_recon::{contour_error, from_sweep, reconstruct, ReconSettings};
//!
//! let w = Whisker::uniform();
//! let settings = SweepSettings { points: 20, ..Default::default() };
//! let truth = sweep(&w, beam_model::FluidLoad { q: 5.0, alpha: 0.0 }, &Profile::g2(), &settings).unwrap();
//! // only the observables (x0, Ax, Ay, MA, phi0) go in
//! let rec = reconstruct(&w, &from_sweep(&truth), None, &ReconSettings::default()).unwrap();
//! assert!((rec.identification.q - 5.0).abs() < 1e-12);
//! assert!(contour_error(&rec.points, &Profile::g2()).iter().all(|e| *e < 1e-9));
//! ```

pub mod error;
pub mod identify;
pub mod noise;
pub mod observables;
pub mod reconstruct;
pub mod thesis;

pub use error::{ReconError, Result};
pub use identify::{identify, Identification};
pub use noise::{add_noise, noise_study, NoiseResult};
pub use observables::{from_sweep, ObservableRow};
pub use reconstruct::{
    contour_error, reconstruct, ReconMethod, ReconPoint, ReconSettings, Reconstruction,
};
