//! What a solve returns: the elastica, the tip, the base observables and statistics.

use serde::{Deserialize, Serialize};

/// The deformed whisker sampled along its arc length (base at the origin).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Elastica {
    /// Arc length s in [0, 1].
    pub s: Vec<f64>,
    /// x(s).
    pub x: Vec<f64>,
    /// y(s).
    pub y: Vec<f64>,
    /// Tangent angle phi(s).
    pub phi: Vec<f64>,
    /// Curvature kappa(s) = phi'(s).
    pub kappa: Vec<f64>,
    /// Bending moment m(s) = e(s)^4 (kappa - kappa0).
    pub m: Vec<f64>,
}

impl Elastica {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.s.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.s.is_empty()
    }

    /// Appends a sample.
    pub(crate) fn push(&mut self, s: f64, x: f64, y: f64, phi: f64, kappa: f64, m: f64) {
        self.s.push(s);
        self.x.push(x);
        self.y.push(y);
        self.phi.push(phi);
        self.kappa.push(kappa);
        self.m.push(m);
    }
}

/// Position and tangent angle of one point of the whisker.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EndState {
    /// x coordinate (base at x = 0).
    pub x: f64,
    /// y coordinate.
    pub y: f64,
    /// Tangent angle.
    pub phi: f64,
}

/// The observables at the base: reactions of the support on the whisker and the base angle.
/// `Ax = -(f cos beta + q s1 cos alpha)`, `Ay = f sin beta + q s1 sin alpha`, `MA = -m(0)`,
/// `phi0 = phi(0)` (spec/model.md; thesis [5.1, 6.7-6.9]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BaseObservables {
    /// Horizontal reaction.
    pub ax: f64,
    /// Vertical reaction.
    pub ay: f64,
    /// Reaction moment.
    pub ma: f64,
    /// Base angle.
    pub phi0: f64,
}

/// Statistics of a solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SolveStats {
    /// Newton (or outer) iterations of the final solve.
    pub iterations: usize,
    /// Final residual of the boundary conditions.
    pub residual: f64,
    /// Load-continuation steps used (0 when the direct solve succeeded).
    pub continuation_steps: usize,
    /// Right-hand-side evaluations or FDM sweeps, a machine-independent cost measure.
    pub evaluations: usize,
}

/// A solved scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// The deformed shape, base at the origin.
    pub elastica: Elastica,
    /// The free end s = 1.
    pub tip: EndState,
    /// The loaded end s = s1 (equals `tip` when s1 = 1).
    pub loaded_end: EndState,
    /// Base observables.
    pub base: BaseObservables,
    /// Statistics.
    pub stats: SolveStats,
}
