//! The Newton system of multiple shooting, solved by its structure: Gaussian elimination
//! with partial (row) pivoting on a staircase of rows with a dense border.
//!
//! With nodes `x_0 < ... < x_{m-1}`, node states `s_j` and parameters `p`, the linearised
//! conditions are
//!
//! ```text
//! bc:   B_a ds_0 + B_b ds_{m-1} + B_p dp = -g
//! c_j:  G_j ds_j - ds_{j+1} + H_j dp    = -c_j      (j = 0 .. m-2)
//! ```
//!
//! (`G_j`, `H_j` the sensitivities of segment `j`'s end to its start and to `p`). Ordering
//! the unknowns `ds_0 .. ds_{m-2}` (the *core*) before the *border* `(ds_{m-1}, dp)` and the
//! rows `bc, c_0, .., c_{m-2}`, each row's core entries lie in a window of `2n` columns
//! starting at its first non-zero, and no step of elimination moves them out of it: the
//! candidates for the pivot of core column `c` are the rows not yet pivoted whose window
//! starts at or before `c` (at most `2n + k` of them), and the fill of their elimination
//! stays in the window and the border. The work is `O(m (n + k)^2 n)` and the storage
//! `O(m n (n + k))`, against `O(m^3 n^3)` and `O(m^2 n^2)` of a dense LU; the elimination is
//! LAPACK's `gbtrf` (banded LU with partial pivoting) with border columns carried along.
//! What remains, `n + k` rows in the border columns, is factored by faer's pivoted LU.
//!
//! Condensing (eliminating `ds_{j+1} = G_j ds_j + ...` forward, the textbook reduction to an
//! `(n + k)`-square system in `ds_0, dp`) was not used: it multiplies the `G_j` together,
//! which brings back single shooting's conditioning (`e^{k}` for `y'' = k^2 y`).

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use faer::linalg::solvers::Solve;
use faer::Mat;

use crate::BvpError;

/// A linear system with staircase rows and a dense border (module docs), being filled and
/// then solved.
#[derive(Clone, Debug)]
pub(crate) struct Staircase {
    /// Core columns.
    nc: usize,
    /// Border columns.
    nb: usize,
    /// Window width.
    w: usize,
    /// Per row: the first core column of its window.
    off: Vec<usize>,
    /// Per row: the window's entries (`w` each).
    core: Vec<f64>,
    /// Per row: the border entries (`nb` each).
    border: Vec<f64>,
    /// Right-hand side.
    rhs: Vec<f64>,
}

impl Staircase {
    /// `nc + nb` zero rows with windows of width `w`; `off[i]` the window start of row `i`
    /// (non-decreasing).
    pub(crate) fn new(nc: usize, nb: usize, w: usize, off: Vec<usize>) -> Self {
        let rows = nc + nb;
        debug_assert_eq!(off.len(), rows);
        debug_assert!(off.windows(2).all(|p| p[0] <= p[1]));
        Staircase {
            nc,
            nb,
            w,
            off,
            core: vec![0.0; rows * w],
            border: vec![0.0; rows * nb],
            rhs: vec![0.0; rows],
        }
    }

    /// Adds `v` at row `i`, column `col` (core columns first, then border).
    pub(crate) fn add(&mut self, i: usize, col: usize, v: f64) {
        if col >= self.nc {
            self.border[i * self.nb + col - self.nc] += v;
        } else {
            let t = col - self.off[i];
            debug_assert!(t < self.w, "row {i}: column {col} outside its window");
            self.core[i * self.w + t] += v;
        }
    }

    /// Sets the right-hand side of row `i`.
    pub(crate) fn set_rhs(&mut self, i: usize, v: f64) {
        self.rhs[i] = v;
    }

