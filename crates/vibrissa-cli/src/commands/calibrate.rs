//! `vibrissa calibrate`: the whisker's own parameters (theta, a, b, k and, in physical units,
//! E I) fitted to logs of sweeps past objects of known contour (profile-recon's
//! [`calibrate`](profile_recon::calibrate)); writes the calibrated `scene.ron`, the residual
//! of every row and the figures.

use std::path::{Path, PathBuf};

use std::io::IsTerminal;
use std::time::Duration;

use profile_recon::calibrate::{CalibLog, Calibration, Progress, ProgressFn, Stage};
use vibrissa_io::calibration::{fit_logs, CalibFlags};

pub use crate::commands::calibrate_summary::json_of;
pub use vibrissa_io::calibration::LogInput;

use crate::atomic::OutputDir;
use crate::cli::{text, CalibrateArgs};
use crate::commands::calibrate_inputs::{calib_model, parse_fit, read_log, split_log_arg};
use crate::commands::calibrate_out::{self, RESIDUALS_CSV};
use crate::commands::calibrate_summary::print_summary;
use crate::commands::recon_io;
use crate::error::CliError;
use crate::plot::FigureStyle;
use crate::resolve::Resolved;

/// Runs `vibrissa calibrate`, its figures written as `style` says.
pub fn run(args: &CalibrateArgs, style: FigureStyle) -> Result<(), CliError> {
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
    check_flow_angle(args, &r)?;
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
        calibrate_out::write_figures(&cal, &inputs, &logs, &start, &units, style, |n| {
            out.path_for(n)
        })?;
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

/// Refuses a flow angle outside (-90°, 90°) (spec/cli.md), in degrees and naming where it
/// was given (`--alpha-deg` or the scene's `loads.alpha_deg`).
fn check_flow_angle(args: &CalibrateArgs, r: &Resolved) -> Result<(), CliError> {
    let deg = r.scene.loads.fluid.alpha.to_degrees();
    if deg.abs() < 90.0 {
        return Ok(());
    }
    let reason = "the flow angle must lie in (-90, 90) degrees: a flow along or against the \
                  whisker's base direction has no component across it";
    match &args.fluid.alpha_deg {
        Some(raw) => Err(CliError::invalid_argument("--alpha-deg", raw, reason)),
        None => Err(CliError::Io(vibrissa_io::IoError::Usage {
            reason: format!("the scene's loads.alpha_deg = {deg}: {reason}"),
        })),
    }
}

impl From<&CalibrateArgs> for CalibFlags {
    fn from(args: &CalibrateArgs) -> Self {
        CalibFlags {
            whisker: (&args.whisker).into(),
            fluid: (&args.fluid).into(),
            fit: args.fit.clone(),
            starts: text(&args.starts),
        }
    }
}

/// Fits the whisker of `r` (start values, units) to the logs `inputs` as `args` asks
/// (`--fit`, `--starts`, `--q` with `--alpha-deg`; `vibrissa_io::calibration::fit_logs`)
/// with a progress bar on a terminal: the calibration and the library's logs.
pub fn fit_inputs(
    inputs: &[LogInput],
    r: &Resolved,
    args: &CalibrateArgs,
) -> Result<(Calibration, Vec<CalibLog>), CliError> {
    let rows: usize = inputs.iter().map(|l| l.table.rows()).sum();
    Ok(with_progress(rows, |progress| {
        fit_logs(inputs, r, &args.into(), progress)
    })?)
}

/// Logs of at least this many rows in all show a progress bar (on a terminal).
pub const PROGRESS_ROWS: usize = 1000;

/// Runs `f` with a progress bar on stderr, driven by the library's [`Progress`] reports,
/// when stderr is a terminal and the logs have at least [`PROGRESS_ROWS`] rows.
fn with_progress<T>(rows: usize, f: impl FnOnce(ProgressFn<'_>) -> T) -> T {
    let bar = (rows >= PROGRESS_ROWS && std::io::stderr().is_terminal()).then(|| {
        let pb = indicatif::ProgressBar::new(1);
        pb.set_style(
            indicatif::ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} ({elapsed})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        pb.enable_steady_tick(Duration::from_millis(200));
        pb
    });
    let report = |p: &Progress| {
        let Some(pb) = &bar else { return };
        let what = match p.stage {
            Stage::Screen => "screening candidate starts",
            Stage::Search => "local fits",
            Stage::AllRows => "extending the fit to every row",
            Stage::Polish => "polishing",
        };
        let cost = if p.cost.is_finite() {
            format!(", cost {:.3e}", p.cost)
        } else {
            String::new()
        };
        pb.set_message(format!(
            "calibrating {rows} rows: {what} ({} in use{cost})",
            p.rows
        ));
        pb.set_length(p.total.max(1) as u64);
        pb.set_position(p.done as u64);
    };
    let out = f(&report);
    if let Some(pb) = bar {
        pb.finish_and_clear();
    }
    out
}
