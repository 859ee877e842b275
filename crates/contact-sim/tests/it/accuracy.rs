//! Accuracy on demand (`SweepSettings::accuracy`) against independent truth: on seeded random
//! scenes (profiles g1, g2, ge, a parabola; theta 0.1..1, q 0..8, rigid or spring support)
//! the sweep at T = 1e-6 and 1e-4 against the default sweep (rows at ~1e-10): the same rows
//! (phases; the base positions within T), every row within T of the default's, and every row's estimate
//! bounding its actual difference.

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, ContactError, Phase, Profile, SweepResult, SweepSettings};

use crate::random_scene;
use random_scene::{random_scene, Seeded};

/// The largest difference of two rows' observables, base position and contact point.
fn row_difference(a: &contact_sim::SweepPoint, b: &contact_sim::SweepPoint) -> f64 {
    let mut d = [
        a.x0 - b.x0,
        a.ax - b.ax,
        a.ay - b.ay,
        a.ma - b.ma,
        a.phi0 - b.phi0,
    ];
    if a.phase != Phase::None {
        d[0] = d[0].abs().max((a.xc - b.xc).abs()).max((a.yc - b.yc).abs());
    }
    d.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// The rows of `res`, a sweep at the accuracy `tol`, against those of the default sweep
/// `truth` of the same scene (`name`): the same rows and phases, every row and estimate within
/// `tol`, every estimate bounding the row's difference (the default's own error, ~1e-10,
/// allowed up to 1e-9); each row's difference and estimate.
fn rows_against(name: &str, res: &SweepResult, truth: &SweepResult, tol: f64) -> Vec<(f64, f64)> {
    let acc = res.accuracy.as_ref().unwrap();
    assert_eq!(acc.tol, tol, "{name}");
    assert_eq!(res.points.len(), truth.points.len(), "{name}");
    assert_eq!(acc.estimates.len(), res.points.len(), "{name}");
    let rows = res.points.iter().zip(&truth.points).zip(&acc.estimates);
    rows.map(|((a, b), &e)| {
        assert_eq!(a.phase, b.phase, "{name}: x0 {}", a.x0);
        let d = row_difference(a, b);
        assert!(
            d <= tol,
            "{name}: row at x0 {} off by {d:e} at T = {tol:e}",
            a.x0
        );
        assert!(e <= tol, "{name}: estimate {e:e} at x0 {}", a.x0);
        assert!(
            d <= e + 1e-9,
            "{name}: difference {d:e}, estimate {e:e} at T = {tol:e}: {a:?} vs {b:?}"
        );
        (d, e)
    })
    .collect()
}

fn run(w: &Whisker, flow: FluidLoad, p: &Profile, accuracy: Option<f64>) -> SweepResult {
    let s = SweepSettings {
        points: 40,
        accuracy,
        ..SweepSettings::default()
    };
    sweep(w, flow, p, &s).unwrap()
}

#[test]
fn rows_meet_the_accuracy_asked_for_and_their_estimates_bound_their_errors() {
    let mut rng = Seeded(0x5eed_0021);
    let profiles = ["g1", "g2", "ge", "parabola:2,0.4,0.5"];
    let mut scenes = 0;
    let mut worst_ratio: f64 = 0.0;
    for k in 0..16 {
        let p = Profile::parse(profiles[k % profiles.len()]).unwrap();
        let theta = rng.range(0.1, 1.0);
        let q = rng.range(0.0, 8.0);
        let stiff = if rng.next() < 0.5 {
            f64::INFINITY
        } else {
            rng.range(2.0, 50.0)
        };
        let w = Whisker::new(theta, 0.0, 0.0, stiff);
        let flow = FluidLoad { q, alpha: 0.0 };
        let settings = SweepSettings {
            points: 40,
            ..SweepSettings::default()
        };
        let Ok(truth) = sweep(&w, flow, &p, &settings) else {
            continue; // no contact for this scene
        };
        assert!(truth.accuracy.is_none());
        scenes += 1;
        for tol in [1e-6, 1e-4] {
            let res = run(&w, flow, &p, Some(tol));
            let name = format!("{} theta {theta:.3} q {q:.3} k {stiff:.2}", p.name());
            for (d, e) in rows_against(&name, &res, &truth, tol) {
                worst_ratio = worst_ratio.max(d / e);
            }
        }
    }
    assert!(scenes >= 8, "{scenes} scenes in contact");
    assert!(worst_ratio < 1.0, "{worst_ratio}");
}

#[test]
fn an_accuracy_out_of_range_is_refused() {
    let w = Whisker::uniform();
    let flow = FluidLoad { q: 5.0, alpha: 0.0 };
    for bad in [0.0, 1.0, 1e-13, f64::NAN] {
        let s = SweepSettings {
            accuracy: Some(bad),
            ..SweepSettings::default()
        };
        let err = sweep(&w, flow, &Profile::g1(), &s).unwrap_err();
        assert!(
            matches!(
                err,
                ContactError::InvalidParameter {
                    name: "accuracy",
                    ..
                }
            ),
            "{err}"
        );
    }
}

/// The row where a contact is released is estimated under its own condition, zero force:
/// held at its contour point instead, its estimate came out ~1e7 times its error and a
/// sweep at 1e-6 of this scene was refused (found by seeded random sweeps at T = 1e-4..1e-8:
/// 4 refusals of 180, all at a release). At T = 1e-6 the sweep goes through, and the release
/// row's estimate bounds its difference from the default sweep (whose rows agree with a
/// sweep at 1e-14 to 5e-11).
#[test]
fn a_release_row_is_estimated_at_zero_force() {
    let p = Profile::g1();
    let w = Whisker::new(0.470, -0.006, -0.217, f64::INFINITY);
    let flow = FluidLoad {
        q: 5.16,
        alpha: -0.78,
    };
    let truth = run(&w, flow, &p, None);
    assert_eq!(truth.separation, contact_sim::Separation::Release);
    let res = run(&w, flow, &p, Some(1e-6));
    let acc = res.accuracy.as_ref().unwrap();
    // the release: the row of least x0, at zero force
    let (i, row) = res
        .points
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.x0.total_cmp(&b.1.x0))
        .unwrap();
    assert_eq!(row.f, 0.0);
    assert!(
        acc.estimates[i] <= 1e-6,
        "release estimate {:e}",
        acc.estimates[i]
    );
    // and every row, the release's included, within its estimate of the default's
    rows_against("g1 theta 0.47 q 5.16 alpha -0.78", &res, &truth, 1e-6);
}

