//! The ABD Jacobian of a problem with **separated** boundary conditions, factored without
//! the border of [`super::abd`]: Gaussian elimination with partial (row) pivoting on the
//! matrix in the staircase order of de Boor & Weiss's SOLVEBLOK,
//!
//! ```text
//! [ Ba_a            Bp_a ]   the n_a boundary rows free of y(b)
//! [ A_0  C_0        P_0  ]   interval 0
//! [      A_1  C_1   P_1  ]   interval 1
//! [           ...        ]
//! [           Bb_b  Bp_b ]   the n_b = n + k - n_a rows free of y(a)
//! ```
//!
//! Stage `j` eliminates the `n` columns of `y_j` from the `n_a` rows carried from the stage
//! before (in `y_j` and `p`; at stage 0 the rows of `Ba_a`) stacked on interval `j`'s `n`
//! rows, pivoting over these `n_a + n` rows, which are all the rows with an entry in those
//! columns: the elimination is plain GEPP of the reordered matrix, and as stable. The `n`
//! pivot rows are kept for back substitution, the other `n_a` rows (in `y_{j+1}` and `p`)
//! are the next carry. The last carry and the `n_b` rows of `Bb_b` form a dense square
//! system of `n + k` unknowns `(y_{m-1}, p)`.
//!
//! Against the bordered elimination (which carries `y_0` through every interval because a
//! general boundary row may couple both ends): rows of width `2n + k` instead of `3n + k`,
//! `n_a + n` rows per stage instead of `2n`, and a final system of `n + k` instead of
//! `2n + k` unknowns; for scipy's `big_problem` (`n = 60`, `n_a = 30`) 2.3x fewer
//! instructions in the factorisation and 1.8x in a solve (`docs/bvp20.md`).

// Index arithmetic on flat row-major blocks (`a[r * n + c]`) reads as the equations do.
#![allow(clippy::needless_range_loop)]

use super::abd::{pivot, AbdMatrix};
use crate::BvpError;

/// The factors of an [`AbdMatrix`] with separated boundary rows (module doc).
#[derive(Debug, Clone, Default)]
pub struct SeparatedLu {
    n: usize,
    k: usize,
    m: usize,
    /// Row width `2n + k` (`y_j | y_{j+1} | p`).
    w: usize,
    /// The boundary rows free of `y(b)` (their indices in `bc`), then those free of `y(a)`.
    a_rows: Vec<usize>,
    b_rows: Vec<usize>,
    /// Per stage (`m - 1`): the swap of each of the `n` steps.
    swaps: Vec<usize>,
    /// Per stage: multipliers `l[step][row]`, `n * (n_a + n)`.
    mult: Vec<f64>,
    /// Per stage: the `n` pivot rows, `n * w`.
    piv: Vec<f64>,
    /// The final dense LU, `(n+k)^2`, and its row permutation.
    fin: Vec<f64>,
    fin_perm: Vec<usize>,
    /// Scratch: the carry and the interval's rows.
    work: Vec<f64>,
}

/// Whether row `r` of a row-major block of width `n` is zero.
fn zero_row(b: &[f64], r: usize, n: usize) -> bool {
    b[r * n..(r + 1) * n].iter().all(|&v| v == 0.0)
}

impl SeparatedLu {
    /// Bytes held (capacities).
    pub fn bytes(&self) -> usize {
        let v = [&self.mult, &self.piv, &self.fin, &self.work];
        let u = [&self.swaps, &self.fin_perm, &self.a_rows, &self.b_rows];
        v.iter().map(|b| b.capacity()).sum::<usize>() * std::mem::size_of::<f64>()
            + u.iter().map(|b| b.capacity()).sum::<usize>() * std::mem::size_of::<usize>()
    }

