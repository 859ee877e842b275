//! Pseudo-arclength continuation of a solution curve, with located events.

// `!(x > c)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
//!
//! A [`Curve`] is the set of solutions of `R(u) = 0` with `R: R^N -> R^(N-1)`: generically a
//! one-dimensional curve, which may turn back in any coordinate (a fold). [`Arclength`]
//! follows it point by point (Keller's method):
//!
//! ```text
//! predictor:  p = u_k + h t_k / |t_k|_w             (t_k the unit tangent at u_k)
//! corrector:  R(u) = 0,  t_k . (u - p) = 0          (the hyperplane through p normal to t_k)
//! ```
//!
//! so folds are passed like any other point. The step `h` adapts to the corrector's effort
//! (grown after an easy correction, shortened after a hard one, halved after a failure) and
//! to the turning of the tangent (a step across which the tangent turns by more than
//! [`ArcControl::min_turn_cos`] is retried shorter). `|t|_w` is the curve's own step
//! metric ([`Curve::step_length`]).
//!
//! Events are scalar conditions `g(u)` positive before the event: after a step the caller
//! checks which changed sign; [`locate`] finds each zero by the Illinois variant of regula
//! falsi along the chord between the two points, every trial point a solution of the curve
//! on a hyperplane across the chord, so a located event is an exact point of the curve
//! within `tol` of the event. [`Arclength::earliest`] locates several and keeps the first
//! along the tangent.
//!
//! The driver loop stays with the caller, like an ODE stepper's: it decides what the events
//! mean (end, switch of equations, a restart on another curve with [`Arclength::restart`])
//! and which points it keeps.
//!
//! ```
//! use bvp_solvers::arclength::{locate, ArcControl, Arclength, Attempt, Curve};
//!
//! /// The unit circle `x^2 + y^2 = 1`, corrected by Newton on the 2x2 system.
//! struct Circle;
//! impl Curve<2> for Circle {
//!     type Point = [f64; 2];
//!     type Error = ();
//!     fn coords(&self, p: &[f64; 2]) -> [f64; 2] { *p }
//!     fn correct(&self, p: [f64; 2], n: [f64; 2], _r: f64) -> Result<[f64; 2], ()> {
//!         let mut u = p;
//!         for _ in 0..20 {
//!             let r = [u[0] * u[0] + u[1] * u[1] - 1.0, n[0] * (u[0] - p[0]) + n[1] * (u[1] - p[1])];
//!             let (a, b, c, d) = (2.0 * u[0], 2.0 * u[1], n[0], n[1]);
//!             let det = a * d - b * c;
//!             u[0] -= (d * r[0] - b * r[1]) / det;
//!             u[1] -= (a * r[1] - c * r[0]) / det;
//!         }
//!         Ok(u)
//!     }
//!     fn tangent(&self, p: &[f64; 2], dir: &[f64; 2]) -> [f64; 2] {
//!         let t = [-p[1], p[0]];
//!         if t[0] * dir[0] + t[1] * dir[1] < 0.0 { [p[1], -p[0]] } else { t }
//!     }
//!     fn iterations(&self, _p: &[f64; 2]) -> usize { 2 }
//! }
//!
//! // From (1, 0) counter-clockwise until y changes sign again (past the fold at x = -1).
//! let ctl = ArcControl { initial: 0.1, max: 0.3, min: 1e-9, ..ArcControl::default() };
//! let mut arc = Arclength::new(&Circle, [1.0, 0.0], [0.0, 1.0], ctl);
//! let mut event = None;
//! for _ in 0..100 {
//!     let Attempt::Point(p, t) = arc.attempt(&Circle) else { continue };
//!     if arc.current()[1] > 0.0 && p[1] <= 0.0 {
//!         let y = |q: &[f64; 2]| Ok::<f64, ()>(q[1]);
//!         event = Some(locate(&Circle, arc.current(), &p, &y, 1e-13).unwrap());
//!         break;
//!     }
//!     arc.accept(&Circle, p, t);
//! }
//! let at = event.unwrap();
//! assert!((at[0] + 1.0).abs() < 1e-12 && at[1].abs() < 1e-12);
//! ```

