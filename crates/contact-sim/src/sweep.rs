//! The quasi-static sweep (thesis ch. 5, Fig. 5.6), driven by the quantity the experimenter
//! moves, the base position x0: the whisker under the flow alone, the exact first contact
//! ([`crate::first_contact`]), the contact branch followed by continuation in x0 through
//! phase switches and folds of the contact point (`continuation`), events located on
//! the branch (`events`), and the rows of the log assembled here: pre-contact rows,
//! then contact rows evenly spaced in x0 from the first contact to the separation, plus one
//! row at each phase switch.

use crate::accuracy::{row_branch, row_integration_tol, RowIntegration, Rows, SweepAccuracy};
use crate::branch::{Branch, Node};
use crate::contact_law::Tilt;
use crate::continuation::{trace_tightened, End, StepControl, Trace};
use crate::error::{ContactError, Result};
use crate::first_contact::first_node;
pub use crate::first_contact::{FirstContact, FirstTouch};
use crate::motion::Frame;
use crate::phase::{ContactState, Phase};
use crate::profile::Profile;
use beam_model::equations::Sensitivities;
use beam_model::shot::{shoot, Integration};
use beam_model::{FluidLoad, Loads, Whisker};
use serde::{Deserialize, Serialize};

/// Largest number of contact rows a sweep accepts.
pub const MAX_POINTS: usize = 100_000;

/// Settings of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepSettings {
    /// Contact rows from the first contact to the separation (both included), evenly spaced
    /// in the base position x0; one row per phase switch is added. At least 2, at most
    /// [`MAX_POINTS`].
    pub points: usize,
    /// Rows before contact (flow only), spaced `pre_contact_spacing` in x0.
    pub pre_contact_rows: usize,
    /// Spacing of the pre-contact rows in x0.
    pub pre_contact_spacing: f64,
    /// Integrator tolerance of the shots.
    pub integration_tol: f64,
    /// Residual tolerance of the phase solves.
    pub solve_tol: f64,
    /// Location tolerance of events in the branch state `(phi1 or s1, f, t)`.
    pub event_tol: f64,
    /// Whether to check at every node that no other part of the whisker enters the obstacle.
    pub check_penetration: bool,
    /// Step budget of the continuation along the contact branch.
    pub max_steps: usize,
    /// Largest continuation step (in the branch state). The default, 0.2, keeps the traced
    /// nodes close enough for the rows' predictions to converge in two or three shots
    /// (measured on seven CLI scenes: 1.0 left fewer, costlier nodes and more expensive rows,
    /// with the same answers).
    pub max_step: f64,
    /// The accuracy asked for of every row (absolute, in [1e-12, 1e-2]): the contact rows
    /// solved at tolerances derived from it, each row given an a-posteriori error estimate
    /// ([`crate::accuracy`]), and the sweep refused when a row's estimate exceeds it. `None`
    /// (the default): the rows at `integration_tol` and `solve_tol`, without estimates.
    #[serde(default)]
    pub accuracy: Option<f64>,
    /// The law of the contact force ([`crate::friction`]): frictionless (the default) or
    /// Coulomb friction; `mu = 0` is the frictionless sweep exactly.
    #[serde(default)]
    pub contact_law: crate::contact_law::ContactLaw,
    /// How the base moves ([`crate::motion`]): translate (the default, the thesis's sweep),
    /// rotate (whisking), or a path of poses ([`crate::path`]). The rows are evenly spaced
    /// in the motion's coordinate (x0, gamma, or the path parameter p).
    #[serde(default)]
    pub motion: crate::motion::BaseMotion,
}

impl Default for SweepSettings {
    fn default() -> Self {
        SweepSettings {
            points: 200,
            pre_contact_rows: 10,
            pre_contact_spacing: 0.05,
            integration_tol: 1e-12,
            solve_tol: 1e-11,
            event_tol: 1e-10,
            check_penetration: true,
            max_steps: 20_000,
            max_step: 0.2,
            accuracy: None,
            contact_law: crate::contact_law::ContactLaw::Frictionless,
            motion: crate::motion::BaseMotion::Translate,
        }
    }
}

