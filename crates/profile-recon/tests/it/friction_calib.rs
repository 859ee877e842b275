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
    let fr = cal.friction.expect("the contact law of a fit with mu");
    assert!(fr.sliding_rows >= slides / 2, "{fr:?}");
    assert_eq!(fr.cone_violations, 0);
    for (p, t) in [
        (CalibParam::Theta, truth.theta),
        (CalibParam::A, truth.a),
        (CalibParam::B, truth.b),
    ] {
        assert!((value(&cal, p).0.unwrap() - t).abs() < 1e-7, "{p:?}");
    }
    let k = value(&cal, CalibParam::K).0.unwrap();
    assert!((1.0 / k - 0.1).abs() < 1e-7, "{k}");
}

/// Phase B with friction: g1 under q = 5 (theta 0.75, k 20, mu 0.5; frec's stream scene).
#[test]
fn an_exact_tangential_log_gives_mu() {
    let truth = Whisker::new(0.75, 0.0, 0.0, 20.0);
    let flow = FluidLoad { q: 5.0, alpha: 0.0 };
    let profile = Profile::g1();
    let res = frictional(&truth, flow, &profile, 0.5, 30);
    let phases: String = res.points.iter().map(|p| p.phase.letter()).collect();
    let slips: String = res
        .points
        .iter()
        .map(|p| match p.slip {
            SlipState::Slip => 's',
            SlipState::Stick => 't',
            _ => '-',
        })
        .collect();
    let logs = [log_of(&res, &profile)];
    let start = Whisker::new(0.7, 0.05, -0.05, 25.0);
    let settings = CalibSettings {
        fit: fit_all(),
        ..Default::default()
    };
    let cal = calibrate(&start, &logs, &settings).unwrap();
    let (mu, se) = value(&cal, CalibParam::Mu);
    eprintln!(
        "g1: phases {phases}, slip {slips}; mu {mu:?} +- {se:?}, theta {:?}, {:?}, warnings {:?}",
        value(&cal, CalibParam::Theta),
        cal.friction,
        cal.warnings
    );
    assert!((mu.unwrap() - 0.5).abs() < 1e-8);
    assert!((value(&cal, CalibParam::Theta).0.unwrap() - 0.75).abs() < 1e-7);
}

/// A tip pinned by mu = 10 (contact-sim's pinned-tip scene): no row slides, so mu is not
/// identifiable: no value, the verdict says so with the stick rows' lower bound; the shape
/// parameters are still found.
#[test]
fn a_log_without_sliding_leaves_mu_unidentifiable() {
    let truth = Whisker::new(0.3, 1.0, 0.5, f64::INFINITY);
    let flow = FluidLoad { q: 0.5, alpha: 0.0 };
    let profile = Profile::g2();
    let res = frictional(&truth, flow, &profile, 10.0, 12);
    assert!(res.points.iter().all(|p| p.slip != SlipState::Slip));
    let logs = [log_of(&res, &profile)];
    let settings = CalibSettings {
        fit: vec![CalibParam::A, CalibParam::B, CalibParam::Mu],
        ..Default::default()
    };
    let start = Whisker::new(0.3, 0.8, 0.4, f64::INFINITY);
    let cal = calibrate(&start, &logs, &settings).unwrap();
    let e = cal.parameter(CalibParam::Mu).unwrap();
    eprintln!("pinned: {e:?} {:?} {:?}", cal.friction, cal.warnings);
    assert!(
        !e.identifiable && e.value.is_none() && e.stderr.is_none(),
        "{e:?}"
    );
    let fr = cal.friction.unwrap();
    assert_eq!(fr.sliding_rows, 0);
    assert!(cal
        .warnings
        .iter()
        .any(|w| w.starts_with("mu is not identifiable")));
    // the truth's largest |ft| / fn over the contact rows is the lower bound's reference
    let truth_ratio = res
        .points
        .iter()
        .filter(|p| p.f > 1e-3)
        .map(|p| p.ft.abs() / p.f)
        .fold(0.0, f64::max);
    assert!(
        (fr.stick_ratio - truth_ratio).abs() < 1e-6 * truth_ratio.max(1.0),
        "{} vs {truth_ratio}",
        fr.stick_ratio
    );
    assert!((value(&cal, CalibParam::A).0.unwrap() - 1.0).abs() < 1e-7);
}

