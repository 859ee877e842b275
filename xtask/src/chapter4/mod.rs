//! Chapter 4: tip coordinates against load and elastica families of scenarios 1-18
//! (Figs. 4.3-4.29), the ANSYS comparison (Tables 4.2, 4.3), and the beam-model issue's
//! work-precision charts and stability maps.
//!
//! One module per part of the chapter: [`tip_coordinates`] (Figs. 4.3, 4.4, 4.7, 4.9,
//! 4.11, 4.14, 4.16, 4.17), [`elastica`] (the elastica families, Figs. 4.5-4.29),
//! [`ansys`] (Tables 4.2, 4.3), [`work_precision`] and [`stability`] (the beam-model
//! issue's charts); [`styles`] holds how curve families and methods are drawn.

mod ansys;
mod elastica;
mod stability;
mod styles;
mod tip_coordinates;
mod work_precision;

use beam_model::Method;
use vibrissa_io::atomic::OutputDir;

use crate::common::{self, Ctx};
use crate::{Failure, Report};

/// The thesis's FDM: h = 0.01.
const FDM: Method = Method::Fdm { n: 100 };
/// The thesis's RK4 comparison: h = 0.01.
const RK4: Method = Method::Rk4 { n: 100 };
/// Points of the load grids of the tip-coordinate figures.
const GRID: usize = 40;

fn accurate() -> Method {
    Method::accurate()
}

/// A part of the chapter: writes its figures and records them (or their failures).
type Part = fn(&OutputDir, &mut Report);

/// Runs chapter 4; every figure that fails is recorded in the report and the others go on.
pub fn run(out: &OutputDir, report: &mut Report, _ctx: &mut Ctx) -> Result<(), Failure> {
    // Work-precision first and alone, so that its timings are not disturbed by other work.
    let parts: [(&str, Part); 7] = [
        ("work-precision charts", work_precision::work_precision),
        ("Figs. 4.3, 4.4", tip_coordinates::fig_4_3_4_4),
        ("Fig. 4.7", tip_coordinates::fig_4_7),
        ("tip-coordinate figures", tip_coordinates::tip_figures),
        ("elastica figures", elastica::elastica_figures),
        ("Tables 4.2, 4.3 (ANSYS)", ansys::ansys_tables),
        ("stability maps", stability::stability_maps),
    ];
    for (i, (what, part)) in parts.into_iter().enumerate() {
        common::step(4, i + 1, parts.len(), what);
        part(out, report);
    }
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
}
