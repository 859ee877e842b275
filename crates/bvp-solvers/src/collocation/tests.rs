//! Unit tests of the collocation pieces: the ABD elimination against a dense LU on a seeded
//! random battery, the Jacobian blocks against scipy's closed form, the singular-term
//! projectors, and the error paths.

// Index arithmetic on flat row-major blocks (`a[r * n + c]`) reads as the equations do.
#![allow(clippy::needless_range_loop)]

use super::abd::{AbdLu, AbdMatrix};
use super::system::System;
use super::*;

/// A small seeded generator (xorshift64*), uniform in `[-1, 1)`.
pub(super) struct Rng(pub(super) u64);
impl Rng {
    pub(super) fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// The full matrix of an ABD system, column by column from `J e_c`.
pub(super) fn to_dense(mat: &AbdMatrix) -> Vec<Vec<f64>> {
    let nt = mat.m * mat.n + mat.k;
    let mut d = vec![vec![0.0; nt]; nt];
    for c in 0..nt {
        let mut e = vec![0.0; nt];
        e[c] = 1.0;
        for (r, v) in mat.mul(&e).into_iter().enumerate() {
            d[r][c] = v;
        }
    }
    d
}

/// Dense Gaussian elimination with partial pivoting (the reference).
pub(super) fn dense_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
            .unwrap();
        a.swap(k, p);
        b.swap(k, p);
        for i in k + 1..n {
            let l = a[i][k] / a[k][k];
            for j in k..n {
                a[i][j] -= l * a[k][j];
            }
            b[i] -= l * b[k];
        }
    }
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| a[k][j] * b[j]).sum();
        b[k] = (b[k] - s) / a[k][k];
    }
    b
}

/// 300 random ABD systems (n in 1..=5, k in 0..=2, m in 2..=12, non-separated boundary
/// rows): the structured elimination agrees with dense pivoted LU to 1e-9 relative.
#[test]
fn abd_matches_dense_lu_on_a_random_battery() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut worst = 0.0f64;
    for case in 0..300 {
        let n = 1 + case % 5;
        let k = (case / 5) % 3;
        let m = 2 + (case * 7) % 11;
        let mut mat = AbdMatrix::zeros(n, k, m);
        for v in mat
            .a
            .iter_mut()
            .chain(mat.c.iter_mut())
            .chain(mat.p.iter_mut())
            .chain(mat.ba.iter_mut())
            .chain(mat.bb.iter_mut())
            .chain(mat.bp.iter_mut())
        {
            *v = rng.next();
        }
        let nt = m * n + k;
        let b: Vec<f64> = (0..nt).map(|_| rng.next()).collect();
        let dense = to_dense(&mat);
        let xref = dense_solve(dense, b.clone());
        let lu = AbdLu::factor(&mat).unwrap();
        let mut x = b.clone();
        lu.solve_in_place(&mut x, &mut Vec::new());
        let scale = xref.iter().fold(1.0f64, |s, v| s.max(v.abs()));
        let err = x
            .iter()
            .zip(&xref)
            .fold(0.0f64, |s, (u, v)| s.max((u - v).abs()))
            / scale;
        worst = worst.max(err);
        // the residual too, independent of the reference
        let r = mat.mul(&x);
        let res = r
            .iter()
            .zip(&b)
            .fold(0.0f64, |s, (u, v)| s.max((u - v).abs()));
        assert!(res < 1e-9 * scale, "case {case}: residual {res:e}");
    }
    assert!(worst < 1e-9, "worst relative difference {worst:e}");
}

/// A periodic (non-separated) structure whose `y_j` blocks alone are singular: the pivoting
/// must reach across the carry; exact solution recovered.
#[test]
fn abd_solves_a_known_solution_with_identity_blocks() {
    // y_{j+1} - y_j = 1 (n = 1), y_0 + y_{m-1} = m - 1: y_j = j.
    let m = 6;
    let mut mat = AbdMatrix::zeros(1, 0, m);
    mat.a.fill(-1.0);
    mat.c.fill(1.0);
    mat.ba[0] = 1.0;
    mat.bb[0] = 1.0;
    let mut b = vec![1.0; m];
    b[m - 1] = (m - 1) as f64;
    let lu = AbdLu::factor(&mat).unwrap();
    lu.solve_in_place(&mut b, &mut Vec::new());
    for (j, v) in b.iter().enumerate() {
        assert!((v - j as f64).abs() < 1e-13, "{j}: {v}");
    }
}

