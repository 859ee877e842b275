//! [`solve_square`]: the one interface for a square [`NewtonSystem`] that carries a point of
//! its own: the Newton path (a start stage from a known Jacobian, then Newton), with the
//! trust region from the same start where it does not reach a solution.

use super::{neither, NonlinearOptions, Solver};
use crate::newton::{newton, NewtonAnswer, NewtonPolicy, NewtonSystem, Termination};
use crate::trust_region::{self, forward_difference_jacobian, NonlinearSystem, TrustRegionOptions};
use crate::BvpError;

/// How [`solve_square`] reached its result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SquareReport {
    /// The solver that gave the result.
    pub solver: Solver,
    /// Newton iterations spent before the stage that gave the result (the start stage's
    /// before `newton`'s, all of them before the trust region's).
    pub newton_iterations: usize,
}

impl Default for SquareReport {
    /// The Newton path, no iterations.
    fn default() -> Self {
        SquareReport {
            solver: Solver::Newton,
            newton_iterations: 0,
        }
    }
}

/// Solves the square system `sys` from `u0` through the Newton path, then the fallback:
///
/// 1. with a start Jacobian `jac0` and `opts.start`: [`newton`] from `u0` with `jac0` under
///    that policy (its evaluation errors only end the stage);
/// 2. `opts.newton`: [`newton`] from `u0`, with a Jacobian evaluated there;
/// 3. `opts.trust_region`: [`trust_region::solve`] from `u0`, where no stage reached a
///    solution. Its trial points are those of the Newton path's rules: an inadmissible point
///    ([`NewtonSystem::admissible`]) or one that fails to evaluate is not evaluated further
///    and counts as infinitely bad (the step is rejected, the radius shrinks). At its
///    solution the system is evaluated once more, with a Jacobian where the Newton policy
///    wants one at the solution, for the answer's point (iterations: the trust region's).
///    Its tolerance is absolute ([`NewtonSystem::scale`] does not apply).
///
/// A stage that reaches a solution ([`Termination::is_solution`]) gives the answer; where
/// the stages run are the same, the answer is [`newton`]'s, bit for bit. Where no solver
/// reaches a solution the answer is the Newton path's last (its best point, its residual,
/// and why it stopped). `report` says which solver gave it; it is written, not returned, so
/// that the last stage's answer reaches the caller as it comes, uncopied (the contact sweep
/// calls this in its hot loop).
///
/// # Errors
/// `InvalidInput` if no stage can run; the last Newton stage's evaluation errors
/// ([`newton`]) where the fallback does not rescue it; the trust region's error where it
/// ran alone and failed.
pub fn solve_square<const N: usize, S>(
    sys: &S,
    u0: [f64; N],
    jac0: Option<[[f64; N]; N]>,
    opts: &NonlinearOptions,
    report: &mut SquareReport,
) -> Result<NewtonAnswer<N, S::Point>, S::Error>
where
    S: NewtonSystem<N>,
    S::Error: std::error::Error + From<BvpError> + Send + Sync + 'static,
{
    *report = SquareReport::default();
    let Some(tr) = &opts.trust_region else {
        return newton_path(sys, u0, jac0, opts, report);
    };
    let mut last = None;
    let mut spent = 0;
    for (policy, jac) in [
        (opts.start.filter(|_| jac0.is_some()), jac0),
        (opts.newton, None),
    ] {
        let Some(policy) = policy else { continue };
        report.newton_iterations = spent;
        let result = newton(sys, u0, jac, &policy);
        if result.as_ref().is_ok_and(|a| a.termination.is_solution()) {
            return result;
        }
        spent += result.as_ref().map_or(0, |a| a.iterations);
        last = Some(result);
    }
    let policy = opts.newton.or(opts.start);
    let jacobian = policy.is_none_or(|p: NewtonPolicy| p.jacobian_at_solution);
    match (rescue(sys, &u0, tr, jacobian), last) {
        (Err(_), Some(result)) => result,
        (rescued, _) => {
            *report = SquareReport {
                solver: Solver::TrustRegion,
                newton_iterations: spent,
            };
            rescued
        }
    }
}

/// [`solve_square`] without a fallback: the start stage (if it applies), then `opts.newton`
/// where it does not reach a solution; the last stage's outcome as it comes.
fn newton_path<const N: usize, S: NewtonSystem<N>>(
    sys: &S,
    u0: [f64; N],
    jac0: Option<[[f64; N]; N]>,
    opts: &NonlinearOptions,
    report: &mut SquareReport,
) -> Result<NewtonAnswer<N, S::Point>, S::Error>
where
    S::Error: From<BvpError>,
{
    if let (Some(policy), true) = (&opts.start, jac0.is_some()) {
        let Some(next) = &opts.newton else {
            return newton(sys, u0, jac0, policy);
        };
        match newton(sys, u0, jac0, policy) {
            Ok(a) if a.termination.is_solution() => return Ok(a),
            Ok(a) => report.newton_iterations = a.iterations,
            Err(_) => {}
        }
        return newton(sys, u0, None, next);
    }
    match &opts.newton {
        Some(policy) => newton(sys, u0, None, policy),
        None => Err(neither().into()),
    }
}

/// The trust region from `u0` on `sys`, and the system's evaluation at its solution (with a
/// Jacobian if `jacobian`) as an answer.
fn rescue<const N: usize, S>(
    sys: &S,
    u0: &[f64; N],
    opts: &TrustRegionOptions,
    jacobian: bool,
) -> Result<NewtonAnswer<N, S::Point>, S::Error>
where
    S: NewtonSystem<N>,
    S::Error: std::error::Error + From<BvpError> + Send + Sync + 'static,
{
    let sol = trust_region::solve(&AsSystem::<S, N>(sys), u0, opts)?;
    let u: [f64; N] = std::array::from_fn(|i| sol.x[i]);
    let e = sys.eval(&u, jacobian)?;
    Ok(NewtonAnswer {
        u,
        r: e.r,
        norm: e.r.iter().map(|v| v * v).sum::<f64>().sqrt(),
        jac: e.jac.unwrap_or([[f64::NAN; N]; N]),
        point: e.point,
        iterations: usize::try_from(sol.iterations).unwrap_or(usize::MAX),
        step: [0.0; N],
        termination: Termination::Converged,
    })
}

/// A square [`NewtonSystem`] seen by the trust region: an inadmissible point or a failed
/// evaluation has a NaN residual (an infinite cost); the Jacobian is the system's, or forward
/// differences where it gives none.
struct AsSystem<'a, S, const N: usize>(&'a S);

impl<const N: usize, S> NonlinearSystem for AsSystem<'_, S, N>
where
    S: NewtonSystem<N>,
    S::Error: std::error::Error + From<BvpError> + Send + Sync + 'static,
{
    type Error = S::Error;

    fn n_unknowns(&self) -> usize {
        N
    }

    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), S::Error> {
        let u: [f64; N] = std::array::from_fn(|i| x[i]);
        let e = self.0.admissible(&u).then(|| self.0.eval(&u, false).ok());
        match e.flatten() {
            Some(e) => r.copy_from_slice(&e.r),
            None => r.fill(f64::NAN),
        }
        Ok(())
    }

    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> Result<(), S::Error> {
        let u: [f64; N] = std::array::from_fn(|i| x[i]);
        match self.0.eval(&u, true)?.jac {
            Some(j) => {
                for (out, row) in jac.chunks_exact_mut(N).zip(&j) {
                    out.copy_from_slice(row);
                }
                Ok(())
            }
            None => forward_difference_jacobian(self, x, jac),
        }
    }
}

#[cfg(test)]
mod tests;
