//! Closed forms, singular Jacobians, failed trial points, the published test problems of
//! Moré, Garbow & Hillstrom (ACM TOMS 7, 1981) and a seeded random battery with known roots.

use super::*;
use crate::BvpError;

/// A system given by a closure (`n` unknowns), failing where the closure returns `None`.
struct F<G: Fn(&[f64], &mut [f64]) -> Option<()>>(usize, G);

impl<G: Fn(&[f64], &mut [f64]) -> Option<()>> NonlinearSystem for F<G> {
    type Error = BvpError;
    fn n_unknowns(&self) -> usize {
        self.0
    }
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), BvpError> {
        (self.1)(x, r).ok_or(BvpError::InvalidInput {
            name: "x",
            value: x[0],
            reason: "outside the domain",
        })
    }
}

/// A small linear congruential generator in [0, 1) (seeded, reproducible).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn no_fallback(tol: f64) -> SquareNewton {
    SquareNewton {
        trust_region: None,
        ..SquareNewton::new(tol)
    }
}

#[test]
fn the_circle_meets_the_line_at_sqrt_2() {
    let sys = F(2, |x: &[f64], r: &mut [f64]| {
        r[0] = x[0] * x[0] + x[1] * x[1] - 4.0;
        r[1] = x[1] - x[0];
        Some(())
    });
    let out = no_fallback(1e-13).solve(&sys, &[1.0, 2.0]).unwrap();
    let s2 = 2f64.sqrt();
    assert!((out.x[0] - s2).abs() < 1e-13 && (out.x[1] - s2).abs() < 1e-13);
    assert_eq!(out.solver, Solver::Newton);
    assert!(out.iterations <= 6, "{out:?}");
    assert_eq!(out.linear.qr, 0);
}

/// A linear system `A x = b` of size 60 with `b = A x*`: LU steps land on `x*`.
#[test]
fn a_linear_system_is_solved_in_one_step() {
    let n = 60;
    let mut g = Lcg(7);
    let a: Vec<f64> = (0..n * n)
        .map(|k| g.next() - 0.5 + if k % (n + 1) == 0 { 3.0 } else { 0.0 })
        .collect();
    let xs: Vec<f64> = (0..n).map(|_| 4.0 * g.next() - 2.0).collect();
    let b: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| a[i * n + j] * xs[j]).sum())
        .collect();
    let sys = F(n, |x: &[f64], r: &mut [f64]| {
        for i in 0..n {
            r[i] = (0..n).map(|j| a[i * n + j] * x[j]).sum::<f64>() - b[i];
        }
        Some(())
    });
    let out = no_fallback(1e-9).solve(&sys, &vec![0.0; n]).unwrap();
    // a forward-difference Jacobian: the first step leaves ~1e-8 relative, the second none
    assert!(out.iterations <= 2, "{}", out.iterations);
    let err = out
        .x
        .iter()
        .zip(&xs)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-10, "{err:e}");
}

/// The truncated QR step of rank-deficient `J = U V^T` (rank 3 of 7, seeded) solves a
/// consistent `J dx = b` (checked by multiplying back): the permutation and the truncation
/// are right.
#[test]
fn the_truncated_qr_step_solves_rank_deficient_consistent_systems() {
    let mut g = Lcg(11);
    for case in 0..50 {
        let (n, k) = (7, 1 + case % 5);
        let u: Vec<f64> = (0..n * k).map(|_| g.next() - 0.5).collect();
        let v: Vec<f64> = (0..n * k).map(|_| g.next() - 0.5).collect();
        let j: Vec<f64> = (0..n * n)
            .map(|ij| {
                let (i, c) = (ij / n, ij % n);
                (0..k).map(|l| u[i * k + l] * v[c * k + l]).sum()
            })
            .collect();
        let xs: Vec<f64> = (0..n).map(|_| g.next() - 0.5).collect();
        let b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|c| j[i * n + c] * xs[c]).sum())
            .collect();
        let (dx, by_qr) = newton_step(n, &j, &b).unwrap();
        assert!(by_qr, "case {case}: rank {k} of {n} taken as regular");
        let res = (0..n)
            .map(|i| ((0..n).map(|c| j[i * n + c] * dx[c]).sum::<f64>() - b[i]).abs())
            .fold(0.0, f64::max);
        assert!(res < 1e-12, "case {case}: |J dx - b| = {res:e}");
    }
    // rank 0: an error naming the pivot
    assert!(matches!(
        newton_step(2, &[0.0; 4], &[1.0, 1.0]),
        Err((_, p)) if p == 0.0
    ));
}

/// `r = (x^2 - 1, y - x)` with its analytic Jacobian.
struct Parabola;

impl NonlinearSystem for Parabola {
    type Error = BvpError;
    fn n_unknowns(&self) -> usize {
        2
    }
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), BvpError> {
        r[0] = x[0] * x[0] - 1.0;
        r[1] = x[1] - x[0];
        Ok(())
    }
    fn jacobian(&self, x: &[f64], j: &mut [f64]) -> Result<(), BvpError> {
        j.copy_from_slice(&[2.0 * x[0], 0.0, -1.0, 1.0]);
        Ok(())
    }
}

