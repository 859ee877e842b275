//! Friction along a path of poses ([`crate::motion::BaseMotion::Path`]; spec/model.md "Base
//! motions" and "Friction at the contact"): the frictional trace in each segment's frame
//! (`branch::reframe`: the segment's two base conditions linear in its parameter, the
//! coordinate `-p`), as the frictionless path sweep ([`crate::path`]) does:
//!
//! - the first touch scanned segment by segment ([`crate::path::first_touch_on_path`]);
//! - a segment's trace ends on its next row exactly (the event `Corner`, solved at
//!   `p = i + 1`); the next segment's trace goes on from the same state, phase and mode (a
//!   stick keeps its anchor: the material point is the lab's, not the frame's) solved in the
//!   next segment's frame; a path that ends in contact ends the sweep there
//!   ([`Separation::PathEnd`]);
//! - the rows are evenly spaced in `p` within each segment (their number in proportion to
//!   the segment's share of the contact, two at least: the segment's ends), every corner
//!   inside the contact a row of its own, the stick/slip switches too; the slip displacement
//!   runs on over the corners.

use super::branch::{Con, Mode, Node};
use super::settings::FrictionSettings;
use super::start::{first_node, sweeper};
use super::trace::Trace;
use super::trace::{Sweeper, SWITCH_PROBE};
use super::{events_on_rows, rows};
use crate::accuracy::row_integration_tol;
use crate::contact_law::{FrictionEvent, FrictionEventKind};
use crate::error::ContactError;
use crate::error::Result;
use crate::motion::{Frame, Poses};
use crate::path::{first_touch_on_path, path_row, pre_contact_rows};
use crate::profile::Profile;
use crate::sweep::{
    check_accuracy, Separation, SweepPoint, SweepProgress, SweepResult, SweepSettings,
};
use beam_model::{FluidLoad, Whisker};

