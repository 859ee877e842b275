//! The safeguards of [`newton_guarded`](super::newton_guarded): a largest step, stall
//! detection, the predicted exit and the negligible-step exit.

use super::system::{evaluate_again, NewtonAnswer, NewtonSystem, Termination};
#[cfg(doc)]
use super::{newton, newton_guarded, NewtonPolicy};

/// Safeguards of [`newton_guarded`] beyond the [`NewtonPolicy`]: a largest step, stall
/// detection and two early exits that save the evaluation of a step predicted to converge.
/// [`Safeguards::NONE`] (the default) is plain [`newton`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Safeguards {
    /// The largest step: a correction whose largest component exceeds it is scaled down to
    /// it (that component exactly `±max_step`); infinite for none.
    pub max_step: f64,
    /// Fail as [`Termination::Stalled`] when the residual stops falling fast enough.
    pub stall: Option<Stall>,
    /// End at a negligible step.
    pub small_step: Option<SmallStep>,
    /// After a step from a residual norm at most `predict_below` (times the scale), return
    /// its trial without evaluating it as [`Termination::Predicted`]: with quadratic
    /// convergence the trial's residual is of the order of its square, and the caller
    /// verifies it. The answer carries the previous iterate's residual, Jacobian and point,
    /// and the step ([`NewtonAnswer::step`]) to extrapolate them.
    pub predict_below: Option<f64>,
}

impl Safeguards {
    /// No safeguard.
    pub const NONE: Safeguards = Safeguards {
        max_step: f64::INFINITY,
        stall: None,
        small_step: None,
        predict_below: None,
    };
}

impl Default for Safeguards {
    fn default() -> Self {
        Safeguards::NONE
    }
}

/// Stall detection: at each iterate (before its step) a residual norm below `factor` times
/// the best so far, or within `floor` (times the scale: the rounding floor, where no
/// progress is expected), resets the count; any other counts, and `patience` such iterates
/// in a row end the iteration as [`Termination::Stalled`] (cycling, diverging, or crawling
/// along limited steps: a caller can then change its problem, e.g. shorten a continuation
/// step, instead of spending the step budget).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stall {
    /// The reduction of the best residual norm that counts as progress (e.g. 0.5).
    pub factor: f64,
    /// Iterates without progress in a row that stop the iteration.
    pub patience: usize,
    /// Residual norm (relative to the scale) under which an iterate always counts as
    /// progress.
    pub floor: f64,
}

/// The negligible-step exit: a step whose every component `du_i` satisfies
/// `|du_i| <= rel * max(|u_i| + shift, floor)` (`u` the trial) ends the iteration at the
/// trial: the iterate has converged to rounding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmallStep {
    /// Relative size of a negligible step (e.g. a few machine epsilons).
    pub rel: f64,
    /// Added to `|u_i|` (1 for `rel (1 + |u_i|)`).
    pub shift: f64,
    /// Lower bound of `|u_i| + shift` (1 for `rel max(|u_i|, 1)`).
    pub floor: f64,
    /// `Some(bound)`: the trial is evaluated (without a Jacobian) and accepted as
    /// [`Termination::Converged`] when its residual norm is at most `bound` times the scale
    /// of the iterate the step left, otherwise the iteration ends there as
    /// [`Termination::NoDescent`]; `None`: the trial is returned unevaluated as
    /// [`Termination::Predicted`] (as with [`Safeguards::predict_below`]).
    pub check: Option<f64>,
}

impl SmallStep {
    /// Whether the step `du` to `trial` is negligible.
    fn negligible<const N: usize>(&self, du: &[f64; N], trial: &[f64; N]) -> bool {
        du.iter()
            .zip(trial)
            .all(|(d, t)| d.abs() <= self.rel * (t.abs() + self.shift).max(self.floor))
    }
}

/// The best residual norm so far and the iterates since it last fell enough ([`Stall`]).
pub(super) struct StallWatch {
    best: f64,
    count: usize,
}

impl Default for StallWatch {
    fn default() -> Self {
        StallWatch {
            best: f64::INFINITY,
            count: 0,
        }
    }
}

impl StallWatch {
    /// Records the iterate's residual norm; whether the iteration has stalled.
    pub(super) fn stalled(&mut self, stall: &Stall, norm: f64, scale: f64) -> bool {
        if norm < stall.factor * self.best || norm <= stall.floor * scale {
            (self.best, self.count) = (norm, 0);
            false
        } else {
            self.best = self.best.min(norm);
            self.count += 1;
            self.count >= stall.patience
        }
    }
}

