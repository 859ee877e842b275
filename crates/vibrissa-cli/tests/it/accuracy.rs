//! `--tol` of `sweep` and `reconstruct` (accuracy on demand): the rows and points against the
//! default run's (~1e-10), the worst estimate reported and bounding the differences, the
//! scene's `sweep.tol` round trip, a request no row can meet (exit 1 naming the row) and bad
//! values (exit 2 naming `--tol`).

use crate::common;

use std::path::Path;

use common::{assert_ok, col, json, num, run, stderr, table, words};

/// The numeric columns `names` of a CSV file, row by row.
fn columns(path: &Path, names: &[&str]) -> Vec<Vec<f64>> {
    let (header, rows) = table(path);
    let idx: Vec<usize> = names.iter().map(|n| col(&header, n)).collect();
    rows.iter()
        .map(|r| idx.iter().map(|&i| num(&r[i])).collect())
        .collect()
}

/// The largest difference of two tables (NaN equal to NaN: the rows before contact).
fn largest_difference(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mut worst: f64 = 0.0;
    for (ra, rb) in a.iter().zip(b) {
        for (x, y) in ra.iter().zip(rb) {
            if !(x.is_nan() && y.is_nan()) {
                worst = worst.max((x - y).abs());
            }
        }
    }
    worst
}

#[test]
fn sweep_and_reconstruct_meet_the_accuracy_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sweep = [
        "sweep",
        "--profile",
        "g1",
        "--q",
        "5",
        "--theta",
        "0.75",
        "--k",
        "20",
    ];
    let flags = ["--points", "60", "--figures", "none", "--json", "--out"];
    let mut args: Vec<&str> = sweep.iter().chain(&flags).copied().collect();
    args.push("base");
    let base = json(&run(&args, d));
    assert!(base.get("tol").is_none() && base.get("max_estimate").is_none());
    let obs = ["x0", "Ax", "Ay", "MA", "phi0", "xc", "yc"];
    let truth = columns(&d.join("base/observables.csv"), &obs);
    for tol in ["1e-6", "1e-4"] {
        let t: f64 = tol.parse().unwrap();
        let out = format!("sw{tol}");
        let mut a = args.clone();
        a.pop();
        a.extend([out.as_str(), "--tol", tol]);
        let v = json(&run(&a, d));
        assert_eq!(v["tol"].as_f64(), Some(t));
        // contact rows are the elastica's (no linear rung), as the summary says
        assert_eq!(v["model_used"], "elastica");
        assert_eq!(v["rows"], base["rows"]);
        let est = v["max_estimate"].as_f64().unwrap();
        let diff = largest_difference(
            &columns(&d.join(&out).join("observables.csv"), &obs),
            &truth,
        );
        assert!(
            diff <= est && est <= t,
            "T {tol}: difference {diff:e}, estimate {est:e}"
        );
        // the scene remembers the accuracy: the folder's scene sweeps it again
        let scene = std::fs::read_to_string(d.join(&out).join("scene.ron")).unwrap();
        assert!(scene.contains("tol: Some("), "{scene}");
        let again = json(&run(
            &[
                "sweep",
                &format!("{out}/scene.ron"),
                "--figures",
                "none",
                "--json",
                "--out",
                "again",
            ],
            d,
        ));
        assert_eq!(again["tol"], v["tol"]);
        assert_eq!(again["max_estimate"], v["max_estimate"]);
    }
    // the default log reconstructed at T against the default reconstruction
    let rec = [
        "reconstruct",
        "base",
        "--figures",
        "none",
        "--json",
        "--out",
    ];
    let r0 = json(&run(&[&rec[..], &["rec"]].concat(), d));
    assert!(r0.get("max_estimate").is_none());
    let points = columns(&d.join("rec/reconstruction.csv"), &["x", "y"]);
    for tol in ["1e-6", "1e-4"] {
        let t: f64 = tol.parse().unwrap();
        let out = format!("rec{tol}");
        let v = json(&run(&[&rec[..], &[out.as_str(), "--tol", tol]].concat(), d));
        assert_eq!(v["tol"].as_f64(), Some(t));
        assert_eq!(v["model_used"], "elastica");
        let est = v["max_estimate"].as_f64().unwrap();
        let diff = largest_difference(
            &columns(&d.join(&out).join("reconstruction.csv"), &["x", "y"]),
            &points,
        );
        assert!(
            diff <= est && est <= t,
            "T {tol}: difference {diff:e}, estimate {est:e}"
        );
    }
}

