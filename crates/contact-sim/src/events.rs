//! Events along the contact branch and their location: the phase switches A -> B
//! (`phi1 = psi`) and B -> A (`s1 = 1`), release (`f = 0`), snap (a turning point of the base
//! position, `dx0/dsigma = 0`) and a second contact (another part of the whisker reaching the
//! contour).
//!
//! An event is bracketed by two nodes of the branch, one on each side, and located by
//! [`bvp_solvers::continuation::locate`] (regula falsi along the chord, every trial point a
//! solution of the branch equations on a hyperplane across it), so the located node is an
//! exact equilibrium, within `tol` of the event in the state `(v, f, t)`.

use crate::branch::Node;
use crate::error::Result;
use crate::phase::{ContactState, Phase};
use crate::profile::Profile;
use beam_model::path::{shape_path, ShapePiece};
use beam_model::{FluidLoad, Scene, Whisker};
use bvp_solvers::integrator::StepInterpolant;

/// Integration tolerance of the shape checked for penetration (its depths are then accurate
/// to ~1e-10, well inside the margin a second contact must exceed).
const SHAPE_TOL: f64 = 1e-10;

/// The validity of the phase of `node`: `phi1 - psi` in phase A (tip contact needs the tip
/// steeper than the contour), `1 - s1` in phase B.
pub(crate) fn phase_margin(node: &Node) -> f64 {
    match node.phase {
        Phase::B => 1.0 - node.state.s1,
        _ => node.state.phi1 - node.state.point.psi,
    }
}

/// How far the whisker next to its contact point is from touching the contour a second time
/// right there (positive: clear; zero: the event), the conditions the depth of
/// [`penetration`] only sees quadratically after the fact (a bump growing out of the contact
/// point itself):
/// - phase A: `cos((phi1 - psi) / 2)`, zero where the rate `d'(1) = sin(phi1 - psi) / cos psi`
///   at which the depth rises towards the tip vanishes at the far end of the phase's range
///   `0 < phi1 - psi < pi` (the near end, `phi1 = psi`, is the switch to phase B): the tip
///   curled back until it runs along the contour the other way has the segment next to it
///   touching;
/// - phase B: `kappa_c - kappa0(s1)`, the contour's curvature `g'' / (1 + g'^2)^(3/2)` at
///   the contact point less the whisker's there (`m(s1) = 0`: its pre-curvature
///   `A s1 + B`), `-d''(s1) cos psi`: a whisker bending more sharply than the contour
///   lies on it on both sides of `s1`.
pub(crate) fn near_margin(whisker: &Whisker, profile: &Profile, node: &Node) -> f64 {
    let st = &node.state;
    match node.phase {
        Phase::B => profile.curvature_at(node.u[2]) - whisker.kappa0(st.s1),
        _ => (0.5 * (st.phi1 - st.point.psi)).cos(),
    }
}

/// How deep the whisker of `state` enters the obstacle away from its contact point (positive
/// inside, negative: the least clearance there), bounded on the dense elastica of one DOP853
/// integration at [`SHAPE_TOL`] ([`shape_path`]; the loads are not validated: a trial may
/// exceed their bounds), not sampled.
///
/// The depth `d(s) = y(s) - g(x(s))` (for a circle also `min`-ed with the depth inside its
/// vertical sides, `r - |x - xc|`) is zero at the contact point `s1`. Walking outward from
/// `s1` on the integrator's own steps (their 7th-order interpolants, [`beam_model::path::ShapePath::pieces`]),
/// the *contact basin* is the stretch on which `d` provably rises towards `s1` (interval
/// arithmetic on the step's polynomial: the enclosure of `d'` keeps its sign; the last
/// [`NEAR`] next to a tangential contact, where `d' -> 0`, also where `d` stays within
/// [`NOISE`] of its value at `s1`): there the whisker lies below the contact point's own
/// level. The depth is the maximum of `d` over the rest of the whisker, found by branch and
/// bound ([`region_max`]) to [`EPS`], with a rigorous upper bound on every sub-step from the
/// enclosure of `d'` ([`Depth::upper`]); where nothing lies beyond the basin, the depth at
/// its far end (the base, or the free tip). A second contact anywhere, the segment next to
/// the tip or next to a tangential contact curling in, is a sign change of this quantity,
/// which is continuous along the branch where it crosses zero (the maximum of a bump).
/// The contact point's own depth counts where it exceeds [`CONTACT_SLACK`] (a state that is
/// not on the contour).
pub(crate) fn penetration(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    state: &ContactState,
) -> Result<f64> {
    penetration_under(whisker, &state.loads(flow), profile, state)
}

