//! End-to-end tests of `vibrissa reconstruct`: sweep -> reconstruct round trips, logs written
//! by other programs, and one-line errors that leave no output behind.

use std::fs;
use std::path::Path;
use std::process::Output;

use crate::common;
use common::{
    assert_ok, json, one_line_error, parse, rows_reversed, run, run_stdin, stderr, words,
};

/// A failure: non-zero exit, one line on stderr mentioning every needle, no panic, and no
/// output directory (nor a staging leftover) in `cwd`.
fn assert_fails(o: &Output, needles: &[&str], cwd: &Path) {
    assert!(
        !o.status.success(),
        "expected failure, stderr: {}",
        stderr(o)
    );
    one_line_error(o, needles);
    assert!(!cwd.join("rec").exists(), "no output directory on failure");
    for e in fs::read_dir(cwd).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.contains("staging"), "staging leftover {name}");
    }
}

const WHISKER: [&str; 4] = ["--theta", "0.75", "--k", "20"];
const Q: f64 = 5.0;

/// Sweeps past g1 into `cwd/sw` and returns the observables text.
fn sweep(cwd: &Path) -> String {
    let mut args = vec!["sweep", "--profile", "g1", "--q", "5", "--points", "16"];
    args.extend(WHISKER);
    args.extend(["--out", "sw"]);
    let o = run(&args, cwd);
    assert_ok(&o);
    fs::read_to_string(cwd.join("sw/observables.csv")).unwrap()
}

fn reconstruct(cwd: &Path, log: &str, extra: &[&str]) -> Output {
    let mut args = vec!["reconstruct", log];
    args.extend(WHISKER);
    args.extend(extra);
    run(&args, cwd)
}

fn col(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap()
}

#[test]
fn sweep_reconstruct_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let obs = sweep(cwd);
    let v = json(&reconstruct(
        cwd,
        "sw/observables.csv",
        &["--profile", "g1", "--json", "--out", "rec"],
    ));
    let q = v["q"].as_f64().unwrap();
    assert!((q - Q).abs() < 1e-9, "identified q = {q}");
    assert_eq!(v["q_given"], false);
    assert_eq!(v["method"], "accurate");
    let max_error = v["max_error"].as_f64().unwrap();
    assert!(max_error < 1e-9, "max error {max_error}");

    let (oh, orows) = parse(&obs);
    let rec = fs::read_to_string(cwd.join("rec/reconstruction.csv")).unwrap();
    assert!(
        rec.starts_with("x0,x,y,s1,f,psi,phase,sigma,residual,hypotheses,error\n"),
        "{rec}"
    );
    let (rh, rrows) = parse(&rec);
    // One row per contact row of the input, in order, x0 bit-identical. A row whose contact
    // force is below the log's precision (f = 0 at the first touch, ~1e-12 at a release) is
    // the free whisker within the noise: pre-contact by the model (spec/model.md).
    let (fi, pi, xi) = (col(&oh, "f"), col(&oh, "phase"), col(&oh, "x0"));
    let force = |r: &Vec<String>| r[fi].parse::<f64>().unwrap();
    let contact: Vec<&Vec<String>> = orows
        .iter()
        .filter(|r| r[pi] != "none" && force(r) > 1e-9)
        .collect();
    assert_eq!(rrows.len(), contact.len());
    assert_eq!(v["points"].as_u64().unwrap() as usize, contact.len());
    // Rows are numbered from 1 as in the sweep's text and JSON.
    let first = v["first_contact_row"].as_u64().unwrap() as usize;
    let first_true = orows.iter().position(|r| force(r) > 1e-9).unwrap();
    assert_eq!(first, first_true + 1);
    assert!(v["alpha_deg"].as_f64().unwrap().abs() < 1e-7);
    for (r, o) in rrows.iter().zip(&contact) {
        assert_eq!(r[0], o[xi]);
        let (a, b) = (r[0].parse::<f64>().unwrap(), o[xi].parse::<f64>().unwrap());
        assert_eq!(a.to_bits(), b.to_bits());
        let e = r[col(&rh, "error")].parse::<f64>().unwrap();
        assert!(e < 1e-9, "e = {e}");
        assert!(["A", "B"].contains(&r[col(&rh, "phase")].as_str()));
    }
    let phases = &v["phases"];
    assert_eq!(
        phases["A"].as_u64().unwrap() + phases["B"].as_u64().unwrap(),
        contact.len() as u64
    );
    assert!(cwd.join("rec/reconstruction.svg").exists());
    assert!(cwd.join("rec/error.svg").exists());

    // Without --profile: the exact header and no error figure; q given.
    let v = json(&reconstruct(
        cwd,
        "sw/observables.csv",
        &["--q", "5", "--json", "--out", "rec2"],
    ));
    assert_eq!(v["q_given"], true);
    assert_eq!(v["q"].as_f64().unwrap(), Q);
    assert!(v.get("max_error").is_none());
    let rec2 = fs::read_to_string(cwd.join("rec2/reconstruction.csv")).unwrap();
    assert!(
        rec2.starts_with("x0,x,y,s1,f,psi,phase,sigma,residual,hypotheses\n"),
        "{rec2}"
    );
    assert!(!cwd.join("rec2/error.svg").exists());

    // The human summary.
    let o = reconstruct(cwd, "sw/observables.csv", &["--out", "rec3"]);
    assert_ok(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("q = 5"), "{out}");
}

