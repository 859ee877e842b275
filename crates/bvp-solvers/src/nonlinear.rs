//! One interface for small non-linear systems `r(x) = 0` of `M` equations in `N <= M`
//! unknowns (the `fsolve` equivalent): the one Newton
//! ([`gauss_newton`]: Newton's step `J dx = r` for `M = N`, the
//! normal equations `J^T J dx = J^T r` for `M > N`) under its [`NewtonPolicy`] is the fast
//! path; argmin's trust region ([`trust_region::solve`], globalised) is the fallback, from
//! the same start, where Newton does not reach a solution. The answer says which one solved
//! the system and why it stopped ([`Termination`]).
//!
//! Two entry points: [`solve`] for a [`NonlinearSystem`] of any shape (Gauss-Newton's step),
//! and [`solve_square`] for a square [`NewtonSystem`] that carries a point of its own (the
//! domain's state at the solution), may start from a known Jacobian (Broyden's method first,
//! [`NonlinearOptions::start`]) and may rule trial points out
//! ([`NewtonSystem::admissible`]); its Newton path is
//! [`newton`](crate::newton::newton)'s, step for step.
//!
//! ```
//! use bvp_solvers::nonlinear::{solve, NonlinearOptions, Solver};
//! use bvp_solvers::trust_region::NonlinearSystem;
//! use bvp_solvers::BvpError;
//!
//! /// The circle `x^2 + y^2 = 4` meets the line `y = x`.
//! struct Meet;
//! impl NonlinearSystem for Meet {
//!     type Error = BvpError;
//!     fn n_unknowns(&self) -> usize { 2 }
//!     fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), BvpError> {
//!         r[0] = x[0] * x[0] + x[1] * x[1] - 4.0;
//!         r[1] = x[1] - x[0];
//!         Ok(())
//!     }
//! }
//! let out = solve::<2, 2, _>(&Meet, &[1.0, 2.0], &NonlinearOptions::new(1e-12)).unwrap();
//! assert_eq!(out.solver, Solver::Newton);
//! assert!((out.x[0] - 2f64.sqrt()).abs() < 1e-12);
//! ```

use crate::newton::{gauss_newton, Evaluation, NewtonPolicy, NewtonSystem, Termination};
use crate::trust_region::{self, NonlinearSystem, TrustRegionOptions};
use crate::BvpError;

mod square;
mod square_newton;
pub use square::{solve_square, SquareReport};
pub use square_newton::{LinearSteps, SquareNewton, SquareNewtonAnswer};

/// Options of [`solve`] and [`solve_square`]: the fast path's policies and the fallback's
/// options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonlinearOptions {
    /// With a start Jacobian ([`solve_square`] only): this policy first, from it (typically
    /// Broyden's method with full steps, [`crate::newton::JacobianUpdate::Broyden`]); `newton`
    /// runs only where it does not reach a solution. Ignored without a start Jacobian.
    pub start: Option<NewtonPolicy>,
    /// Newton (Gauss-Newton for `M > N`) under this policy, with a Jacobian evaluated at
    /// the start; `None` skips it (the trust region alone for systems on which Newton cannot
    /// succeed: a least-squares minimum above the tolerance, or evaluations that carry state
    /// from one to the next).
    pub newton: Option<NewtonPolicy>,
    /// The trust region where the Newton path does not reach a solution; `None` for no
    /// fallback (where a failure is itself the answer: a continuation corrector whose failure
    /// shortens the step, or a fast attempt the caller follows up itself).
    pub trust_region: Option<TrustRegionOptions>,
}

impl NonlinearOptions {
    /// Residual norm `tol` for both: [`NewtonPolicy::new`] and the trust region's defaults;
    /// no start policy.
    pub fn new(tol: f64) -> Self {
        NonlinearOptions {
            start: None,
            newton: Some(NewtonPolicy::new(tol)),
            trust_region: Some(TrustRegionOptions {
                tol,
                ..TrustRegionOptions::default()
            }),
        }
    }
}

/// Which solver gave the answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// The Newton fast path.
    Newton,
    /// The trust-region fallback.
    TrustRegion,
}

