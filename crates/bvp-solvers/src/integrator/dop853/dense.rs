//! Dense output: Hairer's 7th-order continuous extension of each accepted step (three extra
//! stages `k14..k16`), stored per step in [`OdeSolution`] and evaluated by
//! [`OdeSolution::eval`], or copied out of the stepper one step at a time
//! ([`StepInterpolant`]).

use super::coef::*;
use crate::integrator::OdeSystem;

/// How much of the current step's interpolant is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolant {
    /// None yet.
    None,
    /// The cubic Hermite part (the step's ends and slopes: no extra evaluation).
    Cubic,
    /// Hairer's 7th-order continuous extension (three extra evaluations).
    Full,
}

/// Result of a [`Dop853`](super::Dop853) integration: the end state and (optionally) the dense output.
#[derive(Clone, Debug)]
pub struct OdeSolution {
    /// Where the integration ended (`s1`, or the event location).
    pub s_end: f64,
    /// State at `s_end`.
    pub u_end: Vec<f64>,
    /// Work counters.
    pub stats: super::IntegrationStats,
    /// The step the controller proposed after the first accepted step
    /// ([`Stepper::start_step`](super::Stepper::start_step)).
    pub start_step: Option<f64>,
    pub(super) dim: usize,
    pub(super) s_start: f64,
    pub(super) u_start: Vec<f64>,
    /// Step start points plus the end (len = steps + 1), empty if not dense.
    pub(super) points: Vec<f64>,
    /// Step sizes (len = steps).
    pub(super) hs: Vec<f64>,
    /// 8 * dim interpolation coefficients per step.
    pub(super) cont: Vec<f64>,
    pub(super) dense: bool,
}

/// Evaluates the DOP853 dense output of one step with coefficients `rc` (8 blocks of `n`).
#[inline]
pub(super) fn dense_eval(rc: &[f64], n: usize, theta: f64, out: &mut [f64]) {
    by_dim!(n, dense_eval_in(rc, theta, out))
}

/// [`dense_eval`] in the dimension `d`.
#[inline(always)]
fn dense_eval_in<D: Dim>(d: D, rc: &[f64], theta: f64, out: &mut [f64]) {
    let n = d.n();
    let (rc, out) = (&rc[..8 * n], &mut out[..n]);
    let t1 = 1.0 - theta;
    for (i, o) in out.iter_mut().enumerate() {
        let r = |j: usize| rc[j * n + i];
        *o = r(0)
            + theta
                * (r(1)
                    + t1 * (r(2)
                        + theta
                            * (r(3) + t1 * (r(4) + theta * (r(5) + t1 * (r(6) + theta * r(7)))))));
    }
}

/// A copy of one accepted step's interpolant that outlives the [`Stepper`](super::Stepper)'s
/// move to the next step ([`Stepper::interpolant`](super::Stepper::interpolant)), for a
/// state of dimension `N`: with `theta = (s - start) / h`,
///
/// ```text
/// u(theta) = r0 + theta (r1 + (1 - theta) (r2 + theta (r3 + (1 - theta) (r4 + theta (r5
///          + (1 - theta) (r6 + theta r7))))))
/// ```
///
/// (Hairer's 7th-order continuous extension of `DOP853`, [`Interpolant::Full`]); its first
/// four terms alone are the cubic Hermite interpolant of the step's ends and slopes
/// ([`Interpolant::Cubic`], exact at the ends, `O(h^4)` inside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepInterpolant<const N: usize> {
    pub(super) start: f64,
    pub(super) h: f64,
    pub(super) level: Interpolant,
    /// The coefficient blocks `r0..r7` (the last four valid at [`Interpolant::Full`] only).
    pub(super) rc: [[f64; N]; 8],
}

impl<const N: usize> Default for StepInterpolant<N> {
    /// An interpolant with nothing copied ([`Interpolant::None`]: it evaluates nowhere).
    fn default() -> Self {
        StepInterpolant {
            start: 0.0,
            h: 0.0,
            level: Interpolant::None,
            rc: [[0.0; N]; 8],
        }
    }
}

impl<const N: usize> StepInterpolant<N> {
    /// Start of the step.
    pub fn start(&self) -> f64 {
        self.start
    }

