//! Lengths along the obstacle's contour, which the rolling condition of a stuck tangential
//! contact (`sigma - s1` constant) and the rows' slip displacement measure.

use crate::profile::Profile;

/// Signed arc length of the contour from parameter `a` to `b` (Gauss-Legendre, 5 points on
/// pieces of at most 0.05 in `t`).
pub(super) fn arc_length(profile: &Profile, a: f64, b: f64) -> f64 {
    const X: [f64; 5] = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.236_926_885_056_189,
        0.478_628_670_499_366,
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
    ];
    let pieces = ((b - a).abs() / 0.05).ceil().max(1.0) as usize;
    let h = (b - a) / pieces as f64;
    let mut s = 0.0;
    for k in 0..pieces {
        let mid = a + (k as f64 + 0.5) * h;
        for (x, w) in X.iter().zip(W) {
            let g = profile.at(mid + 0.5 * h * x);
            s += w * 0.5 * h * g.dx.hypot(g.dy);
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The contour's arc length: a circle's is `r dt`, a parabola's the closed form
    /// `[x sqrt(1 + x^2) + asinh x] / 2` (g2: `y = 1/2 + x^2/2`).
    #[test]
    fn arc_lengths_are_the_closed_forms() {
        let c = Profile::parse("circle:0.2,1.3,0.5").unwrap();
        assert!((arc_length(&c, -0.3, 0.9) - 0.5 * 1.2).abs() < 1e-14);
        let g2 = Profile::g2();
        let exact = |x: f64| 0.5 * (x * (1.0 + x * x).sqrt() + x.asinh());
        let s = arc_length(&g2, -0.4, 1.3);
        assert!((s - (exact(1.3) - exact(-0.4))).abs() < 1e-13, "{s}");
    }
}
