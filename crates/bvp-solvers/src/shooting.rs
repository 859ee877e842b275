//! Shooting for two-point boundary-value problems: parameters `p` (unknown initial values,
//! free parameters) are found so that the boundary residuals at the end of the span vanish,
//!
//! `R(p) = residual(p, u(s1; p)) = 0`, where `u' = G_p(s, u)`, `u(s0) = u0(p)`.
//!
//! Two drivers:
//! - [`solve_shooting`], the one the domain runs: the problem shoots itself and returns the
//!   end state with its sensitivities `d u_end / d p` (variational equations integrated
//!   along, [`ShotProblem`]); Newton ([`crate::newton::newton_guarded`]) with that exact
//!   Jacobian, one shot per step, under any [`NewtonPolicy`] and [`Safeguards`].
//! - [`Shooting`], for a problem posed as a bare ODE without variational equations
//!   ([`ShootingProblem`]): the trust-region method of [`crate::trust_region`] with a
//!   forward-difference Jacobian of `R` (each column costs one integration); robust from far
//!   guesses, but its Jacobian is only as accurate as `sqrt` of the shot's noise.

use crate::integrator::{Dop853, OdeSystem, Rk4};
use crate::newton::{
    newton_guarded, Evaluation, NewtonAnswer, NewtonPolicy, NewtonSystem, Safeguards,
};
use crate::nonlinear::SquareNewton;
use crate::trust_region::{self, NonlinearSystem, TrustRegionOptions};
use crate::{BvpError, Result};

/// A boundary-value problem posed for shooting as a bare ODE (no sensitivities): solved by
/// [`Shooting`] with a forward-difference Jacobian.
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

/// A boundary-value problem posed for shooting with analytic sensitivities: a shot with the
/// parameters `p` reaches an end state (whatever the problem integrates: the state at the
/// far end, with its derivatives `d u_end / d p` from the variational equations
/// `U' = (dG/du) U + dG/dp`, `U(s0) = d u0 / d p`, integrated along when asked for), and
/// the boundary residuals `R(p, u_end)` vanish at the solution. [`solve_shooting`] finds
/// `p` by [`newton_guarded`] with the exact Jacobian `dR/dp = dR/du_end U(s1) + dR/dp`
/// that [`ShotProblem::residual_jacobian`] assembles, one shot per Newton step.
///
/// ```
/// use bvp_solvers::integrator::{Dop853, OdeSystem};
/// use bvp_solvers::newton::{NewtonPolicy, Safeguards, Termination};
/// use bvp_solvers::shooting::{solve_shooting, ShotProblem};
///
/// /// y'' = -y, y(0) = 0, y(pi/2) = 1 (solution sin s): unknown slope p = y'(0); with the
/// /// variational equation of (y, y') in p alongside.
/// struct Sine;
/// struct Rhs;
/// impl OdeSystem for Rhs {
///     fn dim(&self) -> usize { 4 }
///     fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
///         du[0] = u[1];
///         du[1] = -u[0];
///         du[2] = u[3];
///         du[3] = -u[2];
///     }
/// }
/// impl ShotProblem<1> for Sine {
///     type End = Vec<f64>;
///     type Error = bvp_solvers::BvpError;
///     fn shoot(&self, p: &[f64; 1], _sensitivities: bool) -> Result<Vec<f64>, Self::Error> {
///         let end = std::f64::consts::FRAC_PI_2;
///         Ok(Dop853::new(1e-12, 1e-12).integrate(&Rhs, 0.0, end, &[0.0, p[0], 0.0, 1.0])?.u_end)
///     }
///     fn residual(&self, _p: &[f64; 1], u: &Vec<f64>) -> [f64; 1] {
///         [u[0] - 1.0]
///     }
///     fn residual_jacobian(&self, _p: &[f64; 1], u: &Vec<f64>) -> Option<[[f64; 1]; 1]> {
///         Some([[u[2]]])
///     }
/// }
///
/// let out = solve_shooting(&Sine, [0.3], &NewtonPolicy::new(1e-10), &Safeguards::NONE);
/// let out = out.unwrap();
/// assert_eq!(out.termination, Termination::Converged);
/// assert!((out.u[0] - 1.0).abs() < 1e-8);
/// ```
pub trait ShotProblem<const N: usize> {
    /// What a shot reaches: the end state, with its sensitivities when asked for.
    type End;
    /// The error of a shot.
    type Error;