    /// Size of the step (signed).
    pub fn h(&self) -> f64 {
        self.h
    }

    /// How much of the interpolant was computed when it was copied.
    pub fn level(&self) -> Interpolant {
        self.level
    }

    /// The 7th-order interpolant at `theta` into `out`; `false` (and `out` untouched) unless
    /// it was copied in full.
    pub fn eval(&self, theta: f64, out: &mut [f64; N]) -> bool {
        if self.level != Interpolant::Full {
            return false;
        }
        dense_eval(self.rc.as_flattened(), N, theta, out);
        true
    }

    /// Component `i` of the 7th-order interpolant at `theta` with its first two derivatives
    /// by `theta`, `[u_i, du_i/dtheta, d^2u_i/dtheta^2]` (the nested form differentiated
    /// level by level; `d/ds = (1/h) d/dtheta`); `None` unless it was copied in full, or if
    /// `i >= N`.
    pub fn eval_jet(&self, i: usize, theta: f64) -> Option<[f64; 3]> {
        if self.level != Interpolant::Full || i >= N {
            return None;
        }
        let r = |j: usize| self.rc[j][i];
        let t1 = 1.0 - theta;
        // from the innermost level out: w = r_j + t w_in with t = theta (t' = 1) or
        // 1 - theta (t' = -1): w' = t' w_in + t w_in', w'' = 2 t' w_in' + t w_in''
        let (mut w, mut d1, mut d2) = (r(7), 0.0, 0.0);
        for j in (0..7).rev() {
            let (t, dt) = if j % 2 == 0 { (theta, 1.0) } else { (t1, -1.0) };
            d2 = 2.0 * dt * d1 + t * d2;
            d1 = dt * w + t * d1;
            w = r(j) + t * w;
        }
        Some([w, d1, d2])
    }

    /// All eight coefficient blocks `r0..r7` of the 7th-order interpolant (module docs of
    /// [`StepInterpolant`]), for a caller that bounds the polynomial over a range of
    /// `theta` (e.g. by interval arithmetic on the nested form); `None` unless it was
    /// copied in full.
    pub fn coefficients(&self) -> Option<&[[f64; N]; 8]> {
        (self.level == Interpolant::Full).then_some(&self.rc)
    }

    /// The coefficient blocks `r0..r3` of the cubic Hermite part (module docs of
    /// [`StepInterpolant`]): `u(theta) = r0 + theta (r1 + (1 - theta) (r2 + theta r3))`,
    /// `h u'(theta) = r1 + (1 - 2 theta) r2 + theta (2 - 3 theta) r3`; `None` if no
    /// interpolant was computed.
    pub fn cubic_coefficients(&self) -> Option<&[[f64; N]; 4]> {
        if self.level == Interpolant::None {
            return None;
        }
        self.rc.first_chunk::<4>()
    }

    /// The cubic Hermite part at `theta` into `out` and its derivative `du/ds` into `dout`;
    /// `false` (outputs untouched) if no interpolant was computed.
    pub fn eval_cubic(&self, theta: f64, out: &mut [f64; N], dout: &mut [f64; N]) -> bool {
        if self.level == Interpolant::None {
            return false;
        }
        let [r0, r1, r2, r3, ..] = &self.rc;
        let th = theta;
        for i in 0..N {
            let (r0, r1, r2, r3) = (r0[i], r1[i], r2[i], r3[i]);
            out[i] = r0 + th * (r1 + (1.0 - th) * (r2 + th * r3));
            dout[i] = (r1 + (1.0 - 2.0 * th) * r2 + th * (2.0 - 3.0 * th) * r3) / self.h;
        }
        true
    }
}

