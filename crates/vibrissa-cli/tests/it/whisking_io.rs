//! `vibrissa sweep --motion` (issue 38, items 1, 3, 4): the flags and the scene's keys, the
//! log's pose columns, the JSON's motion and pose range, physical units of the base and of
//! pegs, and the refusals. `cargo test -p vibrissa-cli --test it -- wio`

use crate::common;

use std::fs;

use common::{col, json, num, run, stderr, table};

/// The base turn `atan(0.2 / 0.6)` where the straight whisker at the origin first touches
/// `peg:-0.2,0.6`, and the peg's distance r from the base.
fn peg_touch() -> (f64, f64) {
    ((0.2f64).atan2(0.6), 0.4f64.sqrt())
}

/// Whisking the straight uniform rigid whisker past `peg:-0.2,0.6` through the CLI: the
/// JSON names the motion and the pose range, the log's `gamma` rises row by row from the
/// touch at the peg's angle, `y0` and `x0` stay at the base, `phi0 = pi/2 + gamma` (rigid)
/// row by row, and the base moment rises as linear theory says, `dMA/dgamma -> 3/r`
/// (Kaneko 1998; spec/model.md) to second order in the turn.
#[test]
fn wio_rotate_past_a_peg_through_the_cli() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(
        &[
            "sweep",
            "--motion",
            "rotate",
            "--profile",
            "peg:-0.2,0.6",
            "--points",
            "200",
            "--figures",
            "none",
            "--json",
            "--out",
            "w",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v = json(&o);
    let (gt, r) = peg_touch();
    assert_eq!(v["motion"], "rotate");
    assert_eq!(v["phases"], "B");
    let g = &v["pose"]["gamma_deg"];
    assert!(
        (g[0].as_f64().unwrap() - gt.to_degrees()).abs() < 1e-6,
        "{v}"
    );
    assert!(g[1].as_f64().unwrap() > g[0].as_f64().unwrap());
    assert_eq!(v["pose"]["x0"][0], 0.0);
    assert_eq!(v["pose"]["y0"][1], 0.0);
    let (h, rows) = table(&dir.path().join("w/observables.csv"));
    let (cg, cm, cp, cy, cx) = (
        col(&h, "gamma"),
        col(&h, "MA"),
        col(&h, "phi0"),
        col(&h, "y0"),
        col(&h, "x0"),
    );
    let mut last = f64::NEG_INFINITY;
    let mut linear = 0;
    for row in &rows {
        let (gamma, ma, phi0) = (num(&row[cg]), num(&row[cm]), num(&row[cp]));
        assert!(gamma > last, "gamma must rise: {gamma} after {last}");
        last = gamma;
        assert_eq!((num(&row[cy]), num(&row[cx])), (0.0, 0.0));
        assert!(
            (phi0 - std::f64::consts::FRAC_PI_2 - gamma).abs() < 1e-9,
            "phi0 = pi/2 + gamma (rigid): {phi0} at {gamma}"
        );
        let d = gamma - gt;
        if row[col(&h, "phase")] == "B" && d > 1e-3 && d < 0.05 {
            let rel = (ma.abs() / d - 3.0 / r) / (3.0 / r);
            assert!(
                rel.abs() < 0.5 * d * d,
                "dMA/dgamma at d = {d}: rel. {rel:e}"
            );
            linear += 1;
        }
    }
    assert!(linear >= 3, "{linear} rows in the linear range");
}

/// The figures of a whisking sweep: the observables against the turn gamma in degrees,
/// the fan of shapes about the fixed base, the obstacle drawn whole (a peg as a dot, a disc
/// as a filled circle).
#[test]
fn wio_whisking_figures_are_drawn_against_the_turn() {
    let dir = tempfile::tempdir().unwrap();
    for (profile, legend) in [
        ("peg:-0.2,0.6", "peg (a point obstacle)"),
        ("disc:-0.3,0.8,0.15", "disc (solid inside)"),
    ] {
        let out = if profile.starts_with("peg") { "p" } else { "d" };
        let o = run(
            &[
                "sweep",
                "--motion",
                "rotate",
                "--theta",
                "0.6",
                "--k",
                "25",
                "--profile",
                profile,
                "--points",
                "20",
                "--out",
                out,
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let svg =
            |n: &str| common::svg_text(&fs::read_to_string(dir.path().join(out).join(n)).unwrap());
        let obs = svg("observables.svg");
        assert!(
            obs.contains("base turn γ [°]") && !obs.contains("base x"),
            "{obs}"
        );
        assert!(obs.contains("turns counter-clockwise"), "{obs}");
        let shapes = svg("shapes.svg");
        assert!(
            shapes.contains(legend) && shapes.contains("base (fixed, turning)"),
            "{shapes}"
        );
        assert!(!shapes.contains("sweep (base → −x)"), "{shapes}");
    }
}

/// The same whisking scene in a physical scene (the beta whisker, lengths in mm: the base
/// at (--x0, --y0) mm, the peg in mm) and in whisker lengths (every length divided by L)
/// gives the same rows: lengths in mm = L x the dimensionless ones, angles equal.
#[test]
fn wio_physical_and_dimensionless_whisking_agree() {
    let dir = tempfile::tempdir().unwrap();
    let l = 66.2;
    fs::write(
        dir.path().join("beta.ron"),
        "(units: Physical(preset: \"beta\"), whisker: (theta: 0.6), \
         motion: \"rotate\", x0: 3.31, y0: -6.62, gamma_deg: -5.0)",
    )
    .unwrap();
    let peg = format!("peg:{},{}", -0.2 * l, 0.6 * l);
    let o = run(
        &[
            "sweep",
            "beta.ron",
            "--profile",
            &peg,
            "--points",
            "12",
            "--figures",
            "none",
            "--out",
            "p",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(
        &[
            "sweep",
            "--theta",
            "0.6",
            "--motion",
            "rotate",
            "--x0",
            "0.05",
            "--y0",
            "-0.1",
            "--gamma-deg",
            "-5",
            "--profile",
            "peg:-0.2,0.6",
            "--points",
            "12",
            "--figures",
            "none",
            "--out",
            "d",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (hp, rp) = table(&dir.path().join("p/observables.csv"));
    let (hd, rd) = table(&dir.path().join("d/observables.csv"));
    assert_eq!(hp, hd);
    assert_eq!(rp.len(), rd.len());
    let mut worst: f64 = 0.0;
    for (a, b) in rp.iter().zip(&rd) {
        for name in ["x0", "y0", "xc", "yc", "s1", "gamma", "phi0", "psi"] {
            let i = col(&hp, name);
            if a[i].is_empty() || (num(&a[i]).is_nan() && num(&b[i]).is_nan()) {
                continue;
            }
            let scale = if ["gamma", "phi0", "psi"].contains(&name) {
                1.0
            } else {
                l
            };
            let e = (num(&a[i]) - scale * num(&b[i])).abs() / scale;
            worst = worst.max(e);
            assert!(e < 1e-8, "{name}: {} mm against {} L", a[i], b[i]);
        }
    }
    println!("physical vs dimensionless whisking: worst {worst:.1e} (in L or rad)");
    // the folder's scene.ron keeps the motion and sweeps again to the same log
    let scene = fs::read_to_string(dir.path().join("p/scene.ron")).unwrap();
    assert!(
        scene.contains("motion: Some(\"rotate\")") && scene.contains("gamma_deg: Some(-5.0)"),
        "{scene}"
    );
    let o = run(
        &["sweep", "p/scene.ron", "--figures", "none", "--out", "p2"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        fs::read(dir.path().join("p/observables.csv")).unwrap(),
        fs::read(dir.path().join("p2/observables.csv")).unwrap()
    );
}

/// Bad motions exit 2 naming the flag or the scene key (with its line) or the path table
/// (file, line, column); no folder is left behind (friction with a turning base, pegs and
/// discs is `friction_whisk::`'s).
#[test]
fn wio_bad_motions_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let base = [
        "sweep",
        "--profile",
        "peg:-0.2,0.6",
        "--points",
        "5",
        "--figures",
        "none",
    ];
    let refused = |extra: &[&str], code: i32, needles: &[&str]| {
        let mut a: Vec<&str> = base[..1].to_vec();
        if !extra.contains(&"--profile") {
            a.extend(&base[1..3]);
        }
        a.extend(&base[3..]);
        a.extend(extra);
        a.extend(["--out", "bad"]);
        let o = run(&a, d);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(code), "{extra:?}: {e}");
        assert_eq!(e.trim().lines().count(), 1, "{e}");
        for n in needles {
            assert!(e.contains(n), "{extra:?}: `{n}` not in {e}");
        }
        assert!(!d.join("bad").exists());
    };
    refused(
        &["--motion", "whisk"],
        2,
        &["`--motion`", "whisk", "rotate"],
    );
    refused(&["--y0", "0.1"], 2, &["`--y0`", "rotate"]);
    refused(
        &["--motion", "rotate", "--gamma-deg", "nan"],
        2,
        &["`--gamma-deg`"],
    );
    refused(
        &["--motion", "rotate", "--x0", "abc"],
        2,
        &["`--x0`", "abc"],
    );
    refused(&["--motion", "path"], 2, &["`--motion`", "path"]);
    refused(&["--motion", "path:none.csv"], 2, &["none.csv"]);
    fs::write(d.join("bad.csv"), "x0,y0,gamma_deg\n0,0,0\n0,zero,5\n").unwrap();
    refused(&["--motion", "path:bad.csv"], 2, &["bad.csv", ":3", "y0"]);
    fs::write(d.join("k.csv"), "x0;y0;gamma_deg;k\n0;0;0;5\n0;0;5;0\n").unwrap();
    refused(&["--motion", "path:k.csv"], 2, &["k.csv", ":3", "k"]);
    // a good path: swept once contact-sim follows paths, refused by name until then
    fs::write(d.join("p.csv"), "x0_mm,y0,gamma_deg\n0,0,0\n0,0,60\n").unwrap();
    refused(&["--motion", "path:p.csv"], 2, &["p.csv", "physical"]);
    fs::write(d.join("p.csv"), "x0,y0,gamma_deg\n0,0,0\n0,0,60\n").unwrap();
    let o = run(
        &[&base[..], &["--motion", "path:p.csv", "--out", "path"]].concat(),
        d,
    );
    match o.status.code() {
        Some(1) => assert!(stderr(&o).contains("path"), "{}", stderr(&o)),
        Some(0) => {
            let (h, rows) = table(&d.join("path/observables.csv"));
            for row in rows {
                let g = num(&row[col(&h, "gamma")]);
                assert!((0.0..=60f64.to_radians() + 1e-12).contains(&g));
            }
        }
        c => panic!("{c:?}: {}", stderr(&o)),
    }
    // the scene's keys: named with their line
    let scene = |body: &str| {
        fs::write(d.join("s.ron"), format!("(\n  whisker: (),\n{body}\n)")).unwrap();
        let o = run(
            &[
                "sweep",
                "s.ron",
                "--profile",
                "peg:-0.2,0.6",
                "--figures",
                "none",
                "--out",
                "bad",
            ],
            d,
        );
        (o.status.code(), stderr(&o))
    };
    let (c, e) = scene("  motion: \"whisk\",");
    assert_eq!(c, Some(2), "{e}");
    assert!(e.contains("s.ron:3") && e.contains("motion"), "{e}");
    let (c, e) = scene("  y0: 0.1,");
    assert_eq!(c, Some(2), "{e}");
    assert!(
        e.contains("s.ron:3") && e.contains("y0") && e.contains("rotate"),
        "{e}"
    );
    let (c, e) = scene("  motion: \"path\",\n  path: \"x0,y0,gamma_deg\\n0,0,0\\n0,0,x\\n\",");
    assert_eq!(c, Some(2), "{e}");
    assert!(
        e.contains("s.ron:4") && e.contains("inline") && e.contains("line 3"),
        "{e}"
    );
}
