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

use crate::accurate::{base_ivp, evaluate, RowEval, K_SIGMA};
use crate::common::{free_flow, KnownFlow, NoiseScales, ReconSettings};
use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Dop853;
use serde::{Deserialize, Serialize};

/// Smallest relative noise level assumed for a log: an exact (simulated) log carries its
/// solver's tolerance (the sweep solves to 1e-11; the free rows of one sweep differ by ~1e-12).
pub const NOISE_FLOOR: f64 = 1e-11;
/// Integrator tolerance of the first pass over the rows that picks the seed row.
const SEED_TOL: f64 = 1e-6;
/// Rows (best fits first) among which the seed's group of equal free rows is looked for.
const SEED_CANDIDATES: usize = 64;
/// Largest relative noise level the identification raises an estimate to.
pub const MAX_NOISE: f64 = 1e-2;

/// The identified flow and the pre-contact part of the log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Identification {
    /// Fluid load q [6.1] (given or identified).
    pub q: f64,
    /// Flow angle alpha (rad) [6.1] (given or identified).
    pub alpha: f64,
    /// Relative noise level used (given, or estimated from the log).
    pub noise: f64,
    /// Whether [`Identification::noise`] was estimated from the log.
    pub noise_estimated: bool,
    /// 0-based indices of the pre-contact rows (the free whisker under the flow).
    pub pre_contact: Vec<usize>,
    /// 0-based index of the first contact row in the input order (`rows.len()` if none).
    pub first_contact_row: usize,
    /// Model check: the largest `|m(1)|` of the free-whisker integration over the
    /// pre-contact rows (`MA`, `phi0` against the free solution; small when the whisker
    /// parameters are right), NaN without pre-contact rows.
    pub model_mismatch: f64,
    /// Free tip `(x1 - x0, y1, phi1)` under the flow: where the first tip contact will happen
    /// (thesis 6.1), NaN without pre-contact rows.
    pub free_tip: (f64, f64, f64),
}

impl Identification {
    /// The identified flow as a load.
    pub fn flow(&self) -> FluidLoad {
        FluidLoad {
            q: self.q,
            alpha: self.alpha,
        }
    }
}

