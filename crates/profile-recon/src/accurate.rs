//! Method `accurate`: the observables ARE the initial values of the first-order system at the
//! base, `(phi, m, x, y)(0) = (phi0, -MA, x0, 0)` (spec/model.md, thesis ch. 6 reformulated).
//!
//! For a contact at `s1` the internal force at `s < s1` is fixed by the base reaction and the
//! flow on `[0, s]` alone [6.8, 6.9]: it does not depend on `s1`. So ONE integration from the
//! base over `[0, 1]` (under the phase-A loads of the row) gives the state of every phase
//! hypothesis at once:
//! - phase A (`s1 = 1`): consistent when `m(1) = 0` [6.6] and `phi(1) >= psi`; the contact
//!   point is `r(1)`;
//! - phase B: every root `s1` of the moment condition `m(s1) = 0` on `(0, 1)`, all of them
//!   bracketed on the dense output (each step cut in [`SAMPLES`] parts, and each part with an
//!   extremum of `m` cut there, so that two close roots are not lost) and located by Brent;
//!   consistent when the contact is tangential, `phi(s1) = psi(s1)`; the point is `r(s1)`.
//!   Extrema of `m` towards zero (roots of `m'`, bracketed the same way) are hypotheses too,
//!   with `m(s1)` as one more residual: as `f -> 0` in phase B (a release) the root of `m` is
//!   double and has no sign change.
//!
//! The phase is the hypothesis with the smallest residual relative to its own noise
//! sensitivity (`z = |residual| / sigma_unit`), not the slope-jump rule [6.10] and not a
//! neighbouring row: every row is reconstructed on its own. The Jacobian of the residuals and of
//! the contact point with respect to `(Ax, Ay, MA, phi0)` comes from the variational equations
//! of the same system, integrated once more at a loose tolerance ([`JACOBIAN_TOL`]: an error
//! estimate needs a few digits); it gives both the `z` of each hypothesis and the error
//! estimate of the point (the noise level propagated through it, roots moved by
//! `ds1 = -dm / m'(s1)`).
//!
//! Under noise the measured observables are not exactly consistent with any hypothesis; the
//! point is that of the most likely consistent observables (the residual's share of the
//! point's error removed, `project`), its error estimate the conditional deviation given
//! the residual, widened by whatever else fits the row as well: other consistent hypotheses
//! (`RowEval::ambiguity`) and, for a tip contact, a tangential contact just short of the
//! tip (`RowEval::tip_ambiguity`).
//!
//! The base integration keeps a lazy dense output: its cubic Hermite part scans every step
//! (`close_steps`), the 7th-order interpolant is completed only on the steps that may hold
//! a root or an extremum of `m`.

use crate::common::{contact_force, force_components, NoiseScales, ReconPoint};
use crate::error::Result;
use crate::observables::ObservableRow;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::{Dop853, OdeSolution, OdeSystem};
use bvp_solvers::roots::{brent, RootOptions};
use contact_sim::Phase;

/// Sub-intervals per integration step scanned for sign changes of `m`.
pub const SAMPLES: usize = 3;
/// Winding of `phi` away from `phi0` (rad) beyond which the integration stops: no physical
/// contact lies beyond (this keeps a thin tip under a wrong hypothesis from spiralling).
pub const MAX_WINDING: f64 = 12.0;
/// Number of standard deviations within which a hypothesis counts as consistent.
pub const K_SIGMA: f64 = 6.0;
/// Arcs back from the tip at which a phase-A row is checked for a phase-B look-alike:
/// `TIP_FIRST * TIP_RATIO^k`, `k < TIP_GRID`, from 1e-5 to 0.5 of the whisker (and the
/// zeros of the tangency residual between them).
pub const TIP_GRID: usize = 16;
const TIP_FIRST: f64 = 1e-5;
/// `(0.5 / 1e-5)^(1 / 15)`.
const TIP_RATIO: f64 = 2.057_143_874_950_285;
/// Integrator tolerance of the variational equations (the Jacobian of the error estimate).
pub const JACOBIAN_TOL: f64 = 1e-3;

/// The first-order system [3.25] integrated from the base with the base reaction of a row:
/// the internal force at `s` is `(P, Q)(s) = (-Ax - q s cos alpha, Ay - q s sin alpha)` in the
/// form of [6.8, 6.9] (the force balance of `[0, s]`, valid up to any contact `s1 >= s`), so
///
/// ```text
/// phi' = m / e^4 + A s + B,  m' = P sin phi + Q cos phi,  x' = cos phi,  y' = sin phi,
/// ```
///
/// with `(phi, m, x, y)(0) = (phi0, -MA, x0, 0)`; optionally followed by the variational
/// equations with respect to `(Ax, Ay, MA, phi0)` (4 components each).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BaseOde {
    whisker: Whisker,
    ax: f64,
    ay: f64,
    q_cos: f64,
    q_sin: f64,
    sens: bool,
}

