//! The two contact phases at one contour point and the state of a contact row; the
//! branch of each phase is solved and traced in `branch` and
//! `continuation`.
//!
//! - Phase A (tip contact, Fig. 5.3): s1 = 1, unknowns `(phi1, f)`, conditions: base
//!   condition [3.21, 3.22] and tip height `y(1) = g(xc)`; valid while `phi1 > psi`.
//! - Phase B (tangential contact, Fig. 5.4): `phi(s1) = psi`, unknowns `(f, s1)`, the same two
//!   conditions at `s1`; valid while `s1 < 1`.
//!
//! The contact force is the DP force `f (sin psi, -cos psi)`, i.e. `beta = pi/2 - psi`, and the
//! flow acts on `[0, s1]` at any angle alpha (spec/model.md). The base position follows as
//! `x0 = xc - (x(s1) - x(0))`.

pub use crate::contact_force::contact_loads;
use crate::contact_force::Tilt;
use beam_model::{FluidLoad, Loads, Reactions};
use serde::{Deserialize, Serialize};

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

    /// `-`, `A` or `B`: the phase in one letter.
    pub fn letter(&self) -> char {
        match self {
            Phase::None => '-',
            Phase::A => 'A',
            Phase::B => 'B',
        }
    }
}

/// The phase's [`Phase::label`] (`A`, `B` or `none`), as in messages.
impl std::fmt::Display for Phase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.label())
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
    /// The force's tilt (a sliding frictional contact, `ft = s mu f`; [`Tilt::NONE`]
    /// without friction): `f` is the normal part of the force.
    #[serde(default)]
    pub tilt: Tilt,
}

impl ContactState {
    /// The loads on the whisker in this state.
    pub fn loads(&self, flow: FluidLoad) -> Loads {
        self.tilt.loads(flow, self.point.psi, self.f, self.s1)
    }

    /// Base observables `(Ax, Ay, MA, phi0)` [6.7-6.9] under the flow `flow` on `[0, s1]`:
    /// `Ax = -(f sin psi + q s1 cos alpha)`, `Ay = f cos psi + q s1 sin alpha`, `MA = -m(0)`;
    /// with a tilt those of the force `f n + ft t`, `ft = s mu f`
    /// ([`crate::contact_law::frictional_observables`]).
    pub fn observables(&self, flow: FluidLoad) -> (f64, f64, f64, f64) {
        if !self.tilt.is_none() {
            let (psi, f, s1) = (self.point.psi, self.f, self.s1);
            let (ax, ay, ma) = crate::contact_force::frictional_observables(
                flow,
                psi,
                f,
                self.tilt.ft(f),
                s1,
                self.m0,
            );
            return (ax, ay, ma, self.phi0);
        }
        let (s, c) = self.point.psi.sin_cos();
        let r = Reactions::balancing((self.f * s, self.f * c), flow, self.s1);
        (r.ax, r.ay, -self.m0, self.phi0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_model::LoadKind;
    use std::f64::consts::FRAC_PI_2;

    /// A contact state's observables are the force balance [6.7-6.9] written out: the base
    /// holds the contact force `f (sin psi, -cos psi)` at `s1` and the flow on `[0, s1]`.
    #[test]
    fn observables_balance_the_contact_force_and_the_flow() {
        let flow = FluidLoad { q: 2.5, alpha: 0.3 };
        let (f, psi, s1, m0, phi0) = (1.7, 0.4, 0.8, -0.35, 1.9);
        let point = ContourPoint {
            xc: 0.3,
            yc: 0.9,
            psi,
        };
        let st = ContactState {
            phase: Phase::B,
            point,
            f,
            s1,
            phi1: psi,
            x0: 0.1,
            phi0,
            m0,
            iterations: 0,
            residual: 0.0,
            tilt: Tilt::NONE,
        };
        let (ax, ay, ma, p0) = st.observables(flow);
        let ax_true = -(f * psi.sin() + flow.q * s1 * flow.alpha.cos());
        let ay_true = f * psi.cos() + flow.q * s1 * flow.alpha.sin();
        assert!((ax - ax_true).abs() < 1e-14, "{ax} vs {ax_true}");
        assert!((ay - ay_true).abs() < 1e-14, "{ay} vs {ay_true}");
        assert_eq!((ma, p0), (-m0, phi0));
        let loads = st.loads(flow);
        assert_eq!(
            (loads.tip.f, loads.tip.beta, loads.s1),
            (f, FRAC_PI_2 - psi, s1)
        );
        assert_eq!(loads.tip.kind, LoadKind::Dp);
    }

    /// A phase's label, letter and message name.
    #[test]
    fn phases_name_themselves() {
        let names = [
            (Phase::None, "none", '-'),
            (Phase::A, "A", 'A'),
            (Phase::B, "B", 'B'),
        ];
        for (p, label, letter) in names {
            assert_eq!(
                (p.label(), p.letter(), p.to_string()),
                (label, letter, label.into())
            );
        }
    }
}
