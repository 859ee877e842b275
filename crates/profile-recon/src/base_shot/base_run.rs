//! The one integration from the base that every hypothesis of a row reads ([`BaseRun`]):
//! the DOP853 stepper driven step by step over `[0, 1]` (stopped early where `phi` winds by
//! [`MAX_WINDING`]); the cheap cubic part of each step's interpolant judges whether the
//! moment `m` may have a root or an extremum there ([`close_step`]), and only those steps get
//! Hairer's 7th-order interpolant (three more evaluations each).

use super::base_ode::BaseOde;
use super::context::{MAX_WINDING, SAMPLES};
use crate::error::Result;
use crate::observables::ObservableRow;
use bvp_solvers::grid::locate_from;
use bvp_solvers::integrator::{Dop853, Interpolant, StepInterpolant};

/// The base integration of a row [3.25, 6.8, 6.9]: the interpolant of every accepted step
/// (complete on the close steps, the cubic part elsewhere) and the end state.
#[derive(Clone, Debug)]
pub(super) struct BaseRun {
    /// The accepted steps (one allocation; each interpolant copied once, in place).
    steps: Vec<Kept>,
    /// Where the integration ended: 1, or where `phi` wound by [`MAX_WINDING`].
    pub s_end: f64,
    /// The state `(phi, m, x, y)` at `s_end`.
    pub u_end: [f64; 4],
}

/// An accepted step as a [`BaseRun`] keeps it.
#[derive(Clone, Debug, Default)]
struct Kept {
    /// Its interpolant (complete on a close step, the cubic part elsewhere).
    interp: StepInterpolant<4>,
    /// Where it ends (the last at `s_end`).
    end: f64,
    /// Whether `m` may have a root or an extremum on it ([`close_step`]).
    close: bool,
}

/// One step of a [`BaseRun`]: `[start, end]`, whether it is close, and its interpolant.
#[derive(Clone, Copy, Debug)]
pub(super) struct RunStep<'a> {
    pub start: f64,
    pub end: f64,
    pub close: bool,
    pub interp: &'a StepInterpolant<4>,
}

impl RunStep<'_> {
    /// The state at `s` in `[start, end)` into `out`, as [`BaseRun::eval_into`] gives it there
    /// (the 7th-order interpolant; a step that is not close has none inside: `false`),
    /// without looking for the step.
    pub(super) fn eval_inside(&self, s: f64, out: &mut [f64; 4]) -> bool {
        debug_assert!(self.start <= s && s < self.end);
        let p = self.interp;
        if p.level() != Interpolant::Full {
            let mut d = [0.0; 4];
            return s == p.start() && p.eval_cubic(0.0, out, &mut d);
        }
        p.eval((s - p.start()) / p.h(), out)
    }
}

impl BaseRun {
    /// Integrates `ode` (without sensitivities) from the base with the row's initial state
    /// `(phi0, -MA, x0, 0)` to `s = 1`, or to where `|phi - phi0| = MAX_WINDING` (located on
    /// the step's interpolant).
    ///
    /// # Errors
    /// The integrator's errors.
    pub(super) fn new(ode: &BaseOde, row: &ObservableRow, integrator: &Dop853) -> Result<Self> {
        let u0 = ode.initial(row);
        let phi0 = row.phi0;
        let mut winding = |_: f64, u: &[f64]| MAX_WINDING - (u[0] - phi0).abs();
        let mut st = integrator.stepper(ode, 0.0, 1.0, &u0)?;
        let mut run = BaseRun {
            steps: Vec::with_capacity(32),
            s_end: 1.0,
            u_end: [0.0; 4],
        };
        let mut g_old = winding(0.0, &u0);
        while st.step()? {
            st.prepare(Interpolant::Cubic);
            let (g_new, hit) = st.crossing(&mut winding, g_old)?;
            let end = match &hit {
                Some(e) => e.s,
                None if st.is_last() => 1.0,
                None => st.end(),
            };
            run.steps.push(Kept::default());
            let kept = run.steps.last_mut().expect("just pushed");
            kept.end = end;
            let held = st.interpolant_into(&mut kept.interp);
            debug_assert!(held, "the base system has 4 components");
            kept.close = close_step(&kept.interp, end - kept.interp.start());
            if kept.close {
                st.prepare(Interpolant::Full);
                st.interpolant_into(&mut kept.interp);
            }
            if let Some(e) = hit {
                run.s_end = e.s;
                run.u_end.copy_from_slice(&e.u);
                return Ok(run);
            }
            g_old = g_new;
        }
        run.u_end.copy_from_slice(st.state());
        Ok(run)
    }

