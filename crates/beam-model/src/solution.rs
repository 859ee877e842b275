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

    /// An empty elastica with room for `n` samples.
    pub(crate) fn with_capacity(n: usize) -> Self {
        Elastica {
            s: Vec::with_capacity(n),
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            phi: Vec::with_capacity(n),
            kappa: Vec::with_capacity(n),
            m: Vec::with_capacity(n),
        }
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

/// Which method produced a solution's numbers ([`SolveStats::method_used`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum MethodKind {
    /// Adaptive DOP853 shooting.
    #[default]
    Accurate,
    /// Fixed-step RK4 shooting.
    Rk4,
    /// Central finite differences [3.25, 3.27].
    Fdm,
    /// FDM on nested grids with two Richardson levels.
    FdmRichardson,
    /// One integration from a known tip angle (no boundary-value solve).
    Shape,
    /// The spectral Picard iteration of the integral form (weak and moderate loads); with
    /// [`ModelKind::Linear`], its first iterate alone (linear small-deflection theory
    /// evaluated by the same Chebyshev quadrature, no iteration).
    Picard,
    /// The cheapest method that meets a requested accuracy (`Method::Auto`).
    Auto,
    /// Multiple shooting on `[0, s1]` (`Method::MultipleShooting`, `accurate`'s last
    /// fallback).
    MultipleShooting,
    /// Collocation with load continuation on `[0, s1]` (`Method::Collocation`, `accurate`'s
    /// last fallback after multiple shooting).
    Collocation,
}

impl MethodKind {
    /// The name used by the CLI and the charts (`accurate`, `rk4`, `fdm`, `fdm-richardson`,
    /// `shape`, `picard`, `auto`, `multiple-shooting`, `collocation`).
    pub fn name(&self) -> &'static str {
        match self {
            MethodKind::Accurate => "accurate",
            MethodKind::Rk4 => "rk4",
            MethodKind::Fdm => "fdm",
            MethodKind::FdmRichardson => "fdm-richardson",
            MethodKind::Shape => "shape",
            MethodKind::Picard => "picard",
            MethodKind::Auto => "auto",
            MethodKind::MultipleShooting => "multiple-shooting",
            MethodKind::Collocation => "collocation",
        }
    }
}

/// Which model of the whisker produced a solution's numbers ([`SolveStats::model_used`]),
/// beside the method that computed them ([`SolveStats::method_used`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ModelKind {
    /// Linear small-deflection theory: the loads' moment on the unloaded shape
    /// (module [`linear`](crate::linear)); only `Method::Auto` answers with it, where its
    /// a-priori bound proves it meets the accuracy asked for.
    Linear,
    /// The large-deflection elastica [3.25] with its boundary conditions [3.21, 3.22]:
    /// every method's model.
    #[default]
    Elastica,
}

impl ModelKind {
    /// The name used by the CLI (`linear`, `elastica`).
    pub fn name(&self) -> &'static str {
        match self {
            ModelKind::Linear => "linear",
            ModelKind::Elastica => "elastica",
        }
    }
}

/// Statistics of a solve, with its a-posteriori error estimate.
///
/// `error_estimate` bounds the absolute error of the returned tip, loaded end (x, y, phi)
/// and base observables (MA, phi0; Ax, Ay follow from phi1) by an independent second
/// solution, not by the solve's own residual: a tighter-tolerance shot corrected by one
/// Newton step (`accurate`), a doubled grid (`fdm`, `rk4`), the last Richardson level
/// (`fdm-richardson`), the contraction bound plus a doubled grid (`picard`); linear theory
/// (`model_used` linear, `auto` only) bounds the model's error a priori (a closed-form
/// contraction constant of the integral form, module `methods::linear_rung`) and adds a
/// doubled grid's difference. A solve whose estimate exceeds `tolerance` is returned as
/// [`ModelError::Inaccurate`](crate::ModelError::Inaccurate), never as a solution.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolveStats {
    /// Newton (or outer) iterations of the final solve.
    pub iterations: usize,
    /// Final residual of the boundary conditions.
    pub residual: f64,
    /// Load-continuation steps used (0 when the direct solve succeeded).
    pub continuation_steps: usize,
    /// Right-hand-side evaluations or FDM sweeps, a machine-independent cost measure.
    pub evaluations: usize,
    /// A-posteriori estimate of the absolute error (see the type's docs); NaN when none was
    /// computed (a bare shape integration).
    #[serde(default = "nan")]
    pub error_estimate: f64,
    /// The accuracy the estimate was checked against (`Method::tolerance`).
    #[serde(default = "inf")]
    pub tolerance: f64,
    /// The method that produced the numbers.
    #[serde(default)]
    pub method_used: MethodKind,
    /// The model whose numbers they are: the elastica, or linear theory where `auto`
    /// proved it meets the accuracy asked for (absent from old JSON: the elastica).
    #[serde(default)]
    pub model_used: ModelKind,
    /// Load steps at which the continuation's corrector converged on another equilibrium
    /// (rejected by the branch guard): when > 0, other equilibria exist along the load path;
    /// the one returned is the branch reached by loading from zero.
    #[serde(default)]
    pub branch_jumps: usize,
    /// The method that was requested; differs from `method_used` after a fallback (e.g.
    /// `accurate` -> `fdm-richardson` where shooting is ill-conditioned).
    #[serde(default)]
    pub requested: MethodKind,
}