/// A singular system (both boundary rows on the same state) is an error naming a row.
#[test]
fn abd_reports_a_singular_jacobian() {
    let mut mat = AbdMatrix::zeros(1, 0, 3);
    mat.a.fill(-1.0);
    mat.c.fill(1.0);
    // bc row is zero: singular
    let err = AbdLu::factor(&mat).unwrap_err();
    assert!(matches!(err, BvpError::SingularJacobian { .. }), "{err}");
}

/// scipy's `test_compute_global_jac`: the blocks of the Sturm-Liouville problem
/// `y'' = -p^2 y` against their closed forms, with analytic and differenced Jacobians.
#[test]
fn jacobian_blocks_match_scipy_closed_form() {
    let prob = FnProblem {
        f: |_x: f64, y: &[f64], p: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -p[0] * p[0] * y[0];
        },
        bc: |ya: &[f64], yb: &[f64], p: &[f64], r: &mut [f64]| {
            r[0] = ya[0];
            r[1] = yb[0];
            r[2] = ya[1] - p[0];
        },
    };
    let m = 5;
    let x: Vec<f64> = (0..m).map(|i| i as f64 / 4.0).collect();
    let pi = std::f64::consts::PI;
    let y: Vec<f64> = x
        .iter()
        .flat_map(|&t| [(pi * t).sin(), pi * (pi * t).cos()])
        .collect();
    let p = [3.0];
    let mut sys = System::new(&prob, 2, 1, 0.0, None);
    let mut col = system::Colloc::default();
    sys.collocation(&x, &y, &p, &mut col);
    let mut bc0 = [0.0; 3];
    sys.bc(&y[..2], &y[8..], &p, &mut bc0);
    let mut mat = AbdMatrix::default();
    sys.jacobian(&x, &y, &p, &col, &bc0, &mut mat);
    let h: f64 = 0.25;
    let pp = 3.0f64;
    // scipy's J_block(h, p): rows [dPhi0/dy_i | dPhi0/dy_{i+1}]
    let a = [
        h * h * pp * pp / 12.0 - 1.0,
        -0.5 * h,
        0.5 * h * pp * pp,
        h * h * pp * pp / 12.0 - 1.0,
    ];
    let c = [
        -h * h * pp * pp / 12.0 + 1.0,
        -0.5 * h,
        0.5 * h * pp * pp,
        1.0 - h * h * pp * pp / 12.0,
    ];
    for i in 0..m - 1 {
        for q in 0..4 {
            assert!(
                (mat.a[i * 4 + q] - a[q]).abs() < 1e-6,
                "A[{i}][{q}] {} vs {}",
                mat.a[i * 4 + q],
                a[q]
            );
            assert!((mat.c[i * 4 + q] - c[q]).abs() < 1e-6, "C[{i}][{q}]");
        }
        let y0 = &y[i * 2..i * 2 + 2];
        let y1 = &y[i * 2 + 2..i * 2 + 4];
        let p0 = pp * h * h / 6.0 * (y0[0] - y1[0]);
        let p1 = pp * (h * (y0[0] + y1[0]) + h * h / 6.0 * (y0[1] - y1[1]));
        assert!(
            (mat.p[i * 2] - p0).abs() < 1e-6,
            "P[{i}][0] {} vs {p0}",
            mat.p[i * 2]
        );
        assert!(
            (mat.p[i * 2 + 1] - p1).abs() < 1e-6,
            "P[{i}][1] {} vs {p1}",
            mat.p[i * 2 + 1]
        );
    }
    let ba = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
    let bb = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let bp = [0.0, 0.0, -1.0];
    for q in 0..6 {
        assert!((mat.ba[q] - ba[q]).abs() < 1e-7 && (mat.bb[q] - bb[q]).abs() < 1e-7);
    }
    for q in 0..3 {
        assert!((mat.bp[q] - bp[q]).abs() < 1e-7);
    }
}

/// `S = diag(0, -2)` (Emden): `B = I - S^+ S = diag(1, 0)`, `D = (I - S)^+ = diag(1, 1/3)`.
#[test]
fn singular_term_projectors() {
    let sg = singular_term(&[0.0, 0.0, 0.0, -2.0], 2).unwrap();
    let b = [1.0, 0.0, 0.0, 0.0];
    let d = [1.0, 0.0, 0.0, 1.0 / 3.0];
    for q in 0..4 {
        assert!((sg.b[q] - b[q]).abs() < 1e-14 && (sg.d[q] - d[q]).abs() < 1e-14);
    }
}

