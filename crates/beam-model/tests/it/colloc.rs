//! Collocation as a rung of `auto` (issue #36 item 5).
//!
//! `colloc_rung_measure` (#[ignore], a diagnostic): on the tip-force cases of the slender
//! battery (`tests/battery.rs`), `auto` at 1e-8 against `collocation` at 1e-8 on its own:
//! the time of each solve, the method `auto` used, both estimates and their difference
//! (two independent discretisations), with the growth exponent `sqrt(f) / theta` of the
//! tip's boundary layer that `auto`'s rule reads (`docs/bvp-auto.md`):
//! `cargo test --release -p beam-model --test it -- colloc_rung_measure --ignored --nocapture`.

use beam_model::{solve, Loads, Method, Scene, Solution, TipForce, Whisker};
use std::time::Instant;

fn deg(d: f64) -> f64 {
    d.to_radians()
}

fn timed(scene: &Scene, method: &Method) -> (Result<Solution, String>, f64) {
    let t0 = Instant::now();
    let r = solve(scene, method).map_err(|e| e.to_string());
    (r, t0.elapsed().as_secs_f64())
}

fn describe(r: &Result<Solution, String>) -> String {
    match r {
        Ok(s) => format!(
            "{} est {:.1e} evals {}",
            s.stats.method_used.name(),
            s.stats.error_estimate,
            s.stats.evaluations
        ),
        Err(e) => format!("ERR {}", e.chars().take(90).collect::<String>()),
    }
}

#[test]
#[ignore = "a diagnostic of minutes; run with --ignored --nocapture"]
fn colloc_rung_measure() {
    let loads: Vec<(&str, Loads)> = vec![
        ("f=1", Loads::tip(TipForce::dp(1.0, 0.0))),
        ("f=5", Loads::tip(TipForce::dp(5.0, 0.0))),
        ("f=20", Loads::tip(TipForce::dp(20.0, 0.0))),
        ("f=10,b=-60", Loads::tip(TipForce::dp(10.0, deg(-60.0)))),
        (
            "f=5,b=30,q=5",
            Loads::combined(TipForce::dp(5.0, deg(30.0)), 5.0, 0.0),
        ),
        ("ap f=5", Loads::tip(TipForce::ap(5.0, 0.0))),
    ];
    let supports = [
        ("rigid", 0.0, 0.0, f64::INFINITY),
        ("k=10", 0.0, 0.0, 10.0),
        ("A=2,B=-1,k=20", 2.0, -1.0, 20.0),
    ];
    let thetas: Vec<f64> = std::env::var("COLLOC_THETAS")
        .ok()
        .map(|s| s.split(',').map(|t| t.parse().unwrap()).collect())
        .unwrap_or_else(|| vec![0.01, 0.015, 0.02, 0.03, 0.05, 0.1]);
    let tol = 1e-8;
    println!("theta | support | load | sqrt(f)/theta | auto s | auto | colloc s | colloc | |auto-colloc|");
    for &theta in &thetas {
        for (sn, a, b, k) in supports {
            for (ln, l) in &loads {
                let scene = Scene::new(Whisker::new(theta, a, b, k), *l);
                let g = l.tip.f.sqrt() / theta;
                let (ra, ta) = timed(&scene, &Method::Auto { tol, samples: 100 });
                let (rc, tc) = timed(&scene, &Method::Collocation { tol, samples: 100 });
                let d = match (&ra, &rc) {
                    (Ok(x), Ok(y)) => format!("{:.1e}", x.difference(y)),
                    _ => "-".into(),
                };
                println!(
                    "{theta} | {sn} | {ln} | {g:.0} | {ta:.3} | {} | {tc:.3} | {} | {d}",
                    describe(&ra),
                    describe(&rc)
                );
            }
        }
    }
}

