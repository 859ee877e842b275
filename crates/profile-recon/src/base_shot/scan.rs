//! Where the phase-B hypotheses of a row lie: every root of the moment `m` on `(0, 1)` and
//! every extremum of `m` towards zero (a double root at a release), bracketed on the
//! interpolants of the base integration and located by Brent. The run picked the steps on
//! which one may lie from the cheap cubic part of the interpolant
//! ([`close_step`](super::base_run::close_step)); [`candidates`] scans them.

use super::base_ode::{comp, BaseOde};
use super::base_run::{BaseRun, RunStep};
use super::context::SAMPLES;
use crate::error::Result;
use crate::observables::ObservableRow;
use bvp_solvers::integrator::{Interpolant, OdeSystem};
use bvp_solvers::roots::{brent, cauchy, RootOptions};
use bvp_solvers::BvpError;
use contact_sim::Phase;

/// The arc lengths of a row's hypotheses.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Candidates {
    /// Phase A at `s = 1` (if the integration got there) and the simple roots of `m` on
    /// `(0, 1)` (phase B), in the order found.
    pub roots: Vec<(Phase, f64)>,
    /// Extrema of `m` towards zero on `(0, 1)`: double-root (release) hypotheses of phase B.
    pub touching: Vec<f64>,
}

/// The state of the scan along the whisker.
struct Scan<'a> {
    run: &'a BaseRun,
    ode: &'a BaseOde,
    opts: RootOptions,
    /// `(s, m)` at the last sample.
    prev: (f64, f64),
    /// `m'` at the last sample.
    prev_slope: f64,
    /// The step being scanned (the brackets of its roots and extrema lie on it).
    step: Option<RunStep<'a>>,
    out: Candidates,
}

