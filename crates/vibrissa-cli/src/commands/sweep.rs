//! `vibrissa sweep`: the whisker swept past an obstacle under the fluid load; the
//! observables log `observables.csv` and its figures.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

use contact_sim::{
    sweep_with_progress, ContactLaw, Profile, SweepProgress, SweepResult, SweepSettings,
};

use crate::atomic::{write_atomic, OutputDir};
use crate::cli::SweepArgs;
use crate::commands::observables::{
    observables_csv_in, OBSERVABLES_HEADER, OBSERVABLES_QUANTITIES,
};
use crate::commands::outputs::{output_scene, scene_unit_notes, write_scene_ron, write_units_of};
use crate::commands::shapes::{write_shapes_csv, write_shapes_svg};
use crate::commands::sweep_events::{friction_note, sweep_summary, RowCounts};
use crate::commands::sweep_figures::{write_sweep_figures, FigureContext};
use crate::error::CliError;
use crate::plot::FigureStyle;
use crate::printer::Printer;
use crate::resolve::{profile_arg, resolve_model, LoadedScene, ProfileArg, Resolved};
use crate::units::{Quantity, UnitSystem};
use vibrissa_io::resolve::motion::{sweep_motion, MotionGiven, ResolvedMotion};
use vibrissa_io::summary::SweepSummary;

pub use vibrissa_io::resolve::sweep::{
    check_sweep_loads, missing_profile, sweep_contact_law, sweep_points, sweep_settings,
    sweep_settings_with, sweep_tol, DEFAULT_POINTS,
};

/// Runs `vibrissa sweep`, its figures written as `style` says.
pub fn run(args: &SweepArgs, style: FigureStyle) -> Result<(), CliError> {
    let file = LoadedScene::load_opt(args.scene.as_deref())?;
    let profile =
        profile_arg(&args.profile, file.as_ref()).ok_or_else(|| missing_profile(file.as_ref()))?;
    let points = sweep_points(crate::cli::text(&args.points).as_ref(), file.as_ref())?;
    let tol = sweep_tol(crate::cli::text(&args.tol).as_ref(), file.as_ref())?;
    let law = sweep_contact_law(crate::cli::text(&args.mu).as_ref(), file.as_ref())?;
    let flags = crate::resolve::ModelFlags {
        whisker: (&args.whisker).into(),
        fluid: (&args.fluid).into(),
        ..Default::default()
    };
    let r = resolve_model(&flags, file)?;
    check_sweep_loads(&r)?;
    let units = r.units();
    let contour = profile.parse(&units)?;
    let motion = sweep_motion(&motion_given(args), r.file.as_ref(), &units)?;
    let mut inputs: Vec<(&str, PathBuf)> = Vec::new();
    if let Some(scene) = &args.scene {
        inputs.push(("scene file", scene.clone()));
    }
    if let Some(points) = profile.points_path() {
        inputs.push(("contour table", points));
    }
    if let Some(path) = &motion.path_file {
        inputs.push(("path table", path.clone()));
    }
    let inputs: Vec<(&str, &std::path::Path)> =
        inputs.iter().map(|(w, p)| (*w, p.as_path())).collect();
    crate::atomic::refuse_over_inputs(&args.out, &inputs)?;
    // The output folder (its lock, staging folder and marker) and the units sidecar of
    // `observables.csv` need nothing of the sweep: made before it, their flushes to disk
    // run while it solves instead of after it (a failed sweep removes the staging folder,
    // the lock and the parent folders made for --out).
    let out = OutputDir::create(&args.out)?;
    write_sweep_units(&r, &out)?;
    let settings = SweepSettings {
        motion: motion.motion.clone(),
        ..sweep_settings_with(points, tol, law)
    };
    let res = run_sweep_with(&r, &contour, &profile, &settings)?;
    write_sweep_outputs(&r, &contour, &res, &profile, (points, law), &out, style)?;
    write_motion(&out, &motion)?;
    if res.points.iter().any(|p| p.k.is_some()) {
        // a path that sets the follicle stiffness: the log has the column `k`
        vibrissa_io::observables::write_observables_units(
            &out.path_for("observables.csv"),
            &units,
            true,
        )?;
    }
    if args.shapes {
        write_shapes_csv(&r, &res, &out.path_for("shapes.csv"))?;
    }
    let files = out.commit()?;
    let mut stdout = Printer::stdout().published(Some(args.out.as_path()));
    if args.json {
        let mut v = serde_json::to_value(
            SweepSummary::of(&res, points, law, &units).with_motion(&motion.motion),
        )
        .unwrap_or_default();
        v["profile"] = serde_json::Value::String(profile.spec.clone());
        v["out"] = serde_json::Value::String(args.out.display().to_string());
        v["files"] = serde_json::Value::from(files.len());
        stdout.line(v)
    } else {
        // The summary line comes last (spec/cli.md: stdout ends with it).
        stdout.line(format_args!(
            "wrote {} files to {}",
            files.len(),
            args.out.display()
        ))?;
        stdout.line(format_args!(
            "sweep {}: {}{}{}",
            profile.spec,
            sweep_summary(&res, points, &units),
            friction_note(&res, law.mu()),
            accuracy_note(&res)
        ))
    }
}

