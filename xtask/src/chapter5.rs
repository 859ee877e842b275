//! Chapter 5: the sweeps of every case past its contour (Figs. 5.8-5.44), as observables
//! against the base position x0, scene sketches and one observables CSV per sweep.

use beam_model::{shape_from_tip_angle, Loads, Scene};
use contact_sim::phase::contact_loads;
use contact_sim::{FirstContact, Phase, Separation, SweepPoint};
use vibrissa_cli::atomic::OutputDir;
use vibrissa_cli::csvio::{Cell, CsvWriter};
use vibrissa_cli::plot::{Chart, Series, Style};

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
        "Ax" => "horizontal base force Ax [–]",
        "Ay" => "vertical base force Ay [–]",
        "MA" => "base moment MA [–]",
        "phi0" => "base angle φ₀ [rad]",
        "s1" => "loaded arc length s₁ [–]",
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

fn chart_of(group: &[&SweepRun], q: usize, title: &str) -> Chart {
    let (name, get) = QUANTITIES[q];
    let mut c = Chart::new(
        format!("{title}: {name}"),
        "base position x₀ [–]",
        axis_label(name),
    );
    for (i, r) in group.iter().enumerate() {
        if let Ok(s) = &r.result {
            let pts = s.points.iter().map(|p| (p.x0, get(p))).collect();
            let style = if i % 2 == 0 {
                Style::Line
            } else {
                Style::Dashed
            };
            c.series
                .push(Series::new(r.case.label.clone(), pts, style).color(i));
        }
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
        if let Some(first) = charts.first_mut() {
            if constant.contains(&"phi0") {
                first.note = "φ₀ = π/2 throughout (rigid support): its panel is left out".into();
            }
        }
        let stem = format!("fig{}", fig.replace('.', "_"));
        let r = common::svg(out, entry, &format!("{stem}.svg"), &charts, 2);
        note_err(entry, &stem, r);
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
    let charts: Vec<Chart> = (0..6).map(|q| chart_of(group, q, "ge, q = 0")).collect();
    let r = common::svg(out, entry, "fig5_46.svg", &charts, 2);
    note_err(entry, "fig5_46", r);
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
    let mut charts = Vec::new();
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
                "case {} ({}) {}",
                r.case.case, r.case.profile_name, r.case.label
            ),
            "x [–]",
            "y [–]",
        )
        .equal_aspect();
        let (mut xmin, mut xmax) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut named = [false; 3];
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
            for &(x, _) in &pts {
                xmin = xmin.min(x);
                xmax = xmax.max(x);
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
            let (k, color, label) = match p.phase {
                Phase::None => (0, 7, "no contact"),
                Phase::A => (1, 0, "phase A (tip)"),
                Phase::B => (2, 1, "phase B (tangential)"),
            };
            let name = if named[k] { "" } else { label };
            named[k] = true;
            chart
                .series
                .push(Series::new(name, pts, Style::Line).color(color));
        }
        if xmin.is_finite() {
            let (a, b) = (xmin - 0.2, xmax + 0.2);
            let g: Vec<(f64, f64)> = (0..=200)
                .map(|i| {
                    let x = a + (b - a) * i as f64 / 200.0;
                    (x, r.case.profile.y(x))
                })
                .filter(|&(_, y)| y.is_finite() && y < 1.6)
                .collect();
            chart.series.push(
                Series::new(format!("contour {}", r.case.profile_name), g, Style::Dashed).color(3),
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
    let stem = format!("fig{}", fig.replace('.', "_"));
    let cols = if charts.len() > 1 { 2 } else { 1 };
    let r = common::svg(out, entry, &format!("{stem}.svg"), &charts, cols)
        .and_then(|()| common::csv(out, entry, &format!("{stem}.csv"), &w));
    note_err(entry, &stem, r);
}
