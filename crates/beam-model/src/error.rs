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

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, ModelError>;

/// Checks that `value` is finite, naming the parameter otherwise.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64> {
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
