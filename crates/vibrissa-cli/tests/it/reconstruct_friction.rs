//! End-to-end tests of `vibrissa reconstruct --mu` (spec/cli.md, "Friction"; issue 39 item
//! 3): a frictional log written here from contact-sim's frictional sweep (the CLI's sweep
//! takes `--mu` in another branch), mu identified with its standard error, the `ft` column
//! against the hidden truth, the warning of `--mu 0` on a log that shows friction, and `--mu`
//! refused where it is wrong.

use std::fs;
use std::path::Path;

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, ContactLaw, Phase, Profile, SweepResult, SweepSettings};

use crate::common;
use common::{json, parse, run, stderr};

const WHISKER: [&str; 4] = ["--theta", "0.5", "--k", "10"];

/// contact-sim's sliding scene (theta 0.5, k 10, q 1 at 0.2 rad, a circle) at `mu`, its
/// observables written to `cwd/log.csv` with 17 significant digits.
fn frictional_log(cwd: &Path, mu: f64) -> SweepResult {
    let w = Whisker::new(0.5, 0.0, 0.0, 10.0);
    let flow = FluidLoad { q: 1.0, alpha: 0.2 };
    let profile = Profile::parse("circle:0.3,1.5,0.6").unwrap();
    let s = SweepSettings {
        points: 30,
        contact_law: ContactLaw::Coulomb { mu },
        ..SweepSettings::default()
    };
    let r = sweep(&w, flow, &profile, &s).unwrap();
    let mut text = String::from("x0,Ax,Ay,MA,phi0\n");
    for p in &r.points {
        text.push_str(&format!(
            "{:e},{:e},{:e},{:e},{:e}\n",
            p.x0, p.ax, p.ay, p.ma, p.phi0
        ));
    }
    fs::write(cwd.join("log.csv"), text).unwrap();
    r
}

fn reconstruct(cwd: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["reconstruct", "log.csv"];
    args.extend(WHISKER);
    args.extend(extra);
    run(&args, cwd)
}

#[test]
fn mu_is_identified_and_ft_written_per_point() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let truth = frictional_log(cwd, 0.4);
    let v = json(&reconstruct(
        cwd,
        &[
            "--mu",
            "identify",
            "--json",
            "--figures",
            "none",
            "--out",
            "rec",
        ],
    ));
    let mu = &v["mu"];
    let (value, se) = (
        mu["value"].as_f64().unwrap(),
        mu["stderr"].as_f64().unwrap(),
    );
    assert!(
        (value - 0.4).abs() <= 1e-9 && se < 1e-8 && !mu["given"].as_bool().unwrap(),
        "{v}"
    );
    assert!(v["friction"]["proves_friction"].as_bool().unwrap(), "{v}");
    let (header, rows) = parse(&fs::read_to_string(cwd.join("rec/reconstruction.csv")).unwrap());
    let c = |n: &str| header.iter().position(|h| h == n).unwrap();
    assert_eq!(&header[..7], ["x0", "x", "y", "s1", "f", "psi", "phase"]);
    let mut n = 0;
    for r in &rows {
        let x0: f64 = r[c("x0")].parse().unwrap();
        let t = truth
            .points
            .iter()
            .find(|p| p.x0 == x0 && p.phase != Phase::None)
            .unwrap();
        let num = |k: &str| r[c(k)].parse::<f64>().unwrap();
        assert!(
            (num("x") - t.xc).abs() < 1e-10 && (num("y") - t.yc).abs() < 1e-10,
            "{r:?}"
        );
        assert!(
            (num("ft") - t.ft).abs() < 1e-5 && (num("f") - t.f).abs() < 1e-5,
            "{r:?} vs {t:?}"
        );
        n += 1;
    }
    assert!(n >= 20);
}

#[test]
fn mu_zero_warns_on_a_frictional_log_and_not_on_a_frictionless_one() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let truth = frictional_log(cwd, 0.4);
    let o = reconstruct(cwd, &["--mu", "0", "--figures", "none", "--out", "rec"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("warning: the log shows friction") && err.contains("standard deviations"),
        "{err}"
    );
    // the widened error estimates cover the biased points
    let (header, rows) = parse(&fs::read_to_string(cwd.join("rec/reconstruction.csv")).unwrap());
    let c = |n: &str| header.iter().position(|h| h == n).unwrap();
    for r in &rows {
        let num = |k: &str| r[c(k)].parse::<f64>().unwrap();
        let t = truth.points.iter().find(|p| p.x0 == num("x0")).unwrap();
        assert!(
            (num("x") - t.xc).hypot(num("y") - t.yc) <= num("sigma") + 1e-10,
            "{r:?}"
        );
    }
    // the frictionless log: no warning, the points of a reconstruction without --mu
    frictional_log(cwd, 0.0);
    let o = reconstruct(cwd, &["--mu", "0", "--figures", "none", "--out", "rec0"]);
    assert!(
        o.status.success() && !stderr(&o).contains("warning"),
        "{}",
        stderr(&o)
    );
    let o = reconstruct(cwd, &["--figures", "none", "--out", "plain"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (ha, ra) = parse(&fs::read_to_string(cwd.join("rec0/reconstruction.csv")).unwrap());
    let (hb, rb) = parse(&fs::read_to_string(cwd.join("plain/reconstruction.csv")).unwrap());
    assert_eq!(ha[..hb.len()], hb[..]);
    assert_eq!(ra.len(), rb.len());
    for (a, b) in ra.iter().zip(&rb) {
        assert_eq!(a[..7], b[..7]);
    }
}

#[test]
fn a_wrong_mu_is_refused_on_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    frictional_log(cwd, 0.4);
    for (mu, extra) in [
        ("-1", vec![]),
        ("abc", vec![]),
        ("11", vec![]),
        ("0.4", vec!["--method", "thesis"]),
    ] {
        let mut args = vec!["--mu", mu, "--out", "rec"];
        args.extend(extra.iter().copied());
        let o = reconstruct(cwd, &args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{mu}: {err}");
        assert!(
            err.contains("--mu") && err.trim_end().lines().count() == 1,
            "{err}"
        );
        assert!(!cwd.join("rec").exists());
    }
}
