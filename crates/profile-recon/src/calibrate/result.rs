//! The result of a calibration: the final Jacobian (central differences) and its analysis,
//! the estimates in the parameters' own form, the flows, every row, and the checks' findings.

use super::fit::jacobian_central;
use super::friction_check::friction_warning;
use super::ident::analyse;
use super::problem::{CalibProblem, Kinds};
use super::residual::{flow_of, Model, RowKind};
use super::run::{logs_noise, start_failure, Rounds, NOISE_CHECK, OUTLIER_SHARE};
use super::whiten::Whitener;
use super::{CalibParam, Calibration, Combination, LogFit, ParamEstimate, RowFit};
use crate::error::{ReconError, Result};
use beam_model::Whisker;
use contact_sim::Phase;

/// The letters of the row kinds, as a row's fit carries them ([`RowFit::kind`]; here, where
/// the fits are made).
impl RowKind {
    /// The row kind in one letter: the phase's ([`Phase::letter`]: `-` before contact, `A`,
    /// `B`), `x` for a row left out.
    pub fn letter(&self) -> char {
        match self {
            RowKind::Pre => Phase::None.letter(),
            RowKind::A => Phase::A.letter(),
            RowKind::B { .. } => Phase::B.letter(),
            RowKind::Skipped => 'x',
        }
    }

    /// Whether a letter of [`RowKind::letter`] is a contact's (`A` or `B`).
    pub fn is_contact_letter(letter: char) -> bool {
        letter == Phase::A.letter() || letter == Phase::B.letter()
    }
}

/// The result: the final Jacobian (central differences), its analysis, the estimates, the
/// flows, the rows and the checks.
pub(crate) fn summarize(
    prob: &mut CalibProblem<'_>,
    fit: &Rounds,
    costs: &[f64],
    start: &Whisker,
) -> Result<Calibration> {
    let n = prob.dim();
    let nres = prob.residual_count(&fit.kinds);
    if nres <= n {
        return Err(ReconError::CalibrationUnderdetermined {
            residuals: nres,
            rows: nres / super::residual::RESIDUALS_PER_ROW,
            parameters: n,
        });
    }
    let bounds = prob.bounds();
    let cols = jacobian_central(prob, &fit.p, &fit.kinds, &bounds, 1e-5)
        .ok_or_else(|| start_failure(prob, &fit.p, &fit.kinds))?;
    let info = analyse(&cols, &prob.bounds().scale);
    let s = (2.0 * fit.cost / (nres - n) as f64).sqrt();
    let cov: Vec<Vec<f64>> = info
        .covariance
        .iter()
        .map(|r| r.iter().map(|v| v * s * s).collect())
        .collect();
    let (model, flows) = prob.unpack(&fit.p);
    let start_model = Model::of(start);
    let parameters = estimates(prob, &fit.p, &cov, &info.identifiable, &start_model);
    let nfree = prob.free.len();
    let correlation = (0..nfree)
        .map(|i| {
            (0..nfree)
                .map(|j| {
                    let d = (cov[i][i] * cov[j][j]).sqrt();
                    if info.identifiable[i] && info.identifiable[j] && d > 0.0 {
                        cov[i][j] / d
                    } else {
                        f64::NAN
                    }
                })
                .collect()
        })
        .collect();
    let determined = combinations(prob, &fit.p, &info.determined, &cov);
    let mut out_model = model;
    for (i, param) in prob.free.iter().enumerate() {
        if !info.identifiable[i] {
            match param {
                CalibParam::Theta => out_model.theta = start_model.theta,
                CalibParam::A => out_model.a = start_model.a,
                CalibParam::B => out_model.b = start_model.b,
                CalibParam::K => out_model.c = start_model.c,
                CalibParam::Ei => out_model.lambda = 1.0,
                CalibParam::Mu => out_model.mu = f64::NAN,
            }
        }
    }
    let logs = log_fits(prob, &flows, &fit.kinds, &cov);
    let rows = row_fits(prob, &fit.p, &fit.kinds, s);
    let contact: Vec<f64> = rows
        .iter()
        .filter(|r| RowKind::is_contact_letter(r.kind))
        .map(|r| r.distance)
        .collect();
    // the distance of no row is none (NaN), not 0
    let rms_distance = (contact.iter().map(|d| d * d).sum::<f64>() / contact.len() as f64).sqrt();
    let log_noise = logs_noise(prob);
    let mut cal = Calibration {
        whisker: out_model.whisker(),
        lambda: out_model.lambda,
        parameters,
        correlation,
        determined,
        singular_values: info.relative_singular_values,
        logs,
        rows,
        rms_distance,
        noise_level: s,
        log_noise,
        iterations: fit.iterations,
        evaluations: fit.evaluations,
        fits: costs.to_vec(),
        warnings: Vec::new(),
        friction: None,
    };
    cal.warnings = warnings(&cal, fit, costs);
    if prob.free.contains(&CalibParam::Mu) {
        let mu_ok = prob
            .free
            .iter()
            .position(|p| *p == CalibParam::Mu)
            .is_some_and(|i| info.identifiable[i]);
        let fr = super::friction_check::friction_fit(prob, &fit.p, &fit.kinds, mu_ok);
        cal.warnings
            .extend(super::friction_check::fit_warnings(&fr, mu_ok));
        cal.friction = Some(fr);
    } else {
        let found: Vec<String> = (0..prob.logs.len())
            .filter_map(|l| friction_warning(&cal, prob.logs, l))
            .collect();
        cal.warnings.extend(found);
    }
    Ok(cal)
}

