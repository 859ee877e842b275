//! Calibration (issue 19): whiskers drawn at random (theta 0.05..1, A, B in +-2, k 5..rigid),
//! swept past known contours by contact-sim, calibrated from a start off by up to 50 %.
//!
//! - `exact_*`: exact logs give every fitted parameter to 1e-7 (relative to `max(|value|,
//!   1)`; `k` through its compliance `1/k`), and the calibrated whisker reconstructs a second,
//!   unknown contour as well as the true one;
//! - `noisy_*`: relative noise 1e-4 and 1e-3: the truth within 3 standard errors for at
//!   least 95 % of the (case, parameter) pairs; standard errors shrinking as 1/sqrt(rows);
//! - a log of the free whisker only is refused (theta, A, B need contact), but gives `k`
//!   alone; three contact rows are not taken for the flow's, one free row is recognised;
//! - `design_*`: the predicted standard errors of the design advice against a fit.
//!
//! The default tests take ~5 s (`cargo test -p profile-recon --test it -- calibrate::`); the big
//! battery is ignored: `cargo test --release -p profile-recon --test it -- calibrate::
//! --ignored --nocapture` (about 60 s in release on the 2-core machine).

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, Phase, Profile, SweepResult, SweepSettings};
use profile_recon::calibrate::{
    calibrate, design, CalibLog, CalibParam, CalibSettings, Calibration, DesignSettings,
};
use profile_recon::{
    add_noise, contour_error, from_sweep, reconstruct, KnownFlow, ReconError, ReconSettings,
};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// A random calibration case.
#[derive(Clone, Debug)]
struct Case {
    truth: Whisker,
    flow: FluidLoad,
    profile: (String, Profile),
}

fn random_profile(rng: &mut StdRng) -> (String, Profile) {
    match rng.gen_range(0..5) {
        0 => ("g1".into(), Profile::g1()),
        1 => ("g2".into(), Profile::g2()),
        2 => ("ge".into(), Profile::ge()),
        3 => {
            let a = rng.gen_range(0.5..3.0);
            let xv = rng.gen_range(-0.6..0.2);
            let yv = rng.gen_range(0.4..0.8);
            (
                format!("parabola:{a:.3},{xv:.3},{yv:.3}"),
                Profile::Parabola { a, xv, yv },
            )
        }
        _ => {
            let r = rng.gen_range(0.3..0.8);
            let xc = rng.gen_range(-0.5..0.0);
            let yc = rng.gen_range(0.5..0.8) + r;
            (
                format!("circle:{xc:.3},{yc:.3},{r:.3}"),
                Profile::Circle { xc, yc, r },
            )
        }
    }
}

fn random_case(rng: &mut StdRng, i: usize) -> Case {
    let theta = if i % 8 == 5 {
        0.05
    } else {
        rng.gen_range(0.1..=1.0)
    };
    let a = rng.gen_range(-2.0..2.0);
    let b = rng.gen_range(-2.0..2.0);
    let k = if rng.gen_bool(0.3) {
        f64::INFINITY
    } else {
        rng.gen_range(5.0..50.0)
    };
    let q = rng.gen_range(0.5..5.0);
    let alpha = rng.gen_range(-40.0f64..40.0).to_radians();
    Case {
        truth: Whisker::new(theta, a, b, k),
        flow: FluidLoad { q, alpha },
        profile: random_profile(rng),
    }
}

/// The sweep of a case and its log (`None` if the sweep failed or has fewer than 8 contact
/// rows).
fn sweep_of(case: &Case, points: usize) -> Option<(SweepResult, CalibLog)> {
    let settings = SweepSettings {
        points,
        ..Default::default()
    };
    let res = sweep(&case.truth, case.flow, &case.profile.1, &settings).ok()?;
    // at least a handful of contact rows
    let log = (res.contact_points().count() >= 8).then(|| CalibLog {
        rows: from_sweep(&res),
        profile: case.profile.1.clone(),
        flow: KnownFlow::default(),
        poses: Vec::new(),
    })?;
    Some((res, log))
}

