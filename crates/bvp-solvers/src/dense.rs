//! Small dense linear algebra: the systems of a few unknowns that Newton steps, whitening
//! and least-squares fits solve. Gaussian elimination with partial pivoting ([`solve`], any
//! `N x N`, e.g. `solve::<2>` for a 2x2), the inverse by Gauss-Jordan elimination
//! ([`inverse`]), and the Cholesky factor `A = L L^T` of a symmetric positive definite
//! matrix with its triangular solves ([`cholesky`], [`cholesky_in_place`],
//! [`forward_substitute`], [`back_substitute_transposed`], [`solve_spd`]).
//!
//! A singular (or not positive definite) matrix is `None`: the callers decide what a
//! missing step means to them (a rejected Newton step, an unwhitened row).
//!
//! The dynamic-size routines take row-major matrices as flat slices (`a[i * n + j]`); the
//! fixed-size ones take `[[f64; N]; N]` (rows), flattened with `as_flattened`.

/// Solves `m x = b` by Gaussian elimination with partial pivoting; `None` if `m` is singular
/// (a zero or non-finite pivot) or the solution is not finite.
///
/// ```
/// use bvp_solvers::dense::solve;
/// // 2x + y = 5, x - y = 1
/// let x = solve(&[[2.0, 1.0], [1.0, -1.0]], &[5.0, 1.0]).unwrap();
/// assert!((x[0] - 2.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15);
/// ```
pub fn solve<const N: usize>(m: &[[f64; N]; N], b: &[f64; N]) -> Option<[f64; N]> {
    let mut a = *m;
    let mut x = *b;
    for k in 0..N {
        let p = (k..N).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        a.swap(k, p);
        x.swap(k, p);
        if !(a[k][k].abs() > 0.0 && a[k][k].is_finite()) {
            return None;
        }
        for i in k + 1..N {
            let l = a[i][k] / a[k][k];
            let pivot = a[k];
            for (aij, pkj) in a[i][k..].iter_mut().zip(&pivot[k..]) {
                *aij -= l * pkj;
            }
            x[i] -= l * x[k];
        }
    }
    for k in (0..N).rev() {
        let s: f64 = (k + 1..N).map(|j| a[k][j] * x[j]).sum();
        x[k] = (x[k] - s) / a[k][k];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// A pivot of [`inverse`] below this fraction of the matrix's largest entry counts as zero.
pub const INVERSE_PIVOT_REL: f64 = 1e-12;

/// `m^-1` by Gauss-Jordan elimination with partial pivoting; `None` when `m` has no finite
/// nonzero entry or a pivot falls below [`INVERSE_PIVOT_REL`] of its largest entry.
// `i`, `j` index the rows of `a` and `inv` together
#[allow(clippy::needless_range_loop)]
pub fn inverse<const N: usize>(m: &[[f64; N]; N]) -> Option<[[f64; N]; N]> {
    let big = m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    let mut a = *m;
    let mut inv = [[0.0; N]; N];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for col in 0..N {
        let piv = (col..N).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[piv][col].abs() < INVERSE_PIVOT_REL * big {
            return None;
        }
        a.swap(col, piv);
        inv.swap(col, piv);
        let d = a[col][col];
        for j in 0..N {
            a[col][j] /= d;
            inv[col][j] /= d;
        }
        for i in 0..N {
            if i != col {
                let f = a[i][col];
                for j in 0..N {
                    a[i][j] -= f * a[col][j];
                    inv[i][j] -= f * inv[col][j];
                }
            }
        }
    }
    Some(inv)
}

/// `m v` (`M x N` times `N`).
pub fn mul_vec<const N: usize, const M: usize>(m: &[[f64; N]; M], v: &[f64; N]) -> [f64; M] {
    let mut out = [0.0; M];
    for (o, row) in out.iter_mut().zip(m) {
        *o = row.iter().zip(v).map(|(a, b)| a * b).sum();
    }
    out
}

/// Overwrites the row-major `n x n` matrix `a` (symmetric positive definite; only its lower
/// triangle is read) with its Cholesky factor `L` (`a = L L^T`, lower triangular, zeros
/// above the diagonal); `None` at the first pivot `a_ii - sum_k L_ik^2` that is not positive
/// and finite (`a` then partly overwritten).
///
/// # Panics
/// If `a.len() != n * n`.
pub fn cholesky_in_place(a: &mut [f64], n: usize) -> Option<()> {
    assert_eq!(a.len(), n * n, "cholesky_in_place: a is not n x n");
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| a[i * n + k] * a[j * n + k]).sum();
            if i == j {
                let d = a[i * n + i] - s;
                if !(d > 0.0 && d.is_finite()) {
                    return None;
                }
                a[i * n + i] = d.sqrt();
            } else {
                a[i * n + j] = (a[i * n + j] - s) / a[j * n + j];
            }
        }
        a[i * n + i + 1..(i + 1) * n].fill(0.0);
    }
    Some(())
}

