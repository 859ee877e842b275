//! End-to-end tests of `vibrissa calibrate`: sweep past a known post -> calibrate from a
//! wrong start -> the JSON against the truth; the calibrated scene.ron reused by `sweep` and
//! `reconstruct`; physical units with E I; one-line errors naming the culprit.

use std::fs;
use std::path::Path;
use std::process::Output;

use crate::common;
use common::{assert_ok, json, one_line_error, run, stderr, words};

/// A failure: exit code `code`, one line on stderr mentioning every needle, no panic, no
/// output folder `cal`.
fn assert_fails(o: &Output, code: i32, needles: &[&str], cwd: &Path) {
    assert_eq!(o.status.code(), Some(code), "stderr: {}", stderr(o));
    one_line_error(o, needles);
    assert!(!cwd.join("cal").exists(), "no output directory on failure");
}

const POST: &str = "circle:-0.2,1.3,0.5";

/// The true whisker's sweep past the post into `cwd/post`.
fn sweep_post(cwd: &Path) {
    let o = run(
        &[
            "sweep",
            "--profile",
            POST,
            "--theta",
            "0.6",
            "--a",
            "0.5",
            "--b",
            "0.3",
            "--k",
            "20",
            "--q",
            "2",
            "--alpha-deg",
            "10",
            "--points",
            "40",
            "--figures",
            "none",
            "--out",
            "post",
        ],
        cwd,
    );
    assert_ok(&o);
}

#[test]
fn sweep_then_calibrate_gives_the_truth_and_a_reusable_scene() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    sweep_post(cwd);
    // a wrong start (the folder's scene.ron holds the truth: the flags override it)
    let o = run(
        &words("calibrate post --theta 0.8 --a 0.3 --b 0.2 --k 30 --json --out cal"),
        cwd,
    );
    let v = json(&o);
    let p = &v["parameters"];
    for (name, truth) in [("theta", 0.6), ("a", 0.5), ("b", 0.3), ("k", 20.0)] {
        let est = p[name]["value"].as_f64().unwrap();
        assert!((est - truth).abs() < 1e-7 * truth.max(1.0), "{name}: {est}");
        assert_eq!(p[name]["identifiable"], true);
        assert!(p[name]["stderr"].as_f64().unwrap() < 1e-6);
    }
    let log = &v["logs"][0];
    assert!((log["q"].as_f64().unwrap() - 2.0).abs() < 1e-8);
    assert!((log["alpha_deg"].as_f64().unwrap() - 10.0).abs() < 1e-6);
    assert!(log["rows"].as_u64().unwrap() >= 40);
    assert!(v["rms_residual"].as_f64().unwrap() < 1e-8);
    for f in [
        "scene.ron",
        "residuals.csv",
        "residuals.units.csv",
        "contour-1.svg",
        "residuals.svg",
    ] {
        assert!(cwd.join("cal").join(f).is_file(), "{f}");
    }
    // the flow known and held fixed
    let o = run(
        &words("calibrate post --theta 0.8 --k 30 --q 2 --alpha-deg 10 --json"),
        cwd,
    );
    let fixed = json(&o);
    assert_eq!(fixed["logs"][0]["q"].as_f64().unwrap(), 2.0);
    assert_eq!(fixed["logs"][0]["q_stderr"].as_f64().unwrap(), 0.0);
    assert!((fixed["parameters"]["theta"]["value"].as_f64().unwrap() - 0.6).abs() < 1e-7);
    let res = fs::read_to_string(cwd.join("cal/residuals.csv")).unwrap();
    assert!(res.starts_with("log,row,x0,kind,s1,x,y,distance,sigma,chi\n"));
    calibrated_scene_is_reusable(cwd);
}

/// The calibrated scene `cal/scene.ron` reconstructs an unknown object swept with the true
/// whisker, and is a scene `sweep` runs.
fn calibrated_scene_is_reusable(cwd: &Path) {
    let o = run(&words("sweep --profile parabola:1.5,-0.2,0.55 --theta 0.6 --a 0.5 --b 0.3 --k 20 --q 2 --points 20 --figures none --out unknown"),
        cwd,
    );
    assert_ok(&o);
    let o = run(&words("reconstruct unknown/observables.csv cal/scene.ron --profile parabola:1.5,-0.2,0.55 --json --figures none --out rec"),
        cwd,
    );
    let r = json(&o);
    assert!(r["max_error"].as_f64().unwrap() < 1e-7, "{r}");
    // and is a scene `sweep` runs
    let o = run(
        &words("sweep cal/scene.ron --points 10 --figures none --out again"),
        cwd,
    );
    assert_ok(&o);
}

