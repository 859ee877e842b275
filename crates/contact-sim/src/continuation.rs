//! Pseudo-arclength continuation of the contact branch from the first contact to the
//! separation, in the direction in which the base position x0 falls (the base moves towards
//! -x; spec/model.md, contact).
//!
//! Each step predicts along the unit tangent of the branch in `(v, f, t)` and corrects on the
//! hyperplane through the prediction normal to the tangent, so folds of the contact point
//! (xc reversing while x0 keeps falling) are passed like any other point. The step adapts to
//! the corrector's effort and to the turning of the tangent. After each step the events
//! between the two nodes are checked and the earliest one is located ([`crate::events`]):
//! a phase switch continues on the other phase's branch; a release (`f = 0`), a snap (x0
//! reaching a turning point), a second contact or the end of the contour ends the trace.
//! Every loop has a budget: a trace that does not separate within `max_steps` steps ends as
//! [`End::NotReached`].

use crate::branch::{dot, Branch, Constraint, Node};
use crate::error::{ContactError, Result};
use crate::events::{locate, penetration, phase_margin, smooth_turn, x0_rate};
use crate::phase::Phase;

/// How the trace ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum End {
    /// x0 reached a turning point: the whisker snaps off (the node at the turning point).
    Snap(Node),
    /// The contact force fell to zero (the node at f = 0).
    Release(Node),
    /// Another point of the whisker reaches the obstacle (the last node with one contact).
    MultiContact(Node),
    /// The contact point reached the end of the contour's parameter range.
    OffContour(Node),
    /// A tangential contact slid down to the base (`s1 = BASE_CONTACT`).
    AtBase(Node),
    /// No separation within the step budget.
    NotReached(Node, usize),
}

/// The traced branch: its nodes in the order of the motion (x0 strictly falling; a phase
/// switch appears twice, once in each phase's variables), the switch nodes, and the end.
pub(crate) struct Trace {
    pub nodes: Vec<Node>,
    pub switches: Vec<Node>,
    pub end: End,
}

/// Step control of the trace.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StepControl {
    /// First step length.
    pub initial: f64,
    /// Largest step length.
    pub max: f64,
    /// Smallest step length before the trace gives up.
    pub min: f64,
    /// Step budget.
    pub max_steps: usize,
    /// Event location tolerance in the state.
    pub event_tol: f64,
    /// Whether to check for a second contact at every node.
    pub check_penetration: bool,
}

/// Penetration depth below which a second contact is not counted (the shape check's own
/// accuracy is ~1e-10).
const PENETRATION_MARGIN: f64 = 1e-8;

/// A step below which a rise of x0 is the turning point itself (x0 stationary within the
/// shots' accuracy).
const SNAP_STEP: f64 = 1e-7;

/// Longest step over which an event is located (longer steps are shrunk first).
const EVENT_BRACKET: f64 = 0.02;

/// The events checked after each step, in the order they are reported at equal position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Event {
    Switch,
    Release,
    Snap,
    SecondContact,
    AtBase,
}

/// The contact arc length at which a tangential contact has slid down to the base: the
/// obstacle reaches the base's path and the single-contact sweep ends there.
pub(crate) const BASE_CONTACT: f64 = 1e-2;