/// [`penetration`] of the whisker under `loads` (a frictional contact's,
/// [`crate::friction::frictional_loads`]) at `state`'s contact point and tip angle.
pub(crate) fn penetration_under(
    whisker: &Whisker,
    loads: &beam_model::Loads,
    profile: &Profile,
    state: &ContactState,
) -> Result<f64> {
    if profile.is_peg() {
        // a point is touched at one point of the whisker at a time: another part reaching
        // it would have to pass through the contact point itself (the whisker looping back
        // onto the peg), which no shape here does; nothing enters a point
        return Ok(f64::NEG_INFINITY);
    }
    let scene = Scene::new(*whisker, *loads);
    let path = shape_path(&scene, state.phi1, SHAPE_TOL)?;
    let pieces = path.pieces();
    // the shape placed with its loaded end on the state's contour point: the shape's own
    // integration puts it within its error (~1e-9 times the conditioning of a slender tip)
    // of where the state's shots put it, and only the shape relative to that point counts
    let end = pieces.first().map_or((0.0, 0.0), |p| {
        let mut u = [0.0; 2];
        p.poly.eval(0.0, &mut u);
        (p.offset.0 + u[0], p.offset.1 + u[1])
    });
    let (x0, dy) = if state.point.xc.is_finite() && state.point.yc.is_finite() {
        (state.point.xc - end.0, state.point.yc - end.1)
    } else {
        (state.x0, 0.0)
    };
    let depth = Depth { profile, x0, dy };
    Ok(deepest(&depth, &pieces))
}

/// The depth of [`penetration`] over `pieces` (ordered outward from the contact point:
/// the loaded part's, then the free segment's).
fn deepest(depth: &Depth, pieces: &[ShapePiece]) -> f64 {
    let split = pieces.iter().position(|p| p.free).unwrap_or(pieces.len());
    let (loaded, free) = pieces.split_at(split);
    let Some(first) = loaded.first() else {
        return f64::NEG_INFINITY;
    };
    let contact = depth.at(first, 0.0).min();
    let mut deepest = if contact > CONTACT_SLACK {
        contact
    } else {
        f64::NEG_INFINITY
    };
    for side in [loaded, free] {
        if side.is_empty() {
            continue;
        }
        let (k, theta) = basin_end(depth, side, contact);
        let value = if k >= side.len() {
            // the whole side rises towards the contact point: its far end
            depth.at(&side[side.len() - 1], 1.0).min()
        } else {
            let mut items = vec![(k, theta, 1.0)];
            items.extend((k + 1..side.len()).map(|j| (j, 0.0, 1.0)));
            region_max(depth, side, &items)
        };
        deepest = deepest.max(value);
    }
    deepest
}

/// Depth below which a part of the elastica is not resolved further ([`region_max`]): its
/// upper bound is reported instead.
const COLD: f64 = 1e-3;

/// The resolution of the deepest point ([`region_max`]): every part of the whisker outside
/// the contact basin is bounded within this of the value returned.
const EPS: f64 = 1e-13;

/// The stretch next to a contact point (in arc length) where `d` may stay within [`NOISE`]
/// of its value at the contact point instead of rising towards it provably (a tangential
/// contact, `d'(s1) = 0` to the solve's accuracy).
const NEAR: f64 = 1e-4;

