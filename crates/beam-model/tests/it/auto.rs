//! Accuracy on demand (`Method::Auto`): every answer within the accuracy asked for,
//! checked against independent truth — linear small-deflection theory in its limit,
//! Mattiasson's elliptic integrals, and `accurate` (DOP853 shooting, its own estimate
//! below 1e-10) on a seeded battery over the parameter space the CLI accepts for weak and
//! moderate loads, where the spectral Picard iteration is meant to answer.

use crate::support;

use beam_model::{solve, Loads, Method, MethodKind, ModelKind, Scene, TipForce, Whisker};

fn auto(tol: f64) -> Method {
    Method::Auto { tol, samples: 100 }
}

/// A small deterministic generator (SplitMix64) for the seeded battery.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
}

#[test]
fn weak_flow_matches_linear_theory() {
    // Uniform rigid straight whisker, flow along +x: x1 -> q/8 and tip angle change -> q/6
    // (spec/model.md); the nonlinear correction is O(q^3).
    let q = 1e-3;
    let s = Scene::new(
        Whisker::new(1.0, 0.0, 0.0, f64::INFINITY),
        Loads::fluid(q, 0.0),
    );
    let sol = solve(&s, &auto(1e-10)).unwrap();
    assert_eq!(sol.stats.method_used, MethodKind::Picard);
    assert!((sol.tip.x / (q / 8.0) - 1.0).abs() < 1e-5, "{}", sol.tip.x);
    let turn = std::f64::consts::FRAC_PI_2 - sol.tip.phi;
    assert!((turn / (q / 6.0) - 1.0).abs() < 1e-5, "{turn}");
}

#[test]
fn tip_force_matches_mattiasson() {
    for f in [0.5, 1.0, 2.0] {
        let s = Scene::new(
            Whisker::new(1.0, 0.0, 0.0, f64::INFINITY),
            Loads::tip(TipForce::dp(f, 0.0)),
        );
        let sol = solve(&s, &auto(1e-10)).unwrap();
        let (x1, y1, _) = support::mattiasson(f);
        let err = (sol.tip.x - x1).abs().max((sol.tip.y - y1).abs());
        assert!(err < 1e-9, "f = {f}: error {err:e} ({:?})", sol.stats);
        assert!(sol.stats.error_estimate <= 1e-10);
    }
}

/// The seeded battery: tapered, pre-curved whiskers on rigid or elastic supports under
/// weak and moderate tip forces (DP and AP) and flows at any angle, loaded to their tip
/// or in part (s1 < 1). Every answer of `auto` must lie within the accuracy asked for of
/// `accurate` (plus the reference's own estimate), at 1e-4, 1e-6 and 1e-8.
#[test]
fn auto_meets_every_accuracy_asked_for() {
    let (cases, picard) = battery(0x5EED_0021, 60, 0.1, 1.5, 3.0);
    assert!(cases >= 50, "only {cases} cases with a reference");
    // The weak and moderate loads of this battery are Picard's regime.
    assert!(
        picard >= 2 * cases,
        "picard answered {picard} of {}",
        3 * cases
    );
}

/// The same over the CLI's whole range of loads (f, q up to 30) and tapers down to 0.05:
/// where the iteration does not contract, shooting answers, and every estimate still
/// bounds its error. ~1 min in release:
/// `cargo test --release -p beam-model --test it -- auto:: --ignored --nocapture`.
#[test]
#[ignore]
fn auto_battery_wide() {
    let (cases, picard) = battery(0xA070_2026, 400, 0.05, 30.0, 30.0);
    assert!(cases >= 200, "only {cases} cases with a reference");
    assert!(picard > 0);
}

