//! The force of a contact on the whisker and the loads it makes (spec/model.md, contact and
//! "Friction at the contact"): the normal force `f n` of the frictionless contact
//! [5.4-5.10], the frictional `F = fn n + ft t`, and a sliding contact's [`Tilt`]. A leaf of
//! the crate: the contact states ([`crate::phase`]), the contact law
//! ([`crate::contact_law`]) and both sweeps build on it.

use beam_model::{FluidLoad, LoadKind, Loads, Reactions, TipForce};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

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

/// Loads of a frictional contact: the force `F = fn n + ft t` (`n = (sin psi, -cos psi)`,
/// `t = (cos psi, sin psi)`) at `s1` as a direction-preserving tip force
/// `|F| (cos beta, -sin beta)`, and the flow on `[0, s1]`. With `ft = 0` it is
/// [`contact_loads`] exactly.
pub fn frictional_loads(flow: FluidLoad, psi: f64, f: f64, ft: f64, s1: f64) -> Loads {
    if ft == 0.0 {
        return contact_loads(flow, psi, f, s1);
    }
    let (fx, fy) = force(psi, f, ft);
    Loads {
        tip: TipForce {
            f: fx.hypot(fy),
            beta: (-fy).atan2(fx),
            kind: LoadKind::Dp,
        },
        fluid: flow,
        s1,
    }
}

/// The force on the whisker `fn n + ft t` in components.
pub fn force(psi: f64, f: f64, ft: f64) -> (f64, f64) {
    let (sp, cp) = psi.sin_cos();
    (f * sp + ft * cp, -f * cp + ft * sp)
}

/// The base observables `(Ax, Ay, MA)` of a frictional contact: `Ax = -(Fx + q s1 cos
/// alpha)`, `Ay = -Fy + q s1 sin alpha` (spec/model.md), `MA = -m(0)`.
pub fn frictional_observables(
    flow: FluidLoad,
    psi: f64,
    f: f64,
    ft: f64,
    s1: f64,
    m0: f64,
) -> (f64, f64, f64) {
    let (fx, fy) = force(psi, f, ft);
    let r = Reactions::balancing((fx, -fy), flow, s1);
    (r.ax, r.ay, -m0)
}

/// The tilt of a sliding contact's force (spec/model.md, "Friction at the contact"): in
/// slip `ft = s mu fn`, so `F = fn (n + s mu t)`, the frictionless force turned by
/// `atan(s mu)` and stretched by `sqrt(1 + mu^2)`: a tip force of size `fn sqrt(1 + mu^2)`
/// at `beta = pi/2 - psi - atan(s mu)`. A sliding stretch of a frictional sweep is the
/// frictionless contact branch (`branch::Branch`) under this force; [`Tilt::NONE`]
/// (`s_mu = 0`) is the frictionless force, taking exactly the frictionless arithmetic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Tilt {
    /// `s mu`: the friction coefficient with the sign `s = -sign(u)` of the tangential force
    /// (`u` the sliding velocity of the touching material point along `t`).
    pub s_mu: f64,
}

impl Tilt {
    /// The frictionless force, normal to the obstacle.
    pub const NONE: Tilt = Tilt { s_mu: 0.0 };

    /// Whether the force is the frictionless one (`s mu = 0`).
    pub fn is_none(&self) -> bool {
        self.s_mu == 0.0
    }

    /// `|F| / fn = sqrt(1 + mu^2)`.
    pub fn scale(&self) -> f64 {
        self.s_mu.hypot(1.0)
    }

    /// The tangential force `ft = s mu fn` of a normal force `f`.
    pub fn ft(&self, f: f64) -> f64 {
        if self.is_none() {
            0.0
        } else {
            self.s_mu * f
        }
    }

    /// The loads of normal force `f` at `s1` on the contour angle `psi`: the tip force
    /// `f sqrt(1 + mu^2)` at `beta = pi/2 - psi - atan(s mu)` and the flow on `[0, s1]`;
    /// [`contact_loads`] exactly for [`Tilt::NONE`].
    pub fn loads(&self, flow: FluidLoad, psi: f64, f: f64, s1: f64) -> Loads {
        let mut l = contact_loads(flow, psi, f, s1);
        if !self.is_none() {
            l.tip.f = f * self.scale();
            l.tip.beta -= self.s_mu.atan();
        }
        l
    }
}
