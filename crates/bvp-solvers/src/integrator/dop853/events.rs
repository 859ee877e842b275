//! Event location: the first sign change of a scalar function `g(s, u)` over an accepted
//! step, located by Brent's method on the step's dense output.

use super::dense::dense_eval;
use crate::roots::{brent, RootOptions};
use crate::{BvpError, Result};

/// An accepted step `[x, x + h]` (`posneg` its direction) with its dense coefficients `rc`.
pub(super) struct StepSpan<'a> {
    pub x: f64,
    pub h: f64,
    pub posneg: f64,
    pub rc: &'a [f64],
}

/// Locates the zero of `ev` in the step `span`, given a sign change (or an exact zero at the
/// end `xph`), to `|ds| <= 1e-14 max(|x|, |xph|, |h|)`; `buf` (length `dim`) is scratch.
pub(super) fn locate<E: FnMut(f64, &[f64]) -> f64>(
    ev: &mut E,
    g_new: f64,
    span: &StepSpan<'_>,
    buf: &mut [f64],
) -> Result<f64> {
    let StepSpan { x, h, posneg, rc } = *span;
    let n = buf.len();
    let xph = x + h;
    if g_new == 0.0 {
        return Ok(xph);
    }
    let scale = x.abs().max(xph.abs()).max(h.abs());
    let opts = RootOptions {
        xtol: 1e-14 * scale,
        ftol: 0.0,
        max_iter: 200,
    };
    let (a, b) = if posneg > 0.0 { (x, xph) } else { (xph, x) };
    let root = brent(
        |s: f64| -> Result<f64> {
            let theta = (s - x) / h;
            dense_eval(rc, n, theta, buf);
            let g = ev(s, buf);
            if g.is_nan() {
                Err(BvpError::NonFinite {
                    what: "event function",
                    s,
                })
            } else {
                Ok(g)
            }
        },
        a,
        b,
        &opts,
    )?;
    Ok(root.x)
}

/// Whether `g` crossed zero between `g_old` and `g_new` (or hit it exactly at the end).
pub(super) fn crossed(g_old: f64, g_new: f64) -> bool {
    g_new == 0.0 || (g_old != 0.0 && (g_old < 0.0) != (g_new < 0.0))
}

/// `g` if it is not NaN (an event function's value at `s`).
pub(super) fn finite(g: f64, s: f64) -> Result<f64> {
    if g.is_nan() {
        Err(BvpError::NonFinite {
            what: "event function",
            s,
        })
    } else {
        Ok(g)
    }
}
