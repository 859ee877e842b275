//! `vibrissa calibrate`: the whisker's own parameters (theta, a, b, k and, in physical units,
//! E I) fitted to logs of sweeps past objects of known contour (profile-recon's
//! [`calibrate`](profile_recon::calibrate)); writes the calibrated `scene.ron`, the residual
//! of every row and the figures.

use std::path::{Path, PathBuf};

use profile_recon::calibrate::{calibrate, CalibLog, CalibParam, CalibSettings, Calibration};
use profile_recon::{KnownFlow, ReconError};

pub use crate::commands::calibrate_inputs::LogInput;
pub use crate::commands::calibrate_summary::json_of;

use crate::atomic::OutputDir;
use crate::cli::CalibrateArgs;
use crate::commands::calibrate_inputs::{calib_model, parse_fit, read_log, split_log_arg};
use crate::commands::calibrate_out::{self, RESIDUALS_CSV};
use crate::commands::calibrate_summary::print_summary;
use crate::commands::recon_io;
use crate::commands::reconstruct::rows_of;
use crate::error::CliError;
use crate::resolve::{parse_count, Resolved};

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
    let r = calib_model(args, scene_path.as_deref())?;
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
