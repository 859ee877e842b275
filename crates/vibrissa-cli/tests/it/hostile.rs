//! The hostile-input suite (issue #34 item 8): the built binary run on inputs a careless or
//! unlucky user gives it, generated from a seed, each outcome checked for its CLASS rather
//! than its numbers:
//!
//! - the exit code is one of 0 (success), 1 (solver failure), 2 (usage or input error), 3 (no
//!   contact), 4 (output not delivered); never 101 (a panic) nor a signal;
//! - stderr holds no panic message, no backtrace and no "internal error";
//! - a failure prints exactly one line on stderr, `error: ...`, and that line names something
//!   of the input: the file, the flag, the value, the column or the profile (for exit 2 and
//!   4 always; a solver failure names the solver instead);
//! - a success's JSON parses and its `observables.csv` / `reconstruction.csv` is whole (every
//!   row as many fields as its header);
//! - a failure leaves no output folder it did not have before, an earlier folder unchanged,
//!   and no staging folder behind.
//!
//! Families (each case is a subprocess in a folder of its own): scene files (valid scenes
//! of `scenes/` truncated, with numbers replaced by hostile literals, unknown or missing
//! fields, binary garbage, empty), observables logs (columns dropped, renamed or doubled,
//! cells replaced, truncated, garbage, reordered rows) for `reconstruct` and `--stream`,
//! flags with extreme values (`1e300`, `-0`, `NaN`, `inf`, huge `--points` and `--n`),
//! profile strings, closed pipes and `/dev/full` for every command, and concurrent writers
//! to one `--out`. Output folders (issue #34 item 6) have tests of their own at the end: a
//! symbolic link followed, files vibrissa did not write refused, two live writers, a writer
//! killed mid-run (SIGKILL and SIGTERM), a read-only parent, `--out` naming a file, and
//! `--stream` with `--out`.
//!
//! The seed is `VIBRISSA_HOSTILE_SEED` (default below); `VIBRISSA_HOSTILE_CASES` scales the
//! random families. The counts per class are printed (`cargo test -p vibrissa-cli --test it
//! -- hostile:: --nocapture`).

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The default seed of the random families.
const SEED: u64 = 0x5EED_0034;

/// Longest a case may run before it counts as a hang.
const TIMEOUT: Duration = Duration::from_secs(90);

/// SplitMix64: a small, well-mixed generator (no dependency, the same stream everywhere).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
    fn bytes(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.next() as u8).collect()
    }
}

/// Number literals a user (or a broken sensor) may type, in RON, CSV and flags.
const HOSTILE_NUMBERS: &[&str] = &[
    "1e300",
    "-1e300",
    "1e-320",
    "-0",
    "-0.0",
    "0",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "abc",
    "",
    "1,5",
    "0x10",
    "1e",
    "--1",
    "18446744073709551616",
    "-1",
    "2.5e3",
    "١",
];

/// Literals of other RON types put where a number goes.
const ODD_RON: &[&str] = &[
    "\"5\"",
    "true",
    "()",
    "[1, 2]",
    "Some(1.0)",
    "None",
    "Physical()",
    "(x: 1)",
    "'c'",
];

/// Where a case's standard output goes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Sink {
    /// A file (read back afterwards).
    File,
    /// A pipe whose read end is closed before the command writes.
    ClosedPipe,
    /// `/dev/full`: every write fails with ENOSPC.
    Full,
}

/// One run of the binary.
#[derive(Clone, Debug)]
struct Case {
    family: &'static str,
    name: String,
    args: Vec<String>,
    /// Files written into the case's folder first (name, contents).
    files: Vec<(String, Vec<u8>)>,
    stdin: Option<Vec<u8>>,
    sink: Sink,
    /// At least one of these must appear in the line of an exit 2 or 4.
    needles: Vec<String>,
    /// The `--out` folder, if the case has one.
    out: Option<String>,
    /// An earlier output folder copied in as `out` before the run (its files must survive
    /// a failure unchanged).
    prior_out: bool,
    /// Exit codes this case may end with (empty: any of 0..=4).
    expect: Vec<i32>,
}

impl Case {
    fn new(family: &'static str, name: impl Into<String>, args: &[&str]) -> Self {
        Case {
            family,
            name: name.into(),
            args: args.iter().map(|s| s.to_string()).collect(),
            files: Vec::new(),
            stdin: None,
            sink: Sink::File,
            needles: Vec::new(),
            out: None,
            prior_out: false,
            expect: Vec::new(),
        }
    }
    fn file(mut self, name: &str, contents: impl Into<Vec<u8>>) -> Self {
        self.files.push((name.to_string(), contents.into()));
        self
    }
    fn needles(mut self, n: &[&str]) -> Self {
        self.needles.extend(n.iter().map(|s| s.to_string()));
        self
    }
    fn out(mut self, dir: &str) -> Self {
        self.args.push("--out".into());
        self.args.push(dir.into());
        self.out = Some(dir.into());
        self
    }
    fn expect(mut self, codes: &[i32]) -> Self {
        self.expect = codes.to_vec();
        self
    }
    fn command_line(&self) -> String {
        let mut s = String::from("vibrissa");
        for a in &self.args {
            s.push(' ');
            if a.is_empty() || a.contains(|c: char| c.is_whitespace() || !c.is_ascii_graphic()) {
                s.push_str(&format!("{a:?}"));
            } else {
                s.push_str(a);
            }
        }
        match self.sink {
            Sink::File => {}
            Sink::ClosedPipe => s.push_str(" | (closed)"),
            Sink::Full => s.push_str(" > /dev/full"),
        }
        s
    }
}

/// What the suite needs of a real sweep: its folder's files and its log.
struct Fixture {
    /// `observables.csv` of a small sweep past g1 (q = 5, theta = 0.75, k = 20).
    log: String,
    /// The sweep folder's files (name, contents), to copy as a `--out` folder written before.
    folder: Vec<(String, Vec<u8>)>,
}

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_vibrissa")
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// The whisker and flow of the fixture's sweep.
const WHISKER: [&str; 6] = ["--theta", "0.75", "--k", "20", "--q", "5"];

