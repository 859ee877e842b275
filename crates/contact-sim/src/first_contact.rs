//! The first contact (thesis ch. 5.2.1): the whisker under the flow alone, approached by the
//! contour as the base moves towards -x.
//!
//! With the free elastica `r(s)` relative to the base and `x_R(y)` the contour's right flank,
//! the point `s` touches the contour when the base is at `D(s) = x_R(y(s)) - x(s)`; the first
//! contact is the maximum of `D` over `s`. Since `D'(s) = sin(phi(s) - psi) / sin(psi)`, an
//! interior maximum is a tangency `phi(s) = psi` (phase B first) and a maximum at the tip with
//! `phi1 > psi` is a tip contact (phase A first). Every sign change of `phi - psi` along the
//! whisker is bracketed on a fine sampling of the dense free solution and refined by
//! bisection to machine precision, so the first contact is exact to the integrator's
//! tolerance, not to a sampling step.
//!
//! The contact branch starts at the first touch's base position (`first_node`): a tip touch
//! is the free whisker itself, a tangential one is followed along the phase-B branch from
//! its own touch.

use crate::branch::{Branch, Constraint, Node, Rescue};
use crate::error::{ContactError, Result};
use crate::phase::Phase;
use crate::profile::Profile;
use beam_model::equations::{Sensitivities, WhiskerOde};
use beam_model::shot::{shoot, Integration, Shot};
use beam_model::{FluidLoad, Loads, Whisker};
use bvp_solvers::continuation::{BranchGuard, Continuation};
use bvp_solvers::integrator::{Dop853, OdeSolution};
use bvp_solvers::newton::{JacobianUpdate, NewtonPolicy, Safeguards, SmallStep};
use bvp_solvers::roots::bisect;
use bvp_solvers::shooting::{solve_shooting, ShotProblem};
use serde::{Deserialize, Serialize};
use std::cell::Cell;

/// How the contact began.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum FirstContact {
    /// The tip touched first (phi1 > psi).
    Tip,
    /// A point s1 < 1 touched tangentially first.
    Tangential,
}

impl FirstContact {
    /// `tip` or `tangential`, as the outputs name it.
    pub fn label(&self) -> &'static str {
        match self {
            FirstContact::Tip => "tip",
            FirstContact::Tangential => "tangential",
        }
    }

    /// The phase the contact begins in: A at the tip, B tangential.
    pub fn phase(&self) -> Phase {
        match self {
            FirstContact::Tip => Phase::A,
            FirstContact::Tangential => Phase::B,
        }
    }
}

/// Where and how the free whisker first touches the contour.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FirstTouch {
    /// Tip or tangential.
    pub kind: FirstContact,
    /// Arc length of the touching point (1 for the tip).
    pub s: f64,
    /// Contour parameter of the touched point ([`Profile::at`]).
    pub t: f64,
    /// Touched contour point x.
    pub xc: f64,
    /// Touched contour point y.
    pub yc: f64,
    /// Contour angle there.
    pub psi: f64,
    /// Base position at the first touch.
    pub x0: f64,
    /// Tip angle of the free whisker.
    pub phi1: f64,
    /// Base y at the first touch (0 for a translation; [`crate::motion`]).
    #[serde(default)]
    pub y0: f64,
    /// Turn of the follicle at the first touch (rad; 0 for a translation).
    #[serde(default)]
    pub gamma: f64,
}

/// Samples of the free elastica that bracket the tangency points.
const SAMPLES: usize = 600;

/// The free elastica under the flow alone, as dense output from the tip to the base.
struct FreeShape {
    sol: OdeSolution,
    /// Base position relative to the tip's frame.
    base: (f64, f64),
}

impl FreeShape {
    /// `(x, y, phi)` of the point at arc length `s`, relative to the base.
    fn at(&self, s: f64) -> Option<(f64, f64, f64)> {
        let mut u = [0.0; 4];
        self.sol
            .eval_into(s, &mut u)
            .then(|| (u[2] - self.base.0, u[3] - self.base.1, u[0]))
    }
}