fn nan() -> f64 {
    f64::NAN
}

fn inf() -> f64 {
    f64::INFINITY
}

impl Default for SolveStats {
    fn default() -> Self {
        SolveStats {
            iterations: 0,
            residual: 0.0,
            continuation_steps: 0,
            evaluations: 0,
            branch_jumps: 0,
            error_estimate: f64::NAN,
            tolerance: f64::INFINITY,
            method_used: MethodKind::Accurate,
            model_used: ModelKind::Elastica,
            requested: MethodKind::Accurate,
        }
    }
}

impl SolveStats {
    /// Whether the numbers come from another method than the one requested.
    pub fn fell_back(&self) -> bool {
        self.method_used != self.requested
    }
}

/// A fold of the load path: the load scale at which the equilibrium followed from zero
/// turns back (`dR/dphi1 = 0`), with its tip and base angles.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadFold {
    /// The load scale of the fold (the loads there are `lambda` times the scene's).
    pub lambda: f64,
    /// The tip angle there.
    pub phi1: f64,
    /// The base angle there.
    pub phi0: f64,
}

/// An equilibrium at full load on the load path (tip and base angles).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathEquilibrium {
    /// The tip angle `phi1`.
    pub phi1: f64,
    /// The base angle `phi0`.
    pub phi0: f64,
}

/// What following the load path found: the folds passed before the first arrival at full
/// load (in order), that arrival, and the other equilibria at full load met further along
/// the path (at most three, within 100 steps past the arrival and load scales in [0, 2]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadPath {
    /// Folds of the path from zero load to the returned equilibrium.
    pub folds: Vec<LoadFold>,
    /// The returned equilibrium: the first arrival at full load.
    pub arrival: PathEquilibrium,
    /// Other equilibria at full load further along the same path.
    pub others: Vec<PathEquilibrium>,
    /// Accepted arclength steps from zero load to the arrival.
    pub steps: usize,
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
    /// The load path from zero where the method's own load continuation stalled or ended
    /// past a fold: its folds and the other equilibria at full load (`None` otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_path: Option<LoadPath>,
}

impl Solution {
    /// Largest difference of the tip, the loaded end and the base observables from `other`
    /// (NaN if any is NaN): the norm of the methods' error estimates.
    pub fn difference(&self, other: &Solution) -> f64 {
        let (a, b) = (self, other);
        [
            a.tip.x - b.tip.x,
            a.tip.y - b.tip.y,
            a.tip.phi - b.tip.phi,
            a.loaded_end.x - b.loaded_end.x,
            a.loaded_end.y - b.loaded_end.y,
            a.loaded_end.phi - b.loaded_end.phi,
            a.base.ma - b.base.ma,
            a.base.phi0 - b.base.phi0,
            a.base.ax - b.base.ax,
            a.base.ay - b.base.ay,
        ]
        .iter()
        .fold(
            0.0,
            |m, d| if d.is_nan() { f64::NAN } else { m.max(d.abs()) },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stats written before `model_used` existed read back as the elastica's; the field
    /// round-trips.
    #[test]
    fn model_used_defaults_to_the_elastica_and_round_trips() {
        let old = r#"{"iterations": 3, "residual": 0.0, "continuation_steps": 0,
            "evaluations": 10, "method_used": "Picard"}"#;
        let stats: SolveStats = serde_json::from_str(old).unwrap();
        assert_eq!(stats.model_used, ModelKind::Elastica);
        assert_eq!(stats.method_used, MethodKind::Picard);
        let linear = SolveStats {
            model_used: ModelKind::Linear,
            // (JSON has no NaN)
            error_estimate: 1e-3,
            tolerance: 1e-2,
            ..stats
        };
        let text = serde_json::to_string(&linear).unwrap();
        let back: SolveStats = serde_json::from_str(&text).unwrap();
        assert_eq!(back.model_used, ModelKind::Linear);
        assert_eq!(
            (ModelKind::Linear.name(), ModelKind::Elastica.name()),
            ("linear", "elastica")
        );
    }
}
