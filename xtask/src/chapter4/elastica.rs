//! The elastica families of scenarios 1-18 (Figs. 4.5, 4.6, 4.10, 4.12, 4.13, 4.15,
//! 4.18-4.29): the deformed whisker of every case, one panel per parameter set, one curve
//! per load (or stiffness, or conicity).

use std::time::Instant;

use beam_model::scenarios::{self, Case};
use beam_model::{solve, Scene, Solution};
use vibrissa_io::atomic::OutputDir;
use vibrissa_io::csvio::{Cell, CsvWriter};
use vibrissa_plot::{Chart, Series, Style};

use super::styles::{family_marker, method_key, DASHES};
use super::{accurate, FDM, RK4};
use crate::captions::caption;
use crate::common::{self, note_err, par_map, pretty, sci, svg_keyed};
use crate::{Entry, Report};

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

/// The cases of scenario `id` whose label has the token `filter` (all of them if `None`).
fn figure_cases(id: u8, filter: Option<&str>) -> Vec<Case> {
    scenarios::scenario(id)
        .map(|s| s.cases)
        .unwrap_or_default()
        .into_iter()
        .filter(|c| match filter {
            None => true,
            Some(t) => c.label.split_whitespace().any(|x| x == t),
        })
        .collect()
}

/// The elastica figures of [`ELASTICA`], their cases solved by every method at once.
pub(super) fn elastica_figures(out: &OutputDir, report: &mut Report) {
    let methods = [accurate(), FDM, RK4];
    let specs: Vec<_> = ELASTICA.iter().collect();
    // Solve every case of every figure at once (in parallel).
    let mut jobs: Vec<(usize, usize, Scene)> = Vec::new();
    let mut figure_cases_of: Vec<Vec<Case>> = Vec::new();
    for (k, &&(_, id, filter, _, _)) in specs.iter().enumerate() {
        let cases = figure_cases(id, filter);
        for (m, _) in methods.iter().enumerate() {
            for c in &cases {
                jobs.push((k, m, c.scene));
            }
        }
        figure_cases_of.push(cases);
    }
    let t0 = Instant::now();
    let sols = par_map(&jobs, |(_, m, scene)| {
        solve(scene, &methods[*m]).map_err(|e| e.to_string())
    });
    let secs = t0.elapsed().as_secs_f64();
    let mut by_fig: Vec<Vec<Vec<Result<Solution, String>>>> = figure_cases_of
        .iter()
        .map(|_| methods.iter().map(|_| Vec::new()).collect())
        .collect();
    for ((k, m, _), s) in jobs.iter().zip(sols) {
        by_fig[*k][*m].push(s.unwrap_or_else(|| Err("the solve panicked".to_string())));
    }
    for (k, &&(fig, id, _, curve, cols)) in specs.iter().enumerate() {
        let entry = report.entry(fig, caption(fig));
        let cases = &figure_cases_of[k];
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

/// The methods of an elastica figure, in the order of its solutions.
const NAMES: [&str; 3] = ["accurate", "fdm", "rk4"];

/// Writes an elastica figure: its panels, its CSV of every shape and its key numbers.
/// `sols[m][i]` is the solution of case `i` by method `m` of [`NAMES`].
fn elastica_figure(
    out: &OutputDir,
    entry: &mut Entry,
    fig: &str,
    cases: &[Case],
    sols: &[Vec<Result<Solution, String>>],
    curve: &str,
    cols: usize,
) -> Result<(), String> {
    let panels = Panels::of(cases, curve);
    let charts: Vec<Chart> = (0..panels.labels.len())
        .map(|k| elastica_panel(fig, cases, sols, &panels, k))
        .collect();
    let w = elastica_csv(cases, sols)?;
    let stem = common::fig_stem(fig);
    if charts.len() == 1 {
        common::svg_column(out, entry, &format!("{stem}.svg"), &charts[0])?;
    } else if panels.same_curves {
        let heading = pretty(&panels.shared.join(" "));
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
    elastica_numbers(entry, cases, sols);
    Ok(())
}

/// A case label split into its panel (the label without the curve token) and its curve
/// (the token starting with `curve`; `curve` + `inf` if there is none).
fn split_label(label: &str, curve: &str) -> (String, String) {
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
}

/// The panels of an elastica figure.
struct Panels<'a> {
    /// The prefix of the curve token.
    curve: &'a str,
    /// Each panel's label (a case label without its curve token), in case order.
    labels: Vec<String>,
    /// Whether every panel has the same curves: then one legend (in the first panel)
    /// serves the figure.
    same_curves: bool,
    /// Under one legend, the parameters all panels share (for the figure's heading).
    shared: Vec<String>,
}

impl<'a> Panels<'a> {
    fn of(cases: &[Case], curve: &'a str) -> Self {
        let mut labels: Vec<String> = Vec::new();
        for c in cases {
            let p = split_label(&c.label, curve).0;
            if !labels.contains(&p) {
                labels.push(p);
            }
        }
        // The curve labels of each panel.
        let curves_of = |p: &str| -> Vec<String> {
            cases
                .iter()
                .map(|c| split_label(&c.label, curve))
                .filter(|(cp, _)| cp == p)
                .map(|(_, cl)| cl)
                .collect()
        };
        let same_curves = labels.iter().all(|p| curves_of(p) == curves_of(&labels[0]));
        let shared: Vec<String> = if same_curves && labels.len() > 1 {
            labels[0]
                .split_whitespace()
                .filter(|t| labels.iter().all(|p| p.split_whitespace().any(|u| u == *t)))
                .map(str::to_string)
                .collect()
        } else {
            Vec::new()
        };
        Panels {
            curve,
            labels,
            same_curves,
            shared,
        }
    }
}

/// Panel `k` of an elastica figure: each of its cases in its own colour, dash and marker,
/// fdm (the thesis's method) a line, accurate markers at every tenth node on it (the two
/// coincide at print).
fn elastica_panel(
    fig: &str,
    cases: &[Case],
    sols: &[Vec<Result<Solution, String>>],
    panels: &Panels<'_>,
    k: usize,
) -> Chart {
    let p = &panels.labels[k];
    let title = if panels.labels.len() == 1 {
        format!("Fig. {fig} ({})", pretty(p))
    } else {
        let own: Vec<&str> = p
            .split_whitespace()
            .filter(|t| !panels.shared.iter().any(|s| s == t))
            .collect();
        pretty(&own.join(" "))
    };
    let mut chart = Chart::new(title, "x [–]", "y [–]").equal_aspect();
    chart.hide_legend = panels.same_curves && k > 0;
    let mut color = 0;
    for (i, c) in cases.iter().enumerate() {
        let (cp, cl) = split_label(&c.label, panels.curve);
        if cp != *p {
            continue;
        }
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
    chart
}

/// The CSV of an elastica figure: every node of every shape, by case and method.
fn elastica_csv(
    cases: &[Case],
    sols: &[Vec<Result<Solution, String>>],
) -> Result<CsvWriter, String> {
    let mut w = CsvWriter::new(&["case", "method", "s", "x", "y", "phi", "m"]);
    for (i, c) in cases.iter().enumerate() {
        for (m, name) in NAMES.iter().enumerate() {
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
    Ok(w)
}

/// Key numbers of an elastica figure: the cases, the failed solves of each method and
/// the largest tip distance of fdm and rk4 from accurate.
fn elastica_numbers(entry: &mut Entry, cases: &[Case], sols: &[Vec<Result<Solution, String>>]) {
    entry.number("cases", cases.len().to_string(), None);
    for (m, name) in NAMES.iter().enumerate() {
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elastica_figures_cover_their_scenarios() {
        for (fig, id, filter, curve, _) in ELASTICA {
            assert!(scenarios::scenario(id).is_some(), "Fig. {fig}: no scenario");
            let n = figure_cases(id, filter).len();
            assert!(n > 0, "Fig. {fig}: no cases");
            assert!(!curve.is_empty());
        }
    }
}