impl BaseOde {
    pub(crate) fn new(whisker: &Whisker, flow: FluidLoad, row: &ObservableRow, sens: bool) -> Self {
        let (sa, ca) = flow.alpha.sin_cos();
        BaseOde {
            whisker: *whisker,
            ax: row.ax,
            ay: row.ay,
            q_cos: flow.q * ca,
            q_sin: flow.q * sa,
            sens,
        }
    }

    /// `(P, Q)(s)`.
    #[inline]
    fn force(&self, s: f64) -> (f64, f64) {
        (-self.ax - self.q_cos * s, self.ay - self.q_sin * s)
    }

    /// Initial state for `row`.
    fn initial(&self, row: &ObservableRow) -> Vec<f64> {
        let mut u = vec![0.0; self.dim()];
        u[..4].copy_from_slice(&[row.phi0, -row.ma, row.x0, 0.0]);
        if self.sens {
            u[4 * 3 + 1] = -1.0; // d m(0) / d MA
            u[4 * 4] = 1.0; // d phi(0) / d phi0
        }
        u
    }
}

impl OdeSystem for BaseOde {
    fn dim(&self) -> usize {
        if self.sens {
            20
        } else {
            4
        }
    }

    #[inline]
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]) {
        let w = &self.whisker;
        let (phi, m) = (u[0], u[1]);
        let e = w.diameter(s);
        let e2 = e * e;
        let inv_e4 = 1.0 / (e2 * e2);
        let (sp, cp) = phi.sin_cos();
        let (p, q) = self.force(s);
        du[0] = m * inv_e4 + w.a * s + w.b;
        du[1] = p * sp + q * cp;
        du[2] = cp;
        du[3] = sp;
        if !self.sens {
            return;
        }
        let jm = p * cp - q * sp;
        for j in 0..4 {
            let o = 4 * (j + 1);
            let (dphi, dm) = (u[o], u[o + 1]);
            // dP/dAx = -1, dQ/dAy = 1
            let explicit = match j {
                0 => -sp,
                1 => cp,
                _ => 0.0,
            };
            du[o] = dm * inv_e4;
            du[o + 1] = jm * dphi + explicit;
            du[o + 2] = -sp * dphi;
            du[o + 3] = cp * dphi;
        }
    }
}

/// Integrates [`BaseOde`] from the base to `s_end` (at most 1; the state part stops early
/// if `phi` winds by [`MAX_WINDING`]) with dense output.
pub(crate) fn base_ivp(
    whisker: &Whisker,
    flow: FluidLoad,
    row: &ObservableRow,
    integrator: &Dop853,
) -> Result<OdeSolution> {
    let ode = BaseOde::new(whisker, flow, row, false);
    let u0 = ode.initial(row);
    let phi0 = row.phi0;
    let (sol, _) = integrator.integrate_until(&ode, 0.0, 1.0, &u0, |_, u| {
        MAX_WINDING - (u[0] - phi0).abs()
    })?;
    Ok(sol)
}

/// One phase hypothesis of a row.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hypothesis {
    pub phase: Phase,
    pub s1: f64,
    pub x: f64,
    pub y: f64,
    pub f: f64,
    pub psi: f64,
    /// Reported residual (A: |m(1)|, B: |phi - psi|).
    pub residual: f64,
    /// Residual over its noise sensitivity at unit relative noise.
    pub z: f64,
    /// Standard deviation of the point at unit relative noise.
    pub sigma_unit: f64,
    /// Square-root part of the point's error (a double root: noise `dm` in the moment moves
    /// it by `sqrt(2 dm / |m''|)`), at unit relative noise; 0 for simple roots and phase A.
    pub sigma_sqrt: f64,
    /// Signed consistency residual `r` (A: `m(1)`; B: `Q sin phi - P cos phi` at `s1`; 0 for
    /// the double root of a release) and its derivatives with respect to `(Ax, Ay, MA, phi0)`.
    pub r: f64,
    /// `dr / d(Ax, Ay, MA, phi0)` (zero without the Jacobian).
    pub dr: [f64; 4],
    /// Length of the linear projection's move of the point (see [`evaluate`]).
    pub shift: f64,
}

impl Hypothesis {
    /// Error estimate (one standard deviation) of the point at relative noise `level`.
    pub fn sigma(&self, level: f64) -> f64 {
        level * self.sigma_unit + level.sqrt() * self.sigma_sqrt
    }
}