impl Scan<'_> {
    /// `m'` at state `u`.
    fn slope(&self, s: f64, u: &[f64]) -> f64 {
        let mut du = [0.0; 4];
        self.ode.rhs(s, u, &mut du);
        du[1]
    }

    /// The state at `t` into `buf` as [`BaseRun::eval_into`] gives it, inside the step being
    /// scanned from its interpolant directly (no search for the step).
    fn state_at(&self, t: f64, buf: &mut [f64; 4]) -> bool {
        match &self.step {
            Some(p) if p.start <= t && t < p.end => p.eval_inside(t, buf),
            _ => self.run.eval_into(t, buf),
        }
    }

    /// `m` on the interpolant (NaN outside).
    fn m_at(&self, t: f64) -> Result<f64> {
        let mut buf = [0.0; 4];
        Ok(if self.state_at(t, &mut buf) {
            buf[1]
        } else {
            f64::NAN
        })
    }

    /// `m'` on the interpolant (NaN outside).
    fn d_at(&self, t: f64) -> Result<f64> {
        let mut buf = [0.0; 4];
        Ok(if self.state_at(t, &mut buf) {
            self.slope(t, &buf)
        } else {
            f64::NAN
        })
    }

    /// The root of `m` bracketed by `[a, b]`, if inside `(0, 1)`: on the polynomial of the
    /// step being scanned by Cauchy's method where the bracket lies on it (its jet is a few
    /// operations, and a root next to a double root, as at the tip of a contact whose force
    /// runs along the tip, takes a few steps where Brent's secants crept for ~30), else by
    /// Brent on the interpolants.
    fn root(&mut self, a: f64, b: f64) {
        let on_step = self.step.and_then(|p| {
            let inside = p.start <= a.min(b) && a.max(b) <= p.end;
            (inside && p.interp.level() == Interpolant::Full).then_some(p.interp)
        });
        let found = match on_step {
            Some(p) => {
                let (s0, h) = (p.start(), p.h());
                // the same absolute tolerance in s as Brent's, in theta = (s - s0) / h
                let opts = RootOptions {
                    xtol: (self.opts.xtol + 4.0 * f64::EPSILON * a.abs().max(b.abs())) / h.abs(),
                    ..self.opts
                };
                // (a full interpolant of 4 components always has the jet of m)
                let jet =
                    |th: f64| Ok::<_, BvpError>(p.eval_jet(comp::M, th).unwrap_or([f64::NAN; 3]));
                cauchy(jet, (a - s0) / h, (b - s0) / h, &opts)
                    .ok()
                    .map(|r| s0 + r.x * h)
            }
            None => brent(|t| self.m_at(t), a, b, &self.opts).ok().map(|r| r.x),
        };
        if let Some(x) = found {
            if x > 0.0 && x < 1.0 {
                self.out.roots.push((Phase::B, x));
            }
        }
    }

    /// The sample at `s` with state `u`, against the previous one.
    fn sample(&mut self, s: f64, u: &[f64]) {
        let m = u[1];
        let ms = self.slope(s, u);
        let (s_prev, m_prev) = self.prev;
        let prev_slope = self.prev_slope;
        if m_prev != 0.0 && m_prev.signum() != m.signum() {
            // a sign change of m in (0, 1): a phase-B root (m(1) = 0 is phase A)
            if m == 0.0 {
                if s < 1.0 {
                    self.out.roots.push((Phase::B, s));
                }
            } else {
                self.root(s_prev, s);
            }
        } else if prev_slope.signum() != ms.signum() && s < 1.0 {
            // an extremum of m inside the sub-interval: two roots if it crosses zero,
            // else, if it turns towards zero, a double-root hypothesis (a release in
            // phase B as f -> 0 has no sign change of m)
            let towards_zero =
                (m_prev > 0.0 && prev_slope < 0.0) || (m_prev < 0.0 && prev_slope > 0.0);
            if towards_zero {
                self.extremum(s_prev, s, m);
            }
        }
        self.prev_slope = ms;
        self.prev = (s, m);
    }

    /// An extremum of `m` towards zero inside `[a, b]` (`m` = `m(b)`).
    fn extremum(&mut self, a: f64, b: f64, m: f64) {
        if let Ok(e) = brent(|t| self.d_at(t), a, b, &self.opts) {
            let me = self.m_at(e.x).unwrap_or(f64::NAN);
            if me.signum() != m.signum() && me != 0.0 {
                self.root(a, e.x);
                self.root(e.x, b);
            }
            // the extremum itself is the double-root hypothesis whether or not
            // it dips across zero: at a release (f = 0) the log's last digits
            // decide that, and the two roots of a shallow dip are determined
            // only to the square root of the precision (its `z` rules it out
            // when the dip is beyond the noise)
            if e.x > 0.0 && e.x < 1.0 {
                self.out.touching.push(e.x);
            }
        }
    }
}

/// The hypotheses of a row from its base integration `run` (of `ode`): phase A if `reached`
/// (`s = 1`), then every sign change of `m` on the close steps, each step cut in [`SAMPLES`]
/// parts and each part with an extremum of `m` cut there (two close roots are not lost),
/// and the extrema of `m` towards zero.
pub(super) fn candidates(
    run: &BaseRun,
    ode: &BaseOde,
    row: &ObservableRow,
    reached: bool,
) -> Candidates {
    let mut scan = Scan {
        run,
        ode,
        opts: RootOptions {
            xtol: 1e-15,
            ftol: 0.0,
            max_iter: 200,
        },
        prev: (0.0, -row.ma),
        prev_slope: 0.0,
        step: None,
        out: Candidates::default(),
    };
    if reached {
        scan.out.roots.push((Phase::A, 1.0));
    }
    scan.prev_slope = scan.slope(0.0, &[row.phi0, -row.ma, row.x0, 0.0]);
    let mut u = [0.0; 4];
    for step in run.steps() {
        if !step.close {
            // m keeps its sign and its direction on this step: only its end is carried
            if let Some([r0, r1, r2, r3]) = step.interp.cubic_coefficients() {
                // the cubic's m and m' at theta = 1 as eval_cubic gives them (m alone)
                let (th, i) = (1.0f64, 1);
                let m = r0[i] + th * (r1[i] + (1.0 - th) * (r2[i] + th * r3[i]));
                let hd = r1[i] + (1.0 - 2.0 * th) * r2[i] + th * (2.0 - 3.0 * th) * r3[i];
                scan.prev = (step.end, m);
                scan.prev_slope = hd / step.interp.h();
            }
            continue;
        }
        scan.step = Some(step);
        for k in 0..SAMPLES {
            // the last sample exactly at the step's end (its state exactly)
            let s = if k + 1 == SAMPLES {
                step.end
            } else {
                step.start + (step.end - step.start) * (k + 1) as f64 / SAMPLES as f64
            };
            if scan.state_at(s, &mut u) {
                scan.sample(s, &u);
            }
        }
    }
    scan.out
}

