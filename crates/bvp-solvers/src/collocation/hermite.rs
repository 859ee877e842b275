//! Dense output: the C1 piecewise cubic Hermite interpolant of the node values `y_i` and
//! slopes `f_i = f(x_i, y_i, p)`, as scipy's `solve_bvp` returns. On the collocation
//! solution it agrees with the collocating cubic of each interval (Lobatto IIIA of order 4
//! is the cubic through `y_i`, `y_{i+1}` with slopes `f_i`, `f_{i+1}`), so its error between
//! nodes is `O(h^4)` like the nodes'.

// Index arithmetic on flat row-major blocks (`a[r * n + c]`) reads as the equations do.
#![allow(clippy::needless_range_loop)]

/// Index `i` of the interval `[x_i, x_{i+1}]` holding `t` (clamped to the first / last
/// interval outside `[x_0, x_{m-1}]`).
pub fn interval(x: &[f64], t: f64) -> usize {
    let m = x.len();
    let i = x.partition_point(|&xi| xi <= t);
    i.clamp(1, m - 1) - 1
}

/// The cubic Hermite value [H.1] and derivative on `[x0, x0 + h]` at `t`, written into `out`
/// and `dout` (either may be empty to skip it):
/// `y(s) = h00 y0 + h h10 f0 + h01 y1 + h h11 f1`, `s = (t - x0) / h`,
/// `h00 = 2s^3 - 3s^2 + 1`, `h10 = s^3 - 2s^2 + s`, `h01 = 3s^2 - 2s^3`, `h11 = s^3 - s^2`.
#[allow(clippy::too_many_arguments)]
pub fn hermite(
    x0: f64,
    h: f64,
    y0: &[f64],
    y1: &[f64],
    f0: &[f64],
    f1: &[f64],
    t: f64,
    out: &mut [f64],
    dout: &mut [f64],
) {
    let s = (t - x0) / h;
    let (s2, s3) = (s * s, s * s * s);
    if !out.is_empty() {
        let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
        let h10 = (s3 - 2.0 * s2 + s) * h;
        let h01 = 3.0 * s2 - 2.0 * s3;
        let h11 = (s3 - s2) * h;
        for i in 0..out.len() {
            out[i] = h00 * y0[i] + h10 * f0[i] + h01 * y1[i] + h11 * f1[i];
        }
    }
    if !dout.is_empty() {
        let d00 = (6.0 * s2 - 6.0 * s) / h;
        let d10 = 3.0 * s2 - 4.0 * s + 1.0;
        let d11 = 3.0 * s2 - 2.0 * s;
        for i in 0..dout.len() {
            dout[i] = d00 * (y0[i] - y1[i]) + d10 * f0[i] + d11 * f1[i];
        }
    }
}
