//! The frictional path followed from its first node to its end.

use super::branch::{dot4, norm4, sub4, Con, FrictionBranch, Mode, Node};
use super::kinds::{Ev, PENETRATION_MARGIN};
use crate::contact_law::{FrictionEvent, FrictionEventKind};
use crate::error::{ContactError, Result};
use crate::phase::Phase;
use crate::sweep::Separation;

/// How far in x0 the new mode at a stick/slip switch is followed to check that it keeps the
/// law ([`Sweeper::probe`]).
pub(super) const SWITCH_PROBE: f64 = 1e-4;

/// Longest step over which an event is located (longer steps are shortened first; the
/// trace's steps were at most this long before they grew to the frictionless sweep's 0.2).
const EVENT_BRACKET: f64 = 0.05;

/// The traced path: nodes in the order of the motion (a switch node appears twice, once in
/// each mode), the switch events, and the end.
pub(super) struct Trace {
    pub(super) nodes: Vec<Node>,
    pub(super) events: Vec<FrictionEvent>,
    pub(super) end: Separation,
}

pub(super) struct Sweeper<'a> {
    /// The trace's equations (looser tolerances than the sweep's).
    pub(super) b: FrictionBranch<'a>,
    /// The equations at the sweep's tolerances: a second contact is located on them (its
    /// depth margin, 1e-10, is below the trace's integration tolerance).
    pub(super) tight: FrictionBranch<'a>,
    pub(super) event_tol: f64,
    pub(super) max_step: f64,
    pub(super) max_steps: usize,
    pub(super) check_penetration: bool,
}

