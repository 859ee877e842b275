//! The commands of the binary and the outputs they share.

pub mod demo;
pub mod reconstruct;
pub mod solve;
pub mod sweep;

use std::path::{Path, PathBuf};

use beam_model::Solution;
use contact_sim::{Phase, SweepPoint, SweepResult};

use crate::cli::Command;
use crate::csvio::{Cell, CsvWriter};
use crate::error::CliError;
use crate::plot::{write_svg, write_svg_panels, Chart, Series, Style};

/// Runs one command.
pub fn run(command: Command) -> Result<(), CliError> {
    match command {
        Command::Solve(args) => solve::run(&args),
        Command::Sweep(args) => sweep::run(&args),
        Command::Reconstruct(args) => reconstruct::run(&args),
        Command::Demo(args) => demo::run(&args),
    }
}

/// The header of `elastica.csv`.
pub const ELASTICA_HEADER: [&str; 6] = ["s", "x", "y", "phi", "kappa", "m"];

/// The header of `observables.csv` (spec/cli.md).
pub const OBSERVABLES_HEADER: [&str; 11] = [
    "x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "phase", "xc", "yc", "psi",
];

/// Writes `elastica.csv` of a solution to `path`.
pub fn write_elastica_csv(sol: &Solution, path: &Path) -> Result<(), CliError> {
    let e = &sol.elastica;
    let mut w = CsvWriter::new(&ELASTICA_HEADER);
    for i in 0..e.len() {
        w.push_numbers(&[e.s[i], e.x[i], e.y[i], e.phi[i], e.kappa[i], e.m[i]])?;
    }
    w.write(path)
}

/// Writes the elastica figure (equal aspect), with the unloaded shape dashed if given.
pub fn write_elastica_svg(
    sol: &Solution,
    unloaded: Option<&Solution>,
    title: &str,
    path: &Path,
) -> Result<(), CliError> {
    let pts = |s: &Solution| -> Vec<(f64, f64)> {
        s.elastica
            .x
            .iter()
            .copied()
            .zip(s.elastica.y.iter().copied())
            .collect()
    };
    let mut chart = Chart::new(title, "x", "y").equal_aspect();
    if let Some(u) = unloaded {
        chart = chart.with(Series::new("unloaded", pts(u), Style::Dashed).color(7));
    }
    chart = chart.with(Series::new("loaded", pts(sol), Style::Line).color(0));
    write_svg(&chart, path, (640, 640))
}

/// The rows of `observables.csv` (header [`OBSERVABLES_HEADER`]) for sweep points.
pub fn observables_csv(points: &[SweepPoint]) -> Result<CsvWriter, CliError> {
    let mut w = CsvWriter::new(&OBSERVABLES_HEADER);
    for p in points {
        w.push_row(&[
            Cell::Num(p.x0),
            Cell::Num(p.ax),
            Cell::Num(p.ay),
            Cell::Num(p.ma),
            Cell::Num(p.phi0),
            Cell::Num(p.f),
            Cell::Num(p.s1),
            Cell::Text(p.phase.label()),
            Cell::Num(p.xc),
            Cell::Num(p.yc),
            Cell::Num(p.psi),
        ])?;
    }
    Ok(w)
}

/// Writes `observables.csv` of a sweep to `path`.
pub fn write_observables_csv(res: &SweepResult, path: &Path) -> Result<(), CliError> {
    observables_csv(&res.points)?.write(path)
}

fn phase_color(p: Phase) -> usize {
    match p {
        Phase::None => 7,
        Phase::A => 0,
        Phase::B => 1,
    }
}

