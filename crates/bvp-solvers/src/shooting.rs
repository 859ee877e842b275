//! Shooting for two-point boundary-value problems.
//!
//! Unknown initial values and free parameters `p` (length `n_params`) are found so that the
//! boundary residuals at the end of the span vanish:
//!
//! `R(p) = residual(p, u(s1; p)) = 0`, where `u' = G_p(s, u)`, `u(s0) = u0(p)`, `(s0, s1) = span(p)`,
//!
//! solved by the trust-region method of [`crate::trust_region`] with a forward-difference
//! Jacobian of `R` (each column costs one integration).

use crate::integrator::{Dop853, OdeSystem, Rk4};
use crate::trust_region::{self, NonlinearSystem, TrustRegionOptions};
use crate::{BvpError, Result};

/// A boundary-value problem posed for shooting.
///
/// ```
/// use bvp_solvers::integrator::{Dop853, OdeSystem};
/// use bvp_solvers::shooting::{Shooting, ShootingIntegrator, ShootingProblem};
/// use bvp_solvers::trust_region::TrustRegionOptions;
///
/// /// y'' = -y, y(0) = 0, y(pi/2) = 1 (solution sin s): unknown slope p = y'(0).
/// struct Sine;
/// struct Rhs;
/// impl OdeSystem for Rhs {
///     fn dim(&self) -> usize { 2 }
///     fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
///         du[0] = u[1];
///         du[1] = -u[0];
///     }
/// }
/// impl ShootingProblem for Sine {
///     type System = Rhs;
///     fn n_params(&self) -> usize { 1 }
///     fn system(&self, _p: &[f64]) -> Rhs { Rhs }
///     fn span(&self, _p: &[f64]) -> (f64, f64) { (0.0, std::f64::consts::FRAC_PI_2) }
///     fn initial_state(&self, p: &[f64], u0: &mut [f64]) {
///         u0[0] = 0.0;
///         u0[1] = p[0];
///     }
///     fn residual(&self, _p: &[f64], u_end: &[f64], r: &mut [f64]) {
///         r[0] = u_end[0] - 1.0;
///     }
/// }
///
/// let shooting = Shooting {
///     integrator: ShootingIntegrator::Dop853(Dop853::new(1e-12, 1e-12)),
///     options: TrustRegionOptions::default(),
/// };
/// let sol = shooting.solve(&Sine, &[0.3]).unwrap();
/// assert!((sol.params[0] - 1.0).abs() < 1e-8);
/// ```
pub trait ShootingProblem {
    /// The first-order system integrated for given parameters.
    type System: OdeSystem;
    /// Number of unknown parameters = number of boundary residuals.
    fn n_params(&self) -> usize;
    /// The ODE for given parameters `p` (free parameters may enter the right-hand side).
    fn system(&self, p: &[f64]) -> Self::System;
    /// Integration span `(s0, s1)` (either direction); may depend on `p`.
    fn span(&self, p: &[f64]) -> (f64, f64);
    /// Writes the initial state `u(s0)` for parameters `p` (length `system(p).dim()`).
    fn initial_state(&self, p: &[f64], u0: &mut [f64]);
    /// Boundary residuals at the end state, length `n_params`.
    fn residual(&self, p: &[f64], u_end: &[f64], r: &mut [f64]);
}

/// The integrator used for each shot.
#[derive(Clone, Debug)]
pub enum ShootingIntegrator {
    /// Classical RK4 with a fixed number of equal steps (residual smooth in `p`).
    Rk4 {
        /// Number of steps.
        steps: usize,
    },
    /// Adaptive DOP853 (the residual has tolerance-level noise in `p`, which limits the
    /// forward-difference Jacobian to about `sqrt(tol)` relative accuracy).
    Dop853(Dop853),
}

/// Shooting solver: integrator + trust-region options.
#[derive(Clone, Debug)]
pub struct Shooting {
    /// Integrator of each shot.
    pub integrator: ShootingIntegrator,
    /// Options of the trust-region solve for the parameters (`tol` applies to `||R||_2`).
    pub options: TrustRegionOptions,
}

/// A converged shooting solution.
#[derive(Clone, Debug, PartialEq)]
pub struct ShootingSolution {
    /// The parameters `p`.
    pub params: Vec<f64>,
    /// End state `u(s1; p)`.
    pub u_end: Vec<f64>,
    /// `||R(p)||_2`.
    pub residual_norm: f64,
    /// Trust-region iterations.
    pub iterations: u64,
}

struct ShootingSystem<'a, P: ShootingProblem> {
    problem: &'a P,
    integrator: &'a ShootingIntegrator,
}

impl<P: ShootingProblem> ShootingSystem<'_, P> {
    /// Integrates one shot; returns the end state.
    fn shoot(&self, p: &[f64]) -> Result<Vec<f64>> {
        let sys = self.problem.system(p);
        let n = sys.dim();
        let (s0, s1) = self.problem.span(p);
        let mut u0 = vec![0.0; n];
        self.problem.initial_state(p, &mut u0);
        match self.integrator {
            ShootingIntegrator::Rk4 { steps } => {
                let mut u_end = vec![0.0; n];
                Rk4 { steps: *steps }.integrate_final(&sys, s0, s1, &u0, &mut u_end)?;
                Ok(u_end)
            }
            ShootingIntegrator::Dop853(d) => {
                let d = Dop853 {
                    dense: false,
                    ..d.clone()
                };
                Ok(d.integrate(&sys, s0, s1, &u0)?.u_end)
            }
        }
    }
}

impl<P: ShootingProblem> NonlinearSystem for ShootingSystem<'_, P> {
    type Error = BvpError;
    fn n_unknowns(&self) -> usize {
        self.problem.n_params()
    }
    fn residual(&self, p: &[f64], r: &mut [f64]) -> Result<()> {
        let u_end = self.shoot(p)?;
        self.problem.residual(p, &u_end, r);
        if let Some(i) = r.iter().position(|v| !v.is_finite()) {
            return Err(BvpError::NonFinite {
                what: "shooting residual (s = component index)",
                s: i as f64,
            });
        }
        Ok(())
    }
}

impl Shooting {
    /// Solves `R(p) = 0` from the guess `p0` (see the module documentation).
    ///
    /// # Errors
    /// `NoConvergence { method: "trust-region", .. }` if the residual norm does not reach
    /// `options.tol`; integrator errors of a shot (`NonFinite`, `StepSizeUnderflow`, ...);
    /// `DimensionMismatch` if `p0.len() != n_params`.
    pub fn solve<P: ShootingProblem>(&self, problem: &P, p0: &[f64]) -> Result<ShootingSolution> {
        let sys = ShootingSystem {
            problem,
            integrator: &self.integrator,
        };
        let sol = trust_region::solve(&sys, p0, &self.options)?;
        let u_end = sys.shoot(&sol.x)?;
        Ok(ShootingSolution {
            params: sol.x,
            u_end,
            residual_norm: sol.residual_norm,
            iterations: sol.iterations,
        })
    }
}
