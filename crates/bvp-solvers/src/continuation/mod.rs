//! Continuation: following a branch of solutions of a parameter-dependent problem.
//!
//! (Step 1 of merging the two drivers: both live here; see [`arclength`] and [`natural`].)

pub mod arclength;
pub mod natural;

pub use arclength::{locate, ArcControl, Arclength, Attempt, Curve, Predictor, MAX_LOCATE};
pub use natural::{BranchGuard, Continuation, ContinuationFailure, ContinuationStats, StallCause};