fn log_of(case: &Case, points: usize) -> Option<CalibLog> {
    sweep_of(case, points).map(|s| s.1)
}

/// A start off by up to 50 % in every parameter (an absolute 0.25 for A, B near 0; a
/// rigid truth starts at k = 50).
fn wrong_start(truth: &Whisker, rng: &mut StdRng) -> Whisker {
    let mut u = [0.0; 6];
    u.iter_mut().for_each(|v| *v = rng.gen_range(-0.5..0.5));
    let theta = (truth.theta * (1.0 + u[0])).clamp(0.02, 1.0);
    let a = truth.a * (1.0 + u[1]) + 0.5 * u[4];
    let b = truth.b * (1.0 + u[2]) + 0.5 * u[5];
    let k = match truth.support.stiffness() {
        k if k.is_finite() => k * (1.0 + u[3]),
        _ => 50.0,
    };
    Whisker::new(theta, a, b, k)
}

/// `(estimate - truth, stderr)` of each fitted parameter, `k` as its compliance.
fn errors(cal: &Calibration, truth: &Whisker) -> Vec<(CalibParam, f64, f64)> {
    cal.parameters
        .iter()
        .filter(|p| p.identifiable)
        .map(|p| {
            let v = p.value.unwrap_or(f64::NAN);
            let sd = p.stderr.unwrap_or(f64::NAN);
            match p.param {
                CalibParam::Theta => (p.param, v - truth.theta, sd),
                CalibParam::A => (p.param, v - truth.a, sd),
                CalibParam::B => (p.param, v - truth.b, sd),
                CalibParam::K => (
                    p.param,
                    1.0 / v - truth.support.compliance(),
                    if v.is_finite() { sd / (v * v) } else { sd },
                ),
                CalibParam::Ei => (p.param, v - 1.0, sd),
                // frictionless logs: mu = 0
                CalibParam::Mu => (p.param, v, sd),
            }
        })
        .collect()
}

fn relative(p: CalibParam, err: f64, truth: &Whisker) -> f64 {
    let v = match p {
        CalibParam::Theta => truth.theta,
        CalibParam::A => truth.a,
        CalibParam::B => truth.b,
        CalibParam::K => truth.support.compliance(),
        CalibParam::Ei | CalibParam::Mu => 1.0,
    };
    err.abs() / v.abs().max(1.0)
}

/// Calibrates a case from a wrong start on its exact log: `None` if the sweep itself failed,
/// else the calibration and, if a parameter is off by more than 1e-7, what is wrong (with
/// whether the calibration warned about it).
fn exact_case(
    case: &Case,
    points: usize,
    rng: &mut StdRng,
) -> Option<(Calibration, Option<(String, bool)>)> {
    let log = log_of(case, points)?;
    let start = wrong_start(&case.truth, rng);
    let cal = calibrate(&start, &[log], &CalibSettings::default())
        .unwrap_or_else(|e| panic!("{case:?} from {start:?}: {e}"));
    let mut bad = None;
    for (p, e, _) in errors(&cal, &case.truth) {
        let rel = relative(p, e, &case.truth);
        if (rel.is_nan() || rel >= 1e-7) && bad.is_none() {
            bad = Some((
                format!("{case:?} from {start:?}: {} off by {rel:.2e}", p.name()),
                !cal.warnings.is_empty(),
            ));
        }
    }
    if !cal.parameters.iter().all(|p| p.identifiable) && bad.is_none() {
        bad = Some((
            format!("{case:?}: {:?}", cal.parameters),
            !cal.warnings.is_empty(),
        ));
    }
    Some((cal, bad))
}

