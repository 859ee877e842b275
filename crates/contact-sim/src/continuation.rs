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

use crate::ahead::{with_checks, Ahead};
use crate::branch::{dot, Branch, Constraint, Node, Rescue};
use crate::error::{ContactError, Result};
use crate::events::{near_margin, penetration, phase_margin, x0_rate};
use crate::phase::Phase;
use beam_model::shot::Integration;
use bvp_solvers::continuation::{locate, ArcControl, Arclength, Attempt, Curve};

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
    /// The contact with a peg reached the tip (`s1 = 1`): the tip slides past the point and
    /// releases it (the node at `s1 = 1`).
    TipPassed(Node),
    /// The coordinate reached the end of the branch's frame ([`crate::motion::Frame::floor`]:
    /// a corner of a path, or its last row), the node on it.
    Corner(Node),
}

/// The traced branch: its nodes in the order of the motion (x0 strictly falling; a phase
/// switch appears twice, once in each phase's variables), the switch nodes, and the end.
pub(crate) struct Trace {
    pub nodes: Vec<Node>,
    pub switches: Vec<Node>,
    pub end: End,
}

impl Trace {
    /// Solves the nodes that become rows (the switches and the end) again on `branch` (the
    /// sweep's full tolerances) from the trace's own: a switch on its phase boundary, a
    /// release at `f = 0`, any other end on the hyperplane through it normal to the branch.
    ///
    /// One-off solves from nodes on the branch whose failure ends the sweep: Newton, the trust
    /// region the fallback ([`Rescue::TrustRegion`]; the end's plane keeps it within 1e-3).
    pub(crate) fn tighten(&mut self, branch: &Branch) -> Result<()> {
        for n in &mut self.switches {
            *n = branch.correct(n.phase, n.u, Constraint::PhaseEnd, Rescue::TrustRegion)?;
        }
        if let End::TipPassed(n) = &mut self.end {
            *n = branch.correct(n.phase, n.u, Constraint::PhaseEnd, Rescue::TrustRegion)?;
            return Ok(());
        }
        if let (End::Corner(n), Some(floor)) = (&mut self.end, branch.frame.floor()) {
            let at = Constraint::BasePosition(floor);
            *n = branch.correct(n.phase, n.u, at, Rescue::TrustRegion)?;
            return Ok(());
        }
        let end = match &mut self.end {
            End::Release(n) => {
                let mut at =
                    branch.correct(n.phase, n.u, Constraint::NoForce, Rescue::TrustRegion)?;
                at.state.f = at.state.f.max(0.0);
                at.u[1] = at.state.f;
                *n = at;
                return Ok(());
            }
            End::TipPassed(n) | End::Corner(n) => n,
            End::Snap(n)
            | End::MultiContact(n)
            | End::OffContour(n)
            | End::AtBase(n)
            | End::NotReached(n, _) => n,
        };
        if end.u == self.nodes[0].u {
            // the first node, solved at the full tolerances already
            *end = self.nodes[0];
            return Ok(());
        }
        let t = end.tangent(&[0.0, 0.0, 0.0]);
        let plane = Constraint::Hyperplane {
            n: t,
            p: end.u,
            radius: 1e-3,
        };
        *end = branch.correct(end.phase, end.u, plane, Rescue::TrustRegion)?;
        Ok(())
    }
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

impl StepControl {
    /// The trace's steps up to `max` (the first a fifth of it, the smallest 1e-10) within
    /// the budget `max_steps`, its events located to `event_tol`, a second contact checked
    /// at every node if `check_penetration`.
    pub(crate) fn new(max: f64, max_steps: usize, event_tol: f64, check_penetration: bool) -> Self {
        StepControl {
            initial: max * 0.2,
            max,
            min: 1e-10,
            max_steps,
            event_tol,
            check_penetration,
        }
    }
}

/// The trace's integrator tolerance (at most as tight as the sweep's): its nodes guide the
/// rows' predictions, whose errors (~1e-6 from the Hermite interpolant) dwarf it, and the
/// nodes that become rows are solved again at the sweep's own ([`Trace::tighten`]). Kept
/// ten times below the second-contact margin, whose depth check runs on the trace's shots.
/// Measured on the 200-point g1 sweep (callgrind): the trace 17.8 M instructions at 1e-10,
/// 15.4 M here, the rows unchanged (30.6 M); 1e-8 saved no more (15.5 M).
const TRACE_INTEGRATION_TOL: f64 = 1e-9;

/// The trace's residual tolerance (at most as tight as the sweep's): at 1e-8 the trace is
/// cheaper (12.9 M) but the rows cost more from its coarser nodes (32.7 M against 30.6 M).
const TRACE_SOLVE_TOL: f64 = 1e-9;

/// [`trace`] from `first` at looser tolerances than `branch`'s (integrator tolerance `tol`):
/// the trace's nodes only guide the rows and bracket the events; the nodes that become rows
/// (switches, the end) are then solved again on `branch` ([`Trace::tighten`]).
pub(crate) fn trace_tightened(
    branch: &Branch,
    tol: f64,
    first: Node,
    ctl: &StepControl,
) -> Result<Trace> {
    let loose = Integration::adaptive(tol.max(TRACE_INTEGRATION_TOL));
    let trace_branch = Branch {
        integration: &loose,
        tol: branch.tol.max(TRACE_SOLVE_TOL),
        ..*branch
    };
    let mut tr = trace(&trace_branch, first, ctl)?;
    tr.tighten(branch)?;
    Ok(tr)
}

/// Penetration depth below which a second contact is not counted, and at which it is
/// located: the depth of [`penetration`] excludes the contact point's basin and is bounded
/// on the dense elastica to 1e-13, so the margin only absorbs the shape's integration error
/// (its tolerance 1e-10); the located row lies that far inside at most.
const PENETRATION_MARGIN: f64 = 1e-10;

/// A step below which a rise of x0 is the turning point itself (x0 stationary within the
/// shots' accuracy).
const SNAP_STEP: f64 = 1e-7;

/// Corrector iterations from which the next step is shortened (a prediction that far off
/// costs more shots than the shorter step saves).
const HARD: usize = 6;

/// Longest step over which an event is located (longer steps are shrunk first).
const EVENT_BRACKET: f64 = 0.02;

/// The events checked after each step, in the order they are reported at equal position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Event {
    Switch,
    Release,
    Snap,
    SecondContact,
    /// The whisker next to the contact point touching ([`near_margin`]).
    Touch,
    AtBase,
    /// The coordinate reaching the end of the frame (a path's next row).
    Corner,
}