/// The Cholesky factor `L` of the symmetric positive definite `a` ([`cholesky_in_place`]).
pub fn cholesky<const N: usize>(a: &[[f64; N]; N]) -> Option<[[f64; N]; N]> {
    let mut l = *a;
    cholesky_in_place(l.as_flattened_mut(), N)?;
    Some(l)
}

/// Solves `L y = b` in place (`b` becomes `y`) for the row-major lower-triangular `n x n`
/// `l` (`n = b.len()`) by forward substitution.
pub fn forward_substitute(l: &[f64], b: &mut [f64]) {
    let n = b.len();
    for i in 0..n {
        let s: f64 = (0..i).map(|k| l[i * n + k] * b[k]).sum();
        b[i] = (b[i] - s) / l[i * n + i];
    }
}

/// Solves `L^T x = y` in place (`y` becomes `x`) for the row-major lower-triangular `n x n`
/// `l` (`n = y.len()`) by back substitution.
pub fn back_substitute_transposed(l: &[f64], y: &mut [f64]) {
    let n = y.len();
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| l[k * n + i] * y[k]).sum();
        y[i] = (y[i] - s) / l[i * n + i];
    }
}

/// Solves the symmetric positive definite system `a x = b` (`a` by rows, `n = b.len()`) by
/// its Cholesky factor; `None` if `a` is not positive definite.
///
/// # Panics
/// If `a` is not `n x n`.
pub fn solve_spd<R: AsRef<[f64]>>(a: &[R], b: &[f64]) -> Option<Vec<f64>> {
    let n = b.len();
    assert_eq!(a.len(), n, "solve_spd: a has not b.len() rows");
    let mut l: Vec<f64> = a.iter().flat_map(|r| r.as_ref().iter().copied()).collect();
    cholesky_in_place(&mut l, n)?;
    let mut x = b.to_vec();
    forward_substitute(&l, &mut x);
    back_substitute_transposed(&l, &mut x);
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `N x N` Hilbert matrix `1 / (i + j + 1)` (symmetric positive definite).
    fn hilbert<const N: usize>() -> [[f64; N]; N] {
        std::array::from_fn(|i| std::array::from_fn(|j| 1.0 / (i + j + 1) as f64))
    }

    /// `a b` for square matrices.
    fn mul<const N: usize>(a: &[[f64; N]; N], b: &[[f64; N]; N]) -> [[f64; N]; N] {
        std::array::from_fn(|i| std::array::from_fn(|j| (0..N).map(|k| a[i][k] * b[k][j]).sum()))
    }

    #[test]
    fn solve_matches_a_known_solution_and_refuses_singular_matrices() {
        let m = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]];
        let x = [1.0, -2.0, 0.5];
        let b = mul_vec(&m, &x);
        let got = solve(&m, &b).unwrap();
        assert!(got.iter().zip(&x).all(|(a, b)| (a - b).abs() < 1e-15));
        assert!(solve(&[[1.0, 2.0], [2.0, 4.0]], &[1.0, 1.0]).is_none());
        assert!(solve(&[[f64::NAN, 0.0], [0.0, 1.0]], &[1.0, 1.0]).is_none());
    }

    #[test]
    fn solve_of_a_2x2_is_cramers_rule() {
        // det = 3 * 4 - 2 * (-1) = 14: x = (5 * 4 - 2 * 6) / 14, y = (3 * 6 + 5) / 14
        let x = solve(&[[3.0, 2.0], [-1.0, 4.0]], &[5.0, 6.0]).unwrap();
        assert!((x[0] - 8.0 / 14.0).abs() < 1e-15 && (x[1] - 23.0 / 14.0).abs() < 1e-15);
    }

    #[test]
    fn solve_leaves_a_small_residual_on_the_hilbert_matrix() {
        // cond(H5) ~ 4.8e5: the backward-stable solve has a residual at the rounding level
        // of |H| |x| (|x| ~ 1e5 here)
        let h = hilbert::<5>();
        let b = [1.0, -2.0, 3.0, 0.5, 1.0];
        let x = solve(&h, &b).unwrap();
        let size = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(size > 1e4, "{x:?}");
        let r = mul_vec(&h, &x);
        for (ri, bi) in r.iter().zip(&b) {
            assert!((ri - bi).abs() < 10.0 * f64::EPSILON * size, "{r:?}");
        }
        // the exact solution of H3 x = (11/6, 13/12, 47/60) is (1, 1, 1)
        let x = solve(&hilbert::<3>(), &[11.0 / 6.0, 13.0 / 12.0, 47.0 / 60.0]).unwrap();
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-13), "{x:?}");
    }

    #[test]
    fn inverse_gives_the_inverse_and_refuses_a_singular_matrix() {
        let m = [
            [0.0, 2.0, 1.0, 0.0],
            [1.0, 0.5, 0.0, 3.0],
            [4.0, 0.0, 1.0, 1.0],
            [0.0, 1.0, 0.0, 2.0],
        ];
        let inv = inverse(&m).unwrap();
        let p = mul(&m, &inv);
        for (i, row) in p.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                assert!(
                    (v - f64::from(u8::from(i == j))).abs() < 1e-14,
                    "{i} {j} {v}"
                );
            }
        }
        let mut sing = m;
        sing[3] = [0.0; 4];
        assert!(inverse(&sing).is_none());
        assert!(inverse(&[[0.0; 2]; 2]).is_none());
        // the inverse of the 3x3 Hilbert matrix is known in integers
        let want = [
            [9.0, -36.0, 30.0],
            [-36.0, 192.0, -180.0],
            [30.0, -180.0, 180.0],
        ];
        let inv = inverse(&hilbert::<3>()).unwrap();
        for (a, b) in inv.iter().flatten().zip(want.iter().flatten()) {
            assert!((a - b).abs() < 1e-11 * b.abs(), "{inv:?}");
        }
    }

    #[test]
    fn cholesky_factor_of_a_known_matrix() {
        // L = [[2, 0, 0], [1, 3, 0], [-1, 2, 1]] gives A = L L^T
        let a = [[4.0, 2.0, -2.0], [2.0, 10.0, 5.0], [-2.0, 5.0, 6.0]];
        let l = cholesky(&a).unwrap();
        let want = [[2.0, 0.0, 0.0], [1.0, 3.0, 0.0], [-1.0, 2.0, 1.0]];
        assert_eq!(l, want);
        // not positive definite: the second pivot 1 - 4 < 0
        assert!(cholesky(&[[1.0, 2.0], [2.0, 1.0]]).is_none());
        assert!(cholesky(&[[0.0]]).is_none());
    }

    #[test]
    fn triangular_solves_invert_the_factor() {
        let l = [2.0, 0.0, 0.0, 1.0, 3.0, 0.0, -1.0, 2.0, 1.0];
        // L y = b with y = (1, -1, 2): b = (2, -2, -1)
        let mut y = [2.0, -2.0, -1.0];
        forward_substitute(&l, &mut y);
        assert_eq!(y, [1.0, -1.0, 2.0]);
        // L^T x = y with x = (1, 0, -1): L^T x = (2 + 1, -2, -1)
        let mut x = [3.0, -2.0, -1.0];
        back_substitute_transposed(&l, &mut x);
        assert_eq!(x, [1.0, 0.0, -1.0]);
    }

    #[test]
    fn spd_solve_on_the_hilbert_matrix() {
        // row sums of H4 as the right-hand side: the solution is all ones
        let h = hilbert::<4>();
        let b: Vec<f64> = h.iter().map(|r| r.iter().sum()).collect();
        let x = solve_spd(&h, &b).unwrap();
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-11), "{x:?}");
        // and agrees with the pivoted solve on a small system given as rows of Vecs
        let a = vec![vec![4.0, 1.0], vec![1.0, 3.0]];
        let x = solve_spd(&a, &[1.0, 2.0]).unwrap();
        let y = solve(&[[4.0, 1.0], [1.0, 3.0]], &[1.0, 2.0]).unwrap();
        assert!((x[0] - y[0]).abs() < 1e-15 && (x[1] - y[1]).abs() < 1e-15);
        assert!(solve_spd(&[vec![0.0]], &[1.0]).is_none());
    }
}