    /// Factors `mat` if its boundary rows are separated (every row of `bc` has a zero
    /// derivative with respect to `y(a)` or to `y(b)`; `p` may enter any), reusing the
    /// buffers; `Ok(false)` (nothing factored) if a row couples both ends.
    /// [`BvpError::SingularJacobian`] as [`super::abd::AbdLu::factor`].
    pub fn factor_into(&mut self, mat: &AbdMatrix) -> Result<bool, BvpError> {
        let (n, k, m) = (mat.n, mat.k, mat.m);
        let nbc = n + k;
        self.a_rows.clear();
        self.b_rows.clear();
        for r in 0..nbc {
            let free_a = zero_row(&mat.ba, r, n);
            let free_b = zero_row(&mat.bb, r, n);
            match (free_a, free_b) {
                (_, true) => self.a_rows.push(r),
                (true, false) => self.b_rows.push(r),
                (false, false) => return Ok(false),
            }
        }
        let na = self.a_rows.len();
        let w = 2 * n + k;
        let tiny = mat.pivot_floor()?;
        let nst = m - 1;
        let nr = na + n;
        let nf = n + k;
        (self.n, self.k, self.m, self.w) = (n, k, m, w);
        // every entry read later is written below: resized, never cleared
        self.swaps.resize(nst * n, 0);
        self.mult.resize(nst * n * nr, 0.0);
        self.piv.resize(nst * n * w, 0.0);
        self.fin.resize(nf * nf, 0.0);
        self.fin_perm.resize(nf, 0);
        self.work.resize(nr * w, 0.0);
        let work = &mut self.work;
        // the first carry: the rows free of y(b), in y_0 | (y_1: none) | p
        for (i, &r) in self.a_rows.iter().enumerate() {
            let row = &mut work[i * w..(i + 1) * w];
            row[..n].copy_from_slice(&mat.ba[r * n..(r + 1) * n]);
            row[n..2 * n].fill(0.0);
            row[2 * n..].copy_from_slice(&mat.bp[r * k..(r + 1) * k]);
        }
        for j in 0..nst {
            // interval j's rows below the carry: y_j -> [0, n), y_{j+1} -> [n, 2n)
            for r in 0..n {
                let row = &mut work[(na + r) * w..(na + r + 1) * w];
                row[..n].copy_from_slice(&mat.a[(j * n + r) * n..(j * n + r + 1) * n]);
                row[n..2 * n].copy_from_slice(&mat.c[(j * n + r) * n..(j * n + r + 1) * n]);
                row[2 * n..].copy_from_slice(&mat.p[(j * n + r) * k..(j * n + r + 1) * k]);
            }
            for s in 0..n {
                self.swaps[j * n + s] = pivot(work, w, (s, s, nr), tiny, j * n + s)?;
                let inv = 1.0 / work[s * w + s];
                let (top, bottom) = work.split_at_mut((s + 1) * w);
                let prow = &top[s * w + s..(s + 1) * w];
                let mult = &mut self.mult[(j * n + s) * nr..(j * n + s + 1) * nr];
                for (rr, l_out) in bottom.chunks_exact_mut(w).zip(&mut mult[s + 1..]) {
                    let l = rr[s] * inv;
                    *l_out = l;
                    if l != 0.0 {
                        for (a, b) in rr[s..].iter_mut().zip(prow) {
                            *a -= l * b;
                        }
                    }
                    rr[s] = 0.0;
                }
            }
            self.piv[j * n * w..(j + 1) * n * w].copy_from_slice(&work[..n * w]);
            // the new carry: rows n..nr, y_{j+1} moves to the current slot
            for r in 0..na {
                let src = (n + r) * w;
                let dst = r * w;
                work.copy_within(src + n..src + 2 * n, dst);
                work[dst + n..dst + 2 * n].fill(0.0);
                work.copy_within(src + 2 * n..src + w, dst + 2 * n);
            }
        }
        // final system in (y_{m-1}, p): the carry, then the rows free of y(a)
        let fin = &mut self.fin;
        for r in 0..na {
            let row = &mut fin[r * nf..(r + 1) * nf];
            row[..n].copy_from_slice(&work[r * w..r * w + n]);
            row[n..].copy_from_slice(&work[r * w + 2 * n..(r + 1) * w]);
        }
        for (i, &r) in self.b_rows.iter().enumerate() {
            let row = &mut fin[(na + i) * nf..(na + i + 1) * nf];
            row[..n].copy_from_slice(&mat.bb[r * n..(r + 1) * n]);
            row[n..].copy_from_slice(&mat.bp[r * k..(r + 1) * k]);
        }
        let perm = &mut self.fin_perm;
        for (i, v) in perm.iter_mut().enumerate() {
            *v = i;
        }
        for s in 0..nf {
            let best = pivot(fin, nf, (s, s, nf), tiny, (m - 1) * n + s)?;
            perm.swap(s, best);
            let inv = 1.0 / fin[s * nf + s];
            let (top, bottom) = fin.split_at_mut((s + 1) * nf);
            let prow = &top[s * nf + s + 1..(s + 1) * nf];
            for rr in bottom.chunks_exact_mut(nf) {
                let l = rr[s] * inv;
                rr[s] = l;
                if l != 0.0 {
                    for (a, b) in rr[s + 1..].iter_mut().zip(prow) {
                        *a -= l * b;
                    }
                }
            }
        }
        Ok(true)
    }

