//! Coulomb friction at the contact (spec/model.md, "Friction at the contact"; beyond the
//! thesis, whose ch. 7 names frictional contact as the model's next step).
//!
//! **The contact law is a value of its own**, [`ContactLaw`], part of the sweep's settings
//! (`SweepSettings::contact_law`): [`ContactLaw::Frictionless`] (the default) and
//! [`ContactLaw::Coulomb`] with `mu = 0` run the frictionless sweep unchanged (same code path,
//! the same rows bit for bit; callgrind on the bench scene +0.65 %, docs/friction.md);
//! `mu > 0` runs the frictional sweep of this module. The base motion stays the sweep's:
//! the branch's two base conditions and its falling coordinate come from the motion's
//! `Frame` as in the frictionless branch (`branch::reframe`: a translation holds
//! `R0 = 0` and reads `x0`, a rotation about `(x0, y0)` holds the base position and reads
//! `-gamma`), so the stick/slip legs, the events and the rows are one code for every motion
//! and obstacle: graphs, pegs (`peg:x,y`, tangential contact only; the tip sliding past
//! releases it, and a stuck peg holds `s1`: the contour is a point, `sigma` constant) and
//! discs (`disc:x,y,r`, contour parameter the polar angle, `sigma = r t`). The law is frame
//! free: the material point's sliding velocity is the contact point's motion along the fixed
//! contour less `ds1`, in the lab frame whatever the base does (docs/friction-whisk.md).
//! Along a path of poses each segment's trace runs in the segment's frame and ends on its
//! next row, where the next segment's goes on from the same state and mode (`path`).
//!
//! **A contact that slides throughout** (its first touch a tip touch whose mode is slip, and
//! the sliding never stopping along the traced path) runs on the frictionless machinery
//! under the tilted force `F = fn (n + s mu t)` ([`Tilt`](crate::contact_law::Tilt),
//! `slide`): the same trace, rows, depth checks and estimates, 1.07x the frictionless
//! sweep's instructions on the bench scene (the frictional legs below: 2.55x). Every other
//! contact (stick at the touch, a slip -> stick switch or a reversal on the path, a
//! tangential first touch) runs on the frictional legs below, from the start.
//!
//! **The model.** Boundary tangent `t = (cos psi, sin psi)`, outward normal
//! `n = (sin psi, -cos psi)`; the force on the whisker `F = fn n + ft t`, `fn >= 0`. It is
//! applied as a direction-preserving tip force of size `|F|` at angle `beta` with
//! `F = |F| (cos beta, -sin beta)`; with `ft = 0` this is the frictionless
//! `beta = pi/2 - psi` [5.4-5.10]. Quasi-static Coulomb law with `u` the velocity along `t` of
//! the whisker's touching material point relative to the obstacle as the base moves:
//! - stick (`u = 0`): `|ft| <= mu fn`;
//! - slip (`u != 0`): `ft = -mu fn sign(u)`.
//!
//! **Both phases** (`branch`). The state is `w = (v, fn, ft, t)`:
//! `v = phi1` in phase A (tip contact, `s1 = 1`), `v = s1` in phase B (tangential contact,
//! `phi(s1) = psi(t)` built into the shot), the force components and the contour parameter
//! of the contact point ([`Profile::at`]). Two equations hold in every phase and mode, the
//! base condition `R0 = phi(0) - pi/2 - m(0)/k = 0` [3.21, 3.22] and the contact point on the
//! contour `R1 = y(s1) - y(0) - yc(t) = 0` (`m(s1) = 0`: the segment beyond `s1` is unloaded);
//! the mode adds a third:
//! - stick, phase A: `t = t*` (the tip is the material point, pinned where it stuck);
//! - stick, phase B: rolling without sliding, `sigma(t) - s1 = sigma(t*) - s1*`. The touching
//!   material point of an inextensible whisker on a fixed obstacle moves along `t` at
//!   `d sigma - d s1` (`sigma` the contour's arc length oriented with the whisker: at a
//!   tangential contact the whisker's tangent is the contour's `t`), so `u = 0` is rolling;
//!   "s1 and the contact point stay put" would be two conditions where one is free
//!   (docs/friction.md, with the battery's check of it);
//! - slip: `ft = s mu fn` with `s = -sign(u)`, `u` of the sign of `dt` along the path in
//!   phase A (the contour parameter rises with x, the direction of `t`), of
//!   `d sigma - d s1` in phase B.
//!
//! so each leg (phase and mode) is a curve in `w`, followed by pseudo-arclength continuation
//! in the direction of falling base position `x0 = xc(t) - (x(s1) - x(0))`, its Jacobian from
//! the shot's exact sensitivities (`d/dFx`, `d/dFy` from `d/df`, `d/dbeta`; at `F = 0` from
//! two shots along the axes; `d/ds1` in phase B, where `t` also turns `phi1 = psi(t)`).
//!
//! **Events**, each located on the curve by regula falsi along the chord (every trial an exact
//! equilibrium on a hyperplane across it) to `event_tol` in `w`:
//! - stick -> slip where `mu fn - |ft|` falls to zero (either edge of the cone: a sliding
//!   reversal is a slip -> stick -> slip sequence through the cone's interior);
//! - slip -> stick where the sliding velocity vanishes (`-s dt/dpath`, `-s (dsigma -
//!   ds1)/dpath` in phase B, falls to zero);
//! - the phase switches A -> B (`phi1 = psi`) and B -> A (`s1 = 1`) as in the frictionless
//!   sweep: the other phase's curve entered on its valid side in the same mode (a stick
//!   re-anchored at the switch, where tip and touching point coincide), a snap where x0
//!   rises along it;
//! - release (`fn = 0`), snap (x0 at a turning point), a second contact (the depth of
//!   `events`), the whisker next to the contact touching, the contact at the base
//!   (`s1 = 0.01`), the end of the contour — as in the frictionless sweep.
//!
//! At each switch the new mode is checked to be consistent (stick: the force moves into the
//! cone; slip: the sliding is against `ft`); where neither mode is, the quasi-static problem
//! has no continuation and the sweep says so ([`FrictionIndeterminate`](crate::ContactError::FrictionIndeterminate)) rather
//! than return a row that breaks the law. At the first touch (`F = 0`, tip or tangential) the
//! mode is the first of stick, slip `s = +1`, slip `s = -1` whose curve keeps the law a short
//! way on.
//!
//! **Rows** at evenly spaced base positions from the first touch to the separation, one more
//! at each stick/slip or phase switch, each solved in the leg of its stretch of the path (the
//! anchor is the sweep's state) from the bracketing nodes; each row carries `ft`, the
//! [`SlipState`] and the material point's slip displacement since the first touch,
//! `sigma - s1` less its value at the touch (in phase A the tip's arc length along the
//! contour; constant while stuck).

