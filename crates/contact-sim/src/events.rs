//! Events along the contact branch and their location: the phase switches A -> B
//! (`phi1 = psi`) and B -> A (`s1 = 1`), release (`f = 0`), snap (a turning point of the base
//! position, `dx0/dsigma = 0`) and a second contact (another part of the whisker reaching the
//! contour).
//!
//! An event is bracketed by two nodes of the branch, one on each side, and located by the
//! Illinois variant of regula falsi along the chord between them: every trial point is a
//! solution of the branch equations on a hyperplane across the chord, so the located node is
//! an exact equilibrium, within `tol` of the event in the state `(v, f, t)`.

use crate::branch::{dot, norm, sub, Branch, Constraint, Node};
use crate::error::Result;
use crate::phase::{ContactState, Phase};
use crate::profile::Profile;
use beam_model::shot::Integration;
use beam_model::{shape_with, FluidLoad, Scene, Whisker};

/// Integration tolerance of the shape checked for penetration (its depths are then accurate
/// to ~1e-10, well inside the margin a second contact must exceed).
const SHAPE_TOL: f64 = 1e-10;

/// Iterations of the Illinois method (each one a corrector solve).
const MAX_ILLINOIS: usize = 80;

/// The validity of the phase of `node`: `phi1 - psi` in phase A (tip contact needs the tip
/// steeper than the contour), `1 - s1` in phase B.
pub(crate) fn phase_margin(node: &Node) -> f64 {
    match node.phase {
        Phase::B => 1.0 - node.state.s1,
        _ => node.state.phi1 - node.state.point.psi,
    }
}

/// How deep the whisker of `state` enters the obstacle away from its contact point (positive
/// inside): the maximum over the elastica (one DOP853 shot at tolerance [`SHAPE_TOL`], its
/// dense output sampled at 200 intervals; no validation of the loads: a
/// trial may exceed their bounds, the maximum refined by the parabola through its
/// neighbours) of the depth below the contour, for a circle also inside
/// its vertical sides. Only the contact point itself is excluded (`|s - s1| < 2e-3`), so a
/// free segment that curls into the obstacle next to a tangential contact counts.
pub(crate) fn penetration(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    state: &ContactState,
) -> Result<f64> {
    let scene = Scene::new(*whisker, state.loads(flow));
    let sol = shape_with(&scene, state.phi1, &Integration::adaptive(SHAPE_TOL), 200)?;
    let el = &sol.elastica;
    let depth_at = |i: usize| -> f64 {
        if (el.s[i] - state.s1).abs() < 2e-3 {
            return f64::NEG_INFINITY;
        }
        let x = state.x0 + el.x[i];
        let g = profile.y(x);
        if !g.is_finite() {
            return f64::NEG_INFINITY;
        }
        let mut d = el.y[i] - g;
        if let Profile::Circle { xc, r, .. } = *profile {
            d = d.min(r - (x - xc).abs());
        }
        d
    };
    let depths: Vec<f64> = (0..el.len()).map(depth_at).collect();
    let Some((i, &dmax)) = depths.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else {
        return Ok(f64::NEG_INFINITY);
    };
    if i == 0 || i + 1 >= depths.len() || !depths[i - 1].is_finite() || !depths[i + 1].is_finite() {
        return Ok(dmax);
    }
    // the vertex of the parabola through the three samples around the largest depth
    let (a, b, c) = (depths[i - 1], dmax, depths[i + 1]);
    let curv = a - 2.0 * b + c;
    if curv < 0.0 {
        Ok(b - (c - a) * (c - a) / (8.0 * curv))
    } else {
        Ok(dmax)
    }
}

/// Locates the zero of the event function `g` between `a` (`g > 0`) and `b` (`g <= 0`), both
/// in the same phase. Returns the node on the valid side (`g > 0` or `g = 0`) within `tol` of
/// the event, or `a` itself if a trial point cannot be solved (the bracket is then reported
/// by the caller as it is).
pub(crate) fn locate(
    branch: &Branch,
    a: &Node,
    b: &Node,
    g: &dyn Fn(&Node) -> Result<f64>,
    tol: f64,
) -> Result<Node> {
    let d = sub(&b.u, &a.u);
    let len = norm(&d);
    if len <= tol {
        return Ok(*a);
    }
    let n = [d[0] / len, d[1] / len, d[2] / len];
    let (mut sa, mut ga, mut na) = (0.0, g(a)?, *a);
    let (mut sb, mut gb) = (1.0, g(b)?);
    let mut side = 0;
    for _ in 0..MAX_ILLINOIS {
        if (sb - sa) * len <= tol {
            break;
        }
        let mut s = sb - gb * (sb - sa) / (gb - ga);
        if !(s > sa && s < sb) {
            s = 0.5 * (sa + sb);
        }
        let p = crate::branch::lerp(&a.u, &b.u, s);
        let node = branch.correct(a.phase, p, Constraint::Hyperplane { n, p, radius: len })?;
        let gs = g(&node)?;
        if gs > 0.0 {
            (sa, ga, na) = (s, gs, node);
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        } else if gs == 0.0 {
            return Ok(node);
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

/// `dx0/dsigma` at `node` along the branch tangent oriented like `dir`.
pub(crate) fn x0_rate(node: &Node, dir: &[f64; 3]) -> f64 {
    node.x0_rate(&node.tangent(dir))
}

/// Whether two unit tangents are close enough for a step between them to be trusted.
pub(crate) fn smooth_turn(t0: &[f64; 3], t1: &[f64; 3]) -> bool {
    dot(t0, t1) > 0.9
}
