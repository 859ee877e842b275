//! Identification of the flow `(q, alpha)` from the model (thesis 6.1, Table 6.1), not from
//! statistics of the leading rows.
//!
//! A row is pre-contact when it is what the free whisker under the flow gives [6.1]:
//! `Ax = -q cos alpha`, `Ay = q sin alpha` (no contact force in the balance [6.8, 6.9] at
//! `s1 = 1`) and `MA`, `phi0` of the free solution with those loads (the integration from the
//! base with the row's own `phi0`, `MA` ends with `m(1) = 0`), both within the noise level.
//! The noise level is given, or estimated from the log itself as the median, over the rows,
//! of the best hypothesis' residual relative to its sensitivity (every row, pre-contact or
//! not, fits exactly one hypothesis up to the noise), capped by a model-free reference (the
//! scatter of the third differences of the columns along `x0`): a wrong whisker makes every
//! residual large, which must not pass for noise.
//!
//! Steps: (1) seed: the row that fits the free whisker under its OWN flow
//! `q = hypot(Ax, Ay)`, `alpha = atan2(Ay, -Ax)` best; (2) every row evaluated under the
//! seed's flow; (3) noise level; (4) pre-contact rows = within `K_SIGMA` noise of the free
//! whisker; (5) `(q, alpha)` from the mean `Ax, Ay` of the pre-contact rows, and the rows
//! evaluated again if that changed the flow. `q` and `alpha` may be given instead; with both
//! given, a log without any pre-contact row is accepted. Nothing depends on the order or the
//! spacing of the rows.

use crate::base_shot::{base_ivp_fast, evaluate, RowCtx, RowEval, K_SIGMA};
pub use crate::common::NOISE_FLOOR;
use crate::common::{free_flow, KnownFlow, NoiseScales, ReconSettings};
use crate::error::{ReconError, Result};
use crate::judge::is_pre_contact;
use crate::observables::ObservableRow;
pub use crate::result::Identification;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Dop853;

/// Integrator tolerance of the first pass over the rows that picks the seed row.
const SEED_TOL: f64 = 1e-6;
/// Rows (best fits first) among which the seed's group of equal free rows is looked for.
const SEED_CANDIDATES: usize = 64;
/// Largest relative noise level the identification raises an estimate to.
pub const MAX_NOISE: f64 = 1e-2;

/// [`ReconError::InvalidParameter`] naming `name = value` unless `ok`.
fn require(ok: bool, name: &'static str, value: f64, reason: &'static str) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(ReconError::InvalidParameter {
            name,
            value,
            reason,
        })
    }
}

/// Checks the given flow values.
pub(crate) fn check_known(known: &KnownFlow) -> Result<()> {
    if let Some(q) = known.q {
        let ok = q.is_finite() && q >= 0.0;
        require(ok, "q", q, "the fluid load must be finite and >= 0")?;
    }
    if let Some(a) = known.alpha {
        let ok = a.is_finite() && a.abs() < std::f64::consts::FRAC_PI_2;
        require(ok, "alpha", a, "the flow angle must lie in (-pi/2, pi/2)")?;
    }
    Ok(())
}

/// Checks the whisker, the known flow, the settings and the rows of an identification.
fn check_inputs(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: &KnownFlow,
    settings: &ReconSettings,
) -> Result<()> {
    whisker.validate()?;
    check_known(known)?;
    if let Some(l) = settings.noise {
        let ok = l.is_finite() && l >= 0.0;
        require(
            ok,
            "noise",
            l,
            "the relative noise level must be finite and >= 0",
        )?;
    }
    let tol = settings.tol;
    let ok = tol.is_finite() && tol > 0.0;
    require(ok, "tol", tol, "the tolerance must be finite and > 0")?;
    if rows.is_empty() {
        return Err(ReconError::TooFewRows {
            found: 0,
            needed: 1,
            what: "identification needs at least one row",
        });
    }
    for (i, r) in rows.iter().enumerate() {
        r.validate(i)?;
    }
    Ok(())
}

/// `flow` with the known parts of `known` put in.
fn with_known(flow: FluidLoad, known: &KnownFlow) -> FluidLoad {
    FluidLoad {
        q: known.q.unwrap_or(flow.q),
        alpha: known.alpha.unwrap_or(flow.alpha),
    }
}

