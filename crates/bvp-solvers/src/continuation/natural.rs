//! Natural-parameter (load) continuation: step a parameter `lambda` from an easy value to the
//! target, starting each solve from a prediction off the previous solutions, with step halving
//! on failure.
//!
//! [`Continuation::follow`] (and [`Continuation::follow_from`], with a known first slope) is
//! the one driver: a secant predictor, a jump guard that rejects a corrector landing on
//! another branch, a step budget, and a failure that carries the last inner error
//! ([`ContinuationFailure`]).

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::BvpError;
use std::fmt;

/// Step-size controlled natural-parameter continuation.
///
/// Starting at `lambda = from` with step `initial_step`, each step tries
/// `lambda_next = lambda + h` (clipped to `to`), correcting a prediction off the last
/// solutions. On success the step is accepted and `h <- min(2h, max_step)`; on failure
/// `h <- h/2` and the step is retried; when `h < min_step` the continuation stops (e.g. at a
/// fold of the solution branch, where natural-parameter continuation cannot pass): see
/// [`Continuation::follow`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Continuation {
    /// First step size (`> 0`; the sign is taken from `to - from`).
    pub initial_step: f64,
    /// Smallest step before giving up (`> 0`).
    pub min_step: f64,
    /// Largest step (`>= min_step`).
    pub max_step: f64,
}

/// Work counters of a continuation run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ContinuationStats {
    /// Accepted steps (the known start at `from` is not one).
    pub steps: usize,
    /// Failed solves that halved the step.
    pub halvings: usize,
    /// Of those, correctors rejected by the jump guard of [`Continuation::follow`]: they
    /// converged on another solution branch, which is therefore near.
    pub jumps: usize,
}

impl Continuation {
    /// Validates the bounds and step sizes.
    fn check(&self, from: f64, to: f64) -> Result<(), BvpError> {
        let bad = |name, value, reason| BvpError::InvalidInput {
            name,
            value,
            reason,
        };
        if !from.is_finite() {
            return Err(bad("from", from, "must be finite"));
        }
        if !to.is_finite() {
            return Err(bad("to", to, "must be finite"));
        }
        if !(self.min_step > 0.0 && self.min_step.is_finite()) {
            return Err(bad("min_step", self.min_step, "must be finite and > 0"));
        }
        if !(self.max_step >= self.min_step && self.max_step.is_finite()) {
            return Err(bad(
                "max_step",
                self.max_step,
                "must be finite and >= min_step",
            ));
        }
        if !(self.initial_step >= self.min_step && self.initial_step <= self.max_step) {
            return Err(bad(
                "initial_step",
                self.initial_step,
                "must lie in [min_step, max_step]",
            ));
        }
        Ok(())
    }

    /// Follows the solution branch `y(lambda)` of a parameter-dependent problem from
    /// `(from, start)` (a known solution, not re-solved) to `to`, the one driver of load
    /// continuation:
    ///
    /// - predictor: the secant through the last two accepted points,
    ///   `y_pred = y_k + (lambda - lambda_k) (y_k - y_{k-1}) / (lambda_k - lambda_{k-1})`
    ///   (the constant `y_k` on the first step);
    /// - corrector: `correct(lambda, &y_pred)`, the caller's solver warm-started from the
    ///   prediction;
    /// - jump guard: a corrector that lands farther than
    ///   `guard.absolute + guard.relative * |y_pred - y_k|` (max-norm) from its prediction has
    ///   jumped to another branch; the step is rejected like a failed corrector;
    /// - step control: success doubles the step (capped at `max_step`), a rejection halves
    ///   it; below `min_step`, or after `guard.max_attempts` correctors, the run fails.
    ///
    /// Returns the solution at `to` and the work counters.
    ///
    /// # Errors
    /// [`ContinuationFailure`] with the parameter reached, the failing step and its
    /// [`StallCause`]: the corrector's last error, the last branch jump, or the exhausted
    /// budget. Bad bounds or step sizes give `StallCause::Invalid`.
    pub fn follow<E, F>(
        &self,
        from: f64,
        to: f64,
        start: Vec<f64>,
        guard: &BranchGuard,
        correct: F,
    ) -> Result<(Vec<f64>, ContinuationStats), ContinuationFailure<E>>
    where
        F: FnMut(f64, &[f64]) -> Result<Vec<f64>, E>,
    {
        let slope = vec![0.0; start.len()];
        self.follow_from(from, to, start, slope, guard, correct)
    }