/// The free whisker's tip-angle equation as a [`ShotProblem`]: the base condition
/// [3.21, 3.22] of a shot from the tip at `phi1`, with its exact derivative from the shot's
/// variational equations.
struct FreeTip<'a> {
    whisker: &'a Whisker,
    loads: Loads,
    integration: &'a Integration,
    /// The turn of the follicle: the base condition `phi0 = pi/2 + gamma + m0/k`.
    gamma: f64,
    /// The error of a shot that failed (the iteration stops there).
    error: Cell<Option<beam_model::ModelError>>,
}

impl ShotProblem<1> for FreeTip<'_> {
    type End = Shot;
    type Error = ();
    fn shoot(&self, p: &[f64; 1], _sensitivities: bool) -> std::result::Result<Shot, ()> {
        let sens = Sensitivities::TipAngle;
        shoot(self.whisker, &self.loads, p[0], sens, self.integration)
            .map_err(|e| self.error.set(Some(e)))
    }
    fn residual(&self, _p: &[f64; 1], shot: &Shot) -> [f64; 1] {
        [self.whisker.support.residual(shot.phi0, shot.m0) - self.gamma]
    }
    fn residual_jacobian(&self, _p: &[f64; 1], shot: &Shot) -> Option<[[f64; 1]; 1]> {
        let d = shot.d_phi1;
        Some([[self.whisker.support.residual_rate(d.phi0, d.m0)]])
    }
}

/// The tip angle of the free whisker under `flow` (its base turned by `gamma`): Newton on the base condition
/// [3.21, 3.22] with the exact derivative of the shot, from `guess`: at most 40 shots, full
/// steps; the step after a residual of 1e-15, or a step below `1e-15 (1 + |phi1|)`, is
/// returned unshot; a failed iteration within 1e-11 is accepted.
pub(crate) fn free_tip_angle(
    whisker: &Whisker,
    flow: FluidLoad,
    (guess, gamma): (f64, f64),
    integration: &Integration,
) -> Result<f64> {
    let problem = FreeTip {
        whisker,
        loads: Loads::fluid(flow.q, flow.alpha),
        integration,
        gamma,
        error: Cell::new(None),
    };
    let policy = NewtonPolicy {
        max_iter: 39,
        halvings: 0,
        update: JacobianUpdate::Reevaluate { keep_below: 0.0 },
        jacobian_at_solution: false,
        noise_floor: 1e-11,
        ..NewtonPolicy::new(0.0)
    };
    let guards = Safeguards {
        small_step: Some(SmallStep {
            rel: 1e-15,
            shift: 1.0,
            floor: 0.0,
            check: None,
        }),
        predict_below: Some(1e-15),
        ..Safeguards::NONE
    };
    let out = solve_shooting(&problem, [guess], &policy, &guards);
    if let Some(e) = problem.error.take() {
        return Err(e.into());
    }
    match out {
        Ok(ans) if ans.termination.is_solution() => Ok(ans.u[0]),
        other => {
            let last = other.map_or(f64::NAN, |a| a.norm);
            Err(ContactError::NoContact {
                reason: format!(
                    "the free whisker under the flow could not be solved (base residual {last:.3e})"
                ),
            })
        }
    }
}

/// The tip angle of the free whisker under `flow` alone: method `accurate` at tolerance `tol`
/// (16 samples) for a start, then [`free_tip_angle`] on the shots of `integration`.
pub(crate) fn free_tip(
    whisker: &Whisker,
    flow: FluidLoad,
    tol: f64,
    integration: &Integration,
) -> Result<f64> {
    let scene = beam_model::Scene::new(*whisker, Loads::fluid(flow.q, flow.alpha));
    let method = beam_model::Method::Accurate { tol, samples: 16 };
    let guess = beam_model::solve(&scene, &method)?.tip.phi;
    free_tip_angle(whisker, flow, (guess, 0.0), integration)
}