/// How far row `row` is from the free whisker under its own flow (relative units): the
/// contact force left by the known parts of the flow plus `|m(1)|` of the free integration.
fn free_fit(
    whisker: &Whisker,
    row: &ObservableRow,
    known: &KnownFlow,
    scales: &NoiseScales,
    integrator: &Dop853,
) -> (f64, FluidLoad) {
    let flow = with_known(free_flow(row.ax, row.ay), known);
    let (f, _) = crate::common::contact_force(row, flow, 1.0);
    let fu = scales.0[0].max(scales.0[1]).max(1e-300);
    let mu = (scales.0[2] + fu).max(1e-300);
    let fit = match base_ivp_fast(whisker, flow, row, integrator) {
        Ok(sol) if sol.s_end >= 1.0 => f / fu + sol.u_end[1].abs() / mu,
        _ => f64::INFINITY,
    };
    (fit, flow)
}

/// The result of an identification with the rows' evaluations under the final flow (reused by
/// the reconstruction).
pub(crate) struct Identified {
    pub id: Identification,
    pub evals: Vec<RowEval>,
    pub scales: NoiseScales,
}

/// Relative noise level estimated from the evaluations: the median best `z` over the rows
/// divided by the median of `|N(0, 1)|`.
fn estimate_noise(evals: &[RowEval]) -> f64 {
    let mut z: Vec<f64> = evals
        .iter()
        .map(|e| e.best_z())
        .filter(|z| z.is_finite())
        .collect();
    if z.is_empty() {
        return NOISE_FLOOR;
    }
    // the median: the element a sort would put in the middle
    let mid = z.len() / 2;
    let (_, median, _) = z.select_nth_unstable_by(mid, f64::total_cmp);
    (*median / 0.6745).max(NOISE_FLOOR)
}

/// Model-free noise level of a log: rows sorted by `x0`, the third divided difference of each
/// column over consecutive quadruples, normalised so that white noise of standard deviation
/// `sigma` gives `N(0, sigma^2)`; per column the median magnitude over `0.6745` relative to the
/// column scale, the largest over the columns. The smooth part of a log adds `O(h^3)`, so
/// this is an upper reference, not an estimate for exact logs; infinite with fewer than 4
/// distinct `x0`.
pub(crate) fn smoothness_noise(rows: &[ObservableRow], scales: &NoiseScales) -> f64 {
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_by(|&a, &b| rows[a].x0.total_cmp(&rows[b].x0));
    order.dedup_by(|a, b| (rows[*a].x0 - rows[*b].x0).abs() <= 1e-12 * (1.0 + rows[*b].x0.abs()));
    if order.len() < 4 {
        return f64::INFINITY;
    }
    let col = |r: &ObservableRow, j: usize| [r.ax, r.ay, r.ma, r.phi0][j];
    let mut worst: f64 = 0.0;
    for j in 0..4 {
        if scales.0[j] == 0.0 {
            continue;
        }
        let mut d: Vec<f64> = order
            .windows(4)
            .map(|q| {
                let x: [f64; 4] = std::array::from_fn(|i| rows[q[i]].x0);
                let w: [f64; 4] = std::array::from_fn(|i| {
                    1.0 / (0..4)
                        .filter(|&k| k != i)
                        .map(|k| x[i] - x[k])
                        .product::<f64>()
                });
                let norm = w.iter().map(|v| v * v).sum::<f64>().sqrt();
                let v: f64 = q.iter().zip(&w).map(|(&i, wi)| wi * col(&rows[i], j)).sum();
                (v / norm).abs()
            })
            .filter(|v| v.is_finite())
            .collect();
        if d.is_empty() {
            continue;
        }
        let mid = d.len() / 2;
        let (_, median, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
        worst = worst.max(*median / 0.6745 / scales.0[j]);
    }
    worst.max(NOISE_FLOOR)
}

/// `flow` from the mean base forces of `rows[idx]` [6.1], with the known parts put in.
fn mean_flow(rows: &[ObservableRow], idx: &[usize], known: &KnownFlow) -> FluidLoad {
    let n = idx.len().max(1) as f64;
    let ax = idx.iter().map(|&i| rows[i].ax).sum::<f64>() / n;
    let ay = idx.iter().map(|&i| rows[i].ay).sum::<f64>() / n;
    with_known(free_flow(ax, ay), known)
}

/// Step (1), the seed flows of a log whose flow is not known in full (module docs), and the
/// row that fits the free whisker under its own flow best; `reference` is
/// [`smoothness_noise`] of the log.
fn seed_flows(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: &KnownFlow,
    scales: &NoiseScales,
    reference: f64,
) -> (Vec<FluidLoad>, usize) {
    // a coarse pass over every row
    let coarse = Dop853::new(SEED_TOL, SEED_TOL);
    let mut fits: Vec<(f64, usize)> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| (free_fit(whisker, r, known, scales, &coarse).0, i))
        .collect();
    fits.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The free rows all fit equally well (they show the same forces). First seed:
    // the mean over the rows that fit within the first pass's precision of the best
    // and whose forces lie within the noise reference of the best row's (one near-free
    // row, a release with f ~ 1e-10, cannot outvote the others). Under noise a
    // contact row with a small force may fit best: the second seed is the largest
    // group of rows whose fits are within the noise reference too and whose forces
    // lie within it of one another. Both are tried; the flow under which the log
    // shows the lower noise level wins, and its pre-contact rows then fix it exactly
    // (step 5).
    let best = fits.first().map_or(f64::INFINITY, |c| c.0);
    let b = fits.first().map_or(0, |c| c.1);
    let level = reference.clamp(1e-9, MAX_NOISE);
    let radius = K_SIGMA * level * scales.0[0].hypot(scales.0[1]);
    let near = |a: usize, c: usize| {
        let (ra, rc) = (&rows[a], &rows[c]);
        (ra.ax - rc.ax).hypot(ra.ay - rc.ay) <= radius
    };
    let group_of = |centre: usize, bound: f64| -> Vec<usize> {
        fits.iter()
            .take(SEED_CANDIDATES)
            .filter(|c| c.0 <= bound && near(centre, c.1))
            .map(|c| c.1)
            .collect()
    };
    let first = group_of(b, 10.0 * best + 10.0 * SEED_TOL);
    let mut seeds = vec![mean_flow(rows, &first, known)];
    // candidates in the order of their fit: ties go to the better fit
    let bound = 10.0 * best + 10.0 * SEED_TOL + K_SIGMA * level;
    let mut largest: Vec<usize> = Vec::new();
    for c in fits.iter().take(SEED_CANDIDATES).filter(|c| c.0 <= bound) {
        let g = group_of(c.1, bound);
        if g.len() > largest.len() {
            largest = g;
        }
    }
    if largest.len() > first.len() {
        seeds.push(mean_flow(rows, &largest, known));
    }
    (seeds, b)
}

