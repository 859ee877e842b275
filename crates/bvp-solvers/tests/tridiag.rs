//! Thomas algorithm against a dense partial-pivoting solve and a manufactured solution.

use bvp_solvers::tridiag::Tridiagonal;
use bvp_solvers::BvpError;

/// Deterministic pseudo-random numbers in [-1, 1) (64-bit LCG, top 53 bits).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Dense Gaussian elimination with partial pivoting (independent reference).
fn dense_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
            .unwrap();
        a.swap(k, p);
        b.swap(k, p);
        for i in k + 1..n {
            let m = a[i][k] / a[k][k];
            let pivot_row = a[k].clone();
            for (aij, akj) in a[i][k..].iter_mut().zip(&pivot_row[k..]) {
                *aij -= m * akj;
            }
            b[i] -= m * b[k];
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|j| a[i][j] * x[j]).sum();
        x[i] = (b[i] - s) / a[i][i];
    }
    x
}

fn random_tridiagonal(n: usize, rng: &mut Lcg, dominance: f64) -> Tridiagonal {
    let mut t = Tridiagonal::new(n);
    for i in 0..n {
        t.lower[i] = rng.next();
        t.upper[i] = rng.next();
        // |diag| >= dominance > 2 >= |lower| + |upper|: strictly diagonally dominant.
        t.diag[i] = dominance * rng.next().signum() * (1.0 + rng.next().abs());
    }
    t
}

fn to_dense(t: &Tridiagonal) -> Vec<Vec<f64>> {
    let n = t.len();
    let mut a = vec![vec![0.0; n]; n];
    for i in 0..n {
        a[i][i] = t.diag[i];
        if i > 0 {
            a[i][i - 1] = t.lower[i];
        }
        if i + 1 < n {
            a[i][i + 1] = t.upper[i];
        }
    }
    a
}

#[test]
fn thomas_matches_dense_solve() {
    let mut rng = Lcg(42);
    for &n in &[1usize, 2, 3, 10, 57] {
        let t = random_tridiagonal(n, &mut rng, 2.5);
        let rhs: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let x = t.solve(&rhs).unwrap();
        let xd = dense_solve(to_dense(&t), rhs.clone());
        let err = x
            .iter()
            .zip(&xd)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-13, "n = {n}: |x_thomas - x_dense| = {err:e}");
    }
}

#[test]
fn thomas_recovers_manufactured_solution_in_place() {
    // 1D Laplacian with Dirichlet rows: -x_{i-1} + 2 x_i - x_{i+1}; symmetric positive
    // definite, condition ~ n^2, no diagonal dominance margin.
    let n = 200;
    let mut t = Tridiagonal::new(n);
    for i in 0..n {
        t.lower[i] = -1.0;
        t.diag[i] = 2.0;
        t.upper[i] = -1.0;
    }
    let x_true: Vec<f64> = (0..n).map(|i| (0.1 * i as f64).sin() + 0.5).collect();
    let mut rhs = t.mul_vec(&x_true).unwrap();
    let mut scratch = vec![0.0; n];
    t.solve_in_place(&mut rhs, &mut scratch).unwrap();
    let err = rhs
        .iter()
        .zip(&x_true)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    // cond_inf ~ n^2 / 2 = 2e4: error bound ~ 2e4 * eps * few.
    assert!(err < 1e-10, "error {err:e}");
}

#[test]
fn zero_pivot_reports_row() {
    // Row 0 pivot is zero.
    let mut t = Tridiagonal::new(3);
    t.diag = vec![0.0, 1.0, 1.0];
    t.upper = vec![1.0, 1.0, 0.0];
    assert_eq!(
        t.solve(&[1.0, 1.0, 1.0]),
        Err(BvpError::SingularJacobian { row: 0, pivot: 0.0 })
    );

    // Exactly singular leading 2x2 block [[1, 1], [1, 1]]: pivot of row 1 is 1 - 1*1 = 0.
    let mut t = Tridiagonal::new(4);
    t.diag = vec![1.0, 1.0, 3.0, 3.0];
    t.lower = vec![0.0, 1.0, 1.0, 1.0];
    t.upper = vec![1.0, 1.0, 1.0, 0.0];
    match t.solve(&[1.0; 4]) {
        Err(BvpError::SingularJacobian { row, pivot }) => {
            assert_eq!(row, 1);
            assert_eq!(pivot, 0.0);
        }
        other => panic!("expected singular row 1, got {other:?}"),
    }

    // Pure Neumann Laplacian [-1 1; 1 -2 1; ...; 1 -1]: singular (constants in the kernel);
    // the pivot cancels to zero only in the last row.
    let n = 50;
    let mut t = Tridiagonal::new(n);
    for i in 0..n {
        t.lower[i] = 1.0;
        t.upper[i] = 1.0;
        t.diag[i] = -2.0;
    }
    t.diag[0] = -1.0;
    t.diag[n - 1] = -1.0;
    match t.solve(&vec![0.0; n]) {
        Err(BvpError::SingularJacobian { row, pivot }) => {
            assert_eq!(row, n - 1);
            assert!(pivot.abs() < 1e-12, "pivot {pivot:e}");
        }
        other => panic!("expected singular last row, got {other:?}"),
    }
}

#[test]
fn dimension_errors() {
    let t = Tridiagonal::new(3);
    let mut rhs = vec![0.0; 2];
    let mut scratch = vec![0.0; 3];
    assert_eq!(
        t.solve_in_place(&mut rhs, &mut scratch),
        Err(BvpError::DimensionMismatch {
            name: "rhs",
            expected: 3,
            found: 2
        })
    );
    let mut rhs = vec![0.0; 3];
    let mut short = vec![0.0; 2];
    assert!(matches!(
        t.solve_in_place(&mut rhs, &mut short),
        Err(BvpError::DimensionMismatch {
            name: "scratch",
            ..
        })
    ));
    let mut bad = Tridiagonal::new(3);
    bad.upper.pop();
    assert!(matches!(
        bad.solve(&[0.0; 3]),
        Err(BvpError::DimensionMismatch { .. })
    ));
    // The empty system is trivially solved.
    assert_eq!(Tridiagonal::new(0).solve(&[]), Ok(vec![]));
}
