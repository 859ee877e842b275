//! The DOP853 stepper: one accepted step at a time (rejected attempts are retried inside),
//! with the step's interpolant on demand. [`Dop853::integrate`] and
//! [`Dop853::integrate_until`] drive it; a caller that needs to look at every step (its own
//! stopping rule, a scan of the solution as it grows) drives it directly.

use super::control::{StepControl, Verdict};
use super::dense::{dense_eval, extend, hermite, Interpolant, StepInterpolant};
use super::{events, step};
use super::{Dop853, Event, IntegrationStats};
use crate::integrator::{all_finite, check_initial, check_span, OdeSystem};
use crate::{BvpError, Result};

/// A DOP853 integration advanced one accepted step at a time (module docs).
///
/// ```
/// use bvp_solvers::integrator::{Dop853, Interpolant, OdeSystem};
///
/// struct Decay;
/// impl OdeSystem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) { du[0] = -u[0]; }
/// }
/// let opts = Dop853::new(1e-12, 1e-12);
/// let mut st = opts.stepper(&Decay, 0.0, 2.0, &[1.0]).unwrap();
/// let mut mid = [0.0];
/// while st.step().unwrap() {
///     // the middle of every step, from its 7th-order interpolant
///     st.prepare(Interpolant::Full);
///     assert!(st.interpolant::<1>().unwrap().eval(0.5, &mut mid));
///     let s = st.start() + 0.5 * st.h();
///     assert!((mid[0] - (-s).exp()).abs() < 1e-11);
/// }
/// assert!((st.state()[0] - (-2.0f64).exp()).abs() < 1e-12);
/// ```
pub struct Stepper<'a, S: OdeSystem + ?Sized> {
    sys: &'a S,
    opts: &'a Dop853,
    n: usize,
    s1: f64,
    posneg: f64,
    /// Start of the current step (after [`Stepper::step`]), else the current point.
    x: f64,
    /// Size of the current step, else of the next attempt.
    h: f64,
    /// The controller's proposal for the step after the current one.
    h_next: f64,
    /// Its proposal after the first accepted step ([`Stepper::start_step`]).
    start_step: Option<f64>,
    /// All work space in one allocation ([`Parts`]): the stages `k1..k16` (16 blocks of
    /// `n`), the state at `x`, the state at the end of the current step, a scratch vector
    /// and the interpolation coefficients of the current step (8 blocks of `n`).
    buf: Vec<f64>,
    control: StepControl,
    stats: IntegrationStats,
    attempts: usize,
    /// The current step ends at `s1`.
    last: bool,
    /// An accepted step is held (not yet committed by the next [`Stepper::step`]).
    held: bool,
    done: bool,
    interp: Interpolant,
}

thread_local! {
    /// The work space of this thread's last [`Stepper`], kept for its next one.
    static SPARE: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A work space of `len` values: this thread's spare one where it has one (no allocation
/// and no zeroing per integration: measured 2 % of a contact sweep's instructions), its
/// earlier values left in place, for the stepper writes every value before it reads it.
/// Debug builds (the tests) fill it with NaN instead, so that a read before a write shows
/// in every result.
fn spare_buffer(len: usize) -> Vec<f64> {
    let mut v = SPARE.with(|s| std::mem::take(&mut *s.borrow_mut()));
    if cfg!(debug_assertions) {
        v.clear();
        v.resize(len, f64::NAN);
    } else {
        v.resize(len, 0.0);
    }
    v
}

/// The work space goes back to the thread's spare (the larger of the two is kept).
impl<S: OdeSystem + ?Sized> Drop for Stepper<'_, S> {
    fn drop(&mut self) {
        let buf = std::mem::take(&mut self.buf);
        SPARE.with(|s| {
            let mut s = s.borrow_mut();
            if buf.capacity() > s.capacity() {
                *s = buf;
            }
        });
    }
}