mod branch;
mod contour;
mod events;
mod kinds;
mod path;
mod rows;
mod settings;
mod slide;
mod start;
mod trace;

use crate::accuracy::row_integration_tol;
pub use crate::contact_law::{ContactLaw, FrictionEvent, FrictionEventKind, SlipState, MAX_MU};
use crate::error::Result;
use crate::first_contact::{FirstContact, FirstTouch};
use crate::motion::Frame;
use crate::profile::Profile;
use crate::sweep::{
    check_accuracy, pre_contact_rows, Separation, SweepPoint, SweepProgress, SweepResult,
    SweepSettings,
};
use beam_model::{FluidLoad, Whisker};
use branch::{Mode, Node};
pub(crate) use path::sweep_path;
use rows::rows;
pub(crate) use settings::FrictionSettings;
use start::{first_node, sweeper};
use trace::Sweeper;

/// What the frictional sweep returns to [`crate::driver::sweep`].
pub(crate) struct FrictionalRows {
    /// The contact rows and their estimates (NaN without an accuracy asked for).
    pub rows: Vec<(SweepPoint, f64)>,
    pub events: Vec<FrictionEvent>,
    pub separation: Separation,
    /// x0 of the first touch.
    pub first_x0: f64,
}

/// The frictional sweep's contact rows from its first node `first` (`start::first_node`),
/// on the legs of `sw` (`start::sweeper`).
fn frictional_rows(
    sw: &Sweeper,
    first: Node,
    set: &FrictionSettings,
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<FrictionalRows> {
    progress(SweepProgress::Coarse { steps: 0 });
    let tr = sw.trace_or_retrace(first)?;
    let separation = tr.end;
    progress(SweepProgress::Coarse {
        steps: tr.nodes.len(),
    });
    let rows = rows(sw, &sw.tight, &tr, set, &mut |done, total| {
        progress(SweepProgress::Fine { done, total })
    })?;
    Ok(FrictionalRows {
        rows,
        events: tr.events,
        separation,
        first_x0: first.x0,
    })
}

/// The frictional sweep (`mu > 0`) from the free whisker's tip angle `phi1` and its first
/// touch: the pre-contact rows of the frictionless sweep, then the frictional contact rows
/// ([`frictional_rows`]), with the accuracy asked for (`SweepSettings::accuracy`) every row's
/// estimate, the sweep refused where one exceeds it (no second, tighter pass here). Progress
/// goes to `progress` as the frictionless sweep's: `Coarse` before and after the trace (its
/// nodes), `Fine` for every row.
pub(crate) fn sweep(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
    (phi1, touch): (f64, &FirstTouch),
    mu: f64,
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<SweepResult> {
    let frame = settings.motion.frame().unwrap_or_default();
    let set = FrictionSettings::of(settings, mu, frame);
    let scene = (whisker, flow, profile);
    let sw = sweeper(scene, &set);
    let first = first_node(&sw, touch, &set)?;
    // a peg has no contour parameter of its own (its tip passing ends on s1 = 1): the
    // frictional legs there
    if let (FirstContact::Tip, Mode::Slip { s }, false) = (touch.kind, first.mode, profile.is_peg())
    {
        // sliding from the tip touch: the frictionless machinery under the tilted force,
        // where the contact slides throughout (`slide`)
        let at = (phi1, touch);
        if let Some(r) = slide::sliding_sweep(scene, settings, at, (s, mu), progress) {
            return Ok(r);
        }
    }
    let fr = frictional_rows(&sw, first, &set, progress)?;
    let mut points = pre_contact_rows(whisker, flow, phi1, fr.first_x0, settings)?;
    let pre = points.len();
    points.extend(fr.rows.iter().map(|r| r.0));
    let mut events = events_on_rows(fr.events, &points[pre..]);
    let mut touch = *touch;
    if frame != Frame::Translate {
        // the rows, the events and the first touch carry the pose of their coordinate (as
        // the frictionless sweep's, `SweepPoint::from_state`)
        for p in &mut points[pre..] {
            let pose = frame.pose(p.x0);
            (p.x0, p.y0, p.gamma) = (pose.x0, pose.y0, pose.gamma);
        }
        for e in &mut events {
            e.x0 = frame.pose(e.x0).x0;
        }
        touch.x0 = frame.pose(touch.x0).x0;
    }
    let accuracy = settings
        .accuracy
        .map(|tol| {
            let first = fr.rows.first().map_or(f64::NAN, |r| r.1);
            let mut estimates = vec![first; pre];
            estimates.extend(fr.rows.iter().map(|r| r.1));
            check_accuracy(&points, estimates, tol, row_integration_tol(tol))
        })
        .transpose()?;
    Ok(SweepResult {
        q: flow.q,
        alpha: flow.alpha,
        points,
        first_contact: touch.kind,
        first_touch: touch,
        separation: fr.separation,
        accuracy,
        friction_events: events,
    })
}

/// Each stick/slip switch as its own row gives it: the event rows are solved again on their
/// events at the sweep's tolerances after the trace located them at its looser ones, so the
/// record takes the row's base position, contact point and forces: the row within 1e-6 in x0
/// of the event (a slip-to-stick switch, where the sliding stops, is a tangency of the two
/// legs and the trace locates it only to about 1e-7; the rows are 1e-3 and more apart); an
/// event without such a row keeps the trace's values.
fn events_on_rows(
    mut events: Vec<crate::contact_law::FrictionEvent>,
    rows: &[SweepPoint],
) -> Vec<crate::contact_law::FrictionEvent> {
    for e in &mut events {
        let near = rows
            .iter()
            .min_by(|a, b| (a.x0 - e.x0).abs().total_cmp(&(b.x0 - e.x0).abs()));
        if let Some(p) = near.filter(|p| (p.x0 - e.x0).abs() <= 1e-6) {
            (e.x0, e.xc, e.f, e.ft) = (p.x0, p.xc, p.f, p.ft);
        }
    }
    events
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact_law::{force, frictional_loads};

    /// `F = fn n + ft t` as a tip force: the loads' vector is the force, and `ft = 0` gives
    /// the frictionless loads bit for bit.
    #[test]
    fn the_frictional_force_is_the_tip_force() {
        let flow = FluidLoad { q: 1.0, alpha: 0.2 };
        for (psi, f, ft) in [(0.3, 2.0, 0.5), (-0.7, 1.0, -0.9), (1.2, 0.4, 0.0)] {
            let l = frictional_loads(flow, psi, f, ft, 1.0);
            let (fx, fy) = force(psi, f, ft);
            let (sb, cb) = l.tip.beta.sin_cos();
            assert!((l.tip.f * cb - fx).abs() < 1e-15 && (-l.tip.f * sb - fy).abs() < 1e-15);
            // the normal and tangential parts of the force
            let (sp, cp) = psi.sin_cos();
            assert!((fx * sp - fy * cp - f).abs() < 1e-15);
            assert!((fx * cp + fy * sp - ft).abs() < 1e-15);
        }
        let l = frictional_loads(flow, 0.4, 1.5, 0.0, 0.8);
        assert_eq!(l, crate::phase::contact_loads(flow, 0.4, 1.5, 0.8));
    }

    /// `ContactLaw` refuses a negative or non-finite coefficient and names it.
    #[test]
    fn the_law_refuses_bad_coefficients() {
        assert!(ContactLaw::Coulomb { mu: 0.5 }.validate().is_ok());
        assert_eq!(ContactLaw::Coulomb { mu: 0.0 }.friction(), None);
        assert_eq!(ContactLaw::default().mu(), 0.0);
        for mu in [-0.1, f64::NAN, f64::INFINITY, 11.0] {
            let e = ContactLaw::Coulomb { mu }.validate().unwrap_err();
            assert!(e.to_string().contains("mu"), "{e}");
        }
    }
}