#[test]
fn exact_logs_give_the_truth_and_reconstruct_an_unknown_contour() {
    let mut rng = StdRng::seed_from_u64(1901);
    let cases = [
        Case {
            truth: Whisker::new(0.6, 0.5, 0.3, 20.0),
            flow: FluidLoad { q: 2.0, alpha: 0.2 },
            profile: ("g2".into(), Profile::g2()),
        },
        Case {
            truth: Whisker::new(0.3, -1.2, 0.8, f64::INFINITY),
            flow: FluidLoad {
                q: 1.0,
                alpha: -0.4,
            },
            profile: (
                "circle".into(),
                Profile::Circle {
                    xc: -0.3,
                    yc: 1.4,
                    r: 0.6,
                },
            ),
        },
        Case {
            truth: Whisker::new(0.2, 0.5, -0.3, 8.0),
            flow: FluidLoad { q: 2.0, alpha: 0.0 },
            profile: ("g2".into(), Profile::g2()),
        },
    ];
    for case in &cases {
        let (cal, bad) = exact_case(case, 40, &mut rng).expect("sweep");
        assert!(bad.is_none(), "{bad:?}");
        // a second contour, unknown: reconstructed with the calibrated whisker as with the true
        let other = Profile::Parabola {
            a: 1.5,
            xv: -0.2,
            yv: 0.55,
        };
        let settings = SweepSettings {
            points: 30,
            ..Default::default()
        };
        let Ok(res) = sweep(&case.truth, case.flow, &other, &settings) else {
            continue;
        };
        let rows = from_sweep(&res);
        let rs = ReconSettings::default();
        let with_cal = reconstruct(&cal.whisker, &rows, None, &rs).unwrap();
        let with_truth = reconstruct(&case.truth, &rows, None, &rs).unwrap();
        let max = |e: Vec<f64>| e.into_iter().fold(0.0, f64::max);
        let (ec, et) = (
            max(contour_error(&with_cal.points, &other)),
            max(contour_error(&with_truth.points, &other)),
        );
        assert!(
            ec < 1e-7 && ec < et + 1e-7,
            "{case:?}: calibrated {ec:.2e}, true {et:.2e}"
        );
    }
}

/// The seeded cases of the noisy battery at relative noise `level`, in order: `f(i, case,
/// noisy log, start, sweep)` for each, returning whether the calibration counted, until `n`
/// counted.
fn noisy_cases(
    n: usize,
    level: f64,
    points: usize,
    seed: u64,
    mut f: impl FnMut(usize, &Case, CalibLog, Whisker, &SweepResult) -> bool,
) {
    let mut rng = StdRng::seed_from_u64(seed);
    let (mut cases, mut i) = (0, 0);
    while cases < n && i < 10 * n {
        i += 1;
        let case = random_case(&mut rng, i);
        if case.truth.theta < 0.1 && level > 1e-4 {
            // slender tips at noise 1e-3 are beyond the base integration (README)
            continue;
        }
        let Some((res, mut log)) = sweep_of(&case, points) else {
            continue;
        };
        log.rows = add_noise(&log.rows, level, 1000 + i as u64);
        let start = wrong_start(&case.truth, &mut rng);
        cases += usize::from(f(i, &case, log, start, &res));
    }
}

/// (Case, parameter) pairs within 3 standard errors, pairs with an estimate, pairs asked
/// for, and cases, over `n` random cases at relative noise `level`.
fn noisy_battery(n: usize, level: f64, points: usize, seed: u64) -> [usize; 4] {
    let (mut within, mut total, mut asked, mut cases, mut flagged) = (0, 0, 0, 0, 0);
    noisy_cases(n, level, points, seed, |i, case, log, start, _| {
        let Ok(cal) = calibrate(&start, &[log], &CalibSettings::default()) else {
            return false;
        };
        cases += 1;
        asked += cal.parameters.len();
        flagged += usize::from(!cal.warnings.is_empty());
        for (p, e, sd) in errors(&cal, &case.truth) {
            total += 1;
            if e.abs() <= 3.0 * sd {
                within += 1;
            } else {
                eprintln!(
                    "noise {level:e}, case {i} ({}): {} off by {e:.3e} = {:.1} stderr; {:?}",
                    case.profile.0,
                    p.name(),
                    e / sd,
                    cal.warnings
                );
            }
        }
        true
    });
    eprintln!("noise {level:e}: {flagged} of {cases} calibrations came with a warning");
    [within, total, asked, cases]
}

