//! The whisker shapes along a sweep: `shapes.csv` (every row's shape, `sweep --shapes`)
//! and the figure `shapes.svg` (the whisker at the events and between them, with the
//! obstacle, the contact points and the directions of the sweep and the flow).

use std::path::Path;

use beam_model::FluidLoad;
use contact_sim::{Phase, Profile, SweepPoint, SweepResult};

use crate::commands::outputs::write_units_of;
use crate::commands::phases::{phase_color, phase_dash, NamedOnce};
use crate::commands::sweep_events::{sweep_events, SweepEvent};
use crate::commands::sweep_figures::FigureContext;
use crate::csvio::CsvWriter;
use crate::error::CliError;
use crate::plot::{Chart, Mark, MarkStyle, Marker, Series, Style};
use crate::resolve::Resolved;
use crate::units::Quantity;

/// The header of `shapes.csv`.
pub const SHAPES_HEADER: [&str; 5] = ["row", "s", "x", "y", "phi"];

/// The whisker's shape at a sweep row (the free whisker under the flow before contact; with
/// the contact force at its point otherwise): one DOP853 integration from the loaded end at
/// the row's tip angle, `intervals` intervals up to the contact point, then the load-free segment
/// beyond a tangential contact to the tip; positions relative to the base.
pub fn row_shape(
    whisker: &beam_model::Whisker,
    flow: FluidLoad,
    p: &contact_sim::SweepPoint,
    intervals: usize,
) -> Result<beam_model::Solution, beam_model::ModelError> {
    p.shape(whisker, flow, 1e-10, intervals)
}

/// Writes `shapes.csv` (header [`SHAPES_HEADER`], rows numbered from 1 as in
/// `observables.csv`) in the scene's units, with its units sidecar.
pub fn write_shapes_csv(
    r: &Resolved,
    res: &SweepResult,
    path: &std::path::Path,
) -> Result<(), CliError> {
    let units = r.units();
    let l = units.scale(Quantity::Length);
    let flow = FluidLoad {
        q: res.q,
        alpha: res.alpha,
    };
    let mut w = CsvWriter::new(&SHAPES_HEADER);
    for (i, p) in res.points.iter().enumerate() {
        let sol = row_shape(&r.scene.whisker, flow, p, 100).map_err(|e| {
            CliError::Io(vibrissa_io::IoError::Solver {
                reason: format!(
                    "shapes.csv: the shape of row {} (x0 = {}): {e}",
                    i + 1,
                    p.x0
                ),
                source: Some(Box::new(e)),
            })
        })?;
        let e = &sol.elastica;
        for k in 0..e.len() {
            w.push_numbers(&[
                (i + 1) as f64,
                e.s[k] * l,
                (p.x0 + e.x[k]) * l,
                (p.y0 + e.y[k]) * l,
                e.phi[k],
            ])?;
        }
    }
    w.write(path)?;
    Ok(write_units_of(
        path,
        &SHAPES_HEADER,
        &[
            Quantity::Number,
            Quantity::Length,
            Quantity::Length,
            Quantity::Length,
            Quantity::Angle,
        ],
        &units,
    )?)
}

/// The rows whose shapes `shapes.svg` draws: every event and evenly spaced contact rows
/// between them, 8 in all at most, in row order.
fn picked_rows(events: &[SweepEvent], contact: &[usize]) -> Vec<usize> {
    let mut picks: Vec<usize> = events.iter().map(|e| e.index).collect();
    let extra = 8usize.saturating_sub(picks.len()).min(contact.len());
    for k in 0..extra {
        let i = contact[(k + 1) * contact.len() / (extra + 1)];
        picks.push(i);
    }
    picks.sort_unstable();
    picks.dedup();
    picks
}

/// The shape of a contact row in plot coordinates (whisker lengths, relative to the
/// origin), if it passes through its contact point.
fn drawn_shape(r: &Resolved, res: &SweepResult, p: &SweepPoint) -> Option<Vec<(f64, f64)>> {
    let flow = FluidLoad {
        q: res.q,
        alpha: res.alpha,
    };
    let sol = row_shape(&r.scene.whisker, flow, p, 200).ok()?;
    // Draw only shapes that pass through their contact point.
    let miss = (sol.loaded_end.x + p.x0 - p.xc).hypot(sol.loaded_end.y + p.y0 - p.yc);
    if miss.is_nan() || miss >= 1e-4 {
        return None;
    }
    let e = &sol.elastica;
    Some(
        e.x.iter()
            .zip(&e.y)
            .map(|(x, y)| (x + p.x0, y + p.y0))
            .collect(),
    )
}