    /// Solves `J x = b` in place, as [`super::abd::AbdLu::solve_in_place`] (`b` ordered as
    /// the rows: intervals, then all `n + k` boundary rows in `bc`'s order; `x` as the
    /// unknowns `y_0, ..., y_{m-1}, p`). `tmp` is scratch of any length.
    pub fn solve_in_place(&self, b: &mut [f64], tmp: &mut Vec<f64>) {
        let (n, k, m, w) = (self.n, self.k, self.m, self.w);
        let na = self.a_rows.len();
        let nst = m - 1;
        let nr = na + n;
        let nf = n + k;
        // tmp: pivot-row rhs per stage (nst * n), the working rhs (nr), the final rhs (nf);
        // every entry is written before it is read: no clearing
        tmp.resize(nst * n + nr + nf, 0.0);
        let (prhs, rest) = tmp.split_at_mut(nst * n);
        let (wr, fr) = rest.split_at_mut(nr);
        let bc = &b[(m - 1) * n..];
        for (i, &r) in self.a_rows.iter().enumerate() {
            wr[i] = bc[r];
        }
        for j in 0..nst {
            wr[na..].copy_from_slice(&b[j * n..(j + 1) * n]);
            for s in 0..n {
                wr.swap(s, self.swaps[j * n + s]);
                let ws = wr[s];
                if ws != 0.0 {
                    let mult = &self.mult[(j * n + s) * nr..(j * n + s + 1) * nr];
                    for (v, l) in wr[s + 1..].iter_mut().zip(&mult[s + 1..]) {
                        *v -= l * ws;
                    }
                }
            }
            prhs[j * n..(j + 1) * n].copy_from_slice(&wr[..n]);
            wr.copy_within(n..nr, 0);
        }
        // final system: carry, then the rows free of y(a)
        let bc = &b[(m - 1) * n..];
        for (i, &pi) in self.fin_perm.iter().enumerate() {
            fr[i] = if pi < na {
                wr[pi]
            } else {
                bc[self.b_rows[pi - na]]
            };
        }
        for s in 0..nf {
            let v = fr[s];
            if v != 0.0 {
                for r in s + 1..nf {
                    fr[r] -= self.fin[r * nf + s] * v;
                }
            }
        }
        for s in (0..nf).rev() {
            let row = &self.fin[s * nf..(s + 1) * nf];
            let v: f64 = fr[s] - dot(&row[s + 1..], &fr[s + 1..]);
            fr[s] = v / row[s];
        }
        // unknowns: y_{m-1}, p
        b[(m - 1) * n..m * n].copy_from_slice(&fr[..n]);
        b[m * n..].copy_from_slice(&fr[n..]);
        // back substitution for y_{m-2}, ..., y_0
        for j in (0..nst).rev() {
            let (head, tail) = b.split_at_mut((j + 1) * n);
            let yj = &mut head[j * n..];
            let next = &tail[..n];
            let p = &tail[tail.len() - k..];
            for s in (0..n).rev() {
                let row = &self.piv[(j * n + s) * w..(j * n + s + 1) * w];
                let v = prhs[j * n + s]
                    - dot(&row[n..2 * n], next)
                    - dot(&row[2 * n..], p)
                    - dot(&row[s + 1..n], &yj[s + 1..]);
                yj[s] = v / row[s];
            }
        }
    }
}

