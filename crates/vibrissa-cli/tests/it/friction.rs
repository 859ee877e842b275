//! `vibrissa sweep --mu` (issue 39, item 2): the flag and the scene's `mu`, the log's
//! `ft`, `slip`, `y0`, `gamma` columns, the friction events in the summary and the JSON,
//! the refusals, `--mu 0` byte for byte the frictionless sweep, and logs with and without
//! the new columns read by `reconstruct`.

use crate::common;

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

use common::{col, json, num, run, scenes_dir, stderr, stdout, sweep_flags, table};

/// Every file of a folder (name -> bytes), the lock and marker files of the folder included.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

/// Runs `sweep ARGS --out a` and `sweep ARGS --mu 0 --out b` (and `--mu -0`, `--mu 0.0e0`):
/// every file of the folders is byte for byte the same, the printed summary too.
fn assert_mu_zero_identical(cwd: &Path, args: &[&str]) {
    let mut outs = Vec::new();
    for (i, mu) in [None, Some("0"), Some("-0"), Some("0.0e0")]
        .iter()
        .enumerate()
    {
        let out = format!("o{i}");
        let mut a = vec!["sweep"];
        a.extend(args);
        if let Some(mu) = mu {
            a.extend(["--mu", mu]);
        }
        a.extend(["--out", &out]);
        let o = run(&a, cwd);
        let printed = stdout(&o).replace(&out, "OUT");
        outs.push((files(&cwd.join(&out)), printed));
    }
    let (first, printed) = &outs[0];
    assert!(first.contains_key("observables.csv") && first.contains_key("scene.ron"));
    assert!(
        first.contains_key("observables.units.csv"),
        "{:?}",
        first.keys()
    );
    for (other, p) in &outs[1..] {
        assert_eq!(
            first.keys().collect::<Vec<_>>(),
            other.keys().collect::<Vec<_>>()
        );
        for (name, bytes) in first {
            assert!(other[name] == *bytes, "{name} differs with --mu 0");
        }
        assert_eq!(printed, p);
    }
}

#[test]
fn mu_zero_writes_the_same_bytes_as_no_mu() {
    let dir = tempfile::tempdir().unwrap();
    // g1 under q = 5 (phases ABA), with the figures (SVG)
    assert_mu_zero_identical(dir.path(), &sweep_flags("g1", "12"));
    let scene = scenes_dir().join("physical-beta-g1.ron");
    assert_mu_zero_identical(
        dir.path(),
        &[
            scene.to_str().unwrap(),
            "--points",
            "8",
            "--figures",
            "none",
        ],
    );
}

/// The frictionless log has the columns of spec/cli.md, after `psi`: `ft` (0), `slip`
/// (`none`), `y0` and `gamma` (0 for the translating sweep), with their units.
#[test]
fn the_log_has_the_friction_and_pose_columns() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = vec!["sweep"];
    let flags = sweep_flags("g1", "12");
    a.extend(&flags);
    a.extend(["--figures", "none", "--out", "sw"]);
    stdout(&run(&a, dir.path()));
    let (h, rows) = table(&dir.path().join("sw/observables.csv"));
    assert_eq!(
        h.join(","),
        "x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi,ft,slip,y0,gamma"
    );
    assert!(rows.len() >= 22);
    for r in &rows {
        assert_eq!(r.len(), 15);
        assert_eq!(&r[11..], &["0.0", "none", "0.0", "0.0"]);
    }
    let units = fs::read_to_string(dir.path().join("sw/observables.units.csv")).unwrap();
    assert_eq!(
        units,
        "x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi,ft,slip,y0,gamma\n1,1,1,1,rad,1,1,,1,1,rad,1,,1,rad\n"
    );
}

