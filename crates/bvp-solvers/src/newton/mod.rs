//! Newton's method for small systems `R(u) = 0`, `u` in `R^N`, `R` in `R^M`, with one
//! convergence policy: a damped step (halved until the residual norm falls), the Jacobian
//! kept while it contracts the residual fast enough (simplified Newton) or updated by
//! Broyden's rank-one formula, a noise floor under which a stalled iteration is accepted, and
//! an answer that always says why it stopped ([`Termination`]) with the best point reached.
//!
//! One iteration, three step rules (`J = dR/du`):
//! - [`newton`] (`M = N`): `J du = R`;
//! - [`gauss_newton`] (`M >= N`, least squares `min |R|^2`): the normal equations
//!   `J^T J du = J^T R`;
//! - [`projection`] (`M <= N`, the nearest point of `R = 0` to a measured `u_m` in the metric
//!   `W^-1`, `W = diag(w)`): the Gauss-Newton step of the constrained least-squares problem
//!   `u' = u_m - W J^T (J W J^T)^-1 (R(u) + J (u_m - u))`.
//!
//! For `M = N` and a regular `J` all three are the Newton step `u' = u - J^-1 R`.
//!
//! The system ([`NewtonSystem`]) evaluates its residual, with the Jacobian on request, and
//! carries a point of its own along (whatever the domain computes with the residual: a
//! shot, a contact state), so that the converged answer needs no extra evaluation; it may
//! also say when consecutive points have settled ([`NewtonSystem::settled`]: converged by the
//! domain's own measure).
//!
//! ```
//! use bvp_solvers::newton::{newton, Evaluation, NewtonPolicy, NewtonSystem, Termination};
//!
//! /// The circle `x^2 + y^2 = 4` meets the line `y = x`.
//! struct Meet;
//! impl NewtonSystem<2> for Meet {
//!     type Point = ();
//!     type Error = ();
//!     fn eval(&self, u: &[f64; 2], jacobian: bool) -> Result<Evaluation<2, ()>, ()> {
//!         let r = [u[0] * u[0] + u[1] * u[1] - 4.0, u[1] - u[0]];
//!         let jac = jacobian.then_some([[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]]);
//!         Ok(Evaluation { r, jac, point: () })
//!     }
//! }
//! let out = newton(&Meet, [1.0, 2.0], None, &NewtonPolicy::new(1e-14)).unwrap();
//! assert_eq!(out.termination, Termination::Converged);
//! assert!((out.u[0] - 2f64.sqrt()).abs() < 1e-14 && (out.u[1] - 2f64.sqrt()).abs() < 1e-14);
//! ```

mod guards;
mod least_squares;
mod system;
use crate::dense::solve;
use guards::{early_exit, limit, StallWatch};
pub use guards::{Safeguards, SmallStep, Stall};
pub use least_squares::{gauss_newton, projection};
use system::{evaluate_again, norm};
pub use system::{Evaluation, NewtonAnswer, NewtonSystem, Termination};

/// How the Jacobian is obtained after a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JacobianUpdate {
    /// Evaluated again where the step contracted the residual by less than `keep_below`
    /// (`|R_new| / |R_old| > keep_below`), kept otherwise (simplified Newton); 0 (or less)
    /// evaluates it at every step, asked for with every trial.
    Reevaluate {
        /// Largest contraction ratio at which the old Jacobian is kept.
        keep_below: f64,
    },
    /// Never evaluated (but at the solution if the policy wants it there): Broyden's
    /// rank-one update `J += (dR - J du) du^T / (du . du)` of the given start Jacobian; the
    /// iteration stops as [`Termination::NoDescent`] when a full step contracts the residual
    /// by less than `min_contraction`.
    Broyden {
        /// The contraction every step must reach.
        min_contraction: f64,
    },
}

