//! The studies behind the chapter-4 charts against independent truth: Mattiasson's
//! elliptic-integral solution (the reference of the work-precision errors and the ANSYS
//! table), the theoretical orders of the fixed-step methods, the thesis's printed errors
//! (4.26), and stability maps whose failures are data.

#[path = "../../../crates/beam-model/tests/support/mod.rs"]
mod support;

use beam_model::{scenarios, solve, Loads, Method, ModelError, Scene, TipForce, Whisker};
use support::mattiasson;
use xtask::study::{
    self, ansys_comparison, default_map_methods, observed_orders, stability_map, stability_maps,
    to_csv, work_precision, AnsysLoad, LoadAxis, Outcome, REFERENCE_TOL,
};

#[test]
fn work_precision_has_the_theoretical_orders_and_accurate_reaches_1e10() {
    for (name, scene) in scenarios::reference_scenes() {
        let points = work_precision(&scene, name).unwrap();
        assert_eq!(points.len(), 8 + 8 + 6 + 10 + 5);
        for p in &points {
            assert!(
                p.error.is_finite() && p.seconds > 0.0 && p.evaluations > 0,
                "{p:?}"
            );
            // the norm of the accuracy asked for contains the tip
            assert!(p.tip_error <= p.error, "{p:?}");
            assert_eq!(p.scene, name);
        }
        // the orders in the thesis's measure, the tip error
        let tip: Vec<_> = points
            .iter()
            .map(|p| study::WorkPoint {
                error: p.tip_error,
                ..p.clone()
            })
            .collect();
        // fdm: second order over the whole range (errors 1e-4 .. 1e-8).
        for (n, order) in observed_orders(&tip, "fdm") {
            assert!(
                (order - 2.0).abs() < 0.05,
                "{name} fdm n={n}: order {order}"
            );
        }
        // rk4: fourth order while the error is well above the reference's (~1e-14).
        let rk4: Vec<_> = tip.iter().filter(|p| p.method == "rk4").collect();
        for (w, (n, order)) in rk4.windows(2).zip(observed_orders(&tip, "rk4")) {
            if w[1].error > 1e-11 {
                assert!((order - 4.0).abs() < 0.1, "{name} rk4 n={n}: order {order}");
            }
        }
        // in the norm of the accuracy asked for as well, once asymptotic (n >= 40; measured
        // on the conical scene: 3.81, 3.88 from n = 10, 20)
        for (n, order) in observed_orders(&points, "fdm") {
            assert!((order - 2.0).abs() < 0.05, "{name} fdm n={n}: {order}");
        }
        let rk4: Vec<_> = points.iter().filter(|p| p.method == "rk4").collect();
        for (w, (n, order)) in rk4.windows(2).zip(observed_orders(&points, "rk4")) {
            if n >= 40.0 && w[1].error > 1e-11 {
                assert!((order - 4.0).abs() < 0.1, "{name} rk4 n={n}: {order}");
            }
        }
        let best = points
            .iter()
            .filter(|p| p.method == "accurate")
            .map(|p| p.error)
            .fold(f64::INFINITY, f64::min);
        assert!(best < 1e-10, "{name}: accurate best {best:e}");
        // The automatic choice meets every accuracy asked for (against Mattiasson or the
        // reference solution, ~1e-13).
        for p in points.iter().filter(|p| p.method == "auto") {
            assert!(p.error <= p.setting + 1e-12, "{name}: auto {p:?}");
        }
        let csv = to_csv(&points);
        let mut lines = csv.lines();
        assert_eq!(
            lines.next(),
            Some("method,setting,error,tip_error,seconds,evaluations")
        );
        for (line, p) in lines.zip(&points) {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!(f.len(), 6);
            assert_eq!(f[0], p.method);
            assert_eq!(f[2].parse::<f64>().unwrap(), p.error);
            assert_eq!(f[3].parse::<f64>().unwrap(), p.tip_error);
        }
    }
}

