//! The researcher's workflow (issue 13): contours as CSV points files with units and any
//! delimiter, self-describing output folders (`scene.ron`, units sidecars) that
//! `reconstruct DIR` reads with no further flags, physical units end to end, one row
//! numbering in text, JSON and CSV, and figures as SVG and PNG.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use vibrissa_cli::resolve::read_points_file;
use vibrissa_cli::units::UnitSystem;

fn run(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vibrissa"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    assert!(o.status.success(), "stderr: {}", stderr(o));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&stdout(o)).expect("stdout is one JSON object")
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// A CSV table as header and rows of strings (comma separated, as the CLI writes).
fn table(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("column {name} in {header:?}"))
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or_else(|_| panic!("`{s}` is a number"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// g1 of the thesis: y = cosh(x / 2) - 4/5.
fn g1(x: f64) -> f64 {
    (x / 2.0).cosh() - 0.8
}

const L_BETA_MM: f64 = 66.2;

fn physical_beta() -> UnitSystem {
    UnitSystem::new(Some(
        beam_model::Preset::from_name("beta").unwrap().whisker(),
    ))
}

#[test]
fn points_files_name_their_columns_with_units_and_any_delimiter() {
    let dir = tempfile::tempdir().unwrap();
    let xs: Vec<f64> = (0..=50).map(|i| -2.5 + 0.1 * i as f64).collect();
    // Semicolons, `x_mm;y_mm`, decimal commas (as a spreadsheet in many locales writes).
    let mut semi = String::from("x_mm;y_mm\n");
    for &x in &xs {
        semi += &format!("{};{}\n", x * L_BETA_MM, g1(x) * L_BETA_MM).replace('.', ",");
    }
    let p = dir.path().join("semi.csv");
    fs::write(&p, &semi).unwrap();
    let (x, y) = read_points_file(&p, &physical_beta()).unwrap();
    assert_eq!(x.len(), xs.len());
    for ((a, b), &xt) in x.iter().zip(&y).zip(&xs) {
        assert!((a - xt).abs() < 1e-12, "x {a} vs {xt}");
        assert!((b - g1(xt)).abs() < 1e-12, "y {b} vs {}", g1(xt));
    }
    // Tabs, units in brackets, an extra column, a comment line; metres.
    let mut tab = String::from("# measured contour\nx [m]\ty [m]\tquality\n");
    for &xv in &xs {
        tab += &format!(
            "{}\t{}\tgood\n",
            xv * L_BETA_MM / 1e3,
            g1(xv) * L_BETA_MM / 1e3
        );
    }
    let p = dir.path().join("tab.tsv");
    fs::write(&p, &tab).unwrap();
    let (x, y) = read_points_file(&p, &physical_beta()).unwrap();
    assert!((x[0] + 2.5).abs() < 1e-12 && (y[50] - g1(2.5)).abs() < 1e-12);
    // A dimensionless scene reads plain `x,y` as whisker lengths.
    let p = dir.path().join("plain.csv");
    fs::write(&p, "x,y\n-1,1\n0,0.5\n1,1\n2,2.5\n").unwrap();
    let (x, y) = read_points_file(&p, &UnitSystem::DIMENSIONLESS).unwrap();
    assert_eq!((x[3], y[1]), (2.0, 0.5));
}

#[test]
fn points_file_errors_name_file_line_and_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let err = |name: &str, text: &str, units: &UnitSystem| {
        let p = dir.path().join(name);
        fs::write(&p, text).unwrap();
        read_points_file(&p, units).unwrap_err().to_string()
    };
    let d = UnitSystem::DIMENSIONLESS;
    // dimensionless scene: (file, contents, what the message must say)
    let cases = [
        (
            "noheader.csv",
            "-1,1\n0,0.5\n1,1\n2,2.5\n",
            "noheader.csv:1: the first line holds numbers",
        ),
        (
            "names.csv",
            "a;b\n-1;1\n0;0.5\n1;1\n2;2.5\n",
            "names.csv:1: the header must name an x and a y column",
        ),
        (
            "order.csv",
            "x,y\n-1,1\n1,0.5\n0.5,1\n2,2.5\n",
            "order.csv:4: column `x`: x = 0.5 does not increase",
        ),
        (
            "mm.csv",
            "x_mm,y_mm\n-1,1\n0,0.5\n1,1\n2,2.5\n",
            "mm.csv:1: column `x_mm`: values in `mm` need a physical scene",
        ),
        (
            "short.csv",
            "x,y\n-1,1\n0,0.5\n",
            "short.csv:3: expected at least 4 data rows, found 2",
        ),
        (
            "ragged.csv",
            "x\ty\n-1\t1\n0\n",
            "ragged.csv:3: expected 2 fields as in the header, found 1 (tab separated)",
        ),
    ];
    for (name, text, expected) in cases {
        let e = err(name, text, &d);
        assert!(e.contains(expected), "{e}");
    }
    // physical scene: the whole message, with the file's full path
    let e = err(
        "bad.csv",
        "x_mm;y_mm\n-1;1\n0;abc\n1;1\n2;2.5\n",
        &physical_beta(),
    );
    assert_eq!(
        e,
        format!(
            "{}:3: column `y_mm`: `abc` is not a number",
            dir.path().join("bad.csv").display()
        )
    );
}

/// Sweeps `args` into `cwd/out`, then reconstructs the folder with no further flags into
/// `cwd/rec`; checks the round trip: q to 1e-8 relative, every reconstructed contact point
/// against the sweep's (xc, yc) to 1e-8 relative, x0 copied bit for bit. Returns the
/// reconstruction's JSON.
fn round_trip(cwd: &Path, sweep_args: &[&str], q_true: f64) -> serde_json::Value {
    let mut args = vec!["sweep"];
    args.extend(sweep_args);
    args.extend(["--out", "out"]);
    let o = run(&args, cwd);
    stdout(&o);
    assert!(cwd.join("out/scene.ron").is_file());
    let v = json(&run(&["reconstruct", "out", "--json", "--out", "rec"], cwd));
    let q = v["q"].as_f64().unwrap();
    assert!(rel(q, q_true) < 1e-8, "q = {q}, true {q_true}");
    let (oh, orows) = table(&cwd.join("out/observables.csv"));
    let (rh, rrows) = table(&cwd.join("rec/reconstruction.csv"));
    assert!(!rrows.is_empty());
    assert_eq!(v["points"].as_u64().unwrap() as usize, rrows.len());
    let (ox0, oxc, oyc) = (col(&oh, "x0"), col(&oh, "xc"), col(&oh, "yc"));
    let (rx0, rx, ry) = (col(&rh, "x0"), col(&rh, "x"), col(&rh, "y"));
    // The contour's size sets the scale of the relative error.
    let scale = orows
        .iter()
        .filter(|r| r[oxc] != "NaN")
        .map(|r| num(&r[oxc]).abs().max(num(&r[oyc]).abs()))
        .fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    for r in &rrows {
        let o = orows
            .iter()
            .find(|o| o[ox0] == r[rx0])
            .unwrap_or_else(|| panic!("x0 {} copied exactly from the log", r[rx0]));
        worst = worst
            .max((num(&r[rx]) - num(&o[oxc])).abs() / scale)
            .max((num(&r[ry]) - num(&o[oyc])).abs() / scale);
    }
    assert!(worst < 1e-8, "worst relative contour error {worst:e}");
    // The reconstruction folder describes itself too.
    assert!(cwd.join("rec/scene.ron").is_file());
    assert!(cwd.join("rec/reconstruction.units.csv").is_file());
    v
}

#[test]
fn reconstruct_dir_round_trip_dimensionless() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let v = round_trip(
        cwd,
        &[
            "--profile",
            "g1",
            "--q",
            "5",
            "--theta",
            "0.75",
            "--k",
            "20",
            "--points",
            "24",
        ],
        5.0,
    );
    assert_eq!(v["units"], "dimensionless");
    let units = fs::read_to_string(cwd.join("out/observables.units.csv")).unwrap();
    assert_eq!(
        units,
        "x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi\n1,1,1,1,rad,1,1,,1,1,rad\n"
    );
    // The scene states every parameter, the true point count included.
    let scene = fs::read_to_string(cwd.join("out/scene.ron")).unwrap();
    for needle in [
        "theta: 0.75",
        "k: Some(20.0)",
        "q: 5.0",
        "points: 24",
        "\"g1\"",
    ] {
        assert!(scene.contains(needle), "scene.ron lacks {needle}:\n{scene}");
    }
    // Flags still override the folder's scene: a wrong taper makes the rows inconsistent.
    let o = run(
        &["reconstruct", "out", "--theta", "0.5", "--out", "bad"],
        cwd,
    );
    assert!(!o.status.success());
    let e = stderr(&o);
    // refused, naming the log: no row fits the free whisker of the wrong taper, or no
    // contact point is consistent with it
    assert!(
        e.contains("observables.csv:")
            && (e.contains("no consistent contact point") || e.contains("check the whisker")),
        "{e}"
    );
    assert!(!cwd.join("bad").exists());
}

#[test]
fn reconstruct_dir_round_trip_physical() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let scene = scenes_dir().join("physical-beta-g1.ron");
    let scene = scene.to_str().unwrap();
    let v = round_trip(cwd, &[scene, "--points", "30"], 0.003);
    assert_eq!(v["units"], "physical");
    let units = fs::read_to_string(cwd.join("out/observables.units.csv")).unwrap();
    assert_eq!(
        units,
        "x0,Ax,Ay,MA,phi0,f,s1,phase,xc,yc,psi\nmm,N,N,N mm,rad,N,mm,,mm,mm,rad\n"
    );
    // Positions are in mm: the pre-contact rows carry s1 = L = 66.2 mm and Ax = -Q L in N.
    let (oh, orows) = table(&cwd.join("out/observables.csv"));
    assert!(rel(num(&orows[0][col(&oh, "s1")]), L_BETA_MM) < 1e-12);
    assert!(rel(-num(&orows[0][col(&oh, "Ax")]), 0.003 * 0.0662) < 1e-9);
    // The log in mm and N is refused with a dimensionless scene: its sidecar says why.
    fs::write(
        cwd.join("dimless.ron"),
        "(whisker: (theta: 0.75, k: Some(20.0)))",
    )
    .unwrap();
    let o = run(&["reconstruct", "out", "dimless.ron", "--out", "bad"], cwd);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("observables.units.csv:2: column `x0`: values in `mm` need a physical scene"),
        "{e}"
    );
    // Figures say their units, small forces and moments with a prefix.
    let svg = svg_text(&fs::read_to_string(cwd.join("out/observables.svg")).unwrap());
    for needle in ["x0 [mm]", "Ax [µN]", "MA [mN mm]", "q = 0.003 N/m"] {
        assert!(svg.contains(needle), "observables.svg lacks {needle}");
    }
    let svg = fs::read_to_string(cwd.join("rec/reconstruction.svg")).unwrap();
    assert!(svg.contains("x [mm]") && svg.contains("y [mm]"));
}