#[test]
fn logs_of_other_programs() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let obs = sweep(cwd);
    let (h, rows) = parse(&obs);
    let reference = {
        let o = reconstruct(cwd, "sw/observables.csv", &["--out", "ref"]);
        assert_ok(&o);
        fs::read_to_string(cwd.join("ref/reconstruction.csv")).unwrap()
    };
    // Shuffled columns, an extra text column, CRLF line ends.
    let order = ["phi0", "MA", "x0", "Ay", "Ax"];
    let mut text = String::from("phi0,comment,MA,x0,Ay,Ax\r\n");
    for (i, r) in rows.iter().enumerate() {
        let f: Vec<&str> = order.iter().map(|n| r[col(&h, n)].as_str()).collect();
        text.push_str(&format!(
            "{},sample {i},{},{},{},{}\r\n",
            f[0], f[1], f[2], f[3], f[4]
        ));
    }
    fs::write(cwd.join("foreign.csv"), text).unwrap();
    let o = reconstruct(cwd, "foreign.csv", &["--out", "foreign"]);
    assert_ok(&o);
    let got = fs::read_to_string(cwd.join("foreign/reconstruction.csv")).unwrap();
    assert_eq!(got, reference);

    // Only the five required columns.
    let mut text = String::from("x0,Ax,Ay,MA,phi0\n");
    for r in &rows {
        let f: Vec<&str> = ["x0", "Ax", "Ay", "MA", "phi0"]
            .iter()
            .map(|n| r[col(&h, n)].as_str())
            .collect();
        text.push_str(&f.join(","));
        text.push('\n');
    }
    fs::write(cwd.join("five.csv"), text).unwrap();
    let v = json(&reconstruct(cwd, "five.csv", &["--json", "--out", "five"]));
    assert!((v["q"].as_f64().unwrap() - Q).abs() < 1e-9);
    let got = fs::read_to_string(cwd.join("five/reconstruction.csv")).unwrap();
    assert_eq!(got, reference);
}

