//! Chapter 5: the sweeps of every case past its contour (Figs. 5.8-5.44), as observables
//! against the base position x0, scene sketches and one observables CSV per sweep.

use beam_model::{shape_from_tip_angle, Loads, Scene};
use contact_sim::phase::contact_loads;
use contact_sim::{FirstContact, Phase, Separation, SweepPoint};
use vibrissa_cli::atomic::OutputDir;
use vibrissa_cli::csvio::{Cell, CsvWriter};
use vibrissa_cli::plot::{
    size_for_this_thread, write_panels_with_heading, Chart, Dash, FigureSize, Heading, Marker,
    Series, Style,
};

use crate::captions::caption;
use crate::common::{self, md_table, note_err, sig, Ctx, SweepRun, SWEEP_POINTS};
use crate::{Entry, Failure, Report};

/// The observables figures: `(case, profile, [Ax/Ay fig, MA/phi0 fig, s1/f fig])`.
pub const GROUPS: [(&str, &str, [&str; 3]); 11] = [
    ("1", "g1", ["5.9", "5.10", "5.11"]),
    ("1", "g2", ["5.12", "5.13", "5.14"]),
    ("2", "g1", ["5.15", "5.16", "5.17"]),
    ("2", "g2", ["5.18", "5.19", "5.20"]),
    ("3", "g1", ["5.22", "5.23", "5.24"]),
    ("3", "g2", ["5.25", "5.26", "5.27"]),
    ("4A", "g1", ["5.28", "5.29", "5.30"]),
    ("4A", "g2", ["5.31", "5.32", "5.33"]),
    ("4B", "g2", ["5.35", "5.36", "5.37"]),
    ("5", "g1", ["5.38", "5.39", "5.40"]),
    ("5", "g2", ["5.41", "5.42", "5.43"]),
];

/// Runs chapter 5.
pub fn run(out: &OutputDir, report: &mut Report, ctx: &mut Ctx) -> Result<(), Failure> {
    common::step(5, 1, 2, "the chapter-5 sweeps");
    let runs = ctx.sweeps().to_vec();
    common::step(5, 2, 2, "figures and tables of the sweeps");
    // Fig. 5.8: case 1 on g1, q = 5.
    sketch(out, report, "5.8", &runs, |r| {
        r.case.case == "1" && r.case.profile_name == "g1" && r.case.label == "q=5"
    });
    for (case, profile, figs) in GROUPS {
        let group: Vec<&SweepRun> = runs
            .iter()
            .filter(|r| r.case.case == case && r.case.profile_name == profile)
            .collect();
        if case == "3" && profile == "g1" {
            sketch(out, report, "5.21", &runs, |r| {
                r.case.case == "3" && r.case.profile_name == "g1" && r.case.label == "k=5"
            });
        }
        if case == "4B" {
            sketch(out, report, "5.34", &runs, |r| {
                r.case.case == "4B" && r.case.label != "A=0 B=0"
            });
        }
        observables(out, report, &group, figs, case, profile);
    }
    // The experimental contour ge (q = 0): Fig. 5.44 (contour, with the sweep) and the
    // simulated observables of Fig. 5.46.
    sketch(out, report, "5.44", &runs, |r| r.case.case == "exp");
    let exp: Vec<&SweepRun> = runs.iter().filter(|r| r.case.case == "exp").collect();
    observables_all(out, report, &exp);
    Ok(())
}

/// The observables CSV of a sweep (`x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi`), as the CLI
/// writes it.
fn sweep_csv(points: &[SweepPoint]) -> CsvWriter {
    vibrissa_cli::commands::observables_csv(points)
        .unwrap_or_else(|_| CsvWriter::new(&vibrissa_cli::commands::OBSERVABLES_HEADER))
}

fn first_contact_name(f: FirstContact) -> &'static str {
    match f {
        FirstContact::Tip => "tip (A)",
        FirstContact::Tangential => "tangential (B)",
    }
}

