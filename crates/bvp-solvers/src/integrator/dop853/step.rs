//! One DOP853 step: the twelve stages `k2..k12` (`k1` is the FSAL derivative of the previous
//! step), the 8th-order update and the combined 5th/3rd-order error norm of Hairer's code.

use super::coef::*;
use crate::integrator::OdeSystem;

/// Evaluates the stages `k2..k12` of the step `[x, x + h]` from `y` (with `k1` in `k[..n]`)
/// into `k`; `tmp` is scratch. Costs 11 right-hand-side evaluations.
pub(super) fn stages<S: OdeSystem + ?Sized>(
    sys: &S,
    x: f64,
    h: f64,
    y: &[f64],
    k: &mut [f64],
    tmp: &mut [f64],
) {
    by_dim!(y.len(), stages_in(sys, x, h, y, k, tmp))
}

/// [`stages`] in the dimension `d`.
#[inline(always)]
fn stages_in<D: Dim, S: OdeSystem + ?Sized>(
    d: D,
    sys: &S,
    x: f64,
    h: f64,
    y: &[f64],
    k: &mut [f64],
    tmp: &mut [f64],
) {
    let n = d.n();
    let (y, k, tmp) = (&y[..n], &mut k[..12 * n], &mut tmp[..n]);
    // ---- the 12 stages
    combo(n, y, h, k, [(0, A21)], tmp);
    sys.rhs(x + C[1] * h, tmp, &mut k[n..2 * n]);
    combo(n, y, h, k, [(0, A31), (1, A32)], tmp);
    sys.rhs(x + C[2] * h, tmp, &mut k[2 * n..3 * n]);
    combo(n, y, h, k, [(0, A41), (2, A43)], tmp);
    sys.rhs(x + C[3] * h, tmp, &mut k[3 * n..4 * n]);
    combo(n, y, h, k, [(0, A51), (2, A53), (3, A54)], tmp);
    sys.rhs(x + C[4] * h, tmp, &mut k[4 * n..5 * n]);
    combo(n, y, h, k, [(0, A61), (3, A64), (4, A65)], tmp);
    sys.rhs(x + C[5] * h, tmp, &mut k[5 * n..6 * n]);
    combo(n, y, h, k, [(0, A71), (3, A74), (4, A75), (5, A76)], tmp);
    sys.rhs(x + C[6] * h, tmp, &mut k[6 * n..7 * n]);
    combo(
        n,
        y,
        h,
        k,
        [(0, A81), (3, A84), (4, A85), (5, A86), (6, A87)],
        tmp,
    );
    sys.rhs(x + C[7] * h, tmp, &mut k[7 * n..8 * n]);
    combo(
        n,
        y,
        h,
        k,
        [(0, A91), (3, A94), (4, A95), (5, A96), (6, A97), (7, A98)],
        tmp,
    );
    sys.rhs(x + C[8] * h, tmp, &mut k[8 * n..9 * n]);
    combo(
        n,
        y,
        h,
        k,
        [
            (0, A101),
            (3, A104),
            (4, A105),
            (5, A106),
            (6, A107),
            (7, A108),
            (8, A109),
        ],
        tmp,
    );
    sys.rhs(x + C[9] * h, tmp, &mut k[9 * n..10 * n]);
    combo(
        n,
        y,
        h,
        k,
        [
            (0, A111),
            (3, A114),
            (4, A115),
            (5, A116),
            (6, A117),
            (7, A118),
            (8, A119),
            (9, A1110),
        ],
        tmp,
    );
    sys.rhs(x + C[10] * h, tmp, &mut k[10 * n..11 * n]);
    let xph = x + h;
    combo(
        n,
        y,
        h,
        k,
        [
            (0, A121),
            (3, A124),
            (4, A125),
            (5, A126),
            (6, A127),
            (7, A128),
            (8, A129),
            (9, A1210),
            (10, A1211),
        ],
        tmp,
    );
    sys.rhs(xph, tmp, &mut k[11 * n..12 * n]);
}

/// The 8th-order update `ynew = y + h sum b_i k_i` and the error norm
/// `err = |h| E5 / sqrt(n (E5 + 0.01 E3))` with `E5 = sum (e5_i/sk_i)^2`,
/// `E3 = sum (e3_i/sk_i)^2`, `sk_i = atol + rtol max(|y_i|, |ynew_i|)`.
pub(super) fn update_and_error(
    y: &[f64],
    h: f64,
    k: &[f64],
    ynew: &mut [f64],
    rtol: f64,
    atol: f64,
) -> f64 {
    by_dim!(y.len(), update_and_error_in(y, h, k, ynew, rtol, atol))
}

/// [`update_and_error`] in the dimension `d`.
#[inline(always)]
fn update_and_error_in<D: Dim>(
    d: D,
    y: &[f64],
    h: f64,
    k: &[f64],
    ynew: &mut [f64],
    rtol: f64,
    atol: f64,
) -> f64 {
    let n = d.n();
    let (y, k, ynew) = (&y[..n], &k[..12 * n], &mut ynew[..n]);
    // ---- 8th-order solution and error estimate
    let mut err = 0.0;
    let mut err2 = 0.0;
    for i in 0..n {
        let bsum = lin(
            k,
            n,
            i,
            [
                (0, B1),
                (5, B6),
                (6, B7),
                (7, B8),
                (8, B9),
                (9, B10),
                (10, B11),
                (11, B12),
            ],
        );
        ynew[i] = y[i] + h * bsum;
        let e3 = bsum - BHH1 * k[i] - BHH2 * k[8 * n + i] - BHH3 * k[11 * n + i];
        let e5 = lin(
            k,
            n,
            i,
            [
                (0, ER1),
                (5, ER6),
                (6, ER7),
                (7, ER8),
                (8, ER9),
                (9, ER10),
                (10, ER11),
                (11, ER12),
            ],
        );
        let sk = atol + rtol * y[i].abs().max(ynew[i].abs());
        err2 += (e3 / sk).powi(2);
        err += (e5 / sk).powi(2);
    }
    let mut deno = err + 0.01 * err2;
    if deno <= 0.0 {
        deno = 1.0;
    }
    h.abs() * err * (1.0 / (n as f64 * deno)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::ring_cases;

    /// The stage loops unrolled for a fixed dimension give the very numbers of the run-time
    /// dimension's loops, for every dimension the dispatch fixes.
    #[test]
    fn fixed_dimensions_reproduce_the_dynamic_step_bit_for_bit() {
        for (n, sys, y) in ring_cases() {
            let mut k1 = vec![0.0; 16 * n];
            sys.rhs(0.2, &y, &mut k1[..n]);
            let (mut k2, mut tmp1, mut tmp2) = (k1.clone(), vec![0.0; n], vec![0.0; n]);
            stages(&sys, 0.2, 0.05, &y, &mut k1, &mut tmp1);
            stages_in(Dynamic(n), &sys, 0.2, 0.05, &y, &mut k2, &mut tmp2);
            assert_eq!(k1, k2, "stages, n = {n}");
            let (mut y1, mut y2) = (vec![0.0; n], vec![0.0; n]);
            let e1 = update_and_error(&y, 0.05, &k1, &mut y1, 1e-9, 1e-9);
            let e2 = update_and_error_in(Dynamic(n), &y, 0.05, &k2, &mut y2, 1e-9, 1e-9);
            assert_eq!((y1, e1.to_bits()), (y2, e2.to_bits()), "update, n = {n}");
        }
    }
}