/// `du` scaled down so that its largest component is at most `max_step` (that component
/// set to exactly `±max_step`).
pub(super) fn limit<const N: usize>(mut du: [f64; N], max_step: f64) -> [f64; N] {
    let big = du.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
    if big > max_step {
        let f = max_step / big;
        for d in du.iter_mut() {
            *d = if d.abs() == big {
                max_step.copysign(*d)
            } else {
                *d * f
            };
        }
    }
    du
}

/// The exits of [`Safeguards`] before the step `du` from `ans` is evaluated: the predicted
/// one, then the negligible step's. Moves `ans` to the trial and says why it ends, or
/// `None` to go on.
pub(super) fn early_exit<const N: usize, const M: usize, S: NewtonSystem<N, M>>(
    sys: &S,
    ans: &mut NewtonAnswer<N, S::Point, M>,
    du: &[f64; N],
    guards: &Safeguards,
    scale: f64,
    it: usize,
) -> Result<Option<Termination>, S::Error> {
    let trial: [f64; N] = std::array::from_fn(|i| ans.u[i] - du[i]);
    let predicted = guards.predict_below.is_some_and(|p| ans.norm <= p * scale);
    let small = guards.small_step.filter(|s| s.negligible(du, &trial));
    if !predicted && small.is_none() {
        return Ok(None);
    }
    ans.u = trial;
    ans.step = std::array::from_fn(|i| -du[i]);
    ans.iterations = it + 1;
    let check = match small {
        Some(SmallStep {
            check: Some(bound), ..
        }) if !predicted => bound,
        _ => return Ok(Some(Termination::Predicted)),
    };
    evaluate_again(sys, ans, false)?;
    Ok(Some(if ans.norm <= check * scale {
        Termination::Converged
    } else {
        Termination::NoDescent
    }))
}

#[cfg(test)]
mod tests {
    use super::super::{
        newton, newton_guarded, Evaluation, JacobianUpdate, NewtonPolicy, NewtonSystem,
    };
    use super::*;
    use std::cell::Cell;

    /// `R(u) = f(u)` in one unknown with `f'` as the Jacobian; counts evaluations (and
    /// those without a Jacobian); `scale` multiplies the residual's scale.
    struct Scalar<F: Fn(f64) -> (f64, f64)> {
        f: F,
        evals: Cell<usize>,
        plain: Cell<usize>,
        scale: f64,
    }

    fn scalar<F: Fn(f64) -> (f64, f64)>(f: F) -> Scalar<F> {
        Scalar {
            f,
            evals: Cell::new(0),
            plain: Cell::new(0),
            scale: 1.0,
        }
    }

    impl<F: Fn(f64) -> (f64, f64)> NewtonSystem<1> for Scalar<F> {
        type Point = ();
        type Error = ();
        fn eval(&self, u: &[f64; 1], jacobian: bool) -> Result<Evaluation<1, ()>, ()> {
            self.evals.set(self.evals.get() + 1);
            if !jacobian {
                self.plain.set(self.plain.get() + 1);
            }
            let (r, d) = (self.f)(u[0]);
            Ok(Evaluation {
                r: [r],
                jac: Some([[d]]),
                point: (),
            })
        }
        fn scale(&self, _point: &()) -> f64 {
            self.scale
        }
    }

    /// Full steps with the Jacobian at every one (the scalar shooting's policy).
    fn full_steps(tol: f64) -> NewtonPolicy {
        NewtonPolicy {
            halvings: 0,
            update: JacobianUpdate::Reevaluate { keep_below: 0.0 },
            jacobian_at_solution: false,
            ..NewtonPolicy::new(tol)
        }
    }

    #[test]
    fn a_largest_step_limits_every_step_exactly_and_keeps_its_direction() {
        let line = scalar(|u| (u - 10.0, 1.0));
        let guards = Safeguards {
            max_step: 1.0,
            ..Safeguards::NONE
        };
        let out = newton_guarded(&line, [0.0], None, &full_steps(1e-14), &guards).unwrap();
        assert_eq!(out.termination, Termination::Converged);
        // ten steps of exactly 1 land exactly on the root
        assert_eq!((out.iterations, out.u[0], out.step[0]), (10, 10.0, 1.0));
        assert_eq!(limit([3.0, -1.5], 1.0), [1.0, -0.5]);
        assert_eq!(limit([-0.7, 0.2], 1.0), [-0.7, 0.2]);
    }

