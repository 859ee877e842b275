//! Snapshot (insta, rounded) of Tables 4.2/4.3: our exact elastica next to the thesis's
//! ANSYS tips (the study lives in the xtask that draws the charts).

use xtask::study::{ansys_comparison, AnsysLoad};

#[test]
fn tables_4_2_and_4_3_against_ansys() {
    let mut out = String::from("kind load | ANSYS x1 y1 | ours x1 y1 (mm) | err x y (%)\n");
    for r in ansys_comparison().unwrap() {
        let kind = match r.load_kind {
            AnsysLoad::Tip => "f",
            AnsysLoad::Fluid => "q",
        };
        out.push_str(&format!(
            "{kind} {:>4} | {:>7.3} {:>7.3} | {:>7.3} {:>7.3} | {:.2} {:.2}\n",
            r.load,
            r.ansys_x1_mm,
            r.ansys_y1_mm,
            r.ours_x1_mm,
            r.ours_y1_mm,
            r.err_ours_x_pct,
            r.err_ours_y_pct
        ));
    }
    insta::assert_snapshot!(out);
}