/// The contact arc length at which a tangential contact has slid down to the base: the
/// obstacle reaches the base's path and the single-contact sweep ends there.
pub(crate) const BASE_CONTACT: f64 = 1e-2;

impl Event {
    /// Whether the event has happened at `node` (its condition crossed; `tn` the tangent
    /// there). The second contact is not checked here: it costs a shot of its own.
    fn passed(self, branch: &Branch, node: &Node, tn: &[f64; 3]) -> bool {
        match self {
            Event::Switch => phase_margin(node) <= 0.0,
            Event::Release => node.state.f < 0.0,
            Event::Snap => node.x0_rate(tn) >= 0.0,
            Event::AtBase => node.phase == Phase::B && node.state.s1 <= BASE_CONTACT,
            Event::Touch => near_margin(branch.whisker, branch.profile, node) <= 0.0,
            Event::SecondContact => false,
            Event::Corner => branch.frame.floor().is_some_and(|c| node.x0() <= c),
        }
    }

    /// The event's condition, positive before the event and zero at it (`t_ref` the
    /// tangent that orients the snap's x0 rate).
    fn condition(self, branch: &Branch, n: &Node, t_ref: &[f64; 3]) -> Result<f64> {
        Ok(match self {
            Event::Switch => phase_margin(n),
            Event::Release => n.state.f,
            Event::Snap => -x0_rate(n, t_ref),
            Event::AtBase => n.state.s1 - BASE_CONTACT,
            Event::Touch => near_margin(branch.whisker, branch.profile, n),
            Event::SecondContact => PENETRATION_MARGIN - depth(branch, n)?,
            Event::Corner => n.x0() - branch.frame.floor().unwrap_or(f64::NEG_INFINITY),
        })
    }

