//! The calibration batteries of issue 37: seeded logs of the kinds an independent check found
//! the calibration weak on, each calibrated from the CLI's default start (a uniform, straight,
//! rigid whisker) and checked against the truth it was made from.
//!
//! The generator samples four families ([`Family`]):
//! - `Rigid`: uniform rigid whiskers (theta = 1, no spring, mild pre-curvature) on a strong
//!   flow (q 3..8), one row before contact;
//! - `CircleTip`: a uniform whisker against a circular post, tip contact only (phase A
//!   throughout), ending in a snap;
//! - `Weak`: tapered (theta 0.3..0.8), pre-curved whiskers on soft springs (k 2..8), a weak
//!   flow (q ~ 0.1) and weak contact (largest contact force 0.05..0.3), ten rows before
//!   contact, ending at a fold (a snap);
//! - `Joint`: a tapered (theta ~ 0.35), pre-curved (A ~ -0.4, B ~ 0.6) rigid whisker swept
//!   past two contours under two flows, the two logs fitted jointly.
//!
//! **Independent evidence.** The logs are made by contact-sim's sweep, but none is used before
//! it passes a check that shares no code with it: [`rk4_residual`] integrates the
//! first-order system of spec/model.md from each logged base state (x0, 0, phi0, m(0) = -MA,
//! the contact force from the base forces and the flow [6.8, 6.9]) with a hand-written
//! classical RK4 and Richardson extrapolation, and measures the contact conditions at the
//! logged s1 (m(s1) = 0, r(s1) on the contour, the force normal to it; phi(s1) = psi in phase
//! B) and, for the rows before contact, m(1) = 0 and the base forces equal to the flow's. The
//! calibrations are then judged against the truth the logs were made from, never against the
//! code's own answers.
//!
//! The default test runs a short seeded subset (~30 s in the test profile on 2 cores); the
//! battery is ignored: `cargo test -p profile-recon --test it -- calibrate_battery:: --ignored
//! --nocapture` (the figures of docs/calib.md).

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, Phase, Profile, Separation, SweepResult, SweepSettings};
use profile_recon::calibrate::{calibrate, CalibLog, CalibParam, CalibSettings, Calibration};
use profile_recon::{add_noise, from_sweep, KnownFlow};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::f64::consts::FRAC_PI_2;

/// The families of the issue's list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Family {
    Rigid,
    CircleTip,
    Weak,
    Joint,
}

const FAMILIES: [Family; 4] = [
    Family::Rigid,
    Family::CircleTip,
    Family::Weak,
    Family::Joint,
];

/// One sweep of a case.
#[derive(Clone, Debug)]
struct Sweep {
    flow: FluidLoad,
    profile: Profile,
    result: SweepResult,
}

/// A case: the truth and its sweeps.
#[derive(Clone, Debug)]
struct Case {
    family: Family,
    truth: Whisker,
    sweeps: Vec<Sweep>,
}

fn settings(points: usize, pre: usize) -> SweepSettings {
    SweepSettings {
        points,
        pre_contact_rows: pre,
        ..Default::default()
    }
}

fn max_force(res: &SweepResult) -> f64 {
    res.contact_points().map(|p| p.f).fold(0.0, f64::max)
}

/// A random contour the whisker meets: a parabola, a circle or g1/g2.
fn contour(rng: &mut StdRng) -> Profile {
    match rng.gen_range(0..4) {
        0 => Profile::g2(),
        1 => Profile::g1(),
        2 => Profile::Parabola {
            a: rng.gen_range(0.5..2.5),
            xv: rng.gen_range(-0.5..0.1),
            yv: rng.gen_range(0.45..0.75),
        },
        _ => {
            let r = rng.gen_range(0.3..0.8);
            Profile::Circle {
                xc: rng.gen_range(-0.4..0.0),
                yc: rng.gen_range(0.5..0.8) + r,
                r,
            }
        }
    }
}