    /// One shot with the parameters `p`; with the sensitivities `d u_end / d p` (the
    /// variational equations integrated along) if `sensitivities` is set (a problem may
    /// always integrate them).
    ///
    /// # Errors
    /// Whatever keeps the shot from reaching the end (an integrator error); at a Newton
    /// trial it only rejects the step.
    fn shoot(
        &self,
        p: &[f64; N],
        sensitivities: bool,
    ) -> std::result::Result<Self::End, Self::Error>;

    /// The boundary residuals `R(p, u_end)`.
    fn residual(&self, p: &[f64; N], end: &Self::End) -> [f64; N];

    /// `dR/dp` by the chain rule through the shot's sensitivities; `None` when the shot
    /// carries none.
    fn residual_jacobian(&self, p: &[f64; N], end: &Self::End) -> Option<[[f64; N]; N]>;

    /// The residual's scale at an end state ([`NewtonSystem::scale`]; default 1).
    fn scale(&self, _end: &Self::End) -> f64 {
        1.0
    }
}

/// A [`ShotProblem`] as the [`NewtonSystem`] of its parameters.
struct ShotSystem<'a, P>(&'a P);

impl<const N: usize, P: ShotProblem<N>> NewtonSystem<N> for ShotSystem<'_, P> {
    type Point = P::End;
    type Error = P::Error;

    fn eval(
        &self,
        p: &[f64; N],
        jacobian: bool,
    ) -> std::result::Result<Evaluation<N, P::End>, P::Error> {
        let end = self.0.shoot(p, jacobian)?;
        Ok(Evaluation {
            r: self.0.residual(p, &end),
            jac: self.0.residual_jacobian(p, &end),
            point: end,
        })
    }

    fn scale(&self, end: &P::End) -> f64 {
        self.0.scale(end)
    }
}

