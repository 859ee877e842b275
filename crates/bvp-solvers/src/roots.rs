//! Scalar roots of `f(x) = 0` on a bracketing interval: bisection and Brent's method (the
//! `fzero` equivalents), and bisection on a predicate ([`bisect`]).
//!
//! Both take *fallible* closures `FnMut(f64) -> Result<f64, E>` so that callers can propagate
//! their own error types; the only requirement is `E: From<BvpError>`.

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::BvpError;

/// A located root.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Root {
    /// The root estimate.
    pub x: f64,
    /// `f(x)`.
    pub fx: f64,
    /// Iterations (function evaluations after the two end points).
    pub iterations: usize,
}

/// Stopping criteria of the root finders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RootOptions {
    /// Absolute tolerance on `x`: stop when the bracket half-width is
    /// `<= xtol/2 + 2 eps |x|` (Brent) or `<= xtol` (bisection).
    pub xtol: f64,
    /// Stop as soon as `|f(x)| <= ftol` (0 disables).
    pub ftol: f64,
    /// Iteration budget; exceeding it gives `NoConvergence`.
    pub max_iter: usize,
}

impl Default for RootOptions {
    fn default() -> Self {
        Self {
            xtol: 1e-14,
            ftol: 0.0,
            max_iter: 200,
        }
    }
}

fn check_inputs(a: f64, b: f64, opts: &RootOptions) -> Result<(), BvpError> {
    if !a.is_finite() {
        return Err(BvpError::InvalidInput {
            name: "a",
            value: a,
            reason: "bracket ends must be finite",
        });
    }
    if !b.is_finite() {
        return Err(BvpError::InvalidInput {
            name: "b",
            value: b,
            reason: "bracket ends must be finite",
        });
    }
    if !(opts.xtol >= 0.0) {
        return Err(BvpError::InvalidInput {
            name: "xtol",
            value: opts.xtol,
            reason: "must be >= 0",
        });
    }
    if !(opts.ftol >= 0.0) {
        return Err(BvpError::InvalidInput {
            name: "ftol",
            value: opts.ftol,
            reason: "must be >= 0",
        });
    }
    Ok(())
}

fn finite(fx: f64, x: f64) -> Result<f64, BvpError> {
    if fx.is_nan() {
        Err(BvpError::NonFinite {
            what: "root function value",
            s: x,
        })
    } else {
        Ok(fx)
    }
}

/// The values at the ends of a bracket, or a root already found at one of them.
enum Ends {
    Root(Root),
    Values(f64, f64),
}

/// Checks the inputs and evaluates `f` at `a`, then `b`: an end where `f` vanishes (or is
/// within `ftol`) is the root.
fn ends<F, E>(f: &mut F, a: f64, b: f64, opts: &RootOptions) -> Result<Ends, E>
where
    F: FnMut(f64) -> Result<f64, E>,
    E: From<BvpError>,
{
    check_inputs(a, b, opts)?;
    let at = |x: f64, fx: f64| {
        Ends::Root(Root {
            x,
            fx,
            iterations: 0,
        })
    };
    let fa = finite(f(a)?, a)?;
    if fa == 0.0 || fa.abs() <= opts.ftol {
        return Ok(at(a, fa));
    }
    let fb = finite(f(b)?, b)?;
    if fb == 0.0 || fb.abs() <= opts.ftol {
        return Ok(at(b, fb));
    }
    Ok(Ends::Values(fa, fb))
}

/// Bisection on a predicate: `below(x)` is `Some(true)` left of the point sought and
/// `Some(false)` right of it (on `[lo, hi]` it changes once). Halves `[lo, hi]` until its
/// ends are adjacent floats, at most `max_iter` times, or until `below` returns `None` (the
/// function is not defined there); returns the midpoint of the last bracket. No end is
/// evaluated: the caller knows the bracket.
///
/// ```
/// use bvp_solvers::roots::bisect;
/// let x = bisect(|x| Some(x * x < 2.0), 1.0, 2.0, 200);
/// assert!((x - 2f64.sqrt()).abs() <= 2.0 * f64::EPSILON);
/// ```
pub fn bisect<P: FnMut(f64) -> Option<bool>>(
    mut below: P,
    lo: f64,
    hi: f64,
    max_iter: usize,
) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    for _ in 0..max_iter {
        let m = 0.5 * (lo + hi);
        if m <= lo || m >= hi {
            break;
        }
        match below(m) {
            Some(true) => lo = m,
            Some(false) => hi = m,
            None => break,
        }
    }
    0.5 * (lo + hi)
}