/// Everything the identification and the reconstruction need of one row under one flow.
#[derive(Clone, Debug)]
pub(crate) struct RowEval {
    /// Phase-A contact force `f` of [6.8, 6.9] at `s1 = 1` over its sensitivity (pre-contact
    /// rows: within the noise of 0).
    pub f_z: f64,
    /// `|m(1)|` (the free-whisker check when `f = 0`), NaN if the integration stopped early.
    pub m1: f64,
    /// Tip state `(x(1) - x0, y(1), phi(1))` (the free tip for a pre-contact row).
    pub tip: (f64, f64, f64),
    /// All hypotheses (A first if the integration reached `s = 1`).
    pub hyps: Vec<Hypothesis>,
    /// For the phase-A hypothesis: for arcs `delta` back from the tip ([`TIP_GRID`] of them,
    /// geometric from 1e-5 to 0.5), the relative noise level at which a phase-B contact at
    /// `1 - delta` fits the row as well ([`RowEval::tip_ambiguity`]); empty without one.
    pub tip_levels: Vec<(f64, f64)>,
    /// Integrations spent.
    pub evaluations: usize,
}

impl RowEval {
    /// The chosen hypothesis at relative noise `level`: among the hypotheses consistent
    /// within [`K_SIGMA`] standard deviations, the best determined one (smallest error
    /// estimate: near a phase switch, or as `f -> 0`, several fit and their points agree to
    /// within their error estimates); if consistent hypotheses disagree beyond their error
    /// estimates, the most likely one (smallest `z`), whose error estimate then covers the
    /// others ([`RowEval::ambiguity`]); without any consistent one, the smallest `z`.
    pub fn chosen(&self, level: f64) -> Option<&Hypothesis> {
        let consistent: Vec<&Hypothesis> = self
            .hyps
            .iter()
            .filter(|h| h.z <= K_SIGMA * level)
            .collect();
        let by_z = |a: &&Hypothesis, b: &&Hypothesis| a.z.total_cmp(&b.z);
        let Some(best) = consistent
            .iter()
            .copied()
            .min_by(|a, b| a.sigma(level).total_cmp(&b.sigma(level)))
        else {
            return self.hyps.iter().min_by(by_z);
        };
        let agree = consistent.iter().all(|c| {
            (c.x - best.x).hypot(c.y - best.y) <= K_SIGMA * (best.sigma(level) + c.sigma(level))
        });
        if agree {
            Some(best)
        } else {
            consistent.into_iter().min_by(by_z)
        }
    }

    /// The phase-A hypothesis at relative noise `level`: how far back from the tip a phase-B
    /// contact fits the same row, the largest arc `delta` at which both phase-B conditions,
    /// `m(1 - delta) = 0` and `g = f sin(phi - psi) = 0` there, hold within 3 standard
    /// deviations (those of `m(1)` and `g(1)`). Under noise a small tangential contact force
    /// short of the tip and a tip contact can give the same observables; the point is only
    /// known to within that arc (0 for an exact log, or when no such contact fits).
    pub fn tip_ambiguity(&self, level: f64) -> f64 {
        // look-alikes within 3 standard deviations (a 6-sigma one is not a likely truth)
        self.tip_levels
            .iter()
            .filter(|(_, need)| *need * K_SIGMA <= 3.0 * level)
            .map(|(d, _)| *d)
            .fold(0.0, f64::max)
    }

    /// The largest distance from `b`'s point to the point of another hypothesis consistent at
    /// `level` (0 if none): a row that several phases fit is only known to within that.
    pub fn ambiguity(&self, b: &Hypothesis, level: f64) -> f64 {
        self.hyps
            .iter()
            .filter(|h| !std::ptr::eq(*h, b) && h.z <= K_SIGMA * level)
            .map(|h| (h.x - b.x).hypot(h.y - b.y))
            .fold(0.0, f64::max)
    }

    /// The smallest `z` (infinite without hypotheses).
    pub fn best_z(&self) -> f64 {
        self.hyps.iter().map(|h| h.z).fold(f64::INFINITY, f64::min)
    }

    /// The reconstructed point of row `i` at relative noise `level`, from the linear
    /// projection of the chosen hypothesis (no further integration).
    pub fn point(&self, i: usize, row: &ObservableRow, level: f64) -> Option<ReconPoint> {
        let b = self.chosen(level)?;
        Some(self.make_point(i, row, level, b, b, 0, 0.0))
    }

