//! `vibrissa demo`: the whole chain on a built-in scene.
//!
//! The built-in scene (thesis ch. 5, case 5 on g1, simplified): a tapered whisker
//! (theta = 0.75) on a torsional spring (k = 20) under the flow q = 5, swept past the
//! contour g1. The demo solves the free whisker under the flow, sweeps it past g1 and (once
//! `profile-recon` lands) identifies q and reconstructs the contour from the observables.

use std::path::Path;

use beam_model::solve;
use contact_sim::{Profile, SweepResult};
use profile_recon::{contour_error, from_sweep, reconstruct, ReconSettings};

use crate::atomic::OutputDir;
use crate::cli::DemoArgs;
use crate::commands::recon_io::{write_reconstruction_csv, RECON_CSV};
use crate::commands::reconstruct::summary::{
    max_of, phase_counts, row_ranges, rows_without_points,
};
use crate::commands::reconstruct::write_reconstruction_figures;
use crate::commands::solve::write_solution_files;
use crate::commands::sweep::{run_sweep, write_sweep_outputs, write_sweep_units};
use crate::commands::sweep_events::sweep_summary;
use crate::error::CliError;
use crate::plot::FigureStyle;
use crate::printer::Printer;
use crate::resolve::{profile_arg, resolve_model, LoadedScene, ModelFlags, Resolved};
use crate::scene_file::SceneFile;
use crate::units::UnitSystem;

/// The built-in demo scene (also written to `scene.ron` in the output folder).
pub const DEMO_SCENE: &str = "\
// The vibrissa demo scene: a tapered whisker on a torsional spring under the flow q = 5,
// swept past the contour g1 (thesis ch. 5).
(
    units: Dimensionless,
    whisker: (theta: 0.75, a: 0.0, b: 0.0, k: Some(20.0)),
    loads: (q: 5.0),
    profile: Some(\"g1\"),
    sweep: Some((points: 120)),
    method: (name: \"accurate\"),
)
";

/// Runs `vibrissa demo`, its figures written as `style` says.
pub fn run(args: &DemoArgs, style: FigureStyle) -> Result<(), CliError> {
    if args.points < 2 {
        return Err(CliError::invalid_argument(
            "--points",
            args.points.to_string(),
            "must be at least 2",
        ));
    }
    let path = Path::new("<built-in demo scene>");
    let file = LoadedScene {
        file: SceneFile::parse(DEMO_SCENE, path)?,
        text: DEMO_SCENE.to_string(),
        path: path.to_path_buf(),
    };
    let profile = profile_arg(&None, Some(&file)).ok_or_else(|| {
        CliError::Io(vibrissa_io::IoError::Solver {
            reason: "demo scene has no profile".to_string(),
            source: None,
        })
    })?;
    let r = resolve_model(&ModelFlags::default(), Some(file))?;
    let contour = profile.parse(&r.units())?;

    // 1. The free whisker under the flow.
    let free = solve(&r.scene, &r.method).map_err(|e| r.culprit(&e))?;
    // 2. The sweep past the contour.
    let res = run_sweep(&r, &contour, &profile, args.points)?;

    let out = OutputDir::create(&args.out)?;
    // write_sweep_outputs writes scene.ron with the points actually used.
    write_solution_files(&r, &free, &out, style)?;
    write_sweep_units(&r, &out)?;
    write_sweep_outputs(
        &r,
        &contour,
        &res,
        &profile,
        (args.points, contact_sim::ContactLaw::Frictionless),
        &out,
        style,
    )?;
    // 3. Identification and reconstruction.
    let mut summary = Vec::new();
    reconstruct_step(&r, &contour, &res, &out, &mut summary, style)?;
    let files = out.commit()?;

    let mut stdout = Printer::stdout().published(Some(args.out.as_path()));
    stdout.line(format_args!(
        "demo: theta = 0.75, k = 20, q = 5, contour g1 ({} contact rows requested)",
        args.points
    ))?;
    stdout.line(format_args!(
        "  free whisker under the flow: tip ({:.5}, {:.5}), MA = {:.5}, phi0 = {:.5}",
        free.tip.x, free.tip.y, free.base.ma, free.base.phi0
    ))?;
    stdout.line(format_args!(
        "  sweep: {}",
        sweep_summary(&res, args.points, &UnitSystem::DIMENSIONLESS)
    ))?;
    for line in &summary {
        stdout.line(format_args!("  {line}"))?;
    }
    stdout.line(format_args!(
        "wrote {} files to {}",
        files.len(),
        args.out.display()
    ))
}

/// Identification of q and accurate contour reconstruction from the sweep's observables
/// alone: writes `reconstruction.csv` (with the error column against the true contour),
/// `reconstruction.svg` and `error.svg` (as `style` says), and pushes the results to
/// `summary`.
pub fn reconstruct_step(
    resolved: &Resolved,
    contour: &Profile,
    sweep: &SweepResult,
    out: &OutputDir,
    summary: &mut Vec<String>,
    style: FigureStyle,
) -> Result<(), CliError> {
    let rows = from_sweep(sweep);
    let settings = ReconSettings::default();
    let rec = reconstruct(&resolved.scene.whisker, &rows, None, &settings).map_err(|e| {
        CliError::Io(vibrissa_io::IoError::Solver {
            reason: format!("demo reconstruction: {e}"),
            source: Some(Box::new(e)),
        })
    })?;
    let errors = contour_error(&rec.points, contour);
    let units = UnitSystem::DIMENSIONLESS;
    write_reconstruction_csv(
        &rec.points,
        Some(&errors),
        &units,
        &[],
        &out.path_for(RECON_CSV),
    )?;
    write_reconstruction_figures(
        &rec.points,
        Some(contour),
        Some(&errors),
        "demo: contour g1, q = 5",
        &units,
        |n| out.path_for(n),
        style,
    )?;
    let q_true = resolved.q();
    let id = &rec.identification;
    let free = rows_without_points(&rec.points, rows.len());
    let with: Vec<usize> = rec.points.iter().map(|p| p.row).collect();
    summary.push(format!(
        "identification: q = {:.12} (true {q_true}, error {:.2e}) from the {} rows without \
         contact force (rows {}: before contact, and the first touch and release with f = 0), \
         {} rows reconstructed (rows {})",
        id.q,
        (id.q - q_true).abs(),
        free.len(),
        row_ranges(&free),
        with.len(),
        row_ranges(&with),
    ));
    let (na, nb) = phase_counts(&rec.points);
    summary.push(format!(
        "reconstruction ({}): {} contact points, phases A {na} / B {nb}, max residual {:.2e}",
        settings.method.name(),
        rec.points.len(),
        max_of(&rec.points.iter().map(|p| p.residual).collect::<Vec<_>>()),
    ));
    summary.push(format!(
        "contour error (eq. 6.11): max e = {:.2e} over {} points",
        max_of(&errors),
        errors.len()
    ));
    Ok(())
}
