//! The frictional sweep's rows: their base positions, solves, estimates and slip displacement.

use super::branch::{dot4, norm4, sub4, Con, FrictionBranch, Mode, Node};
use super::contour::arc_length;
use super::settings::FrictionSettings;
use super::trace::{Sweeper, Trace};
use crate::accuracy::ESTIMATE_MARGIN;
use crate::contact_law::frictional_observables;
use crate::error::Result;
use crate::phase::Phase;
use crate::sweep::{Separation, SweepPoint};
use beam_model::shot::Integration;
use beam_model::FluidLoad;

/// The rows: `points` evenly spaced in x0 from the first touch to the end, and one at every
/// stick/slip or phase switch (the new leg's node); each solved on `tight` (the sweep's
/// tolerances; the trace's nodes are looser) in its stretch's mode from the bracketing nodes
/// (cubic Hermite prediction in x0 from the nodes' tangents, the chord method from the
/// node's Jacobian at the row's base position, Newton where it fails). A switch's row is
/// solved on its event itself: a stick/slip switch in the new mode with the old mode's
/// equation as the fourth (the force on the cone's edge and the material point where it
/// stuck, both exactly), a phase switch on `phi1 = psi` in tip-contact form.
pub(super) fn rows(
    sw: &Sweeper,
    tight: &FrictionBranch,
    tr: &Trace,
    set: &FrictionSettings,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<(SweepPoint, f64)>> {
    let row_branch = set.rows_at.map(|(it, st, _)| FrictionBranch {
        integration: Integration::adaptive(it),
        tol: st,
        ..tight.clone_shallow()
    });
    let loose = set.rows_at.map(|(_, _, lt)| FrictionBranch {
        integration: Integration::adaptive(lt),
        ..tight.clone_shallow()
    });
    let rb = row_branch.as_ref().unwrap_or(tight);
    let nodes = &exact_stops(rb, &tr.nodes)?;
    // the material point's reference: the first node's contact point and arc length
    let origin = (nodes[0].w[3], nodes[0].s1());
    let mut sigma = (origin.0, 0.0);
    let last = nodes.len() - 1;
    let (xa, xb) = (nodes[0].x0, nodes[last].x0);
    // targets: (x0, the node index of a switch or of the ends)
    let n = set.points;
    let mut targets: Vec<(f64, Option<(usize, Con)>)> = (0..n)
        .map(|k| match k {
            0 => (xa, Some((0, Con::Base(xa)))),
            _ if k + 1 == n => (
                xb,
                Some((last, end_hold(&nodes[last], &tr.end, sw.exact_ends()))),
            ),
            _ => (xa + (xb - xa) * k as f64 / (n - 1) as f64, None),
        })
        .collect();
    for i in 1..last {
        if nodes[i].phase != nodes[i + 1].phase {
            // a phase switch's row in tip-contact form (`s1 = 1`, `phi1 = psi`), as the
            // frictionless sweep writes it
            let j = if nodes[i].phase == Phase::A { i } else { i + 1 };
            targets.push((nodes[j].x0, Some((j, Con::PhaseEnd))));
        } else if nodes[i].mode != nodes[i + 1].mode {
            // the new leg's node: where the force leaves the cone on the old leg too (the
            // material point where it stuck and the force on the cone's edge); where the
            // sliding stops, the two legs are tangent and the stop exact already
            // ([`exact_stops`])
            let con = match nodes[i].mode {
                Mode::Stick { .. } => Con::Mode(nodes[i].mode),
                Mode::Slip { .. } => Con::Base(nodes[i + 1].x0),
            };
            targets.push((nodes[i + 1].x0, Some((i + 1, con))));
        }
    }
    targets.sort_by(|a, b| b.0.total_cmp(&a.0));
    targets.dedup_by(|b, a| {
        if a.0 == b.0 {
            a.1 = a.1.or(b.1);
            true
        } else {
            false
        }
    });
    let total = targets.len();
    let mut out: Vec<(SweepPoint, f64)> = Vec::with_capacity(total);
    let mut seg = 0;
    for (x, at) in targets {
        let (node, hold) = match at {
            Some((i, con)) => {
                let n = &nodes[i];
                let node = rb.correct_near(n.phase, n.mode, n.w, con, Some(&n.jac), false)?;
                // an estimate's solve holds the row where it is (its own base position but
                // at the path's end)
                let hold = if i == last { con } else { Con::Base(node.x0) };
                (node, hold)
            }
            None => {
                while seg + 1 < last
                    && (nodes[seg + 1].x0 > x || !nodes[seg].same_leg(&nodes[seg + 1]))
                {
                    seg += 1;
                }
                let (a, b) = (&nodes[seg], &nodes[seg + 1]);
                let p = predict(sw, a, b, x);
                // the chord method from the bracketing node's Jacobian first (shots without
                // sensitivities), Newton where it does not converge; with an accuracy asked
                // for, Newton alone, as the estimate's second solve
                let node = match set.rows_at {
                    None => {
                        rb.correct_near(a.phase, a.mode, p, Con::Base(x), Some(&a.jac), false)?
                    }
                    Some(_) => rb.correct(a.phase, a.mode, p, Con::Base(x))?,
                };
                (node, Con::Base(x))
            }
        };
        let est = match &loose {
            Some(l) => estimate(l, &node, hold)?,
            None => f64::NAN,
        };
        // the contour's arc length from the first node's contact point, summed from row to
        // row (one quadrature piece each rather than the whole way from the start)
        let t = node.w[3];
        sigma = (t, sigma.1 + arc_length(sw.b.profile, sigma.0, t));
        out.push((row_of(sw.b.flow, (sigma.1, origin.1), &node), est));
        progress(out.len(), total);
    }
    Ok(out)
}

/// The trace's nodes with every slip -> stick switch solved on `rb` (the rows' tolerances):
/// the old leg's node on the sliding leg at its base position, the anchor of the new stick
/// leg its contact point (and arc length) there, the new leg's first node that node. The two
/// legs are tangent at the stop (the sliding speed vanishes), so the stick node cannot be put
/// on the cone's edge by a solve of its own (a singular system); the anchor moves by the
/// trace's tolerance.
fn exact_stops(rb: &FrictionBranch, nodes: &[Node]) -> Result<Vec<Node>> {
    let mut out = nodes.to_vec();
    for i in 1..out.len().saturating_sub(1) {
        let (a, b) = (out[i], out[i + 1]);
        if a.phase != b.phase
            || !matches!((a.mode, b.mode), (Mode::Slip { .. }, Mode::Stick { .. }))
        {
            continue;
        }
        let on = rb.correct_near(a.phase, a.mode, a.w, Con::Base(a.x0), Some(&a.jac), true)?;
        let stick = Mode::Stick {
            anchor: on.w[3],
            s1: on.s1(),
        };
        out[i] = on;
        for n in out[i + 1..].iter_mut() {
            if n.phase != b.phase || n.mode != b.mode {
                break;
            }
            n.mode = stick;
        }
        out[i + 1] = Node { mode: stick, ..on };
    }
    Ok(out)
}

/// The state at base position `x` between the nodes `a` and `b` of one leg: their cubic
/// Hermite interpolant in x0 from the curve's tangents (`dw/dx0 = tangent / (dx0 . tangent)`),
/// linear where x0 is nearly stationary at either node (a fold: the slopes blow up).
pub(super) fn predict(sw: &Sweeper, a: &Node, b: &Node, x: f64) -> [f64; 4] {
    let chord = sub4(&b.w, &a.w);
    let h = b.x0 - a.x0;
    let th = (x - a.x0) / h;
    let slope = |n: &Node| {
        let t = sw.b.tangent(n, &chord);
        let rate = dot4(&n.jac[2], &t);
        // x0's rate against the chord's: a fold nearby where it is far below it
        (rate.signum() == h.signum() && rate.abs() * norm4(&chord) > 0.2 * h.abs())
            .then(|| t.map(|v| v / rate))
    };
    match (slope(a), slope(b)) {
        (Some(da), Some(db)) => {
            let [h00, h10, h01, h11] = bvp_solvers::interp::hermite_basis(th);
            std::array::from_fn(|i| h00 * a.w[i] + h10 * h * da[i] + h01 * b.w[i] + h11 * h * db[i])
        }
        _ => std::array::from_fn(|i| a.w[i] + th * chord[i]),
    }
}

/// How the row at the end of the path is held when it is solved again: the release at
/// `fn = 0`, an end on its phase's end (the tip passing a peg, a snap at a phase switch)
/// there where `exact` ([`Sweeper::exact_ends`]), any other end at its contour point (in stick, whose contour point the mode
/// holds, at its normal force).
pub(super) fn end_hold(n: &Node, end: &Separation, exact: bool) -> Con {
    let on_end = match n.phase {
        Phase::B => (n.w[0] - 1.0).abs(),
        _ => (n.w[0] - n.geom.psi).abs(),
    };
    if matches!(end, Separation::PathEnd) {
        // a path segment's end: on its row of the path
        return Con::Base(n.x0);
    }
    if exact && on_end < 1e-8 {
        // the tip passing a peg, a snap at a phase switch: on the phase's end itself
        return Con::PhaseEnd;
    }
    let release = matches!(end, Separation::Release);
    let axis = match n.mode {
        Mode::Slip { .. } if !release => [0.0, 0.0, 0.0, 1.0],
        _ => [0.0, 1.0, 0.0, 0.0],
    };
    Con::Plane { n: axis, p: n.w }
}

/// A row's error estimate: the row solved again with the looser integration of `loose`
/// (Newton from the row, at its base position; at its contour point where the row ends the
/// path), twice the largest change of its observables and contact point.
pub(super) fn estimate(loose: &FrictionBranch, n: &Node, hold: Con) -> Result<f64> {
    let m = loose.correct(n.phase, n.mode, n.w, hold)?;
    let obs = |n: &Node| {
        let (ax, ay, ma) =
            frictional_observables(loose.flow, n.geom.psi, n.w[1], n.w[2], n.s1(), n.m0);
        [n.x0, ax, ay, ma, n.phi0, n.geom.x, n.geom.y]
    };
    let (a, b) = (obs(n), obs(&m));
    Ok(ESTIMATE_MARGIN
        * a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max))
}

/// A log row of a node: the observables of `F = fn n + ft t`, the slip state and the
/// touching material point's slip displacement since the first contact node (contour
/// parameter `t0`, contact arc length `s10`), `sigma(t) - s1 - (sigma(t0) - s10)`, from
/// `sigma = sigma(t) - sigma(t0)` (`sigma` the contour's arc length, `s1 = 1` in tip contact:
/// there the tip's displacement along the contour).
pub(super) fn row_of(flow: FluidLoad, (sigma, s10): (f64, f64), n: &Node) -> SweepPoint {
    let [_, f, ft, _] = n.w;
    let s1 = n.s1();
    let (ax, ay, ma) = frictional_observables(flow, n.geom.psi, f, ft, s1, n.m0);
    SweepPoint {
        x0: n.x0,
        ax,
        ay,
        ma,
        phi0: n.phi0,
        f,
        s1,
        phi1: n.phi1(),
        phase: n.phase,
        xc: n.geom.x,
        yc: n.geom.y,
        psi: n.geom.psi,
        ft,
        slip: n.mode.slip_state(),
        slip_distance: sigma - (s1 - s10),
        y0: 0.0,
        gamma: 0.0,
        k: None,
    }
}