/// The convergence policy of [`newton`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonPolicy {
    /// Converged when the residual's Euclidean norm is at most `tol`.
    pub tol: f64,
    /// Newton steps at most.
    pub max_iter: usize,
    /// Step halvings per step at most (0: full steps only, accepted whatever the residual).
    pub halvings: usize,
    /// How the Jacobian follows the iterate.
    pub update: JacobianUpdate,
    /// Whether the answer carries a Jacobian evaluated at the solution (else the last one).
    /// The Jacobian is then asked for already with the trial that the last contraction
    /// predicts to converge (`|R| rho <= tol`), so that a converged answer costs no extra
    /// evaluation.
    pub jacobian_at_solution: bool,
    /// A failed iteration whose best residual norm is at most this is accepted as
    /// [`Termination::NoiseFloor`] (the evaluations' own noise stops it above `tol`).
    pub noise_floor: f64,
}

impl NewtonPolicy {
    /// Residual norm `tol`, 20 steps with up to 5 halvings, the Jacobian evaluated again
    /// unless a step contracted the residual by 20x, a Jacobian at the solution, no noise
    /// floor.
    pub fn new(tol: f64) -> Self {
        NewtonPolicy {
            tol,
            max_iter: 20,
            halvings: 5,
            update: JacobianUpdate::Reevaluate { keep_below: 0.05 },
            jacobian_at_solution: true,
            noise_floor: 0.0,
        }
    }
}

/// Newton's method on `sys` from `u0` under `policy` (module docs): steps `J du = R`;
/// `jac0` is a start Jacobian (required for [`JacobianUpdate::Broyden`]; otherwise the first
/// evaluation computes one when it is `None`).
///
/// # Errors
/// An evaluation error at `u0`, or where a Jacobian is evaluated; errors at trial points
/// only reject the step. A `Broyden` policy without `jac0` ends as
/// [`Termination::Singular`].
pub fn newton<const N: usize, S: NewtonSystem<N>>(
    sys: &S,
    u0: [f64; N],
    jac0: Option<[[f64; N]; N]>,
    policy: &NewtonPolicy,
) -> Result<NewtonAnswer<N, S::Point>, S::Error> {
    newton_guarded(sys, u0, jac0, policy, &Safeguards::NONE)
}

/// [`newton`] with [`Safeguards`]: at each iterate, in this order, convergence, a singular
/// Jacobian, stall detection, the step (limited to `max_step`), the predicted exit, the
/// negligible-step exit, then the trial's evaluation (with up to `max_iter` evaluated steps;
/// the checks and exits before the evaluation also run at the last iterate).
///
/// # Errors
/// As [`newton`]; also an evaluation error at the negligible step's checked trial.
pub fn newton_guarded<const N: usize, S: NewtonSystem<N>>(
    sys: &S,
    u0: [f64; N],
    jac0: Option<[[f64; N]; N]>,
    policy: &NewtonPolicy,
    guards: &Safeguards,
) -> Result<NewtonAnswer<N, S::Point>, S::Error> {
    iterate(sys, u0, jac0, policy, guards, |jac, r, _| solve(jac, r))
}

