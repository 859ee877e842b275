//! Outputs a researcher can trust: no command writes over a file it reads, killed runs leave
//! nothing behind for long, and the messages of the stream and of incomplete scenes name the
//! user's own input (each test failed on the code before it).

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use crate::common;
use common::{assert_ok, one_line_error, run, run_stdin, scenes_dir, stderr, words};

/// Exit 2 with one line holding every needle.
fn refused(o: &Output, needles: &[&str]) {
    assert_eq!(o.status.code(), Some(2), "{}", stderr(o));
    one_line_error(o, needles);
}

fn sweep_folder(cwd: &Path, name: &str, extra: &[&str]) {
    let mut args = vec!["sweep", "--profile", "g1", "--q", "5", "--points", "8"];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--out", name]);
    let o = run(&args, cwd);
    assert_ok(&o);
}

#[test]
fn sweep_and_solve_refuse_an_out_folder_holding_their_scene() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    sweep_folder(cwd, "d", &[]);
    let before = fs::read(cwd.join("d/scene.ron")).unwrap();
    let o = run(&words("sweep d/scene.ron --out d"), cwd);
    refused(&o, &["--out", "scene file being read", "d/scene.ron"]);
    let o = run(&words("solve d/scene.ron --out d"), cwd);
    refused(&o, &["--out", "scene file being read"]);
    assert_eq!(fs::read(cwd.join("d/scene.ron")).unwrap(), before);
    // a contour table inside the output folder is an input too
    fs::create_dir(cwd.join("t")).unwrap();
    let mut table = String::from("x,y\n");
    for i in 0..=40 {
        let x = -2.0 + 0.1 * i as f64;
        table += &format!("{x},{}\n", (x / 2.0).cosh() - 0.8);
    }
    fs::write(cwd.join("t/post.csv"), table).unwrap();
    fs::write(cwd.join("t/.vibrissa-output"), "written by vibrissa\n").unwrap();
    let o = run(
        &words("sweep --profile points:t/post.csv --q 5 --out t"),
        cwd,
    );
    refused(&o, &["contour table being read"]);
    assert!(cwd.join("t/post.csv").exists());
}

#[test]
fn out_dash_is_refused_not_a_folder_named_dash() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    for args in [
        vec!["sweep", "--profile", "g1", "--out", "-"],
        vec!["solve", "--out", "-"],
    ] {
        let o = run(&args, cwd);
        refused(&o, &["`-` for `--out`", "standard output"]);
    }
    assert!(!cwd.join("-").exists());
}

/// What a killed run leaves (its lock file, its staging folder holding the manifest, the
/// earlier folder set aside) is removed by the next run; a folder of the same pattern that
/// is not ours (no manifest) stays.
#[test]
fn a_killed_runs_staging_folder_is_removed_by_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let stale = cwd.join(".d.staging-4194304");
    fs::create_dir(&stale).unwrap();
    fs::write(stale.join("observables.csv"), "half written").unwrap();
    fs::write(stale.join(".vibrissa-output"), "# vibrissa output folder\n").unwrap();
    let aside = cwd.join(".d.old-4194304");
    fs::create_dir(&aside).unwrap();
    fs::write(aside.join(".vibrissa-output"), "# vibrissa output folder\n").unwrap();
    let not_ours = cwd.join(".d.staging-mine");
    fs::create_dir(&not_ours).unwrap();
    fs::write(not_ours.join("notes.txt"), "mine").unwrap();
    fs::write(cwd.join(".d.lock"), "").unwrap();
    sweep_folder(cwd, "d", &[]);
    assert!(!stale.exists(), "the stale staging folder is still there");
    assert!(!aside.exists(), "the old folder set aside is still there");
    assert!(!cwd.join(".d.lock").exists());
    let mut left: Vec<String> = fs::read_dir(cwd)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, vec![".d.staging-mine".to_string(), "d".to_string()]);
    assert_eq!(
        fs::read_to_string(not_ours.join("notes.txt")).unwrap(),
        "mine"
    );
}

#[test]
fn scene_files_with_a_byte_order_mark_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let text = fs::read_to_string(scenes_dir().join("c1-uniform-rigid-g1.ron")).unwrap();
    fs::write(cwd.join("bom.ron"), format!("\u{feff}{text}")).unwrap();
    let o = run(&words("solve bom.ron --json"), cwd);
    assert_ok(&o);
}