/// One attempt at a case of `family` (`None`: the sweep failed or missed the family's
/// features; the generator draws again).
fn attempt(family: Family, rng: &mut StdRng, points: usize) -> Option<Case> {
    let one = |truth: Whisker, flow: FluidLoad, profile: Profile, pre: usize| {
        let result = sweep(&truth, flow, &profile, &settings(points, pre)).ok()?;
        (result.contact_points().count() >= 8).then_some(Sweep {
            flow,
            profile,
            result,
        })
    };
    let alpha = |rng: &mut StdRng, deg: f64| rng.gen_range(-deg..deg).to_radians();
    let (truth, sweeps) = match family {
        Family::Rigid => {
            let truth = Whisker::new(
                1.0,
                rng.gen_range(-0.8..0.8),
                rng.gen_range(-0.4..0.4),
                f64::INFINITY,
            );
            let flow = FluidLoad {
                q: rng.gen_range(3.0..8.0),
                alpha: alpha(rng, 30.0),
            };
            (truth, vec![one(truth, flow, contour(rng), 1)?])
        }
        Family::CircleTip => {
            let k = if rng.gen_bool(0.5) {
                f64::INFINITY
            } else {
                rng.gen_range(5.0..40.0)
            };
            let truth = Whisker::new(1.0, rng.gen_range(-0.5..0.5), rng.gen_range(-0.3..0.3), k);
            let flow = FluidLoad {
                q: rng.gen_range(0.2..2.0),
                alpha: alpha(rng, 20.0),
            };
            // a small post at the tip's height: the tip rides over it
            let r = rng.gen_range(0.05..0.2);
            let post = Profile::Circle {
                xc: rng.gen_range(-0.3..-0.05),
                yc: rng.gen_range(0.85..0.97) + r,
                r,
            };
            let s = one(truth, flow, post, 10)?;
            let tip_only = s.result.contact_points().all(|p| p.phase == Phase::A);
            (tip_only && s.result.separation == Separation::Snap).then_some(())?;
            (truth, vec![s])
        }
        Family::Weak => {
            let truth = Whisker::new(
                rng.gen_range(0.3..0.8),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-0.6..0.6),
                rng.gen_range(2.0..8.0),
            );
            let flow = FluidLoad {
                q: rng.gen_range(0.05..0.15),
                alpha: alpha(rng, 30.0),
            };
            // a contour at the tip's height: grazed
            let profile = Profile::Parabola {
                a: rng.gen_range(0.5..3.0),
                xv: rng.gen_range(-0.5..0.0),
                yv: rng.gen_range(0.9..1.0),
            };
            let s = one(truth, flow, profile, 10)?;
            let f = max_force(&s.result);
            ((0.05..0.5).contains(&f) && s.result.separation == Separation::Snap).then_some(())?;
            (truth, vec![s])
        }
        Family::Joint => {
            let truth = Whisker::new(
                rng.gen_range(0.3..0.4),
                rng.gen_range(-0.5..-0.3),
                rng.gen_range(0.5..0.7),
                f64::INFINITY,
            );
            let mut sweeps = Vec::new();
            for _ in 0..2 {
                let flow = FluidLoad {
                    q: rng.gen_range(0.5..3.0),
                    alpha: alpha(rng, 30.0),
                };
                sweeps.push(one(truth, flow, contour(rng), 10)?);
            }
            (truth, sweeps)
        }
    };
    Some(Case {
        family,
        truth,
        sweeps,
    })
}

/// The `n`-th case of `family` for `seed`: draws until a sweep has the family's features.
fn case(family: Family, seed: u64, points: usize) -> Option<Case> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..200).find_map(|_| attempt(family, &mut rng, points))
}

// ---------------------------------------------------------------------------------------
// the independent check: classical RK4 with Richardson extrapolation (spec/model.md)
// ---------------------------------------------------------------------------------------

