//! The forward solver against independent truth: Mattiasson's elliptic-integral solution,
//! the linear limit, load-free arcs and Euler spirals, balance of forces and moments, and
//! the convergence of the fixed-step methods.

use crate::support;

use beam_model::{solve, Loads, Method, ModelError, Scene, Support, TipForce, Whisker};
use std::f64::consts::FRAC_PI_2;
use support::{mattiasson, simpson};

fn tip_scene(f: f64) -> Scene {
    Scene::new(Whisker::uniform(), Loads::tip(TipForce::dp(f, 0.0)))
}

/// Mattiasson's table (spec/model.md), five digits.
const MATTIASSON: [(f64, f64, f64); 4] = [
    (1.0, 0.30172, 0.94357),
    (2.0, 0.49346, 0.83936),
    (5.0, 0.71379, 0.61237),
    (10.0, 0.81061, 0.44500),
];

#[test]
fn elliptic_reference_reproduces_the_published_table() {
    for (f, x1, y1) in MATTIASSON {
        let (x, y, _) = mattiasson(f);
        assert!(
            (x - x1).abs() < 6e-6 && (y - y1).abs() < 6e-6,
            "f={f}: {x} {y}"
        );
    }
    let (_, _, t) = mattiasson(1.0);
    assert!((t - 0.46135).abs() < 6e-6);
}

#[test]
fn accurate_matches_mattiasson_to_1e9() {
    for f in [0.5, 1.0, 2.0, 5.0, 10.0, 20.0] {
        let sol = solve(&tip_scene(f), &Method::accurate()).unwrap();
        let (x1, y1, t) = mattiasson(f);
        let ex = (sol.tip.x - x1).abs();
        let ey = (sol.tip.y - y1).abs();
        let et = ((FRAC_PI_2 - sol.tip.phi) - t).abs();
        assert!(
            ex < 1e-9 && ey < 1e-9 && et < 1e-9,
            "f={f}: {ex:e} {ey:e} {et:e}"
        );
    }
}

#[test]
fn every_method_matches_mattiasson_to_five_digits_on_a_fine_grid() {
    for method in [
        Method::Fdm { n: 2000 },
        Method::Rk4 { n: 200 },
        Method::accurate(),
    ] {
        for (f, x1, y1) in MATTIASSON {
            let sol = solve(&tip_scene(f), &method).unwrap();
            assert!(
                (sol.tip.x - x1).abs() < 1e-5 && (sol.tip.y - y1).abs() < 1e-5,
                "{} f={f}: ({}, {})",
                method.name(),
                sol.tip.x,
                sol.tip.y
            );
        }
    }
}

#[test]
fn small_loads_follow_linear_theory() {
    // Tip load: x1 = f/3, tip rotation f/2; fluid load: x1 = q/8, rotation q/6.
    let eps = 1e-4;
    let sol = solve(&tip_scene(eps), &Method::accurate()).unwrap();
    assert!((sol.tip.x / eps - 1.0 / 3.0).abs() < 1e-4);
    assert!(((FRAC_PI_2 - sol.tip.phi) / eps - 0.5).abs() < 1e-4);
    let fluid = Scene::new(Whisker::uniform(), Loads::fluid(eps, 0.0));
    let sol = solve(&fluid, &Method::accurate()).unwrap();
    assert!((sol.tip.x / eps - 1.0 / 8.0).abs() < 1e-4);
    assert!(((FRAC_PI_2 - sol.tip.phi) / eps - 1.0 / 6.0).abs() < 1e-4);
}

#[test]
fn unloaded_whiskers_are_straight_arcs_and_euler_spirals() {
    for method in [
        Method::accurate(),
        Method::Rk4 { n: 100 },
        Method::Fdm { n: 100 },
    ] {
        let straight = solve(&Scene::default(), &method).unwrap();
        assert!(straight.tip.x.abs() < 1e-14 && (straight.tip.y - 1.0).abs() < 1e-12);
    }
    // Circular arc: phi = pi/2 + B s.
    let b = 1.5;
    let w = Whisker {
        b,
        ..Whisker::uniform()
    };
    let sol = solve(&Scene::new(w, Loads::none()), &Method::accurate()).unwrap();
    assert!((sol.tip.x - (b.cos() - 1.0) / b).abs() < 1e-12);
    assert!((sol.tip.y - b.sin() / b).abs() < 1e-12);
    // Euler spiral: phi = pi/2 + A s^2/2 (Fresnel integrals by Simpson quadrature).
    let a = -3.0;
    let w = Whisker {
        a,
        ..Whisker::uniform()
    };
    let sol = solve(&Scene::new(w, Loads::none()), &Method::accurate()).unwrap();
    let x = simpson(|s| -(0.5 * a * s * s).sin(), 0.0, 1.0, 20000);
    let y = simpson(|s| (0.5 * a * s * s).cos(), 0.0, 1.0, 20000);
    assert!((sol.tip.x - x).abs() < 1e-12 && (sol.tip.y - y).abs() < 1e-12);
}