#[test]
fn a_sweep_without_obstacle_says_what_to_add_not_an_empty_flag_value() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::write(cwd.join("w.ron"), "(whisker: (theta: 0.5))").unwrap();
    let o = run(&words("sweep w.ron --out x"), cwd);
    refused(&o, &["w.ron:1:", "no obstacle", "profile"]);
    assert!(!stderr(&o).contains("invalid value ``"));
    let o = run(&words("sweep --out x"), cwd);
    refused(&o, &["a sweep needs an obstacle: give --profile"]);
    assert!(!stderr(&o).contains("invalid value ``"));
}

#[test]
fn the_stream_reads_a_folder_scene_physical_units_and_checks_rows_as_files() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let scene = scenes_dir().join("physical-beta-g1.ron");
    let o = run(
        &[
            "sweep",
            scene.to_str().unwrap(),
            "--points",
            "12",
            "--out",
            "pb",
        ],
        cwd,
    );
    assert_ok(&o);
    let log = fs::read_to_string(cwd.join("pb/observables.csv")).unwrap();
    // `reconstruct DIR --stream`: the folder's scene, the log in mm and N read as such
    let o = run_stdin(
        &words("reconstruct pb --stream --q 0.003 --alpha-deg 0"),
        cwd,
        &log,
    );
    assert_ok(&o);
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    let rows: Vec<Vec<f64>> = out
        .lines()
        .skip(1)
        .map(|l| l.split(',').filter_map(|c| c.parse().ok()).collect())
        .collect();
    let contact = log
        .lines()
        .filter(|l| l.contains(",A,") || l.contains(",B,"))
        .count();
    assert!(rows.len() + 2 >= contact && !rows.is_empty(), "{out}");
    // the contact points are in mm: near the contour g1 scaled by L = 66.2 mm
    for r in &rows {
        let (x, y) = (r[1] / 66.2, r[2] / 66.2);
        assert!((y - ((x / 2.0).cosh() - 0.8)).abs() < 1e-8, "{r:?}");
    }
    // rows are checked as in a file
    let o = run_stdin(
        &words("reconstruct --stream"),
        cwd,
        "x0,Ax,Ay,MA,phi0\n1,2,3\n",
    );
    refused(&o, &["<stdin>:2:", "3 fields where the header has 5"]);
    let o = run_stdin(
        &words("reconstruct --stream"),
        cwd,
        "x0,Ax,Ay,MA,phi0\n1,2,3,4,5,6\n",
    );
    refused(&o, &["<stdin>:2:", "6 fields where the header has 5"]);
    let o = run_stdin(&words("reconstruct --stream"), cwd, "");
    refused(&o, &["standard input is empty"]);
}

/// `--figures` chooses the figure files (default SVG only: a sweep folder was 92 % PNG).
#[test]
fn figures_are_written_as_figures_says() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let count = |name: &str, ext: &str| {
        fs::read_dir(cwd.join(name))
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .path()
                    .extension()
                    .is_some_and(|x| x == ext)
            })
            .count()
    };
    sweep_folder(cwd, "default", &[]);
    assert_eq!((count("default", "svg"), count("default", "png")), (3, 0));
    sweep_folder(cwd, "none", &["--figures", "none"]);
    assert_eq!((count("none", "svg"), count("none", "png")), (0, 0));
    sweep_folder(cwd, "png", &["--figures", "png"]);
    assert_eq!((count("png", "svg"), count("png", "png")), (0, 3));
    sweep_folder(cwd, "all", &["--figures", "all"]);
    assert_eq!((count("all", "svg"), count("all", "png")), (3, 3));
    // the CSVs are the same whatever the figures
    assert_eq!(
        fs::read(cwd.join("none/observables.csv")).unwrap(),
        fs::read(cwd.join("all/observables.csv")).unwrap()
    );
    let o = run(&words("sweep --profile g1 --figures gif --out x"), cwd);
    refused(&o, &["gif", "--figures"]);
}

/// `sweep --help` lists only what a sweep uses: no tip force, load kind, method or grid.
#[test]
fn sweep_help_lists_only_what_a_sweep_uses() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&words("sweep --help"), dir.path());
    let help = String::from_utf8_lossy(&o.stdout).into_owned();
    for flag in [
        "--theta",
        "--k",
        "--q",
        "--alpha-deg",
        "--profile",
        "--points",
        "--figures",
    ] {
        assert!(help.contains(flag), "sweep --help lacks {flag}");
    }
    for flag in ["--f ", "--beta-deg", "--load", "--method", "--n "] {
        assert!(!help.contains(flag), "sweep --help lists {flag}");
    }
    let o = run(&words("sweep --profile g1 --f 1 --out x"), dir.path());
    refused(&o, &["--f"]);
}

