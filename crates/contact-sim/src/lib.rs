//! # contact-sim
//!
//! Quasi-static sweep of a whisker past a convex obstacle under flow (thesis ch. 5):
//!
//! | module | concept |
//! |---|---|
//! | [`profile`] | convex contours g1, g2, ge, parabola, cosh, circle arc, tabulated points |
//! | [`phase`] | tip contact (phase A) and tangential contact (phase B) at one contour point |
//! | [`cases`] | the chapter-5 cases as reference problems |
//! | [`sweep`](mod@sweep) | first contact, the march along the contour, phase switches, snap and release |
//!
//! ```
//! use beam_model::Whisker;
//! use contact_sim::{sweep, Profile, Separation, SweepSettings};
//!
//! // Thesis case 1: a uniform rigid whisker under q = 5 swept past the catenary g1.
//! let settings = SweepSettings { points: 20, ..Default::default() };
//! let r = sweep(&Whisker::uniform(), 5.0, &Profile::g1(), &settings).unwrap();
//! assert_eq!(r.phase_pattern(), "ABA"); // tip, tangential, tip contact
//! assert_eq!(r.separation, Separation::Release); // the flow absorbs the snap
//! ```

pub mod cases;
pub mod error;
pub mod phase;
pub mod profile;
pub mod sweep;

pub use error::{ContactError, Result};
pub use phase::{ContactState, ContourPoint, Phase};
pub use profile::Profile;
pub use sweep::{
    sweep, sweep_with_progress, FirstContact, Separation, SweepPoint, SweepProgress, SweepResult,
    SweepSettings,
};