#[test]
fn noisy_logs_truth_within_three_standard_errors() {
    // a small sample (the battery measures the rates: 157/160 at both levels)
    for (level, share) in [(1e-4, 0.9), (1e-3, 0.8)] {
        let [within, total, _, cases] = noisy_battery(6, level, 40, 77);
        eprintln!("noise {level:e}: {within}/{total} within 3 stderr over {cases} cases");
        assert!(cases >= 5);
        assert!(within as f64 >= share * total as f64, "{within}/{total}");
    }
}

#[test]
#[ignore = "battery: ~60 s in release"]
fn battery_exact_and_noisy() {
    let mut rng = StdRng::seed_from_u64(19);
    let (mut done, mut failed_sweeps, mut flagged, mut silent) = (0, 0, 0, 0);
    let mut singular = 0;
    let t = std::time::Instant::now();
    for i in 0..30 {
        let case = random_case(&mut rng, i);
        // the singular case of each scene: its free rows only (one configuration, seen ten
        // times) cannot determine theta, A, B
        if let Some(mut free) = log_of(&case, 20) {
            free.rows.truncate(10);
            let start = wrong_start(&case.truth, &mut rng);
            match calibrate(&start, &[free], &CalibSettings::default()) {
                Err(ReconError::CalibrationNoContact { .. }) => singular += 1,
                other => panic!("case {i}: free rows only: {other:?}"),
            }
        }
        match exact_case(&case, 60, &mut rng) {
            Some((_, None)) => done += 1,
            Some((_, Some((what, warned)))) => {
                eprintln!("case {i}: {what} (warned: {warned})");
                if warned {
                    flagged += 1;
                } else {
                    silent += 1;
                }
            }
            None => failed_sweeps += 1,
        }
    }
    eprintln!(
        "exact: {done} cases calibrated to 1e-7, {flagged} missed with a warning, {silent} \
         missed silently, {failed_sweeps} sweeps failed or too short; {singular} free-rows-only \
         logs all refused (no contact row) ({:?})",
        t.elapsed()
    );
    // The issue asks for 95 % at both levels. Measured: 157/160 pairs at 1e-4 (case 31, a
    // local minimum, reported) and 157/160 at 1e-3 (case 47, a local minimum, reported;
    // case 22: a and b 3.5 standard errors off at the global minimum, the same from the
    // truth). Three calibrations at each level warn (case 21 at 1e-4, theta = 0.05 with
    // contact forces of 5-25 noise deviations, within 3 standard errors). Before the rounds'
    // consistent row set, the outlier passes, the pushing-contact and free-group checks and
    // the count of rows a fit cannot use: 151/160 (case 29 silently 4-8 standard errors off)
    // and 154/160. Both shares: of the pairs with an estimate, and of all pairs asked for (a
    // parameter reported unidentifiable counts as a miss).
    for level in [1e-4f64, 1e-3] {
        let seed = 7 + level.log10().abs() as u64;
        let [within, total, asked, cases] = noisy_battery(40, level, 60, seed);
        let share = within as f64 / total as f64;
        eprintln!(
            "noise {level:e}: {within}/{total} = {share:.3} within 3 stderr over {cases} cases \
             ({within}/{asked} of the pairs asked for)"
        );
        assert!(
            share >= 0.95 && within as f64 >= 0.95 * asked as f64,
            "{within}/{total}"
        );
    }
    assert_eq!(silent, 0);
    assert!(flagged * 10 <= done, "{flagged} of {done}");
}

#[test]
fn standard_errors_shrink_as_one_over_sqrt_rows() {
    let case = Case {
        truth: Whisker::new(0.5, 0.4, -0.3, 15.0),
        flow: FluidLoad { q: 2.0, alpha: 0.1 },
        profile: ("g2".into(), Profile::g2()),
    };
    let mut sds = Vec::new();
    for points in [40, 160] {
        let mut log = log_of(&case, points).unwrap();
        log.rows = add_noise(&log.rows, 1e-4, 5);
        let cal = calibrate(&case.truth, &[log], &CalibSettings::default()).unwrap();
        sds.push(
            cal.parameters
                .iter()
                .map(|p| p.stderr.unwrap())
                .collect::<Vec<_>>(),
        );
    }
    for (p, (a, b)) in sds[0].iter().zip(&sds[1]).enumerate() {
        let ratio = a / b;
        // four times the rows: half the standard error (the noise level is estimated)
        assert!((1.5..2.7).contains(&ratio), "parameter {p}: ratio {ratio}");
    }
}