/// Runs `n` seeded cases (theta from `theta_min`, f up to `f_max`, q up to `q_max`);
/// returns the cases with a reference and the answers given by Picard.
fn battery(seed: u64, n: usize, theta_min: f64, f_max: f64, q_max: f64) -> (usize, usize) {
    let mut rng = Rng(seed);
    let (mut cases, mut picard, mut worst) = (0, 0, 0.0f64);
    for case in 0..n {
        let theta = rng.range(theta_min, 1.0);
        let (a, b) = (rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
        let k = if rng.unit() < 0.5 {
            f64::INFINITY
        } else {
            rng.range(2.0, 50.0)
        };
        let f = if rng.unit() < 0.5 {
            0.0
        } else {
            rng.range(0.0, f_max)
        };
        let beta = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
        let tip = if rng.unit() < 0.3 {
            TipForce::ap(f, beta)
        } else {
            TipForce::dp(f, beta)
        };
        let q = rng.range(0.0, q_max);
        let alpha = rng.range(-1.5, 1.5);
        let mut loads = Loads::combined(tip, q, alpha);
        if rng.unit() < 0.3 {
            loads.s1 = rng.range(0.5, 1.0);
        }
        let scene = Scene::new(Whisker::new(theta, a, b, k), loads);
        let Ok(reference) = solve(&scene, &Method::accurate()) else {
            continue;
        };
        if reference.stats.error_estimate > 1e-10 {
            continue;
        }
        cases += 1;
        for tol in [1e-4, 1e-6, 1e-8] {
            let sol = match solve(&scene, &auto(tol)) {
                Ok(sol) => sol,
                // A refusal is an answer too (no numbers, so never a wrong one).
                Err(e) => {
                    println!("refused case {case} at {tol:e}: {e}");
                    continue;
                }
            };
            let err = sol.difference(&reference);
            let allowed = tol + reference.stats.error_estimate;
            assert!(
                err <= allowed,
                "case {case} ({scene:?}) at tol {tol:e}: error {err:e} by {} (estimate {:e})",
                sol.stats.method_used.name(),
                sol.stats.error_estimate
            );
            assert!(sol.stats.error_estimate <= tol);
            // The estimate is honest: it bounds the actual error.
            assert!(
                err <= sol.stats.error_estimate + reference.stats.error_estimate + 1e-14,
                "case {case} ({scene:?}) at tol {tol:e}: error {err:e} > estimate {:e} ({})",
                sol.stats.error_estimate,
                sol.stats.method_used.name()
            );
            worst = worst.max(err / tol);
            if sol.stats.method_used == MethodKind::Picard {
                picard += 1;
            }
        }
    }
    println!("{cases} cases x 3 accuracies: {picard} by picard; worst error/tol {worst:.2e}");
    (cases, picard)
}

#[test]
fn strong_loads_go_to_shooting_and_impossible_accuracies_are_refused() {
    // A strong tip force on a slender whisker: the iteration does not contract, shooting
    // answers.
    let s = Scene::new(
        Whisker::new(0.3, 0.0, 0.0, f64::INFINITY),
        Loads::tip(TipForce::dp(20.0, 0.0)),
    );
    let sol = solve(&s, &auto(1e-6)).unwrap();
    assert_ne!(sol.stats.method_used, MethodKind::Picard);
    assert!(sol.stats.error_estimate <= 1e-6);
    // Out of range: named.
    let e = solve(&s, &auto(1e-15)).unwrap_err();
    assert!(e.to_string().contains("tol"), "{e}");
}

/// A whisker of the command line's space: theta 0.05..1, A, B within ±2, k 1..50 or rigid.
fn command_line_whisker(rng: &mut Rng) -> Whisker {
    let theta = rng.range(0.05, 1.0);
    let (a, b) = (rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
    let k = if rng.unit() < 0.5 {
        f64::INFINITY
    } else {
        rng.range(1.0, 50.0)
    };
    Whisker::new(theta, a, b, k)
}

/// A tip force of magnitude `f` at any angle, angle-preserving in 30 %.
fn tip_force(rng: &mut Rng, f: f64) -> TipForce {
    let beta = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
    if rng.unit() < 0.3 {
        TipForce::ap(f, beta)
    } else {
        TipForce::dp(f, beta)
    }
}

/// Loaded in part (s1 in 0.5..1) in 30 %.
fn partly_loaded(rng: &mut Rng, loads: &mut Loads) {
    if rng.unit() < 0.3 {
        loads.s1 = rng.range(0.5, 1.0);
    }
}

/// The estimates of `accurate` (default tolerance: a search shot at 1e-10 against the
/// dense shot at 1e-12) and of `auto` asked for 1e-4..1e-12 (stage 2 at the asked accuracy
/// against the dense shot a hundred times tighter) bound their errors against `accurate`
/// at 1e-14 (whose estimate comes from a check shot), on seeded scenes over the command
/// line's space: theta 0.05..1, A, B within ±2, k 1..50 or rigid, DP/AP forces up to 20 at
/// any angle, flows up to 20, loaded in part in a third. Where `auto` is asked for 1e-8
/// and answers by shooting, the battery above cannot see the estimate's honesty: it
/// compares with `accurate`'s default, whose error is of the same order. Only answers by
/// shooting count (Picard's are checked above). Returns (scenes compared, worst error /
/// estimate) per method.
fn estimates_bound_errors(seed: u64, n: usize) -> Vec<(usize, f64)> {
    let methods: Vec<Method> = std::iter::once(Method::accurate())
        .chain([1e-4, 1e-6, 1e-8, 1e-10, 1e-12].map(auto))
        .collect();
    let mut rng = Rng(seed);
    let mut out = vec![(0, 0.0_f64); methods.len()];
    let mut evaluations = vec![Vec::new(); methods.len()];
    for case in 0..n {
        let whisker = command_line_whisker(&mut rng);
        let f = if rng.unit() < 0.3 {
            0.0
        } else {
            rng.range(0.0, 20.0)
        };
        let tip = tip_force(&mut rng, f);
        let mut loads = Loads::combined(tip, rng.range(0.0, 20.0), rng.range(-1.5, 1.5));
        partly_loaded(&mut rng, &mut loads);
        let scene = Scene::new(whisker, loads);
        let Some(truth) = truth_of(&scene) else {
            continue;
        };
        if truth.stats.method_used != MethodKind::Accurate {
            continue;
        }
        for ((m, (cases, worst)), spent) in methods
            .iter()
            .zip(out.iter_mut())
            .zip(evaluations.iter_mut())
        {
            // a refusal is an answer too (no numbers, so never a wrong one)
            let Ok(sol) = solve(&scene, m) else {
                continue;
            };
            if sol.stats.method_used != MethodKind::Accurate {
                continue;
            }
            *cases += 1;
            spent.push(sol.stats.evaluations);
            let err = sol.difference(&truth);
            let ratio = err / (sol.stats.error_estimate + truth.stats.error_estimate);
            assert!(
                ratio <= 1.0,
                "case {case} ({scene:?}) by {m:?}: error {err:e} > estimate {:e} (+ {:e})",
                sol.stats.error_estimate,
                truth.stats.error_estimate
            );
            *worst = worst.max(ratio);
        }
    }
    for ((m, (cases, worst)), spent) in methods.iter().zip(&out).zip(&evaluations) {
        println!(
            "{m:?}: {cases} scenes by shooting, worst error / estimate {worst:.3}, \
             median {} evaluations",
            {
                let mut v = spent.clone();
                v.sort_unstable();
                v.get(v.len() / 2).copied().unwrap_or(0)
            }
        );
    }
    out
}

#[test]
fn estimates_of_accurate_and_auto_bound_their_errors() {
    for (cases, _) in estimates_bound_errors(0x5EED_E571, 40) {
        assert!(cases >= 25, "only {cases} scenes answered by shooting");
    }
}

/// The same on 1000 scenes (~1 min in release; measured: ~820 scenes by shooting per
/// method, worst error / estimate 0.56):
/// `cargo test --release -p beam-model --test it -- auto:: --ignored --nocapture`.
#[test]
#[ignore]
fn estimates_of_accurate_and_auto_bound_their_errors_wide() {
    for (cases, _) in estimates_bound_errors(0xE571_2026, 1000) {
        assert!(cases >= 700, "only {cases} scenes answered by shooting");
    }
}

/// Linear theory's answers (`auto`'s first rung, `stats.model_used` linear) on seeded weak
/// loads over the command line's space (theta 0.05..1, A, B within ±2, k 1..50 or rigid,
/// DP/AP forces and flows of magnitudes log-uniform in 1e-6..1 at any angle, loaded in part
/// in a third), asked for 1e-2 .. 1e-10: each has its true error (against `accurate` at
/// 1e-14, plus that one's estimate) within its estimate, and its estimate within the
/// accuracy asked for; every other answer is within the accuracy asked for as well.
/// Returns, per accuracy, the scenes answered by linear theory and the worst true error /
/// estimate among them.
fn linear_answers(seed: u64, n: usize) -> Vec<(f64, usize, f64)> {
    let tols: Vec<f64> = (2..=10).map(|e| 10f64.powi(-e)).collect();
    let mut out: Vec<(f64, usize, f64)> = tols.iter().map(|&t| (t, 0, 0.0)).collect();
    let mut rng = Rng(seed);
    let weak = |rng: &mut Rng| 10f64.powf(rng.range(-6.0, 0.0));
    for case in 0..n {
        let whisker = command_line_whisker(&mut rng);
        let f = if rng.unit() < 0.3 {
            0.0
        } else {
            weak(&mut rng)
        };
        let tip = tip_force(&mut rng, f);
        let q = if rng.unit() < 0.2 {
            0.0
        } else {
            weak(&mut rng)
        };
        let alpha = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
        let mut loads = Loads::combined(tip, q, alpha);
        partly_loaded(&mut rng, &mut loads);
        let scene = Scene::new(whisker, loads);
        let Some(truth) = truth_of(&scene) else {
            continue;
        };
        let slack = truth.stats.error_estimate;
        for (tol, count, worst) in out.iter_mut() {
            let Ok(sol) = solve(&scene, &auto(*tol)) else {
                continue;
            };
            let err = sol.difference(&truth);
            let est = sol.stats.error_estimate;
            assert!(
                err <= *tol + slack && est <= *tol,
                "case {case} ({scene:?}) at {tol:e}: error {err:e}, estimate {est:e} ({:?})",
                sol.stats
            );
            if sol.stats.model_used == ModelKind::Linear {
                assert_eq!(sol.stats.method_used, MethodKind::Picard);
                assert!(
                    err <= est + slack,
                    "case {case} ({scene:?}) at {tol:e}: linear error {err:e} > estimate {est:e}"
                );
                *count += 1;
                *worst = worst.max(err / est);
            }
        }
    }
    for (tol, count, worst) in &out {
        println!(
            "T {tol:e}: {count} of {n} scenes by linear theory, worst error / estimate {worst:.3}"
        );
    }
    out
}

/// 2000 scenes, under a second (measured: 1621 scenes answered by linear theory at 1e-2,
/// 1215 at 1e-4, 577 at 1e-8, 335 at 1e-10; worst error / estimate 0.83).
#[test]
fn linear_answers_are_within_their_estimates() {
    let out = linear_answers(0x11AE_2026, 2000);
    // weak loads: linear theory answers a loose accuracy often, a tight one less often
    assert!(out[0].1 >= 1500 && out[8].1 >= 200, "{out:?}");
    assert!(out.iter().all(|o| o.2 <= 1.0), "{out:?}");
}

/// The reference of the estimate batteries: `accurate` at 1e-14 (`None` where it fails).
fn truth_of(scene: &Scene) -> Option<beam_model::Solution> {
    let tight = Method::Accurate {
        tol: 1e-14,
        samples: 100,
    };
    solve(scene, &tight).ok()
}

/// The space of [`ap_soft_springs`]: springs `k` log-uniform in `k`, AP forces uniform in
/// `f`, at `|beta|` uniform in 60..90 degrees.
struct ApSpace {
    k: (f64, f64),
    f: (f64, f64),
}

/// The space of issue 34's first batteries: k in [0.5, 5], f in [0.5, 10].
const AP_SPACE: ApSpace = ApSpace {
    k: (0.5, 5.0),
    f: (0.5, 10.0),
};

/// Issue 34's widened space: k in [0.2, 5], f in [0.5, 15].
const AP_SPACE_WIDE: ApSpace = ApSpace {
    k: (0.2, 5.0),
    f: (0.5, 15.0),
};

/// Issue 34, item 3: angle-preserving tip forces on soft springs (`space`: k log-uniform,
/// f uniform) at large |beta| (60..90 degrees, either sign), tapered and pre-curved
/// whiskers, with flows in half the scenes and loaded in part in a fifth. Every answer of
/// `auto` at 1e-4, 1e-6, 1e-8 of the scenes numbered `cases` (of the seeded sequence) is
/// checked against an independent tight solve by another method: RK4 shooting on 4000
/// steps (its own estimate, from 8000, below 1e-11), itself confirmed by `accurate` at
/// 1e-14 to 1e-9 (scenes where the two land on different equilibria are skipped and
/// counted). Its error must lie within its estimate (plus the reference's) and within the
/// accuracy asked for. Returns (answers compared, worst error / estimate, worst error / tol).
fn ap_soft_springs(seed: u64, space: &ApSpace, cases: std::ops::Range<usize>) -> (usize, f64, f64) {
    let mut rng = Rng(seed);
    let (mut answers, mut worst_est, mut worst_tol, mut skipped) = (0, 0.0f64, 0.0f64, 0);
    let mut worst_at = String::new();
    for case in 0..cases.end {
        let theta = rng.range(0.2, 1.0);
        let (a, b) = (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let k = (rng.range(space.k.0.ln(), space.k.1.ln())).exp();
        let f = rng.range(space.f.0, space.f.1);
        let sign = if rng.unit() < 0.5 { -1.0 } else { 1.0 };
        let beta = sign * rng.range(60.0, 90.0).to_radians();
        let q = if rng.unit() < 0.5 {
            0.0
        } else {
            rng.range(0.0, 5.0)
        };
        let mut loads = Loads::combined(TipForce::ap(f, beta), q, rng.range(-1.5, 1.5));
        if rng.unit() < 0.2 {
            loads.s1 = rng.range(0.5, 1.0);
        }
        if case < cases.start {
            continue;
        }
        let scene = Scene::new(Whisker::new(theta, a, b, k), loads);
        let Ok(truth) = solve(&scene, &Method::Rk4 { n: 4000 }) else {
            skipped += 1;
            continue;
        };
        let same = truth_of(&scene).is_some_and(|t| t.difference(&truth) < 1e-9);
        if truth.stats.error_estimate > 1e-11 || !same {
            skipped += 1;
            continue;
        }
        for tol in [1e-4, 1e-6, 1e-8] {
            let Ok(sol) = solve(&scene, &auto(tol)) else {
                continue;
            };
            answers += 1;
            let err = sol.difference(&truth);
            let est = sol.stats.error_estimate;
            assert!(
                err <= est + truth.stats.error_estimate && est <= tol,
                "case {case} ({scene:?}) at {tol:e}: error {err:e}, estimate {est:e} ({})",
                sol.stats.method_used.name()
            );
            if err / est > worst_est {
                worst_est = err / est;
                worst_at = format!("case {case} at {tol:e} by {}", sol.stats.method_used.name());
            }
            worst_tol = worst_tol.max(err / tol);
        }
    }
    println!(
        "AP soft springs: {answers} answers compared ({skipped} scenes skipped: no tight reference or two equilibria); worst error / estimate {worst_est:.3} ({worst_at}), worst error / tol {worst_tol:.3}"
    );
    (answers, worst_est, worst_tol)
}

/// The scene: `solve --a -0.0058 --b 0.2905 --k 2 --f 7.3596 --beta-deg -89.3414
/// --load ap --tol 1e-6` answered Ay = -0.5579378350 with an estimate of 4.05e-7, where
/// `accurate`, `rk4` and `fdm-richardson` agree on -0.5579330935 (error 4.7e-6).
#[test]
fn an_ap_force_on_a_soft_spring_meets_the_accuracy_asked_for() {
    let scene = Scene::new(
        Whisker::new(1.0, -0.0058, 0.2905, 2.0),
        Loads::tip(TipForce::ap(7.3596, (-89.3414f64).to_radians())),
    );
    let truth = solve(&scene, &Method::Rk4 { n: 4000 }).unwrap();
    assert!(truth.stats.error_estimate < 1e-11);
    for tol in [1e-4, 1e-6, 1e-8] {
        let sol = solve(&scene, &auto(tol)).unwrap();
        let err = sol.difference(&truth);
        assert!(
            err <= sol.stats.error_estimate + truth.stats.error_estimate
                && sol.stats.error_estimate <= tol,
            "at {tol:e}: Ay {} vs {}, error {err:e}, estimate {:e} ({})",
            sol.base.ay,
            truth.base.ay,
            sol.stats.error_estimate,
            sol.stats.method_used.name()
        );
    }
}

/// Case 90 of the 300-scene run (theta 0.978, A 0.644, B 0.336, k 0.545, AP f 3.52 at
/// beta -82.0 degrees, no flow): `auto` at 1e-6 answered from a dense shot at 1e-8 of 3
/// DOP853 steps with an error of 2.0e-6 (`Ax`) under an estimate of 6.0e-7 from stage 2's
/// shot at 1e-6, whose error was as large (a few large steps: the global error does not
/// scale with the tolerance, module `accurate`, `ASYMPTOTIC_STEPS`). At every accuracy
/// from 1e-4 to 1e-8 the error now lies within the estimate, itself within the accuracy.
#[test]
fn an_ap_force_on_a_very_soft_spring_meets_the_accuracy_asked_for() {
    let scene = Scene::new(
        Whisker::new(
            0.9783224388196412,
            0.6443987228592805,
            0.3360533451296168,
            0.5446785868752674,
        ),
        Loads::tip(TipForce::ap(3.5249865454096883, -1.4304555629011306)),
    );
    let truth = solve(&scene, &Method::Rk4 { n: 4000 }).unwrap();
    assert!(truth.stats.error_estimate < 1e-11);
    // confirmed by another method
    let tight = truth_of(&scene).unwrap();
    assert!(tight.difference(&truth) < 1e-10);
    for tol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
        let sol = solve(&scene, &auto(tol)).unwrap();
        let err = sol.difference(&truth);
        let est = sol.stats.error_estimate;
        assert!(
            err <= est + truth.stats.error_estimate && est <= tol,
            "at {tol:e}: Ax {} vs {}, error {err:e}, estimate {est:e} ({})",
            sol.base.ax,
            truth.base.ax,
            sol.stats.method_used.name()
        );
    }
}

/// 24 scenes of [`AP_SPACE`] (measured: 69 answers, worst error / estimate 0.42, worst
/// error / tol 0.36), and cases 84..96 of the 300-scene run, case 90 among them.
#[test]
fn ap_forces_on_soft_springs_meet_the_accuracy_asked_for() {
    let (answers, _, _) = ap_soft_springs(0x5EED_0034, &AP_SPACE, 0..24);
    assert!(answers >= 45, "only {answers} answers compared");
    let (answers, _, _) = ap_soft_springs(0xA9_0034, &AP_SPACE, 84..96);
    assert!(answers >= 24, "only {answers} answers compared");
}

/// The same on 300 scenes: `cargo test --release -p beam-model --test it -- auto:: --ignored
/// --nocapture`. Measured: 780 answers compared (40 scenes skipped), worst error /
/// estimate 0.49 (case 152 at 1e-8), worst error / tol 0.34. Before the fix of
/// `ASYMPTOTIC_STEPS` (module `accurate`) it failed at case 90 (theta 0.978, A 0.644,
/// B 0.336, k 0.545, AP f 3.52 at beta -82.0 degrees) at 1e-6: error 2.0e-6 under an
/// estimate of 6.0e-7.
#[test]
#[ignore = "300 scenes, about a minute; run with --ignored"]
fn ap_forces_on_soft_springs_meet_the_accuracy_asked_for_wide() {
    let (answers, worst_est, worst_tol) = ap_soft_springs(0xA9_0034, &AP_SPACE, 0..300);
    assert!(answers >= 600, "only {answers} answers compared");
    assert!(worst_est < 1.0 && worst_tol < 1.0);
}

/// Issue 34's widened space ([`AP_SPACE_WIDE`]: springs down to k = 0.2, forces up to
/// f = 15), 300 scenes: `cargo test --release -p beam-model --test it -- auto:: --ignored
/// --nocapture wider`.
#[test]
#[ignore = "300 scenes, about a minute; run with --ignored"]
fn ap_forces_on_softer_springs_meet_the_accuracy_asked_for_wider() {
    let (answers, worst_est, worst_tol) = ap_soft_springs(0x3A9_0034, &AP_SPACE_WIDE, 0..300);
    assert!(answers >= 500, "only {answers} answers compared");
    assert!(worst_est < 1.0 && worst_tol < 1.0);
}
