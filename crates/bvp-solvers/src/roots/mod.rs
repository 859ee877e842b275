//! Scalar roots: a bracket grown outwards from a start ([`grow_brackets`]), then Brent's
//! method on it (the `fzero` equivalent, [`brent`]) or bisection on a predicate ([`bisect`]);
//! where the first two derivatives are cheap (a polynomial, an interpolant), Cauchy's method
//! on the bracket ([`cauchy`], third order, and quick next to a double root).
//!
//! [`brent`] takes a *fallible* closure `FnMut(f64) -> Result<f64, E>` so that callers can
//! propagate their own error types; the only requirement is `E: From<BvpError>`.

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::BvpError;

mod cauchy;
pub use cauchy::cauchy;

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
    /// `<= xtol/2 + 2 eps |x|`.
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

/// The `NotBracketed` error of the ends `(a, f(a))`, `(b, f(b))` of a bracket (in order).
fn not_bracketed((a, fa): (f64, f64), (b, fb): (f64, f64)) -> BvpError {
    let ((a, fa), (b, fb)) = if a <= b {
        ((a, fa), (b, fb))
    } else {
        ((b, fb), (a, fa))
    };
    BvpError::NotBracketed { a, b, fa, fb }
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

/// How [`grow_brackets`] steps out from its start: steps of `first`, each `factor` times
/// longer than the one before, at most `steps` on each side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Growth {
    /// The first step (> 0).
    pub first: f64,
    /// How many times longer each step is than the one before (>= 1).
    pub factor: f64,
    /// Steps on each side, at most.
    pub steps: usize,
    /// `true`: each step starts where the one before ended (the `k`-th point is
    /// `x0 +- (first + first factor + ... + first factor^k)`); `false`: every step starts at
    /// `x0` (the `k`-th point is `x0 +- first factor^k`).
    pub chained: bool,
}

impl Growth {
    /// Steps from the start (not chained) of `first factor^k`, `k = 0, 1, ...`, as long as
    /// they are at most `reach` (`factor > 1`).
    ///
    /// ```
    /// use bvp_solvers::roots::Growth;
    /// // 1, 2, 4, ..., 2^19 = 524288 <= 1e6
    /// assert_eq!(Growth::within(1.0, 2.0, 1e6).steps, 20);
    /// ```
    pub const fn within(first: f64, factor: f64, reach: f64) -> Growth {
        assert!(factor > 1.0, "the steps must grow");
        let (mut steps, mut d) = (0, first);
        while d <= reach {
            steps += 1;
            d *= factor;
        }
        Growth {
            first,
            factor,
            steps,
            chained: false,
        }
    }
}

/// One side of a [`Brackets`] scan: where it is, what `side` said there, its last step.
#[derive(Clone, Copy, Debug)]
struct Flank {
    /// `-1` left, `+1` right.
    dir: f64,
    /// The end of the scan on this side (the scan stops after evaluating it).
    bound: f64,
    /// The last point evaluated.
    at: f64,
    /// `side` there.
    value: Option<bool>,
    /// The last step (chained) or offset from the start.
    len: f64,
    /// Whether the side has reached its bound.
    done: bool,
}

impl Flank {
    /// A side from `x0` (where `side` is `value`) to `bound`; done at once unless `bound`
    /// lies beyond `x0` in the direction `dir`.
    fn new(dir: f64, x0: f64, value: bool, bound: f64) -> Self {
        Flank {
            dir,
            bound,
            at: x0,
            value: Some(value),
            len: 0.0,
            done: !((bound - x0) * dir > 0.0),
        }
    }

    /// The `k`-th step: the next point (clamped to the bound) evaluated, and the bracket
    /// `(lower, upper)` between it and the point before if `side` changed there (both
    /// defined and different).
    fn step<P: FnMut(f64) -> Option<bool>>(
        &mut self,
        side: &mut P,
        x0: f64,
        g: &Growth,
        k: usize,
    ) -> Option<(f64, f64)> {
        if self.done {
            return None;
        }
        self.len = if k == 0 { g.first } else { self.len * g.factor };
        let from = if g.chained { self.at } else { x0 };
        let x = from + self.dir * self.len;
        let x = if self.dir > 0.0 {
            x.min(self.bound)
        } else {
            x.max(self.bound)
        };
        let v = side(x);
        let found = match (self.value, v) {
            (Some(a), Some(b)) if a != b => Some((self.at.min(x), self.at.max(x))),
            _ => None,
        };
        (self.at, self.value) = (x, v);
        self.done = x == self.bound;
        found
    }
}