/// The motion flags as typed (`--motion`, `--x0`, `--y0`, `--gamma-deg`).
fn motion_given(args: &SweepArgs) -> MotionGiven {
    MotionGiven {
        motion: crate::cli::text(&args.motion),
        x0: crate::cli::text(&args.x0),
        y0: crate::cli::text(&args.y0),
        gamma_deg: crate::cli::text(&args.gamma_deg),
        path: None,
    }
}

/// Records the base motion in the folder's `scene.ron` (rewritten with the keys `motion`,
/// `x0`, `y0`, `gamma_deg`, `path`; a path table read from a file is copied beside it as
/// `path.csv`), so that the folder sweeps and reconstructs again as it was made. Nothing is
/// changed for a translation.
fn write_motion(out: &OutputDir, motion: &ResolvedMotion) -> Result<(), CliError> {
    if motion.motion == contact_sim::BaseMotion::Translate {
        return Ok(());
    }
    let path = out.path_for("scene.ron");
    let text = std::fs::read_to_string(&path).map_err(|e| CliError::io(&path, e))?;
    let notes: Vec<String> = text
        .lines()
        .take_while(|l| l.starts_with("// "))
        .map(|l| l[3..].to_string())
        .collect();
    let mut scene = vibrissa_io::scene_file::SceneFile::parse(&text, &path)?;
    scene.motion = Some(motion.label.to_string());
    if let Some((x0, y0, g0)) = motion.start {
        (scene.x0, scene.y0, scene.gamma_deg) = (Some(x0), Some(y0), Some(g0));
    }
    if let Some(file) = &motion.path_file {
        let bytes = std::fs::read(file).map_err(|e| CliError::io(file, e))?;
        write_atomic(&out.path_for("path.csv"), &bytes)?;
        scene.path = Some("path.csv".to_string());
    } else if let Some(inline) = &motion.path_inline {
        scene.path = Some(inline.clone());
    }
    Ok(write_scene_ron(&path, &scene, &notes)?)
}

/// `; worst row estimate E (row r) for --tol T` after the summary of a sweep run with an
/// accuracy asked for; nothing otherwise.
pub fn accuracy_note(res: &SweepResult) -> String {
    let Some(acc) = &res.accuracy else {
        return String::new();
    };
    match acc.worst() {
        Some((row, e)) => format!(
            "; worst row error estimate {e:.2e} (row {}) for --tol {:e}",
            row + 1,
            acc.tol
        ),
        None => String::new(),
    }
}

/// The JSON summary of a sweep (`sweep --json`) under the contact law `law`: the library's
/// [`SweepSummary`] serialised (rows numbered from 1 as in [`RowCounts`], positions and
/// loads in `units`).
pub fn sweep_json(
    res: &SweepResult,
    requested: usize,
    law: ContactLaw,
    units: &UnitSystem,
) -> serde_json::Value {
    serde_json::to_value(SweepSummary::of(res, requested, law, units)).unwrap_or_default()
}

/// Runs the sweep of `points` contact rows (the sweep's own accuracy) with a spinner on
/// stderr when it is a terminal.
pub fn run_sweep(
    r: &Resolved,
    contour: &Profile,
    profile: &ProfileArg,
    points: usize,
) -> Result<SweepResult, CliError> {
    run_sweep_with(r, contour, profile, &sweep_settings(points, None))
}

/// Runs the sweep with `settings` with a spinner on stderr when it is a terminal.
pub fn run_sweep_with(
    r: &Resolved,
    contour: &Profile,
    profile: &ProfileArg,
    settings: &SweepSettings,
) -> Result<SweepResult, CliError> {
    // Progress on stderr only when it is a terminal: the coarse pass that looks for the
    // separation counts its contour steps, then a bar counts the requested contact points.
    let bar = std::io::stderr().is_terminal().then(|| {
        let pb = indicatif::ProgressBar::new_spinner();
        pb.set_style(
            indicatif::ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
        );
        pb.set_message(format!(
            "sweeping past {}: coarse pass, finding the separation: 0 steps",
            profile.spec
        ));
        pb.enable_steady_tick(Duration::from_millis(120));
        pb
    });
    let mut fine_started = false;
    let res = sweep_with_progress(
        &r.scene.whisker,
        r.scene.loads.fluid,
        contour,
        settings,
        &mut |p| {
            let Some(pb) = &bar else { return };
            match p {
                SweepProgress::Coarse { steps } => pb.set_message(format!(
                    "sweeping past {}: coarse pass, finding the separation: {steps} steps",
                    profile.spec
                )),
                SweepProgress::Fine { done, total } => {
                    if !fine_started {
                        fine_started = true;
                        pb.set_length(total as u64);
                        pb.set_style(
                            indicatif::ProgressStyle::with_template(
                                "{msg} [{bar:40}] {pos}/{len} contact points ({elapsed})",
                            )
                            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                        );
                        pb.set_message(format!("sweeping past {}", profile.spec));
                    }
                    pb.set_position(done as u64);
                }
            }
        },
    );
    if let Some(pb) = bar {
        pb.finish_and_clear();
    }
    res.map_err(|e| r.contact_culprit(e, profile).into())
}

