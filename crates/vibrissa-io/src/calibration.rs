//! A calibration's request, compute and report, without a command line: the whisker's own
//! parameters (theta, a, b, k and, in physical units, E I) fitted to logs of sweeps past
//! known contours (`profile_recon::calibrate`).
//!
//! - [`CalibFlags`]: the values given over a scene file (start whisker, flow, `fit`,
//!   `starts`), [`calib_model`] resolves them, [`parse_fit`] checks the list to fit;
//! - [`LogInput`]: one log in the model's units with its known contour (the command line
//!   reads it from a file, the Python package builds it from columns);
//! - [`fit_logs`]: the fit, its failures named by their culprit (a log's line, a flag);
//! - [`CalibrationReport`]: the result in the scene's units (`calibrate --json`, the
//!   Python package's dict), serialisable.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use beam_model::PhysicalWhisker;
use contact_sim::Profile;
use profile_recon::calibrate::{
    calibrate_with_progress, CalibLog, CalibParam, CalibSettings, Calibration, ParamEstimate,
    ProgressFn,
};
use profile_recon::{KnownFlow, ReconError};
use serde::Serialize;

use crate::csvio::Table;
use crate::error::IoError;
use crate::recon::{poses_of, rows_of};
use crate::resolve::{
    resolve_model, FluidFlags, LoadedScene, ModelFlags, Resolved, Value, WhiskerFlags,
};
use crate::summary::{finite, finite_opt, units_word, Finite};
use crate::units::{Quantity, UnitSystem};

/// The values of a calibration given over a scene file, each named by its flag in messages.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CalibFlags {
    /// The start whisker (`--theta`, `--a`, `--b`, `--k`).
    pub whisker: WhiskerFlags,
    /// `--q` (starts the fit; with `--alpha-deg` the flow is held fixed) and `--alpha-deg`.
    pub fluid: FluidFlags,
    /// `--fit`: a comma-separated list of theta, a, b, k, ei (default theta,a,b,k).
    pub fit: Option<String>,
    /// `--starts`: the number of start points screened (at least 1).
    pub starts: Option<Value>,
}

/// One log as read: its origin, table (model units), x0 as given and contour.
#[derive(Debug, Clone)]
pub struct LogInput {
    /// The argument as given (names the log in the outputs).
    pub arg: String,
    /// The observables file (or the origin named in messages).
    pub path: PathBuf,
    /// The table (model units).
    pub table: Table,
    /// The x0 column as given.
    pub x0_given: Vec<f64>,
    /// The pose columns as given (`y0`, `gamma`, `k` of a log of any base motion; none for
    /// a translate log), copied into `residuals.csv`.
    pub pose_given: crate::recon_io::PoseColumns,
    /// The known contour: its spec and the parsed, dimensionless profile.
    pub profile: (String, Profile),
}

/// The start whisker and flow of a calibration: the scene file `file` (if any) under the
/// values of `flags`.
pub fn calib_model(flags: &CalibFlags, file: Option<LoadedScene>) -> Result<Resolved, IoError> {
    let model = ModelFlags {
        whisker: flags.whisker.clone(),
        fluid: flags.fluid.clone(),
        ..ModelFlags::default()
    };
    resolve_model(&model, file)
}

/// Parses `--fit` (default `theta,a,b,k`; `ei` only in physical units; `mu`, the friction
/// coefficient at the contact, issue 39).
pub fn parse_fit(raw: Option<&str>, units: &UnitSystem) -> Result<Vec<CalibParam>, IoError> {
    let Some(raw) = raw else {
        return Ok(CalibSettings::default().fit);
    };
    let mut out = Vec::new();
    for name in raw.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let p = CalibParam::parse(name).ok_or_else(|| {
            IoError::invalid_argument(
                "--fit",
                raw,
                format!("unknown parameter `{name}`: expected a list of theta, a, b, k, ei, mu"),
            )
        })?;
        if p == CalibParam::Ei && !units.is_physical() {
            return Err(IoError::invalid_argument(
                "--fit",
                raw,
                "ei cannot be fitted to a dimensionless log: its forces are in units of E·Ib/L² \
                 (ei = 1 by definition); give a physical scene (units: Physical(...))",
            ));
        }
        if out.contains(&p) {
            return Err(IoError::invalid_argument(
                "--fit",
                raw,
                format!("`{name}` is given twice"),
            ));
        }
        out.push(p);
    }
    if out.is_empty() {
        return Err(IoError::invalid_argument(
            "--fit",
            raw,
            "no parameter to fit",
        ));
    }
    Ok(out)
}