    /// As [`RowEval::point`], with the chosen hypothesis projected to the consistent
    /// observables by [`project`] where its linear projection moves the point by more than
    /// [`PROJECT_MIN`] (noisy logs); the error estimate then also carries the uncertainty of
    /// an identified flow, `flow_sd` = standard deviations of `(q cos alpha, q sin alpha)`
    /// (each perturbation one more evaluation of the row).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn projected_point(
        &self,
        i: usize,
        row: &ObservableRow,
        level: f64,
        whisker: &Whisker,
        flow: FluidLoad,
        flow_sd: [f64; 2],
        scales: &NoiseScales,
        integrator: &Dop853,
    ) -> Result<Option<ReconPoint>> {
        let Some(b) = self.chosen(level) else {
            return Ok(None);
        };
        if b.shift <= PROJECT_MIN {
            return Ok(Some(self.make_point(i, row, level, b, b, 0, 0.0)));
        }
        let (p, mut evals) = project(whisker, flow, row, scales, integrator, b)?;
        // the flow's own uncertainty: the same hypothesis under the flow moved by one
        // standard deviation in each component
        let (sa, ca) = flow.alpha.sin_cos();
        let (qc, qs) = (flow.q * ca, flow.q * sa);
        let mut flow_var = 0.0;
        for (k, sd) in flow_sd.iter().enumerate() {
            if *sd <= 0.0 {
                continue;
            }
            let (c, s) = if k == 0 { (qc + sd, qs) } else { (qc, qs + sd) };
            let moved = crate::common::free_flow(-c, s);
            let e = evaluate(whisker, moved, row, scales, integrator)?;
            evals += e.evaluations;
            let near = e
                .hyps
                .iter()
                .filter(|c| c.phase == b.phase && (c.sigma_sqrt == 0.0) == (b.sigma_sqrt == 0.0))
                .min_by(|x, y| (x.s1 - b.s1).abs().total_cmp(&(y.s1 - b.s1).abs()));
            flow_var += match near {
                Some(h) => (h.x - b.x).powi(2) + (h.y - b.y).powi(2),
                // the hypothesis does not survive the flow's uncertainty: the row's
                // point is as uncertain as its spread of hypotheses says
                None => self.ambiguity(b, f64::INFINITY).powi(2),
            };
        }
        Ok(Some(self.make_point(
            i,
            row,
            level,
            b,
            &p.unwrap_or(*b),
            evals,
            flow_var,
        )))
    }

    /// The point of hypothesis `b` (its values from `v`, its projection).
    #[allow(clippy::too_many_arguments)]
    fn make_point(
        &self,
        i: usize,
        row: &ObservableRow,
        level: f64,
        b: &Hypothesis,
        v: &Hypothesis,
        extra: usize,
        flow_var: f64,
    ) -> ReconPoint {
        let alternatives = self
            .hyps
            .iter()
            .filter(|h| !std::ptr::eq(*h, b) && h.z <= K_SIGMA * level)
            .count();
        ReconPoint {
            row: i,
            x0: row.x0,
            x: v.x,
            y: v.y,
            s1: v.s1,
            f: v.f,
            psi: v.psi,
            phase: b.phase,
            residual: b.residual,
            // an inconsistent row implies its own noise level z; an ambiguous row is known to
            // within the spread of the hypotheses that fit it
            sigma: v
                .sigma(level.max(b.z))
                .hypot(flow_var.sqrt())
                .max(self.ambiguity(b, level))
                .max(if b.phase == Phase::A {
                    self.tip_ambiguity(level)
                } else {
                    0.0
                }),
            alternatives,
            evaluations: self.evaluations + extra,
        }
    }
}

/// `phi - psi` wrapped to `(-pi, pi]`.
fn wrap(d: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let r = d.rem_euclid(t);
    if r > std::f64::consts::PI {
        r - t
    } else {
        r
    }
}

/// The steps of a lazy base integration on which `m` may have a root or an extremum: the
/// cubic Hermite part of the step's interpolant (exact at the ends, `O(h^4)` inside) at the
/// ends and at the thirds comes within twice the step's variation of `m` (its range there,
/// or `h |m'|`) of zero, or `m'` changes sign there. Elsewhere `m` keeps its sign and its
/// direction with a margin that the cubic's error cannot close on an accepted step, and
/// the scan of [`evaluate`] has nothing to find.
fn close_steps(sol: &OdeSolution) -> Vec<bool> {
    let pts = sol.step_points();
    let mut u = [0.0; 4];
    let mut du = [0.0; 4];
    pts.windows(2)
        .enumerate()
        .map(|(idx, w)| {
            let h = (w[1] - w[0]).abs();
            let (mut lo, mut hi, mut amin, mut dmax) =
                (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, 0.0f64);
            let mut dsign = 0.0f64;
            let mut turns = false;
            for k in 0..=SAMPLES {
                if !sol.eval_cubic_on(idx, k as f64 / SAMPLES as f64, &mut u, &mut du) {
                    return true;
                }
                let (m, d) = (u[1], du[1]);
                if !(m.is_finite() && d.is_finite()) {
                    return true;
                }
                lo = lo.min(m);
                hi = hi.max(m);
                amin = amin.min(m.abs());
                dmax = dmax.max(d.abs());
                if d == 0.0 || (dsign != 0.0 && d.signum() != dsign) {
                    turns = true;
                }
                dsign = d.signum();
            }
            turns || amin <= 2.0 * (hi - lo).max(h * dmax)
        })
        .collect()
}

