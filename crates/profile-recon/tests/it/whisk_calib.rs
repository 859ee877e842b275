//! Calibration from logs of a turning base (issue 38, item 3; docs/whisking-recon.md,
//! "Calibration from whisking logs"). Truth: a whisker (theta, A, B, k) and a flow, whisked
//! by contact-sim past a known peg or disc (`BaseMotion::Rotate`, the rows carrying their
//! pose `y0`, `gamma`); the calibration starts from the CLI's default start (theta 1,
//! A = B = 0, a stiff spring), the flow unknown, and must give the truth back: to 1e-7 on
//! the exact log (relative to max(1, |value|), k as 1/k), within 3 standard errors at
//! relative noise 1e-4 (seeded `add_noise`).
//!
//! `cargo test -p profile-recon --test it -- whisk_calib::wcal` (the battery: `--ignored
//! --nocapture`; every fourth scene without flow, `WCAL_NO_FLOW=0` puts it back)

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, BaseMotion, Profile, SweepSettings};
use profile_recon::calibrate::{calibrate, CalibLog, CalibParam, CalibSettings, Calibration};
use profile_recon::{add_noise, from_sweep, poses_of_sweep, KnownFlow};

/// Whether every fourth scene has no flow (on; `WCAL_NO_FLOW=0` puts the flow back: the
/// scenes of before branch `wleft`, where scene 7, a disc without flow, missed until the
/// lone free row of a log without flow was recognised, docs/whisking-recon.md "The no-flow
/// disc scene").
fn no_flow() -> bool {
    std::env::var("WCAL_NO_FLOW").map_or(true, |v| v != "0")
}

/// A seeded scene: the truth, the flow, the obstacle, the motion.
pub(crate) struct Scene {
    pub truth: Whisker,
    pub flow: FluidLoad,
    pub profile: Profile,
    pub motion: BaseMotion,
}

/// Scene `i` of the seeded cases: a tapered, pre-curved whisker on a spring under a flow at
/// an angle, its base at `(bx, by)` turned from `gamma0`, an obstacle at distance `d` in
/// the direction the tip sweeps into (as contact-sim's whisking battery draws them).
pub(crate) fn scene(i: u64) -> Scene {
    // a small LCG (the scenes are fixed by the seed)
    let mut state = 0x5EED_0038u64 ^ i.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut range = |a: f64, b: f64| a + (b - a) * next();
    let (theta, a, b, k) = (
        range(0.4, 0.9),
        range(-0.5, 0.5),
        range(-0.4, 0.4),
        range(10.0, 40.0),
    );
    // every third scene rigid; every fourth without flow ([`no_flow`])
    let k = if i % 3 == 2 { f64::INFINITY } else { k };
    let truth = Whisker::new(theta, a, b, k);
    let (q, alpha) = (range(0.5, 2.0), range(-30.0, 30.0).to_radians());
    let flow = FluidLoad {
        q: if i % 4 == 3 && no_flow() { 0.0 } else { q },
        alpha,
    };
    let (bx, by) = (range(-0.2, 0.2), range(-0.2, 0.2));
    let gamma0 = range(-0.4, 0.1);
    let d = range(0.45, 0.75);
    let ang = gamma0 + range(0.3, 0.7);
    let (px, py) = (bx - d * ang.sin(), by + d * ang.cos());
    let profile = if i.is_multiple_of(2) {
        Profile::Peg { x: px, y: py }
    } else {
        let r = range(0.08, 0.25);
        Profile::Disc {
            x: px - r * ang.sin(),
            y: py + r * ang.cos(),
            r,
        }
    };
    Scene {
        truth,
        flow,
        profile,
        motion: BaseMotion::Rotate {
            x0: bx,
            y0: by,
            gamma0,
        },
    }
}

/// The log of a scene (30 contact points, 4 free rows before the first contact).
pub(crate) fn log_of(s: &Scene) -> CalibLog {
    let settings = SweepSettings {
        points: 30,
        pre_contact_rows: 4,
        motion: s.motion.clone(),
        ..SweepSettings::default()
    };
    let res = sweep(&s.truth, s.flow, &s.profile, &settings).expect("the whisking sweep");
    CalibLog {
        rows: from_sweep(&res),
        profile: s.profile.clone(),
        flow: KnownFlow::default(),
        poses: poses_of_sweep(&res),
    }
}

