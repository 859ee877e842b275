//! `vibrissa sweep`: the whisker swept past an obstacle under the fluid load; the
//! observables log `observables.csv` and its figures.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

use contact_sim::{sweep_with_progress, Profile, SweepProgress, SweepResult, SweepSettings};

use crate::atomic::{write_atomic, OutputDir};
use crate::cli::SweepArgs;
use crate::commands::json::{json_number, json_opt};
use crate::commands::observables::{
    observables_csv_in, OBSERVABLES_HEADER, OBSERVABLES_QUANTITIES,
};
use crate::commands::outputs::{output_scene, scene_unit_notes, write_scene_ron, write_units_of};
use crate::commands::shapes::{write_shapes_csv, write_shapes_svg};
use crate::commands::sweep_events::{sweep_events, sweep_summary, RowCounts};
use crate::commands::sweep_figures::{write_sweep_figures, FigureContext};
use crate::error::CliError;
use crate::printer::Printer;
use crate::resolve::{
    parse_count, parse_number, profile_arg, resolve_model, LoadedScene, ProfileArg, Resolved,
};
use crate::units::{Quantity, UnitSystem};

/// Default number of contact points.
pub const DEFAULT_POINTS: usize = 200;

/// Runs `vibrissa sweep`.
pub fn run(args: &SweepArgs) -> Result<(), CliError> {
    let file = LoadedScene::load_opt(args.scene.as_deref())?;
    let profile =
        profile_arg(&args.profile, file.as_ref()).ok_or_else(|| missing_profile(file.as_ref()))?;
    let points = sweep_points(args.points.as_deref(), file.as_ref())?;
    let tol = sweep_tol(args.tol.as_deref(), file.as_ref())?;
    let flags = crate::resolve::ModelFlags {
        whisker: (&args.whisker).into(),
        fluid: (&args.fluid).into(),
        ..Default::default()
    };
    let r = resolve_model(&flags, file)?;
    check_sweep_loads(&r)?;
    let units = r.units();
    let contour = profile.parse(&units)?;
    let mut inputs: Vec<(&str, PathBuf)> = Vec::new();
    if let Some(scene) = &args.scene {
        inputs.push(("scene file", scene.clone()));
    }
    if let Some(points) = profile.points_path() {
        inputs.push(("contour table", points));
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
    let res = run_sweep_with(&r, &contour, &profile, &sweep_settings(points, tol))?;
    write_sweep_outputs(&r, &contour, &res, &profile, points, &out)?;
    if args.shapes {
        write_shapes_csv(&r, &res, &out.path_for("shapes.csv"))?;
    }
    let files = out.commit()?;
    let mut stdout = Printer::stdout().published(Some(args.out.as_path()));
    if args.json {
        let mut v = sweep_json(&res, points, &units);
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
            "sweep {}: {}{}",
            profile.spec,
            sweep_summary(&res, points, &units),
            accuracy_note(&res)
        ))
    }
}

/// The accuracy asked for of a sweep's rows: `--tol` (typed as `raw`), else the scene
/// file's `sweep.tol`, else none; in [1e-12, 1e-2].
pub fn sweep_tol(raw: Option<&str>, file: Option<&LoadedScene>) -> Result<Option<f64>, CliError> {
    const RANGE: &str = "the accuracy asked for must be in [1e-12, 1e-2]";
    let ok = |t: f64| {
        (contact_sim::accuracy::ACCURACY_MIN..=contact_sim::accuracy::ACCURACY_MAX).contains(&t)
    };
    match (raw, file) {
        (Some(raw), _) => {
            let t = parse_number("--tol", raw)?;
            if !ok(t) {
                return Err(CliError::invalid_argument("--tol", raw, RANGE));
            }
            Ok(Some(t))
        }
        (None, Some(f)) => match f.file.sweep.as_ref().and_then(|s| s.tol) {
            Some(t) if !ok(t) => Err(f.error_at("sweep.tol", format!("{RANGE}, got {t}")).into()),
            t => Ok(t),
        },
        (None, None) => Ok(None),
    }
}

