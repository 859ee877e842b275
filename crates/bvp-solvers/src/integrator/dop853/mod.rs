//! Dormand-Prince 8(5,3) (Hairer's `DOP853`): the driver loop; the tableau, one step, the
//! step-size controller, the dense output and event location live in the submodules.

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod coef;
mod control;
mod dense;
mod events;
mod step;

use super::{all_finite, check_initial, check_span, OdeSystem};
use crate::{BvpError, Result};
use coef::NSTAGE;
use control::{StepControl, Verdict};
use dense::dense_eval;
pub use dense::OdeSolution;

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
    /// With `dense`: store only the cubic Hermite part of each step's interpolant and the
    /// stages its completion needs; [`OdeSolution::refine`] completes a step on demand
    /// (three right-hand-side evaluations per refined step instead of per step).
    pub lazy_dense: bool,
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

/// Work buffers of a DOP853 call (one allocation).
struct Work {
    k: Vec<f64>,
    y: Vec<f64>,
    ynew: Vec<f64>,
    tmp: Vec<f64>,
    rc: Vec<f64>,
}

impl Work {
    fn new(n: usize) -> Self {
        Self {
            k: vec![0.0; NSTAGE * n],
            y: vec![0.0; n],
            ynew: vec![0.0; n],
            tmp: vec![0.0; n],
            rc: vec![0.0; 8 * n],
        }
    }
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
            lazy_dense: false,
        }
    }

    /// Sets whether the dense output is stored.
    pub fn with_dense(self, dense: bool) -> Self {
        Self { dense, ..self }
    }

    /// Stores a lazy dense output (implies `dense`): each step keeps its cubic Hermite
    /// interpolant ([`OdeSolution::eval_cubic_into`]) and the stages from which
    /// [`OdeSolution::refine`] completes Hairer's 7th-order interpolant where it is needed
    /// ([`OdeSolution::eval_into`] reports `false` on a step not refined yet). For callers
    /// that scan a solution cheaply and look closely at a few steps only.
    pub fn with_lazy_dense(self) -> Self {
        Self {
            dense: true,
            lazy_dense: true,
            ..self
        }
    }

    fn check(&self) -> Result<()> {
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

    /// Hairer's `HINIT`: initial step guess for order `iord = 8`.
    #[allow(clippy::too_many_arguments)]
    fn hinit<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        x: f64,
        y: &[f64],
        f0: &[f64],
        f1: &mut [f64],
        y1: &mut [f64],
        posneg: f64,
        hmax: f64,
    ) -> f64 {
        let n = y.len();
        let mut dnf = 0.0;
        let mut dny = 0.0;
        for i in 0..n {
            let sk = self.atol + self.rtol * y[i].abs();
            dnf += (f0[i] / sk).powi(2);
            dny += (y[i] / sk).powi(2);
        }
        let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
            1e-6
        } else {
            (dny / dnf).sqrt() * 0.01
        };
        h = h.min(hmax) * posneg;
        for i in 0..n {
            y1[i] = y[i] + h * f0[i];
        }
        sys.rhs(x + h, y1, f1);
        let mut der2: f64 = 0.0;
        for i in 0..n {
            let sk = self.atol + self.rtol * y[i].abs();
            der2 += ((f1[i] - f0[i]) / sk).powi(2);
        }
        der2 = der2.sqrt() / h.abs();
        let der12 = der2.abs().max(dnf.sqrt());
        let h1 = if der12 <= 1e-15 || !der12.is_finite() {
            (1e-6f64).max(h.abs() * 1e-3)
        } else {
            (0.01 / der12).powf(1.0 / 8.0)
        };
        let h = (100.0 * h.abs()).min(h1).min(hmax);
        if h.is_finite() && h > 0.0 {
            h
        } else {
            hmax.min(1e-6)
        }
    }

    fn run<S: OdeSystem + ?Sized, E: FnMut(f64, &[f64]) -> f64>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
        mut event: Option<E>,
    ) -> Result<(OdeSolution, Option<Event>)> {
        self.check()?;
        check_span(s0, s1)?;
        let n = sys.dim();
        check_initial(n, u0)?;
        let mut stats = IntegrationStats::default();
        let mut sol = OdeSolution {
            s_end: s0,
            u_end: u0.to_vec(),
            stats,
            dim: n,
            s_start: s0,
            u_start: if self.dense { u0.to_vec() } else { Vec::new() },
            points: Vec::new(),
            hs: Vec::new(),
            cont: Vec::new(),
            stages: Vec::new(),
            refined: Vec::new(),
            scratch: Vec::new(),
            dense: self.dense,
        };
        if self.dense {
            // room for a typical integration (vector growth was ~4 % of a short one)
            const GUESS: usize = 32;
            sol.points.reserve(GUESS + 1);
            sol.points.push(s0);
            sol.hs.reserve(GUESS);
            sol.cont.reserve(GUESS * 8 * n);
            if self.lazy_dense {
                sol.stages.reserve(GUESS * 9 * n);
                sol.refined.reserve(GUESS);
            }
        }
        if s0 == s1 {
            return Ok((sol, None));
        }
        // full interpolants of every step (eager dense output), or the cubic part only (lazy
        // dense output, events: completed on the step where an event is located)
        let eager = self.dense && !self.lazy_dense;
        let lazy = self.dense && self.lazy_dense;
        let need_cont = self.dense || event.is_some();
        let Work {
            mut k,
            mut y,
            mut ynew,
            mut tmp,
            mut rc,
        } = Work::new(n);
        y.copy_from_slice(u0);

        let uround = f64::EPSILON;
        let posneg = if s1 > s0 { 1.0 } else { -1.0 };
        let hmax = (s1 - s0).abs();
        let mut control = StepControl::new(hmax, posneg);

        let mut x = s0;
        sys.rhs(x, &y, &mut k[..n]);
        stats.rhs_evals += 1;
        if !all_finite(&k[..n]) {
            return Err(BvpError::NonFinite {
                what: "ODE right-hand side",
                s: x,
            });
        }
        let mut h = match self.h_init {
            Some(h0) => h0.abs().min(hmax) * posneg,
            None => {
                let (k0, rest) = k.split_at_mut(n);
                let hh = self.hinit(sys, x, &y, k0, &mut rest[..n], &mut tmp, posneg, hmax);
                stats.rhs_evals += 1;
                hh * posneg
            }
        };

        let mut g_old = 0.0;
        if let Some(ev) = event.as_mut() {
            g_old = ev(x, &y);
            if g_old.is_nan() {
                return Err(BvpError::NonFinite {
                    what: "event function",
                    s: x,
                });
            }
        }

        let mut last = false;
        let mut attempts = 0usize;
        let mut last_err_nonfinite = false;
        // The step budget bounds the loop: every pass is one attempt.
        loop {
            if attempts >= self.max_steps {
                return Err(BvpError::TooManySteps {
                    max_steps: self.max_steps,
                    s: x,
                });
            }
            if 0.1 * h.abs() <= x.abs() * uround || h == 0.0 {
                if last_err_nonfinite {
                    return Err(BvpError::NonFinite {
                        what: "ODE right-hand side",
                        s: x,
                    });
                }
                return Err(BvpError::StepSizeUnderflow { s: x, h });
            }
            if (x + 1.01 * h - s1) * posneg > 0.0 {
                h = s1 - x;
                last = true;
            }
            attempts += 1;

            step::stages(sys, x, h, &y, &mut k, &mut tmp);
            stats.rhs_evals += 11;
            let xph = x + h;
            let err = step::update_and_error(&y, h, &k, &mut ynew, self.rtol, self.atol);

            if !err.is_finite() {
                // A trial stage left the domain of G (or overflowed): retreat.
                last_err_nonfinite = true;
                last = false;
                stats.rejected += 1;
                h = control.retreat(h);
                continue;
            }
            last_err_nonfinite = false;

            let h_next = match control.judge(err, h) {
                Verdict::Reject { h_retry } => {
                    stats.rejected += 1;
                    last = false;
                    h = h_retry;
                    continue;
                }
                Verdict::Accept { h_next } => h_next,
            };
            stats.steps += 1;
            // k13 = G(x + h, u_new): FSAL derivative
            sys.rhs(xph, &ynew, &mut k[12 * n..13 * n]);
            stats.rhs_evals += 1;
            if !all_finite(&k[12 * n..13 * n]) || !all_finite(&ynew) {
                return Err(BvpError::NonFinite {
                    what: "ODE right-hand side",
                    s: xph,
                });
            }
            if eager {
                dense::prepare(sys, x, h, &y, &ynew, &mut k, &mut tmp, &mut rc);
                stats.rhs_evals += 3;
            } else if need_cont {
                dense::hermite(h, &y, &ynew, &k, &mut rc);
            }
            let mut complete = eager;

            if let Some(ev) = event.as_mut() {
                let g_new = ev(xph, &ynew);
                if g_new.is_nan() {
                    return Err(BvpError::NonFinite {
                        what: "event function",
                        s: xph,
                    });
                }
                if events::crossed(g_old, g_new) {
                    if !complete {
                        dense::extend(sys, x, h, &y, &mut k, &mut tmp, &mut rc);
                        stats.rhs_evals += 3;
                        complete = true;
                    }
                    let s_ev = events::locate(ev, g_new, x, h, posneg, &rc, n, &mut tmp)?;
                    let mut u_ev = vec![0.0; n];
                    if s_ev == xph {
                        u_ev.copy_from_slice(&ynew);
                    } else {
                        dense_eval(&rc, n, (s_ev - x) / h, &mut u_ev);
                    }
                    if self.dense {
                        sol.points.push(s_ev);
                        sol.hs.push(h);
                        sol.cont.extend_from_slice(&rc);
                        if lazy {
                            sol.store_stages(&k, complete);
                        }
                    }
                    sol.s_end = s_ev;
                    sol.u_end.copy_from_slice(&u_ev);
                    sol.stats = stats;
                    return Ok((sol, Some(Event { s: s_ev, u: u_ev })));
                }
                g_old = g_new;
            }

            if self.dense {
                sol.points.push(if last { s1 } else { xph });
                sol.hs.push(h);
                sol.cont.extend_from_slice(&rc);
                if lazy {
                    sol.store_stages(&k, complete);
                }
            }
            // FSAL: k1 <- k13
            k.copy_within(12 * n..13 * n, 0);
            std::mem::swap(&mut y, &mut ynew);
            x = xph;
            if last {
                break;
            }
            h = h_next;
        }
        sol.s_end = s1;
        sol.u_end.copy_from_slice(&y);
        sol.stats = stats;
        Ok((sol, None))
    }
}