impl Dop853 {
    /// A [`Stepper`] for `u' = G(s, u)`, `u(s0) = u0` from `s0` to `s1` (either direction):
    /// checks the input, evaluates `G(s0, u0)` and chooses the initial step.
    ///
    /// # Errors
    /// `InvalidInput` (bad tolerances/bounds, non-finite `u0`), `DimensionMismatch`,
    /// `NonFinite` (`G(s0, u0)` not finite).
    pub fn stepper<'a, S: OdeSystem + ?Sized>(
        &'a self,
        sys: &'a S,
        s0: f64,
        s1: f64,
        u0: &[f64],
    ) -> Result<Stepper<'a, S>> {
        self.check()?;
        check_span(s0, s1)?;
        let n = sys.dim();
        check_initial(n, u0)?;
        let posneg = if s1 > s0 { 1.0 } else { -1.0 };
        let hmax = (s1 - s0).abs();
        let mut st = Stepper {
            sys,
            opts: self,
            n,
            s1,
            posneg,
            x: s0,
            h: 0.0,
            h_next: 0.0,
            start_step: None,
            buf: spare_buffer((super::coef::NSTAGE + 11) * n),
            control: StepControl::new(hmax, posneg),
            stats: IntegrationStats::default(),
            attempts: 0,
            last: false,
            held: false,
            done: s0 == s1,
            interp: Interpolant::None,
        };
        st.parts().y.copy_from_slice(u0);
        if st.done {
            return Ok(st);
        }
        let p = st.parts();
        sys.rhs(s0, p.y, &mut p.k[..n]);
        st.stats.rhs_evals += 1;
        if !all_finite(&st.parts().k[..n]) {
            return Err(BvpError::NonFinite {
                what: "ODE right-hand side",
                s: s0,
            });
        }
        st.h = match self.h_init {
            Some(h0) => h0.abs().min(hmax) * posneg,
            None => {
                let hh = st.hinit(hmax);
                st.stats.rhs_evals += 1;
                hh * posneg
            }
        };
        Ok(st)
    }
}

/// The work space of a [`Stepper`], split.
struct Parts<'b> {
    k: &'b mut [f64],
    y: &'b mut [f64],
    ynew: &'b mut [f64],
    tmp: &'b mut [f64],
    rc: &'b mut [f64],
}

