//! Chapter 5: the sweeps of every case past its contour (Figs. 5.8-5.44), as observables
//! against the base position x0, scene sketches and one observables CSV per sweep.
//!
//! [`mod@observables`] draws the observables of each group of sweeps (Figs. 5.9-5.43, 5.46)
//! and writes the sweeps' CSVs; [`mod@sketch`] draws the scene sketches (Figs. 5.8, 5.21,
//! 5.34, 5.44). This module holds the house style both share: case labels, contact-phase
//! lines and the figure with one key above its panels.

mod friction;
mod observables;
mod sketch;

use contact_sim::Phase;
use vibrissa_io::atomic::OutputDir;
use vibrissa_plot::{Chart, Dash};

use crate::common::{self, Ctx, Layout, SweepRun};
use crate::{Entry, Failure, Report};

use observables::{observables, observables_all};
use sketch::sketch;

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
    // Beyond the thesis: the README's friction figure (issue 39).
    friction::friction(out, report);
    Ok(())
}

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

/// The colour, dash and legend text of a contact phase (the CLI's house style: no contact
/// dotted grey, phase A solid blue, phase B dashed orange).
fn phase_style(p: Phase) -> (usize, usize, Dash, &'static str) {
    match p {
        Phase::None => (0, 7, Dash::Dotted, "no contact"),
        Phase::A => (1, 0, Dash::Solid, "phase A (tip)"),
        Phase::B => (2, 1, Dash::Dashed, "phase B (tangential)"),
    }
}

/// Writes `charts` as one figure `name` (SVG and PNG) laid out by `layout` (`cols` panels
/// a row, one key for all panels above them from the first chart's legend, and the note
/// under it); records the file. With `column`, the figure is one journal column wide
/// instead of the page.
fn figure(
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    charts: &[Chart],
    layout: &Layout<'_>,
    column: bool,
) -> Result<(), String> {
    let style = if column { common::COLUMN } else { common::PAGE };
    common::svg_headed(style, out, entry, name, charts, layout)
}
