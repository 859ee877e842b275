//! The figures of a sweep's observables: `observables.svg` (the base observables against
//! x0) and `contact.svg` (contact force and point), one line per run of equal phase (and,
//! with friction, of equal slip state: stuck rows heavy, sliding rows thin), the events and
//! the stick/slip switches marked.

use std::path::PathBuf;

use contact_sim::{Phase, SlipState, SweepResult};

use crate::commands::phases::{phase_color, phase_dash, phase_name};
use crate::commands::sweep_events::{friction_label, friction_switches, sweep_events};
use crate::error::CliError;
use crate::plot::{Chart, FigureStyle, Heading, Mark, Series, Style};
use crate::units::{Quantity, UnitSystem};

/// The line width of a slip state, a multiple of the standard: stuck rows heavy (2.4),
/// sliding and frictionless rows standard, so that stick and slip differ in greyscale and
/// on top of the phase's colour and dash.
pub fn slip_width(s: SlipState) -> f64 {
    match s {
        SlipState::Stick => 2.4,
        SlipState::Slip | SlipState::None => 1.0,
    }
}

/// The legend text of a run: the phase's name, with `, stick` or `, slip` in a frictional
/// sweep.
fn run_name(phase: Phase, slip: SlipState) -> String {
    match slip {
        SlipState::None => phase_name(phase).to_string(),
        s => format!(
            "{}, {} ({})",
            phase_name(phase),
            s.label(),
            match s {
                SlipState::Stick => "heavy line",
                _ => "thin line",
            }
        ),
    }
}

/// Series of `value` against x0, one per run of equal phase and slip state (coloured and
/// dashed by phase, heavy where stuck; runs touch so the curve is continuous, except at the
/// jump of a tangential first contact), only contact rows if `contact_only`. Each legend
/// text is given once.
fn phase_series(
    res: &SweepResult,
    x_scale: f64,
    value: impl Fn(&contact_sim::SweepPoint) -> f64,
    contact_only: bool,
) -> Vec<Series> {
    let rows: Vec<_> = res
        .points
        .iter()
        .filter(|p| !contact_only || p.phase != Phase::None)
        .collect();
    let mut out: Vec<Series> = Vec::new();
    let mut named: Vec<String> = Vec::new();
    let mut i = 0;
    while i < rows.len() {
        let (phase, slip) = (rows[i].phase, rows[i].slip);
        let mut j = i;
        while j < rows.len() && rows[j].phase == phase && rows[j].slip == slip {
            j += 1;
        }
        let mut pts: Vec<(f64, f64)> = rows[i..j]
            .iter()
            .map(|p| (p.x0 * x_scale, value(p)))
            .collect();
        if j < rows.len() {
            // At a tangential first contact the observables jump (the flow beyond s1 is
            // dropped): the free whisker's values run on to that x0, and no line joins them
            // to the contact's.
            let jump =
                phase == Phase::None && res.first_contact == contact_sim::FirstContact::Tangential;
            let v = if jump {
                value(rows[j - 1])
            } else {
                value(rows[j])
            };
            pts.push((rows[j].x0 * x_scale, v));
        }
        let mut name = run_name(phase, slip);
        if named.contains(&name) {
            name.clear();
        } else {
            named.push(name.clone());
        }
        let mut series = Series::new(name, pts, Style::Line)
            .color(phase_color(phase))
            .dash(phase_dash(phase));
        if slip != SlipState::None {
            series = series.width(slip_width(slip));
        }
        out.push(series);
        i = j;
    }
    out
}

/// The event lines of a sweep: its events ([`sweep_events`]) and its stick/slip switches
/// ([`friction_switches`], labelled `stick→slip`, `slip→stick`).
fn event_marks(res: &SweepResult, x_scale: f64) -> Vec<Mark> {
    let mut marks: Vec<Mark> = sweep_events(res)
        .into_iter()
        .map(|e| Mark::vline(res.points[e.index].x0 * x_scale, e.label, 6))
        .collect();
    marks.extend(friction_switches(res).into_iter().map(|s| {
        Mark::vline(
            res.points[s.index].x0 * x_scale,
            friction_label(s.event.kind),
            4,
        )
    }));
    marks
}

fn chart_of(
    title: &str,
    y_label: &str,
    series: Vec<Series>,
    x_label: &str,
    marks: &[Mark],
) -> Chart {
    let mut c = Chart::new(title, x_label, y_label);
    for s in series {
        c = c.with(s);
    }
    for m in marks {
        c = c.mark(m.clone());
    }
    c
}

/// What the figures of a sweep need to know besides the rows.
#[derive(Debug, Clone)]
pub struct FigureContext {
    /// The unit system of the axes.
    pub units: UnitSystem,
    /// Names the scene in the titles, e.g. `contour g1, q = 5`.
    pub scene: String,
    /// A rigid support: phi0 is pi/2 throughout and its panel is left out.
    pub rigid: bool,
    /// How the figures are written (`--size`, `--figures`).
    pub style: FigureStyle,
}