/// Every row of a log is accounted for: the rows without contact force (before contact, the
/// touch and the release with f = 0) and the contact points add up to the rows, in the text
/// and in JSON (before: "rows 12-132 reconstructed: 120 points").
#[test]
fn reconstruct_accounts_for_every_row() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let o = run(&words("sweep --profile g1 --q 5 --points 20 --out sw"), cwd);
    assert_ok(&o);
    let o = run(&words("reconstruct sw --out rec"), cwd);
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    // 32 rows: 10 before contact, the touch, 20 requested + 2 events - the release row
    assert!(
        text.contains("32 rows: 12 without contact force")
            && text.contains("rows 1-11, 32)")
            && text.contains("20 contact points (rows 12-31;"),
        "{text}"
    );
    let o = run(&words("reconstruct sw --json --out rec2"), cwd);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["rows_without_force"], "1-11, 32");
    assert_eq!(v["points"], 20);
    let csv = fs::read_to_string(cwd.join("rec/reconstruction.csv")).unwrap();
    assert_eq!(csv.lines().count(), 21);
}

/// A physical scene that never touches says which lengths its numbers are in and names the
/// contour as the user gave it (in mm), with exit code 3.
#[test]
fn no_contact_in_a_physical_scene_names_its_units() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    fs::write(
        cwd.join("nc.ron"),
        "(units: Physical(preset: \"beta\"), whisker: (theta: 0.75), loads: (q: 0.003), \
         profile: Some(\"circle:0,200,40\"))",
    )
    .unwrap();
    let o = run(&words("sweep nc.ron --out x"), cwd);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("66.2 mm") && e.contains("`circle:0,200,40` as given"),
        "{e}"
    );
}

/// An output folder that cannot be written is reported against `--out`, not as a bare
/// lock-file path.
#[test]
fn an_unwritable_out_names_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&words("solve --out /proc/vibrissa-x"), dir.path());
    refused(
        &o,
        &[
            "for `--out`",
            "/proc/vibrissa-x",
            "cannot write an output folder there",
        ],
    );
}

/// `--shapes` writes the whisker's shape at every row; checked against the log it came with:
/// each shape starts at its row's base position, a tip contact ends at its contact point, and
/// no shape enters the obstacle (y <= g1(x)).
#[test]
fn shapes_csv_holds_every_rows_shape() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let o = run(
        &words("sweep --profile g1 --q 5 --theta 0.75 --k 20 --points 10 --shapes --out s"),
        cwd,
    );
    assert_ok(&o);
    let read = |name: &str| -> (Vec<String>, Vec<Vec<String>>) {
        let text = fs::read_to_string(cwd.join("s").join(name)).unwrap();
        let mut lines = text
            .lines()
            .map(|l| l.split(',').map(str::to_string).collect());
        (lines.next().unwrap(), lines.collect())
    };
    let (oh, obs) = read("observables.csv");
    let (sh, shapes) = read("shapes.csv");
    assert_eq!(sh, ["row", "s", "x", "y", "phi"]);
    let c = |h: &[String], n: &str| h.iter().position(|x| x == n).unwrap();
    let num = |s: &str| s.parse::<f64>().unwrap();
    for (i, row) in obs.iter().enumerate() {
        let pts: Vec<&Vec<String>> = shapes
            .iter()
            .filter(|r| num(&r[0]) as usize == i + 1)
            .collect();
        assert!(pts.len() >= 101, "row {}", i + 1);
        let s_last = num(&pts[pts.len() - 1][1]);
        assert!(
            (s_last - 1.0).abs() < 1e-12,
            "row {} ends at s = {s_last}",
            i + 1
        );
        let x0 = num(&row[c(&oh, "x0")]);
        assert!((num(&pts[0][2]) - x0).abs() < 1e-12 && num(&pts[0][3]).abs() < 1e-12);
        for p in &pts {
            let (x, y) = (num(&p[2]), num(&p[3]));
            assert!(
                y - ((x / 2.0).cosh() - 0.8) < 1e-8,
                "row {} enters g1 at x = {x}",
                i + 1
            );
        }
        if row[c(&oh, "phase")] == "A" {
            let tip = pts[pts.len() - 1];
            let (xc, yc) = (num(&row[c(&oh, "xc")]), num(&row[c(&oh, "yc")]));
            assert!(
                (num(&tip[2]) - xc).hypot(num(&tip[3]) - yc) < 1e-8,
                "row {}",
                i + 1
            );
        }
    }
}