/// The estimate of every fitted parameter (`k` and `ei` mapped back from `1/k`, `ln lambda`).
fn estimates(
    prob: &CalibProblem<'_>,
    p: &[f64],
    cov: &[Vec<f64>],
    identifiable: &[bool],
    start: &Model,
) -> Vec<ParamEstimate> {
    prob.free
        .iter()
        .enumerate()
        .map(|(i, &param)| {
            let sd = cov[i][i].max(0.0).sqrt();
            let (value, stderr, st) = match param {
                CalibParam::K => {
                    let c = p[i];
                    let k = if c > 0.0 { 1.0 / c } else { f64::INFINITY };
                    (k, sd * k * k, 1.0 / start.c)
                }
                CalibParam::Ei => (p[i].exp(), sd * p[i].exp(), 1.0),
                CalibParam::Mu => (p[i], sd, start.mu),
                CalibParam::Theta => (p[i], sd, start.theta),
                CalibParam::A => (p[i], sd, start.a),
                CalibParam::B => (p[i], sd, start.b),
            };
            let ok = identifiable[i];
            ParamEstimate {
                param,
                value: ok.then_some(value),
                stderr: ok.then_some(stderr),
                identifiable: ok,
                start: st,
            }
        })
        .collect()
}

/// The determined combinations as terms of the whisker's parameters.
fn combinations(
    prob: &CalibProblem<'_>,
    p: &[f64],
    determined: &[Vec<f64>],
    cov: &[Vec<f64>],
) -> Vec<Combination> {
    determined
        .iter()
        .map(|c| {
            let terms = prob
                .free
                .iter()
                .zip(c)
                .filter(|(_, v)| **v != 0.0)
                .map(|(param, v)| (*param, *v))
                .collect();
            let value = c.iter().zip(p).map(|(a, b)| a * b).sum();
            let var: f64 = (0..c.len())
                .map(|i| (0..c.len()).map(|j| c[i] * cov[i][j] * c[j]).sum::<f64>())
                .sum();
            Combination {
                terms,
                value,
                stderr: var.max(0.0).sqrt(),
            }
        })
        .collect()
}

/// The flow of every log with its standard errors (delta method from the Cartesian form).
fn log_fits(
    prob: &CalibProblem<'_>,
    flows: &[(f64, f64)],
    kinds: &Kinds,
    cov: &[Vec<f64>],
) -> Vec<LogFit> {
    let mut k = prob.free.len();
    flows
        .iter()
        .enumerate()
        .map(|(l, &(qc, qs))| {
            let f = flow_of(qc, qs);
            let given = prob.fixed_flow[l].is_some();
            let (q_sd, a_sd) = if given {
                (0.0, 0.0)
            } else {
                let (i, j) = (k, k + 1);
                k += 2;
                let q = f.q.max(f64::MIN_POSITIVE);
                let gq = [qc / q, qs / q];
                let ga = [-qs / (q * q), qc / (q * q)];
                let quad = |g: [f64; 2]| {
                    (g[0] * g[0] * cov[i][i]
                        + 2.0 * g[0] * g[1] * cov[i][j]
                        + g[1] * g[1] * cov[j][j])
                        .max(0.0)
                        .sqrt()
                };
                (quad(gq), quad(ga))
            };
            let count = |pred: fn(&RowKind) -> bool| kinds[l].iter().filter(|k| pred(k)).count();
            LogFit {
                q: f.q,
                alpha: f.alpha,
                q_stderr: q_sd,
                alpha_stderr: a_sd,
                given,
                rows: prob.logs[l].rows.len(),
                pre_contact: count(|k| *k == RowKind::Pre),
                contact: count(|k| matches!(k, RowKind::A | RowKind::B { .. })),
                skipped: count(|k| *k == RowKind::Skipped),
            }
        })
        .collect()
}