/// A flow with the rows evaluated under it, the noise level and the pre-contact rows.
struct State {
    flow: FluidLoad,
    evals: Vec<RowEval>,
    level: f64,
    pre: Vec<usize>,
}

/// The passes of an identification over the rows of one log.
struct Passes<'a> {
    whisker: &'a Whisker,
    rows: &'a [ObservableRow],
    known: &'a KnownFlow,
    settings: &'a ReconSettings,
    scales: &'a NoiseScales,
    integrator: &'a Dop853,
    /// [`smoothness_noise`] of the log.
    reference: f64,
}

impl Passes<'_> {
    /// Every row evaluated under `flow`.
    fn eval_all(&self, flow: FluidLoad) -> Result<Vec<RowEval>> {
        let ctx = RowCtx {
            whisker: self.whisker,
            flow,
            scales: self.scales,
            integrator: self.integrator,
        };
        crate::rows_par::map_rows(self.rows.len(), |i| evaluate(&ctx, &self.rows[i]))
    }

    /// Step (3): the given noise level, else the estimate capped by the reference.
    fn level_of(&self, evals: &[RowEval]) -> f64 {
        self.settings
            .noise
            .unwrap_or_else(|| estimate_noise(evals).min(self.reference).max(NOISE_FLOOR))
    }

    /// Step (4): the pre-contact rows at `level`.
    fn pre_of(evals: &[RowEval], level: f64) -> Vec<usize> {
        (0..evals.len())
            .filter(|&i| is_pre_contact(&evals[i], level))
            .collect()
    }

    /// Steps (2)-(4) under `flow`.
    fn state(&self, flow: FluidLoad) -> Result<State> {
        let evals = self.eval_all(flow)?;
        let level = self.level_of(&evals);
        let pre = Self::pre_of(&evals, level);
        Ok(State {
            flow,
            evals,
            level,
            pre,
        })
    }

    /// The seed under which the log explains itself best: every row fits one hypothesis at
    /// a lower noise level (a wrong flow raises the level, and at a raised level more rows
    /// pass for free).
    fn best_of(&self, seeds: &[FluidLoad]) -> Result<State> {
        let mut st = self.state(seeds[0])?;
        for &other in &seeds[1..] {
            let o = self.state(other)?;
            if o.level < st.level || (o.level == st.level && o.pre.len() > st.pre.len()) {
                st = o;
            }
        }
        Ok(st)
    }

    /// Without pre-contact rows, an estimated level is doubled up to `reference`.
    fn raise(&self, st: &mut State, reference: f64) {
        while st.pre.is_empty() && self.settings.noise.is_none() && st.level < reference {
            st.level = (st.level * 2.0).min(reference);
            st.pre = Self::pre_of(&st.evals, st.level);
        }
    }

    /// A log without pre-contact rows under the seeds: the level raised, the best row's own
    /// flow, or `alpha = 0` with a given `q`; otherwise [`ReconError::NoPreContactRows`].
    fn without_free_rows(&self, st: &mut State, best_row: Option<usize>) -> Result<()> {
        // The model-based estimate can come out low (a row with an ill-conditioned spurious
        // hypothesis fits too well): without any pre-contact row the level is raised, but
        // never beyond the model-free reference of the log's smoothness (so that a wrong
        // whisker, whose residuals look like noise to the model, finds no free row).
        let reference = self.reference.min(MAX_NOISE);
        self.raise(st, reference);
        // fallback: the best row's own flow (it is the free whisker at some level)
        if st.pre.is_empty() && self.settings.noise.is_none() {
            if let Some(b) = best_row {
                let r = &self.rows[b];
                *st = self.state(with_known(free_flow(r.ax, r.ay), self.known))?;
                self.raise(st, reference);
            }
        }
        if st.pre.is_empty() {
            match self.known.q {
                // q given, alpha not: the thesis's flow direction alpha = 0
                Some(q) => *st = self.state(FluidLoad { q, alpha: 0.0 })?,
                None => {
                    return Err(ReconError::NoPreContactRows {
                        rows: self.rows.len(),
                    })
                }
            }
        }
        Ok(())
    }

    /// Step (5): the flow from the mean of the pre-contact rows; evaluated again if it moved.
    fn settle(&self, st: &mut State) -> Result<()> {
        for _ in 0..2 {
            if st.pre.is_empty() {
                break;
            }
            let next = mean_flow(self.rows, &st.pre, self.known);
            // a move within one noise standard deviation of a row's forces changes no point
            // beyond its error estimate
            let small = st.level * self.scales.0[0].hypot(self.scales.0[1]);
            let (flow, level) = (st.flow, st.level);
            let moved = (next.q - flow.q).abs() > small
                || (next.alpha - flow.alpha).abs() * flow.q.max(next.q) > small;
            if !moved {
                break;
            }
            let evals = self.eval_all(next)?;
            let level = self.level_of(&evals).max(level);
            let pre = Self::pre_of(&evals, level);
            *st = State {
                flow: next,
                evals,
                level,
                pre,
            };
        }
        Ok(())
    }
}

