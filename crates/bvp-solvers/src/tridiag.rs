//! Tridiagonal systems by the Thomas algorithm (Gaussian elimination without pivoting).
//!
//! Row `i` of `T x = r` reads `lower[i] x[i-1] + diag[i] x[i] + upper[i] x[i+1] = r[i]`,
//! with `lower[0]` and `upper[n-1]` ignored. Forward sweep
//!
//! ```text
//! p_0 = d_0,                     c_0 = u_0 / p_0,   r'_0 = r_0 / p_0
//! p_i = d_i - l_i c_{i-1},       c_i = u_i / p_i,   r'_i = (r_i - l_i r'_{i-1}) / p_i
//! ```
//!
//! and back substitution `x_{n-1} = r'_{n-1}`, `x_i = r'_i - c_i x_{i+1}`: `8n` flops, no
//! allocation in [`Tridiagonal::solve_in_place`]. Stable without pivoting for diagonally
//! dominant or symmetric positive (negative) definite matrices, which is what the FDM
//! Jacobians of well-posed problems are for small `h`.

use crate::{BvpError, Result};

/// Absolute pivot floor of the Thomas algorithm.
pub const PIVOT_ABS_FLOOR: f64 = 1e-300;

/// Relative pivot threshold: a pivot `p_i = d_i - l_i c_{i-1}` with
/// `|p_i| <= PIVOT_REL_TOL * (|d_i| + |l_i c_{i-1}|)` is cancellation noise of an exactly
/// singular leading block and is reported as zero.
pub const PIVOT_REL_TOL: f64 = 8.0 * f64::EPSILON;

/// A tridiagonal `n x n` matrix stored by its three diagonals, each of length `n`
/// (`lower[0]` and `upper[n-1]` are unused).
#[derive(Clone, Debug, PartialEq)]
pub struct Tridiagonal {
    /// Sub-diagonal: `lower[i]` multiplies `x[i-1]` in row `i`.
    pub lower: Vec<f64>,
    /// Main diagonal.
    pub diag: Vec<f64>,
    /// Super-diagonal: `upper[i]` multiplies `x[i+1]` in row `i`.
    pub upper: Vec<f64>,
}

impl Tridiagonal {
    /// The `n x n` zero matrix.
    pub fn new(n: usize) -> Self {
        Self {
            lower: vec![0.0; n],
            diag: vec![0.0; n],
            upper: vec![0.0; n],
        }
    }

    /// Dimension `n` (the length of `diag`).
    pub fn len(&self) -> usize {
        self.diag.len()
    }

    /// `true` for the `0 x 0` matrix.
    pub fn is_empty(&self) -> bool {
        self.diag.is_empty()
    }

    fn check_shape(&self) -> Result<usize> {
        let n = self.diag.len();
        if self.lower.len() != n {
            return Err(BvpError::DimensionMismatch {
                name: "tridiagonal lower",
                expected: n,
                found: self.lower.len(),
            });
        }
        if self.upper.len() != n {
            return Err(BvpError::DimensionMismatch {
                name: "tridiagonal upper",
                expected: n,
                found: self.upper.len(),
            });
        }
        Ok(n)
    }

    /// Solves `T x = rhs` in place by the Thomas algorithm: on success `rhs` holds `x`.
    /// `scratch` (length at least `n`) receives the modified super-diagonal `c_i`.
    ///
    /// # Errors
    /// - [`BvpError::DimensionMismatch`] if the diagonals, `rhs` or `scratch` have the wrong
    ///   length;
    /// - [`BvpError::SingularJacobian`] `{ row, pivot }` at the first pivot `p_i` with
    ///   `|p_i| <= 1e-300` or `|p_i| <= 8 eps (|d_i| + |l_i c_{i-1}|)` (see
    ///   [`PIVOT_REL_TOL`]); `rhs` is then left partially overwritten. A NaN pivot is also
    ///   reported this way.
    pub fn solve_in_place(&self, rhs: &mut [f64], scratch: &mut [f64]) -> Result<()> {
        let n = self.check_shape()?;
        if rhs.len() != n {
            return Err(BvpError::DimensionMismatch {
                name: "rhs",
                expected: n,
                found: rhs.len(),
            });
        }
        if scratch.len() < n {
            return Err(BvpError::DimensionMismatch {
                name: "scratch",
                expected: n,
                found: scratch.len(),
            });
        }
        if n == 0 {
            return Ok(());
        }
        let (l, d, u) = (&self.lower, &self.diag, &self.upper);
        let c = &mut scratch[..n];

        let p = d[0];
        check_pivot(0, p, d[0].abs())?;
        c[0] = u[0] / p;
        rhs[0] /= p;
        for i in 1..n {
            let lc = l[i] * c[i - 1];
            let p = d[i] - lc;
            check_pivot(i, p, d[i].abs() + lc.abs())?;
            c[i] = u[i] / p;
            rhs[i] = (rhs[i] - l[i] * rhs[i - 1]) / p;
        }
        for i in (0..n - 1).rev() {
            rhs[i] -= c[i] * rhs[i + 1];
        }
        Ok(())
    }

    /// Solves `T x = rhs` and returns `x` (allocates; see [`Tridiagonal::solve_in_place`]).
    ///
    /// # Errors
    /// As [`Tridiagonal::solve_in_place`].
    pub fn solve(&self, rhs: &[f64]) -> Result<Vec<f64>> {
        let mut x = rhs.to_vec();
        let mut scratch = vec![0.0; self.diag.len()];
        self.solve_in_place(&mut x, &mut scratch)?;
        Ok(x)
    }
}

#[inline]
fn check_pivot(row: usize, pivot: f64, scale: f64) -> Result<()> {
    let a = pivot.abs();
    // `!(a > ...)` also catches NaN.
    if !(a > PIVOT_ABS_FLOOR && a > PIVOT_REL_TOL * scale) {
        return Err(BvpError::SingularJacobian { row, pivot });
    }
    Ok(())
}

/// Thomas algorithm against a dense partial-pivoting solve and a manufactured solution.
#[cfg(test)]
mod tests {
    use super::*;

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

    /// The dense product `a x`.
    fn mul(a: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
        a.iter()
            .map(|row| row.iter().zip(x).map(|(a, x)| a * x).sum())
            .collect()
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
        let mut rhs = mul(&to_dense(&t), &x_true);
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
}