    /// [`Continuation::follow`] with the branch's slope `dy/dlambda` at `from` known (e.g. from
    /// linear theory): the first step predicts along it instead of keeping `start`.
    ///
    /// # Errors
    /// As [`Continuation::follow`]; a `slope` of another length than `start` gives
    /// `StallCause::Invalid`.
    pub fn follow_from<E, F>(
        &self,
        from: f64,
        to: f64,
        start: Vec<f64>,
        slope: Vec<f64>,
        guard: &BranchGuard,
        mut correct: F,
    ) -> Result<(Vec<f64>, ContinuationStats), ContinuationFailure<E>>
    where
        F: FnMut(f64, &[f64]) -> Result<Vec<f64>, E>,
    {
        let fail = |reached, step, steps, cause| ContinuationFailure {
            reached,
            target: to,
            step,
            steps,
            cause,
        };
        if let Err(e) = self.check(from, to) {
            return Err(fail(from, 0.0, 0, StallCause::Invalid(e)));
        }
        if slope.len() != start.len() {
            let e = BvpError::DimensionMismatch {
                name: "continuation slope",
                expected: start.len(),
                found: slope.len(),
            };
            return Err(fail(from, 0.0, 0, StallCause::Invalid(e)));
        }
        let dir = if to >= from { 1.0 } else { -1.0 };
        let mut stats = ContinuationStats::default();
        let (mut lambda, mut y) = (from, start);
        let mut slope = slope;
        let mut h = self.initial_step;
        let mut attempts = 0usize;
        let mut pred = vec![0.0; y.len()];
        while lambda != to {
            if attempts >= guard.max_attempts {
                return Err(fail(
                    lambda,
                    h,
                    stats.steps,
                    StallCause::Budget {
                        max_attempts: guard.max_attempts,
                    },
                ));
            }
            attempts += 1;
            let remaining = (to - lambda).abs();
            let next = if remaining <= h { to } else { lambda + dir * h };
            let dl = next - lambda;
            for ((p, &yi), &d) in pred.iter_mut().zip(&y).zip(&slope) {
                *p = yi + d * dl;
            }
            let outcome = match correct(next, &pred) {
                Ok(sol) if sol.len() != y.len() => {
                    Err(StallCause::Invalid(BvpError::DimensionMismatch {
                        name: "continuation state",
                        expected: y.len(),
                        found: sol.len(),
                    }))
                }
                Ok(sol) => {
                    let distance = max_diff(&sol, &pred);
                    let allowed = guard.absolute + guard.relative * max_diff(&pred, &y);
                    if distance.is_finite() && distance <= allowed {
                        Ok(sol)
                    } else {
                        Err(StallCause::Jump {
                            at: next,
                            distance,
                            allowed,
                        })
                    }
                }
                Err(e) => Err(StallCause::Inner(e)),
            };
            match outcome {
                Ok(sol) => {
                    for ((d, &a), &b) in slope.iter_mut().zip(&sol).zip(&y) {
                        *d = (a - b) / dl;
                    }
                    y = sol;
                    lambda = next;
                    stats.steps += 1;
                    h = (2.0 * h).min(self.max_step);
                }
                Err(cause @ StallCause::Invalid(_)) => {
                    return Err(fail(lambda, h, stats.steps, cause));
                }
                Err(cause) => {
                    stats.halvings += 1;
                    if matches!(cause, StallCause::Jump { .. }) {
                        stats.jumps += 1;
                    }
                    let tried = h.min(remaining);
                    h = 0.5 * tried;
                    if h < self.min_step {
                        return Err(fail(lambda, tried, stats.steps, cause));
                    }
                }
            }
        }
        Ok((y, stats))
    }
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The jump guard and budget of [`Continuation::follow`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BranchGuard {
    /// Largest distance (max-norm) of a corrector from its prediction, absolute part.
    pub absolute: f64,
    /// ... plus this multiple of the predicted change `|y_pred - y_k|`.
    pub relative: f64,
    /// Most corrector calls (accepted and rejected) before the run gives up.
    pub max_attempts: usize,
}

impl Default for BranchGuard {
    /// `0.2 + 0.5 |y_pred - y_k|`, 2000 correctors.
    fn default() -> Self {
        BranchGuard {
            absolute: 0.2,
            relative: 0.5,
            max_attempts: 2000,
        }
    }
}

/// Why [`Continuation::follow`] stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum StallCause<E> {
    /// The corrector's error at the last failed step.
    Inner(E),
    /// The corrector converged, but on another branch: `distance` from its prediction at
    /// `lambda = at`, more than the `allowed` distance.
    Jump {
        /// The parameter of the rejected step.
        at: f64,
        /// Distance of the corrector from the prediction (max-norm).
        distance: f64,
        /// The guard's bound.
        allowed: f64,
    },
    /// The corrector budget ([`BranchGuard::max_attempts`]) is used up.
    Budget {
        /// The budget.
        max_attempts: usize,
    },
    /// Bad bounds, step sizes or a corrector of the wrong dimension.
    Invalid(BvpError),
}

/// The failure of [`Continuation::follow`]: how far it came and why it stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct ContinuationFailure<E> {
    /// Last parameter value that solved.
    pub reached: f64,
    /// The target value.
    pub target: f64,
    /// The step that failed last.
    pub step: f64,
    /// Accepted steps before the failure.
    pub steps: usize,
    /// The last failure.
    pub cause: StallCause<E>,
}