/// The legend text of a whisker drawn in phase `p`.
fn shape_name(p: Phase) -> &'static str {
    match p {
        Phase::B => "whisker, phase B (tangential)",
        _ => "whisker, phase A (tip)",
    }
}

/// The whiskers drawn: their series (one per shape, in row order), their contact points and
/// base positions (in `l` units), and the range of x they cover (whisker lengths).
struct Shapes {
    series: Vec<Series>,
    contact: Vec<(f64, f64)>,
    bases: Vec<(f64, f64)>,
    x_range: Option<(f64, f64)>,
    y_range: Option<(f64, f64)>,
}

impl Shapes {
    fn of(r: &Resolved, res: &SweepResult, picks: &[usize], l: f64) -> Self {
        let mut s = Shapes {
            series: Vec::new(),
            contact: Vec::new(),
            bases: Vec::new(),
            x_range: None,
            y_range: None,
        };
        let mut named = NamedOnce::default();
        for &i in picks {
            let p = &res.points[i];
            let Some(shape) = drawn_shape(r, res, p) else {
                continue;
            };
            let pts: Vec<(f64, f64)> = shape.iter().map(|(x, y)| (x * l, y * l)).collect();
            for q in &pts {
                let x = q.0 / l;
                let (lo, hi) = s.x_range.unwrap_or((f64::INFINITY, f64::NEG_INFINITY));
                s.x_range = Some((lo.min(x), hi.max(x)));
                let y = q.1 / l;
                let (lo, hi) = s.y_range.unwrap_or((f64::INFINITY, f64::NEG_INFINITY));
                s.y_range = Some((lo.min(y), hi.max(y)));
            }
            // a contact row is drawn as phase A unless it is phase B
            let phase = if p.phase == Phase::B {
                Phase::B
            } else {
                Phase::A
            };
            let name = named.name(phase, shape_name(phase));
            s.series.push(
                Series::new(name, pts, Style::Line)
                    .color(phase_color(phase))
                    .dash(phase_dash(phase)),
            );
            s.contact.push((p.xc * l, p.yc * l));
            s.bases.push((p.x0 * l, p.y0 * l));
        }
        s
    }
}

/// The contour between `a` and `b` (whisker lengths) below the height 1.25, in `l` units.
fn contour_line(contour: &Profile, (a, b): (f64, f64), l: f64) -> Vec<(f64, f64)> {
    let ymax = 1.25;
    (0..=400)
        .map(|i| {
            let x = a + (b - a) * i as f64 / 400.0;
            (x, contour.y(x))
        })
        .filter(|p| p.1.is_finite() && p.1 < ymax)
        .map(|(x, y)| (x * l, y * l))
        .collect()
}

/// The events marked at their contact points: first contact a triangle, the separation a
/// diamond, the switches between by turns.
/// The obstacle as drawn: a graph as its contour with the solid side above filled, a disc
/// as its whole circle filled inside, a peg as a dot.
fn obstacle_series(contour: &Profile, (a, b): (f64, f64), l: f64) -> Series {
    match *contour {
        Profile::Peg { x, y } => Series::new(
            "peg (a point obstacle)",
            vec![(x * l, y * l)],
            Style::Points,
        )
        .color(6)
        .marker(Marker::Circle),
        Profile::Disc { x, y, r } => {
            let pts = (0..=180)
                .map(|i| {
                    let t = std::f64::consts::TAU * i as f64 / 180.0;
                    ((x + r * t.cos()) * l, (y + r * t.sin()) * l)
                })
                .collect();
            Series::new("disc (solid inside)", pts, Style::Region).color(6)
        }
        _ => Series::new(
            "obstacle (solid above)",
            contour_line(contour, (a, b), l),
            Style::Obstacle,
        )
        .color(6),
    }
}

fn event_marks(chart: Chart, res: &SweepResult, events: &[SweepEvent], l: f64) -> Chart {
    let last = events.len().saturating_sub(1);
    events.iter().enumerate().fold(chart, |chart, (k, e)| {
        let p = &res.points[e.index];
        let (color, marker) = match k {
            0 => (2, Marker::Triangle),
            k if k == last => (3, Marker::Diamond),
            k => [
                (4, Marker::TriangleDown),
                (8, Marker::Square),
                (9, Marker::Circle),
            ][(k - 1) % 3],
        };
        chart.mark(
            Mark::point(p.xc * l, p.yc * l, e.label.clone(), color)
                .styled(MarkStyle::Marker(marker)),
        )
    })
}

