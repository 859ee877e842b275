//! Self-describing output folders (issue 13): `scene.ron` and units sidecars that
//! `reconstruct DIR` reads with no further flags, one row numbering in text, JSON and CSV,
//! and the folder's own refusals (what it lacks, writing over what it reads).

use std::fs;

use crate::common;
use common::*;

#[test]
fn reconstruct_dir_round_trip_dimensionless() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let v = round_trip(cwd, &sweep_flags("g1", "24"), 5.0);
    assert_eq!(v["units"], "dimensionless");
    let units = fs::read_to_string(cwd.join("out/observables.units.csv")).unwrap();
    assert_eq!(
        units,
        "x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi,ft,slip,y0,gamma\n1,1,1,1,rad,1,1,,1,1,rad,1,,1,rad\n"
    );
    // The scene states every parameter, the true point count included.
    let scene = fs::read_to_string(cwd.join("out/scene.ron")).unwrap();
    for needle in [
        "theta: 0.75",
        "k: Some(20.0)",
        "q: 5.0",
        "points: 24",
        "\"g1\"",
    ] {
        assert!(scene.contains(needle), "scene.ron lacks {needle}:\n{scene}");
    }
    // Flags still override the folder's scene: a wrong taper makes the rows inconsistent.
    let o = run(
        &["reconstruct", "out", "--theta", "0.5", "--out", "bad"],
        cwd,
    );
    assert!(!o.status.success());
    let e = stderr(&o);
    // refused, naming the log: no row fits the free whisker of the wrong taper, or no
    // contact point is consistent with it
    assert!(
        e.contains("observables.csv:")
            && (e.contains("no consistent contact point") || e.contains("check the whisker")),
        "{e}"
    );
    assert!(!cwd.join("bad").exists());
}

#[test]
fn reconstruct_dir_round_trip_physical() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let scene = scenes_dir().join("physical-beta-g1.ron");
    let scene = scene.to_str().unwrap();
    let v = round_trip(cwd, &[scene, "--points", "30"], 0.003);
    assert_eq!(v["units"], "physical");
    let units = fs::read_to_string(cwd.join("out/observables.units.csv")).unwrap();
    assert_eq!(
        units,
        "x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi,ft,slip,y0,gamma\nmm,N,N,N mm,rad,N,mm,,mm,mm,rad,N,,mm,rad\n"
    );
    // Positions are in mm: the pre-contact rows carry s1 = L = 66.2 mm and Ax = -Q L in N.
    let (oh, orows) = table(&cwd.join("out/observables.csv"));
    assert!(rel(num(&orows[0][col(&oh, "s1")]), L_BETA_MM) < 1e-12);
    assert!(rel(-num(&orows[0][col(&oh, "Ax")]), 0.003 * 0.0662) < 1e-9);
    // The log in mm and N is refused with a dimensionless scene: its sidecar says why.
    fs::write(
        cwd.join("dimless.ron"),
        "(whisker: (theta: 0.75, k: Some(20.0)))",
    )
    .unwrap();
    let o = run(&["reconstruct", "out", "dimless.ron", "--out", "bad"], cwd);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("observables.units.csv:2: column `x0`: values in `mm` need a physical scene"),
        "{e}"
    );
    // Figures say their units, small forces and moments with a prefix.
    let svg = svg_text(&fs::read_to_string(cwd.join("out/observables.svg")).unwrap());
    for needle in ["x0 [mm]", "Ax [µN]", "MA [mN mm]", "q = 0.003 N/m"] {
        assert!(svg.contains(needle), "observables.svg lacks {needle}");
    }
    let svg = fs::read_to_string(cwd.join("rec/reconstruction.svg")).unwrap();
    assert!(svg.contains("x [mm]") && svg.contains("y [mm]"));
}