/// A curve of solutions `R(u) = 0`, `R: R^N -> R^(N-1)`, as [`Arclength`] traces it.
pub trait Curve<const N: usize> {
    /// A solved point (its coordinates and whatever the caller keeps with them).
    type Point: Clone;
    /// The corrector's error.
    type Error;

    /// The coordinates `u` of a point.
    fn coords(&self, p: &Self::Point) -> [f64; N];

    /// Solves `R(u) = 0` with `n . (u - p) = 0`, starting from `p` (`n` a unit vector). A
    /// solution or an iterate farther than `radius` from `p` may be refused: the
    /// prediction was off the curve.
    ///
    /// # Errors
    /// The corrector's own when it does not converge.
    fn correct(&self, p: [f64; N], n: [f64; N], radius: f64) -> Result<Self::Point, Self::Error>;

    /// The unit tangent of the curve at `p` (the null vector of `dR/du`), with the sign that
    /// makes it point along `dir`.
    fn tangent(&self, p: &Self::Point, dir: &[f64; N]) -> [f64; N];

    /// How many corrector iterations `p` took (the step control grows the step after an
    /// easy correction and shortens it after a hard one).
    fn iterations(&self, p: &Self::Point) -> usize;

    /// The length of the unit tangent `t` at `p` in the curve's step metric: a predictor
    /// step of length `h` moves `h / step_length` along `t`. Euclidean (1) by default;
    /// a curve whose coordinates differ in scale weighs them here.
    fn step_length(&self, _p: &Self::Point, _t: &[f64; N]) -> f64 {
        1.0
    }
}

/// Step control of [`Arclength`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcControl {
    /// First step length.
    pub initial: f64,
    /// Largest step length.
    pub max: f64,
    /// Smallest step length: a corrector failing below it ends the attempt
    /// ([`Attempt::Failed`]).
    pub min: f64,
    /// Factor of the step after an easy correction (at most [`ArcControl::easy`] iterations).
    pub grow: f64,
    /// Factor of the step after a hard one (at least [`ArcControl::hard`] iterations).
    pub shorten: f64,
    /// Corrector iterations up to which a correction is easy.
    pub easy: usize,
    /// Corrector iterations from which a correction is hard.
    pub hard: usize,
    /// Smallest cosine of the angle between the tangents at the two ends of a step that is
    /// trusted; a sharper turn halves the step and retries it.
    pub min_turn_cos: f64,
}

impl Default for ArcControl {
    /// Steps in `[1e-9, 0.1]` from 0.01, x1.6 after at most 3 iterations, x0.6 after 6 or
    /// more, turns up to ~25 degrees a step.
    fn default() -> Self {
        ArcControl {
            initial: 0.01,
            max: 0.1,
            min: 1e-9,
            grow: 1.6,
            shorten: 0.6,
            easy: 3,
            hard: 6,
            min_turn_cos: 0.9,
        }
    }
}

/// The outcome of one predictor-corrector attempt ([`Arclength::attempt`]).
#[derive(Clone, Debug)]
pub enum Attempt<P, E, const N: usize> {
    /// A corrected point with its tangent (oriented like the current one), not yet accepted.
    Point(P, [f64; N]),
    /// The corrector failed or the tangent turned too sharply: the step was halved, try again.
    Retry,
    /// The corrector failed with the step already below [`ArcControl::min`]: its error.
    Failed(E),
}

/// The state of a pseudo-arclength trace of a [`Curve`]: the current point, its oriented
/// unit tangent and the step length.
#[derive(Clone, Debug)]
pub struct Arclength<P, const N: usize> {
    cur: P,
    u: [f64; N],
    t: [f64; N],
    h: f64,
    ctl: ArcControl,
}

