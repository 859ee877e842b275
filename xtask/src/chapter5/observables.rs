//! The observables of the chapter-5 sweeps against the base position x0 (Figs. 5.9-5.43,
//! 5.46): base forces A_x, A_y, base moment M_A, base angle φ_0, loaded arc length s_1 and
//! contact force f, one curve per case of a group; the observables CSV of every sweep and
//! the per-case table of contact phases.

use contact_sim::{FirstContact, Phase, Separation, SweepPoint, SweepResult};
use vibrissa_io::atomic::OutputDir;
use vibrissa_io::csvio::CsvWriter;
use vibrissa_plot::{Chart, Dash, Marker, Series, Style};

use super::style::{figure, phase_style, pretty_label};
use crate::captions::caption;
use crate::common::{self, fig_stem, md_table, note_err, sig, Layout, SweepRun, SWEEP_POINTS};
use crate::{Entry, Report};

/// The observables CSV of a sweep (`x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi`), as the CLI
/// writes it.
fn sweep_csv(points: &[SweepPoint]) -> CsvWriter {
    vibrissa_io::observables::observables_csv(points)
        .unwrap_or_else(|_| CsvWriter::new(&vibrissa_io::observables::OBSERVABLES_HEADER))
}

/// How the contact began, with the phase it began in: `tip (A)`, `tangential (B)`.
fn first_contact_name(f: FirstContact) -> String {
    format!("{} ({})", f.label(), f.phase().letter())
}

/// How the contact ended ([`Separation`]'s name), with the contour point of a second contact.
fn separation_name(s: &Separation) -> String {
    match s {
        Separation::MultiContact { xc } => format!("{s} at xc = {}", sig(*xc, 4)),
        _ => s.to_string(),
    }
}

type Obs = fn(&SweepPoint) -> f64;

const QUANTITIES: [(&str, Obs); 6] = [
    ("Ax", |p| p.ax),
    ("Ay", |p| p.ay),
    ("MA", |p| p.ma),
    ("phi0", |p| p.phi0),
    ("s1", |p| p.s1),
    ("f", |p| p.f),
];

/// The axis label (symbol and unit; the thesis's variables are dimensionless) of a quantity.
fn axis_label(name: &str) -> &'static str {
    match name {
        "Ax" => "horizontal base force A_x [–]",
        "Ay" => "vertical base force A_y [–]",
        "MA" => "base moment M_A [–]",
        "phi0" => "base angle φ_0 [rad]",
        "s1" => "loaded arc length s_1 [–]",
        _ => "contact force f [–]",
    }
}

/// Whether quantity `q` stays constant (to rounding) over every sweep of the group, as phi0
/// does on a rigid support: such a panel says nothing and is left out.
fn constant_over(group: &[&SweepRun], q: usize) -> bool {
    group.iter().all(|r| match &r.result {
        Ok(s) => {
            let (lo, hi) = finite_range(&s.points, q);
            hi - lo <= 1e-8
        }
        Err(_) => true,
    })
}

/// The smallest and largest finite value of quantity `q` along a sweep (`(∞, −∞)` if none).
fn finite_range(points: &[SweepPoint], q: usize) -> (f64, f64) {
    points
        .iter()
        .map(QUANTITIES[q].1)
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        })
}

/// The symbol of a quantity as a panel title (plot-label markup: `A_x` sets x as a subscript).
fn symbol(name: &str) -> &'static str {
    match name {
        "Ax" => "A_x",
        "Ay" => "A_y",
        "MA" => "M_A",
        "phi0" => "φ_0",
        "s1" => "s_1",
        _ => "f",
    }
}

/// The x axis of every observables panel.
const X0_LABEL: &str = "base position x_0 [–]";

/// The line of the i-th case of a group, as the thesis captions give them (continuous,
/// dashed, dotted, dash-dotted, grey), with a marker shape of its own so that the cases also
/// differ in greyscale print: `(colour, dash, marker)`.
fn case_style(i: usize) -> (usize, Dash, Marker) {
    const STYLES: [(usize, Dash, Marker); 5] = [
        (0, Dash::Solid, Marker::Circle),
        (1, Dash::Dashed, Marker::Square),
        (2, Dash::Dotted, Marker::Triangle),
        (3, Dash::DashDot, Marker::Diamond),
        (7, Dash::LongDash, Marker::TriangleDown),
    ];
    STYLES[i % STYLES.len()]
}

/// Markers along a curve: about this many per series.
const MARKERS_PER_SERIES: usize = 9;