/// One row of the observables log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepPoint {
    /// Base position.
    pub x0: f64,
    /// Horizontal base reaction.
    pub ax: f64,
    /// Vertical base reaction.
    pub ay: f64,
    /// Base moment reaction.
    pub ma: f64,
    /// Base angle.
    pub phi0: f64,
    /// Contact force (0 before contact).
    pub f: f64,
    /// Contact arc length (1 before contact and in phase A).
    pub s1: f64,
    /// Tangent angle at s1 (`psi` in phase B; the free tip angle before contact).
    pub phi1: f64,
    /// Phase.
    pub phase: Phase,
    /// Contact point x (NaN before contact).
    pub xc: f64,
    /// Contact point y (NaN before contact).
    pub yc: f64,
    /// Contour angle at the contact point (NaN before contact).
    pub psi: f64,
    /// Tangential part of the contact force along the boundary's tangent
    /// `(cos psi, sin psi)` (0 without friction and before contact); `f` is the normal part.
    #[serde(default)]
    pub ft: f64,
    /// Stick, slip, or none (before contact and without friction).
    #[serde(default)]
    pub slip: crate::contact_law::SlipState,
    /// The touching material point's slip displacement since the first touch: the signed
    /// arc length along the contour (towards +x) it has slid, `sigma - s1` less its value at
    /// the touch (`sigma` the contact point's arc length; in tip contact the contact point's
    /// arc length from the first touch); constant while stuck, 0 without friction.
    #[serde(default)]
    pub slip_distance: f64,
    /// Base y of the row's pose (0 for a translation; [`crate::motion`]).
    #[serde(default)]
    pub y0: f64,
    /// Turn of the follicle at the row (rad, counter-clockwise; 0 for a translation): the
    /// unloaded base direction is `pi/2 + gamma`, so `phi0 = pi/2 + gamma - MA/k`.
    #[serde(default)]
    pub gamma: f64,
    /// The follicle stiffness at the row, where the motion (a path) sets it.
    #[serde(default)]
    pub k: Option<f64>,
}

/// How the contact ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Separation {
    /// Separation 1: x0 reached a local minimum and the whisker snaps off.
    Snap,
    /// Separation 2: the contact force fell to zero.
    Release,
    /// A second point of the whisker would enter the obstacle at this contour point; the
    /// single-contact model stops there.
    MultiContact {
        /// The contour point where it was detected.
        xc: f64,
    },
    /// The contact point reached the end of the contour (a table's last knot, a circle's
    /// vertical end) before separation.
    EndOfContour,
    /// The contact point slid down the whisker to the base (s1 = 0.01): the obstacle reaches
    /// the base's path, and the sweep cannot go on.
    ContactAtBase,
    /// The tip slid past a peg (the contact reached `s1 = 1`) and released it.
    TipPassed,
    /// The path of poses ended while the whisker was still in contact ([`crate::path`]):
    /// the sweep ends at its last row.
    PathEnd,
    /// No separation within the continuation's step budget.
    NotReached {
        /// The steps taken.
        steps: usize,
    },
}

/// How the outputs name the separation: `snap`, `release`, `second contact`, `end of
/// contour`, `contact at the base`, `tip passed the peg`, `end of the path` or `not reached within N
/// steps`.
impl std::fmt::Display for Separation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Separation::Snap => f.write_str("snap"),
            Separation::Release => f.write_str("release"),
            Separation::MultiContact { .. } => f.write_str("second contact"),
            Separation::EndOfContour => f.write_str("end of contour"),
            Separation::ContactAtBase => f.write_str("contact at the base"),
            Separation::TipPassed => f.write_str("tip passed the peg"),
            Separation::PathEnd => f.write_str("end of the path"),
            Separation::NotReached { steps } => write!(f, "not reached within {steps} steps"),
        }
    }
}