/// The rise above the contact point's depth tolerated within [`NEAR`] of it ([`NEAR`]).
const NOISE: f64 = 1e-12;

/// The contact point's own depth above which it counts ([`penetration`]): a state off the
/// contour (the solves put it within ~1e-9).
const CONTACT_SLACK: f64 = 1e-8;

/// Levels of bisection of one integrator step at most ([`basin_end`], [`region_max`]).
const MAX_LEVEL: u32 = 48;

/// Sub-steps [`region_max`] evaluates at most before it reports its bounds as they stand.
const BUDGET: usize = 20_000;

/// Where the contact basin ends on `side` (pieces outward from the contact point, whose
/// depth is `contact`): the piece and `theta` of the first point not shown to lie in it;
/// `(side.len(), 1.0)` if it covers the side.
fn basin_end(depth: &Depth, side: &[ShapePiece], contact: f64) -> (usize, f64) {
    let mut from_contact = 0.0;
    // sub-steps at most before the basin is cut where the search stands (conservative: the
    // rest goes to `region_max`); met where the bound stays within NOISE of the contact's
    // depth along a whole piece (a frictional whisk past a disc, docs/friction-whisk.md):
    // the depth-first bisection would otherwise visit up to 2^MAX_LEVEL sub-steps
    let mut budget = 10 * BUDGET;
    for (k, p) in side.iter().enumerate() {
        let h = p.poly.h().abs();
        // nearest sub-interval first: a stack popped from its end
        let mut stack = vec![(0.0, 1.0, 0u32)];
        while let Some((a, b, level)) = stack.pop() {
            let near = from_contact + b * h <= NEAR;
            if depth.falls_outward(p, (a, b))
                || (near && {
                    let (da, db) = (depth.at(p, a), depth.at(p, b));
                    depth.upper(p, (a, b), (da, db)) <= contact + NOISE
                })
            {
                continue;
            }
            budget = budget.saturating_sub(1);
            if level >= MAX_LEVEL || budget == 0 {
                return (k, a);
            }
            let m = 0.5 * (a + b);
            stack.push((m, b, level + 1));
            stack.push((a, m, level + 1));
        }
        from_contact += h;
    }
    (side.len(), 1.0)
}

/// The largest depth over `items` (`(piece, theta_a, theta_b)` of `side`): branch and bound,
/// each sub-step bounded by [`Depth::upper`] and bisected until its bound lies within
/// [`EPS`] of the deepest point evaluated, or below `-COLD`. Conservative: a bound left over
/// (below `-COLD`, or at the level and budget limits) is returned where it exceeds the
/// deepest point evaluated.
fn region_max(depth: &Depth, side: &[ShapePiece], items: &[(usize, f64, f64)]) -> f64 {
    let mut best = f64::NEG_INFINITY;
    let mut left_over = f64::NEG_INFINITY;
    let mut work = Vec::with_capacity(4 * items.len());
    for &(k, a, b) in items {
        let (da, db) = (depth.at(&side[k], a), depth.at(&side[k], b));
        best = best.max(da.min()).max(db.min());
        work.push((k, a, b, da, db, 0u32));
    }
    let mut evaluations = 0;
    while let Some((k, a, b, da, db, level)) = work.pop() {
        let p = &side[k];
        let ub = depth.upper(p, (a, b), (da, db));
        if ub <= best + EPS {
            continue;
        }
        if ub < -COLD || level >= MAX_LEVEL || evaluations >= BUDGET {
            left_over = left_over.max(ub);
            continue;
        }
        let m = 0.5 * (a + b);
        let dm = depth.at(p, m);
        evaluations += 1;
        best = best.max(dm.min());
        work.push((k, a, m, da, dm, level + 1));
        work.push((k, m, b, dm, db, level + 1));
    }
    best.max(left_over)
}