fn fixture(dir: &Path) -> Fixture {
    let mut args = vec!["sweep", "--profile", "g1", "--points", "12"];
    args.extend(WHISKER);
    args.extend(["--figures", "none", "--out", "base"]);
    let o = Command::new(bin())
        .args(&args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let base = dir.join("base");
    let mut folder = Vec::new();
    for e in fs::read_dir(&base).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            folder.push((
                e.file_name().to_string_lossy().into_owned(),
                fs::read(e.path()).unwrap(),
            ));
        }
    }
    folder.sort();
    Fixture {
        log: fs::read_to_string(base.join("observables.csv")).unwrap(),
        folder,
    }
}

// ---------------------------------------------------------------------------------------
// The families
// ---------------------------------------------------------------------------------------

/// The byte ranges of the number literals of a RON text (outside comments and strings).
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'"' => {
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += 1;
                }
                i += 1;
            }
            c if c.is_ascii_digit() && (i == 0 || !b[i - 1].is_ascii_alphanumeric()) => {
                let start = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b"+-.".contains(&b[i])) {
                    i += 1;
                }
                spans.push((start, i));
            }
            _ => i += 1,
        }
    }
    spans
}

fn scene_texts() -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = fs::read_dir(scenes_dir())
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "ron").then(|| {
                (
                    p.file_name().unwrap().to_string_lossy().into_owned(),
                    fs::read_to_string(&p).unwrap(),
                )
            })
        })
        .collect();
    v.sort();
    v
}

/// A valid scene, mutated in one hostile way; solved (`solve --json`) or, for scenes with a
/// profile, sometimes swept.
fn scene_cases(rng: &mut Rng, n: usize) -> Vec<Case> {
    let scenes = scene_texts();
    let mut cases = Vec::new();
    for i in 0..n {
        let (name, text) = rng.pick(&scenes).clone();
        let (what, mutated): (String, Vec<u8>) = match rng.below(9) {
            0 => {
                let cut = rng.below(text.len());
                (
                    format!("truncated at byte {cut}"),
                    text.as_bytes()[..cut].to_vec(),
                )
            }
            1..=3 => {
                let spans = number_spans(&text);
                let (s, e) = *rng.pick(&spans);
                let lit = if rng.below(3) == 0 {
                    *rng.pick(ODD_RON)
                } else {
                    *rng.pick(HOSTILE_NUMBERS)
                };
                let mut t = text.clone();
                t.replace_range(s..e, lit);
                (
                    format!("number `{}` -> `{lit}`", &text[s..e]),
                    t.into_bytes(),
                )
            }
            4 => {
                let at = text.find("whisker: (").unwrap() + "whisker: (".len();
                let mut t = text.clone();
                t.insert_str(at, "bogus_key: 1.0, ");
                ("unknown field".to_string(), t.into_bytes())
            }
            5 => {
                let lines: Vec<&str> = text.lines().collect();
                let code: Vec<usize> = (0..lines.len())
                    .filter(|&k| {
                        let l = lines[k].trim();
                        !l.is_empty() && !l.starts_with("//") && l != "(" && l != ")"
                    })
                    .collect();
                let drop = *rng.pick(&code);
                let t: Vec<&str> = lines
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| *k != drop)
                    .map(|(_, l)| *l)
                    .collect();
                (
                    format!("line {} removed", drop + 1),
                    t.join("\n").into_bytes(),
                )
            }
            6 => {
                let mut b = text.clone().into_bytes();
                for _ in 0..1 + rng.below(4) {
                    let at = rng.below(b.len());
                    b[at] = rng.next() as u8;
                }
                ("bytes flipped".to_string(), b)
            }
            7 => {
                let len = rng.below(300);
                ("binary garbage".to_string(), rng.bytes(len))
            }
            _ => {
                let t = ["", "   \n", "// only a comment\n", "()", "(\n", "\u{feff}"];
                ("empty-ish".to_string(), rng.pick(&t).as_bytes().to_vec())
            }
        };
        let file = format!("h{i}.ron");
        let sweep = text.contains("profile:") && rng.below(3) == 0;
        let mut case = if sweep {
            Case::new(
                "scene",
                format!("sweep {name}: {what}"),
                &["sweep", &file, "--points", "6", "--figures", "none"],
            )
            .out("o")
        } else {
            Case::new(
                "scene",
                format!("solve {name}: {what}"),
                &["solve", &file, "--json"],
            )
        };
        case = case.file(&file, mutated).needles(&[&file]);
        cases.push(case);
    }
    cases
}