/// The iteration of [`newton`], [`gauss_newton`] and [`projection`]: `step(J, R, u)` is the
/// full correction `du` (the trial is `u - lambda du`), `None` where it does not exist.
fn iterate<const N: usize, const M: usize, S: NewtonSystem<N, M>>(
    sys: &S,
    u0: [f64; N],
    jac0: Option<[[f64; N]; M]>,
    policy: &NewtonPolicy,
    guards: &Safeguards,
    step: impl Fn(&[[f64; N]; M], &[f64; M], &[f64; N]) -> Option<[f64; N]>,
) -> Result<NewtonAnswer<N, S::Point, M>, S::Error> {
    // a Jacobian wanted after every step comes with every trial
    let every_step = matches!(policy.update,
        JacobianUpdate::Reevaluate { keep_below } if keep_below <= 0.0);
    let (mut ans, mut jac_fresh) = start(sys, u0, jac0, policy)?;
    let mut scale = sys.scale(&ans.point);
    if ans.norm <= policy.tol * scale {
        // converged at the start: the Jacobian at the solution, if asked for and not there
        if policy.jacobian_at_solution && !jac_fresh {
            evaluate_again(sys, &mut ans, true)?;
        }
        return Ok(ans);
    }
    if ans.norm.is_nan() {
        ans.termination = Termination::NoDescent;
        return Ok(ans);
    }
    // the last step's contraction |R_new| / |R_old| (none before the first step)
    let mut contraction = f64::NAN;
    let mut watch = StallWatch::default();
    for it in 0..=policy.max_iter {
        let last = it == policy.max_iter;
        if last && guards == &Safeguards::NONE {
            break;
        }
        let Some(du) = step(&ans.jac, &ans.r, &ans.u) else {
            if last {
                break;
            }
            ans.termination = Termination::Singular;
            return finish(sys, ans, policy, jac_fresh);
        };
        if let Some(stall) = &guards.stall {
            if watch.stalled(stall, ans.norm, scale) {
                ans.termination = Termination::Stalled;
                return finish(sys, ans, policy, jac_fresh);
            }
        }
        let du = limit(du, guards.max_step);
        if let Some(exit) = early_exit(sys, &mut ans, &du, guards, scale, it)? {
            ans.termination = exit;
            return Ok(ans);
        }
        if last {
            break;
        }
        // a trial predicted to converge brings the Jacobian at the solution along
        let want_jac = every_step
            || (policy.jacobian_at_solution && ans.norm * contraction <= policy.tol * scale);
        let Some((lambda, trial, eval, rn)) = damped_step(sys, &ans, &du, policy, want_jac) else {
            ans.termination = Termination::NoDescent;
            return finish(sys, ans, policy, jac_fresh);
        };
        contraction = rn / ans.norm;
        let taken: [f64; N] = std::array::from_fn(|i| -(lambda * du[i]));
        if let JacobianUpdate::Broyden { min_contraction } = policy.update {
            broyden_update(&mut ans.jac, &du, &ans.r, &eval.r);
            let scale = sys.scale(&eval.point);
            if rn > policy.tol * scale && (contraction >= min_contraction || contraction.is_nan()) {
                ans = NewtonAnswer {
                    u: trial,
                    r: eval.r,
                    norm: rn,
                    point: eval.point,
                    iterations: it + 1,
                    step: taken,
                    termination: Termination::NoDescent,
                    ..ans
                };
                return Ok(ans);
            }
        }
        let settled = sys.settled(&ans.point, &eval.point);
        ans.u = trial;
        ans.r = eval.r;
        ans.norm = rn;
        ans.point = eval.point;
        ans.iterations = it + 1;
        ans.step = taken;
        scale = sys.scale(&ans.point);
        jac_fresh = false;
        if let Some(j) = eval.jac {
            ans.jac = j;
            jac_fresh = true;
        }
        if settled {
            return Ok(ans);
        }
        let converged = rn <= policy.tol * scale;
        if converged && (!policy.jacobian_at_solution || jac_fresh) {
            return Ok(ans);
        }
        // a fresh Jacobian at the solution, or where the current one converges slowly
        let reevaluate = converged
            || matches!(policy.update,
                JacobianUpdate::Reevaluate { keep_below } if contraction > keep_below);
        if reevaluate && !jac_fresh {
            jac_fresh = evaluate_again(sys, &mut ans, true)?;
            scale = sys.scale(&ans.point);
        }
        if converged {
            return Ok(ans);
        }
    }
    ans.termination = Termination::MaxIterations;
    finish(sys, ans, policy, jac_fresh)
}

