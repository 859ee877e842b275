//! Natural-parameter continuation: the pseudo-arclength driver with the parameter as its one
//! coordinate.
//!
//! [`Continuation::follow`] (and [`Continuation::follow_from`], with a known first slope)
//! steps a parameter `lambda` from a known solution to a target, each solve warm-started
//! from the secant prediction off the last two solutions. It runs on [`Arclength`]: the
//! branch seen as a curve whose only coordinate is `lambda` (a [`Curve`] of dimension 1),
//! so the tangent is `+-1`, the tangent predictor steps `lambda` by exactly the step, the
//! corrector's hyperplane is `lambda = const` (the caller's solve at a fixed parameter),
//! and the step control is the arclength's ([`ArcControl`] with the step doubled after
//! every accepted point and halved after a rejected one). What the natural path adds on top:
//!
//! - the secant predictor of the state the caller solves for (the arclength's points carry
//!   it; the predictor of the coordinate is the arclength's);
//! - a jump guard ([`BranchGuard`]) that rejects a corrector landing on another branch;
//! - the last step clipped to end exactly on the target, and a budget of corrector calls;
//! - a failure that carries the last inner error ([`ContinuationFailure`]).

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::arclength::{ArcControl, Arclength, Attempt, Curve, Predictor};
use crate::BvpError;
use std::cell::{Cell, RefCell};
use std::fmt;

/// Step-size controlled natural-parameter continuation.
///
/// Starting at `lambda = from` with step `initial_step`, each step tries
/// `lambda_next = lambda + h` (clipped to `to`), correcting a prediction off the last
/// solutions. On success the step is accepted and `h <- min(2h, max_step)`; on failure
/// `h <- h/2` and the step is retried; when `h < min_step` the continuation stops (e.g. at a
/// fold of the solution branch, where natural-parameter continuation cannot pass: there
/// [`Arclength`] on the curve in `(state, lambda)` takes over): see
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

    /// The arclength step control the natural path runs on: steps in
    /// `[min_step, max_step]` from `initial_step`, doubled after every accepted point (every
    /// correction counts as easy), halved after a rejected one, the tangent predictor (in
    /// the one coordinate `lambda`: a step of exactly `h`), no turn check (the tangent is
    /// always `+-1`).
    pub fn control(&self) -> ArcControl {
        ArcControl {
            initial: self.initial_step,
            max: self.max_step,
            min: self.min_step,
            grow: 2.0,
            shorten: 1.0,
            easy: usize::MAX,
            hard: usize::MAX,
            min_turn_cos: 0.0,
            predictor: Predictor::Tangent,
        }
    }

    /// Follows the solution branch `y(lambda)` of a parameter-dependent problem from
    /// `(from, start)` (a known solution, not re-solved) to `to`, the one driver of
    /// natural-parameter continuation:
    ///
    /// - predictor: the secant through the last two accepted points,
    ///   `y_pred = y_k + (lambda - lambda_k) (y_k - y_{k-1}) / (lambda_k - lambda_{k-1})`
    ///   (the constant `y_k` on the first step);
    /// - corrector: `correct(lambda, &y_pred)`, the caller's solver warm-started from the
    ///   prediction;
    /// - jump guard: a corrector that lands farther than
    ///   `guard.absolute + guard.relative * |y_pred - y_k|` (max-norm) from its prediction has
    ///   jumped to another branch; the step is rejected like a failed corrector;
    /// - step control ([`Continuation::control`]): success doubles the step (capped at
    ///   `max_step`), a rejection halves it; below `min_step`, or after
    ///   `guard.max_attempts` correctors, the run fails.
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
        correct: F,
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
        let path = NaturalPath {
            correct: RefCell::new(correct),
            guard,
            to,
            ends: Cell::new(false),
            jumps: Cell::new(0),
            invalid: RefCell::new(None),
        };
        let first = State {
            lambda: from,
            y: start,
            slope,
        };
        let mut arc = Arclength::new(&path, first, [dir], self.control());
        let mut stats = ContinuationStats::default();
        let mut attempts = 0usize;
        while arc.current().lambda != to {
            let (lambda, h) = (arc.current().lambda, arc.step());
            if attempts >= guard.max_attempts {
                let cause = StallCause::Budget {
                    max_attempts: guard.max_attempts,
                };
                return Err(fail(lambda, h, stats.steps, cause));
            }
            attempts += 1;
            // the last step ends exactly on the target
            let remaining = (to - lambda).abs();
            path.ends.set(remaining <= h);
            arc.limit_step(remaining);
            let tried = arc.step();
            let cause = match arc.attempt(&path) {
                Attempt::Point(point, t) => {
                    arc.accept(&path, point, t);
                    stats.steps += 1;
                    continue;
                }
                Attempt::Retry => match path.invalid.take() {
                    Some(e) => StallCause::Invalid(e),
                    None => {
                        stats.halvings += 1;
                        continue;
                    }
                },
                Attempt::Failed(cause) => cause,
            };
            stats.jumps = path.jumps.get();
            if matches!(cause, StallCause::Invalid(_)) {
                return Err(fail(lambda, h, stats.steps, cause));
            }
            stats.halvings += 1;
            return Err(fail(lambda, tried, stats.steps, cause));
        }
        stats.jumps = path.jumps.get();
        Ok((arc.into_current().y, stats))
    }
}