/// Without `mu` in the fit: a sliding log is calibrated as a frictionless one and warned
/// about; the same scene at mu = 0 is not.
#[test]
fn a_frictionless_fit_of_a_frictional_log_warns() {
    let truth = Whisker::new(0.5, 0.0, 0.0, 10.0);
    let flow = FluidLoad { q: 1.0, alpha: 0.2 };
    let profile = Profile::parse("circle:0.3,1.5,0.6").unwrap();
    let settings = CalibSettings {
        fit: vec![CalibParam::Theta, CalibParam::K],
        ..Default::default()
    };
    let start = Whisker::new(0.6, 0.0, 0.0, 15.0);
    for mu in [0.0, 0.4] {
        let res = frictional(&truth, flow, &profile, mu, 30);
        let cal = calibrate(&start, &[log_of(&res, &profile)], &settings).unwrap();
        let warned = cal.warnings.iter().any(|w| w.contains("prove friction"));
        eprintln!("mu {mu}: {:?}", cal.warnings);
        assert_eq!(warned, mu > 0.0, "{:?}", cal.warnings);
        assert!(cal.friction.is_none());
    }
}

// ---------------------------------------------------------------------------------------
// The seeded battery (issue 39 items 4-5 for calibration)
// ---------------------------------------------------------------------------------------

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// One scene of the battery: the truth, its flow, the contour and mu.
#[derive(Clone, Debug)]
struct Scene {
    truth: Whisker,
    flow: FluidLoad,
    profile: Profile,
    mu: f64,
}

/// Scene `i` of the seeded battery: whiskers from slender (theta 0.3) to uniform, pre-curved
/// (|A|, |B| <= 0.4), rigid or on springs (k 5..40); flows at angles (q 0..3, alpha
/// -0.5..0.5); the thesis's graphs g1, g2, parabolas and circles (both graphs); mu from 0 to
/// 1.5 (every sixth scene frictionless, mu = 0 exactly).
fn scene(i: u64) -> Scene {
    let mut rng = StdRng::seed_from_u64(0x000f_ca1c ^ (i * 7919));
    let theta = rng.gen_range(0.3..1.0);
    let a = rng.gen_range(-0.4..0.4);
    let b = rng.gen_range(-0.4..0.4);
    let k = if rng.gen_bool(0.3) {
        f64::INFINITY
    } else {
        rng.gen_range(5.0..40.0)
    };
    let flow = FluidLoad {
        q: rng.gen_range(0.0..3.0),
        alpha: rng.gen_range(-0.5..0.5),
    };
    let profile = match i % 4 {
        0 => Profile::g1(),
        1 => Profile::g2(),
        2 => Profile::parse(&format!(
            "parabola:{},{},{}",
            rng.gen_range(0.8..3.0),
            rng.gen_range(-0.2..0.2),
            rng.gen_range(0.55..0.8)
        ))
        .unwrap(),
        _ => Profile::parse(&format!(
            "circle:{},{},{}",
            rng.gen_range(-0.1..0.4),
            rng.gen_range(1.2..1.6),
            rng.gen_range(0.5..0.8)
        ))
        .unwrap(),
    };
    let mu = if i % 6 == 5 {
        0.0
    } else {
        rng.gen_range(0.0..1.5)
    };
    Scene {
        truth: Whisker::new(theta, a, b, k),
        flow,
        profile,
        mu,
    }
}

/// What one calibration of a scene gave.
#[derive(Clone, Debug)]
struct Outcome {
    /// Contact rows of the truth that slide with a force (what makes mu identifiable).
    truth_sliding: usize,
    /// The fitted mu and its standard error (None: not identifiable).
    mu: Option<(f64, f64)>,
    /// The largest error of theta, A, B, 1/k relative to max(1, |value|), and in standard
    /// errors.
    worst_shape: f64,
    worst_shape_se: f64,
}

/// Calibrates scene `s` (its sweep of 30 contact rows, noised at `noise` with `seed`) from
/// the CLI's default start (theta 1, A = B = 0, rigid) fitting theta, A, B, k, mu; None when
/// contact-sim does not sweep the scene or the whisker never touches.
fn run(s: &Scene, noise: f64, seed: u64) -> Option<Outcome> {
    let set = SweepSettings {
        points: 30,
        contact_law: ContactLaw::Coulomb { mu: s.mu },
        ..SweepSettings::default()
    };
    let res = sweep(&s.truth, s.flow, &s.profile, &set).ok()?;
    let fmax = res.points.iter().map(|p| p.f).fold(0.0, f64::max);
    let truth_sliding = res
        .points
        .iter()
        .filter(|p| p.slip == SlipState::Slip && p.f > 1e-3 * fmax)
        .count();
    if res.points.iter().filter(|p| p.f > 1e-3 * fmax).count() < 8 {
        return None;
    }
    let mut log = log_of(&res, &s.profile);
    if noise > 0.0 {
        log.rows = profile_recon::add_noise(&log.rows, noise, seed);
    }
    let settings = CalibSettings {
        fit: fit_all(),
        ..Default::default()
    };
    let cal = calibrate(&Whisker::uniform(), &[log], &settings).ok()?;
    let mu = cal
        .parameter(CalibParam::Mu)
        .and_then(|p| p.value.zip(p.stderr));
    let (mut worst_shape, mut worst_shape_se) = (0.0f64, 0.0f64);
    for p in &cal.parameters {
        let (Some(v), Some(sd)) = (p.value, p.stderr) else {
            continue;
        };
        let (err, se) = match p.param {
            CalibParam::Theta => (v - s.truth.theta, sd),
            CalibParam::A => (v - s.truth.a, sd),
            CalibParam::B => (v - s.truth.b, sd),
            CalibParam::K => (
                1.0 / v - s.truth.support.compliance(),
                if v.is_finite() { sd / (v * v) } else { sd },
            ),
            _ => continue,
        };
        worst_shape = worst_shape.max(err.abs());
        worst_shape_se = worst_shape_se.max(err.abs() / se.max(1e-300));
    }
    Some(Outcome {
        truth_sliding,
        mu,
        worst_shape,
        worst_shape_se,
    })
}

