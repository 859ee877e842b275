//! Chapter 4: tip coordinates against load and elastica families of scenarios 1-18
//! (Figs. 4.3-4.29), the ANSYS comparison (Tables 4.2, 4.3), and the beam-model issue's
//! work-precision charts and stability maps.

use std::time::Instant;

use beam_model::scenarios::{self, Case};
use beam_model::{solve, EndState, Method, Scene, Solution};
use vibrissa_cli::atomic::OutputDir;
use vibrissa_cli::csvio::{Cell, CsvWriter};
use vibrissa_cli::plot::{
    size_for_this_thread, Chart, Dash, FigureSize, HeatMap, Mark, MarkStyle, Marker, Panel, Series,
    Style,
};
use xtask::study::{self, LoadAxis, Outcome, StabilityMap};

use crate::captions::caption;
use crate::common::{self, note_err, par_map, pretty, sci, sig, svg_keyed, Ctx};
use crate::{Entry, Failure, Report};

/// The thesis's FDM: h = 0.01.
const FDM: Method = Method::Fdm { n: 100 };
/// The thesis's RK4 comparison: h = 0.01.
const RK4: Method = Method::Rk4 { n: 100 };
/// Points of the load grids of the tip-coordinate figures.
const GRID: usize = 40;

fn accurate() -> Method {
    Method::accurate()
}

/// Runs chapter 4; every figure that fails is recorded in the report and the others go on.
pub fn run(out: &OutputDir, report: &mut Report, _ctx: &mut Ctx) -> Result<(), Failure> {
    // Work-precision first and alone, so that its timings are not disturbed by other work.
    let step = |i, what| common::step(4, i, 7, what);
    step(1, "work-precision charts");
    work_precision(out, report);
    step(2, "Figs. 4.3, 4.4");
    fig_4_3_4_4(out, report);
    step(3, "Fig. 4.7");
    fig_4_7(out, report);
    step(4, "tip-coordinate figures");
    tip_figures(out, report);
    step(5, "elastica figures");
    elastica_figures(out, report);
    step(6, "Tables 4.2, 4.3 (ANSYS)");
    ansys_tables(out, report);
    step(7, "stability maps");
    stability_maps(out, report);
    // Thesis order: Figs. 4.3-4.29, Tables 4.2-4.3, then the beam-model issue's charts.
    report.entries.sort_by_key(|e| order_key(&e.figure));
    Ok(())
}

/// Sort key of a chapter-4 entry: figures by number, then tables, then the rest (stable).
fn order_key(figure: &str) -> (u8, u32) {
    let num = |s: &str| s.strip_prefix("4.").and_then(|n| n.parse::<u32>().ok());
    if let Some(n) = num(figure) {
        (0, n)
    } else if let Some(n) = figure.strip_prefix("Table ").and_then(num) {
        (1, n)
    } else {
        (2, 0)
    }
}

// ---------------------------------------------------------------------------------------
// Tip coordinates against load
// ---------------------------------------------------------------------------------------

/// A curve family of a tip-coordinate figure: a scene whose load magnitude is varied.
#[derive(Clone)]
struct Family {
    label: String,
    scene: Scene,
}

/// One row of panels (x1 and y1) of a tip-coordinate figure.
struct PanelRow {
    title: String,
    families: Vec<Family>,
}

/// How the grid value enters the scene.
#[derive(Clone, Copy)]
enum Vary {
    /// The tip force f (DP or AP).
    TipForce,
    /// The fluid load q.
    Fluid,
    /// The tip-force angle beta, in degrees.
    BetaDeg,
}

fn with_value(scene: &Scene, vary: Vary, v: f64) -> Scene {
    let mut s = *scene;
    match vary {
        Vary::TipForce => s.loads.tip.f = v,
        Vary::Fluid => s.loads.fluid.q = v,
        Vary::BetaDeg => s.loads.tip.beta = v.to_radians(),
    }
    s
}