/// The one scene of the seeded battery below whose sweep at T = 1e-8 was refused (seed 12,
/// scene 15: g1, theta 0.067 on a spring, q 5.98 at -33 degrees; a row's estimate 1.19e-8):
/// the rows were integrated once more ten times tighter (rows at 1e-13, their estimates at
/// 1e-11), and the sweep answered, every row within its estimate of the default sweep's.
/// Since issue 34 (the whisker bounded on its dense output, the segment next to the tip
/// included) this sweep ends at its second contact at x0 = 1.530864 instead of 1.530878
/// (the last row touching within 5.4e-10, checked from its logged observables in
/// `tests/precurved.rs`): its rows sit 1.4e-5 further on and none needs the tighter pass.
/// The sweep is answered either way, every row within its estimate of the default sweep's.
#[test]
fn a_row_estimated_above_the_accuracy_asked_for_is_solved_again_tighter() {
    let mut rng = Seeded(12);
    let scene = (0..=15).map(|k| random_scene(&mut rng, k)).last().unwrap();
    let (p, w, flow) = (&scene.profile, &scene.whisker, scene.flow);
    assert!((w.theta - 0.067).abs() < 5e-4, "{}", scene.name);
    let base = SweepSettings {
        points: 60,
        ..SweepSettings::default()
    };
    let truth = sweep(w, flow, p, &base).unwrap();
    let tight = SweepSettings {
        accuracy: Some(1e-8),
        ..base
    };
    let res = sweep(w, flow, p, &tight).unwrap();
    let acc = res.accuracy.as_ref().unwrap();
    assert!(
        (acc.integration_tol - 1e-13).abs() < 1e-25
            || ((acc.integration_tol - 1e-12).abs() < 1e-24
                && acc.estimates.iter().all(|&e| e <= 1e-8)),
        "{}: rows at {:e}",
        scene.name,
        acc.integration_tol
    );
    let checked = rows_against(&scene.name, &res, &truth, 1e-8);
    assert!(checked.len() >= 60, "{}", checked.len());
}

/// Seeded random sweeps at T = 1e-4, 1e-6, 1e-8 (every profile kind of the CLI's names, theta
/// 0.05..1, A, B, rigid or spring, q 0..8, flows at ±45 degrees) against the default sweep of
/// the same scene, whose rows sit at the same base positions (its trace, first contact and
/// events are the same; a sweep at 1e-14 has its own first contact and so its own grid of
/// x0): every row of an answered sweep within its estimate of the default's row (the
/// default's own error allowed, 1e-9 as above), every estimate within T; a sweep refused for
/// an estimate above T even with the rows ten times tighter is counted (a row the looser
/// integration cannot show to T), at most one in two hundred (none of 555 now; 1 of 554,
/// a row at 1.2 T, before the rows were solved again tighter; 5 before the release row was
/// estimated at zero force).
#[test]
#[ignore = "about 20 s in release; run with --ignored"]
fn random_sweeps_meet_the_accuracy_asked_for_or_say_where_not() {
    let (mut answered, mut refused, mut rows) = (0, Vec::new(), 0);
    let mut worst_ratio: f64 = 0.0;
    for seed in [7u64, 11, 12, 13] {
        let mut rng = Seeded(seed);
        for k in 0..60 {
            let scene = random_scene(&mut rng, k);
            let (p, w, flow) = (&scene.profile, &scene.whisker, scene.flow);
            let base = SweepSettings {
                points: 60,
                ..SweepSettings::default()
            };
            let Ok(truth) = sweep(w, flow, p, &base) else {
                continue; // no contact for this scene
            };
            for tol in [1e-4, 1e-6, 1e-8] {
                let name = format!("seed {seed} {} T {tol:e}", scene.name);
                let s = SweepSettings {
                    accuracy: Some(tol),
                    ..base.clone()
                };
                let res = match sweep(w, flow, p, &s) {
                    Ok(res) => res,
                    Err(e @ ContactError::AccuracyNotMet { .. }) => {
                        refused.push(format!("{name}: {e}"));
                        continue;
                    }
                    Err(e) => panic!("{name}: {e}"),
                };
                answered += 1;
                for (d, e) in rows_against(&name, &res, &truth, tol) {
                    // (the default's own error allowed, as `rows_against` does)
                    worst_ratio = worst_ratio.max(d / (e + 1e-9));
                    rows += 1;
                }
            }
        }
    }
    println!(
        "--tol sweeps: {answered} answered ({rows} rows, worst difference/estimate {worst_ratio:.3}), {} refused",
        refused.len()
    );
    for r in &refused {
        println!("refused: {r}");
    }
    assert!(answered >= 400, "{answered} sweeps answered");
    assert!(refused.len() * 200 <= answered, "{} refused", refused.len());
}
