//! The global part of the guard against local minima: before any local fit, seeded
//! candidate whiskers around the start are ranked by a phase-free objective on a subsample
//! of the rows, and the local fits start from the best ones.
//!
//! The local fit decides each contact row's phase at its current parameters; from a start
//! far off, rows near a phase switch are decided wrongly and the fit can settle in a
//! consistent but wrong compromise. The screening objective has no phase decision: every row
//! counts with its best hypothesis (tip contact or any root of `m`), its residuals scaled by
//! fixed per-log scales (the columns' full scales), each row's contribution capped so that
//! a hopeless row does not dominate.

use super::problem::CalibProblem;
use super::residual::{hypotheses, row_residuals, Model, RowCtx, RowKind};
use super::{CalibParam, Stage};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// Contact rows per log in the screening subsample.
const ROWS: usize = 16;
/// Cap of one row's scaled squared residual.
const CAP: f64 = 1e4;

/// The screening objective of the parameter vector `p` (module docs): the sum over the
/// subsample `rows[l]` of each row's smallest scaled squared residual, capped.
pub(crate) fn objective(prob: &CalibProblem<'_>, p: &[f64], rows: &[Vec<(usize, bool)>]) -> f64 {
    let (model, flows) = prob.unpack(p);
    let mut total = 0.0;
    for (l, sub) in rows.iter().enumerate() {
        let sc = &prob.scales[l].0;
        let sf = sc[0].max(sc[1]).max(1e-12);
        let sm = sc[2].max(1e-12);
        let sp = sc[3].max(1e-12) * 1e-2 + sm * model.c;
        let ctx = RowCtx {
            model: &model,
            flow: flows[l],
            profile: &prob.logs[l].profile,
            integrator: &prob.integrator,
            pose: crate::pose::RowPose::TRANSLATE,
            shift: 0.0,
            law: super::residual::ContactLaw::Normal,
        };
        for &(i, pre) in sub {
            let row = &prob.logs[l].rows[i];
            let ctx = prob.placed(&ctx, l, i);
            let scaled = |kind: RowKind, r: &[f64; 4]| -> f64 {
                let s = match kind {
                    RowKind::Pre => [sp, sf, sf, sm],
                    RowKind::A => [sp, sm, 1e-2, sf],
                    _ => [sp, 1e-2, sf, sf],
                };
                r.iter().zip(s).map(|(v, s)| (v / s).powi(2)).sum::<f64>()
            };
            let best = if pre {
                row_residuals(&ctx, row, RowKind::Pre).map_or(CAP, |h| scaled(h.kind, &h.r))
            } else {
                hypotheses(&ctx, row)
                    .iter()
                    .map(|h| scaled(h.kind, &h.r))
                    .fold(CAP, f64::min)
            };
            total += best.min(CAP);
        }
    }
    total
}

/// The subsample: per log one pre-contact row and about [`ROWS`] contact rows evenly
/// spread, each with whether it is pre-contact.
pub(crate) fn subsample(prob: &CalibProblem<'_>, pre: &[Vec<bool>]) -> Vec<Vec<(usize, bool)>> {
    prob.logs
        .iter()
        .zip(pre)
        .map(|(log, p)| {
            let n = log.rows.len();
            let contact: Vec<usize> = (0..n).filter(|&i| !p[i]).collect();
            let step = contact.len().div_ceil(ROWS).max(1);
            let mut out: Vec<(usize, bool)> = (0..n)
                .filter(|&i| p[i])
                .take(1)
                .map(|i| (i, true))
                .collect();
            out.extend(contact.iter().step_by(step).map(|&i| (i, false)));
            out
        })
        .collect()
}

