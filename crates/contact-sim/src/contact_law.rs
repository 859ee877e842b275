//! The law of the contact force (spec/model.md, "Friction at the contact"): frictionless or
//! Coulomb with coefficient mu, the slip state of a row, the stick/slip events, and the loads
//! and base observables of a force `F = fn n + ft t` at the contact. The sweep
//! ([`mod@crate::sweep`]) and the frictional tip contact ([`crate::friction`]) both build on it.

pub use crate::contact_force::{force, frictional_loads, frictional_observables, Tilt};
use crate::error::ContactError;
use crate::error::Result;
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
