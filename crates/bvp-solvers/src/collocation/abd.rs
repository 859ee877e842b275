//! The almost-block-diagonal (ABD) linear system of the collocation Newton step, solved by
//! structured Gaussian elimination with partial pivoting (Wright's "stable compactification"
//! ordering, as in the bordered ABD solvers of COLNEW's successors).
//!
//! The unknowns are the node values `y_0, ..., y_{m-1}` (`n` each) and the parameters `p`
//! (`k`). Interval `j` contributes `n` rows `A_j y_j + C_j y_{j+1} + P_j p = r_j` (the
//! derivative of the collocation residual [`super::system::System::collocation`], eq. (2) of the module doc);
//! the boundary conditions give `n + k` rows `Ba y_0 + Bb y_{m-1} + Bp p = r_bc`, which may
//! couple both ends (periodic, non-separated) and the parameters.
//!
//! Elimination keeps `y_0` and `p` as border columns. A *carry* of `n` rows in
//! `(y_0, y_j, p)` is stacked on interval `j`'s rows in `(y_j, y_{j+1}, p)`; the `n` columns
//! of `y_j` are eliminated over these `2n` rows with row pivoting. The `n` pivot rows are kept
//! for back substitution, the other `n` rows (free of `y_j`) are the next carry, in
//! `(y_0, y_{j+1}, p)`. The last carry and the boundary rows form a dense square system of
//! `2n + k` unknowns `(y_0, y_{m-1}, p)`, solved by pivoted LU. Cost `O(m n^3)`, storage
//! `O(m n^2)`; the factors are kept so that the simplified Newton iterations re-solve with a
//! new right-hand side at `O(m n^2)`. Pivoting is over the rows of two neighbouring
//! intervals, which keeps growing and decaying modes of dichotomic problems bounded (tested
//! on a boundary layer and against a dense LU on random systems).

// Index arithmetic on flat row-major blocks (`a[r * n + c]`) reads as the equations do.
#![allow(clippy::needless_range_loop)]

use crate::BvpError;

/// Row-major blocks of the ABD Jacobian (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct AbdMatrix {
    /// States per node.
    pub n: usize,
    /// Unknown parameters.
    pub k: usize,
    /// Nodes.
    pub m: usize,
    /// `A_j` (coefficient of `y_j` in interval `j`'s rows), `(m-1) * n * n`.
    pub a: Vec<f64>,
    /// `C_j` (coefficient of `y_{j+1}`), `(m-1) * n * n`.
    pub c: Vec<f64>,
    /// `P_j` (coefficient of `p`), `(m-1) * n * k`.
    pub p: Vec<f64>,
    /// `Ba`, `(n+k) * n`.
    pub ba: Vec<f64>,
    /// `Bb`, `(n+k) * n`.
    pub bb: Vec<f64>,
    /// `Bp`, `(n+k) * k`.
    pub bp: Vec<f64>,
}

impl AbdMatrix {
    /// Zeroed blocks for `m` nodes, `n` states and `k` parameters.
    pub fn zeros(n: usize, k: usize, m: usize) -> Self {
        let mi = m.saturating_sub(1);
        Self {
            n,
            k,
            m,
            a: vec![0.0; mi * n * n],
            c: vec![0.0; mi * n * n],
            p: vec![0.0; mi * n * k],
            ba: vec![0.0; (n + k) * n],
            bb: vec![0.0; (n + k) * n],
            bp: vec![0.0; (n + k) * k],
        }
    }

    /// Sizes the blocks for `m` nodes, `n` states and `k` parameters, keeping the buffers
    /// (and any old values: the caller writes every block before it is factored).
    pub fn resize(&mut self, n: usize, k: usize, m: usize) {
        let mi = m.saturating_sub(1);
        (self.n, self.k, self.m) = (n, k, m);
        self.a.resize(mi * n * n, 0.0);
        self.c.resize(mi * n * n, 0.0);
        self.p.resize(mi * n * k, 0.0);
        self.ba.resize((n + k) * n, 0.0);
        self.bb.resize((n + k) * n, 0.0);
        self.bp.resize((n + k) * k, 0.0);
    }

    /// Bytes held (capacities).
    pub fn bytes(&self) -> usize {
        let v = [&self.a, &self.c, &self.p, &self.ba, &self.bb, &self.bp];
        v.iter().map(|b| b.capacity()).sum::<usize>() * std::mem::size_of::<f64>()
    }

