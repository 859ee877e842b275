//! The pose columns through the binary (issue 38, item 3; docs/whisking-recon.md, "Paths in
//! the calibration"): `vibrissa sweep --motion path:FILE` along poses changing x0, y0 and
//! gamma with the follicle tensing (`k` per row), then `calibrate` of its log (theta, A, B
//! fitted, k the log's known column) gives the whisker back, and `reconstruction.csv` and
//! `residuals.csv` carry the log's `y0`, `gamma`, `k` as given; a translate log's outputs
//! are those of before byte for byte; a path row that changes only k is refused by line.
//!
//! `cargo test -p vibrissa-cli --test it -- path_calib::wleft`

use crate::common;

use std::fs;

use common::{col, json, parse, run, stderr};

const PEG: &str = "peg:-0.25,0.55";
const WHISKER: [&str; 10] = [
    "--theta",
    "0.8",
    "--a",
    "0.2",
    "--b",
    "0.1",
    "--q",
    "1",
    "--alpha-deg",
    "10",
];
/// Three poses changing x0, y0 and gamma at once, the follicle tensing 15 -> 40 -> 25.
const PATH: &str = "x0,y0,gamma_deg,k\n0.05,-0.1,-6,15\n0.0,-0.06,23,40\n-0.04,0.0,57,25\n";

/// The columns `names` of a CSV file's rows, as numbers.
fn columns(text: &str, names: &[&str]) -> Vec<Vec<f64>> {
    let (h, rows) = parse(text);
    let idx: Vec<usize> = names.iter().map(|n| col(&h, n)).collect();
    rows.iter()
        .map(|r| idx.iter().map(|&i| num(&r[i])).collect())
        .collect()
}

fn num(cell: &str) -> f64 {
    cell.parse()
        .unwrap_or_else(|_| panic!("`{cell}` is not a number"))
}

/// The last three cells of a row, as numbers (the pose columns `y0, gamma, k`).
fn pose_of(r: &[String]) -> Vec<f64> {
    r[r.len() - 3..].iter().map(|c| num(c)).collect()
}

