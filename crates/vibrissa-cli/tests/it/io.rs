//! Integration tests of the I/O layers: CSV, atomic output, scene files and SVG charts.

use std::fs;
use std::path::Path;

use vibrissa_cli::atomic::{write_atomic, OutputDir};
use vibrissa_cli::csvio::{parse_table, read_table, Cell, CsvWriter};
use vibrissa_cli::plot::{Chart, FigureStyle, HeatMap, Panel, Series, Style};
use vibrissa_cli::scene_file::{LoadKind, SceneFile, SweepSpec, Units, WhiskerSpec};

fn csv_err(text: &str, required: &[&str], min_rows: usize) -> String {
    parse_table(text, Path::new("obs.csv"), required, min_rows)
        .unwrap_err()
        .to_string()
}

#[test]
fn csv_round_trip_is_bit_exact() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.csv");
    let xs = [0.1, 1.0 / 3.0, -2.5e-17, 1e300, 0.0, 123456789.123];
    let mut w = CsvWriter::new(&["x0", "Ax", "phase"]);
    for (i, &x) in xs.iter().enumerate() {
        let phase = if i % 2 == 0 { "A" } else { "none" };
        w.push_row(&[Cell::Num(x), Cell::Num(-x * 7.0), Cell::Text(phase)])
            .unwrap();
    }
    w.write(&path).unwrap();
    let t = read_table(&path, &["x0", "Ax"], xs.len()).unwrap();
    assert_eq!(t.header, ["x0", "Ax", "phase"]);
    for (a, b) in t.column("x0").unwrap().iter().zip(xs) {
        assert_eq!(a.to_bits(), b.to_bits());
    }
    assert_eq!(t.column("Ax").unwrap()[1], -(1.0 / 3.0) * 7.0);
    assert_eq!(t.text_column("phase").unwrap()[1], "none");
    assert_eq!(t.line_of(0), Some(2));
    // A row with the wrong number of cells is refused, not a panic.
    assert!(w.push_numbers(&[1.0]).is_err());
}

#[test]
fn csv_reader_is_lenient_about_foreign_files() {
    let text = "\u{feff} phase , MA,x0 ,extra,Ay,Ax,phi0\r\n\
                none, 0 ,1.5,foo,0,0,0\r\n\
                \r\n\
                # a comment\r\n\
                \"A\",2e-3,-1,bar,1,2,3";
    let t = parse_table(
        text,
        Path::new("f.csv"),
        &["x0", "Ax", "Ay", "MA", "phi0"],
        2,
    )
    .unwrap();
    assert_eq!(t.rows(), 2);
    assert_eq!(t.column("x0").unwrap(), &[1.5, -1.0]);
    assert_eq!(t.column("MA").unwrap(), &[0.0, 2e-3]);
    assert_eq!(t.text_column("phase").unwrap(), &["none", "A"]);
    assert_eq!(t.text_column("extra").unwrap(), &["foo", "bar"]);
    assert_eq!(t.lines, vec![2, 5]);
}

#[test]
fn csv_errors_name_file_line_and_column() {
    assert_eq!(
        csv_err("x0,Ax\n1,2\n", &["x0", "Ay"], 1),
        "obs.csv:1: column `Ay`: missing required column (the header has: x0,Ax; comma separated)"
    );
    assert_eq!(
        csv_err("x0,Ax\n1,2\n3\n", &["x0"], 1),
        "obs.csv:3: expected 2 fields as in the header, found 1 (comma separated)"
    );
    assert_eq!(
        csv_err("x0,Ax\n1,2\n3,abc\n", &["x0", "Ax"], 1),
        "obs.csv:3: column `Ax`: `abc` is not a number"
    );
    assert_eq!(
        csv_err("x0,Ax\n1,2\n3,NaN\n", &["x0", "Ax"], 1),
        "obs.csv:3: column `Ax`: value `NaN` is not finite"
    );
    assert_eq!(
        csv_err("x0,Ax\n1,inf\n", &["Ax"], 1),
        "obs.csv:2: column `Ax`: value `inf` is not finite"
    );
    assert_eq!(
        csv_err("x0,Ax\n1,2\n", &["x0"], 3),
        "obs.csv:2: expected at least 3 data rows, found 1"
    );
    assert_eq!(
        csv_err("", &["x0"], 1),
        "obs.csv:1: the file is empty: no header line"
    );
    // NaN outside the required columns is accepted.
    let t = parse_table("x0,f\n1,NaN\n", Path::new("a"), &["x0"], 1).unwrap();
    assert!(t.column("f").unwrap()[0].is_nan());
    let missing = read_table(Path::new("/nonexistent/obs.csv"), &[], 0).unwrap_err();
    assert!(matches!(missing, vibrissa_io::IoError::Io { .. }));
    assert!(missing.to_string().starts_with("/nonexistent/obs.csv: "));
}