impl Sweeper<'_> {
    /// Follows the path from `first` (in `mode`) to the separation.
    pub(super) fn trace(&self, first: Node) -> Result<Trace> {
        let mut nodes = vec![first];
        let mut events = Vec::new();
        if self.check_penetration {
            // the first touch must leave the rest of the whisker outside, in either phase
            // (as the frictionless sweep, `continuation::trace`): a tip touch of a curled
            // whisker can come with its body already across the contour, and a tangential
            // first touch removes the flow beyond s1 (spec/model.md), so the unloaded segment
            // can bend into the obstacle at once; the events below only see their conditions
            // change sign, never a depth that is there from the start
            let depth = self.depth(&first)?;
            let near = if first.phase == Phase::B {
                self.condition(Ev::Touch, &first, &[0.0; 4])?
            } else {
                1.0
            };
            if depth > PENETRATION_MARGIN || near <= 0.0 {
                let kind = if first.phase == Phase::B {
                    "tangential (flow on [0, s1] only)"
                } else {
                    "tip"
                };
                return Err(ContactError::NoContact {
                    reason: format!(
                        "at the first touch (x0 = {:.6}) the {kind} contact state puts another part of the whisker {depth:.3e} inside the contour (curvature margin {near:.3e}); a single-contact sweep cannot start",
                        first.x0
                    ),
                });
            }
        }
        let mut cur = first;
        let mut dir = self.b.falling(&cur);
        let mut h = 0.01f64.min(self.max_step);
        let mut steps = 0;
        let mut zero_stretch = 0;
        loop {
            if steps >= self.max_steps {
                return Ok(Trace {
                    nodes,
                    events,
                    end: Separation::NotReached { steps },
                });
            }
            steps += 1;
            let scale = [1.0, 1.0 / cur.w[1].abs().max(1.0), 1.0, 1.0];
            let scale = [scale[0], scale[1], scale[1], scale[3]];
            let tn = self.b.tangent(&cur, &dir);
            let sn = norm4(&[
                tn[0] * scale[0],
                tn[1] * scale[1],
                tn[2] * scale[2],
                tn[3] * scale[3],
            ]);
            let raw = h / sn;
            let p = [
                cur.w[0] + raw * tn[0],
                cur.w[1] + raw * tn[1],
                cur.w[2] + raw * tn[2],
                cur.w[3] + raw * tn[3],
            ];
            let next = match self.b.correct_near(
                cur.phase,
                cur.mode,
                p,
                Con::Plane { n: tn, p },
                Some(&cur.jac),
                true,
            ) {
                Ok(n) if dot4(&self.b.tangent(&n, &tn), &tn) > 0.95 => Ok(n),
                Ok(_) => Err(None),
                Err(e) => Err(Some(e)),
            };
            let next = match next {
                Ok(n) => n,
                Err(e) => {
                    h *= 0.5;
                    if h < 1e-9 {
                        return match e {
                            Some(ContactError::LeftContour { .. }) => Ok(Trace {
                                nodes,
                                events,
                                end: Separation::EndOfContour,
                            }),
                            Some(e) => Err(e),
                            None => Err(self.stalled(&cur, h, "the path turns too sharply")),
                        };
                    }
                    continue;
                }
            };
            // events between cur and next: the earliest
            let chord = sub4(&next.w, &cur.w);
            let mut first_ev: Option<(f64, Ev, Node)> = None;
            let mut shrink = false;
            for &ev in self.events_of(cur.mode) {
                let cb = self.condition(ev, &next, &chord)?;
                if cb >= 0.0 {
                    continue;
                }
                let ca = self.condition(ev, &cur, &chord)?;
                if ca < 0.0 {
                    // already across at the start: only a switch that was just made
                    continue;
                }
                if norm4(&chord) > EVENT_BRACKET {
                    // an event over a long step: the step shortened first (the chord's
                    // trial points are solved on hyperplanes across it)
                    shrink = true;
                    break;
                }
                let (th, at) = self.locate(ev, &cur, &next, ca, cb)?;
                if first_ev.as_ref().is_none_or(|f| th < f.0) {
                    first_ev = Some((th, ev, at));
                }
            }
            if shrink {
                h = 0.5 * h.min(norm4(&chord));
                if h < 1e-9 {
                    // the corrector lands far from the prediction however short the step
                    return Err(self.stalled(&cur, h, "an event's step cannot be shortened"));
                }
                continue;
            }
            let Some((_, ev, at)) = first_ev else {
                dir = self.b.tangent(&next, &tn);
                nodes.push(next);
                cur = next;
                zero_stretch = 0;
                h = (h * 1.5).min(self.max_step);
                continue;
            };
            nodes.push(at);
            let end = |s| {
                Ok(Trace {
                    nodes: nodes.clone(),
                    events: events.clone(),
                    end: s,
                })
            };
            match ev {
                Ev::Release => {
                    // on fn = 0 itself (as the frictionless sweep's release)
                    let p = [at.w[0], 0.0, at.w[2], at.w[3]];
                    let n = [0.0, 1.0, 0.0, 0.0];
                    let on = self.b.correct(at.phase, at.mode, p, Con::Plane { n, p })?;
                    let mut nodes = nodes.clone();
                    nodes.pop();
                    nodes.push(on);
                    return Ok(Trace {
                        nodes,
                        events,
                        end: Separation::Release,
                    });
                }
                Ev::Corner => {
                    // a path's segment ends on its next row exactly, in contact (the next
                    // segment's trace goes on from here, `super::path`)
                    let floor = self.b.frame.floor().unwrap_or(at.x0);
                    let on = self.b.correct(at.phase, at.mode, at.w, Con::Base(floor))?;
                    let mut nodes = nodes.clone();
                    nodes.pop();
                    nodes.push(on);
                    return Ok(Trace {
                        nodes,
                        events,
                        end: Separation::PathEnd,
                    });
                }
                Ev::Snap => return end(Separation::Snap),
                Ev::Touch | Ev::Depth => return end(Separation::MultiContact { xc: at.geom.x }),
                Ev::AtBase => return end(Separation::ContactAtBase),
                Ev::PhaseEnd if self.b.profile.is_peg() => {
                    // a peg has no tip contact: the tip slides past it (as the frictionless
                    // sweep's `End::TipPassed`), on `s1 = 1` itself
                    let on = self.b.correct(at.phase, at.mode, at.w, Con::PhaseEnd)?;
                    let mut nodes = nodes.clone();
                    nodes.pop();
                    nodes.push(on);
                    return Ok(Trace {
                        nodes,
                        events,
                        end: Separation::TipPassed,
                    });
                }
                Ev::PhaseEnd => {
                    let Some((start, tn)) = self.switch_phase(&at)? else {
                        // the other phase's curve leaves towards larger x0: no quasi-static
                        // continuation, the whisker snaps off at the switch (on the switch
                        // itself where the motion turns or the obstacle is closed)
                        if self.exact_ends() {
                            let on = self.b.correct(at.phase, at.mode, at.w, Con::PhaseEnd)?;
                            let mut nodes = nodes.clone();
                            nodes.pop();
                            nodes.push(on);
                            return Ok(Trace {
                                nodes,
                                events,
                                end: Separation::Snap,
                            });
                        }
                        return end(Separation::Snap);
                    };
                    if self.check_penetration
                        && start.phase == Phase::B
                        && self.condition(Ev::Touch, &start, &tn)? <= 0.0
                    {
                        // the tangential phase starts with the whisker bending into the
                        // contour on both sides of the contact point
                        return end(Separation::MultiContact { xc: at.geom.x });
                    }
                    nodes.push(start);
                    dir = tn;
                    cur = start;
                    h = 0.01f64.min(self.max_step);
                }
                Ev::Cone | Ev::Sliding => {
                    zero_stretch += 1;
                    if zero_stretch > 2 {
                        return Err(self.indeterminate(&at, "stick and slip alternate on the spot"));
                    }
                    let (kind, mode) = if ev == Ev::Cone {
                        let s = at.w[2].signum();
                        (FrictionEventKind::StickToSlip, Mode::Slip { s })
                    } else {
                        (
                            FrictionEventKind::SlipToStick,
                            Mode::Stick {
                                anchor: at.w[3],
                                s1: at.s1(),
                            },
                        )
                    };
                    let start = self.b.correct_near(
                        at.phase,
                        mode,
                        at.w,
                        Con::Base(at.x0),
                        Some(&at.jac),
                        true,
                    )?;
                    if !self.probe(&start, SWITCH_PROBE) {
                        let reason = match kind {
                            FrictionEventKind::StickToSlip => {
                                "the force leaves the cone, and sliding against it does not follow the base (a dynamic slip)"
                            }
                            FrictionEventKind::SlipToStick => {
                                "the sliding stops, and sticking does not keep the force in the cone"
                            }
                        };
                        return Err(self.indeterminate(&start, reason));
                    }
                    events.push(FrictionEvent {
                        kind,
                        x0: start.x0,
                        xc: start.geom.x,
                        f: start.w[1],
                        ft: start.w[2],
                    });
                    nodes.push(start);
                    dir = self.b.falling(&start);
                    cur = start;
                    h = 0.01f64.min(self.max_step);
                }
            }
        }
    }

    /// The node of the other phase at a phase switch `at` (`phi1 = psi` with `s1 = 1`), in
    /// the same mode (a stick re-anchored at the switch: the tip is the touching material
    /// point there), with the tangent that enters the new phase's valid side (`s1 < 1` in
    /// B, `phi1 > psi` in A); `None` where x0 rises along it (as the frictionless sweep's
    /// switch, `continuation::switch_phase`).
    fn switch_phase(&self, at: &Node) -> Result<Option<(Node, [f64; 4])>> {
        let [_, f, ft, t] = at.w;
        let (phase, w) = match at.phase {
            Phase::B => (Phase::A, [at.geom.psi, f, ft, t]),
            _ => (Phase::B, [1.0, f, ft, t]),
        };
        let mode = match at.mode {
            Mode::Stick { .. } => Mode::Stick { anchor: t, s1: 1.0 },
            slip => slip,
        };
        let start = self.b.correct(phase, mode, w, Con::Base(at.x0))?;
        let into = match phase {
            Phase::B => [-1.0, 0.0, 0.0, 0.0],
            _ => [1.0, 0.0, 0.0, -start.geom.dpsi],
        };
        let tn = self.b.tangent(&start, &into);
        if dot4(&start.jac[2], &tn) >= 0.0 {
            return Ok(None);
        }
        Ok(Some((start, tn)))
    }

    /// Whether an end on a phase's end is solved on it exactly (and its row held there,
    /// `rows::end_hold`): for every motion but the translation and for closed obstacles;
    /// the translating graph sweep keeps its rows as before.
    pub(super) fn exact_ends(&self) -> bool {
        self.b.frame != crate::motion::Frame::Translate || self.b.profile.is_closed()
    }

    pub(super) fn indeterminate(&self, n: &Node, reason: &str) -> ContactError {
        ContactError::FrictionIndeterminate {
            x0: n.x0,
            xc: n.geom.x,
            mu: self.b.mu,
            reason: reason.into(),
        }
    }

    pub(super) fn stalled(&self, n: &Node, step: f64, reason: &str) -> ContactError {
        ContactError::BranchStalled {
            phase: n.phase,
            x0: n.x0,
            xc: n.geom.x,
            step,
            reason: reason.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{sweep, ContactError, ContactLaw, Profile, SweepSettings};
    use beam_model::{FluidLoad, Whisker};

    /// A curled whisker (theta 0.478, A 1.926, B 1.241, k 0.392, no flow) first touches g1
    /// with its tip while its segment near s = 0.93 is already 9.96e-3 inside the contour.
    /// The frictionless sweep refuses to start there; the frictional one (mu 0.855) logged 25
    /// rows with that segment inside (found by the independent scipy checker,
    /// docs/independent-check.md). Both now refuse with the depth.
    #[test]
    fn a_tip_touch_with_the_body_inside_is_refused_with_friction_too() {
        let whisker = Whisker::new(
            0.4778808036089372,
            1.9257387174939256,
            1.2408163600516502,
            0.392420361915408,
        );
        let flow = FluidLoad { q: 0.0, alpha: 0.0 };
        for mu in [0.0, 0.8550254338813659] {
            let settings = SweepSettings {
                points: 24,
                contact_law: ContactLaw::Coulomb { mu },
                ..SweepSettings::default()
            };
            match sweep(&whisker, flow, &Profile::g1(), &settings) {
                Err(ContactError::NoContact { reason }) => {
                    assert!(reason.contains("9.96"), "mu {mu}: {reason}");
                    assert!(reason.contains("tip contact state"), "mu {mu}: {reason}");
                }
                other => panic!(
                    "mu {mu}: the sweep started: {:?}",
                    other.map(|r| r.points.len())
                ),
            }
        }
    }
}
