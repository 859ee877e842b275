//! The follicle: a rigid clamp or a torsional spring at the base.

use crate::error::{ModelError, Result};
use serde::{Deserialize, Serialize};

/// Smallest admissible spring stiffness: a softer base turns by `m(0)/k`, more than 100 rad
/// under a unit moment.
pub const K_MIN: f64 = 1e-2;

/// Support of the whisker base (thesis Fig. 3.1, boundary conditions [3.21, 3.22]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Support {
    /// Clamped base: `phi(0) = pi/2`.
    Rigid,
    /// Torsional spring of dimensionless stiffness `k = K L / (E I_b)` [3.19]:
    /// `phi(0) = pi/2 + m(0)/k` (a Robin condition `phi(0) - (phi'(0) - B)/k = pi/2`).
    Spring {
        /// Stiffness k > 0.
        k: f64,
    },
}

impl Support {
    /// A support from a stiffness, `k = +inf` meaning rigid. Rejects `k <` [`K_MIN`] and NaN.
    pub fn from_stiffness(k: f64) -> Result<Self> {
        if k.is_nan() || k <= 0.0 {
            return Err(ModelError::InvalidParameter {
                name: "k",
                value: k,
                reason: "the base spring stiffness must be > 0 (use inf for a rigid support)",
            });
        }
        if k < K_MIN {
            return Err(ModelError::InvalidParameter {
                name: "k",
                value: k,
                reason: "the base spring stiffness must be >= 0.01 (or inf for a rigid support)",
            });
        }
        Ok(if k.is_infinite() {
            Support::Rigid
        } else {
            Support::Spring { k }
        })
    }

    /// The stiffness, `+inf` for a rigid support.
    pub fn stiffness(&self) -> f64 {
        match *self {
            Support::Rigid => f64::INFINITY,
            Support::Spring { k } => k,
        }
    }

    /// Compliance `1/k` (0 for a rigid support).
    pub fn compliance(&self) -> f64 {
        match *self {
            Support::Rigid => 0.0,
            Support::Spring { k } => 1.0 / k,
        }
    }

    /// Base-angle residual `phi(0) - pi/2 - m(0)/k` [3.21, 3.22]; zero for a solution.
    pub fn residual(&self, phi0: f64, m0: f64) -> f64 {
        phi0 - std::f64::consts::FRAC_PI_2 - m0 * self.compliance()
    }

    /// The rate of the [`Support::residual`] when `(phi0, m0)` change at rates
    /// `(dphi0, dm0)`: `dphi0 - dm0/k`.
    pub fn residual_rate(&self, dphi0: f64, dm0: f64) -> f64 {
        dphi0 - self.compliance() * dm0
    }

    pub(crate) fn validate(&self) -> Result<()> {
        if let Support::Spring { k } = *self {
            Support::from_stiffness(k)?;
        }
        Ok(())
    }
}