/// [`Parabola`] from `(0, 0.5)`, where `J = [[0, 0], [-1, 1]]` is singular: the truncated
/// QR step is taken (LU would divide by 0) and the solve reaches a root `(+-1, +-1)`.
#[test]
fn a_singular_start_jacobian_is_stepped_over() {
    let out = SquareNewton::new(1e-13)
        .solve(&Parabola, &[0.0, 0.5])
        .unwrap();
    assert!(out.linear.qr >= 1, "{out:?}");
    assert!((out.x[0].abs() - 1.0).abs() < 1e-13 && (out.x[1] - out.x[0]).abs() < 1e-13);
    // a Jacobian of rank 0 with a residual that does not vanish: the error names it
    let flat = F(2, |_x: &[f64], r: &mut [f64]| {
        r.fill(1.0);
        Some(())
    });
    let e = no_fallback(1e-10).solve(&flat, &[0.0, 0.0]).unwrap_err();
    assert!(matches!(e, BvpError::SingularJacobian { .. }), "{e}");
    // with the fallback: the trust region's failure, with the residual it reached
    let e = SquareNewton::new(1e-10)
        .solve(&flat, &[0.0, 0.0])
        .unwrap_err();
    assert!(matches!(e, BvpError::NoConvergence { .. }), "{e}");
}

/// `ln x = 0` from `x = 10`: the full step lands at `x = -13`, where the residual fails;
/// the failed trials only halve the step, and Newton reaches `x = 1`.
#[test]
fn a_failed_trial_point_shrinks_the_step() {
    let sys = F(1, |x: &[f64], r: &mut [f64]| {
        (x[0] > 0.0).then(|| r[0] = x[0].ln())
    });
    let out = no_fallback(1e-14).solve(&sys, &[10.0]).unwrap();
    assert!(out.failed_trials >= 1, "{out:?}");
    assert_eq!(out.solver, Solver::Newton);
    assert!((out.x[0] - 1.0).abs() < 1e-14, "{}", out.x[0]);
    // a NaN residual counts as a failure too: sqrt(x) - 1 = 0 from 9 (full step to -3)
    let sys = F(1, |x: &[f64], r: &mut [f64]| {
        r[0] = x[0].sqrt() - 2.0 + 0.0 * x[0];
        Some(())
    });
    let out = no_fallback(1e-14).solve(&sys, &[0.01]).unwrap();
    assert!((out.x[0] - 4.0).abs() < 1e-13, "{}", out.x[0]);
    // the error at the start is the system's own
    assert!(matches!(
        no_fallback(1e-14).solve(&F(1, |_: &[f64], _: &mut [f64]| None), &[1.0]),
        Err(BvpError::InvalidInput { name: "x", .. })
    ));
}

/// Moré, Garbow & Hillstrom's problems 1 (Rosenbrock), 3 (Powell badly scaled), 7 (helical
/// valley), 13 (Powell singular) and 30 (Broyden tridiagonal, n = 100) from their standard
/// starts, against the published roots.
#[test]
fn published_test_problems() {
    let rosenbrock = F(2, |x: &[f64], r: &mut [f64]| {
        r[0] = 10.0 * (x[1] - x[0] * x[0]);
        r[1] = 1.0 - x[0];
        Some(())
    });
    let out = no_fallback(1e-12).solve(&rosenbrock, &[-1.2, 1.0]).unwrap();
    assert!((out.x[0] - 1.0).abs() < 1e-12 && (out.x[1] - 1.0).abs() < 1e-12);
    // Armijo's test rejects the full steps that overshoot the valley: damped, 10 steps
    assert!(out.iterations <= 12, "{out:?}");

    // root (1.098159e-5, 9.106146) (MGH's table)
    let powell = F(2, |x: &[f64], r: &mut [f64]| {
        r[0] = 1e4 * x[0] * x[1] - 1.0;
        r[1] = (-x[0]).exp() + (-x[1]).exp() - 1.0001;
        Some(())
    });
    let out = SquareNewton::new(1e-12)
        .solve(&powell, &[0.0, 1.0])
        .unwrap();
    assert!((out.x[0] - 1.098159e-5).abs() < 1e-11, "{:?}", out.x);
    assert!((out.x[1] - 9.106146).abs() < 1e-6, "{:?}", out.x);

    // root (1, 0, 0)
    let helical = F(3, |x: &[f64], r: &mut [f64]| {
        let t = x[1].atan2(x[0]) / (2.0 * std::f64::consts::PI);
        r[0] = 10.0 * (x[2] - 10.0 * t);
        r[1] = 10.0 * ((x[0] * x[0] + x[1] * x[1]).sqrt() - 1.0);
        r[2] = x[2];
        Some(())
    });
    let out = SquareNewton::new(1e-12).solve(&helical, &[-1.0, 0.0, 0.0]);
    let out = out.unwrap();
    assert!((out.x[0] - 1.0).abs() < 1e-10 && out.x[1].abs() < 1e-10 && out.x[2].abs() < 1e-10);

    // root 0, where J is singular: Newton converges linearly, |x| ~ sqrt of the residual
    let singular = F(4, |x: &[f64], r: &mut [f64]| {
        r[0] = x[0] + 10.0 * x[1];
        r[1] = 5f64.sqrt() * (x[2] - x[3]);
        r[2] = (x[1] - 2.0 * x[2]).powi(2);
        r[3] = 10f64.sqrt() * (x[0] - x[3]).powi(2);
        Some(())
    });
    let out = no_fallback(1e-14)
        .solve(&singular, &[3.0, -1.0, 0.0, 1.0])
        .unwrap();
    assert!(out.x.iter().all(|v| v.abs() < 1e-6), "{:?}", out.x);
    assert!(out.iterations > 10, "linear convergence expected: {out:?}");

    // Broyden tridiagonal, n = 100, from -1: the residual vanishes and the trust region,
    // another algorithm, finds the same root
    let n = 100;
    let broyden = F(n, move |x: &[f64], r: &mut [f64]| {
        for i in 0..n {
            let l = if i > 0 { x[i - 1] } else { 0.0 };
            let u = if i + 1 < n { x[i + 1] } else { 0.0 };
            r[i] = (3.0 - 2.0 * x[i]) * x[i] - l - 2.0 * u + 1.0;
        }
        Some(())
    });
    let out = no_fallback(1e-12).solve(&broyden, &vec![-1.0; n]).unwrap();
    assert!(out.iterations <= 6, "{}", out.iterations);
    let tr = trust_region::solve(
        &broyden,
        &vec![-1.0; n],
        &TrustRegionOptions {
            tol: 1e-12,
            ..TrustRegionOptions::default()
        },
    )
    .unwrap();
    let d = out
        .x
        .iter()
        .zip(&tr.x)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(d < 1e-11, "{d:e}");
}

