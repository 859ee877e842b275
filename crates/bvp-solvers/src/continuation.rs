//! Natural-parameter (load) continuation: step a parameter `lambda` from an easy value to the
//! target, starting each solve from the previous solution, with step halving on failure.

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::BvpError;

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
        let bad = |name, value, reason| -> E {
            BvpError::InvalidInput {
                name,
                value,
                reason,
            }
            .into()
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
        let mut stats = ContinuationStats::default();
        let mut state = solve(from, &start)?;
        let dir = if to >= from { 1.0 } else { -1.0 };
        let mut lambda = from;
        let mut h = self.initial_step;
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
}
