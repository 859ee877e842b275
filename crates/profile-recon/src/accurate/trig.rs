//! `sin` and `cos` of the tangent angle `phi` for the base integration, whose right-hand side
//! needs both at every stage ([`sin_cos`]): a table of both at multiples of 1/16 rad and the
//! Taylor series of the remainder (|d| <= 1/32) through the addition theorem, about a fifth
//! of the cost of the library's `sin_cos` and within an ulp or two of it (unit tests); the
//! library's `sin_cos` itself outside the table (beyond any winding of a whisker).

use std::sync::OnceLock;

/// Table spacing (rad).
const SPACING: f64 = 1.0 / 16.0;
/// The table covers `|phi| <= HALF * SPACING` (16 rad: `phi0` plus the
/// [`MAX_WINDING`](super::MAX_WINDING) of a row).
const HALF: usize = 256;

/// `(sin, cos)` at `(k - HALF) * SPACING`, `k = 0..=2 HALF`.
fn table() -> &'static [(f64, f64)] {
    static TABLE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    TABLE.get_or_init(|| {
        (0..=2 * HALF)
            .map(|k| ((k as f64 - HALF as f64) * SPACING).sin_cos())
            .collect()
    })
}

/// `(sin x, cos x)` (module docs): `sin(a + d) = sin a + (sin a (cos d - 1) + cos a sin d)`,
/// `cos(a + d) = cos a + (cos a (cos d - 1) - sin a sin d)` with `a` the nearest table
/// point, `sin d` to `d^7` and `cos d - 1` to `d^8` (truncation below 1e-19).
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    let t = x * (1.0 / SPACING) + (HALF as f64 + 0.5);
    if !(t >= 0.0 && t < (2 * HALF + 1) as f64) {
        return x.sin_cos();
    }
    // t >= 0: the conversion truncates to the nearest table point's index
    let k = t as i32;
    let (sa, ca) = table()[k as usize];
    // exact: the table point is within a factor 2 of x, or 0
    let d = x - f64::from(k - HALF as i32) * SPACING;
    let d2 = d * d;
    let sd = d + d * d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0 + d2 * (-1.0 / 5040.0)));
    let cd1 = d2 * (-0.5 + d2 * (1.0 / 24.0 + d2 * (-1.0 / 720.0 + d2 * (1.0 / 40320.0))));
    (sa + (sa * cd1 + ca * sd), ca + (ca * cd1 - sa * sd))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn within_two_ulps_of_the_library_over_the_table() {
        // a fine irregular grid over the table and past its ends
        let mut worst: f64 = 0.0;
        let n = 400_000;
        for i in 0..=n {
            let x = -17.0 + 34.0 * (i as f64 / n as f64) + 1e-7 * (i as f64).sin();
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            // ulps of the larger of the two magnitudes (an absolute error near a zero)
            let ulp = f64::EPSILON * s0.abs().max(c0.abs());
            worst = worst.max((s - s0).abs() / ulp).max((c - c0).abs() / ulp);
        }
        assert!(worst <= 2.0, "{worst} ulps");
    }

    #[test]
    fn table_points_and_the_outside_are_the_library_values() {
        for x in [0.0, -0.0, 1.0, -3.0625, 16.0, -16.0, 16.04, -20.0, 1e300] {
            assert_eq!(sin_cos(x), x.sin_cos(), "{x}");
        }
        let (s, c) = sin_cos(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
    }
}