/// The observables text with the field `column` of the data row at file line `line`
/// (1-based) replaced by `value`.
fn with_cell(obs: &str, line: usize, column: &str, value: &str) -> String {
    let (h, _) = parse(obs);
    let c = col(&h, column);
    obs.lines()
        .enumerate()
        .map(|(i, l)| {
            if i + 1 == line {
                let mut f: Vec<&str> = l.split(',').collect();
                f[c] = value;
                f.join(",")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn bad_logs_fail_with_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let obs = sweep(cwd);
    let (h, _) = parse(&obs);

    // A missing required column.
    let ma = col(&h, "MA");
    let dropped: String = obs
        .lines()
        .map(|l| {
            let f: Vec<&str> = l
                .split(',')
                .enumerate()
                .filter(|(i, _)| *i != ma)
                .map(|(_, f)| f)
                .collect();
            f.join(",") + "\n"
        })
        .collect();
    fs::write(cwd.join("nocol.csv"), dropped).unwrap();
    let o = reconstruct(cwd, "nocol.csv", &["--out", "rec"]);
    assert_fails(&o, &["nocol.csv:1", "MA"], cwd);

    // NaN in a row (a contact row, line 15): file, line and column named.
    fs::write(cwd.join("nan.csv"), with_cell(&obs, 15, "Ay", "NaN")).unwrap();
    let o = reconstruct(cwd, "nan.csv", &["--out", "rec"]);
    assert_fails(&o, &["nan.csv:15", "Ay"], cwd);

    // A non-numeric cell.
    fs::write(cwd.join("text.csv"), with_cell(&obs, 7, "phi0", "abc")).unwrap();
    let o = reconstruct(cwd, "text.csv", &["--out", "rec"]);
    assert_fails(&o, &["text.csv:7", "phi0", "abc"], cwd);

    // Too few rows.
    let two: String = obs.lines().take(2).map(|l| format!("{l}\n")).collect();
    fs::write(cwd.join("short.csv"), two).unwrap();
    let o = reconstruct(cwd, "short.csv", &["--out", "rec"]);
    assert_fails(&o, &["short.csv"], cwd);

    // Only pre-contact rows: no contact to reconstruct.
    let pre: String = obs.lines().take(6).map(|l| format!("{l}\n")).collect();
    fs::write(cwd.join("pre.csv"), pre).unwrap();
    let o = reconstruct(cwd, "pre.csv", &["--out", "rec"]);
    assert_fails(&o, &["pre.csv:6", "no contact"], cwd);

    // A missing file.
    let o = reconstruct(cwd, "absent.csv", &["--out", "rec"]);
    assert_fails(&o, &["absent.csv"], cwd);

    // The wrong whisker: the first contact row is inconsistent, named by its line.
    let o = run(&words("reconstruct sw/observables.csv --out rec"), cwd);
    assert_fails(
        &o,
        &["sw/observables.csv:", "no consistent contact point"],
        cwd,
    );

    // Bad flags.
    let o = reconstruct(
        cwd,
        "sw/observables.csv",
        &["--method", "magic", "--out", "rec"],
    );
    assert_fails(&o, &["--method", "magic"], cwd);
    let o = reconstruct(
        cwd,
        "sw/observables.csv",
        &["--tolerance", "-1", "--out", "rec"],
    );
    assert_fails(&o, &["--tolerance"], cwd);
    let o = reconstruct(cwd, "sw/observables.csv", &["--q", "-2", "--out", "rec"]);
    assert_fails(&o, &["--q"], cwd);
    let o = reconstruct(
        cwd,
        "sw/observables.csv",
        &["--profile", "zz", "--out", "rec"],
    );
    assert_fails(&o, &["--profile"], cwd);
}

/// `--stream`: the log on standard input (reversed, as another sensor order), each contact
/// point on standard output; the same points as the batch reconstruction, flow given or
/// identified from the first free row.
#[test]
fn stream_gives_the_batch_points() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let obs = sweep(cwd);
    let o = reconstruct(cwd, "sw/observables.csv", &["--out", "rec"]);
    assert_ok(&o);
    let batch = fs::read_to_string(cwd.join("rec/reconstruction.csv")).unwrap();
    let (_, brows) = parse(&batch);
    let input = rows_reversed(&obs);
    for extra in [&["--q", "5", "--alpha-deg", "0"][..], &[][..]] {
        let mut args = vec!["reconstruct", "--stream"];
        args.extend(WHISKER);
        args.extend(extra);
        let o = run_stdin(&args, cwd, &input);
        assert_ok(&o);
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(
            text.starts_with("x0,x,y,s1,f,psi,phase,sigma,residual,hypotheses\n"),
            "{text}"
        );
        let (_, srows) = parse(&text);
        assert_eq!(srows.len(), brows.len(), "{extra:?}");
        for s in &srows {
            let b = brows.iter().find(|b| b[0] == s[0]).expect("same x0");
            for k in 1..3 {
                let (x, y) = (s[k].parse::<f64>().unwrap(), b[k].parse::<f64>().unwrap());
                assert!((x - y).abs() < 1e-10, "{extra:?}: {s:?} vs {b:?}");
            }
            assert_eq!(s[6], b[6]);
        }
    }
    // a flow angle out of range is refused, naming the flag
    let o = reconstruct(
        cwd,
        "sw/observables.csv",
        &["--alpha-deg", "95", "--out", "rec4"],
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--alpha-deg"), "{}", stderr(&o));
    assert!(!cwd.join("rec4").exists());
}