/// For [`Hypothesis::tip`]: at `s = 1 - delta` on a grid of `delta`, the relative noise level
/// `max(|m(s)| / sd_m, |g(s)| / sd_g) / K_SIGMA` at which the phase-B conditions hold there
/// (`g = Q sin phi - P cos phi`; `sd_m`, `sd_g` the standard deviations of `m(1)`, `g(1)` at
/// unit noise; the cubic part of the interpolant is accurate enough for a level).
fn tip_levels(sol: &OdeSolution, ode: &BaseOde, sd_m: f64, sd_g: f64) -> Vec<(f64, f64)> {
    let mut out = vec![(0.0, f64::INFINITY); TIP_GRID];
    let (mut u, mut du) = ([0.0; 4], [0.0; 4]);
    let tiny = f64::MIN_POSITIVE;
    // (m, g) at 1 - d
    let mut at = |d: f64| -> Option<(f64, f64)> {
        let s = 1.0 - d;
        if !sol.eval_cubic_into(s, &mut u, &mut du) {
            return None;
        }
        let (p, q) = ode.force(s);
        let (sp, cp) = u[0].sin_cos();
        Some((u[1], q * sp - p * cp))
    };
    let need = |m: f64, g: f64| (m.abs() / sd_m.max(tiny)).max(g.abs() / sd_g.max(tiny)) / K_SIGMA;
    let mut prev: Option<(f64, f64, f64)> = None;
    for (k, o) in out.iter_mut().enumerate() {
        let d = TIP_FIRST * TIP_RATIO.powi(k as i32);
        let Some((m, g)) = at(d) else {
            continue;
        };
        *o = (d, need(m, g));
        // g changes sign between grid points: the phase-B look-alike is where g = 0
        if let Some((d0, _, g0)) = prev {
            if g0 != 0.0 && g0.signum() != g.signum() {
                let (mut a, mut b, mut ga) = (d0, d, g0);
                for _ in 0..12 {
                    let c = 0.5 * (a + b);
                    let Some((_, gc)) = at(c) else { break };
                    if gc.signum() == ga.signum() {
                        (a, ga) = (c, gc);
                    } else {
                        b = c;
                    }
                }
                let c = 0.5 * (a + b);
                if let Some((mc, gc)) = at(c) {
                    let nc = need(mc, gc);
                    if nc < o.1 {
                        *o = (c.max(d), nc);
                    }
                }
            }
        }
        prev = Some((d, m, g));
    }
    out
}