/// Splits a CSV text into header fields and rows of fields.
fn split_csv(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
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

fn join_csv(header: &[String], rows: &[Vec<String>], sep: &str) -> String {
    let mut s = header.join(sep) + "\n";
    for r in rows {
        s += &(r.join(sep) + "\n");
    }
    s
}

const REQUIRED: [&str; 5] = ["x0", "Ax", "Ay", "MA", "phi0"];

/// The fixture's log mutated in one hostile way, and what a message about it may name.
fn mutate_log(rng: &mut Rng, log: &str) -> (String, Vec<u8>, Vec<String>) {
    let (mut header, mut rows) = split_csv(log);
    let col = |h: &[String], name: &str| h.iter().position(|c| c == name).unwrap();
    match rng.below(12) {
        0 => {
            let name = *rng.pick(&REQUIRED);
            let j = col(&header, name);
            header.remove(j);
            for r in &mut rows {
                r.remove(j);
            }
            (
                format!("column {name} dropped"),
                join_csv(&header, &rows, ",").into_bytes(),
                vec![name.to_string()],
            )
        }
        1 => {
            let name = *rng.pick(&REQUIRED);
            let j = col(&header, name);
            header[j] = format!("{name}{name}");
            (
                format!("column {name} renamed"),
                join_csv(&header, &rows, ",").into_bytes(),
                vec![name.to_string()],
            )
        }
        2 => {
            let name = *rng.pick(&REQUIRED);
            let j = col(&header, name);
            header.push(name.to_string());
            for r in &mut rows {
                let v = r[j].clone();
                r.push(v);
            }
            (
                format!("column {name} twice"),
                join_csv(&header, &rows, ",").into_bytes(),
                vec![name.to_string()],
            )
        }
        3..=5 => {
            let name = *rng.pick(&REQUIRED);
            let j = col(&header, name);
            let i = rng.below(rows.len());
            let lit = *rng.pick(HOSTILE_NUMBERS);
            rows[i][j] = lit.to_string();
            (
                format!("row {} column {name} = `{lit}`", i + 1),
                join_csv(&header, &rows, ",").into_bytes(),
                vec![name.to_string(), format!(":{}", i + 2)],
            )
        }
        6 => {
            let text = join_csv(&header, &rows, ",");
            let cut = rng.below(text.len());
            (
                format!("truncated at byte {cut}"),
                text.as_bytes()[..cut].to_vec(),
                Vec::new(),
            )
        }
        7 => {
            let i = rng.below(rows.len());
            if rng.below(2) == 0 {
                rows[i].push("7".into());
            } else {
                rows[i].pop();
            }
            (
                format!("row {} with a field more or less", i + 1),
                join_csv(&header, &rows, ",").into_bytes(),
                vec![format!(":{}", i + 2)],
            )
        }
        8 => {
            let len = rng.below(400);
            ("binary garbage".into(), rng.bytes(len), Vec::new())
        }
        9 => {
            let t = ["", "\n", "x0,Ax,Ay,MA,phi0\n", "\u{feff}", ",,,,\n"];
            (
                "empty-ish".into(),
                rng.pick(&t).as_bytes().to_vec(),
                Vec::new(),
            )
        }
        10 => {
            // rows in another order: the spec says any order is read
            for k in (1..rows.len()).rev() {
                let j = rng.below(k + 1);
                rows.swap(k, j);
            }
            let sep = *rng.pick(&[",", ";", "\t"]);
            (
                format!("rows shuffled, separator {sep:?}"),
                join_csv(&header, &rows, sep).into_bytes(),
                Vec::new(),
            )
        }
        _ => {
            let i = rng.below(rows.len());
            let r = rows[i].clone();
            rows.insert(i, r);
            (
                format!("row {} twice", i + 1),
                join_csv(&header, &rows, ",").into_bytes(),
                Vec::new(),
            )
        }
    }
}

/// Mutated logs for `reconstruct LOG` (a file, with or without an earlier output folder).
fn log_cases(rng: &mut Rng, fx: &Fixture, n: usize) -> Vec<Case> {
    (0..n)
        .map(|i| {
            let (what, text, mut needles) = mutate_log(rng, &fx.log);
            let file = format!("log{i}.csv");
            needles.push(file.clone());
            let mut args = vec!["reconstruct", file.as_str()];
            args.extend(WHISKER);
            if rng.below(2) == 0 {
                args.push("--json");
            }
            args.extend(["--figures", "none"]);
            let mut c = Case::new("log", format!("reconstruct: {what}"), &args)
                .file(&file, text)
                .out("o");
            c.needles.extend(needles);
            c.prior_out = rng.below(3) == 0;
            c
        })
        .collect()
}

/// Mutated logs on the standard input of `reconstruct --stream`.
fn stream_cases(rng: &mut Rng, fx: &Fixture, n: usize) -> Vec<Case> {
    (0..n)
        .map(|_| {
            let (what, text, mut needles) = mutate_log(rng, &fx.log);
            needles.push("<stdin>".into());
            let mut args = vec!["reconstruct", "--stream"];
            args.extend(WHISKER);
            let mut c = Case::new("stream", format!("stream: {what}"), &args);
            c.stdin = Some(text);
            c.needles = needles;
            c
        })
        .collect()
}

/// One flag of `solve` or `sweep` given an extreme or malformed value.
fn flag_cases(rng: &mut Rng, n: usize) -> Vec<Case> {
    const SOLVE_FLAGS: &[&str] = &[
        "--theta",
        "--a",
        "--b",
        "--k",
        "--f",
        "--beta-deg",
        "--q",
        "--alpha-deg",
        "--n",
        "--tol",
    ];
    const SWEEP_FLAGS: &[&str] = &[
        "--theta",
        "--a",
        "--b",
        "--k",
        "--q",
        "--alpha-deg",
        "--points",
        "--tol",
    ];
    const HUGE: &[&str] = &[
        "1000000000",
        "4294967296",
        "1e12",
        "99999999999999999999",
        "100000000000000000000000000",
    ];
    let mut cases = Vec::new();
    for _ in 0..n {
        let sweep = rng.below(3) == 0;
        let flag = *rng.pick(if sweep { SWEEP_FLAGS } else { SOLVE_FLAGS });
        let value = if matches!(flag, "--n" | "--points") && rng.below(2) == 0 {
            *rng.pick(HUGE)
        } else {
            *rng.pick(HOSTILE_NUMBERS)
        };
        let mut c = if sweep {
            let mut args = vec!["sweep", "--profile", "g1", "--q", "5", "--points", "6"];
            args.retain(|a| *a != flag);
            if flag == "--q" || flag == "--points" {
                // the flag replaces the default given above
                let k = args.iter().position(|a| *a == "5" || *a == "6").unwrap();
                args.remove(k);
            }
            args.extend([flag, value, "--figures", "none"]);
            Case::new("flag", format!("sweep {flag} {value:?}"), &args).out("o")
        } else {
            Case::new(
                "flag",
                format!("solve {flag} {value:?}"),
                &["solve", "--q", "1", flag, value, "--json"],
            )
        };
        c.needles = vec![flag.to_string()];
        if !value.is_empty() {
            c.needles.push(value.to_string());
        }
        cases.push(c);
    }
    cases
}

/// Profile strings, malformed or pointing at bad tables.
fn profile_cases(rng: &mut Rng, n: usize) -> Vec<Case> {
    let fixed = [
        "",
        "points:",
        "points:missing.csv",
        "points:.",
        "points:empty.csv",
        "points:garbage.csv",
        "points:nan.csv",
        "points:onecol.csv",
        "points:unsorted.csv",
        "parabola:",
        "parabola:1,2",
        "parabola:a,b,c",
        "parabola:1,0,0.5,9",
        "parabola:-1,0,0.5",
        "parabola:nan,0,0.5",
        "parabola:1e300,0,0.5",
        "circle:0,0,-1",
        "circle:0,1.5,0",
        "circle:inf,1,1",
        "cosh:0,0,0,0",
        "cosh:1,-1,0,0.5",
        "g9",
        "G1",
        "g1 ",
        "peg:",
        "peg:nan,1",
        "disc:0,1.5",
        "disc:0,1.5,-2",
        ":",
        "::::",
        "points:points:x",
    ];
    let mut nan_table = String::from("x,y\n");
    let mut unsorted = String::from("x,y\n");
    for i in 0..=20 {
        let x = -2.0 + 0.2 * i as f64;
        let y = (x / 2.0f64).cosh() - 0.8;
        nan_table += &if i == 7 {
            format!("{x},NaN\n")
        } else {
            format!("{x},{y}\n")
        };
        unsorted += &format!("{},{y}\n", if i == 9 { 5.0 } else { x });
    }
    let files: Vec<(String, Vec<u8>)> = vec![
        ("empty.csv".into(), Vec::new()),
        ("garbage.csv".into(), rng.bytes(200)),
        ("nan.csv".into(), nan_table.into_bytes()),
        ("onecol.csv".into(), b"x\n1\n2\n3\n".to_vec()),
        ("unsorted.csv".into(), unsorted.into_bytes()),
    ];
    let mut cases = Vec::new();
    for i in 0..n {
        let p = if i < fixed.len() {
            fixed[i].to_string()
        } else {
            // random garbage after a known kind
            let kind = *rng.pick(&["parabola:", "circle:", "cosh:", "points:", "peg:", ""]);
            let body: String = (0..rng.below(12))
                .map(|_| *rng.pick(&['1', ',', '.', '-', 'e', 'x', ' ', ':', 'é', '0']))
                .collect();
            format!("{kind}{body}")
        };
        let mut c = Case::new(
            "profile",
            format!("sweep --profile {p:?}"),
            &[
                "sweep",
                "--profile",
                &p,
                "--q",
                "5",
                "--points",
                "6",
                "--figures",
                "none",
            ],
        )
        .out("o")
        .needles(&["--profile"]);
        if !p.trim().is_empty() {
            c.needles.push(p.clone());
        }
        if let Some(f) = p
            .strip_prefix("points:")
            .map(str::trim)
            .filter(|f| !f.is_empty())
        {
            c.needles.push(f.to_string());
        }
        if p.starts_with('-') {
            // a value that starts like a flag is given as --profile=VALUE (as a user must)
            c.args.retain(|a| a != "--profile" && *a != p);
            c.args.insert(1, format!("--profile={p}"));
        }
        c.files = files.clone();
        cases.push(c);
    }
    cases
}

/// Every command, human and `--json`, into a closed pipe and into `/dev/full`.
fn pipe_cases(fx: &Fixture) -> Vec<Case> {
    let mut cases = Vec::new();
    let commands: Vec<(&str, Vec<&str>, bool)> = vec![
        ("solve", vec!["solve", "--f", "1"], false),
        (
            "solve --out",
            vec!["solve", "--f", "1", "--out", "o"],
            false,
        ),
        (
            "sweep",
            vec![
                "sweep",
                "--profile",
                "g1",
                "--q",
                "5",
                "--points",
                "6",
                "--out",
                "o",
            ],
            false,
        ),
        (
            "reconstruct",
            vec![
                "reconstruct",
                "log.csv",
                "--theta",
                "0.75",
                "--k",
                "20",
                "--out",
                "o",
            ],
            false,
        ),
        (
            "reconstruct --stream",
            vec!["reconstruct", "--stream", "--theta", "0.75", "--k", "20"],
            true,
        ),
        (
            "calibrate",
            vec!["calibrate", "base", "--fit", "k", "--out", "o"],
            false,
        ),
        ("demo", vec!["demo", "--points", "6", "--out", "o"], false),
        ("--help", vec!["--help"], false),
        ("sweep --help", vec!["sweep", "--help"], false),
    ];
    for (name, args, stdin) in commands {
        for json in [false, true] {
            if json && (stdin || name.contains("help") || name == "demo") {
                continue;
            }
            for sink in [Sink::ClosedPipe, Sink::Full] {
                let mut a = args.clone();
                if json {
                    a.push("--json");
                }
                a.extend(["--figures", "none"]);
                if name.contains("help") {
                    a.retain(|x| *x != "--figures" && *x != "none");
                }
                let mut c = Case::new(
                    "pipe",
                    format!("{name}{} {sink:?}", if json { " --json" } else { "" }),
                    &a,
                )
                .file("log.csv", fx.log.clone())
                .needles(&["standard output"])
                .expect(&[4]);
                if name == "calibrate" {
                    for (f, bytes) in &fx.folder {
                        c = c.file(&format!("base/{f}"), bytes.clone());
                    }
                }
                if a.contains(&"--out") {
                    c.out = Some("o".into());
                }
                if stdin {
                    c.stdin = Some(fx.log.clone().into_bytes());
                }
                c.sink = sink;
                cases.push(c);
            }
        }
    }
    cases
}

// ---------------------------------------------------------------------------------------
// Running and judging
// ---------------------------------------------------------------------------------------

/// The result of one case.
struct Outcome {
    code: Option<i32>,
    stdout: Vec<u8>,
    stderr: String,
    elapsed: Duration,
}

fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut m = BTreeMap::new();
    if let Ok(rd) = fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                for (k, v) in snapshot(&p) {
                    m.insert(k, v);
                }
            } else if let Ok(b) = fs::read(&p) {
                m.insert(p, b);
            }
        }
    }
    m
}