/// The state (x, y, phi, m) at `s1` of the first-order system of spec/model.md from the
/// base state of `p` under the point force `(fx, fy)` at `s1` and the flow on `[0, s1]`
/// (`m' = Fx sin phi - Fy cos phi + q (s1 - s) sin(phi + alpha)`), by `n` RK4 steps.
#[allow(clippy::too_many_arguments)]
fn rk4(
    w: &Whisker,
    flow: FluidLoad,
    start: [f64; 4],
    force: (f64, f64),
    s1: f64,
    n: usize,
) -> [f64; 4] {
    let s_end = s1;
    let e4 = |s: f64| (1.0 + (w.theta - 1.0) * s).powi(4);
    let rhs = |s: f64, u: [f64; 4]| -> [f64; 4] {
        let (phi, m) = (u[2], u[3]);
        // integrated to s1 only: the loads act on the whole interval
        let load = force.0 * phi.sin() - force.1 * phi.cos()
            + flow.q * (s1 - s) * (phi + flow.alpha).sin();
        [phi.cos(), phi.sin(), m / e4(s) + w.a * s + w.b, load]
    };
    let h = s_end / n as f64;
    let mut u = start;
    for i in 0..n {
        let s = i as f64 * h;
        let add = |u: [f64; 4], k: [f64; 4], c: f64| std::array::from_fn(|j| u[j] + c * k[j]);
        let k1 = rhs(s, u);
        let k2 = rhs(s + h / 2.0, add(u, k1, h / 2.0));
        let k3 = rhs(s + h / 2.0, add(u, k2, h / 2.0));
        let k4 = rhs(s + h, add(u, k3, h));
        u = std::array::from_fn(|j| u[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]));
    }
    u
}

/// [`rk4`] at `n` and `2n` steps, Richardson-extrapolated (order 4).
fn rk4_richardson(
    w: &Whisker,
    flow: FluidLoad,
    start: [f64; 4],
    force: (f64, f64),
    s1: f64,
) -> [f64; 4] {
    let a = rk4(w, flow, start, force, s1, 400);
    let b = rk4(w, flow, start, force, s1, 800);
    std::array::from_fn(|j| b[j] + (b[j] - a[j]) / 15.0)
}

/// The worst violation over the rows of `s` of the conditions the rows state (module docs),
/// computed without the project's integrators or contact code.
fn rk4_residual(truth: &Whisker, s: &Sweep) -> f64 {
    let flow = s.flow;
    let (qc, qs) = (flow.q * flow.alpha.cos(), flow.q * flow.alpha.sin());
    let mut worst = 0.0f64;
    for p in &s.result.points {
        let start = [p.x0, 0.0, p.phi0, -p.ma];
        // the follicle law [3.21, 3.22]
        worst = worst.max((p.phi0 - FRAC_PI_2 + p.ma * truth.support.compliance()).abs());
        match p.phase {
            Phase::None => {
                worst = worst.max((p.ax + qc).abs()).max((p.ay - qs).abs());
                let u = rk4_richardson(truth, flow, start, (0.0, 0.0), 1.0);
                worst = worst.max(u[3].abs());
            }
            Phase::A | Phase::B => {
                let s1 = if p.phase == Phase::A { 1.0 } else { p.s1 };
                // the point force from the base forces: Ax = -(Fx + q s1 cos alpha),
                // Ay = -Fy + q s1 sin alpha
                let fx = -p.ax - qc * s1;
                let fy = qs * s1 - p.ay;
                let u = rk4_richardson(truth, flow, start, (fx, fy), s1);
                let (g, dg, _) = s.profile.eval(u[0]);
                let psi = dg.atan();
                let dist = (u[1] - g) / (1.0 + dg * dg).sqrt();
                // frictionless: no component along the contour's tangent (cos psi, sin psi)
                let tangential = fx * psi.cos() + fy * psi.sin();
                worst = worst.max(u[3].abs()).max(dist.abs()).max(tangential.abs());
                if p.phase == Phase::B {
                    let d = (u[2] - psi + std::f64::consts::PI)
                        .rem_euclid(2.0 * std::f64::consts::PI)
                        - std::f64::consts::PI;
                    worst = worst.max(d.abs());
                }
            }
        }
    }
    worst
}