/// The points of `get` against x0 along a sweep, as a line: where a tangential first
/// contact makes the observables jump (the flow beyond s1 is dropped), the free whisker's
/// value runs on to the contact's x0 and no line joins it to the contact's value (as the
/// CLI's sweep figures draw it).
fn sweep_line(s: &SweepResult, get: Obs) -> Vec<(f64, f64)> {
    let mut pts = Vec::with_capacity(s.points.len() + 2);
    for (i, p) in s.points.iter().enumerate() {
        if i > 0 {
            let prev = &s.points[i - 1];
            if s.first_contact == FirstContact::Tangential
                && prev.phase == Phase::None
                && p.phase != Phase::None
            {
                pts.push((p.x0, get(prev)));
                pts.push((f64::NAN, f64::NAN));
            }
        }
        pts.push((p.x0, get(p)));
    }
    pts
}

/// An empty panel of quantity `q` against x0, titled `title: symbol` (the contact force
/// from zero up).
fn quantity_chart(q: usize, title: &str) -> Chart {
    let name = QUANTITIES[q].0;
    let c = Chart::new(
        format!("{title}: {}", symbol(name)),
        X0_LABEL,
        axis_label(name),
    );
    if name == "f" {
        c.y_from_zero()
    } else {
        c
    }
}

/// Quantity `q` of every sweep of a group against x0, one line and sparse markers per case.
fn chart_of(group: &[&SweepRun], q: usize, title: &str) -> Chart {
    let get = QUANTITIES[q].1;
    let mut c = quantity_chart(q, title);
    let n = group.len().max(1);
    for (i, r) in group.iter().enumerate() {
        if let Ok(s) = &r.result {
            let (color, dash, marker) = case_style(i);
            let pts = sweep_line(s, get);
            // Sparse markers, evenly spread in x0 (the rows crowd where the sweep refines
            // its step) and staggered between the cases so that they do not sit on each
            // other; drawn as isolated points: the line itself carries no name, the marker
            // series carries the legend entry (line sample and marker).
            let rows: Vec<(f64, f64)> = s
                .points
                .iter()
                .map(|p| (p.x0, get(p)))
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            let (lo, hi) = rows
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p.0), b.max(p.0))
                });
            let mut picked: Vec<usize> = Vec::new();
            for m in 0..MARKERS_PER_SERIES {
                let t = (m as f64 + (i as f64 + 0.5) / n as f64) / MARKERS_PER_SERIES as f64;
                let target = lo + (hi - lo) * t;
                let nearest = (0..rows.len()).min_by(|&a, &b| {
                    (rows[a].0 - target)
                        .abs()
                        .total_cmp(&(rows[b].0 - target).abs())
                });
                if let Some(j) = nearest {
                    if !picked.contains(&j) {
                        picked.push(j);
                    }
                }
            }
            let marks: Vec<(f64, f64)> = picked
                .iter()
                .flat_map(|&j| [rows[j], (f64::NAN, f64::NAN)])
                .collect();
            c.series
                .push(Series::new("", pts, Style::Line).color(color).dash(dash));
            c.series.push(
                Series::new(pretty_label(&r.case.label), marks, Style::LinePoints)
                    .color(color)
                    .dash(dash)
                    .marker(marker),
            );
        }
    }
    c
}

/// One sweep's observable against x0, one series per run of equal phase in the house style
/// (runs joined, except across the jump at a tangential first contact).
fn phase_chart(s: &SweepResult, q: usize, title: &str) -> Chart {
    let get = QUANTITIES[q].1;
    let mut c = quantity_chart(q, title);
    let mut named = [false; 3];
    let mut end = 0;
    for run in s.points.chunk_by(|a, b| a.phase == b.phase) {
        end += run.len();
        let phase = run[0].phase;
        let mut pts: Vec<(f64, f64)> = run.iter().map(|p| (p.x0, get(p))).collect();
        // The run reaches to the next one's first x0: with its own last value across the
        // jump at a tangential first contact, else with the next run's first value.
        if let (Some(next), Some(last)) = (s.points.get(end), run.last()) {
            let jump = phase == Phase::None && s.first_contact == FirstContact::Tangential;
            pts.push((next.x0, get(if jump { last } else { next })));
        }
        let (k, color, dash, label) = phase_style(phase);
        let name = if named[k] { "" } else { label };
        named[k] = true;
        c.series
            .push(Series::new(name, pts, Style::Line).color(color).dash(dash));
    }
    c
}

/// Writes the sweeps' CSVs (once, listed in `entry`) and the per-case table.
fn sweep_files_and_table(out: &OutputDir, entry: &mut Entry, group: &[&SweepRun]) {
    let mut rows = Vec::new();
    for r in group {
        match &r.result {
            Ok(s) => {
                let name = r.csv_name();
                let res = common::csv(out, entry, &name, &sweep_csv(&s.points));
                note_err(entry, &name, res);
                rows.push(vec![
                    r.case.label.clone(),
                    first_contact_name(s.first_contact),
                    separation_name(&s.separation),
                    s.phase_pattern(),
                    s.points.len().to_string(),
                    format!("{:.2}", r.seconds),
                ]);
            }
            Err(e) => {
                entry.fail(format!("sweep {}: {e}", r.name()));
                rows.push(vec![
                    r.case.label.clone(),
                    "failed".to_string(),
                    e.clone(),
                    "-".to_string(),
                    "0".to_string(),
                    format!("{:.2}", r.seconds),
                ]);
            }
        }
    }
    entry.block(md_table(
        &[
            "case",
            "first contact",
            "separation",
            "phases",
            "rows",
            "time [s]",
        ],
        &rows,
    ));
}