#[test]
fn an_accuracy_no_row_meets_fails_naming_the_row() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = run(
        &words("sweep --profile g1 --q 5 --points 20 --figures none --out s --tol 1e-12"),
        d,
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("row ") && stderr(&o).contains("error estimate"),
        "{}",
        stderr(&o)
    );
    let o = run(
        &words("sweep --profile g1 --q 5 --points 20 --figures none --out s"),
        d,
    );
    assert!(o.status.success());
    let o = run(
        &words("reconstruct s --figures none --out r --tol 1e-12"),
        d,
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("observables.csv:") && stderr(&o).contains("--tol"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn bad_accuracies_are_refused_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = run(
        &words("sweep --profile g1 --q 5 --points 20 --figures none --out s"),
        d,
    );
    assert!(o.status.success());
    for bad in ["0", "abc", "1", "-1e-6", "nan"] {
        for args in [
            vec![
                "sweep",
                "--profile",
                "g1",
                "--q",
                "5",
                "--out",
                "x",
                "--tol",
                bad,
            ],
            vec!["reconstruct", "s", "--out", "x", "--tol", bad],
        ] {
            let o = run(&args, d);
            assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
            assert!(stderr(&o).contains("`--tol`"), "{args:?}: {}", stderr(&o));
        }
    }
    // a stream and the thesis method refuse it
    let o = run(&words("reconstruct --stream s/scene.ron --tol 1e-6"), d);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("`--tol`") && stderr(&o).contains("--stream"),
        "{}",
        stderr(&o)
    );
    let o = run(
        &words("reconstruct s --method thesis --out x --tol 1e-6"),
        d,
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("`--tol`"), "{}", stderr(&o));
    // a scene's sweep.tol out of range names its field
    std::fs::write(
        d.join("bad.ron"),
        "(whisker: (theta: 1.0, a: 0.0, b: 0.0, k: None), loads: (q: 5.0), profile: \
         Some(\"g1\"), sweep: Some((points: 20, tol: Some(2.0))))\n",
    )
    .unwrap();
    let o = run(&words("sweep bad.ron --out x"), d);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("sweep.tol"), "{}", stderr(&o));
}

#[test]
fn help_documents_the_accuracy() {
    let d = Path::new(".");
    for cmd in ["sweep", "reconstruct"] {
        let o = run(&[cmd, "--help"], d);
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            text.contains("--tol <T>") && text.contains("[1e-12, 1e-2]"),
            "{text}"
        );
    }
}

/// `solve --tol T` answers by linear small-deflection theory where its a-priori bound (plus
/// the grid's estimate) meets T: a weak flow at 1e-3 is linear theory's, within its estimate
/// of the default solve, and the summary says so; at the default accuracy the same flow is
/// the elastica's.
#[test]
fn a_weak_flow_at_a_loose_accuracy_is_answered_by_linear_theory() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let flow = [
        "solve",
        "--theta",
        "0.5",
        "--k",
        "10",
        "--q",
        "0.05",
        "--figures",
        "none",
    ];
    let reference = json(&run(&[&flow[..], &["--json", "--out", "r"]].concat(), d));
    assert_eq!(reference["stats"]["model_used"], "elastica");
    let auto = json(&run(
        &[&flow[..], &["--json", "--out", "a", "--tol", "1e-8"]].concat(),
        d,
    ));
    assert_eq!(auto["stats"]["model_used"], "elastica");
    let v = json(&run(
        &[&flow[..], &["--json", "--out", "l", "--tol", "1e-3"]].concat(),
        d,
    ));
    let st = &v["stats"];
    assert_eq!(st["model_used"], "linear", "{v}");
    assert_eq!(st["method_used"], "picard");
    let est = st["error_estimate"].as_f64().unwrap();
    assert!(est <= 1e-3, "{est}");
    for (part, key) in [("tip", "x"), ("tip", "y"), ("base", "MA"), ("base", "phi0")] {
        let (a, b) = (
            v[part][key].as_f64().unwrap(),
            reference[part][key].as_f64().unwrap(),
        );
        // the reference is within 1e-8 of the elastica
        assert!((a - b).abs() <= est + 1e-8, "{part}.{key}: {a} vs {b}");
    }
    let o = run(&[&flow[..], &["--out", "h", "--tol", "1e-3"]].concat(), d);
    assert_ok(&o);
    let summary = String::from_utf8_lossy(&o.stdout);
    // `auto` chose the method: no fallback is reported
    assert!(
        summary.contains("auto (n = 100) -> picard, linear model")
            && !summary.contains("fell back"),
        "{summary}"
    );
}
