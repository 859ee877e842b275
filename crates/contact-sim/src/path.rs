//! The sweep along a path of poses ([`crate::motion::BaseMotion::Path`], spec/model.md "Base motions"): the
//! base follows any sequence of poses `(x0, y0, gamma)`, linear between rows, the follicle's
//! stiffness `k(p)` along it where the path gives it (linear in the compliance `1/k`: the
//! follicle tensing, `phi0 = pi/2 + gamma(p) - MA/k(p)`, [3.21, 3.22] turned and tensed).
//!
//! The path parameter `p` (0 at the first row, `n - 1` at the last) is the sweep's
//! coordinate; the continuation works in the falling `-p`. On each segment the branch is
//! solved in the segment's frame ([`crate::motion`]'s notes: the fourth unknown `p` read
//! from the pivot row of `Q(u) = w D(u)`, so the state stays `(v, f, t)` and everything of
//! the translation applies unchanged). The corners are breakpoints:
//!
//! - the first touch is scanned segment by segment (`touch_scan::scan_touch`, its
//!   steps divided by the segment's speed, the last step landing on the corner);
//! - the trace of a segment ends on its corner (`End::Corner`, solved at `p = i + 1`
//!   exactly), and the next segment's trace starts from the same state solved in the next
//!   frame (a turning point of `p` at the corner is a snap there); no step straddles a
//!   corner;
//! - the rows are evenly spaced in `p` over the whole contact, each solved in its segment's
//!   frame; every corner inside the contact is a row of its own (like a phase switch);
//! - a path that ends in contact ends the sweep at its last row: [`crate::sweep::Separation::PathEnd`]
//!   (`end of the path`).
//!
//! Each segment's trace has the sweep's step budget.

use crate::accuracy::{row_branch, RowIntegration};
use crate::branch::{Branch, Constraint, Node, Rescue};
use crate::continuation::{End, Trace};
use crate::error::{ContactError, Result};
use crate::first_contact::{first_node, free_tip_angle, FirstTouch};
use crate::motion::{Frame, Poses};
use crate::phase::{ContactState, Phase};
use crate::profile::Profile;
use crate::sweep::{
    hold_of, separation, trace_seeing_switches, SweepPoint, SweepProgress, SweepResult,
    SweepSettings,
};
use crate::sweep::{rows_accuracy, rows_within_accuracy};
use crate::touch_scan::{scan_touch, with_compliance};
use beam_model::equations::Sensitivities;
use beam_model::shot::{shoot, Integration};
use beam_model::{FluidLoad, Loads, Whisker};

/// The branch of one segment of the path.
fn segment_branch<'a>(base: &Branch<'a>, path: &Poses, i: usize) -> Branch<'a> {
    let compliance = base.whisker.support.compliance();
    Branch {
        frame: Frame::Path(path.segment_frame(i, compliance)),
        ..*base
    }
}

/// The segment a coordinate `c = -p` lies in (the last for `p` at the end).
fn segment_of(path: &Poses, c: f64) -> usize {
    let last = path.poses.len() - 2;
    ((-c).floor().max(0.0) as usize).min(last)
}

/// The first touch along the path: each segment scanned from its first row (the free
/// whisker at the segment's pose and follicle), the first one that reaches the obstacle.
pub(crate) fn first_touch_on_path(
    whisker: &Whisker,
    flow: FluidLoad,
    (phi1, tol): (f64, f64),
    profile: &Profile,
    path: &Poses,
) -> Result<(usize, FirstTouch)> {
    let compliance = whisker.support.compliance();
    for i in 0..path.poses.len() - 1 {
        let frame = Frame::Path(path.segment_frame(i, compliance));
        if let Ok(touch) = scan_touch(whisker, flow, (phi1, tol), profile, frame, -(i as f64))? {
            return Ok((i, touch));
        }
    }
    Err(ContactError::NoContact {
        reason: format!(
            "the whisker does not touch {} along the path (p from 0 to {})",
            profile.name(),
            path.end()
        ),
    })
}