#[test]
fn atomic_write_replaces_and_leaves_no_temporaries() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("a.txt");
    write_atomic(&p, b"one").unwrap();
    write_atomic(&p, b"two").unwrap();
    assert_eq!(fs::read_to_string(&p).unwrap(), "two");
    let names: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 1);
    let err = write_atomic(&dir.path().join("missing/a.txt"), b"x").unwrap_err();
    assert!(err.to_string().contains("missing/a.txt"), "{err}");
}

#[test]
fn output_dir_commits_all_or_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    // A failed command: nothing appears, no staging folder or lock is left.
    {
        let o = OutputDir::create(&out).unwrap();
        write_atomic(&o.path_for("half.csv"), b"x").unwrap();
    }
    assert!(!out.exists());
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0);
    // ... nor the parent folders made for it (the folder is made before the sweep runs).
    {
        let o = OutputDir::create(&dir.path().join("new/deeper/run")).unwrap();
        write_atomic(&o.path_for("half.csv"), b"x").unwrap();
        assert!(dir.path().join("new/deeper").is_dir());
    }
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0);
    // A folder not written by vibrissa is never replaced.
    fs::create_dir(&out).unwrap();
    fs::write(out.join("keep.txt"), "k").unwrap();
    let err = OutputDir::create(&out).unwrap_err().to_string();
    assert!(
        err.contains("keep.txt, which vibrissa did not write"),
        "{err}"
    );
    assert_eq!(fs::read_to_string(out.join("keep.txt")).unwrap(), "k");
    fs::remove_dir_all(&out).unwrap();
    // A first run writes a.csv and error.svg.
    let o = OutputDir::create(&out).unwrap();
    write_atomic(&o.path_for("a.csv"), b"old").unwrap();
    write_atomic(&o.path_for("error.svg"), b"<svg/>").unwrap();
    o.commit().unwrap();
    // A second run replaces the folder as a whole: nothing of the first is left mixed in.
    let o = OutputDir::create(&out).unwrap();
    // ... while it runs, a concurrent writer into the same folder is refused
    let err = OutputDir::create(&out).unwrap_err().to_string();
    assert!(err.contains("another vibrissa process"), "{err}");
    write_atomic(&o.path_for("a.csv"), b"new").unwrap();
    let sub = o.path_for("fig");
    fs::create_dir_all(&sub).unwrap();
    write_atomic(&sub.join("f.svg"), b"<svg/>").unwrap();
    let files = o.commit().unwrap();
    assert_eq!(files, vec![out.join("a.csv"), out.join("fig/f.svg")]);
    assert_eq!(fs::read_to_string(out.join("a.csv")).unwrap(), "new");
    assert!(!out.join("error.svg").exists());
    // only the folder is left beside it (no lock, no staging, no old copy)
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
    // the lock is released: a third run may write
    drop(OutputDir::create(&out).unwrap());
}

/// Six writers into one folder, each writing a full set of files tagged with its id:
/// every writer either commits or is refused by the lock, and the folder always holds one
/// writer's complete set (never a mix).
#[test]
fn concurrent_writers_never_mix_their_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shared");
    for _round in 0..20 {
        let handles: Vec<_> = (0..6)
            .map(|id| {
                let out = out.clone();
                std::thread::spawn(move || -> bool {
                    let Ok(o) = OutputDir::create(&out) else {
                        return false;
                    };
                    for name in ["a.csv", "b.csv", "c.svg"] {
                        write_atomic(&o.path_for(name), format!("{id}").as_bytes()).unwrap();
                    }
                    o.commit().is_ok()
                })
            })
            .collect();
        let committed = handles
            .into_iter()
            .map(|h| h.join().unwrap())
            .filter(|&c| c)
            .count();
        assert!(committed >= 1 || out.exists());
        let ids: Vec<String> = ["a.csv", "b.csv", "c.svg"]
            .iter()
            .map(|n| fs::read_to_string(out.join(n)).unwrap())
            .collect();
        assert!(ids.iter().all(|i| *i == ids[0]), "mixed output {ids:?}");
    }
}