/// Figs. of one group (a case on one contour): A_x/A_y, M_A/φ_0 and s_1/f against x0,
/// the first with the sweeps' CSVs and table, the others with the extremes per case.
pub(super) fn observables(
    out: &OutputDir,
    report: &mut Report,
    group: &[&SweepRun],
    figs: [&str; 3],
    case: &str,
    profile: &str,
) {
    let title = format!("case {case} ({profile})");
    for (k, fig) in figs.iter().enumerate() {
        let entry = report.entry(*fig, caption(fig));
        if group.is_empty() {
            entry.fail(format!("no sweep cases for {title}"));
            continue;
        }
        // A constant panel (phi0 on a rigid support) is left out; the other says why.
        let mut charts = Vec::new();
        let mut constant = Vec::new();
        for q in [2 * k, 2 * k + 1] {
            if constant_over(group, q) {
                constant.push(QUANTITIES[q].0);
            } else {
                charts.push(chart_of(group, q, &title));
            }
        }
        let note = constant
            .iter()
            .map(|&q| {
                let sym = symbol(q);
                match q {
                    "phi0" => "φ_0 = π/2 throughout (rigid support): no φ_0 panel".to_string(),
                    "s1" => "s_1 = 1 throughout (tip contact only): no s_1 panel".to_string(),
                    _ => format!("{sym} constant: no {sym} panel"),
                }
            })
            .collect::<Vec<_>>()
            .join("; ");
        let stem = fig_stem(fig);
        if charts.is_empty() {
            entry.fail(format!("{stem}: {note}"));
        } else {
            // Two panels side by side across the page; a lone panel, one column wide.
            let lone = charts.len() == 1;
            let size = if lone { (560, 420) } else { (1120, 420) };
            let layout = Layout {
                cols: 2,
                size,
                title: "",
                note: &note,
            };
            let r = figure(out, entry, &format!("{stem}.svg"), &charts, &layout, lone);
            note_err(entry, &stem, r);
        }
        if k == 0 {
            entry.number(
                "sweep",
                format!("{SWEEP_POINTS} contact points per sweep, q at alpha = 0"),
                None,
            );
            sweep_files_and_table(out, entry, group);
        } else {
            for r in group {
                if r.result.is_ok() {
                    entry.file(out.path_for(&r.csv_name()));
                }
            }
            // Key numbers: the extremes of the two quantities per case.
            for r in group {
                if let Ok(s) = &r.result {
                    let ext = |q: usize| {
                        let (lo, hi) = finite_range(&s.points, q);
                        format!("{}: {}..{}", QUANTITIES[q].0, sig(lo, 4), sig(hi, 4))
                    };
                    entry.number(
                        r.case.label.clone(),
                        format!("{}; {}", ext(2 * k), ext(2 * k + 1)),
                        None,
                    );
                }
            }
        }
    }
}

/// Fig. 5.46-like: all six observables of the ge sweep (simulation only).
pub(super) fn observables_all(out: &OutputDir, report: &mut Report, group: &[&SweepRun]) {
    let entry = report.entry(
        "5.46",
        format!(
            "{} — simulated observables only (the experimental data of Will et al. 2016 \
             are not part of this project).",
            caption("5.46")
        ),
    );
    if group.is_empty() {
        entry.fail("no ge sweep case");
        return;
    }
    // One sweep: the phases in the house style; a constant φ_0 (rigid support, rounding
    // noise only) gets no panel.
    let mut charts = Vec::new();
    let mut note = String::new();
    for r in group {
        if let Ok(s) = &r.result {
            for (q, &(name, _)) in QUANTITIES.iter().enumerate() {
                if constant_over(std::slice::from_ref(r), q) {
                    if name == "phi0" {
                        note = "φ_0 = π/2 throughout (rigid support): no φ_0 panel".into();
                    }
                    continue;
                }
                let title = format!("ge, {}", pretty_label(&r.case.label));
                charts.push(phase_chart(s, q, &title));
            }
            break;
        }
    }
    if charts.is_empty() {
        entry.fail("the ge sweep failed");
    } else {
        let layout = Layout {
            cols: 3,
            size: (1680, 840),
            title: "",
            note: &note,
        };
        let r = figure(out, entry, "fig5_46.svg", &charts, &layout, false);
        note_err(entry, "fig5_46", r);
    }
    sweep_files_and_table(out, entry, group);
}