    /// The steps in order.
    pub(super) fn steps(&self) -> impl Iterator<Item = RunStep<'_>> {
        self.steps.iter().map(|k| RunStep {
            start: k.interp.start(),
            end: k.end,
            close: k.close,
            interp: &k.interp,
        })
    }

    /// Index of the step holding `s` in `[0, s_end]` (the last one starting at or before it).
    fn step_index(&self, s: f64) -> Option<usize> {
        if self.steps.is_empty() || !(s.is_finite() && s >= 0.0 && s <= self.s_end) {
            return None;
        }
        let k = self.steps.partition_point(|p| p.interp.start() <= s);
        Some(k.saturating_sub(1).min(self.steps.len() - 1))
    }

    /// The state at `s` into `out` from the 7th-order interpolant (the end state at `s_end`,
    /// a step's start state on any step); `false` where that is not available (outside
    /// `[0, s_end]`, inside a step that is not close).
    pub(super) fn eval_into(&self, s: f64, out: &mut [f64; 4]) -> bool {
        let Some(k) = self.step_index(s) else {
            return false;
        };
        if s == self.s_end {
            *out = self.u_end;
            return true;
        }
        let p = &self.steps[k].interp;
        if p.level() != Interpolant::Full {
            // a step's start is its interpolant's first coefficient, exactly
            let mut d = [0.0; 4];
            return s == p.start() && p.eval_cubic(0.0, out, &mut d);
        }
        p.eval((s - p.start()) / p.h(), out)
    }

    /// The cubic Hermite part of the interpolant at `s` into `out` and its derivative into
    /// `dout` (any step; `false` outside `[0, s_end]`).
    pub(super) fn cubic_at(&self, s: f64, out: &mut [f64; 4], dout: &mut [f64; 4]) -> bool {
        let Some(k) = self.step_index(s) else {
            return false;
        };
        let p = &self.steps[k].interp;
        p.eval_cubic((s - p.start()) / p.h(), out, dout)
    }

    /// The cubic Hermite part of the interpolant at `s` into `out`, as
    /// [`cubic_at`](Self::cubic_at) gives it, without the derivative (and its divisions),
    /// with the step looked for from `*hint` (the step of the arc asked for before,
    /// updated): walked to from there, which for a sequence of nearby arcs is a step or two
    /// instead of a binary search whose branches the processor cannot predict (measured on
    /// the 16 arcs of [`tip_levels`](super::tip::tip_levels): a stream row 7.9-8.0 -> 7.6
    /// µs in phase A, 7.6 -> 6.8 µs in phase B, for 0.7 k fewer instructions).
    pub(super) fn cubic_value_near(&self, s: f64, hint: &mut usize, out: &mut [f64; 4]) -> bool {
        if self.steps.is_empty() || !(s.is_finite() && s >= 0.0 && s <= self.s_end) {
            return false;
        }
        // the last step starting at or before s (the first if none), as `step_index` finds it
        let k = locate_from(self.steps.len(), |k| self.steps[k].interp.start(), s, hint);
        self.cubic_value_on(k, s, out)
    }

    /// The cubic part of step `k`'s interpolant at `s` into `out`.
    fn cubic_value_on(&self, k: usize, s: f64, out: &mut [f64; 4]) -> bool {
        let p = &self.steps[k].interp;
        let Some([r0, r1, r2, r3]) = p.cubic_coefficients() else {
            return false;
        };
        let th = (s - p.start()) / p.h();
        for i in 0..4 {
            out[i] = r0[i] + th * (r1[i] + (1.0 - th) * (r2[i] + th * r3[i]));
        }
        true
    }
}

/// Whether `m` may have a root or an extremum on a step (`span` its length as integrated):
/// the cubic Hermite part of the step's interpolant (exact at the ends, `O(h^4)` inside) at
/// the ends and at the [`SAMPLES`] parts comes within twice the step's variation of `m` (its
/// range there, or `h |m'|`) of zero, or `m'` changes sign there. Elsewhere `m` keeps its
/// sign and its direction with a margin that the cubic's error cannot close on an accepted
/// step, and the scan of [`candidates`](super::scan::candidates) has nothing to find.
pub(super) fn close_step(cubic: &StepInterpolant<4>, span: f64) -> bool {
    // m and h m' of the cubic from its coefficients (no division per sample)
    let Some([r0, r1, r2, r3]) = cubic.cubic_coefficients() else {
        return true;
    };
    let (r0, r1, r2, r3) = (r0[1], r1[1], r2[1], r3[1]);
    let dir = cubic.h().signum();
    let (mut lo, mut hi, mut amin, mut hdmax) =
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, 0.0f64);
    let mut dsign = 0.0f64;
    let mut turns = false;
    for k in 0..=SAMPLES {
        let th = k as f64 / SAMPLES as f64;
        let m = r0 + th * (r1 + (1.0 - th) * (r2 + th * r3));
        let hd = r1 + (1.0 - 2.0 * th) * r2 + th * (2.0 - 3.0 * th) * r3;
        if !(m.is_finite() && hd.is_finite()) {
            return true;
        }
        lo = lo.min(m);
        hi = hi.max(m);
        amin = amin.min(m.abs());
        hdmax = hdmax.max(hd.abs());
        // the sign of m'
        let d = hd * dir;
        if d == 0.0 || (dsign != 0.0 && d.signum() != dsign) {
            turns = true;
        }
        dsign = d.signum();
    }
    // the variation over the step as integrated: span |m'| = (span / h) |h m'|
    turns || amin <= 2.0 * (hi - lo).max(span.abs() / cubic.h().abs() * hdmax)
}

