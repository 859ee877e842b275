//! Helpers shared by the CLI's integration tests: running the binary (with its words
//! written as one command line, with a stdin), the one-line failure every refusal must be,
//! reading its CSV and JSON outputs, and the sweep -> `reconstruct DIR` round trip. Each
//! test file uses a part of them.
#![allow(dead_code)]

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use vibrissa_cli::units::UnitSystem;

pub fn run(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vibrissa"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the binary runs")
}

/// The arguments of a command line as a test writes it: `line` split on white space (no
/// argument of such a line holds a space).
pub fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// Runs the binary with `args` in `cwd`, `input` written to its stdin.
pub fn run_stdin(args: &[&str], cwd: &Path, input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vibrissa"))
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

/// Asserts that the run succeeded, showing its stderr otherwise.
pub fn assert_ok(o: &Output) {
    assert!(o.status.success(), "stderr: {}", stderr(o));
}

/// The stderr of a refused run, asserted to be one line that mentions every needle, with no
/// panic. (The callers check the exit code and what must not be left behind.)
pub fn one_line_error(o: &Output, needles: &[&str]) -> String {
    let err = stderr(o);
    assert_eq!(err.trim_end().lines().count(), 1, "one-line error: {err:?}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "stderr {err:?} should mention {n:?}");
    }
    err
}

/// A log's text with its data rows in reverse order under the same header, each line ended
/// by a newline: the stream's input whose points must be the batch's.
pub fn rows_reversed(log: &str) -> String {
    let mut lines: Vec<&str> = log.lines().collect();
    let header = lines.remove(0);
    lines.reverse();
    std::iter::once(header)
        .chain(lines)
        .map(|l| format!("{l}\n"))
        .collect()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    assert!(o.status.success(), "stderr: {}", stderr(o));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&stdout(o)).expect("stdout is one JSON object")
}

pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// A CSV table as header and rows of strings (comma separated, as the CLI writes).
pub fn table(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    parse(&text)
}

/// Data rows of a CSV text as (header, rows of fields).
pub fn parse(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = text.lines().map(|l| l.trim_end_matches('\r'));
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

pub fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("column {name} in {header:?}"))
}

pub fn num(s: &str) -> f64 {
    s.parse().unwrap_or_else(|_| panic!("`{s}` is a number"))
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// g1 of the thesis: y = cosh(x / 2) - 4/5.
pub fn g1(x: f64) -> f64 {
    (x / 2.0).cosh() - 0.8
}

pub const L_BETA_MM: f64 = 66.2;

pub fn physical_beta() -> UnitSystem {
    UnitSystem::new(Some(
        beam_model::Preset::from_name("beta").unwrap().whisker(),
    ))
}

/// Sweeps `args` into `cwd/out`, then reconstructs the folder with no further flags into
/// `cwd/rec`; checks the round trip: q to 1e-8 relative, every reconstructed contact point
/// against the sweep's (xc, yc) to 1e-8 relative, x0 copied bit for bit. Returns the
/// reconstruction's JSON.
pub fn round_trip(cwd: &Path, sweep_args: &[&str], q_true: f64) -> serde_json::Value {
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

/// The text of an SVG with the subscript markup taken out (`A<tspan ..>x</tspan>` reads
/// `Ax`).
pub fn svg_text(svg: &str) -> String {
    let mut out = String::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<tspan") {
        out.push_str(&rest[..i]);
        rest = &rest[i + rest[i..].find('>').unwrap() + 1..];
    }
    out.push_str(rest);
    out.replace("</tspan>", "")
}

/// The whisker and flow of most tests: theta = 0.75 on a spring k = 20 under q = 5.
pub const WHISKER_Q5: [&str; 6] = ["--q", "5", "--theta", "0.75", "--k", "20"];

/// `--profile PROFILE`, the whisker and flow of [`WHISKER_Q5`] and `--points POINTS`.
pub fn sweep_flags<'a>(profile: &'a str, points: &'a str) -> Vec<&'a str> {
    let mut v = vec!["--profile", profile];
    v.extend(WHISKER_Q5);
    v.extend(["--points", points]);
    v
}

/// g1 over [-2.5, 2.5] (51 rows) as a semicolon table under `header`, x and y multiplied by
/// `scale`.
pub fn g1_table(header: &str, scale: f64) -> String {
    let mut text = format!("{header}\n");
    for i in 0..=50 {
        let x = -2.5 + 0.1 * i as f64;
        text += &format!("{};{}\n", x * scale, g1(x) * scale);
    }
    text
}