/// Moment balance about the base: m(0) = (r(s1) - r0) x F + int_0^s1 (r - r0) x Q ds.
fn moment_balance_residual(scene: &Scene) -> f64 {
    let method = Method::Accurate {
        tol: 1e-12,
        samples: 4000,
    };
    let sol = solve(scene, &method).unwrap();
    let l = &scene.loads;
    let beta = l.tip.effective_beta(sol.loaded_end.phi);
    let (fx, fy) = (l.tip.f * beta.cos(), -l.tip.f * beta.sin());
    let (qx, qy) = (
        l.fluid.q * l.fluid.alpha.cos(),
        -l.fluid.q * l.fluid.alpha.sin(),
    );
    let el = &sol.elastica;
    // Simpson over the samples on [0, s1] (uniform spacing 1/4000, s1 = 1 here).
    let n = el.len() - 1;
    let h = 1.0 / n as f64;
    let mut integral = 0.0;
    for i in 0..=n {
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        integral += w * (el.x[i] * qy - el.y[i] * qx);
    }
    integral *= h / 3.0;
    let moment = sol.loaded_end.x * fy - sol.loaded_end.y * fx + integral;
    // m(s) = sum over the loads beyond s of (r_load - r(s)) x F, and MA = -m(0)
    (-sol.base.ma - moment).abs()
}

#[test]
fn forces_and_moments_balance() {
    let scenes = beam_model::scenarios::reference_scenes();
    for (name, scene) in scenes.iter() {
        let r = moment_balance_residual(scene);
        assert!(r < 1e-9, "{name}: moment balance residual {r:e}");
        let sol = solve(scene, &Method::accurate()).unwrap();
        // Force balance: reactions equal minus the applied loads.
        let l = &scene.loads;
        let beta = l.tip.effective_beta(sol.loaded_end.phi);
        let sum_x = sol.base.ax + l.tip.f * beta.cos() + l.fluid.q * l.s1 * l.fluid.alpha.cos();
        let sum_y = sol.base.ay - l.tip.f * beta.sin() - l.fluid.q * l.s1 * l.fluid.alpha.sin();
        assert!(sum_x.abs() < 1e-14 && sum_y.abs() < 1e-14);
    }
}

#[test]
fn spring_support_satisfies_its_robin_condition() {
    for method in [
        Method::accurate(),
        Method::Rk4 { n: 100 },
        Method::Fdm { n: 400 },
    ] {
        let w = Whisker {
            support: Support::Spring { k: 5.0 },
            theta: 0.6,
            a: 1.0,
            b: -0.5,
        };
        let sol = solve(&Scene::new(w, Loads::fluid(10.0, 0.0)), &method).unwrap();
        let m0 = -sol.base.ma;
        let r = sol.base.phi0 - FRAC_PI_2 - m0 / 5.0;
        // FDM reports MA from the moment equation (trapezoidal), consistent with its discrete
        // Robin condition to O(h^2) = 1e-5 at n = 400; shooting satisfies it exactly.
        let tol = if method.name() == "fdm" { 1e-5 } else { 1e-11 };
        assert!(r.abs() < tol, "{}: {r:e}", method.name());
    }
}

