//! Mesh control as in Kierzenka & Shampine's bvp4c and scipy's `solve_bvp`: one node into
//! each interval whose relative residual is in `(tol, 100 tol)`, two (thirds) where it is
//! `>= 100 tol`; and, in the same pass, the removal of a node between two intervals whose
//! residuals are so far below `tol` that the merged interval is predicted to meet `tol / 2`
//! (node removal as bvp4c does it; the rule and its threshold are ours, see [`MERGE_RATIO`]).

// Index arithmetic on flat row-major blocks (`a[r * n + c]`) reads as the equations do.
#![allow(clippy::needless_range_loop)]

/// The refined mesh: midpoints of the intervals in `insert_1`, thirds of those in
/// `insert_2` (scipy's `modify_mesh`).
pub fn modify_mesh(x: &[f64], insert_1: &[usize], insert_2: &[usize]) -> Vec<f64> {
    let mut out = Vec::with_capacity(x.len() + insert_1.len() + 2 * insert_2.len());
    let (mut a, mut b) = (0, 0);
    for i in 0..x.len() {
        out.push(x[i]);
        while a < insert_1.len() && insert_1[a] < i {
            a += 1;
        }
        while b < insert_2.len() && insert_2[b] < i {
            b += 1;
        }
        if a < insert_1.len() && insert_1[a] == i {
            out.push(0.5 * (x[i] + x[i + 1]));
        }
        if b < insert_2.len() && insert_2[b] == i {
            out.push((2.0 * x[i] + x[i + 1]) / 3.0);
            out.push((x[i] + 2.0 * x[i + 1]) / 3.0);
        }
    }
    out
}

/// Residual ratio below which two neighbouring intervals are merged. The residual of the
/// collocating cubic is `O(h^3)` (the derivative of an `O(h^4)` interpolation error), so
/// doubling `h` multiplies it by about 8; with `2^3.5 = 11.3` as the margin, the merged
/// interval is predicted below `tol / 2`.
pub const MERGE_RATIO: f64 = 1.0 / 22.7;

/// Nodes to remove: the node between intervals `i` and `i + 1` when neither is refined,
/// both residuals are below `MERGE_RATIO tol` and neither neighbour was merged already.
pub fn removable(rms: &[f64], tol: f64, refine: &[bool]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut i = 0;
    while i + 1 < rms.len() {
        if !refine[i]
            && !refine[i + 1]
            && rms[i] < MERGE_RATIO * tol
            && rms[i + 1] < MERGE_RATIO * tol
        {
            out.push(i + 1);
            i += 2;
        } else {
            i += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs of quiet intervals merge, never across a refined one nor twice in a row.
    #[test]
    fn removable_nodes() {
        let t = 1e-3;
        let q = 1e-6;
        let rms = [q, q, q, 2e-3, q, q, q, q];
        let refine: Vec<bool> = rms.iter().map(|&r| r > t).collect();
        assert_eq!(removable(&rms, t, &refine), vec![1, 5, 7]);
    }

    /// scipy's `test_modify_mesh`, both cases.
    #[test]
    fn modify_mesh_matches_scipy() {
        let x = modify_mesh(&[0.0, 1.0, 3.0, 9.0], &[0], &[2]);
        assert_eq!(x, vec![0.0, 0.5, 1.0, 3.0, 5.0, 7.0, 9.0]);
        let x = modify_mesh(&[-6.0, -3.0, 0.0, 3.0, 6.0], &[1], &[0, 2, 3]);
        assert_eq!(
            x,
            vec![-6.0, -5.0, -4.0, -3.0, -1.5, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
        );
    }
}
