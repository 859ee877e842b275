//! The files of `vibrissa solve`'s elastica: `elastica.csv` (with its units sidecar) and
//! its figure, the loaded shape with the unloaded one and the loads as arrows.

use std::path::Path;

use beam_model::Solution;

use crate::commands::outputs::write_units_of;
use crate::csvio::CsvWriter;
use crate::error::CliError;
use crate::plot::{Chart, FigureStyle, Mark, Series, Style};
use crate::units::{Quantity, UnitSystem};

/// The header of `elastica.csv`.
pub const ELASTICA_HEADER: [&str; 6] = ["s", "x", "y", "phi", "kappa", "m"];
/// The quantities of the `elastica.csv` columns.
pub const ELASTICA_QUANTITIES: [Quantity; 6] = [
    Quantity::Length,
    Quantity::Length,
    Quantity::Length,
    Quantity::Angle,
    Quantity::Curvature,
    Quantity::Moment,
];
/// Writes `elastica.csv` of a solution in `units`, with its units sidecar.
pub fn write_elastica_csv(sol: &Solution, units: &UnitSystem, path: &Path) -> Result<(), CliError> {
    let e = &sol.elastica;
    let sc: Vec<f64> = ELASTICA_QUANTITIES
        .iter()
        .map(|q| units.scale(*q))
        .collect();
    let mut w = CsvWriter::new(&ELASTICA_HEADER);
    for i in 0..e.len() {
        w.push_numbers(&[
            e.s[i] * sc[0],
            e.x[i] * sc[1],
            e.y[i] * sc[2],
            e.phi[i],
            e.kappa[i] * sc[4],
            e.m[i] * sc[5],
        ])?;
    }
    w.write(path)?;
    Ok(write_units_of(
        path,
        &ELASTICA_HEADER,
        &ELASTICA_QUANTITIES,
        units,
    )?)
}
/// Writes the elastica figure in `units` (SVG at `path` and/or a PNG beside it, as `style`
/// says), with the
/// `loads` drawn as arrows if given: the tip force at the loaded end (direction [3.16],
/// rotated with the end if angle preserving) and the flow, `q (cos α, −sin α)`, along the
/// loaded part.
pub fn write_elastica_figure(
    sol: &Solution,
    unloaded: Option<&Solution>,
    loads: Option<&beam_model::Loads>,
    title: &str,
    units: &UnitSystem,
    path: &Path,
    style: FigureStyle,
) -> Result<(), CliError> {
    let l = units.scale(Quantity::Length);
    let pts = |s: &Solution| -> Vec<(f64, f64)> {
        s.elastica
            .x
            .iter()
            .zip(&s.elastica.y)
            .map(|(x, y)| (x * l, y * l))
            .collect()
    };
    let mut chart = Chart::new(
        title,
        units.label("x", Quantity::Length),
        units.label("y", Quantity::Length),
    )
    .equal_aspect()
    .note(units.describe());
    if let Some(u) = unloaded {
        chart = chart.with(Series::new("unloaded", pts(u), Style::Dashed).color(7));
    }
    chart = chart.with(Series::new("loaded", pts(sol), Style::Line).color(0));
    let base = (sol.elastica.x[0] * l, sol.elastica.y[0] * l);
    chart = chart.mark(Mark::point(base.0, base.1, "base", 7));
    if let Some(loads) = loads {
        chart = load_arrows(chart, sol, loads, l);
    }
    Ok(style.write_svg(&chart, path, (640, 640))?)
}

/// The loads of a solve as arrows ending on the whisker (0.2 whisker lengths for the tip
/// force, 0.1 for the flow).
fn load_arrows(mut chart: Chart, sol: &Solution, loads: &beam_model::Loads, l: f64) -> Chart {
    let tip = &loads.tip;
    if tip.f > 0.0 {
        let end = &sol.loaded_end;
        let ang = match tip.kind {
            beam_model::LoadKind::Dp => -tip.beta,
            beam_model::LoadKind::Ap => end.phi - std::f64::consts::FRAC_PI_2 - tip.beta,
        };
        let (dx, dy) = (0.2 * ang.cos(), 0.2 * ang.sin());
        chart = chart.mark(Mark::arrow(
            (end.x - dx) * l,
            (end.y - dy) * l,
            dx * l,
            dy * l,
            "tip force f",
            3,
        ));
    }
    let fl = &loads.fluid;
    let e = &sol.elastica;
    if fl.q > 0.0 && e.x.len() > 4 {
        let (dx, dy) = (0.1 * fl.alpha.cos(), -0.1 * fl.alpha.sin());
        let n = e.x.len() - 1;
        let loaded =
            e.s.iter()
                .filter(|&&s| s <= loads.s1 + 1e-12)
                .count()
                .max(2)
                - 1;
        for k in 0..4 {
            let i = ((2 * k + 1) * loaded / 8).min(n);
            let label = if k == 0 { "flow q" } else { "" };
            chart = chart.mark(Mark::arrow(
                (e.x[i] - dx) * l,
                (e.y[i] - dy) * l,
                dx * l,
                dy * l,
                label,
                5,
            ));
        }
    }
    chart
}
