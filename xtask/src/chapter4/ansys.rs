//! Tables 4.2 and 4.3: the tip coordinates of the β vibrissa under a concentrated tip
//! force and under a distributed (fluid) load, ANSYS against the thesis's model and ours.

use vibrissa_io::atomic::OutputDir;
use vibrissa_io::csvio::CsvWriter;
use xtask::study;

use crate::captions::caption;
use crate::common::{self, note_err, sig};
use crate::Report;

/// Tables 4.2 (tip force) and 4.3 (fluid load).
pub(super) fn ansys_tables(out: &OutputDir, report: &mut Report) {
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
