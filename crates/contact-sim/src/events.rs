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
use beam_model::path::{shape_path, PathPoint, ShapePath};
use beam_model::{FluidLoad, Scene, Whisker};

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

/// How deep the whisker of `state` enters the obstacle away from its contact point (positive
/// inside): the maximum over the elastica of the depth below the contour (for a circle also
/// inside its vertical sides), sampled at `s = i/200` ([`samples`]) on the dense elastica of
/// one DOP853 integration at [`SHAPE_TOL`] ([`shape_path`]; the loads are not validated: a
/// trial may exceed their bounds), the maximum refined by the parabola through its
/// neighbours. Only the contact point itself is excluded (`|s - s1| < 2e-3`), so a free
/// segment that curls into the obstacle next to a tangential contact counts.
///
/// The grid is sampled only where the depth may come within [`COLD`] of the contour: on
/// each interval between the integrator's step points the depth is bounded by its end
/// values and a Lipschitz bound ([`depth_bound`]); where every interval stays colder, that
/// bound (below `-COLD`) is returned instead of the sampled maximum.
pub(crate) fn penetration(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    state: &ContactState,
) -> Result<f64> {
    let scene = Scene::new(*whisker, state.loads(flow));
    let path = shape_path(&scene, state.phi1, SHAPE_TOL)?;
    let depth = |p: PathPoint| -> f64 {
        let x = state.x0 + p.x;
        let g = profile.y(x);
        if !g.is_finite() {
            return f64::NEG_INFINITY;
        }
        let mut d = p.y - g;
        if let Profile::Circle { xc, r, .. } = *profile {
            d = d.min(r - (x - xc).abs());
        }
        d
    };
    let knots = path.knots();
    let (mut hot, mut cold_max) = (Vec::new(), f64::NEG_INFINITY);
    for w in knots.windows(2) {
        let bound = depth_bound(&path, profile, state.x0, (w[0], w[1]), &depth);
        if bound >= -COLD {
            hot.push((w[0], w[1]));
        } else {
            cold_max = cold_max.max(bound);
        }
    }
    let ss = samples(path.s1());
    let in_hot = |s: f64| hot.iter().any(|&(a, b)| s >= a && s <= b);
    // the samples in order: each step found from the last one's
    let mut hint = 0;
    let depths: Vec<f64> = (0..ss.len())
        .map(|i| {
            let near = (i.saturating_sub(1)..=(i + 1).min(ss.len() - 1)).any(|j| in_hot(ss[j]));
            if !near || (ss[i] - state.s1).abs() < 2e-3 {
                return f64::NEG_INFINITY;
            }
            path.at_near(ss[i], &mut hint)
                .map_or(f64::NEG_INFINITY, &depth)
        })
        .collect();
    let sampled = refined_max(&depths);
    Ok(if sampled >= -COLD {
        sampled
    } else {
        sampled.max(cold_max)
    })
}

/// Depth below which an interval of the elastica is not sampled ([`penetration`]).
const COLD: f64 = 1e-3;

/// The sample points of [`penetration`]: `s = i/200` and the loaded length `s1`.
fn samples(s1: f64) -> Vec<f64> {
    let grid = (0..=200).map(|i| i as f64 / 200.0);
    let mut ss: Vec<f64> = grid.clone().filter(|&s| s <= s1).collect();
    if ss.last().is_none_or(|&l| l < s1) {
        ss.push(s1);
    }
    ss.extend(grid.filter(|&s| s > s1));
    ss
}

/// An upper bound of the depth on the interval `[a, b]` of `path` (base at `x0`): the mean of
/// the end depths plus `L (b - a)/2`, with `L = sqrt(1 + G^2)` bounding `|d depth/ds|`
/// (`|sin phi - g' cos phi| <= sqrt(1 + g'^2)`; a circle's sides change at rate `<= 1`) and
/// `G` the largest `|g'|` where the interval can reach, `|x - x(a)| <= b - a` (at the ends
/// of that range for a convex closed form). Infinite (no bound) for a tabulated contour,
/// beyond a circle's sides or where an end depth is not finite.
fn depth_bound(
    path: &ShapePath,
    profile: &Profile,
    x0: f64,
    (a, b): (f64, f64),
    depth: &dyn Fn(PathPoint) -> f64,
) -> f64 {
    let (Some(pa), Some(pb)) = (path.at(a), path.at(b)) else {
        return f64::INFINITY;
    };
    let (da, db) = (depth(pa), depth(pb));
    let h = b - a;
    let (lo, hi) = (x0 + pa.x - h, x0 + pa.x + h);
    let (dlo, dhi) = profile.domain();
    if matches!(profile, Profile::Points(_)) || !(lo > dlo && hi < dhi) {
        return f64::INFINITY;
    }
    let g = profile.eval(lo).1.abs().max(profile.eval(hi).1.abs());
    let bound = 0.5 * (da + db) + 0.5 * h * (1.0 + g * g).sqrt();
    if bound.is_finite() {
        bound
    } else {
        f64::INFINITY
    }
}

/// The largest of `depths`, refined to the vertex of the parabola through it and its two
/// neighbours where both are finite and the three bend down.
fn refined_max(depths: &[f64]) -> f64 {
    let Some((i, &dmax)) = depths.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else {
        return f64::NEG_INFINITY;
    };
    if i == 0 || i + 1 >= depths.len() || !depths[i - 1].is_finite() || !depths[i + 1].is_finite() {
        return dmax;
    }
    let (a, b, c) = (depths[i - 1], dmax, depths[i + 1]);
    let curv = a - 2.0 * b + c;
    if curv < 0.0 {
        b - (c - a) * (c - a) / (8.0 * curv)
    } else {
        dmax
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
    use std::f64::consts::FRAC_PI_2;

    /// A straight whisker (no pre-curvature, no load) standing at `x0` under a circle: its
    /// depth in the obstacle is that of its highest sample off the contact point,
    /// `s = 0.995`, below the arc, `0.995 - g(x0)`, or inside the circle's side,
    /// `r - |x0 - xc|`, whichever is less; none once the circle is above it.
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
        };
        let s = TestScene::straight(Profile::Circle {
            xc: 0.05,
            yc: 1.2,
            r: 0.5,
        });
        let depth = |s: &TestScene, x0| penetration(&s.whisker, s.flow, &s.profile, &state(x0));
        for x0 in [0.0, 0.2, -0.3] {
            let g = 1.2 - (0.25 - (x0 - 0.05f64).powi(2)).sqrt();
            let truth = (0.995 - g).min(0.5 - (x0 - 0.05f64).abs());
            let depth = depth(&s, x0).unwrap();
            assert!((depth - truth).abs() < 1e-12, "{x0}: {depth} vs {truth}");
        }
        let above = TestScene::straight(Profile::Circle {
            xc: 0.05,
            yc: 2.0,
            r: 0.5,
        });
        assert!(depth(&above, 0.0).unwrap() < 0.0);
    }
}