/// `--mu` out of [0, 10] or not a number: exit 2, one line naming `--mu` and the value as
/// typed, no output folder; the scene's `mu` likewise, naming the field and its line.
#[test]
fn bad_mu_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    for bad in ["-0.1", "NaN", "10.5", "inf", "abc", ""] {
        let mut a = vec!["sweep"];
        let flags = sweep_flags("g1", "12");
        a.extend(&flags);
        a.extend(["--mu", bad, "--out", "never"]);
        let o = run(&a, dir.path());
        assert_eq!(o.status.code(), Some(2), "--mu {bad}: {}", stderr(&o));
        let e = stderr(&o);
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
        assert!(
            e.contains(&format!("invalid value `{bad}` for `--mu`")),
            "--mu {bad}: {e}"
        );
        assert!(!dir.path().join("never").exists());
    }
    for (bad, line) in [("-1.0", 4), ("12.0", 4)] {
        let scene = dir.path().join("bad.ron");
        fs::write(
            &scene,
            format!(
                "(\n  whisker: (theta: 0.75, k: Some(20.0)),\n  loads: (q: 5.0),\n  mu: {bad},\n  profile: \"g1\",\n)\n"
            ),
        )
        .unwrap();
        let o = run(&["sweep", "bad.ron", "--out", "never"], dir.path());
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains(&format!("bad.ron:{line}:")), "{e}");
        assert!(e.contains("`mu`") || e.contains("mu:"), "{e}");
        assert!(e.contains("[0, 10]"), "{e}");
        assert!(!dir.path().join("never").exists());
    }
}

/// A sweep the quasi-static frictional model cannot follow (the tapered, pre-curved rigid
/// whisker of [`STUCK`] past g2 at mu = 0.5: stuck from the touch, its force reaches the
/// cone's edge at x0 = 0.904884 where sliding against it would not follow the base, a
/// dynamic slip): exit 1, one line naming it, no folder left.
#[test]
fn a_frictional_sweep_the_model_cannot_finish_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = vec!["sweep"];
    a.extend(STUCK);
    a.extend(["--mu", "0.5", "--out", "never"]);
    let o = run(&a, dir.path());
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(e.contains("friction"), "{e}");
    assert!(e.contains("0.904884"), "{e}");
    assert!(!e.contains("panick"), "{e}");
    assert!(!dir.path().join("never").exists());
}

/// The frictional scene of the tests: a tapered, pre-curved rigid whisker past g2 under
/// q = 0.5 (it sticks from the touch; with mu = 10 it stays stuck to the snap).
const STUCK: [&str; 12] = [
    "--theta",
    "0.3",
    "--a",
    "1",
    "--b",
    "0.5",
    "--q",
    "0.5",
    "--profile",
    "g2",
    "--points",
    "12",
];

