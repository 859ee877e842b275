//! `vibrissa calibrate`: the whisker's own parameters (theta, a, b, k and, in physical units,
//! E I) fitted to logs of sweeps past objects of known contour (profile-recon's
//! [`calibrate`](profile_recon::calibrate)); writes the calibrated `scene.ron`, the residual
//! of every row and the figures.

use std::path::{Path, PathBuf};

use beam_model::PhysicalWhisker;
use contact_sim::Profile;
use profile_recon::calibrate::{
    calibrate, CalibLog, CalibParam, CalibSettings, Calibration, ParamEstimate,
};
use profile_recon::{KnownFlow, ReconError};

use crate::atomic::OutputDir;
use crate::cli::{CalibrateArgs, ModelFlags};
use crate::commands::calibrate_out::{self, RESIDUALS_CSV};
use crate::commands::recon_io;
use crate::commands::reconstruct::{rows_of, REQUIRED_COLUMNS};
use crate::csvio::{read_table, Table};
use crate::error::CliError;
use crate::resolve::{
    parse_count, physical_whisker, resolve_model, LoadedScene, ProfileArg, Resolved,
};
use crate::units::{Quantity, UnitSystem};

/// One log as read: its origin, table (model units), x0 as given and contour. The Python
/// package builds these from columns in memory (`path` then names the log in messages).
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
    /// The known contour: its spec and the parsed, dimensionless profile.
    pub profile: (String, Profile),
}

/// Runs `vibrissa calibrate`.
pub fn run(args: &CalibrateArgs) -> Result<(), CliError> {
    if !args.advise.is_empty() {
        return crate::commands::calibrate_advice::run(args);
    }
    let specs: Vec<(String, PathBuf, Option<String>)> = args
        .logs
        .iter()
        .map(|a| split_log_arg(a))
        .collect::<Result<_, _>>()?;
    // the whisker's start values and the units: --scene, else the first sweep folder's
    let first_folder = specs
        .iter()
        .find(|s| s.1.is_dir())
        .map(|s| s.1.join(recon_io::SCENE_RON));
    let scene_path = args.scene.clone().or(first_folder.filter(|p| p.is_file()));
    let file = LoadedScene::load_opt(scene_path.as_deref())?;
    let flags = ModelFlags {
        whisker: args.whisker.clone(),
        fluid: args.fluid.clone(),
        ..ModelFlags::default()
    };
    let r = resolve_model(&flags, file)?;
    let units = r.units();
    // the request is checked before any log is read
    parse_fit(args.fit.as_deref(), &units)?;
    let inputs: Vec<LogInput> = specs
        .iter()
        .map(|(arg, path, profile)| read_log(arg, path, profile.as_deref(), args, &r))
        .collect::<Result<_, _>>()?;
    if let Some(out) = &args.out {
        let files: Vec<(&str, &Path)> = inputs.iter().map(|l| ("log", l.path.as_path())).collect();
        crate::atomic::refuse_over_inputs(out, &files)?;
    }
    let (cal, logs) = fit_inputs(&inputs, &r, args)?;
    let start = r.scene.whisker;
    let phys = r.physical;
    if let Some(out_dir) = &args.out {
        let out = OutputDir::create(out_dir)?;
        calibrate_out::write_calibrated_scene(
            &r,
            &cal,
            &inputs,
            &out.path_for(recon_io::SCENE_RON),
        )?;
        calibrate_out::write_residuals(&cal, &inputs, &units, &out.path_for(RESIDUALS_CSV))?;
        calibrate_out::write_figures(&cal, &inputs, &logs, &start, &units, |n| out.path_for(n))?;
        out.commit()?;
    }
    if args.json {
        println!(
            "{}",
            json_of(&cal, &inputs, &units, phys.as_ref(), args.out.as_deref())
        );
    } else {
        print_summary(&cal, &inputs, &units, phys.as_ref());
        if let Some(d) = &args.out {
            println!(
                "wrote scene.ron, {RESIDUALS_CSV} and figures to {}",
                d.display()
            );
        }
    }
    Ok(())
}