#[test]
fn a_log_of_the_free_whisker_only_is_refused_but_gives_k() {
    let truth = Whisker::new(0.5, 0.4, -0.3, 15.0);
    let case = Case {
        truth,
        flow: FluidLoad { q: 2.0, alpha: 0.1 },
        profile: ("g2".into(), Profile::g2()),
    };
    let mut log = log_of(&case, 20).unwrap();
    // the free rows only: one configuration, seen ten times; theta, A, B need contact
    log.rows.truncate(10);
    let start = Whisker::new(0.6, 0.3, -0.2, 20.0);
    let e = calibrate(
        &start,
        std::slice::from_ref(&log),
        &CalibSettings::default(),
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            ReconError::CalibrationNoContact {
                contact: 0,
                fitted: 0,
                rows: 10,
                ..
            }
        ),
        "{e}"
    );
    // k from the follicle law of the rows alone
    let only_k = CalibSettings {
        fit: vec![CalibParam::K],
        ..Default::default()
    };
    // (the shape held at the truth's: a wrong one leaves m(1) != 0, which the whitening
    // correlates with the follicle law through the noise of phi0)
    let shape = Whisker {
        support: start.support,
        ..truth
    };
    let cal = calibrate(&shape, std::slice::from_ref(&log), &only_k).unwrap();
    let k = cal.parameter(CalibParam::K).unwrap();
    assert!(
        k.identifiable && (k.value.unwrap() - 15.0).abs() < 1e-6,
        "{k:?}"
    );
    // the distance of no contact row is none, not 0
    assert!(cal.rms_distance.is_nan());
    // two whiskers in one file: the contact rows of another whisker and contour than the
    // free rows' cannot be fitted by one whisker; refused or warned, never silent
    let other = Case {
        truth: Whisker::new(1.0, -1.5, 1.2, 3.0),
        flow: FluidLoad {
            q: 0.3,
            alpha: -0.5,
        },
        profile: ("g1".into(), Profile::g1()),
    };
    let mut mixed = log.clone();
    mixed
        .rows
        .extend(log_of(&other, 20).unwrap().rows.into_iter().skip(10));
    match calibrate(&start, &[mixed], &CalibSettings::default()) {
        Err(e) => eprintln!("mixed: {e}"),
        Ok(cal) => assert!(!cal.warnings.is_empty(), "{:?}", cal.parameters),
    }
}

#[test]
fn three_contact_rows_are_not_taken_for_the_flow() {
    let truth = Whisker::new(0.6, 0.5, 0.3, 20.0);
    let case = Case {
        truth,
        flow: FluidLoad { q: 5.0, alpha: 0.0 },
        profile: ("g2".into(), Profile::g2()),
    };
    let log = log_of(&case, 40).unwrap();
    let first = log.rows.len() / 2;
    let three = CalibLog {
        rows: log.rows[first..first + 3].to_vec(),
        ..log.clone()
    };
    // issue 34: taken for three rows of the free whisker, q = 7.24 and k "identifiable"
    match calibrate(&truth, &[three], &CalibSettings::default()) {
        Err(e) => eprintln!("three rows: {e}"),
        Ok(cal) => {
            assert_eq!(cal.logs[0].pre_contact, 0, "{:?}", cal.logs);
            assert!(
                cal.warnings
                    .iter()
                    .any(|w| w.contains("no row of the free whisker")),
                "{:?}",
                cal.warnings
            );
        }
    }
    // one row before contact (the first contact's row, where the force is zero, removed):
    // recognised as the free whisker
    let mut one = log.clone();
    let pre: Vec<usize> = (0..one.rows.len())
        .filter(|&i| (one.rows[i].ax + 5.0).abs() < 1e-9 && one.rows[i].ay.abs() < 1e-9)
        .collect();
    assert!(pre.len() >= 11, "{}", pre.len());
    let keep = pre[0];
    one.rows = one
        .rows
        .iter()
        .enumerate()
        .filter(|(i, _)| *i == keep || !pre.contains(i))
        .map(|(_, r)| *r)
        .collect();
    let cal = calibrate(&truth, &[one], &CalibSettings::default()).unwrap();
    assert_eq!(cal.logs[0].pre_contact, 1, "{:?}", cal.logs);
    assert!((cal.logs[0].q - 5.0).abs() < 1e-8, "{:?}", cal.logs);
}