/// Checks the given flow values.
pub(crate) fn check_known(known: &KnownFlow) -> Result<()> {
    if let Some(q) = known.q {
        if !(q.is_finite() && q >= 0.0) {
            return Err(ReconError::InvalidParameter {
                name: "q",
                value: q,
                reason: "the fluid load must be finite and >= 0",
            });
        }
    }
    if let Some(a) = known.alpha {
        if !(a.is_finite() && a.abs() < std::f64::consts::FRAC_PI_2) {
            return Err(ReconError::InvalidParameter {
                name: "alpha",
                value: a,
                reason: "the flow angle must lie in (-pi/2, pi/2)",
            });
        }
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
    let fit = match base_ivp(whisker, flow, row, integrator) {
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
    z.sort_by(f64::total_cmp);
    (z[z.len() / 2] / 0.6745).max(NOISE_FLOOR)
}

/// Whether an evaluated row is pre-contact at noise `level`.
fn is_pre_contact(e: &RowEval, level: f64) -> bool {
    let za = e.hyps.iter().find(|h| h.phase == contact_sim::Phase::A);
    e.f_z <= K_SIGMA * level && za.is_some_and(|h| h.z <= K_SIGMA * level)
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
                let x: Vec<f64> = q.iter().map(|&i| rows[i].x0).collect();
                let w: Vec<f64> = (0..4)
                    .map(|i| {
                        1.0 / (0..4)
                            .filter(|&k| k != i)
                            .map(|k| x[i] - x[k])
                            .product::<f64>()
                    })
                    .collect();
                let norm = w.iter().map(|v| v * v).sum::<f64>().sqrt();
                let v: f64 = q.iter().zip(&w).map(|(&i, wi)| wi * col(&rows[i], j)).sum();
                (v / norm).abs()
            })
            .filter(|v| v.is_finite())
            .collect();
        if d.is_empty() {
            continue;
        }
        d.sort_by(f64::total_cmp);
        worst = worst.max(d[d.len() / 2] / 0.6745 / scales.0[j]);
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

/// Identification with the evaluations of every row (module docs).
pub(crate) fn identify_rows(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: KnownFlow,
    settings: &ReconSettings,
) -> Result<Identified> {
    whisker.validate()?;
    check_known(&known)?;
    if let Some(l) = settings.noise {
        if !(l.is_finite() && l >= 0.0) {
            return Err(ReconError::InvalidParameter {
                name: "noise",
                value: l,
                reason: "the relative noise level must be finite and >= 0",
            });
        }
    }
    if !(settings.tol.is_finite() && settings.tol > 0.0) {
        return Err(ReconError::InvalidParameter {
            name: "tol",
            value: settings.tol,
            reason: "the tolerance must be finite and > 0",
        });
    }
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
    let scales = NoiseScales::of(rows);
    // a first step of 1/20 of the unit whisker (the accepted steps at tol 1e-12 are ~1/15..1/30;
    // a step too long is only rejected and shortened): saves Hairer's initial-step guess
    let integrator = Dop853 {
        h_init: Some(0.05),
        ..Dop853::new(settings.tol, settings.tol).with_dense(true)
    };
    // (1) seed flows
    let mut best_row: Option<usize> = None;
    let seeds: Vec<FluidLoad> = match (known.q, known.alpha) {
        (Some(q), Some(alpha)) => vec![FluidLoad { q, alpha }],
        _ => {
            // a coarse pass over every row
            let coarse = Dop853::new(SEED_TOL, SEED_TOL);
            let mut fits: Vec<(f64, usize)> = rows
                .iter()
                .enumerate()
                .map(|(i, r)| (free_fit(whisker, r, &known, &scales, &coarse).0, i))
                .collect();
            fits.sort_by(|a, b| a.0.total_cmp(&b.0));
            // The free rows all fit equally well (they show the same forces). First seed:
            // the mean over the rows that fit within the first pass's precision of the best
            // and whose forces lie within the noise reference of the best row's (one near-free
            // row, a release with f ~ 1e-10, cannot outvote the others). Under noise a
            // contact row with a small force may fit best: the second seed is the largest
            // group of rows whose fits are within the noise reference too and whose forces
            // lie within it of one another. Both are tried below; the flow under which the log
            // shows the lower noise level wins, and its pre-contact rows then fix it exactly
            // (step 5).
            let best = fits.first().map_or(f64::INFINITY, |c| c.0);
            let b = fits.first().map_or(0, |c| c.1);
            let level = smoothness_noise(rows, &scales).clamp(1e-9, MAX_NOISE);
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
            best_row = Some(b);
            let first = group_of(b, 10.0 * best + 10.0 * SEED_TOL);
            let mut seeds = vec![mean_flow(rows, &first, &known)];
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
                seeds.push(mean_flow(rows, &largest, &known));
            }
            seeds
        }
    };
    let eval_all = |flow: FluidLoad| -> Result<Vec<RowEval>> {
        rows.iter()
            .map(|r| evaluate(whisker, flow, r, &scales, &integrator))
            .collect()
    };
    let reference = smoothness_noise(rows, &scales);
    let level_of = |evals: &[RowEval]| {
        settings
            .noise
            .unwrap_or_else(|| estimate_noise(evals).min(reference).max(NOISE_FLOOR))
    };
    let pre_of = |evals: &[RowEval], level: f64| -> Vec<usize> {
        (0..rows.len())
            .filter(|&i| is_pre_contact(&evals[i], level))
            .collect()
    };
    let mut flow = seeds[0];
    let mut evals = eval_all(flow)?;
    let mut level = level_of(&evals);
    let mut pre = pre_of(&evals, level);
    for &other in &seeds[1..] {
        let e = eval_all(other)?;
        let l = level_of(&e);
        let p = pre_of(&e, l);
        // the right flow explains the log best: every row fits one hypothesis at a lower
        // noise level (a wrong flow raises the level, and at a raised level more rows pass
        // for free)
        if l < level || (l == level && p.len() > pre.len()) {
            (flow, evals, level, pre) = (other, e, l, p);
        }
    }
    if known.q.is_none() || known.alpha.is_none() {
        // The model-based estimate can come out low (a row with an ill-conditioned spurious
        // hypothesis fits too well): without any pre-contact row the level is raised, but
        // never beyond the model-free reference of the log's smoothness (so that a wrong
        // whisker, whose residuals look like noise to the model, finds no free row).
        let reference = reference.min(MAX_NOISE);
        while pre.is_empty() && settings.noise.is_none() && level < reference {
            level = (level * 2.0).min(reference);
            pre = (0..rows.len())
                .filter(|&i| is_pre_contact(&evals[i], level))
                .collect();
        }
        // fallback: the best row's own flow (it is the free whisker at some level)
        if pre.is_empty() && settings.noise.is_none() {
            if let Some(b) = best_row {
                flow = with_known(free_flow(rows[b].ax, rows[b].ay), &known);
                evals = eval_all(flow)?;
                level = level_of(&evals);
                pre = (0..rows.len())
                    .filter(|&i| is_pre_contact(&evals[i], level))
                    .collect();
                while pre.is_empty() && level < reference {
                    level = (level * 2.0).min(reference);
                    pre = (0..rows.len())
                        .filter(|&i| is_pre_contact(&evals[i], level))
                        .collect();
                }
            }
        }
        if pre.is_empty() {
            match known.q {
                // q given, alpha not: the thesis's flow direction alpha = 0
                Some(q) => {
                    flow = FluidLoad { q, alpha: 0.0 };
                    evals = eval_all(flow)?;
                    level = level_of(&evals);
                    pre = (0..rows.len())
                        .filter(|&i| is_pre_contact(&evals[i], level))
                        .collect();
                }
                None => return Err(ReconError::NoPreContactRows { rows: rows.len() }),
            }
        }
        // (5) the flow from the mean of the pre-contact rows; evaluate again if it moved
        for _ in 0..2 {
            if pre.is_empty() {
                break;
            }
            let n = pre.len() as f64;
            let ax = pre.iter().map(|&i| rows[i].ax).sum::<f64>() / n;
            let ay = pre.iter().map(|&i| rows[i].ay).sum::<f64>() / n;
            let next = with_known(free_flow(ax, ay), &known);
            // a move within one noise standard deviation of a row's forces changes no point
            // beyond its error estimate
            let small = level * scales.0[0].hypot(scales.0[1]);
            let moved = (next.q - flow.q).abs() > small
                || (next.alpha - flow.alpha).abs() * flow.q.max(next.q) > small;
            if !moved {
                break;
            }
            flow = next;
            evals = eval_all(flow)?;
            level = level_of(&evals).max(level);
            pre = (0..rows.len())
                .filter(|&i| is_pre_contact(&evals[i], level))
                .collect();
        }
    }
    let first_contact_row = (0..rows.len())
        .find(|i| pre.binary_search(i).is_err())
        .unwrap_or(rows.len());
    let model_mismatch = if pre.is_empty() {
        f64::NAN
    } else {
        pre.iter().map(|&i| evals[i].m1).fold(0.0, f64::max)
    };
    let free_tip = pre
        .first()
        .map_or((f64::NAN, f64::NAN, f64::NAN), |&i| evals[i].tip);
    Ok(Identified {
        id: Identification {
            q: flow.q,
            alpha: flow.alpha,
            noise: level,
            noise_estimated: settings.noise.is_none(),
            pre_contact: pre,
            first_contact_row,
            model_mismatch,
            free_tip,
        },
        evals,
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
