//! `vibrissa reconstruct`: identification of the fluid load and contour reconstruction from
//! an observables log (thesis ch. 6), written as `reconstruction.csv` and its figures.
//!
//! The command reads as parse -> resolve -> compute -> write -> summary:
//! [`options`] (flags, whisker), [`compute`] (the library and its culprits),
//! [`recon_io`] (inputs, units, `reconstruction.csv`, `scene.ron`),
//! [`figures`], [`summary`] (text and JSON); [`stream`] is `--stream`.

pub mod compute;
pub mod figures;
pub mod options;
pub mod stream;
pub mod summary;

use std::path::{Path, PathBuf};

use contact_sim::Profile;
use profile_recon::{contour_error, Reconstruction};

pub use super::recon_io::{RECONSTRUCTION_HEADER, RECON_CSV};
pub use compute::{reconstruct_log, rows_of};
pub use figures::write_reconstruction_figures;
pub use options::{
    recon_model, ReconFlags, ReconOptions, DEFAULT_TOLERANCE_ACCURATE, DEFAULT_TOLERANCE_THESIS,
};
pub use summary::{
    max_of, phase_counts, recon_json, row_ranges, rows_without_points, summary_line,
};

use crate::atomic::OutputDir;
use crate::cli::ReconstructArgs;
use crate::commands::recon_io;
use crate::csvio::{read_table, Table};
use crate::error::CliError;
use crate::plot::FigureStyle;
use crate::printer::Printer;
use crate::resolve::{LoadedScene, ProfileArg, Resolved};
use crate::units::{Quantity, UnitSystem};
use summary::unit_suffix;

pub use vibrissa_io::recon_io::REQUIRED_COLUMNS;

/// What `reconstruct LOG` works on once its inputs are resolved.
struct Inputs<'a> {
    /// The log as given (a file, or a sweep folder).
    observables: &'a Path,
    out_dir: &'a Path,
    log_path: PathBuf,
    opts: ReconOptions,
    r: Resolved,
    units: UnitSystem,
    /// `--profile`: the true contour, for the error column.
    truth: Option<Profile>,
}

/// Runs `vibrissa reconstruct`, its figures written as `style` says.
pub fn run(args: &ReconstructArgs, style: FigureStyle) -> Result<(), CliError> {
    if args.stream {
        return stream::run_stream(args);
    }
    let mu = args
        .mu
        .as_deref()
        .map(vibrissa_io::recon_friction::MuRequest::parse)
        .transpose()?;
    let inputs = resolve(args)?;
    let mut table = read_table(&inputs.log_path, &REQUIRED_COLUMNS, 2)?;
    let pose = recon_io::PoseColumns::of(&table);
    let x0_given = recon_io::to_model_units(&mut table, &inputs.units)?;
    if let Some(mu) = mu {
        return run_frictional(args, &inputs, &table, &x0_given, mu, style);
    }
    let ans = vibrissa_io::recon_friction::reconstruct_default_log(
        &args.into(),
        &inputs.opts,
        &inputs.r,
        &table,
    )?;
    if let Some(ev) = &ans.biased {
        let line = table.line_of(ev.row).unwrap_or(ev.row + 2);
        eprintln!("{}", vibrissa_io::recon_friction::biased_warning(ev, line));
    }
    let rec = &ans.rec;
    let errors = inputs.truth.as_ref().map(|p| contour_error(&rec.points, p));
    let files = write(
        args,
        &inputs,
        rec,
        None,
        errors.as_deref(),
        (&x0_given, &pose),
        style,
    )?;
    if args.json {
        let (units, method) = (&inputs.units, inputs.opts.method);
        let max_error = errors.as_deref().map(max_of);
        let mut v = recon_json(rec, method, table.rows(), units, max_error, inputs.out_dir);
        default_friction_json(&mut v, &ans, &table);
        if let Some(o) =
            vibrissa_io::summary::ObstacleSummary::of(rec, inputs.truth.as_ref(), units)
        {
            v["obstacle"] = serde_json::to_value(o).unwrap_or_default();
        }
        let mut stdout = Printer::stdout().published(Some(inputs.out_dir));
        return stdout.line(v);
    }
    print_summary(args, &inputs, rec, &table, errors.as_deref(), files.len())?;
    let mut stdout = Printer::stdout().published(Some(inputs.out_dir));
    stdout.line(default_friction_line(&ans, &table))
}