const GOOD: &str = r#"// A scene: the whisker, its loads, optional obstacle sweep and method settings.
(
    units: Dimensionless,
    whisker: (theta: 0.5, a: 0.1, b: -0.2, k: Some(20.0)),
    loads: (f: 0.0, beta_deg: 0.0, load: Ap, q: 5.0, alpha_deg: 0.0),
    profile: Some("g1"),
    sweep: Some((points: 200)),
    method: (name: "accurate", n: None),
)
"#;

fn scene_err(text: &str) -> String {
    SceneFile::parse(text, Path::new("scene.ron"))
        .unwrap_err()
        .to_string()
}

#[test]
fn scene_good_file_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("scene.ron");
    fs::write(&p, GOOD).unwrap();
    let s = SceneFile::load(&p).unwrap();
    assert_eq!(s.whisker.theta, 0.5);
    assert_eq!(s.whisker.k, Some(20.0));
    assert_eq!(s.loads.load, LoadKind::Ap);
    assert_eq!(s.loads.q, 5.0);
    assert_eq!(s.profile.as_deref(), Some("g1"));
    assert_eq!(
        s.sweep,
        Some(SweepSpec {
            points: 200,
            tol: None
        })
    );
    let again = SceneFile::parse(&s.to_ron().unwrap(), Path::new("x.ron")).unwrap();
    assert_eq!(again, s);
}

#[test]
fn scene_minimal_file_and_physical_units() {
    let s = SceneFile::parse("(whisker: ())", Path::new("m.ron")).unwrap();
    assert_eq!(
        s,
        SceneFile::with_whisker(WhiskerSpec {
            theta: 1.0,
            a: 0.0,
            b: 0.0,
            k: None
        })
    );
    assert_eq!(s.method.name, "accurate");
    let s = SceneFile::parse(
        r#"(units: Physical(preset: "beta"), whisker: (k: 3.0), profile: "g2")"#,
        Path::new("m.ron"),
    )
    .unwrap();
    assert!(matches!(&s.units, Units::Physical { preset: Some(p), .. } if p == "beta"));
    assert_eq!(s.whisker.k, Some(3.0));
    assert_eq!(s.profile.as_deref(), Some("g2"));
    let s = SceneFile::parse(
        "(units: Physical(length_mm: 66.2, base_diameter_mm: 0.225, youngs_modulus_gpa: 1.40), whisker: ())",
        Path::new("m.ron"),
    )
    .unwrap();
    assert!(matches!(s.units, Units::Physical { length_mm: Some(l), .. } if l == 66.2));
    assert_eq!(
        scene_err("(\n units: Physical(length_mm: 66.2),\n whisker: ())"),
        "scene.ron:2:2: field `units.base_diameter_mm`: is required when no preset is given"
    );
}

#[test]
fn scene_unknown_field_names_line_and_field() {
    let text = GOOD.replace("theta: 0.5,", "theta: 0.5, thetaa: 1.0,");
    let e = scene_err(&text);
    assert!(e.starts_with("scene.ron:4:"), "{e}");
    assert!(e.contains("field `whisker.thetaa`"), "{e}");
    let e = scene_err("(whisker: (), colour: 3)");
    assert!(e.starts_with("scene.ron:1:"), "{e}");
    assert!(e.contains("field `colour`"), "{e}");
    assert!(scene_err("(loads: ())").contains("field `whisker`"));
}

#[test]
fn scene_range_errors_name_field_and_line() {
    let text = GOOD.replace("theta: 0.5", "theta: -0.5");
    assert_eq!(
        scene_err(&text),
        "scene.ron:4:15: field `whisker.theta`: must be in (0, 1], got -0.5"
    );
    let text = GOOD.replace("points: 200", "points: 1");
    assert_eq!(
        scene_err(&text),
        "scene.ron:7:18: field `sweep.points`: must be at least 2, got 1"
    );
    let text = GOOD.replace("n: None", "n: Some(3)");
    assert_eq!(
        scene_err(&text),
        "scene.ron:8:32: field `method.n`: must be at least 4, got 3"
    );
    let text = GOOD.replace("Some(20.0)", "Some(-1.0)");
    assert!(scene_err(&text).starts_with("scene.ron:4:44: field `whisker.k`: must be positive"));
    let text = GOOD.replace("q: 5.0", "q: inf");
    assert_eq!(
        scene_err(&text),
        "scene.ron:5:46: field `loads.q`: must be finite, got inf"
    );
}

