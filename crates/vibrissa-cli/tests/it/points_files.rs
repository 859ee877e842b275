//! Contours as CSV points files (issue 13): columns named with their units, any delimiter,
//! errors naming file, line and what is wrong, and tables that sweep and reconstruct.

use std::fs;

use vibrissa_cli::resolve::read_points_file;
use vibrissa_cli::units::UnitSystem;

use crate::common;
use common::*;

#[test]
fn points_files_name_their_columns_with_units_and_any_delimiter() {
    let dir = tempfile::tempdir().unwrap();
    let xs: Vec<f64> = (0..=50).map(|i| -2.5 + 0.1 * i as f64).collect();
    // Semicolons, `x_mm;y_mm`, decimal commas (as a spreadsheet in many locales writes).
    let mut semi = String::from("x_mm;y_mm\n");
    for &x in &xs {
        semi += &format!("{};{}\n", x * L_BETA_MM, g1(x) * L_BETA_MM).replace('.', ",");
    }
    let p = dir.path().join("semi.csv");
    fs::write(&p, &semi).unwrap();
    let (x, y) = read_points_file(&p, &physical_beta()).unwrap();
    assert_eq!(x.len(), xs.len());
    for ((a, b), &xt) in x.iter().zip(&y).zip(&xs) {
        assert!((a - xt).abs() < 1e-12, "x {a} vs {xt}");
        assert!((b - g1(xt)).abs() < 1e-12, "y {b} vs {}", g1(xt));
    }
    // Tabs, units in brackets, an extra column, a comment line; metres.
    let mut tab = String::from("# measured contour\nx [m]\ty [m]\tquality\n");
    for &xv in &xs {
        tab += &format!(
            "{}\t{}\tgood\n",
            xv * L_BETA_MM / 1e3,
            g1(xv) * L_BETA_MM / 1e3
        );
    }
    let p = dir.path().join("tab.tsv");
    fs::write(&p, &tab).unwrap();
    let (x, y) = read_points_file(&p, &physical_beta()).unwrap();
    assert!((x[0] + 2.5).abs() < 1e-12 && (y[50] - g1(2.5)).abs() < 1e-12);
    // A dimensionless scene reads plain `x,y` as whisker lengths.
    let p = dir.path().join("plain.csv");
    fs::write(&p, "x,y\n-1,1\n0,0.5\n1,1\n2,2.5\n").unwrap();
    let (x, y) = read_points_file(&p, &UnitSystem::DIMENSIONLESS).unwrap();
    assert_eq!((x[3], y[1]), (2.0, 0.5));
}

#[test]
fn points_file_errors_name_file_line_and_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let err = |name: &str, text: &str, units: &UnitSystem| {
        let p = dir.path().join(name);
        fs::write(&p, text).unwrap();
        read_points_file(&p, units).unwrap_err().to_string()
    };
    let d = UnitSystem::DIMENSIONLESS;
    // dimensionless scene: (file, contents, what the message must say)
    let cases = [
        (
            "noheader.csv",
            "-1,1\n0,0.5\n1,1\n2,2.5\n",
            "noheader.csv:1: the first line holds numbers",
        ),
        (
            "names.csv",
            "a;b\n-1;1\n0;0.5\n1;1\n2;2.5\n",
            "names.csv:1: the header must name an x and a y column",
        ),
        (
            "order.csv",
            "x,y\n-1,1\n1,0.5\n0.5,1\n2,2.5\n",
            "order.csv:4: column `x`: x = 0.5 does not increase",
        ),
        (
            "mm.csv",
            "x_mm,y_mm\n-1,1\n0,0.5\n1,1\n2,2.5\n",
            "mm.csv:1: column `x_mm`: values in `mm` need a physical scene",
        ),
        (
            "short.csv",
            "x,y\n-1,1\n0,0.5\n",
            "short.csv:3: expected at least 4 data rows, found 2",
        ),
        (
            "ragged.csv",
            "x\ty\n-1\t1\n0\n",
            "ragged.csv:3: expected 2 fields as in the header, found 1 (tab separated)",
        ),
    ];
    for (name, text, expected) in cases {
        let e = err(name, text, &d);
        assert!(e.contains(expected), "{e}");
    }
    // physical scene: the whole message, with the file's full path
    let e = err(
        "bad.csv",
        "x_mm;y_mm\n-1;1\n0;abc\n1;1\n2;2.5\n",
        &physical_beta(),
    );
    assert_eq!(
        e,
        format!(
            "{}:3: column `y_mm`: `abc` is not a number",
            dir.path().join("bad.csv").display()
        )
    );
}

#[test]

fn a_table_over_pm_2_5_sweeps_and_reconstructs() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::write(cwd.join("g1.csv"), g1_table("x;y", 1.0)).unwrap();
    round_trip(cwd, &sweep_flags("points:g1.csv", "30"), 5.0);
    // The table is copied into the folder and its scene points at the copy.
    assert!(cwd.join("out/profile.csv").is_file());
    let scene = fs::read_to_string(cwd.join("out/scene.ron")).unwrap();
    assert!(scene.contains("\"points:profile.csv\""), "{scene}");
}

#[test]

fn a_circle_post_of_radius_0_6_sweeps_and_reconstructs() {
    let dir = tempfile::tempdir().unwrap();
    round_trip(
        dir.path(),
        &[
            "--profile",
            "circle:0,1.3,0.6",
            "--q",
            "1",
            "--theta",
            "0.75",
            "--k",
            "20",
            "--points",
            "30",
        ],
        1.0,
    );
}

#[test]

fn a_physical_table_in_mm_with_semicolons_sweeps() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::write(cwd.join("g1mm.csv"), g1_table("x_mm;y_mm", L_BETA_MM)).unwrap();
    let scene = fs::read_to_string(scenes_dir().join("physical-beta-g1.ron"))
        .unwrap()
        .replace("Some(\"g1\")", "Some(\"points:g1mm.csv\")");
    fs::write(cwd.join("beta.ron"), scene).unwrap();
    round_trip(cwd, &["beta.ron", "--points", "30"], 0.003);
}