/// Evaluates every phase hypothesis of `row` under `flow`, with the Jacobian of each with
/// respect to the observables (variational equations, columns scaled by `scales`).
pub(crate) fn evaluate(
    whisker: &Whisker,
    flow: FluidLoad,
    row: &ObservableRow,
    scales: &NoiseScales,
    integrator: &Dop853,
) -> Result<RowEval> {
    // lazy dense output: the cubic part of every step scans for roots and extrema of m, the
    // complete 7th-order interpolant is made only on the steps that may hold one
    let lazy = Dop853 {
        dense: true,
        lazy_dense: true,
        ..integrator.clone()
    };
    let mut sol = base_ivp(whisker, flow, row, &lazy)?;
    let ode = BaseOde::new(whisker, flow, row, false);
    let reached = sol.s_end >= 1.0;
    let mut evaluations = 1;
    let close = close_steps(&sol);
    for (idx, &c) in close.iter().enumerate() {
        if c {
            sol.refine(&ode, idx);
        }
    }
    // hypotheses: A (if s = 1 was reached) and every root of m on (0, s_end)
    let mut hyp_s: Vec<(Phase, f64)> = Vec::new();
    if reached {
        hyp_s.push((Phase::A, 1.0));
    }
    let mut touching: Vec<f64> = Vec::new();
    {
        let sol = &sol;
        let mut u = [0.0; 4];
        let mut du_c = [0.0; 4];
        let mut prev: (f64, f64) = (0.0, -row.ma);
        let slope = |s: f64, u: &[f64]| {
            let mut du = [0.0; 4];
            ode.rhs(s, u, &mut du);
            du[1]
        };
        let mut prev_slope = slope(0.0, &[row.phi0, -row.ma, row.x0, 0.0]);
        let opts = RootOptions {
            xtol: 1e-15,
            ftol: 0.0,
            max_iter: 200,
        };
        // m and m' on the dense output
        let m_at = |t: f64| -> Result<f64> {
            let mut buf = [0.0; 4];
            Ok(if sol.eval_into(t, &mut buf) {
                buf[1]
            } else {
                f64::NAN
            })
        };
        let d_at = |t: f64| -> Result<f64> {
            let mut buf = [0.0; 4];
            Ok(if sol.eval_into(t, &mut buf) {
                slope(t, &buf)
            } else {
                f64::NAN
            })
        };
        let root = |a: f64, b: f64, hyp_s: &mut Vec<(Phase, f64)>| {
            if let Ok(r) = brent(m_at, a, b, &opts) {
                if r.x > 0.0 && r.x < 1.0 {
                    hyp_s.push((Phase::B, r.x));
                }
            }
        };
        for (idx, w) in sol.step_points().windows(2).enumerate() {
            if !close[idx] {
                // m keeps its sign and its direction on this step: only its end is carried
                if sol.eval_cubic_on(idx, 1.0, &mut u, &mut du_c) {
                    prev = (w[1], u[1]);
                    prev_slope = du_c[1];
                }
                continue;
            }
            for k in 0..SAMPLES {
                // the last sample exactly at the step's end (stored exactly, refined or not)
                let s = if k + 1 == SAMPLES {
                    w[1]
                } else {
                    w[0] + (w[1] - w[0]) * (k + 1) as f64 / SAMPLES as f64
                };
                if !sol.eval_into(s, &mut u) {
                    continue;
                }
                let m = u[1];
                let ms = slope(s, &u);
                let (s_prev, m_prev) = prev;
                if m_prev != 0.0 && m_prev.signum() != m.signum() {
                    // a sign change of m in (0, 1): a phase-B root (m(1) = 0 is phase A)
                    if m == 0.0 {
                        if s < 1.0 {
                            hyp_s.push((Phase::B, s));
                        }
                    } else {
                        root(s_prev, s, &mut hyp_s);
                    }
                } else if prev_slope.signum() != ms.signum() && s < 1.0 {
                    // an extremum of m inside the sub-interval: two roots if it crosses zero,
                    // else, if it turns towards zero, a double-root hypothesis (a release in
                    // phase B as f -> 0 has no sign change of m)
                    let towards_zero =
                        (m_prev > 0.0 && prev_slope < 0.0) || (m_prev < 0.0 && prev_slope > 0.0);
                    if towards_zero {
                        if let Ok(e) = brent(d_at, s_prev, s, &opts) {
                            let me = m_at(e.x).unwrap_or(f64::NAN);
                            if me.signum() != m.signum() && me != 0.0 {
                                root(s_prev, e.x, &mut hyp_s);
                                root(e.x, s, &mut hyp_s);
                            }
                            // the extremum itself is the double-root hypothesis whether or not
                            // it dips across zero: at a release (f = 0) the log's last digits
                            // decide that, and the two roots of a shallow dip are determined
                            // only to the square root of the precision (its `z` rules it out
                            // when the dip is beyond the noise)
                            if e.x > 0.0 && e.x < 1.0 {
                                touching.push(e.x);
                            }
                        }
                    }
                }
                prev_slope = ms;
                prev = (s, m);
            }
        }
    }
    // a root found at the end of a close step belongs to the next step: complete that one too
    for &(_, s) in hyp_s.iter() {
        if let Some(i) = sol.step_index(s) {
            sol.refine(&ode, i);
        }
    }
    for &s in &touching {
        if let Some(i) = sol.step_index(s) {
            sol.refine(&ode, i);
        }
    }
    let mut u = [0.0; 4];
    hyp_s.extend(touching.iter().map(|&t| (Phase::B, t)));
    // the Jacobian: variational equations up to the last hypothesis
    let s_jac = hyp_s.iter().map(|h| h.1).fold(0.0, f64::max);
    let jac_sol = if s_jac > 0.0 {
        evaluations += 1;
        let sode = BaseOde::new(whisker, flow, row, true);
        Dop853::new(JACOBIAN_TOL, JACOBIAN_TOL)
            .with_lazy_dense()
            .integrate(&sode, 0.0, s_jac, &sode.initial(row))
            .ok()
            .map(|mut j| {
                // the interpolant is needed at the hypotheses only
                for &(_, s) in &hyp_s {
                    if let Some(i) = j.step_index(s) {
                        j.refine(&sode, i);
                    }
                }
                j
            })
    } else {
        None
    };
    let tiny = f64::MIN_POSITIVE;
    let (sa, ca) = flow.alpha.sin_cos();
    let mut hyps = Vec::with_capacity(hyp_s.len());
    let mut tip_table = Vec::new();
    let mut du = [0.0; 4];
    let mut jv = [0.0; 20];
    for (k, &(phase, s)) in hyp_s.iter().enumerate() {
        let touch = k >= hyp_s.len() - touching.len();
        if !sol.eval_into(s, &mut u) {
            continue;
        }
        let (phi, m, x, y) = (u[0], u[1], u[2], u[3]);
        ode.rhs(s, &u, &mut du);
        let (dphi_s, dm_s) = (du[0], du[1]);
        let (f, psi) = contact_force(row, flow, s);
        let (sp, cp) = phi.sin_cos();
        let d = wrap(phi - psi);
        // derivative of f sin(phi - psi) = Q sin phi - P cos phi along s
        let g_s = -flow.q * sa * sp + flow.q * ca * cp + dm_s * dphi_s;
        let have_jac = jac_sol.as_ref().is_some_and(|j| j.eval_into(s, &mut jv));
        let mut var_r = 0.0;
        let mut var_v = 0.0;
        let mut var_xy = 0.0;
        // covariance of the residual with the point (unit noise), for the projection below
        let mut cov = (0.0, 0.0);
        let mut dr_obs = [0.0; 4];
        if have_jac {
            // j indexes the columns of the Jacobian, the scales and the residual's gradient
            #[allow(clippy::needless_range_loop)]
            for j in 0..4 {
                let sc = scales.0[j];
                if sc == 0.0 {
                    continue;
                }
                let o = 4 * (j + 1);
                let (dphi, dm, dx, dy) = (jv[o], jv[o + 1], jv[o + 2], jv[o + 3]);
                let (dp, dq) = match j {
                    0 => (-1.0, 0.0),
                    1 => (0.0, 1.0),
                    _ => (0.0, 0.0),
                };
                // d [f sin(phi - psi)] at fixed s
                let dg = dq * sp - dp * cp + dm_s * dphi;
                match phase {
                    Phase::B if touch => {
                        // at an extremum of m the location moves to second order: derivatives
                        // at fixed s1; m itself is a residual there
                        var_r += (dg * sc).powi(2);
                        var_v += (dm * sc).powi(2);
                        var_xy += (dx * sc).powi(2) + (dy * sc).powi(2);
                    }
                    Phase::B => {
                        let ds = if dm_s != 0.0 { -dm / dm_s } else { 0.0 };
                        let dr = dg + g_s * ds;
                        let (px, py) = (dx + cp * ds, dy + sp * ds);
                        dr_obs[j] = dr;
                        var_r += (dr * sc).powi(2);
                        var_xy += (px * sc).powi(2) + (py * sc).powi(2);
                        cov = (cov.0 + dr * px * sc * sc, cov.1 + dr * py * sc * sc);
                    }
                    _ => {
                        dr_obs[j] = dm;
                        var_r += (dm * sc).powi(2);
                        var_v += (dg * sc).powi(2);
                        var_xy += (dx * sc).powi(2) + (dy * sc).powi(2);
                        cov = (cov.0 + dm * dx * sc * sc, cov.1 + dm * dy * sc * sc);
                    }
                }
            }
        }
        let (z, residual) = match phase {
            Phase::B if touch => {
                let zm = m.abs() / var_v.sqrt().max(tiny);
                (
                    ((f * d).abs() / var_r.sqrt().max(tiny)).max(zm),
                    d.abs().max(m.abs()),
                )
            }
            Phase::B => ((f * d).abs() / var_r.sqrt().max(tiny), d.abs()),
            _ => {
                // A needs phi(1) >= psi, i.e. g = f sin(phi - psi) >= 0 (a half-plane of tip
                // forces): the distance of the force from it, over the deviation of g, counts
                // like a residual (f d instead would make a noise-sized force of random
                // direction, a free row's, look like a violation)
                let viol = (-(f * d.sin())).max(0.0) / var_v.sqrt().max(tiny);
                ((m.abs() / var_r.sqrt().max(tiny)).max(viol), m.abs())
            }
        };
        // The observables carry noise; the consistency condition (A: m(1) = 0 [6.6]; B:
        // f sin(phi - psi) = Q sin phi - P cos phi = 0 at s1) holds for the true ones. The
        // most likely true observables are the nearest (in the noise metric) on which the
        // linearised condition holds: the measured ones moved by
        // `delta_j = sc_j^2 dr_j r / sum_k (sc_k dr_k)^2`, which moves the point by the part of
        // its error that the residual reveals, and leaves it the conditional covariance
        // `C_pp - c c^T / var_r` (`c` the residual-point covariance). Not for the double
        // root of a release (its location moves to second order).
        let (mut x, mut y) = (x, y);
        let mut var_post = var_xy;
        let r = match phase {
            _ if touch => 0.0,
            Phase::B => {
                let (p, q) = ode.force(s);
                q * sp - p * cp
            }
            _ => m,
        };
        let mut shift = 0.0;
        if have_jac && !touch && var_r > 0.0 {
            shift = r.abs() * cov.0.hypot(cov.1) / var_r;
            x -= r * cov.0 / var_r;
            y -= r * cov.1 / var_r;
            // (at least 1 % of the prior deviation: the projection is linearised)
            var_post = (var_xy - (cov.0 * cov.0 + cov.1 * cov.1) / var_r).max(1e-4 * var_xy);
        }
        if phase == Phase::A && !touch && have_jac {
            tip_table = tip_levels(&sol, &ode, var_r.sqrt(), var_v.sqrt());
        }
        hyps.push(Hypothesis {
            phase,
            s1: s,
            x,
            y,
            f,
            psi,
            residual,
            z: if z.is_nan() { f64::INFINITY } else { z },
            sigma_unit: if have_jac {
                var_post.sqrt()
            } else {
                f64::INFINITY
            },
            r,
            dr: dr_obs,
            shift,
            sigma_sqrt: if touch {
                // m'' = P' sin phi + Q' cos phi + (P cos phi - Q sin phi) phi'
                let (p, q) = ode.force(s);
                let m2 = -flow.q * ca * sp - flow.q * sa * cp + (p * cp - q * sp) * dphi_s;
                (2.0 * var_v.sqrt() / m2.abs().max(tiny)).sqrt()
            } else {
                0.0
            },
        });
    }
    // the phase-A force and the free-whisker check
    let (fa, fb) = force_components(row, flow, 1.0);
    let f_unit = scales.0[0].max(scales.0[1]).max(tiny);
    let tip = if reached {
        let u = &sol.u_end;
        (u[2] - row.x0, u[3], u[0])
    } else {
        (f64::NAN, f64::NAN, f64::NAN)
    };
    let m1 = if reached {
        sol.u_end[1].abs()
    } else {
        f64::NAN
    };
    Ok(RowEval {
        f_z: fa.hypot(fb) / f_unit,
        m1,
        tip,
        hyps,
        tip_levels: tip_table,
        evaluations,
    })
}