/// The tip of each (row, family, method, grid value).
struct TipData {
    grid: Vec<f64>,
    methods: Vec<(Method, &'static str)>,
    /// `tips[row][family][method][i]`.
    tips: Vec<Vec<Vec<Vec<Option<EndState>>>>>,
}

fn solve_tips(
    rows: &[PanelRow],
    grid: &[f64],
    vary: Vary,
    methods: &[(Method, &'static str)],
) -> TipData {
    let mut jobs = Vec::new();
    for (r, row) in rows.iter().enumerate() {
        for (f, fam) in row.families.iter().enumerate() {
            for (m, _) in methods.iter().enumerate() {
                for (i, &v) in grid.iter().enumerate() {
                    jobs.push((r, f, m, i, with_value(&fam.scene, vary, v)));
                }
            }
        }
    }
    let res = par_map(&jobs, |(_, _, m, _, scene)| {
        solve(scene, &methods[*m].0).ok().map(|s| s.tip)
    });
    let mut tips: Vec<Vec<Vec<Vec<Option<EndState>>>>> = rows
        .iter()
        .map(|row| {
            row.families
                .iter()
                .map(|_| vec![vec![None; grid.len()]; methods.len()])
                .collect()
        })
        .collect();
    for ((r, f, m, i, _), tip) in jobs.iter().zip(res) {
        tips[*r][*f][*m][*i] = tip.flatten();
    }
    TipData {
        grid: grid.to_vec(),
        methods: methods.to_vec(),
        tips,
    }
}

/// Writes a tip-coordinate figure (panels x1 and y1 per row) with its CSV and numbers.
fn tip_figure(
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    rows: &[PanelRow],
    data: &TipData,
    load_label: &str,
) -> Result<(), String> {
    let mut charts = Vec::new();
    let mut w = CsvWriter::new(&["row", "family", "method", load_label, "x1", "y1", "phi1"]);
    let load_axis = match load_label {
        "beta [deg]" => "β [°]".to_string(),
        l => format!("{l} [–]"),
    };
    for (r, row) in rows.iter().enumerate() {
        let (labels, shared) = family_labels(&row.families);
        // The row's title as printed (the CSV keeps it as it is).
        let shown = if row.title.contains(' ') {
            row.title.replace("beta", "β")
        } else {
            pretty(&row.title)
        };
        let title = if shared.is_empty() {
            shown
        } else {
            format!("{shown} ({shared})")
        };
        let mut cx = Chart::new(
            format!("{title}: tip x_1"),
            load_axis.as_str(),
            "tip x_1 [–]",
        )
        .y_from_zero();
        let mut cy = Chart::new(
            format!("{title}: tip y_1"),
            load_axis.as_str(),
            "tip y_1 [–]",
        )
        .y_from_zero();
        let single = row.families.len() == 1;
        for (f, fam) in row.families.iter().enumerate() {
            if !single {
                // The family's key: its colour, dash and marker.
                for c in [&mut cx, &mut cy] {
                    c.series.push(
                        Series::new(labels[f].clone(), Vec::new(), Style::LinePoints)
                            .color(f)
                            .dash(DASHES[f % DASHES.len()])
                            .marker(family_marker(f)),
                    );
                }
            }
            // fdm's line first, the markers on top of it.
            let mut order: Vec<usize> = (0..data.methods.len()).collect();
            order.sort_by_key(|&m| data.methods[m].1 != "fdm");
            for m in order {
                let tips = &data.tips[r][f][m];
                let coord = |y: bool| -> Vec<(f64, f64)> {
                    data.grid
                        .iter()
                        .zip(tips)
                        .map(|(&v, t)| (v, t.map_or(f64::NAN, |t| if y { t.y } else { t.x })))
                        .collect()
                };
                for (c, pts) in [(&mut cx, coord(false)), (&mut cy, coord(true))] {
                    draw_method(c, data.methods[m].1, pts, single, f);
                }
            }
            for (m, (_, mname)) in data.methods.iter().enumerate() {
                for (&v, t) in data.grid.iter().zip(&data.tips[r][f][m]) {
                    let (x, y, p) = t.map_or((f64::NAN, f64::NAN, f64::NAN), |t| (t.x, t.y, t.phi));
                    w.push_row(&[
                        Cell::Text(&row.title),
                        Cell::Text(&fam.label),
                        Cell::Text(mname),
                        Cell::Num(v),
                        Cell::Num(x),
                        Cell::Num(y),
                        Cell::Num(p),
                    ])
                    .map_err(|e| e.to_string())?;
                }
            }
        }
        if !single {
            // What lines, markers and rings stand for (black: for every family).
            for c in [&mut cx, &mut cy] {
                for (_, mname) in &data.methods {
                    method_key(c, mname);
                }
            }
        }
        charts.push(cx);
        charts.push(cy);
    }
    // One legend above all panels; four rows of panels flatter, to fit the page.
    let aspect = if rows.len() > 2 { 0.5 } else { 0.75 };
    svg_keyed(out, entry, &format!("{name}.svg"), &charts, 2, aspect, "")?;
    common::csv(out, entry, &format!("{name}.csv"), &w)?;
    // Numbers: failures per method and the largest distance of each method from accurate.
    let acc = data.methods.iter().position(|m| m.1 == "accurate");
    for (m, (_, mname)) in data.methods.iter().enumerate() {
        let mut failed = 0;
        let mut total = 0;
        let mut max_d: f64 = 0.0;
        for (r, row) in rows.iter().enumerate() {
            for f in 0..row.families.len() {
                for i in 0..data.grid.len() {
                    total += 1;
                    match (
                        data.tips[r][f][m][i],
                        acc.and_then(|a| data.tips[r][f][a][i]),
                    ) {
                        (None, _) => failed += 1,
                        (Some(t), Some(a)) => {
                            max_d = max_d.max((t.x - a.x).abs().max((t.y - a.y).abs()));
                        }
                        _ => {}
                    }
                }
            }
        }
        entry.number(
            format!("{mname}: failed solves"),
            format!("{failed} of {total}"),
            None,
        );
        if Some(m) != acc && acc.is_some() {
            entry.number(
                format!("{mname}: max tip distance to accurate"),
                sci(max_d),
                None,
            );
        }
    }
    Ok(())
}

/// The dash patterns of curve families, in order.
const DASHES: [Dash; 5] = [
    Dash::Solid,
    Dash::Dashed,
    Dash::DashDot,
    Dash::Dotted,
    Dash::LongDash,
];

/// The marker of curve family `f`: after five families the markers shift by one against
/// the dashes, so that no two of the first ten families look alike.
fn family_marker(f: usize) -> Marker {
    Marker::of_color(f + f / DASHES.len())
}

/// The legend text of a method: fdm and rk4 at the thesis's step.
fn method_label(mname: &str) -> String {
    match mname {
        "fdm" | "rk4" => format!("{mname}, h = 0.01"),
        m => m.to_string(),
    }
}

/// Adds one method's curve of a tip-coordinate panel. fdm (the thesis's method) is a line,
/// accurate filled markers on it, rk4 open rings around them, so that curves that coincide
/// stay visible. In a panel of one family (`single`) the methods have their own colours
/// and legend entries; otherwise the family `f` sets colour, dash and marker and
/// [`method_key`] explains the methods.
fn draw_method(c: &mut Chart, mname: &str, pts: Vec<(f64, f64)>, single: bool, f: usize) {
    let name = if single {
        method_label(mname)
    } else {
        String::new()
    };
    match mname {
        "fdm" => {
            let (color, dash) = if single {
                (0, Dash::Solid)
            } else {
                (f, DASHES[f % DASHES.len()])
            };
            c.series.push(
                Series::new(name, break_jumps(pts), Style::Line)
                    .color(color)
                    .dash(dash),
            );
        }
        "rk4" => {
            let color = if single { 2 } else { f };
            for (k, &(x, y)) in pts.iter().enumerate() {
                let label = if k == 0 { name.clone() } else { String::new() };
                c.marks.push(
                    Mark::point(x, y, label, color).styled(MarkStyle::Marker(Marker::Circle)),
                );
            }
        }
        _ => {
            let (color, marker) = if single {
                (1, Marker::Circle)
            } else {
                (f, family_marker(f))
            };
            c.series.push(
                Series::new(name, pts, Style::Points)
                    .color(color)
                    .marker(marker),
            );
        }
    }
}

/// The points with a NaN put into each jump (to another branch, such as the straight
/// whisker under an axial force at beta = 90 deg), so that the line does not join the two
/// branches: a step above 0.1 and five times the steps on either side.
fn break_jumps(pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let step = |i: usize| -> Option<f64> {
        let (a, b) = (pts.get(i)?, pts.get(i + 1)?);
        let d = (b.1 - a.1).abs();
        d.is_finite().then_some(d)
    };
    let mut out = Vec::with_capacity(pts.len() + 2);
    for (i, &p) in pts.iter().enumerate() {
        out.push(p);
        if let Some(d) = step(i) {
            let near = [i.checked_sub(1).and_then(step), step(i + 1)]
                .into_iter()
                .flatten()
                .fold(0.0, f64::max);
            if d > 0.1 && d > 5.0 * near {
                out.push((f64::NAN, f64::NAN));
            }
        }
    }
    out
}

/// The legend entry (black, without data) saying how a method is drawn in a panel of
/// several families.
fn method_key(c: &mut Chart, mname: &str) {
    let label = method_label(mname);
    match mname {
        "fdm" => c
            .series
            .push(Series::new(format!("{label} (lines)"), Vec::new(), Style::Line).color(6)),
        "rk4" => c.marks.push(
            Mark::point(f64::NAN, f64::NAN, format!("{label} (rings)"), 6)
                .styled(MarkStyle::Marker(Marker::Circle)),
        ),
        _ => c.series.push(
            Series::new(format!("{label} (markers)"), Vec::new(), Style::Points)
                .color(6)
                .marker(Marker::Circle),
        ),
    }
}

/// The legend labels of families for print (`k = 20`, `θ = 0.5`), without the tokens all
/// families share, which are returned apart (`α = 0°`) for the panel's title. A family
/// without a base stiffness among families with one has a rigid base (`k = ∞`).
fn family_labels(families: &[Family]) -> (Vec<String>, String) {
    if let [only] = families {
        return (vec![String::new()], pretty(&only.label));
    }
    let tokens: Vec<Vec<&str>> = families
        .iter()
        .map(|f| f.label.split_whitespace().collect())
        .collect();
    let shared: Vec<&str> = tokens
        .first()
        .map(|t| {
            t.iter()
                .copied()
                .filter(|x| tokens.iter().all(|u| u.contains(x)))
                .collect()
        })
        .unwrap_or_default();
    let any_k = tokens.iter().flatten().any(|t| t.starts_with("k="));
    let labels = tokens
        .iter()
        .map(|t| {
            let mut own: Vec<&str> = t.iter().copied().filter(|x| !shared.contains(x)).collect();
            if any_k && !t.iter().any(|x| x.starts_with("k=")) {
                own.insert(0, "k=inf");
            }
            pretty(&own.join(" "))
        })
        .collect();
    (labels, pretty(&shared.join(" ")))
}

fn load_grid(max: f64) -> Vec<f64> {
    (1..=GRID).map(|i| max * i as f64 / GRID as f64).collect()
}

/// Figs. 4.3 and 4.4: DP tip load, beta = 0, FDM and RK4 at h = 0.01 and accurate.
fn fig_4_3_4_4(out: &OutputDir, report: &mut Report) {
    let t0 = Instant::now();
    let methods = [(FDM, "fdm"), (RK4, "rk4"), (accurate(), "accurate")];
    let Some(sc) = scenarios::scenario(1) else {
        report
            .entry("4.3", caption("4.3"))
            .fail("scenario 1 missing");
        return;
    };
    let rows = vec![PanelRow {
        title: "Fig. 4.3 (beta = 0)".to_string(),
        families: vec![Family {
            label: String::new(),
            scene: sc.cases[0].scene,
        }],
    }];
    let data = solve_tips(&rows, &load_grid(40.0), Vary::TipForce, &methods);
    let entry = report.entry("4.3", caption("4.3"));
    let r = tip_figure(out, entry, "fig4_3", &rows, &data, "f");
    note_err(entry, "fig4_3", r);
    entry.number("load grid", format!("f = 1..40 ({GRID} points)"), None);
    // Fig. 4.4: |FDM - RK4| (the thesis's curve) and both against accurate.
    let entry = report.entry("4.4", caption("4.4"));
    let tips = &data.tips[0][0];
    let diff = |a: usize, b: usize, y: bool| -> Vec<(f64, f64)> {
        data.grid
            .iter()
            .enumerate()
            .map(|(i, &v)| match (tips[a][i], tips[b][i]) {
                (Some(p), Some(q)) => (
                    v,
                    if y {
                        (p.y - q.y).abs()
                    } else {
                        (p.x - q.x).abs()
                    },
                ),
                _ => (v, f64::NAN),
            })
            .collect()
    };
    let pairs = [
        (0, 1, "|fdm - rk4|"),
        (0, 2, "|fdm - accurate|"),
        (1, 2, "|rk4 - accurate|"),
    ];
    let mut cx = Chart::new(
        "Fig. 4.4: difference of tip x_1",
        "f [–]",
        "absolute difference |Δx_1| [–]",
    )
    .log(false, true);
    let mut cy = Chart::new(
        "Fig. 4.4: difference of tip y_1",
        "f [–]",
        "absolute difference |Δy_1| [–]",
    )
    .log(false, true);
    cy.hide_legend = true;
    let mut w = CsvWriter::new(&["pair", "f", "dx1", "dy1"]);
    for (c, &(a, b, name)) in pairs.iter().enumerate() {
        let dx = diff(a, b, false);
        let dy = diff(a, b, true);
        // |fdm - rk4| and |fdm - accurate| coincide: a line and markers on it; the
        // much smaller |rk4 - accurate| dash-dotted with its own markers.
        let series = |pts: Vec<(f64, f64)>| {
            let label = name.replace(" - ", " − ");
            match c {
                0 => Series::new(label, pts, Style::Line).color(0),
                1 => Series::new(label, pts, Style::Points)
                    .color(1)
                    .marker(Marker::Square),
                _ => Series::new(label, pts, Style::LinePoints)
                    .color(2)
                    .dash(Dash::DashDot)
                    .marker(Marker::Triangle),
            }
        };
        for (px, py) in dx.iter().zip(&dy) {
            let _ = w.push_row(&[
                Cell::Text(name),
                Cell::Num(px.0),
                Cell::Num(px.1),
                Cell::Num(py.1),
            ]);
        }
        let mx = dx
            .iter()
            .chain(&dy)
            .map(|p| p.1)
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
        entry.number(format!("max {name} (x1, y1)"), sci(mx), None);
        cx.series.push(series(dx));
        cy.series.push(series(dy));
    }
    let r = common::svg(out, entry, "fig4_4.svg", &[cx, cy], 2)
        .and_then(|()| common::csv(out, entry, "fig4_4.csv", &w));
    note_err(entry, "fig4_4", r);
    entry.number(
        "time (Figs. 4.3-4.4)",
        format!("{:.2} s", t0.elapsed().as_secs_f64()),
        None,
    );
}

/// Fig. 4.7: tip coordinates against the force angle beta for f = 20 and f = 40.
fn fig_4_7(out: &OutputDir, report: &mut Report) {
    let methods = [(FDM, "fdm"), (RK4, "rk4"), (accurate(), "accurate")];
    let base = Scene::new(
        beam_model::Whisker::uniform(),
        beam_model::Loads::tip(beam_model::TipForce::dp(20.0, 0.0)),
    );
    let rows: Vec<PanelRow> = [20.0, 40.0]
        .iter()
        .map(|&f| {
            let mut s = base;
            s.loads.tip.f = f;
            PanelRow {
                title: format!("f = {f}"),
                families: vec![Family {
                    label: String::new(),
                    scene: s,
                }],
            }
        })
        .collect();
    let grid: Vec<f64> = (0..=36).map(|i| 2.5 * i as f64).collect();
    let data = solve_tips(&rows, &grid, Vary::BetaDeg, &methods);
    let entry = report.entry("4.7", caption("4.7"));
    let r = tip_figure(out, entry, "fig4_7", &rows, &data, "beta [deg]");
    note_err(entry, "fig4_7", r);
    entry.number("beta grid", "0..90 deg, step 2.5 deg", None);
}

/// Families of a scenario: its cases with the load token (`f=`, `q=`) removed, grouped.
fn families(cases: &[Case], keep: impl Fn(&Case) -> bool) -> Vec<Family> {
    let mut out: Vec<Family> = Vec::new();
    for c in cases.iter().filter(|c| keep(c)) {
        let label = c
            .label
            .split_whitespace()
            .filter(|t| !t.starts_with("f=") && !t.starts_with("q="))
            .collect::<Vec<_>>()
            .join(" ");
        if !out.iter().any(|f| f.label == label) {
            out.push(Family {
                label,
                scene: c.scene,
            });
        }
    }
    out
}

/// Figs. 4.9, 4.11, 4.14, 4.16, 4.17.
fn tip_figures(out: &OutputDir, report: &mut Report) {
    let both = [(accurate(), "accurate"), (FDM, "fdm")];
    let three = [(accurate(), "accurate"), (FDM, "fdm"), (RK4, "rk4")];
    // (figure, scenario, rows split by this token prefix, vary, load max, methods)
    type Spec<'a> = (
        &'a str,
        u8,
        Option<&'a str>,
        Vary,
        f64,
        &'a [(Method, &'static str)],
    );
    let specs: [Spec<'_>; 5] = [
        ("4.9", 2, None, Vary::TipForce, 30.0, &both),
        ("4.11", 3, None, Vary::Fluid, 40.0, &three),
        ("4.14", 4, None, Vary::Fluid, 40.0, &both),
        ("4.16", 5, None, Vary::Fluid, 40.0, &both),
        ("4.17", 6, Some("k="), Vary::Fluid, 20.0, &both),
    ];
    for (fig, id, split, vary, max, methods) in specs {
        let t0 = Instant::now();
        let entry_caption = caption(fig);
        let Some(sc) = scenarios::scenario(id) else {
            report
                .entry(fig, entry_caption)
                .fail(format!("scenario {id} missing"));
            continue;
        };
        let rows: Vec<PanelRow> = match split {
            None => vec![PanelRow {
                title: format!("Fig. {fig}"),
                families: families(&sc.cases, |_| true),
            }],
            Some(prefix) => {
                let mut keys: Vec<String> = Vec::new();
                for c in &sc.cases {
                    let k = token(&c.label, prefix).unwrap_or_else(|| format!("{prefix}inf"));
                    if !keys.contains(&k) {
                        keys.push(k);
                    }
                }
                keys.iter()
                    .map(|k| PanelRow {
                        title: k.clone(),
                        families: families(&sc.cases, |c| {
                            token(&c.label, prefix).unwrap_or_else(|| format!("{prefix}inf")) == *k
                        })
                        .into_iter()
                        .map(|mut f| {
                            f.label = f
                                .label
                                .split_whitespace()
                                .filter(|t| !t.starts_with(prefix))
                                .collect::<Vec<_>>()
                                .join(" ");
                            f
                        })
                        .collect(),
                    })
                    .collect()
            }
        };
        let grid = load_grid(max);
        let data = solve_tips(&rows, &grid, vary, methods);
        let entry = report.entry(fig, entry_caption);
        let name = format!("fig{}", fig.replace('.', "_"));
        let load = match vary {
            Vary::Fluid => "q",
            _ => "f",
        };
        let r = tip_figure(out, entry, &name, &rows, &data, load);
        note_err(entry, &name, r);
        entry.number(
            "scenario / grid",
            format!(
                "scenario {id} ({}), {load} = {}..{max} ({GRID} points)",
                sc.title,
                sig(max / GRID as f64, 3)
            ),
            None,
        );
        entry.number("time", format!("{:.2} s", t0.elapsed().as_secs_f64()), None);
    }
}

