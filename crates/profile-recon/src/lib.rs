//! # profile-recon
//!
//! Fluid-load identification and obstacle contour reconstruction from the base observables
//! (thesis ch. 6):
//!
//! | module | concept |
//! |---|---|
//! | [`observables`] | the measured rows `(x0, Ax, Ay, MA, phi0)` |
//! | [`common`] | settings, known flow, the force balance [6.8, 6.9], quality measure [6.11], noise scales, row numbering |
//! | [`result`] | what a reconstruction returns: identification, points, the accuracy report (below every method) |
//! | [`identify`](mod@identify) | flow `(q, alpha)`, noise level and pre-contact rows from the model [6.1] (Table 6.1) |
//! | [`base_shot`] | method `accurate`: one shot from the base per row, all phase-B roots bracketed, error estimate |
//! | `judge` | the one per-row decision (pre-contact or contact point, with its statistics) of identification, reconstruction and stream |
//! | [`thesis`] | method `thesis`: the thesis's five equations [6.5-6.10] |
//! | [`reconstruct`](mod@reconstruct) | identification then one point per contact row with either method |
//! | [`accuracy`] | accuracy on demand ([`reconstruct_to`]): the points at the tolerance an accuracy needs, each with its error estimate |
//! | [`stream`] | rows one at a time, each point as soon as it is known |
//! | [`noise`] | seeded sensor noise and the error-against-noise study |
//! | [`pose`] | logs of any base motion: the rows' poses `(y0, gamma)` and the base frame the methods run in |
//! | [`obstacle`] | a peg's position, a disc's centre and radius from the contact points, with standard errors |
//! | [`friction`] | frictional logs: contact points, `fn`, `ft` and `mu` from the base observables alone |
//! | [`calibrate`](mod@calibrate) | the whisker's own parameters from sweeps past known contours; design advice |
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

pub mod accuracy;
pub mod base_shot;
pub mod calibrate;
pub mod common;
pub mod error;
pub mod friction;
pub mod identify;
mod judge;
pub mod noise;
pub mod observables;
pub mod obstacle;
pub mod pose;
pub mod reconstruct;
pub mod result;
mod rows_par;
pub mod stream;
pub mod thesis;

pub use accuracy::{reconstruct_to, ReconAccuracy};
pub use beam_model::AccuracyReport;
pub use common::{
    contact_force, contour_error, free_flow, KnownFlow, NoiseScales, ReconMethod, ReconSettings,
};
pub use error::{ReconError, Result};
pub use friction::stream::{FrictionalStreamEnd, FrictionalStreamer};
pub use friction::{
    reconstruct_frictional, reconstruct_frictional_on, widen_frictionless, FrictionEvidence,
    FrictionalPoint, FrictionalReconstruction, MuEstimate,
};
pub use identify::identify;
pub use noise::{add_noise, noise_study, NoiseResult};
pub use observables::{from_sweep, ObservableRow};
pub use obstacle::{estimate_disc, estimate_peg, DiscEstimate, PegEstimate};
pub use pose::{in_base_frame, poses_of_sweep, reconstruct_posed, reconstruct_posed_to, RowPose};
pub use reconstruct::{reconstruct, reconstruct_with};
pub use result::{Identification, ReconPoint, Reconstruction};
pub use stream::Streamer;