/// `a . b` over the shorter length.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::super::tests::{dense_solve, to_dense, Rng};
    use super::*;

    /// Random blocks with separated boundary rows: `n_a` rows free of `y(b)`, the others
    /// free of `y(a)`, in a random order; `p` enters any row.
    fn random_separated(rng: &mut Rng, n: usize, k: usize, m: usize, na: usize) -> AbdMatrix {
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
        // row r is an a-row if it is among the first na of a random order
        let mut order: Vec<usize> = (0..n + k).collect();
        for i in (1..order.len()).rev() {
            let j = ((rng.next() + 1.0) * 0.5 * (i + 1) as f64) as usize % (i + 1);
            order.swap(i, j);
        }
        for (pos, &r) in order.iter().enumerate() {
            let blk = if pos < na { &mut mat.bb } else { &mut mat.ba };
            blk[r * n..(r + 1) * n].fill(0.0);
        }
        mat
    }

    /// 400 random separated systems (n 1..=6, k 0..=2, m 2..=12, every split `n_a` of the
    /// `n + k` boundary rows from 0 to `n + k`): the elimination without the border agrees
    /// with dense pivoted LU to 1e-9 relative, and its residual `|J x - b|` is as small.
    #[test]
    fn separated_matches_dense_lu_on_a_random_battery() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let mut worst = 0.0f64;
        let mut lu = SeparatedLu::default();
        for case in 0..400 {
            let n = 1 + case % 6;
            let k = (case / 6) % 3;
            let m = 2 + (case * 7) % 11;
            let na = (case / 18) % (n + k + 1);
            let mat = random_separated(&mut rng, n, k, m, na);
            let nt = m * n + k;
            let b: Vec<f64> = (0..nt).map(|_| rng.next()).collect();
            let xref = dense_solve(to_dense(&mat), b.clone());
            // one factor object for all cases: a dirty workspace of other sizes
            assert!(lu.factor_into(&mat).unwrap(), "case {case}: not separated");
            let mut x = b.clone();
            lu.solve_in_place(&mut x, &mut vec![f64::NAN; 7]);
            let scale = xref.iter().fold(1.0f64, |s, v| s.max(v.abs()));
            let err = x
                .iter()
                .zip(&xref)
                .fold(0.0f64, |s, (u, v)| s.max((u - v).abs()))
                / scale;
            worst = worst.max(err);
            let res = mat
                .mul(&x)
                .iter()
                .zip(&b)
                .fold(0.0f64, |s, (u, v)| s.max((u - v).abs()));
            assert!(res < 1e-9 * scale, "case {case}: residual {res:e}");
        }
        assert!(worst < 1e-9, "worst relative difference {worst:e}");
    }

    /// A row that couples both ends (periodic) is left to the bordered elimination.
    #[test]
    fn a_coupled_row_is_not_separated() {
        let mut rng = Rng(7);
        let mut mat = random_separated(&mut rng, 3, 1, 5, 2);
        let r = (0..4).find(|&r| mat.bb[r * 3..r * 3 + 3].iter().all(|&v| v == 0.0));
        mat.bb[r.unwrap() * 3] = 0.5;
        assert!(!SeparatedLu::default().factor_into(&mat).unwrap());
    }

    /// A zero boundary row is a singular Jacobian, reported with a row.
    #[test]
    fn a_singular_system_is_an_error() {
        let mut mat = AbdMatrix::zeros(1, 0, 4);
        mat.a.fill(-1.0);
        mat.c.fill(1.0);
        let err = SeparatedLu::default().factor_into(&mat).unwrap_err();
        assert!(matches!(err, BvpError::SingularJacobian { .. }), "{err}");
    }
}