/// Shooting with analytic sensitivities: the parameters of `problem` from `p0` by
/// [`newton_guarded`] under `policy` and `guards`, one shot per evaluation; the answer's
/// point is the last shot's end state.
///
/// # Errors
/// A shot's error at `p0` (or where only a Jacobian is evaluated, [`crate::newton::newton`]'s
/// rules).
pub fn solve_shooting<const N: usize, P: ShotProblem<N>>(
    problem: &P,
    p0: [f64; N],
    policy: &NewtonPolicy,
    guards: &Safeguards,
) -> std::result::Result<NewtonAnswer<N, P::End>, P::Error> {
    newton_guarded(&ShotSystem(problem), p0, None, policy, guards)
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
///
/// A free parameter in the equation: the first eigenvalue of `y'' + lambda y = 0`,
/// `y(0) = y(1) = 0`, normalised by `y'(0) = 1`, is `lambda = pi^2` (`y = sin(pi s) / pi`);
/// the unknown `lambda` enters the right-hand side, the residual is `y(1)`.
///
/// ```
/// use bvp_solvers::integrator::{Dop853, OdeSystem};
/// use bvp_solvers::shooting::{Shooting, ShootingIntegrator, ShootingProblem};
/// use bvp_solvers::trust_region::TrustRegionOptions;
///
/// struct Mode(f64);
/// impl OdeSystem for Mode {
///     fn dim(&self) -> usize { 2 }
///     fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
///         du[0] = u[1];
///         du[1] = -self.0 * u[0];
///     }
/// }
/// struct Eigen;
/// impl ShootingProblem for Eigen {
///     type System = Mode;
///     fn n_params(&self) -> usize { 1 }
///     fn system(&self, p: &[f64]) -> Mode { Mode(p[0]) }
///     fn span(&self, _p: &[f64]) -> (f64, f64) { (0.0, 1.0) }
///     fn initial_state(&self, _p: &[f64], u0: &mut [f64]) {
///         u0[0] = 0.0;
///         u0[1] = 1.0;
///     }
///     fn residual(&self, _p: &[f64], u_end: &[f64], r: &mut [f64]) {
///         r[0] = u_end[0];
///     }
/// }
///
/// let shooting = Shooting {
///     integrator: ShootingIntegrator::Dop853(Dop853::new(1e-13, 1e-13)),
///     options: TrustRegionOptions { tol: 1e-12, ..TrustRegionOptions::default() },
/// };
/// let sol = shooting.solve(&Eigen, &[8.0]).unwrap();
/// let pi2 = std::f64::consts::PI.powi(2);
/// assert!((sol.params[0] - pi2).abs() < 1e-8, "{}", sol.params[0]);
/// // y'(1) = cos(pi) = -1
/// assert!((sol.u_end[1] + 1.0).abs() < 1e-9);
/// ```
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

    /// Solves `R(p) = 0` from `p0` by the square Newton method `newton`
    /// ([`SquareNewton`]: pivoted LU of the forward-difference Jacobian of `R`, a shot that
    /// fails at a trial point halves the step, the trust region as its fallback), instead of
    /// the trust region alone ([`Shooting::solve`], whose results this leaves unchanged);
    /// `self.options` is not used. `iterations` counts Newton's and the fallback's.
    ///
    /// # Errors
    /// As [`SquareNewton::solve`]: a shot's error at `p0`; `NoConvergence` (method
    /// `"square-newton"` without a fallback, else the trust region's); `DimensionMismatch`
    /// if `p0.len() != n_params`.
    pub fn solve_newton<P: ShootingProblem>(
        &self,
        problem: &P,
        p0: &[f64],
        newton: &SquareNewton,
    ) -> Result<ShootingSolution> {
        let sys = ShootingSystem {
            problem,
            integrator: &self.integrator,
        };
        let sol = newton.solve(&sys, p0)?;
        let u_end = sys.shoot(&sol.x)?;
        Ok(ShootingSolution {
            params: sol.x,
            u_end,
            residual_norm: sol.residual_norm,
            iterations: (sol.iterations + sol.trust_region_iterations) as u64,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::newton::Termination;
    use crate::testing::Harmonic;

    /// `y'' = -y`, `y(0) = 1`, `y(1) = 2`; unknown `p = y'(0)`. Exact: `y = cos x + B sin x`,
    /// `B = (2 - cos 1) / sin 1`.
    struct LinearBvp;

    impl ShootingProblem for LinearBvp {
        type System = Harmonic;
        fn n_params(&self) -> usize {
            1
        }
        fn system(&self, _p: &[f64]) -> Harmonic {
            Harmonic
        }
        fn span(&self, _p: &[f64]) -> (f64, f64) {
            (0.0, 1.0)
        }
        fn initial_state(&self, p: &[f64], u0: &mut [f64]) {
            u0[0] = 1.0;
            u0[1] = p[0];
        }
        fn residual(&self, _p: &[f64], u_end: &[f64], r: &mut [f64]) {
            r[0] = u_end[0] - 2.0;
        }
    }

    fn b() -> f64 {
        (2.0 - 1f64.cos()) / 1f64.sin()
    }

    fn shooting(integrator: ShootingIntegrator) -> Shooting {
        let options = TrustRegionOptions {
            tol: 1e-12,
            max_iters: 100,
            ..TrustRegionOptions::default()
        };
        Shooting {
            integrator,
            options,
        }
    }

    #[test]
    fn linear_bvp_closed_form() {
        let b = b();
        let dop = shooting(ShootingIntegrator::Dop853(Dop853::new(1e-13, 1e-13)));
        let sol = dop.solve(&LinearBvp, &[0.0]).unwrap();
        assert!((sol.params[0] - b).abs() < 1e-10, "{}", sol.params[0] - b);
        assert!((sol.u_end[1] - (-1f64.sin() + b * 1f64.cos())).abs() < 1e-10);
        // RK4 with 100 steps: O(h^4) ~ 1e-9
        let rk = shooting(ShootingIntegrator::Rk4 { steps: 100 });
        let sol = rk.solve(&LinearBvp, &[0.0]).unwrap();
        assert!((sol.params[0] - b).abs() < 1e-8, "{}", sol.params[0] - b);
        assert!((sol.params[0] - b).abs() > 1e-14); // really the RK4 discretisation
                                                    // one parameter, two given
        assert!(matches!(
            dop.solve(&LinearBvp, &[0.0, 1.0]),
            Err(BvpError::DimensionMismatch { .. })
        ));
    }

    /// The square Newton on the same problem: the answer of the trust region within the
    /// shot's noise, in no more iterations.
    #[test]
    fn square_newton_shooting_agrees_with_the_closed_form() {
        let b = b();
        let dop = shooting(ShootingIntegrator::Dop853(Dop853::new(1e-13, 1e-13)));
        let sol = dop
            .solve_newton(&LinearBvp, &[0.0], &SquareNewton::new(1e-12))
            .unwrap();
        assert!((sol.params[0] - b).abs() < 1e-10, "{}", sol.params[0] - b);
        let tr = dop.solve(&LinearBvp, &[0.0]).unwrap();
        assert!((sol.params[0] - tr.params[0]).abs() < 1e-10);
        assert!(
            sol.iterations <= tr.iterations,
            "{} > {}",
            sol.iterations,
            tr.iterations
        );
        assert!(matches!(
            dop.solve_newton(&LinearBvp, &[0.0, 1.0], &SquareNewton::new(1e-12)),
            Err(BvpError::DimensionMismatch { .. })
        ));
    }

    /// `y' = y^2`, `y(0) = p`, `y(1/2) = 1`: `y = p / (1 - p s)`, root `p = 2/3`. From
    /// `p = -3` the full Newton step lands at `p = 10.75`, whose shot blows up at
    /// `s = 0.093` (an integrator error): the failed trials halve the step and Newton
    /// reaches `2/3`.
    struct BlowUp;
    struct Square;
    impl OdeSystem for Square {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
            du[0] = u[0] * u[0];
        }
    }
    impl ShootingProblem for BlowUp {
        type System = Square;
        fn n_params(&self) -> usize {
            1
        }
        fn system(&self, _p: &[f64]) -> Square {
            Square
        }
        fn span(&self, _p: &[f64]) -> (f64, f64) {
            (0.0, 0.5)
        }
        fn initial_state(&self, p: &[f64], u0: &mut [f64]) {
            u0[0] = p[0];
        }
        fn residual(&self, _p: &[f64], u_end: &[f64], r: &mut [f64]) {
            r[0] = u_end[0] - 1.0;
        }
    }

    #[test]
    fn a_shot_that_fails_at_a_trial_only_shrinks_the_newton_step() {
        let dop = shooting(ShootingIntegrator::Dop853(Dop853 {
            max_steps: 2000,
            ..Dop853::new(1e-12, 1e-12)
        }));
        assert!(dop.shooting_fails_at(&BlowUp, 10.75));
        let newton = SquareNewton {
            trust_region: None,
            ..SquareNewton::new(1e-11)
        };
        let sol = dop.solve_newton(&BlowUp, &[-3.0], &newton).unwrap();
        assert!(
            (sol.params[0] - 2.0 / 3.0).abs() < 1e-9,
            "{}",
            sol.params[0]
        );
    }

    impl Shooting {
        fn shooting_fails_at<P: ShootingProblem>(&self, problem: &P, p: f64) -> bool {
            let sys = ShootingSystem {
                problem,
                integrator: &self.integrator,
            };
            sys.shoot(&[p]).is_err()
        }
    }

    /// The same problem with its sensitivity `v = dy/dp` (`v'' = -v`, `v(0) = 0`,
    /// `v'(0) = 1`: `v(1) = sin 1`) for [`solve_shooting`]: the residual is linear in `p`,
    /// so one Newton step lands on `B`.
    struct LinearShot;

    impl ShotProblem<1> for LinearShot {
        type End = [f64; 2];
        type Error = BvpError;
        fn shoot(&self, p: &[f64; 1], _sensitivities: bool) -> Result<[f64; 2]> {
            // (y, y') and (v, v') are both solutions of the harmonic system: closed forms
            let y1 = 1f64.cos() + p[0] * 1f64.sin();
            Ok([y1, 1f64.sin()])
        }
        fn residual(&self, _p: &[f64; 1], end: &[f64; 2]) -> [f64; 1] {
            [end[0] - 2.0]
        }
        fn residual_jacobian(&self, _p: &[f64; 1], end: &[f64; 2]) -> Option<[[f64; 1]; 1]> {
            Some([[end[1]]])
        }
    }

    #[test]
    fn newton_with_exact_sensitivities_solves_a_linear_shot_in_one_step() {
        let out = solve_shooting(
            &LinearShot,
            [0.0],
            &NewtonPolicy::new(1e-12),
            &Safeguards::NONE,
        )
        .unwrap();
        assert_eq!(out.termination, Termination::Converged);
        assert_eq!(out.iterations, 1);
        assert!((out.u[0] - b()).abs() < 1e-14, "{}", out.u[0] - b());
        assert!((out.point[0] - 2.0).abs() < 1e-14);
    }
}