/// A complete sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepResult {
    /// Fluid load q.
    pub q: f64,
    /// Flow angle alpha (rad): the flow is `q (cos alpha, -sin alpha)` on `[0, s1]`.
    pub alpha: f64,
    /// The rows in the order of the motion (x0 strictly decreasing in a translation, gamma
    /// strictly increasing in a rotation, the path parameter strictly increasing along a
    /// path), pre-contact rows first.
    pub points: Vec<SweepPoint>,
    /// How the contact began.
    pub first_contact: FirstContact,
    /// The free whisker's first touch, exact: touching arc length, contour point, x0.
    pub first_touch: FirstTouch,
    /// How it ended.
    pub separation: Separation,
    /// With `SweepSettings::accuracy`: the accuracy asked for and every row's estimate.
    #[serde(default)]
    pub accuracy: Option<SweepAccuracy>,
    /// The stick/slip switches of a frictional sweep, in the order of the motion (empty
    /// without friction).
    #[serde(default)]
    pub friction_events: Vec<crate::contact_law::FrictionEvent>,
}

impl SweepResult {
    /// The rows in contact.
    pub fn contact_points(&self) -> impl Iterator<Item = &SweepPoint> {
        self.points.iter().filter(|p| p.phase != Phase::None)
    }

    /// The sequence of phases in contact, e.g. `"AB"`, `"BA"`, `"A"`.
    pub fn phase_pattern(&self) -> String {
        let mut s = String::new();
        for p in self.contact_points() {
            let c = p.phase.letter();
            if !s.ends_with(c) {
                s.push(c);
            }
        }
        s
    }
}

impl SweepPoint {
    /// The row of the contact state `st` (its `x0` the motion's falling coordinate in
    /// `frame`); under a tilt (a sliding frictional contact) with `ft = s mu f` and
    /// `slip = slip` (the slip distance is the frictional sweep's).
    pub(crate) fn from_state(st: &ContactState, flow: FluidLoad, frame: Frame) -> Self {
        let (ax, ay, ma, phi0) = st.observables(flow);
        let pose = frame.pose(st.x0);
        SweepPoint {
            x0: pose.x0,
            ax,
            ay,
            ma,
            phi0,
            f: st.f,
            s1: st.s1,
            phi1: st.phi1,
            phase: st.phase,
            xc: st.point.xc,
            yc: st.point.yc,
            psi: st.point.psi,
            ft: st.tilt.ft(st.f),
            slip: if st.tilt.is_none() {
                crate::contact_law::SlipState::None
            } else {
                crate::contact_law::SlipState::Slip
            },
            slip_distance: 0.0,
            y0: pose.y0,
            gamma: pose.gamma,
            k: None,
        }
    }

    /// The loads of this row under `flow`: the flow alone before contact; the flow on
    /// `[0, s1]` and the contact force at `s1` in contact [6.8, 6.9]
    /// ([`contact_loads`](crate::phase::contact_loads)).
    pub fn loads(&self, flow: FluidLoad) -> Loads {
        match self.phase {
            Phase::None => crate::phase::contact_loads(flow, 0.0, 0.0, 1.0),
            _ => crate::contact_law::frictional_loads(flow, self.psi, self.f, self.ft, self.s1),
        }
    }

    /// The whole whisker at this row (positions relative to the base; the free whisker under
    /// the flow before contact): one DOP853 integration at tolerance `tol` from the loaded
    /// end at the row's tip angle, `samples` intervals, then the load-free segment beyond a
    /// tangential contact ([`beam_model::shape_from_tip_angle`]). What the figures draw and
    /// the second-contact check looks at.
    ///
    /// # Errors
    /// The integration's error.
    pub fn shape(
        &self,
        whisker: &Whisker,
        flow: FluidLoad,
        tol: f64,
        samples: usize,
    ) -> std::result::Result<beam_model::Solution, beam_model::ModelError> {
        let scene = beam_model::Scene::new(*whisker, self.loads(flow));
        beam_model::shape_from_tip_angle(&scene, self.phi1, tol, samples)
    }
}

/// Progress of a running sweep, reported to [`crate::driver::sweep_with_progress`]'s callback.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepProgress {
    /// The continuation along the contact branch towards the separation: steps done.
    Coarse {
        /// Steps done.
        steps: usize,
    },
    /// The rows at evenly spaced base positions: rows done out of the requested number.
    Fine {
        /// Points done.
        done: usize,
        /// Points requested.
        total: usize,
    },
}