    /// The smallest pivot the eliminations accept: `1e-14` of the matrix's largest entry;
    /// [`BvpError::NonFinite`] where an entry is not finite.
    pub(super) fn pivot_floor(&self) -> Result<f64, BvpError> {
        let scale = self
            .a
            .iter()
            .chain(&self.c)
            .chain(&self.p)
            .chain(&self.ba)
            .chain(&self.bb)
            .chain(&self.bp)
            .fold(0.0f64, |s, v| s.max(v.abs()));
        if !scale.is_finite() {
            return Err(BvpError::NonFinite {
                what: "collocation Jacobian",
                s: f64::NAN,
            });
        }
        Ok(1e-14 * scale)
    }

    /// The product `J x` (for tests and residual checks); `x` ordered `[y_0, ..., y_{m-1}, p]`.
    pub fn mul(&self, x: &[f64]) -> Vec<f64> {
        let (n, k, m) = (self.n, self.k, self.m);
        let xp = &x[m * n..];
        let mut out = vec![0.0; m * n + k];
        for j in 0..m - 1 {
            for r in 0..n {
                let mut s = 0.0;
                for c in 0..n {
                    s += self.a[(j * n + r) * n + c] * x[j * n + c];
                    s += self.c[(j * n + r) * n + c] * x[(j + 1) * n + c];
                }
                for c in 0..k {
                    s += self.p[(j * n + r) * k + c] * xp[c];
                }
                out[j * n + r] = s;
            }
        }
        for r in 0..n + k {
            let mut s = 0.0;
            for c in 0..n {
                s += self.ba[r * n + c] * x[c] + self.bb[r * n + c] * x[(m - 1) * n + c];
            }
            for c in 0..k {
                s += self.bp[r * k + c] * xp[c];
            }
            out[(m - 1) * n + r] = s;
        }
        out
    }
}

/// One step of partial pivoting on the rows `s..rows` of the row-major block `a` of width
/// `w`: the row of the largest `|a[r][col]|` (the first of equals) swapped into row `s`, its
/// index returned. [`BvpError::SingularJacobian`] (at the Jacobian's row `row`) where that
/// pivot is NaN or at most `tiny`. Shared by the bordered elimination here and the
/// separated one ([`super::separated`]).
pub(super) fn pivot(
    a: &mut [f64],
    w: usize,
    (s, col, rows): (usize, usize, usize),
    tiny: f64,
    row: usize,
) -> Result<usize, BvpError> {
    let mut best = s;
    let mut bv = a[s * w + col].abs();
    for r in s + 1..rows {
        let v = a[r * w + col].abs();
        if v > bv {
            bv = v;
            best = r;
        }
    }
    if bv.is_nan() || bv <= tiny {
        return Err(BvpError::SingularJacobian { row, pivot: bv });
    }
    if best != s {
        let (top, bottom) = a.split_at_mut(best * w);
        top[s * w..(s + 1) * w].swap_with_slice(&mut bottom[..w]);
    }
    Ok(best)
}

/// The factors of an [`AbdMatrix`]: per interval the row swaps, multipliers and pivot rows,
/// and the pivoted LU of the final `(2n + k)` system.
#[derive(Debug, Clone, Default)]
pub struct AbdLu {
    n: usize,
    k: usize,
    m: usize,
    /// Row width of the working rows: `3n + k` (`y_0 | y_j | y_{j+1} | p`).
    w: usize,
    /// Per eliminated interval (`m - 2` of them): the swap of each of the `n` steps.
    swaps: Vec<usize>,
    /// Per eliminated interval: multipliers `l[step][row]`, `n * 2n`.
    mult: Vec<f64>,
    /// Per eliminated interval: the `n` pivot rows, `n * w`.
    piv: Vec<f64>,
    /// The final dense LU, `(2n+k)^2`, and its row permutation.
    fin: Vec<f64>,
    fin_perm: Vec<usize>,
    /// Scratch of the elimination: the carry and the interval's rows, `2n * w`.
    work: Vec<f64>,
}

impl AbdLu {
    /// Factors `mat`; [`BvpError::SingularJacobian`] with the global row (`j * n + step`) and
    /// pivot when a pivot is zero or below `1e-14` of the matrix's largest entry.
    pub fn factor(mat: &AbdMatrix) -> Result<Self, BvpError> {
        let mut lu = AbdLu::default();
        lu.factor_into(mat)?;
        Ok(lu)
    }