/// A frictional sweep: its rows obey the law (|ft| <= mu f, stick rows keep their contact
/// point), the JSON carries mu and the switches, scene.ron carries mu and sweeping it
/// again writes the same log.
#[test]
fn a_frictional_sweep_writes_ft_slip_and_mu() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = vec!["sweep"];
    a.extend(STUCK);
    a.extend(["--mu", "10", "--figures", "none", "--json", "--out", "sw"]);
    let v = json(&run(&a, dir.path()));
    assert_eq!(v["mu"].as_f64(), Some(10.0));
    assert!(v["friction_events"].is_array());
    let (h, rows) = table(&dir.path().join("sw/observables.csv"));
    let (f, ft, slip, phase, xc, yc) = (
        col(&h, "f"),
        col(&h, "ft"),
        col(&h, "slip"),
        col(&h, "phase"),
        col(&h, "xc"),
        col(&h, "yc"),
    );
    let mut stuck = 0;
    let mut anchor: Option<(f64, f64)> = None;
    for r in &rows {
        if r[phase] == "none" {
            assert_eq!((r[ft].as_str(), r[slip].as_str()), ("0.0", "none"));
            continue;
        }
        assert!(r[slip] == "stick" || r[slip] == "slip", "{}", r[slip]);
        let (fnorm, ftan) = (num(&r[f]), num(&r[ft]));
        assert!(fnorm >= -1e-12 && ftan.abs() <= 10.0 * fnorm + 1e-12);
        if r[slip] == "stick" {
            stuck += 1;
            let p = (num(&r[xc]), num(&r[yc]));
            let a = *anchor.get_or_insert(p);
            assert!(
                (p.0 - a.0).hypot(p.1 - a.1) < 1e-9,
                "{p:?} moved from {a:?}"
            );
        }
    }
    assert!(stuck >= 12, "{stuck} stuck rows");
    assert!(ft_nonzero(&rows, ft), "some ft differs from 0");
    let scene = fs::read_to_string(dir.path().join("sw/scene.ron")).unwrap();
    assert!(scene.contains("mu: 10.0"), "{scene}");
    // the scene written sweeps again to the same log, byte for byte
    let o = run(
        &[
            "sweep",
            "sw/scene.ron",
            "--figures",
            "none",
            "--out",
            "again",
        ],
        dir.path(),
    );
    let printed = stdout(&o);
    assert!(printed.contains("friction mu = 10"), "{printed}");
    assert!(
        printed.contains("rows stick 12, slip 0; switches stick→slip 0, slip→stick 0"),
        "{printed}"
    );
    assert_eq!(
        fs::read(dir.path().join("sw/observables.csv")).unwrap(),
        fs::read(dir.path().join("again/observables.csv")).unwrap()
    );
}

fn ft_nonzero(rows: &[Vec<String>], ft: usize) -> bool {
    rows.iter().any(|r| num(&r[ft]) != 0.0)
}

/// `reconstruct` reads the log with the new columns and the same log cut back to the
/// eleven columns of logs written before them: the same contact points, bit for bit.
#[test]
fn reconstruct_reads_logs_with_and_without_the_new_columns() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = vec!["sweep"];
    let flags = sweep_flags("g1", "12");
    a.extend(&flags);
    a.extend(["--figures", "none", "--out", "sw"]);
    stdout(&run(&a, dir.path()));
    let text = fs::read_to_string(dir.path().join("sw/observables.csv")).unwrap();
    let old: String = text
        .lines()
        .map(|l| l.split(',').take(11).collect::<Vec<_>>().join(",") + "\n")
        .collect();
    assert!(old.starts_with("x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi\n"));
    fs::write(dir.path().join("old.csv"), &old).unwrap();
    let whisker = ["--theta", "0.75", "--k", "20", "--q", "5"];
    let mut points = Vec::new();
    for (log, out) in [("sw/observables.csv", "rnew"), ("old.csv", "rold")] {
        let mut a = vec!["reconstruct", log];
        a.extend(whisker);
        a.extend(["--figures", "none", "--out", out]);
        stdout(&run(&a, dir.path()));
        let (h, rows) = table(&dir.path().join(out).join("reconstruction.csv"));
        let (x, y) = (col(&h, "x"), col(&h, "y"));
        assert!(rows.len() >= 12);
        points.push(
            rows.iter()
                .map(|r| (r[x].clone(), r[y].clone()))
                .collect::<Vec<_>>(),
        );
    }
    assert_eq!(points[0], points[1]);
    // the row-by-row reader of --stream takes both headers too
    for log in ["sw/observables.csv", "old.csv"] {
        let body = fs::read(dir.path().join(log)).unwrap();
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_vibrissa"))
            .args(["reconstruct", "--stream"])
            .args(whisker)
            .current_dir(dir.path())
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        use std::io::Write;
        child.stdin.take().unwrap().write_all(&body).unwrap();
        let o = child.wait_with_output().unwrap();
        assert!(o.status.success(), "{log}: {}", stderr(&o));
        let lines = String::from_utf8_lossy(&o.stdout).lines().count();
        assert!(lines >= 12, "{log}: {lines} lines");
    }
}