/// The token of `label` starting with `prefix`.
fn token(label: &str, prefix: &str) -> Option<String> {
    label
        .split_whitespace()
        .find(|t| t.starts_with(prefix))
        .map(str::to_string)
}

// ---------------------------------------------------------------------------------------
// Elastica families
// ---------------------------------------------------------------------------------------

/// `(figure, scenario, case filter token, curve token prefix, panel columns)`.
const ELASTICA: [(&str, u8, Option<&str>, &str, usize); 18] = [
    ("4.5", 1, Some("beta=0deg"), "f=", 1),
    ("4.6", 1, Some("beta=45deg"), "f=", 1),
    ("4.10", 2, None, "f=", 1),
    ("4.12", 3, Some("alpha=0deg"), "q=", 1),
    ("4.13", 3, Some("alpha=45deg"), "q=", 1),
    ("4.15", 4, None, "k=", 2),
    ("4.18", 7, None, "q=", 3),
    ("4.19", 8, None, "k=", 3),
    ("4.20", 9, None, "theta=", 3),
    ("4.21", 10, None, "k=", 3),
    ("4.22", 11, None, "f=", 2),
    ("4.23", 12, None, "f=", 2),
    ("4.24", 13, None, "f=", 2),
    ("4.25", 14, None, "f=", 2),
    ("4.26", 15, None, "f=", 2),
    ("4.27", 16, None, "f=", 2),
    ("4.28", 17, None, "f=", 3),
    ("4.29", 18, None, "f=", 3),
];

