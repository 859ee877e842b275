//! A sweep's log reconstructed as a batch, then streamed row by row as a sensor sends it,
//! through the facade `vibrissa` (and the layers it re-exports) alone.
//!
//! ```sh
//! cargo run --release --example reconstruct_log [SCENE.ron]
//! ```
//!
//! 1. The scene (default `scenes/c5-tapered-precurved-elastic-g1.ron`: a tapered,
//!    pre-curved whisker on a spring past the contour g1 under q = 5, dimensionless) is swept
//!    and its log written as `vibrissa sweep` writes it (`observables.csv` and its units
//!    sidecar, [`vibrissa::io::write_observables`]) into a temporary folder.
//! 2. The file is read back ([`vibrissa::io::read_observables`]) and reconstructed as a
//!    batch ([`vibrissa::Scene::reconstruct`]): the flow identified from the rows before
//!    contact [6.1], then each contact row's point by integrating the elastica from the
//!    logged base observables [6.5-6.9].
//! 3. The same file is streamed line by line into
//!    [`vibrissa::profile_recon::Streamer`]: each contact point is printed as soon as its
//!    row arrives (the flow is fixed by the first free row).
//!
//! The checks, each against something the reconstruction did not compute: every point
//! (batch and stream) lies on the sweep's own contact point `(xc, yc)` (the forward problem
//! solved the contact; the reconstruction only sees the base), the identified `q` is the
//! scene's, and the stream gives the batch's rows. A failed check prints one line on stderr
//! and exits with 1.

// `!(error <= tolerance)` on purpose: a NaN fails every check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::error::Error;
use std::io::{BufRead, BufReader};
use std::process::ExitCode;
use std::time::Instant;

use vibrissa::beam_model::Whisker;
use vibrissa::profile_recon::{KnownFlow, ObservableRow, ReconSettings, Streamer};
use vibrissa::reconstruct::CONSISTENCY_TOLERANCE;
use vibrissa::{Scene, Units};

/// The scene swept when none is given.
pub const DEFAULT_SCENE: &str = "scenes/c5-tapered-precurved-elastic-g1.ron";

/// Largest distance (whisker lengths) of a reconstructed point to the sweep's contact point
/// accepted: the sweep's rows and the reconstruction are each accurate to ~1e-10.
const TOLERANCE: f64 = 1e-8;

fn main() -> ExitCode {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| DEFAULT_SCENE.into());
    match run(&path) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Sweeps `path`, writes its log, reconstructs it as a batch and as a stream, and checks
