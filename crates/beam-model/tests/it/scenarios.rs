//! Every thesis load scenario (1-18, AP included) solves with every method, and the methods
//! agree with each other as the grid is refined.

use beam_model::{scenarios, solve, Method};

#[test]
fn all_eighteen_scenarios_solve_with_every_method() {
    let mut count = 0;
    for sc in scenarios::all() {
        assert!(!sc.cases.is_empty(), "scenario {} has no cases", sc.id);
        for case in &sc.cases {
            let acc = solve(&case.scene, &Method::accurate())
                .unwrap_or_else(|e| panic!("scenario {} {}: accurate: {e}", sc.id, case.label));
            for method in [Method::Rk4 { n: 100 }, Method::Fdm { n: 100 }] {
                let sol = solve(&case.scene, &method).unwrap_or_else(|e| {
                    panic!("scenario {} {}: {}: {e}", sc.id, case.label, method.name())
                });
                // the thesis grid h = 0.01 is within 2e-2 of the exact tip everywhere
                let err = (sol.tip.x - acc.tip.x).hypot(sol.tip.y - acc.tip.y);
                assert!(
                    err < 2e-2,
                    "scenario {} {}: {} differs from accurate by {err:e}",
                    sc.id,
                    case.label,
                    method.name()
                );
            }
            count += 1;
        }
    }
    assert!(count > 200, "only {count} cases");
}

#[test]
fn methods_agree_as_the_grid_is_refined() {
    for (name, scene) in scenarios::reference_scenes() {
        let acc = solve(&scene, &Method::accurate()).unwrap();
        let mut prev = [f64::INFINITY; 2];
        for n in [50, 200, 800] {
            for (k, method) in [Method::Fdm { n }, Method::Rk4 { n }].iter().enumerate() {
                let s = solve(&scene, method).unwrap();
                let err = (s.tip.x - acc.tip.x).hypot(s.tip.y - acc.tip.y);
                assert!(
                    err < prev[k] / 3.0,
                    "{name} {} n={n}: {err:e}",
                    method.name()
                );
                prev[k] = err;
            }
        }
        assert!(prev[0] < 1e-5 && prev[1] < 1e-11, "{name}: {prev:?}");
    }
}

#[test]
fn ap_tip_load_bends_past_horizontal_and_solves_by_every_method() {
    // Thesis ch. 4.2.2: the AP tip angle reaches its minimum -pi/2 near f = 15, then the
    // whisker coils further and the tip angle turns back (at f = 30 it is near 0 again).
    let mut tip = Vec::new();
    for f in [1.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0] {
        let scene = beam_model::Scene::new(
            beam_model::Whisker::uniform(),
            beam_model::Loads::tip(beam_model::TipForce::ap(f, 0.0)),
        );
        let acc = solve(&scene, &Method::accurate()).unwrap();
        tip.push(acc.tip.phi);
        let fdm = solve(&scene, &Method::Fdm { n: 400 }).unwrap();
        assert!((fdm.tip.phi - acc.tip.phi).abs() < 1e-2, "f={f}");
    }
    let (imin, min) =
        tip.iter().enumerate().fold(
            (0, f64::INFINITY),
            |a, (i, &p)| if p < a.1 { (i, p) } else { a },
        );
    assert_eq!(imin, 3, "minimum at f = 15: {tip:?}");
    assert!((min + std::f64::consts::FRAC_PI_2).abs() < 0.05, "{min}");
    assert!(tip[..4].windows(2).all(|w| w[1] < w[0]) && tip[3..].windows(2).all(|w| w[1] > w[0]));
}
