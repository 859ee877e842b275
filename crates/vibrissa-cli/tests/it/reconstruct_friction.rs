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

/// The log written by [`frictional_log`], read back as the library's rows.
fn rows_of_log(cwd: &Path) -> Vec<profile_recon::ObservableRow> {
    let (_, rows) = parse(&fs::read_to_string(cwd.join("log.csv")).unwrap());
    rows.iter()
        .map(|r| {
            let v: Vec<f64> = r.iter().map(|c| c.parse().unwrap()).collect();
            profile_recon::ObservableRow {
                x0: v[0],
                ax: v[1],
                ay: v[2],
                ma: v[3],
                phi0: v[4],
            }
        })
        .collect()
}

/// `reconstruct` without `--mu` (spec/cli.md: the JSON gives mu identified with its standard
/// error): on a frictionless log today's points, bit for bit the library's frictionless
/// reconstruction, no `ft` column, and mu consistent with 0 within 3 standard errors; on a
/// frictional log (mu 0.4) mu to 1e-9 with its standard error, the warning of a biased
/// frictionless reconstruction and error estimates that cover the truth.
#[test]
fn frec_without_mu_identifies_mu_beside_the_frictionless_points() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    frictional_log(cwd, 0.0);
    let o = reconstruct(cwd, &["--json", "--figures", "none", "--out", "plain"]);
    assert!(
        o.status.success() && !stderr(&o).contains("warning"),
        "{}",
        stderr(&o)
    );
    let v = json(&o);
    let (value, se) = (
        v["mu"]["value"].as_f64().unwrap(),
        v["mu"]["stderr"].as_f64().unwrap(),
    );
    assert!(value.abs() <= 3.0 * se && se < 1e-8, "{v}");
    assert!(!v["friction"]["proves_friction"].as_bool().unwrap(), "{v}");
    let text = fs::read_to_string(cwd.join("plain/reconstruction.csv")).unwrap();
    assert!(text.starts_with("x0,x,y,s1,f,psi,phase,sigma,residual,hypotheses\n"));
    let w = Whisker::new(0.5, 0.0, 0.0, 10.0);
    let lib = profile_recon::reconstruct_with(
        &w,
        &rows_of_log(cwd),
        profile_recon::KnownFlow::default(),
        &profile_recon::ReconSettings::default(),
    )
    .unwrap();
    let (header, rows) = parse(&text);
    let c = |n: &str| header.iter().position(|h| h == n).unwrap();
    assert_eq!(rows.len(), lib.points.len());
    for (r, p) in rows.iter().zip(&lib.points) {
        let num = |k: &str| r[c(k)].parse::<f64>().unwrap();
        assert_eq!(
            [num("x"), num("y"), num("f"), num("sigma")],
            [p.x, p.y, p.f, p.sigma],
            "{r:?}"
        );
    }

    let truth = frictional_log(cwd, 0.4);
    let o = reconstruct(cwd, &["--json", "--figures", "none", "--out", "fr"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: the log shows friction"),
        "{}",
        stderr(&o)
    );
    let v = json(&o);
    let (value, se) = (
        v["mu"]["value"].as_f64().unwrap(),
        v["mu"]["stderr"].as_f64().unwrap(),
    );
    assert!(
        (value - 0.4).abs() <= 1e-9 && se < 1e-8 && !v["mu"]["given"].as_bool().unwrap(),
        "{v}"
    );
    assert!(v["friction"]["proves_friction"].as_bool().unwrap(), "{v}");
    let (header, rows) = parse(&fs::read_to_string(cwd.join("fr/reconstruction.csv")).unwrap());
    let c = |n: &str| header.iter().position(|h| h == n).unwrap();
    assert!(!header.iter().any(|h| h == "ft"), "{header:?}");
    for r in &rows {
        let num = |k: &str| r[c(k)].parse::<f64>().unwrap();
        let t = truth.points.iter().find(|p| p.x0 == num("x0")).unwrap();
        assert!(
            (num("x") - t.xc).hypot(num("y") - t.yc) <= num("sigma") + 1e-10,
            "{r:?}"
        );
    }
}

/// `reconstruct --stream --mu identify` on the frictional log: the header of the file with
/// `ft`, one row per contact row with the point, s1 and phase of the batch `reconstruct --mu
/// identify` (to 1e-12: the stream's flow is its first free row's, the batch's the mean of
/// the pre-contact rows), each `ft` within 1e-5 of the truth (the batch's bound; NaN on the
/// first two contact rows, whose tangent needs three points), and mu on standard error (to
/// 1e-8 of 0.4).
#[test]
fn frec_stream_with_mu_gives_the_batch_points_and_ft() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let truth = frictional_log(cwd, 0.4);
    let o = reconstruct(
        cwd,
        &["--mu", "identify", "--figures", "none", "--out", "rec"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (hb, rb) = parse(&fs::read_to_string(cwd.join("rec/reconstruction.csv")).unwrap());
    let body = fs::read(cwd.join("log.csv")).unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_vibrissa"))
        .args(["reconstruct", "--stream", "--mu", "identify"])
        .args(WHISKER)
        .current_dir(cwd)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    use std::io::Write;
    child.stdin.take().unwrap().write_all(&body).unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let (hs, rs) = parse(&String::from_utf8_lossy(&o.stdout));
    assert_eq!(hs, hb, "the stream's header is the file's");
    assert_eq!(rs.len(), rb.len());
    let c = |n: &str| hs.iter().position(|h| h == n).unwrap();
    let mut unknown = 0;
    for (s, b) in rs.iter().zip(&rb) {
        let num = |r: &Vec<String>, k: &str| r[c(k)].parse::<f64>().unwrap();
        assert_eq!(s[c("x0")].parse::<f64>().unwrap(), num(b, "x0"));
        assert_eq!(s[c("phase")], b[c("phase")]);
        for k in ["x", "y", "s1"] {
            assert!((num(s, k) - num(b, k)).abs() < 1e-12, "{k}: {s:?} vs {b:?}");
        }
        let t = truth.points.iter().find(|p| p.x0 == num(s, "x0")).unwrap();
        if num(s, "ft").is_nan() {
            // a tip contact before three distinct points: the tangent is not known yet
            unknown += 1;
            continue;
        }
        assert!((num(s, "ft") - t.ft).abs() < 1e-5, "{s:?} vs {t:?}");
    }
    assert!(unknown <= 2, "{unknown} rows without ft");
    let err = stderr(&o);
    let mu: f64 = err
        .split("mu = ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no mu on stderr: {err}"));
    assert!(
        (mu - 0.4).abs() < 1e-8 && err.contains("sliding rows"),
        "{err}"
    );
}
