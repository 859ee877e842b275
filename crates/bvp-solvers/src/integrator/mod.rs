//! Integrators for first-order systems `u' = G(s, u)`.
//!
//! * [`Rk4`]: the classical fourth-order Runge-Kutta method with equal steps, returning the
//!   whole [`Trajectory`] (global error `O(h^4)`).
//! * [`Dop853`]: the explicit Runge-Kutta pair of Dormand and Prince of order 8 with the
//!   combined 5th/3rd-order error estimator, step-size control and 7th-order dense output of
//!   Hairer's `DOP853` (Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., §II.10), plus
//!   event location (first zero of a scalar function of the solution) by Brent's method on the
//!   dense output.
//!
//! Layout (as in the `russell_ode` and `ode_solvers` crates): `rk4.rs` for the fixed-step
//! method; `dop853/` split into the tableau (`coef`), one step with its error norm
//! (`step`), the step-size controller (`control`), the stepper that takes one accepted step
//! at a time ([`Stepper`], `stepper`), the dense output (`dense`) and event location
//! (`events`), with the driver of `integrate`/`integrate_until` in `dop853/mod.rs`.
//!
//! Both methods allocate their work space once per call; no allocation happens per step
//! (except for the stored dense output when it is requested).

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::{BvpError, Result};

mod dop853;
mod rk4;

pub use dop853::{
    Dop853, Event, IntegrationStats, Interpolant, OdeSolution, StepInterpolant, Stepper,
};
pub use rk4::{Rk4, Trajectory};

/// A first-order system `u' = G(s, u)` of dimension [`OdeSystem::dim`].
///
/// ```
/// use bvp_solvers::integrator::{Dop853, OdeSystem};
///
/// /// The harmonic oscillator u'' = -u as a first-order system.
/// struct Oscillator;
/// impl OdeSystem for Oscillator {
///     fn dim(&self) -> usize { 2 }
///     fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
///         du[0] = u[1];
///         du[1] = -u[0];
///     }
/// }
///
/// let sol = Dop853::new(1e-12, 1e-12).integrate(&Oscillator, 0.0, 1.0, &[0.0, 1.0]).unwrap();
/// assert!((sol.u_end[0] - 1f64.sin()).abs() < 1e-11);
/// ```
pub trait OdeSystem {
    /// Dimension `n` of the state `u`.
    fn dim(&self) -> usize;
    /// Writes `G(s, u)` into `du` (both of length `n`).
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]);
}

impl<T: OdeSystem + ?Sized> OdeSystem for &T {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]) {
        (**self).rhs(s, u, du)
    }
}

pub(crate) fn check_span(s0: f64, s1: f64) -> Result<()> {
    if !s0.is_finite() {
        return Err(BvpError::InvalidInput {
            name: "s0",
            value: s0,
            reason: "integration bounds must be finite",
        });
    }
    if !s1.is_finite() {
        return Err(BvpError::InvalidInput {
            name: "s1",
            value: s1,
            reason: "integration bounds must be finite",
        });
    }
    Ok(())
}

pub(crate) fn check_initial(n: usize, u0: &[f64]) -> Result<()> {
    if u0.len() != n {
        return Err(BvpError::DimensionMismatch {
            name: "initial state u0",
            expected: n,
            found: u0.len(),
        });
    }
    if let Some(&v) = u0.iter().find(|v| !v.is_finite()) {
        return Err(BvpError::InvalidInput {
            name: "u0",
            value: v,
            reason: "initial state must be finite",
        });
    }
    Ok(())
}

#[inline]
pub(crate) fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}
