//! Calibration battery (issue 19).

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, Profile, SweepSettings};
use profile_recon::calibrate::{calibrate, CalibLog, CalibParam, CalibSettings};
use profile_recon::{from_sweep, KnownFlow};

fn log_of(w: &Whisker, flow: FluidLoad, profile: &Profile, points: usize) -> CalibLog {
    let settings = SweepSettings {
        points,
        ..Default::default()
    };
    let res = sweep(w, flow, profile, &settings).unwrap();
    CalibLog {
        rows: from_sweep(&res),
        profile: profile.clone(),
        flow: KnownFlow::default(),
    }
}

#[test]
fn smoke_exact_log() {
    let truth = Whisker::new(0.6, 0.5, 0.3, 20.0);
    let flow = FluidLoad { q: 2.0, alpha: 0.2 };
    let log = log_of(&truth, flow, &Profile::g2(), 40);
    let start = Whisker::new(0.8, 0.3, 0.2, 30.0);
    let t = std::time::Instant::now();
    let cal = calibrate(&start, &[log], &CalibSettings::default()).unwrap();
    eprintln!("{:?}", t.elapsed());
    eprintln!("{:#?}", cal.parameters);
    eprintln!("{:?} {:?} noise {} log {} it {} ev {}", cal.logs, cal.warnings, cal.noise_level, cal.log_noise, cal.iterations, cal.evaluations);
    eprintln!("starts {:?}", cal.starts);
    let th = cal.parameter(CalibParam::Theta).unwrap().value.unwrap();
    assert!((th - 0.6).abs() < 1e-7);
}
