//! The frictional sweep's rows: their base positions, solves, estimates and slip displacement.

use super::branch::{Con, FrictionBranch, Mode, Node};
use super::contour::arc_length;
use super::settings::FrictionSettings;
use super::trace::{Sweeper, Trace};
use crate::accuracy::ESTIMATE_MARGIN;
use crate::contact_law::frictional_observables;
use crate::error::Result;
use crate::phase::Phase;
use crate::profile::Profile;
use crate::sweep::{Separation, SweepPoint};
use beam_model::shot::Integration;
use beam_model::FluidLoad;

/// The rows: `points` evenly spaced in x0 from the first touch to the end, and one at every
/// stick/slip or phase switch (the new leg's node); each solved in its stretch's mode from the bracketing
/// nodes (linear prediction in x0, the chord method from the node's Jacobian at the row's
/// base position, Newton where it fails).
pub(super) fn rows(
    sw: &Sweeper,
    tr: &Trace,
    set: &FrictionSettings,
) -> Result<Vec<(SweepPoint, f64)>> {
    let nodes = &tr.nodes;
    // the material point's reference: the first node's contact point and arc length
    let origin = (nodes[0].w[3], nodes[0].s1());
    let last = nodes.len() - 1;
    let (xa, xb) = (nodes[0].x0, nodes[last].x0);
    let row_branch = set.rows_at.map(|(it, st, _)| FrictionBranch {
        integration: Integration::adaptive(it),
        tol: st,
        ..sw.b.clone_shallow()
    });
    let loose = set.rows_at.map(|(_, _, lt)| FrictionBranch {
        integration: Integration::adaptive(lt),
        ..sw.b.clone_shallow()
    });
    let rb = row_branch.as_ref().unwrap_or(&sw.b);
    // targets: (x0, the node index of a switch or of the ends)
    let n = set.points;
    let mut targets: Vec<(f64, Option<usize>)> = (0..n)
        .map(|k| match k {
            0 => (xa, Some(0)),
            _ if k + 1 == n => (xb, Some(last)),
            _ => (xa + (xb - xa) * k as f64 / (n - 1) as f64, None),
        })
        .collect();
    for i in 1..last {
        if !nodes[i].same_leg(&nodes[i + 1]) {
            // the new leg's node; a phase switch's row in tip-contact form (`s1 = 1`,
            // `phi1 = psi`), as the frictionless sweep writes it
            let j = if nodes[i].phase != nodes[i + 1].phase && nodes[i].phase == Phase::A {
                i
            } else {
                i + 1
            };
            targets.push((nodes[j].x0, Some(j)));
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
    let mut out: Vec<(SweepPoint, f64)> = Vec::with_capacity(targets.len());
    let mut seg = 0;
    for (x, at) in targets {
        let (node, hold) = match at {
            Some(i) if i == last => {
                let n = &nodes[i];
                (
                    rb.correct(n.phase, n.mode, n.w, end_hold(n, &tr.end))?,
                    end_hold(n, &tr.end),
                )
            }
            Some(i) => (
                rb.correct(nodes[i].phase, nodes[i].mode, nodes[i].w, Con::Base(x))?,
                Con::Base(x),
            ),
            None => {
                while seg + 1 < last
                    && (nodes[seg + 1].x0 > x || !nodes[seg].same_leg(&nodes[seg + 1]))
                {
                    seg += 1;
                }
                let (a, b) = (&nodes[seg], &nodes[seg + 1]);
                let wth = (x - a.x0) / (b.x0 - a.x0);
                let p = [
                    a.w[0] + wth * (b.w[0] - a.w[0]),
                    a.w[1] + wth * (b.w[1] - a.w[1]),
                    a.w[2] + wth * (b.w[2] - a.w[2]),
                    a.w[3] + wth * (b.w[3] - a.w[3]),
                ];
                // the chord method from the bracketing node's Jacobian first (shots without
                // sensitivities), Newton where it does not converge; with an accuracy asked
                // for, Newton alone, as the estimate's second solve
                let chord = match set.rows_at {
                    None => rb.correct_chord(a.phase, a.mode, p, x, &a.jac),
                    Some(_) => None,
                };
                let node = match chord {
                    Some(n) => n,
                    None => rb.correct(a.phase, a.mode, p, Con::Base(x))?,
                };
                (node, Con::Base(x))
            }
        };
        let est = match &loose {
            Some(l) => estimate(l, &node, hold)?,
            None => f64::NAN,
        };
        out.push((row_of(sw.b.flow, sw.b.profile, origin, &node), est));
    }
    Ok(out)
}

/// How the row at the end of the path is held when it is solved again: the release at
/// `fn = 0`, any other end at its contour point (in stick, whose contour point the mode
/// holds, at its normal force).
pub(super) fn end_hold(n: &Node, end: &Separation) -> Con {
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
/// touching material point's slip displacement since the first contact node `(t0, s10)`,
/// `sigma(t) - s1 - (sigma(t0) - s10)` (`sigma` the contour's arc length, `s1 = 1` in tip
/// contact: there the tip's displacement along the contour).
pub(super) fn row_of(
    flow: FluidLoad,
    profile: &Profile,
    (t0, s10): (f64, f64),
    n: &Node,
) -> SweepPoint {
    let [_, f, ft, t] = n.w;
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
        slip_distance: arc_length(profile, t0, t) - (s1 - s10),
        y0: 0.0,
        gamma: 0.0,
        k: None,
    }
}