/// The iteration's start: the evaluation at `u0` (with a Jacobian unless `jac0` is given or
/// the policy is Broyden's) as an answer, and whether its Jacobian was evaluated there.
#[allow(clippy::type_complexity)]
fn start<const N: usize, const M: usize, S: NewtonSystem<N, M>>(
    sys: &S,
    u0: [f64; N],
    jac0: Option<[[f64; N]; M]>,
    policy: &NewtonPolicy,
) -> Result<(NewtonAnswer<N, S::Point, M>, bool), S::Error> {
    let broyden = matches!(policy.update, JacobianUpdate::Broyden { .. });
    let first = sys.eval(&u0, jac0.is_none() && !broyden)?;
    let jac_fresh = first.jac.is_some() && jac0.is_none();
    let ans = NewtonAnswer {
        u: u0,
        r: first.r,
        norm: norm(&first.r),
        jac: jac0.or(first.jac).unwrap_or([[f64::NAN; N]; M]),
        point: first.point,
        iterations: 0,
        step: [0.0; N],
        termination: Termination::Converged,
    };
    Ok((ans, jac_fresh))
}

/// The trial `u - lambda du` with the largest `lambda = 1, 1/2, ...` (at most
/// `policy.halvings` halvings) that is admissible, evaluates, and lowers the residual norm
/// (or reaches the tolerance); a full step only, accepted as it comes, without halvings.
#[allow(clippy::type_complexity)]
fn damped_step<const N: usize, const M: usize, S: NewtonSystem<N, M>>(
    sys: &S,
    ans: &NewtonAnswer<N, S::Point, M>,
    du: &[f64; N],
    policy: &NewtonPolicy,
    want_jac: bool,
) -> Option<(f64, [f64; N], Evaluation<N, S::Point, M>, f64)> {
    let mut lambda = 1.0;
    let tries = policy.halvings.max(1);
    for _ in 0..tries {
        let mut trial = ans.u;
        for (t, d) in trial.iter_mut().zip(du) {
            *t -= lambda * d;
        }
        if !sys.admissible(&trial) {
            lambda *= 0.5;
            continue;
        }
        if let Ok(e) = sys.eval(&trial, want_jac) {
            let rn = norm(&e.r);
            let accept = if policy.halvings == 0 {
                !rn.is_nan()
            } else {
                rn.is_finite() && (rn < ans.norm || rn <= policy.tol * sys.scale(&e.point))
            };
            if accept {
                return Some((lambda, trial, e, rn));
            }
        }
        lambda *= 0.5;
    }
    None
}

/// Broyden's rank-one update of `jac` after the step `-du` that took the residual from `r`
/// to `r_new`: `J += (dR - J s) s^T / (s . s)`, `s = -du`.
fn broyden_update<const N: usize, const M: usize>(
    jac: &mut [[f64; N]; M],
    du: &[f64; N],
    r: &[f64; M],
    r_new: &[f64; M],
) {
    let s: [f64; N] = std::array::from_fn(|i| -du[i]);
    let ss: f64 = s.iter().map(|v| v * v).sum();
    if ss <= 0.0 || ss.is_nan() {
        return;
    }
    for (i, row) in jac.iter_mut().enumerate() {
        let js: f64 = row.iter().zip(&s).map(|(a, b)| a * b).sum();
        let d = r_new[i] - r[i] - js;
        for (jk, sk) in row.iter_mut().zip(&s) {
            *jk += d * sk / ss;
        }
    }
}

/// A failed iteration: within the noise floor it is accepted, re-evaluated at its iterate
/// (with a Jacobian if the policy wants one at the solution and the last is stale).
fn finish<const N: usize, const M: usize, S: NewtonSystem<N, M>>(
    sys: &S,
    mut ans: NewtonAnswer<N, S::Point, M>,
    policy: &NewtonPolicy,
    jac_fresh: bool,
) -> Result<NewtonAnswer<N, S::Point, M>, S::Error> {
    if ans.norm <= policy.noise_floor * sys.scale(&ans.point) {
        ans.termination = Termination::NoiseFloor;
        if policy.jacobian_at_solution && !jac_fresh {
            // the point and Jacobian of a new evaluation; the residual judged stays
            let (r, norm) = (ans.r, ans.norm);
            evaluate_again(sys, &mut ans, true)?;
            (ans.r, ans.norm) = (r, norm);
        }
    }
    Ok(ans)
}

#[cfg(test)]
mod tests;