fn run_case(case: &Case, dir: &Path, fx: &Fixture) -> Outcome {
    fs::create_dir_all(dir).unwrap();
    for (name, contents) in &case.files {
        let p = dir.join(name);
        fs::create_dir_all(p.parent().unwrap()).unwrap();
        fs::write(p, contents).unwrap();
    }
    if case.prior_out {
        let out = dir.join(case.out.as_deref().unwrap());
        fs::create_dir_all(&out).unwrap();
        for (name, contents) in &fx.folder {
            fs::write(out.join(name), contents).unwrap();
        }
    }
    let stdin_path = dir.join(".stdin");
    fs::write(&stdin_path, case.stdin.as_deref().unwrap_or_default()).unwrap();
    let out_path = dir.join(".stdout");
    let err_path = dir.join(".stderr");
    let stdout = match case.sink {
        Sink::File => Stdio::from(fs::File::create(&out_path).unwrap()),
        Sink::Full => Stdio::from(
            fs::OpenOptions::new()
                .write(true)
                .open("/dev/full")
                .unwrap(),
        ),
        Sink::ClosedPipe => {
            // the read end closed before the command starts: its first write fails (a
            // pipe made by `Stdio::piped` would race the command's first write)
            let (reader, writer) = std::io::pipe().unwrap();
            drop(reader);
            Stdio::from(writer)
        }
    };
    let t0 = Instant::now();
    let mut child = Command::new(bin())
        .args(&case.args)
        .current_dir(dir)
        .env_remove("RUST_BACKTRACE")
        .stdin(Stdio::from(fs::File::open(&stdin_path).unwrap()))
        .stdout(stdout)
        .stderr(Stdio::from(fs::File::create(&err_path).unwrap()))
        .spawn()
        .unwrap();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s);
        }
        if t0.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Outcome {
        code: status.and_then(|s| s.code()),
        stdout: fs::read(&out_path).unwrap_or_default(),
        stderr: fs::read_to_string(&err_path).unwrap_or_default(),
        elapsed: t0.elapsed(),
    }
}