/// Every row at the fit (`s` the fitted noise level).
fn row_fits(prob: &CalibProblem<'_>, p: &[f64], kinds: &Kinds, s: f64) -> Vec<RowFit> {
    let results = prob.evaluate(p, kinds).unwrap_or_default();
    let (model, flows) = prob.unpack(p);
    let mut out = Vec::new();
    for (l, used) in prob.used.iter().enumerate() {
        let ctx = prob.ctx(l, &model, flows[l]);
        for (k, &i) in used.iter().enumerate() {
            let Some(res) = results.get(l).and_then(|r| r.get(k)) else {
                continue;
            };
            let w: &Whitener = &prob.whiteners[l][k];
            let kind = res.kind.letter();
            let (s1, di) = match res.kind {
                RowKind::Pre | RowKind::Skipped => (f64::NAN, None),
                RowKind::A => (1.0, Some(2)),
                RowKind::B { s1 } => (s1, Some(1)),
            };
            let chi = if res.kind == RowKind::Skipped {
                f64::NAN
            } else {
                let z = prob.whitened(&ctx, l, k, res);
                z.iter().map(|v| v * v).sum::<f64>().sqrt() / s.max(f64::MIN_POSITIVE)
            };
            out.push(RowFit {
                log: l,
                row: i,
                kind,
                s1,
                x: res.point.0,
                y: res.point.1,
                distance: res.distance,
                sigma: di.map_or(f64::NAN, |d| w.sd(d) * s),
                chi,
            });
        }
    }
    out
}

/// The checks' findings.
fn warnings(cal: &Calibration, fit: &Rounds, costs: &[f64]) -> Vec<String> {
    let mut w = Vec::new();
    if fit.lost > 0 {
        w.push(format!(
            "{} contact row(s) admit no contact hypothesis with the fitted whisker, or cannot be \
             used by it, and were left out",
            fit.lost
        ));
    }
    for (l, log) in cal.logs.iter().enumerate() {
        let n = l + 1;
        if log.pre_contact == 0 && !log.given {
            w.push(format!(
                "log {n}: no row of the free whisker (before contact): its flow is fitted from \
                 its contact rows alone"
            ));
        }
        if log.contact == 0 {
            w.push(format!(
                "log {n}: none of its rows is in the fit as a contact row; it gives its flow \
                 and the follicle law only"
            ));
        } else if log.skipped as f64 > OUTLIER_SHARE * (log.contact + log.skipped) as f64 {
            w.push(format!(
                "log {n}: {} of its {} contact rows were left out of the fit (contact forces \
                 within the noise of zero, phase borders, folds or outliers)",
                log.skipped,
                log.contact + log.skipped
            ));
        }
    }
    let unknown: Vec<&str> = cal
        .parameters
        .iter()
        .filter(|p| !p.identifiable)
        .map(|p| p.param.name())
        .collect();
    if !unknown.is_empty() {
        w.push(format!(
            "not determined by these logs (start values kept): {}",
            unknown.join(", ")
        ));
    }
    if cal.noise_level > NOISE_CHECK * cal.log_noise.max(1e-9) {
        w.push(format!(
            "the fit's residuals imply a relative noise level {:.2e}, {:.0} times the logs' own \
             ({:.2e}) after {} local fit(s): a local minimum, a wrong contour or flow, or a \
             whisker the model cannot describe",
            cal.noise_level,
            cal.noise_level / cal.log_noise.max(1e-9),
            cal.log_noise,
            costs.len()
        ));
    }
    w
}
