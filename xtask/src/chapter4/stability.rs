//! The beam-model issue's stability maps (thesis §4.2.2, §4.3.3): where each method
//! converges, fails or lands on a wrong branch over conicity θ and load, per base stiffness.

use std::time::Instant;

use vibrissa_io::atomic::OutputDir;
use vibrissa_io::csvio::{Cell, CsvWriter};
use vibrissa_plot::{HeatMap, Panel};
use xtask::study::{self, LoadAxis, Outcome, StabilityMap};

use crate::common::{self, note_err, par_map};
use crate::Report;

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

/// The stability maps of every load axis and base stiffness, one figure and CSV each.
pub(super) fn stability_maps(out: &OutputDir, report: &mut Report) {
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
