//! The obstacle itself from the reconstructed contact points (issue 38): a peg touched along
//! a whisking log is one point that every contact row gives again; a disc is the circle its
//! contact points lie on.
//!
//! - [`estimate_peg`]: the mean of the rows' points, its standard error per coordinate
//!   `sd / sqrt(n)` with `sd` the larger of the points' sample standard deviation and their
//!   own mean error estimate (`ReconPoint::sigma`, which carries the identified flow's
//!   uncertainty, common to all rows, that their scatter cannot show), and the spread (the
//!   largest distance of a point from the mean: ~1e-12 on an exact log, the check that the
//!   points are one point).
//! - [`estimate_disc`]: the weighted least-squares circle (geometric distances
//!   `|p - c| - r`, each weighted by `1 / sigma^2` of its point, started from the algebraic
//!   fit of Kasa 1976 and refined by Gauss-Newton), with the covariance `(J^T W J)^-1`,
//!   scaled by `chi^2 / (n - 3)` where the points scatter more than their error estimates
//!   say. A short arc leaves the centre and the radius correlated: the standard errors say
//!   so; a point less certain than the others (a row at a phase event) weighs less.

use crate::error::{ReconError, Result};
use crate::result::ReconPoint;
use serde::{Deserialize, Serialize};

/// Largest Gauss-Newton steps of [`estimate_disc`].
const DISC_ITERATIONS: usize = 50;

/// A peg's position from the contact points of a log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PegEstimate {
    /// Peg x: the mean of the points' x.
    pub x: f64,
    /// Peg y: the mean of the points' y.
    pub y: f64,
    /// Standard error of `x`.
    pub stderr_x: f64,
    /// Standard error of `y`.
    pub stderr_y: f64,
    /// Largest distance of a point from `(x, y)`.
    pub spread: f64,
    /// Contact points used.
    pub rows: usize,
}

/// A disc's centre and radius from the contact points of a log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DiscEstimate {
    /// Centre x.
    pub x: f64,
    /// Centre y.
    pub y: f64,
    /// Radius.
    pub r: f64,
    /// Standard errors of `(x, y, r)`.
    pub stderr: [f64; 3],
    /// Root mean square of the points' distances from the circle.
    pub rms: f64,
    /// Contact points used.
    pub rows: usize,
}

/// The mean error estimate `sqrt(mean sigma^2)` of the points (0 where none is finite).
fn mean_sigma(points: &[ReconPoint]) -> f64 {
    let s: Vec<f64> = points
        .iter()
        .map(|p| p.sigma)
        .filter(|s| s.is_finite())
        .collect();
    if s.is_empty() {
        return 0.0;
    }
    (s.iter().map(|v| v * v).sum::<f64>() / s.len() as f64).sqrt()
}

/// The peg's position from the contact points of a log against it (module docs).
///
/// # Errors
/// [`ReconError::TooFewRows`] without a point.
pub fn estimate_peg(points: &[ReconPoint]) -> Result<PegEstimate> {
    let n = points.len();
    if n == 0 {
        return Err(ReconError::TooFewRows {
            found: 0,
            needed: 1,
            what: "a peg's position needs a contact point",
        });
    }
    let nf = n as f64;
    let x = points.iter().map(|p| p.x).sum::<f64>() / nf;
    let y = points.iter().map(|p| p.y).sum::<f64>() / nf;
    let var = |f: &dyn Fn(&ReconPoint) -> f64, m: f64| {
        if n < 2 {
            return 0.0;
        }
        points.iter().map(|p| (f(p) - m).powi(2)).sum::<f64>() / (nf - 1.0)
    };
    let own = mean_sigma(points);
    let sd_x = var(&|p| p.x, x).sqrt().max(own);
    let sd_y = var(&|p| p.y, y).sqrt().max(own);
    let spread = points
        .iter()
        .map(|p| (p.x - x).hypot(p.y - y))
        .fold(0.0, f64::max);
    Ok(PegEstimate {
        x,
        y,
        stderr_x: sd_x / nf.sqrt(),
        stderr_y: sd_y / nf.sqrt(),
        spread,
        rows: n,
    })
}