#[test]
fn work_precision_errors_are_errors_against_the_exact_elastica() {
    // Scene 1 (f = 5, beta = 0) has Mattiasson's closed form: the reference is exact to
    // ~1e-13, so every recorded error is the true error of that method.
    let (name, scene) = scenarios::reference_scenes()[0];
    let (x1, y1, _) = mattiasson(5.0);
    let reference = solve(
        &scene,
        &Method::Accurate {
            tol: REFERENCE_TOL,
            samples: 100,
        },
    )
    .unwrap();
    let ref_err = (reference.tip.x - x1)
        .abs()
        .max((reference.tip.y - y1).abs());
    assert!(ref_err < 1e-12, "reference vs Mattiasson: {ref_err:e}");
    let points = work_precision(&scene, name).unwrap();
    for p in points.iter().filter(|p| p.tip_error > 1e-10) {
        let m = match p.method {
            "fdm" => Method::Fdm {
                n: p.setting as usize,
            },
            "rk4" => Method::Rk4 {
                n: p.setting as usize,
            },
            "fdm-richardson" => Method::FdmRichardson {
                n: p.setting as usize,
            },
            "auto" => Method::Auto {
                tol: p.setting,
                samples: 100,
            },
            _ => Method::Accurate {
                tol: p.setting,
                samples: 100,
            },
        };
        let sol = solve(&scene, &m).unwrap();
        let truth = (sol.tip.x - x1).abs().max((sol.tip.y - y1).abs());
        assert!(
            (p.tip_error - truth).abs() <= 1e-12 + 1e-6 * truth,
            "{} {}: {:e} vs {truth:e}",
            p.method,
            p.setting,
            p.tip_error
        );
    }
}

#[test]
fn work_precision_rejects_an_invalid_scene() {
    let scene = Scene::new(Whisker::uniform(), Loads::tip(TipForce::dp(f64::NAN, 0.0)));
    assert!(matches!(
        work_precision(&scene, "bad"),
        Err(ModelError::InvalidParameter { name: "f", .. })
    ));
}

#[test]
fn ansys_table_against_mattiasson_and_the_thesis() {
    let rows = ansys_comparison().unwrap();
    assert_eq!(rows.len(), 10);
    let l_mm = 66.2;
    // f = 1: the published Mattiasson tip (five digits) and the exact one.
    let r = &rows[0];
    assert_eq!((r.load_kind, r.load), (AnsysLoad::Tip, 1.0));
    assert!(
        (r.ours_x1_mm - 0.30172 * l_mm).abs() < 1e-3,
        "{}",
        r.ours_x1_mm
    );
    assert!(
        (r.ours_y1_mm - 0.94357 * l_mm).abs() < 1e-3,
        "{}",
        r.ours_y1_mm
    );
    // f0 = E Ib / L^2 = 4.019e-5 N for the beta whisker (spec/model.md).
    assert!((r.load_si - 4.019e-5).abs() < 1e-8, "{}", r.load_si);
    for r in rows.iter().filter(|r| r.load_kind == AnsysLoad::Tip) {
        let (x1, y1, _) = mattiasson(r.load);
        assert!((r.ours_x1_mm - x1 * l_mm).abs() < 1e-6, "f={}", r.load);
        assert!((r.ours_y1_mm - y1 * l_mm).abs() < 1e-6, "f={}", r.load);
    }
    for (r, &(ex, ey)) in rows.iter().zip(study::PRINTED_ERRORS.iter()) {
        // The transcription reproduces the thesis's own error column (4.26) to its 3
        // decimals, except two printed values that its own columns do not give:
        // q = 1, x1: 0.337 % (0.343 %), q = 10, y1: 1.331 % (1.333 %).
        assert!((r.err_thesis_x_pct - ex).abs() < 7e-3, "{r:?}");
        assert!((r.err_thesis_y_pct - ey).abs() < 7e-3, "{r:?}");
        // Ours against the FEM: within the ~2.6 % the thesis reports for its model.
        assert!(r.err_ours_x_pct < 3.0 && r.err_ours_y_pct < 3.0, "{r:?}");
        // The thesis's model (FDM, h = 0.01) against ours: within 1.5 %.
        let dx = study::error_pct(r.ours_x1_mm, r.thesis_x1_mm);
        let dy = study::error_pct(r.ours_y1_mm, r.thesis_y1_mm);
        assert!(dx < 1.5 && dy < 1.5, "{r:?}: {dx} {dy}");
    }
}

const THETAS: [f64; 6] = [0.05, 0.1, 0.2, 0.4, 0.6, 1.0];

fn loads(kind: LoadAxis) -> Vec<f64> {
    match kind {
        LoadAxis::TipAp => vec![0.0, 10.0, 15.0, 25.0, 30.0],
        _ => vec![0.0, 10.0, 20.0, 40.0],
    }
}