#[test]
fn rows_are_counted_the_same_way_in_text_json_and_csv() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let mut args = vec!["sweep"];
    args.extend(sweep_flags("g1", "12"));
    let mut a = args.to_vec();
    a.extend(["--json", "--out", "j"]);
    let v = json(&run(&a, cwd));
    let mut a = args.to_vec();
    a.extend(["--out", "t"]);
    let text = stdout(&run(&a, cwd));
    let (h, rows) = table(&cwd.join("j/observables.csv"));
    let phase = col(&h, "phase");
    let first = rows.iter().position(|r| r[phase] != "none").unwrap() + 1;
    let last = rows.iter().rposition(|r| r[phase] != "none").unwrap() + 1;
    let contact = rows.iter().filter(|r| r[phase] != "none").count();
    assert_eq!(v["rows"].as_u64().unwrap() as usize, rows.len());
    assert_eq!(v["first_contact_row"].as_u64().unwrap() as usize, first);
    assert_eq!(v["separation_row"].as_u64().unwrap() as usize, last);
    assert_eq!(v["contact_rows"].as_u64().unwrap() as usize, contact);
    assert_eq!(v["points_requested"], 12);
    assert_eq!(
        v["event_rows"].as_u64().unwrap() as usize,
        contact - 12,
        "--points N gives N contact rows plus the event rows"
    );
    for key in ["first_contact", "separation", "phases"] {
        assert!(v[key].is_string(), "{key}: {v}");
    }
    assert!(text.contains(&format!("{} rows (", rows.len())), "{text}");
    assert!(
        text.contains(&format!(
            "first contact {} at row {first} ",
            v["first_contact"].as_str().unwrap()
        )),
        "{text}"
    );
    assert!(text.contains(&format!("at row {last} ")), "{text}");
    // The events of the JSON name rows of the CSV.
    for e in v["events"].as_array().unwrap() {
        let row = e["row"].as_u64().unwrap() as usize;
        assert_eq!(
            num(&rows[row - 1][col(&h, "x0")]),
            e["x0"].as_f64().unwrap()
        );
    }
    // reconstruct numbers rows the same way: its first reconstructed row is a contact row
    // with a contact force, right after the flow-only rows.
    let v2 = json(&run(&["reconstruct", "j", "--json", "--out", "r"], cwd));
    let r1 = v2["first_contact_row"].as_u64().unwrap() as usize;
    assert!(r1 == first || r1 == first + 1, "{r1} vs {first}");
    assert!(num(&rows[r1 - 1][col(&h, "f")]) > 0.0);
    assert_eq!(v2["rows"].as_u64().unwrap() as usize, rows.len());
    // one point per row with a contact force above the log's precision (a release row at
    // f ~ 1e-12 is the free whisker within it)
    let with_force = rows[r1 - 1..]
        .iter()
        .filter(|r| num(&r[col(&h, "f")]) > 1e-9)
        .count();
    assert_eq!(v2["points"].as_u64().unwrap() as usize, with_force);
}

#[test]
fn demo_scene_records_the_points_it_used() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&["demo", "--points", "5", "--out", "d"], dir.path());
    let text = stdout(&o);
    let scene = fs::read_to_string(dir.path().join("d/scene.ron")).unwrap();
    assert!(scene.contains("points: 5,"), "{scene}");
    assert!(!scene.contains("points: 120"));
    assert!(text.contains("5 requested"), "{text}");
    // The scene reads back and reproduces the demo's folder.
    let o = run(&["sweep", "d/scene.ron", "--out", "again"], dir.path());
    stdout(&o);
    assert_eq!(
        fs::read_to_string(dir.path().join("d/observables.csv")).unwrap(),
        fs::read_to_string(dir.path().join("again/observables.csv")).unwrap()
    );
}

#[test]
fn reconstruct_dir_names_what_the_folder_lacks() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::create_dir(cwd.join("empty")).unwrap();
    let o = run(&["reconstruct", "empty", "--out", "rec"], cwd);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("empty/observables.csv: a sweep folder needs observables.csv"),
        "{e}"
    );
    fs::write(cwd.join("empty/observables.csv"), "x0,Ax,Ay,MA,phi0\n").unwrap();
    let o = run(&["reconstruct", "empty", "--out", "rec"], cwd);
    let e = stderr(&o);
    assert!(
        e.contains("empty/scene.ron: a sweep folder needs its scene.ron"),
        "{e}"
    );
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(!cwd.join("rec").exists());
}

/// `reconstruct DIR --out DIR` would replace the sweep's folder with the reconstruction: it
/// is refused before anything is written, and the sweep's files stay.
#[test]
fn reconstruct_refuses_to_write_over_the_folder_it_reads() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    stdout(&run(
        &[
            "sweep",
            "--profile",
            "g1",
            "--q",
            "5",
            "--points",
            "5",
            "--out",
            "out",
        ],
        cwd,
    ));
    let before = fs::read(cwd.join("out/observables.csv")).unwrap();
    for target in ["out", "."] {
        let o = run(&["reconstruct", "out", "--out", target], cwd);
        assert!(!o.status.success(), "--out {target} accepted");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("--out") && err.contains("holds the log"),
            "{err}"
        );
    }
    assert_eq!(fs::read(cwd.join("out/observables.csv")).unwrap(), before);
    assert!(!cwd.join("out/reconstruction.csv").exists());
}