impl<S: OdeSystem + ?Sized> Stepper<'_, S> {
    /// The work space split into its parts.
    fn parts(&mut self) -> Parts<'_> {
        let n = self.n;
        let (k, rest) = self.buf.split_at_mut(super::coef::NSTAGE * n);
        let (y, rest) = rest.split_at_mut(n);
        let (ynew, rest) = rest.split_at_mut(n);
        let (tmp, rc) = rest.split_at_mut(n);
        Parts {
            k,
            y,
            ynew,
            tmp,
            rc,
        }
    }

    /// The work space's offsets: stages, state, end state, scratch, coefficients.
    fn offsets(&self) -> [usize; 5] {
        let k = super::coef::NSTAGE * self.n;
        [0, k, k + self.n, k + 2 * self.n, k + 3 * self.n]
    }

    /// Hairer's `HINIT`: initial step guess for order `iord = 8` (uses `k1` and two stage
    /// slots as scratch).
    fn hinit(&mut self, hmax: f64) -> f64 {
        let (n, x, posneg) = (self.n, self.x, self.posneg);
        let (atol, rtol) = (self.opts.atol, self.opts.rtol);
        let sys = self.sys;
        let p = self.parts();
        let (f0, rest) = p.k.split_at_mut(n);
        let f1 = &mut rest[..n];
        let (y, y1) = (&*p.y, p.tmp);
        let mut dnf = 0.0;
        let mut dny = 0.0;
        for i in 0..n {
            let sk = atol + rtol * y[i].abs();
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
            let sk = atol + rtol * y[i].abs();
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

    /// Moves past the held step (FSAL: `k1 <- k13`).
    fn commit(&mut self) {
        let n = self.n;
        let p = self.parts();
        p.k.copy_within(12 * n..13 * n, 0);
        p.y.copy_from_slice(p.ynew);
        self.x += self.h;
        self.held = false;
        self.interp = Interpolant::None;
        if self.last {
            self.done = true;
        } else {
            self.h = self.h_next;
        }
    }

    /// Takes the next accepted step (retrying rejected attempts with smaller steps): `true`
    /// with the step held ([`Stepper::start`], [`Stepper::h`], [`Stepper::end_state`],
    /// [`Stepper::interpolant`]), `false` once the end `s1` was reached.
    ///
    /// # Errors
    /// `StepSizeUnderflow`, `TooManySteps`, `NonFinite` (the right-hand side returned NaN/inf
    /// at an accepted state, or at every retreat of a trial stage).
    pub fn step(&mut self) -> Result<bool> {
        if self.held {
            self.commit();
        }
        if self.done {
            return Ok(false);
        }
        let n = self.n;
        let mut last_err_nonfinite = false;
        // the step budget bounds the loop: every pass is one attempt
        loop {
            let (x, mut h) = (self.x, self.h);
            if self.attempts >= self.opts.max_steps {
                return Err(BvpError::TooManySteps {
                    max_steps: self.opts.max_steps,
                    s: x,
                });
            }
            if 0.1 * h.abs() <= x.abs() * f64::EPSILON || h == 0.0 {
                if last_err_nonfinite {
                    return Err(BvpError::NonFinite {
                        what: "ODE right-hand side",
                        s: x,
                    });
                }
                return Err(BvpError::StepSizeUnderflow { s: x, h });
            }
            if (x + 1.01 * h - self.s1) * self.posneg > 0.0 {
                h = self.s1 - x;
                self.h = h;
                self.last = true;
            }
            self.attempts += 1;
            let (sys, rtol, atol) = (self.sys, self.opts.rtol, self.opts.atol);
            let p = self.parts();
            step::stages(sys, x, h, p.y, p.k, p.tmp);
            let err = step::update_and_error(p.y, h, p.k, p.ynew, rtol, atol);
            self.stats.rhs_evals += 11;
            if !err.is_finite() {
                // a trial stage left the domain of G (or overflowed): retreat
                last_err_nonfinite = true;
                self.last = false;
                self.stats.rejected += 1;
                self.h = self.control.retreat(h);
                continue;
            }
            last_err_nonfinite = false;
            match self.control.judge(err, h) {
                Verdict::Reject { h_retry } => {
                    self.stats.rejected += 1;
                    self.last = false;
                    self.h = h_retry;
                }
                Verdict::Accept { h_next } => {
                    self.h_next = h_next;
                    if self.start_step.is_none() {
                        self.start_step = Some(h_next.abs());
                    }
                    break;
                }
            }
        }
        self.stats.steps += 1;
        // k13 = G(x + h, u_new): FSAL derivative
        let xph = self.x + self.h;
        let sys = self.sys;
        let p = self.parts();
        sys.rhs(xph, p.ynew, &mut p.k[12 * n..13 * n]);
        let finite = all_finite(&p.k[12 * n..13 * n]) && all_finite(p.ynew);
        self.stats.rhs_evals += 1;
        if !finite {
            return Err(BvpError::NonFinite {
                what: "ODE right-hand side",
                s: xph,
            });
        }
        self.held = true;
        Ok(true)
    }

    /// Computes the held step's interpolant up to `level` (the cubic part costs nothing;
    /// the full one three evaluations, once).
    pub fn prepare(&mut self, level: Interpolant) {
        if !self.held || level == Interpolant::None {
            return;
        }
        let (sys, x, h, interp) = (self.sys, self.x, self.h, self.interp);
        let p = self.parts();
        if interp == Interpolant::None {
            hermite(h, p.y, p.ynew, p.k, p.rc);
            self.interp = Interpolant::Cubic;
        }
        if level == Interpolant::Full && self.interp != Interpolant::Full {
            let p = self.parts();
            extend(sys, x, h, p.y, p.k, p.tmp, p.rc);
            self.stats.rhs_evals += 3;
            self.interp = Interpolant::Full;
        }
    }

    /// Start of the held step (the current point otherwise).
    pub fn start(&self) -> f64 {
        self.x
    }

    /// Size of the held step.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// End of the held step as computed (`start + h`).
    pub fn end(&self) -> f64 {
        self.x + self.h
    }

    /// Whether the held step is the last (it ends at `s1`).
    pub fn is_last(&self) -> bool {
        self.last
    }

    /// Direction of integration (`+1` or `-1`).
    pub fn direction(&self) -> f64 {
        self.posneg
    }

    /// State at the start of the held step (the current state otherwise).
    pub fn state(&self) -> &[f64] {
        let [_, y, ..] = self.offsets();
        &self.buf[y..y + self.n]
    }

    /// State at the end of the held step.
    pub fn end_state(&self) -> &[f64] {
        let [_, _, ynew, ..] = self.offsets();
        &self.buf[ynew..ynew + self.n]
    }

    /// The held step's interpolation coefficients (8 blocks of `dim`; the last four valid
    /// once [`Interpolant::Full`] is prepared) and how far they are computed.
    pub(super) fn coefficients(&self) -> (&[f64], Interpolant) {
        let [_, _, _, _, rc] = self.offsets();
        (&self.buf[rc..rc + 8 * self.n], self.interp)
    }

    /// A copy of the held step's interpolant as far as it is prepared ([`Stepper::prepare`]),
    /// kept after the stepper moves on; `None` without a held step or if `N` is not the
    /// system's dimension.
    pub fn interpolant<const N: usize>(&self) -> Option<StepInterpolant<N>> {
        let mut out = StepInterpolant::default();
        self.interpolant_into(&mut out).then_some(out)
    }

    /// [`Stepper::interpolant`] written into `out` in place (only the blocks prepared are
    /// copied, the others left as they were: a caller that keeps every step's interpolant
    /// in a `Vec` copies each once); `false` (and `out` untouched) without a held step or
    /// if `N` is not the system's dimension.
    pub fn interpolant_into<const N: usize>(&self, out: &mut StepInterpolant<N>) -> bool {
        if !self.held || N != self.n {
            return false;
        }
        let (rc, level) = self.coefficients();
        let blocks = match level {
            Interpolant::None => 0,
            Interpolant::Cubic => 4,
            Interpolant::Full => 8,
        };
        out.start = self.x;
        out.h = self.h;
        out.level = level;
        for (b, src) in out.rc.iter_mut().zip(rc.chunks_exact(N)).take(blocks) {
            b.copy_from_slice(src);
        }
        true
    }

    /// The held step checked for a zero of the event function `g = ev(s, u)`, which had the
    /// value `g_old` at the step's start: `g` at the step's end, and the event if `g` crossed
    /// zero over the step (a sign change, or an exact zero at the end), located by Brent's
    /// method on the step's 7th-order interpolant (prepared here) to
    /// `|ds| <= 1e-14 max(|start|, |end|, |h|)`, with the state there.
    ///
    /// # Errors
    /// `NonFinite` if `ev` returns NaN.
    pub fn crossing<E: FnMut(f64, &[f64]) -> f64>(
        &mut self,
        ev: &mut E,
        g_old: f64,
    ) -> Result<(f64, Option<Event>)> {
        let xph = self.end();
        let g_new = events::finite(ev(xph, self.end_state()), xph)?;
        if !self.held || !events::crossed(g_old, g_new) {
            return Ok((g_new, None));
        }
        self.prepare(Interpolant::Full);
        let n = self.n;
        let [_, _, ynew, _, rc] = self.offsets();
        let rc = &self.buf[rc..rc + 8 * n];
        let mut u = vec![0.0; n];
        let span = events::StepSpan {
            x: self.x,
            h: self.h,
            posneg: self.posneg,
            rc,
        };
        let s = events::locate(ev, g_new, &span, &mut u)?;
        if s == xph {
            u.copy_from_slice(&self.buf[ynew..ynew + n]);
        } else {
            dense_eval(rc, n, (s - self.x) / self.h, &mut u);
        }
        Ok((g_new, Some(Event { s, u })))
    }

    /// The step size the controller proposed after the first accepted step (`None` before
    /// it): the natural step at the start, whatever the initial guess was. An integration
    /// of a nearby problem from the same point at tolerance `tol'` starts well with it
    /// scaled by `(tol' / tol)^(1/8)` ([`Dop853::h_init`]; the initial guess otherwise
    /// costs an evaluation and, being cautious, often a short first step).
    pub fn start_step(&self) -> Option<f64> {
        self.start_step
    }

    /// Work counters so far.
    pub fn stats(&self) -> IntegrationStats {
        self.stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Harmonic;

    #[test]
    fn an_interpolant_written_in_place_is_the_copy() {
        let opts = Dop853::new(1e-10, 1e-10);
        let mut st = opts.stepper(&Harmonic, 0.0, 3.0, &[0.0, 1.0]).unwrap();
        let mut kept = StepInterpolant::<2>::default();
        assert!(!st.interpolant_into(&mut kept), "no step held yet");
        assert_eq!(kept, StepInterpolant::default());
        assert!(st.step().unwrap());
        assert!(!st.interpolant_into(&mut StepInterpolant::<3>::default()));
        // the cubic part, then the whole interpolant over it: each the copy's
        st.prepare(Interpolant::Cubic);
        assert!(st.interpolant_into(&mut kept));
        assert_eq!(Some(kept), st.interpolant::<2>());
        st.prepare(Interpolant::Full);
        assert!(st.interpolant_into(&mut kept));
        assert_eq!(Some(kept), st.interpolant::<2>());
        let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
        assert!(kept.eval(0.5, &mut a));
        let s = st.start() + 0.5 * st.h();
        assert!((a[0] - s.sin()).abs() < 1e-9 && (a[1] - s.cos()).abs() < 1e-9);
        // the next step's cubic part over it: the blocks not prepared are left as they were
        assert!(st.step().unwrap());
        st.prepare(Interpolant::Cubic);
        let before = kept;
        assert!(st.interpolant_into(&mut kept));
        assert_eq!(kept.level(), Interpolant::Cubic);
        assert!(!kept.eval(0.5, &mut b));
        assert_eq!(kept.rc[4..], before.rc[4..]);
    }

    #[test]
    fn a_copied_interpolant_is_the_held_steps() {
        let opts = Dop853::new(1e-12, 1e-12);
        let mut st = opts.stepper(&Harmonic, 0.0, 3.0, &[0.0, 1.0]).unwrap();
        assert!(st.interpolant::<2>().is_none(), "no step held yet");
        assert!(st.step().unwrap());
        assert_eq!(st.interpolant::<2>().unwrap().level(), Interpolant::None);
        assert!(st
            .interpolant::<2>()
            .unwrap()
            .cubic_coefficients()
            .is_none());
        st.prepare(Interpolant::Full);
        let copy = st.interpolant::<2>().unwrap();
        assert_eq!((copy.start(), copy.h()), (st.start(), st.h()));
        let (mut a, mut b, mut db) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        for theta in [0.0, 0.3, 1.0] {
            // the held step's own coefficients
            dense_eval(st.coefficients().0, 2, theta, &mut a);
            assert!(copy.eval(theta, &mut b));
            assert_eq!(a, b);
            // the cubic part: at the ends the step's values and slopes
            assert!(copy.eval_cubic(theta, &mut b, &mut db));
            if theta != 0.3 {
                let s = st.start() + theta * st.h();
                assert!((b[0] - s.sin()).abs() < 1e-12 && (b[1] - s.cos()).abs() < 1e-12);
                assert!((db[0] - s.cos()).abs() < 1e-12 && (db[1] + s.sin()).abs() < 1e-12);
            }
        }
        // the cubic's coefficients give the cubic part's values and h times its slopes
        let [r0, r1, r2, r3] = *copy.cubic_coefficients().unwrap();
        let th: f64 = 0.3;
        assert!(copy.eval_cubic(th, &mut b, &mut db));
        for i in 0..2 {
            assert_eq!(
                b[i],
                r0[i] + th * (r1[i] + (1.0 - th) * (r2[i] + th * r3[i]))
            );
            let hd = r1[i] + (1.0 - 2.0 * th) * r2[i] + th * (2.0 - 3.0 * th) * r3[i];
            assert_eq!(db[i], hd / copy.h());
        }
        // the copy outlives the step
        assert!(st.step().unwrap());
        assert!(copy.eval(0.5, &mut b));
        assert!((b[0] - (copy.start() + 0.5 * copy.h()).sin()).abs() < 1e-12);
    }

    #[test]
    fn crossing_locates_the_first_zero_on_the_held_step() {
        // sin s crosses zero at pi
        let opts = Dop853::new(1e-12, 1e-12);
        let mut st = opts
            .stepper(&Harmonic, 0.5, 5.0, &[0.5f64.sin(), 0.5f64.cos()])
            .unwrap();
        let mut ev = |_: f64, u: &[f64]| u[0];
        let mut g_old = 0.5f64.sin();
        let mut found = None;
        while st.step().unwrap() {
            let (g, hit) = st.crossing(&mut ev, g_old).unwrap();
            if let Some(e) = hit {
                assert!(st.start() < e.s && e.s <= st.end());
                found = Some(e);
                break;
            }
            assert_eq!(g, st.end_state()[0]);
            g_old = g;
        }
        let e = found.expect("a crossing");
        assert!((e.s - std::f64::consts::PI).abs() < 1e-12, "{}", e.s);
        assert!(
            e.u[0].abs() < 1e-12 && (e.u[1] + 1.0).abs() < 1e-11,
            "{:?}",
            e.u
        );
        // an event function that returns NaN is an error
        let mut nan = |_: f64, _: &[f64]| f64::NAN;
        assert!(st.crossing(&mut nan, 1.0).is_err());
    }
}