/// A solution of [`solve`].
#[derive(Clone, Debug, PartialEq)]
pub struct NonlinearAnswer {
    /// The solution `x`.
    pub x: Vec<f64>,
    /// `|r(x)|_2`.
    pub residual_norm: f64,
    /// Iterations of the solver that gave the answer.
    pub iterations: usize,
    /// Newton iterations spent before a fallback (0 when Newton gave the answer or did not
    /// run).
    pub newton_iterations: usize,
    /// The solver that gave the answer.
    pub solver: Solver,
    /// Why it stopped: [`Termination::Converged`] or [`Termination::NoiseFloor`].
    pub termination: Termination,
}

/// A [`NonlinearSystem`] seen by [`newton`](crate::newton) with `N` unknowns and `M`
/// equations.
struct AsNewton<'a, S>(&'a S);

impl<const N: usize, const M: usize, S: NonlinearSystem> NewtonSystem<N, M> for AsNewton<'_, S> {
    type Point = ();
    type Error = S::Error;

    fn eval(&self, u: &[f64; N], jacobian: bool) -> Result<Evaluation<N, (), M>, S::Error> {
        let mut r = [0.0; M];
        self.0.residual(u, &mut r)?;
        let jac = if jacobian {
            let mut j = vec![0.0; M * N];
            self.0.jacobian(u, &mut j)?;
            Some(std::array::from_fn(|i| {
                std::array::from_fn(|k| j[i * N + k])
            }))
        } else {
            None
        };
        Ok(Evaluation { r, jac, point: () })
    }
}

/// Solves `sys` (`N` unknowns, `M >= N` residuals) from `x0`: Newton under `opts.newton`
/// (module docs), and where it ends without a solution (or its evaluations fail), the trust
/// region from `x0` under `opts.trust_region` (`opts.start` does not apply: no start
/// Jacobian).
///
/// # Errors
/// `DimensionMismatch` if `N`, `M` or `x0` do not fit `sys`; `InvalidInput` if neither
/// solver is configured; `NoConvergence` (method `"newton"`, the residual reached) where
/// Newton fails without a fallback; otherwise the trust region's errors
/// ([`trust_region::solve`]: `NoConvergence` with the best residual, or the system's own
/// error).
pub fn solve<const N: usize, const M: usize, S: NonlinearSystem>(
    sys: &S,
    x0: &[f64],
    opts: &NonlinearOptions,
) -> Result<NonlinearAnswer, S::Error> {
    for (name, expected, found) in [
        ("unknowns", sys.n_unknowns(), N),
        ("residuals", sys.n_residuals(), M),
        ("start x0", N, x0.len()),
    ] {
        if expected != found || M < N {
            return Err(BvpError::DimensionMismatch {
                name,
                expected,
                found,
            }
            .into());
        }
    }
    let mut newton_iterations = 0;
    let mut newton_residual = f64::NAN;
    if let Some(policy) = &opts.newton {
        let u0: [f64; N] = std::array::from_fn(|i| x0[i]);
        if let Ok(a) = gauss_newton(&AsNewton(sys), u0, None::<[[f64; N]; M]>, policy) {
            if a.termination.is_solution() {
                return Ok(NonlinearAnswer {
                    x: a.u.to_vec(),
                    residual_norm: a.norm,
                    iterations: a.iterations,
                    newton_iterations: 0,
                    solver: Solver::Newton,
                    termination: a.termination,
                });
            }
            newton_iterations = a.iterations;
            newton_residual = a.norm;
        }
    }
    let Some(tr) = &opts.trust_region else {
        return Err(match opts.newton {
            Some(_) => BvpError::NoConvergence {
                method: "newton",
                iterations: newton_iterations,
                residual: newton_residual,
            },
            None => neither(),
        }
        .into());
    };
    let sol = trust_region::solve(sys, x0, tr)?;
    Ok(NonlinearAnswer {
        x: sol.x,
        residual_norm: sol.residual_norm,
        iterations: usize::try_from(sol.iterations).unwrap_or(usize::MAX),
        newton_iterations,
        solver: Solver::TrustRegion,
        termination: Termination::Converged,
    })
}

