//! Standard errors, correlations and the identifiability verdict of a fit from its
//! (whitened) Jacobian `J`, columns scaled to unit norm (`Js = J S^-1`, `S = diag |J_i|`):
//!
//! - singular values `sigma_k` of `Js` (one-sided Jacobi SVD, accurate to the last digits
//!   for the small singular values, unlike the eigenvalues of `J^T J`);
//! - a direction `v_k` with `sigma_k <= NULL_RATIO sigma_max` is a (near-)null direction of
//!   the Fisher information `J^T J`: the residuals do not change along it;
//! - a parameter with a component `|v_k,i| > NULL_COMPONENT` in a null direction is not
//!   identifiable; the combinations of those parameters orthogonal to the null directions
//!   are what the logs determine;
//! - the covariance is `s^2 S^-1 V Sigma^-2 V^T S^-1` over the non-null directions (the
//!   pseudo-inverse of the Fisher information), `s^2` the residual variance.

use super::fit::dot;

/// Relative singular value below which a direction is taken as null: the central-difference
/// Jacobian of integrations at 1e-12 leaves exactly singular directions at 1e-9..1.3e-6
/// (measured on free-whisker logs, where three columns are parallel); an identifiable but
/// weak direction at 1e-5 would have standard errors 1e5 times the noise level.
pub const NULL_RATIO: f64 = 1e-5;
/// Component of a null direction beyond which a parameter takes part in it.
pub const NULL_COMPONENT: f64 = 0.01;

/// Singular values and right singular vectors of the columns `cols` (`m x n`, column
/// major) by one-sided Jacobi rotations: returns `(sigma, v)` with `v[k]` the `k`-th right
/// singular vector (length `n`), sorted by falling `sigma`.
pub fn svd_cols(cols: &[Vec<f64>]) -> (Vec<f64>, Vec<Vec<f64>>) {
    let n = cols.len();
    let mut a: Vec<Vec<f64>> = cols.to_vec();
    let mut v: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|k| if i == k { 1.0 } else { 0.0 }).collect())
        .collect();
    for _sweep in 0..60 {
        let mut off = 0.0f64;
        for i in 0..n {
            for k in i + 1..n {
                let alpha = dot(&a[i], &a[i]);
                let beta = dot(&a[k], &a[k]);
                let gamma = dot(&a[i], &a[k]);
                if gamma == 0.0 || alpha == 0.0 || beta == 0.0 {
                    continue;
                }
                off = off.max(gamma.abs() / (alpha * beta).sqrt());
                let zeta = (beta - alpha) / (2.0 * gamma);
                let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
                let t = if zeta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = c * t;
                rotate(&mut a, i, k, c, s);
                rotate(&mut v, i, k, c, s);
            }
        }
        if off < 1e-15 {
            break;
        }
    }
    // column i of the rotated matrix is sigma_i u_i; v holds the rotations column-wise
    let mut order: Vec<(f64, usize)> = a
        .iter()
        .enumerate()
        .map(|(i, c)| (dot(c, c).sqrt(), i))
        .collect();
    order.sort_by(|x, y| y.0.total_cmp(&x.0));
    let sigma = order.iter().map(|o| o.0).collect();
    // v[i] is the i-th column of V as a vector over parameters: V[p][i] = v[i][p]
    let vecs = order.iter().map(|o| v[o.1].clone()).collect();
    (sigma, vecs)
}

fn rotate(m: &mut [Vec<f64>], i: usize, k: usize, c: f64, s: f64) {
    for r in 0..m[i].len() {
        let (x, y) = (m[i][r], m[k][r]);
        m[i][r] = c * x - s * y;
        m[k][r] = s * x + c * y;
    }
}

/// What the Jacobian says about the parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Information {
    /// Singular values of the column-scaled Jacobian over the largest, falling.
    pub relative_singular_values: Vec<f64>,
    /// Whether each parameter is identifiable.
    pub identifiable: Vec<bool>,
    /// Covariance at unit residual variance (pseudo-inverse of `J^T J` over the non-null
    /// directions).
    pub covariance: Vec<Vec<f64>>,
    /// The combinations the logs determine among the unidentifiable parameters: coefficient
    /// vectors over all parameters (0 outside them), largest coefficient 1.
    pub determined: Vec<Vec<f64>>,
}

/// Analyses the Jacobian `cols` (column-major, one column per parameter; `scale` the
/// parameters' typical sizes, kept for the callers' symmetry: the verdict is scale-free).
pub fn analyse(cols: &[Vec<f64>], scale: &[f64]) -> Information {
    let n = cols.len();
    debug_assert_eq!(scale.len(), n);
    let norms: Vec<f64> = cols.iter().map(|c| dot(c, c).sqrt()).collect();
    let scaled: Vec<Vec<f64>> = cols
        .iter()
        .zip(&norms)
        .map(|(c, &s)| {
            if s > 0.0 {
                c.iter().map(|v| v / s).collect()
            } else {
                vec![0.0; c.len()]
            }
        })
        .collect();
    let (sigma, v) = svd_cols(&scaled);
    let smax = sigma.first().copied().unwrap_or(0.0);
    let null: Vec<bool> = sigma
        .iter()
        .map(|&s| !(s > NULL_RATIO * smax && smax > 0.0))
        .collect();
    let mut identifiable: Vec<bool> = norms.iter().map(|&s| s > 0.0).collect();
    for (k, vk) in v.iter().enumerate() {
        if null[k] {
            for i in 0..n {
                if vk[i].abs() > NULL_COMPONENT {
                    identifiable[i] = false;
                }
            }
        }
    }
    let mut covariance = vec![vec![0.0; n]; n];
    for (k, vk) in v.iter().enumerate() {
        if null[k] {
            continue;
        }
        let w = 1.0 / (sigma[k] * sigma[k]);
        for i in 0..n {
            for j in 0..n {
                if norms[i] > 0.0 && norms[j] > 0.0 {
                    covariance[i][j] += w * vk[i] * vk[j] / (norms[i] * norms[j]);
                }
            }
        }
    }
    let determined = determined_combinations(&v, &null, &identifiable, &norms);
    Information {
        relative_singular_values: sigma
            .iter()
            .map(|s| if smax > 0.0 { s / smax } else { 0.0 })
            .collect(),
        identifiable,
        covariance,
        determined,
    }
}