impl OdeSolution {
    /// Dense output at `s` inside the integrated span (`None` outside, or if the solution was
    /// computed with `dense == false`). The interpolant is Hairer's 7th-order continuous
    /// extension, evaluated on the step containing `s`.
    pub fn eval(&self, s: f64) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.dim];
        if self.eval_into(s, &mut out) {
            Some(out)
        } else {
            None
        }
    }

    /// As [`OdeSolution::eval`], writing into `out` (length `dim`); returns `false` (and leaves
    /// `out` unspecified) if `s` is outside the span, not dense, or `out` has the wrong length.
    pub fn eval_into(&self, s: f64, out: &mut [f64]) -> bool {
        self.eval_on(s, out, |sol| sol.step_index(s))
    }

    /// [`OdeSolution::eval_into`] with the step looked for from `*hint` (the step of the
    /// point asked for before, updated; any value to start): walked to from there, which
    /// for a sequence of nearby points (sampling a shape) is a step or two instead of a
    /// binary search whose branches the processor cannot predict. The same values.
    pub fn eval_near(&self, s: f64, hint: &mut usize, out: &mut [f64]) -> bool {
        self.eval_on(s, out, |sol| sol.step_near(s, hint))
    }

    /// The state at `s` into `out` from the step that `step` finds (as
    /// [`OdeSolution::eval_into`]: the ends exactly, `false` outside the span).
    fn eval_on(&self, s: f64, out: &mut [f64], step: impl FnOnce(&Self) -> Option<usize>) -> bool {
        if out.len() != self.dim || !self.in_span(s) {
            return false;
        }
        if self.hs.is_empty() {
            out.copy_from_slice(&self.u_start);
            return true;
        }
        if s == self.s_end {
            out.copy_from_slice(&self.u_end);
            return true;
        }
        let Some(idx) = step(self) else {
            return false;
        };
        let n = self.dim;
        let theta = (s - self.points[idx]) / self.hs[idx];
        dense_eval(&self.cont[idx * 8 * n..(idx + 1) * 8 * n], n, theta, out);
        true
    }

    /// The interpolant of step `k` ([`OdeSolution::step_index`]) of a linear map `map` of the
    /// state (applied to each coefficient block: the interpolant is linear in them), for a
    /// caller that samples a few quantities of a larger state many times on few steps;
    /// `None` outside the steps or without dense output. Only a *linear* map is right: an
    /// offset belongs to the first block alone.
    pub fn step_interpolant_of<const M: usize>(
        &self,
        k: usize,
        map: impl Fn(&[f64]) -> [f64; M],
    ) -> Option<StepInterpolant<M>> {
        let n = self.dim;
        let rc = self.cont.get(k * 8 * n..(k + 1) * 8 * n)?;
        let mut out = StepInterpolant {
            start: self.points[k],
            h: self.hs[k],
            level: Interpolant::Full,
            rc: [[0.0; M]; 8],
        };
        for (b, src) in out.rc.iter_mut().zip(rc.chunks_exact(n)) {
            *b = map(src);
        }
        Some(out)
    }

    /// [`OdeSolution::step_index`] walked to from `*hint` (updated): for a sequence of nearby
    /// points a step or two instead of a binary search ([`OdeSolution::eval_near`]).
    pub fn step_near(&self, s: f64, hint: &mut usize) -> Option<usize> {
        let (dir, t) = self.key_of(s)?;
        let key = |k: usize| dir * (self.points[k] - self.s_start);
        Some(crate::grid::locate_from(self.hs.len(), key, t, hint))
    }

    /// The direction of integration and `s` measured along it from the start, the key by
    /// which the steps are sorted (`None` without steps, or outside the span).
    fn key_of(&self, s: f64) -> Option<(f64, f64)> {
        if self.hs.is_empty() || !self.in_span(s) {
            return None;
        }
        let dir = if self.s_end >= self.s_start {
            1.0
        } else {
            -1.0
        };
        Some((dir, dir * (s - self.s_start)))
    }

    /// Whether `s` lies in the integrated span of a dense output.
    fn in_span(&self, s: f64) -> bool {
        let (lo, hi) = if self.s_end >= self.s_start {
            (self.s_start, self.s_end)
        } else {
            (self.s_end, self.s_start)
        };
        self.dense && s.is_finite() && s >= lo && s <= hi
    }

    /// Index of the step containing `s`, the last one whose start is `<= s` in the direction
    /// of integration (`None` outside the span or without dense output).
    pub fn step_index(&self, s: f64) -> Option<usize> {
        let (dir, t) = self.key_of(s)?;
        let nsteps = self.hs.len();
        Some(
            self.points[..nsteps]
                .partition_point(|&p| dir * (p - self.s_start) <= t)
                .saturating_sub(1)
                .min(nsteps - 1),
        )
    }

    /// Number of stored steps.
    pub fn steps(&self) -> usize {
        self.hs.len()
    }

    /// An empty solution at `(s0, u0)` (room reserved for a typical dense output).
    pub(super) fn start(s0: f64, u0: &[f64], dense: bool) -> Self {
        let n = u0.len();
        let mut sol = OdeSolution {
            s_end: s0,
            u_end: u0.to_vec(),
            stats: super::IntegrationStats::default(),
            start_step: None,
            dim: n,
            s_start: s0,
            u_start: if dense { u0.to_vec() } else { Vec::new() },
            points: Vec::new(),
            hs: Vec::new(),
            cont: Vec::new(),
            dense,
        };
        if dense {
            // room for a typical integration (vector growth was ~4 % of a short one)
            const GUESS: usize = 32;
            sol.points.reserve(GUESS + 1);
            sol.points.push(s0);
            sol.hs.reserve(GUESS);
            sol.cont.reserve(GUESS * 8 * n);
        }
        sol
    }

    /// Stores a step of size `h` ending at `end` with its interpolant's coefficients `rc`
    /// (the stepper's held step, prepared in full by the caller).
    pub(super) fn store_step(&mut self, end: f64, h: f64, rc: &[f64]) {
        self.points.push(end);
        self.hs.push(h);
        self.cont.extend_from_slice(rc);
    }

    /// Accepted step end points, including the start (and ending at `s_end`); empty if the
    /// integration was not dense.
    pub fn step_points(&self) -> &[f64] {
        &self.points
    }

    /// State dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }
}

