//! [`SquareNewton`]: a square non-linear system `r(x) = 0` of any size known only at run
//! time (a [`NonlinearSystem`] with `n_residuals == n_unknowns`), by a damped Newton method
//! that factors the Jacobian itself, with argmin's trust region as its fallback.
//!
//! One iteration (`J = dr/dx`, the system's Jacobian or forward differences):
//!
//! 1. the Newton step `J dx = -r` by faer's partially pivoted LU; where a pivot of `U` is
//!    below `n eps max|U|` (numerically singular `J`), the least-squares step of smallest
//!    norm on `J`'s numerical range instead: column-pivoted QR `J P = Q R` truncated to the
//!    rank `k` (`|R_kk| > n eps |R_00|`), `dx = P [R_11^-1 (Q^T (-r))_1; 0]`;
//! 2. damping: the trial `x + lambda dx`, `lambda = 1, 1/2, 1/4, ...` (at most
//!    [`SquareNewton::halvings`] halvings), is accepted where
//!    `|r(x + lambda dx)|_2 <= (1 - 1e-4 lambda) |r(x)|_2` (Armijo's test on the residual
//!    norm). A trial point whose residual fails to evaluate (the system's error) or is not
//!    finite is not an end: it only halves `lambda` ([`SquareNewtonAnswer::failed_trials`]);
//! 3. the Jacobian is evaluated again after a step that contracted the residual by less
//!    than [`SquareNewton::keep_below`] (simplified Newton: kept otherwise); a stale Jacobian
//!    whose step finds no descent is evaluated afresh before the iteration gives up.
//!
//! The iteration converges when `|r|_2 <= tol`. Where it stops without (no descent after
//! every halving, `max_iter` steps, a Jacobian that fails to evaluate or a zero step), the
//! trust region ([`trust_region::solve`]) continues from the best point, on a view of the
//! system in which a failed evaluation is a NaN residual (an infinite cost: the step is
//! rejected and the radius shrinks) rather than the end of the solve.
//!
//! ```
//! use bvp_solvers::nonlinear::SquareNewton;
//! use bvp_solvers::trust_region::NonlinearSystem;
//! use bvp_solvers::BvpError;
//!
//! /// Rosenbrock's function as a system: 10 (y - x^2) = 0, 1 - x = 0.
//! struct Rosenbrock;
//! impl NonlinearSystem for Rosenbrock {
//!     type Error = BvpError;
//!     fn n_unknowns(&self) -> usize { 2 }
//!     fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), BvpError> {
//!         r[0] = 10.0 * (x[1] - x[0] * x[0]);
//!         r[1] = 1.0 - x[0];
//!         Ok(())
//!     }
//! }
//! let out = SquareNewton::new(1e-12).solve(&Rosenbrock, &[-1.2, 1.0]).unwrap();
//! assert!((out.x[0] - 1.0).abs() < 1e-12 && (out.x[1] - 1.0).abs() < 1e-12);
//! ```

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use faer::linalg::solvers::Solve;
use faer::Mat;

use super::Solver;
use crate::trust_region::{self, forward_difference_jacobian, NonlinearSystem, TrustRegionOptions};
use crate::BvpError;

/// A damped Newton method for square systems of run-time size (module docs), with the
/// trust region as its fallback.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SquareNewton {
    /// Converged when `|r|_2 <= tol`.
    pub tol: f64,
    /// Newton steps at most.
    pub max_iter: usize,
    /// Halvings of the step per iteration at most.
    pub halvings: usize,
    /// The Jacobian is kept after a step with `|r_new| <= keep_below |r_old|`; 0 evaluates
    /// it at every step.
    pub keep_below: f64,
    /// The fallback where Newton stops short (`tol` is taken from [`SquareNewton::tol`]);
    /// `None`: Newton's failure is the answer.
    pub trust_region: Option<TrustRegionOptions>,
}

impl SquareNewton {
    /// `tol`, 100 steps, 30 halvings, a fresh Jacobian every step, the trust region's
    /// defaults as fallback.
    pub fn new(tol: f64) -> Self {
        SquareNewton {
            tol,
            max_iter: 100,
            halvings: 30,
            keep_below: 0.0,
            trust_region: Some(TrustRegionOptions {
                tol,
                ..TrustRegionOptions::default()
            }),
        }
    }
}

/// How the last linear step was solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct LinearSteps {
    /// Steps by the pivoted LU.
    pub lu: usize,
    /// Steps by the rank-truncated QR (a numerically singular Jacobian).
    pub qr: usize,
}

