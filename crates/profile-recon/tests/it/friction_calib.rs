//! Calibration of frictional logs (issue 39, item 4; spec/model.md "Friction at the
//! contact"): `calibrate --fit ...,mu` on contact-sim's frictional sweeps past known contours.
//! The truth is the whisker and the `mu` the sweeps were made with; the calibration sees the
//! base observables alone (no `ft`, no `slip` column).

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, ContactLaw, Profile, SlipState, SweepResult, SweepSettings};
use profile_recon::calibrate::{calibrate, CalibLog, CalibParam, CalibSettings, Calibration};
use profile_recon::{from_sweep, KnownFlow};

/// A frictional sweep of `points` contact rows.
fn frictional(
    w: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    mu: f64,
    points: usize,
) -> SweepResult {
    let s = SweepSettings {
        points,
        contact_law: ContactLaw::Coulomb { mu },
        ..SweepSettings::default()
    };
    sweep(w, flow, profile, &s).expect("the frictional sweep")
}

fn log_of(res: &SweepResult, profile: &Profile) -> CalibLog {
    CalibLog {
        rows: from_sweep(res),
        profile: profile.clone(),
        flow: KnownFlow::default(),
        poses: Vec::new(),
    }
}

fn fit_all() -> Vec<CalibParam> {
    vec![
        CalibParam::Theta,
        CalibParam::A,
        CalibParam::B,
        CalibParam::K,
        CalibParam::Mu,
    ]
}

fn value(cal: &Calibration, p: CalibParam) -> (Option<f64>, Option<f64>) {
    let e = cal.parameter(p).expect("a fitted parameter");
    (e.value, e.stderr)
}

/// The sliding scene (tip contact sliding from the touch, contact-sim's accuracy scene).
#[test]
fn an_exact_sliding_log_gives_mu() {
    let truth = Whisker::new(0.5, 0.0, 0.0, 10.0);
    let flow = FluidLoad { q: 1.0, alpha: 0.2 };
    let profile = Profile::parse("circle:0.3,1.5,0.6").unwrap();
    let res = frictional(&truth, flow, &profile, 0.4, 40);
    let slides = res
        .points
        .iter()
        .filter(|p| p.slip == SlipState::Slip)
        .count();
    let logs = [log_of(&res, &profile)];
    let start = Whisker::new(0.6, 0.1, -0.1, 15.0);
    let settings = CalibSettings {
        fit: fit_all(),
        ..Default::default()
    };
    let cal = calibrate(&start, &logs, &settings).unwrap();
    let (mu, se) = value(&cal, CalibParam::Mu);
    eprintln!(
        "sliding: {slides} sliding rows in the truth; mu {mu:?} +- {se:?}, theta {:?}, k {:?}, warnings {:?}",
        value(&cal, CalibParam::Theta),
        value(&cal, CalibParam::K),
        cal.warnings
    );
    assert!((mu.unwrap() - 0.4).abs() < 1e-8);
}