impl<P: Clone, const N: usize> Arclength<P, N> {
    /// Starts at the solved point `start`, in the direction of the tangent there oriented
    /// along `dir`, with the step [`ArcControl::initial`].
    pub fn new<C: Curve<N, Point = P>>(
        curve: &C,
        start: P,
        dir: [f64; N],
        ctl: ArcControl,
    ) -> Self {
        let t = curve.tangent(&start, &dir);
        Arclength {
            u: curve.coords(&start),
            cur: start,
            t,
            h: ctl.initial,
            ctl,
        }
    }

    /// The current point.
    pub fn current(&self) -> &P {
        &self.cur
    }

    /// Its oriented unit tangent.
    pub fn tangent(&self) -> &[f64; N] {
        &self.t
    }

    /// The step length of the next attempt.
    pub fn step(&self) -> f64 {
        self.h
    }

    /// The step control.
    pub fn control(&self) -> &ArcControl {
        &self.ctl
    }

    /// One predictor-corrector step of length [`Arclength::step`] from the current point.
    /// A failed corrector, or a tangent that turns more than [`ArcControl::min_turn_cos`]
    /// allows, halves the step ([`Attempt::Retry`]); a corrector that fails with the step
    /// below [`ArcControl::min`] gives its error ([`Attempt::Failed`]). The point returned is
    /// not accepted until [`Arclength::accept`].
    pub fn attempt<C: Curve<N, Point = P>>(&mut self, curve: &C) -> Attempt<P, C::Error, N> {
        let hs = self.h / curve.step_length(&self.cur, &self.t);
        let mut p = self.u;
        for (pi, ti) in p.iter_mut().zip(&self.t) {
            *pi += hs * ti;
        }
        let point = match curve.correct(p, self.t, 0.5 * hs + 1e-9) {
            Ok(point) => point,
            Err(e) => {
                self.h *= 0.5;
                if self.h < self.ctl.min {
                    return Attempt::Failed(e);
                }
                return Attempt::Retry;
            }
        };
        let tn = curve.tangent(&point, &self.t);
        if !(dot(&self.t, &tn) > self.ctl.min_turn_cos) && self.h > self.ctl.min {
            self.h *= 0.5;
            return Attempt::Retry;
        }
        Attempt::Point(point, tn)
    }

    /// Accepts `point` (tangent `t`) as the current point, and adapts the step to the
    /// corrector's effort there.
    pub fn accept<C: Curve<N, Point = P>>(&mut self, curve: &C, point: P, t: [f64; N]) {
        let iterations = curve.iterations(&point);
        self.u = curve.coords(&point);
        self.cur = point;
        self.t = t;
        if iterations <= self.ctl.easy {
            self.h = (self.h * self.ctl.grow).min(self.ctl.max);
        } else if iterations >= self.ctl.hard {
            self.h = (self.h * self.ctl.shorten).max(self.ctl.min);
        }
    }

    /// Multiplies the step by `factor` (at least [`ArcControl::min`] when `floor` is set);
    /// returns whether the step is still at least the smallest one.
    pub fn shorten(&mut self, factor: f64, floor: bool) -> bool {
        self.h *= factor;
        if floor {
            self.h = self.h.max(self.ctl.min);
        }
        self.h >= self.ctl.min
    }

    /// Continues from `point` with tangent `t` (e.g. on another curve after an event),
    /// with a step no longer than `h_max`.
    pub fn restart<C: Curve<N, Point = P>>(
        &mut self,
        curve: &C,
        point: P,
        t: [f64; N],
        h_max: f64,
    ) {
        self.u = curve.coords(&point);
        self.cur = point;
        self.t = t;
        self.h = self.h.min(h_max);
    }

    /// The position of `point` along the current tangent, `t . (u - u_cur)`.
    pub fn along<C: Curve<N, Point = P>>(&self, curve: &C, point: &P) -> f64 {
        let u = curve.coords(point);
        self.t
            .iter()
            .zip(u.iter().zip(&self.u))
            .map(|(t, (a, b))| t * (a - b))
            .sum()
    }

