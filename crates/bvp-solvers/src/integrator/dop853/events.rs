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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::Dop853;
    use crate::testing::Harmonic;
    use std::f64::consts::FRAC_PI_2;

    /// `u = (sin s, cos s)`: the event `u1 = cos s = 0` lies at `pi/2`, where `u = (1, 0)`.
    #[test]
    fn the_zero_of_cos_is_located_at_half_pi() {
        let (sol, ev) = Dop853::new(1e-13, 1e-13)
            .integrate_until(&Harmonic, 0.0, 3.0, &[0.0, 1.0], |_, u| u[1])
            .unwrap();
        let ev = ev.expect("an event");
        assert!((ev.s - FRAC_PI_2).abs() < 1e-12, "{:e}", ev.s - FRAC_PI_2);
        assert!((ev.u[0] - 1.0).abs() < 1e-12, "{:?}", ev.u);
        // located to the dense output's own zero
        assert!(ev.u[1].abs() < 1e-15, "{:e}", ev.u[1]);
        assert_eq!((sol.s_end, sol.u_end.clone()), (ev.s, ev.u));
        // backwards from pi: the same zero, approached from the other side
        let (_, ev) = Dop853::new(1e-13, 1e-13)
            .integrate_until(&Harmonic, 3.0, 0.0, &[3f64.sin(), 3f64.cos()], |_, u| u[1])
            .unwrap();
        assert!((ev.unwrap().s - FRAC_PI_2).abs() < 1e-12);
    }

    /// On a step whose interpolant is the line `u = -1 + 4 theta` the zero is at
    /// `theta = 1/4`, in either direction; an exact zero at the end is the end.
    #[test]
    fn locate_finds_the_zero_of_the_step_polynomial() {
        let mut rc = [0.0; 8];
        rc[0] = -1.0;
        rc[1] = 4.0;
        let mut buf = [0.0];
        let mut ev = |_: f64, u: &[f64]| u[0];
        let span = StepSpan {
            x: 1.0,
            h: 2.0,
            posneg: 1.0,
            rc: &rc,
        };
        let s = locate(&mut ev, 3.0, &span, &mut buf).unwrap();
        assert!((s - 1.5).abs() <= 1e-14 * 3.0, "{s}");
        let back = StepSpan {
            x: 1.0,
            h: -2.0,
            posneg: -1.0,
            rc: &rc,
        };
        let s = locate(&mut ev, 3.0, &back, &mut buf).unwrap();
        assert!((s - 0.5).abs() <= 1e-14 * 3.0, "{s}");
        assert_eq!(locate(&mut ev, 0.0, &span, &mut buf).unwrap(), 3.0);
        let mut nan = |_: f64, _: &[f64]| f64::NAN;
        assert!(locate(&mut nan, 3.0, &span, &mut buf).is_err());
    }

    #[test]
    fn a_crossing_is_a_sign_change_or_a_zero_at_the_end() {
        assert!(crossed(-1.0, 2.0) && crossed(2.0, -1.0) && crossed(1.0, 0.0));
        // a zero at the start is not a crossing (it was the last step's end)
        assert!(!crossed(0.0, 1.0) && !crossed(1.0, 2.0) && !crossed(-1.0, -2.0));
        assert_eq!(finite(-2.0, 0.5), Ok(-2.0));
        assert!(finite(f64::NAN, 0.5).is_err());
    }
}
