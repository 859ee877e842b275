//! The one error type of the crate.

use bvp_solvers::BvpError;
use thiserror::Error;

/// Everything that can go wrong when building or solving a whisker scene.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// A scene parameter is out of its admissible range or not finite.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter, named as in the thesis and the CLI (`theta`, `k`, `f`, ...).
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is admissible.
        reason: &'static str,
    },
    /// A solution method did not converge, even with load continuation.
    #[error("{method} solve failed at load scale {load_scale:.4} after {iterations} iterations (residual {residual:.3e})")]
    NoConvergence {
        /// The method (`accurate`, `rk4`, `fdm`).
        method: &'static str,
        /// Fraction of the target loads reached by continuation (1 = full load).
        load_scale: f64,
        /// Iterations of the last attempt.
        iterations: usize,
        /// Residual of the last attempt.
        residual: f64,
    },
    /// Load continuation stopped before the full load: `cause` is the last failure of the
    /// corrector (or a [`ModelError::BranchJump`], or [`ModelError::Budget`]).
    #[error("{method}: load continuation stalled at load scale {load_scale:.4} (step {step:.1e}): {cause}")]
    ContinuationFailed {
        /// The method.
        method: &'static str,
        /// Fraction of the target loads reached (1 = full load).
        load_scale: f64,
        /// The last step that failed.
        step: f64,
        /// The last inner failure.
        cause: Box<ModelError>,
    },
    /// A continuation corrector converged on another equilibrium branch: it landed `distance`
    /// (rad, max-norm) from its prediction, more than the guard allows.
    #[error("{method}: branch jump at load scale {load_scale:.4} (distance {distance:.3e} rad > {allowed:.3e})")]
    BranchJump {
        /// The method.
        method: &'static str,
        /// Load scale of the rejected step.
        load_scale: f64,
        /// Distance from the prediction.
        distance: f64,
        /// The guard's bound.
        allowed: f64,
    },
    /// The continuation ended past a fold of the load path from zero (`dR/dphi1 <= 0` at its
    /// answer, `phi1`) and the load path itself could not be followed to full load: no
    /// answer by the rule every method follows.
    #[error("{method}: the load path from zero folds (the continuation ended past a fold at phi1 = {phi1:.6}) and could not be followed through its folds to full load")]
    FoldedPath {
        /// The method.
        method: &'static str,
        /// The loaded-end angle the continuation reached.
        phi1: f64,
    },
    /// The load paths on `n` and `2n` grid intervals reached different equilibria: the grid
    /// does not resolve the whisker (usually the thin tip's boundary layer).
    #[error("{method}: the load paths on {n} and 2x{n} intervals reach different equilibria (distance {distance:.3e}); the grid does not resolve the tip, use a finer --n")]
    BranchAmbiguous {
        /// The method.
        method: &'static str,
        /// The coarser grid's intervals per unit length.
        n: usize,
        /// Largest difference of tip, loaded end and base observables.
        distance: f64,
    },
    /// A work budget (continuation correctors, integration steps, grid size) was used up.
    #[error("{method}: budget of {limit} {what} used up")]
    Budget {
        /// The method.
        method: &'static str,
        /// What was counted.
        what: &'static str,
        /// The budget.
        limit: usize,
    },
    /// The a-posteriori error estimate of a solve exceeds the requested accuracy: the
    /// numbers are not trustworthy and are not returned.
    #[error("{method}: estimated error {estimate:.3e} exceeds the requested accuracy {tolerance:.1e} (theta = {theta}); {hint}")]
    Inaccurate {
        /// The method (after any fallback).
        method: &'static str,
        /// The error estimate (max over tip, loaded end and base observables).
        estimate: f64,
        /// The requested accuracy.
        tolerance: f64,
        /// The whisker's conicity (thin tips are the usual cause).
        theta: f64,
        /// What may help.
        hint: &'static str,
    },
    /// An underlying BVP routine failed.
    #[error("{method}: {source}")]
    Solver {
        /// The method that called it.
        method: &'static str,
        /// The failure.
        #[source]
        source: BvpError,
    },
}

impl From<BvpError> for ModelError {
    fn from(source: BvpError) -> Self {
        ModelError::Solver {
            method: "bvp",
            source,
        }
    }
}

impl ModelError {
    /// The same failure reported under the method the user asked for: `accurate` names its
    /// FDM + Richardson fallback as `accurate (fdm-richardson fallback)` rather than `fdm`.
    pub(crate) fn in_method(mut self, name: &'static str) -> Self {
        match &mut self {
            ModelError::NoConvergence { method, .. }
            | ModelError::ContinuationFailed { method, .. }
            | ModelError::BranchJump { method, .. }
            | ModelError::FoldedPath { method, .. }
            | ModelError::BranchAmbiguous { method, .. }
            | ModelError::Budget { method, .. }
            | ModelError::Inaccurate { method, .. }
            | ModelError::Solver { method, .. } => *method = name,
            ModelError::InvalidParameter { .. } => {}
        }
        self
    }

    /// Maps a failure of [`Continuation::follow`](bvp_solvers::continuation::Continuation::follow)
    /// to a model error that names the method and carries the last inner error.
    pub(crate) fn from_continuation(
        method: &'static str,
        fail: bvp_solvers::continuation::ContinuationFailure<ModelError>,
    ) -> Self {
        use bvp_solvers::continuation::StallCause;
        let cause = match fail.cause {
            StallCause::Inner(e) => e,
            StallCause::Jump {
                at,
                distance,
                allowed,
            } => ModelError::BranchJump {
                method,
                load_scale: at,
                distance,
                allowed,
            },
            StallCause::Budget { max_attempts } => ModelError::Budget {
                method,
                what: "continuation correctors",
                limit: max_attempts,
            },
            StallCause::Invalid(source) => return ModelError::Solver { method, source },
        };
        ModelError::ContinuationFailed {
            method,
            load_scale: fail.reached,
            step: fail.step,
            cause: Box::new(cause),
        }
    }
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, ModelError>;

/// Checks that `value` is finite, naming the parameter otherwise.
pub fn finite(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ModelError::InvalidParameter {
            name,
            value,
            reason: "must be a finite number",
        })
    }
}