    /// The earliest along the tangent of several events passed between the current point
    /// and `point`, each located by [`locate`] within `tol`: `(key, located point)`, or
    /// `None` for no events.
    ///
    /// # Errors
    /// The first error of a condition or a corrector.
    pub fn earliest<C, K, G>(
        &self,
        curve: &C,
        point: &P,
        events: &[(K, G)],
        tol: f64,
    ) -> Result<Option<(K, P)>, C::Error>
    where
        C: Curve<N, Point = P>,
        K: Copy,
        G: Fn(&P) -> Result<f64, C::Error>,
    {
        let mut best: Option<(K, P, f64)> = None;
        for (key, g) in events {
            let at = locate(curve, &self.cur, point, g, tol)?;
            let s = self.along(curve, &at);
            if best.as_ref().is_none_or(|b| s < b.2) {
                best = Some((*key, at, s));
            }
        }
        Ok(best.map(|(k, p, _)| (k, p)))
    }
}

/// Iterations of [`locate`] (each one a corrector solve).
pub const MAX_LOCATE: usize = 80;

/// Locates the zero of the event condition `g` between the points `a` (`g > 0`) and `b`
/// (`g <= 0`) of `curve` by the Illinois variant of regula falsi along the chord: each trial
/// point is corrected onto the curve on the hyperplane through it normal to the chord.
/// Returns the point on the valid side (`g > 0` or `g = 0`) within `tol` of the event along
/// the chord, after at most [`MAX_LOCATE`] trials (then the last valid-side point).
///
/// # Errors
/// The first error of `g` or of a corrector.
pub fn locate<C, G, const N: usize>(
    curve: &C,
    a: &C::Point,
    b: &C::Point,
    g: &G,
    tol: f64,
) -> Result<C::Point, C::Error>
where
    C: Curve<N>,
    G: Fn(&C::Point) -> Result<f64, C::Error> + ?Sized,
{
    let (ua, ub) = (curve.coords(a), curve.coords(b));
    let mut n = ub;
    for (ni, a) in n.iter_mut().zip(&ua) {
        *ni -= a;
    }
    let len = dot(&n, &n).sqrt();
    if len <= tol {
        return Ok(a.clone());
    }
    for v in &mut n {
        *v /= len;
    }
    let (mut sa, mut ga, mut na) = (0.0, g(a)?, a.clone());
    let (mut sb, mut gb) = (1.0, g(b)?);
    let mut side = 0;
    for _ in 0..MAX_LOCATE {
        if (sb - sa) * len <= tol {
            break;
        }
        let mut s = sb - gb * (sb - sa) / (gb - ga);
        if !(s > sa && s < sb) {
            s = 0.5 * (sa + sb);
        }
        let mut p = ua;
        for (pi, b) in p.iter_mut().zip(&ub) {
            *pi += s * (b - *pi);
        }
        let point = curve.correct(p, n, len)?;
        let gs = g(&point)?;
        if gs > 0.0 {
            (sa, ga, na) = (s, gs, point);
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        } else if gs == 0.0 {
            return Ok(point);
        } else {
            (sb, gb) = (s, gs);
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        }
    }
    Ok(na)
}