/// The error of options without a solver.
fn neither() -> BvpError {
    BvpError::InvalidInput {
        name: "NonlinearOptions",
        value: f64::NAN,
        reason: "needs a Newton policy or a trust region",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    /// `r = (x^2 + y^2 - 4, y - x)` (and, with `extra`, `x + y - extra`): counts residuals.
    struct Meet {
        extra: Option<f64>,
        calls: Cell<usize>,
    }

    impl NonlinearSystem for Meet {
        type Error = BvpError;
        fn n_unknowns(&self) -> usize {
            2
        }
        fn n_residuals(&self) -> usize {
            2 + usize::from(self.extra.is_some())
        }
        fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), BvpError> {
            self.calls.set(self.calls.get() + 1);
            r[0] = x[0] * x[0] + x[1] * x[1] - 4.0;
            r[1] = x[1] - x[0];
            if let Some(c) = self.extra {
                r[2] = x[0] + x[1] - c;
            }
            Ok(())
        }
    }

    fn meet(extra: Option<f64>) -> Meet {
        Meet {
            extra,
            calls: Cell::new(0),
        }
    }

    #[test]
    fn newton_is_the_fast_path() {
        let sys = meet(None);
        let out = solve::<2, 2, _>(&sys, &[1.0, 2.0], &NonlinearOptions::new(1e-12)).unwrap();
        assert_eq!(
            (out.solver, out.termination),
            (Solver::Newton, Termination::Converged)
        );
        assert!(out.residual_norm <= 1e-12 && out.iterations <= 6);
        let s2 = 2f64.sqrt();
        assert!((out.x[0] - s2).abs() < 1e-12 && (out.x[1] - s2).abs() < 1e-12);
        // a consistent overdetermined system: Gauss-Newton
        let out = solve::<2, 3, _>(
            &meet(Some(2.0 * s2)),
            &[1.0, 2.0],
            &NonlinearOptions::new(1e-12),
        );
        assert_eq!(out.unwrap().solver, Solver::Newton);
    }

    #[test]
    fn the_trust_region_takes_over_where_newton_stops_short() {
        // one Newton step is not enough from far away: the trust region solves it
        let opts = NonlinearOptions {
            newton: Some(NewtonPolicy {
                max_iter: 1,
                ..NewtonPolicy::new(1e-12)
            }),
            ..NonlinearOptions::new(1e-12)
        };
        let out = solve::<2, 2, _>(&meet(None), &[5.0, -3.0], &opts).unwrap();
        assert_eq!(out.solver, Solver::TrustRegion);
        assert_eq!(out.newton_iterations, 1);
        assert!(out.residual_norm <= 1e-12);
        // without the fast path the trust region alone, as `trust_region::solve`
        let tr_only = NonlinearOptions {
            newton: None,
            ..opts
        };
        let (a, b) = (meet(None), meet(None));
        let out = solve::<2, 2, _>(&a, &[5.0, -3.0], &tr_only).unwrap();
        let tr = tr_only.trust_region.unwrap();
        let direct = trust_region::solve(&b, &[5.0, -3.0], &tr).unwrap();
        assert_eq!(out.solver, Solver::TrustRegion);
        assert_eq!(out.x, direct.x);
        assert_eq!(a.calls.get(), b.calls.get());
    }

    #[test]
    fn an_inconsistent_system_fails_with_the_trust_regions_error() {
        // the line x + y = 0 misses the meeting points: no solution
        let out = solve::<2, 3, _>(&meet(Some(0.0)), &[1.0, 2.0], &NonlinearOptions::new(1e-12));
        assert!(
            matches!(out, Err(BvpError::NoConvergence { .. })),
            "{out:?}"
        );
        // wrong dimensions
        let out = solve::<3, 3, _>(&meet(None), &[1.0, 2.0], &NonlinearOptions::new(1e-12));
        assert!(matches!(out, Err(BvpError::DimensionMismatch { .. })));
        let out = solve::<2, 2, _>(&meet(None), &[1.0], &NonlinearOptions::new(1e-12));
        assert!(matches!(out, Err(BvpError::DimensionMismatch { .. })));
    }
}
