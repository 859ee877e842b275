//! `sin` and `cos` of one angle together, for the shots' right-hand side (one call per
//! evaluation, a quarter of a shot's work with the C library's `sincos`).
//!
//! The angle is reduced by `pi/2` in two parts (Cody and Waite: `k pi/2` with the 33-bit
//! head of `pi/2`, exact for `|k| < 2^20`, and its 53-bit tail), and the sine and cosine of
//! the remainder `|r| <= pi/4` are fdlibm's kernel polynomials (`__kernel_sin`,
//! `__kernel_cos`, error below 1 ulp of the kernel's result). The absolute error is a few
//! 1e-17 for `|x| <= 1e5` (the tail's rounding times `k`, below 1e-21, plus the
//! remainder's rounding); beyond, and for non-finite angles, the standard library answers.

use std::f64::consts::FRAC_2_PI;

/// The first 33 bits of `pi/2` (fdlibm's `pio2_1`): `k * PIO2_HI` is exact for `|k| < 2^20`.
const PIO2_HI: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
/// `pi/2 - PIO2_HI` (fdlibm's `pio2_1t`).
const PIO2_LO: f64 = f64::from_bits(0x3DD0_B461_1A62_6331);
/// `1.5 2^52`: adding and subtracting it rounds to an integer.
const ROUNDING: f64 = 6_755_399_441_055_744.0;
/// The largest `|x|` reduced here (`k < 2^17`).
const REDUCED: f64 = 1e5;

/// fdlibm's `__kernel_sin` coefficients (`S1 = -1.66666666666666324348e-01`, ...).
const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549);
const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6);
const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5);
const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D);
const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB);
const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C);

/// fdlibm's `__kernel_cos` coefficients (`C1 = 4.16666666666666019037e-02`, ...).
const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C);
const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177);
const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590);
const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD);
const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4);
const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4);

/// `(sin x, cos x)` (module docs).
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() > REDUCED {
        return x.sin_cos();
    }
    // the nearest integer k to x 2/pi by the 1.5 2^52 shift (exact for |x 2/pi| < 2^51);
    // the shifted value's last two bits are k mod 4
    let shifted = x * FRAC_2_PI + ROUNDING;
    let k = shifted - ROUNDING;
    let quadrant = shifted.to_bits() & 3;
    let r = (x - k * PIO2_HI) - k * PIO2_LO;
    let z = r * r;
    // fdlibm __kernel_sin(r, 0, 0)
    let v = z * r;
    let p = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    let s = r + v * (S1 + z * p);
    // fdlibm __kernel_cos(r, 0)
    let q = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let c = w + (((1.0 - w) - hz) + z * q);
    match quadrant {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constants are fdlibm's (their decimal values).
    #[test]
    fn constants_are_fdlibms() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b.abs();
        assert!(close(PIO2_HI, 1.5707963267341256) && close(PIO2_LO, 6.077100506506192e-11));
        assert!((PIO2_HI + PIO2_LO - std::f64::consts::FRAC_PI_2).abs() < 1e-16);
        assert!(close(S1, -1.6666666666666632e-1) && close(S6, 1.589_690_995_211_55e-10));
        assert!(close(C1, 4.16666666666666e-2) && close(C6, -1.1359647557788195e-11));
    }

    /// Against the standard library over the angles a whisker reaches (and far beyond):
    /// within 2e-16 absolute, exact quadrants at the multiples of pi/2.
    #[test]
    fn matches_the_standard_library() {
        let mut worst: f64 = 0.0;
        let mut x = -1000.0;
        while x <= 1000.0 {
            for t in [x, x * 1e-3, x * 1e-9, x * 50.0] {
                let (s, c) = sin_cos(t);
                let (s0, c0) = t.sin_cos();
                worst = worst.max((s - s0).abs()).max((c - c0).abs());
            }
            x += 0.001_234_567;
        }
        assert!(worst <= 2e-16, "{worst:e}");
        for k in -8..=8 {
            let t = k as f64 * std::f64::consts::FRAC_PI_2;
            let (s, c) = sin_cos(t);
            let (s0, c0) = t.sin_cos();
            assert!((s - s0).abs() <= 1e-15 && (c - c0).abs() <= 1e-15, "{k}");
        }
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        let (s, c) = sin_cos(1e6);
        assert_eq!((s, c), 1e6f64.sin_cos());
        assert!(sin_cos(f64::NAN).0.is_nan());
    }
}
