//! Advice before any experiment: which object to sweep past so that the calibration
//! determines the whisker best. For each candidate contour the nominal whisker is swept
//! (contact-sim), and the Jacobian of the calibration's whitened residuals at the truth gives
//! the Fisher information of that log: the predicted standard errors at a relative noise
//! level are `noise * sqrt(diag((J^T J)^-1))` (the Cramér-Rao bound of the linearised
//! problem), and singular directions show what the log could never determine.

use super::fit::jacobian_central;
use super::ident::analyse;
use super::problem::CalibProblem;
use super::residual::{tip_force, Model, RowKind, F_MIN_REL};
use super::{CalibLog, CalibParam, ParamEstimate};
use crate::common::{KnownFlow, NoiseScales};
use crate::error::{ReconError, Result};
use crate::observables::from_sweep;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Dop853;
use contact_sim::{sweep, Phase, Profile, SweepSettings};
use serde::{Deserialize, Serialize};

/// Settings of [`design`].
#[derive(Clone, Debug, PartialEq)]
pub struct DesignSettings {
    /// The parameters to be fitted.
    pub fit: Vec<CalibParam>,
    /// The sensor's relative noise level (the convention of [`add_noise`](crate::add_noise)).
    pub noise: f64,
    /// Whether the flow will be fitted too (true: it costs information) or is known.
    pub fit_flow: bool,
    /// The sweep of each candidate (rows, tolerances).
    pub sweep: SweepSettings,
}

impl Default for DesignSettings {
    fn default() -> Self {
        DesignSettings {
            fit: super::CalibSettings::default().fit,
            noise: 1e-4,
            fit_flow: true,
            sweep: SweepSettings {
                points: 100,
                ..SweepSettings::default()
            },
        }
    }
}

/// The predicted outcome of calibrating on one candidate object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignPrediction {
    /// The candidate's name.
    pub name: String,
    /// Rows of its sweep (pre-contact + contact).
    pub rows: usize,
    /// Contact rows.
    pub contact: usize,
    /// Per fitted parameter: the nominal value and the predicted standard error at the
    /// noise level (`None` where the log could not determine it).
    pub parameters: Vec<ParamEstimate>,
    /// The largest predicted standard error relative to `max(|value|, 0.1)` over the
    /// parameters (infinite if one is not identifiable): the figure to rank candidates by.
    pub worst_relative: f64,
}

/// Predicts the standard errors of a calibration of `whisker` under `flow` on each
/// candidate contour (module docs), in the order given.
///
/// # Errors
/// The sweep's error of a candidate (the whisker never touches it, ...) as
/// [`ReconError::Model`] / [`ReconError::InvalidParameter`]; a candidate whose log cannot be
/// evaluated at the truth as [`ReconError::CalibrationStart`].
pub fn design(
    whisker: &Whisker,
    flow: FluidLoad,
    candidates: &[(String, Profile)],
    settings: &DesignSettings,
) -> Result<Vec<DesignPrediction>> {
    whisker.validate()?;
    candidates
        .iter()
        .map(|(name, profile)| predict(whisker, flow, name, profile, settings))
        .collect()
}

