//! The loads: a concentrated force at `s1` and a uniform fluid load on `[0, s1]`.

use crate::error::{finite, ModelError, Result};
use serde::{Deserialize, Serialize};

/// Largest admissible load magnitude f or q (dimensionless; the thesis's loads are <= 30,
/// a rat whisker at f = 1000 carries 40 mN).
pub const LOAD_MAX: f64 = 1e3;

/// How a tip force follows the deformation (thesis Fig. 2.29).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum LoadKind {
    /// Direction preserving: force vector `f (cos beta, -sin beta)`.
    #[default]
    Dp,
    /// Angle preserving: the force turns with the tip, vector angle `phi1 - pi/2 - beta` [4.3].
    Ap,
}

/// Concentrated force at the loaded end `s1`, magnitude `f = F L^2 / (E I_b)` [3.16].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TipForce {
    /// Magnitude f >= 0.
    pub f: f64,
    /// Angle beta (rad): beta = 0 pushes towards +x.
    pub beta: f64,
    /// Direction or angle preserving.
    pub kind: LoadKind,
}

impl TipForce {
    /// A direction-preserving force.
    pub fn dp(f: f64, beta: f64) -> Self {
        TipForce {
            f,
            beta,
            kind: LoadKind::Dp,
        }
    }

    /// An angle-preserving force.
    pub fn ap(f: f64, beta: f64) -> Self {
        TipForce {
            f,
            beta,
            kind: LoadKind::Ap,
        }
    }

    /// The equivalent direction-preserving angle once the tip angle `phi1` is known:
    /// `beta` for DP, `beta + pi/2 - phi1` for AP (so that the vector is `f (cos, -sin)` of it).
    #[inline]
    pub fn effective_beta(&self, phi1: f64) -> f64 {
        match self.kind {
            LoadKind::Dp => self.beta,
            LoadKind::Ap => self.beta + std::f64::consts::FRAC_PI_2 - phi1,
        }
    }
}

/// Uniform fluid load per unit length `q = Q L^3 / (E I_b)` [3.17] at angle alpha, acting on
/// `[0, s1]`: vector `q (cos alpha, -sin alpha)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FluidLoad {
    /// Magnitude q >= 0.
    pub q: f64,
    /// Angle alpha (rad): alpha = 0 pushes towards +x.
    pub alpha: f64,
}

/// All loads on a whisker.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Loads {
    /// Concentrated force at `s1`.
    pub tip: TipForce,
    /// Fluid load on `[0, s1]`.
    pub fluid: FluidLoad,
    /// Loaded length s1 in (0, 1]: 1 except in tangential contact (phase B); the segment
    /// `(s1, 1]` is load free.
    pub s1: f64,
}

impl Default for Loads {
    fn default() -> Self {
        Loads {
            tip: TipForce::default(),
            fluid: FluidLoad::default(),
            s1: 1.0,
        }
    }
}

impl Loads {
    /// No load at all.
    pub fn none() -> Self {
        Self::default()
    }

    /// A tip force only.
    pub fn tip(tip: TipForce) -> Self {
        Loads {
            tip,
            ..Self::default()
        }
    }

    /// A fluid load only.
    pub fn fluid(q: f64, alpha: f64) -> Self {
        Loads {
            fluid: FluidLoad { q, alpha },
            ..Self::default()
        }
    }

    /// Tip force and fluid load together.
    pub fn combined(tip: TipForce, q: f64, alpha: f64) -> Self {
        Loads {
            tip,
            fluid: FluidLoad { q, alpha },
            s1: 1.0,
        }
    }

    /// The same loads scaled by `lambda` (load continuation).
    pub fn scaled(&self, lambda: f64) -> Self {
        let mut l = *self;
        l.tip.f *= lambda;
        l.fluid.q *= lambda;
        l
    }

    /// Checks every load parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        finite("f", self.tip.f)?;
        finite("beta", self.tip.beta)?;
        finite("q", self.fluid.q)?;
        finite("alpha", self.fluid.alpha)?;
        finite("s1", self.s1)?;
        if self.tip.f < 0.0 {
            return Err(ModelError::InvalidParameter {
                name: "f",
                value: self.tip.f,
                reason: "the tip force magnitude must be >= 0 (its direction is set by beta)",
            });
        }
        if self.fluid.q < 0.0 {
            return Err(ModelError::InvalidParameter {
                name: "q",
                value: self.fluid.q,
                reason: "the fluid load magnitude must be >= 0 (its direction is set by alpha)",
            });
        }
        for (name, v) in [("f", self.tip.f), ("q", self.fluid.q)] {
            if v > LOAD_MAX {
                return Err(ModelError::InvalidParameter {
                    name,
                    value: v,
                    reason: "the load magnitude must be <= 1000",
                });
            }
        }
        if !(self.s1 > 0.0 && self.s1 <= 1.0) {
            return Err(ModelError::InvalidParameter {
                name: "s1",
                value: self.s1,
                reason: "the loaded length must be in (0, 1]",
            });
        }
        Ok(())
    }

    /// Largest load magnitude, `max(f, q)`.
    pub fn magnitude(&self) -> f64 {
        self.tip.f.max(self.fluid.q)
    }
}
