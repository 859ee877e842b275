//! The whisker: a tapered, pre-curved, dimensionless beam of length 1.

use crate::error::{finite, ModelError, Result};
use crate::support::Support;
use serde::{Deserialize, Serialize};

/// Smallest admissible conicity: at theta = 0.01 the tip's bending stiffness is 1e-8 of the
/// base's and its boundary layer (width ~ theta) needs ~ 1e4 grid intervals for an error
/// of 1e-9; below, the budgets of [`solve`](crate::solve) cannot guarantee an answer.
/// Rat whiskers have theta ~ 0.02..0.1.
pub const THETA_MIN: f64 = 0.01;

/// Largest magnitude of the pre-curvature coefficients A and B: |kappa0| <= 2 * 100 rad per
/// whisker length (a curl of 16 turns), far beyond real whiskers.
pub const PRECURVATURE_MAX: f64 = 100.0;

/// Geometry and support of a dimensionless whisker (thesis ch. 3).
///
/// - conicity: diameter ratio `e(s) = 1 + (theta - 1) s`, bending stiffness `EI(s) = e(s)^4`
///   [3.8], `0 < theta <= 1`;
/// - Cesaro pre-curvature `kappa0(s) = A s + B` [3.5];
/// - support: rigid or a torsional spring `k`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Whisker {
    /// Tip/base diameter ratio theta in (0, 1]; 1 is a cylinder.
    pub theta: f64,
    /// Cesaro slope A of the pre-curvature.
    pub a: f64,
    /// Cesaro offset B of the pre-curvature.
    pub b: f64,
    /// The base support.
    pub support: Support,
}

impl Default for Whisker {
    fn default() -> Self {
        Whisker {
            theta: 1.0,
            a: 0.0,
            b: 0.0,
            support: Support::Rigid,
        }
    }
}

impl Whisker {
    /// A whisker from its parameters, `k = +inf` meaning a rigid support (not validated;
    /// see [`Whisker::validate`]).
    pub fn new(theta: f64, a: f64, b: f64, k: f64) -> Self {
        Whisker {
            theta,
            a,
            b,
            support: if k.is_infinite() && k > 0.0 {
                Support::Rigid
            } else {
                Support::Spring { k }
            },
        }
    }

    /// A straight, cylindrical, rigidly clamped whisker.
    pub fn uniform() -> Self {
        Self::default()
    }

    /// Checks every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        finite("theta", self.theta)?;
        if !(self.theta > 0.0 && self.theta <= 1.0) {
            return Err(ModelError::InvalidParameter {
                name: "theta",
                value: self.theta,
                reason: "the conicity (tip/base diameter ratio) must be in (0, 1]",
            });
        }
        if self.theta < THETA_MIN {
            return Err(ModelError::InvalidParameter {
                name: "theta",
                value: self.theta,
                reason: "the conicity must be >= 0.01: thinner tips are beyond the solver's resolution budget",
            });
        }
        for (name, v) in [("A", self.a), ("B", self.b)] {
            finite(name, v)?;
            if v.abs() > PRECURVATURE_MAX {
                return Err(ModelError::InvalidParameter {
                    name,
                    value: v,
                    reason: "the pre-curvature coefficients must be within [-100, 100]",
                });
            }
        }
        self.support.validate()
    }

    /// Diameter ratio `e(s) = 1 + (theta - 1) s` [3.8].
    #[inline]
    pub fn diameter(&self, s: f64) -> f64 {
        1.0 + (self.theta - 1.0) * s
    }

    /// Bending stiffness `EI(s)/EI_b = e(s)^4` [3.8].
    #[inline]
    pub fn stiffness(&self, s: f64) -> f64 {
        let e = self.diameter(s);
        let e2 = e * e;
        e2 * e2
    }

    /// Pre-curvature `kappa0(s) = A s + B` [3.5].
    #[inline]
    pub fn kappa0(&self, s: f64) -> f64 {
        self.a * s + self.b
    }

    /// Tangent angle of a load-free segment that starts at `s1` with angle `phi1`:
    /// `phi1 + A (s^2 - s1^2)/2 + B (s - s1)` (the curvature is the pre-curvature, [3.5]).
    #[inline]
    pub fn phi_free(&self, s1: f64, phi1: f64, s: f64) -> f64 {
        phi1 + 0.5 * self.a * (s * s - s1 * s1) + self.b * (s - s1)
    }

    /// Unloaded tangent angle `pi/2 + A s^2/2 + B s` (rigid base): the load-free segment
    /// from the base ([`Whisker::phi_free`]).
    #[inline]
    pub fn phi_unloaded(&self, s: f64) -> f64 {
        self.phi_free(0.0, std::f64::consts::FRAC_PI_2, s)
    }
}