/// The JSON's `mu` and `friction` of a reconstruction without `--mu`: `mu` identified (value,
/// standard error, rows, chi2_dof) or null, `friction` the evidence, or `{"identified":
/// false, "reason": ...}`.
fn default_friction_json(
    v: &mut serde_json::Value,
    ans: &vibrissa_io::recon_friction::DefaultAnswer,
    table: &Table,
) {
    use vibrissa_io::recon_friction as rf;
    match &ans.frictional {
        Ok(fr) => {
            let friction = rf::FrictionSummary::of(fr, table);
            v["mu"] = serde_json::to_value(friction.mu).unwrap_or_default();
            v["friction"] = serde_json::to_value(&friction).unwrap_or_default();
        }
        Err(reason) => {
            v["mu"] = serde_json::Value::Null;
            v["friction"] = serde_json::json!({ "identified": false, "reason": reason });
        }
    }
}

/// The summary's friction line of a reconstruction without `--mu`.
fn default_friction_line(
    ans: &vibrissa_io::recon_friction::DefaultAnswer,
    table: &Table,
) -> String {
    use vibrissa_io::recon_friction::FrictionSummary;
    let fr = match &ans.frictional {
        Ok(fr) => fr,
        Err(reason) => return format!("mu not identified: {reason}"),
    };
    let s = FrictionSummary::of(fr, table);
    let mu = match s.mu {
        Some(m) => format!(
            "mu = {:.6} +- {:.2e} (identified from {} sliding rows)",
            m.value, m.stderr, m.rows
        ),
        None => "mu not identified (no sliding row with a contact force)".to_string(),
    };
    if s.proves_friction {
        format!("{mu}; the log shows friction: the frictionless points are biased (--mu identify)")
    } else {
        format!("{mu}; no evidence of friction")
    }
}

/// Parse and resolve: the flags, the log and scene to read (a sweep folder gives both),
/// the whisker and the true contour.
fn resolve(args: &ReconstructArgs) -> Result<Inputs<'_>, CliError> {
    let (Some(observables), Some(out_dir)) = (&args.observables, &args.out) else {
        return Err(CliError::invalid_argument(
            "OBSERVABLES.csv",
            "",
            "the observables log and --out are needed (or --stream)",
        ));
    };
    let opts = ReconOptions::parse(&args.into())?;
    let (log_path, scene_path) = recon_io::resolve_input(observables, args.scene.as_deref())?;
    crate::atomic::refuse_over_inputs(out_dir, &[("log", &log_path)])?;
    let file = LoadedScene::load_opt(scene_path.as_deref())?;
    let r = recon_model(args, file)?;
    let units = r.units();
    let truth = match &args.profile {
        Some(spec) => Some(
            ProfileArg {
                spec: spec.clone(),
                file: None,
            }
            .parse(&units)?,
        ),
        None => None,
    };
    Ok(Inputs {
        observables,
        out_dir,
        log_path,
        opts,
        r,
        units,
        truth,
    })
}

/// Write: `reconstruction.csv` (with the column `ft` of a frictional reconstruction, where
/// `ft` is given), `scene.ron` and the figures into the output folder, all or nothing (the
/// figures as `style` says); returns the files written. `given`: the log's `x0` and pose
/// columns as given, copied into the file.
fn write(
    args: &ReconstructArgs,
    inputs: &Inputs<'_>,
    rec: &Reconstruction,
    ft: Option<&[f64]>,
    errors: Option<&[f64]>,
    given: (&[f64], &recon_io::PoseColumns),
    style: FigureStyle,
) -> Result<Vec<PathBuf>, CliError> {
    let (x0_given, pose) = given;
    let units = &inputs.units;
    let out = OutputDir::create(inputs.out_dir)?;
    let csv = out.path_for(RECON_CSV);
    match ft {
        Some(ft) => vibrissa_io::recon_friction::write_reconstruction_csv_ft(
            rec, ft, errors, units, x0_given, &csv,
        )?,
        None => recon_io::write_reconstruction_csv_posed(
            &rec.points,
            errors,
            units,
            x0_given,
            pose,
            &csv,
        )?,
    }
    recon_io::write_recon_scene(
        &inputs.r,
        rec.identification.q,
        args.profile.clone(),
        &inputs.log_path,
        &out.path_for(recon_io::SCENE_RON),
    )?;
    write_reconstruction_figures(
        &rec.points,
        inputs.truth.as_ref(),
        errors,
        &format!(
            "q = {:.6}{} {}",
            rec.identification.q * units.scale(Quantity::LineLoad),
            unit_suffix(units, Quantity::LineLoad),
            if rec.q_given { "given" } else { "identified" }
        ),
        units,
        |n| out.path_for(n),
        style,
    )?;
    Ok(out.commit()?)
}