/// The first 4 blocks of the dense-output coefficients of the step `[x, x + h]` (uses `k1`
/// and `k13`): alone they are the cubic Hermite interpolant of the step's ends.
pub(super) fn hermite(h: f64, y: &[f64], ynew: &[f64], k: &[f64], rc: &mut [f64]) {
    let n = y.len();
    for i in 0..n {
        let ydiff = ynew[i] - y[i];
        let bspl = h * k[i] - ydiff;
        rc[i] = y[i];
        rc[n + i] = ydiff;
        rc[2 * n + i] = bspl;
        rc[3 * n + i] = ydiff - h * k[12 * n + i] - bspl;
    }
}

/// A stage: the combination of earlier stages (slot, coefficient), its node `C`, its slot.
type Stage = ([(usize, f64); 8], f64, usize);

/// The extra stages `k14..k16` of the dense output.
const EXTRA_STAGES: [Stage; 3] = [
    (
        [
            (0, A141),
            (6, A147),
            (7, A148),
            (8, A149),
            (9, A1410),
            (10, A1411),
            (11, A1412),
            (12, A1413),
        ],
        C14,
        13,
    ),
    (
        [
            (0, A151),
            (5, A156),
            (6, A157),
            (7, A158),
            (10, A1511),
            (11, A1512),
            (12, A1513),
            (13, A1514),
        ],
        C15,
        14,
    ),
    (
        [
            (0, A161),
            (5, A166),
            (6, A167),
            (7, A168),
            (8, A169),
            (12, A1613),
            (13, A1614),
            (14, A1615),
        ],
        C16,
        15,
    ),
];

/// The coefficient blocks 5..8 of the dense output: combinations of the stages `k1, k6..k16`.
const DENSE_ROWS: [[(usize, f64); 12]; 4] = [
    [
        (0, D41),
        (5, D46),
        (6, D47),
        (7, D48),
        (8, D49),
        (9, D410),
        (10, D411),
        (11, D412),
        (12, D413),
        (13, D414),
        (14, D415),
        (15, D416),
    ],
    [
        (0, D51),
        (5, D56),
        (6, D57),
        (7, D58),
        (8, D59),
        (9, D510),
        (10, D511),
        (11, D512),
        (12, D513),
        (13, D514),
        (14, D515),
        (15, D516),
    ],
    [
        (0, D61),
        (5, D66),
        (6, D67),
        (7, D68),
        (8, D69),
        (9, D610),
        (10, D611),
        (11, D612),
        (12, D613),
        (13, D614),
        (14, D615),
        (15, D616),
    ],
    [
        (0, D71),
        (5, D76),
        (6, D77),
        (7, D78),
        (8, D79),
        (9, D710),
        (10, D711),
        (11, D712),
        (12, D713),
        (13, D714),
        (14, D715),
        (15, D716),
    ],
];