#[test]
fn scene_malformed_ron_names_line_and_column() {
    let e = SceneFile::parse(
        "(\n  whisker: (theta: 1.0,\n  loads: (f: ),\n)",
        Path::new("bad.ron"),
    )
    .unwrap_err();
    match &e {
        vibrissa_io::IoError::Scene { line, column, .. } => assert_eq!((*line, *column), (3, 8)),
        other => panic!("unexpected {other:?}"),
    }
    assert!(e.to_string().starts_with("bad.ron:3:8: "), "{e}");
    assert_eq!(e.exit_code(), 2);
}

#[test]
fn svg_chart_is_written_with_series_names() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("c.svg");
    let beam: Vec<(f64, f64)> = (0..=20)
        .map(|i| {
            let s = i as f64 / 20.0;
            (s.sin(), 1.0 - s.cos())
        })
        .collect();
    let mut gap = beam.clone();
    gap[5].1 = f64::NAN;
    let chart = Chart::new("Elastica", "x", "y")
        .with(Series::new("rigid & <straight>", beam, Style::Line))
        .with(Series::new("with gap", gap, Style::Dashed).color(1))
        .with(Series::new("only NaN", vec![(f64::NAN, 1.0)], Style::Points).color(2))
        .equal_aspect();
    FigureStyle::default()
        .write_svg(&chart, &p, (640, 480))
        .unwrap();
    let svg = fs::read_to_string(&p).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..50]);
    assert!(svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("rigid &amp; &lt;straight&gt;"));
    assert!(svg.contains("with gap") && svg.contains("only NaN") && svg.contains("Elastica"));

    let wp = Chart::new("Work precision", "n", "error")
        .log(true, true)
        .with(Series::new(
            "fdm",
            vec![(10.0, 1e-3), (100.0, 1e-5), (1000.0, 0.0)],
            Style::LinePoints,
        ));
    let p2 = dir.path().join("panels.svg");
    FigureStyle::default()
        .write_svg_panels(&[chart.clone(), wp.clone(), wp, chart], 2, &p2, (1000, 800))
        .unwrap();
    let svg = fs::read_to_string(&p2).unwrap();
    assert!(svg.contains("Work precision") && svg.contains("fdm"));
    let err = FigureStyle::default()
        .write_svg_panels(&[], 2, &dir.path().join("none.svg"), (100, 100))
        .unwrap_err();
    assert!(err
        .to_string()
        .ends_with("none.svg: cannot draw the figure: no panels to draw"));
    assert!(!dir.path().join("none.svg").exists());
}

#[test]
fn svg_heatmap_checks_its_shape() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("map.svg");
    let mut map = HeatMap {
        title: "Stability".into(),
        x_label: "q".into(),
        y_label: "x0".into(),
        x_values: vec![0.0, 1.0, 2.0],
        y_values: vec![-1.0, 1.0],
        cells: vec![vec![0, 1, 1], vec![0, 0, 2]],
        categories: vec![
            ("stable".into(), (200, 230, 200)),
            ("snap".into(), (240, 180, 180)),
            ("no contact".into(), (220, 220, 220)),
        ],
    };
    FigureStyle::default()
        .write_figure(&[Panel::HeatMap(&map)], 1, &p, (600, 400))
        .unwrap();
    let svg = fs::read_to_string(&p).unwrap();
    assert!(svg.contains("no contact") && svg.contains("Stability"));
    map.cells[1][2] = 7;
    let e = FigureStyle::default()
        .write_figure(&[Panel::HeatMap(&map)], 1, &p, (600, 400))
        .unwrap_err();
    assert!(
        e.to_string()
            .ends_with("cells row 1 uses category 7 but only 3 categories are defined"),
        "{e}"
    );
    map.cells.pop();
    let e = FigureStyle::default()
        .write_figure(&[Panel::HeatMap(&map)], 1, &p, (600, 400))
        .unwrap_err();
    assert!(e
        .to_string()
        .ends_with("cells has 1 rows but y_values has 2 values"));
}