/// Linear projection moves larger than this (whisker lengths) are iterated to the manifold of
/// consistent observables (`project`); exact logs move by ~1e-12 and are left as they are.
pub const PROJECT_MIN: f64 = 1e-9;
/// Gauss-Newton steps of [`project`] at most.
const PROJECT_STEPS: usize = 4;

/// The most likely true observables of a noisy row under hypothesis `h`: the nearest (in the
/// noise metric of `scales`) to the measured ones on which the consistency condition `r = 0`
/// holds, by Gauss-Newton steps of the constrained least-squares problem (each a new
/// integration from the base at the moved observables, [`evaluate`]):
/// `obs' = meas - W dr (r + dr . (meas - obs)) / (dr W dr)` with `W = diag(scales^2)`.
/// Returns `h` with the point, `s1`, `f`, `psi` and the error estimate of the projected
/// observables (the consistency residual and `z` stay the measured row's), or `None` if the
/// hypothesis is lost on the way (then the linear projection stands).
pub(crate) fn project(
    whisker: &Whisker,
    flow: FluidLoad,
    row: &ObservableRow,
    scales: &NoiseScales,
    integrator: &Dop853,
    h0: &Hypothesis,
) -> Result<(Option<Hypothesis>, usize)> {
    let meas = [row.ax, row.ay, row.ma, row.phi0];
    let mut evals = 0;
    let mut obs = meas;
    let mut h = *h0;
    for _ in 0..PROJECT_STEPS {
        let w: Vec<f64> = (0..4).map(|j| scales.0[j] * scales.0[j]).collect();
        let sdr: f64 = (0..4).map(|j| w[j] * h.dr[j] * h.dr[j]).sum();
        if sdr.is_nan() || sdr <= 0.0 {
            return Ok((None, evals));
        }
        let num = h.r + (0..4).map(|j| h.dr[j] * (meas[j] - obs[j])).sum::<f64>();
        let next: Vec<f64> = (0..4)
            .map(|j| meas[j] - w[j] * h.dr[j] * num / sdr)
            .collect();
        let trial = ObservableRow {
            ax: next[0],
            ay: next[1],
            ma: next[2],
            phi0: next[3],
            ..*row
        };
        let e = evaluate(whisker, flow, &trial, scales, integrator)?;
        evals += e.evaluations;
        let Some(hn) = e
            .hyps
            .iter()
            .filter(|c| c.phase == h.phase && c.sigma_sqrt == 0.0)
            .min_by(|a, b| (a.s1 - h.s1).abs().total_cmp(&(b.s1 - h.s1).abs()))
        else {
            return Ok((None, evals));
        };
        let moved = (hn.x - h.x).hypot(hn.y - h.y);
        obs.copy_from_slice(&next);
        h = *hn;
        if moved <= 1e-3 * h.shift.max(PROJECT_MIN) {
            break;
        }
    }
    Ok((
        Some(Hypothesis {
            residual: h0.residual,
            z: h0.z,
            r: h0.r,
            dr: h0.dr,
            shift: h0.shift,
            ..h
        }),
        evals,
    ))
}