impl<E: fmt::Display> fmt::Display for ContinuationFailure<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "continuation stalled at parameter {} (target {}, step {:.3e}, {} steps): ",
            self.reached, self.target, self.step, self.steps
        )?;
        match &self.cause {
            StallCause::Inner(e) => write!(f, "{e}"),
            StallCause::Jump {
                at,
                distance,
                allowed,
            } => write!(
                f,
                "branch jump at {at} (distance {distance:.3e} > {allowed:.3e})"
            ),
            StallCause::Budget { max_attempts } => {
                write!(f, "budget of {max_attempts} corrector calls used up")
            }
            StallCause::Invalid(e) => write!(f, "{e}"),
        }
    }
}

impl<E: fmt::Debug + fmt::Display> std::error::Error for ContinuationFailure<E> {}

#[cfg(test)]
mod tests {
    use super::*;

    /// Newton on `f(x) = 0` from `x0` with the derivative `df`, to `|f| <= 1e-14 (1 + |lambda|)`.
    fn newton(
        lambda: f64,
        x0: f64,
        f: impl Fn(f64) -> f64,
        df: impl Fn(f64) -> f64,
    ) -> Result<f64, BvpError> {
        let mut x = x0;
        for _ in 0..60 {
            let r = f(x);
            if r.abs() <= 1e-14 * (1.0 + lambda.abs()) {
                return Ok(x);
            }
            x -= r / df(x);
        }
        Err(BvpError::NoConvergence {
            method: "test newton",
            iterations: 60,
            residual: f(x),
        })
    }

    fn cont(initial_step: f64, min_step: f64, max_step: f64) -> Continuation {
        Continuation {
            initial_step,
            min_step,
            max_step,
        }
    }

    /// `x = sqrt(lambda)` (Newton on `x^2 = lambda`) from `(1, 1)` to 4 and back: the answers
    /// are the roots 2 and 1 to rounding, with no rejected step.
    #[test]
    fn follows_the_square_root_branch_both_ways() {
        let c = cont(0.25, 1e-6, 1.0);
        let sqrt = |l: f64, p: &[f64]| newton(l, p[0], |x| x * x - l, |x| 2.0 * x).map(|x| vec![x]);
        let (x, stats) = c
            .follow(1.0, 4.0, vec![1.0], &BranchGuard::default(), sqrt)
            .unwrap();
        assert!((x[0] - 2.0).abs() < 1e-14, "{}", x[0]);
        // steps 0.25, 0.5, 1.0, 1.0 (max_step), then 0.25 clipped to 4: five steps
        assert_eq!((stats.steps, stats.halvings, stats.jumps), (5, 0, 0));
        let (x, _) = c
            .follow(4.0, 1.0, vec![2.0], &BranchGuard::default(), sqrt)
            .unwrap();
        assert!((x[0] - 1.0).abs() < 1e-14, "{}", x[0]);
        // the slope known at the start (1 / (2 sqrt(1)) = 1/2) is used on the first step:
        // a corrector that accepts only a prediction within 1e-2 of the root succeeds at once
        let strict = |l: f64, p: &[f64]| {
            let x = l.sqrt();
            if (p[0] - x).abs() < 1e-2 {
                Ok(vec![x])
            } else {
                Err(BvpError::InvalidInput {
                    name: "prediction",
                    value: p[0],
                    reason: "too far",
                })
            }
        };
        let c = cont(0.1, 1e-6, 0.1);
        let (x, stats) = c
            .follow_from(
                1.0,
                1.1,
                vec![1.0],
                vec![0.5],
                &BranchGuard::default(),
                strict,
            )
            .unwrap();
        assert_eq!((x[0], stats.steps, stats.halvings), (1.1f64.sqrt(), 1, 0));
        // without the slope the constant prediction 1 is 0.049 off: the step is halved
        let (_, stats) = c
            .follow(1.0, 1.1, vec![1.0], &BranchGuard::default(), strict)
            .unwrap();
        assert!(stats.halvings >= 1, "{stats:?}");
    }

