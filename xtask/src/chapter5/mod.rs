//! Chapter 5: the sweeps of every case past its contour (Figs. 5.8-5.44), as observables
//! against the base position x0, scene sketches and one observables CSV per sweep.
//!
//! [`mod@observables`] draws the observables of each group of sweeps (Figs. 5.9-5.43, 5.46)
//! and writes the sweeps' CSVs; [`mod@sketch`] draws the scene sketches (Figs. 5.8, 5.21,
//! 5.34, 5.44). [`mod@style`] holds the house style both share: case labels, contact-phase
//! lines and the figure with one key above its panels.

mod friction;
mod observables;
mod sketch;
mod style;

use vibrissa_io::atomic::OutputDir;

use crate::common::{self, Ctx, SweepRun};
use crate::{Failure, Report};

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
