//! The figures of `vibrissa reconstruct`: `reconstruction.svg` (the reconstructed points
//! with their error bars over the true contour, if known, and the error panel) and
//! `error.svg`.

use std::path::PathBuf;

use contact_sim::{Phase, Profile};
use profile_recon::ReconPoint;

use crate::commands::phases::{phase_color, phase_name};
use crate::error::CliError;
use crate::plot::{Chart, FigureStyle, Series, Style};
use crate::units::{Quantity, UnitSystem};

/// The true contour over the x range of the points (5 % beyond each end, within its
/// domain), 301 points in `l` units; `None` without finite points.
fn true_contour_line(points: &[ReconPoint], p: &Profile, l: f64) -> Option<Vec<(f64, f64)>> {
    let xs = points.iter().map(|p| p.x).filter(|x| x.is_finite());
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let pad = 0.05 * (hi - lo).max(1e-3);
    let (dlo, dhi) = p.domain();
    let (a, b) = ((lo - pad).max(dlo), (hi + pad).min(dhi));
    Some(
        (0..=300)
            .map(|i| {
                let x = a + (b - a) * i as f64 / 300.0;
                (x * l, p.y(x) * l)
            })
            .collect(),
    )
}

/// The contour panel: the obstacle (solid above its contour) under the points of each
/// phase with their ±σ bars, the contour line again on top of them.
fn contour_chart(
    points: &[ReconPoint],
    truth: Option<&Profile>,
    title: &str,
    units: &UnitSystem,
) -> Chart {
    let l = units.scale(Quantity::Length);
    let mut chart = Chart::new(
        format!("reconstructed contour ({title})"),
        units.label("x", Quantity::Length),
        units.label("y", Quantity::Length),
    )
    .equal_aspect()
    .note(format!(
        "each point from one contact row's base observables alone, bars ±σ; {}",
        units.describe()
    ));
    let true_line = truth.and_then(|p| true_contour_line(points, p, l));
    if let Some(line) = &true_line {
        chart = chart
            .with(Series::new("obstacle (true contour)", line.clone(), Style::Obstacle).color(6));
    }
    for phase in [Phase::A, Phase::B] {
        let name = format!("reconstructed, {}", phase_name(phase));
        let sel: Vec<&ReconPoint> = points.iter().filter(|p| p.phase == phase).collect();
        if !sel.is_empty() {
            let pts = sel.iter().map(|p| (p.x * l, p.y * l)).collect();
            let err = sel.iter().map(|p| p.sigma * l).collect();
            chart = chart.with(
                Series::new(name, pts, Style::Points)
                    .color(phase_color(phase))
                    .errors(err),
            );
        }
    }
    if let Some(line) = true_line {
        chart = chart.with(Series::new("", line, Style::Line).color(6));
    }
    chart
}

/// The error panel: the true error where the contour is known, and the estimate σ.
fn error_chart(points: &[ReconPoint], errors: Option<&[f64]>, units: &UnitSystem) -> Chart {
    let l = units.scale(Quantity::Length);
    let x_of = |p: &ReconPoint| p.x * l;
    let mut resid = Chart::new(
        "error of each point",
        units.label("x", Quantity::Length),
        units.label("error", Quantity::Length),
    )
    .log(false, true);
    if let Some(e) = errors {
        let pts = points
            .iter()
            .zip(e)
            .map(|(p, &e)| (x_of(p), e * l))
            .collect();
        resid = resid
            .note(
                "e = |y − g(x)| (thesis eq. 6.11); points with e = 0 are not shown on the log axis",
            )
            .with(Series::new("true error e", pts, Style::Points).color(3));
    }
    let sig = points.iter().map(|p| (x_of(p), p.sigma * l)).collect();
    resid.with(
        Series::new("estimate σ", sig, Style::Points)
            .color(5)
            .marker(crate::plot::Marker::Triangle),
    )
}

/// Writes `reconstruction.svg` (the reconstructed points, with the true contour if known,
/// over the error panel) and, with errors, `error.svg` (e against x, log scale), the axes in
/// `units` (as `style` says: `--figures`, `--size`). Returns the SVG file names written.
pub fn write_reconstruction_figures(
    points: &[ReconPoint],
    truth: Option<&Profile>,
    errors: Option<&[f64]>,
    title: &str,
    units: &UnitSystem,
    path_for: impl Fn(&str) -> PathBuf,
    style: FigureStyle,
) -> Result<Vec<&'static str>, CliError> {
    let chart = contour_chart(points, truth, title, units);
    let resid = error_chart(points, errors, units);
    style.write_svg_panels(
        &[chart, resid.clone()],
        1,
        &path_for("reconstruction.svg"),
        (800, 900),
    )?;
    let mut written = vec!["reconstruction.svg"];
    if errors.is_some() {
        style.write_svg(&resid, &path_for("error.svg"), (800, 480))?;
        written.push("error.svg");
    }
    Ok(written)
}
