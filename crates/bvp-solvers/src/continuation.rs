//! Natural-parameter (load) continuation: step a parameter `lambda` from an easy value to the
//! target, starting each solve from the previous solution, with step halving on failure.
//!
//! [`Continuation::run`] is the plain driver (each solve starts from the last solution);
//! [`Continuation::follow`] is the driver of the beam methods: a secant predictor, a jump
//! guard that rejects a corrector landing on another branch, a step budget, and a failure
//! that carries the last inner error ([`ContinuationFailure`]).

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::BvpError;
use std::fmt;

/// Step-size controlled natural-parameter continuation.
///
/// Starting at `lambda = from` with step `initial_step`, each step tries
/// `lambda_next = lambda + h` (clipped to `to`), solving from the last solution. On success the
/// step is accepted and `h <- min(2h, max_step)`; on failure `h <- h/2` and the step is retried;
/// when `h < min_step` the continuation stops with `ContinuationStalled` (e.g. at a fold of
/// the solution branch, where natural-parameter continuation cannot pass).
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
    /// Accepted steps (not counting the initial solve at `from`).
    pub steps: usize,
    /// Failed solves that halved the step.
    pub halvings: usize,
    /// Of those, correctors rejected by the jump guard of [`Continuation::follow`]: they
    /// converged on another solution branch, which is therefore near.
    pub jumps: usize,
}

impl Continuation {
    /// Steps a parameter from `from` to `to`: first `solve(from, &start)` (`start` is the
    /// initial guess at `from`; its failure is returned as is), then each solve starts from
    /// the last solution; halves the step on failure, grows it (x2, capped at `max_step`) after
    /// success; errors with `ContinuationStalled { reached, target, step }` when the step falls
    /// below `min_step`. Returns the solution at `to`.
    ///
    /// # Errors
    /// `InvalidInput` for non-finite `from`/`to` or bad step sizes; the first solve's error;
    /// `ContinuationStalled`.
    pub fn run<T: Clone, E: From<BvpError>, F: FnMut(f64, &T) -> Result<T, E>>(
        &self,
        from: f64,
        to: f64,
        start: T,
        mut solve: F,
    ) -> Result<(T, ContinuationStats), E> {
        self.check(from, to).map_err(E::from)?;
        let mut stats = ContinuationStats::default();
        let mut state = solve(from, &start)?;
        let dir = if to >= from { 1.0 } else { -1.0 };
        let mut lambda = from;
        let mut h = self.initial_step;
        // Every attempt either advances lambda by at least min_step or halves h, which falls
        // below min_step after log2(max_step / min_step) halvings in a row: at most
        // |to - from| / min_step accepted steps (`follow` has an explicit budget).
        while lambda != to {
            let remaining = (to - lambda).abs();
            let next = if remaining <= h { to } else { lambda + dir * h };
            match solve(next, &state) {
                Ok(s) => {
                    state = s;
                    lambda = next;
                    stats.steps += 1;
                    h = (2.0 * h).min(self.max_step);
                }
                Err(_) => {
                    stats.halvings += 1;
                    let tried = h.min(remaining);
                    h = 0.5 * tried;
                    if h < self.min_step {
                        return Err(BvpError::ContinuationStalled {
                            reached: lambda,
                            target: to,
                            step: tried,
                        }
                        .into());
                    }
                }
            }
        }
        Ok((state, stats))
    }

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