/// Writes the units sidecar of a sweep's `observables.csv`, `observables.units.csv`, into
/// `out` (it depends on the scene's units only: written before the sweep).
pub fn write_sweep_units(r: &Resolved, out: &OutputDir) -> Result<(), CliError> {
    Ok(write_units_of(
        &out.path_for("observables.csv"),
        &OBSERVABLES_HEADER,
        &OBSERVABLES_QUANTITIES,
        &r.units(),
    )?)
}

/// Writes a sweep's folder into `out` (its units sidecar aside, [`write_sweep_units`]):
/// `observables.csv` (in the scene's units), `scene.ron` (every parameter, units included, the
/// true point count and the friction coefficient of `run = (points, law)`; a points profile
/// is copied beside it as `profile.csv`), and the figures `observables`, `contact` and
/// `shapes` (as `style` says: `--figures`, `--size`).
pub fn write_sweep_outputs(
    r: &Resolved,
    contour: &Profile,
    res: &SweepResult,
    profile: &ProfileArg,
    run: (usize, ContactLaw),
    out: &OutputDir,
    style: FigureStyle,
) -> Result<(), CliError> {
    if !style.draws() {
        // no figure to draw: neither the shapes solved for them nor their threads
        return write_sweep_data(r, res, profile, run, out);
    }
    let ctx = FigureContext {
        units: r.units(),
        scene: scene_title(r, &profile.spec),
        rigid: r.scene.whisker.support.stiffness().is_infinite(),
        style,
    };
    // The shapes (eight whiskers solved, then drawn: the longest of the figures) on a
    // thread of their own from the start; the data files, then the other two figures (on
    // two threads) meanwhile.
    crate::plot::both(
        || write_shapes_svg(r, contour, res, &ctx, &out.path_for("shapes.svg")),
        || {
            write_sweep_data(r, res, profile, run, out)?;
            write_sweep_figures(res, &ctx, |n| out.path_for(n)).map(|_| ())
        },
    )
}

/// Writes a sweep's data files into `out`: `observables.csv` (its units sidecar aside),
/// `scene.ron` and, for a points profile, `profile.csv`.
fn write_sweep_data(
    r: &Resolved,
    res: &SweepResult,
    profile: &ProfileArg,
    (points, law): (usize, ContactLaw),
    out: &OutputDir,
) -> Result<(), CliError> {
    let units = r.units();
    observables_csv_in(&res.points, &units)?.write(&out.path_for("observables.csv"))?;
    let spec = match profile.points_path() {
        Some(path) => {
            let bytes = std::fs::read(&path).map_err(|e| CliError::io(&path, e))?;
            write_atomic(&out.path_for("profile.csv"), &bytes)?;
            "points:profile.csv".to_string()
        }
        None => profile.spec.trim().to_string(),
    };
    let n = RowCounts::of(res, points);
    let mut notes = vec![
        format!(
            "Written by vibrissa {} (`sweep`): the scene that produced the files beside it.",
            env!("CARGO_PKG_VERSION")
        ),
        "Reconstruct them with `vibrissa reconstruct DIR` (this folder).".to_string(),
    ];
    notes.extend(scene_unit_notes(&units));
    notes.push(format!(
        "observables.csv: x0, s1, xc, yc, y0 in {l}; Ax, Ay, f, ft in {f}; MA in {m}; phi0, \
         psi, gamma in rad (observables.units.csv; 1 = dimensionless).",
        l = units.unit(Quantity::Length),
        f = units.unit(Quantity::Force),
        m = units.unit(Quantity::Moment)
    ));
    notes.push(format!(
        "Rows: {} = {} before contact + {} in contact ({} requested points + {} at events).",
        n.rows, n.pre_contact, n.contact, n.requested, n.event_rows
    ));
    let mut scene = output_scene(r, Some(spec), Some(points));
    scene.mu = law.mu();
    if let (Some(s), Some(acc)) = (scene.sweep.as_mut(), &res.accuracy) {
        s.tol = Some(acc.tol);
    }
    Ok(write_scene_ron(&out.path_for("scene.ron"), &scene, &notes)?)
}

/// Names a sweep's scene in figure notes: `contour g1, q = 5, theta = 0.75, k = 20`.
pub fn scene_title(r: &Resolved, profile: &str) -> String {
    let g = &r.given;
    let u = r.units();
    let q_unit = match u.unit(Quantity::LineLoad) {
        "1" => String::new(),
        x => format!(" {x}"),
    };
    let mut s = format!("contour {profile}, q = {}{q_unit}", g.q.value);
    if g.alpha_deg.value != 0.0 {
        s += &format!(" at {}°", g.alpha_deg.value);
    }
    s += &format!(", θ = {}", g.theta.value);
    if g.k.value.is_finite() {
        let k_unit = if u.is_physical() { " N m/rad" } else { "" };
        s += &format!(", k = {}{k_unit}", g.k.value);
    } else {
        s += ", rigid support";
    }
    s
}