/// Solves the symmetric 3x3 system `a z = b` by Gaussian elimination with partial pivoting;
/// `None` when it is singular.
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for c in 0..3 {
        let p = (c..3).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c] == 0.0 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        let (pivot_row, pivot_b) = (a[c], b[c]);
        for (row, bi) in a.iter_mut().zip(b.iter_mut()).skip(c + 1) {
            let f = row[c] / pivot_row[c];
            for (v, pv) in row.iter_mut().zip(pivot_row).skip(c) {
                *v -= f * pv;
            }
            *bi -= f * pivot_b;
        }
    }
    let mut z = [0.0; 3];
    for i in (0..3).rev() {
        let s: f64 = (i + 1..3).map(|j| a[i][j] * z[j]).sum();
        z[i] = (b[i] - s) / a[i][i];
    }
    z.iter().all(|v| v.is_finite()).then_some(z)
}

/// The weight `1 / sigma^2` of a point in the circle fit (`sigma` floored at 1e-15: exact
/// points weigh alike).
fn weight(p: &ReconPoint) -> f64 {
    let s = if p.sigma.is_finite() {
        p.sigma.max(1e-15)
    } else {
        1.0
    };
    1.0 / (s * s)
}

/// `J^T W J`, `J^T W r` and `r^T W r` of the geometric circle residuals `|p - c| - r` at
/// `(cx, cy, r)`, weighted by [`weight`].
fn normal_equations(points: &[ReconPoint], c: [f64; 3]) -> ([[f64; 3]; 3], [f64; 3], f64) {
    let (mut n, mut g, mut ss) = ([[0.0; 3]; 3], [0.0; 3], 0.0);
    for p in points {
        let w = weight(p);
        let (dx, dy) = (p.x - c[0], p.y - c[1]);
        let d = dx.hypot(dy);
        let res = d - c[2];
        let j = if d > 0.0 {
            [-dx / d, -dy / d, -1.0]
        } else {
            [0.0, 0.0, -1.0]
        };
        for a in 0..3 {
            for b in 0..3 {
                n[a][b] += w * j[a] * j[b];
            }
            g[a] += w * j[a] * res;
        }
        ss += w * res * res;
    }
    (n, g, ss)
}

