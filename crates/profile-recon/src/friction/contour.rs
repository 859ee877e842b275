//! The contour traced by the contact points of a log: the tangent angle `psi` where one row
//! alone cannot give it (a tip contact, phase A: the tip touches at an angle the whisker does
//! not share), and which rows slide.
//!
//! **Tangent at a tip contact.** The contact points of all rows lie on the contour (phase A:
//! the tip; phase B: `r(s1)`). Points that coincide within their error estimates are one
//! point (the rows of a stuck tip). Through the distinct points, read as a graph `y(x)` (every
//! profile kind of spec/cli.md is one where the whisker touches it), local least-squares
//! polynomials of degree `d = 2..=7` on the `d + 3` points nearest in `x` give
//! `psi = atan(y'(x))` at the row's point; each fit's error estimate `e_d` is the noise
//! propagated through it (the points' own error estimates as the deviations of `y`) plus its
//! largest distance to the fits of higher degree beyond their noise (truncation; the highest
//! fit: its distance to the one below). `psi` is the mean of the fits' angles weighted by
//! `1 / e_d^2` and its error estimate the same mean of `e_d` plus the fit's distance to `psi`: both move continuously
//! with the points (taking the fit with the smallest estimate switched degree under changes
//! of 1e-11, and a coincidental agreement of two neighbouring degrees passed for an
//! accuracy of 5e-9 where the tangent was off by 2e-6; docs/friction-recon.md, "The traced
//! tangent's error").
//!
//! **Sliding rows.** In the order of the motion ([`motion_order`]: the translating base moves
//! towards -x, so by falling `x0`), the material point that touches is the tip in phase A and
//! the whisker's point at `s1` in phase B. A tip that stays within its error estimates is
//! stuck; in phase B sticking is rolling without sliding, the contact moving along the
//! contour as far as `s1` moves along the whisker (docs/friction.md), so a row pair slides
//! where the chord between its points differs from `|delta s1|` beyond the errors (and 1e-3
//! of the chord, its difference from the arc). A row slides when it moved from every
//! neighbour it has in that order: the rows where sliding starts or stops are not counted
//! (their force may be anywhere in the cone).

// small dense least squares: index loops read as the formulas
#![allow(clippy::needless_range_loop)]

/// Rows `idx` ordered as the base moves (the translating base: falling `x0`, then input
/// order). The one place that knows the motion: a path of poses orders its rows by the
/// pose's parameter instead.
pub fn motion_order(x0: &[f64], idx: &[usize]) -> Vec<usize> {
    let mut o = idx.to_vec();
    o.sort_by(|&a, &b| x0[b].total_cmp(&x0[a]).then(a.cmp(&b)));
    o
}

/// A contact point with its error estimate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sample {
    pub x: f64,
    pub y: f64,
    pub sigma: f64,
}

/// The distinct points among `pts` (within `K_SIGMA` times their error estimates plus 1e-10),
/// sorted by `x`; a cluster's point is its first.
pub(crate) fn distinct(pts: &[Sample], k: f64) -> Vec<Sample> {
    let mut v = pts.to_vec();
    v.sort_by(|a, b| a.x.total_cmp(&b.x));
    let mut out: Vec<Sample> = Vec::new();
    for p in v {
        let same = out
            .iter()
            .rev()
            .take(8)
            .any(|q| (p.x - q.x).hypot(p.y - q.y) <= k * (p.sigma + q.sigma) + 1e-10);
        if !same {
            out.push(p);
        }
    }
    out
}

/// The least-squares polynomial of degree `d` through `pts` (weights `1 / sigma^2`, the
/// deviations floored at 1e-14) around `x`: `(y'(x), sd of y'(x))`.
fn slope_fit(pts: &[Sample], x: f64, d: usize) -> Option<(f64, f64)> {
    let n = d + 1;
    let h = pts
        .iter()
        .map(|p| (p.x - x).abs())
        .fold(0.0, f64::max)
        .max(1e-300);
    // normal equations in u = (x - x0) / h
    let mut a = vec![vec![0.0; n]; n];
    let mut rhs = vec![0.0; n];
    for p in pts {
        let u = (p.x - x) / h;
        let w = 1.0 / p.sigma.max(1e-14).powi(2);
        let pw: Vec<f64> = (0..n).map(|k| u.powi(k as i32)).collect();
        for i in 0..n {
            rhs[i] += w * pw[i] * p.y;
            for j in 0..n {
                a[i][j] += w * pw[i] * pw[j];
            }
        }
    }
    // the slope coefficient c1 and its variance (A^-1)_11
    let inv_col = solve(a.clone(), {
        let mut e = vec![0.0; n];
        e[1] = 1.0;
        e
    })?;
    let c = solve(a, rhs)?;
    let var = inv_col[1].max(0.0);
    Some((c[1] / h, var.sqrt() / h))
}

