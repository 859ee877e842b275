//! Cauchy's method on a bracket ([`cauchy`]): the root of the local quadratic Taylor model,
//! for a function whose first two derivatives are cheap (a polynomial, an interpolant).

use super::{check_inputs, finite, not_bracketed, Root, RootOptions};
use crate::BvpError;

/// The step of Cauchy's method from a point where `(f, f', f'') = jet`: the root nearest
/// to the point of the quadratic model `f + f' d + f'' d^2 / 2 = 0`, in the form that does
/// not cancel, `d = -2 f / (f' + sign(f') sqrt(f'^2 - 2 f f''))`; `None` where the model
/// has no real root (or none nearer than infinity).
fn step([f, d1, d2]: [f64; 3]) -> Option<f64> {
    let disc = d1 * d1 - 2.0 * f * d2;
    if !(disc >= 0.0) {
        return None;
    }
    let den = d1 + disc.sqrt().copysign(d1);
    let d = -2.0 * f / den;
    d.is_finite().then_some(d)
}

/// Cauchy's method (Traub 1964, *Iterative Methods for the Solution of Equations*, 8.4:
/// third order at a simple root) safeguarded by a bracket `[a, b]` with `f(a) f(b) <= 0`.
/// `jet(x)` returns `(f, f', f'')` at `x`.
///
/// From the end with the smaller `|f|`, each step goes to the nearest root of the local
/// quadratic model; a step that leaves the bracket, a model without a real root,
/// or a bracket that has not halved in two steps is replaced by bisection, and a step
/// shorter than `tol1` is lengthened to `tol1` (as Brent's is) so that the bracket closes
/// around the root. Terminates when the bracket's half-width is `<= tol1 = 2 eps |x| +
/// xtol/2` (the end with the smaller `|f|` is the root), when `f(x) = 0`, or when
/// `|f(x)| <= ftol`.
///
/// Where Brent's method falls back to bisection for long (a root close to a double root,
/// next to a bracket end: `f = c (1 - x)^2 - eps`, whose secants creep), the quadratic
/// model holds the curvature and lands next to the root in one step.
///
/// ```
/// use bvp_solvers::roots::{cauchy, RootOptions};
/// use bvp_solvers::BvpError;
/// // a root 5.4e-7 short of the end of [0.98, 1], next to the double root at 1
/// let jet = |x: f64| Ok::<_, BvpError>([2.0 * (1.0 - x).powi(2) - 5.9e-13, -4.0 * (1.0 - x), 4.0]);
/// let r = cauchy(jet, 0.98, 1.0, &RootOptions::default()).unwrap();
/// assert!((r.x - (1.0 - (5.9e-13f64 / 2.0).sqrt())).abs() < 1e-14);
/// assert!(r.iterations <= 4);
/// ```
///
/// # Errors
/// `NotBracketed` if `f(a)` and `f(b)` have the same strict sign; `NoConvergence` after
/// `max_iter` iterations; `NonFinite` if `f` returns NaN; `InvalidInput` for non-finite ends
/// or tolerances; any error of `jet`.
pub fn cauchy<F, E>(mut jet: F, a: f64, b: f64, opts: &RootOptions) -> Result<Root, E>
where
    F: FnMut(f64) -> Result<[f64; 3], E>,
    E: From<BvpError>,
{
    check_inputs(a, b, opts)?;
    let at = |x: f64, fx: f64, iterations: usize| Root { x, fx, iterations };
    let done = |fx: f64| fx == 0.0 || fx.abs() <= opts.ftol;
    let ja = jet(a)?;
    finite(ja[0], a)?;
    if done(ja[0]) {
        return Ok(at(a, ja[0], 0));
    }
    let jb = jet(b)?;
    finite(jb[0], b)?;
    if done(jb[0]) {
        return Ok(at(b, jb[0], 0));
    }
    if (ja[0] < 0.0) == (jb[0] < 0.0) {
        return Err(not_bracketed((a, ja[0]), (b, jb[0])).into());
    }
    // the bracket: where f < 0 and where f > 0, with their values
    let (mut neg, mut pos) = if ja[0] < 0.0 {
        ((a, ja[0]), (b, jb[0]))
    } else {
        ((b, jb[0]), (a, ja[0]))
    };
    // the current point: the end with the smaller |f|
    let (mut x, mut j) = if ja[0].abs() <= jb[0].abs() {
        (a, ja)
    } else {
        (b, jb)
    };
    // the bracket's width two steps back and one step back
    let mut widths = [f64::INFINITY; 2];
    let eps = f64::EPSILON;
    for it in 1..=opts.max_iter + 1 {
        let best = if neg.1.abs() <= pos.1.abs() { neg } else { pos };
        let tol1 = 2.0 * eps * best.0.abs() + 0.5 * opts.xtol;
        let width = (pos.0 - neg.0).abs();
        if 0.5 * width <= tol1 {
            return Ok(at(best.0, best.1, it - 1));
        }
        if it > opts.max_iter {
            break;
        }
        let (lo, hi) = (neg.0.min(pos.0), neg.0.max(pos.0));
        let mid = 0.5 * (lo + hi);
        let x_new = match step(j) {
            Some(d) if width <= 0.5 * widths[0] || widths[0].is_infinite() => {
                let d = if d.abs() > tol1 { d } else { tol1.copysign(d) };
                let t = x + d;
                if t > lo && t < hi {
                    t
                } else {
                    mid
                }
            }
            _ => mid,
        };
        widths = [widths[1], width];
        // a forced bisection starts the halving count anew
        if x_new == mid {
            widths = [f64::INFINITY, width];
        }
        x = x_new;
        j = jet(x)?;
        let fx = finite(j[0], x)?;
        if done(fx) {
            return Ok(at(x, fx, it));
        }
        if fx < 0.0 {
            neg = (x, fx);
        } else {
            pos = (x, fx);
        }
    }
    Err(BvpError::NoConvergence {
        method: "cauchy",
        iterations: opts.max_iter,
        residual: neg.1.abs().min(pos.1.abs()),
    }
    .into())
}