/// The library's settings of a sweep of `points` contact rows at the accuracy `tol` (none:
/// the sweep's own).
pub fn sweep_settings(points: usize, tol: Option<f64>) -> SweepSettings {
    SweepSettings {
        points,
        accuracy: tol,
        ..SweepSettings::default()
    }
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

/// The error of a sweep without an obstacle (`file`: the scene file given, if any).
pub fn missing_profile(file: Option<&LoadedScene>) -> CliError {
    const KINDS: &str = "g1, g2, ge, parabola:a,xv,yv, cosh:a,c,xv,d, circle:xc,yc,r or \
                         points:FILE.csv";
    match file {
        Some(f) => f
            .error_at(
                "profile",
                format!("the scene has no obstacle: add `profile: Some(\"g1\")` (or {KINDS}) or give --profile"),
            )
            .into(),
        None => CliError::Usage {
            reason: format!("a sweep needs an obstacle: give --profile P ({KINDS})"),
        },
    }
}

/// The number of contact rows: `--points` (typed as `raw`), else the scene file's
/// `sweep.points`, else [`DEFAULT_POINTS`]; at least 2 and at most
/// [`contact_sim::sweep::MAX_POINTS`].
pub fn sweep_points(raw: Option<&str>, file: Option<&LoadedScene>) -> Result<usize, CliError> {
    let points = match (raw, file.and_then(|f| f.file.sweep.as_ref())) {
        (Some(raw), _) => {
            let n = parse_count("--points", raw, 2)?;
            if n > contact_sim::sweep::MAX_POINTS {
                return Err(CliError::invalid_argument(
                    "--points",
                    raw,
                    "at most 100000 contact rows",
                ));
            }
            n
        }
        (None, Some(s)) => s.points,
        (None, None) => DEFAULT_POINTS,
    };
    if points > crate::resolve::MAX_COUNT {
        return Err(CliError::invalid_argument(
            "sweep.points",
            points.to_string(),
            format!(
                "must be at most {} (the memory and time of one run are bounded)",
                crate::resolve::MAX_COUNT
            ),
        ));
    }
    Ok(points)
}

/// The JSON summary of a sweep (`sweep --json`): `first_contact`, `separation`, `phases`,
/// `rows` and the row counts and positions of the events, rows numbered from 1 as in
/// [`RowCounts`], positions and loads in `units`.
pub fn sweep_json(res: &SweepResult, requested: usize, units: &UnitSystem) -> serde_json::Value {
    let n = RowCounts::of(res, requested);
    let l = units.scale(Quantity::Length);
    let x0_of = |row: Option<usize>| json_opt(row.map(|r| res.points[r - 1].x0 * l));
    let events: Vec<serde_json::Value> = sweep_events(res)
        .into_iter()
        .map(|e| {
            serde_json::json!({
                "event": e.label,
                "row": e.index + 1,
                "x0": json_number(res.points[e.index].x0 * l),
            })
        })
        .collect();
    let mut v = serde_json::json!({
        "first_contact": res.first_contact.label(),
        "first_contact_row": n.first_contact_row,
        "first_contact_x0": x0_of(n.first_contact_row),
        "separation": res.separation.to_string(),
        "separation_row": n.separation_row,
        "separation_x0": x0_of(n.separation_row),
        "phases": res.phase_pattern(),
        "rows": n.rows,
        "pre_contact_rows": n.pre_contact,
        "contact_rows": n.contact,
        "points_requested": n.requested,
        "event_rows": n.event_rows,
        "events": events,
        "q": json_number(res.q * units.scale(Quantity::LineLoad)),
        "alpha_deg": json_number(res.alpha.to_degrees()),
        "units": if units.is_physical() { "physical" } else { "dimensionless" },
        "length_unit": units.unit(Quantity::Length),
        "force_unit": units.unit(Quantity::Force),
        "moment_unit": units.unit(Quantity::Moment),
    });
    if let Some(acc) = &res.accuracy {
        v["tol"] = json_number(acc.tol);
        // the contact rows are always the elastica's (no linear rung): spec/cli.md's
        // `model_used` of the accuracy asked for
        v["model_used"] = serde_json::Value::from(beam_model::ModelKind::Elastica.name());
        if let Some((row, e)) = acc.worst() {
            v["max_estimate"] = json_number(e);
            v["max_estimate_row"] = serde_json::Value::from(row + 1);
        }
    }
    v
}

/// The sweep computes the contact force itself: refuses a tip force, and a flow angle outside
/// (-90, 90) degrees (the flow must push the whisker towards the obstacle's side, +x).
pub fn check_sweep_loads(r: &Resolved) -> Result<(), CliError> {
    use crate::resolve::Origin;
    // The sweep's phase solves are adaptive shooting with exact sensitivities (tolerance
    // 1e-12); a fixed-grid method or grid size would be silently ignored, so it is refused.
    if !matches!(r.method, beam_model::Method::Accurate { .. }) {
        return Err(CliError::invalid_argument(
            "--method",
            r.method.name().to_string(),
            "the sweep always solves its contact phases with `accurate` shooting; leave --method at accurate",
        ));
    }
    if let Some(n) = &r.given.n {
        if let crate::resolve::Origin::Flag { flag, raw } = &n.origin {
            return Err(CliError::invalid_argument(
                *flag,
                raw.clone(),
                "the sweep uses adaptive shooting and has no grid: --n does not apply",
            ));
        }
    }
    let alpha = r.given.alpha_deg.value;
    let checks = [
        (
            &r.given.f,
            "loads.f",
            r.given.f.value != 0.0,
            "a sweep computes the contact force itself; leave the tip force at 0",
        ),
        (
            &r.given.alpha_deg,
            "loads.alpha_deg",
            !(alpha > -90.0 && alpha < 90.0),
            "the sweep's flow angle must lie in (-90, 90) degrees (a flow towards +x)",
        ),
    ];
    for (p, field, bad, what) in checks {
        if bad {
            return Err(match (&p.origin, &r.file) {
                (Origin::Flag { flag, raw }, _) => {
                    CliError::invalid_argument(*flag, raw.clone(), what)
                }
                (_, Some(file)) => file
                    .error_at(field, format!("{what}, got {}", p.value))
                    .into(),
                _ => CliError::invalid_argument(field, p.value.to_string(), what),
            });
        }
    }
    Ok(())
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
    write_units_of(
        &out.path_for("observables.csv"),
        &OBSERVABLES_HEADER,
        &OBSERVABLES_QUANTITIES,
        &r.units(),
    )
}

/// Writes a sweep's folder into `out` (its units sidecar aside, [`write_sweep_units`]):
/// `observables.csv` (in the scene's units), `scene.ron` (every parameter, units included, the
/// true point count; a points profile is copied beside it as `profile.csv`), and the figures
/// `observables`, `contact` and `shapes` (as `--figures` says).
pub fn write_sweep_outputs(
    r: &Resolved,
    contour: &Profile,
    res: &SweepResult,
    profile: &ProfileArg,
    points: usize,
    out: &OutputDir,
) -> Result<(), CliError> {
    if crate::plot::figure_formats() == crate::plot::FigureFormats::None {
        // no figure to draw: neither the shapes solved for them nor their threads
        return write_sweep_data(r, res, profile, points, out);
    }
    let ctx = FigureContext {
        units: r.units(),
        scene: scene_title(r, &profile.spec),
        rigid: r.scene.whisker.support.stiffness().is_infinite(),
    };
    // The shapes (eight whiskers solved, then drawn: the longest of the figures) on a
    // thread of their own from the start; the data files, then the other two figures (on
    // two threads) meanwhile.
    crate::plot::both(
        || write_shapes_svg(r, contour, res, &ctx, &out.path_for("shapes.svg")),
        || {
            write_sweep_data(r, res, profile, points, out)?;
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
    points: usize,
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
        "observables.csv: x0, s1, xc, yc in {l}; Ax, Ay, f in {f}; MA in {m}; phi0, psi in rad \
         (observables.units.csv; 1 = dimensionless).",
        l = units.unit(Quantity::Length),
        f = units.unit(Quantity::Force),
        m = units.unit(Quantity::Moment)
    ));
    notes.push(format!(
        "Rows: {} = {} before contact + {} in contact ({} requested points + {} at events).",
        n.rows, n.pre_contact, n.contact, n.requested, n.event_rows
    ));
    let mut scene = output_scene(r, Some(spec), Some(points));
    if let (Some(s), Some(acc)) = (scene.sweep.as_mut(), &res.accuracy) {
        s.tol = Some(acc.tol);
    }
    write_scene_ron(&out.path_for("scene.ron"), &scene, &notes)
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
