//! Cubic Hermite interpolation: the basis shared by the continuation's predictor and the
//! sweep's row predictions.

/// The cubic Hermite basis at `s` on a unit interval (`s = 0` at the first node, 1 at the
/// second; any `s` extrapolates): the weights `[h00, h10, h01, h11]` of
/// `u(s) = h00 u0 + h10 h u0' + h01 u1 + h11 h u1'` for an interval of length `h`.
pub fn hermite_basis(s: f64) -> [f64; 4] {
    let (s2, s3) = (s * s, s * s * s);
    [
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + s,
        -2.0 * s3 + 3.0 * s2,
        s3 - s2,
    ]
}

#[cfg(test)]
mod tests {
    /// The basis reproduces cubics exactly, in and beyond the interval.
    #[test]
    fn reproduces_cubics() {
        let (p, dp) = (
            |x: f64| x * x * x - 2.0 * x * x + 0.5,
            |x: f64| 3.0 * x * x - 4.0 * x,
        );
        let (a, h) = (0.3, 0.7);
        for s in [-0.5, 0.0, 0.25, 1.0, 1.8] {
            let [h00, h10, h01, h11] = super::hermite_basis(s);
            let got = h00 * p(a) + h10 * h * dp(a) + h01 * p(a + h) + h11 * h * dp(a + h);
            assert!((got - p(a + s * h)).abs() < 1e-13, "s = {s}: {got}");
        }
    }
}
