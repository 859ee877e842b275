//! The law of the contact force (spec/model.md, "Friction at the contact"): frictionless or
//! Coulomb with coefficient mu, the slip state of a row, the stick/slip events, and the loads
//! and base observables of a force `F = fn n + ft t` at the contact. The sweep
//! ([`mod@crate::sweep`]) and the frictional tip contact ([`crate::friction`]) both build on it.

use crate::error::ContactError;
use crate::error::Result;
use beam_model::FluidLoad;
use beam_model::LoadKind;
use beam_model::Loads;
use beam_model::Reactions;
use beam_model::TipForce;
use serde::{Deserialize, Serialize};

/// The law of the force at the contact (spec/model.md, "Friction at the contact").
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum ContactLaw {
    /// The force normal to the obstacle, `F = f n` (thesis ch. 5).
    #[default]
    Frictionless,
    /// Coulomb friction with coefficient `mu >= 0`: `|ft| <= mu fn` in stick,
    /// `ft = -mu fn sign(u)` in slip. `mu = 0` is [`ContactLaw::Frictionless`] exactly.
    Coulomb {
        /// The friction coefficient.
        mu: f64,
    },
}

impl ContactLaw {
    /// The friction coefficient (0 without friction).
    pub fn mu(&self) -> f64 {
        match *self {
            ContactLaw::Frictionless => 0.0,
            ContactLaw::Coulomb { mu } => mu,
        }
    }

    /// `Some(mu)` where the law has friction (`mu > 0`), `None` where the frictionless sweep
    /// applies.
    pub fn friction(&self) -> Option<f64> {
        let mu = self.mu();
        (mu > 0.0).then_some(mu)
    }

    /// Refuses a coefficient that is negative, not finite or above 10, naming it.
    pub fn validate(&self) -> Result<()> {
        let mu = self.mu();
        if !(0.0..=MAX_MU).contains(&mu) {
            return Err(ContactError::InvalidParameter {
                name: "mu",
                value: mu,
                reason: "the friction coefficient must lie in [0, 10]",
            });
        }
        Ok(())
    }
}

/// Largest friction coefficient a sweep accepts.
pub const MAX_MU: f64 = 10.0;

/// The slip state of a row: `none` before contact (and without friction), `stick` or
/// `slip` (spec/cli.md, column `slip`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum SlipState {
    /// Before contact, or a frictionless contact.
    #[default]
    None,
    /// The touching material point stays put on the obstacle; `|ft| <= mu fn`.
    Stick,
    /// The touching material point slides; `ft = -mu fn sign(u)`.
    Slip,
}

impl SlipState {
    /// `none`, `stick` or `slip`, as in the observables CSV.
    pub fn label(&self) -> &'static str {
        match self {
            SlipState::None => "none",
            SlipState::Stick => "stick",
            SlipState::Slip => "slip",
        }
    }
}

/// A stick/slip switch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum FrictionEventKind {
    /// `|ft|` reached `mu fn`: the material point starts to slide.
    StickToSlip,
    /// The sliding velocity vanished: the material point sticks.
    SlipToStick,
}

/// A located stick/slip switch of a frictional sweep (its row is in the log too).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrictionEvent {
    /// Which switch.
    pub kind: FrictionEventKind,
    /// Base position.
    pub x0: f64,
    /// Contact point x.
    pub xc: f64,
    /// Normal force fn.
    pub f: f64,
    /// Tangential force ft.
    pub ft: f64,
}

/// Loads of a frictional contact: the force `F = fn n + ft t` (`n = (sin psi, -cos psi)`,
/// `t = (cos psi, sin psi)`) at `s1` as a direction-preserving tip force
/// `|F| (cos beta, -sin beta)`, and the flow on `[0, s1]`. With `ft = 0` it is
/// [`contact_loads`](crate::phase::contact_loads) exactly.
pub fn frictional_loads(flow: FluidLoad, psi: f64, f: f64, ft: f64, s1: f64) -> Loads {
    if ft == 0.0 {
        return crate::phase::contact_loads(flow, psi, f, s1);
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
    /// [`contact_loads`](crate::phase::contact_loads) exactly for [`Tilt::NONE`].
    pub fn loads(&self, flow: FluidLoad, psi: f64, f: f64, s1: f64) -> Loads {
        let mut l = crate::phase::contact_loads(flow, psi, f, s1);
        if !self.is_none() {
            l.tip.f = f * self.scale();
            l.tip.beta -= self.s_mu.atan();
        }
        l
    }
}
