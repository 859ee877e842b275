//! The one error type of the crate.

use crate::phase::Phase;
use beam_model::ModelError;
use bvp_solvers::BvpError;
use thiserror::Error;

/// Everything that can go wrong in a contact sweep.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ContactError {
    /// The whisker model rejected a parameter or failed to solve.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A profile specification could not be parsed.
    #[error("invalid profile '{spec}': {reason}")]
    ProfileSpec {
        /// The specification as given.
        spec: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The contour is not strictly convex where the sweep needs it.
    #[error("profile {profile} is not strictly convex at x = {x:.6} (g'' = {g2:.3e})")]
    NotConvex {
        /// The profile's name.
        profile: String,
        /// Where convexity fails.
        x: f64,
        /// Its second derivative there.
        g2: f64,
    },
    /// A sweep parameter is out of range.
    #[error("invalid sweep parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is admissible.
        reason: &'static str,
    },
    /// The whisker never touches the obstacle.
    #[error("no contact: {reason}")]
    NoContact {
        /// Why.
        reason: String,
    },
    /// A contact phase could not be solved at a contour point.
    #[error("phase {phase} solve failed at contour point xc = {xc:.6} after {iterations} iterations (residual {residual:.3e})")]
    PhaseSolve {
        /// `A` or `B`.
        phase: Phase,
        /// The contour point.
        xc: f64,
        /// Iterations.
        iterations: u64,
        /// Final residual norm.
        residual: f64,
    },
    /// The contact point reached the end of the contour's parameter range (a table's last
    /// knot, a circle's vertical end).
    #[error("the contact point left profile {profile} (contour parameter t = {t:.6})")]
    LeftContour {
        /// The profile's name.
        profile: String,
        /// The contour parameter reached.
        t: f64,
    },
    /// The continuation of the contact branch could not go on.
    #[error("the contact branch stalled in phase {phase} at base position x0 = {x0:.6} (contact point xc = {xc:.6}, step {step:.2e}): {reason}")]
    BranchStalled {
        /// `A` or `B`.
        phase: Phase,
        /// Last base position reached.
        x0: f64,
        /// Last contact point.
        xc: f64,
        /// The last step length tried.
        step: f64,
        /// Why.
        reason: String,
    },
    /// A row's error estimate exceeds the accuracy asked for (`SweepSettings::accuracy`).
    #[error("row {} (x0 = {x0:.6}): error estimate {estimate:.3e} exceeds the accuracy asked for, {tol:e} (the best this sweep reaches there)", row + 1)]
    AccuracyNotMet {
        /// 0-based index of the row in `SweepResult::points`.
        row: usize,
        /// Its base position.
        x0: f64,
        /// Its error estimate.
        estimate: f64,
        /// The accuracy asked for.
        tol: f64,
    },
    /// A frictional sweep reached a tangential contact (phase B) without a frictional model
    /// for it. No longer returned: phase B has friction (crate::friction); kept so that
    /// callers matching it still build.
    #[error("friction in tangential contact is not implemented: the tip contact turns tangential at x0 = {x0:.6} (xc = {xc:.6}); sweep this scene with mu = 0")]
    FrictionInTangentialContact {
        /// Base position where the tangential contact begins.
        x0: f64,
        /// Its contact point.
        xc: f64,
    },
    /// Neither stick nor slip continues a frictional sweep quasi-statically.
    #[error("friction (mu = {mu}): no quasi-static continuation at x0 = {x0:.6} (xc = {xc:.6}): {reason}")]
    FrictionIndeterminate {
        /// Base position.
        x0: f64,
        /// Contact point.
        xc: f64,
        /// The friction coefficient.
        mu: f64,
        /// Why.
        reason: String,
    },
    /// A combination of motion, obstacle and contact law the sweep does not follow yet.
    #[error("{what} not implemented")]
    NotImplemented {
        /// What, e.g. "friction with motion rotate is".
        what: String,
    },
    /// An underlying BVP routine failed.
    #[error(transparent)]
    Bvp(#[from] BvpError),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, ContactError>;
