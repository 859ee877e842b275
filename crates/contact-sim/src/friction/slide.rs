//! A frictional sweep that slides throughout, run on the frictionless machinery (issue 39's
//! cost).
//!
//! In slip `ft = s mu fn`, so the force is `F = fn (n + s mu t)`: the frictionless force
//! turned by `atan(s mu)` and stretched by `sqrt(1 + mu^2)` ([`Tilt`]). A sliding leg is
//! therefore the frictionless contact branch ([`crate::branch::Branch`] with that tilt), and
//! a sweep whose contact starts sliding (the first touch's mode, [`super::start`]) and never
//! stops is the frictionless sweep under the tilted force: its trace
//! (`continuation::trace_tightened`: phase switches, snap, release, second contact with the
//! depth checks ahead, end of contour), its rows (`rows::rows`, Broyden rows, the accuracy's
//! estimates and their tighter pass), only with the slip law added:
//!
//! - **the sliding never stops**: at every traced node after the touch the touching
//!   material point slides against `ft`, `-s u > 0` with `u` its velocity along `t` per
//!   unit of the path (phase A: `dt`, the contour parameter rising along `t`; phase B:
//!   `|c'(t)| dt - ds1`, rolling subtracted), along the branch's tangent oriented with the
//!   motion ([`slides_throughout`]). Where it fails (a slip -> stick switch or a sliding
//!   reversal on the path, or a phase switch after which sliding the same way breaks the
//!   law), the sweep falls back to the frictional sweep with its stick legs and switches
//!   ([`super::frictional_rows`]) from the start;
//! - the rows' `ft = s mu fn`, `slip = slip` and the slip distance (the contour's arc length
//!   summed from row to row, less the change of `s1`, [`slip_distances`]).

use super::contour::arc_length;
use crate::branch::Node;
use crate::contact_law::Tilt;
use crate::error::{ContactError, Result};
use crate::first_contact::FirstTouch;
use crate::phase::Phase;
use crate::profile::Profile;
use crate::sweep::{contact_sweep, SweepPoint, SweepProgress, SweepResult, SweepSettings};
use beam_model::{FluidLoad, Whisker};

/// The frictional sweep of a contact that starts sliding with `ft = s mu fn` (`s` from the
/// first touch's probes) on the frictionless machinery under the tilted force, if it slides
/// throughout ([`slides_throughout`]); `None` where it does not (or where that sweep fails
/// otherwise): the caller then runs the frictional sweep with its stick legs.
pub(super) fn sliding_sweep(
    (whisker, flow, profile): (&Whisker, FluidLoad, &Profile),
    settings: &SweepSettings,
    (phi1, touch): (f64, &FirstTouch),
    (s, mu): (f64, f64),
    progress: &mut dyn FnMut(SweepProgress),
) -> Option<SweepResult> {
    let tilt = Tilt { s_mu: s * mu };
    let check = |nodes: &[Node]| slides_throughout(profile, nodes, s, mu);
    let scene = (whisker, flow, profile);
    let mut r = contact_sweep(scene, settings, (phi1, *touch), (tilt, &check), progress).ok()?;
    slip_distances(profile, &mut r.points);
    Some(r)
}

/// The velocity `u` along `t` of the touching material point per unit of the branch's
/// tangent `tn` (in `(v, f, t)`) at `n`: `dt` in phase A (the tip; the contour parameter
/// rises along `t`, spec/model.md), `|c'(t)| dt - ds1` in phase B (the contact point's arc
/// length less the whisker's, rolling).
pub(super) fn sliding_rate(profile: &Profile, n: &Node, tn: &[f64; 3]) -> f64 {
    match n.phase {
        Phase::B => {
            let g = profile.at(n.u[2]);
            g.dx.hypot(g.dy) * tn[2] - tn[0]
        }
        _ => tn[2],
    }
}

/// Whether every traced node after the first touch slides against `ft = s mu fn`:
/// `-s u > 0` along the branch's tangent oriented with the motion (towards the next node of
/// the same phase, or from the one before). A node where it fails is a slip -> stick switch
/// (or a reversal) the frictionless machinery does not follow: the error names it.
pub(super) fn slides_throughout(profile: &Profile, nodes: &[Node], s: f64, mu: f64) -> Result<()> {
    for (i, n) in nodes.iter().enumerate().skip(1) {
        let along = |a: &Node, b: &Node| {
            (a.phase == b.phase && a.u != b.u).then(|| crate::branch::sub(&b.u, &a.u))
        };
        let dir = nodes
            .get(i + 1)
            .and_then(|b| along(n, b))
            .or_else(|| along(&nodes[i - 1], n));
        let Some(dir) = dir else { continue };
        let u = sliding_rate(profile, n, &n.tangent(&dir));
        // a NaN rate fails too
        if (-s * u).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(ContactError::FrictionIndeterminate {
                x0: n.x0(),
                xc: n.state.point.xc,
                mu,
                reason: format!(
                    "the sliding with ft = {s} mu fn stops in phase {} (rate {u:.3e})",
                    n.phase
                ),
            });
        }
    }
    Ok(())
}

/// Each contact row's slip displacement since the first contact row (contour parameter
/// `t0`, contact arc length `s10`): `sigma(t) - sigma(t0) - (s1 - s10)`, the contour's arc
/// length summed from row to row ([`arc_length`]; the contour parameter of a row is `xc` on
/// a graph, `psi` on a circle, [`Profile::at`]).
pub(super) fn slip_distances(profile: &Profile, points: &mut [SweepPoint]) {
    let param = |p: &SweepPoint| match profile {
        Profile::Circle { .. } | Profile::Disc { .. } => p.psi,
        _ => p.xc,
    };
    let mut origin: Option<(f64, f64, f64)> = None;
    for p in points.iter_mut().filter(|p| p.phase != Phase::None) {
        let t = param(p);
        let (t_prev, sigma, s10) = origin.unwrap_or((t, 0.0, p.s1));
        let sigma = sigma + arc_length(profile, t_prev, t);
        p.slip_distance = sigma - (p.s1 - s10);
        origin = Some((t, sigma, s10));
    }
}