fn exp_f(_x: f64, y: &[f64], _p: &[f64], dy: &mut [f64]) {
    dy[0] = y[1];
    dy[1] = y[0];
}
fn exp_bc(ya: &[f64], yb: &[f64], _p: &[f64], r: &mut [f64]) {
    r[0] = ya[0] - 1.0;
    r[1] = yb[0];
}

/// Bad input is an error naming the culprit, never a panic.
#[test]
fn bad_input_is_an_error_naming_it() {
    let o = BvpOptions::default();
    let y5 = vec![vec![0.0, 0.0]; 5];
    let x5: Vec<f64> = (0..5).map(|i| i as f64 / 4.0).collect();
    // non-increasing mesh (scipy's x = [0, 1, 0.5])
    let e = solve_bvp(exp_f, exp_bc, &[0.0, 1.0, 0.5], &y5[..3], &[], &o).unwrap_err();
    assert!(
        e.to_string().contains("x_mesh") && e.to_string().contains("increasing"),
        "{e}"
    );
    // y_guess length
    let e = solve_bvp(exp_f, exp_bc, &x5, &y5[..4], &[], &o).unwrap_err();
    assert!(
        matches!(
            e,
            BvpError::DimensionMismatch {
                expected: 5,
                found: 4,
                ..
            }
        ),
        "{e}"
    );
    // ragged y
    let mut yr = y5.clone();
    yr[2] = vec![0.0];
    let e = solve_bvp(exp_f, exp_bc, &x5, &yr, &[], &o).unwrap_err();
    assert!(
        matches!(
            e,
            BvpError::DimensionMismatch {
                expected: 2,
                found: 1,
                ..
            }
        ),
        "{e}"
    );
    // NaN in the mesh, the guess, tol
    let mut xn = x5.clone();
    xn[2] = f64::NAN;
    assert!(solve_bvp(exp_f, exp_bc, &xn, &y5, &[], &o)
        .unwrap_err()
        .to_string()
        .contains("x_mesh"));
    let mut yn = y5.clone();
    yn[1][0] = f64::NAN;
    assert!(solve_bvp(exp_f, exp_bc, &x5, &yn, &[], &o)
        .unwrap_err()
        .to_string()
        .contains("y_guess"));
    let bad = BvpOptions {
        tol: -1.0,
        ..Default::default()
    };
    assert!(solve_bvp(exp_f, exp_bc, &x5, &y5, &[], &bad)
        .unwrap_err()
        .to_string()
        .contains("tol"));
    // S of the wrong size (scipy's S = [[0, 0]])
    let bad = BvpOptions {
        singular: Some(vec![0.0, 0.0]),
        ..Default::default()
    };
    let e = solve_bvp(exp_f, exp_bc, &x5, &y5, &[], &bad).unwrap_err();
    assert!(
        matches!(
            e,
            BvpError::DimensionMismatch {
                expected: 4,
                found: 2,
                ..
            }
        ),
        "{e}"
    );
    // an f that returns NaN
    let e = solve_bvp(
        |_, _, _, dy: &mut [f64]| dy.fill(f64::NAN),
        exp_bc,
        &x5,
        &y5,
        &[],
        &o,
    )
    .unwrap_err();
    assert!(matches!(e, BvpError::NonFinite { .. }), "{e}");
    // too few nodes
    assert!(solve_bvp(exp_f, exp_bc, &[0.0], &y5[..1], &[], &o).is_err());
}

/// scipy's `test_failures`: the node budget (status 1) and a singular Jacobian (status 2).
#[test]
fn scipy_failures() {
    let x = [0.0, 1.0];
    let y = vec![vec![0.0, 0.0]; 2];
    let o = BvpOptions {
        tol: 1e-5,
        max_nodes: 5,
        ..Default::default()
    };
    let e = solve_bvp(exp_f, exp_bc, &x, &y, &[], &o).unwrap_err();
    match e {
        BvpError::MeshLimit {
            max_nodes,
            needed,
            max_rms_residual,
            ..
        } => {
            assert_eq!(max_nodes, 5);
            assert!(needed > 5 && max_rms_residual > 1e-5);
        }
        other => panic!("{other}"),
    }
    let x5: Vec<f64> = (0..5).map(|i| i as f64 / 4.0).collect();
    let y5 = vec![vec![0.0, 0.0]; 5];
    let e = solve_bvp(
        |_, _, _, dy: &mut [f64]| dy.fill(0.0),
        |ya, yb, _, r| {
            r[0] = ya[0];
            r[1] = yb[0] - 1.0;
        },
        &x5,
        &y5,
        &[],
        &BvpOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(e, BvpError::SingularJacobian { .. }), "{e}");
}
