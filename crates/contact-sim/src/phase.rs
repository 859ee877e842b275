//! The two contact phases at one contour point, each a 2x2 system solved by argmin's trust
//! region (the thesis used MATLAB's fsolve) around shots from the loaded end with exact
//! Jacobians from the variational equations.
//!
//! - Phase A (tip contact, Fig. 5.3): s1 = 1, unknowns `(phi1, f)`, conditions: base
//!   condition [3.21, 3.22] and tip height `y(1) = g(xc)`; valid while `phi1 > psi`.
//! - Phase B (tangential contact, Fig. 5.4): `phi(s1) = psi`, unknowns `(f, s1)`, the same two
//!   conditions at `s1`; valid while `s1 < 1`.
//!
//! The contact force is the DP force `f (sin psi, -cos psi)`, i.e. `beta = pi/2 - psi`, and the
//! flow acts on `[0, s1]` at any angle alpha (spec/model.md). The base position follows as
//! `x0 = xc - (x(s1) - x(0))`.

use crate::error::{ContactError, Result};
use crate::profile::Profile;
use beam_model::equations::Sensitivities;
use beam_model::shot::{shoot, Integration, Shot};
use beam_model::{FluidLoad, LoadKind, Loads, ModelError, TipForce, Whisker};
use bvp_solvers::trust_region::{self, NonlinearSystem, TrustRegionOptions};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;
use std::f64::consts::FRAC_PI_2;

/// Contact phase of a sweep row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Phase {
    /// Before contact: the flow alone.
    None,
    /// Tip contact.
    A,
    /// Tangential contact.
    B,
}

impl Phase {
    /// `A`, `B` or `none`, as in the observables CSV.
    pub fn label(&self) -> &'static str {
        match self {
            Phase::None => "none",
            Phase::A => "A",
            Phase::B => "B",
        }
    }

    fn letter(&self) -> char {
        match self {
            Phase::None => '-',
            Phase::A => 'A',
            Phase::B => 'B',
        }
    }
}

/// A contour point `(xc, g(xc))` with its contour angle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContourPoint {
    /// x of the contact point.
    pub xc: f64,
    /// y of the contact point, `g(xc)`.
    pub yc: f64,
    /// Contour angle `psi = atan g'(xc)`.
    pub psi: f64,
}

impl ContourPoint {
    /// The contour point of `profile` at `xc`.
    pub fn on(profile: &Profile, xc: f64) -> Self {
        let (yc, d, _) = profile.eval(xc);
        ContourPoint {
            xc,
            yc,
            psi: d.atan(),
        }
    }
}

/// The solved state of the whisker in contact at one contour point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactState {
    /// The phase.
    pub phase: Phase,
    /// The contour point.
    pub point: ContourPoint,
    /// Contact force magnitude f.
    pub f: f64,
    /// Contact arc length s1 (1 in phase A).
    pub s1: f64,
    /// Tangent angle at s1 (`psi` in phase B).
    pub phi1: f64,
    /// Base position x0.
    pub x0: f64,
    /// Base angle phi0.
    pub phi0: f64,
    /// Bending moment at the base m(0) (`MA = -m(0)`).
    pub m0: f64,
    /// Trust-region iterations.
    pub iterations: u64,
    /// Final residual norm.
    pub residual: f64,
}

impl ContactState {
    /// The loads on the whisker in this state.
    pub fn loads(&self, flow: FluidLoad) -> Loads {
        contact_loads(flow, self.point.psi, self.f, self.s1)
    }

    /// Base observables `(Ax, Ay, MA, phi0)` [6.7-6.9] under the flow `flow` on `[0, s1]`:
    /// `Ax = -(f sin psi + q s1 cos alpha)`, `Ay = f cos psi + q s1 sin alpha`, `MA = -m(0)`.
    pub fn observables(&self, flow: FluidLoad) -> (f64, f64, f64, f64) {
        let (s, c) = self.point.psi.sin_cos();
        let (sa, ca) = flow.alpha.sin_cos();
        (
            -(self.f * s + flow.q * self.s1 * ca),
            self.f * c + flow.q * self.s1 * sa,
            -self.m0,
            self.phi0,
        )
    }
}

/// Loads of a contact: DP force `f (sin psi, -cos psi)` (`beta = pi/2 - psi`) at `s1` and the
/// flow `q (cos alpha, -sin alpha)` on `[0, s1]` (spec/model.md, contact).
pub fn contact_loads(flow: FluidLoad, psi: f64, f: f64, s1: f64) -> Loads {
    Loads {
        tip: TipForce {
            f,
            beta: FRAC_PI_2 - psi,
            kind: LoadKind::Dp,
        },
        fluid: flow,
        s1,
    }
}

/// The contact problem at one contour point for one phase.
pub struct PhaseProblem<'a> {
    whisker: &'a Whisker,
    flow: FluidLoad,
    point: ContourPoint,
    phase: Phase,
    integration: &'a Integration,
    cache: RefCell<Option<([f64; 2], Shot)>>,
}

impl<'a> PhaseProblem<'a> {
    /// Phase `phase` (A or B) at `point`.
    pub fn new(
        whisker: &'a Whisker,
        flow: FluidLoad,
        point: ContourPoint,
        phase: Phase,
        integration: &'a Integration,
    ) -> Self {
        PhaseProblem {
            whisker,
            flow,
            point,
            phase,
            integration,
            cache: RefCell::new(None),
        }
    }