/// The brackets of [`grow_brackets`], nearest first.
#[derive(Clone, Debug)]
pub struct Brackets<P> {
    side: P,
    x0: f64,
    growth: Growth,
    /// Left, right.
    flanks: [Flank; 2],
    /// Steps taken on each side.
    k: usize,
    /// The brackets found at the last step, not yet returned (left first).
    found: [Option<(f64, f64)>; 2],
}

/// Brackets of the points where `side` changes, grown outwards from `x0` (where it is
/// `at_x0`) on both sides by the steps of `growth`, the points clamped to `[lo, hi]` (a
/// side ends at its bound, or at once where its bound is `x0`: give `lo = x0` to scan
/// right only). A bracket is two consecutive points of one side where `side` is defined
/// (`Some`) and differs, returned as `(lower, upper)`; the nearer first (the left at equal
/// steps), each side going on past its brackets until its steps are spent. The brackets
/// feed [`brent`] or [`bisect`]; only the scanned points are evaluated.
///
/// ```
/// use bvp_solvers::roots::{brent, grow_brackets, Growth, RootOptions};
/// use bvp_solvers::BvpError;
/// let f = |x: f64| x * x - 2.0;
/// let growth = Growth { first: 0.125, factor: 2.0, steps: 10, chained: true };
/// // from 0 (f < 0): points +-0.125, +-0.375, +-0.875, +-1.875, ...
/// let mut brackets = grow_brackets(|x| Some(f(x) > 0.0), 0.0, false, (-10.0, 10.0), growth);
/// assert_eq!(brackets.next(), Some((-1.875, -0.875)));
/// let (a, b) = brackets.next().unwrap();
/// let root = brent(|x| Ok::<_, BvpError>(f(x)), a, b, &RootOptions::default()).unwrap();
/// assert!((root.x - 2f64.sqrt()).abs() <= 4.0 * f64::EPSILON);
/// assert_eq!(brackets.next(), None);
/// ```
pub fn grow_brackets<P: FnMut(f64) -> Option<bool>>(
    side: P,
    x0: f64,
    at_x0: bool,
    (lo, hi): (f64, f64),
    growth: Growth,
) -> Brackets<P> {
    Brackets {
        side,
        x0,
        growth,
        flanks: [
            Flank::new(-1.0, x0, at_x0, lo),
            Flank::new(1.0, x0, at_x0, hi),
        ],
        k: 0,
        found: [None; 2],
    }
}

impl<P: FnMut(f64) -> Option<bool>> Iterator for Brackets<P> {
    type Item = (f64, f64);

    fn next(&mut self) -> Option<(f64, f64)> {
        loop {
            if let Some(b) = self.found.iter_mut().find_map(Option::take) {
                return Some(b);
            }
            if self.k >= self.growth.steps || self.flanks.iter().all(|f| f.done) {
                return None;
            }
            for (flank, found) in self.flanks.iter_mut().zip(&mut self.found) {
                *found = flank.step(&mut self.side, self.x0, &self.growth, self.k);
            }
            self.k += 1;
        }
    }
}