#[test]
fn a_log_of_the_free_whisker_only_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    sweep_post(cwd);
    // the 10 rows before contact only: nothing to fit theta, a, b to (issue 34: it exited 0
    // with "rms distance -0.000e0")
    let text = fs::read_to_string(cwd.join("post/observables.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    fs::write(cwd.join("free.csv"), lines[..11].join("\n") + "\n").unwrap();
    let o = run(
        &[
            "calibrate",
            &format!("free.csv={POST}"),
            "--theta",
            "0.8",
            "--k",
            "30",
            "--json",
            "--out",
            "cal",
        ],
        cwd,
    );
    assert_fails(
        &o,
        2,
        &["free.csv", "free whisker", "0 of 0 contact row"],
        cwd,
    );
    // the follicle law alone gives k from the same rows (the shape held at the truth's: a
    // wrong one leaves m(1) != 0, and a warning)
    let o = run(
        &[
            "calibrate",
            &format!("free.csv={POST}"),
            "--fit",
            "k",
            "--theta",
            "0.6",
            "--a",
            "0.5",
            "--b",
            "0.3",
            "--json",
        ],
        cwd,
    );
    let v = json(&o);
    let k = v["parameters"]["k"]["value"].as_f64().unwrap();
    assert!((k - 20.0).abs() < 1e-6, "{v}");
    // rows of one whisker at one base position (x0 constant): no contact row either
    let row = lines[30];
    let same: Vec<&str> = std::iter::once(lines[0]).chain([row; 6]).collect();
    fs::write(cwd.join("same.csv"), same.join("\n") + "\n").unwrap();
    let o = run(
        &["calibrate", &format!("same.csv={POST}"), "--out", "cal"],
        cwd,
    );
    assert_fails(&o, 2, &["same.csv", "contact row"], cwd);
    // three contact rows and no row before contact: not taken for the flow's rows; the
    // flow fitted from contact rows alone is said
    let three: Vec<&str> = std::iter::once(lines[0])
        .chain([lines[25], lines[30], lines[35]])
        .collect();
    fs::write(cwd.join("three.csv"), three.join("\n") + "\n").unwrap();
    let o = run(&["calibrate", &format!("three.csv={POST}"), "--json"], cwd);
    if o.status.success() {
        let v = json(&o);
        assert_eq!(v["logs"][0]["pre_contact"], 0, "{v}");
        let w = v["warnings"].as_array().unwrap();
        assert!(
            w.iter()
                .any(|w| w.as_str().unwrap().contains("no row of the free whisker")),
            "{v}"
        );
    } else {
        assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
        assert_ne!(o.status.code(), Some(0));
    }
}

#[test]
fn unclear_flags_are_named_in_the_users_units() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    sweep_post(cwd);
    // issue 34: `--alpha-deg 90` exited 1 showing the angle in radians
    let o = run(&words("calibrate post --q 2 --alpha-deg 90 --out cal"), cwd);
    assert_fails(&o, 2, &["--alpha-deg", "`90`", "(-90, 90) degrees"], cwd);
    // `c1.csv=` said "invalid value `` for `--profile`"
    let o = run(&words("calibrate post/observables.csv= --out cal"), cwd);
    assert_fails(
        &o,
        2,
        &["post/observables.csv=", "no contour after `=`"],
        cwd,
    );
}