#[test]
fn rows_are_counted_the_same_way_in_text_json_and_csv() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let args = [
        "sweep",
        "--profile",
        "g1",
        "--q",
        "5",
        "--theta",
        "0.75",
        "--k",
        "20",
        "--points",
        "12",
    ];
    let mut a = args.to_vec();
    a.extend(["--json", "--out", "j"]);
    let v = json(&run(&a, cwd));
    let mut a = args.to_vec();
    a.extend(["--out", "t"]);
    let text = stdout(&run(&a, cwd));
    let (h, rows) = table(&cwd.join("j/observables.csv"));
    let phase = col(&h, "phase");
    let first = rows.iter().position(|r| r[phase] != "none").unwrap() + 1;
    let last = rows.iter().rposition(|r| r[phase] != "none").unwrap() + 1;
    let contact = rows.iter().filter(|r| r[phase] != "none").count();
    assert_eq!(v["rows"].as_u64().unwrap() as usize, rows.len());
    assert_eq!(v["first_contact_row"].as_u64().unwrap() as usize, first);
    assert_eq!(v["separation_row"].as_u64().unwrap() as usize, last);
    assert_eq!(v["contact_rows"].as_u64().unwrap() as usize, contact);
    assert_eq!(v["points_requested"], 12);
    assert_eq!(
        v["event_rows"].as_u64().unwrap() as usize,
        contact - 12,
        "--points N gives N contact rows plus the event rows"
    );
    for key in ["first_contact", "separation", "phases"] {
        assert!(v[key].is_string(), "{key}: {v}");
    }
    assert!(text.contains(&format!("{} rows (", rows.len())), "{text}");
    assert!(
        text.contains(&format!(
            "first contact {} at row {first} ",
            v["first_contact"].as_str().unwrap()
        )),
        "{text}"
    );
    assert!(text.contains(&format!("at row {last} ")), "{text}");
    // The events of the JSON name rows of the CSV.
    for e in v["events"].as_array().unwrap() {
        let row = e["row"].as_u64().unwrap() as usize;
        assert_eq!(
            num(&rows[row - 1][col(&h, "x0")]),
            e["x0"].as_f64().unwrap()
        );
    }
    // reconstruct numbers rows the same way: its first reconstructed row is a contact row
    // with a contact force, right after the flow-only rows.
    let v2 = json(&run(&["reconstruct", "j", "--json", "--out", "r"], cwd));
    let r1 = v2["first_contact_row"].as_u64().unwrap() as usize;
    assert!(r1 == first || r1 == first + 1, "{r1} vs {first}");
    assert!(num(&rows[r1 - 1][col(&h, "f")]) > 0.0);
    assert_eq!(v2["rows"].as_u64().unwrap() as usize, rows.len());
    // one point per row with a contact force above the log's precision (a release row at
    // f ~ 1e-12 is the free whisker within it)
    let with_force = rows[r1 - 1..]
        .iter()
        .filter(|r| num(&r[col(&h, "f")]) > 1e-9)
        .count();
    assert_eq!(v2["points"].as_u64().unwrap() as usize, with_force);
}