/// The disc's centre and radius from the contact points of a log against it: the
/// least-squares circle with standard errors (module docs).
///
/// # Errors
/// [`ReconError::TooFewRows`] with fewer than 3 points, or when they lie on a line (no
/// circle is determined).
pub fn estimate_disc(points: &[ReconPoint]) -> Result<DiscEstimate> {
    let n = points.len();
    let degenerate = |found| ReconError::TooFewRows {
        found,
        needed: 3,
        what: "a disc needs 3 contact points not on one line",
    };
    if n < 3 {
        return Err(degenerate(n));
    }
    // Kasa: x^2 + y^2 + D x + E y + F = 0 by linear least squares, centred for conditioning
    let nf = n as f64;
    let (mx, my) = (
        points.iter().map(|p| p.x).sum::<f64>() / nf,
        points.iter().map(|p| p.y).sum::<f64>() / nf,
    );
    let (mut a, mut b) = ([[0.0; 3]; 3], [0.0; 3]);
    for p in points {
        let (u, v) = (p.x - mx, p.y - my);
        let row = [u, v, 1.0];
        let rhs = -(u * u + v * v);
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] += row[i] * row[j];
            }
            b[i] += row[i] * rhs;
        }
    }
    let [d, e, f] = solve3(a, b).ok_or(degenerate(n))?;
    let (cu, cv) = (-d / 2.0, -e / 2.0);
    let r2 = cu * cu + cv * cv - f;
    if r2.is_nan() || r2 <= 0.0 {
        return Err(degenerate(n));
    }
    let mut c = [mx + cu, my + cv, r2.sqrt()];
    // Gauss-Newton on the geometric distances
    for _ in 0..DISC_ITERATIONS {
        let (jtj, jtr, _) = normal_equations(points, c);
        let Some(step) = solve3(jtj, jtr.map(|v| -v)) else {
            return Err(degenerate(n));
        };
        for k in 0..3 {
            c[k] += step[k];
        }
        let size = step.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if size <= 1e-15 * (1.0 + c[2]) {
            break;
        }
    }
    let (jtj, _, chi2) = normal_equations(points, c);
    let rms = (points
        .iter()
        .map(|p| ((p.x - c[0]).hypot(p.y - c[1]) - c[2]).powi(2))
        .sum::<f64>()
        / nf)
        .sqrt();
    let dof = if n > 3 { (n - 3) as f64 } else { 1.0 };
    // the covariance (J^T W J)^-1, scaled up by the misfit where the points scatter more
    // than their error estimates say
    let s2 = (chi2 / dof).max(1.0);
    let mut stderr = [f64::INFINITY; 3];
    for (k, se) in stderr.iter_mut().enumerate() {
        let mut unit = [0.0; 3];
        unit[k] = 1.0;
        if let Some(col) = solve3(jtj, unit) {
            *se = (s2 * col[k]).max(0.0).sqrt();
        }
    }
    Ok(DiscEstimate {
        x: c[0],
        y: c[1],
        r: c[2],
        stderr,
        rms,
        rows: n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use contact_sim::Phase;

    fn at(x: f64, y: f64, sigma: f64) -> ReconPoint {
        ReconPoint {
            row: 0,
            x0: 0.0,
            x,
            y,
            s1: 1.0,
            f: 1.0,
            psi: 0.0,
            phase: Phase::B,
            residual: 0.0,
            sigma,
            alternatives: 0,
            evaluations: 1,
        }
    }

    #[test]
    fn a_peg_is_the_mean_with_its_standard_error() {
        let pts = [at(1.0, 2.0, 0.0), at(1.2, 2.0, 0.0), at(1.1, 2.3, 0.0)];
        let e = estimate_peg(&pts).unwrap();
        assert!((e.x - 1.1).abs() < 1e-15 && (e.y - 2.1).abs() < 1e-15);
        // sample sd of x: 0.1, of y: sqrt(0.03)
        assert!((e.stderr_x - 0.1 / 3f64.sqrt()).abs() < 1e-15);
        assert!((e.stderr_y - (0.03f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((e.spread - 0.2).abs() < 1e-15);
        // the points' own error estimates floor the scatter
        let pts = [at(1.0, 2.0, 0.5), at(1.0, 2.0, 0.5)];
        let e = estimate_peg(&pts).unwrap();
        assert!((e.stderr_x - 0.5 / 2f64.sqrt()).abs() < 1e-15);
        assert!(estimate_peg(&[]).is_err());
    }

    #[test]
    fn a_disc_through_points_on_a_short_arc_is_found_to_rounding() {
        let (cx, cy, r) = (0.3, 1.1, 0.25);
        let pts: Vec<ReconPoint> = (0..12)
            .map(|i| {
                let t = -1.2 + 0.07 * i as f64;
                at(cx + r * t.cos(), cy + r * t.sin(), 0.0)
            })
            .collect();
        let e = estimate_disc(&pts).unwrap();
        assert!((e.x - cx).abs() < 1e-12 && (e.y - cy).abs() < 1e-12 && (e.r - r).abs() < 1e-12);
        assert!(e.rms < 1e-14, "{}", e.rms);
        // collinear points determine no circle
        let line: Vec<ReconPoint> = (0..5).map(|i| at(i as f64, 2.0 * i as f64, 0.0)).collect();
        assert!(estimate_disc(&line).is_err());
        assert!(estimate_disc(&pts[..2]).is_err());
    }

    #[test]
    fn the_disc_standard_errors_cover_a_seeded_noise() {
        use rand::{rngs::StdRng, Rng, SeedableRng};
        use rand_distr::StandardNormal;
        let (cx, cy, r, sd) = (-0.2, 0.9, 0.3, 1e-4);
        let mut rng = StdRng::seed_from_u64(38);
        let (mut inside, trials) = (0, 200);
        for _ in 0..trials {
            let pts: Vec<ReconPoint> = (0..30)
                .map(|i| {
                    let t = 0.4 + 0.05 * i as f64;
                    let (nx, ny): (f64, f64) =
                        (rng.sample(StandardNormal), rng.sample(StandardNormal));
                    at(cx + r * t.cos() + sd * nx, cy + r * t.sin() + sd * ny, 0.0)
                })
                .collect();
            let e = estimate_disc(&pts).unwrap();
            if (e.r - r).abs() <= 3.0 * e.stderr[2] && (e.x - cx).abs() <= 3.0 * e.stderr[0] {
                inside += 1;
            }
        }
        // 3 standard errors hold ~99 % of Gaussian draws (both at once ~98 %)
        assert!(inside >= trials * 9 / 10, "{inside} of {trials}");
    }
}
