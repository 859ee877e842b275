//! The one error type of the crate.

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
        phase: char,
        /// The contour point.
        xc: f64,
        /// Iterations.
        iterations: u64,
        /// Final residual norm.
        residual: f64,
    },
    /// An underlying BVP routine failed.
    #[error(transparent)]
    Bvp(#[from] BvpError),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, ContactError>;