#[test]
fn design_predicts_the_fitted_standard_errors() {
    let truth = Whisker::new(0.6, 0.5, 0.3, 20.0);
    let flow = FluidLoad { q: 2.0, alpha: 0.2 };
    let candidates = vec![
        ("g2".to_string(), Profile::g2()),
        (
            "post".to_string(),
            Profile::Circle {
                xc: -0.3,
                yc: 1.2,
                r: 0.4,
            },
        ),
    ];
    let settings = DesignSettings {
        sweep: SweepSettings {
            points: 40,
            ..Default::default()
        },
        ..Default::default()
    };
    let pred = design(&truth, flow, &candidates, &settings).unwrap();
    assert_eq!(pred.len(), 2);
    // against a fit of a noisy g2 log at the same noise level
    let case = Case {
        truth,
        flow,
        profile: candidates[0].clone(),
    };
    let mut log = log_of(&case, 40).unwrap();
    log.rows = add_noise(&log.rows, settings.noise, 3);
    let cal = calibrate(&truth, &[log], &CalibSettings::default()).unwrap();
    for (p, f) in pred[0].parameters.iter().zip(&cal.parameters) {
        let (a, b) = (p.stderr.unwrap(), f.stderr.unwrap());
        assert!(
            (0.5..2.0).contains(&(a / b)),
            "{:?}: predicted {a:.3e}, fitted {b:.3e}",
            p.param
        );
    }
    assert!(pred.iter().all(|p| p.worst_relative.is_finite()));
}

#[test]
fn several_logs_of_one_whisker_are_fitted_jointly_each_with_its_flow() {
    let truth = Whisker::new(0.5, -0.4, 0.6, 12.0);
    let cases = [
        Case {
            truth,
            flow: FluidLoad { q: 2.0, alpha: 0.3 },
            profile: ("g2".into(), Profile::g2()),
        },
        Case {
            truth,
            flow: FluidLoad {
                q: 0.8,
                alpha: -0.2,
            },
            profile: (
                "post".into(),
                Profile::Circle {
                    xc: -0.3,
                    yc: 1.3,
                    r: 0.5,
                },
            ),
        },
    ];
    let logs: Vec<CalibLog> = cases.iter().map(|c| log_of(c, 30).unwrap()).collect();
    let start = Whisker::new(0.7, -0.2, 0.4, 20.0);
    let cal = calibrate(&start, &logs, &CalibSettings::default()).unwrap();
    for (p, e, _) in errors(&cal, &truth) {
        assert!(relative(p, e, &truth) < 1e-7, "{}: {e:e}", p.name());
    }
    for (fit, case) in cal.logs.iter().zip(&cases) {
        assert!((fit.q - case.flow.q).abs() < 1e-8 && (fit.alpha - case.flow.alpha).abs() < 1e-8);
    }
    // the joint fit determines the whisker better than either log alone
    let alone = calibrate(&start, &logs[..1], &CalibSettings::default()).unwrap();
    let sd = |c: &Calibration| c.parameter(CalibParam::A).unwrap().stderr.unwrap();
    assert!(
        sd(&cal) < sd(&alone) * 1.5,
        "{} vs {}",
        sd(&cal),
        sd(&alone)
    );
}

