//! The scene sketches of chapter 5 (Figs. 5.8, 5.21, 5.34, 5.44): the contour (obstacle)
//! and the deformed whisker at several base positions x0 of a sweep, one panel per sweep,
//! each shape in the line of its contact phase, with the contact points.

use beam_model::{FluidLoad, Solution};
use contact_sim::{Phase, SweepPoint, SweepResult};
use vibrissa_io::atomic::OutputDir;
use vibrissa_io::csvio::{Cell, CsvWriter};
use vibrissa_plot::{Chart, Marker, Series, Style};

use super::style::{figure, phase_style, pretty_label};
use crate::captions::caption;
use crate::common::{self, fig_stem, note_err, sig, Layout, SweepRun};
use crate::{Entry, Report};

/// The contact phases in key order.
const PHASES: [Phase; 3] = [Phase::None, Phase::A, Phase::B];

/// A scene sketch: the contour and the whisker at several base positions of each sweep
/// selected by `pick` (one panel per sweep).
pub(super) fn sketch(
    out: &OutputDir,
    report: &mut Report,
    fig: &str,
    runs: &[SweepRun],
    pick: impl Fn(&SweepRun) -> bool,
) {
    let entry = report.entry(fig, caption(fig));
    let picked: Vec<&SweepRun> = runs.iter().filter(|r| pick(r)).collect();
    if picked.is_empty() {
        entry.fail("no matching sweep case");
        return;
    }
    let mut charts: Vec<Chart> = Vec::new();
    let mut seen_any = [false; 3];
    let mut aspects = Vec::new();
    let mut w = CsvWriter::new(&["case", "row", "x0", "phase", "s", "x", "y"]);
    for r in &picked {
        let s = match &r.result {
            Ok(s) => s,
            Err(e) => {
                entry.fail(format!("sweep {}: {e}", r.name()));
                continue;
            }
        };
        let idx = shape_rows(s);
        let panel = sketch_panel(entry, r, s, &idx, &mut w);
        for (k, seen) in panel.named.iter().enumerate() {
            seen_any[k] |= *seen;
        }
        aspects.extend(panel.aspect);
        entry.number(
            format!("{} shapes", r.name()),
            format!(
                "{} (x0 = {})",
                idx.len(),
                idx.iter()
                    .map(|&i| sig(s.points[i].x0, 3))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            None,
        );
        charts.push(panel.chart);
    }
    if charts.is_empty() {
        return;
    }
    one_key(&mut charts[0], seen_any);
    let r = write_sketch(out, entry, fig, &charts, &aspects)
        .and_then(|()| common::csv(out, entry, &format!("{}.csv", fig_stem(fig)), &w));
    note_err(entry, &fig_stem(fig), r);
}

/// The rows of a sweep drawn in its sketch: the last pre-contact row and 7 contact rows
/// evenly spread.
fn shape_rows(s: &SweepResult) -> Vec<usize> {
    let contact: Vec<usize> = (0..s.points.len())
        .filter(|&i| s.points[i].phase != Phase::None)
        .collect();
    let mut idx: Vec<usize> = Vec::new();
    if let Some(&first) = contact.first() {
        if first > 0 {
            idx.push(first - 1);
        }
    }
    let n = contact.len();
    for k in 0..7usize {
        if n > 0 {
            idx.push(contact[(k * (n - 1)) / 6]);
        }
    }
    idx.dedup();
    idx
}

/// The panel of one sweep in a sketch.
struct SketchPanel {
    chart: Chart,
    /// Which phases (in [`PHASES`] order) the panel draws.
    named: [bool; 3],
    /// The height of the obstacle's box over its width, if any shape was drawn.
    aspect: Option<f64>,
}

/// Draws the shapes of sweep `r` (result `s`) at rows `idx` with their contact points and
/// the obstacle under them, and writes their points to `w`; a shape that cannot be
/// computed is recorded in `entry` and left out.
fn sketch_panel(
    entry: &mut Entry,
    r: &SweepRun,
    s: &SweepResult,
    idx: &[usize],
    w: &mut CsvWriter,
) -> SketchPanel {
    let mut chart = Chart::new(
        format!(
            "case {} ({}), {}",
            r.case.case,
            r.case.profile_name,
            pretty_label(&r.case.label)
        ),
        "x [–]",
        "y [–]",
    )
    .equal_aspect();
    let (mut xmin, mut xmax, mut ymax) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    let mut named = [false; 3];
    let mut contact_pts = Vec::new();
    for &i in idx {
        let p = &s.points[i];
        let sol = match whisker_shape(r, p) {
            Ok(sol) => sol,
            Err(e) => {
                entry.fail(format!("shape of {} at x0 = {}: {e}", r.name(), p.x0));
                continue;
            }
        };
        let el = &sol.elastica;
        let pts: Vec<(f64, f64)> =
            el.x.iter()
                .zip(&el.y)
                .map(|(&x, &y)| (p.x0 + x, y))
                .collect();
        for &(x, y) in &pts {
            xmin = xmin.min(x);
            xmax = xmax.max(x);
            ymax = ymax.max(y);
        }
        if p.phase != Phase::None && p.xc.is_finite() && p.yc.is_finite() {
            contact_pts.push((p.xc, p.yc));
        }
        for (j, &(x, y)) in pts.iter().enumerate() {
            let _ = w.push_row(&[
                Cell::Text(&r.case.label),
                Cell::Num(i as f64),
                Cell::Num(p.x0),
                Cell::Text(p.phase.label()),
                Cell::Num(el.s[j]),
                Cell::Num(x),
                Cell::Num(y),
            ]);
        }
        let (k, color, dash, label) = phase_style(p.phase);
        let name = if named[k] { "" } else { label };
        named[k] = true;
        chart
            .series
            .push(Series::new(name, pts, Style::Line).color(color).dash(dash));
    }
    if !contact_pts.is_empty() {
        chart.series.push(
            Series::new("contact point", contact_pts, Style::Points)
                .color(6)
                .marker(Marker::Circle),
        );
    }
    let aspect = xmin.is_finite().then(|| {
        let (obstacle, aspect) = obstacle(r, xmin, xmax, ymax);
        chart.series.insert(0, obstacle);
        aspect
    });
    SketchPanel {
        chart,
        named,
        aspect,
    }
}

/// The whisker of sweep `r` at row `p` ([`SweepPoint::shape`]): free under its fluid load
/// before contact, else under the fluid load and the contact force, from the row's tip angle.
fn whisker_shape(r: &SweepRun, p: &SweepPoint) -> Result<Solution, String> {
    let flow = FluidLoad {
        q: r.case.q,
        alpha: 0.0,
    };
    p.shape(&r.case.whisker, flow, 1e-10, 100)
        .map_err(|e| e.to_string())
}

/// The obstacle (its solid side filled) under shapes spanning `xmin..xmax` in x, up to a
/// little above their highest point `ymax`, and the height over the width of its box.
fn obstacle(r: &SweepRun, xmin: f64, xmax: f64, ymax: f64) -> (Series, f64) {
    let (a, b) = (xmin - 0.2, xmax + 0.2);
    let top = ymax + 0.25;
    let g: Vec<(f64, f64)> = (0..=400)
        .map(|i| {
            let x = a + (b - a) * i as f64 / 400.0;
            (x, r.case.profile.y(x))
        })
        .filter(|&(_, y)| y.is_finite() && y < top)
        .collect();
    let series = Series::new(
        format!("obstacle {}", r.case.profile_name),
        g,
        Style::Obstacle,
    )
    .color(6);
    (series, top / (b - a))
}

/// One key above all panels, from the first chart: it names every phase drawn in any
/// panel (`seen_any`, in [`PHASES`] order; an empty series stands in for a phase the first
/// panel lacks), in phase order (obstacle, phases, contact points) and the contact points
/// drawn on top.
fn one_key(first: &mut Chart, seen_any: [bool; 3]) {
    for (k, phase) in PHASES.into_iter().enumerate() {
        let (_, color, dash, label) = phase_style(phase);
        if seen_any[k] && !first.series.iter().any(|s| s.name == label) {
            first.series.push(
                Series::new(label, Vec::new(), Style::Line)
                    .color(color)
                    .dash(dash),
            );
        }
    }
    first.series.sort_by_key(|s| match s.name.as_str() {
        "" => 9,
        n if n.starts_with("obstacle") => 0,
        "contact point" => 10,
        n => {
            1 + PHASES
                .iter()
                .position(|&p| phase_style(p).3 == n)
                .unwrap_or(3)
        }
    });
}

/// Writes the sketch's panels, two a row (a lone one alone); `aspects` are the panels'
/// obstacle boxes, height over width.
fn write_sketch(
    out: &OutputDir,
    entry: &mut Entry,
    fig: &str,
    charts: &[Chart],
    aspects: &[f64],
) -> Result<(), String> {
    let cols = if charts.len() > 1 { 2 } else { 1 };
    let rows = charts.len().div_ceil(cols);
    let layout = Layout {
        cols,
        size: (560 * cols as u32, 420 * rows as u32),
        title: "",
        note: "the base moves towards −x (right to left)",
    };
    // A lone sketch about as high as wide (the ge sweep) takes one column; a flat one (the
    // wide g1 sweeps) the page.
    let column = charts.len() == 1 && aspects.iter().all(|&a| a > 0.5);
    let name = format!("{}.svg", fig_stem(fig));
    figure(out, entry, &name, charts, &layout, column)
}