/// `auto` on slender whiskers under direction-preserving tip forces (growth exponent
/// `sqrt(f) / theta` above `COLLOCATION_GROWTH`) answers by collocation, its estimate
/// within the tolerance and bounding its error against FDM + two Richardson levels on
/// 3200..12800 intervals (an independent discretisation, its own estimate added).
#[test]
fn auto_answers_slender_tip_forces_by_collocation_within_its_estimate() {
    let cases = [
        (0.01, f64::INFINITY, TipForce::dp(5.0, 0.0)),
        (0.02, 20.0, TipForce::dp(10.0, deg(-60.0))),
    ];
    for (theta, k, force) in cases {
        let scene = Scene::new(Whisker::new(theta, 0.0, 0.0, k), Loads::tip(force));
        let tol = 1e-8;
        let sol = solve(&scene, &Method::Auto { tol, samples: 100 }).unwrap();
        assert_eq!(sol.stats.method_used.name(), "collocation", "theta {theta}");
        let r = solve(&scene, &Method::FdmRichardson { n: 3200 }).unwrap();
        let err = sol.difference(&r);
        println!(
            "theta {theta}: error {err:.1e}, estimate {:.1e}, reference estimate {:.1e}",
            sol.stats.error_estimate, r.stats.error_estimate
        );
        assert!(sol.stats.error_estimate <= tol);
        assert!(
            err <= sol.stats.error_estimate + r.stats.error_estimate,
            "theta {theta}: error {err:e} above the estimate {:e} + {:e}",
            sol.stats.error_estimate,
            r.stats.error_estimate
        );
    }
}

/// The rule reads the scene's numbers only: a moderate whisker under a tip force, an
/// angle-preserving force on a thin one and a flow on a thin one keep `auto`'s other rungs.
#[test]
fn auto_keeps_its_other_rungs_outside_the_rule() {
    let cases = [
        Scene::new(
            Whisker::new(0.5, 2.0, -1.0, 20.0),
            Loads::combined(TipForce::dp(5.0, deg(30.0)), 5.0, 0.0),
        ),
        Scene::new(
            Whisker::new(0.3, 0.0, 0.0, f64::INFINITY),
            Loads::tip(TipForce::ap(2.0, 0.0)),
        ),
        Scene::new(
            Whisker::new(0.05, 0.0, 0.0, f64::INFINITY),
            Loads::fluid(5.0, 0.0),
        ),
    ];
    for scene in cases {
        let sol = solve(
            &scene,
            &Method::Auto {
                tol: 1e-8,
                samples: 100,
            },
        )
        .unwrap();
        assert_ne!(sol.stats.method_used.name(), "collocation");
        assert!(sol.stats.error_estimate <= 1e-8);
    }
}

/// The battery's failures (`docs/bvp-auto.md`): an angle-preserving force on `theta = 0.01`
/// winds the tip up (the number of turns `(phi(1) - phi(0)) / 2 pi` against the force),
/// and the compressive combined load on `theta = 0.01`; each by collocation at 1e-8 and by
/// `accurate`, with the error or the load scale where the continuation stopped:
/// `cargo test --release -p beam-model --test it -- colloc_failures --ignored --nocapture`.
#[test]
#[ignore = "a diagnostic of a minute; run with --ignored --nocapture"]
fn colloc_failures() {
    let rigid = Whisker::new(0.01, 0.0, 0.0, f64::INFINITY);
    for f in [0.25, 0.5, 1.0, 2.0, 3.0, 5.0] {
        let scene = Scene::new(rigid, Loads::tip(TipForce::ap(f, 0.0)));
        for (name, m) in [
            (
                "collocation",
                Method::Collocation {
                    tol: 1e-8,
                    samples: 100,
                },
            ),
            ("accurate", Method::accurate()),
        ] {
            let (r, t) = timed(&scene, &m);
            match r {
                Ok(s) => println!(
                    "ap f={f} theta=0.01 rigid {name}: {t:.2} s, turns {:.2}, est {:.1e}",
                    (s.tip.phi - s.base.phi0) / std::f64::consts::TAU,
                    s.stats.error_estimate
                ),
                Err(e) => println!("ap f={f} theta=0.01 rigid {name}: {t:.2} s, {e}"),
            }
        }
    }
    for (sn, k) in [("rigid", f64::INFINITY), ("k=10", 10.0)] {
        let scene = Scene::new(
            Whisker::new(0.01, 0.0, 0.0, k),
            Loads::combined(TipForce::dp(10.0, deg(90.0)), 10.0, deg(-30.0)),
        );
        let (r, t) = timed(
            &scene,
            &Method::Collocation {
                tol: 1e-8,
                samples: 100,
            },
        );
        println!(
            "f=10,b=90,q=10,a=-30 theta=0.01 {sn} collocation: {t:.2} s, {}",
            describe(&r)
        );
    }
}