#[test]
fn demo_scene_records_the_points_it_used() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&["demo", "--points", "5", "--out", "d"], dir.path());
    let text = stdout(&o);
    let scene = fs::read_to_string(dir.path().join("d/scene.ron")).unwrap();
    assert!(scene.contains("points: 5,"), "{scene}");
    assert!(!scene.contains("points: 120"));
    assert!(text.contains("5 requested"), "{text}");
    // The scene reads back and reproduces the demo's folder.
    let o = run(&["sweep", "d/scene.ron", "--out", "again"], dir.path());
    stdout(&o);
    assert_eq!(
        fs::read_to_string(dir.path().join("d/observables.csv")).unwrap(),
        fs::read_to_string(dir.path().join("again/observables.csv")).unwrap()
    );
}

/// Width and height of a PNG from its IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}

/// The printed `width` and `height` of an SVG (millimetres) and its canvas width
/// (points, from the viewBox).
fn svg_size(svg: &str) -> (f64, f64, f64) {
    let attr = |name: &str| -> String {
        let start = svg.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        let end = start + svg[start..].find('"').unwrap();
        svg[start..end].to_string()
    };
    let mm = |name: &str| {
        attr(name)
            .strip_suffix("mm")
            .unwrap()
            .parse::<f64>()
            .unwrap()
    };
    let vb: Vec<f64> = attr("viewBox")
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    (mm("width"), mm("height"), vb[2])
}