/// Seeded battery over sizes 1..40 and random strongly non-linear maps with a known root
/// `x*`: `r_i = sum_j A_ij (x_j - x*_j) + c_i sin(x_i - x*_i)^2 + d_i (x_{i+1} - x*_{i+1})^3`
/// from `x* + 0.3 w`, `w` in `[-1, 1]^n`. A solve that ends must land on `x*` within 1e-9
/// (or on another root); at most 2 % may fail (measured: see the printed count).
#[test]
fn random_battery_lands_on_the_known_root() {
    let mut g = Lcg(2026);
    let mut worst: f64 = 0.0;
    let mut failures = 0;
    for case in 0..300 {
        let n = 1 + case % 40;
        let a: Vec<f64> = (0..n * n)
            .map(|k| 2.0 * g.next() - 1.0 + if k % (n + 1) == 0 { 2.0 } else { 0.0 })
            .collect();
        let c: Vec<f64> = (0..n).map(|_| 4.0 * g.next() - 2.0).collect();
        let d: Vec<f64> = (0..n).map(|_| 2.0 * g.next() - 1.0).collect();
        let xs: Vec<f64> = (0..n).map(|_| 10.0 * g.next() - 5.0).collect();
        let x0: Vec<f64> = xs
            .iter()
            .map(|v| v + 0.3 * (2.0 * g.next() - 1.0))
            .collect();
        let sys = F(n, |x: &[f64], r: &mut [f64]| {
            for i in 0..n {
                let lin: f64 = (0..n).map(|j| a[i * n + j] * (x[j] - xs[j])).sum();
                let nxt = if i + 1 < n { x[i + 1] - xs[i + 1] } else { 0.0 };
                r[i] = lin + c[i] * (x[i] - xs[i]).sin().powi(2) + d[i] * nxt.powi(3);
            }
            Some(())
        });
        let Ok(out) = SquareNewton::new(1e-13).solve(&sys, &x0) else {
            failures += 1;
            continue;
        };
        let err = out
            .x
            .iter()
            .zip(&xs)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        worst = worst.max(err);
        // the root is isolated (J(x*) = A regular) but another root may be nearer: then the
        // residual still vanishes
        if err > 1e-9 {
            assert!(out.residual_norm <= 1e-13, "case {case}: {err:e}");
        }
    }
    println!("worst distance to x*: {worst:e}, {failures} of 300 failed");
    assert!(failures <= 6, "{failures} of 300 failed");
}

#[test]
fn bad_input_is_an_error_naming_it() {
    let sys = F(2, |_: &[f64], r: &mut [f64]| {
        r.fill(0.0);
        Some(())
    });
    let e = SquareNewton::new(1e-10).solve(&sys, &[1.0]).unwrap_err();
    assert!(
        matches!(e, BvpError::DimensionMismatch { found: 1, .. }),
        "{e}"
    );
    let e = SquareNewton::new(0.0).solve(&sys, &[1.0, 2.0]).unwrap_err();
    assert!(
        matches!(e, BvpError::InvalidInput { name: "tol", .. }),
        "{e}"
    );
}