#[test]
fn stability_maps_on_a_small_grid() {
    for kind in LoadAxis::ALL {
        for k in [f64::INFINITY, 5.0] {
            let maps =
                stability_maps(&default_map_methods(), kind, &loads(kind), &THETAS, k).unwrap();
            let [acc, rk4, fdm] = &maps[..] else {
                panic!("three maps expected")
            };
            assert_eq!(acc.method, "accurate");
            for m in &maps {
                assert_eq!(m.cells.len(), m.loads.len());
                assert!(m.cells.iter().all(|row| row.len() == THETAS.len()));
                // No load: the unloaded whisker, directly.
                assert!(m.cells[0].iter().all(|o| *o
                    == Outcome::Converged {
                        continuation_steps: 0
                    }));
            }
            for (i, row) in acc.cells.iter().enumerate() {
                for (j, o) in row.iter().enumerate() {
                    let (load, theta) = (acc.loads[i], THETAS[j]);
                    let at = format!("{} k={k} load={load} theta={theta}", kind.name());
                    // Measured on the default grid: accurate converges everywhere for
                    // theta >= 0.35 (DP tip load, k = 5, fails at theta = 0.3, f >= 38; the
                    // issue hoped for 0.2). Its failures are data, not panics.
                    if theta >= 0.4 {
                        assert!(
                            o.is_converged() || matches!(o, Outcome::FellBack { .. }),
                            "accurate fails at {at}"
                        );
                    }
                    // solved (by shooting, or by its fdm-richardson fallback, credited as such)
                    // exactly where the reference solved
                    let solved = o.is_converged()
                        || *o
                            == Outcome::FellBack {
                                method_used: "fdm-richardson",
                            };
                    assert_eq!(solved, acc.reference[i][j], "{at}");
                    // The cheaper methods agree with accurate wherever both converge,
                    // except fdm/rk4 at n = 100 under AP loads on thin tips (theta < 0.5).
                    for m in [rk4, fdm] {
                        if m.cells[i][j] == Outcome::Wrong {
                            assert!(kind == LoadAxis::TipAp && theta < 0.5, "{} {at}", m.method);
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn stability_map_records_failures_and_rejects_bad_grids() {
    // f = 40 on theta = 0.05 with fdm on 4 intervals: the error estimate (0.38, the doubled
    // grid's) exceeds the fixed-grid bound 5e-2 and the solve is refused; that is a cell,
    // not an error. On 100 intervals the same cell converges (estimate 1e-4).
    let m = stability_map(
        Method::Fdm { n: 4 },
        LoadAxis::TipDp,
        &[0.0, 40.0],
        &[0.05, 1.0],
        f64::INFINITY,
    )
    .unwrap();
    assert_eq!(m.cells[1][0], Outcome::Failed);
    assert_eq!(m.counts(), (2, 2, 0));
    let m = stability_map(
        Method::Fdm { n: 100 },
        LoadAxis::TipDp,
        &[40.0],
        &[0.05],
        f64::INFINITY,
    )
    .unwrap();
    assert!(m.cells[0][0].is_converged() && m.reference[0][0]);
    let bad: [(&[f64], &[f64], f64); 5] = [
        (&[], &[1.0], f64::INFINITY),
        (&[1.0], &[0.0], f64::INFINITY),
        (&[-1.0], &[1.0], f64::INFINITY),
        (&[f64::NAN], &[1.0], f64::INFINITY),
        (&[1.0], &[1.0], -2.0),
    ];
    for (l, t, k) in bad {
        let r = stability_map(Method::accurate(), LoadAxis::Fluid, l, t, k);
        assert!(
            matches!(r, Err(ModelError::InvalidParameter { .. })),
            "{l:?} {t:?} {k}"
        );
    }
    let r = stability_map(Method::Rk4 { n: 1 }, LoadAxis::Fluid, &[1.0], &[1.0], 5.0);
    assert!(matches!(
        r,
        Err(ModelError::InvalidParameter { name: "n", .. })
    ));
}

/// The default maps with timings (`cargo test --release -- --ignored --nocapture`).
#[test]
#[ignore]
fn print_default_maps() {
    for kind in LoadAxis::ALL {
        for k in study::DEFAULT_KS {
            let t = std::time::Instant::now();
            let maps = stability_maps(
                &default_map_methods(),
                kind,
                &kind.default_loads(),
                &study::default_thetas(),
                k,
            )
            .unwrap();
            println!("{} k={k}: {:.2?}", kind.name(), t.elapsed());
            for m in &maps {
                println!(
                    "  {} (converged, failed, wrong) = {:?}",
                    m.method,
                    m.counts()
                );
            }
        }
    }
}