/// Whether phi0 varies beyond rounding over the rows.
fn phi0_varies(res: &SweepResult) -> bool {
    let (lo, hi) = res
        .points
        .iter()
        .map(|p| p.phi0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    hi - lo > 1e-8
}

/// Writes the figures of a sweep into `dir` (staging paths), as `ctx.style` says:
/// `observables.svg` (Ax, Ay, MA and, unless the support is rigid, phi0 against x0, thesis
/// Figs. 5.9/5.10) and `contact.svg` (f and s1 against x0, Fig. 5.11), with the events
/// marked. Returns the SVG file names written.
pub fn write_sweep_figures(
    res: &SweepResult,
    ctx: &FigureContext,
    path_for: impl Fn(&str) -> PathBuf,
) -> Result<Vec<&'static str>, CliError> {
    let u = &ctx.units;
    let (l, fs, ms) = (
        u.scale(Quantity::Length),
        u.scale(Quantity::Force),
        u.scale(Quantity::Moment),
    );
    let x_label = u.label("base x_0", Quantity::Length);
    let marks = event_marks(res, l);
    let mut charts = vec![
        chart_of(
            "horizontal base force",
            &u.label("A_x", Quantity::Force),
            phase_series(res, l, |p| p.ax * fs, false),
            &x_label,
            &marks,
        ),
        chart_of(
            "vertical base force",
            &u.label("A_y", Quantity::Force),
            phase_series(res, l, |p| p.ay * fs, false),
            &x_label,
            &marks,
        ),
        chart_of(
            "base moment",
            &u.label("M_A", Quantity::Moment),
            phase_series(res, l, |p| p.ma * ms, false),
            &x_label,
            &marks,
        ),
    ];
    if !ctx.rigid && phi0_varies(res) {
        charts.push(chart_of(
            "base angle",
            &u.label("φ_0", Quantity::Angle),
            phase_series(res, l, |p| p.phi0, false),
            &x_label,
            &marks,
        ));
    }
    let mut note = format!(
        "{}; the base moves towards −x (right to left); {}",
        ctx.scene,
        u.describe()
    );
    if charts.len() == 3 {
        note += "; φ_0 = π/2 throughout (rigid support, no panel)";
    }
    let heading = Heading {
        title: "Base observables along the sweep".to_string(),
        note: note.clone(),
    };
    let (cols, size) = if charts.len() == 4 {
        (2, (1100, 860))
    } else {
        (3, (1500, 480))
    };
    let observables_path = path_for("observables.svg");
    let observables = || -> Result<(), CliError> {
        Ok(ctx
            .style
            .write_panels_with_heading(&charts, cols, &heading, &observables_path, size)?)
    };
    let mut written = vec!["observables.svg"];
    let has_contact = res.contact_points().next().is_some();
    let contact = || -> Result<(), CliError> {
        if !has_contact {
            return Ok(());
        }
        let charts = [
            chart_of(
                "contact force",
                &u.label("f", Quantity::Force),
                phase_series(res, l, |p| p.f * fs, true),
                &x_label,
                &marks,
            )
            .y_from_zero(),
            chart_of(
                "contact on the whisker",
                &u.label("s_1", Quantity::Length),
                phase_series(res, l, |p| p.s1 * l, true),
                &x_label,
                &marks,
            ),
            chart_of(
                "contact on the obstacle",
                &u.label("x_c", Quantity::Length),
                phase_series(res, l, |p| p.xc * l, true),
                &x_label,
                &marks,
            ),
        ];
        let heading = Heading {
            title: "Contact force and contact point along the sweep".to_string(),
            note,
        };
        Ok(ctx.style.write_panels_with_heading(
            &charts,
            3,
            &heading,
            &path_for("contact.svg"),
            (1500, 480),
        )?)
    };
    crate::plot::both(observables, contact)?;
    if has_contact {
        written.push("contact.svg");
    }
    Ok(written)
}
#[cfg(test)]
mod tests {
    use super::*;
    use beam_model::{FluidLoad, Whisker};
    use contact_sim::{FirstContact, Profile, SweepSettings};

    /// Thesis case 2 (conical whisker past g1 under q = 5): the first contact is
    /// tangential and the observables jump there (the flow beyond s1 is dropped). The free
    /// whisker's run of Ax ends at that x0 with its own value, and the contact run starts
    /// from the contact's: no line joins the two.
    #[test]
    fn a_tangential_first_contact_is_drawn_as_a_jump() {
        let w = Whisker::new(0.5, 0.0, 0.0, f64::INFINITY);
        let settings = SweepSettings {
            points: 40,
            ..SweepSettings::default()
        };
        let res = contact_sim::sweep(
            &w,
            FluidLoad { q: 5.0, alpha: 0.0 },
            &Profile::g1(),
            &settings,
        )
        .unwrap();
        assert_eq!(res.first_contact, FirstContact::Tangential);
        let first = res
            .points
            .iter()
            .position(|p| p.phase != Phase::None)
            .unwrap();
        let (free, touch) = (&res.points[first - 1], &res.points[first]);
        assert!(
            (touch.ax - free.ax).abs() > 0.1,
            "no jump: {} {}",
            free.ax,
            touch.ax
        );
        let series = phase_series(&res, 1.0, |p| p.ax, false);
        let end = *series[0].points.last().unwrap();
        assert_eq!(end, (touch.x0, free.ax), "the free run ends at the jump");
        assert_eq!(series[1].points[0], (touch.x0, touch.ax));
        // Elsewhere the runs touch: the contact runs share their switch rows.
        for w in series[1..].windows(2) {
            assert_eq!(w[0].points.last(), w[1].points.first());
        }
    }
}
