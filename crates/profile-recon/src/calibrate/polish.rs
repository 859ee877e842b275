//! The final polish of a calibration (module docs of [`calibrate`](super)): the phases as
//! settled by the search, the integrations at the polish tolerance, the projection of
//! noisy rows onto the model, and passes without the rows the fit cannot use at its end
//! (not evaluable, degenerate, or outliers).

use super::fit::{cost, levenberg_marquardt, LmSettings, Problem};
use super::problem::{CalibProblem, Kinds};
use super::residual::RowKind;
use super::run::{start_failure, Rounds, OUTLIER, OUTLIER_SHARE};
use super::{CalibSettings, Stage};
use crate::error::Result;
use bvp_solvers::integrator::Dop853;

/// The final polish: the phases as settled, the integrations at [`CalibSettings::polish_tol`]
/// (the searches run at the looser [`CalibSettings::tol`]), the whiteners made at the fit,
/// and Levenberg-Marquardt to convergence; the problem keeps the polished integrator and
/// whiteners for the result.
pub(crate) fn polish(
    prob: &mut CalibProblem<'_>,
    fit: &mut Rounds,
    settings: &CalibSettings,
) -> Result<()> {
    let tol = settings.polish_tol.min(settings.tol);
    let search = prob.integrator.clone();
    prob.integrator = Dop853 {
        h_init: Some(0.05),
        ..Dop853::new(tol, tol)
    };
    if !prob.reweight_or_skip(&fit.p, &mut fit.kinds) {
        // no polish: the search's fit stands
        prob.integrator = search;
        if !prob.reweight_or_skip(&fit.p, &mut fit.kinds) {
            return Err(start_failure(prob, &fit.p, &fit.kinds));
        }
        return Ok(());
    }
    // the projection changes a row's whitened residual by about the noise level squared:
    // below the integration's tolerance (exact logs) there is nothing to gain
    if prob.log_noise.powi(2) > tol {
        prob.projection = settings.projection;
    }
    let lm = LmSettings {
        max_iter: settings.max_iter,
        floor: tol,
        ..LmSettings::default()
    };
    // the estimate is the fit of the rows that are in it at the end: a row left out at the
    // fit (no longer evaluable, degenerate, or an outlier) means another pass without it
    let rows = prob.used.iter().map(Vec::len).sum();
    for pass in 0..POLISH_PASSES {
        prob.progress
            .stage(Stage::Polish, pass, POLISH_PASSES, rows, fit.cost);
        let before = skipped(&fit.kinds);
        if let Some(res) = levenberg_marquardt(prob, &fit.p, &fit.kinds, &prob.bounds(), &lm) {
            fit.iterations += res.iterations;
            fit.evaluations += res.evaluations;
            fit.p = res.p;
            fit.kinds = res.state;
        }
        if !prob.reweight_or_skip(&fit.p, &mut fit.kinds) {
            return Err(start_failure(prob, &fit.p, &fit.kinds));
        }
        prob.skip_degenerate(&mut fit.kinds);
        leave_out_outliers(prob, &fit.p, &mut fit.kinds);
        if skipped(&fit.kinds) == before {
            break;
        }
    }
    let (r, _) = prob
        .residuals(&fit.p, &fit.kinds)
        .ok_or_else(|| start_failure(prob, &fit.p, &fit.kinds))?;
    fit.cost = cost(&r);
    Ok(())
}

/// Passes of the polish at most (each a fit of the rows still in).
const POLISH_PASSES: usize = 3;

/// Which rows are skipped.
fn skipped(kinds: &Kinds) -> Vec<bool> {
    kinds
        .iter()
        .flatten()
        .map(|k| *k == RowKind::Skipped)
        .collect()
}

/// Leaves out the contact rows beyond [`OUTLIER`] times the logs' noise level at `p`
/// (unless they are more than [`OUTLIER_SHARE`] of the contact rows, at least two);
/// returns how many were.
fn leave_out_outliers(prob: &CalibProblem<'_>, p: &[f64], kinds: &mut Kinds) -> usize {
    let norms = prob.row_norms(p, kinds);
    let limit = OUTLIER * prob.log_noise.max(1e-9);
    let contact = |k: &RowKind| matches!(k, RowKind::A | RowKind::B { .. });
    let n_contact = kinds.iter().flatten().filter(|k| contact(k)).count();
    let out: Vec<(usize, usize)> = kinds
        .iter()
        .enumerate()
        .flat_map(|(l, ks)| ks.iter().enumerate().map(move |(k, kind)| (l, k, *kind)))
        .filter(|&(l, k, kind)| contact(&kind) && norms[l][k] > limit)
        .map(|(l, k, _)| (l, k))
        .collect();
    if out.len() as f64 > (OUTLIER_SHARE * n_contact as f64).max(2.0) {
        return 0;
    }
    for &(l, k) in &out {
        kinds[l][k] = RowKind::Skipped;
    }
    out.len()
}

#[cfg(test)]
mod tests {
    use super::super::test_log::{exact, problem};
    use super::super::CalibParam;
    use super::*;

    #[test]
    fn an_outlier_is_left_out_but_not_a_crowd() {
        let mut e = exact(3, 24);
        let truth_kinds = e.kinds.clone();
        let contact: Vec<usize> = (0..truth_kinds.len())
            .filter(|&i| matches!(truth_kinds[i], RowKind::A | RowKind::B { .. }))
            .collect();
        // rows moved off the model by 1e-3 of the moment's full scale (whitened: 1e-3 at
        // unit relative noise, far beyond six times a noise level of 1e-6)
        let scale = e.log.rows.iter().map(|r| r.ma.abs()).fold(0.0, f64::max);
        let moved = |e: &mut super::super::test_log::Exact, k: usize| {
            e.log.rows[contact[k]].ma += 1e-3 * scale;
        };
        let run = |e: &super::super::test_log::Exact| {
            let logs = [e.log.clone()];
            let mut prob = problem(&logs, vec![CalibParam::A], &e.truth);
            prob.log_noise = 1e-6;
            let qf = (e.flow.q * e.flow.alpha.cos(), e.flow.q * e.flow.alpha.sin());
            let p = prob.pack(&prob.base, &[qf]);
            let mut kinds = vec![e.kinds.clone()];
            assert!(prob.reweight(&p, &kinds));
            let out = leave_out_outliers(&prob, &p, &mut kinds);
            (out, skipped(&kinds))
        };
        moved(&mut e, 10);
        let (out, skip) = run(&e);
        assert_eq!(out, 1);
        assert!(
            (0..skip.len()).all(|i| skip[i] == (i == contact[10])),
            "{skip:?}"
        );
        // more than a tenth of the contact rows (at least two) off: the model is in doubt,
        // not the rows; none is left out
        for k in [3, 6] {
            moved(&mut e, k);
        }
        assert_eq!(run(&e), (0, vec![false; skip.len()]));
    }
}