    /// `x^3 - 3x = lambda` has a lower branch `x < -1` up to its fold at `(lambda, x) = (2, -1)`
    /// and beyond it only the upper root (`x = 2.1038...` at `lambda = 3`): Newton from the
    /// prediction past the fold lands there, the guard rejects it, and the run stops at the
    /// fold; without the guard it ends on the other branch.
    #[test]
    fn the_jump_guard_stops_at_a_fold_where_newton_changes_branch() {
        let cubic = |l: f64, p: &[f64]| {
            newton(l, p[0], |x| x * x * x - 3.0 * x - l, |x| 3.0 * x * x - 3.0).map(|x| vec![x])
        };
        let c = cont(0.5, 1e-4, 0.5);
        let start = vec![-(3.0f64.sqrt())];
        let guard = BranchGuard::default();
        let mut landed_above = 0;
        let fail = c
            .follow(0.0, 3.0, start.clone(), &guard, |l, p: &[f64]| {
                let x = cubic(l, p)?;
                if x[0] > -1.0 {
                    landed_above += 1;
                }
                Ok::<_, BvpError>(x)
            })
            .unwrap_err();
        assert!(fail.reached <= 2.0 && fail.reached > 2.0 - 1e-3, "{fail:?}");
        assert!(fail.step < 2e-4, "{}", fail.step);
        assert_eq!(fail.target, 3.0);
        assert!(landed_above > 0, "Newton did land on the upper branch");
        match fail.cause {
            // the last rejection: a jump, or Newton failing at the fold itself
            StallCause::Jump { at, distance, .. } => {
                assert!(at > 2.0 && distance > 1.0, "{at} {distance}")
            }
            StallCause::Inner(_) => {}
            other => panic!("{other:?}"),
        }
        let open = BranchGuard {
            absolute: f64::INFINITY,
            ..guard
        };
        let (x, _) = c.follow(0.0, 3.0, start, &open, cubic).unwrap();
        // the one real root of x^3 - 3x - 3 (Cardano): cbrt(3/2 + sqrt(5)/2) + cbrt(3/2 - sqrt(5)/2)
        let s5 = 5.0f64.sqrt();
        let upper = (1.5 + 0.5 * s5).cbrt() + (1.5 - 0.5 * s5).cbrt();
        assert!((x[0] - upper).abs() < 1e-14, "{} vs {upper}", x[0]);
    }

    /// A corrector that needs the prediction within 0.3 of the answer `x(lambda) = lambda`:
    /// the constant first prediction fails three times, then the secant is exact.
    #[test]
    fn counts_halvings_and_rejects_bad_settings() {
        let c = cont(1.0, 1e-3, 1.0);
        let near = |l: f64, g: &[f64]| {
            if (g[0] - l).abs() > 0.3 {
                Err(BvpError::InvalidInput {
                    name: "guess",
                    value: g[0],
                    reason: "too far",
                })
            } else {
                Ok(vec![l])
            }
        };
        let (x, stats) = c
            .follow(0.0, 2.0, vec![0.0], &BranchGuard::default(), near)
            .unwrap();
        assert_eq!(x, vec![2.0]);
        // h = 1 and 0.5 fail; at 0.25 the answer is 0.25 from the prediction, more than the
        // guard's 0.2: a jump; 0.125 is accepted, then the exact secant: 0.25, 0.5, 1.0 and
        // the last 0.125 (clipped)
        assert_eq!((stats.steps, stats.halvings, stats.jumps), (5, 3, 1));
        let (x, _) = c
            .follow(2.0, 1.0, vec![2.0], &BranchGuard::default(), near)
            .unwrap();
        assert_eq!(x, vec![1.0]);
        let bad = cont(0.0, 1e-3, 1.0)
            .follow(0.0, 1.0, vec![0.0], &BranchGuard::default(), near)
            .unwrap_err();
        assert!(matches!(
            bad.cause,
            StallCause::Invalid(BvpError::InvalidInput {
                name: "initial_step",
                ..
            })
        ));
        let bad = c
            .follow(0.0, f64::NAN, vec![0.0], &BranchGuard::default(), near)
            .unwrap_err();
        assert!(matches!(
            bad.cause,
            StallCause::Invalid(BvpError::InvalidInput { name: "to", .. })
        ));
        let bad = c
            .follow_from(0.0, 1.0, vec![0.0], vec![], &BranchGuard::default(), near)
            .unwrap_err();
        assert!(matches!(
            bad.cause,
            StallCause::Invalid(BvpError::DimensionMismatch { .. })
        ));
    }

