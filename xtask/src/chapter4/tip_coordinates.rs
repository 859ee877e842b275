//! Tip coordinates against load (Figs. 4.3, 4.4, 4.7, 4.9, 4.11, 4.14, 4.16, 4.17): the
//! tip x_1 and y_1 of each curve family over a load grid, solved by fdm and rk4 at the
//! thesis's step and by the accurate method.

use std::time::Instant;

use beam_model::scenarios::{self, Case};
use beam_model::{solve, EndState, Method, Scene};
use vibrissa_io::atomic::OutputDir;
use vibrissa_io::csvio::{Cell, CsvWriter};
use vibrissa_plot::{Chart, Dash, Marker, Series, Style};

use super::styles::{draw_method, family_marker, method_key, DASHES};
use super::{accurate, FDM, GRID, RK4};
use crate::captions::caption;
use crate::common::{self, note_err, par_map, pretty, sci, sig, svg_keyed};
use crate::{Entry, Report};

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
        let tips = data.row(r);
        charts.extend(row_charts(row, &tips, &load_axis));
        write_row_tips(&mut w, row, &tips)?;
    }
    // One legend above all panels; four rows of panels flatter, to fit the page.
    let aspect = if rows.len() > 2 { 0.5 } else { 0.75 };
    svg_keyed(out, entry, &format!("{name}.svg"), &charts, 2, aspect, "")?;
    common::csv(out, entry, &format!("{name}.csv"), &w)?;
    tip_numbers(entry, rows, data);
    Ok(())
}

/// The tips of one row of panels: `tips[family][method][i]` over the grid.
struct RowTips<'a> {
    grid: &'a [f64],
    methods: &'a [(Method, &'static str)],
    tips: &'a [Vec<Vec<Option<EndState>>>],
}

impl TipData {
    /// The tips of row `r`.
    fn row(&self, r: usize) -> RowTips<'_> {
        RowTips {
            grid: &self.grid,
            methods: &self.methods,
            tips: &self.tips[r],
        }
    }
}

/// The title of a row's panels as printed, with the tokens its families share in
/// brackets (the CSV keeps the row's title as it is).
fn row_title(row: &PanelRow, shared: &str) -> String {
    let shown = if row.title.contains(' ') {
        row.title.replace("beta", "β")
    } else {
        pretty(&row.title)
    };
    if shared.is_empty() {
        shown
    } else {
        format!("{shown} ({shared})")
    }
}

/// The two panels (tip x_1 and tip y_1 against load) of a row: each family's key and
/// curves, then the key of how the methods are drawn (for several families).
fn row_charts(row: &PanelRow, data: &RowTips<'_>, load_axis: &str) -> [Chart; 2] {
    let (labels, shared) = family_labels(&row.families);
    let title = row_title(row, &shared);
    let mut cx = Chart::new(format!("{title}: tip x_1"), load_axis, "tip x_1 [–]").y_from_zero();
    let mut cy = Chart::new(format!("{title}: tip y_1"), load_axis, "tip y_1 [–]").y_from_zero();
    let single = row.families.len() == 1;
    for (f, label) in labels.iter().enumerate() {
        if !single {
            // The family's key: its colour, dash and marker.
            for c in [&mut cx, &mut cy] {
                c.series.push(
                    Series::new(label.clone(), Vec::new(), Style::LinePoints)
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
            let tips = &data.tips[f][m];
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
    }
    if !single {
        // What lines, markers and rings stand for (black: for every family).
        for c in [&mut cx, &mut cy] {
            for (_, mname) in data.methods {
                method_key(c, mname);
            }
        }
    }
    [cx, cy]
}

/// Writes the tips of a row to the figure's CSV: by family, method and grid value.
fn write_row_tips(w: &mut CsvWriter, row: &PanelRow, data: &RowTips<'_>) -> Result<(), String> {
    for (f, fam) in row.families.iter().enumerate() {
        for (m, (_, mname)) in data.methods.iter().enumerate() {
            for (&v, t) in data.grid.iter().zip(&data.tips[f][m]) {
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
    Ok(())
}

/// Key numbers of a tip-coordinate figure: failures per method and the largest distance
/// of each method from accurate.
fn tip_numbers(entry: &mut Entry, rows: &[PanelRow], data: &TipData) {
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
pub(super) fn fig_4_3_4_4(out: &OutputDir, report: &mut Report) {
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
pub(super) fn fig_4_7(out: &OutputDir, report: &mut Report) {
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
pub(super) fn tip_figures(out: &OutputDir, report: &mut Report) {
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
        let name = common::fig_stem(fig);
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