/// Whether a CSV output is whole: a header, then rows of as many fields.
fn whole_csv(path: &Path) -> Result<(), String> {
    let text = fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if !text.ends_with('\n') {
        return Err(format!("{} does not end with a newline", path.display()));
    }
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let n = lines.next().map_or(0, |h| h.split(',').count());
    for (i, l) in lines.enumerate() {
        if l.split(',').count() != n {
            return Err(format!(
                "{} line {}: {} fields, header {n}",
                path.display(),
                i + 2,
                l.split(',').count()
            ));
        }
    }
    Ok(())
}

/// The problems of an outcome ("" when it is of an allowed class and clean).
fn judge(case: &Case, dir: &Path, o: &Outcome, before: &BTreeMap<PathBuf, Vec<u8>>) -> Vec<String> {
    let mut bad = Vec::new();
    let Some(code) = o.code else {
        bad.push(format!(
            "no exit code (killed by a signal or hung past {TIMEOUT:?})"
        ));
        return bad;
    };
    if !(0..=4).contains(&code) {
        bad.push(format!("exit code {code}"));
    }
    if !case.expect.is_empty() && !case.expect.contains(&code) {
        bad.push(format!("exit {code}, expected one of {:?}", case.expect));
    }
    let err = o.stderr.as_str();
    for marker in ["panicked", "backtrace", "internal error", "RUST_BACKTRACE"] {
        if err.contains(marker) {
            bad.push(format!("stderr holds `{marker}`"));
        }
    }
    let staging_left = fs::read_dir(dir)
        .unwrap()
        .flatten()
        .any(|e| e.file_name().to_string_lossy().contains("staging"));
    if staging_left {
        bad.push("a staging folder was left behind".into());
    }
    let lock_left = fs::read_dir(dir).unwrap().flatten().any(|e| {
        let n = e.file_name().to_string_lossy().into_owned();
        n.starts_with('.') && n.ends_with(".lock")
    });
    if lock_left {
        bad.push("a lock file was left behind".into());
    }
    if code != 0 {
        let lines: Vec<&str> = err.trim_end().lines().collect();
        if lines.len() != 1 {
            bad.push(format!("{} lines on stderr", lines.len()));
        }
        if !err.starts_with("error: ") {
            bad.push("stderr does not start with `error: `".into());
        }
        let named = case.needles.iter().any(|n| err.contains(n.as_str()));
        if (code == 2 || code == 4) && !case.needles.is_empty() && !named {
            bad.push(format!("the message names none of {:?}", case.needles));
        }
        // a failure before publishing leaves the output folder as it was
        if code != 4 {
            if let Some(out) = &case.out {
                let now = snapshot(&dir.join(out));
                let was: BTreeMap<_, _> = before
                    .iter()
                    .filter(|(p, _)| p.starts_with(dir.join(out)))
                    .map(|(p, b)| (p.clone(), b.clone()))
                    .collect();
                if now != was {
                    bad.push(format!("the failed run changed {out}/"));
                }
                if !case.prior_out && dir.join(out).exists() {
                    bad.push(format!("the failed run left a folder {out}/"));
                }
            }
        }
    } else {
        if case.args.iter().any(|a| a == "--json") && case.sink == Sink::File {
            if let Err(e) = serde_json::from_slice::<serde_json::Value>(&o.stdout) {
                bad.push(format!("stdout is not one JSON object: {e}"));
            }
        }
        if let Some(out) = &case.out {
            for f in ["observables.csv", "reconstruction.csv", "elastica.csv"] {
                let p = dir.join(out).join(f);
                if p.exists() {
                    if let Err(e) = whole_csv(&p) {
                        bad.push(e);
                    }
                }
            }
        }
    }
    // output not delivered: whatever was published is whole
    if code == 4 {
        if let Some(out) = &case.out {
            for f in ["observables.csv", "reconstruction.csv", "elastica.csv"] {
                let p = dir.join(out).join(f);
                if p.exists() {
                    if let Err(e) = whole_csv(&p) {
                        bad.push(e);
                    }
                }
            }
        }
    }
    bad
}