#[cfg(test)]
mod tests {
    use super::super::brent;
    use super::*;

    fn ok<const N: usize>(v: [f64; N]) -> Result<[f64; N], BvpError> {
        Ok(v)
    }

    /// Closed-form roots, to a few ulps, in a handful of steps (third order).
    #[test]
    fn cauchy_finds_closed_form_roots() {
        let o = RootOptions {
            xtol: 0.0,
            ..RootOptions::default()
        };
        type Case = (fn(f64) -> [f64; 3], f64, f64, f64);
        let cases: [Case; 4] = [
            (|x| [x * x - 2.0, 2.0 * x, 2.0], 0.0, 2.0, 2f64.sqrt()),
            (
                |x| [x.ln() - 1.0, 1.0 / x, -1.0 / (x * x)],
                1.0,
                4.0,
                std::f64::consts::E,
            ),
            (|x| [x.exp() - 3.0, x.exp(), x.exp()], 0.0, 2.0, 3f64.ln()),
            (
                |x| {
                    let c = x.cos();
                    [x.tan() - 1.0, 1.0 / (c * c), 2.0 * x.tan() / (c * c)]
                },
                0.0,
                1.5,
                std::f64::consts::FRAC_PI_4,
            ),
        ];
        for (f, a, b, truth) in cases {
            let r = cauchy(|x| ok(f(x)), a, b, &o).unwrap();
            assert!(
                (r.x - truth).abs() <= 4.0 * f64::EPSILON * truth,
                "{} vs {truth}",
                r.x
            );
            assert!(r.iterations <= 10, "{}", r.iterations);
        }
    }

    /// A root next to a double root at a bracket end (the moment of a tip contact whose
    /// force runs along the tip, `m(1)` at the integration's noise): Cauchy lands on it
    /// at once, where Brent's secants creep for tens of steps. The same root either way.
    #[test]
    fn a_root_next_to_a_double_root_takes_a_few_steps() {
        let o = RootOptions {
            xtol: 1e-15,
            ..RootOptions::default()
        };
        for (c, tiny) in [(1.9, 5.9e-13), (0.3, 1e-15), (40.0, 2e-10)] {
            let f = move |x: f64| [c * (1.0 - x).powi(2) - tiny, -2.0 * c * (1.0 - x), 2.0 * c];
            let truth = 1.0 - (tiny / c).sqrt();
            let r = cauchy(|x| ok(f(x)), 0.98, 1.0, &o).unwrap();
            let rb = brent(|x| Ok::<_, BvpError>(f(x)[0]), 0.98, 1.0, &o).unwrap();
            assert!((r.x - truth).abs() <= 1e-15, "{} vs {truth}", r.x);
            assert!((rb.x - truth).abs() <= 1e-15, "{} vs {truth}", rb.x);
            assert!(r.iterations <= 4, "{}", r.iterations);
            assert!(rb.iterations >= 15, "{}", rb.iterations);
        }
    }