/// The frictional sweep (`mu > 0`) along `path` from the free whisker's tip angle `phi1`
/// (unturned): the rows before contact of the frictionless path sweep, then the frictional
/// contact rows segment by segment (the module's notes), with their estimates where an
/// accuracy is asked for.
pub(crate) fn sweep_path(
    (whisker, flow, profile): (&Whisker, FluidLoad, &Profile),
    settings: &SweepSettings,
    path: &Poses,
    (phi1, mu): (f64, f64),
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<SweepResult> {
    let scene = (whisker, flow, profile);
    let tol = settings.integration_tol;
    let (i0, touch) = first_touch_on_path(whisker, flow, (phi1, tol), profile, path)?;
    profile.convex_at(touch.t)?;
    let compliance = whisker.support.compliance();
    let frame_of = |i: usize| Frame::Path(path.segment_frame(i, compliance));
    let last_segment = path.poses.len() - 2;
    let mut set = FrictionSettings::of(settings, mu, frame_of(i0));
    let first = first_node(&sweeper(scene, &set), &touch, &set)?;
    progress(SweepProgress::Coarse { steps: 0 });
    // the trace, segment by segment
    let mut traces: Vec<(usize, Trace)> = Vec::new();
    // the segments (by index in `traces`) that start with a switch at their corner
    let mut switched: Vec<(usize, Vec<FrictionEventKind>)> = Vec::new();
    let (mut i, mut start) = (i0, first);
    loop {
        set.frame = frame_of(i);
        let tr = sweeper(scene, &set).trace_or_retrace(start)?;
        let corner = matches!(tr.end, Separation::PathEnd) && i < last_segment;
        let end = *tr.nodes.last().expect("a trace has its first node");
        traces.push((i, tr));
        if !corner {
            break;
        }
        i += 1;
        set.frame = frame_of(i);
        let sw = sweeper(scene, &set);
        start = sw
            .tight
            .correct(end.phase, end.mode, end.w, Con::Base(-(i as f64)))?;
        // the motion's direction may change at the corner: the mode that keeps the law
        // from here on (the same, else stick at the corner's state, else the other slip),
        // the switch recorded with the corner's row
        if !sw.probe(&start, SWITCH_PROBE) {
            let (at, kinds) = mode_at_corner(&sw, &start)?;
            switched.push((traces.len(), kinds));
            start = at;
        }
    }
    let steps = traces.iter().map(|(_, t)| t.nodes.len()).sum();
    progress(SweepProgress::Coarse { steps });
    // the rows of each segment, their number in proportion to its share of the contact
    let span = |t: &Trace| t.nodes[0].x0 - t.nodes.last().map_or(t.nodes[0].x0, |n| n.x0);
    let total: f64 = traces
        .iter()
        .map(|(_, t)| span(t))
        .sum::<f64>()
        .max(f64::MIN_POSITIVE);
    let mut rows_out: Vec<(SweepPoint, f64)> = Vec::new();
    let mut events = Vec::new();
    let done = std::cell::Cell::new(0);
    for (k, (i, tr)) in traces.iter().enumerate() {
        set.frame = frame_of(*i);
        let share = span(tr) / total * settings.points.saturating_sub(1) as f64;
        set.points = (share.round() as usize + 1).max(2);
        let sw = sweeper(scene, &set);
        let mut seg_rows = rows(&sw, &sw.tight, tr, &set, &mut |d, _| {
            progress(SweepProgress::Fine {
                done: done.get() + d,
                total: settings.points,
            })
        })?;
        done.set(done.get() + seg_rows.len());
        let seg_events = events_on_rows(
            tr.events.clone(),
            &seg_rows.iter().map(|r| r.0).collect::<Vec<_>>(),
        );
        if k > 0 && !seg_rows.is_empty() {
            // the first row is the corner's, the previous segment's last; the slip
            // displacement runs on from there. Where the mode switched at the corner the
            // corner's row is the new leg's (as a switch's row), with the switch's events
            let offset = rows_out.last().map_or(0.0, |r| r.0.slip_distance);
            match switched.iter().find(|(j, _)| *j == k) {
                Some((_, kinds)) => {
                    rows_out.pop();
                    let r = seg_rows[0].0;
                    events.extend(kinds.iter().map(|&kind| FrictionEvent {
                        kind,
                        x0: r.x0,
                        xc: r.xc,
                        f: r.f,
                        ft: r.ft,
                    }));
                }
                None => {
                    seg_rows.remove(0);
                }
            }
            for r in &mut seg_rows {
                r.0.slip_distance += offset;
            }
        }
        rows_out.extend(seg_rows);
        events.extend(seg_events);
    }
    let separation = traces.last().expect("one segment at least").1.end;
    let mut points = pre_contact_rows(whisker, flow, (phi1, -touch.x0), path, settings)?;
    let pre = points.len();
    points.extend(rows_out.iter().map(|r| path_row(r.0, path)));
    for e in &mut events {
        e.x0 = path.pose(-e.x0).x0;
    }
    let accuracy = settings
        .accuracy
        .map(|tol| {
            let first = rows_out.first().map_or(f64::NAN, |r| r.1);
            let mut estimates = vec![first; pre];
            estimates.extend(rows_out.iter().map(|r| r.1));
            check_accuracy(&points, estimates, tol, row_integration_tol(tol))
        })
        .transpose()?;
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
        friction_events: events,
    })
}

/// The mode at a corner `at` (solved in the new segment's frame) where its own does not keep
/// the law, taken on from the same state (no jump of the force at a fixed pose): a sliding
/// that the new direction of the motion would reverse sticks at the corner (probed down to
/// 1e-7 in the coordinate: the force may cross the cone fast, as against a peg), a stick
/// whose force the new direction pushes out of the cone slides with `ft`'s sign; the node
/// and the switch's event. Neither: no quasi-static continuation (`FrictionIndeterminate`).
fn mode_at_corner(sw: &Sweeper, at: &Node) -> Result<(Node, Vec<FrictionEventKind>)> {
    let (mode, kind) = match at.mode {
        Mode::Stick { .. } => (
            Mode::Slip {
                s: at.w[2].signum(),
            },
            FrictionEventKind::StickToSlip,
        ),
        Mode::Slip { .. } => (
            Mode::Stick {
                anchor: at.w[3],
                s1: at.s1(),
            },
            FrictionEventKind::SlipToStick,
        ),
    };
    if let Ok(n) = sw.tight.correct(at.phase, mode, at.w, Con::Base(at.x0)) {
        let mut dx = SWITCH_PROBE;
        while dx >= 1e-7 {
            if sw.probe(&n, dx) {
                return Ok((n, vec![kind]));
            }
            dx *= 0.1;
        }
    }
    Err(ContactError::FrictionIndeterminate {
        x0: at.x0,
        xc: at.geom.x,
        mu: sw.b.mu,
        reason: "at a corner of the path neither the contact's mode nor the other keeps the law"
            .into(),
    })
}