#[cfg(test)]
mod tests {
    use super::super::base_ode::base_ivp;
    use super::super::base_ode::tests::row;
    use super::*;
    use beam_model::{FluidLoad, Whisker};

    #[test]
    fn the_run_is_the_dense_integration_where_it_is_complete() {
        let w = Whisker::new(0.6, 2.0, -1.0, f64::INFINITY);
        let flow = FluidLoad { q: 3.0, alpha: 0.2 };
        let r = row(-1.0, 6.0, 0.9, 1.5);
        let opts = Dop853::new(1e-12, 1e-12);
        let ode = BaseOde::new(&w, flow, &r, false);
        let run = BaseRun::new(&ode, &r, &opts).unwrap();
        let full = base_ivp(&w, flow, &r, &opts.clone().with_dense(true)).unwrap();
        assert_eq!(run.s_end, full.s_end);
        assert_eq!(run.u_end.to_vec(), full.u_end);
        let (mut u, mut du) = ([0.0; 4], [0.0; 4]);
        let mut closes = 0;
        for (k, p) in run.steps().enumerate() {
            assert_eq!(
                (p.start, p.end),
                (full.step_points()[k], full.step_points()[k + 1])
            );
            // the start state on every step; inside, the 7th-order interpolant on close steps
            assert!(run.eval_into(p.start, &mut u));
            assert_eq!(Some(u.to_vec()), full.eval(p.start));
            let mid = 0.5 * (p.start + p.end);
            assert_eq!(run.eval_into(mid, &mut u), p.close);
            if p.close {
                closes += 1;
                assert_eq!(Some(u.to_vec()), full.eval(mid));
            }
            // the cubic everywhere, close to the truth
            assert!(run.cubic_at(mid, &mut u, &mut du));
            // without the derivative, from any hint: the same step and values
            for mut hint in [0, k, run.steps.len() + 3] {
                let mut v = [0.0; 4];
                assert!(run.cubic_value_near(mid, &mut hint, &mut v) && v == u);
                assert_eq!(hint, k);
            }
            let exact = full.eval(mid).unwrap();
            assert!((u[1] - exact[1]).abs() < 1e-4, "{} vs {}", u[1], exact[1]);
        }
        // m changes sign on this row: some steps are close, not all
        assert!(closes > 0 && closes < run.steps.len(), "{closes}");
        assert!(!run.eval_into(1.5, &mut u) && !run.cubic_at(-0.1, &mut u, &mut du));
    }

    #[test]
    fn winding_stops_the_run_early() {
        // a moment of 20 winds phi by 20 rad over the whisker: stopped at 12 rad, s = 0.6
        let flow = FluidLoad { q: 0.0, alpha: 0.0 };
        let r = row(0.0, 0.0, -20.0, 0.0);
        let ode = BaseOde::new(&Whisker::uniform(), flow, &r, false);
        let run = BaseRun::new(&ode, &r, &Dop853::new(1e-12, 1e-12)).unwrap();
        assert!(
            (run.s_end - MAX_WINDING / 20.0).abs() < 1e-9,
            "{}",
            run.s_end
        );
        assert!((run.u_end[0] - MAX_WINDING).abs() < 1e-9);
        assert_eq!(run.steps.last().map(|k| k.end), Some(run.s_end));
    }

    #[test]
    fn a_step_far_from_a_root_of_m_is_not_close() {
        // m from -1 to about -0.9, rising all along (m' = 0.1 cos phi, phi in [-0.8, 0.2])
        let flow = FluidLoad { q: 0.0, alpha: 0.0 };
        let r = row(0.0, 0.1, 1.0, 0.2);
        let ode = BaseOde::new(&Whisker::uniform(), flow, &r, false);
        let run = BaseRun::new(&ode, &r, &Dop853::new(1e-12, 1e-12)).unwrap();
        assert!(run.steps().all(|p| !p.close));
    }
}
