//! # contact-sim
//!
//! Quasi-static sweep of a whisker past a convex obstacle under flow (thesis ch. 5):
//!
//! | module | concept |
//! |---|---|
//! | [`profile`] | convex contours g1, g2, ge, parabola, cosh, circle arc, tabulated points |
//! | [`phase`] | tip contact (phase A) and tangential contact (phase B) at one contour point |
//! | [`cases`] | the chapter-5 cases as reference problems |
//! | [`sweep`] | first contact, the march along the contour, phase switches, snap and release |

pub mod cases;
pub mod error;
pub mod phase;
pub mod profile;
pub mod sweep;

pub use error::{ContactError, Result};
pub use phase::{ContactState, ContourPoint, Phase};
pub use profile::Profile;
pub use sweep::{sweep, FirstContact, Separation, SweepPoint, SweepResult, SweepSettings};