/// Brent's method (Brent 1973, *Algorithms for Minimization without Derivatives*, ch. 4;
/// the `zeroin` algorithm): inverse quadratic interpolation / secant steps safeguarded by
/// bisection on a bracket `[b, c]` with `f(b) f(c) <= 0`. Terminates when the half-width
/// `|c - b|/2 <= tol1 = 2 eps |b| + xtol/2`, when `f(b) = 0`, or when `|f(b)| <= ftol`.
/// Superlinear for smooth simple roots, never worse than about twice bisection.
///
/// # Errors
/// `NotBracketed` if `f(a)` and `f(b)` have the same strict sign; `NoConvergence` after
/// `max_iter` iterations; `NonFinite` if `f` returns NaN; `InvalidInput` for non-finite ends
/// or tolerances; any error of `f`.
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
        return Err(not_bracketed((a, fa), (b, fb)).into());
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

    fn ok(x: f64) -> Result<f64, BvpError> {
        Ok(x)
    }

    /// Brent on roots known in closed form: to within a few ulps of the truth.
    #[test]
    fn brent_finds_closed_form_roots() {
        let o = RootOptions {
            xtol: 0.0,
            ..RootOptions::default()
        };
        // (f, bracket, root)
        type Case = (fn(f64) -> f64, f64, f64, f64);
        let cases: [Case; 4] = [
            (|x| x * x - 2.0, 0.0, 2.0, 2f64.sqrt()),
            (|x| x.ln() - 1.0, 1.0, 4.0, std::f64::consts::E),
            (|x| x.exp() - 3.0, 0.0, 2.0, 3f64.ln()),
            (|x| x.tan() - 1.0, 0.0, 1.5, std::f64::consts::FRAC_PI_4),
        ];
        for (f, a, b, truth) in cases {
            let r = brent(|x| ok(f(x)), a, b, &o).unwrap();
            assert!(
                (r.x - truth).abs() <= 4.0 * f64::EPSILON * truth,
                "{} vs {truth}",
                r.x
            );
            assert!(r.iterations < 20, "{}", r.iterations);
        }
    }

    /// Bisection on a predicate ends at adjacent floats around the closed-form root.
    #[test]
    fn bisect_finds_closed_form_roots() {
        let x = bisect(|x| Some(x * x * x < 2.0), 0.0, 2.0, 200);
        assert!((x - 2f64.cbrt()).abs() <= 2.0 * f64::EPSILON, "{x}");
        let x = bisect(|x| Some(x.cos() > 0.0), 0.0, 3.0, 200);
        assert!(
            (x - std::f64::consts::FRAC_PI_2).abs() <= 2.0 * f64::EPSILON,
            "{x}"
        );
    }

    /// Offsets from the start (not chained): the points are `x0 +- first factor^k`, clamped,
    /// a side ending at its bound.
    #[test]
    fn brackets_grow_by_offsets_and_stop_at_the_bounds() {
        let mut seen = Vec::new();
        let g = Growth::within(0.5, 2.0, 100.0);
        assert_eq!(g.steps, 8); // 0.5 .. 64
        let found: Vec<_> = grow_brackets(
            |x| {
                seen.push(x);
                Some(x > 3.0)
            },
            1.0,
            false,
            (-0.2, 1e3),
            g,
        )
        .collect();
        // left: 0.5, 0, -0.2 (the bound); right: 1.5, 2, 3, 5 (the change), 9, ..., 65
        assert_eq!(found, vec![(3.0, 5.0)]);
        assert_eq!(
            seen,
            vec![0.5, 1.5, 0.0, 2.0, -0.2, 3.0, 5.0, 9.0, 17.0, 33.0, 65.0]
        );
    }

    /// Chained steps: each starts where the last ended; both sides report their changes,
    /// the nearer first; undefined points bracket nothing.
    #[test]
    fn chained_brackets_come_nearest_first() {
        let g = Growth {
            first: 1.0,
            factor: 3.0,
            steps: 4,
            chained: true,
        };
        // points right of 0: 1, 4, 13, 40; left: -1, -4, -13, -40
        let side = |x: f64| (x != -13.0).then_some(!(-30.0..=2.0).contains(&x));
        let found: Vec<_> = grow_brackets(side, 0.0, false, (-1e9, 1e9), g).collect();
        // the left change at -40 is not bracketed with the undefined -13
        assert_eq!(found, vec![(1.0, 4.0)]);
        let side = |x: f64| Some(!(-3.0..=2.0).contains(&x));
        let found: Vec<_> = grow_brackets(side, 0.0, false, (-1e9, 1e9), g).collect();
        assert_eq!(found, vec![(-4.0, -1.0), (1.0, 4.0)]);
        // a side whose bound is the start is not scanned
        let found: Vec<_> = grow_brackets(side, 0.0, false, (0.0, 1e9), g).collect();
        assert_eq!(found, vec![(1.0, 4.0)]);
    }

    /// A grown bracket fed to Brent: the root of `tanh(x - 3)` from `x0 = 0`, exactly 3.
    #[test]
    fn grown_brackets_feed_brent() {
        let f = |x: f64| (x - 3.0).tanh();
        let g = Growth {
            first: 1e-3,
            factor: 4.0,
            steps: 30,
            chained: true,
        };
        let (a, b) = grow_brackets(|x| Some(f(x) > 0.0), 0.0, false, (0.0, f64::INFINITY), g)
            .next()
            .unwrap();
        assert!(a < 3.0 && b > 3.0, "{a} {b}");
        let r = brent(|x| ok(f(x)), a, b, &RootOptions::default()).unwrap();
        assert!((r.x - 3.0).abs() <= 4.0 * f64::EPSILON, "{}", r.x);
    }
}