/// `count` seeded candidates around `p0` (theta within a factor 2 and in [0.02, 1], A and
/// B within `0.75 |value| + 0.5`, `1/k` kept (the follicle law's), E I within a factor 2), the
/// flows kept; returned with `p0` first, sorted by the screening [`objective`].
pub(crate) fn candidates(
    prob: &CalibProblem<'_>,
    p0: &[f64],
    pre: &[Vec<bool>],
    count: usize,
    seed: u64,
) -> Vec<(f64, Vec<f64>)> {
    let rows = subsample(prob, pre);
    let mut rng = StdRng::seed_from_u64(seed);
    let start: Model = prob.unpack(p0).0;
    let mut out = vec![(objective(prob, p0, &rows), p0.to_vec())];
    let n_rows = rows.iter().map(Vec::len).sum();
    for k in 0..count {
        prob.progress
            .stage(Stage::Screen, k, count, n_rows, out[0].0);
        let mut p = p0.to_vec();
        for (v, param) in p.iter_mut().zip(&prob.free) {
            *v = match param {
                CalibParam::Theta => {
                    (start.theta * 2f64.powf(rng.gen_range(-1.0..1.0))).clamp(0.02, 1.0)
                }
                CalibParam::A => start.a + (0.75 * start.a.abs() + 0.5) * rng.gen_range(-1.0..1.0),
                CalibParam::B => start.b + (0.75 * start.b.abs() + 0.5) * rng.gen_range(-1.0..1.0),
                // the follicle law gives 1/k directly (linear least squares)
                CalibParam::K => *v,
                CalibParam::Ei => start.lambda.ln() + 2f64.ln() * rng.gen_range(-1.0..1.0),
                // the slip rows' residuals are linear in mu: the start's
                CalibParam::Mu => *v,
            };
        }
        out.push((objective(prob, &p, &rows), p));
    }
    // the designed set: a grid over the whole range of the shape parameters, so that a
    // truth far from the start (a slender tip from a uniform start) has a candidate near it
    if count > 0 {
        for p in designed(prob, p0) {
            out.push((objective(prob, &p, &rows), p));
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// Grid values of theta, A and B of the designed candidates ([`designed`]).
const GRID: [&[f64]; 3] = [
    &[0.25, 0.45, 0.7, 1.0],
    &[-1.0, 0.0, 1.0],
    &[-0.6, 0.0, 0.6],
];

/// The designed candidates: `p0` with its free theta, A, B on every point of [`GRID`] (the
/// parameters not fitted, k and E I kept; the follicle law gives `1/k` and the flows come
/// from the free rows).
pub(crate) fn designed(prob: &CalibProblem<'_>, p0: &[f64]) -> Vec<Vec<f64>> {
    let slot = |param: CalibParam| prob.free.iter().position(|p| *p == param);
    let axes = [
        slot(CalibParam::Theta),
        slot(CalibParam::A),
        slot(CalibParam::B),
    ];
    let mut out: Vec<Vec<f64>> = vec![p0.to_vec()];
    for (axis, values) in axes.iter().zip(GRID) {
        let Some(i) = axis else { continue };
        out = out
            .iter()
            .flat_map(|p| {
                values.iter().map(move |v| {
                    let mut q = p.clone();
                    q[*i] = *v;
                    q
                })
            })
            .collect();
    }
    if axes.iter().all(Option::is_none) {
        out.clear();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::residual::tip_force;
    use super::super::test_log::{exact, problem};
    use super::*;

    #[test]
    fn the_truth_screens_best() {
        let e = exact(3, 24);
        let logs = [e.log.clone()];
        let free = vec![CalibParam::Theta, CalibParam::A, CalibParam::K];
        let prob = problem(&logs, free, &e.truth);
        let qf = (e.flow.q * e.flow.alpha.cos(), e.flow.q * e.flow.alpha.sin());
        let p0 = prob.pack(&prob.base, &[qf]);
        let pre: Vec<Vec<bool>> = vec![e.kinds.iter().map(|k| *k == RowKind::Pre).collect()];
        let rows = subsample(&prob, &pre);
        // one pre-contact row and every contact row up to 16 (24 and more: every other)
        assert!(rows[0][0].1 && rows[0][1..].iter().all(|r| !r.1));
        assert!((12..=17).contains(&rows[0].len()), "{}", rows[0].len());
        // the truth explains every row with its best hypothesis, but for a contact row
        // without force (the first contact: no push, so no hypothesis), which counts the cap
        let force = |i: usize| tip_force(&prob.base, qf, &logs[0].rows[i]);
        let fmax = (0..logs[0].rows.len()).map(force).fold(0.0, f64::max);
        let forceless = rows[0]
            .iter()
            .filter(|r| !r.1 && force(r.0) < 1e-9 * fmax)
            .count();
        assert_eq!(forceless, 1);
        let at_truth = objective(&prob, &p0, &rows);
        assert!((at_truth - CAP).abs() < 1e-12, "{at_truth:e}");
        let forced = vec![rows[0]
            .iter()
            .copied()
            .filter(|r| r.1 || force(r.0) >= 1e-9 * fmax)
            .collect()];
        assert!(objective(&prob, &p0, &forced) < 1e-18);
        let mut off = p0.clone();
        off[1] += 0.1;
        assert!(objective(&prob, &off, &forced) > 1e-6);
        // the candidates, sorted, the truth first, the compliance and the flow kept
        let c = candidates(&prob, &p0, &pre, 4, 3);
        // the start, four seeded, and the designed grid over theta and A (4 x 3)
        assert_eq!(c.len(), 5 + 12);
        assert_eq!(designed(&prob, &p0).len(), 12);
        assert!(c.windows(2).all(|w| w[0].0 <= w[1].0));
        // the truth among them, and nothing screened worse than the best
        assert!(c.iter().any(|(_, p)| *p == p0));
        assert!(c[0].0 <= at_truth);
        assert!(c.iter().all(|(_, p)| p[2] == p0[2] && p[3..] == p0[3..]));
        assert!(c.iter().all(|(_, p)| (0.02..=1.0).contains(&p[0])));
    }
}