/// The text of an SVG with the subscript markup taken out (`A<tspan ..>x</tspan>` reads
/// `Ax`).
fn svg_text(svg: &str) -> String {
    let mut out = String::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<tspan") {
        out.push_str(&rest[..i]);
        rest = &rest[i + rest[i..].find('>').unwrap() + 1..];
    }
    out.push_str(rest);
    out.replace("</tspan>", "")
}

/// Every font size of an SVG in printed points: (text, subscripts).
fn printed_font_sizes(svg: &str) -> (Vec<f64>, Vec<f64>) {
    let (w_mm, _, canvas) = svg_size(svg);
    let k = w_mm / 25.4 * 72.0 / canvas;
    let mut text = Vec::new();
    let mut sub = Vec::new();
    for (i, _) in svg.match_indices("font-size=\"") {
        let v: f64 = svg[i + 11..i + 11 + svg[i + 11..].find('"').unwrap()]
            .parse()
            .unwrap();
        let tag_start = svg[..i].rfind('<').unwrap();
        if svg[tag_start..].starts_with("<tspan") {
            sub.push(v * k);
        } else {
            text.push(v * k);
        }
    }
    (text, sub)
}

#[test]
fn figures_come_as_svg_and_png_with_symbols_units_and_events() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    // A rigid support: phi0 = pi/2 throughout, so no phi0 panel.
    let o = run(
        &[
            "sweep",
            "--profile",
            "g1",
            "--q",
            "5",
            "--points",
            "20",
            "--out",
            "rigid",
        ],
        cwd,
    );
    stdout(&o);
    let raw = fs::read_to_string(cwd.join("rigid/observables.svg")).unwrap();
    // Subscripts are set as such: A_x, M_A, x_0.
    assert!(
        raw.contains(">A<tspan") && raw.contains(">M<tspan"),
        "no subscripts"
    );
    let svg = svg_text(&raw);
    assert!(
        !svg.contains("φ0 [rad]"),
        "a rigid support has no phi0 panel"
    );
    assert!(svg.contains("φ0 = π/2 throughout (rigid support, no panel)"));
    for needle in [
        "base x0 [–]",
        "Ax [–]",
        "Ay [–]",
        "MA [–]",
        "first contact (",
        "phase A: tip contact",
        "no contact (flow only)",
    ] {
        assert!(svg.contains(needle), "observables.svg lacks {needle}");
    }
    // An elastic support has the phi0 panel.
    let o = run(
        &[
            "sweep",
            "--profile",
            "g1",
            "--q",
            "5",
            "--k",
            "20",
            "--points",
            "20",
            "--figures",
            "all",
            "--out",
            "spring",
        ],
        cwd,
    );
    stdout(&o);
    let svg = svg_text(&fs::read_to_string(cwd.join("spring/observables.svg")).unwrap());
    assert!(svg.contains("φ0 [rad]"));
    let shapes = fs::read_to_string(cwd.join("spring/shapes.svg")).unwrap();
    for needle in [
        "obstacle (solid above)",
        "flow direction",
        "sweep (base → −x)",
        "first contact",
        "contact points",
    ] {
        assert!(shapes.contains(needle), "shapes.svg lacks {needle}");
    }
    // Sub-pixel coordinates: the curves' paths use fractional pixel positions.
    let frac = shapes
        .split("d=\"M")
        .skip(1)
        .flat_map(|p| p.split('"').next().unwrap().split([' ', 'L', 'M']))
        .filter(|t| t.contains('.'))
        .count();
    assert!(frac > 100, "only {frac} fractional coordinates");
    // Every SVG prints one column wide (85 mm) with text of 7 pt or more (subscripts
    // 5.5 pt or more), and has its PNG twin at 300 dpi of that print.
    let mut n = 0;
    for e in fs::read_dir(cwd.join("spring")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "svg") {
            let svg = fs::read_to_string(&p).unwrap();
            let (w, h, _) = svg_size(&svg);
            assert!((w - 85.0).abs() < 1e-9, "{}: {w} mm wide", p.display());
            let (text, sub) = printed_font_sizes(&svg);
            let small = text
                .iter()
                .chain(&sub)
                .fold(f64::INFINITY, |a, &b| a.min(b));
            assert!(
                text.iter().all(|&v| v >= 6.99),
                "{}: text at {small} pt",
                p.display()
            );
            assert!(
                sub.iter().all(|&v| v >= 5.5),
                "{}: subscript at {small} pt",
                p.display()
            );
            let png = fs::read(p.with_extension("png")).unwrap();
            let px = |mm: f64| (mm / 25.4 * 300.0).round() as i64;
            let (pw, ph) = png_size(&png);
            assert!(
                (i64::from(pw) - px(w)).abs() <= 1 && (i64::from(ph) - px(h)).abs() <= 1,
                "{}: {pw}x{ph} px for {w}x{h} mm",
                p.display()
            );
            n += 1;
        }
    }
    assert_eq!(n, 3, "observables, contact, shapes");
    // Phases and events differ in line style, not only in colour.
    let raw = fs::read_to_string(cwd.join("spring/observables.svg")).unwrap();
    let dashes: std::collections::BTreeSet<&str> = raw
        .split("stroke-dasharray=\"")
        .skip(1)
        .map(|t| &t[..t.find('"').unwrap()])
        .collect();
    assert!(dashes.len() >= 4, "dash patterns: {dashes:?}");
    // --size page prints 175 mm wide, slides 254 mm.
    for (size, mm) in [("page", 175.0), ("slide", 254.0)] {
        let o = run(
            &[
                "sweep",
                "--profile",
                "g1",
                "--q",
                "5",
                "--points",
                "20",
                "--size",
                size,
                "--out",
                size,
            ],
            cwd,
        );
        stdout(&o);
        let svg = fs::read_to_string(cwd.join(size).join("observables.svg")).unwrap();
        assert!((svg_size(&svg).0 - mm).abs() < 1e-9, "{size}");
    }
}