    /// The constraint that puts a corrected node on the event directly (switch and
    /// release), `None` for events located along the chord.
    fn constraint(self, branch: &Branch) -> Option<Constraint> {
        match self {
            Event::Switch => Some(Constraint::PhaseEnd),
            Event::Release => Some(Constraint::NoForce),
            Event::Corner => branch.frame.floor().map(Constraint::BasePosition),
            _ => None,
        }
    }

    /// How the trace ends at the event located at `at` (`None`: a phase switch, the trace
    /// goes on).
    fn end(self, at: Node) -> Option<End> {
        match self {
            Event::Release => Some(End::Release(at)),
            Event::Snap => Some(End::Snap(at)),
            Event::SecondContact | Event::Touch => Some(End::MultiContact(at)),
            Event::AtBase => Some(End::AtBase(at)),
            Event::Corner => Some(End::Corner(at)),
            Event::Switch => None,
        }
    }
}

/// Penetration depth of the rest of the whisker into the contour at `n` ([`penetration`]).
fn depth(branch: &Branch, n: &Node) -> Result<f64> {
    penetration(branch.whisker, branch.flow, branch.profile, &n.state)
}

/// The contact branch of one phase as a curve in `(v, f, t)` for the arclength driver: the
/// hyperplane corrector of [`Branch::correct`], the tangent of [`Node::tangent`], and a step
/// measured with the force relative to its size, `|(dv, df/F, dt)|` with `F = max(1, |f|)`:
/// forces that grow large (a contact sliding to the base) are followed in proportion, not
/// in unit steps.
pub(crate) struct PhaseCurve<'b, 'a> {
    pub branch: &'b Branch<'a>,
    pub phase: Phase,
    /// The nodes the corrections start from (the current one, and the one before it on
    /// this branch): their branch Jacobians, extrapolated to the prediction, start each
    /// corrector in place of one evaluated there ([`PhaseCurve::jacobian_at`]).
    pub near: Option<(Node, Option<Node>)>,
}

impl PhaseCurve<'_, '_> {
    /// The branch Jacobian at `p` predicted from the current node `a` and the one before,
    /// `b`: linear extrapolation along the chord `b -> a` (an error `O(h^2)` for a step `h`,
    /// against `O(h)` of `a`'s own, so Broyden's method starts from a contraction of ~1e-3
    /// rather than ~1e-2); `a`'s own without `b`.
    fn jacobian_at(&self, p: &[f64; 3]) -> Option<[[f64; 3]; 3]> {
        let (a, b) = self.near.as_ref()?;
        let Some(b) = b else {
            return Some(a.jac);
        };
        let chord = crate::branch::sub(&a.u, &b.u);
        let len2 = dot(&chord, &chord);
        if len2 <= 0.0 || len2.is_nan() {
            return Some(a.jac);
        }
        let w = dot(&crate::branch::sub(p, &a.u), &chord) / len2;
        let mut j = a.jac;
        for (row, (ra, rb)) in j.iter_mut().zip(a.jac.iter().zip(&b.jac)) {
            for k in 0..3 {
                row[k] = ra[k] + w * (ra[k] - rb[k]);
            }
        }
        Some(j)
    }
}

impl Curve<3> for PhaseCurve<'_, '_> {
    type Point = Node;
    type Error = ContactError;

    fn coords(&self, p: &Node) -> [f64; 3] {
        p.u
    }

    /// The pseudo-arclength corrector: Newton alone ([`Rescue::NewtonOnly`]). Its failure is
    /// the arclength driver's signal to shorten the step; a trust-region rescue would spend
    /// shots on every rejected step and could converge on another part of the branch (the
    /// jump the short step and the hyperplane's radius exist to prevent).
    fn correct(&self, _from: &Node, p: [f64; 3], n: [f64; 3], radius: f64) -> Result<Node> {
        let plane = Constraint::Hyperplane { n, p, radius };
        let near = self.jacobian_at(&p);
        self.branch
            .correct_near(self.phase, p, plane, near.as_ref(), Rescue::NewtonOnly)
    }

