//! A whisker calibrated from a log of a sweep past a known object, through the facade
//! `vibrissa` (and the layers it re-exports) alone.
//!
//! ```sh
//! cargo run --release --example calibrate_whisker [SCENE.ron]
//! ```
//!
//! The scene (default `scenes/c5-tapered-precurved-elastic-g1.ron`: theta 0.75, pre-curvature
//! A = -1, B = -0.5 [3.5], follicle spring k = 20 [3.21], past the contour g1 under q = 5,
//! dimensionless) plays the experiment: it is swept and its log written as `vibrissa sweep`
//! writes it (`observables.csv`, [`vibrissa::io::write_observables`]); the log is read back
//! ([`vibrissa::io::read_observables`]) and the whisker's own parameters theta, A, B, k are
//! fitted to it from a start 10-60 % off, knowing only the object's contour (the scene's
//! profile) and not the flow ([`vibrissa::profile_recon::calibrate::calibrate`]).
//!
//! The check is against the truth the calibration never sees (the scene's whisker): every
//! parameter within 1e-6 of it (an exact log: the fit reaches the integrator's floor), the
//! flow within 1e-6 of the scene's q. Each estimate is printed with its standard error. A
//! failed check prints one line on stderr and exits with 1.

// `!(error <= tolerance)` on purpose: a NaN fails every check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::error::Error;
use std::process::ExitCode;
use std::time::Instant;

use vibrissa::beam_model::Whisker;
use vibrissa::contact_sim::Profile;
use vibrissa::profile_recon::calibrate::{calibrate, CalibLog, CalibParam, CalibSettings};
use vibrissa::profile_recon::{KnownFlow, ObservableRow};
use vibrissa::{Scene, Units};

/// The scene swept when none is given.
pub const DEFAULT_SCENE: &str = "scenes/c5-tapered-precurved-elastic-g1.ron";

/// Largest error of a fitted parameter accepted on an exact log.
const TOLERANCE: f64 = 1e-6;

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

/// Sweeps `path` (the experiment), writes and reads back its log, calibrates from a start
/// off the truth and checks the fit against the truth.
fn run(path: &str) -> Result<(), Box<dyn Error>> {
    let scene = Scene::load(path)?;
    if scene.spec.units != Units::Dimensionless {
        return Err(format!("{path}: this example calibrates dimensionless logs").into());
    }
    let spec = scene
        .spec
        .profile
        .clone()
        .ok_or("the scene names no object (profile)")?;
    let object = Profile::parse(&spec)?;
    let w = &scene.spec.whisker;
    let truth = Whisker::new(w.theta, w.a, w.b, w.k.unwrap_or(f64::INFINITY));

    // The experiment: a sweep past the known object, its log on disk and read back.
    let dir = std::env::temp_dir().join(format!("vibrissa-calibrate-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let log_path = dir.join("observables.csv");
    vibrissa::io::write_observables(&scene.sweep()?, &log_path)?;
    let log = vibrissa::io::read_observables(&log_path);
    std::fs::remove_dir_all(&dir)?;
    let log = log?;
    let column = |name: &str| log.column(name).ok_or(format!("no column {name}"));
    let (x0, ax, ay, ma, phi0) = (
        column("x0")?,
        column("Ax")?,
        column("Ay")?,
        column("MA")?,
        column("phi0")?,
    );
    let rows: Vec<ObservableRow> = (0..log.len())
        .map(|i| ObservableRow {
            x0: x0[i],
            ax: ax[i],
            ay: ay[i],
            ma: ma[i],
            phi0: phi0[i],
        })
        .collect();
    println!(
        "log: {} rows past `{spec}` read back from {}",
        rows.len(),
        log_path.display()
    );

    // The calibration: theta, A, B, k from a start 10-60 % off; the flow unknown.
    let k_start = if truth.support.stiffness().is_finite() {
        1.4 * truth.support.stiffness()
    } else {
        50.0
    };
    let start = Whisker::new(
        (0.75 * truth.theta).max(0.05),
        0.7 * truth.a + 0.3,
        0.7 * truth.b - 0.2,
        k_start,
    );
    let logs = [CalibLog {
        rows,
        profile: object,
        flow: KnownFlow::default(),
        poses: Vec::new(),
    }];
    let settings = CalibSettings {
        fit: vec![
            CalibParam::Theta,
            CalibParam::A,
            CalibParam::B,
            CalibParam::K,
        ],
        ..CalibSettings::default()
    };
    let t = Instant::now();
    let cal = calibrate(&start, &logs, &settings)?;
    println!(
        "calibrated in {:.2} s ({} residual evaluations, {} local fits); rms distance of the \
         contact points to the object {:.2e}",
        t.elapsed().as_secs_f64(),
        cal.evaluations,
        cal.fits.len(),
        cal.rms_distance
    );
    let truth_of = |p: CalibParam| match p {
        CalibParam::Theta => truth.theta,
        CalibParam::A => truth.a,
        CalibParam::B => truth.b,
        CalibParam::K => truth.support.stiffness(),
        CalibParam::Ei => 1.0,
        // the logs above are frictionless
        CalibParam::Mu => 0.0,
    };
    let mut worst = (0.0f64, "");
    for e in &cal.parameters {
        let value = e
            .value
            .ok_or(format!("{} not identifiable", e.param.name()))?;
        let stderr = e.stderr.unwrap_or(f64::NAN);
        let err = (value - truth_of(e.param)).abs();
        println!(
            "  {:>5} = {value:+.10} ± {stderr:.1e}  (start {:+.4}, truth {:+.4}, error {err:.1e})",
            e.param.name(),
            e.start,
            truth_of(e.param)
        );
        if !(err <= worst.0) {
            worst = (err, e.param.name());
        }
    }
    let q_true = scene.spec.loads.q;
    let dq = (cal.logs[0].q - q_true).abs();
    println!(
        "  flow: q = {:.10} (truth {q_true}, error {dq:.1e}); warnings: {}",
        cal.logs[0].q,
        if cal.warnings.is_empty() {
            "none".to_string()
        } else {
            cal.warnings.join("; ")
        }
    );
    if !(worst.0 <= TOLERANCE) {
        return Err(format!("{} off the truth by {:e}", worst.1, worst.0).into());
    }
    if !(dq <= TOLERANCE) {
        return Err(format!("q off the truth by {dq:e}").into());
    }
    println!("checks passed: every parameter within {TOLERANCE:e} of the truth");
    Ok(())
}

#[test]
fn example_checks_pass() {
    run(DEFAULT_SCENE).expect("the example's checks");
}
