//! Friction in a calibration (issue 39): what the contact law of a fit with `mu` found
//! ([`FrictionFit`]: sliding and stick rows, the stick rows' lower bound of mu, the cone's
//! violations) and, for a calibration without `mu`, whether a log's rows prove friction.
//!
//! **A log calibrated without `mu`** is fitted as a frictionless one (every row's force
//! normal to the known contour). Its residuals then show friction as tangential contact
//! forces: the log is reconstructed at the calibrated whisker and flow on its known contour
//! ([`reconstruct_frictional_on`], the contact point needs no mu), and a tangential force
//! beyond 6 of its standard deviations (`FrictionEvidence::proves_friction`) is reported as a
//! warning naming the row and its `ft`, with the mu its sliding rows give: the frictionless
//! calibration of that log is biased, and `mu` should be fitted too.

use super::problem::{CalibProblem, Kinds};
use super::residual::{row_residuals, ContactLaw, RowCtx};
use super::run::{pre_contact, subsample_rows, LONG_LOG};
use super::whiten::whitener;
use super::{CalibLog, Calibration, FrictionFit};
use crate::base_shot::K_SIGMA;
use crate::common::{KnownFlow, ReconSettings};
use crate::friction::reconstruct_frictional_on;
use crate::observables::ObservableRow;

/// The contact law's findings at the fit `p` with `kinds` (a fit with `mu`): rows by law,
/// the stick rows' largest `|ft| / fn`, and the stick rows outside the fitted cone (by more
/// than [`K_SIGMA`] standard deviations of `ft` at the logs' noise level, and 1e-8 of `fn`)
/// when `mu` is identifiable.
pub(crate) fn friction_fit(
    prob: &CalibProblem<'_>,
    p: &[f64],
    kinds: &Kinds,
    mu_ok: bool,
) -> FrictionFit {
    let (model, flows) = prob.unpack(p);
    let laws = prob.laws.borrow().clone();
    let mut out = FrictionFit {
        sliding_rows: 0,
        stick_rows: 0,
        stick_ratio: f64::NAN,
        cone_violations: 0,
    };
    for (l, used) in prob.used.iter().enumerate() {
        let ctx = prob.ctx(l, &model, flows[l]);
        for (k, &i) in used.iter().enumerate() {
            let kind = kinds[l][k];
            let Some(ix) = ContactLaw::index(kind) else {
                continue;
            };
            match laws[l][i] {
                ContactLaw::Slip { .. } => out.sliding_rows += 1,
                ContactLaw::Normal => {}
                ContactLaw::Stick => {
                    out.stick_rows += 1;
                    let placed = RowCtx {
                        law: ContactLaw::Normal,
                        ..prob.placed(&ctx, l, i)
                    };
                    let row = &prob.logs[l].rows[i];
                    let Some(res) = row_residuals(&placed, row, kind) else {
                        continue;
                    };
                    let (ft, fnn) = (res.r[ix], res.compression);
                    if fnn > 0.0 {
                        out.stick_ratio = out.stick_ratio.max(ft.abs() / fnn);
                    }
                    if mu_ok {
                        let sd = whitener(&placed, row, &res, &prob.scales[l])
                            .map_or(0.0, |w| w.sd(ix) * prob.log_noise);
                        if ft.abs() - model.mu * fnn > K_SIGMA * sd + 1e-8 * fnn.abs() {
                            out.cone_violations += 1;
                        }
                    }
                }
            }
        }
    }
    out
}

/// The warnings of a fit with `mu` (module docs).
pub(crate) fn fit_warnings(fr: &FrictionFit, mu_ok: bool) -> Vec<String> {
    let mut w = Vec::new();
    if !mu_ok {
        let bound = if fr.stick_ratio.is_finite() {
            format!(
                "; the force of the sticking rows only bounds it from below, mu >= {:.4}",
                fr.stick_ratio
            )
        } else {
            String::new()
        };
        w.push(if fr.sliding_rows == 0 {
            format!(
                "mu is not identifiable: no contact row of these logs slides ({} stick){bound}",
                fr.stick_rows
            )
        } else {
            format!(
                "mu is not identifiable from the {} sliding row(s) of these logs{bound}",
                fr.sliding_rows
            )
        });
    }
    if fr.cone_violations > 0 {
        w.push(format!(
            "{} sticking row(s) need more friction than the fitted mu (their |ft| / fn beyond \
             the cone by more than {K_SIGMA} standard deviations): a wrong contour, or a law \
             the rows do not follow",
            fr.cone_violations
        ));
    }
    w
}

/// The warning of log `l` (0-based) of a calibration `cal` made without `mu` whose rows
/// prove friction (module docs), None for a log that does not (or a posed log, or one past
/// a peg, or one the frictional reconstruction cannot read). Logs longer than `LONG_LOG`
/// rows are judged on an evenly spread subsample.
pub(crate) fn friction_warning(cal: &Calibration, logs: &[CalibLog], l: usize) -> Option<String> {
    let log = &logs[l];
    if !log.poses.is_empty() || matches!(log.profile, contact_sim::Profile::Peg { .. }) {
        return None;
    }
    let fit = cal.logs.get(l)?;
    let lambda = cal.lambda;
    let pre = pre_contact(&log.rows, false);
    let idx = subsample_rows(&log.rows, &pre, LONG_LOG);
    let rows: Vec<ObservableRow> = idx
        .iter()
        .map(|&i| {
            let r = &log.rows[i];
            ObservableRow {
                ax: r.ax / lambda,
                ay: r.ay / lambda,
                ma: r.ma / lambda,
                ..*r
            }
        })
        .collect();
    let known = KnownFlow {
        q: Some(fit.q),
        alpha: Some(fit.alpha),
    };
    let fr = reconstruct_frictional_on(
        &cal.whisker,
        &rows,
        known,
        &ReconSettings::default(),
        None,
        Some(&log.profile),
    )
    .ok()?;
    let ev = fr.evidence.filter(|e| e.proves_friction())?;
    let mu = fr.mu.map_or(String::new(), |m| {
        format!(
            "; its {} sliding row(s) give mu ~ {:.4} +- {:.1e}",
            m.rows, m.value, m.stderr
        )
    });
    Some(format!(
        "log {}: its rows prove friction (row {} at x0 = {}: ft = {:.3e}, {:.0} standard \
         deviations from 0 on the known contour at the calibrated whisker{mu}): the \
         frictionless calibration of it is biased; fit mu too (--fit ...,mu)",
        l + 1,
        idx[ev.row] + 1,
        ev.x0,
        ev.ft,
        ev.z()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_warnings_of_an_unidentifiable_mu_give_its_lower_bound() {
        let fr = FrictionFit {
            sliding_rows: 0,
            stick_rows: 12,
            stick_ratio: 0.25,
            cone_violations: 0,
        };
        let w = fit_warnings(&fr, false);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].contains("no contact row") && w[0].contains("mu >= 0.2500"),
            "{w:?}"
        );
        assert!(fit_warnings(&fr, true).is_empty());
        let bad = FrictionFit {
            cone_violations: 2,
            ..fr
        };
        assert!(fit_warnings(&bad, true)[0].starts_with("2 sticking row(s)"));
    }
}
