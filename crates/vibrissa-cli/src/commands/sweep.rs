//! `vibrissa sweep`: the whisker swept past an obstacle under the fluid load; the
//! observables log `observables.csv` and its figures.

use std::io::IsTerminal;
use std::time::Duration;

use beam_model::{shape_from_tip_angle, FluidLoad, Scene};
use contact_sim::phase::contact_loads;
use contact_sim::{sweep_with_progress, Phase, Profile, SweepProgress, SweepResult, SweepSettings};

use crate::atomic::OutputDir;
use crate::cli::SweepArgs;
use crate::commands::{sweep_summary, write_observables_csv, write_sweep_figures};
use crate::error::CliError;
use crate::plot::{write_svg, Chart, Series, Style};
use crate::resolve::{parse_count, profile_arg, resolve_model, LoadedScene, ProfileArg, Resolved};

/// Default number of contact points.
pub const DEFAULT_POINTS: usize = 200;

/// Runs `vibrissa sweep`.
pub fn run(args: &SweepArgs) -> Result<(), CliError> {
    let file = LoadedScene::load_opt(args.scene.as_deref())?;
    let profile = profile_arg(&args.profile, file.as_ref()).ok_or_else(|| {
        CliError::invalid_argument(
            "--profile",
            "",
            "a sweep needs an obstacle: give --profile or `profile` in the scene file",
        )
    })?;
    let points = match (
        &args.points,
        file.as_ref().and_then(|f| f.file.sweep.as_ref()),
    ) {
        (Some(raw), _) => {
            let n = parse_count("--points", raw, 2)?;
            if n > contact_sim::sweep::MAX_POINTS {
                return Err(CliError::invalid_argument(
                    "--points",
                    raw.clone(),
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
    let r = resolve_model(&args.model, file)?;
    check_sweep_loads(&r)?;
    let contour = profile.parse()?;
    let res = run_sweep(&r, &contour, &profile, points)?;
    let out = OutputDir::create(&args.out)?;
    write_sweep_outputs(&r, &contour, &res, &profile.spec, &out)?;
    let files = out.commit()?;
    println!("sweep {}: {}", profile.spec, sweep_summary(&res));
    println!("wrote {} files to {}", files.len(), args.out.display());
    Ok(())
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
                (_, Some(file)) => file.error_at(field, format!("{what}, got {}", p.value)),
                _ => CliError::invalid_argument(field, p.value.to_string(), what),
            });
        }
    }
    Ok(())
}

/// Runs the sweep with a spinner on stderr when it is a terminal.
pub fn run_sweep(
    r: &Resolved,
    contour: &Profile,
    profile: &ProfileArg,
    points: usize,
) -> Result<SweepResult, CliError> {
    let settings = SweepSettings {
        points,
        ..SweepSettings::default()
    };
    // A progress bar on stderr only when it is a terminal: a spinner while the coarse pass
    // looks for the separation, then a bar over the requested contact points.
    let bar = std::io::stderr().is_terminal().then(|| {
        let pb = indicatif::ProgressBar::new_spinner();
        pb.set_message(format!(
            "sweeping past {}: finding the separation",
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
        &settings,
        &mut |p| {
            let Some(pb) = &bar else { return };
            match p {
                SweepProgress::Coarse { .. } => pb.tick(),
                SweepProgress::Fine { done, total } => {
                    if !fine_started {
                        fine_started = true;
                        pb.set_length(total as u64);
                        pb.set_style(
                            indicatif::ProgressStyle::with_template(
                                "{msg} [{bar:40}] {pos}/{len} points ({elapsed})",
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
    res.map_err(|e| r.contact_culprit(e, profile))
}

/// Writes `observables.csv`, `observables.svg`, `contact.svg` and `shapes.svg` into `out`.
pub fn write_sweep_outputs(
    r: &Resolved,
    contour: &Profile,
    res: &SweepResult,
    title: &str,
    out: &OutputDir,
) -> Result<(), CliError> {
    write_observables_csv(res, &out.path_for("observables.csv"))?;
    write_sweep_figures(res, title, |n| out.path_for(n))?;
    write_shapes_svg(r, contour, res, title, &out.path_for("shapes.svg"))
}

/// The contour with the whisker at a few positions of the sweep (thesis Fig. 5.7 style).
fn write_shapes_svg(
    r: &Resolved,
    contour: &Profile,
    res: &SweepResult,
    title: &str,
    path: &std::path::Path,
) -> Result<(), CliError> {
    let contact: Vec<_> = res.contact_points().collect();
    let mut chart = Chart::new(format!("whisker shapes ({title})"), "x", "y").equal_aspect();
    let picks = 6usize.min(contact.len());
    let mut xs = vec![];
    for i in 0..picks {
        let idx = if picks == 1 {
            0
        } else {
            i * (contact.len() - 1) / (picks - 1)
        };
        let p = contact[idx];
        let scene = Scene::new(
            r.scene.whisker,
            contact_loads(
                FluidLoad {
                    q: res.q,
                    alpha: res.alpha,
                },
                p.psi,
                p.f,
                p.s1,
            ),
        );
        let Ok(sol) = shape_from_tip_angle(&scene, p.phi1, 1e-10, 100) else {
            continue;
        };
        // Draw only shapes that pass through their contact point.
        let miss = (sol.loaded_end.x + p.x0 - p.xc).hypot(sol.loaded_end.y - p.yc);
        if miss.is_nan() || miss >= 1e-4 {
            continue;
        }
        let pts: Vec<(f64, f64)> = sol
            .elastica
            .x
            .iter()
            .zip(&sol.elastica.y)
            .map(|(x, y)| (x + p.x0, *y))
            .collect();
        xs.extend(pts.iter().map(|q| q.0));
        let name = if i == 0 { "whisker" } else { "" };
        let color = if p.phase == Phase::B { 1 } else { 0 };
        chart = chart.with(Series::new(name, pts, Style::Line).color(color));
    }
    let (lo, hi) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    if lo.is_finite() && hi.is_finite() {
        let (dlo, dhi) = contour.domain();
        let (a, b) = ((lo - 0.2).max(dlo), (hi + 0.2).min(dhi));
        let line: Vec<(f64, f64)> = (0..=300)
            .map(|i| {
                let x = a + (b - a) * i as f64 / 300.0;
                (x, contour.y(x))
            })
            .filter(|p| p.1.is_finite() && p.1 < 1.6)
            .collect();
        chart = chart.with(Series::new("contour", line, Style::Line).color(7));
    }
    if chart.series.is_empty() {
        return Ok(());
    }
    write_svg(&chart, path, (800, 640))
}
