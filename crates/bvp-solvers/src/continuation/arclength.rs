//! Pseudo-arclength continuation of a solution curve, with located events.

// `!(x > c)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
//!
//! A [`Curve`] is the set of solutions of `R(u) = 0` with `R: R^N -> R^(N-1)`: generically a
//! one-dimensional curve, which may turn back in any coordinate (a fold). [`Arclength`]
//! follows it point by point (Keller's method):
//!
//! ```text
//! predictor:  p = H(u_{k-1}, t_{k-1}; u_k, t_k)(h / |t_k|_w)   (t_k the unit tangent at u_k)
//! corrector:  R(u) = 0,  t_k . (u - p) = 0          (the hyperplane through p normal to t_k)
//! ```
//!
//! where `H` is the cubic Hermite interpolant through the last two points and their
//! tangents, extrapolated a distance `h / |t_k|_w` beyond `u_k` (error `O(h^4)`; at the first
//! point of a curve the tangent step `p = u_k + h t_k / |t_k|_w`, error `O(h^2)`).
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
//! use bvp_solvers::continuation::{locate, ArcControl, Arclength, Attempt, Curve};
//!
//! /// The unit circle `x^2 + y^2 = 1`, corrected by Newton on the 2x2 system.
//! struct Circle;
//! impl Curve<2> for Circle {
//!     type Point = [f64; 2];
//!     type Error = ();
//!     fn coords(&self, p: &[f64; 2]) -> [f64; 2] { *p }
//!     fn correct(&self, _from: &[f64; 2], p: [f64; 2], n: [f64; 2], _r: f64) -> Result<[f64; 2], ()> {
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
    /// prediction was off the curve. `from` is the solved point the prediction was made
    /// from (the current point of a step; in [`locate`] the bracket's end on the valid
    /// side), for a curve whose points carry more than their coordinates (the natural path
    /// predicts its state from it).
    ///
    /// # Errors
    /// The corrector's own when it does not converge.
    fn correct(
        &self,
        from: &Self::Point,
        p: [f64; N],
        n: [f64; N],
        radius: f64,
    ) -> Result<Self::Point, Self::Error>;

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
    /// How the next point is predicted.
    pub predictor: Predictor,
}

/// The predictor of [`Arclength`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Predictor {
    /// Along the tangent, `p = u_k + h t_k`: error `O(h^2)`.
    Tangent,
    /// The cubic Hermite interpolant through the last two points and their tangents,
    /// extrapolated: error `O(h^4)`; the tangent at the first point of a curve.
    Hermite,
}

impl Default for ArcControl {
    /// Steps in `[1e-9, 0.1]` from 0.01, x1.6 after at most 3 iterations, x0.6 after 6 or
    /// more, turns up to ~25 degrees a step, the Hermite predictor.
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
            predictor: Predictor::Hermite,
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
    /// The point accepted before the current one on the same curve, with its tangent (the
    /// predictor's second node).
    prev: Option<([f64; N], [f64; N])>,
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
            prev: None,
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

    /// Shortens the step of the next attempt to at most `h_max` (the natural path clips
    /// its last step to end on the target).
    pub fn limit_step(&mut self, h_max: f64) {
        self.h = self.h.min(h_max);
    }

    /// The current point, ending the trace.
    pub fn into_current(self) -> P {
        self.cur
    }

    /// One predictor-corrector step of length [`Arclength::step`] from the current point.
    /// A failed corrector, or a tangent that turns more than [`ArcControl::min_turn_cos`]
    /// allows, halves the step ([`Attempt::Retry`]); a corrector that fails with the step
    /// below [`ArcControl::min`] gives its error ([`Attempt::Failed`]). The point returned is
    /// not accepted until [`Arclength::accept`].
    pub fn attempt<C: Curve<N, Point = P>>(&mut self, curve: &C) -> Attempt<P, C::Error, N> {
        let hs = self.h / curve.step_length(&self.cur, &self.t);
        let p = self.predict(hs);
        let point = match curve.correct(&self.cur, p, self.t, 0.5 * hs + 1e-9) {
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

    /// The predicted point `hs` along the curve from the current one: the cubic Hermite
    /// interpolant through the previous and the current point with their unit tangents
    /// (parametrised by arc length, estimated from the chord and the tangents' turn as on a
    /// circle), extrapolated to `hs` beyond the current
    /// point: its error is `O(hs^4)` for `hs` up to a few chords, against `O(hs^2)` of the
    /// tangent alone, which is the predictor at the first point of a curve, with
    /// [`Predictor::Tangent`], and where the previous point is not usable (a chord of zero
    /// length, a step over four chords long, or tangents turned by more than
    /// [`ArcControl::min_turn_cos`] allows).
    fn predict(&self, hs: f64) -> [f64; N] {
        let mut p = self.u;
        let prev = self
            .prev
            .filter(|_| self.ctl.predictor == Predictor::Hermite);
        let hermite = prev.and_then(|(u0, t0)| {
            let d = u0
                .iter()
                .zip(&self.u)
                .map(|(a, b)| (b - a) * (b - a))
                .sum::<f64>()
                .sqrt();
            (d > 0.0 && hs <= 4.0 * d && dot(&t0, &self.t) > self.ctl.min_turn_cos)
                .then_some((u0, t0, d))
        });
        let Some((u0, t0, chord)) = hermite else {
            for (pi, ti) in p.iter_mut().zip(&self.t) {
                *pi += hs * ti;
            }
            return p;
        };
        // the arc length between the two points from the chord and the turn of the tangent
        // (exact on a circle): the unit tangents are derivatives in arc length
        let half = 0.5 * dot(&t0, &self.t).clamp(-1.0, 1.0).acos();
        let d = if half > 1e-8 {
            chord * half / half.sin()
        } else {
            chord
        };
        // on [u0 (s = 0), u (s = 1)], evaluated at s = 1 + hs/d
        let [h00, h10, h01, h11] = crate::interp::hermite_basis(1.0 + hs / d);
        for i in 0..N {
            p[i] = h00 * u0[i] + h10 * d * t0[i] + h01 * self.u[i] + h11 * d * self.t[i];
        }
        p
    }

    /// Accepts `point` (tangent `t`) as the current point, and adapts the step to the
    /// corrector's effort there.
    pub fn accept<C: Curve<N, Point = P>>(&mut self, curve: &C, point: P, t: [f64; N]) {
        let iterations = curve.iterations(&point);
        self.prev = Some((self.u, self.t));
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
        self.prev = None;
        self.limit_step(h_max);
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
        let point = curve.correct(&na, p, n, len)?;
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
mod tests;