/// Bisection on `[a, b]` (either order) with `f(a) f(b) <= 0`: the bracket is halved at its
/// midpoint, keeping the half with a sign change, until its half-width is `<= xtol` (or the
/// midpoint is not representable between the ends) or `|f(mid)| <= ftol`. Gains one bit per
/// iteration.
///
/// # Errors
/// `NotBracketed` if `f(a)` and `f(b)` have the same strict sign; `NoConvergence` after
/// `max_iter` iterations; `NonFinite` if `f` returns NaN; `InvalidInput` for non-finite ends;
/// any error of `f`.
pub fn bisection<F, E>(mut f: F, a: f64, b: f64, opts: &RootOptions) -> Result<Root, E>
where
    F: FnMut(f64) -> Result<f64, E>,
    E: From<BvpError>,
{
    let (a, b) = if a <= b { (a, b) } else { (b, a) };
    let (mut fa, mut fb) = match ends(&mut f, a, b, opts)? {
        Ends::Root(r) => return Ok(r),
        Ends::Values(fa, fb) => (fa, fb),
    };
    let (mut a, mut b) = (a, b);
    if (fa < 0.0) == (fb < 0.0) {
        return Err(BvpError::NotBracketed { a, b, fa, fb }.into());
    }
    // the end of the current bracket with the smaller |f|
    let best = |a: f64, fa: f64, b: f64, fb: f64| {
        if fa.abs() <= fb.abs() {
            (a, fa)
        } else {
            (b, fb)
        }
    };
    for it in 1..=opts.max_iter {
        let m = a + 0.5 * (b - a);
        if m <= a || m >= b {
            // the bracket is two adjacent floats
            let (x, fx) = best(a, fa, b, fb);
            return Ok(Root {
                x,
                fx,
                iterations: it - 1,
            });
        }
        let fm = finite(f(m)?, m)?;
        if fm == 0.0 || fm.abs() <= opts.ftol {
            return Ok(Root {
                x: m,
                fx: fm,
                iterations: it,
            });
        }
        if (fm < 0.0) == (fa < 0.0) {
            a = m;
            fa = fm;
        } else {
            b = m;
            fb = fm;
        }
        if 0.5 * (b - a) <= opts.xtol {
            let (x, fx) = best(a, fa, b, fb);
            return Ok(Root {
                x,
                fx,
                iterations: it,
            });
        }
    }
    Err(BvpError::NoConvergence {
        method: "bisection",
        iterations: opts.max_iter,
        residual: fa.abs().min(fb.abs()),
    }
    .into())
}

/// Brent's method (Brent 1973, *Algorithms for Minimization without Derivatives*, ch. 4;
/// the `zeroin` algorithm): inverse quadratic interpolation / secant steps safeguarded by
/// bisection on a bracket `[b, c]` with `f(b) f(c) <= 0`. Terminates when the half-width
/// `|c - b|/2 <= tol1 = 2 eps |b| + xtol/2`, when `f(b) = 0`, or when `|f(b)| <= ftol`.
/// Superlinear for smooth simple roots, never worse than about twice bisection.
///
/// # Errors
/// As [`bisection`] (`method: "brent"`).
pub fn brent<F, E>(mut f: F, a: f64, b: f64, opts: &RootOptions) -> Result<Root, E>
where
    F: FnMut(f64) -> Result<f64, E>,
    E: From<BvpError>,
{
    let (mut fa, mut fb) = match ends(&mut f, a, b, opts)? {
        Ends::Root(r) => return Ok(r),
        Ends::Values(fa, fb) => (fa, fb),
    };
    let (mut a, mut b) = (a, b);
    if (fa < 0.0) == (fb < 0.0) {
        let (lo, hi, flo, fhi) = if a <= b {
            (a, b, fa, fb)
        } else {
            (b, a, fb, fa)
        };
        return Err(BvpError::NotBracketed {
            a: lo,
            b: hi,
            fa: flo,
            fb: fhi,
        }
        .into());
    }
    let eps = f64::EPSILON;
    let mut c = a;
    let mut fc = fa;
    let mut d = b - a;
    let mut e = d;
    for it in 0..=opts.max_iter {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * eps * b.abs() + 0.5 * opts.xtol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 || fb.abs() <= opts.ftol {
            return Ok(Root {
                x: b,
                fx: fb,
                iterations: it,
            });
        }
        if it == opts.max_iter {
            break;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            // attempt inverse quadratic interpolation (secant if a == c)
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            let min1 = 3.0 * xm * q - (tol1 * q).abs();
            let min2 = (e * q).abs();
            if 2.0 * p < min1.min(min2) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        if d.abs() > tol1 {
            b += d;
        } else {
            b += tol1.copysign(xm);
        }
        fb = finite(f(b)?, b)?;
    }
    Err(BvpError::NoConvergence {
        method: "brent",
        iterations: opts.max_iter,
        residual: fb.abs(),
    }
    .into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bisect_halves_a_given_number_of_times_and_stops_where_undefined() {
        // x < 0.3 on [0, 1]: after 12 halvings the midpoint is within 2^-13 of 0.3
        let x = bisect(|t| Some(t < 0.3), 0.0, 1.0, 12);
        assert!((x - 0.3).abs() <= 0.5f64.powi(13), "{x}");
        // the bracket stops shrinking where the predicate is not known: [0, 1] -> [0, 0.5],
        // then 0.25 is undefined
        let x = bisect(|t| (t > 0.4).then_some(t < 0.3), 0.0, 1.0, 12);
        assert_eq!(x, 0.25);
        // without a budget the bracket shrinks to adjacent floats
        let x = bisect(|t| Some(t * t < 2.0), 1.0, 2.0, 1000);
        assert!((x - 2f64.sqrt()).abs() <= 2.0 * f64::EPSILON);
    }
}
