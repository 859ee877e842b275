//! Mesh control as in Kierzenka & Shampine's bvp4c and scipy's `solve_bvp`: one node into
//! each interval whose relative residual is in `(tol, 100 tol)`, two (thirds) where it is
//! `>= 100 tol`.

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

#[cfg(test)]
mod tests {
    use super::*;

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