/// Fits the whisker of `r` (start values, units) to the logs `inputs` as `args` asks
/// (`--fit`, `--starts`, `--q` with `--alpha-deg`): the calibration and the library's logs.
pub fn fit_inputs(
    inputs: &[LogInput],
    r: &Resolved,
    args: &CalibrateArgs,
) -> Result<(Calibration, Vec<CalibLog>), CliError> {
    // --q and --alpha-deg given: the flow of every log is known and held fixed; --q alone
    // starts the fit (the scene's loads are not taken as known)
    let known = KnownFlow {
        q: args.fluid.q.as_ref().map(|_| r.scene.loads.fluid.q),
        alpha: args
            .fluid
            .alpha_deg
            .as_ref()
            .map(|_| r.scene.loads.fluid.alpha),
    };
    let units = r.units();
    let fit = parse_fit(args.fit.as_deref(), &units)?;
    if known.q.is_some() && known.alpha.is_some() && fit.contains(&CalibParam::Ei) {
        return Err(CliError::invalid_argument(
            "--q",
            args.fluid.q.clone().unwrap_or_default(),
            "a flow held fixed cannot be combined with fitting ei (the flow is in units of the \
             stiffness being fitted): leave out --q/--alpha-deg to fit the flow too",
        ));
    }
    let mut settings = CalibSettings {
        fit,
        ..CalibSettings::default()
    };
    if let Some(raw) = &args.starts {
        settings.starts = parse_count("--starts", raw, 1)?;
    }
    let logs: Vec<CalibLog> = inputs
        .iter()
        .map(|l| {
            Ok(CalibLog {
                rows: rows_of(&l.table)?,
                profile: l.profile.1.clone(),
                flow: known,
            })
        })
        .collect::<Result<_, CliError>>()?;
    let cal = calibrate(&r.scene.whisker, &logs, &settings).map_err(|e| culprit(e, inputs))?;
    Ok((cal, logs))
}

/// `LOG` or `LOG=PROFILE`: the argument, the path and the profile spec. An argument that
/// names an existing file or folder as a whole is a path (even with `=` in it).
fn split_log_arg(arg: &str) -> Result<(String, PathBuf, Option<String>), CliError> {
    let whole = PathBuf::from(arg);
    if whole.exists() {
        return Ok((arg.to_string(), whole, None));
    }
    if let Some((p, prof)) = arg.rsplit_once('=') {
        let path = PathBuf::from(p);
        if path.exists() {
            return Ok((arg.to_string(), path, Some(prof.to_string())));
        }
    }
    Err(CliError::io(
        arg,
        std::io::Error::new(
            std::io::ErrorKind::NotFound,
            "no such log (an observables CSV or a sweep folder, optionally LOG=PROFILE)",
        ),
    ))
}

/// Parses `--fit` (default `theta,a,b,k`; `ei` only in physical units).
pub(crate) fn parse_fit(
    raw: Option<&str>,
    units: &UnitSystem,
) -> Result<Vec<CalibParam>, CliError> {
    let Some(raw) = raw else {
        return Ok(CalibSettings::default().fit);
    };
    let mut out = Vec::new();
    for name in raw.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let p = CalibParam::parse(name).ok_or_else(|| {
            CliError::invalid_argument(
                "--fit",
                raw,
                format!("unknown parameter `{name}`: expected a list of theta, a, b, k, ei"),
            )
        })?;
        if p == CalibParam::Ei && !units.is_physical() {
            return Err(CliError::invalid_argument(
                "--fit",
                raw,
                "ei cannot be fitted to a dimensionless log: its forces are in units of E·Ib/L² \
                 (ei = 1 by definition); give a physical scene (units: Physical(...))",
            ));
        }
        if out.contains(&p) {
            return Err(CliError::invalid_argument(
                "--fit",
                raw,
                format!("`{name}` is given twice"),
            ));
        }
        out.push(p);
    }
    if out.is_empty() {
        return Err(CliError::invalid_argument(
            "--fit",
            raw,
            "no parameter to fit",
        ));
    }
    Ok(out)
}