    #[test]
    fn a_stalled_iteration_fails_at_once_unless_at_its_floor() {
        // R = u^2 + 1 has no root: Newton wanders for the whole budget without the guard
        let policy = full_steps(1e-12);
        let plain = newton(&scalar(|u| (u * u + 1.0, 2.0 * u)), [0.3], None, &policy).unwrap();
        assert_eq!(plain.termination, Termination::MaxIterations);
        let sys = scalar(|u| (u * u + 1.0, 2.0 * u));
        let stall = Stall {
            factor: 0.5,
            patience: 2,
            floor: 1e-9,
        };
        let guards = Safeguards {
            stall: Some(stall),
            ..Safeguards::NONE
        };
        let out = newton_guarded(&sys, [0.3], None, &policy, &guards).unwrap();
        assert_eq!(out.termination, Termination::Stalled);
        assert!(!out.termination.is_solution());
        assert!(sys.evals.get() < 10, "{}", sys.evals.get());
        // at the floor no iterate counts as a stall
        let mut watch = StallWatch::default();
        assert!((0..5).all(|_| !watch.stalled(&stall, 1e-10, 1.0)));
        // a residual that halves is progress, two that do not in a row a stall
        let mut watch = StallWatch::default();
        assert!(!watch.stalled(&stall, 1.0, 1.0));
        assert!(!watch.stalled(&stall, 0.4, 1.0));
        assert!(!watch.stalled(&stall, 0.3, 1.0));
        assert!(watch.stalled(&stall, 0.25, 1.0));
    }

    #[test]
    fn the_predicted_exit_returns_the_last_step_unevaluated() {
        let s2 = 2f64.sqrt();
        let sys = scalar(|u| (u * u - 2.0, 2.0 * u));
        let guards = Safeguards {
            predict_below: Some(1e-7),
            ..Safeguards::NONE
        };
        let out = newton_guarded(&sys, [1.0], None, &full_steps(1e-15), &guards).unwrap();
        assert_eq!(out.termination, Termination::Predicted);
        assert!(out.termination.is_solution());
        // one evaluation per iterate, none of the returned trial
        assert_eq!(sys.evals.get(), out.iterations);
        // the residual carried is the previous iterate's, the step leads to ~its square
        assert!(out.norm <= 1e-7 && out.norm > 0.0, "{}", out.norm);
        assert!((out.u[0] - s2).abs() < 1e-15);
        // relative to the system's scale
        let scaled = Scalar {
            scale: 1e-6,
            ..scalar(|u| (u * u - 2.0, 2.0 * u))
        };
        let out = newton_guarded(&scaled, [1.0], None, &full_steps(1e-15), &guards).unwrap();
        assert!(out.norm <= 1e-13, "{}", out.norm);
    }

    #[test]
    fn a_negligible_step_ends_at_rounding_checked_or_not() {
        let s2 = 2f64.sqrt();
        // a tolerance of zero is not reached: the step falls to rounding
        let mut small = SmallStep {
            rel: 4.0 * f64::EPSILON,
            shift: 0.0,
            floor: 1.0,
            check: Some(1e-12),
        };
        let sys = scalar(|u| (u * u - 2.0, 2.0 * u));
        let guards = Safeguards {
            small_step: Some(small),
            ..Safeguards::NONE
        };
        let out = newton_guarded(&sys, [1.0], None, &full_steps(0.0), &guards).unwrap();
        assert_eq!(out.termination, Termination::Converged);
        assert!((out.u[0] - s2).abs() <= 4.0 * f64::EPSILON);
        // the check is one evaluation without a Jacobian
        assert_eq!(sys.plain.get(), 1);
        assert_eq!(sys.evals.get(), out.iterations + 1);
        // a check that fails ends without descent
        small.check = Some(0.0);
        let guards = Safeguards {
            small_step: Some(small),
            ..Safeguards::NONE
        };
        let noisy = scalar(|u| (u * u - 2.0 + 1e-9, 2.0 * u));
        let out = newton_guarded(&noisy, [1.0], None, &full_steps(0.0), &guards).unwrap();
        assert_eq!(out.termination, Termination::NoDescent);
        // unchecked: the trial returned as predicted, without evaluation
        small.check = None;
        let guards = Safeguards {
            small_step: Some(small),
            ..Safeguards::NONE
        };
        let sys = scalar(|u| (u * u - 2.0, 2.0 * u));
        let out = newton_guarded(&sys, [1.0], None, &full_steps(0.0), &guards).unwrap();
        assert_eq!(out.termination, Termination::Predicted);
        assert_eq!(sys.evals.get(), out.iterations);
        assert!(small.negligible(&[1e-16], &[1.0]) && !small.negligible(&[1e-15], &[1.0]));
    }
}