    /// Solves the system (consuming it).
    ///
    /// # Errors
    /// `SingularJacobian` with the row (column) and the largest candidate pivot where a
    /// core column has no non-zero pivot, or the border's LU has a pivot below
    /// `n eps max|U|`.
    pub(crate) fn solve(mut self) -> Result<Vec<f64>, BvpError> {
        let (nc, nb, w) = (self.nc, self.nb, self.w);
        let rows = nc + nb;
        // hi: rows at positions >= hi have never been swapped (they keep their order, with
        // window starts beyond the current column)
        let mut hi = 0;
        let scale = self.core.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for c in 0..nc {
            while hi < rows && self.off[hi] <= c {
                hi += 1;
            }
            // rebase the candidates' windows to start at c (their entries before c are 0)
            let mut best = (c, 0.0);
            for i in c..hi {
                let shift = c - self.off[i];
                if shift > 0 {
                    let row = &mut self.core[i * w..(i + 1) * w];
                    row.copy_within(shift.., 0);
                    row[w - shift..].fill(0.0);
                    self.off[i] = c;
                }
                let a = self.core[i * w].abs();
                if a > best.1 {
                    best = (i, a);
                }
            }
            let (p, pivot) = best;
            if !(pivot > f64::EPSILON * scale * 1e-3) {
                return Err(BvpError::SingularJacobian { row: c, pivot });
            }
            if p != c {
                self.swap(p, c);
            }
            let d = self.core[c * w];
            for i in c + 1..hi {
                let l = self.core[i * w] / d;
                if l == 0.0 {
                    continue;
                }
                let (top, bottom) = self.core.split_at_mut(i * w);
                let prow = &top[c * w..(c + 1) * w];
                for (t, v) in bottom[..w].iter_mut().enumerate() {
                    *v -= l * prow[t];
                }
                let (top, bottom) = self.border.split_at_mut(i * nb);
                let prow = &top[c * nb..(c + 1) * nb];
                for (t, v) in bottom[..nb].iter_mut().enumerate() {
                    *v -= l * prow[t];
                }
                self.rhs[i] -= l * self.rhs[c];
            }
        }
        // the border block: rows nc.., columns of the border
        let a = Mat::from_fn(nb, nb, |i, j| self.border[(nc + i) * nb + j]);
        let lu = a.partial_piv_lu();
        let u = lu.U();
        let big = (0..nb)
            .flat_map(|i| (i..nb).map(move |j| (i, j)))
            .map(|(i, j)| u[(i, j)].abs())
            .fold(0.0, f64::max);
        if let Some(i) = (0..nb).find(|&i| !(u[(i, i)].abs() > nb as f64 * f64::EPSILON * big)) {
            return Err(BvpError::SingularJacobian {
                row: nc + i,
                pivot: u[(i, i)],
            });
        }
        let b = Mat::from_fn(nb, 1, |i, _| self.rhs[nc + i]);
        let y = lu.solve(&b);
        let mut x = vec![0.0; rows];
        for i in 0..nb {
            x[nc + i] = y[(i, 0)];
        }
        // back substitution through the core
        for c in (0..nc).rev() {
            let row = &self.core[c * w..(c + 1) * w];
            let mut s = self.rhs[c];
            for (t, v) in row.iter().enumerate().skip(1) {
                if c + t < nc {
                    s -= v * x[c + t];
                }
            }
            for (j, v) in self.border[c * nb..(c + 1) * nb].iter().enumerate() {
                s -= v * x[nc + j];
            }
            x[c] = s / row[0];
        }
        Ok(x)
    }

    /// Swaps rows `a` and `b` (windows, starts, border, right-hand side).
    fn swap(&mut self, a: usize, b: usize) {
        let (w, nb) = (self.w, self.nb);
        for t in 0..w {
            self.core.swap(a * w + t, b * w + t);
        }
        for t in 0..nb {
            self.border.swap(a * nb + t, b * nb + t);
        }
        self.off.swap(a, b);
        self.rhs.swap(a, b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeded random multiple-shooting systems (n states, k parameters, m nodes, with
    /// non-separated boundary rows) solved by the staircase and checked by multiplying back
    /// into the dense matrix assembled independently.
    #[test]
    fn random_staircases_are_solved_to_rounding() {
        let mut seed = 99u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for case in 0..60 {
            let (n, k, m) = (1 + case % 4, case % 3, 2 + case % 7);
            let nc = (m - 1) * n;
            let nb = n + k;
            let size = nc + nb;
            let mut dense = vec![0.0; size * size];
            let mut off = vec![0; nb];
            off.extend((0..m - 1).flat_map(|j| std::iter::repeat_n(j * n, n)));
            let mut s = Staircase::new(nc, nb, 2 * n, off);
            let mut put = |s: &mut Staircase, i: usize, c: usize, v: f64| {
                s.add(i, c, v);
                dense[i * size + c] += v;
            };
            // boundary rows: s_0, s_{m-1} (first border block), p
            for i in 0..nb {
                for c in 0..n {
                    put(&mut s, i, c, rnd());
                    put(&mut s, i, nc + c, rnd());
                }
                for c in 0..k {
                    put(&mut s, i, nc + n + c, rnd());
                }
            }
            for j in 0..m - 1 {
                for r in 0..n {
                    let i = nb + j * n + r;
                    for c in 0..n {
                        put(&mut s, i, j * n + c, 3.0 * rnd());
                    }
                    put(&mut s, i, (j + 1) * n + r, -1.0);
                    for c in 0..k {
                        put(&mut s, i, nc + n + c, rnd());
                    }
                }
            }
            let b: Vec<f64> = (0..size).map(|_| rnd()).collect();
            for (i, v) in b.iter().enumerate() {
                s.set_rhs(i, *v);
            }
            let x = s.solve().unwrap();
            let res = (0..size)
                .map(|i| {
                    let ax: f64 = (0..size).map(|c| dense[i * size + c] * x[c]).sum();
                    (ax - b[i]).abs()
                })
                .fold(0.0, f64::max);
            let xmax = x.iter().map(|v| v.abs()).fold(1.0, f64::max);
            assert!(
                res < 1e-11 * xmax,
                "case {case} (n {n}, k {k}, m {m}): {res:e}"
            );
        }
    }

    #[test]
    fn a_singular_system_names_its_column() {
        // two identical rows
        let mut s = Staircase::new(1, 1, 2, vec![0, 0]);
        s.add(0, 0, 1.0);
        s.add(0, 1, 1.0);
        s.add(1, 0, 1.0);
        s.add(1, 1, 1.0);
        assert!(matches!(s.solve(), Err(BvpError::SingularJacobian { .. })));
    }
}
