//! The mode of the contact at the first touch and at a switch: the probe of a mode's law.

use super::branch::{dot4, Con, FrictionBranch, Mode, Node};
use super::contour::arc_length;
use super::settings::FrictionSettings;
use super::trace::{Sweeper, Trace};
use crate::error::Result;
use crate::first_contact::{FirstContact, FirstTouch};
use crate::motion::Frame;
use crate::phase::Phase;
use crate::profile::Profile;
use beam_model::shot::Integration;
use beam_model::{FluidLoad, Whisker};

/// The trace's integrator tolerance (at most as tight as the sweep's), as the frictionless
/// trace's (`continuation::TRACE_INTEGRATION_TOL`): the nodes only guide the rows and bracket
/// the events; every row, the event rows on their events, is solved at the sweep's own.
pub(super) const TRACE_INTEGRATION_TOL: f64 = 1e-9;

/// The trace's residual tolerance (at most as tight as the sweep's).
pub(super) const TRACE_SOLVE_TOL: f64 = 1e-9;

/// The trace's longest step in `(v, fn/F, ft/F, t)`, `F = max(1, |fn|)` (the frictionless
/// sweep's default `max_step`; events are located by bisection down to 0.05 first).
pub(super) const MAX_STEP: f64 = 0.2;

/// How far in x0 the candidate modes of the first touch are followed to decide between
/// them ([`Sweeper::first_mode`]).
pub(super) const PROBE: f64 = 1e-3;

/// The frictional trace of one scene in the frame of `set`: its equations at the trace's
/// looser tolerances (its nodes only guide the rows and bracket the events, as the
/// frictionless sweep's `continuation::trace_tightened`) and at the sweep's own (`tight`:
/// the rows, the first node and the event rows on their events).
pub(super) fn sweeper<'a>(
    (whisker, flow, profile): (&'a Whisker, FluidLoad, &'a Profile),
    set: &FrictionSettings,
) -> Sweeper<'a> {
    let tight = FrictionBranch {
        whisker,
        flow,
        profile,
        integration: Integration::adaptive(set.integration_tol),
        tol: set.solve_tol,
        mu: set.mu,
        frame: set.frame,
    };
    Sweeper {
        b: FrictionBranch {
            integration: Integration::adaptive(set.integration_tol.max(TRACE_INTEGRATION_TOL)),
            tol: set.solve_tol.max(TRACE_SOLVE_TOL),
            ..tight.clone_shallow()
        },
        tight,
        event_tol: set.event_tol,
        max_step: set.max_step.min(MAX_STEP),
        max_steps: set.max_steps,
        check_penetration: set.check_penetration,
    }
}

/// The first node of the contact at the touch `touch`, its mode decided
/// ([`Sweeper::first_mode`]), exact at the sweep's tolerances: at a tip touch the free
/// whisker itself (F = 0); at a tangential touch the frictionless sweep's phase-B state at
/// the touch's base position (the flow acts on [0, s1] only, so the state jumps from the
/// free whisker's, `first_contact::first_node`), its force normal (`ft = 0`, inside the cone).
pub(super) fn first_node(sw: &Sweeper, touch: &FirstTouch, set: &FrictionSettings) -> Result<Node> {
    let (phase, w0) = match touch.kind {
        FirstContact::Tangential => {
            let integration = Integration::adaptive(set.integration_tol);
            let branch = crate::branch::Branch {
                whisker: sw.b.whisker,
                flow: sw.b.flow,
                profile: sw.b.profile,
                integration: &integration,
                tol: set.solve_tol,
                frame: set.frame,
                tilt: crate::contact_law::Tilt::NONE,
            };
            let n = crate::first_contact::first_node(&branch, touch)?;
            (Phase::B, [n.u[0], n.u[1], 0.0, n.u[2]])
        }
        _ => (Phase::A, [touch.phi1, 0.0, 0.0, touch.t]),
    };
    let stick = Mode::Stick {
        anchor: w0[3],
        s1: if phase == Phase::B { w0[0] } else { 1.0 },
    };
    let (_, n0) = sw.b.eval(phase, stick, w0, true)?;
    let first = sw.first_mode(&n0)?;
    // the first node exact at the sweep's tolerances (its state is the touch's, no solve)
    Ok(sw.tight.eval(first.phase, first.mode, first.w, true)?.1)
}