    /// Newton on `y^3 + y = lambda` (one root for every lambda): `follow` reaches lambda = 10
    /// and the answer solves the equation to rounding.
    fn cubic_newton(lambda: f64, y0: f64) -> Result<f64, BvpError> {
        let mut y = y0;
        for it in 0..30 {
            let r = y * y * y + y - lambda;
            if r.abs() < 1e-13 * (1.0 + lambda.abs()) {
                return Ok(y);
            }
            y -= r / (3.0 * y * y + 1.0);
            if it == 29 {
                break;
            }
        }
        Err(BvpError::NoConvergence {
            method: "cubic",
            iterations: 30,
            residual: y * y * y + y - lambda,
        })
    }

    #[test]
    fn follow_reaches_the_target_with_a_secant_predictor() {
        let cont = Continuation {
            initial_step: 0.1,
            min_step: 1e-6,
            max_step: 0.5,
        };
        let mut calls = 0;
        let (y, stats) = cont
            .follow(
                0.0,
                10.0,
                vec![0.0],
                &BranchGuard::default(),
                |l, p: &[f64]| {
                    calls += 1;
                    cubic_newton(l, p[0]).map(|y| vec![y])
                },
            )
            .unwrap();
        // y^3 + y = 10 has the root y = 2 exactly
        assert!((y[0] - 2.0).abs() < 1e-12, "{}", y[0]);
        assert_eq!(stats.halvings, 0);
        assert_eq!(stats.steps, calls);
    }

    /// [`Continuation::follow`] from `(0, [0])` to 1 with steps in `[0.01, 0.25]`: its failure.
    fn failure_to_one(
        guard: &BranchGuard,
        correct: impl FnMut(f64, &[f64]) -> Result<Vec<f64>, BvpError>,
    ) -> ContinuationFailure<BvpError> {
        cont(0.25, 0.01, 0.25)
            .follow(0.0, 1.0, vec![0.0], guard, correct)
            .unwrap_err()
    }

    #[test]
    fn follow_fails_with_the_last_inner_error_or_the_jump() {
        // a corrector that fails beyond lambda = 0.5 with its own error
        let fail = failure_to_one(&BranchGuard::default(), |l, _p| {
            if l > 0.5 {
                Err(BvpError::NoConvergence {
                    method: "inner",
                    iterations: 7,
                    residual: l,
                })
            } else {
                Ok(vec![l])
            }
        });
        assert_eq!(fail.reached, 0.5);
        assert!(fail.step < 0.02 && fail.step >= 0.01, "{}", fail.step);
        match fail.cause {
            StallCause::Inner(BvpError::NoConvergence {
                method: "inner",
                iterations: 7,
                residual,
            }) => assert!(residual > 0.5 && residual < 0.52, "{residual}"),
            other => panic!("{other:?}"),
        }
        // a corrector that lands on another branch (y jumps by 1 at lambda > 0.5)
        let guard = BranchGuard {
            absolute: 0.2,
            relative: 0.5,
            max_attempts: 1000,
        };
        let fail = failure_to_one(&guard, |l, _p| Ok(vec![if l > 0.5 { l + 1.0 } else { l }]));
        assert_eq!(fail.reached, 0.5);
        match fail.cause {
            StallCause::Jump { distance, .. } => assert!(distance > 0.9, "{distance}"),
            other => panic!("{other:?}"),
        }
        // the corrector budget (a guard wide enough to accept the first, unpredicted step)
        let guard = BranchGuard {
            absolute: 1.0,
            relative: 0.5,
            max_attempts: 3,
        };
        let fail = failure_to_one(&guard, |l, _p| Ok(vec![l]));
        assert_eq!(fail.cause, StallCause::Budget { max_attempts: 3 });
        assert_eq!(fail.steps, 3);
    }
}