/// Runs `cases` on `threads` threads; returns the counts per family and exit code, and the
/// failures (case, command, stderr, problems).
fn run_all(cases: &[Case], root: &Path, fx: &Fixture, threads: usize) -> Report {
    let next = AtomicUsize::new(0);
    let report = Mutex::new(Report::default());
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(case) = cases.get(i) else { break };
                let dir = root.join(format!("case{i}"));
                fs::create_dir_all(&dir).unwrap();
                let o = run_case(case, &dir, fx);
                let before = if case.prior_out {
                    let out = dir.join(case.out.as_deref().unwrap());
                    fx.folder
                        .iter()
                        .map(|(n, b)| (out.join(n), b.clone()))
                        .collect()
                } else {
                    BTreeMap::new()
                };
                let problems = judge(case, &dir, &o, &before);
                let mut r = report.lock().unwrap();
                let class = o.code.map_or("hang/signal".to_string(), |c| c.to_string());
                *r.counts
                    .entry(case.family)
                    .or_default()
                    .entry(class)
                    .or_default() += 1;
                r.slowest = r.slowest.max(o.elapsed);
                if !problems.is_empty() {
                    r.failures.push(format!(
                        "[{}] {}\n    $ {}\n    exit {:?}, stderr: {:?}\n    {}",
                        case.family,
                        case.name,
                        case.command_line(),
                        o.code,
                        o.stderr,
                        problems.join("; ")
                    ));
                }
                if problems.is_empty() {
                    let _ = fs::remove_dir_all(&dir);
                }
            });
        }
    });
    report.into_inner().unwrap()
}

#[derive(Default)]
struct Report {
    counts: BTreeMap<&'static str, BTreeMap<String, usize>>,
    failures: Vec<String>,
    slowest: Duration,
}

impl Report {
    fn print(&self, seed: u64) {
        eprintln!("hostile suite, seed {seed:#x}: cases per family and exit code");
        let mut total: BTreeMap<String, usize> = BTreeMap::new();
        for (family, by_code) in &self.counts {
            let line: Vec<String> = by_code
                .iter()
                .map(|(c, n)| {
                    *total.entry(c.clone()).or_default() += n;
                    format!("exit {c}: {n}")
                })
                .collect();
            eprintln!("  {family:<8} {}", line.join(", "));
        }
        let line: Vec<String> = total
            .iter()
            .map(|(c, n)| format!("exit {c}: {n}"))
            .collect();
        eprintln!("  {:<8} {}", "all", line.join(", "));
        eprintln!("  slowest case {:.2} s", self.slowest.as_secs_f64());
    }
}

fn seed() -> u64 {
    std::env::var("VIBRISSA_HOSTILE_SEED")
        .ok()
        .and_then(|s| {
            let s = s.trim();
            s.strip_prefix("0x")
                .map_or_else(|| s.parse().ok(), |h| u64::from_str_radix(h, 16).ok())
        })
        .unwrap_or(SEED)
}