    fn tangent(&self, p: &Node, dir: &[f64; 3]) -> [f64; 3] {
        p.tangent(dir)
    }

    fn iterations(&self, p: &Node) -> usize {
        p.state.iterations as usize
    }

    fn step_length(&self, p: &Node, t: &[f64; 3]) -> f64 {
        let fscale = p.state.f.abs().max(1.0);
        (t[0] * t[0] + (t[1] / fscale).powi(2) + t[2] * t[2]).sqrt()
    }
}

/// The state of a trace: the nodes so far and the arclength driver on the current phase's
/// branch.
struct Tracer<'b, 'a> {
    branch: &'b Branch<'a>,
    ctl: &'b StepControl,
    nodes: Vec<Node>,
    switches: Vec<Node>,
    arc: Arclength<Node, 3>,
    /// Where a second core checks the accepted nodes for a second contact while the trace
    /// goes on ([`crate::ahead`]; each with the trace's state before it); `None`: each is
    /// checked before it is accepted.
    ahead: Option<Ahead<Node, Before>>,
}

/// The trace's state before a node was accepted: the driver, the counts of nodes and
/// switches.
type Before = (Arclength<Node, 3>, usize, usize);

/// Traces the branch from `first` until it separates. Where a second core exists the
/// second-contact checks run on it while the trace goes on ([`crate::ahead`]); the trace is
/// step for step the same either way.
fn trace(branch: &Branch, first: Node, ctl: &StepControl) -> Result<Trace> {
    if !ctl.check_penetration {
        return trace_with(branch, first, ctl, None);
    }
    let check = |n: &Node| Ok(depth(branch, n)? > PENETRATION_MARGIN);
    with_checks(check, |ahead| trace_with(branch, first, ctl, ahead))
}