#[test]
fn physical_units_fit_the_bending_stiffness() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    // the beta whisker with E = 1.4 GPa sweeps; the start says 2 GPa
    let truth = "(units: Physical(preset: \"beta\"), whisker: (theta: 0.6, a: 20.0, b: 5.0, k: Some(2e-5)), loads: (q: 0.002), profile: Some(\"circle:-13,86,33\"), sweep: Some((points: 40)))";
    fs::write(cwd.join("truth.ron"), truth).unwrap();
    let o = run(&words("sweep truth.ron --figures none --out sw"), cwd);
    assert_ok(&o);
    let start = truth
        .replace(
            "preset: \"beta\"",
            "preset: \"beta\", youngs_modulus_gpa: Some(2.0)",
        )
        .replace("theta: 0.6", "theta: 0.7");
    fs::write(cwd.join("start.ron"), start).unwrap();
    let o = run(&words("calibrate sw/observables.csv --scene start.ron --fit theta,a,b,k,ei --json --figures none --out cal"),
        cwd,
    );
    let v = json(&o);
    let p = &v["parameters"];
    // E I of the beta whisker: 1.4 GPa * pi (0.225 mm)^4 / 64
    let ei = 1.4e9 * std::f64::consts::PI * 0.225e-3f64.powi(4) / 64.0;
    let est = p["ei"]["value"].as_f64().unwrap();
    assert!((est / ei - 1.0).abs() < 1e-6, "ei {est} vs {ei}: {v}");
    assert!(
        (p["k"]["value"].as_f64().unwrap() / 2e-5 - 1.0).abs() < 1e-6,
        "{v}"
    );
    assert!(
        (p["a"]["value"].as_f64().unwrap() / 20.0 - 1.0).abs() < 1e-6,
        "{v}"
    );
    assert!(
        (v["logs"][0]["q"].as_f64().unwrap() / 0.002 - 1.0).abs() < 1e-6,
        "{v}"
    );
    let scene = fs::read_to_string(cwd.join("cal/scene.ron")).unwrap();
    // the fitted modulus, written into the scene's physical units (1.4 GPa)
    let e_gpa: f64 = scene
        .split("youngs_modulus_gpa: Some(")
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no fitted modulus in {scene}"));
    assert!((e_gpa / 1.4 - 1.0).abs() < 1e-6, "{scene}");
    // ei in a dimensionless log is refused
    fs::remove_dir_all(cwd.join("cal")).unwrap();
    let o = run(
        &words("calibrate sw/observables.csv --profile g1 --fit ei"),
        cwd,
    );
    assert_fails(&o, 2, &["--fit", "ei", "dimensionless"], cwd);
}

#[test]
fn bad_input_names_the_culprit() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    sweep_post(cwd);
    let o = run(&words("calibrate nowhere.csv --profile g1 --out cal"), cwd);
    assert_fails(&o, 2, &["nowhere.csv"], cwd);
    let o = run(&words("calibrate post --fit theta,zeta --out cal"), cwd);
    assert_fails(&o, 2, &["--fit", "zeta"], cwd);
    let o = run(&words("calibrate post/observables.csv --out cal"), cwd);
    assert_fails(&o, 2, &["no known contour", "--profile"], cwd);
    let o = run(&words("calibrate post=parabola:x --out cal"), cwd);
    assert_fails(&o, 2, &["parabola:x"], cwd);
    // a value that is not a number names the file, line and column
    let text = fs::read_to_string(cwd.join("post/observables.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut cells: Vec<&str> = lines[5].split(',').collect();
    cells[1] = "abc";
    lines[5] = cells.join(",");
    fs::write(cwd.join("bad.csv"), lines.join("\n") + "\n").unwrap();
    let o = run(
        &["calibrate", &format!("bad.csv={POST}"), "--out", "cal"],
        cwd,
    );
    assert_fails(&o, 2, &["bad.csv:6", "Ax"], cwd);
}

#[test]
fn advice_ranks_candidate_objects_before_any_experiment() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let o = run(
        &[
            "calibrate",
            "--advise",
            POST,
            "--advise",
            "g2",
            "--advise",
            "circle:9,9,0.1",
            "--theta",
            "0.6",
            "--a",
            "0.5",
            "--b",
            "0.3",
            "--k",
            "20",
            "--q",
            "2",
            "--points",
            "30",
            "--json",
        ],
        cwd,
    );
    let v = json(&o);
    let advice = v["advice"].as_array().unwrap();
    assert_eq!(advice.len(), 3);
    for a in &advice[..2] {
        for name in ["theta", "a", "b", "k"] {
            let sd = a["parameters"][name]["stderr"].as_f64().unwrap();
            assert!(sd > 0.0 && sd < 1.0, "{a}");
        }
    }
    // a post the whisker never reaches gets no advice, said so
    assert!(
        advice[2]["error"]
            .as_str()
            .unwrap()
            .contains("never touches"),
        "{v}"
    );
    let o = run(&words("calibrate x.csv --advise g2"), cwd);
    assert_fails(&o, 2, &["--advise"], cwd);
}

