//! The contract of `spec/rust.md` run through the facade alone on
//! `scenes/physical-beta-g1.ron`, compared bit for bit with what the command line writes for
//! the same scene (`observables.csv`, `reconstruction.csv`): every number the facade returns
//! must parse back from the CLI's cell to the same `f64` bits (NaN where the CLI writes NaN).

use std::path::Path;

use clap::Parser;
use vibrissa::{Error, Phase, Scene};

fn scene_path() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/physical-beta-g1.ron")
}

/// Runs the CLI (its library entry, as the binary does) with `args`, figures off.
fn cli(args: &[&str]) {
    let cli = vibrissa_cli::cli::Cli::try_parse_from(
        ["vibrissa", "--figures", "none"].iter().chain(args.iter()),
    )
    .expect("a valid command line");
    let style = cli.figure_style();
    vibrissa_cli::commands::run(cli.command, style).expect("the CLI succeeds");
}

/// The CSV file as header and rows of cells.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).expect("readable CSV");
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

/// The cell's number (NaN for an empty cell).
fn num(cell: &str) -> f64 {
    if cell.is_empty() {
        f64::NAN
    } else {
        cell.parse().expect("a number")
    }
}

fn same_bits(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

#[test]
fn physical_scene_sweep_and_reconstruction_match_the_cli_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let (sweep_dir, recon_dir) = (dir.path().join("sweep"), dir.path().join("recon"));
    let scene_arg = scene_path();
    cli(&[
        "sweep",
        scene_arg.to_str().unwrap(),
        "--out",
        sweep_dir.to_str().unwrap(),
    ]);
    cli(&[
        "reconstruct",
        sweep_dir.to_str().unwrap(),
        "--out",
        recon_dir.to_str().unwrap(),
    ]);

    let scene = Scene::load(scene_path()).unwrap();
    assert!(scene.units().unwrap().is_physical());
    let sweep = scene.sweep().unwrap();

    // observables.csv: every cell, bit for bit
    let (header, rows) = read_csv(&sweep_dir.join("observables.csv"));
    assert_eq!(
        header.join(","),
        "x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi,ft,slip,y0,gamma"
    );
    assert_eq!(rows.len(), sweep.rows().len());
    let mut compared = 0;
    for (i, (cells, row)) in rows.iter().zip(sweep.rows()).enumerate() {
        let values = [
            row.x0,
            row.ax,
            row.ay,
            row.ma,
            row.phi0,
            row.f,
            row.s1,
            f64::NAN,
            row.xc,
            row.yc,
            row.psi,
            row.ft,
            f64::NAN,
            row.y0,
            row.gamma,
        ];
        for (j, v) in values.iter().enumerate() {
            if j == 7 {
                assert_eq!(cells[7], row.phase.label(), "row {}", i + 1);
                continue;
            }
            if j == 12 {
                assert_eq!(cells[12], row.slip.label(), "row {}", i + 1);
                continue;
            }
            assert!(
                same_bits(num(&cells[j]), *v),
                "row {} column {}: CLI {} vs library {v:e}",
                i + 1,
                header[j],
                cells[j]
            );
            compared += 1;
        }
        if row.phase == Phase::None {
            assert!(row.xc.is_nan() && num(&cells[8]).is_nan(), "row {}", i + 1);
        }
    }
    assert!(compared >= 10 * 100, "{compared} numbers compared");

    // events: first contact, separation, in rows of the CSV and the scene's mm
    let (kind, first) = sweep.first_contact();
    let first = first.expect("a first contact row");
    assert_eq!(sweep.rows()[first.row - 1].x0, first.x0);
    assert_ne!(sweep.rows()[first.row - 1].phase, Phase::None);
    assert_eq!(sweep.rows()[first.row - 2].phase, Phase::None);
    assert_eq!(kind.phase(), sweep.rows()[first.row - 1].phase);
    let (_, sep) = sweep.separation();
    let sep = sep.expect("a separation row");
    assert!(
        sep.row > first.row && sep.x0 < first.x0,
        "x0 decreases along the sweep"
    );
    let events = sweep.events();
    assert_eq!(events.first().map(|e| e.row), Some(first.row));
    assert_eq!(events.last().map(|e| e.row), Some(sep.row));

    // reconstruction.csv: from the CLI's log read back, and from the sweep itself
    let (header, rows) = read_csv(&recon_dir.join("reconstruction.csv"));
    let log = vibrissa::io::read_observables(sweep_dir.join("observables.csv")).unwrap();
    for rec in [
        scene.reconstruct(&log).unwrap(),
        scene.reconstruct(&sweep).unwrap(),
    ] {
        assert_eq!(rows.len(), rec.rows.len());
        for (i, (cells, p)) in rows.iter().zip(&rec.rows).enumerate() {
            let values = [p.x0, p.x, p.y, p.s1, p.f, p.psi];
            for (j, v) in values.iter().enumerate() {
                assert!(
                    same_bits(num(&cells[j]), *v),
                    "reconstruction row {} column {}: CLI {} vs library {v:e}",
                    i + 1,
                    header[j],
                    cells[j]
                );
            }
            assert_eq!(cells[6], p.phase.label());
            assert!(same_bits(num(&cells[7]), p.sigma));
            assert!(same_bits(num(&cells[8]), p.residual));
        }
        // the reconstructed points lie on the swept contact points (independent truth:
        // the sweep's own contact points), to well under a micrometre
        // (a row the reconstruction cannot place, e.g. at a phase switch, is left out; the
        // others are matched by their x0, copied exactly)
        let contact = sweep.counts().contact;
        assert!(
            rec.rows.len() + 4 >= contact,
            "{} of {contact}",
            rec.rows.len()
        );
        let worst = rec
            .rows
            .iter()
            .map(|r| {
                let s = sweep.rows().iter().find(|s| s.x0 == r.x0).expect("its row");
                assert_eq!(s.phase, r.phase, "x0 = {}", r.x0);
                (s.xc - r.x).hypot(s.yc - r.y)
            })
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "worst distance {worst:e} mm");
    }
}

#[test]
fn scenes_round_trip_and_errors_fall_in_the_three_classes() {
    let scene = Scene::load(scene_path()).unwrap();
    let again = Scene::from_ron(&scene.to_ron().unwrap()).unwrap();
    assert_eq!(again, scene);

    // invalid input names the field
    let mut bad = scene.clone();
    bad.spec.whisker.theta = 2.0;
    let e = bad.sweep().unwrap_err();
    assert_eq!(e.exit_code(), 2, "{e}");
    assert!(e.to_string().contains("whisker.theta"), "{e}");

    // an obstacle far away: no contact
    let mut far = scene.clone();
    far.spec.profile = Some("circle:1000,1000,1".into());
    let e = far.sweep().unwrap_err();
    assert!(matches!(e, Error::NoContact { .. }), "{e}");
    assert_eq!(e.exit_code(), 3);

    // a missing file
    let e = Scene::load("no/such/scene.ron").unwrap_err();
    assert_eq!(e.exit_code(), 2);
    assert!(e.to_string().contains("no/such/scene.ron"), "{e}");
}
