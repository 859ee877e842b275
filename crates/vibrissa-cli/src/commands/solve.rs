//! `vibrissa solve`: one configuration, as JSON or a short summary, optionally with the
//! elastica as CSV and SVG.

use beam_model::{solve, Loads, Method, Scene, Solution};
use serde_json::Value;
use vibrissa_io::summary::SolveSummary;

use crate::atomic::OutputDir;
use crate::cli::SolveArgs;
use crate::commands::elastica::{write_elastica_csv, write_elastica_figure};
use crate::commands::outputs::{list_files, output_scene, scene_unit_notes, write_scene_ron};
use crate::error::CliError;
use crate::plot::FigureStyle;
use crate::printer::Printer;
use crate::resolve::{resolve_model, LoadedScene, Resolved};

/// Runs `vibrissa solve`, its figure written as `style` says.
pub fn run(args: &SolveArgs, style: FigureStyle) -> Result<(), CliError> {
    let file = LoadedScene::load_opt(args.scene.as_deref())?;
    let r = resolve_model(&(&args.model).into(), file)?;
    let sol = solve(&r.scene, &r.method).map_err(|e| r.culprit(&e))?;
    let mut written = Vec::new();
    if let Some(dir) = &args.out {
        if let Some(scene) = &args.scene {
            crate::atomic::refuse_over_inputs(dir, &[("scene file", scene)])?;
        }
        let out = OutputDir::create(dir)?;
        write_solution_files(&r, &sol, &out, style)?;
        written = out.commit()?;
    }
    let mut stdout = Printer::stdout().published(args.out.as_deref());
    if args.json {
        stdout.line(solution_json(&r, &sol))?;
        if !written.is_empty() {
            eprintln!("wrote {}", list_files(&written));
        }
    } else {
        stdout.text(&human_summary(&r, &sol))?;
        if !written.is_empty() {
            stdout.line(format_args!("wrote {}", list_files(&written)))?;
        }
    }
    Ok(())
}

/// Writes `elastica.csv` and `elastica.svg` (as `style` says) of a solution into the staged
/// directory.
pub fn write_solution_files(
    r: &Resolved,
    sol: &Solution,
    out: &OutputDir,
    style: FigureStyle,
) -> Result<(), CliError> {
    let units = r.units();
    write_elastica_csv(sol, &units, &out.path_for("elastica.csv"))?;
    write_scene_ron(
        &out.path_for("scene.ron"),
        &output_scene(r, None, None),
        &[
            format!(
                "Written by vibrissa {} (`solve`): the scene of the files beside it.",
                env!("CARGO_PKG_VERSION")
            ),
            scene_unit_notes(&units).join(" "),
        ],
    )?;
    // The unloaded shape for reference (a cheap, always convergent solve).
    let unloaded = solve(
        &Scene::new(r.scene.whisker, Loads::none()),
        &Method::accurate(),
    )
    .ok();
    let title = format!(
        "elastica ({} method, n = {})",
        r.method.name(),
        r.method.intervals()
    );
    write_elastica_figure(
        sol,
        unloaded.as_ref(),
        Some(&r.scene.loads),
        &title,
        &units,
        &out.path_for("elastica.svg"),
        style,
    )
}

/// The JSON object of `solve --json`: the library's [`SolveSummary`] serialised.
pub fn solution_json(r: &Resolved, sol: &Solution) -> Value {
    serde_json::to_value(SolveSummary::of(r, sol)).unwrap_or(Value::Null)
}

/// What the summary says about the load path from zero: its folds (load scale and angles
/// there) and the other equilibria at full load, or that the continuation met other
/// equilibria.
fn load_path_note(sol: &Solution) -> String {
    match &sol.load_path {
        Some(p) if !p.folds.is_empty() => {
            let folds: Vec<String> = p
                .folds
                .iter()
                .map(|f| format!("at load scale {:.4} (phi1 = {:.4})", f.lambda, f.phi1))
                .collect();
            let others: Vec<String> = p
                .others
                .iter()
                .map(|e| format!("phi1 = {:.6}, phi0 = {:.6}", e.phi1, e.phi0))
                .collect();
            format!(
                "; the load path from zero folds {} time(s), {}; the equilibrium returned is its first arrival at full load{}",
                p.folds.len(),
                folds.join(", "),
                if others.is_empty() {
                    String::new()
                } else {
                    format!("; other equilibria at full load on the path: {}", others.join("; "))
                }
            )
        }
        _ if sol.stats.branch_jumps > 0 || sol.load_path.is_some() => {
            "; other equilibria exist near the load path (the one returned is reached by loading from zero)".into()
        }
        _ => String::new(),
    }
}

fn human_summary(r: &Resolved, sol: &Solution) -> String {
    let mut out = format!(
        "solve: {} (n = {}){}, {} model, {} iterations, residual {:.2e}, estimated error {:.1e} (tolerance {:.0e}){}\n",
        r.method.name(),
        r.method.intervals(),
        match sol.stats.requested {
            // `auto` chooses a method; any other request that answers by another fell back
            beam_model::MethodKind::Auto => format!(" -> {}", sol.stats.method_used.name()),
            _ if sol.stats.fell_back() => {
                format!(" -> fell back to {}", sol.stats.method_used.name())
            }
            _ => String::new(),
        },
        sol.stats.model_used.name(),
        sol.stats.iterations,
        sol.stats.residual,
        sol.stats.error_estimate,
        sol.stats.tolerance,
        if sol.stats.continuation_steps > 0 {
            format!(", {} continuation steps", sol.stats.continuation_steps)
        } else {
            String::new()
        } + &load_path_note(sol)
    );
    out += &format!(
        "tip   x = {:.8}  y = {:.8}  phi = {:.8}\n",
        sol.tip.x, sol.tip.y, sol.tip.phi
    );
    if sol.loaded_end != sol.tip {
        out += &format!(
            "s1    x = {:.8}  y = {:.8}  phi = {:.8}\n",
            sol.loaded_end.x, sol.loaded_end.y, sol.loaded_end.phi
        );
    }
    out += &format!(
        "base  Ax = {:.8}  Ay = {:.8}  MA = {:.8}  phi0 = {:.8}\n",
        sol.base.ax, sol.base.ay, sol.base.ma, sol.base.phi0
    );
    if let Some(p) = &r.physical {
        out += &format!(
            "physical  tip ({:.4} mm, {:.4} mm), Ax = {:.4e} N, Ay = {:.4e} N, MA = {:.4e} N m\n",
            p.length_of(sol.tip.x) * 1e3,
            p.length_of(sol.tip.y) * 1e3,
            sol.base.ax * p.force_scale(),
            sol.base.ay * p.force_scale(),
            sol.base.ma * p.moment_scale()
        );
    }
    out
}
