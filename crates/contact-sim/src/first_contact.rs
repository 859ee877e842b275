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

use crate::error::{ContactError, Result};
use crate::profile::Profile;
use beam_model::equations::{Sensitivities, WhiskerOde};
use beam_model::shot::{shoot, Integration, Shot};
use beam_model::{FluidLoad, Loads, Whisker};
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
        [self.whisker.support.residual(shot.phi0, shot.m0)]
    }
    fn residual_jacobian(&self, _p: &[f64; 1], shot: &Shot) -> Option<[[f64; 1]; 1]> {
        let d = shot.d_phi1;
        Some([[self.whisker.support.residual_rate(d.phi0, d.m0)]])
    }
}

/// The tip angle of the free whisker under `flow`: Newton on the base condition
/// [3.21, 3.22] with the exact derivative of the shot, from `guess`: at most 40 shots, full
/// steps; the step after a residual of 1e-15, or a step below `1e-15 (1 + |phi1|)`, is
/// returned unshot; a failed iteration within 1e-11 is accepted.
pub(crate) fn free_tip_angle(
    whisker: &Whisker,
    flow: FluidLoad,
    guess: f64,
    integration: &Integration,
) -> Result<f64> {
    let problem = FreeTip {
        whisker,
        loads: Loads::fluid(flow.q, flow.alpha),
        integration,
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
    })
}