/// A solved point of the natural path: the parameter, the caller's state and its slope
/// `dy/dlambda` (the secant through this point and the one before, or the known first
/// slope).
#[derive(Clone, Debug)]
struct State {
    lambda: f64,
    y: Vec<f64>,
    slope: Vec<f64>,
}

/// The branch `y(lambda)` as a [`Curve`] in its one coordinate `lambda`: the corrector
/// predicts the state by the secant, calls the caller's solve at the fixed parameter and
/// applies the jump guard.
struct NaturalPath<'g, F> {
    correct: RefCell<F>,
    guard: &'g BranchGuard,
    to: f64,
    /// Whether the attempt under way ends on the target (set by the driver).
    ends: Cell<bool>,
    /// Correctors rejected by the guard.
    jumps: Cell<usize>,
    /// A corrector of the wrong dimension: the run ends.
    invalid: RefCell<Option<BvpError>>,
}

impl<E, F> Curve<1> for NaturalPath<'_, F>
where
    F: FnMut(f64, &[f64]) -> Result<Vec<f64>, E>,
{
    type Point = State;
    type Error = StallCause<E>;

    fn coords(&self, p: &State) -> [f64; 1] {
        [p.lambda]
    }

    fn correct(
        &self,
        from: &State,
        p: [f64; 1],
        _n: [f64; 1],
        _radius: f64,
    ) -> Result<State, StallCause<E>> {
        let next = if self.ends.get() { self.to } else { p[0] };
        let dl = next - from.lambda;
        let pred: Vec<f64> = (from.y.iter().zip(&from.slope))
            .map(|(&y, &d)| y + d * dl)
            .collect();
        let sol = (self.correct.borrow_mut())(next, &pred).map_err(StallCause::Inner)?;
        if sol.len() != from.y.len() {
            let e = BvpError::DimensionMismatch {
                name: "continuation state",
                expected: from.y.len(),
                found: sol.len(),
            };
            *self.invalid.borrow_mut() = Some(e.clone());
            return Err(StallCause::Invalid(e));
        }
        let distance = max_diff(&sol, &pred);
        let allowed = self.guard.absolute + self.guard.relative * max_diff(&pred, &from.y);
        if !(distance.is_finite() && distance <= allowed) {
            self.jumps.set(self.jumps.get() + 1);
            return Err(StallCause::Jump {
                at: next,
                distance,
                allowed,
            });
        }
        let slope = (sol.iter().zip(&from.y))
            .map(|(a, b)| (a - b) / dl)
            .collect();
        Ok(State {
            lambda: next,
            y: sol,
            slope,
        })
    }

    fn tangent(&self, _p: &State, dir: &[f64; 1]) -> [f64; 1] {
        [if dir[0] < 0.0 { -1.0 } else { 1.0 }]
    }

    fn iterations(&self, _p: &State) -> usize {
        0
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
mod tests;