/// Fits the whisker of `r` (start values, units) to the logs `inputs` as `flags` ask
/// (`fit`, `starts`, `q` with `alpha_deg`), reporting its stages to `progress`: the
/// calibration and the library's logs.
pub fn fit_logs(
    inputs: &[LogInput],
    r: &Resolved,
    flags: &CalibFlags,
    progress: ProgressFn<'_>,
) -> Result<(Calibration, Vec<CalibLog>), IoError> {
    // q and alpha_deg given: the flow of every log is known and held fixed; q alone
    // starts the fit (the scene's loads are not taken as known)
    let known = KnownFlow {
        q: flags.fluid.q.as_ref().map(|_| r.scene.loads.fluid.q),
        alpha: flags
            .fluid
            .alpha_deg
            .as_ref()
            .map(|_| r.scene.loads.fluid.alpha),
    };
    let units = r.units();
    let fit = parse_fit(flags.fit.as_deref(), &units)?;
    if known.q.is_some() && known.alpha.is_some() && fit.contains(&CalibParam::Ei) {
        return Err(IoError::invalid_argument(
            "--q",
            flags.fluid.q.as_ref().map(Value::raw).unwrap_or_default(),
            "a flow held fixed cannot be combined with fitting ei (the flow is in units of the \
             stiffness being fitted): leave out --q/--alpha-deg to fit the flow too",
        ));
    }
    let mut settings = CalibSettings {
        fit,
        ..CalibSettings::default()
    };
    if let Some(raw) = &flags.starts {
        settings.starts = raw.count("--starts", 1)?;
    }
    let logs: Vec<CalibLog> = inputs
        .iter()
        .map(|l| {
            Ok(CalibLog {
                rows: rows_of(&l.table)?,
                profile: l.profile.1.clone(),
                flow: known,
                // a log of any base motion (issue 38): the rows' poses where a row has one
                // (y0, gamma), none for the translating sweep's (bit for bit as before)
                poses: {
                    let poses = poses_of(&l.table);
                    if poses.iter().all(|p| p.is_translate()) {
                        Vec::new()
                    } else {
                        poses
                    }
                },
            })
        })
        .collect::<Result<_, IoError>>()?;
    let cal = calibrate_with_progress(&r.scene.whisker, &logs, &settings, progress)
        .map_err(|e| culprit(e, inputs))?;
    Ok((cal, logs))
}

/// Maps a calibration error to its culprit (a log's file and line, or the solver).
fn culprit(err: ReconError, inputs: &[LogInput]) -> IoError {
    match err {
        ReconError::CalibrationStart { log, row, x0 } => match inputs.get(log) {
            Some(l) => IoError::Csv {
                path: l.path.clone(),
                line: l.table.line_of(row).unwrap_or(1),
                column: None,
                reason: format!(
                    "x0 = {x0}: the start whisker admits no solution for this row; give start \
                     values closer to the truth (--theta, --a, --b, --k or a scene)"
                ),
            },
            None => IoError::solver(err),
        },
        ReconError::CalibrationNoContact { .. } => IoError::Usage {
            reason: format!(
                "{}: {err}",
                inputs
                    .iter()
                    .map(|i| format!("log `{}`", i.arg))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        },
        // `--fit` asks for a parameter the logs hold as a known column (a path's k)
        ReconError::CalibrationRequest { reason, .. }
            if reason == profile_recon::calibrate::K_IS_KNOWN =>
        {
            IoError::invalid_argument("--fit", "k", reason)
        }
        other => IoError::Solver {
            reason: format!("calibration failed: {other}"),
            source: Some(Box::new(other)),
        },
    }
}

/// A fitted parameter in the scene's units: `(value, stderr)` (None when not identifiable).
/// Physical: a in 1/m², b in 1/m, k in N m/rad, ei in N m² (k scaled with the fitted E I,
/// `lambda` the fitted E I over the start's).
pub fn in_units(
    p: &ParamEstimate,
    lambda: f64,
    phys: Option<&PhysicalWhisker>,
) -> (Option<f64>, Option<f64>) {
    let Some(ph) = phys else {
        return (p.value, p.stderr);
    };
    let l = ph.length;
    let f = match p.param {
        CalibParam::Theta => 1.0,
        CalibParam::A => 1.0 / (l * l),
        CalibParam::B => 1.0 / l,
        CalibParam::K => lambda * ph.moment_scale(),
        CalibParam::Ei => ph.bending_stiffness(),
        // dimensionless in every unit system
        CalibParam::Mu => 1.0,
    };
    (p.value.map(|v| v * f), p.stderr.map(|v| v * f))
}

/// The unit of a parameter in the scene's units.
pub fn unit_of(p: CalibParam, physical: bool) -> &'static str {
    match (p, physical) {
        (_, false) | (CalibParam::Theta | CalibParam::Mu, _) => "1",
        (CalibParam::A, true) => "1/m²",
        (CalibParam::B, true) => "1/m",
        (CalibParam::K, true) => "N m/rad",
        (CalibParam::Ei, true) => "N m²",
    }
}