/// Among the unidentifiable parameters (with non-zero columns), the directions orthogonal
/// to the null directions, in the scaled coordinates, mapped back to coefficients of the
/// parameters themselves (`u_i = |J_i| p_i`).
fn determined_combinations(
    v: &[Vec<f64>],
    null: &[bool],
    identifiable: &[bool],
    norms: &[f64],
) -> Vec<Vec<f64>> {
    let n = identifiable.len();
    let set: Vec<usize> = (0..n)
        .filter(|&i| !identifiable[i] && norms[i] > 0.0)
        .collect();
    if set.is_empty() {
        return Vec::new();
    }
    // null directions restricted to the set, orthonormalised
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for (k, vk) in v.iter().enumerate() {
        if null[k] {
            let r: Vec<f64> = set.iter().map(|&i| vk[i]).collect();
            push_orthonormal(&mut basis, r);
        }
    }
    let mut out = Vec::new();
    for e in 0..set.len() {
        let mut unit = vec![0.0; set.len()];
        unit[e] = 1.0;
        if push_orthonormal(&mut basis, unit) {
            let d = basis.last().cloned().unwrap_or_default();
            let mut coef = vec![0.0; n];
            for (j, &i) in set.iter().enumerate() {
                coef[i] = d[j] * norms[i];
            }
            let big = coef.iter().map(|c: &f64| c.abs()).fold(0.0, f64::max);
            if big > 0.0 {
                let lead = coef.iter().copied().find(|c| c.abs() == big).unwrap_or(big);
                coef.iter_mut().for_each(|c| *c /= lead);
            }
            out.push(coef);
        }
        if basis.len() == set.len() {
            break;
        }
    }
    out
}

/// Gram-Schmidt: appends `r` orthonormalised against `basis` if it is not (nearly) in its
/// span.
fn push_orthonormal(basis: &mut Vec<Vec<f64>>, mut r: Vec<f64>) -> bool {
    for _ in 0..2 {
        for b in basis.iter() {
            let p = dot(b, &r);
            r.iter_mut().zip(b).for_each(|(x, y)| *x -= p * y);
        }
    }
    let nr = dot(&r, &r).sqrt();
    if nr < 1e-6 {
        return false;
    }
    basis.push(r.into_iter().map(|x| x / nr).collect());
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svd_of_a_known_matrix() {
        // columns (3, 0, 0), (0, 4, 0) and their sum: singular, rank 2
        let cols = vec![
            vec![3.0, 0.0, 0.0],
            vec![0.0, 4.0, 0.0],
            vec![3.0, 4.0, 0.0],
        ];
        let (s, v) = svd_cols(&cols);
        assert!(s[2] < 1e-12 * s[0], "{s:?}");
        // the null vector is (1, 1, -1)/sqrt(3) up to sign
        let nv = &v[2];
        assert!((nv[0].abs() - 3f64.sqrt().recip()).abs() < 1e-12);
        assert!((nv[0] - nv[1]).abs() < 1e-12 && (nv[0] + nv[2]).abs() < 1e-12);
    }

    #[test]
    fn verdict_names_the_collinear_pair_and_its_combination() {
        // r = p0 + 2 p1 over many rows (only the combination matters), p2 on its own
        let m = 20;
        let c0: Vec<f64> = (0..m).map(|i| 1.0 + i as f64).collect();
        let c1: Vec<f64> = c0.iter().map(|v| 2.0 * v).collect();
        let c2: Vec<f64> = (0..m).map(|i| ((i * i) % 7) as f64 - 3.0).collect();
        let info = analyse(&[c0, c1, c2], &[1.0; 3]);
        assert_eq!(info.identifiable, vec![false, false, true]);
        assert_eq!(info.determined.len(), 1);
        let d = &info.determined[0];
        // p0 + 2 p1 up to scale: coefficients proportional to (1, 2)
        assert!((d[1] / d[0] - 2.0).abs() < 1e-9, "{d:?}");
        assert_eq!(d[2], 0.0);
        assert!(info.covariance[2][2] > 0.0);
    }

    #[test]
    fn full_rank_is_identifiable_with_the_classic_covariance() {
        let cols = vec![vec![1.0, 1.0, 1.0], vec![0.0, 1.0, 2.0]];
        let info = analyse(&cols, &[1.0; 2]);
        assert_eq!(info.identifiable, vec![true, true]);
        // (X^T X)^-1 for the straight-line fit: [[5/6, -1/2], [-1/2, 1/2]]
        assert!((info.covariance[0][0] - 5.0 / 6.0).abs() < 1e-12);
        assert!((info.covariance[0][1] + 0.5).abs() < 1e-12);
        assert!((info.covariance[1][1] - 0.5).abs() < 1e-12);
    }
}
