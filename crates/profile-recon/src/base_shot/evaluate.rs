//! The evaluation of one row under one flow ([`evaluate`]): one integration from the base,
//! the scan for the phase hypotheses, the variational equations for their Jacobian, and per
//! hypothesis its consistency `z`, its error estimate and the linear projection of its point
//! onto the consistent observables.

use super::base_ode::BaseOde;
use super::base_run::BaseRun;
use super::context::RowCtx;
use super::hypotheses::{Hypothesis, RowEval};
use super::scan::{candidates, Candidates};
use super::tip::tip_levels;
use super::variational::{sensitivities, Sens};
use crate::common::{contact_force, force_components, NoiseScales};
use crate::error::Result;
use crate::observables::ObservableRow;
use beam_model::FluidLoad;
use bvp_solvers::integrator::OdeSystem;
use contact_sim::Phase;

/// Evaluates every phase hypothesis of `row` under `ctx.flow`, with the Jacobian of each with
/// respect to the observables (variational equations, columns scaled by `ctx.scales`).
pub(crate) fn evaluate(ctx: &RowCtx<'_>, row: &ObservableRow) -> Result<RowEval> {
    let RowCtx {
        whisker,
        flow,
        scales,
        integrator,
    } = *ctx;
    // the cubic part of every step scans for roots and extrema of m, the complete 7th-order
    // interpolant is made only on the steps that may hold one
    let ode = BaseOde::new(whisker, flow, row, false).fast();
    let run = BaseRun::new(&ode, row, integrator)?;
    let reached = run.s_end >= 1.0;
    let evaluations = 1;
    // hypotheses: A (if s = 1 was reached) and every root of m on (0, s_end)
    let Candidates {
        roots: mut hyp_s,
        touching,
    } = candidates(&run, &ode, row, reached);
    hyp_s.extend(touching.iter().map(|&t| (Phase::B, t)));
    // the Jacobian: the variational equations carried along the base run's steps up to the
    // last hypothesis (no further integration)
    let arcs: Vec<f64> = hyp_s.iter().map(|h| h.1).collect();
    let jac = sensitivities(&run, &ode, &arcs);
    let mut hyps = Vec::with_capacity(hyp_s.len());
    let mut tip_table = Vec::new();
    let first_touch = hyp_s.len() - touching.len();
    for (k, &(phase, s)) in hyp_s.iter().enumerate() {
        let kind = Kind::of(phase, k >= first_touch);
        let Some(at) = Local::at(&run, &ode, row, flow, s) else {
            continue;
        };
        let jv = jac[k];
        let spread = jv.map(|jv| Spread::of(&at, kind, &jv, scales));
        if let (Kind::Tip, Some(v)) = (kind, &spread) {
            tip_table = tip_levels(&run, &ode, v.var_r.sqrt(), v.var_v.sqrt());
        }
        hyps.push(hypothesis(&ode, flow, &at, kind, spread.as_ref()));
    }
    Ok(summary(
        row,
        flow,
        scales,
        &run,
        (hyps, tip_table, evaluations),
    ))
}