/// The identification of the final state.
fn identification(st: &State, noise_estimated: bool) -> Identification {
    let pre = &st.pre;
    let n = st.evals.len();
    let first_contact_row = (0..n).find(|i| pre.binary_search(i).is_err()).unwrap_or(n);
    let model_mismatch = if pre.is_empty() {
        f64::NAN
    } else {
        pre.iter().map(|&i| st.evals[i].m1).fold(0.0, f64::max)
    };
    let free_tip = pre
        .first()
        .map_or((f64::NAN, f64::NAN, f64::NAN), |&i| st.evals[i].tip);
    Identification {
        q: st.flow.q,
        alpha: st.flow.alpha,
        noise: st.level,
        noise_estimated,
        pre_contact: pre.clone(),
        first_contact_row,
        model_mismatch,
        free_tip,
    }
}

/// Identification with the evaluations of every row (module docs).
pub(crate) fn identify_rows(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: KnownFlow,
    settings: &ReconSettings,
) -> Result<Identified> {
    check_inputs(whisker, rows, &known, settings)?;
    let scales = NoiseScales::of(rows);
    // a first step of 1/20 of the unit whisker (the accepted steps at tol 1e-12 are ~1/15..1/30;
    // a step too long is only rejected and shortened): saves Hairer's initial-step guess
    let integrator = Dop853 {
        h_init: Some(0.05),
        ..Dop853::new(settings.tol, settings.tol).with_dense(true)
    };
    let passes = Passes {
        whisker,
        rows,
        known: &known,
        settings,
        scales: &scales,
        integrator: &integrator,
        reference: smoothness_noise(rows, &scales),
    };
    // (1) seed flows
    let (seeds, best_row) = match (known.q, known.alpha) {
        (Some(q), Some(alpha)) => (vec![FluidLoad { q, alpha }], None),
        _ => {
            let (seeds, b) = seed_flows(whisker, rows, &known, &scales, passes.reference);
            (seeds, Some(b))
        }
    };
    let mut st = passes.best_of(&seeds)?;
    if known.q.is_none() || known.alpha.is_none() {
        passes.without_free_rows(&mut st, best_row)?;
        passes.settle(&mut st)?;
    }
    Ok(Identified {
        id: identification(&st, settings.noise.is_none()),
        evals: st.evals,
        scales,
    })
}