/// The depth of the obstacle's boundary at a point: the depth below the contour graph and,
/// for a circle, inside its vertical sides (`+inf` otherwise); the point lies inside where
/// both are positive.
#[derive(Clone, Copy, Debug)]
struct PointDepth {
    graph: f64,
    side: f64,
}

impl PointDepth {
    /// The depth itself, `min(graph, side)`.
    fn min(self) -> f64 {
        self.graph.min(self.side)
    }
}

/// A closed interval `[lo, hi]`.
#[derive(Clone, Copy, Debug)]
struct Iv {
    lo: f64,
    hi: f64,
}

impl Iv {
    fn point(v: f64) -> Iv {
        Iv { lo: v, hi: v }
    }
    fn plus(self, o: Iv) -> Iv {
        Iv {
            lo: self.lo + o.lo,
            hi: self.hi + o.hi,
        }
    }
    fn minus(self, o: Iv) -> Iv {
        Iv {
            lo: self.lo - o.hi,
            hi: self.hi - o.lo,
        }
    }
    fn times(self, o: Iv) -> Iv {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        Iv {
            lo: p.iter().copied().fold(f64::INFINITY, f64::min),
            hi: p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }
    fn negated(self) -> Iv {
        Iv {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

/// Enclosures of component `i` of the step interpolant `p` and of its `theta`-derivative
/// over `theta` in `[a, b]`: the nested form of [`StepInterpolant::eval_jet`] evaluated in
/// interval arithmetic (`theta` and `1 - theta` as intervals), a rigorous enclosure up to
/// rounding.
fn enclose(p: &StepInterpolant<2>, i: usize, (a, b): (f64, f64)) -> Option<(Iv, Iv)> {
    let rc = p.coefficients()?;
    let th = Iv { lo: a, hi: b };
    let t1 = Iv {
        lo: 1.0 - b,
        hi: 1.0 - a,
    };
    let (mut w, mut d1) = (Iv::point(rc[7][i]), Iv::point(0.0));
    for j in (0..7).rev() {
        let (t, dt) = if j % 2 == 0 { (th, 1.0) } else { (t1, -1.0) };
        let dw = if dt > 0.0 { w } else { w.negated() };
        d1 = dw.plus(t.times(d1));
        w = Iv::point(rc[j][i]).plus(t.times(w));
    }
    Some((w, d1))
}

/// The depth of a whisker with its base at `(x0, dy)` in `profile`, on the pieces of a
/// [`beam_model::path::ShapePath`].
struct Depth<'a> {
    profile: &'a Profile,
    /// Where the shape's positions are measured from: the base `(x0, dy)`.
    x0: f64,
    dy: f64,
}

impl Depth<'_> {
    /// The depth at `theta` of the piece `p` (`-inf` where the contour is not defined).
    fn at(&self, p: &ShapePiece, theta: f64) -> PointDepth {
        let mut u = [0.0; 2];
        if !p.poly.eval(theta, &mut u) {
            return PointDepth {
                graph: f64::NAN,
                side: f64::NAN,
            };
        }
        let (x, y) = (self.x0 + p.offset.0 + u[0], self.dy + p.offset.1 + u[1]);
        if let Profile::Disc { x: cx, y: cy, r } = *self.profile {
            // inside the full circle: r - |p - c|
            return PointDepth {
                graph: r - (x - cx).hypot(y - cy),
                side: f64::INFINITY,
            };
        }
        let g = self.profile.y(x);
        if !g.is_finite() {
            return PointDepth {
                graph: f64::NEG_INFINITY,
                side: f64::NEG_INFINITY,
            };
        }
        let side = match *self.profile {
            Profile::Circle { xc, r, .. } => r - (x - xc).abs(),
            _ => f64::INFINITY,
        };
        PointDepth { graph: y - g, side }
    }

    /// Enclosures of `x` (absolute) and of `dx/dtheta`, `dy/dtheta` over `[a, b]` of `p`.
    fn enclosures(&self, p: &ShapePiece, ab: (f64, f64)) -> Option<(Iv, Iv, Iv)> {
        let (x, dx) = enclose(&p.poly, 0, ab)?;
        let (_, dy) = enclose(&p.poly, 1, ab)?;
        let off = self.x0 + p.offset.0;
        Some((
            Iv {
                lo: x.lo + off,
                hi: x.hi + off,
            },
            dx,
            dy,
        ))
    }

    /// An enclosure of `y` (absolute) over `[a, b]` of `p`.
    fn y_enclosure(&self, p: &ShapePiece, ab: (f64, f64)) -> Option<Iv> {
        let (y, _) = enclose(&p.poly, 1, ab)?;
        let off = self.dy + p.offset.1;
        Some(Iv {
            lo: y.lo + off,
            hi: y.hi + off,
        })
    }

    /// An enclosure of `g'` over the x range `x` (`g'` rises on a convex contour: its values
    /// at the ends); `None` where it is not finite (outside a circle's span).
    fn slope(&self, x: Iv) -> Option<Iv> {
        let (a, b) = (self.profile.eval(x.lo).1, self.profile.eval(x.hi).1);
        (a.is_finite() && b.is_finite()).then(|| Iv {
            lo: a.min(b),
            hi: a.max(b),
        })
    }

    /// An upper bound of the depth over `[a, b]` of `p` (end depths `da`, `db`): for the
    /// graph's depth the lines from both ends with the extreme slopes of the enclosure of
    /// `d' = y' - g'(x) x'`, meeting at their crossing; for a circle's sides
    /// `r - min |x - xc|` over the enclosure of `x`. `+inf` where no enclosure exists.
    fn upper(&self, p: &ShapePiece, (a, b): (f64, f64), (da, db): (PointDepth, PointDepth)) -> f64 {
        let Some((x, dx, dy)) = self.enclosures(p, (a, b)) else {
            return f64::INFINITY;
        };
        if let Profile::Disc { x: cx, y: cy, r } = *self.profile {
            // r less the least distance from the centre to the box of the enclosures
            let Some(y) = self.y_enclosure(p, (a, b)) else {
                return f64::INFINITY;
            };
            let gap = |lo: f64, hi: f64, c: f64| (lo - c).max(c - hi).max(0.0);
            return r - gap(x.lo, x.hi, cx).hypot(gap(y.lo, y.hi, cy));
        }
        let (dlo, dhi) = self.profile.domain();
        if x.hi < dlo || x.lo > dhi {
            return f64::NEG_INFINITY;
        }
        let side = match *self.profile {
            Profile::Circle { xc, r, .. } => {
                let dist = if x.lo <= xc && xc <= x.hi {
                    0.0
                } else {
                    (x.lo - xc).abs().min((x.hi - xc).abs())
                };
                r - dist
            }
            _ => f64::INFINITY,
        };
        let graph = match self.slope(x) {
            Some(g1) if da.graph.is_finite() && db.graph.is_finite() => {
                let d = dy.minus(g1.times(dx));
                let w = b - a;
                if d.hi <= 0.0 {
                    da.graph
                } else if d.lo >= 0.0 {
                    db.graph
                } else {
                    let tau = ((db.graph - da.graph - d.lo * w) / (d.hi - d.lo)).clamp(0.0, w);
                    da.graph + d.hi * tau
                }
            }
            _ => f64::INFINITY,
        };
        let ub = graph.min(side);
        if ub.is_nan() {
            f64::INFINITY
        } else {
            ub
        }
    }

    /// Whether the depth provably falls (does not rise) over `[a, b]` of `p` as `theta`
    /// grows: the enclosure of `d'` of the graph's depth (and of a circle's side depth) at
    /// most zero.
    fn falls_outward(&self, p: &ShapePiece, ab: (f64, f64)) -> bool {
        let Some((x, dx, dy)) = self.enclosures(p, ab) else {
            return false;
        };
        if let Profile::Disc { x: cx, y: cy, .. } = *self.profile {
            // d' = -(p - c) . p' / |p - c|: falls where (p - c) . p' >= 0 throughout
            let Some(y) = self.y_enclosure(p, ab) else {
                return false;
            };
            let shift = |v: Iv, c: f64| Iv {
                lo: v.lo - c,
                hi: v.hi - c,
            };
            let radial = shift(x, cx).times(dx).plus(shift(y, cy).times(dy));
            return radial.lo >= 0.0;
        }
        let Some(g1) = self.slope(x) else {
            return false;
        };
        if dy.minus(g1.times(dx)).hi > 0.0 {
            return false;
        }
        match *self.profile {
            Profile::Circle { xc, r, .. } => {
                // d/dtheta (r - |x - xc|) = -sign(x - xc) x'; or the side's depth stays
                // above the graph's (at most its value at `a`, where it falls), the
                // minimum the graph's
                let side_lo = r - (x.lo - xc).abs().max((x.hi - xc).abs());
                let above = side_lo >= self.at(p, ab.0).graph;
                above
                    || if x.lo > xc {
                        dx.lo >= 0.0
                    } else if x.hi < xc {
                        dx.hi <= 0.0
                    } else {
                        false
                    }
            }
            _ => true,
        }
    }
}

/// `dx0/dsigma` at `node` along the branch tangent oriented like `dir`.
pub(crate) fn x0_rate(node: &Node, dir: &[f64; 3]) -> f64 {
    node.x0_rate(&node.tangent(dir))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::branch::tests::TestScene;
    use crate::phase::ContourPoint;
    use beam_model::{FluidLoad, Whisker};
    use std::f64::consts::FRAC_PI_2;

    /// A straight whisker (no pre-curvature, no load) standing at `x0` under a circle, its
    /// "contact" state off the contour: its depth in the obstacle is that of its top (the
    /// contact point itself counts, being off the contour), below the arc, `1 - g(x0)`, or
    /// inside the circle's side, `r - |x0 - xc|`, whichever is less; once the circle is
    /// above it, the whole whisker rises towards its tip, and the depth is the base's.
    #[test]
    fn a_straight_whisker_enters_a_circle_as_far_as_its_top() {
        let state = |x0: f64| ContactState {
            phase: Phase::A,
            point: ContourPoint {
                xc: x0,
                yc: 1.0,
                psi: 0.5,
            },
            f: 0.0,
            s1: 1.0,
            phi1: FRAC_PI_2,
            x0,
            phi0: FRAC_PI_2,
            m0: 0.0,
            iterations: 0,
            residual: 0.0,
            tilt: crate::contact_law::Tilt::NONE,
        };
        let s = TestScene::straight(Profile::Circle {
            xc: 0.05,
            yc: 1.2,
            r: 0.5,
        });
        let depth = |s: &TestScene, x0| penetration(&s.whisker, s.flow, &s.profile, &state(x0));
        for x0 in [0.0, 0.2, -0.3] {
            let g = 1.2 - (0.25 - (x0 - 0.05f64).powi(2)).sqrt();
            let truth = (1.0 - g).min(0.5 - (x0 - 0.05f64).abs());
            let depth = depth(&s, x0).unwrap();
            assert!((depth - truth).abs() < 1e-12, "{x0}: {depth} vs {truth}");
        }
        let above = TestScene::straight(Profile::Circle {
            xc: 0.05,
            yc: 2.0,
            r: 0.5,
        });
        let base = -(2.0 - (0.25f64 - 0.0025).sqrt());
        let d = depth(&above, 0.0).unwrap();
        assert!((d - base).abs() < 1e-12, "{d} vs {base}");
    }

    /// A uniform whisker bent into a circular arc (`B = kappa`, no load: `x = x0 + (cos
    /// kappa s - 1) / kappa`, `y = sin(kappa s) / kappa`) whose curled tip touches
    /// parabolas through it at several slopes: the depth beyond the contact point's basin is
    /// the closed form's, found by dense sampling (100,000 points) refined by golden section,
    /// to 1e-10 — whether the segment next to the tip dips in (positive) or stays out
    /// (negative), and for a tangential "contact" at s1 = 0.7 with a free segment beyond.
    #[test]
    fn the_depth_beyond_the_basin_is_the_closed_forms() {
        let kappa = 2.0;
        let w = Whisker::new(1.0, 0.0, kappa, f64::INFINITY);
        let flow = FluidLoad { q: 0.0, alpha: 0.0 };
        let x0 = 0.1;
        let pos = |s: f64| {
            (
                x0 + ((kappa * s).cos() - 1.0) / kappa,
                (kappa * s).sin() / kappa,
            )
        };
        let mut seen = [0, 0];
        for s1 in [1.0, 0.7] {
            let (xt, yt) = pos(s1);
            for slope in [-0.9, -0.3, 0.0, 0.2, 0.6, 1.5] {
                for a in [0.5, 2.0, 6.0] {
                    let profile = Profile::Parabola {
                        a,
                        xv: xt - slope / (2.0 * a),
                        yv: yt - slope * slope / (4.0 * a),
                    };
                    let d = |s: f64| {
                        let (x, y) = pos(s);
                        y - profile.y(x)
                    };
                    // the closed form: out from s1 while d falls, then the deepest point
                    let n = 100_000;
                    let dv: Vec<f64> = (0..=n).map(|i| d(i as f64 / n as f64)).collect();
                    let k1 = (s1 * n as f64).round() as usize;
                    let mut lo = k1;
                    while lo > 0 && dv[lo - 1] <= dv[lo] {
                        lo -= 1;
                    }
                    let mut hi = k1;
                    while hi < n && dv[hi + 1] <= dv[hi] {
                        hi += 1;
                    }
                    let mut region: Vec<usize> = (0..=lo).collect();
                    if k1 < n {
                        region.extend(hi..=n);
                    }
                    let mut best = f64::NEG_INFINITY;
                    for &i in &region {
                        best = best.max(dv[i]);
                        let peak = (i == 0 || dv[i - 1] <= dv[i]) && (i == n || dv[i + 1] <= dv[i]);
                        if !peak || i == 0 || i == n {
                            continue;
                        }
                        // golden section on the two neighbouring intervals
                        let (mut a0, mut b0) =
                            ((i - 1) as f64 / n as f64, (i + 1) as f64 / n as f64);
                        let r = 0.5 * (5f64.sqrt() - 1.0);
                        for _ in 0..60 {
                            let (c, e) = (b0 - r * (b0 - a0), a0 + r * (b0 - a0));
                            if d(c) > d(e) {
                                b0 = e;
                            } else {
                                a0 = c;
                            }
                        }
                        best = best.max(d(0.5 * (a0 + b0)));
                    }
                    let state = ContactState {
                        phase: if s1 < 1.0 { Phase::B } else { Phase::A },
                        point: ContourPoint {
                            xc: xt,
                            yc: yt,
                            psi: slope.atan(),
                        },
                        f: 0.0,
                        s1,
                        phi1: FRAC_PI_2 + kappa * s1,
                        x0,
                        phi0: FRAC_PI_2,
                        m0: 0.0,
                        iterations: 0,
                        residual: 0.0,
                        tilt: crate::contact_law::Tilt::NONE,
                    };
                    let got = penetration(&w, flow, &profile, &state).unwrap();
                    assert!(
                        (got - best).abs() < 1e-10 || (best < -COLD && got < -COLD),
                        "s1 {s1} slope {slope} a {a}: {got:e} vs {best:e}"
                    );
                    seen[(best > 0.0) as usize] += 1;
                }
            }
        }
        // both kinds occur: a segment dipping in, and a whisker clear of the contour
        assert!(seen[0] >= 5 && seen[1] >= 5, "{seen:?}");
    }
}
