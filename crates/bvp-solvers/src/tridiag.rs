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

    /// Matrix-vector product `T x`.
    ///
    /// # Errors
    /// [`BvpError::DimensionMismatch`] if the diagonals or `x` have the wrong length.
    pub fn mul_vec(&self, x: &[f64]) -> Result<Vec<f64>> {
        let n = self.check_shape()?;
        if x.len() != n {
            return Err(BvpError::DimensionMismatch {
                name: "x",
                expected: n,
                found: x.len(),
            });
        }
        Ok((0..n)
            .map(|i| {
                let mut s = self.diag[i] * x[i];
                if i > 0 {
                    s += self.lower[i] * x[i - 1];
                }
                if i + 1 < n {
                    s += self.upper[i] * x[i + 1];
                }
                s
            })
            .collect())
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