#[test]

fn a_table_over_pm_2_5_sweeps_and_reconstructs() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let mut text = String::from("x;y\n");
    for i in 0..=50 {
        let x = -2.5 + 0.1 * i as f64;
        text += &format!("{x};{}\n", g1(x));
    }
    fs::write(cwd.join("g1.csv"), text).unwrap();
    round_trip(
        cwd,
        &[
            "--profile",
            "points:g1.csv",
            "--q",
            "5",
            "--theta",
            "0.75",
            "--k",
            "20",
            "--points",
            "30",
        ],
        5.0,
    );
    // The table is copied into the folder and its scene points at the copy.
    assert!(cwd.join("out/profile.csv").is_file());
    let scene = fs::read_to_string(cwd.join("out/scene.ron")).unwrap();
    assert!(scene.contains("\"points:profile.csv\""), "{scene}");
}

#[test]

fn a_circle_post_of_radius_0_6_sweeps_and_reconstructs() {
    let dir = tempfile::tempdir().unwrap();
    round_trip(
        dir.path(),
        &[
            "--profile",
            "circle:0,1.3,0.6",
            "--q",
            "1",
            "--theta",
            "0.75",
            "--k",
            "20",
            "--points",
            "30",
        ],
        1.0,
    );
}

#[test]

fn a_physical_table_in_mm_with_semicolons_sweeps() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let mut text = String::from("x_mm;y_mm\n");
    for i in 0..=50 {
        let x = -2.5 + 0.1 * i as f64;
        text += &format!("{};{}\n", x * L_BETA_MM, g1(x) * L_BETA_MM);
    }
    fs::write(cwd.join("g1mm.csv"), text).unwrap();
    let scene = fs::read_to_string(scenes_dir().join("physical-beta-g1.ron"))
        .unwrap()
        .replace("Some(\"g1\")", "Some(\"points:g1mm.csv\")");
    fs::write(cwd.join("beta.ron"), scene).unwrap();
    round_trip(cwd, &["beta.ron", "--points", "30"], 0.003);
}