/// Identifies the flow `(q, alpha)`, the noise level and the pre-contact rows of a log from the
/// model (module docs) [6.1].
///
/// # Errors
/// [`ReconError::NoPreContactRows`] when no row is the free whisker and q is not given;
/// [`ReconError::NonFinite`], [`ReconError::TooFewRows`], [`ReconError::InvalidParameter`]
/// for bad input; [`ReconError::Model`] / [`ReconError::Bvp`] for solver failures.
pub fn identify(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: KnownFlow,
    settings: &ReconSettings,
) -> Result<Identification> {
    Ok(identify_rows(whisker, rows, known, settings)?.id)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(x0: f64, v: f64) -> ObservableRow {
        ObservableRow {
            x0,
            ax: v,
            ay: 2.0 * v,
            ma: -v,
            phi0: 0.5 * v,
        }
    }

    #[test]
    fn smooth_columns_have_no_third_difference() {
        // quadratic columns on an uneven grid: the third divided difference is 0 (up to
        // rounding, far below the floor)
        let rows: Vec<ObservableRow> = [0.0, 0.1, 0.25, 0.3, 0.5, 0.55, 0.8]
            .iter()
            .map(|&x| row(x, 1.0 + x - 2.0 * x * x))
            .collect();
        let scales = NoiseScales::of(&rows);
        assert!(smoothness_noise(&rows, &scales) < 1e-9);
        // fewer than 4 distinct x0 (a repeated x0 counts once)
        let few = [row(0.0, 1.0), row(0.1, 2.0), row(0.1, 2.0), row(0.2, 3.0)];
        assert_eq!(
            smoothness_noise(&few, &NoiseScales::of(&few)),
            f64::INFINITY
        );
    }

    #[test]
    fn alternating_noise_is_measured_at_its_size() {
        // +-e on equally spaced x0: each third difference of (+e, -e, +e, -e) with the
        // weights (-1, 3, -3, 1) / h^3 normalised by sqrt(20) / h^3 is 8 e / sqrt(20)
        let e = 1e-4;
        let rows: Vec<ObservableRow> = (0..9)
            .map(|k| row(0.1 * k as f64, 1.0 + if k % 2 == 0 { e } else { -e }))
            .collect();
        let scales = NoiseScales::of(&rows);
        let want = 8.0 * e / 20f64.sqrt() / 0.6745 / scales.0[0];
        let got = smoothness_noise(&rows, &scales);
        assert!((got - want).abs() < 1e-6 * want, "{got} vs {want}");
    }

    #[test]
    fn mean_flow_is_the_free_flow_of_the_mean_forces() {
        let rows = [row(0.0, -1.0), row(0.1, -3.0), row(0.2, 100.0)];
        let f = mean_flow(&rows, &[0, 1], &KnownFlow::default());
        // mean (Ax, Ay) = (-2, -4): q = hypot, alpha = atan2(Ay, -Ax)
        assert!((f.q - 20f64.sqrt()).abs() < 1e-15);
        assert!((f.alpha - (-4f64).atan2(2.0)).abs() < 1e-15);
        let given = KnownFlow {
            q: Some(7.0),
            alpha: None,
        };
        assert_eq!(mean_flow(&rows, &[0, 1], &given).q, 7.0);
    }
}