/// Summary: the JSON object (`--json`) or the summary lines.
fn print_summary(
    args: &ReconstructArgs,
    inputs: &Inputs<'_>,
    rec: &Reconstruction,
    table: &Table,
    errors: Option<&[f64]>,
    files: usize,
) -> Result<(), CliError> {
    let (units, method, out_dir) = (&inputs.units, inputs.opts.method, inputs.out_dir);
    let max_error = errors.map(max_of);
    let mut stdout = Printer::stdout().published(Some(out_dir));
    let obstacle = vibrissa_io::summary::ObstacleSummary::of(rec, inputs.truth.as_ref(), units);
    if args.json {
        let mut v = recon_json(rec, method, table.rows(), units, max_error, out_dir);
        if let Some(o) = obstacle {
            v["obstacle"] = serde_json::to_value(o).unwrap_or_default();
        }
        return stdout.line(v);
    }
    let title = inputs
        .observables
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "observables".to_string());
    stdout.line(format_args!(
        "reconstruct {}: {}",
        title,
        summary_line(rec, method, table.rows(), units)
    ))?;
    if let Some(e) = max_error {
        stdout.line(format_args!(
            "max contour error e = {:.3e}{} (eq. 6.11)",
            e * units.scale(Quantity::Length),
            unit_suffix(units, Quantity::Length)
        ))?;
    }
    if let Some(o) = obstacle {
        stdout.line(obstacle_line(&o, &unit_suffix(units, Quantity::Length)))?;
    }
    stdout.line(format_args!(
        "wrote {} files to {}",
        files,
        out_dir.display()
    ))
}

/// The obstacle from the points, one line: a peg's position or a disc's centre and radius with
/// their standard errors.
fn obstacle_line(o: &vibrissa_io::summary::ObstacleSummary, unit: &str) -> String {
    use vibrissa_io::summary::ObstacleSummary;
    match *o {
        ObstacleSummary::Peg {
            x,
            y,
            stderr_x,
            stderr_y,
            rows,
            ..
        } => format!(
            "peg at ({x:.9}, {y:.9}){unit} +- ({stderr_x:.2e}, {stderr_y:.2e}) from {rows} contact rows"
        ),
        ObstacleSummary::Disc {
            x,
            y,
            r,
            stderr,
            rows,
            ..
        } => format!(
            "disc centre ({x:.9}, {y:.9}) radius {r:.9}{unit} +- ({:.2e}, {:.2e}, {:.2e}) from {rows} contact rows",
            stderr[0], stderr[1], stderr[2]
        ),
    }
}

/// `reconstruct --mu`: the frictional reconstruction ([`vibrissa_io::recon_friction`]), the
/// column `ft`, a warning on stderr when `--mu 0` meets a log that shows friction, and the
/// JSON's `mu`.
fn run_frictional(
    args: &ReconstructArgs,
    inputs: &Inputs<'_>,
    table: &Table,
    x0_given: &[f64],
    mu: vibrissa_io::recon_friction::MuRequest,
    style: FigureStyle,
) -> Result<(), CliError> {
    use vibrissa_io::recon_friction as rf;
    let ans = rf::reconstruct_frictional_log(&args.into(), &inputs.opts, &inputs.r, table, mu)?;
    if let Some(ev) = &ans.biased {
        let line = table.line_of(ev.row).unwrap_or(ev.row + 2);
        eprintln!("{}", rf::biased_warning(ev, line));
    }
    if ans.frictional.violations > 0 {
        eprintln!(
            "warning: {} rows break the given mu (their |ft| / fn beyond the cone, or sliding rows off its edge)",
            ans.frictional.violations
        );
    }
    let rec = &ans.rec;
    let errors = inputs.truth.as_ref().map(|p| contour_error(&rec.points, p));
    let files = write(
        args,
        inputs,
        rec,
        Some(&ans.ft),
        errors.as_deref(),
        // the frictional reconstruction is not framed by a pose (docs/whisking-recon.md)
        (x0_given, &recon_io::PoseColumns::default()),
        style,
    )?;
    let friction = rf::FrictionSummary::of(&ans.frictional, table);
    if args.json {
        let (units, method) = (&inputs.units, inputs.opts.method);
        let max_error = errors.as_deref().map(max_of);
        let mut v = recon_json(rec, method, table.rows(), units, max_error, inputs.out_dir);
        v["mu"] = serde_json::to_value(friction.mu).unwrap_or_default();
        v["friction"] = serde_json::to_value(&friction).unwrap_or_default();
        let mut stdout = Printer::stdout().published(Some(inputs.out_dir));
        return stdout.line(v);
    }
    print_summary(args, inputs, rec, table, errors.as_deref(), files.len())?;
    let mut stdout = Printer::stdout().published(Some(inputs.out_dir));
    stdout.line(match friction.mu {
        Some(m) if m.given => format!(
            "mu = {} (given), {} sliding rows",
            m.value, friction.sliding_rows
        ),
        Some(m) => format!(
            "mu = {:.6} +- {:.2e} (identified from {} sliding rows)",
            m.value, m.stderr, m.rows
        ),
        None => "mu not identified (no sliding row with a contact force)".to_string(),
    })
}