    /// [`Self::factor`] into `self`, reusing its buffers (no allocation once they have
    /// grown to the mesh's size: the Newton iterations and meshes of one solve share them).
    pub fn factor_into(&mut self, mat: &AbdMatrix) -> Result<(), BvpError> {
        let (n, k, m) = (mat.n, mat.k, mat.m);
        let w = 3 * n + k;
        let tiny = mat.pivot_floor()?;
        let nint = m - 1;
        let nel = nint.saturating_sub(1);
        let nf = 2 * n + k;
        (self.n, self.k, self.m, self.w) = (n, k, m, w);
        // every entry read later is written below: resizing keeps old values, fills no memory
        let lu = self;
        lu.swaps.resize(nel * n, 0);
        lu.mult.resize(nel * n * 2 * n, 0.0);
        lu.piv.resize(nel * n * w, 0.0);
        lu.fin.resize(nf * nf, 0.0);
        lu.fin_perm.resize(nf, 0);
        lu.work.resize(2 * n * w, 0.0);
        let work = &mut lu.work;
        // carry: n rows of width w, columns y_0 | y_cur | (unused) | p
        for r in 0..n {
            let row = &mut work[r * w..(r + 1) * w];
            row[..n].copy_from_slice(&mat.a[r * n..(r + 1) * n]);
            row[n..2 * n].copy_from_slice(&mat.c[r * n..(r + 1) * n]);
            row[2 * n..3 * n].fill(0.0);
            row[3 * n..].copy_from_slice(&mat.p[r * k..(r + 1) * k]);
        }
        for e in 0..nel {
            let j = e + 1;
            // rows n..2n: interval j, columns y_j -> [n, 2n), y_{j+1} -> [2n, 3n)
            for r in 0..n {
                let row = &mut work[(n + r) * w..(n + r + 1) * w];
                row[..n].fill(0.0);
                row[n..2 * n].copy_from_slice(&mat.a[(j * n + r) * n..(j * n + r + 1) * n]);
                row[2 * n..3 * n].copy_from_slice(&mat.c[(j * n + r) * n..(j * n + r + 1) * n]);
                row[3 * n..].copy_from_slice(&mat.p[(j * n + r) * k..(j * n + r + 1) * k]);
            }
            for s in 0..n {
                let col = n + s;
                lu.swaps[e * n + s] = pivot(work, w, (s, col, 2 * n), tiny, j * n + s)?;
                let d = work[s * w + col];
                let (top, bottom) = work.split_at_mut((s + 1) * w);
                let prow = &top[s * w..];
                for r in s + 1..2 * n {
                    let rr = &mut bottom[(r - s - 1) * w..(r - s) * w];
                    let l = rr[col] / d;
                    lu.mult[(e * n + s) * 2 * n + r] = l;
                    if l != 0.0 {
                        for c in col..w {
                            rr[c] -= l * prow[c];
                        }
                        for c in 0..n {
                            rr[c] -= l * prow[c];
                        }
                    }
                    rr[col] = 0.0;
                }
            }
            lu.piv[e * n * w..(e + 1) * n * w].copy_from_slice(&work[..n * w]);
            // the new carry: rows n..2n, y_{j+1} moves to the current slot
            for r in 0..n {
                let src = (n + r) * w;
                let dst = r * w;
                for c in 0..n {
                    work[dst + c] = work[src + c];
                    work[dst + n + c] = work[src + 2 * n + c];
                    work[dst + 2 * n + c] = 0.0;
                }
                for c in 0..k {
                    work[dst + 3 * n + c] = work[src + 3 * n + c];
                }
            }
        }
        // final system in (y_0, y_{m-1}, p): carry rows then boundary rows
        let fin = &mut lu.fin;
        for r in 0..n {
            let row = &mut fin[r * nf..(r + 1) * nf];
            row[..2 * n].copy_from_slice(&work[r * w..r * w + 2 * n]);
            row[2 * n..].copy_from_slice(&work[r * w + 3 * n..(r + 1) * w]);
        }
        for r in 0..n + k {
            let row = &mut fin[(n + r) * nf..(n + r + 1) * nf];
            row[..n].copy_from_slice(&mat.ba[r * n..(r + 1) * n]);
            row[n..2 * n].copy_from_slice(&mat.bb[r * n..(r + 1) * n]);
            row[2 * n..].copy_from_slice(&mat.bp[r * k..(r + 1) * k]);
        }
        let perm = &mut lu.fin_perm;
        for (i, v) in perm.iter_mut().enumerate() {
            *v = i;
        }
        for s in 0..nf {
            let best = pivot(fin, nf, (s, s, nf), tiny, (m - 1) * n + s)?;
            perm.swap(s, best);
            let d = fin[s * nf + s];
            for r in s + 1..nf {
                let l = fin[r * nf + s] / d;
                fin[r * nf + s] = l;
                if l != 0.0 {
                    for c in s + 1..nf {
                        fin[r * nf + c] -= l * fin[s * nf + c];
                    }
                }
            }
        }
        Ok(())
    }