fn separation_name(s: &Separation) -> String {
    match s {
        Separation::Snap => "snap".to_string(),
        Separation::Release => "release".to_string(),
        Separation::MultiContact { xc } => format!("multi-contact at xc = {}", sig(*xc, 4)),
        Separation::EndOfContour => "end of contour".to_string(),
        Separation::ContactAtBase => "contact at the base".to_string(),
        Separation::NotReached { steps } => format!("not reached within {steps} steps"),
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
    let get = QUANTITIES[q].1;
    group.iter().all(|r| match &r.result {
        Ok(s) => {
            let (lo, hi) = s
                .points
                .iter()
                .map(get)
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                });
            hi - lo <= 1e-8
        }
        Err(_) => true,
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

/// A legend label for a case label: `q=5` → `q = 5`, `theta=0.5 k=inf` → `ϑ = 0.5, k = ∞`,
/// `A=0 B=-0.5` → `A = 0, B = −0.5`.
fn pretty_label(label: &str) -> String {
    label
        .split_whitespace()
        .map(|part| match part.split_once('=') {
            Some((name, value)) => {
                let name = if name == "theta" { "ϑ" } else { name };
                let value = match value {
                    "inf" => "∞".to_string(),
                    "-inf" => "−∞".to_string(),
                    v => v.replacen('-', "−", 1),
                };
                format!("{name} = {value}")
            }
            None => part.to_string(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

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
fn sweep_line(s: &contact_sim::SweepResult, get: Obs) -> Vec<(f64, f64)> {
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

fn chart_of(group: &[&SweepRun], q: usize, title: &str) -> Chart {
    let (name, get) = QUANTITIES[q];
    let mut c = Chart::new(
        format!("{title}: {}", symbol(name)),
        X0_LABEL,
        axis_label(name),
    );
    if name == "f" {
        c = c.y_from_zero();
    }
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

/// The colour, dash and legend text of a contact phase (the CLI's house style: no contact
/// dotted grey, phase A solid blue, phase B dashed orange).
fn phase_style(p: Phase) -> (usize, usize, Dash, &'static str) {
    match p {
        Phase::None => (0, 7, Dash::Dotted, "no contact"),
        Phase::A => (1, 0, Dash::Solid, "phase A (tip)"),
        Phase::B => (2, 1, Dash::Dashed, "phase B (tangential)"),
    }
}

/// One sweep's observable against x0, one series per run of equal phase in the house style
/// (runs joined, except across the jump at a tangential first contact).
fn phase_chart(s: &contact_sim::SweepResult, q: usize, title: &str) -> Chart {
    let (name, get) = QUANTITIES[q];
    let mut c = Chart::new(
        format!("{title}: {}", symbol(name)),
        X0_LABEL,
        axis_label(name),
    );
    if name == "f" {
        c = c.y_from_zero();
    }
    let rows = &s.points;
    let mut named = [false; 3];
    let mut i = 0;
    while i < rows.len() {
        let phase = rows[i].phase;
        let mut j = i;
        while j < rows.len() && rows[j].phase == phase {
            j += 1;
        }
        let mut pts: Vec<(f64, f64)> = rows[i..j].iter().map(|p| (p.x0, get(p))).collect();
        if j < rows.len() {
            let jump = phase == Phase::None && s.first_contact == FirstContact::Tangential;
            let v = if jump {
                get(&rows[j - 1])
            } else {
                get(&rows[j])
            };
            pts.push((rows[j].x0, v));
        }
        let (k, color, dash, label) = phase_style(phase);
        let name = if named[k] { "" } else { label };
        named[k] = true;
        c.series
            .push(Series::new(name, pts, Style::Line).color(color).dash(dash));
        i = j;
    }
    c
}

/// Writes `charts` as one figure `name` (SVG and PNG), `cols` panels a row, with one key for
/// all panels above them (the first chart's legend) and `note` under it; records the file.
/// With `column`, the figure is one journal column wide instead of the page.
#[allow(clippy::too_many_arguments)]
fn figure(
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    charts: &[Chart],
    cols: usize,
    size: (u32, u32),
    note: &str,
    column: bool,
) -> Result<(), String> {
    let _width = column.then(|| size_for_this_thread(FigureSize::Column));
    let path = out.path_for(name);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
    }
    let heading = Heading {
        title: String::new(),
        note: note.to_string(),
    };
    write_panels_with_heading(charts, cols, &heading, &path, size).map_err(|e| e.to_string())?;
    entry.file(path);
    Ok(())
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
                    first_contact_name(s.first_contact).to_string(),
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

fn observables(
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
        let stem = format!("fig{}", fig.replace('.', "_"));
        if charts.is_empty() {
            entry.fail(format!("{stem}: {note}"));
        } else {
            // Two panels side by side across the page; a lone panel, one column wide.
            let lone = charts.len() == 1;
            let size = if lone { (560, 420) } else { (1120, 420) };
            let r = figure(
                out,
                entry,
                &format!("{stem}.svg"),
                &charts,
                2,
                size,
                &note,
                lone,
            );
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
                        let get = QUANTITIES[q].1;
                        let (lo, hi) = s
                            .points
                            .iter()
                            .map(get)
                            .filter(|v| v.is_finite())
                            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                                (a.min(v), b.max(v))
                            });
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
fn observables_all(out: &OutputDir, report: &mut Report, group: &[&SweepRun]) {
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
        let r = figure(
            out,
            entry,
            "fig5_46.svg",
            &charts,
            3,
            (1680, 840),
            &note,
            false,
        );
        note_err(entry, "fig5_46", r);
    }
    sweep_files_and_table(out, entry, group);
}

/// A scene sketch: the contour and the whisker at several base positions of each sweep
/// selected by `pick` (one panel per sweep).
fn sketch(
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
        // Shapes: the last pre-contact row and 7 contact rows evenly spread.
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
        for &i in &idx {
            let p = &s.points[i];
            let loads = if p.phase == Phase::None {
                Loads::fluid(r.case.q, 0.0)
            } else {
                contact_loads(
                    beam_model::FluidLoad {
                        q: r.case.q,
                        alpha: 0.0,
                    },
                    p.psi,
                    p.f.max(0.0),
                    p.s1,
                )
            };
            let scene = Scene::new(r.case.whisker, loads);
            let sol = match shape_from_tip_angle(&scene, p.phi1, 1e-10, 100) {
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
        for (k, seen) in named.iter().enumerate() {
            seen_any[k] |= *seen;
        }
        if !contact_pts.is_empty() {
            chart.series.push(
                Series::new("contact point", contact_pts, Style::Points)
                    .color(6)
                    .marker(Marker::Circle),
            );
        }
        if xmin.is_finite() {
            // The obstacle (its solid side filled), drawn under the shapes, up to a little
            // above the highest whisker point.
            let (a, b) = (xmin - 0.2, xmax + 0.2);
            let top = ymax + 0.25;
            aspects.push(top / (b - a));
            let g: Vec<(f64, f64)> = (0..=400)
                .map(|i| {
                    let x = a + (b - a) * i as f64 / 400.0;
                    (x, r.case.profile.y(x))
                })
                .filter(|&(_, y)| y.is_finite() && y < top)
                .collect();
            chart.series.insert(
                0,
                Series::new(
                    format!("obstacle {}", r.case.profile_name),
                    g,
                    Style::Obstacle,
                )
                .color(6),
            );
        }
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
        charts.push(chart);
    }
    if charts.is_empty() {
        return;
    }
    // One key above all panels, from the first chart: it names every phase drawn in any
    // panel (an empty series stands in for a phase the first panel lacks).
    let first = &mut charts[0];
    for (k, phase) in [Phase::None, Phase::A, Phase::B].into_iter().enumerate() {
        let (_, color, dash, label) = phase_style(phase);
        if seen_any[k] && !first.series.iter().any(|s| s.name == label) {
            first.series.push(
                Series::new(label, Vec::new(), Style::Line)
                    .color(color)
                    .dash(dash),
            );
        }
    }
    // Keep the key in phase order (obstacle, phases, contact points) and the contact
    // points drawn on top.
    first.series.sort_by_key(|s| match s.name.as_str() {
        "" => 9,
        n if n.starts_with("obstacle") => 0,
        "contact point" => 10,
        n => {
            1 + [Phase::None, Phase::A, Phase::B]
                .iter()
                .position(|&p| phase_style(p).3 == n)
                .unwrap_or(3)
        }
    });
    let stem = format!("fig{}", fig.replace('.', "_"));
    let cols = if charts.len() > 1 { 2 } else { 1 };
    let rows = charts.len().div_ceil(cols);
    let size = (560 * cols as u32, 420 * rows as u32);
    let note = "the base moves towards −x (right to left)";
    // A lone sketch about as high as wide (the ge sweep) takes one column; a flat one (the
    // wide g1 sweeps) the page.
    let column = charts.len() == 1 && aspects.iter().all(|&a| a > 0.5);
    let r = figure(
        out,
        entry,
        &format!("{stem}.svg"),
        &charts,
        cols,
        size,
        note,
        column,
    )
    .and_then(|()| common::csv(out, entry, &format!("{stem}.csv"), &w));
    note_err(entry, &stem, r);
}
