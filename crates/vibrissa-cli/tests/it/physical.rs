//! Physical units end to end (issue 13): named contours stay in whisker lengths, and
//! every preset sweeps and reconstructs as the scaled dimensionless scene.

use std::fs;
use std::path::Path;

use crate::common;
use common::*;

/// The named contours g1, g2, ge are in whisker lengths in every unit system [5.2, 5.3,
/// 5.11]: a physical sweep past g1 is the dimensionless sweep with the same whisker scaled by
/// hand (x0 by L, forces by E I / L^2, moments by E I / L; q by E I / L^3, k by E I / L).
/// Before, g1 was applied in mm (first contact at x0 = 4.00 mm instead of 92.66 mm).
#[test]
fn named_contours_are_in_whisker_lengths_in_a_physical_scene() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    // Table 2.2, beta: L = 66.2 mm, d_b = 0.225 mm, E = 1.40 GPa.
    let (l, d, e) = (0.0662f64, 0.225e-3f64, 1.40e9f64);
    let ei = e * std::f64::consts::PI * d.powi(4) / 64.0;
    let (q_si, k_si) = (0.003, 5e-5); // the scene's N/m and N m/rad
    for profile in ["g1", "g2", "ge"] {
        let scene = fs::read_to_string(scenes_dir().join("physical-beta-g1.ron"))
            .unwrap()
            .replace("Some(\"g1\")", &format!("Some(\"{profile}\")"));
        fs::write(cwd.join("beta.ron"), scene).unwrap();
        let phys = json(&run(
            &[
                "sweep", "beta.ron", "--points", "20", "--json", "--out", "phys",
            ],
            cwd,
        ));
        let q = format!("{:?}", q_si * l.powi(3) / ei);
        let k = format!("{:?}", k_si * l / ei);
        let dim = json(&run(
            &[
                "sweep",
                "--profile",
                profile,
                "--theta",
                "0.75",
                "--q",
                &q,
                "--k",
                &k,
                "--points",
                "20",
                "--json",
                "--out",
                "dim",
            ],
            cwd,
        ));
        assert_eq!(phys["phases"], dim["phases"], "{profile}");
        assert_eq!(phys["rows"], dim["rows"], "{profile}");
        let x_phys = phys["first_contact_x0"].as_f64().unwrap();
        let x_dim = dim["first_contact_x0"].as_f64().unwrap();
        assert!(
            rel(x_phys / L_BETA_MM, x_dim) < 1e-9,
            "{profile}: {x_phys} mm vs {x_dim}"
        );
        let (ph, prows) = table(&cwd.join("phys/observables.csv"));
        let (dh, drows) = table(&cwd.join("dim/observables.csv"));
        let f0 = ei / (l * l);
        for (p, q) in prows.iter().zip(&drows) {
            let pair = |name: &str| (num(&p[col(&ph, name)]), num(&q[col(&dh, name)]));
            let (a, b) = pair("x0");
            assert!(
                (a / L_BETA_MM - b).abs() < 1e-9,
                "{profile} x0: {a} mm vs {b}"
            );
            let (a, b) = pair("Ax");
            assert!((a / f0 - b).abs() < 1e-8 * b.abs().max(1.0), "{profile} Ax");
            let (a, b) = pair("MA");
            assert!(
                (a / (f0 * L_BETA_MM) - b).abs() < 1e-8 * b.abs().max(1.0),
                "{profile} MA: {a} N mm vs {b}"
            );
        }
    }
}

/// `sweep ARGS --points 15 --json --figures none --out OUT`: its JSON.
fn sweep_15(cwd: &Path, args: &[&str], out: &str) -> serde_json::Value {
    let mut a = vec!["sweep"];
    a.extend(args);
    a.extend([
        "--points",
        "15",
        "--json",
        "--figures",
        "none",
        "--out",
        out,
    ]);
    json(&run(&a, cwd))
}

/// Every physical preset of Table 2.2 (values typed here, not taken from the library): a
/// sweep past g1 and its reconstruction in physical units equal the dimensionless ones
/// scaled by hand (q = 4 and k = 20 in E I / L^3 and E I / L).
#[test]
fn every_preset_sweeps_and_reconstructs_as_the_scaled_dimensionless_scene() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let dim = sweep_15(
        cwd,
        &[
            "--profile",
            "g1",
            "--theta",
            "0.75",
            "--q",
            "4",
            "--k",
            "20",
        ],
        "dim",
    );
    stdout(&run(
        &[
            "reconstruct",
            "dim",
            "--figures",
            "none",
            "--out",
            "dim-rec",
        ],
        cwd,
    ));
    let (dh, drows) = table(&cwd.join("dim-rec/reconstruction.csv"));
    for (name, l_mm, d_mm, e_gpa) in [
        ("beta", 66.2f64, 0.225f64, 1.40f64),
        ("gamma", 60.3, 0.199, 3.75),
        ("A1", 51.7, 0.16, 2.75),
        ("E2", 48.1, 0.232, 1.9),
    ] {
        let (l, d, e) = (l_mm * 1e-3, d_mm * 1e-3, e_gpa * 1e9);
        let ei = e * std::f64::consts::PI * d.powi(4) / 64.0;
        let (q_si, k_si) = (4.0 * ei / l.powi(3), 20.0 * ei / l);
        fs::write(
            cwd.join(format!("{name}.ron")),
            format!(
                "(units: Physical(preset: \"{name}\"), whisker: (theta: 0.75, k: Some({k_si:?})), \
                 loads: (q: {q_si:?}), profile: Some(\"g1\"))"
            ),
        )
        .unwrap();
        let out = format!("{name}-sw");
        let phys = sweep_15(cwd, &[&format!("{name}.ron")], &out);
        assert_eq!(phys["phases"], dim["phases"], "{name}");
        let (xp, xd) = (
            phys["first_contact_x0"].as_f64().unwrap(),
            dim["first_contact_x0"].as_f64().unwrap(),
        );
        assert!(rel(xp / l_mm, xd) < 1e-9, "{name}: {xp} mm vs {xd}");
        let rec = format!("{name}-rec");
        let v = json(&run(
            &[
                "reconstruct",
                &out,
                "--json",
                "--figures",
                "none",
                "--out",
                &rec,
            ],
            cwd,
        ));
        assert!(
            rel(v["q"].as_f64().unwrap(), q_si) < 1e-9,
            "{name}: q {}",
            v["q"]
        );
        let (ph, prows) = table(&cwd.join(&rec).join("reconstruction.csv"));
        assert_eq!(prows.len(), drows.len(), "{name}");
        for (p, q) in prows.iter().zip(&drows) {
            for c in ["x", "y"] {
                let (a, b) = (num(&p[col(&ph, c)]), num(&q[col(&dh, c)]));
                assert!((a / l_mm - b).abs() < 1e-9, "{name} {c}: {a} mm vs {b}");
            }
        }
    }
}