// ---------------------------------------------------------------------------------------
// calibration and judgement
// ---------------------------------------------------------------------------------------

/// The CLI's default start: a uniform, straight, rigid whisker.
fn default_start() -> Whisker {
    Whisker::new(1.0, 0.0, 0.0, f64::INFINITY)
}

/// The logs of a case at relative noise `level` (0: exact), the flows unknown.
fn logs_of(case: &Case, level: f64, seed: u64) -> Vec<CalibLog> {
    case.sweeps
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let rows = from_sweep(&s.result);
            CalibLog {
                rows: if level > 0.0 {
                    add_noise(&rows, level, seed + i as u64)
                } else {
                    rows
                },
                profile: s.profile.clone(),
                flow: KnownFlow::default(),
                poses: Vec::new(),
            }
        })
        .collect()
}

/// `(param, estimate - truth, stderr)` of every parameter reported identifiable (`k` as
/// its compliance `1/k`).
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

fn scale(p: CalibParam, truth: &Whisker) -> f64 {
    match p {
        CalibParam::Theta => truth.theta,
        CalibParam::A => truth.a,
        CalibParam::B => truth.b,
        CalibParam::K => truth.support.compliance(),
        CalibParam::Ei | CalibParam::Mu => 1.0,
    }
    .abs()
    .max(1.0)
}

/// The tally of a battery.
#[derive(Default, Debug)]
struct Tally {
    cases: usize,
    /// Exact: cases with every determined parameter within 1e-7.
    exact_ok: usize,
    /// Exact: misses that came with a warning or a refusal.
    reported: usize,
    /// Exact: misses without a warning.
    silent: usize,
    /// Parameters reported not determined (with a warning).
    undetermined: usize,
    /// Noisy: (case, parameter) pairs within 3 standard errors, and all pairs.
    within: usize,
    pairs: usize,
    refused: usize,
    times: Vec<f64>,
    /// Worst independent check of the logs.
    worst_log: f64,
}