    /// Bytes held (capacities).
    pub fn bytes(&self) -> usize {
        let v = [&self.mult, &self.piv, &self.fin, &self.work];
        let u = [&self.swaps, &self.fin_perm];
        v.iter().map(|b| b.capacity()).sum::<usize>() * std::mem::size_of::<f64>()
            + u.iter().map(|b| b.capacity()).sum::<usize>() * std::mem::size_of::<usize>()
    }

    /// Solves `J x = b` in place (`b` ordered as the rows: intervals, then boundary rows; `x`
    /// as the unknowns: `y_0, ..., y_{m-1}, p`). `tmp` is scratch of any length.
    pub fn solve_in_place(&self, b: &mut [f64], tmp: &mut Vec<f64>) {
        let (n, k, m, w) = (self.n, self.k, self.m, self.w);
        let nel = (m - 1).saturating_sub(1);
        let nf = 2 * n + k;
        // tmp: pivot-row rhs per eliminated interval (nel * n), then 2n working rhs, then nf
        // every entry is written before it is read: no clearing
        tmp.resize(nel * n + 2 * n + nf, 0.0);
        let (prhs, rest) = tmp.split_at_mut(nel * n);
        let (wr, fr) = rest.split_at_mut(2 * n);
        wr[..n].copy_from_slice(&b[..n]);
        for e in 0..nel {
            let j = e + 1;
            wr[n..].copy_from_slice(&b[j * n..(j + 1) * n]);
            for s in 0..n {
                let best = self.swaps[e * n + s];
                wr.swap(s, best);
                let ws = wr[s];
                for r in s + 1..2 * n {
                    wr[r] -= self.mult[(e * n + s) * 2 * n + r] * ws;
                }
            }
            prhs[e * n..(e + 1) * n].copy_from_slice(&wr[..n]);
            wr.copy_within(n..2 * n, 0);
        }
        // final system
        // the right-hand side (carry, then boundary rows) in the pivoted order
        let bb = &b[(m - 1) * n..];
        for (i, &pi) in self.fin_perm.iter().enumerate() {
            fr[i] = if pi < n { wr[pi] } else { bb[pi - n] };
        }
        for s in 0..nf {
            let v = fr[s];
            for r in s + 1..nf {
                fr[r] -= self.fin[r * nf + s] * v;
            }
        }
        for s in (0..nf).rev() {
            let mut v = fr[s];
            for c in s + 1..nf {
                v -= self.fin[s * nf + c] * fr[c];
            }
            fr[s] = v / self.fin[s * nf + s];
        }
        // unknowns: y_0, y_{m-1}, p
        b[..n].copy_from_slice(&fr[..n]);
        b[(m - 1) * n..m * n].copy_from_slice(&fr[n..2 * n]);
        b[m * n..].copy_from_slice(&fr[2 * n..]);
        // back substitution for y_{m-2}, ..., y_1
        for e in (0..nel).rev() {
            let j = e + 1;
            for s in (0..n).rev() {
                let row = &self.piv[(e * n + s) * w..(e * n + s + 1) * w];
                let mut v = prhs[e * n + s];
                for c in 0..n {
                    v -= row[c] * fr[c]; // y_0
                    v -= row[2 * n + c] * b[(j + 1) * n + c]; // y_{j+1}
                }
                for c in 0..k {
                    v -= row[3 * n + c] * fr[2 * n + c];
                }
                for c in s + 1..n {
                    v -= row[n + c] * b[j * n + c];
                }
                b[j * n + s] = v / row[n + s];
            }
        }
    }
}
