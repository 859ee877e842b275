//! `vibrissa reconstruct` on logs of any base motion (issue 38, item 3): a whisking log
//! against a peg (written from contact-sim's rotation with its pose columns `y0`, `gamma`)
//! gives the peg from every contact row, in the file, the JSON and the stream; `calibrate`
//! fits the whisker and the flow from it (`wcal`). Truth: the peg the log was swept against.
//!
//! `cargo test -p vibrissa-cli --test it -- wrec`

use crate::common;

use std::fs;

use beam_model::{FluidLoad, Whisker};
use common::{assert_ok, col, json, parse, rows_reversed, run, run_stdin, stderr};
use contact_sim::{sweep, BaseMotion, Profile, SweepSettings};

const PEG: (f64, f64) = (-0.25, 0.55);
const WHISKER: [&str; 8] = ["--theta", "0.8", "--a", "0.2", "--b", "0.1", "--k", "30"];

/// Whisks the whisker of [`WHISKER`] under a slanted flow about the base (0.05, -0.1) from
/// gamma0 = -0.1 against [`PEG`]; returns the log as CSV with the pose columns (every value
/// written to round trip exactly).
fn whisking_log() -> String {
    let w = Whisker::new(0.8, 0.2, 0.1, 30.0);
    let flow = FluidLoad {
        q: 1.0,
        alpha: 10f64.to_radians(),
    };
    let settings = SweepSettings {
        points: 30,
        motion: BaseMotion::Rotate {
            x0: 0.05,
            y0: -0.1,
            gamma0: -0.1,
        },
        ..SweepSettings::default()
    };
    let peg = Profile::Peg { x: PEG.0, y: PEG.1 };
    let res = sweep(&w, flow, &peg, &settings).expect("the whisker meets the peg");
    assert!(res.contact_points().count() >= 30);
    let mut s = String::from("x0,Ax,Ay,MA,phi0,y0,gamma\n");
    for p in &res.points {
        s += &format!(
            "{},{},{},{},{},{},{}\n",
            p.x0, p.ax, p.ay, p.ma, p.phi0, p.y0, p.gamma
        );
    }
    s
}

#[test]
fn wrec_a_whisking_log_gives_the_peg_in_the_file_the_json_and_the_stream() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let log = whisking_log();
    fs::write(cwd.join("whisk.csv"), &log).unwrap();
    let peg = format!("peg:{},{}", PEG.0, PEG.1);
    let mut args = vec!["reconstruct", "whisk.csv"];
    args.extend(WHISKER);
    args.extend(["--profile", &peg, "--json", "--out", "rec"]);
    let v = json(&run(&args, cwd));
    let o = &v["obstacle"];
    assert_eq!(o["kind"], "peg", "{v}");
    let (x, y) = (o["x"].as_f64().unwrap(), o["y"].as_f64().unwrap());
    assert!(
        (x - PEG.0).abs() < 1e-10 && (y - PEG.1).abs() < 1e-10,
        "{o}"
    );
    assert!(o["spread"].as_f64().unwrap() < 1e-9, "{o}");
    // every contact row of the file is the peg; its error column the distance to it
    let text = fs::read_to_string(cwd.join("rec/reconstruction.csv")).unwrap();
    let (h, rows) = parse(&text);
    assert!(rows.len() >= 30);
    let (cx, cy, ce) = (col(&h, "x"), col(&h, "y"), col(&h, "error"));
    for r in &rows {
        let (px, py): (f64, f64) = (r[cx].parse().unwrap(), r[cy].parse().unwrap());
        assert!((px - PEG.0).hypot(py - PEG.1) < 1e-9, "{r:?}");
        assert!(r[ce].parse::<f64>().unwrap() < 1e-9, "{r:?}");
        assert_eq!(r[0], "0.05", "x0 copied");
    }
    // without a profile the points are still one peg
    let mut args = vec!["reconstruct", "whisk.csv"];
    args.extend(WHISKER);
    args.extend(["--json", "--out", "rec2"]);
    let v = json(&run(&args, cwd));
    assert_eq!(v["obstacle"]["kind"], "peg", "{v}");
    // the stream, rows reversed: the same points
    let input = rows_reversed(&log);
    let mut args = vec!["reconstruct", "--stream"];
    args.extend(WHISKER);
    let o = run_stdin(&args, cwd, &input);
    assert_ok(&o);
    let (sh, srows) = parse(&String::from_utf8_lossy(&o.stdout));
    assert_eq!(srows.len(), rows.len());
    let (sx, sy) = (col(&sh, "x"), col(&sh, "y"));
    for r in &srows {
        let (px, py): (f64, f64) = (r[sx].parse().unwrap(), r[sy].parse().unwrap());
        assert!((px - PEG.0).hypot(py - PEG.1) < 1e-9, "{r:?}");
    }
}

/// `calibrate` on the whisking log (issue 38, item 3; docs/whisking-recon.md, "Calibration
/// from whisking logs"): from the default start (theta 1, A = B = 0) with the flow unknown,
/// the whisker of [`WHISKER`] and the flow (1, 10 degrees) to 1e-7, written to the
/// calibrated scene.ron; a non-finite pose is refused by line and column.
#[test]
fn wcal_calibrate_fits_a_whisking_log() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::write(cwd.join("whisk.csv"), whisking_log()).unwrap();
    let peg = format!("peg:{},{}", PEG.0, PEG.1);
    let o = run(
        &[
            "calibrate",
            "whisk.csv",
            "--profile",
            &peg,
            "--theta",
            "1",
            "--json",
            "--out",
            "cal",
        ],
        cwd,
    );
    assert_ok(&o);
    let v = json(&o);
    let p = &v["parameters"];
    for (name, truth) in [("theta", 0.8), ("a", 0.2), ("b", 0.1), ("k", 30.0)] {
        let est = p[name]["value"].as_f64().unwrap();
        assert!(
            (est - truth).abs() < 1e-7 * f64::max(truth, 1.0),
            "{name}: {est}"
        );
    }
    let log = &v["logs"][0];
    assert!((log["q"].as_f64().unwrap() - 1.0).abs() < 1e-7, "{log}");
    assert!(
        (log["alpha_deg"].as_f64().unwrap() - 10.0).abs() < 1e-5,
        "{log}"
    );
    // the calibrated scene holds the fitted values
    let ron = fs::read_to_string(cwd.join("cal/scene.ron")).unwrap();
    let value = |key: &str| -> f64 {
        let at = ron
            .find(&format!("{key}:"))
            .unwrap_or_else(|| panic!("{key} in {ron}"));
        let rest = ron[at + key.len() + 1..].trim_start();
        let rest = rest.strip_prefix("Some(").unwrap_or(rest);
        let end = rest.find([',', ')', '\n', ' ']).unwrap();
        rest[..end]
            .parse()
            .unwrap_or_else(|_| panic!("{key}: {rest}"))
    };
    assert!((value("theta") - 0.8).abs() < 1e-7, "{ron}");
    assert!((value("k") - 30.0).abs() < 1e-6, "{ron}");
    // a pose that is not a number: its line and column
    let mut lines: Vec<String> = whisking_log().lines().map(String::from).collect();
    let mut cells: Vec<String> = lines[3].split(',').map(String::from).collect();
    cells[6] = "inf".into();
    lines[3] = cells.join(",");
    fs::write(cwd.join("bad.csv"), lines.join("\n") + "\n").unwrap();
    let o = run(&["calibrate", "bad.csv", "--profile", &peg], cwd);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("bad.csv:4") && e.contains("gamma"), "{e}");
    assert_eq!(e.trim().lines().count(), 1, "{e}");
}