/// The traced segments: each segment's index and trace.
struct Traced {
    segments: Vec<(usize, Trace)>,
}

/// Traces the branch from `first` (on segment `i0`) segment by segment until it separates
/// or the path ends: at each corner the state is solved again in the next segment's frame at
/// the corner's `p` and traced on.
fn trace_path(
    base: &Branch,
    path: &Poses,
    (i0, first): (usize, Node),
    settings: &SweepSettings,
) -> Result<Traced> {
    let mut segments = Vec::new();
    let (mut i, mut start) = (i0, first);
    loop {
        let branch = segment_branch(base, path, i);
        // (a row outside its phase is reported with the sweep's largest step, not this one's)
        let (tr, _) = trace_seeing_switches(&branch, start, settings)?;
        let corner = match tr.end {
            End::Corner(n) if i + 2 < path.poses.len() => Some(n),
            _ => None,
        };
        segments.push((i, tr));
        let Some(n) = corner else {
            return Ok(Traced { segments });
        };
        i += 1;
        let next = segment_branch(base, path, i);
        start = next.correct(
            n.phase,
            n.u,
            Constraint::BasePosition(-(i as f64)),
            Rescue::TrustRegion,
        )?;
    }
}

/// Sweeps the whisker along `path` (the motion of `settings`; the free tip angle `phi1` of
/// the unturned whisker as the first guess): the first touch, the trace segment by segment,
/// the rows evenly spaced in `p` with their estimates, the rows before contact.
pub(crate) fn sweep_path(
    (whisker, flow, profile): (&Whisker, FluidLoad, &Profile),
    settings: &SweepSettings,
    path: &Poses,
    phi1: f64,
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<SweepResult> {
    let tol = settings.integration_tol;
    let (i0, touch) = first_touch_on_path(whisker, flow, (phi1, tol), profile, path)?;
    profile.convex_at(touch.t)?;
    let integration = Integration::adaptive(tol);
    let base = Branch {
        whisker,
        flow,
        profile,
        integration: &integration,
        tol: settings.solve_tol,
        frame: Frame::Translate,
        tilt: crate::contact_law::Tilt::NONE,
    };
    let first = first_node(&segment_branch(&base, path, i0), &touch)?;
    progress(SweepProgress::Coarse { steps: 0 });
    let traced = trace_path(&base, path, (i0, first), settings)?;
    let steps = traced.segments.iter().map(|(_, t)| t.nodes.len()).sum();
    progress(SweepProgress::Coarse { steps });
    for (_, tr) in &traced.segments {
        for n in &tr.nodes {
            profile.convex_at(n.u[2])?;
        }
    }
    let (_, last_trace) = traced.segments.last().expect("one segment at least");
    let (last, separation) = separation(last_trace.end);
    // the whole contact's grid in -p
    let (c_start, c_end) = (first.x0(), last.x0());
    let span = c_start - c_end;
    let points = settings.points;
    let grid: Vec<f64> = (1..points.saturating_sub(1))
        .map(|k| c_start - span * k as f64 / (points - 1) as f64)
        .collect();
    // the contact rows and their estimates at the accuracy asked for (`crate::accuracy`),
    // segment by segment
    let rows_at = |at: Option<&RowIntegration>| -> Result<Vec<(ContactState, f64)>> {
        let mut out = Vec::with_capacity(points + traced.segments.len());
        let count = traced.segments.len();
        for (k, (i, tr)) in traced.segments.iter().enumerate() {
            let seg = segment_branch(&base, path, *i);
            let (row_branch, loose) = row_branch(&seg, at);
            let (from, to) = (tr.nodes[0].x0(), end_node(&tr.end).x0());
            let targets: Vec<f64> = grid
                .iter()
                .copied()
                .filter(|&c| c < from && c > to)
                .collect();
            // the segment's end is a row where the contact ends there; a corner is the next
            // segment's first row
            let end = end_node(&tr.end);
            let last = (k + 1 == count && to < from).then(|| (&end, hold_of(&separation)));
            out.extend(crate::rows::rows_at(
                (&row_branch, loose.as_ref()),
                (&tr.nodes, &tr.switches),
                last,
                &targets,
                points,
                &mut |_, _| {},
            )?);
        }
        Ok(out)
    };
    let (states, row_accuracy) =
        rows_within_accuracy(settings.accuracy, settings.max_step, |at| {
            let states = rows_at(at)?;
            progress(SweepProgress::Fine {
                done: points,
                total: points,
            });
            Ok(states)
        })?;
    let mut points = pre_contact_rows(whisker, flow, (phi1, -touch.x0), path, settings)?;
    points.extend(
        states
            .iter()
            .map(|(s, _)| path_row(SweepPoint::from_state(s, flow, Frame::Translate), path)),
    );
    let accuracy = rows_accuracy(&points, &states, settings.accuracy, row_accuracy)?;
    let mut touch = touch;
    let pose = path.pose(-touch.x0);
    (touch.x0, touch.y0, touch.gamma) = (pose.x0, pose.y0, pose.gamma);
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

/// The node a trace ended on.
fn end_node(end: &End) -> Node {
    match *end {
        End::Snap(n)
        | End::Release(n)
        | End::MultiContact(n)
        | End::OffContour(n)
        | End::AtBase(n)
        | End::TipPassed(n)
        | End::Corner(n)
        | End::NotReached(n, _) => n,
    }
}

/// The row `row` (its `x0` the coordinate `-p`) with the path's pose and k at its `p`.
pub(crate) fn path_row(mut row: SweepPoint, path: &Poses) -> SweepPoint {
    let p = -row.x0;
    let pose = path.pose(p);
    (row.x0, row.y0, row.gamma) = (pose.x0, pose.y0, pose.gamma);
    row.k = path.k(p);
    row
}

/// The rows before contact: the free whisker under the flow at `p` spaced
/// `pre_contact_spacing` before the touch at `p_touch` (rows before the path's start
/// dropped), each at its pose and follicle (the tip angle from `phi1` turned by gamma).
pub(crate) fn pre_contact_rows(
    whisker: &Whisker,
    flow: FluidLoad,
    (phi1, p_touch): (f64, f64),
    path: &Poses,
    settings: &SweepSettings,
) -> Result<Vec<SweepPoint>> {
    let integration = Integration::adaptive(settings.integration_tol);
    let loads = Loads::fluid(flow.q, flow.alpha);
    let free_reactions = beam_model::Reactions::balancing((0.0, 0.0), flow, 1.0);
    let compliance = whisker.support.compliance();
    let mut out = Vec::with_capacity(settings.pre_contact_rows + settings.points);
    let mut guess = phi1;
    for k in (1..=settings.pre_contact_rows).rev() {
        let p = p_touch - k as f64 * settings.pre_contact_spacing;
        if p < 0.0 {
            continue;
        }
        let seg = path.segment_frame(segment_of(path, -p), compliance);
        let at = with_compliance(whisker, seg.compliance(-p));
        let pose = path.pose(p);
        let tip = free_tip_angle(&at, flow, (guess + pose.gamma, pose.gamma), &integration)?;
        guess = tip - pose.gamma;
        let free = shoot(&at, &loads, tip, Sensitivities::None, &integration)?;
        out.push(path_row(
            SweepPoint {
                x0: -p,
                ax: free_reactions.ax,
                ay: free_reactions.ay,
                ma: -free.m0,
                phi0: free.phi0,
                f: 0.0,
                s1: 1.0,
                phi1: tip,
                phase: Phase::None,
                xc: f64::NAN,
                yc: f64::NAN,
                psi: f64::NAN,
                ft: 0.0,
                slip: crate::contact_law::SlipState::None,
                slip_distance: 0.0,
                y0: 0.0,
                gamma: 0.0,
                k: None,
            },
            path,
        ));
    }
    Ok(out)
}