/// A fitted parameter in the scene's units ([`in_units`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParamReport {
    /// The value (`None`: not identifiable, or a rigid support's k = inf).
    #[serde(serialize_with = "finite_opt")]
    pub value: Option<f64>,
    /// Its standard error.
    #[serde(serialize_with = "finite_opt")]
    pub stderr: Option<f64>,
    /// Whether the logs determine it.
    pub identifiable: bool,
    /// Its unit.
    pub unit: &'static str,
    /// k only: whether the fit is a rigid support (k = inf).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rigid: Option<bool>,
    /// k only: the compliance 1/k (what is fitted; finite either way).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compliance: Option<Finite>,
    /// k only: its standard error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compliance_stderr: Option<Finite>,
}

impl ParamReport {
    /// The parameter `p` in the scene's units (`lambda`, `phys` as in [`in_units`]).
    pub fn of(p: &ParamEstimate, lambda: f64, phys: Option<&PhysicalWhisker>) -> Self {
        let (value, stderr) = in_units(p, lambda, phys);
        let mut out = ParamReport {
            value,
            stderr,
            identifiable: p.identifiable,
            unit: unit_of(p.param, phys.is_some()),
            rigid: None,
            compliance: None,
            compliance_stderr: None,
        };
        if p.param == CalibParam::K {
            // a rigid fit: k = inf is written as null, with rigid = true
            out.rigid = Some(p.value.is_some_and(f64::is_infinite));
            if let (Some(k), Some(sd)) = (value, stderr) {
                out.compliance = Some(Finite(1.0 / k));
                out.compliance_stderr = Some(Finite(if k.is_finite() {
                    sd / (k * k)
                } else {
                    f64::NAN
                }));
            }
        }
        out
    }
}

/// One log's flow as fitted and its row counts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LogReport {
    /// The log as given.
    pub log: String,
    /// Its known contour.
    pub profile: String,
    /// The fluid load (the scene's line-load unit).
    #[serde(serialize_with = "finite")]
    pub q: f64,
    /// Its standard error.
    #[serde(serialize_with = "finite")]
    pub q_stderr: f64,
    /// The flow angle (degrees).
    #[serde(serialize_with = "finite")]
    pub alpha_deg: f64,
    /// Its standard error (degrees).
    #[serde(serialize_with = "finite")]
    pub alpha_deg_stderr: f64,
    /// Rows.
    pub rows: usize,
    /// Rows before contact.
    pub pre_contact: usize,
    /// Contact rows fitted.
    pub contact: usize,
    /// Rows left out.
    pub left_out: usize,
}

/// The calibrated whisker in the scene's units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WhiskerReport {
    /// Taper.
    #[serde(serialize_with = "finite")]
    pub theta: f64,
    /// Pre-curvature slope.
    #[serde(serialize_with = "finite")]
    pub a: f64,
    /// Pre-curvature offset.
    #[serde(serialize_with = "finite")]
    pub b: f64,
    /// Base stiffness (`None`: rigid).
    #[serde(serialize_with = "finite")]
    pub k: f64,
    /// The fitted bending stiffness E I (N m², physical units only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ei: Option<Finite>,
}

/// The correlation matrix of the fitted parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CorrelationReport {
    /// The parameters, in the matrix's order.
    pub parameters: Vec<&'static str>,
    /// The matrix.
    pub matrix: Vec<Vec<Finite>>,
}

/// A calibration in the scene's units (`calibrate --json`, spec/cli.md; the Python
/// package's result): parameters, calibrated whisker, logs, residual and the details.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CalibrationReport {
    /// The fitted parameters by name.
    pub parameters: BTreeMap<&'static str, ParamReport>,
    /// The calibrated whisker.
    pub whisker: WhiskerReport,
    /// Each log's flow.
    pub logs: Vec<LogReport>,
    /// The rms distance of the contact points to the known contours.
    #[serde(serialize_with = "finite")]
    pub rms_residual: f64,
    /// Its unit.
    pub rms_residual_unit: &'static str,
    /// The relative noise level of the fit.
    #[serde(serialize_with = "finite")]
    pub noise_level: f64,
    /// The logs' own noise level.
    #[serde(serialize_with = "finite")]
    pub log_noise: f64,
    /// The parameters' correlation.
    pub correlation: CorrelationReport,
    /// Combinations the logs determine.
    pub determined: Vec<String>,
    /// The singular values of the whitened Jacobian.
    pub singular_values: Vec<Finite>,
    /// `physical` or `dimensionless`.
    pub units: &'static str,
    /// Local fits run.
    pub local_fits: usize,
    /// Iterations.
    pub iterations: usize,
    /// Warnings.
    pub warnings: Vec<String>,
    /// The output folder, if any.
    pub out: Option<String>,
    /// The friction coefficient when `mu` was fitted (issue 39; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu: Option<MuCalibReport>,
}