#[test]
fn reconstruct_dir_names_what_the_folder_lacks() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::create_dir(cwd.join("empty")).unwrap();
    let o = run(&["reconstruct", "empty", "--out", "rec"], cwd);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("empty/observables.csv: a sweep folder needs observables.csv"),
        "{e}"
    );
    fs::write(cwd.join("empty/observables.csv"), "x0,Ax,Ay,MA,phi0\n").unwrap();
    let o = run(&["reconstruct", "empty", "--out", "rec"], cwd);
    let e = stderr(&o);
    assert!(
        e.contains("empty/scene.ron: a sweep folder needs its scene.ron"),
        "{e}"
    );
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(!cwd.join("rec").exists());
}

/// `reconstruct DIR --out DIR` would replace the sweep's folder with the reconstruction: it
/// is refused before anything is written, and the sweep's files stay.
#[test]
fn reconstruct_refuses_to_write_over_the_folder_it_reads() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    stdout(&run(
        &[
            "sweep",
            "--profile",
            "g1",
            "--q",
            "5",
            "--points",
            "5",
            "--out",
            "out",
        ],
        cwd,
    ));
    let before = fs::read(cwd.join("out/observables.csv")).unwrap();
    for target in ["out", "."] {
        let o = run(&["reconstruct", "out", "--out", target], cwd);
        assert!(!o.status.success(), "--out {target} accepted");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("--out") && err.contains("holds the log"),
            "{err}"
        );
    }
    assert_eq!(fs::read(cwd.join("out/observables.csv")).unwrap(), before);
    assert!(!cwd.join("out/reconstruction.csv").exists());
}

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

/// Every physical preset of Table 2.2 (values typed here, not taken from the library): a
/// sweep past g1 and its reconstruction in physical units equal the dimensionless ones
/// scaled by hand (q = 4 and k = 20 in E I / L^3 and E I / L).
#[test]
fn every_preset_sweeps_and_reconstructs_as_the_scaled_dimensionless_scene() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let dim = json(&run(
        &[
            "sweep",
            "--profile",
            "g1",
            "--theta",
            "0.75",
            "--q",
            "4",
            "--k",
            "20",
            "--points",
            "15",
            "--json",
            "--figures",
            "none",
            "--out",
            "dim",
        ],
        cwd,
    ));
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
        let phys = json(&run(
            &[
                "sweep",
                &format!("{name}.ron"),
                "--points",
                "15",
                "--json",
                "--figures",
                "none",
                "--out",
                &out,
            ],
            cwd,
        ));
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