    /// `(phi1, f, s1)` from the unknowns.
    fn unpack(&self, x: &[f64]) -> (f64, f64, f64) {
        match self.phase {
            Phase::B => (self.point.psi, x[0], x[1]),
            _ => (x[0], x[1], 1.0),
        }
    }

    fn shot(&self, x: &[f64]) -> std::result::Result<Shot, ContactError> {
        let key = [x[0], x[1]];
        if let Some((k, s)) = *self.cache.borrow() {
            if k == key {
                return Ok(s);
            }
        }
        let (phi1, f, s1) = self.unpack(x);
        if !(s1 > 1e-3 && s1 < 1.0 / (1.0 - self.whisker.theta).max(1e-9)) {
            return Err(ContactError::Model(ModelError::InvalidParameter {
                name: "s1",
                value: s1,
                reason: "contact arc length left the whisker during the phase-B iteration",
            }));
        }
        let loads = contact_loads(self.flow, self.point.psi, f, s1);
        let shot = shoot(
            self.whisker,
            &loads,
            phi1,
            Sensitivities::All,
            self.integration,
        )?;
        *self.cache.borrow_mut() = Some((key, shot));
        Ok(shot)
    }

    /// Solves the phase from `guess` (`[phi1, f]` for A, `[f, s1]` for B).
    pub fn solve(&self, guess: [f64; 2], tol: f64) -> Result<ContactState> {
        let opts = TrustRegionOptions {
            tol,
            max_iters: 30,
            initial_radius: 0.5,
            max_radius: 10.0,
        };
        let (x, iterations, residual) = match trust_region::solve(self, &guess, &opts) {
            Ok(sol) => (sol.x, sol.iterations, sol.residual_norm),
            Err(ContactError::Bvp(bvp_solvers::BvpError::NoConvergence {
                iterations,
                residual,
                ..
            })) => {
                // Thin tips make the residual noisy at the 1e-10 level (adaptive steps), where
                // the trust region can stall just above its target: polish with plain Newton
                // steps and accept the noise floor.
                match self.newton(guess, 1e-9) {
                    Some((x, r, it)) => (x.to_vec(), iterations as u64 + it, r),
                    None => {
                        return Err(ContactError::PhaseSolve {
                            phase: self.phase.letter(),
                            xc: self.point.xc,
                            iterations: iterations as u64,
                            residual,
                        })
                    }
                }
            }
            Err(other) => return Err(other),
        };
        let (phi1, f, s1) = self.unpack(&x);
        let shot = self.shot(&x)?;
        Ok(ContactState {
            phase: self.phase,
            point: self.point,
            f,
            s1,
            phi1,
            x0: self.point.xc - shot.dx,
            phi0: shot.phi0,
            m0: shot.m0,
            iterations,
            residual,
        })
    }

    /// Plain Newton with the exact 2x2 Jacobian from `x0`; the best point if its residual
    /// norm is at most `accept`.
    fn newton(&self, x0: [f64; 2], accept: f64) -> Option<([f64; 2], f64, u64)> {
        let mut x = x0;
        let mut best: Option<([f64; 2], f64)> = None;
        let (mut r, mut j) = ([0.0; 2], [0.0; 4]);
        for it in 0..25u64 {
            self.residual(&x, &mut r).ok()?;
            let norm = r[0].hypot(r[1]);
            if best.is_none_or(|(_, b)| norm < b) {
                best = Some((x, norm));
            }
            if norm <= 1e-13 {
                return Some((x, norm, it));
            }
            self.jacobian(&x, &mut j).ok()?;
            let det = j[0] * j[3] - j[1] * j[2];
            if !(det.is_finite() && det != 0.0) {
                break;
            }
            x[0] -= (j[3] * r[0] - j[1] * r[1]) / det;
            x[1] -= (j[0] * r[1] - j[2] * r[0]) / det;
        }
        best.filter(|(_, b)| *b <= accept).map(|(x, b)| (x, b, 25))
    }
}

impl NonlinearSystem for PhaseProblem<'_> {
    type Error = ContactError;

    fn n_unknowns(&self) -> usize {
        2
    }

    fn residual(&self, x: &[f64], r: &mut [f64]) -> std::result::Result<(), ContactError> {
        let shot = self.shot(x)?;
        r[0] = self.whisker.support.residual(shot.phi0, shot.m0);
        r[1] = shot.dy - self.point.yc;
        Ok(())
    }

    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> std::result::Result<(), ContactError> {
        let shot = self.shot(x)?;
        let c = self.whisker.support.compliance();
        // rows of Shot::sens: d/d(phi1, f, s1) of (phi0, m0, dx, dy)
        let (a, b) = match self.phase {
            Phase::B => (1, 2),
            _ => (0, 1),
        };
        jac[0] = shot.sens[a][0] - c * shot.sens[a][1];
        jac[1] = shot.sens[b][0] - c * shot.sens[b][1];
        jac[2] = shot.sens[a][3];
        jac[3] = shot.sens[b][3];
        Ok(())
    }
}