/// The frictionless contact branch of a sweep ([`crate::driver::sweep_with_progress`]) from
/// its exact first touch `touch` (the free whisker's tip angle `phi1`): followed to the
/// separation, then its rows at evenly spaced base positions with their estimates.
pub(crate) fn frictionless(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
    (phi1, touch): (f64, FirstTouch),
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<SweepResult> {
    let scene = (whisker, flow, profile);
    let untilted = (Tilt::NONE, &(|_: &[Node]| Ok(())) as &SlideCheck<'_>);
    contact_sweep(scene, settings, (phi1, touch), untilted, progress)
}

/// A check of the traced nodes before the rows are solved ([`contact_sweep`]).
pub(crate) type SlideCheck<'c> = dyn Fn(&[Node]) -> Result<()> + 'c;

/// The contact branch under the force tilted by `tilt` ([`Tilt`]; [`Tilt::NONE`]: the
/// frictionless sweep, [`frictionless`]) from the exact first touch: traced to the
/// separation, its nodes handed to `check` (a sliding frictional sweep's test that the
/// sliding never stops, [`crate::friction`]; its error ends the sweep before any row is
/// solved), then the rows at evenly spaced base positions with their estimates. The rows
/// carry `ft = s mu f` and the slip state `slip` under a tilt (their slip distance is the
/// caller's).
pub(crate) fn contact_sweep(
    (whisker, flow, profile): (&Whisker, FluidLoad, &Profile),
    settings: &SweepSettings,
    (phi1, touch): (f64, FirstTouch),
    (tilt, check): (Tilt, &SlideCheck<'_>),
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<SweepResult> {
    let integration = Integration::adaptive(settings.integration_tol);
    let frame = settings.motion.frame().unwrap_or_default();
    let branch = Branch {
        whisker,
        flow,
        profile,
        integration: &integration,
        tol: settings.solve_tol,
        frame,
        tilt,
    };
    let first = first_node(&branch, &touch)?;
    // The branch from the first contact to the separation.
    progress(SweepProgress::Coarse { steps: 0 });
    let (tr, step) = trace_seeing_switches(&branch, first, settings)?;
    check(&tr.nodes)?;
    progress(SweepProgress::Coarse {
        steps: tr.nodes.len(),
    });
    for n in &tr.nodes {
        profile.convex_at(n.u[2])?;
    }
    let (last, separation) = separation(tr.end);
    // the contact rows and their estimates at the accuracy asked for (`crate::accuracy`)
    let (states, row_accuracy) = rows_within_accuracy(settings.accuracy, step, |at| {
        let (row_branch, loose) = row_branch(&branch, at);
        crate::rows::rows(
            (&row_branch, loose.as_ref()),
            &tr.nodes,
            &tr.switches,
            (&last, hold_of(&separation)),
            settings.points,
            &mut |done, total| progress(SweepProgress::Fine { done, total }),
        )
    })?;
    let mut points = pre_contact_rows(whisker, flow, phi1, first.x0(), settings)?;
    let mut touch = touch;
    if let Frame::Rotate { .. } = frame {
        touch.x0 = frame.pose(touch.x0).x0;
    }
    points.extend(
        states
            .iter()
            .map(|(s, _)| SweepPoint::from_state(s, flow, frame)),
    );
    let accuracy = rows_accuracy(&points, &states, settings.accuracy, row_accuracy)?;
    Ok(SweepResult {
        q: flow.q,
        alpha: flow.alpha,
        points,
        first_contact: touch.kind,
        first_touch: touch,
        separation,
        accuracy,
        friction_events: Vec::new(),
    })
}

/// The contact rows with their estimates at the accuracy asked for, `accuracy` (module
/// docs): `rows_at` solves them (its branch from [`row_branch`]) at `accuracy`, and once
/// more at an accuracy [`TIGHTER`] times smaller where a row's estimate exceeds `accuracy`
/// (or is NaN) and the tighter integration is tighter indeed; returned with the accuracy
/// they were solved at.
///
/// # Errors
/// `rows_at`'s; [`ContactError::BranchStalled`] (with the step `step`) where a row lies
/// more than 1e-9 outside its phase: a phase switch between the traced nodes was missed.
pub(crate) fn rows_within_accuracy(
    accuracy: Option<f64>,
    step: f64,
    mut rows_at: impl FnMut(Option<&RowIntegration>) -> Result<Rows>,
) -> Result<(Rows, Option<f64>)> {
    let mut solve = |t: Option<f64>| rows_at(t.map(RowIntegration::new).as_ref());
    let mut states = solve(accuracy)?;
    let row_accuracy = accuracy.map(|tol| {
        let tighter = tol / TIGHTER;
        let missed = states.iter().any(|s| s.1 > tol || s.1.is_nan());
        if missed && row_integration_tol(tighter) < row_integration_tol(tol) {
            tighter
        } else {
            tol
        }
    });
    if row_accuracy != accuracy {
        states = solve(row_accuracy)?;
    }
    // never a row outside its phase (a switch missed between the traced nodes)
    if let Some((s, _)) = states.iter().find(|(s, _)| phase_violation(s) > 1e-9) {
        return Err(ContactError::BranchStalled {
            phase: s.phase,
            x0: s.x0,
            xc: s.point.xc,
            step,
            reason: format!(
                "a row violates its phase condition by {:.3e}: a phase switch between the traced nodes was missed",
                phase_violation(s)
            ),
        });
    }
    Ok((states, row_accuracy))
}

/// The accuracy report of a sweep whose `points` end in the contact rows `rows` (with their
/// estimates, solved at `row_accuracy`), where `accuracy` was asked for: the rows before
/// contact carry the first contact row's estimate (module docs).
///
/// # Errors
/// [`ContactError::AccuracyNotMet`] naming the worst row where an estimate exceeds `accuracy`.
pub(crate) fn rows_accuracy(
    points: &[SweepPoint],
    rows: &[(ContactState, f64)],
    accuracy: Option<f64>,
    row_accuracy: Option<f64>,
) -> Result<Option<SweepAccuracy>> {
    accuracy
        .zip(row_accuracy)
        .map(|(tol, at)| {
            let first_estimate = rows.first().map_or(f64::NAN, |s| s.1);
            let mut estimates = vec![first_estimate; points.len() - rows.len()];
            estimates.extend(rows.iter().map(|s| s.1));
            check_accuracy(points, estimates, tol, row_integration_tol(at))
        })
        .transpose()
}

/// The branch traced from `start` with the sweep's steps ([`trace_tightened`]), traced again
/// with steps 8x shorter, at most twice, where a phase condition dips below zero and back
/// between two traced nodes ([`crossed_unseen`]): a pair of switches the nodes did not see
/// (met whisking a tip past a flat stretch). With the largest step of the trace returned.
///
/// # Errors
/// The trace's.
pub(crate) fn trace_seeing_switches(
    branch: &Branch,
    start: Node,
    settings: &SweepSettings,
) -> Result<(Trace, f64)> {
    let mut ctl = StepControl::new(
        settings.max_step,
        settings.max_steps,
        settings.event_tol,
        settings.check_penetration,
    );
    let mut tr = trace_tightened(branch, settings.integration_tol, start, &ctl)?;
    for _ in 0..2 {
        if !crossed_unseen(branch.profile, &tr.nodes) {
            break;
        }
        ctl.initial /= 8.0;
        ctl.max /= 8.0;
        tr = trace_tightened(branch, settings.integration_tol, start, &ctl)?;
    }
    Ok((tr, ctl.max))
}

/// How far a contact state lies outside its phase: `psi - phi1` in tip contact (phase A
/// needs the tip steeper than the boundary), `s1 - 1` in tangential contact; negative inside.
pub(crate) fn phase_violation(s: &ContactState) -> f64 {
    match s.phase {
        Phase::B => s.s1 - 1.0,
        _ => s.point.psi - s.phi1,
    }
}

/// Whether the phase condition, predicted between consecutive traced nodes of one phase by
/// their cubic Hermite interpolant in the coordinate (no shots), dips below `-1e-7` at one of
/// three interior points of a step: a pair of phase switches inside the step.
pub(crate) fn crossed_unseen(profile: &Profile, nodes: &[Node]) -> bool {
    let margin = |phase: Phase, u: &[f64; 3]| match phase {
        Phase::B => 1.0 - u[0],
        _ => u[0] - profile.at(u[2]).psi,
    };
    nodes.windows(2).any(|w| {
        let (a, b) = (&w[0], &w[1]);
        if a.phase != b.phase || a.phase == Phase::None || a.x0() == b.x0() {
            return false;
        }
        let (sa, sb) = (a.slope(), b.slope());
        if !sa.iter().chain(&sb).all(|v| v.is_finite() && v.abs() < 1e3) {
            return false;
        }
        (1..4).any(|k| {
            let x = a.x0() + (b.x0() - a.x0()) * k as f64 / 4.0;
            let u = crate::branch::hermite((a.x0(), &a.u, &sa), (b.x0(), &b.u, &sb), x);
            margin(a.phase, &u) < -1e-7
        })
    })
}

/// How much tighter the rows' integration runs, once, where a row's estimate at the
/// accuracy asked for exceeds it (measured: 1 of 554 seeded random `--tol` sweeps, a
/// slender whisker, theta 0.067, whose row came out at 1.2 times T = 1e-8).
pub const TIGHTER: f64 = 10.0;

/// The accuracy of a sweep's rows with their `estimates` (rows integrated at
/// `row_integration_tol`), refused (naming the worst row) when an estimate exceeds `tol`.
pub(crate) fn check_accuracy(
    points: &[SweepPoint],
    estimates: Vec<f64>,
    tol: f64,
    row_integration_tol: f64,
) -> Result<SweepAccuracy> {
    let acc = SweepAccuracy {
        tol,
        integration_tol: row_integration_tol,
        estimates,
    };
    match acc.worst() {
        Some((row, estimate)) if estimate > tol || estimate.is_nan() => {
            Err(ContactError::AccuracyNotMet {
                row,
                x0: points[row].x0,
                estimate,
                tol,
            })
        }
        _ => Ok(acc),
    }
}

/// How the estimate of the row where the contact ended holds it: a release at zero force
/// (its defining condition), any other end at its contour point.
pub(crate) fn hold_of(separation: &Separation) -> crate::accuracy::Hold {
    match separation {
        Separation::Release => crate::accuracy::Hold::NoForce,
        _ => crate::accuracy::Hold::ContourPoint,
    }
}

/// The node where the trace ended and how the contact ended there.
pub(crate) fn separation(end: End) -> (Node, Separation) {
    match end {
        End::Snap(n) => (n, Separation::Snap),
        End::Release(n) => (n, Separation::Release),
        End::MultiContact(n) => (
            n,
            Separation::MultiContact {
                xc: n.state.point.xc,
            },
        ),
        End::OffContour(n) => (n, Separation::EndOfContour),
        End::AtBase(n) => (n, Separation::ContactAtBase),
        End::TipPassed(n) => (n, Separation::TipPassed),
        End::Corner(n) => (n, Separation::PathEnd),
        End::NotReached(n, steps) => (n, Separation::NotReached { steps }),
    }
}

/// The rows before contact (the free whisker of tip angle `phi1` under the flow alone),
/// spaced `pre_contact_spacing` in x0 before the first contact at `first_x0`.
pub(crate) fn pre_contact_rows(
    whisker: &Whisker,
    flow: FluidLoad,
    phi1: f64,
    first_x0: f64,
    settings: &SweepSettings,
) -> Result<Vec<SweepPoint>> {
    let integration = Integration::adaptive(settings.integration_tol);
    let loads = Loads::fluid(flow.q, flow.alpha);
    let free_reactions = beam_model::Reactions::balancing((0.0, 0.0), flow, 1.0);
    let mut points = Vec::with_capacity(settings.pre_contact_rows + settings.points);
    let frame = settings.motion.frame().unwrap_or_default();
    let start = settings.motion.start();
    let touch_gamma = frame.pose(first_x0).gamma;
    let mut guess = phi1 - touch_gamma;
    let mut free = shoot(whisker, &loads, phi1, Sensitivities::None, &integration)?;
    // nearest row first, each continued from the one after it in the motion (from the
    // first contact's free state): a soft follicle under flow can hold several free
    // equilibria, and Newton from the touch's angle at the farthest row could land on
    // another branch, one that passes through the obstacle (the independent checker found
    // rows 0.19 inside g2 before a rotation's first touch); reversed at the end
    for k in 1..=settings.pre_contact_rows {
        let c = first_x0 + k as f64 * settings.pre_contact_spacing;
        let pose = frame.pose(c);
        let mut phi1 = phi1;
        if let Frame::Rotate { .. } = frame {
            // the free whisker turned by gamma (rows before the rotation's start dropped)
            if c > start {
                break;
            }
            let at = (guess + pose.gamma, pose.gamma);
            phi1 = crate::first_contact::free_tip_angle(whisker, flow, at, &integration)?;
            guess = phi1 - pose.gamma;
            free = shoot(whisker, &loads, phi1, Sensitivities::None, &integration)?;
        }
        points.push(SweepPoint {
            x0: pose.x0,
            ax: free_reactions.ax,
            ay: free_reactions.ay,
            ma: -free.m0,
            phi0: free.phi0,
            f: 0.0,
            s1: 1.0,
            phi1,
            phase: Phase::None,
            xc: f64::NAN,
            yc: f64::NAN,
            psi: f64::NAN,
            ft: 0.0,
            slip: crate::contact_law::SlipState::None,
            slip_distance: 0.0,
            y0: pose.y0,
            gamma: pose.gamma,
            k: None,
        });
    }
    points.reverse();
    Ok(points)
}

/// Refuses settings the sweep cannot honour, naming the culprit.
pub(crate) fn check_settings(settings: &SweepSettings, flow: FluidLoad) -> Result<()> {
    let bad = |name, value: f64, reason| {
        Err(ContactError::InvalidParameter {
            name,
            value,
            reason,
        })
    };
    if settings.points < 2 || settings.points > MAX_POINTS {
        return bad(
            "points",
            settings.points as f64,
            "a sweep needs between 2 and 100000 contact rows",
        );
    }
    if settings.pre_contact_rows > MAX_POINTS {
        return bad(
            "pre_contact_rows",
            settings.pre_contact_rows as f64,
            "at most 100000 pre-contact rows",
        );
    }
    if !(settings.pre_contact_spacing > 0.0 && settings.pre_contact_spacing.is_finite()) {
        return bad(
            "pre_contact_spacing",
            settings.pre_contact_spacing,
            "the pre-contact spacing must be positive and finite",
        );
    }
    for (name, v) in [
        ("integration_tol", settings.integration_tol),
        ("solve_tol", settings.solve_tol),
        ("event_tol", settings.event_tol),
    ] {
        if !(1e-14..=1e-3).contains(&v) {
            return bad(name, v, "tolerances must lie in [1e-14, 1e-3]");
        }
    }
    if let Some(t) = settings.accuracy {
        if !(crate::accuracy::ACCURACY_MIN..=crate::accuracy::ACCURACY_MAX).contains(&t) {
            return bad(
                "accuracy",
                t,
                "the accuracy asked for must lie in [1e-12, 1e-2]",
            );
        }
    }
    if !(settings.max_step > 1e-6 && settings.max_step <= 1.0) {
        return bad(
            "max_step",
            settings.max_step,
            "the step must lie in (1e-6, 1]",
        );
    }
    if settings.max_steps == 0 || settings.max_steps > 1_000_000 {
        return bad(
            "max_steps",
            settings.max_steps as f64,
            "the step budget must lie in [1, 1000000]",
        );
    }
    settings.contact_law.validate()?;
    let alpha_deg = flow.alpha.to_degrees();
    if !(alpha_deg > -90.0 && alpha_deg < 90.0) {
        return bad(
            "alpha",
            flow.alpha,
            "the sweep's flow angle must lie in (-90, 90) degrees (a flow towards +x)",
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::sweep;

    /// Every row's shape passes through its contact point, and before contact its base
    /// moment is the row's (the shape is the row's equilibrium).
    #[test]
    fn a_row_gives_its_whole_shape() {
        let s = crate::branch::tests::TestScene::bent(1e-12);
        let (whisker, flow) = (s.whisker, s.flow);
        let settings = SweepSettings {
            points: 12,
            ..SweepSettings::default()
        };
        let res = sweep(&whisker, flow, &s.profile, &settings).unwrap();
        let mut contacts = 0;
        for p in &res.points {
            let sol = p.shape(&whisker, flow, 1e-12, 50).unwrap();
            assert!(
                (sol.base.ma - p.ma).abs() < 1e-9,
                "{} vs {}",
                sol.base.ma,
                p.ma
            );
            if p.phase != Phase::None {
                contacts += 1;
                let miss = (sol.loaded_end.x + p.x0 - p.xc).hypot(sol.loaded_end.y - p.yc);
                assert!(miss < 1e-9, "row at x0 = {}: {miss:e}", p.x0);
            }
        }
        assert!(contacts >= 8, "{contacts}");
    }

    /// How the outputs (the CLI's text, JSON and figures; the chapter-5 tables) name the
    /// first contact and the separation.
    #[test]
    fn events_are_named_for_the_outputs() {
        assert_eq!(FirstContact::Tip.label(), "tip");
        assert_eq!(FirstContact::Tangential.label(), "tangential");
        assert_eq!(Separation::Snap.to_string(), "snap");
        assert_eq!(
            Separation::MultiContact { xc: 0.1 }.to_string(),
            "second contact"
        );
        assert_eq!(
            Separation::NotReached { steps: 3 }.to_string(),
            "not reached within 3 steps"
        );
    }

    /// A straight tapered whisker on a very soft follicle (k 0.346) under a slanted flow,
    /// whisked against g2 from -18.1 deg: the free whisker has more than one equilibrium.
    /// The rows before contact were solved from the touch's tip angle with the row's turn
    /// added twice, on another branch than the first contact row: phi0 jumped by 0.61 rad
    /// between the last of them and the touch, and they lay up to 0.19 inside g2 (found by
    /// the independent scipy checker, docs/independent-check.md). Now they continue the
    /// touch's own free state: phi0 and MA change smoothly into the first contact row.
    #[test]
    fn the_rows_before_a_rotations_touch_are_the_touchs_branch() {
        let whisker = Whisker::new(0.6580015840243402, 0.0, 0.0, 0.34643591083394776);
        let flow = FluidLoad {
            q: 1.8112224116927877,
            alpha: 24.52336367102997f64.to_radians(),
        };
        let settings = SweepSettings {
            points: 32,
            motion: crate::BaseMotion::Rotate {
                x0: 0.11764471190460174,
                y0: -0.2629620620730149,
                gamma0: (-18.13872639218409f64).to_radians(),
            },
            ..SweepSettings::default()
        };
        let res = sweep(&whisker, flow, &Profile::g2(), &settings).unwrap();
        let first = res
            .points
            .iter()
            .position(|p| p.phase != Phase::None)
            .unwrap();
        assert_eq!(first, 10);
        for w in res.points[..=first].windows(2) {
            let dgamma = w[1].gamma - w[0].gamma;
            assert!(dgamma > 0.0 && dgamma <= 0.05 + 1e-12, "{dgamma}");
            // a free whisker turned by dgamma: phi0 and MA move by less than dgamma's order
            assert!(
                (w[1].phi0 - w[0].phi0).abs() < 0.1,
                "{} -> {}",
                w[0].phi0,
                w[1].phi0
            );
            assert!(
                (w[1].ma - w[0].ma).abs() < 0.1,
                "{} -> {}",
                w[0].ma,
                w[1].ma
            );
        }
    }
}