fn predict(
    whisker: &Whisker,
    flow: FluidLoad,
    name: &str,
    profile: &Profile,
    settings: &DesignSettings,
) -> Result<DesignPrediction> {
    let res = sweep(whisker, flow, profile, &settings.sweep).map_err(|e| {
        ReconError::InvalidParameter {
            name: "candidate",
            value: f64::NAN,
            reason: if matches!(e, contact_sim::ContactError::NoContact { .. }) {
                "the whisker never touches this candidate object"
            } else {
                "the sweep past this candidate object failed"
            },
        }
    })?;
    let rows = from_sweep(&res);
    let known = KnownFlow {
        q: Some(flow.q),
        alpha: Some(flow.alpha),
    };
    let logs = [CalibLog {
        rows: rows.clone(),
        profile: profile.clone(),
        flow: if settings.fit_flow {
            KnownFlow::default()
        } else {
            known
        },
        poses: Vec::new(),
    }];
    let model = Model::of(whisker);
    let qf = (flow.q * flow.alpha.cos(), flow.q * flow.alpha.sin());
    let fmax = rows
        .iter()
        .map(|r| tip_force(&model, qf, r))
        .fold(0.0, f64::max);
    let kinds: Vec<RowKind> = res
        .points
        .iter()
        .zip(&rows)
        .map(|(p, r)| match p.phase {
            Phase::None => RowKind::Pre,
            _ if tip_force(&model, qf, r) < F_MIN_REL * fmax => RowKind::Skipped,
            Phase::A => RowKind::A,
            Phase::B => RowKind::B { s1: p.s1 },
        })
        .collect();
    let mut prob = CalibProblem {
        logs: &logs,
        free: settings.fit.clone(),
        base: model,
        fixed_flow: vec![(!settings.fit_flow).then_some(qf)],
        used: vec![(0..rows.len()).collect()],
        whiteners: Vec::new(),
        shifts: Vec::new(),
        scales: vec![NoiseScales::of(&rows)],
        integrator: Dop853::new(1e-12, 1e-12),
        log_noise: settings.noise,
        projection: 0,
        progress: super::problem::Reporter::new(None),
        laws: super::problem::start_laws(&logs, &settings.fit),
    };
    let p = prob.pack(&model, &[qf]);
    let mut kinds = vec![kinds];
    let fail = || ReconError::CalibrationStart {
        log: 0,
        row: 0,
        x0: rows.first().map_or(f64::NAN, |r| r.x0),
    };
    if !prob.reweight(&p, &kinds) {
        return Err(fail());
    }
    prob.skip_degenerate(&mut kinds);
    let cols = jacobian_central(&prob, &p, &kinds, &prob.bounds(), 1e-5).ok_or_else(fail)?;
    let info = analyse(&cols, &prob.bounds().scale);
    let mut worst: f64 = 0.0;
    let parameters = prob
        .free
        .iter()
        .enumerate()
        .map(|(i, &param)| {
            let sd = settings.noise * info.covariance[i][i].max(0.0).sqrt();
            let (value, stderr) = match param {
                CalibParam::K => {
                    let k = whisker.support.stiffness();
                    (k, sd * k * k)
                }
                CalibParam::Ei => (1.0, sd),
                CalibParam::Mu => (p[i], sd),
                CalibParam::Theta => (p[i], sd),
                CalibParam::A => (p[i], sd),
                CalibParam::B => (p[i], sd),
            };
            let ok = info.identifiable[i];
            let rel = if ok {
                match param {
                    // relative to the compliance for a spring (finite also for rigid)
                    CalibParam::K => sd / p[i].abs().max(0.01),
                    _ => stderr / value.abs().max(0.1),
                }
            } else {
                f64::INFINITY
            };
            worst = worst.max(rel);
            ParamEstimate {
                param,
                value: ok.then_some(value),
                stderr: ok.then_some(stderr),
                identifiable: ok,
                start: value,
            }
        })
        .collect();
    Ok(DesignPrediction {
        name: name.to_string(),
        rows: rows.len(),
        contact: res.contact_points().count(),
        parameters,
        worst_relative: worst,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The predicted standard errors of `fit` for the whisker of the test log past g1.
    fn stderrs(fit: Vec<CalibParam>, fit_flow: bool) -> Vec<f64> {
        let settings = DesignSettings {
            fit,
            noise: 1e-3,
            fit_flow,
            sweep: SweepSettings {
                points: 24,
                pre_contact_rows: 3,
                ..SweepSettings::default()
            },
        };
        let w = Whisker::new(0.5, 0.4, -0.3, 20.0);
        let flow = FluidLoad { q: 2.0, alpha: 0.2 };
        let out = design(&w, flow, &[("g1".into(), Profile::g1())], &settings).unwrap();
        // three free rows, 24 contact rows and one per phase switch
        assert!(out[0].rows >= 27 && out[0].contact >= 24, "{}", out[0].rows);
        out[0]
            .parameters
            .iter()
            .map(|p| p.stderr.expect("identifiable"))
            .collect()
    }

    #[test]
    fn fitting_more_costs_information() {
        // the Cramér-Rao bound of a parameter grows with every other one fitted alongside
        // (the Schur complement of the Fisher information): the flow, then B
        let known = stderrs(vec![CalibParam::A, CalibParam::B], false);
        let fitted = stderrs(vec![CalibParam::A, CalibParam::B], true);
        let alone = stderrs(vec![CalibParam::A], false);
        assert!(known.iter().all(|s| *s > 0.0 && s.is_finite()), "{known:?}");
        assert!(
            fitted[0] >= known[0] && fitted[1] >= known[1],
            "{fitted:?} {known:?}"
        );
        assert!(alone[0] <= known[0], "{alone:?} {known:?}");
        // of a size that a noise of 1e-3 on 29 rows can give
        assert!(known[0] < 1e-1 && alone[0] > 1e-7, "{known:?}");
    }
}
