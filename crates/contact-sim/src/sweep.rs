//! The quasi-static sweep (thesis ch. 5, Fig. 5.6), driven by the quantity the experimenter
//! moves, the base position x0: the whisker under the flow alone, the exact first contact
//! ([`crate::first_contact`]), the contact branch followed by continuation in x0 through
//! phase switches and folds of the contact point (`continuation`), events located on
//! the branch (`events`), and the rows of the log assembled here: pre-contact rows,
//! then contact rows evenly spaced in x0 from the first contact to the separation, plus one
//! row at each phase switch.

use crate::branch::{Branch, Constraint, Node};
use crate::continuation::{trace, End, StepControl};
use crate::error::{ContactError, Result};
use crate::first_contact::{first_touch, free_tip_angle};
pub use crate::first_contact::{FirstContact, FirstTouch};
use crate::phase::{ContactState, Phase};
use crate::profile::Profile;
use beam_model::equations::Sensitivities;
use beam_model::shot::{shoot, Integration};
use beam_model::{FluidLoad, Loads, Whisker};
use bvp_solvers::continuation::{BranchGuard, Continuation};
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
    /// No separation within the continuation's step budget.
    NotReached {
        /// The steps taken.
        steps: usize,
    },
}

/// A complete sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepResult {
    /// Fluid load q.
    pub q: f64,
    /// Flow angle alpha (rad): the flow is `q (cos alpha, -sin alpha)` on `[0, s1]`.
    pub alpha: f64,
    /// The rows in the order of the motion (x0 strictly decreasing), pre-contact rows first.
    pub points: Vec<SweepPoint>,
    /// How the contact began.
    pub first_contact: FirstContact,
    /// The free whisker's first touch, exact: touching arc length, contour point, x0.
    pub first_touch: FirstTouch,
    /// How it ended.
    pub separation: Separation,
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
            let c = if p.phase == Phase::A { 'A' } else { 'B' };
            if !s.ends_with(c) {
                s.push(c);
            }
        }
        s
    }
}

impl SweepPoint {
    fn from_state(st: &ContactState, flow: FluidLoad) -> Self {
        let (ax, ay, ma, phi0) = st.observables(flow);
        SweepPoint {
            x0: st.x0,
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
        }
    }