/// The last 4 blocks of the dense-output coefficients of the step `[x, x + h]` from `y`
/// and the stages `k1, k6..k13` in `k`: evaluates the extra stages `k14..k16`.
pub(super) fn extend<S: OdeSystem + ?Sized>(
    sys: &S,
    x: f64,
    h: f64,
    y: &[f64],
    k: &mut [f64],
    tmp: &mut [f64],
    rc: &mut [f64],
) {
    by_dim!(y.len(), extend_in(sys, (x, h), y, k, tmp, rc))
}

/// [`extend`] in the dimension `d` (the same sums in the same order).
#[inline(always)]
fn extend_in<D: Dim, S: OdeSystem + ?Sized>(
    d: D,
    sys: &S,
    (x, h): (f64, f64),
    y: &[f64],
    k: &mut [f64],
    tmp: &mut [f64],
    rc: &mut [f64],
) {
    let n = d.n();
    let (y, k, tmp, rc) = (
        &y[..n],
        &mut k[..NSTAGE * n],
        &mut tmp[..n],
        &mut rc[..8 * n],
    );
    for (terms, c, slot) in EXTRA_STAGES {
        combo(n, y, h, k, terms, tmp);
        sys.rhs(x + c * h, tmp, &mut k[slot * n..(slot + 1) * n]);
    }
    for i in 0..n {
        for (b, terms) in DENSE_ROWS.iter().enumerate() {
            rc[(4 + b) * n + i] = h * lin(k, n, i, *terms);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::Dop853;
    use crate::testing::{ring_cases, Harmonic};

    /// Walking from a hint finds the step of the binary search, forwards and backwards,
    /// whatever the hint and the order of the points: the very values of `eval_into`.
    #[test]
    fn evaluation_near_a_hint_is_evaluation() {
        let opts = Dop853::new(1e-9, 1e-9).with_dense(true);
        for (a, b) in [(0.0, 3.0), (3.0, 0.0)] {
            let sol = opts.integrate(&Harmonic, a, b, &[0.0, 1.0]).unwrap();
            assert!(sol.steps() > 5, "{}", sol.steps());
            let mut hint = usize::MAX;
            let (mut u, mut v) = ([0.0; 2], [0.0; 2]);
            // increasing, then scattered (a hint far off), then the end points
            let pts = (0..=60).map(|i| 0.05 * i as f64);
            let scattered = (0..40).map(|i| (i * 17 % 40) as f64 * 0.075);
            for s in pts.chain(scattered).chain([0.0, 3.0]) {
                assert!(sol.eval_into(s, &mut u));
                assert!(sol.eval_near(s, &mut hint, &mut v));
                assert_eq!(u, v, "at {s}");
                assert!((u[0] - (s - a).sin()).abs() < 1e-8, "at {s}: {}", u[0]);
            }
            assert!(
                !sol.eval_near(3.5, &mut hint, &mut v)
                    && !sol.eval_near(f64::NAN, &mut hint, &mut v)
            );
        }
    }

    /// A step's interpolant of a linear map of the state is the map of the dense output
    /// (to rounding), on every step; nothing outside the steps.
    #[test]
    fn a_steps_interpolant_of_a_linear_map_is_the_map_of_the_dense_output() {
        let opts = Dop853::new(1e-10, 1e-10).with_dense(true);
        let sol = opts.integrate(&Harmonic, 0.0, 3.0, &[0.0, 1.0]).unwrap();
        let map = |r: &[f64]| [r[0] + 0.3 * r[1], -2.0 * r[1]];
        let mut hint = usize::MAX;
        for i in 0..=300 {
            let s = 0.01 * i as f64 * (1.0 - 1e-12);
            let k = sol.step_near(s, &mut hint).unwrap();
            assert_eq!(Some(k), sol.step_index(s));
            let p = sol.step_interpolant_of(k, map).unwrap();
            let (mut v, u) = ([0.0; 2], sol.eval(s).unwrap());
            assert!(p.eval((s - p.start()) / p.h(), &mut v));
            let want = map(&u);
            assert!((v[0] - want[0]).abs() <= 1e-15 && (v[1] - want[1]).abs() <= 1e-15);
        }
        assert!(sol.step_interpolant_of(sol.steps(), map).is_none());
    }

    /// The jet of a component is the interpolant's value (to rounding) and its derivatives:
    /// against the exact solution `(sin s, cos s)` of the harmonic oscillator and against
    /// central differences of the interpolant itself; nothing without the full interpolant.
    #[test]
    fn the_jet_is_the_interpolant_and_its_derivatives() {
        use crate::integrator::Interpolant;
        let opts = Dop853::new(1e-11, 1e-11);
        let mut st = opts.stepper(&Harmonic, 0.0, 3.0, &[0.0, 1.0]).unwrap();
        let mut steps = 0;
        while st.step().unwrap() {
            st.prepare(Interpolant::Cubic);
            let cubic = st.interpolant::<2>().unwrap();
            assert!(cubic.eval_jet(0, 0.5).is_none());
            st.prepare(Interpolant::Full);
            let p = st.interpolant::<2>().unwrap();
            assert!(p.eval_jet(2, 0.5).is_none());
            let h = p.h();
            for k in 0..=8 {
                let th = k as f64 / 8.0;
                let s = p.start() + th * h;
                let mut u = [0.0; 2];
                assert!(p.eval(th, &mut u));
                for (i, (d0, d1, d2)) in
                    [(s.sin(), s.cos(), -s.sin()), (s.cos(), -s.sin(), -s.cos())]
                        .into_iter()
                        .enumerate()
                {
                    let [w, w1, w2] = p.eval_jet(i, th).unwrap();
                    assert!((w - u[i]).abs() <= 4e-16, "{w} vs {}", u[i]);
                    assert!((w - d0).abs() < 1e-10);
                    assert!((w1 / h - d1).abs() < 1e-8, "{} vs {d1}", w1 / h);
                    assert!((w2 / (h * h) - d2).abs() < 1e-6, "{} vs {d2}", w2 / (h * h));
                    // central differences of the polynomial (exact to O(dt^2) and rounding)
                    let dt = 1e-3;
                    let at = |t: f64| p.eval_jet(i, t).unwrap();
                    let fd1 = (at(th + dt)[0] - at(th - dt)[0]) / (2.0 * dt);
                    let fd2 = (at(th + dt)[1] - at(th - dt)[1]) / (2.0 * dt);
                    assert!((fd1 - w1).abs() < 1e-6 * (1.0 + w1.abs()), "{fd1} vs {w1}");
                    assert!((fd2 - w2).abs() < 1e-6 * (1.0 + w2.abs()), "{fd2} vs {w2}");
                }
            }
            steps += 1;
        }
        assert!(steps > 3, "{steps}");
    }

    /// The extension unrolled for a fixed dimension gives the very numbers of the run-time
    /// dimension's loops, for every dimension the dispatch fixes.
    #[test]
    fn fixed_dimensions_reproduce_the_dynamic_extension_bit_for_bit() {
        for (n, sys, y) in ring_cases() {
            let k1: Vec<f64> = (0..16 * n).map(|i| (0.37 * i as f64).cos()).collect();
            let (mut k2, mut tmp1, mut tmp2) = (k1.clone(), vec![0.0; n], vec![0.0; n]);
            let mut k1 = k1;
            let (mut rc1, mut rc2) = (vec![0.5; 8 * n], vec![0.5; 8 * n]);
            extend(&sys, 0.2, 0.05, &y, &mut k1, &mut tmp1, &mut rc1);
            extend_in(
                Dynamic(n),
                &sys,
                (0.2, 0.05),
                &y,
                &mut k2,
                &mut tmp2,
                &mut rc2,
            );
            assert_eq!((k1, rc1), (k2, rc2), "n = {n}");
        }
    }
}