/// Gaussian elimination with partial pivoting.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c] == 0.0 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            for k in c..n {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    Some(x)
}

/// The `m` points of `pts` (sorted by `x`) nearest in `x` to `x`.
fn nearest(pts: &[Sample], x: f64, m: usize) -> Option<&[Sample]> {
    if pts.len() < m {
        return None;
    }
    let i = pts.partition_point(|p| p.x < x);
    let mut lo = i.saturating_sub(m).min(pts.len() - m);
    // slide the window towards the nearer side
    while lo + m < pts.len() && lo < i && (pts[lo].x - x).abs() > (pts[lo + m].x - x).abs() {
        lo += 1;
    }
    Some(&pts[lo..lo + m])
}

/// The contour's tangent angle at the point `x` of the distinct contour points `pts` (module
/// docs): `(psi, error estimate)`, None with fewer than 3 points.
pub(crate) fn tangent_at(pts: &[Sample], x: f64) -> Option<(f64, f64)> {
    let fits: Vec<(f64, f64)> = (2..=7)
        .filter_map(|d| {
            slope_fit(
                nearest(pts, x, d + 3)
                    .or_else(|| nearest(pts, x, pts.len()).filter(|w| w.len() > d))?,
                x,
                d,
            )
        })
        .collect();
    // per fit (module docs): its angle, its weight's estimate (noise plus the distance to the
    // next degree) and its error estimate (noise plus the largest distance beyond the noise
    // to the two nearest degrees above, or below where fewer than two are above)
    let n = fits.len();
    let mut est: Vec<(f64, f64, f64)> = Vec::with_capacity(n);
    for k in 0..n {
        let (g, sd) = fits[k];
        let next = (k + 1 < n).then(|| k + 1).or(k.checked_sub(1));
        let wd = next.map_or(f64::INFINITY, |j| sd + (fits[j].0 - g).abs());
        let mut near: Vec<usize> = (k + 1..n).take(2).collect();
        near.extend((0..k).rev().take(2 - near.len()));
        let trunc = near
            .iter()
            .map(|&j| ((fits[j].0 - g).abs() - fits[j].1.max(sd)).max(0.0))
            .fold(if near.is_empty() { f64::INFINITY } else { 0.0 }, f64::max);
        let jac = 1.0 + g * g;
        est.push((g.atan(), (wd / jac).max(1e-15), (sd + trunc) / jac));
    }
    if n == 1 {
        return Some((est[0].0, est[0].2)).filter(|b| b.0.is_finite());
    }
    // weights 1 / e^2: psi and its estimate move continuously with the points (no switch
    // between degrees); the estimate is the same mean of each fit's error estimate plus its
    // distance to psi
    let w: Vec<f64> = est.iter().map(|&(_, e, _)| 1.0 / (e * e)).collect();
    let sw: f64 = w.iter().sum();
    let psi = est.iter().zip(&w).map(|(&(p, _, _), w)| w * p).sum::<f64>() / sw;
    let e = est
        .iter()
        .zip(&w)
        .map(|(&(p, _, r), w)| w * (r + (p - psi).abs()))
        .sum::<f64>()
        / sw;
    Some((psi, e)).filter(|b| b.0.is_finite() && b.1.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tangent_of_a_sampled_curve() {
        // y = 0.5 + 0.8 (x - 0.1)^2 + sin(x) / 10 sampled at 15 points
        let g = |x: f64| 0.5 + 0.8 * (x - 0.1) * (x - 0.1) + x.sin() / 10.0;
        let dg = |x: f64| 1.6 * (x - 0.1) + x.cos() / 10.0;
        let pts: Vec<Sample> = (0..15)
            .map(|k| {
                let x = -0.3 + 0.04 * k as f64;
                Sample {
                    x,
                    y: g(x),
                    sigma: 1e-13,
                }
            })
            .collect();
        for &x in &[-0.3, -0.14, 0.02, 0.26] {
            let (psi, e) = tangent_at(&pts, x).unwrap();
            let err = (psi - dg(x).atan()).abs();
            assert!(
                err < 1e-9 && err <= e.max(1e-12) * 10.0,
                "{x}: {err:e} est {e:e}"
            );
        }
        // a stuck tip: one cluster
        let d = distinct(&[pts[0], pts[0], pts[1]], 6.0);
        assert_eq!(d.len(), 2);
        // too few points
        assert!(tangent_at(&pts[..2], 0.0).is_none());
    }

    #[test]
    fn the_order_of_the_motion_is_falling_x0() {
        assert_eq!(
            motion_order(&[0.1, 0.3, 0.2, 0.3], &[0, 1, 2, 3]),
            vec![1, 3, 2, 0]
        );
    }
}