#[cfg(test)]
mod tests {
    use super::super::base_ode::base_ivp;
    use super::*;
    use beam_model::{FluidLoad, Whisker};
    use bvp_solvers::integrator::{Dop853, OdeSolution};

    /// The roots of `m` on a fine grid of the dense output, by bisection: an independent
    /// count of what the scan must find.
    fn brute_roots(sol: &OdeSolution, n: usize) -> Vec<f64> {
        let m = |s: f64| {
            let mut u = [0.0; 4];
            assert!(sol.eval_into(s, &mut u));
            u[1]
        };
        let end = sol.s_end.min(1.0);
        let mut out = Vec::new();
        for k in 0..n {
            let (mut a, mut b) = (end * k as f64 / n as f64, end * (k + 1) as f64 / n as f64);
            if m(a).signum() == m(b).signum() || b >= 1.0 {
                continue;
            }
            for _ in 0..60 {
                let c = 0.5 * (a + b);
                if m(c).signum() == m(a).signum() {
                    a = c;
                } else {
                    b = c;
                }
            }
            out.push(0.5 * (a + b));
        }
        out
    }

    fn scan_of(w: &Whisker, flow: FluidLoad, row: &ObservableRow) -> Candidates {
        let ode = BaseOde::new(w, flow, row, false);
        let run = BaseRun::new(&ode, row, &Dop853::new(1e-12, 1e-12)).unwrap();
        candidates(&run, &ode, row, run.s_end >= 1.0)
    }

    #[test]
    fn a_constant_moment_has_no_root() {
        // no force: m = -MA throughout, nothing to find but phase A
        let row = ObservableRow {
            x0: 0.0,
            ax: 0.0,
            ay: 0.0,
            ma: 0.4,
            phi0: 1.0,
        };
        let c = scan_of(&Whisker::uniform(), FluidLoad { q: 0.0, alpha: 0.0 }, &row);
        assert_eq!(c.roots, vec![(Phase::A, 1.0)]);
        assert!(c.touching.is_empty());
    }

    #[test]
    fn every_root_of_the_moment_is_found() {
        // a force across a whisker bent back and forth: m changes sign several times
        let w = Whisker::new(0.6, 2.0, -1.0, f64::INFINITY);
        let flow = FluidLoad { q: 3.0, alpha: 0.2 };
        for (ax, ay, ma) in [(-1.0, 6.0, 0.9), (2.0, -5.0, -0.3), (-4.0, 8.0, 1.5)] {
            let row = ObservableRow {
                x0: 0.1,
                ax,
                ay,
                ma,
                phi0: 1.5,
            };
            let c = scan_of(&w, flow, &row);
            // the truth from a complete dense output (the scan's is complete on close steps)
            let full = base_ivp(&w, flow, &row, &Dop853::new(1e-12, 1e-12).with_dense(true));
            let brute = brute_roots(&full.unwrap(), 20_000);
            let found: Vec<f64> = c
                .roots
                .iter()
                .filter(|(p, _)| *p == Phase::B)
                .map(|h| h.1)
                .collect();
            assert_eq!(found.len(), brute.len(), "{found:?} vs {brute:?}");
            assert!(!brute.is_empty());
            for (a, b) in found.iter().zip(&brute) {
                assert!((a - b).abs() < 1e-12, "{a} vs {b}");
            }
        }
    }
}