impl Sweeper<'_> {
    /// The trace from `first` ([`Sweeper::trace`]); where the looser trace stalls (met at a
    /// fold in tangential contact, battery scene 160), the path traced again at the sweep's
    /// own tolerances.
    pub(super) fn trace_or_retrace(&self, first: Node) -> Result<Trace> {
        match self.trace(first) {
            Ok(tr) => Ok(tr),
            Err(_) => Sweeper {
                b: self.tight.clone_shallow(),
                tight: self.tight.clone_shallow(),
                ..*self
            }
            .trace(first),
        }
    }

    /// The mode the contact starts in at the first touch `n0` (`F = 0`, in tip or
    /// tangential contact): the first of
    /// stick, slip with `s = +1`, slip with `s = -1` that keeps the law a short way along
    /// its curve ([`Sweeper::probe`], [`PROBE`] in x0). The probe decides where the tangent
    /// cannot: a straight whisker's tip starts to slide at zero speed (its motion along the
    /// contour is second order in the base's), so both slip curves are tangent to the stick
    /// curve there.
    pub(super) fn first_mode(&self, n0: &Node) -> Result<Node> {
        let (w0, anchor, s1) = (n0.w, n0.w[3], n0.s1());
        for mode in [
            Mode::Stick { anchor, s1 },
            Mode::Slip { s: 1.0 },
            Mode::Slip { s: -1.0 },
        ] {
            let (_, n) = self.b.eval(n0.phase, mode, w0, true)?;
            if self.probe(&n, PROBE)
                || (matches!(mode, Mode::Stick { .. }) && self.sticks_briefly(&n))
            {
                return Ok(n);
            }
        }
        Err(self.indeterminate(n0, "neither stick nor slip starts the contact"))
    }

    /// Whether a stuck first node `n` strictly inside the cone (a tangential touch, whose
    /// state jumps to `fn > 0` with `ft = 0`) keeps the law a shorter way than [`PROBE`]:
    /// stick is then the one consistent mode (`u = 0` with the force inside the cone; a slip
    /// would need `ft` to jump to the cone's edge), however soon the force leaves the cone
    /// (the trace's stick -> slip event follows). Met whisking against a peg: the material
    /// point pinned at a fixed distance from the base (the chord of `[0, s1]` fixed) turns
    /// the force along the whisker by `dft/dgamma ~ 1e3`. Probed down to `1e-7` in the
    /// coordinate; only where the motion turns or the obstacle is closed (the translating
    /// graph sweep keeps its first mode, and its rows, as before).
    fn sticks_briefly(&self, n: &Node) -> bool {
        let inside = n.w[1] > 0.0 && n.w[2].abs() < self.b.mu * n.w[1];
        let new_kind = self.b.frame != Frame::Translate || self.b.profile.is_closed();
        if !(inside && new_kind) {
            return false;
        }
        let mut dx = 0.1 * PROBE;
        while dx >= 1e-7 {
            if self.probe(n, dx) {
                return true;
            }
            dx *= 0.1;
        }
        false
    }

    /// Whether the law holds along the mode's curve from `n` a step `dx` on in x0 (one
    /// corrector solve from the tangent's prediction): `fn >= 0`; stick: `|ft| <= mu fn`;
    /// slip: the material point has moved against `ft`, `-s (t - t(n)) >= 0` in phase A,
    /// `-s (sigma - s1 - (sigma(n) - s1(n))) >= 0` in phase B. At a switch the two modes'
    /// curves are tangent (slip -> stick: the sliding speed is zero; the first touch), so
    /// the tangent alone cannot tell; the step sees the second-order terms.
    pub(super) fn probe(&self, n: &Node, dx: f64) -> bool {
        let t = self.b.tangent(n, &[0.0; 4]);
        let rate = dot4(&n.jac[2], &t);
        if rate.abs() < 1e-9 {
            return false;
        }
        let h = -dx / rate;
        let p = [
            n.w[0] + h * t[0],
            n.w[1] + h * t[1],
            n.w[2] + h * t[2],
            n.w[3] + h * t[3],
        ];
        let Ok(m) = self.b.correct_near(
            n.phase,
            n.mode,
            p,
            Con::Base(n.x0 - dx),
            Some(&n.jac),
            false,
        ) else {
            return false;
        };
        let [_, f, ft, tt] = m.w;
        f >= 0.0
            && match n.mode {
                Mode::Stick { .. } => ft.abs() <= self.b.mu * f + 1e-13,
                Mode::Slip { s } if n.phase == Phase::B => {
                    -s * (arc_length(self.b.profile, n.w[3], tt) - (m.w[0] - n.w[0])) >= 0.0
                }
                Mode::Slip { s } => -s * (tt - n.w[3]) >= 0.0,
            }
    }
}