/// [`trace`], the second-contact checks ahead on another thread where `ahead` is given.
fn trace_with(
    branch: &Branch,
    first: Node,
    ctl: &StepControl,
    ahead: Option<Ahead<Node, Before>>,
) -> Result<Trace> {
    let down = [-first.jac[2][0], -first.jac[2][1], -first.jac[2][2]];
    if ctl.check_penetration {
        let depth = depth(branch, &first)?;
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
    let curve = PhaseCurve {
        branch,
        phase: first.phase,
        near: None,
    };
    let arc_ctl = ArcControl {
        initial: ctl.initial,
        max: ctl.max,
        min: ctl.min,
        hard: HARD,
        ..ArcControl::default()
    };
    let mut tr = Tracer {
        branch,
        ctl,
        nodes: vec![first],
        switches: Vec::new(),
        arc: Arclength::new(&curve, first, down, arc_ctl),
        ahead,
    };
    if x0_rate(&first, tr.arc.tangent()) >= 0.0 {
        return Ok(tr.finish(End::Snap(first)));
    }
    for _ in 0..ctl.max_steps {
        let attempt = tr.arc.attempt(&tr.curve());
        let next = tr.step(attempt);
        // the checks of the nodes accepted ahead of them: those that have come, and all
        // before the trace ends or fails; a node that penetrates takes the trace back to
        // its acceptance, where it is the second-contact event
        let decides = !matches!(next, Ok(None));
        if let Some(node) = tr.take_back(decides)? {
            match tr.handle(&[Event::SecondContact], &node)? {
                Some(end) => return Ok(tr.finish(end)),
                None => continue,
            }
        }
        if let Some(end) = next? {
            return Ok(tr.finish(end));
        }
    }
    if let Some(node) = tr.take_back(true)? {
        if let Some(end) = tr.handle(&[Event::SecondContact], &node)? {
            return Ok(tr.finish(end));
        }
    }
    let end = End::NotReached(*tr.cur(), ctl.max_steps);
    Ok(tr.finish(end))
}

impl<'b, 'a> Tracer<'b, 'a> {
    /// The trace as it ends.
    fn finish(self, end: End) -> Trace {
        Trace {
            nodes: self.nodes,
            switches: self.switches,
            end,
        }
    }

    /// The branch of the current phase.
    fn curve(&self) -> PhaseCurve<'b, 'a> {
        PhaseCurve {
            branch: self.branch,
            phase: self.cur().phase,
            near: Some((*self.cur(), self.previous())),
        }
    }

    /// The node before the current one, if it lies on the same phase's branch.
    fn previous(&self) -> Option<Node> {
        let cur = self.cur();
        let n = self.nodes.len();
        (n >= 2 && self.nodes[n - 1].u == cur.u)
            .then(|| self.nodes[n - 2])
            .filter(|b| b.phase == cur.phase && b.u != cur.u)
    }

    /// The current node.
    fn cur(&self) -> &Node {
        self.arc.current()
    }

    /// The error of a trace that cannot go on from the current node.
    fn stalled(&self, reason: String) -> ContactError {
        let cur = self.cur();
        ContactError::BranchStalled {
            phase: cur.phase,
            x0: cur.x0(),
            xc: cur.state.point.xc,
            step: self.arc.step(),
            reason,
        }
    }

    /// The events passed between the current node and `node` (the second contact checked,
    /// at the cost of a shot, only for a step that is otherwise accepted, and then on the
    /// other thread where the checks run ahead).
    fn events(&self, node: &Node, tn: &[f64; 3]) -> Result<Vec<Event>> {
        let cur = self.cur();
        let mut events: Vec<Event> = [
            Event::Switch,
            Event::Release,
            Event::Snap,
            Event::AtBase,
            Event::Touch,
            Event::Corner,
        ]
        .into_iter()
        .filter(|ev| {
            ev.passed(self.branch, node, tn)
                && (*ev != Event::Touch || self.ctl.check_penetration)
                // the touch only where it is crossed within the step (a phase's first node
                // that starts beyond it ends the trace at the switch)
                && (*ev != Event::Touch || !ev.passed(self.branch, cur, tn))
        })
        .collect();
        if events.is_empty()
            && self.ctl.check_penetration
            && self.ahead.is_none()
            && depth(self.branch, node)? > PENETRATION_MARGIN
        {
            events.push(Event::SecondContact);
        }
        Ok(events)
    }

    /// Accepts `node` when x0 fell (the driver then grows the step after an easy
    /// correction); a rise of x0 shrinks the step, or is the snap's turning point on a tiny
    /// step.
    fn advance(&mut self, node: Node, tn: [f64; 3]) -> Result<Option<End>> {
        if node.x0() >= self.cur().x0() {
            // x0 must fall along an oriented tangent with a negative rate at both ends;
            // a rise means the step jumped over a pair of turning points, or, on a tiny
            // step, that x0 is stationary to within the shots' accuracy: the turning
            // point of the snap, reached within the step.
            if self.arc.step() < SNAP_STEP {
                return Ok(Some(End::Snap(*self.cur())));
            }
            if !self.arc.shorten(0.5, false) {
                return Err(self.stalled("x0 rose between two nodes".into()));
            }
            return Ok(None);
        }
        if let Some(ahead) = &mut self.ahead {
            let before = (self.arc.clone(), self.nodes.len(), self.switches.len());
            ahead.submit(node, before);
        }
        self.arc.accept(&self.curve(), node, tn);
        self.nodes.push(node);
        Ok(None)
    }

    /// Collects the second-contact checks of the nodes accepted ahead of them: those that
    /// have come, or (`wait`) all. A node that penetrates is taken back with the nodes after
    /// it (the trace returns to its state before the node was accepted) and returned, to be
    /// handled as the event it is.
    ///
    /// # Errors
    /// The first check's error.
    fn take_back(&mut self, wait: bool) -> Result<Option<Node>> {
        let Some(ahead) = &mut self.ahead else {
            return Ok(None);
        };
        let Some((node, (arc, nodes, switches))) = ahead.collect(wait)? else {
            return Ok(None);
        };
        self.arc = arc;
        self.nodes.truncate(nodes);
        self.switches.truncate(switches);
        Ok(Some(node))
    }

    /// One step from the attempt's outcome: a node without events is accepted, the
    /// earliest event is handled; a failure below the smallest step stalls the trace
    /// (leaving the contour ends it). `Some`: the trace ends.
    fn step(&mut self, attempt: Attempt<Node, ContactError, 3>) -> Result<Option<End>> {
        let (node, tn) = match attempt {
            Attempt::Point(node, tn) => (node, tn),
            Attempt::Retry => return Ok(None),
            Attempt::Failed(ContactError::LeftContour { .. }) => {
                return Ok(Some(End::OffContour(*self.cur())))
            }
            Attempt::Failed(e) => return Err(self.stalled(e.to_string())),
        };
        let events = self.events(&node, &tn)?;
        if events.is_empty() {
            self.advance(node, tn)
        } else {
            self.handle(&events, &node)
        }
    }

    /// Handles the `events` passed between the current node and `node`: the earliest is
    /// located; a phase switch continues on the other branch, any other event ends the trace
    /// (`Some`). `None` also when the step was shrunk first.
    fn handle(&mut self, events: &[Event], node: &Node) -> Result<Option<End>> {
        let Some((ev, at)) = self.earliest(events, node)? else {
            return Ok(None);
        };
        let cur = self.cur();
        if at.u != cur.u && at.x0() < cur.x0() {
            self.nodes.push(at);
        }
        if let Some(end) = ev.end(at) {
            return Ok(Some(end));
        }
        if self.branch.profile.is_peg() {
            // a peg has no tip contact: the tip slides past it
            return Ok(Some(End::TipPassed(at)));
        }
        self.switch(at)
    }

    /// The earliest of `events` between the current node and `node`, located; `None` when
    /// the step was shrunk first. A second contact before it takes its place.
    ///
    /// Switches and releases alone are solved directly, with the event condition as the
    /// third equation from the secant point of the bracket. Other events are located along
    /// the chord in short brackets ([`Arclength::earliest`]), where the chord stays close to
    /// the branch: longer steps are shrunk first (this also separates several events).
    fn earliest(&mut self, events: &[Event], node: &Node) -> Result<Option<(Event, Node)>> {
        let mut best = match events {
            [ev] => self.direct(*ev, node),
            _ => None,
        };
        let (h, min) = (self.arc.step(), self.ctl.min);
        if best.is_none() {
            if h > EVENT_BRACKET || (events.len() > 1 && h > 64.0 * min) {
                self.arc.shorten(0.25, true);
                return Ok(None);
            }
            let (branch, t) = (self.branch, self.arc.tangent());
            let conditions: Vec<_> = events
                .iter()
                .map(|&ev| (ev, move |n: &Node| ev.condition(branch, n, t)))
                .collect();
            best = self
                .arc
                .earliest(&self.curve(), node, &conditions, self.ctl.event_tol)?;
        }
        // A second contact before the located event ends the trace there.
        if let Some((ev, at)) = best {
            if ev != Event::SecondContact
                && self.ctl.check_penetration
                && depth(self.branch, &at)? > PENETRATION_MARGIN
            {
                let t = self.arc.tangent();
                let g = |n: &Node| Event::SecondContact.condition(self.branch, n, t);
                let sc = locate(&self.curve(), self.cur(), &at, &g, self.ctl.event_tol)?;
                best = Some((Event::SecondContact, sc));
            }
        }
        Ok(best)
    }

    /// A switch or a release solved directly from the secant point of its condition over
    /// the step to `node` (`None` for other events, or if the solve fails or lands outside
    /// the step). Newton alone ([`Rescue::NewtonOnly`]): this is a fast attempt, and where it
    /// fails the caller locates the event on the traced step itself, which cannot leave it.
    fn direct(&self, ev: Event, node: &Node) -> Option<(Event, Node)> {
        let c = ev.constraint(self.branch)?;
        let cur = self.cur();
        let g = |n: &Node| {
            ev.condition(self.branch, n, self.arc.tangent())
                .unwrap_or(f64::NAN)
        };
        let (ga, gb) = (g(cur), g(node));
        let w = ga / (ga - gb);
        let p = crate::branch::lerp(&cur.u, &node.u, w);
        let mut at = self
            .branch
            .correct(cur.phase, p, c, Rescue::NewtonOnly)
            .ok()?;
        if ev == Event::Release {
            // f = 0 to the corrector's tolerance: the release row carries f = 0
            at.state.f = at.state.f.max(0.0);
            at.u[1] = at.state.f;
        }
        let d = crate::branch::sub(&node.u, &cur.u);
        let along = dot(&crate::branch::sub(&at.u, &cur.u), &d) / dot(&d, &d);
        (along > -1e-12 && along < 1.0 + 1e-12 && at.x0() <= cur.x0()).then_some((ev, at))
    }

    /// Continues on the other phase's branch at the switch node `at`; `Some(snap)` when
    /// that branch leaves towards larger x0.
    fn switch(&mut self, at: Node) -> Result<Option<End>> {
        let (next, tn) = switch_phase(self.branch, &at)?;
        // the switch row in tip-contact form: s1 = 1 exactly, phi1 = psi
        self.switches
            .push(if next.phase == Phase::A { next } else { at });
        if x0_rate(&next, &tn) >= 0.0 {
            // The other phase's branch leaves towards larger x0: no quasi-static
            // continuation, the whisker snaps off at the switch.
            return Ok(Some(End::Snap(at)));
        }
        if self.ctl.check_penetration
            && next.phase == Phase::B
            && near_margin(self.branch.whisker, self.branch.profile, &next) <= 0.0
        {
            // the tangential phase starts with the whisker bending into the contour on both
            // sides of the contact point
            return Ok(Some(End::MultiContact(at)));
        }
        self.nodes.push(next);
        let curve = PhaseCurve {
            branch: self.branch,
            phase: next.phase,
            near: None,
        };
        self.arc.restart(&curve, next, tn, self.ctl.initial);
        Ok(None)
    }
}

/// The node of the other phase at a switch node `at` (where `phi1 = psi` and `s1 = 1`), with
/// the tangent that enters the new phase's valid side. A one-off solve whose failure ends the
/// trace: Newton, with the trust region as the fallback ([`Rescue::TrustRegion`]).
fn switch_phase(branch: &Branch, at: &Node) -> Result<(Node, [f64; 3])> {
    let (phase, u) = match at.phase {
        Phase::B => (Phase::A, [at.state.point.psi, at.u[1], at.u[2]]),
        _ => (Phase::B, [1.0, at.u[1], at.u[2]]),
    };
    let next = branch.correct(
        phase,
        u,
        Constraint::BasePosition(at.x0()),
        Rescue::TrustRegion,
    )?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::branch::tests::TestScene;
    use crate::first_contact::{first_node, first_touch, free_tip};

    /// The traced branch from a first touch: x0 never rises from node to node, every node
    /// solves the branch equations again (a fresh evaluation), and every switch node lies
    /// on its phase's end.
    #[test]
    fn the_trace_follows_the_branch_to_its_end() {
        let s = TestScene::bent(1e-12);
        let branch = s.branch();
        let phi1 = free_tip(&s.whisker, s.flow, 1e-12, &s.integration).unwrap();
        let touch = first_touch(&s.whisker, s.flow, phi1, &s.profile, 1e-12).unwrap();
        let first = first_node(&branch, &touch).unwrap();
        let ctl = StepControl::new(0.2, 20_000, 1e-10, false);
        let tr = trace_tightened(&branch, 1e-12, first, &ctl).unwrap();
        assert!(tr.nodes.len() > 5 && !matches!(tr.end, End::NotReached(..)));
        for w in tr.nodes.windows(2) {
            assert!(w[1].x0() <= w[0].x0(), "{} after {}", w[1].x0(), w[0].x0());
        }
        for n in &tr.nodes {
            let (r, _) = branch.eval(n.phase, n.u).unwrap();
            assert!(r[0].hypot(r[1]) < 1e-8, "{r:?}");
        }
        assert!(!tr.switches.is_empty());
        for n in &tr.switches {
            assert!(phase_margin(n).abs() < 1e-9, "{}", phase_margin(n));
        }
    }
}