fn elastica_figures(out: &OutputDir, report: &mut Report) {
    let methods = [accurate(), FDM, RK4];
    let specs: Vec<_> = ELASTICA.iter().collect();
    // Solve every case of every figure at once (in parallel).
    let mut jobs: Vec<(usize, usize, Scene)> = Vec::new();
    let mut figure_cases: Vec<Vec<Case>> = Vec::new();
    for (k, &&(_, id, filter, _, _)) in specs.iter().enumerate() {
        let cases: Vec<Case> = scenarios::scenario(id)
            .map(|s| s.cases)
            .unwrap_or_default()
            .into_iter()
            .filter(|c| match filter {
                None => true,
                Some(t) => c.label.split_whitespace().any(|x| x == t),
            })
            .collect();
        for (m, _) in methods.iter().enumerate() {
            for c in &cases {
                jobs.push((k, m, c.scene));
            }
        }
        figure_cases.push(cases);
    }
    let t0 = Instant::now();
    let sols = par_map(&jobs, |(_, m, scene)| {
        solve(scene, &methods[*m]).map_err(|e| e.to_string())
    });
    let secs = t0.elapsed().as_secs_f64();
    let mut by_fig: Vec<Vec<Vec<Result<Solution, String>>>> = figure_cases
        .iter()
        .map(|_| methods.iter().map(|_| Vec::new()).collect())
        .collect();
    for ((k, m, _), s) in jobs.iter().zip(sols) {
        by_fig[*k][*m].push(s.unwrap_or_else(|| Err("the solve panicked".to_string())));
    }
    for (k, &&(fig, id, _, curve, cols)) in specs.iter().enumerate() {
        let entry = report.entry(fig, caption(fig));
        let cases = &figure_cases[k];
        if cases.is_empty() {
            entry.fail(format!("scenario {id}: no cases"));
            continue;
        }
        let r = elastica_figure(out, entry, fig, cases, &by_fig[k], curve, cols);
        note_err(entry, fig, r);
        entry.number(
            "scenario",
            scenarios::scenario(id).map_or(String::new(), |s| format!("{id}: {}", s.title)),
            None,
        );
    }
    if let Some(e) = report.entries.last_mut() {
        e.number(
            "time (all elastica figures, 3 methods)",
            format!("{secs:.2} s"),
            None,
        );
    }
}