#[test]
fn bad_requests_are_refused() {
    let truth = Whisker::new(0.6, 0.5, 0.3, 20.0);
    let case = Case {
        truth,
        flow: FluidLoad { q: 2.0, alpha: 0.2 },
        profile: ("g2".into(), Profile::g2()),
    };
    let log = log_of(&case, 10).unwrap();
    let empty = CalibSettings {
        fit: vec![],
        ..Default::default()
    };
    assert!(calibrate(&truth, std::slice::from_ref(&log), &empty).is_err());
    let twice = CalibSettings {
        fit: vec![CalibParam::A, CalibParam::A],
        ..Default::default()
    };
    assert!(calibrate(&truth, std::slice::from_ref(&log), &twice).is_err());
    assert!(calibrate(&truth, &[], &CalibSettings::default()).is_err());
    let mut bad = log;
    bad.rows[3].ma = f64::NAN;
    let e = calibrate(&truth, &[bad], &CalibSettings::default()).unwrap_err();
    assert!(e.to_string().contains("row 3"), "{e}");
}

/// The figure of the issue: one calibration of a 200-row log (release: `cargo test --release
/// -p profile-recon --test it -- calibrate::timing --ignored --nocapture`).
#[test]
#[ignore = "timing: run in release"]
fn timing_200_rows() {
    let case = Case {
        truth: Whisker::new(0.6, 0.5, 0.3, 20.0),
        flow: FluidLoad { q: 2.0, alpha: 0.2 },
        profile: ("g2".into(), Profile::g2()),
    };
    let log = log_of(&case, 190).unwrap();
    let rows = log.rows.len();
    let start = Whisker::new(0.8, 0.3, 0.2, 30.0);
    let mut times = Vec::new();
    for _ in 0..5 {
        let t = std::time::Instant::now();
        let cal = calibrate(
            &start,
            std::slice::from_ref(&log),
            &CalibSettings::default(),
        )
        .unwrap();
        times.push(t.elapsed().as_secs_f64());
        assert!(
            cal.warnings.is_empty() && cal.fits.len() == 1,
            "{:?}",
            cal.warnings
        );
    }
    times.sort_by(f64::total_cmp);
    eprintln!(
        "calibration of a {rows}-row log: median {:.3} s, best {:.3} s",
        times[2], times[0]
    );
    // the bound, wall clock (on the shared 2-core machine under load ~13 the
    // process got a third of a core: 0.95 s wall, ~0.3 s of CPU a calibration)
    assert!(rows >= 200 && times[2] < 1.0);
}

