//! Dormand-Prince 8(5,3) (Hairer's `DOP853`): the options and the driver of
//! `integrate`/`integrate_until`; the tableau (`coef`), one step (`step`), the step-size
//! controller (`control`), the stepper ([`Stepper`]), the dense output ([`OdeSolution`],
//! [`StepInterpolant`]) and event location (`events`) live in the submodules.

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod coef;
mod control;
mod dense;
mod events;
mod step;
mod stepper;

use super::OdeSystem;
use crate::{BvpError, Result};
pub use dense::Interpolant;
pub use dense::{OdeSolution, StepInterpolant};
pub use stepper::Stepper;

/// Dormand-Prince 8(5,3) (Hairer's `DOP853`) with step-size control, dense output of order 7,
/// and event location.
///
/// One step of size `h` uses 12 stages `k1..k12` (`k1 = G(s, u)` is reused from the previous
/// step, FSAL) and gives the 8th-order update `u_new = u + h sum b_i k_i`. The local error is
/// estimated as in Hairer's code from the 5th-order difference `e5 = h sum er_i k_i` and the
/// 3rd-order difference `e3 = sum b_i k_i - bhh1 k1 - bhh2 k9 - bhh3 k12`,
/// scaled by `sk_i = atol + rtol max(|u_i|, |u_new,i|)`:
///
/// `err = |h| E5 / sqrt(n (E5 + 0.01 E3))` with `E5 = sum (e5_i/sk_i)^2`, `E3 = sum (e3_i/sk_i)^2`.
///
/// The step is accepted if `err <= 1`; the new step is `h / max(1/6, min(3, err^(1/8)/0.9))`
/// (after a rejection no increase). When `h_init` is `None`, the initial step is Hairer's
/// `HINIT` guess. Dense output uses three extra stages `k14..k16` and Hairer's 7th-degree
/// interpolant.
#[derive(Clone, Debug)]
pub struct Dop853 {
    /// Relative tolerance (`>= 0`).
    pub rtol: f64,
    /// Absolute tolerance (`>= 0`, `rtol + atol > 0`).
    pub atol: f64,
    /// Initial step size magnitude; `None` = Hairer's automatic guess.
    pub h_init: Option<f64>,
    /// Maximum number of attempted steps (accepted + rejected).
    pub max_steps: usize,
    /// Store the dense output for [`OdeSolution::eval`].
    pub dense: bool,
}

/// Work counters of an adaptive integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IntegrationStats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Right-hand-side evaluations.
    pub rhs_evals: usize,
}

/// A located zero of an event function.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Location of the zero crossing.
    pub s: f64,
    /// State there (from the dense output).
    pub u: Vec<f64>,
}

impl Dop853 {
    /// Tolerances `rtol`, `atol`; automatic initial step, `max_steps = 100_000`, no dense output.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self {
            rtol,
            atol,
            h_init: None,
            max_steps: 100_000,
            dense: false,
        }
    }

    /// Sets whether the dense output is stored.
    pub fn with_dense(self, dense: bool) -> Self {
        Self { dense, ..self }
    }

    pub(super) fn check(&self) -> Result<()> {
        let bad = |name, value, reason| {
            Err(BvpError::InvalidInput {
                name,
                value,
                reason,
            })
        };
        if !(self.rtol >= 0.0 && self.rtol.is_finite()) {
            return bad("rtol", self.rtol, "must be finite and >= 0");
        }
        if !(self.atol >= 0.0 && self.atol.is_finite()) {
            return bad("atol", self.atol, "must be finite and >= 0");
        }
        if self.rtol + self.atol <= 0.0 {
            return bad(
                "rtol + atol",
                0.0,
                "at least one tolerance must be positive",
            );
        }
        if let Some(h) = self.h_init {
            if !(h.is_finite() && h != 0.0) {
                return bad("h_init", h, "must be finite and non-zero");
            }
        }
        if self.max_steps == 0 {
            return bad("max_steps", 0.0, "must be at least 1");
        }
        Ok(())
    }

    /// Integrates `u' = G(s, u)`, `u(s0) = u0` from `s0` to `s1` (either direction).
    ///
    /// # Errors
    /// `StepSizeUnderflow`, `TooManySteps`, `NonFinite` (the right-hand side returned NaN/inf at
    /// an accepted state), `InvalidInput` (bad tolerances/bounds, non-finite `u0`),
    /// `DimensionMismatch`.
    pub fn integrate<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
    ) -> Result<OdeSolution> {
        let (sol, _) = self.run(sys, s0, s1, u0, None::<fn(f64, &[f64]) -> f64>)?;
        Ok(sol)
    }

    /// Integrates until the first zero crossing of `event(s, u)` after `s0` (a sign change
    /// between the ends of an accepted step, or an exact zero at a step end), located to
    /// `|ds| <= 1e-14 * max(|s_a|, |s_b|, |h|)` by Brent's method on the dense output; or until
    /// `s1` if there is none. The returned solution ends at the event. A zero of `event` at
    /// `s0` itself is not an event.
    ///
    /// # Errors
    /// As [`Dop853::integrate`]; `NonFinite` if the event function returns NaN.
    pub fn integrate_until<S: OdeSystem + ?Sized, E: FnMut(f64, &[f64]) -> f64>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
        event: E,
    ) -> Result<(OdeSolution, Option<Event>)> {
        self.run(sys, s0, s1, u0, Some(event))
    }

    /// The driver of [`Dop853::integrate`] and [`Dop853::integrate_until`]: a
    /// [`Stepper`], each accepted step's interpolant stored (dense output) and searched for
    /// the event ([`Stepper::crossing`]).
    fn run<S: OdeSystem + ?Sized, E: FnMut(f64, &[f64]) -> f64>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
        mut event: Option<E>,
    ) -> Result<(OdeSolution, Option<Event>)> {
        let mut st = self.stepper(sys, s0, s1, u0)?;
        let mut sol = OdeSolution::start(s0, u0, self.dense);
        if s0 == s1 {
            return Ok((sol, None));
        }
        let mut g_old = 0.0;
        if let Some(ev) = event.as_mut() {
            g_old = events::finite(ev(s0, u0), s0)?;
        }
        while st.step()? {
            if self.dense {
                st.prepare(Interpolant::Full);
            }
            if let Some(ev) = event.as_mut() {
                let (g_new, hit) = st.crossing(ev, g_old)?;
                if let Some(e) = hit {
                    if self.dense {
                        sol.store_step(e.s, st.h(), st.coefficients().0);
                    }
                    sol.s_end = e.s;
                    sol.u_end.copy_from_slice(&e.u);
                    sol.stats = st.stats();
                    sol.start_step = st.start_step();
                    return Ok((sol, Some(e)));
                }
                g_old = g_new;
            }
            if self.dense {
                let end = if st.is_last() { s1 } else { st.end() };
                sol.store_step(end, st.h(), st.coefficients().0);
            }
        }
        sol.s_end = s1;
        sol.u_end.copy_from_slice(st.state());
        sol.stats = st.stats();
        sol.start_step = st.start_step();
        Ok((sol, None))
    }
}
