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

/// The abscissa of a sweep's figures: the base position x0 (scene's length unit) of a
/// translation, the turn gamma in degrees of a sweep that turns the base (whisking).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Abscissa {
    /// Whether the rows turn the base (gamma varies).
    pub turn: bool,
    /// The factor from the model's value (x0 dimensionless, gamma in rad) to the axis.
    pub scale: f64,
}

impl Abscissa {
    /// x0 in `units`, or gamma in degrees where the rows of `res` turn the base.
    pub fn of(res: &SweepResult, units: &UnitSystem) -> Self {
        let turn = res.points.iter().any(|p| p.gamma != res.points[0].gamma);
        Abscissa {
            turn,
            scale: if turn {
                180.0 / std::f64::consts::PI
            } else {
                units.scale(Quantity::Length)
            },
        }
    }

    /// The row's coordinate on the axis.
    pub fn at(&self, p: &contact_sim::SweepPoint) -> f64 {
        if self.turn {
            p.gamma * self.scale
        } else {
            p.x0 * self.scale
        }
    }

    /// The axis label.
    pub fn label(&self, units: &UnitSystem) -> String {
        if self.turn {
            "base turn γ [°]".to_string()
        } else {
            units.label("base x_0", Quantity::Length)
        }
    }
}

/// Series of `value` against x0, one per run of equal phase and slip state (coloured and
/// dashed by phase, heavy where stuck; runs touch so the curve is continuous, except at the
/// jump of a tangential first contact), only contact rows if `contact_only`. Each legend
/// text is given once.
fn phase_series(
    res: &SweepResult,
    x: Abscissa,
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
        let mut pts: Vec<(f64, f64)> = rows[i..j].iter().map(|p| (x.at(p), value(p))).collect();
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
            pts.push((x.at(rows[j]), v));
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
fn event_marks(res: &SweepResult, x: Abscissa) -> Vec<Mark> {
    let mut marks: Vec<Mark> = sweep_events(res)
        .into_iter()
        .map(|e| Mark::vline(x.at(&res.points[e.index]), e.label, 6))
        .collect();
    marks.extend(
        friction_switches(res)
            .into_iter()
            .map(|s| Mark::vline(x.at(&res.points[s.index]), friction_label(s.event.kind), 4)),
    );
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
    let x = Abscissa::of(res, u);
    let x_label = x.label(u);
    let marks = event_marks(res, x);
    let mut charts = vec![
        chart_of(
            "horizontal base force",
            &u.label("A_x", Quantity::Force),
            phase_series(res, x, |p| p.ax * fs, false),
            &x_label,
            &marks,
        ),
        chart_of(
            "vertical base force",
            &u.label("A_y", Quantity::Force),
            phase_series(res, x, |p| p.ay * fs, false),
            &x_label,
            &marks,
        ),
        chart_of(
            "base moment",
            &u.label("M_A", Quantity::Moment),
            phase_series(res, x, |p| p.ma * ms, false),
            &x_label,
            &marks,
        ),
    ];
    if !ctx.rigid && phi0_varies(res) {
        charts.push(chart_of(
            "base angle",
            &u.label("φ_0", Quantity::Angle),
            phase_series(res, x, |p| p.phi0, false),
            &x_label,
            &marks,
        ));
    }
    let motion = if x.turn {
        let p = &res.points[0];
        format!(
            "the base at ({}, {}) turns counter-clockwise (γ rising, left to right)",
            vibrissa_io::units::round_sig(p.x0 * l),
            vibrissa_io::units::round_sig(p.y0 * l)
        )
    } else {
        "the base moves towards −x (right to left)".to_string()
    };
    let mut note = format!("{}; {motion}; {}", ctx.scene, u.describe());
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
                phase_series(res, x, |p| p.f * fs, true),
                &x_label,
                &marks,
            )
            .y_from_zero(),
            chart_of(
                "contact on the whisker",
                &u.label("s_1", Quantity::Length),
                phase_series(res, x, |p| p.s1 * l, true),
                &x_label,
                &marks,
            ),
            chart_of(
                "contact on the obstacle",
                &u.label("x_c", Quantity::Length),
                phase_series(res, x, |p| p.xc * l, true),
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
        let x = Abscissa {
            turn: false,
            scale: 1.0,
        };
        assert_eq!(Abscissa::of(&res, &UnitSystem::DIMENSIONLESS), x);
        let series = phase_series(&res, x, |p| p.ax, false);
        let end = *series[0].points.last().unwrap();
        assert_eq!(end, (touch.x0, free.ax), "the free run ends at the jump");
        assert_eq!(series[1].points[0], (touch.x0, touch.ax));
        // Elsewhere the runs touch: the contact runs share their switch rows.
        for w in series[1..].windows(2) {
            assert_eq!(w[0].points.last(), w[1].points.first());
        }
    }
}