/// The friction coefficient of a calibration with `mu` (`calibrate --json`'s `mu`): its value
/// and standard error (null when the logs leave it unidentifiable: no sliding row), the rows
/// by contact law and the lower bound the sticking rows give.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MuCalibReport {
    /// The fitted mu (None: not identifiable).
    #[serde(serialize_with = "finite_opt")]
    pub value: Option<f64>,
    /// Its standard error.
    #[serde(serialize_with = "finite_opt")]
    pub stderr: Option<f64>,
    /// Whether the logs determine it (some contact row slides).
    pub identifiable: bool,
    /// Contact rows in the fit that slide (`|ft| = mu fn`).
    pub sliding_rows: usize,
    /// Contact rows in the fit that stick (force inside the cone).
    pub stick_rows: usize,
    /// The largest `|ft| / fn` of the sticking rows: mu is at least this (null without one).
    #[serde(serialize_with = "finite_opt")]
    pub lower_bound: Option<f64>,
    /// Sticking rows outside the fitted cone.
    pub cone_violations: usize,
}

impl MuCalibReport {
    /// The report of `cal`'s mu (None when `mu` was not fitted).
    pub fn of(cal: &Calibration) -> Option<Self> {
        let p = cal.parameter(CalibParam::Mu)?;
        let fr = cal.friction?;
        Some(MuCalibReport {
            value: p.value,
            stderr: p.stderr,
            identifiable: p.identifiable,
            sliding_rows: fr.sliding_rows,
            stick_rows: fr.stick_rows,
            lower_bound: fr.stick_ratio.is_finite().then_some(fr.stick_ratio),
            cone_violations: fr.cone_violations,
        })
    }
}

impl CalibrationReport {
    /// The report of `cal` fitted to `inputs`, in `units` (`phys` the physical whisker of a
    /// physical scene), written to `out` if given.
    pub fn of(
        cal: &Calibration,
        inputs: &[LogInput],
        units: &UnitSystem,
        phys: Option<&PhysicalWhisker>,
        out: Option<&Path>,
    ) -> Self {
        let qs = units.scale(Quantity::LineLoad) * cal.lambda;
        let w = &cal.whisker;
        let (a, b, k) = match phys {
            None => (w.a, w.b, w.support.stiffness()),
            Some(ph) => (
                w.a / (ph.length * ph.length),
                w.b / ph.length,
                w.support.stiffness() * cal.lambda * ph.moment_scale(),
            ),
        };
        CalibrationReport {
            parameters: cal
                .parameters
                .iter()
                .map(|p| (p.param.name(), ParamReport::of(p, cal.lambda, phys)))
                .collect(),
            whisker: WhiskerReport {
                theta: w.theta,
                a,
                b,
                k,
                ei: phys.map(|ph| Finite(cal.lambda * ph.bending_stiffness())),
            },
            logs: cal
                .logs
                .iter()
                .zip(inputs)
                .map(|(l, i)| LogReport {
                    log: i.arg.clone(),
                    profile: i.profile.0.clone(),
                    q: l.q * qs,
                    q_stderr: l.q_stderr * qs,
                    alpha_deg: l.alpha.to_degrees(),
                    alpha_deg_stderr: l.alpha_stderr.to_degrees(),
                    rows: l.rows,
                    pre_contact: l.pre_contact,
                    contact: l.contact,
                    left_out: l.skipped,
                })
                .collect(),
            rms_residual: cal.rms_distance * units.scale(Quantity::Length),
            rms_residual_unit: units.unit(Quantity::Length),
            noise_level: cal.noise_level,
            log_noise: cal.log_noise,
            correlation: CorrelationReport {
                parameters: cal.parameters.iter().map(|p| p.param.name()).collect(),
                matrix: cal
                    .correlation
                    .iter()
                    .map(|r| r.iter().map(|v| Finite(*v)).collect())
                    .collect(),
            },
            determined: cal.determined.iter().map(|c| c.describe()).collect(),
            singular_values: cal.singular_values.iter().map(|v| Finite(*v)).collect(),
            units: units_word(units),
            local_fits: cal.fits.len(),
            iterations: cal.iterations,
            warnings: cal.warnings.clone(),
            out: out.map(|p| p.display().to_string()),
            mu: MuCalibReport::of(cal),
        }
    }
}