/// The CLI's default start: theta 1, A = B = 0, k = 1e3.
pub(crate) fn start() -> Whisker {
    Whisker::new(1.0, 0.0, 0.0, 1e3)
}

/// `(parameter, estimate - truth, stderr)` of each fitted parameter, `k` as its compliance.
pub(crate) fn errors(cal: &Calibration, truth: &Whisker) -> Vec<(CalibParam, f64, f64)> {
    cal.parameters
        .iter()
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

pub(crate) fn truth_of(p: CalibParam, t: &Whisker) -> f64 {
    match p {
        CalibParam::Theta => t.theta,
        CalibParam::A => t.a,
        CalibParam::B => t.b,
        CalibParam::K => t.support.compliance(),
        CalibParam::Ei | CalibParam::Mu => 1.0,
    }
}

/// Exact and noisy logs of seeded whisking scenes past pegs and discs: the truth back.
fn check_scenes(ids: &[u64]) {
    let settings = CalibSettings::default();
    let (mut worst, mut worst_se, mut pairs) = (0.0f64, 0.0f64, 0);
    for &i in ids {
        let s = scene(i);
        let log = log_of(&s);
        let cal = calibrate(&start(), std::slice::from_ref(&log), &settings)
            .unwrap_or_else(|e| panic!("scene {i} ({}): {e}", s.profile.name()));
        for (p, err, _) in errors(&cal, &s.truth) {
            let rel = err.abs() / truth_of(p, &s.truth).abs().max(1.0);
            worst = worst.max(rel);
            assert!(
                rel <= 1e-7,
                "scene {i} ({}), exact: {p:?} off by {err:e}; {:?}",
                s.profile.name(),
                cal.warnings
            );
        }
        // the flow too
        let lf = &cal.logs[0];
        // in Cartesian form (alpha means nothing at q = 0)
        let (dc, ds) = (
            lf.q * lf.alpha.cos() - s.flow.q * s.flow.alpha.cos(),
            lf.q * lf.alpha.sin() - s.flow.q * s.flow.alpha.sin(),
        );
        assert!(
            dc.abs() < 1e-7 && ds.abs() < 1e-7,
            "scene {i}: flow {} {} vs {:?}",
            lf.q,
            lf.alpha,
            s.flow
        );
        let noisy = CalibLog {
            rows: add_noise(&log.rows, 1e-4, 100 + i),
            ..log
        };
        let cal = calibrate(&start(), std::slice::from_ref(&noisy), &settings)
            .unwrap_or_else(|e| panic!("scene {i} noisy: {e}"));
        for (p, err, sd) in errors(&cal, &s.truth) {
            pairs += 1;
            let z = err.abs() / sd;
            worst_se = worst_se.max(z);
            assert!(
                z <= 3.0,
                "scene {i} ({}), noise 1e-4: {p:?} off by {err:e} = {z:.2} stderr; {:?}",
                s.profile.name(),
                cal.warnings
            );
        }
    }
    eprintln!(
        "wcal: {} scenes, exact worst {worst:.1e} (relative), noise 1e-4: {pairs} pairs, worst {worst_se:.2} stderr",
        ids.len()
    );
}

/// Two seeded scenes (a peg, a disc) in the default suite.
#[test]
fn wcal_calibration_from_whisking_logs_gives_the_truth() {
    check_scenes(&[0, 1]);
}

/// Scene 7 without flow (a disc, one free row of zero reactions, the contact branch linear
/// from it): the truth back (docs/whisking-recon.md, "The no-flow disc scene").
#[test]
fn wleft_a_no_flow_disc_log_calibrates() {
    if no_flow() {
        check_scenes(&[7]);
    }
}

/// More seeded scenes: `cargo test -p profile-recon --test it -- whisk_calib::wcal --ignored
/// --nocapture`.
#[test]
#[ignore = "a battery: cargo test -p profile-recon --test it -- whisk_calib::wcal --ignored --nocapture"]
fn wcal_calibration_from_whisking_logs_battery() {
    check_scenes(&(0..12).collect::<Vec<_>>());
}

/// A translate log calibrates bit for bit alike without poses and with every pose the
/// translating sweep's (`y0 = 0`, `gamma = 0`).
#[test]
fn wcal_a_translate_log_calibrates_bit_for_bit_as_before() {
    let truth = Whisker::new(0.6, 0.0, 0.3, 20.0);
    let flow = FluidLoad { q: 2.0, alpha: 0.0 };
    let settings = SweepSettings {
        points: 20,
        ..Default::default()
    };
    let res = sweep(&truth, flow, &Profile::g2(), &settings).unwrap();
    let plain = CalibLog {
        rows: from_sweep(&res),
        profile: Profile::g2(),
        flow: KnownFlow::default(),
        poses: Vec::new(),
    };
    let posed = CalibLog {
        poses: poses_of_sweep(&res),
        ..plain.clone()
    };
    assert_eq!(posed.poses.len(), plain.rows.len());
    let fit = CalibSettings {
        fit: vec![CalibParam::Theta, CalibParam::B, CalibParam::K],
        ..Default::default()
    };
    let start = Whisker::new(0.8, 0.0, 0.2, 30.0);
    let a = calibrate(&start, &[plain], &fit).unwrap();
    let b = calibrate(&start, &[posed], &fit).unwrap();
    // bit for bit: Debug prints every f64 round-trip exactly (and NaN == NaN there)
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
    assert!((a.whisker.theta - 0.6).abs() < 1e-7);
}

/// Scene 7 without flow (docs/whisking-recon.md, "The no-flow disc scene"): what the
/// misfit is. Prints the fit from the default start, from the truth, with the flow given
/// (q = 0), from more starts and on a denser log, each with its cost, noise check and
/// warnings. `cargo test -p profile-recon --test it -- whisk_calib::wleft_no_flow --ignored
/// --nocapture`
#[test]
#[ignore = "a diagnosis: cargo test -p profile-recon --test it -- whisk_calib::wleft_no_flow --ignored --nocapture"]
fn wleft_no_flow_disc_diagnosis() {
    let mut s = scene(7);
    s.flow.q = 0.0;
    let show = |what: &str, cal: &Calibration| {
        let e: Vec<String> = errors(cal, &s.truth)
            .iter()
            .map(|(p, e, sd)| format!("{}: {e:+.2e} (se {sd:.1e})", p.name()))
            .collect();
        eprintln!(
            "{what}: theta {:.4} a {:.4} b {:.4} k {:.4}; q {:.2e}; noise {:.2e} vs log {:.2e}; fits {:?}; {}\n  warnings {:?}",
            cal.whisker.theta,
            cal.whisker.a,
            cal.whisker.b,
            cal.whisker.support.stiffness(),
            cal.logs[0].q,
            cal.noise_level,
            cal.log_noise,
            cal.fits,
            e.join(", "),
            cal.warnings
        );
    };
    eprintln!(
        "truth theta {:.4} a {:.4} b {:.4} k {:.4}, {}",
        s.truth.theta,
        s.truth.a,
        s.truth.b,
        s.truth.support.stiffness(),
        s.profile.name()
    );
    let log = log_of(&s);
    let free = log
        .rows
        .iter()
        .filter(|r| r.ax == 0.0 && r.ay == 0.0)
        .count();
    eprintln!("rows {}, with zero base force {free}", log.rows.len());
    let settings = CalibSettings::default();
    let one = std::slice::from_ref(&log);
    show(
        "default start",
        &calibrate(&start(), one, &settings).unwrap(),
    );
    show(
        "from the truth",
        &calibrate(&s.truth, one, &settings).unwrap(),
    );
    let given = CalibLog {
        flow: KnownFlow {
            q: Some(0.0),
            alpha: Some(0.0),
        },
        ..log.clone()
    };
    show(
        "flow given q = 0",
        &calibrate(&start(), std::slice::from_ref(&given), &settings).unwrap(),
    );
    let many = CalibSettings {
        starts: 16,
        ..CalibSettings::default()
    };
    show("16 starts", &calibrate(&start(), one, &many).unwrap());
    let dense = {
        let settings = SweepSettings {
            points: 90,
            pre_contact_rows: 4,
            motion: s.motion.clone(),
            ..SweepSettings::default()
        };
        let res = sweep(&s.truth, s.flow, &s.profile, &settings).unwrap();
        CalibLog {
            rows: from_sweep(&res),
            profile: s.profile.clone(),
            flow: KnownFlow::default(),
            poses: poses_of_sweep(&res),
        }
    };
    show(
        "90 points",
        &calibrate(&start(), std::slice::from_ref(&dense), &settings).unwrap(),
    );
}