/// Calibrates case `i` at `level` and adds the outcome to `t`.
fn judge(i: usize, case: &Case, level: f64, t: &mut Tally) {
    for s in &case.sweeps {
        let r = rk4_residual(&case.truth, s);
        assert!(
            r < 1e-7,
            "case {i}: the log fails the independent check by {r:.2e}"
        );
        t.worst_log = t.worst_log.max(r);
    }
    let logs = logs_of(case, level, 1000 + i as u64);
    let rows: usize = logs.iter().map(|l| l.rows.len()).sum();
    let clock = std::time::Instant::now();
    let res = calibrate(&default_start(), &logs, &CalibSettings::default());
    t.times.push(clock.elapsed().as_secs_f64());
    t.cases += 1;
    let cal = match res {
        Ok(c) => c,
        Err(e) => {
            eprintln!(
                "{level:e} case {i} {:?} ({rows} rows): refused: {e}",
                case.family
            );
            t.refused += 1;
            t.reported += usize::from(level == 0.0);
            return;
        }
    };
    t.undetermined += cal.parameters.iter().filter(|p| !p.identifiable).count();
    let errs = errors(&cal, &case.truth);
    if level == 0.0 {
        let worst = errs
            .iter()
            .map(|(p, e, _)| (e.abs() / scale(*p, &case.truth), *p))
            .fold((0.0f64, CalibParam::Theta), |a, b| {
                if b.0 > a.0 || b.0.is_nan() {
                    b
                } else {
                    a
                }
            });
        if worst.0 < 1e-7 {
            t.exact_ok += 1;
        } else if cal.warnings.is_empty() {
            t.silent += 1;
            eprintln!(
                "exact case {i} {:?}: {} off by {:.2e} SILENTLY; {:?} flows {:?}",
                case.family,
                worst.1.name(),
                worst.0,
                case.truth,
                case.sweeps.iter().map(|s| s.flow).collect::<Vec<_>>()
            );
        } else {
            t.reported += 1;
            eprintln!(
                "exact case {i} {:?}: {} off by {:.2e}, reported: {:?}",
                case.family,
                worst.1.name(),
                worst.0,
                cal.warnings
            );
        }
    } else {
        for (p, e, sd) in errs {
            t.pairs += 1;
            if e.abs() <= 3.0 * sd {
                t.within += 1;
            } else {
                eprintln!(
                    "{level:e} case {i} {:?}: {} off by {e:.3e} = {:.1} stderr; {:?}",
                    case.family,
                    p.name(),
                    e / sd,
                    cal.warnings
                );
            }
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The battery over `n` cases of every family at each level.
fn battery(n: usize, points: usize, levels: &[f64], seed: u64) -> Vec<(f64, Tally)> {
    let cases: Vec<(usize, Case)> = FAMILIES
        .iter()
        .flat_map(|&f| (0..n).map(move |k| (f, k)))
        .enumerate()
        .filter_map(|(i, (f, k))| case(f, seed + 97 * k as u64 + f as u64, points).map(|c| (i, c)))
        .collect();
    levels
        .iter()
        .map(|&level| {
            let mut t = Tally::default();
            for (i, c) in &cases {
                judge(*i, c, level, &mut t);
            }
            eprintln!(
                "noise {level:e}: {} cases; exact ok {}, reported {}, silent {}, refused {}; \
                 within 3 stderr {}/{}; undetermined parameters {}; median time {:.3} s; \
                 worst independent log check {:.1e}",
                t.cases,
                t.exact_ok,
                t.reported,
                t.silent,
                t.refused,
                t.within,
                t.pairs,
                t.undetermined,
                median(&mut t.times.clone()),
                t.worst_log
            );
            (level, t)
        })
        .collect()
}

#[test]
fn the_independent_check_sees_a_wrong_log() {
    // the check is not vacuous: a true log passes it, the same log of another whisker fails
    let c = case(Family::Weak, 5, 20).expect("a weak case");
    assert!(rk4_residual(&c.truth, &c.sweeps[0]) < 1e-8);
    let other = Whisker {
        b: c.truth.b + 1e-4,
        ..c.truth
    };
    assert!(rk4_residual(&other, &c.sweeps[0]) > 1e-6);
    // and RK4 against a closed form: the unloaded circular arc B = 1 ends at (1 - cos 1, sin 1)
    let arc = Whisker::new(1.0, 0.0, 1.0, f64::INFINITY);
    let u = rk4_richardson(
        &arc,
        FluidLoad { q: 0.0, alpha: 0.0 },
        [0.0, 0.0, FRAC_PI_2, 0.0],
        (0.0, 0.0),
        1.0,
    );
    assert!(
        (u[0] + (1.0 - 1f64.cos())).abs() < 1e-12 && (u[1] - 1f64.sin()).abs() < 1e-12,
        "{u:?}"
    );
}

#[test]
fn a_short_seeded_battery_finds_the_truth() {
    let out = battery(1, 40, &[0.0, 1e-3], 370);
    let (_, exact) = &out[0];
    assert_eq!(exact.cases, 4);
    assert_eq!(exact.silent, 0, "{exact:?}");
    assert!(exact.exact_ok >= 3, "{exact:?}");
    let (_, noisy) = &out[1];
    assert!(noisy.within as f64 >= 0.8 * noisy.pairs as f64, "{noisy:?}");
}

#[test]
#[ignore = "battery: minutes in the test profile"]
fn battery_of_issue_37() {
    let out = battery(10, 60, &[0.0, 1e-4, 1e-3], 3701);
    let (_, exact) = &out[0];
    assert_eq!(exact.silent, 0, "{exact:?}");
    assert!(
        exact.exact_ok as f64 >= 0.99 * exact.cases as f64,
        "{exact:?}"
    );
    for (level, t) in &out[1..] {
        assert!(t.within as f64 >= 0.95 * t.pairs as f64, "{level:e}: {t:?}");
    }
}

/// Diagnostics of one case (`CALIB_CASE=FAMILY_INDEX,K`, `CALIB_LEVEL`): the fit from the
/// default start and from the truth. `cargo test -p profile-recon --test it -- calibrate_battery::
/// diagnose -- --ignored --nocapture`.
#[test]
#[ignore = "diagnostics"]
fn diagnose_case() {
    let var = |k: &str| std::env::var(k).ok();
    let level: f64 = var("CALIB_LEVEL").map_or(1e-3, |v| v.parse().unwrap());
    let spec = var("CALIB_CASE").unwrap_or_else(|| "0,0".into());
    let mut it = spec.split(',').map(|v| v.parse::<usize>().unwrap());
    let (f, k) = (it.next().unwrap(), it.next().unwrap());
    let family = FAMILIES[f];
    let i = f * 10 + k;
    let c = case(family, 3701 + 97 * k as u64 + family as u64, 60).unwrap();
    let logs = logs_of(&c, level, 1000 + i as u64);
    eprintln!(
        "{:?} {:?} flows {:?}",
        family,
        c.truth,
        c.sweeps.iter().map(|s| s.flow).collect::<Vec<_>>()
    );
    for (name, start, settings) in [
        ("default", default_start(), CalibSettings::default()),
        (
            "truth",
            c.truth,
            CalibSettings {
                screen: 0,
                starts: 1,
                ..Default::default()
            },
        ),
        (
            "default, 12 starts",
            default_start(),
            CalibSettings {
                starts: 12,
                ..Default::default()
            },
        ),
    ] {
        match calibrate(&start, &logs, &settings) {
            Ok(cal) => {
                let z: Vec<String> = errors(&cal, &c.truth)
                    .iter()
                    .map(|(p, e, sd)| format!("{}: {:+.1}", p.name(), e / sd))
                    .collect();
                let kinds: String = cal.rows.iter().map(|r| r.kind).collect();
                eprintln!(
                    "{name}: {kinds} fits {:?} noise {:.2e} (logs {:.2e}) z [{}]",
                    cal.fits,
                    cal.noise_level,
                    cal.log_noise,
                    z.join(", ")
                );
            }
            Err(e) => eprintln!("{name}: {e}"),
        }
    }
}

#[test]
#[ignore = "debug"]
fn debug_generator() {
    let mut rng = StdRng::seed_from_u64(5);
    for _ in 0..15 {
        let truth = Whisker::new(
            rng.gen_range(0.3..0.8),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-0.6..0.6),
            rng.gen_range(2.0..8.0),
        );
        let flow = FluidLoad { q: 0.1, alpha: 0.0 };
        let p = Profile::Parabola {
            a: rng.gen_range(0.5..3.0),
            xv: rng.gen_range(-0.5..0.0),
            yv: rng.gen_range(0.8..1.0),
        };
        match sweep(&truth, flow, &p, &settings(20, 10)) {
            Ok(r) => eprintln!(
                "{:?} {:?} f {:.3} {}",
                r.separation,
                p,
                max_force(&r),
                r.phase_pattern()
            ),
            Err(e) => eprintln!("err {e}"),
        }
    }
    let c = case(Family::Rigid, 370, 40).unwrap();
    let s = &c.sweeps[0];
    for p in &s.result.points {
        let one = Sweep {
            result: SweepResult {
                points: vec![*p],
                ..s.result.clone()
            },
            ..s.clone()
        };
        eprintln!(
            "{:?} x0 {:.4} f {:.3e} s1 {:.4}: {:.2e}",
            p.phase,
            p.x0,
            p.f,
            p.s1,
            rk4_residual(&c.truth, &one)
        );
    }
}