/// The arrows below the base line: the sweep's direction from the first contact, and the
/// flow's, `(cos α, −sin α)`, if there is a flow.
fn direction_arrows(
    mut chart: Chart,
    res: &SweepResult,
    first_x0: f64,
    (lo, hi): (f64, f64),
    a: f64,
    l: f64,
) -> Chart {
    let span = (hi - lo).max(0.2);
    chart = chart.mark(Mark::arrow(
        (first_x0 + 0.05 * span) * l,
        -0.08 * l,
        -0.3 * span * l,
        0.0,
        "sweep (base → −x)",
        7,
    ));
    if res.q > 0.0 {
        // The flow's direction in the free space below the base line.
        let len = 0.15 * span;
        chart = chart.mark(Mark::arrow(
            (a + 0.02 * span) * l,
            -0.12 * l,
            len * res.alpha.cos() * l,
            -len * res.alpha.sin() * l,
            "flow direction",
            0,
        ));
    }
    chart
}

/// The whisker at the events and a few positions between them, with the obstacle, the
/// contact points and the sweep direction (thesis Fig. 5.7 style).
pub(crate) fn write_shapes_svg(
    r: &Resolved,
    contour: &Profile,
    res: &SweepResult,
    ctx: &FigureContext,
    path: &Path,
) -> Result<(), CliError> {
    let l = ctx.units.scale(Quantity::Length);
    let contact: Vec<usize> = (0..res.points.len())
        .filter(|&i| res.points[i].phase != Phase::None)
        .collect();
    let events = sweep_events(res);
    let shapes = Shapes::of(r, res, &picked_rows(&events, &contact), l);
    let Some((lo, hi)) = shapes.x_range else {
        return Ok(());
    };
    let (dlo, dhi) = contour.domain();
    let (a, b) = match contour {
        // a peg or a disc is drawn whole, wherever the whisker is
        Profile::Peg { .. } | Profile::Disc { .. } => (lo - 0.2, hi + 0.2),
        _ => ((lo - 0.2).max(dlo), (hi + 0.2).min(dhi)),
    };
    let turn = res.points.iter().any(|p| p.gamma != res.points[0].gamma);
    let title = if turn {
        "whisker shapes as the base turns (counter-clockwise)"
    } else {
        "whisker shapes along the sweep"
    };
    // The obstacle first (its solid side filled under everything else).
    let mut chart = Chart::new(
        title,
        ctx.units.label("x", Quantity::Length),
        ctx.units.label("y", Quantity::Length),
    )
    .equal_aspect()
    .note(format!("{}; {}", ctx.scene, ctx.units.describe()))
    .with(obstacle_series(contour, (a, b), l));
    for s in shapes.series {
        chart = chart.with(s);
    }
    chart = chart
        .with(
            Series::new("contact points", shapes.contact, Style::Points)
                .color(5)
                .marker(Marker::Circle),
        )
        .with(
            Series::new(
                if turn {
                    "base (fixed, turning)"
                } else {
                    "base positions"
                },
                shapes.bases,
                Style::Points,
            )
            .color(7)
            .marker(Marker::Square),
        );
    chart = event_marks(chart, res, &events, l);
    let first_x0 = contact.first().map_or(hi, |&i| res.points[i].x0);
    if !turn {
        chart = direction_arrows(chart, res, first_x0, (lo, hi), a, l);
    }
    // The figure's height follows the data (equal scales): whisker lengths above the base
    // line, the arrow below it; a turning base's fan as far as it reaches.
    let yspan = match shapes.y_range {
        Some((ylo, yhi)) if turn => (yhi - ylo + 0.3).max(0.5),
        _ => 1.4,
    };
    let (xspan, yspan) = ((b - a).max(0.5), yspan);
    let plot_w = 1000.0 - 380.0;
    let height = (plot_w * yspan / xspan + 170.0).clamp(420.0, 900.0) as u32;
    Ok(ctx.style.write_svg(&chart, path, (1000, height))?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_picked_rows_are_the_events_and_evenly_spaced_contact_rows() {
        let ev = |index: usize| SweepEvent {
            index,
            label: String::new(),
        };
        let contact: Vec<usize> = (10..30).collect();
        let picks = picked_rows(&[ev(10), ev(20), ev(29)], &contact);
        assert_eq!(picks, vec![10, 13, 16, 20, 23, 26, 29]);
        assert_eq!(picked_rows(&[], &[]), Vec::<usize>::new());
        assert_eq!(shape_name(Phase::B), "whisker, phase B (tangential)");
    }
}