/// Least-squares slope of log(err) against log(h).
fn order(hs: &[f64], errs: &[f64]) -> f64 {
    let n = hs.len() as f64;
    let lx: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ly: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[test]
fn fixed_step_methods_converge_at_their_orders() {
    for (name, scene) in beam_model::scenarios::reference_scenes() {
        let exact = solve(
            &scene,
            &Method::Accurate {
                tol: 1e-13,
                samples: 10,
            },
        )
        .unwrap();
        let ns = [40usize, 80, 160, 320];
        let hs: Vec<f64> = ns.iter().map(|&n| 1.0 / n as f64).collect();
        for (label, make, expected) in [
            ("fdm", (|n| Method::Fdm { n }) as fn(usize) -> Method, 2.0),
            ("rk4", |n| Method::Rk4 { n }, 4.0),
        ] {
            let errs: Vec<f64> = ns
                .iter()
                .map(|&n| {
                    let s = solve(&scene, &make(n)).unwrap();
                    (s.tip.x - exact.tip.x).hypot(s.tip.y - exact.tip.y)
                })
                .collect();
            let p = order(&hs, &errs);
            assert!(
                (p - expected).abs() < 0.25,
                "{name} {label}: order {p:.3} errs {errs:?}"
            );
        }
    }
}

#[test]
fn bad_parameters_are_named() {
    let cases = [
        (
            Whisker {
                theta: 0.0,
                ..Whisker::uniform()
            },
            Loads::none(),
            "theta",
        ),
        (
            Whisker {
                theta: f64::NAN,
                ..Whisker::uniform()
            },
            Loads::none(),
            "theta",
        ),
        (
            Whisker {
                support: Support::Spring { k: -1.0 },
                ..Whisker::uniform()
            },
            Loads::none(),
            "k",
        ),
        (
            Whisker::uniform(),
            Loads::tip(TipForce::dp(f64::NAN, 0.0)),
            "f",
        ),
        (Whisker::uniform(), Loads::fluid(-2.0, 0.0), "q"),
    ];
    for (w, l, name) in cases {
        match solve(&Scene::new(w, l), &Method::accurate()) {
            Err(ModelError::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("expected InvalidParameter({name}), got {other:?}"),
        }
    }
    assert!(Support::from_stiffness(0.0).is_err());
    assert_eq!(
        Support::from_stiffness(f64::INFINITY).unwrap(),
        Support::Rigid
    );
}

#[test]
fn beta_whisker_force_scale_matches_the_thesis() {
    let w = beam_model::Preset::Beta.whisker();
    assert!(
        (w.force_scale() - 4.019e-5).abs() < 5e-9,
        "{}",
        w.force_scale()
    );
    // Remark 4.2: f = 40 is 1.607578e-3 N
    assert!((40.0 * w.force_scale() - 1.607578e-3).abs() < 2e-7);
    let f = w.dimensionless_force(1.607578e-3);
    assert!((f - 40.0).abs() < 5e-3);
}

#[test]
fn fdm_richardson_reaches_shooting_accuracy_and_rescues_thin_tips() {
    // Where shooting works, FDM + two Richardson levels (order 6) agrees with it.
    for (name, scene) in beam_model::scenarios::reference_scenes() {
        let a = solve(&scene, &Method::accurate()).unwrap();
        let r = beam_model::methods::fdm_richardson(&scene).unwrap();
        let d = (a.tip.x - r.tip.x).abs().max((a.tip.y - r.tip.y).abs());
        assert!(d < 1e-9, "{name}: {d:e}");
        assert!((a.base.ma - r.base.ma).abs() < 1e-8, "{name}");
    }
    // A thin tip under a large tip load: single shooting is ill-conditioned there;
    // `accurate` falls back to FDM + Richardson and agrees with a fine plain FDM.
    let w = Whisker {
        theta: 0.15,
        ..Whisker::uniform()
    };
    let scene = Scene::new(w, Loads::tip(TipForce::dp(30.0, 0.0)));
    let acc = solve(&scene, &Method::accurate()).unwrap();
    let fine = solve(&scene, &Method::Fdm { n: 6400 }).unwrap();
    let d = (acc.tip.x - fine.tip.x).hypot(acc.tip.y - fine.tip.y);
    assert!(d < 1e-5, "{d:e}");
}

#[test]
fn fdm_richardson_converges_at_order_six() {
    for (name, scene) in beam_model::scenarios::reference_scenes() {
        let exact = solve(
            &scene,
            &Method::Accurate {
                tol: 1e-14,
                samples: 10,
            },
        )
        .unwrap();
        let ns = [20usize, 40, 80];
        let hs: Vec<f64> = ns.iter().map(|&n| 1.0 / n as f64).collect();
        let errs: Vec<f64> = ns
            .iter()
            .map(|&n| {
                let s = solve(&scene, &Method::FdmRichardson { n }).unwrap();
                (s.tip.x - exact.tip.x).hypot(s.tip.y - exact.tip.y)
            })
            .collect();
        let p = order(&hs, &errs);
        eprintln!("{name}: order {p:.3}, errors {errs:?}");
        assert!((p - 6.0).abs() < 0.5, "{name}: order {p:.3} errs {errs:?}");
    }
}

/// Under a strong tip force the tip aligns with it on more than one branch (the tip angle
/// alike); each solve from scratch must stay on the branch connected to the unloaded whisker,
/// along which the base angle falls steadily with the force (theta = 0.4 on a spring k = 5,
/// DP force along +x: from f ~ 26 on another branch with the base turned the other way,
/// phi0 ~ 2, is near).
#[test]
fn a_strong_force_stays_on_the_branch_from_the_unloaded_whisker() {
    let w = Whisker::new(0.4, 0.0, 0.0, 5.0);
    let mut prev = FRAC_PI_2;
    for i in 1..=20 {
        let f = 2.0 * i as f64;
        let sol = solve(
            &Scene::new(w, Loads::tip(TipForce::dp(f, 0.0))),
            &Method::accurate(),
        )
        .unwrap();
        assert!(
            sol.base.phi0 < prev && sol.base.phi0 > 0.5,
            "f = {f}: phi0 {} after {prev}",
            sol.base.phi0
        );
        prev = sol.base.phi0;
    }
}