/// Reads one log: its observables (a sweep folder's `observables.csv`), converted to model
/// units, and its known contour (`LOG=PROFILE`, else `--profile`, else the folder's
/// `scene.ron`).
fn read_log(
    arg: &str,
    path: &Path,
    profile: Option<&str>,
    args: &CalibrateArgs,
    r: &Resolved,
) -> Result<LogInput, CliError> {
    let units = r.units();
    let (log_path, folder_scene) = if path.is_dir() {
        let (log, scene) = recon_io::resolve_input(path, None)?;
        (log, scene)
    } else {
        (path.to_path_buf(), None)
    };
    let folder = LoadedScene::load_opt(folder_scene.as_deref())?;
    if let Some(f) = &folder {
        if physical_whisker(f)? != r.physical {
            return Err(CliError::Usage {
                reason: format!(
                    "log `{arg}`: its scene.ron has other units than the calibration's ({}); \
                     calibrate logs of one unit system together",
                    units.describe()
                ),
            });
        }
    }
    let prof = match (profile, &args.profile) {
        (Some(p), _) => ProfileArg {
            spec: p.to_string(),
            file: None,
        },
        (None, Some(p)) => ProfileArg {
            spec: p.clone(),
            file: None,
        },
        (None, None) => match folder
            .as_ref()
            .or(r.file.as_ref())
            .and_then(|f| f.file.profile.clone().map(|p| (p, f.clone())))
        {
            Some((spec, f)) => ProfileArg {
                spec,
                file: Some(f),
            },
            None => {
                return Err(CliError::Usage {
                    reason: format!(
                        "log `{arg}`: no known contour: give --profile P, `{arg}=PROFILE`, a \
                         sweep folder or a --scene whose scene.ron names its profile"
                    ),
                })
            }
        },
    };
    let parsed = prof.parse(&units)?;
    let mut table = read_table(&log_path, &REQUIRED_COLUMNS, 2)?;
    let x0_given = recon_io::to_model_units(&mut table, &units)?;
    let rows = rows_of(&table)?;
    for (i, row) in rows.iter().enumerate() {
        row.validate(i).map_err(|e| match e {
            ReconError::NonFinite { row, column, value } => CliError::Csv {
                path: log_path.clone(),
                line: table.line_of(row).unwrap_or(1),
                column: Some(column.to_string()),
                reason: format!("value `{value}` is not finite"),
            },
            other => CliError::solver(other),
        })?;
    }
    Ok(LogInput {
        arg: arg.to_string(),
        path: log_path,
        table,
        x0_given,
        profile: (prof.spec.clone(), parsed),
    })
}

/// Maps a calibration error to its culprit (a log's file and line, or the solver).
fn culprit(err: ReconError, inputs: &[LogInput]) -> CliError {
    match err {
        ReconError::CalibrationStart { log, row, x0 } => match inputs.get(log) {
            Some(l) => CliError::Csv {
                path: l.path.clone(),
                line: l.table.line_of(row).unwrap_or(1),
                column: None,
                reason: format!(
                    "x0 = {x0}: the start whisker admits no solution for this row; give start \
                     values closer to the truth (--theta, --a, --b, --k or a scene)"
                ),
            },
            None => CliError::solver(err),
        },
        other => CliError::Solver {
            reason: format!("calibration failed: {other}"),
            source: Some(Box::new(other)),
        },
    }
}

/// A fitted parameter in the scene's units: `(value, stderr)` (None when not identifiable).
/// Physical: a in 1/m², b in 1/m, k in N m/rad, ei in N m² (k scaled with the fitted E I).
pub(crate) fn in_units(
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
    };
    (p.value.map(|v| v * f), p.stderr.map(|v| v * f))
}

/// The unit of a parameter in the scene's units.
pub(crate) fn unit_of(p: CalibParam, physical: bool) -> &'static str {
    match (p, physical) {
        (_, false) | (CalibParam::Theta, _) => "1",
        (CalibParam::A, true) => "1/m²",
        (CalibParam::B, true) => "1/m",
        (CalibParam::K, true) => "N m/rad",
        (CalibParam::Ei, true) => "N m²",
    }
}

/// A number for JSON (null for NaN and infinities).
pub(crate) fn num(v: f64) -> serde_json::Value {
    if v.is_finite() {
        serde_json::json!(v)
    } else {
        serde_json::Value::Null
    }
}