    /// Seeded battery: random polynomials of degree 7 on brackets with a sign change. The
    /// root is bracketed to the tolerance (the function changes sign within `2 tol1` of it,
    /// or vanishes there), never costs more than bisection would, and is Brent's root where
    /// the bracket holds one root only.
    #[test]
    fn random_polynomials_are_solved_to_the_tolerance() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut unif = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let o = RootOptions {
            xtol: 1e-15,
            ..RootOptions::default()
        };
        let (mut solved, mut single, mut several) = (0, 0, 0);
        for _ in 0..2000 {
            let c: Vec<f64> = (0..8).map(|_| 2.0 * unif() - 1.0).collect();
            let jet = |x: f64| {
                let (mut p, mut d1, mut d2) = (0.0, 0.0, 0.0);
                for &ck in c.iter().rev() {
                    d2 = d2 * x + 2.0 * d1;
                    d1 = d1 * x + p;
                    p = p * x + ck;
                }
                [p, d1, d2]
            };
            let (a, b) = (-1.0 - unif(), 1.0 + unif());
            if (jet(a)[0] < 0.0) == (jet(b)[0] < 0.0) {
                continue;
            }
            let r = cauchy(|x| ok(jet(x)), a, b, &o).unwrap();
            solved += 1;
            let tol1 = 2.0 * f64::EPSILON * r.x.abs() + 0.5 * o.xtol;
            assert!(r.x >= a && r.x <= b);
            let (l, h) = (jet(r.x - 2.0 * tol1)[0], jet(r.x + 2.0 * tol1)[0]);
            assert!(r.fx == 0.0 || (l < 0.0) != (h < 0.0), "{a} {b} {}", r.x);
            // bisection would take log2((b - a) / tol1) steps
            let bisections = ((b - a) / tol1).log2().ceil() as usize;
            assert!(r.iterations <= bisections + 2, "{}", r.iterations);
            // the sign changes on a fine grid: one root only -> Brent's
            let n = 4000;
            let changes = (0..n)
                .filter(|&k| {
                    let x0 = a + (b - a) * k as f64 / n as f64;
                    let x1 = a + (b - a) * (k + 1) as f64 / n as f64;
                    (jet(x0)[0] < 0.0) != (jet(x1)[0] < 0.0)
                })
                .count();
            several += usize::from(changes > 1);
            if changes == 1 {
                single += 1;
                let rb = brent(|x| Ok::<_, BvpError>(jet(x)[0]), a, b, &o).unwrap();
                assert!((r.x - rb.x).abs() <= 4.0 * tol1, "{} vs {}", r.x, rb.x);
            }
        }
        assert!(
            solved > 500 && single > 300 && several > 50,
            "{solved} {single} {several}"
        );
    }

    #[test]
    fn cauchy_reports_bad_brackets_and_values() {
        let o = RootOptions::default();
        let e = cauchy(|x| ok([x * x + 1.0, 2.0 * x, 2.0]), -1.0, 2.0, &o).unwrap_err();
        assert!(matches!(e, BvpError::NotBracketed { a, b, .. } if a == -1.0 && b == 2.0));
        let e = cauchy(|_| ok([f64::NAN, 0.0, 0.0]), 0.0, 1.0, &o).unwrap_err();
        assert!(matches!(e, BvpError::NonFinite { .. }));
        let e = cauchy(|x| ok([x, 1.0, 0.0]), f64::NAN, 1.0, &o).unwrap_err();
        assert!(matches!(e, BvpError::InvalidInput { name: "a", .. }));
        // an end that is a root is returned as it is
        let r = cauchy(|x| ok([x - 1.0, 1.0, 0.0]), 0.0, 1.0, &o).unwrap();
        assert_eq!((r.x, r.iterations), (1.0, 0));
        // a budget too small for the tolerance
        let tight = RootOptions {
            xtol: 0.0,
            ftol: 0.0,
            max_iter: 1,
        };
        let e = cauchy(|x| ok([x.sin(), x.cos(), -x.sin()]), 3.0, 3.5, &tight).unwrap_err();
        assert!(matches!(
            e,
            BvpError::NoConvergence {
                method: "cauchy",
                ..
            }
        ));
    }
}