/// `--method accurate` whose FDM fallback fails too says so under the method the user
/// asked for (it used to begin with `fdm:`, a method never asked for), exits 1 and writes
/// nothing.
#[test]
fn a_failed_accurate_solve_names_accurate_and_its_fallback() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&words("solve --theta 0.08812507096023038 --a 0.9399390342644347 --b 0.8892168273742458 --f 8.834783312984172 --beta-deg 72.94519898236268 --q 14.894809679784851 --alpha-deg -69.4456837754382 --k 0.23624894898551355 --out s"),
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(
        e.starts_with("error: accurate (fdm-richardson fallback): "),
        "{e}"
    );
    assert!(!dir.path().join("s").exists());
}

/// `--tol T` asks for the cheapest method that meets T: a weak flow is answered by the
/// spectral Picard iteration within T of `accurate`, the scene records the request, and
/// a --tol with another method or out of range names the flag.
#[test]
fn tol_picks_the_cheapest_method_that_meets_it() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let json = |args: &[&str]| -> serde_json::Value {
        let o = run(args, cwd);
        assert_ok(&o);
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let flow = [
        "--theta",
        "0.5",
        "--k",
        "10",
        "--q",
        "0.5",
        "--figures",
        "none",
    ];
    let base = |out: &str, extra: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = ["solve", "--json", "--out", out].map(String::from).to_vec();
        v.extend(flow.iter().map(|s| s.to_string()));
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let reference = json(
        &base("r", &[])
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    for tol in [1e-4, 1e-8] {
        let t = format!("{tol:e}");
        let args = base(&format!("t{t}"), &["--tol", &t]);
        let v = json(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(v["stats"]["method_used"], "picard", "{v}");
        // linear theory's bound does not reach 1e-4 at q = 0.5: the elastica's iteration
        assert_eq!(v["stats"]["model_used"], "elastica", "{v}");
        assert_eq!(v["stats"]["tolerance"].as_f64(), Some(tol));
        for (part, key) in [("tip", "x"), ("tip", "y"), ("base", "MA"), ("base", "phi0")] {
            let (a, b) = (
                v[part][key].as_f64().unwrap(),
                reference[part][key].as_f64().unwrap(),
            );
            assert!((a - b).abs() <= tol, "{part}.{key}: {a} vs {b} at {tol:e}");
        }
        let scene = fs::read_to_string(cwd.join(format!("t{t}/scene.ron"))).unwrap();
        assert!(
            scene.contains("name: \"auto\"") && scene.contains("tol: Some("),
            "{scene}"
        );
    }
    let o = run(&words("solve --q 0.5 --tol 1e-4 --method fdm"), cwd);
    refused(&o, &["--tol", "auto", "fdm"]);
    let o = run(&words("solve --q 0.5 --tol 1e-20"), cwd);
    refused(&o, &["--tol", "[1e-12, 1e-2]"]);
}

/// The elastica figure draws its loads (it showed none): the tip force and the flow as
/// arrows explained in the legend, on a print-size canvas.
#[test]
fn the_elastica_figure_draws_its_loads() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(
        &words("solve --f 2 --beta-deg 30 --q 3 --alpha-deg 20 --out e"),
        dir.path(),
    );
    assert_ok(&o);
    let svg = fs::read_to_string(dir.path().join("e/elastica.svg")).unwrap();
    for needle in ["tip force f", "flow q", "width=\"85mm\""] {
        assert!(svg.contains(needle), "elastica.svg lacks {needle}");
    }
    // One filled arrow head per arrow: the tip force and four flow arrows (+ the legend's
    // two samples).
    let heads = svg.matches(" Z\" fill=\"#").count();
    assert!(heads >= 7, "{heads} arrow heads");
}

/// Where no thread can be started (every stack refused: `RUST_MIN_STACK` of 1 TiB), the
/// commands still answer, in line, with the same files: the helper threads of the sweep
/// (second-contact checks, half the rows), of the figures and of the flushes are an
/// optimisation, not a requirement (this panicked before: "failed to spawn thread").
#[test]
fn no_thread_to_start_is_no_error() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let sweep: Vec<&str> = "sweep --profile g1 --q 5 --points 40 --out"
        .split(' ')
        .collect();
    let plain = run(&[&sweep[..], &["plain"]].concat(), dir);
    assert_ok(&plain);
    let lone = Command::new(env!("CARGO_BIN_EXE_vibrissa"))
        .args([&sweep[..], &["lone"]].concat())
        .current_dir(dir)
        .env("RUST_MIN_STACK", "1099511627776")
        .output()
        .expect("the binary runs");
    assert_ok(&lone);
    for name in ["observables.csv", "shapes.svg", "observables.svg"] {
        let (a, b) = (dir.join("plain").join(name), dir.join("lone").join(name));
        assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap(), "{name}");
    }
}