/// Diagnostics of the noisy battery's cases (`CALIB_CASES=21,29,31`, `CALIB_LEVEL=1e-4`,
/// `CALIB_EXACT=1` for the exact log of the case; all cases that miss without
/// `CALIB_CASES`): the local fits, the fit from the truth, the
/// rows that dominate the cost and the rows whose phase differs from the sweep's, and the
/// conditioning. `cargo test --release -p profile-recon --test it -- calibrate::diagnose
/// --ignored --nocapture`.
#[test]
#[ignore = "diagnostics"]
fn diagnose_battery_cases() {
    let var = |k: &str| std::env::var(k).ok();
    let level: f64 = var("CALIB_LEVEL").map_or(1e-4, |v| v.parse().unwrap());
    let only: Vec<usize> = var("CALIB_CASES")
        .map(|v| v.split(',').map(|x| x.parse().unwrap()).collect())
        .unwrap_or_default();
    let exact = var("CALIB_EXACT").is_some();
    let seed = 7 + level.log10().abs() as u64;
    noisy_cases(40, level, 60, seed, |i, case, mut log, start, res| {
        if exact {
            log.rows = from_sweep(res);
        }
        let settings = CalibSettings::default();
        let cal = match calibrate(&start, std::slice::from_ref(&log), &settings) {
            Ok(cal) => cal,
            Err(e) => {
                eprintln!("== case {i}: {e}");
                return false;
            }
        };
        let errs = errors(&cal, &case.truth);
        let miss = errs.iter().any(|(_, e, sd)| e.abs() > 3.0 * sd);
        if !(only.contains(&i) || only.is_empty() && miss) {
            return true;
        }
        let from_truth = CalibSettings {
            screen: 0,
            starts: 1,
            ..settings.clone()
        };
        let tr = calibrate(&case.truth, std::slice::from_ref(&log), &from_truth).unwrap();
        eprintln!(
            "== case {i} ({}): {:?} flow {:?} pattern {}\n   start {start:?}",
            case.profile.0,
            case.truth,
            case.flow,
            res.phase_pattern()
        );
        for (name, c) in [("fit", &cal), ("from truth", &tr)] {
            let z: Vec<String> = errors(c, &case.truth)
                .iter()
                .map(|(p, e, sd)| format!("{}: {:+.1}", p.name(), e / sd))
                .collect();
            let kinds: String = c.rows.iter().map(|r| r.kind).collect();
            eprintln!(
                "   {name}: {kinds} fits {:?}, noise {:.3e} (logs {:.3e}), sv {:.1e}, z [{}], {:?}",
                c.fits,
                c.noise_level,
                c.log_noise,
                c.singular_values.last().unwrap_or(&f64::NAN),
                z.join(", "),
                c.warnings
            );
        }
        for ((r, t), p) in cal.rows.iter().zip(&tr.rows).zip(&res.points) {
            let truth = match p.phase {
                Phase::None => '-',
                Phase::A => 'A',
                Phase::B => 'B',
            };
            let odd = r.kind != truth || (r.kind == 'B' && (r.s1 - p.s1).abs() > 1e-2);
            if odd || r.chi > 4.0 || t.kind != truth {
                eprintln!(
                    "   row {:2} x0 {:+.3}: truth {truth} s1 {:.3} f {:.2e} | fit {} {:.3} chi {:.1} \
                     | from truth {} {:.3} chi {:.1}",
                    r.row, p.x0, p.s1, p.f, r.kind, r.s1, r.chi, t.kind, t.s1, t.chi
                );
            }
        }
        true
    });
}

/// A long log (issue 34: 100,000 rows took ~280 s): ten noisy passes (relative noise 1e-4)
/// of a 10,000-row sweep, calibrated from a wrong start; the progress reports counted.
/// `CALIB_ROWS=100000` for the size. `cargo test -p profile-recon --test it -- calibrate::
/// long_log -- --ignored --nocapture`.
#[test]
#[ignore = "timing: a long log"]
fn long_log_timing() {
    let rows: usize = std::env::var("CALIB_ROWS").map_or(100_000, |v| v.parse().unwrap());
    let case = Case {
        truth: Whisker::new(0.6, 0.5, 0.3, 20.0),
        flow: FluidLoad { q: 2.0, alpha: 0.2 },
        profile: ("g2".into(), Profile::g2()),
    };
    let pass = log_of(&case, rows / 10).unwrap();
    let mut log = pass.clone();
    log.rows = (0..10)
        .flat_map(|k| add_noise(&pass.rows, 1e-4, 40 + k))
        .collect();
    let n = log.rows.len();
    let start = Whisker::new(0.8, 0.3, 0.2, 30.0);
    let reports = std::cell::Cell::new(0usize);
    let t = std::time::Instant::now();
    let cal = profile_recon::calibrate::calibrate_with_progress(
        &start,
        std::slice::from_ref(&log),
        &CalibSettings::default(),
        &|_| reports.set(reports.get() + 1),
    )
    .unwrap();
    let secs = t.elapsed().as_secs_f64();
    eprintln!(
        "{n} rows: {secs:.1} s ({:.3} ms a row), {} progress reports, warnings {:?}",
        1e3 * secs / n as f64,
        reports.get(),
        cal.warnings
    );
    for (p, e, sd) in errors(&cal, &case.truth) {
        eprintln!("  {}: off by {e:.2e} = {:.1} stderr", p.name(), e / sd);
        assert!(e.abs() < 4.0 * sd, "{}", p.name());
    }
    assert!(reports.get() > 10);
}