/// both against the sweep's contact points.
fn run(path: &str) -> Result<(), Box<dyn Error>> {
    let scene = Scene::load(path)?;
    if scene.spec.units != Units::Dimensionless {
        return Err(format!(
            "{path}: this example streams dimensionless logs (see physical_sweep for units)"
        )
        .into());
    }
    let sweep = scene.sweep()?;
    let dir = std::env::temp_dir().join(format!("vibrissa-reconstruct-log-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let log_path = dir.join("observables.csv");
    vibrissa::io::write_observables(&sweep, &log_path)?;
    let result = check(&scene, &sweep, &log_path);
    std::fs::remove_dir_all(&dir)?;
    result
}

fn check(
    scene: &Scene,
    sweep: &vibrissa::Sweep,
    log_path: &std::path::Path,
) -> Result<(), Box<dyn Error>> {
    let rows = sweep.rows();
    let contact = rows.iter().filter(|r| r.xc.is_finite()).count();
    println!(
        "swept: {} rows ({contact} in contact) written to {}",
        rows.len(),
        log_path.display()
    );

    // The batch: the file read back, the flow identified, every contact row's point.
    let log = vibrissa::io::read_observables(log_path)?;
    let t = Instant::now();
    let batch = scene.reconstruct(&log)?;
    let batch_ms = t.elapsed().as_secs_f64() * 1e3;
    let q_true = scene.spec.loads.q;
    let dq = (batch.q - q_true).abs();
    let mut worst_batch = (0.0f64, 0usize);
    for p in &batch.rows {
        let i = rows
            .iter()
            .position(|r| r.x0 == p.x0)
            .ok_or_else(|| format!("batch point at x0 = {} names no row of the log", p.x0))?;
        let d = (p.x - rows[i].xc).hypot(p.y - rows[i].yc);
        if !(d <= worst_batch.0) {
            worst_batch = (d, i + 1);
        }
    }
    println!(
        "batch: q = {:.15} identified (scene {q_true}, error {dq:.1e}), {} points in {batch_ms:.1} ms; \
         worst distance to the sweep's contact point {:.2e} (row {})",
        batch.q,
        batch.rows.len(),
        worst_batch.0,
        worst_batch.1
    );

    // The stream: the same file, line by line, each row pushed as it is read.
    let w = &scene.spec.whisker;
    let whisker = Whisker::new(w.theta, w.a, w.b, w.k.unwrap_or(f64::INFINITY));
    let settings = ReconSettings {
        consistency_tol: Some(CONSISTENCY_TOLERANCE),
        ..ReconSettings::default()
    };
    let mut stream = Streamer::new(&whisker, KnownFlow::default(), &settings)?;
    let mut lines = BufReader::new(std::fs::File::open(log_path)?).lines();
    let header: Vec<String> = lines
        .next()
        .ok_or("empty log")??
        .split(',')
        .map(str::to_string)
        .collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format!("the log has no column {name}"))
    };
    let cols = [col("x0")?, col("Ax")?, col("Ay")?, col("MA")?, col("phi0")?];
    let (mut points, mut pushed, mut busy) = (Vec::new(), 0usize, 0.0f64);
    for line in lines {
        let line = line?;
        let cells: Vec<&str> = line.split(',').collect();
        let v = |k: usize| -> Result<f64, Box<dyn Error>> {
            let cell = cells.get(cols[k]).ok_or("short line")?;
            Ok(cell.parse::<f64>().map_err(|e| format!("`{cell}`: {e}"))?)
        };
        let row = ObservableRow {
            x0: v(0)?,
            ax: v(1)?,
            ay: v(2)?,
            ma: v(3)?,
            phi0: v(4)?,
        };
        let t = Instant::now();
        let out = stream.push(row)?;
        busy += t.elapsed().as_secs_f64();
        pushed += 1;
        for p in out {
            if points.len() % 40 == 0 {
                println!(
                    "  stream: row {:>3} -> contact point ({:+.10}, {:+.10}), phase {:?}",
                    p.row + 1,
                    p.x,
                    p.y,
                    p.phase
                );
            }
            points.push(p);
        }
    }
    points.extend(stream.finish()?);
    let mut worst_stream = (0.0f64, 0usize);
    let mut worst_vs_batch = 0.0f64;
    for p in &points {
        let r = rows.get(p.row).ok_or("a stream point names no row")?;
        let d = (p.x - r.xc).hypot(p.y - r.yc);
        if !(d <= worst_stream.0) {
            worst_stream = (d, p.row + 1);
        }
        let b = batch
            .rows
            .iter()
            .find(|b| b.x0 == r.x0)
            .ok_or_else(|| format!("row {}: a stream point the batch has not", p.row + 1))?;
        worst_vs_batch = worst_vs_batch.max((p.x - b.x).hypot(p.y - b.y));
    }
    println!(
        "stream: {pushed} rows pushed, {} points, {:.1} µs a row; worst distance to the sweep's \
         contact point {:.2e} (row {}), to the batch's point {worst_vs_batch:.2e}",
        points.len(),
        busy / pushed.max(1) as f64 * 1e6,
        worst_stream.0,
        worst_stream.1
    );

    if !(dq <= 1e-9 * q_true.max(1.0)) {
        return Err(format!("q identified {} is not the scene's {q_true}", batch.q).into());
    }
    if batch.rows.len() + 2 < contact || points.len() != batch.rows.len() {
        return Err(format!(
            "{contact} contact rows, {} batch points, {} stream points",
            batch.rows.len(),
            points.len()
        )
        .into());
    }
    for (name, (d, row)) in [("batch", worst_batch), ("stream", worst_stream)] {
        if !(d <= TOLERANCE) {
            return Err(format!("{name} point of row {row} off the contact point by {d:e}").into());
        }
    }
    println!("checks passed: every point within {TOLERANCE:e} of the sweep's contact point");
    Ok(())
}

#[test]
fn example_checks_pass() {
    run(DEFAULT_SCENE).expect("the example's checks");
}