/// Series of `value` against x0, one per run of equal phase (coloured by phase; runs
/// touch so the curve is continuous), only contact rows if `contact_only`.
fn phase_series(
    res: &SweepResult,
    value: impl Fn(&contact_sim::SweepPoint) -> f64,
    contact_only: bool,
) -> Vec<Series> {
    let rows: Vec<_> = res
        .points
        .iter()
        .filter(|p| !contact_only || p.phase != Phase::None)
        .collect();
    let mut out: Vec<Series> = Vec::new();
    let mut named = [false; 3];
    let mut i = 0;
    while i < rows.len() {
        let phase = rows[i].phase;
        let mut j = i;
        while j < rows.len() && rows[j].phase == phase {
            j += 1;
        }
        let mut pts: Vec<(f64, f64)> = rows[i..j].iter().map(|p| (p.x0, value(p))).collect();
        if j < rows.len() {
            pts.push((rows[j].x0, value(rows[j])));
        }
        let idx = match phase {
            Phase::None => 0,
            Phase::A => 1,
            Phase::B => 2,
        };
        let name = if named[idx] {
            String::new()
        } else {
            named[idx] = true;
            match phase {
                Phase::None => "no contact".to_string(),
                Phase::A => "phase A".to_string(),
                Phase::B => "phase B".to_string(),
            }
        };
        out.push(Series::new(name, pts, Style::Line).color(phase_color(phase)));
        i = j;
    }
    out
}

fn chart_of(title: &str, y_label: &str, series: Vec<Series>) -> Chart {
    let mut c = Chart::new(title, "x0", y_label);
    for s in series {
        c = c.with(s);
    }
    c
}

/// Writes the figures of a sweep into `dir` (staging paths): `observables.svg` (Ax, Ay, MA,
/// phi0 against x0, thesis Figs. 5.9/5.10) and `contact.svg` (f and s1 against x0, Fig. 5.11).
/// Returns the file names written.
pub fn write_sweep_figures(
    res: &SweepResult,
    title: &str,
    path_for: impl Fn(&str) -> PathBuf,
) -> Result<Vec<&'static str>, CliError> {
    let charts = [
        chart_of(
            &format!("Ax ({title})"),
            "Ax",
            phase_series(res, |p| p.ax, false),
        ),
        chart_of(
            &format!("Ay ({title})"),
            "Ay",
            phase_series(res, |p| p.ay, false),
        ),
        chart_of(
            &format!("MA ({title})"),
            "MA",
            phase_series(res, |p| p.ma, false),
        ),
        chart_of(
            &format!("phi0 ({title})"),
            "phi0",
            phase_series(res, |p| p.phi0, false),
        ),
    ];
    write_svg_panels(&charts, 2, &path_for("observables.svg"), (1000, 760))?;
    let mut written = vec!["observables.svg"];
    if res.contact_points().next().is_some() {
        let charts = [
            chart_of(
                &format!("contact force f ({title})"),
                "f",
                phase_series(res, |p| p.f, true),
            ),
            chart_of(
                &format!("contact arc length s1 ({title})"),
                "s1",
                phase_series(res, |p| p.s1, true),
            ),
        ];
        write_svg_panels(&charts, 2, &path_for("contact.svg"), (1000, 400))?;
        written.push("contact.svg");
    }
    Ok(written)
}

/// A one-line description of a sweep's outcome.
pub fn sweep_summary(res: &SweepResult) -> String {
    let pre = res.points.iter().filter(|p| p.phase == Phase::None).count();
    let first = match res.first_contact {
        contact_sim::FirstContact::Tip => "tip".to_string(),
        contact_sim::FirstContact::Tangential => "tangential".to_string(),
    };
    let sep = match res.separation {
        contact_sim::Separation::Snap => "snap".to_string(),
        contact_sim::Separation::Release => "release".to_string(),
        contact_sim::Separation::MultiContact { xc } => {
            format!("second contact at xc = {xc:.4} (stopped)")
        }
        contact_sim::Separation::EndOfContour => "end of contour".to_string(),
        contact_sim::Separation::ContactAtBase => "contact at the base".to_string(),
        contact_sim::Separation::NotReached { steps } => {
            format!("not reached within {steps} steps")
        }
    };
    format!(
        "{} rows ({} before contact), first contact {}, separation {}, phases {}",
        res.points.len(),
        pre,
        first,
        sep,
        res.phase_pattern()
    )
}

/// Formats a list of written files relative to nothing (as the OS returned them).
pub fn list_files(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