/// The row's phase-A force over its scale, `|m(1)|` and the tip state (NaN if the
/// integration stopped short of the tip), with the hypotheses.
fn summary(
    row: &ObservableRow,
    flow: FluidLoad,
    scales: &NoiseScales,
    run: &BaseRun,
    (hyps, tip_levels, evaluations): (Vec<Hypothesis>, Vec<(f64, f64)>, usize),
) -> RowEval {
    let tiny = f64::MIN_POSITIVE;
    let reached = run.s_end >= 1.0;
    // the phase-A force and the free-whisker check
    let (fa, fb) = force_components(row, flow, 1.0);
    let f_unit = scales.0[0].max(scales.0[1]).max(tiny);
    let u = &run.u_end;
    let (tip, m1) = if reached {
        ((u[2] - row.x0, u[3], u[0]), u[1].abs())
    } else {
        ((f64::NAN, f64::NAN, f64::NAN), f64::NAN)
    };
    RowEval {
        f_z: fa.hypot(fb) / f_unit,
        m1,
        tip,
        hyps,
        tip_levels,
        evaluations,
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

/// The kind of a hypothesis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Phase A, the contact at the tip: consistent when `m(1) = 0` [6.6].
    Tip,
    /// Phase B at a simple root of `m`: consistent when tangential, `phi(s1) = psi`.
    Root,
    /// Phase B at an extremum of `m` (a release, `f -> 0`): `m(s1)` is a residual too.
    Touch,
}

impl Kind {
    fn of(phase: Phase, touch: bool) -> Self {
        match phase {
            Phase::B if touch => Kind::Touch,
            Phase::B => Kind::Root,
            _ => Kind::Tip,
        }
    }

    fn phase(self) -> Phase {
        if self == Kind::Tip {
            Phase::A
        } else {
            Phase::B
        }
    }
}

/// The state at a hypothesis' arc `s` and the contact it implies.
struct Local {
    s: f64,
    m: f64,
    x: f64,
    y: f64,
    sp: f64,
    cp: f64,
    /// `phi'(s)`.
    dphi_s: f64,
    /// `m'(s)`.
    dm_s: f64,
    f: f64,
    psi: f64,
    /// `phi - psi` wrapped.
    d: f64,
    /// Derivative of `f sin(phi - psi) = Q sin phi - P cos phi` along `s`.
    g_s: f64,
}

impl Local {
    /// The state at `s` on the base integration `run` of `ode` (`None` where it has none).
    fn at(
        run: &BaseRun,
        ode: &BaseOde,
        row: &ObservableRow,
        flow: FluidLoad,
        s: f64,
    ) -> Option<Local> {
        let (mut u, mut du) = ([0.0; 4], [0.0; 4]);
        if !run.eval_into(s, &mut u) {
            return None;
        }
        let (phi, m, x, y) = (u[0], u[1], u[2], u[3]);
        ode.rhs(s, &u, &mut du);
        let (dphi_s, dm_s) = (du[0], du[1]);
        let (f, psi) = contact_force(row, flow, s);
        // x' = cos phi, y' = sin phi
        let (sp, cp) = (du[3], du[2]);
        let (sa, ca) = flow.alpha.sin_cos();
        Some(Local {
            s,
            m,
            x,
            y,
            sp,
            cp,
            dphi_s,
            dm_s,
            f,
            psi,
            d: wrap(phi - psi),
            g_s: -flow.q * sa * sp + flow.q * ca * cp + dm_s * dphi_s,
        })
    }
}

/// Variances (unit relative noise) of a hypothesis' residuals and point, from the Jacobian.
#[derive(Clone, Copy, Debug, Default)]
struct Spread {
    /// Of the consistency residual `r`.
    var_r: f64,
    /// Of the second residual (A: `g = f sin(phi - psi)`; a double root: `m`).
    var_v: f64,
    /// Of the point `(x, y)` (trace).
    var_xy: f64,
    /// Covariance of the residual with the point.
    cov: (f64, f64),
    /// `dr / d(Ax, Ay, MA, phi0)`.
    dr: [f64; 4],
}

impl Spread {
    /// From the variational state `jv` at the hypothesis (columns scaled by `scales`); a
    /// simple root moves with the observables by `ds1 = -dm / m'(s1)`.
    fn of(at: &Local, kind: Kind, jv: &Sens, scales: &NoiseScales) -> Spread {
        let (sp, cp, dm_s, g_s) = (at.sp, at.cp, at.dm_s, at.g_s);
        let mut v = Spread::default();
        // j indexes the columns of the Jacobian, the scales and the residual's gradient
        for (j, &sc) in scales.0.iter().enumerate() {
            if sc == 0.0 {
                continue;
            }
            let (dphi, dm, dx, dy) = (jv[0][j], jv[1][j], jv[2][j], jv[3][j]);
            let (dp, dq) = match j {
                0 => (-1.0, 0.0),
                1 => (0.0, 1.0),
                _ => (0.0, 0.0),
            };
            // d [f sin(phi - psi)] at fixed s
            let dg = dq * sp - dp * cp + dm_s * dphi;
            match kind {
                Kind::Touch => {
                    // at an extremum of m the location moves to second order: derivatives
                    // at fixed s1; m itself is a residual there
                    v.var_r += (dg * sc).powi(2);
                    v.var_v += (dm * sc).powi(2);
                    v.var_xy += (dx * sc).powi(2) + (dy * sc).powi(2);
                }
                Kind::Root => {
                    let ds = if dm_s != 0.0 { -dm / dm_s } else { 0.0 };
                    let dr = dg + g_s * ds;
                    let (px, py) = (dx + cp * ds, dy + sp * ds);
                    v.dr[j] = dr;
                    v.var_r += (dr * sc).powi(2);
                    v.var_xy += (px * sc).powi(2) + (py * sc).powi(2);
                    v.cov = (v.cov.0 + dr * px * sc * sc, v.cov.1 + dr * py * sc * sc);
                }
                Kind::Tip => {
                    v.dr[j] = dm;
                    v.var_r += (dm * sc).powi(2);
                    v.var_v += (dg * sc).powi(2);
                    v.var_xy += (dx * sc).powi(2) + (dy * sc).powi(2);
                    v.cov = (v.cov.0 + dm * dx * sc * sc, v.cov.1 + dm * dy * sc * sc);
                }
            }
        }
        v
    }
}

/// The hypothesis of `kind` at `at` with its spread (`None` without the Jacobian).
fn hypothesis(
    ode: &BaseOde,
    flow: FluidLoad,
    at: &Local,
    kind: Kind,
    spread: Option<&Spread>,
) -> Hypothesis {
    let tiny = f64::MIN_POSITIVE;
    let v = spread.copied().unwrap_or_default();
    let (m, f, d) = (at.m, at.f, at.d);
    let (z, residual) = match kind {
        Kind::Touch => {
            let zm = m.abs() / v.var_v.sqrt().max(tiny);
            (
                ((f * d).abs() / v.var_r.sqrt().max(tiny)).max(zm),
                d.abs().max(m.abs()),
            )
        }
        Kind::Root => ((f * d).abs() / v.var_r.sqrt().max(tiny), d.abs()),
        Kind::Tip => {
            // A needs phi(1) >= psi, i.e. g = f sin(phi - psi) >= 0 (a half-plane of tip
            // forces): the distance of the force from it, over the deviation of g, counts
            // like a residual (f d instead would make a noise-sized force of random
            // direction, a free row's, look like a violation)
            let viol = (-(f * d.sin())).max(0.0) / v.var_v.sqrt().max(tiny);
            ((m.abs() / v.var_r.sqrt().max(tiny)).max(viol), m.abs())
        }
    };
    let rate = ode.rate(at.s, at.sp, at.cp);
    let r = match kind {
        Kind::Touch => 0.0,
        // g = f sin(phi - psi) = -dm'/dphi
        Kind::Root => -rate.dm_dphi,
        Kind::Tip => m,
    };
    let (x, y, var_post, shift) = linear_projection(at, kind, r, spread);
    Hypothesis {
        phase: kind.phase(),
        s1: at.s,
        x,
        y,
        f,
        psi: at.psi,
        residual,
        z: if z.is_nan() { f64::INFINITY } else { z },
        sigma_unit: if spread.is_some() {
            var_post.sqrt()
        } else {
            f64::INFINITY
        },
        r,
        dr: v.dr,
        shift,
        sigma_sqrt: if kind == Kind::Touch {
            // m'' = dm'/ds + dm'/dphi phi' = -q sin(phi + alpha) + dm'/dphi phi'
            let m2 = -flow.q * rate.flow_sin + rate.dm_dphi * at.dphi_s;
            (2.0 * v.var_v.sqrt() / m2.abs().max(tiny)).sqrt()
        } else {
            0.0
        },
    }
}

/// The point of a hypothesis moved to the most likely consistent observables, linearised:
/// `(x, y, var_post, shift)`.
///
/// The observables carry noise; the consistency condition (A: m(1) = 0 [6.6]; B:
/// f sin(phi - psi) = Q sin phi - P cos phi = 0 at s1) holds for the true ones. The
/// most likely true observables are the nearest (in the noise metric) on which the
/// linearised condition holds: the measured ones moved by
/// `delta_j = sc_j^2 dr_j r / sum_k (sc_k dr_k)^2`, which moves the point by the part of
/// its error that the residual reveals, and leaves it the conditional covariance
/// `C_pp - c c^T / var_r` (`c` the residual-point covariance). Not for the double
/// root of a release (its location moves to second order).
fn linear_projection(
    at: &Local,
    kind: Kind,
    r: f64,
    spread: Option<&Spread>,
) -> (f64, f64, f64, f64) {
    let (x, y) = (at.x, at.y);
    match spread {
        Some(v) if kind != Kind::Touch && v.var_r > 0.0 => {
            let (cov, var_r, var_xy) = (v.cov, v.var_r, v.var_xy);
            (
                x - r * cov.0 / var_r,
                y - r * cov.1 / var_r,
                // (at least 1 % of the prior deviation: the projection is linearised)
                (var_xy - (cov.0 * cov.0 + cov.1 * cov.1) / var_r).max(1e-4 * var_xy),
                r.abs() * cov.0.hypot(cov.1) / var_r,
            )
        }
        Some(v) => (x, y, v.var_xy, 0.0),
        None => (x, y, 0.0, 0.0),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use beam_model::Whisker;
    use bvp_solvers::integrator::Dop853;
    use contact_sim::{sweep, Profile, SweepResult, SweepSettings};
    use std::f64::consts::PI;

    #[test]
    fn wrap_lands_in_the_half_open_interval() {
        for (d, w) in [
            (0.5, 0.5),
            (PI, PI),
            (-PI, PI),
            (3.0 * PI / 2.0, -PI / 2.0),
            (7.0, 7.0 - 2.0 * PI),
        ] {
            assert!((wrap(d) - w).abs() < 1e-15, "{d}: {} vs {w}", wrap(d));
        }
    }

    #[test]
    fn linear_projection_satisfies_the_linearised_condition() {
        // one column: r + dr dobs = 0 after the move, the point moved along dp/dobs
        let at = Local {
            s: 1.0,
            m: 0.0,
            x: 1.0,
            y: 2.0,
            sp: 0.0,
            cp: 1.0,
            dphi_s: 0.0,
            dm_s: 0.0,
            f: 0.0,
            psi: 0.0,
            d: 0.0,
            g_s: 0.0,
        };
        // residual 0.1 with gradient 2 (scale 1); point gradient (3, -1)
        let (dr, px, py) = (2.0, 3.0, -1.0);
        let v = Spread {
            var_r: dr * dr,
            var_v: 0.0,
            var_xy: px * px + py * py,
            cov: (dr * px, dr * py),
            dr: [dr, 0.0, 0.0, 0.0],
        };
        let (x, y, var_post, shift) = linear_projection(&at, Kind::Tip, 0.1, Some(&v));
        // dobs = -r / dr = -0.05: the point moves by (3, -1) * -0.05
        assert!(
            (x - 0.85).abs() < 1e-15 && (y - 2.05).abs() < 1e-15,
            "{x} {y}"
        );
        assert!((shift - 0.05 * 10f64.sqrt()).abs() < 1e-15);
        // one noise source fully revealed by the residual: nothing left but the 1 % floor
        assert!((var_post - 1e-4 * 10.0).abs() < 1e-16);
        // a double root is never moved
        let (x, y, _, shift) = linear_projection(&at, Kind::Touch, 0.1, Some(&v));
        assert_eq!((x, y, shift), (1.0, 2.0, 0.0));
    }

    /// A sweep of the uniform whisker past contour g2 in the flow `q = 5`, `alpha = 0`.
    pub(crate) fn g2_sweep(points: usize) -> (Whisker, FluidLoad, SweepResult) {
        let w = Whisker::uniform();
        let flow = FluidLoad { q: 5.0, alpha: 0.0 };
        let settings = SweepSettings {
            points,
            ..Default::default()
        };
        (w, flow, sweep(&w, flow, &Profile::g2(), &settings).unwrap())
    }

    /// [`g2_sweep`] with its rows, their noise scales and the integrator of a row context.
    pub(crate) struct G2Rows {
        pub truth: SweepResult,
        pub rows: Vec<ObservableRow>,
        pub scales: NoiseScales,
        whisker: Whisker,
        flow: FluidLoad,
        integrator: Dop853,
    }

    impl G2Rows {
        pub(crate) fn new(points: usize) -> Self {
            let (whisker, flow, truth) = g2_sweep(points);
            let rows = crate::observables::from_sweep(&truth);
            let scales = NoiseScales::of(&rows);
            G2Rows {
                truth,
                rows,
                scales,
                whisker,
                flow,
                integrator: Dop853::new(1e-12, 1e-12).with_dense(true),
            }
        }

        /// The row context of the sweep's whisker and flow.
        pub(crate) fn ctx(&self) -> RowCtx<'_> {
            RowCtx {
                whisker: &self.whisker,
                flow: self.flow,
                scales: &self.scales,
                integrator: &self.integrator,
            }
        }
    }

    #[test]
    fn a_simulated_row_is_its_own_contact() {
        // round trip: the observables of a simulated sweep give back its hidden contact point
        let g2 = G2Rows::new(12);
        let (truth, rows, ctx) = (&g2.truth, &g2.rows, g2.ctx());
        let mut contacts = 0;
        for (p, row) in truth.points.iter().zip(rows) {
            if p.f <= 1e-9 {
                continue;
            }
            contacts += 1;
            let e = evaluate(&ctx, row).unwrap();
            let h = e.chosen(1e-11).unwrap();
            assert_eq!(h.phase, p.phase);
            assert!((h.x - p.xc).abs() < 1e-9 && (h.y - p.yc).abs() < 1e-9);
            assert!((h.s1 - p.s1).abs() < 1e-8 && (h.f - p.f).abs() < 1e-8 * (1.0 + p.f));
        }
        assert!(contacts > 3);
    }
}