/// The solution of [`SquareNewton::solve`] with its cost.
#[derive(Clone, Debug, PartialEq)]
pub struct SquareNewtonAnswer {
    /// The solution `x`.
    pub x: Vec<f64>,
    /// `|r(x)|_2` (at most `tol`).
    pub residual_norm: f64,
    /// Newton iterations (steps taken), also where the trust region finished.
    pub iterations: usize,
    /// Trust-region iterations (0 where Newton answered).
    pub trust_region_iterations: usize,
    /// Residual evaluations of the Newton phase (trial points included, Jacobians not).
    pub evaluations: usize,
    /// Jacobian evaluations of the Newton phase.
    pub jacobians: usize,
    /// Trial points whose residual failed to evaluate or was not finite (each one halved
    /// the step).
    pub failed_trials: usize,
    /// The Newton steps by LU and by truncated QR.
    pub linear: LinearSteps,
    /// Which solver gave the answer.
    pub solver: Solver,
}

/// `|v|_2`.
fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Why Newton stopped short.
enum Stop {
    /// No descent, step budget, or a Jacobian that failed.
    Stalled,
    /// The Jacobian has no usable range (all of `R` below the cutoff): `row`, `pivot`.
    Singular(usize, f64),
}

/// Solves `J dx = b` (`J` row-major `n x n`): pivoted LU, or where `U` has a pivot below
/// `n eps max|U|` the rank-truncated column-pivoted QR least-squares step. Returns the step
/// and whether QR was used; `Err((row, pivot))` where `J` has numerical rank 0.
pub(crate) fn newton_step(
    n: usize,
    jac: &[f64],
    b: &[f64],
) -> Result<(Vec<f64>, bool), (usize, f64)> {
    let a = Mat::from_fn(n, n, |i, j| jac[i * n + j]);
    let rhs = Mat::from_fn(n, 1, |i, _| b[i]);
    let lu = a.partial_piv_lu();
    let u = lu.U();
    let big = (0..n)
        .flat_map(|i| (i..n).map(move |j| (i, j)))
        .map(|(i, j)| u[(i, j)].abs())
        .fold(0.0, f64::max);
    let cutoff = n as f64 * f64::EPSILON * big;
    let regular = big > 0.0 && (0..n).all(|i| u[(i, i)].abs() > cutoff);
    if regular {
        let x = lu.solve(&rhs);
        let dx: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
        if dx.iter().all(|v| v.is_finite()) {
            return Ok((dx, false));
        }
    }
    let qr = a.col_piv_qr();
    let r = qr.R();
    let r00 = r[(0, 0)].abs();
    let rank = (0..n)
        .take_while(|&k| r[(k, k)].abs() > n as f64 * f64::EPSILON * r00 && r00 > 0.0)
        .count();
    if rank == 0 {
        let row = (0..n)
            .min_by(|&i, &j| u[(i, i)].abs().total_cmp(&u[(j, j)].abs()))
            .unwrap_or(0);
        return Err((row, u[(row, row)]));
    }
    let q = qr.compute_Q();
    // c = Q^T b, then R_11 z = c_1 by back substitution
    let c: Vec<f64> = (0..rank)
        .map(|k| (0..n).map(|i| q[(i, k)] * b[i]).sum())
        .collect();
    let mut z = vec![0.0; rank];
    for k in (0..rank).rev() {
        let s: f64 = (k + 1..rank).map(|j| r[(k, j)] * z[j]).sum();
        z[k] = (c[k] - s) / r[(k, k)];
    }
    let (fwd, _) = qr.P().arrays();
    let mut dx = vec![0.0; n];
    for (k, zk) in z.iter().enumerate() {
        dx[fwd[k]] = *zk;
    }
    Ok((dx, true))
}