#[test]
fn two_logs_of_one_whisker_past_two_objects() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    sweep_post(cwd);
    let o = run(&words("sweep --profile g2 --theta 0.6 --a 0.5 --b 0.3 --k 20 --q 1 --alpha-deg -20 --points 30 --figures none --out bar"),
        cwd,
    );
    assert_ok(&o);
    // a sweep folder and a bare CSV with its own contour, fitted jointly
    let o = run(&words("calibrate post bar/observables.csv=g2 --theta 0.8 --a 0.3 --b 0.2 --k 30 --json --figures none --out cal"),
        cwd,
    );
    let v = json(&o);
    for (name, truth) in [("theta", 0.6), ("a", 0.5), ("b", 0.3), ("k", 20.0)] {
        let est = v["parameters"][name]["value"].as_f64().unwrap();
        assert!((est - truth).abs() < 1e-7 * truth.max(1.0), "{name}: {est}");
    }
    let logs = v["logs"].as_array().unwrap();
    assert_eq!(logs.len(), 2);
    assert!((logs[0]["alpha_deg"].as_f64().unwrap() - 10.0).abs() < 1e-6);
    assert!((logs[1]["q"].as_f64().unwrap() - 1.0).abs() < 1e-8);
    assert!((logs[1]["alpha_deg"].as_f64().unwrap() + 20.0).abs() < 1e-6);
    assert_eq!(logs[1]["profile"], "g2");
    let res = fs::read_to_string(cwd.join("cal/residuals.csv")).unwrap();
    assert!(
        res.lines().any(|l| l.starts_with("2,")),
        "rows of the second log"
    );
}

/// `calibrate --fit ...,mu` (issue 39): a frictional sweep (the tip slides on a circle,
/// mu = 0.4) calibrated from a wrong start gives mu to 1e-8 with its standard error in the
/// JSON's `mu`, the calibrated scene.ron carries it; without mu in `--fit` the same log is
/// fitted as frictionless and warned about.
#[test]
fn calibrate_fits_mu_from_a_frictional_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let o = run(
        &[
            "sweep",
            "--profile",
            "circle:0.3,1.5,0.6",
            "--theta",
            "0.5",
            "--k",
            "10",
            "--q",
            "1",
            "--alpha-deg",
            "10",
            "--mu",
            "0.4",
            "--points",
            "30",
            "--figures",
            "none",
            "--out",
            "fr",
        ],
        cwd,
    );
    assert!(o.status.success(), "sweep: {}", stderr(&o));
    let o = run(
        &[
            "calibrate",
            "fr",
            "--fit",
            "theta,k,mu",
            "--theta",
            "0.6",
            "--k",
            "15",
            "--json",
            "--out",
            "cal",
        ],
        cwd,
    );
    let v = json(&o);
    let mu = &v["mu"];
    assert!((mu["value"].as_f64().unwrap() - 0.4).abs() < 1e-8, "{mu}");
    assert!(mu["stderr"].as_f64().unwrap() < 1e-6, "{mu}");
    assert_eq!(mu["identifiable"], true);
    assert!(mu["sliding_rows"].as_u64().unwrap() >= 10, "{mu}");
    assert_eq!(mu["cone_violations"], 0);
    assert_eq!(v["parameters"]["mu"]["value"], mu["value"]);
    assert_eq!(v["parameters"]["mu"]["unit"], "1");
    assert!((v["parameters"]["theta"]["value"].as_f64().unwrap() - 0.5).abs() < 1e-7);
    let scene = fs::read_to_string(cwd.join("cal/scene.ron")).unwrap();
    assert!(scene.contains("mu: 0.39999999"), "{scene}");
    // without mu: the frictionless fit, warned about
    let o = run(
        &[
            "calibrate",
            "fr",
            "--fit",
            "theta,k",
            "--theta",
            "0.6",
            "--k",
            "15",
            "--json",
        ],
        cwd,
    );
    let v = json(&o);
    assert!(v.get("mu").is_none());
    let warned = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .any(|w| w.as_str().unwrap().contains("prove friction"));
    assert!(warned, "{}", v["warnings"]);
    // an unknown name lists mu among the parameters
    // (the folder `cal` of the fit above exists: the one-line error checked here)
    let o = run(&["calibrate", "fr", "--fit", "theta,nu"], cwd);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("--fit") && err.contains("theta, a, b, k, ei, mu"),
        "{err}"
    );
}
