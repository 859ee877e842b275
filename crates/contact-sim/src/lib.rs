//! # contact-sim
//!
//! Quasi-static sweep of a whisker past a convex obstacle under flow (thesis ch. 5):
//!
//! | module | concept |
//! |---|---|
//! | [`profile`] | convex contours g1, g2, ge, parabola, cosh, circle arc, tabulated points; the contour parameter |
//! | [`phase`] | tip contact (phase A) and tangential contact (phase B) at one contour point |
//! | `branch` | the contact branch in `(phi1 or s1, f, t)`: equations, Jacobian, correctors |
//! | `continuation` | pseudo-arclength continuation of the branch in the direction of falling x0 |
//! | `events` | phase switches, release, snap (x0 turning point), second contact: location |
//! | [`first_contact`] | the exact first touch of the free whisker (tip or tangential) |
//! | [`cases`] | the chapter-5 cases as reference problems |
//! | [`motion`] | the base's pose along the sweep: translate, rotate (whisking), a path of poses |
//! | [`path`] | the sweep along a path of poses: segment frames, corners as breakpoints, k(p) |
//! | [`friction`] | the contact law (frictionless, Coulomb): stick and slip in tip contact, their events |
//! | [`touch_scan`] | the first touch along a rotation, or of a peg or a disc |
//! | `rows` | the log's contact rows at evenly spaced base positions: predicted, corrected |
//! | [`mod@sweep`] | settings, the sweep's course (free whisker, first touch, trace, rows), separation kinds |
//!
//! The sweep follows the base position x0, the quantity the experimenter moves: the contact
//! point may move either way along the contour and reverse; the whisker separates where x0
//! reaches a turning point of the branch (snap) or the contact force falls to zero (release).
//!
//! ```
//! use beam_model::Whisker;
//! use contact_sim::{sweep, Profile, Separation, SweepSettings};
//!
//! // Thesis case 1: a uniform rigid whisker under q = 5 swept past the catenary g1.
//! let settings = SweepSettings { points: 20, ..Default::default() };
//! let flow = beam_model::FluidLoad { q: 5.0, alpha: 0.0 };
//! let r = sweep(&Whisker::uniform(), flow, &Profile::g1(), &settings).unwrap();
//! assert_eq!(r.phase_pattern(), "ABA"); // tip, tangential, tip contact
//! assert_eq!(r.separation, Separation::Release); // the flow absorbs the snap
//! // the base moves left row by row
//! assert!(r.points.windows(2).all(|w| w[1].x0 < w[0].x0));
//! ```

pub mod accuracy;
mod ahead;
mod branch;
pub mod cases;
pub mod contact_force;
pub mod contact_law;
mod continuation;
pub mod driver;
pub mod error;
mod events;
pub mod first_contact;
pub mod friction;
pub mod motion;
pub mod path;
pub mod phase;
pub mod profile;
mod rows;
pub mod sweep;
pub mod touch_scan;

pub use accuracy::SweepAccuracy;
pub use contact_law::{ContactLaw, FrictionEvent, FrictionEventKind, SlipState, Tilt};
pub use driver::{sweep, sweep_with_progress};
pub use error::{ContactError, Result};
pub use motion::{BaseMotion, Pose, Poses};
pub use phase::{ContactState, ContourPoint, Phase};
pub use profile::Profile;
pub use sweep::{
    FirstContact, FirstTouch, Separation, SweepPoint, SweepProgress, SweepResult, SweepSettings,
};