/// Traces the branch from `first` until it separates.
pub(crate) fn trace(branch: &Branch, first: Node, ctl: &StepControl) -> Result<Trace> {
    let down = [-first.jac[2][0], -first.jac[2][1], -first.jac[2][2]];
    let mut t = first.tangent(&down);
    let mut nodes = vec![first];
    let mut switches = Vec::new();
    if ctl.check_penetration {
        let depth = penetration(branch.whisker, branch.flow, branch.profile, &first.state)?;
        if depth > PENETRATION_MARGIN {
            return Err(ContactError::NoContact {
                reason: format!(
                    "at the first touch (x0 = {:.6}) the {} contact state puts another part of the whisker {depth:.3e} inside the contour; a single-contact sweep cannot start",
                    first.x0(),
                    if first.phase == Phase::B { "tangential (flow on [0, s1] only)" } else { "tip" }
                ),
            });
        }
    }
    if x0_rate(&first, &t) >= 0.0 {
        return Ok(Trace {
            nodes,
            switches,
            end: End::Snap(first),
        });
    }
    let mut cur = first;
    let mut h = ctl.initial;
    let stalled = |cur: &Node, h: f64, reason: String| ContactError::BranchStalled {
        phase: crate::branch::phase_letter(cur.phase),
        x0: cur.x0(),
        xc: cur.state.point.xc,
        step: h,
        reason,
    };
    for _ in 0..ctl.max_steps {
        // The step is measured with the force relative to its size, `|(dv, df/F, dt)|` with
        // `F = max(1, |f|)`: forces that grow large (a contact sliding to the base) are
        // followed in proportion, not in unit steps.
        let fscale = cur.state.f.abs().max(1.0);
        let len = (t[0] * t[0] + (t[1] / fscale).powi(2) + t[2] * t[2]).sqrt();
        let hs = h / len;
        let p = [
            cur.u[0] + hs * t[0],
            cur.u[1] + hs * t[1],
            cur.u[2] + hs * t[2],
        ];
        let node = match branch.correct(
            cur.phase,
            p,
            Constraint::Hyperplane {
                n: t,
                p,
                radius: 0.5 * hs + 1e-9,
            },
            true,
        ) {
            Ok(n) => n,
            Err(e) => {
                h *= 0.5;
                if h < ctl.min {
                    return match e {
                        ContactError::LeftContour { .. } => Ok(Trace {
                            nodes,
                            switches,
                            end: End::OffContour(cur),
                        }),
                        e => Err(stalled(&cur, h, e.to_string())),
                    };
                }
                continue;
            }
        };
        let tn = node.tangent(&t);
        if !smooth_turn(&t, &tn) && h > ctl.min {
            h *= 0.5;
            continue;
        }
        // The earliest event in (cur, node].
        let mut events = Vec::new();
        if phase_margin(&node) <= 0.0 {
            events.push(Event::Switch);
        }
        if node.state.f < 0.0 {
            events.push(Event::Release);
        }
        if node.x0_rate(&tn) >= 0.0 {
            events.push(Event::Snap);
        }
        if node.phase == Phase::B && node.state.s1 <= BASE_CONTACT {
            events.push(Event::AtBase);
        }
        // The shape check for a second contact costs a shot of its own: done only for a
        // step that is otherwise accepted (and at located events, below).
        if events.is_empty()
            && ctl.check_penetration
            && penetration(branch.whisker, branch.flow, branch.profile, &node.state)?
                > PENETRATION_MARGIN
        {
            events.push(Event::SecondContact);
        }
        if events.is_empty() {
            if node.x0() >= cur.x0() {
                // x0 must fall along an oriented tangent with a negative rate at both ends;
                // a rise means the step jumped over a pair of turning points, or, on a tiny
                // step, that x0 is stationary to within the shots' accuracy: the turning
                // point of the snap, reached within the step.
                if h < SNAP_STEP {
                    return Ok(Trace {
                        nodes,
                        switches,
                        end: End::Snap(cur),
                    });
                }
                h *= 0.5;
                if h < ctl.min {
                    return Err(stalled(&cur, h, "x0 rose between two nodes".into()));
                }
                continue;
            }
            let easy = node.state.iterations <= 3;
            cur = node;
            t = tn;
            nodes.push(node);
            if easy {
                h = (h * 1.6).min(ctl.max);
            }
            continue;
        }
        // Switches and releases alone are solved directly, with the event condition as the
        // third equation from the secant point of the bracket. Other events are located by
        // regula falsi along the chord in short brackets, where the chord stays close to the
        // branch: longer steps are shrunk first (this also separates several events).
        let single_direct =
            events.len() == 1 && matches!(events[0], Event::Switch | Event::Release);
        let mut best: Option<(Event, Node)> = None;
        if single_direct {
            let ev = events[0];
            let c = if ev == Event::Switch {
                Constraint::PhaseEnd
            } else {
                Constraint::NoForce
            };
            let g = |n: &Node| {
                if ev == Event::Switch {
                    phase_margin(n)
                } else {
                    n.state.f
                }
            };
            let (ga, gb) = (g(&cur), g(&node));
            let w = ga / (ga - gb);
            let p = crate::branch::lerp(&cur.u, &node.u, w);
            if let Ok(mut at) = branch.correct(cur.phase, p, c, true) {
                if ev == Event::Release {
                    // f = 0 to the corrector's tolerance: the release row carries f = 0
                    at.state.f = at.state.f.max(0.0);
                    at.u[1] = at.state.f;
                }
                let d = crate::branch::sub(&node.u, &cur.u);
                let along = dot(&crate::branch::sub(&at.u, &cur.u), &d) / dot(&d, &d);
                if along > -1e-12 && along < 1.0 + 1e-12 && at.x0() <= cur.x0() {
                    best = Some((ev, at));
                }
            }
        }
        if best.is_none() {
            if h > EVENT_BRACKET || (events.len() > 1 && h > 64.0 * ctl.min) {
                h = (h * 0.25).max(ctl.min);
                continue;
            }
            let t_ref = t;
            for &ev in &events {
                let g = |n: &Node| -> Result<f64> {
                    Ok(match ev {
                        Event::Switch => phase_margin(n),
                        Event::Release => n.state.f,
                        Event::Snap => -x0_rate(n, &t_ref),
                        Event::AtBase => n.state.s1 - BASE_CONTACT,
                        Event::SecondContact => {
                            PENETRATION_MARGIN
                                - penetration(
                                    branch.whisker,
                                    branch.flow,
                                    branch.profile,
                                    &n.state,
                                )?
                        }
                    })
                };
                let at = locate(branch, &cur, &node, &g, ctl.event_tol)?;
                let along = dot(&crate::branch::sub(&at.u, &cur.u), &t);
                if best.is_none_or(|(_, b)| along < dot(&crate::branch::sub(&b.u, &cur.u), &t)) {
                    best = Some((ev, at));
                }
            }
        }
        // A second contact before the located event ends the trace there.
        if let Some((ev, at)) = best {
            if ev != Event::SecondContact
                && ctl.check_penetration
                && penetration(branch.whisker, branch.flow, branch.profile, &at.state)?
                    > PENETRATION_MARGIN
            {
                let g = |n: &Node| -> Result<f64> {
                    Ok(PENETRATION_MARGIN
                        - penetration(branch.whisker, branch.flow, branch.profile, &n.state)?)
                };
                let sc = locate(branch, &cur, &at, &g, ctl.event_tol)?;
                best = Some((Event::SecondContact, sc));
            }
        }
        let Some((ev, at)) = best else { continue };
        if at.u != cur.u && at.x0() < cur.x0() {
            nodes.push(at);
        }
        match ev {
            Event::Release => {
                return Ok(Trace {
                    nodes,
                    switches,
                    end: End::Release(at),
                })
            }
            Event::Snap => {
                return Ok(Trace {
                    nodes,
                    switches,
                    end: End::Snap(at),
                })
            }
            Event::SecondContact => {
                return Ok(Trace {
                    nodes,
                    switches,
                    end: End::MultiContact(at),
                })
            }
            Event::AtBase => {
                return Ok(Trace {
                    nodes,
                    switches,
                    end: End::AtBase(at),
                })
            }
            Event::Switch => {
                let (next, tn) = switch_phase(branch, &at)?;
                // the switch row in tip-contact form: s1 = 1 exactly, phi1 = psi
                switches.push(if next.phase == Phase::A { next } else { at });
                if x0_rate(&next, &tn) >= 0.0 {
                    // The other phase's branch leaves towards larger x0: no quasi-static
                    // continuation, the whisker snaps off at the switch.
                    return Ok(Trace {
                        nodes,
                        switches,
                        end: End::Snap(at),
                    });
                }
                nodes.push(next);
                cur = next;
                t = tn;
                h = ctl.initial.min(h);
            }
        }
    }
    Ok(Trace {
        nodes,
        switches,
        end: End::NotReached(cur, ctl.max_steps),
    })
}

/// The node of the other phase at a switch node `at` (where `phi1 = psi` and `s1 = 1`), with
/// the tangent that enters the new phase's valid side.
fn switch_phase(branch: &Branch, at: &Node) -> Result<(Node, [f64; 3])> {
    let (phase, u) = match at.phase {
        Phase::B => (Phase::A, [at.state.point.psi, at.u[1], at.u[2]]),
        _ => (Phase::B, [1.0, at.u[1], at.u[2]]),
    };
    let next = branch.correct(phase, u, Constraint::BasePosition(at.x0()), true)?;
    // The valid side: s1 < 1 in B; phi1 - psi(t) > 0 in A.
    let into = match phase {
        Phase::B => [-1.0, 0.0, 0.0],
        _ => {
            let g = branch.profile.at(next.u[2]);
            [1.0, 0.0, -g.dpsi]
        }
    };
    let tn = next.tangent(&into);
    Ok((next, tn))
}