fn dot<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ellipse `(x/a)^2 + (y/b)^2 = 1` corrected by Newton on the bordered 2x2 system;
    /// counts corrector calls.
    struct Ellipse {
        a: f64,
        b: f64,
        calls: std::cell::Cell<usize>,
    }

    impl Curve<2> for Ellipse {
        type Point = [f64; 2];
        type Error = &'static str;
        fn coords(&self, p: &[f64; 2]) -> [f64; 2] {
            *p
        }
        fn correct(&self, p: [f64; 2], n: [f64; 2], radius: f64) -> Result<[f64; 2], &'static str> {
            self.calls.set(self.calls.get() + 1);
            let (a2, b2) = (self.a * self.a, self.b * self.b);
            let mut u = p;
            for _ in 0..30 {
                let r0 = u[0] * u[0] / a2 + u[1] * u[1] / b2 - 1.0;
                let r1 = n[0] * (u[0] - p[0]) + n[1] * (u[1] - p[1]);
                if r0.abs() < 1e-15 && r1.abs() < 1e-15 {
                    break;
                }
                let (j00, j01, j10, j11) = (2.0 * u[0] / a2, 2.0 * u[1] / b2, n[0], n[1]);
                let det = j00 * j11 - j01 * j10;
                if det.abs() < 1e-300 {
                    return Err("singular");
                }
                u[0] -= (j11 * r0 - j01 * r1) / det;
                u[1] -= (j00 * r1 - j10 * r0) / det;
                if (u[0] - p[0]).hypot(u[1] - p[1]) > radius {
                    return Err("left the radius");
                }
            }
            Ok(u)
        }
        fn tangent(&self, p: &[f64; 2], dir: &[f64; 2]) -> [f64; 2] {
            let g = [p[0] / (self.a * self.a), p[1] / (self.b * self.b)];
            let n = g[0].hypot(g[1]);
            let t = [-g[1] / n, g[0] / n];
            if t[0] * dir[0] + t[1] * dir[1] < 0.0 {
                [-t[0], -t[1]]
            } else {
                t
            }
        }
        fn iterations(&self, _p: &[f64; 2]) -> usize {
            3
        }
    }

    fn ellipse() -> Ellipse {
        Ellipse {
            a: 2.0,
            b: 0.5,
            calls: std::cell::Cell::new(0),
        }
    }

    /// Traces the ellipse once around from (a, 0): every accepted point lies on it, the
    /// trace passes the folds of x (at y = 0) and of y (at x = 0), and the sum of its chords
    /// agrees with the perimeter (Gauss-Kummer series) to the chords' shortfall plus the
    /// last step's overshoot.
    #[test]
    fn traces_an_ellipse_through_its_folds() {
        let curve = ellipse();
        let ctl = ArcControl {
            initial: 0.05,
            max: 0.05,
            ..ArcControl::default()
        };
        let mut arc = Arclength::new(&curve, [2.0, 0.0], [0.0, 1.0], ctl);
        let (mut length, mut x_turns, mut y_turns) = (0.0, 0, 0);
        let mut last = [2.0, 0.0];
        for _ in 0..10_000 {
            let Attempt::Point(p, t) = arc.attempt(&curve) else {
                continue;
            };
            let on = p[0] * p[0] / 4.0 + p[1] * p[1] / 0.25 - 1.0;
            assert!(on.abs() < 1e-13, "off the ellipse by {on:e}");
            x_turns += usize::from((last[0] > 0.0) != (p[0] > 0.0));
            let closed = last[1] < 0.0 && p[1] >= 0.0;
            y_turns += usize::from(closed || (last[1] > 0.0 && p[1] <= 0.0));
            length += (p[0] - last[0]).hypot(p[1] - last[1]);
            last = p;
            arc.accept(&curve, p, t);
            if closed {
                break;
            }
        }
        assert_eq!((x_turns, y_turns), (2, 2));
        // the perimeter, 4 a E(e) with e^2 = 1 - (b/a)^2, by Gauss-Kummer
        let h = ((2.0 - 0.5) / (2.0 + 0.5f64)).powi(2);
        let mut series = 1.0;
        let mut c = 1.0;
        for k in 1..30 {
            // binomial(1/2, k)^2 h^k
            c *= (0.5 - (k as f64 - 1.0)) / k as f64;
            series += c * c * h.powi(k);
        }
        let perimeter = std::f64::consts::PI * 2.5 * series;
        // the chords fall short of the arc by ~h^2 kappa^2/24 per unit length; the last
        // step overshoots the start by at most one step
        let over = length - perimeter;
        assert!(
            over > -1e-3 && over < 0.05 + 1e-3,
            "{length} vs {perimeter}"
        );
    }

    /// Events located on the curve: the crossing of y = 0 past the fold of x at (-a, 0) and
    /// the earliest of two events (x = 1 before x = 0 going left from the top).
    #[test]
    fn locates_events_exactly_and_keeps_the_earliest() {
        let curve = ellipse();
        let y = |q: &[f64; 2]| Ok::<f64, &'static str>(q[1]);
        let at = locate(
            &curve,
            &[-1.9, 0.5 * (1.0 - 0.9025f64).sqrt()],
            &[-1.9, -0.5 * (1.0 - 0.9025f64).sqrt()],
            &y,
            1e-14,
        )
        .unwrap();
        assert!((at[0] + 2.0).abs() < 1e-12 && at[1].abs() < 1e-12, "{at:?}");

        let top = [1.5, 0.5 * (1.0 - 0.5625f64).sqrt()];
        let arc = Arclength::new(&curve, top, [-1.0, 0.0], ArcControl::default());
        let left = [-1.5, top[1]];
        type G = Box<dyn Fn(&[f64; 2]) -> Result<f64, &'static str>>;
        let events: Vec<(char, G)> = vec![
            ('0', Box::new(|q: &[f64; 2]| Ok(q[0]))),
            ('1', Box::new(|q: &[f64; 2]| Ok(q[0] - 1.0))),
        ];
        let (key, p) = arc
            .earliest(&curve, &left, &events, 1e-13)
            .unwrap()
            .unwrap();
        assert_eq!(key, '1');
        assert!((p[0] - 1.0).abs() < 1e-12);
        assert!((p[0] * p[0] / 4.0 + p[1] * p[1] / 0.25 - 1.0).abs() < 1e-13);
    }

    /// The step grows after easy corrections up to the largest, is halved when the
    /// corrector fails, and a failure below the smallest step gives the corrector's error.
    #[test]
    fn the_step_adapts_and_a_failure_below_the_smallest_step_is_reported() {
        let curve = ellipse();
        let ctl = ArcControl {
            initial: 0.01,
            max: 0.04,
            min: 1e-3,
            ..ArcControl::default()
        };
        let mut arc = Arclength::new(&curve, [2.0, 0.0], [0.0, 1.0], ctl);
        let mut steps = Vec::new();
        for _ in 0..6 {
            if let Attempt::Point(p, t) = arc.attempt(&curve) {
                arc.accept(&curve, p, t);
                steps.push(arc.step());
            }
        }
        assert!((steps[0] - 0.016).abs() < 1e-15, "{steps:?}");
        assert_eq!(*steps.last().unwrap(), 0.04);
        // a corrector that always fails: halvings until below min, then its error
        struct Never;
        impl Curve<2> for Never {
            type Point = [f64; 2];
            type Error = &'static str;
            fn coords(&self, p: &[f64; 2]) -> [f64; 2] {
                *p
            }
            fn correct(
                &self,
                _p: [f64; 2],
                _n: [f64; 2],
                _r: f64,
            ) -> Result<[f64; 2], &'static str> {
                Err("never")
            }
            fn tangent(&self, _p: &[f64; 2], _d: &[f64; 2]) -> [f64; 2] {
                [1.0, 0.0]
            }
            fn iterations(&self, _p: &[f64; 2]) -> usize {
                1
            }
        }
        let mut arc = Arclength::new(&Never, [0.0, 0.0], [1.0, 0.0], ctl);
        let mut retries = 0;
        let err = loop {
            match arc.attempt(&Never) {
                Attempt::Retry => retries += 1,
                Attempt::Failed(e) => break e,
                Attempt::Point(..) => unreachable!(),
            }
        };
        // 0.01 -> 0.005 -> 0.0025 -> 0.00125 -> 0.000625 < 1e-3
        assert_eq!((retries, err), (3, "never"));
        assert!(curve.calls.get() > 0);
    }
}
