//! `vibrissa solve`: one configuration, as JSON or a short summary, optionally with the
//! elastica as CSV and SVG.

use beam_model::{solve, Loads, Method, Scene, Solution};
use serde_json::{json, Value};

use crate::atomic::OutputDir;
use crate::cli::SolveArgs;
use crate::commands::elastica::{write_elastica_csv, write_elastica_figure};
use crate::commands::json::json_number as num;
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

/// The JSON object of `solve --json`.
pub fn solution_json(r: &Resolved, sol: &Solution) -> Value {
    let s = &r.scene;
    let end = |e: &beam_model::EndState| json!({"x": num(e.x), "y": num(e.y), "phi": num(e.phi)});
    let mut v = json!({
        "method": r.method.name(),
        "n": r.method.intervals(),
        "tip": end(&sol.tip),
        "loaded_end": end(&sol.loaded_end),
        "base": {
            "Ax": num(sol.base.ax),
            "Ay": num(sol.base.ay),
            "MA": num(sol.base.ma),
            "phi0": num(sol.base.phi0),
        },
        "stats": {
            "iterations": sol.stats.iterations,
            "residual": num(sol.stats.residual),
            "continuation_steps": sol.stats.continuation_steps,
            "evaluations": sol.stats.evaluations,
            "error_estimate": num(sol.stats.error_estimate),
            "tolerance": num(sol.stats.tolerance),
            "method_used": sol.stats.method_used.name(),
            "model_used": sol.stats.model_used.name(),
            "branch_jumps": sol.stats.branch_jumps,
        },
        "scene": {
            "theta": num(s.whisker.theta),
            "a": num(s.whisker.a),
            "b": num(s.whisker.b),
            "k": num(s.whisker.support.stiffness()),
            "f": num(s.loads.tip.f),
            "beta_deg": num(s.loads.tip.beta.to_degrees()),
            "load": match s.loads.tip.kind {
                beam_model::LoadKind::Dp => "dp",
                beam_model::LoadKind::Ap => "ap",
            },
            "q": num(s.loads.fluid.q),
            "alpha_deg": num(s.loads.fluid.alpha.to_degrees()),
        },
        "units": if r.physical.is_some() { "physical" } else { "dimensionless" },
    });
    if let (Some(p), Some(obj)) = (&sol.load_path, v.as_object_mut()) {
        obj.insert(
            "load_path".to_string(),
            json!({
                "folds": p.folds.iter().map(|f| json!({
                    "lambda": num(f.lambda), "phi1": num(f.phi1), "phi0": num(f.phi0),
                })).collect::<Vec<_>>(),
                "arrival": {"phi1": num(p.arrival.phi1), "phi0": num(p.arrival.phi0)},
                "other_equilibria": p.others.iter().map(|e| json!({
                    "phi1": num(e.phi1), "phi0": num(e.phi0),
                })).collect::<Vec<_>>(),
                "steps": p.steps,
            }),
        );
    }
    if let (Some(p), Some(obj)) = (&r.physical, v.as_object_mut()) {
        obj.insert(
            "physical".to_string(),
            json!({
                "length_m": num(p.length),
                "base_diameter_m": num(p.base_diameter),
                "youngs_modulus_pa": num(p.youngs_modulus),
                "tip_m": {"x": num(p.length_of(sol.tip.x)), "y": num(p.length_of(sol.tip.y))},
                "base": {
                    "Ax_N": num(sol.base.ax * p.force_scale()),
                    "Ay_N": num(sol.base.ay * p.force_scale()),
                    "MA_Nm": num(sol.base.ma * p.moment_scale()),
                },
                "f_N": num(s.loads.tip.f * p.force_scale()),
                "q_N_per_m": num(s.loads.fluid.q * p.line_load_scale()),
            }),
        );
    }
    v
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