/// The `--json` object (spec/cli.md): parameters, logs, rms_residual and the details.
pub fn json_of(
    cal: &Calibration,
    inputs: &[LogInput],
    units: &UnitSystem,
    phys: Option<&PhysicalWhisker>,
    out: Option<&Path>,
) -> serde_json::Value {
    let mut params = serde_json::Map::new();
    for p in &cal.parameters {
        let (v, sd) = in_units(p, cal.lambda, phys);
        let mut o = serde_json::json!({
            "value": v.map_or(serde_json::Value::Null, num),
            "stderr": sd.map_or(serde_json::Value::Null, num),
            "identifiable": p.identifiable,
            "unit": unit_of(p.param, phys.is_some()),
        });
        if p.param == CalibParam::K {
            // a rigid fit: k = inf is written as null, with rigid = true; the compliance 1/k
            // (what is fitted) is finite either way
            o["rigid"] = serde_json::json!(p.value.is_some_and(f64::is_infinite));
            if let (Some(k), Some(sd)) = (v, sd) {
                o["compliance"] = num(1.0 / k);
                o["compliance_stderr"] = num(if k.is_finite() {
                    sd / (k * k)
                } else {
                    f64::NAN
                });
            }
        }
        params.insert(p.param.name().to_string(), o);
    }
    let qs = units.scale(Quantity::LineLoad) * cal.lambda;
    let logs: Vec<serde_json::Value> = cal
        .logs
        .iter()
        .zip(inputs)
        .map(|(l, i)| {
            serde_json::json!({
                "log": i.arg,
                "profile": i.profile.0,
                "q": num(l.q * qs),
                "q_stderr": num(l.q_stderr * qs),
                "alpha_deg": num(l.alpha.to_degrees()),
                "alpha_deg_stderr": num(l.alpha_stderr.to_degrees()),
                "rows": l.rows,
                "pre_contact": l.pre_contact,
                "contact": l.contact,
                "left_out": l.skipped,
            })
        })
        .collect();
    let names: Vec<&str> = cal.parameters.iter().map(|p| p.param.name()).collect();
    let corr: Vec<Vec<serde_json::Value>> = cal
        .correlation
        .iter()
        .map(|r| r.iter().map(|v| num(*v)).collect())
        .collect();
    let w = &cal.whisker;
    let (a, b, k) = match phys {
        None => (w.a, w.b, w.support.stiffness()),
        Some(ph) => (
            w.a / (ph.length * ph.length),
            w.b / ph.length,
            w.support.stiffness() * cal.lambda * ph.moment_scale(),
        ),
    };
    let mut whisker = serde_json::json!({"theta": w.theta, "a": num(a), "b": num(b), "k": num(k)});
    if let Some(ph) = phys {
        whisker["ei"] = num(cal.lambda * ph.bending_stiffness());
    }
    serde_json::json!({
        "parameters": params,
        "whisker": whisker,
        "logs": logs,
        "rms_residual": num(cal.rms_distance * units.scale(Quantity::Length)),
        "rms_residual_unit": units.unit(Quantity::Length),
        "noise_level": num(cal.noise_level),
        "log_noise": num(cal.log_noise),
        "correlation": {"parameters": names, "matrix": corr},
        "determined": cal.determined.iter().map(|c| c.describe()).collect::<Vec<_>>(),
        "singular_values": cal.singular_values.iter().map(|v| num(*v)).collect::<Vec<_>>(),
        "units": if units.is_physical() { "physical" } else { "dimensionless" },
        "local_fits": cal.fits.len(),
        "iterations": cal.iterations,
        "warnings": cal.warnings,
        "out": out.map(|p| p.display().to_string()),
    })
}

/// The human summary.
fn print_summary(
    cal: &Calibration,
    inputs: &[LogInput],
    units: &UnitSystem,
    phys: Option<&PhysicalWhisker>,
) {
    let rows: usize = cal.logs.iter().map(|l| l.rows).sum();
    let contact: usize = cal.logs.iter().map(|l| l.contact).sum();
    let left: usize = cal.logs.iter().map(|l| l.skipped).sum();
    let lu = match units.unit(Quantity::Length) {
        "1" => String::new(),
        u => format!(" {u}"),
    };
    println!(
        "calibrate: {} log(s), {rows} rows ({contact} contact rows fitted, {left} left out); \
         rms distance to the contours {:.3e}{lu}; relative noise level {:.2e}",
        cal.logs.len(),
        cal.rms_distance * units.scale(Quantity::Length),
        cal.noise_level
    );
    for p in &cal.parameters {
        let (v, sd) = in_units(p, cal.lambda, phys);
        let unit = match unit_of(p.param, phys.is_some()) {
            "1" => String::new(),
            u => format!(" {u}"),
        };
        match (v, sd) {
            (Some(v), Some(sd)) => println!("  {:<5} = {v:.10} ± {sd:.2e}{unit}", p.param.name()),
            _ => println!("  {:<5} = not identifiable from these logs", p.param.name()),
        }
    }
    for c in &cal.determined {
        println!("  determined: {}", c.describe());
    }
    let qs = units.scale(Quantity::LineLoad) * cal.lambda;
    for (l, i) in cal.logs.iter().zip(inputs) {
        println!(
            "  log {}: q = {:.6e} ± {:.1e}{}, alpha = {:.6}° ± {:.1e}°",
            i.arg,
            l.q * qs,
            l.q_stderr * qs,
            match units.unit(Quantity::LineLoad) {
                "1" => String::new(),
                u => format!(" {u}"),
            },
            l.alpha.to_degrees(),
            l.alpha_stderr.to_degrees()
        );
    }
    for w in &cal.warnings {
        println!("  warning: {w}");
    }
}