fn elastica_figure(
    out: &OutputDir,
    entry: &mut Entry,
    fig: &str,
    cases: &[Case],
    sols: &[Vec<Result<Solution, String>>],
    curve: &str,
    cols: usize,
) -> Result<(), String> {
    // Panels: the label without the curve token; curves: the curve token.
    let split = |label: &str| -> (String, String) {
        let mut panel = Vec::new();
        let mut cur = None;
        for t in label.split_whitespace() {
            if t.starts_with(curve) {
                cur = Some(t.to_string());
            } else {
                panel.push(t);
            }
        }
        (
            panel.join(" "),
            cur.unwrap_or_else(|| format!("{curve}inf")),
        )
    };
    let mut panels: Vec<String> = Vec::new();
    for c in cases {
        let p = split(&c.label).0;
        if !panels.contains(&p) {
            panels.push(p);
        }
    }
    let names = ["accurate", "fdm", "rk4"];
    let mut charts = Vec::new();
    let mut w = CsvWriter::new(&["case", "method", "s", "x", "y", "phi", "m"]);
    // The curve labels of each panel: one legend for the figure (in its first panel) if
    // every panel has the same curves.
    let curves_of = |p: &str| -> Vec<String> {
        cases
            .iter()
            .map(|c| split(&c.label))
            .filter(|(cp, _)| cp == p)
            .map(|(_, cl)| cl)
            .collect()
    };
    let same_curves = panels.iter().all(|p| curves_of(p) == curves_of(&panels[0]));
    // Under one legend, the parameters all panels share go to the figure's heading.
    let shared: Vec<&str> = if same_curves && panels.len() > 1 {
        panels[0]
            .split_whitespace()
            .filter(|t| panels.iter().all(|p| p.split_whitespace().any(|u| u == *t)))
            .collect()
    } else {
        Vec::new()
    };
    let heading = pretty(&shared.join(" "));
    for (k, p) in panels.iter().enumerate() {
        let own: Vec<&str> = p
            .split_whitespace()
            .filter(|t| !shared.contains(t))
            .collect();
        let title = if panels.len() == 1 {
            format!("Fig. {fig} ({})", pretty(p))
        } else {
            pretty(&own.join(" "))
        };
        let mut chart = Chart::new(title, "x [–]", "y [–]").equal_aspect();
        chart.hide_legend = same_curves && k > 0;
        let mut color = 0;
        for (i, c) in cases.iter().enumerate() {
            let (cp, cl) = split(&c.label);
            if cp != *p {
                continue;
            }
            // Each curve its colour, dash and marker: fdm (the thesis's method) a line,
            // accurate markers at every tenth node on it (the two coincide at print).
            let (dash, marker) = (DASHES[color % DASHES.len()], family_marker(color));
            chart.series.push(
                Series::new(pretty(&cl), Vec::new(), Style::LinePoints)
                    .color(color)
                    .dash(dash)
                    .marker(marker),
            );
            if let Ok(s) = &sols[1][i] {
                let pts = s
                    .elastica
                    .x
                    .iter()
                    .copied()
                    .zip(s.elastica.y.iter().copied());
                chart.series.push(
                    Series::new("", pts.collect(), Style::Line)
                        .color(color)
                        .dash(dash),
                );
            }
            if let Ok(s) = &sols[0][i] {
                let e = &s.elastica;
                let pts = (0..e.len())
                    .filter(|&j| j > 0 && (j % 10 == 0 || j + 1 == e.len()))
                    .map(|j| (e.x[j], e.y[j]))
                    .collect();
                chart.series.push(
                    Series::new("", pts, Style::Points)
                        .color(color)
                        .marker(marker),
                );
            }
            color += 1;
        }
        if !chart.hide_legend {
            method_key(&mut chart, "fdm");
            method_key(&mut chart, "accurate");
        }
        charts.push(chart);
    }
    for (i, c) in cases.iter().enumerate() {
        for (m, name) in names.iter().enumerate() {
            if let Ok(s) = &sols[m][i] {
                let e = &s.elastica;
                for j in 0..e.len() {
                    w.push_row(&[
                        Cell::Text(&c.label),
                        Cell::Text(name),
                        Cell::Num(e.s[j]),
                        Cell::Num(e.x[j]),
                        Cell::Num(e.y[j]),
                        Cell::Num(e.phi[j]),
                        Cell::Num(e.m[j]),
                    ])
                    .map_err(|e| e.to_string())?;
                }
            }
        }
    }
    let stem = format!("fig{}", fig.replace('.', "_"));
    if charts.len() == 1 {
        let _size = size_for_this_thread(FigureSize::Column);
        common::svg(out, entry, &format!("{stem}.svg"), &charts, cols)?;
    } else if same_curves {
        svg_keyed(
            out,
            entry,
            &format!("{stem}.svg"),
            &charts,
            cols,
            0.75,
            &heading,
        )?;
    } else {
        common::svg(out, entry, &format!("{stem}.svg"), &charts, cols)?;
    }
    common::csv(out, entry, &format!("{stem}.csv"), &w)?;
    entry.number("cases", cases.len().to_string(), None);
    for (m, name) in names.iter().enumerate() {
        let failed: Vec<&str> = cases
            .iter()
            .zip(&sols[m])
            .filter(|(_, s)| s.is_err())
            .map(|(c, _)| c.label.as_str())
            .collect();
        entry.number(
            format!("{name}: failed"),
            if failed.is_empty() {
                "0".to_string()
            } else {
                format!("{} ({})", failed.len(), failed.join("; "))
            },
            None,
        );
        if m > 0 {
            let d = sols[0]
                .iter()
                .zip(&sols[m])
                .filter_map(|(a, b)| match (a, b) {
                    (Ok(a), Ok(b)) => {
                        Some((a.tip.x - b.tip.x).abs().max((a.tip.y - b.tip.y).abs()))
                    }
                    _ => None,
                })
                .fold(0.0, f64::max);
            entry.number(
                format!("{name} (h = 0.01): max tip distance to accurate"),
                sci(d),
                None,
            );
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Tables 4.2, 4.3
// ---------------------------------------------------------------------------------------

fn ansys_tables(out: &OutputDir, report: &mut Report) {
    let rows = study::ansys_comparison();
    for (table, kind, load) in [
        ("Table 4.2", study::AnsysLoad::Tip, "f"),
        ("Table 4.3", study::AnsysLoad::Fluid, "q"),
    ] {
        let entry = report.entry(table, caption(table));
        let rows = match &rows {
            Ok(r) => r.iter().filter(|r| r.load_kind == kind).collect::<Vec<_>>(),
            Err(e) => {
                entry.fail(format!("ansys_comparison: {e}"));
                continue;
            }
        };
        let mut w = CsvWriter::new(&[
            load,
            "load_si",
            "ansys_x1_mm",
            "ansys_y1_mm",
            "thesis_x1_mm",
            "thesis_y1_mm",
            "ours_x1_mm",
            "ours_y1_mm",
            "err_thesis_x_pct",
            "err_thesis_y_pct",
            "err_ours_x_pct",
            "err_ours_y_pct",
        ]);
        let mut md = Vec::new();
        let (mut max_t, mut max_o): (f64, f64) = (0.0, 0.0);
        for r in &rows {
            let _ = w.push_numbers(&[
                r.load,
                r.load_si,
                r.ansys_x1_mm,
                r.ansys_y1_mm,
                r.thesis_x1_mm,
                r.thesis_y1_mm,
                r.ours_x1_mm,
                r.ours_y1_mm,
                r.err_thesis_x_pct,
                r.err_thesis_y_pct,
                r.err_ours_x_pct,
                r.err_ours_y_pct,
            ]);
            max_t = max_t.max(r.err_thesis_x_pct).max(r.err_thesis_y_pct);
            max_o = max_o.max(r.err_ours_x_pct).max(r.err_ours_y_pct);
            md.push(vec![
                sig(r.load, 3),
                sig(r.load_si, 4),
                format!("{} / {}", r.ansys_x1_mm, r.ansys_y1_mm),
                format!("{} / {}", r.thesis_x1_mm, r.thesis_y1_mm),
                format!("{:.4} / {:.4}", r.ours_x1_mm, r.ours_y1_mm),
                format!("{:.3} / {:.3}", r.err_thesis_x_pct, r.err_thesis_y_pct),
                format!("{:.3} / {:.3}", r.err_ours_x_pct, r.err_ours_y_pct),
            ]);
        }
        let unit = if load == "f" { "[N]" } else { "[N/m]" };
        entry.block(common::md_table(
            &[
                load,
                &format!("{load} {unit}"),
                "ANSYS x1 / y1 [mm]",
                "thesis model x1 / y1 [mm]",
                "ours (accurate) x1 / y1 [mm]",
                "thesis error x1 / y1 [%]",
                "our error x1 / y1 [%]",
            ],
            &md,
        ));
        entry.number(
            "largest error vs ANSYS, ours",
            format!("{max_o:.3} %"),
            None,
        );
        entry.number(
            "largest error vs ANSYS, thesis model",
            format!("{max_t:.3} %"),
            Some(if load == "f" { "2.552 %" } else { "1.805 %" }),
        );
        let name = if load == "f" {
            "table4_2.csv"
        } else {
            "table4_3.csv"
        };
        let r = common::csv(out, entry, name, &w);
        note_err(entry, name, r);
    }
}

// ---------------------------------------------------------------------------------------
// Work-precision and stability maps (beam-model issue)
// ---------------------------------------------------------------------------------------

fn work_precision(out: &OutputDir, report: &mut Report) {
    for (name, scene) in scenarios::reference_scenes() {
        let t0 = Instant::now();
        let entry = report.entry(
            format!("Work-precision: {name}"),
            "Accuracy against speed of the three methods (beam-model issue): tip error \
             max(|x1 - x1_ref|, |y1 - y1_ref|) against an accurate solve at tol 1e-13, \
             against the median wall time of one solve (log-log); fdm n = 25..3200, \
             rk4 n = 10..1280, accurate tol = 1e-4..1e-13; auto (the automatic choice) \
             asked for 1e-4..1e-12.",
        );
        let points = match study::work_precision(&scene, name) {
            Ok(p) => p,
            Err(e) => {
                entry.fail(format!("work_precision({name}): {e}"));
                continue;
            }
        };
        let mut chart = Chart::new(
            format!("work-precision: {name}"),
            "time per solve [s]",
            "tip error [–]",
        )
        .log(true, true);
        for (c, m) in ["fdm", "rk4", "accurate", "fdm-richardson", "auto"]
            .iter()
            .enumerate()
        {
            let pts: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.method == *m)
                .map(|p| (p.seconds, p.error.max(1e-16)))
                .collect();
            let series = Series::new(*m, pts, Style::LinePoints).color(c);
            // The automatic choice: black, dashed, its own marker.
            let series = if *m == "auto" {
                series
                    .color(6)
                    .dash(vibrissa_cli::plot::Dash::Dashed)
                    .marker(vibrissa_cli::plot::Marker::TriangleDown)
            } else {
                series
            };
            chart.series.push(series);
            let best = points
                .iter()
                .filter(|p| p.method == *m && p.error.is_finite())
                .min_by(|a, b| a.error.total_cmp(&b.error));
            if let Some(b) = best {
                entry.number(
                    format!("{m}: smallest error (setting, time)"),
                    format!(
                        "{} ({}, {} s)",
                        sci(b.error),
                        sig(b.setting, 3),
                        sci(b.seconds)
                    ),
                    None,
                );
            }
            let failed = points
                .iter()
                .filter(|p| p.method == *m && !p.error.is_finite())
                .count();
            if failed > 0 {
                entry.number(format!("{m}: failed settings"), failed.to_string(), None);
            }
            if *m == "auto" {
                entry.number(
                    "auto: time / cheapest method meeting the same accuracy (per tol)",
                    auto_vs_envelope(&points),
                    None,
                );
                continue;
            }
            if *m != "accurate" {
                let orders: Vec<String> = study::observed_orders(&points, m)
                    .iter()
                    .map(|(_, o)| format!("{o:.2}"))
                    .collect();
                entry.number(format!("{m}: observed orders"), orders.join(", "), None);
            }
        }
        let stem = format!("work_precision_{name}");
        let r = {
            let _size = size_for_this_thread(FigureSize::Column);
            common::svg(out, entry, &format!("{stem}.svg"), &[chart], 1)
        }
        .and_then(|()| common::text(out, entry, &format!("{stem}.csv"), &study::to_csv(&points)));
        note_err(entry, &stem, r);
        entry.number("time", format!("{:.2} s", t0.elapsed().as_secs_f64()), None);
    }
}

/// For each accuracy asked of `auto`: its time over the time of the fastest other setting
/// of any method whose error meets that accuracy (1 = on the lower envelope).
fn auto_vs_envelope(points: &[study::WorkPoint]) -> String {
    points
        .iter()
        .filter(|p| p.method == "auto")
        .map(|a| {
            let best = points
                .iter()
                .filter(|p| p.method != "auto" && p.error <= a.setting)
                .map(|p| p.seconds)
                .fold(f64::INFINITY, f64::min);
            format!("{}: {:.2}", sci(a.setting), a.seconds / best)
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The outcomes of a stability map, in the order of the cell values, with colours whose
/// grey levels differ too (about 250, 210, 30, 160, 100 in greyscale): converged white and
/// light blue, the fallback a darker blue, a wrong branch orange, a failure dark red.
const CATEGORIES: [(&str, (u8, u8, u8)); 5] = [
    ("converged", (247, 251, 255)),
    ("converged (continuation)", (189, 215, 238)),
    ("failed", (103, 0, 13)),
    ("wrong branch", (230, 159, 0)),
    ("fallback (fdm-richardson)", (33, 113, 181)),
];

fn heatmap(m: &StabilityMap) -> HeatMap {
    let cells = m
        .cells
        .iter()
        .map(|row| {
            row.iter()
                .map(|o| match o {
                    Outcome::Converged {
                        continuation_steps: 0,
                    } => 0,
                    Outcome::Converged { .. } => 1,
                    Outcome::Failed => 2,
                    Outcome::Wrong => 3,
                    Outcome::FellBack { .. } => 4,
                })
                .collect()
        })
        .collect();
    HeatMap {
        title: format!(
            "{} ({}, {})",
            m.method,
            m.kind.name(),
            if m.k.is_finite() {
                format!("k = {}", m.k)
            } else {
                "rigid base".to_string()
            }
        ),
        x_label: "conicity θ [–]".to_string(),
        y_label: match m.kind {
            LoadAxis::Fluid => "fluid load q [–]",
            _ => "tip force f [–]",
        }
        .to_string(),
        x_values: m.thetas.clone(),
        y_values: m.loads.clone(),
        cells,
        categories: CATEGORIES
            .iter()
            .map(|(n, c)| (n.to_string(), *c))
            .collect(),
    }
}

fn stability_maps(out: &OutputDir, report: &mut Report) {
    let methods = study::default_map_methods();
    let thetas = study::default_thetas();
    // One job per (axis, k, load row), so that the work spreads evenly over the threads;
    // the rows are merged into one map per (axis, k) and method.
    let mut combos = Vec::new();
    let mut jobs = Vec::new();
    for axis in LoadAxis::ALL {
        for k in study::DEFAULT_KS {
            combos.push((axis, k));
            for load in axis.default_loads() {
                jobs.push((combos.len() - 1, axis, k, load));
            }
        }
    }
    let t0 = Instant::now();
    let res = par_map(&jobs, |&(_, axis, k, load)| {
        let t = Instant::now();
        let r =
            study::stability_maps(&methods, axis, &[load], &thetas, k).map_err(|e| e.to_string());
        (r, t.elapsed().as_secs_f64())
    });
    let total = t0.elapsed().as_secs_f64();
    let mut merged: Vec<(Result<Vec<StabilityMap>, String>, f64)> =
        combos.iter().map(|_| (Ok(Vec::new()), 0.0)).collect();
    for (&(c, _, _, load), r) in jobs.iter().zip(res) {
        let (r, secs) = r.unwrap_or_else(|| (Err(format!("panicked at load {load}")), 0.0));
        let slot = &mut merged[c];
        slot.1 += secs;
        match (&mut slot.0, r) {
            (Ok(acc), Ok(maps)) if acc.is_empty() => *acc = maps,
            (Ok(acc), Ok(maps)) => {
                for (a, m) in acc.iter_mut().zip(maps) {
                    a.loads.extend(m.loads);
                    a.cells.extend(m.cells);
                    a.reference.extend(m.reference);
                }
            }
            (Ok(_), Err(e)) => slot.0 = Err(e),
            (Err(_), _) => {}
        }
    }
    for (&(axis, k), r) in combos.iter().zip(merged) {
        let entry = report.entry(
            format!("Stability map: {}, k = {k}", axis.name()),
            "Where each method converges (beam-model issue; thesis §4.2.2, §4.3.3): a \
             straight whisker of conicity theta on a base of stiffness k under the load of \
             the axis, solved by accurate, rk4 (h = 0.01) and fdm (h = 0.01); a converged \
             tip more than 1e-2 from the accurate reference counts as wrong branch.",
        );
        let (maps, secs) = match r {
            (Ok(m), s) => (m, s),
            (Err(e), _) => {
                entry.fail(format!("stability_maps: {e}"));
                continue;
            }
        };
        let hms: Vec<HeatMap> = maps.iter().map(heatmap).collect();
        let panels: Vec<Panel<'_>> = hms.iter().map(Panel::HeatMap).collect();
        let kname = if k.is_finite() {
            format!("{k}")
        } else {
            "rigid".to_string()
        };
        let stem = format!("stability_{}_k{kname}", axis.name());
        let mut w = CsvWriter::new(&[
            "method",
            "load",
            "theta",
            "outcome",
            "continuation_steps",
            "reference_converged",
        ]);
        for m in &maps {
            for (i, row) in m.cells.iter().enumerate() {
                for (j, o) in row.iter().enumerate() {
                    let (name, steps) = match o {
                        Outcome::Converged { continuation_steps } => {
                            ("converged", *continuation_steps as f64)
                        }
                        Outcome::Failed => ("failed", f64::NAN),
                        Outcome::Wrong => ("wrong", f64::NAN),
                        Outcome::FellBack { method_used } => (*method_used, f64::NAN),
                    };
                    let _ = w.push_row(&[
                        Cell::Text(m.method),
                        Cell::Num(m.loads[i]),
                        Cell::Num(m.thetas[j]),
                        Cell::Text(name),
                        Cell::Num(steps),
                        Cell::Text(if m.reference[i][j] { "true" } else { "false" }),
                    ]);
                }
            }
            let (c, f, wr) = m.counts();
            entry.number(
                format!("{}: converged / failed / wrong", m.method),
                format!("{c} / {f} / {wr}"),
                None,
            );
        }
        let r = common::svg_panels(out, entry, &format!("{stem}.svg"), &panels, 3)
            .and_then(|()| common::csv(out, entry, &format!("{stem}.csv"), &w));
        note_err(entry, &stem, r);
        entry.number("CPU time (sum over rows)", format!("{secs:.2} s"), None);
    }
    if let Some(e) = report.entries.last_mut() {
        e.number("time (all stability maps)", format!("{total:.2} s"), None);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_sort_in_thesis_order() {
        let mut v = vec![
            "Stability map: fluid",
            "Table 4.2",
            "4.10",
            "4.3",
            "Work-precision: a",
        ];
        v.sort_by_key(|f| order_key(f));
        assert_eq!(
            v,
            [
                "4.3",
                "4.10",
                "Table 4.2",
                "Stability map: fluid",
                "Work-precision: a"
            ]
        );
    }

    #[test]
    fn labels_print_with_symbols() {
        assert_eq!(
            pretty("theta=0.25 alpha=0deg k=inf B=-0.5"),
            "θ\u{a0}=\u{a0}0.25, α\u{a0}=\u{a0}0°, k\u{a0}=\u{a0}∞, B\u{a0}=\u{a0}−0.5"
        );
        let fam = |label: &str| Family {
            label: label.to_string(),
            scene: scenarios::scenario(4).unwrap().cases[0].scene,
        };
        let (labels, shared) = family_labels(&[fam("alpha=0deg"), fam("k=20 alpha=0deg")]);
        assert_eq!(labels, ["k\u{a0}=\u{a0}∞", "k\u{a0}=\u{a0}20"]);
        assert_eq!(shared, "α\u{a0}=\u{a0}0°");
    }

    #[test]
    fn lines_break_at_jumps_only() {
        let smooth: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 0.2 * i as f64)).collect();
        assert_eq!(break_jumps(smooth.clone()), smooth);
        let mut jump = smooth.clone();
        jump.push((10.0, -3.0));
        let out = break_jumps(jump);
        assert_eq!(out.len(), 12);
        assert!(out[10].0.is_nan());
    }

    #[test]
    fn elastica_figures_cover_their_scenarios() {
        for (fig, id, filter, curve, _) in ELASTICA {
            let sc = scenarios::scenario(id).unwrap();
            let n = sc
                .cases
                .iter()
                .filter(|c| match filter {
                    None => true,
                    Some(t) => c.label.split_whitespace().any(|x| x == t),
                })
                .count();
            assert!(n > 0, "Fig. {fig}: no cases");
            assert!(!curve.is_empty());
        }
    }
}