/// The battery over scenes `0..n`: exact logs (mu within 1e-8 where rows slide, never a
/// number where none does; theta, A, B, 1/k within 1e-7) and logs noised at 1e-4 (mu within
/// 3 standard errors). Returns (swept, exact passes, noisy within 3 se, noisy with mu).
fn battery(n: u64, noisy_draws: u64) -> (usize, usize, usize, usize) {
    let (mut swept, mut exact_ok, mut within, mut with_mu) = (0, 0, 0, 0);
    let (mut worst_mu, mut worst_mu_at) = (0.0f64, 0u64);
    let (mut worst_shape, mut worst_shape_at) = (0.0f64, 0u64);
    let (mut worst_z, mut worst_z_at) = (0.0f64, (0u64, 0u64));
    let mut misses = Vec::new();
    for i in 0..n {
        let s = scene(i);
        let Some(o) = run(&s, 0.0, 0) else {
            eprintln!("scene {i}: not swept ({:?})", s);
            continue;
        };
        swept += 1;
        let mu_ok = match (o.truth_sliding, o.mu) {
            (0, None) => true,
            (_, Some((v, _))) => {
                let e = (v - s.mu).abs();
                if e > worst_mu {
                    (worst_mu, worst_mu_at) = (e, i);
                }
                e < 1e-8
            }
            (_, None) => false,
        };
        if o.worst_shape > worst_shape {
            (worst_shape, worst_shape_at) = (o.worst_shape, i);
        }
        let ok = mu_ok && o.worst_shape < 1e-7;
        if ok {
            exact_ok += 1;
        } else {
            misses.push(format!("scene {i} exact: {o:?} truth mu {} ({s:?})", s.mu));
        }
        for d in 0..noisy_draws {
            let Some(on) = run(&s, 1e-4, 1000 * i + d) else {
                continue;
            };
            if let Some((v, se)) = on.mu {
                with_mu += 1;
                let z = (v - s.mu).abs() / se.max(1e-300);
                if z > worst_z {
                    (worst_z, worst_z_at) = (z, (i, d));
                }
                if z <= 3.0 {
                    within += 1;
                } else {
                    misses.push(format!(
                        "scene {i} draw {d} noise 1e-4: mu {v} +- {se:.2e} vs {} ({z:.1} se), {} truth sliding rows, shape {:.1} se",
                        s.mu, on.truth_sliding, on.worst_shape_se
                    ));
                }
            }
        }
    }
    eprintln!(
        "friction calibration battery: {n} scenes, {swept} swept; exact {exact_ok}/{swept} \
         (worst mu error {worst_mu:.1e} at scene {worst_mu_at}, worst shape error \
         {worst_shape:.1e} at scene {worst_shape_at}); noise 1e-4: {within}/{with_mu} with \
         mu within 3 se (worst {worst_z:.2} se at scene/draw {worst_z_at:?})"
    );
    for m in &misses {
        eprintln!("  {m}");
    }
    (swept, exact_ok, within, with_mu)
}

/// The suite's subset: four scenes (one of each contour kind), exact and one noisy draw.
#[test]
fn battery_subset() {
    let (swept, exact_ok, within, with_mu) = battery(4, 1);
    assert!(swept >= 3, "{swept}");
    assert_eq!(exact_ok, swept);
    assert!(within * 10 >= with_mu * 9, "{within}/{with_mu}");
}

/// The full battery: `cargo test -p profile-recon --test it -- friction_calib::battery_full
/// --ignored --nocapture` (docs/friction-calib.md).
#[test]
#[ignore]
fn battery_full() {
    let n = std::env::var("FCAL_SCENES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(60);
    let (swept, exact_ok, within, with_mu) = battery(n, 3);
    assert!(exact_ok * 10 >= swept * 9, "{exact_ok}/{swept}");
    assert!(within * 10 >= with_mu * 9, "{within}/{with_mu}");
}