    /// The loads of this row under `flow`: the flow alone before contact; the flow on
    /// `[0, s1]` and the contact force at `s1` in contact [6.8, 6.9]
    /// ([`contact_loads`](crate::phase::contact_loads)).
    pub fn loads(&self, flow: FluidLoad) -> Loads {
        match self.phase {
            Phase::None => crate::phase::contact_loads(flow, 0.0, 0.0, 1.0),
            _ => crate::phase::contact_loads(flow, self.psi, self.f, self.s1),
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

/// Progress of a running sweep, reported to [`sweep_with_progress`]'s callback.
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

/// Sweeps a whisker under the fluid load `flow` past `profile` (thesis Fig. 5.6).
pub fn sweep(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
) -> Result<SweepResult> {
    sweep_with_progress(whisker, flow, profile, settings, &mut |_| {})
}

/// [`sweep`] reporting its progress to `progress` (e.g. for a progress bar).
pub fn sweep_with_progress(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<SweepResult> {
    // one computation that may split over two cores (bvp_solvers::cores)
    let _claim = bvp_solvers::cores::Claim::new();
    whisker.validate()?;
    Loads::fluid(flow.q, flow.alpha).validate()?;
    check_settings(settings, flow)?;
    profile.check_reachable_convex()?;
    let integration = Integration::adaptive(settings.integration_tol);
    let branch = Branch {
        whisker,
        flow,
        profile,
        integration: &integration,
        tol: settings.solve_tol,
    };
    // The free whisker under the flow, then its exact first touch.
    let guess = beam_model::solve(
        &beam_model::Scene::new(*whisker, Loads::fluid(flow.q, flow.alpha)),
        &beam_model::Method::Accurate {
            tol: settings.integration_tol,
            samples: 16,
        },
    )?
    .tip
    .phi;
    let phi1 = free_tip_angle(whisker, flow, guess, &integration)?;
    let touch = first_touch(whisker, flow, phi1, profile, settings.integration_tol)?;
    profile.convex_at(touch.t)?;
    let first = first_node(&branch, &touch)?;
    // The branch from the first contact to the separation.
    progress(SweepProgress::Coarse { steps: 0 });
    let ctl = StepControl {
        initial: settings.max_step * 0.2,
        max: settings.max_step,
        min: 1e-10,
        max_steps: settings.max_steps,
        event_tol: settings.event_tol,
        check_penetration: settings.check_penetration,
    };
    // The trace's nodes only guide the rows and bracket the events: it runs at looser
    // tolerances, and the nodes that become rows (switches, the end) are solved again at
    // the full ones.
    let loose = Integration::adaptive(settings.integration_tol.max(TRACE_INTEGRATION_TOL));
    let trace_branch = Branch {
        integration: &loose,
        tol: settings.solve_tol.max(TRACE_SOLVE_TOL),
        ..branch
    };
    let mut tr = trace(&trace_branch, first, &ctl)?;
    tr.tighten(&branch)?;
    progress(SweepProgress::Coarse {
        steps: tr.nodes.len(),
    });
    for n in &tr.nodes {
        profile.convex_at(n.u[2])?;
    }
    let (last, separation) = match tr.end {
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
        End::NotReached(n, steps) => (n, Separation::NotReached { steps }),
    };
    let states = crate::rows::rows(
        &branch,
        &tr.nodes,
        &tr.switches,
        &last,
        settings.points,
        &mut |done, total| progress(SweepProgress::Fine { done, total }),
    )?;
    // The free whisker's observables before contact.
    let free = shoot(
        whisker,
        &Loads::fluid(flow.q, flow.alpha),
        phi1,
        Sensitivities::None,
        &integration,
    )?;
    let free_reactions = beam_model::Reactions::balancing((0.0, 0.0), flow, 1.0);
    let mut points = Vec::with_capacity(settings.pre_contact_rows + states.len());
    for k in (1..=settings.pre_contact_rows).rev() {
        points.push(SweepPoint {
            x0: first.x0() + k as f64 * settings.pre_contact_spacing,
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
        });
    }
    points.extend(states.iter().map(|s| SweepPoint::from_state(s, flow)));
    Ok(SweepResult {
        q: flow.q,
        alpha: flow.alpha,
        points,
        first_contact: touch.kind,
        first_touch: touch,
        separation,
    })
}

/// The trace's integrator tolerance (at most as tight as the sweep's): its nodes guide the
/// rows' predictions, whose errors (~1e-6 from the Hermite interpolant) dwarf it.
const TRACE_INTEGRATION_TOL: f64 = 1e-10;

/// The trace's residual tolerance (at most as tight as the sweep's).
const TRACE_SOLVE_TOL: f64 = 1e-9;

/// Refuses settings the sweep cannot honour, naming the culprit.
fn check_settings(settings: &SweepSettings, flow: FluidLoad) -> Result<()> {
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

/// The first node of the branch: the contact state at the base position of the first touch.
/// A tip touch is the free whisker itself (`f = 0`); a tangential touch is solved in phase B,
/// where the flow acts on `[0, s1]` only (spec/model.md), at the same base position.
fn first_node(branch: &Branch, touch: &FirstTouch) -> Result<Node> {
    let (phase, u) = match touch.kind {
        FirstContact::Tip => (Phase::A, [touch.phi1, 0.0, touch.t]),
        FirstContact::Tangential => (Phase::B, [touch.s, 0.0, touch.t]),
    };
    let node = match touch.kind {
        // the free whisker itself: no correction (f = 0 exactly)
        FirstContact::Tip => branch.eval(phase, u)?.1,
        FirstContact::Tangential => {
            match branch.correct(phase, u, Constraint::BasePosition(touch.x0)) {
                Ok(n) if n.state.f >= 0.0 => n,
                _ => tangential_first_node(branch, u, touch.x0)?,
            }
        }
    };
    if node.state.f < -1e-9 || (phase == Phase::B && node.state.s1 >= 1.0) {
        return Err(ContactError::NoContact {
            reason: format!(
                "the first {} contact at x0 = {:.6} has no admissible state (f = {:.3e}, s1 = {:.6})",
                if phase == Phase::B { "tangential" } else { "tip" },
                touch.x0,
                node.state.f,
                node.state.s1
            ),
        });
    }
    Ok(node)
}

/// The phase-B state at the first-touch base position `x0`, reached along the phase-B branch:
/// a tangential touch removes the flow beyond s1 (spec/model.md), which can move the state far
/// from the free whisker's (slender tips). The branch point with `f = 0` is solved first (the
/// whisker under the flow on `[0, s1]` alone, tangent to the contour), then the branch is
/// followed in x0 down to `x0` ([`Continuation::follow`]). Where that branch does not reach `x0`
/// with `f >= 0` (the thesis's phase-B model has no admissible state there), the sweep cannot
/// start and says so.
fn tangential_first_node(branch: &Branch, u: [f64; 3], x0: f64) -> Result<Node> {
    let start = branch.correct(Phase::B, u, Constraint::NoForce)?;
    if start.x0() < x0 - 1e-12 {
        return Err(ContactError::NoContact {
            reason: format!(
                "at the first tangential touch (x0 = {x0:.6}) the phase-B model (flow on [0, s1] only) is not yet in contact (its own touch is at x0 = {:.6})",
                start.x0()
            ),
        });
    }
    if start.x0() - x0 <= 1e-13 {
        return Ok(start);
    }
    // Natural-parameter continuation in x0 with the secant predictor; an inadmissible
    // state (s1 >= 1 or f < 0) counts as a failed corrector.
    let step = (start.x0() - x0).min(0.05);
    let cont = Continuation {
        initial_step: step.max(1e-9),
        min_step: 1e-9,
        max_step: 0.05,
    };
    let guard = BranchGuard {
        absolute: f64::INFINITY,
        relative: 0.0,
        max_attempts: 10_000,
    };
    let mut cur = start;
    let followed = cont.follow(start.x0(), x0, start.u.to_vec(), &guard, |target, guess| {
        let guess = [guess[0], guess[1], guess[2]];
        match branch.correct(Phase::B, guess, Constraint::BasePosition(target)) {
            Ok(n) if n.state.s1 < 1.0 && n.state.f >= 0.0 => {
                cur = n;
                Ok(n.u.to_vec())
            }
            Ok(_) => Err(()),
            Err(_) => Err(()),
        }
    });
    if followed.is_ok() {
        return Ok(cur);
    }
    Err(ContactError::NoContact {
        reason: format!(
            "the tangential first touch at s = {:.6} (x0 = {x0:.6}) has no admissible phase-B state: the phase-B model (flow on [0, s1] only) leaves its own f = 0 touch at x0 = {:.6} and turns back at x0 = {:.6} with f = {:.3e}; the single-contact model cannot start this sweep",
            u[0],
            start.x0(),
            cur.x0(),
            cur.state.f
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row's shape passes through its contact point, and before contact its base
    /// moment is the row's (the shape is the row's equilibrium).
    #[test]
    fn a_row_gives_its_whole_shape() {
        let whisker = Whisker::new(0.6, 0.3, 0.2, 20.0);
        let flow = FluidLoad { q: 2.0, alpha: 0.3 };
        let settings = SweepSettings {
            points: 12,
            ..SweepSettings::default()
        };
        let res = sweep(&whisker, flow, &Profile::g2(), &settings).unwrap();
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
}