fn scale() -> usize {
    std::env::var("VIBRISSA_HOSTILE_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1)
}

#[test]
fn hostile_inputs_end_in_a_class_with_one_line_naming_the_input() {
    let root = tempfile::tempdir().unwrap();
    let fx = fixture(root.path());
    let seed = seed();
    let k = scale();
    let mut rng = Rng(seed);
    let mut cases = Vec::new();
    cases.extend(scene_cases(&mut rng, 60 * k));
    cases.extend(log_cases(&mut rng, &fx, 40 * k));
    cases.extend(stream_cases(&mut rng, &fx, 30 * k));
    cases.extend(flag_cases(&mut rng, 60 * k));
    cases.extend(profile_cases(&mut rng, 45 * k));
    cases.extend(pipe_cases(&fx));
    let report = run_all(&cases, root.path(), &fx, 2);
    report.print(seed);
    assert!(
        report.failures.is_empty(),
        "{} of {} hostile cases failed (seed {seed:#x}; the case folders are kept under {}):\n{}",
        report.failures.len(),
        cases.len(),
        root.keep().display(),
        report.failures.join("\n")
    );
}

/// Four sweeps write one `--out` at once: each ends 0, or 2 refused naming the folder
/// being written; the folder is then whole, the complete output of one of the runs that
/// succeeded (its `scene.ron` names its q), and no staging folder is left.
#[test]
fn concurrent_writers_to_one_out_leave_one_whole_folder() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    let qs = ["3", "4", "5", "6"];
    let children: Vec<_> = qs
        .iter()
        .map(|q| {
            Command::new(bin())
                .args([
                    "sweep",
                    "--profile",
                    "g1",
                    "--q",
                    q,
                    "--points",
                    "8",
                    "--figures",
                    "none",
                    "--out",
                    "shared",
                ])
                .current_dir(dir)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    let mut won = Vec::new();
    for (q, c) in qs.iter().zip(children) {
        let o = c.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        match o.status.code() {
            Some(0) => won.push(*q),
            Some(2) => {
                assert_eq!(err.trim_end().lines().count(), 1, "{err}");
                assert!(err.contains("shared"), "{err}");
            }
            other => panic!("q = {q}: exit {other:?}: {err}"),
        }
    }
    assert!(!won.is_empty(), "no writer succeeded");
    whole_csv(&dir.join("shared/observables.csv")).unwrap();
    let scene = fs::read_to_string(dir.join("shared/scene.ron")).unwrap();
    assert!(
        won.iter().any(|q| scene.contains(&format!("q: {q}.0"))),
        "scene.ron is none of the winners' {won:?}: {scene}"
    );
    for e in fs::read_dir(dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        assert!(!name.contains("staging"), "{name} left behind");
    }
}

// ---------------------------------------------------------------------------------------
// Output folders (issue #34 item 6): each outcome's class (exit code, message, files)
// ---------------------------------------------------------------------------------------

/// A sweep past g1 into `out` (q and points as given, no figures), run in `dir`.
fn sweep_into(dir: &Path, q: &str, points: &str, out: &str) -> Command {
    let mut c = Command::new(bin());
    c.args([
        "sweep",
        "--profile",
        "g1",
        "--q",
        q,
        "--points",
        points,
        "--figures",
        "none",
        "--out",
        out,
    ])
    .current_dir(dir)
    .env_remove("RUST_BACKTRACE");
    c
}

/// Runs `c` to its end: (exit code, stderr).
fn finish(c: &mut Command) -> (Option<i32>, String) {
    let o = c.output().unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Exit 2 and one `error: ` line holding every needle.
fn assert_refused((code, err): &(Option<i32>, String), needles: &[&str]) {
    assert_eq!(*code, Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("error: "), "{err}");
    for n in needles {
        assert!(err.contains(n), "{err:?} lacks {n:?}");
    }
}

/// The names in `dir` that a run leaves beside its output: staging folders, old folders set
/// aside, lock files.
fn leftovers(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".staging-") || n.contains(".old-") || n.ends_with(".lock"))
        .collect();
    v.sort();
    v
}

/// The q a sweep folder's `scene.ron` records.
fn q_of(folder: &Path) -> String {
    let scene = fs::read_to_string(folder.join("scene.ron")).unwrap();
    let at = scene.find("q: ").expect("scene.ron names q");
    scene[at + 3..]
        .split(|c: char| c == ',' || c.is_whitespace())
        .next()
        .unwrap()
        .to_string()
}

/// A symbolic link `--out` is followed: the folder it points to is replaced whole (its stale
/// files gone), the link stays a link to it. A link to nothing or to a file is refused.
#[cfg(unix)]
#[test]
fn a_symlinked_out_is_followed_and_stays_a_link() {
    use std::os::unix::fs::symlink;
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    assert_eq!(finish(&mut sweep_into(dir, "3", "6", "real")).0, Some(0));
    // a stale file of an earlier run, listed in the manifest as if vibrissa wrote it
    let manifest = fs::read_to_string(dir.join("real/.vibrissa-output")).unwrap();
    fs::write(dir.join("real/shapes.csv"), "row,s\n").unwrap();
    fs::write(
        dir.join("real/.vibrissa-output"),
        format!("{manifest}shapes.csv\n"),
    )
    .unwrap();
    symlink("real", dir.join("link")).unwrap();
    let (code, err) = finish(&mut sweep_into(dir, "5", "6", "link"));
    assert_eq!(code, Some(0), "{err}");
    let meta = fs::symlink_metadata(dir.join("link")).unwrap();
    assert!(meta.file_type().is_symlink(), "the link was replaced");
    assert_eq!(fs::read_link(dir.join("link")).unwrap(), Path::new("real"));
    assert_eq!(q_of(&dir.join("real")), "5.0");
    assert!(!dir.join("real/shapes.csv").exists(), "stale output left");
    whole_csv(&dir.join("link/observables.csv")).unwrap();
    assert_eq!(leftovers(dir), Vec::<String>::new());
    // a link to nothing, a link to a file: refused, left as they are
    symlink("nowhere", dir.join("dangling")).unwrap();
    assert_refused(
        &finish(&mut sweep_into(dir, "5", "6", "dangling")),
        &["`dangling` for `--out`", "symbolic link to nowhere"],
    );
    assert!(!dir.join("nowhere").exists());
    fs::write(dir.join("file.txt"), "mine").unwrap();
    symlink("file.txt", dir.join("to-file")).unwrap();
    assert_refused(
        &finish(&mut sweep_into(dir, "5", "6", "to-file")),
        &["`to-file` for `--out`", "not a folder"],
    );
    assert_eq!(fs::read_to_string(dir.join("file.txt")).unwrap(), "mine");
    assert!(fs::symlink_metadata(dir.join("to-file"))
        .unwrap()
        .file_type()
        .is_symlink());
}

/// A folder holding a file vibrissa did not write is refused, naming the file, and nothing
/// in it changes: a user's file added to an earlier output folder (on top or in a
/// subfolder), a user's own folder; an empty folder is used.
#[test]
fn a_folder_with_files_vibrissa_did_not_write_is_refused_naming_one() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    assert_eq!(finish(&mut sweep_into(dir, "3", "6", "d")).0, Some(0));
    fs::write(dir.join("d/notes.txt"), "my notes").unwrap();
    let before = snapshot(&dir.join("d"));
    assert_refused(
        &finish(&mut sweep_into(dir, "5", "6", "d")),
        &["`d` for `--out`", "d/notes.txt", "vibrissa did not write"],
    );
    assert_eq!(snapshot(&dir.join("d")), before, "the folder changed");
    fs::remove_file(dir.join("d/notes.txt")).unwrap();
    fs::create_dir(dir.join("d/mine")).unwrap();
    fs::write(dir.join("d/mine/data.csv"), "1").unwrap();
    assert_refused(&finish(&mut sweep_into(dir, "5", "6", "d")), &["d/mine"]);
    assert_eq!(
        fs::read_to_string(dir.join("d/mine/data.csv")).unwrap(),
        "1"
    );
    fs::remove_dir_all(dir.join("d/mine")).unwrap();
    // nothing foreign left: replaced
    assert_eq!(finish(&mut sweep_into(dir, "5", "6", "d")).0, Some(0));
    assert_eq!(q_of(&dir.join("d")), "5.0");
    // a user's folder (no manifest) with a file: refused; empty: used
    fs::create_dir(dir.join("home")).unwrap();
    fs::write(dir.join("home/thesis.tex"), "\\documentclass").unwrap();
    assert_refused(
        &finish(&mut sweep_into(dir, "5", "6", "home")),
        &["home/thesis.tex"],
    );
    assert!(dir.join("home/thesis.tex").exists());
    fs::create_dir(dir.join("empty")).unwrap();
    assert_eq!(finish(&mut sweep_into(dir, "5", "6", "empty")).0, Some(0));
    whole_csv(&dir.join("empty/observables.csv")).unwrap();
    assert_eq!(leftovers(dir), Vec::<String>::new());
}