/// Locates the first contact of the free whisker (tip angle `phi1`) with `profile`.
pub(crate) fn first_touch(
    whisker: &Whisker,
    flow: FluidLoad,
    phi1: f64,
    profile: &Profile,
    tol: f64,
) -> Result<FirstTouch> {
    let loads = Loads::fluid(flow.q, flow.alpha);
    let ode = WhiskerOde::new(*whisker, loads, phi1, Sensitivities::None);
    let sol =
        Dop853::new(tol, tol)
            .with_dense(true)
            .integrate(&ode, 1.0, 0.0, &[phi1, 0.0, 0.0, 0.0])?;
    let base = (sol.u_end[2], sol.u_end[3]);
    let shape = FreeShape { sol, base };
    // D(s) and the sign of D'(s) = sin(phi - psi)/sin(psi) where the contour is defined.
    // consecutive probes are close: each contour search starts at the last one's answer
    let last_t = Cell::new(f64::NAN);
    let probe = |s: f64| -> Option<(f64, f64, f64)> {
        let (x, y, phi) = shape.at(s)?;
        let t = profile.param_right_near(y, last_t.get())?;
        last_t.set(t);
        let g = profile.at(t);
        Some((g.x - x, phi - g.psi, t))
    };
    let mut candidates: Vec<f64> = Vec::new();
    let mut prev: Option<(f64, f64)> = None;
    for i in 0..=SAMPLES {
        let s = i as f64 / SAMPLES as f64;
        let Some((_, h, _)) = probe(s) else {
            prev = None;
            continue;
        };
        if let Some((sp, hp)) = prev {
            if hp > 0.0 && h <= 0.0 {
                // bisection on the sign of phi - psi to machine precision
                let below = |m| probe(m).map(|(_, hm, _)| hm > 0.0);
                candidates.push(bisect(below, sp, s, 100));
            }
        }
        prev = Some((s, h));
    }
    let tip = probe(1.0);
    if let Some((_, h, _)) = tip {
        if h > 0.0 {
            candidates.push(1.0);
        }
    }
    let best = candidates
        .iter()
        .filter_map(|&s| probe(s).map(|(d, _, t)| (s, d, t)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let Some((s, x0, t)) = best else {
        let top = (0..=SAMPLES)
            .filter_map(|i| shape.at(i as f64 / SAMPLES as f64).map(|p| p.1))
            .fold(f64::NEG_INFINITY, f64::max);
        return Err(ContactError::NoContact {
            reason: format!(
                "the whisker (highest point y = {top:.4}) never meets the right flank of {}",
                profile.name()
            ),
        });
    };
    // Parts of the whisker above the end of a finite contour (a circle's vertical end, a
    // table's last knot) would meet what lies beyond it first: refuse rather than guess.
    let (_, t_hi) = profile.param_range();
    if t_hi.is_finite() {
        let end = profile.at(t_hi);
        for i in 0..=SAMPLES {
            if let Some((x, y, _)) = shape.at(i as f64 / SAMPLES as f64) {
                if y > end.y && end.x - x >= x0 {
                    return Err(ContactError::NoContact {
                        reason: format!(
                            "the whisker first meets {} above the end of its contour (y = {y:.4} > {:.4}); extend the contour",
                            profile.name(),
                            end.y
                        ),
                    });
                }
            }
        }
    }
    let g = profile.at(t);
    let kind = if s == 1.0 {
        FirstContact::Tip
    } else {
        FirstContact::Tangential
    };
    Ok(FirstTouch {
        kind,
        s,
        t,
        xc: g.x,
        yc: g.y,
        psi: g.psi,
        x0,
        phi1,
        y0: 0.0,
        gamma: 0.0,
    })
}

/// The first node of the branch: the contact state at the base position of the first touch.
/// A tip touch is the free whisker itself (`f = 0`); a tangential touch is solved in phase B,
/// where the flow acts on `[0, s1]` only (spec/model.md), at the same base position: Newton
/// alone from the touch ([`Rescue::NewtonOnly`]), since where it fails (or finds `f < 0`)
/// [`tangential_first_node`] follows the phase-B branch there from its own `f = 0` touch, the
/// globalisation that stays on the branch; a trust region could settle on another phase-B
/// state at the same base position (the branch can turn back in x0).
pub(crate) fn first_node(branch: &Branch, touch: &FirstTouch) -> Result<Node> {
    let phase = touch.kind.phase();
    let u = match touch.kind {
        FirstContact::Tip => [touch.phi1, 0.0, touch.t],
        FirstContact::Tangential => [touch.s, 0.0, touch.t],
    };
    let node = match touch.kind {
        // the free whisker itself: no correction (f = 0 exactly)
        FirstContact::Tip => branch.eval(phase, u)?.1,
        FirstContact::Tangential => {
            match branch.correct(
                phase,
                u,
                Constraint::BasePosition(touch.x0),
                Rescue::NewtonOnly,
            ) {
                Ok(n) if n.state.f >= 0.0 => n,
                _ => tangential_first_node(branch, u, touch.x0)?,
            }
        }
    };
    if node.state.f < -1e-9 || (phase == Phase::B && node.state.s1 >= 1.0) {
        return Err(ContactError::NoContact {
            reason: format!(
                "the first {} contact at x0 = {:.6} has no admissible state (f = {:.3e}, s1 = {:.6})",
                touch.kind.label(),
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
/// start and says so. The `f = 0` point is a one-off solve whose failure ends the sweep
/// (Newton, the trust region as the fallback, [`Rescue::TrustRegion`]); the continuation's
/// corrector is Newton alone ([`Rescue::NewtonOnly`]): its failure shortens the step.
fn tangential_first_node(branch: &Branch, u: [f64; 3], x0: f64) -> Result<Node> {
    /// How far before the touch (in the motion's coordinate) the phase-B model's own touch
    /// may lie and still be the touch itself.
    const TOUCH_SLACK: f64 = 1e-9;
    let start = branch.correct(Phase::B, u, Constraint::NoForce, Rescue::TrustRegion)?;
    // the scan's touch (crate::touch_scan) is exact to its clearance's accuracy (~1e-12)
    // divided by the rate of the clearance along the motion, ~1e-11 in the coordinate where
    // a turn or a path moves the touching point slowly (measured: 1.1e-12 .. 1.9e-11 in the
    // path battery, all without flow, where the phase-B model is the free whisker itself)
    if start.x0() < x0 - TOUCH_SLACK {
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
        match branch.correct(
            Phase::B,
            guess,
            Constraint::BasePosition(target),
            Rescue::NewtonOnly,
        ) {
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
    use crate::branch::tests::TestScene;
    use std::f64::consts::FRAC_PI_2;

    /// A straight whisker (no pre-curvature, no flow) first touches a circle whose centre is
    /// above its tip with the tip, where the circle's right flank crosses `y = 1`: base at
    /// `x0 = xc + sqrt(r^2 - (1 - yc)^2)`, contour angle `asin((x0 - xc)/r)`.
    #[test]
    fn a_straight_whisker_touches_a_circle_with_its_tip() {
        let s = TestScene::straight(Profile::parse("circle:0.2,1.3,0.5").unwrap());
        let touch = first_touch(&s.whisker, s.flow, FRAC_PI_2, &s.profile, 1e-12).unwrap();
        let x0 = 0.2 + (0.25f64 - 0.09).sqrt();
        let psi = (0.4f64 / 0.5).asin();
        assert_eq!((touch.kind, touch.s), (FirstContact::Tip, 1.0));
        assert!((touch.x0 - x0).abs() < 1e-12, "{} vs {x0}", touch.x0);
        assert!((touch.xc - x0).abs() < 1e-12 && (touch.yc - 1.0).abs() < 1e-12);
        assert!((touch.psi - psi).abs() < 1e-12 && (touch.t - psi).abs() < 1e-12);
        assert_eq!((touch.kind.label(), touch.kind.phase()), ("tip", Phase::A));
    }

    /// The free tip angle under a flow satisfies the base condition [3.21, 3.22] of a shot
    /// from the tip at that angle.
    #[test]
    fn the_free_tip_angle_meets_the_follicle_law() {
        let s = TestScene::bent(1e-12);
        let phi1 = free_tip(&s.whisker, s.flow, 1e-12, &s.integration).unwrap();
        let loads = Loads::fluid(s.flow.q, s.flow.alpha);
        let shot = shoot(
            &s.whisker,
            &loads,
            phi1,
            Sensitivities::None,
            &s.integration,
        )
        .unwrap();
        let r = s.whisker.support.residual(shot.phi0, shot.m0);
        assert!(r.abs() < 1e-11, "{r:e}");
        assert!(phi1 < FRAC_PI_2, "bent along the flow: {phi1}");
    }
}