#[test]
fn wleft_a_path_log_calibrates_and_its_outputs_carry_the_pose() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::write(cwd.join("path.csv"), PATH).unwrap();
    let mut args = vec!["sweep", "--motion", "path:path.csv", "--profile", PEG];
    args.extend(WHISKER);
    args.extend(["--points", "30", "--figures", "none", "--out", "sw"]);
    let o = run(&args, cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    let log = fs::read_to_string(cwd.join("sw/observables.csv")).unwrap();
    let (h, rows) = parse(&log);
    assert!(h.iter().any(|c| c == "k"), "{h:?}");
    let contact = rows
        .iter()
        .filter(|r| r[col(&h, "phase")] != "none")
        .count();
    assert!(contact >= 25, "{contact} contact rows");

    // calibrate: theta, A, B from the default start, k the log's column
    let o = run(
        &[
            "calibrate",
            "sw/observables.csv",
            "--profile",
            PEG,
            "--fit",
            "theta,a,b",
            "--json",
            "--out",
            "cal",
        ],
        cwd,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v = json(&o);
    for (name, truth) in [("theta", 0.8), ("a", 0.2), ("b", 0.1)] {
        let est = v["parameters"][name]["value"].as_f64().unwrap();
        assert!((est - truth).abs() < 1e-8, "{name}: {est} ({v})");
    }
    let l = &v["logs"][0];
    assert!((l["q"].as_f64().unwrap() - 1.0).abs() < 1e-7, "{l}");
    // asking for k as well: refused, k is the log's
    let o = run(&["calibrate", "sw/observables.csv", "--profile", PEG], cwd);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("k is known"), "{}", stderr(&o));

    // residuals.csv: the pose columns of each row as the log gave them
    let res = fs::read_to_string(cwd.join("cal/residuals.csv")).unwrap();
    let (rh, rrows) = parse(&res);
    assert_eq!(rrows.len(), rows.len());
    assert_eq!(&rh[rh.len() - 3..], ["y0", "gamma", "k"]);
    let given = columns(&log, &["y0", "gamma", "k"]);
    let row = col(&rh, "row");
    for r in &rrows {
        let i: usize = r[row].parse().unwrap();
        // the same numbers, bit for bit (written in the shortest round-trip form)
        assert_eq!(pose_of(r), given[i - 1], "row {i}");
    }
    let units = fs::read_to_string(cwd.join("cal/residuals.units.csv")).unwrap();
    assert!(
        units.lines().next().unwrap().ends_with("y0,gamma,k"),
        "{units}"
    );

    // reconstruct: reconstruction.csv carries them too, row by row
    let mut args = vec!["reconstruct", "sw/observables.csv", "--profile", PEG];
    args.extend(&WHISKER[..6]);
    args.extend(["--k", "20", "--out", "rec"]);
    let o = run(&args, cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    let rec = fs::read_to_string(cwd.join("rec/reconstruction.csv")).unwrap();
    let (ch, crows) = parse(&rec);
    assert_eq!(&ch[ch.len() - 3..], ["y0", "gamma", "k"]);
    let x0s = columns(&log, &["x0"]);
    for r in &crows {
        // the row of the log: x0 and the pose identify it along the path
        let pose = pose_of(r);
        let i = given
            .iter()
            .position(|g| *g == pose)
            .unwrap_or_else(|| panic!("{pose:?} not a row of the log"));
        assert_eq!(num(&r[0]), x0s[i][0]);
        let err: f64 = r[col(&ch, "error")].parse().unwrap();
        assert!(err < 1e-8, "{r:?}");
    }
}

/// A translate log (its `y0`, `gamma` columns all 0) reconstructs and calibrates to the files
/// of a log without those columns, byte for byte (the contract's columns only).
#[test]
fn wleft_a_translate_logs_outputs_are_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let mut args = vec!["sweep", "--profile", "g2"];
    args.extend(WHISKER);
    args.extend([
        "--k",
        "20",
        "--points",
        "20",
        "--figures",
        "none",
        "--out",
        "sw",
    ]);
    let o = run(&args, cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    let log = fs::read_to_string(cwd.join("sw/observables.csv")).unwrap();
    let (h, _) = parse(&log);
    assert!(h.iter().any(|c| c == "gamma"), "{h:?}");
    // the same log without its pose columns (an old translate log)
    let keep: Vec<usize> = (0..h.len())
        .filter(|&i| h[i] != "y0" && h[i] != "gamma")
        .collect();
    let old: String = log
        .lines()
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&i| c[i]).collect::<Vec<_>>().join(",") + "\n"
        })
        .collect();
    fs::write(cwd.join("old.csv"), old).unwrap();
    fs::copy(cwd.join("sw/observables.csv"), cwd.join("new.csv")).unwrap();
    for name in ["old", "new"] {
        let log = format!("{name}.csv");
        let mut args = vec!["reconstruct", &log, "--profile", "g2"];
        args.extend(&WHISKER[..6]);
        let out = format!("rec-{name}");
        args.extend(["--k", "20", "--figures", "none", "--out", &out]);
        let o = run(&args, cwd);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = format!("cal-{name}");
        let o = run(
            &[
                "calibrate",
                &log,
                "--profile",
                "g2",
                "--fit",
                "theta,b",
                "--theta",
                "0.8",
                "--a",
                "0.2",
                "--b",
                "0",
                "--k",
                "20",
                "--figures",
                "none",
                "--out",
                &out,
            ],
            cwd,
        );
        assert!(o.status.success(), "{}", stderr(&o));
    }
    for f in [
        "rec-{}/reconstruction.csv",
        "rec-{}/reconstruction.units.csv",
        "cal-{}/residuals.csv",
        "cal-{}/residuals.units.csv",
    ] {
        let a = fs::read(cwd.join(f.replace("{}", "old"))).unwrap();
        let b = fs::read(cwd.join(f.replace("{}", "new"))).unwrap();
        assert!(a == b, "{f} differs");
    }
    let rec = fs::read_to_string(cwd.join("rec-new/reconstruction.csv")).unwrap();
    assert!(
        rec.starts_with("x0,x,y,s1,f,psi,phase,sigma,residual,hypotheses,error\n"),
        "{}",
        rec.lines().next().unwrap()
    );
}

/// A path row that changes only k (the pose of the row before): refused in one line naming
/// the file's line and the column, exit 2, nothing written.
#[test]
fn wleft_a_k_only_path_row_is_refused_by_line() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::write(
        cwd.join("tense.csv"),
        "x0,y0,gamma_deg,k\n0,0,0,15\n0,0,20,15\n0,0,20,40\n0,0,40,40\n",
    )
    .unwrap();
    let mut args = vec!["sweep", "--motion", "path:tense.csv", "--profile", PEG];
    args.extend(WHISKER);
    args.extend(["--figures", "none", "--out", "sw"]);
    let o = run(&args, cwd);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("tense.csv:4") && e.contains("only k") && e.contains("MA = 0"),
        "{e}"
    );
    assert_eq!(e.trim().lines().count(), 1, "{e}");
    assert!(!cwd.join("sw").exists());
}