/// Waits (at most 60 s) until `path` exists.
fn wait_for(path: &Path) {
    let t0 = Instant::now();
    while !path.exists() {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "{} never came",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// The staging folder of the writer `pid` into `dir/NAME`, once it holds its manifest.
fn staging_of(dir: &Path, name: &str, pid: u32) -> PathBuf {
    let staging = dir.join(format!(".{name}.staging-{pid}"));
    wait_for(&staging.join(".vibrissa-output"));
    staging
}

/// Sends `signal` (`KILL`, `TERM`, `STOP`, `CONT`) to the process `pid`.
fn signal(pid: u32, signal: &str) {
    let sent = Command::new("kill")
        .args([format!("-{signal}"), pid.to_string()])
        .status()
        .unwrap();
    assert!(sent.success(), "kill -{signal} {pid}");
}

/// Two processes into one `--out`: while the first writes (held still by SIGSTOP once its
/// staging folder is there, so that it is surely alive), the second is refused at once with
/// exit 2, "D is being written by another vibrissa process"; the first, let go, ends 0 and
/// its folder is whole; then the second may write.
#[cfg(unix)]
#[test]
fn a_second_live_writer_is_refused_and_the_first_completes() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    let first = sweep_into(dir, "3", "400", "d")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    staging_of(dir, "d", first.id());
    signal(first.id(), "STOP");
    let second = finish(&mut sweep_into(dir, "5", "6", "d"));
    signal(first.id(), "CONT");
    let o = first.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_refused(&second, &["d is being written by another vibrissa process"]);
    assert_eq!(q_of(&dir.join("d")), "3.0");
    whole_csv(&dir.join("d/observables.csv")).unwrap();
    assert_eq!(leftovers(dir), Vec::<String>::new());
    assert_eq!(finish(&mut sweep_into(dir, "5", "6", "d")).0, Some(0));
    assert_eq!(q_of(&dir.join("d")), "5.0");
}

/// A writer killed mid-run (SIGKILL, then SIGTERM: neither lets it clean up) leaves the
/// earlier folder as it was, and its lock file and staging folder; the lock held nothing
/// after its death, so the next run writes at once, removes what was left and replaces the
/// folder.
#[cfg(unix)]
#[test]
fn a_killed_writer_blocks_nothing_and_its_leftovers_go() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    assert_eq!(finish(&mut sweep_into(dir, "3", "6", "d")).0, Some(0));
    let before = snapshot(&dir.join("d"));
    for sig in ["KILL", "TERM"] {
        let mut writer = sweep_into(dir, "5", "100000", "d")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let staging = staging_of(dir, "d", writer.id());
        signal(writer.id(), sig);
        let status = writer.wait().unwrap();
        assert_eq!(status.code(), None, "{sig}: the writer ended on its own");
        // the earlier folder is intact; the killed run's lock file and staging are left
        assert_eq!(snapshot(&dir.join("d")), before, "{sig}: d changed");
        assert!(dir.join(".d.lock").exists() && staging.exists(), "{sig}");
    }
    let t0 = Instant::now();
    let (code, err) = finish(&mut sweep_into(dir, "5", "6", "d"));
    assert_eq!(code, Some(0), "{err}");
    assert!(
        t0.elapsed() < Duration::from_secs(30),
        "the next run waited"
    );
    assert_eq!(q_of(&dir.join("d")), "5.0");
    whole_csv(&dir.join("d/observables.csv")).unwrap();
    assert_eq!(leftovers(dir), Vec::<String>::new());
}

/// A parent folder that cannot be written, and `--out` naming a file: refused (exit 2,
/// naming `--out`), nothing made, nothing changed.
#[cfg(unix)]
#[test]
fn an_unwritable_parent_and_a_file_as_out_are_refused() {
    use std::os::unix::fs::PermissionsExt;
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    fs::write(dir.join("notes.txt"), "mine").unwrap();
    assert_refused(
        &finish(&mut sweep_into(dir, "5", "6", "notes.txt")),
        &["`notes.txt` for `--out`", "not a folder"],
    );
    assert_eq!(fs::read_to_string(dir.join("notes.txt")).unwrap(), "mine");
    // a parent that is a file (refused for root too)
    assert_refused(
        &finish(&mut sweep_into(dir, "5", "6", "notes.txt/d")),
        &[
            "`notes.txt/d` for `--out`",
            "cannot make the folder notes.txt",
        ],
    );
    assert_eq!(fs::read_to_string(dir.join("notes.txt")).unwrap(), "mine");
    let ro = dir.join("ro");
    fs::create_dir(&ro).unwrap();
    assert_eq!(finish(&mut sweep_into(&ro, "3", "6", "d")).0, Some(0));
    let before = snapshot(&ro);
    fs::set_permissions(&ro, fs::Permissions::from_mode(0o555)).unwrap();
    // (root writes anyway: then there is nothing to refuse)
    let writable = fs::write(ro.join("probe"), "").is_ok();
    let r = finish(&mut sweep_into(&ro, "5", "6", "d"));
    let r2 = finish(&mut sweep_into(dir, "5", "6", "ro/new/d"));
    fs::set_permissions(&ro, fs::Permissions::from_mode(0o755)).unwrap();
    if !writable {
        assert_refused(&r, &["`d` for `--out`", "Permission denied"]);
        assert_refused(&r2, &["`ro/new/d` for `--out`", "Permission denied"]);
        assert_eq!(snapshot(&ro), before);
        assert_eq!(leftovers(&ro), Vec::<String>::new());
    }
}

/// `reconstruct --stream` writes to standard output: `--out` with it is refused, naming it,
/// and no folder is made.
#[test]
fn the_stream_refuses_out() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    let r = finish(
        Command::new(bin())
            .args(["reconstruct", "--stream", "--theta", "0.75", "--out", "D"])
            .current_dir(dir)
            .stdin(Stdio::null()),
    );
    assert_refused(&r, &["`D` for `--out`", "--stream"]);
    assert!(!dir.join("D").exists());
}
