//! `sin` and `cos` of the tangent angle `phi` for the base integration, whose right-hand side
//! needs both at every stage ([`SinCos`]): a table of both at multiples of 1/64 rad and the
//! Taylor series of the remainder (|d| <= 1/128, short and evaluated in parallel: the stages
//! of a step wait on it) through the addition theorem, about a quarter of the instructions of
//! the library's `sin_cos` and within an ulp or two of it (unit tests); the library's
//! `sin_cos` itself outside the table (beyond any winding of a whisker).

use std::sync::OnceLock;

/// Table spacing (rad).
const SPACING: f64 = 1.0 / 64.0;
/// The table covers `|phi| <= HALF * SPACING` (16 rad: `phi0` plus the
/// [`MAX_WINDING`](super::MAX_WINDING) of a row).
const HALF: usize = 1024;
/// `2^52 + HALF`: added to `x / SPACING` it rounds it to an integer `k` and leaves
/// `k + HALF` in the low bits of the sum (below `2^12`).
const ROUND: f64 = 4_503_599_627_370_496.0 + HALF as f64;

/// `sin` and `cos` by table and series (module docs).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SinCos {
    /// `(sin, cos)` at `(k - HALF) * SPACING`, `k = 0..=2 HALF`.
    table: &'static [(f64, f64)],
}

impl SinCos {
    /// The table (made once).
    pub(crate) fn new() -> Self {
        static TABLE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
        SinCos {
            table: TABLE.get_or_init(|| {
                (0..=2 * HALF)
                    .map(|k| ((k as f64 - HALF as f64) * SPACING).sin_cos())
                    .collect()
            }),
        }
    }

    /// `(sin x, cos x)`: `sin(a + d) = sin a + (sin a (cos d - 1) + cos a sin d)`,
    /// `cos(a + d) = cos a + (cos a (cos d - 1) - sin a sin d)` with `a` the nearest table
    /// point, `sin d` to `d^5` and `cos d - 1` to `d^6` (truncation below 4e-19).
    #[inline(always)]
    pub(crate) fn at(&self, x: f64) -> (f64, f64) {
        // exact: a power of 2
        let t = x * (1.0 / SPACING);
        let u = t + ROUND;
        // the table point's multiple of SPACING, exact (NaN, infinite or far: the library)
        let k = u - ROUND;
        if k.abs() <= HALF as f64 {
            let (sa, ca) = self.table[(u.to_bits() & 0xfff) as usize];
            // exact: |t - k| <= 1/2 (and the scaling a power of 2)
            let d = (t - k) * SPACING;
            let d2 = d * d;
            let d4 = d2 * d2;
            let sd = d + d * d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0));
            let cd1 = d2 * -0.5 + d4 * (1.0 / 24.0 + d2 * (-1.0 / 720.0));
            (sa + (sa * cd1 + ca * sd), ca + (ca * cd1 - sa * sd))
        } else {
            x.sin_cos()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn within_two_ulps_of_the_library_over_the_table() {
        // a fine irregular grid over the table and past its ends
        let trig = SinCos::new();
        let mut worst: f64 = 0.0;
        let n = 400_000;
        for i in 0..=n {
            let x = -17.0 + 34.0 * (i as f64 / n as f64) + 1e-7 * (i as f64).sin();
            let (s, c) = trig.at(x);
            let (s0, c0) = x.sin_cos();
            // ulps of the larger of the two magnitudes (an absolute error near a zero)
            let ulp = f64::EPSILON * s0.abs().max(c0.abs());
            worst = worst.max((s - s0).abs() / ulp).max((c - c0).abs() / ulp);
        }
        assert!(worst <= 2.0, "{worst} ulps");
    }

    #[test]
    fn table_points_and_the_outside_are_the_library_values() {
        let trig = SinCos::new();
        for x in [0.0, -0.0, 1.0, -3.015625, 16.0, -16.0, 16.01, -20.0, 1e300] {
            assert_eq!(trig.at(x), x.sin_cos(), "{x}");
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (s, c) = trig.at(x);
            assert!(s.is_nan() && c.is_nan(), "{x}");
        }
    }
}