impl SquareNewton {
    /// Solves the square system `sys` from `x0` (module docs).
    ///
    /// # Errors
    /// `DimensionMismatch` for a non-square system or an `x0` of the wrong length;
    /// `InvalidInput` for a `tol` that is not positive; the system's own error where the
    /// residual fails at `x0`; where Newton stops short without a fallback,
    /// `SingularJacobian` (a Jacobian of numerical rank 0: its smallest pivot) or
    /// `NoConvergence { method: "square-newton", iterations, residual }` (the best residual
    /// reached); with the fallback, the trust region's `NoConvergence`.
    pub fn solve<S: NonlinearSystem>(
        &self,
        sys: &S,
        x0: &[f64],
    ) -> Result<SquareNewtonAnswer, S::Error> {
        let n = sys.n_unknowns();
        for (name, expected, found) in [
            ("residuals of a square system", n, sys.n_residuals()),
            ("start x0", n, x0.len()),
        ] {
            if expected != found {
                return Err(BvpError::DimensionMismatch {
                    name,
                    expected,
                    found,
                }
                .into());
            }
        }
        if !(self.tol > 0.0) {
            return Err(BvpError::InvalidInput {
                name: "tol",
                value: self.tol,
                reason: "the residual tolerance must be positive",
            }
            .into());
        }
        let mut out = SquareNewtonAnswer {
            x: x0.to_vec(),
            residual_norm: f64::NAN,
            iterations: 0,
            trust_region_iterations: 0,
            evaluations: 1,
            jacobians: 0,
            failed_trials: 0,
            linear: LinearSteps::default(),
            solver: Solver::Newton,
        };
        let mut r = vec![0.0; n];
        sys.residual(x0, &mut r)?;
        out.residual_norm = norm(&r);
        if !out.residual_norm.is_finite() {
            return Err(BvpError::NonFinite {
                what: "residual at the start x0 (s = iteration)",
                s: 0.0,
            }
            .into());
        }
        let stop = self.newton(sys, &mut out, &mut r);
        let Err(stop) = stop else {
            return Ok(out);
        };
        let Some(tr) = &self.trust_region else {
            return Err(match stop {
                Stop::Singular(row, pivot) => BvpError::SingularJacobian { row, pivot },
                Stop::Stalled => BvpError::NoConvergence {
                    method: "square-newton",
                    iterations: out.iterations,
                    residual: out.residual_norm,
                },
            }
            .into());
        };
        let tr = TrustRegionOptions {
            tol: self.tol,
            ..*tr
        };
        let sol = trust_region::solve(&Forgiving(sys), &out.x, &tr)?;
        out.x = sol.x;
        out.residual_norm = sol.residual_norm;
        out.trust_region_iterations = usize::try_from(sol.iterations).unwrap_or(usize::MAX);
        out.solver = Solver::TrustRegion;
        Ok(out)
    }

    /// The Newton phase: `out` holds the best point and `r` its residual throughout.
    fn newton<S: NonlinearSystem>(
        &self,
        sys: &S,
        out: &mut SquareNewtonAnswer,
        r: &mut [f64],
    ) -> Result<(), Stop> {
        let n = r.len();
        let mut jac = vec![0.0; n * n];
        let mut stale = true; // no Jacobian yet
        let mut fresh = false;
        let mut trial = vec![0.0; n];
        let mut rt = vec![0.0; n];
        loop {
            if out.residual_norm <= self.tol {
                return Ok(());
            }
            if out.iterations >= self.max_iter {
                return Err(Stop::Stalled);
            }
            if stale {
                out.jacobians += 1;
                if sys.jacobian(&out.x, &mut jac).is_err() || jac.iter().any(|v| !v.is_finite()) {
                    return Err(Stop::Stalled);
                }
                fresh = true;
            }
            let b: Vec<f64> = r.iter().map(|v| -v).collect();
            let (dx, by_qr) = newton_step(n, &jac, &b).map_err(|(i, p)| Stop::Singular(i, p))?;
            if by_qr {
                out.linear.qr += 1;
            } else {
                out.linear.lu += 1;
            }
            let mut lambda = 1.0;
            let mut accepted = None;
            for _ in 0..=self.halvings {
                for ((t, x), d) in trial.iter_mut().zip(&out.x).zip(&dx) {
                    *t = x + lambda * d;
                }
                out.evaluations += 1;
                let ok = sys.residual(&trial, &mut rt).is_ok();
                let nt = norm(&rt);
                if !ok || !nt.is_finite() {
                    out.failed_trials += 1;
                } else if nt <= (1.0 - 1e-4 * lambda) * out.residual_norm {
                    accepted = Some(nt);
                    break;
                }
                lambda *= 0.5;
            }
            let Some(nt) = accepted else {
                if fresh {
                    return Err(Stop::Stalled);
                }
                // a kept Jacobian that finds no descent: evaluate it afresh first
                stale = true;
                continue;
            };
            stale = nt > self.keep_below * out.residual_norm;
            fresh = false;
            out.x.copy_from_slice(&trial);
            r.copy_from_slice(&rt);
            out.residual_norm = nt;
            out.iterations += 1;
        }
    }
}

/// The system seen by the fallback: a failed or non-finite residual is a NaN residual (an
/// infinite cost), so that the trust region shrinks its radius instead of ending.
struct Forgiving<'a, S>(&'a S);

impl<S: NonlinearSystem> NonlinearSystem for Forgiving<'_, S> {
    type Error = S::Error;

    fn n_unknowns(&self) -> usize {
        self.0.n_unknowns()
    }

    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), S::Error> {
        if self.0.residual(x, r).is_err() {
            r.fill(f64::NAN);
        }
        Ok(())
    }

    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> Result<(), S::Error> {
        match self.0.jacobian(x, jac) {
            Ok(()) => Ok(()),
            Err(_) => forward_difference_jacobian(self, x, jac),
        }
    }
}

#[cfg(test)]
mod tests;
