//! The types of a collocation solve: its options ([`BvpOptions`]), its answer
//! ([`BvpSolution`], with the dense output) and its work counts ([`BvpStats`]); re-exported
//! by the parent module, where they are documented with [`solve_bvp`].

use super::hermite;
#[cfg(doc)]
use super::{mesh, solve_bvp};
#[cfg(doc)]
use crate::BvpError;

/// Options of [`solve_bvp`]; the defaults are scipy's.
#[derive(Debug, Clone, PartialEq)]
pub struct BvpOptions {
    /// The relative residual asked for (scipy's `tol`, default `1e-3`; raised to `100 eps`
    /// if smaller).
    pub tol: f64,
    /// Tolerance of the boundary residuals (`None`: `tol`, as scipy).
    pub bc_tol: Option<f64>,
    /// Largest mesh allowed (default 1000, scipy's).
    pub max_nodes: usize,
    /// The `n x n` matrix `S` (row-major) of a singular term `S y / (x - a)`.
    pub singular: Option<Vec<f64>>,
    /// Remove nodes where the residual is far below `tol` while refining elsewhere (bvp4c's
    /// rule, [`mesh::removable`]; default `true`). scipy never removes nodes.
    pub remove_nodes: bool,
    /// Meshes solved without refinement before boundary residuals above `bc_tol` are reported
    /// as [`BvpError::NoConvergence`] (default 10, scipy's `max_iteration`).
    pub max_iterations: usize,
}

impl Default for BvpOptions {
    fn default() -> Self {
        Self {
            tol: 1e-3,
            bc_tol: None,
            max_nodes: 1000,
            singular: None,
            remove_nodes: true,
            max_iterations: 10,
        }
    }
}

/// Work counts of a solve.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BvpStats {
    /// Nodes of the final mesh.
    pub nodes: usize,
    /// Meshes solved (1 + refinements + bc-only repeats).
    pub mesh_iterations: usize,
    /// Newton iterations over all meshes.
    pub newton_iterations: usize,
    /// Jacobians evaluated (and factored).
    pub jacobian_evaluations: usize,
    /// Evaluations of `f`, those for differenced Jacobians included.
    pub rhs_evaluations: usize,
    /// Evaluations of `f` spent on differenced Jacobians.
    pub rhs_evaluations_for_jacobian: usize,
    /// Evaluations of `bc`.
    pub bc_evaluations: usize,
    /// Whether `df/dy` was differenced (no analytic Jacobian).
    pub jacobian_by_differences: bool,
}

/// The solution of [`solve_bvp`]: the final mesh, the values and slopes there, the parameters
/// and the residuals reached (the error estimate).
#[derive(Debug, Clone, PartialEq)]
pub struct BvpSolution {
    /// The final mesh.
    pub x: Vec<f64>,
    /// `y` at each node.
    pub y: Vec<Vec<f64>>,
    /// `y' = f(x, y, p)` (with the singular term) at each node.
    pub yp: Vec<Vec<f64>>,
    /// The parameters found.
    pub p: Vec<f64>,
    /// The relative RMS residual of each interval (see the module doc).
    pub rms_residuals: Vec<f64>,
    /// The largest of [`Self::rms_residuals`].
    pub max_rms_residual: f64,
    /// The largest absolute boundary residual.
    pub max_bc_residual: f64,
    /// Work counts.
    pub stats: BvpStats,
}

impl BvpSolution {
    /// `y(t)` from the `C1` cubic Hermite interpolant [H.1] (extrapolated by the end cubics
    /// outside `[a, b]`).
    pub fn eval(&self, t: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.y[0].len()];
        self.eval_into(t, &mut out, &mut []);
        out
    }

    /// `y'(t)` of the interpolant.
    pub fn eval_derivative(&self, t: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.y[0].len()];
        self.eval_into(t, &mut [], &mut out);
        out
    }

    /// `y(t)` into `out` and `y'(t)` into `dout` (either may be empty).
    pub fn eval_into(&self, t: f64, out: &mut [f64], dout: &mut [f64]) {
        let i = hermite::interval(&self.x, t);
        let h = self.x[i + 1] - self.x[i];
        hermite::hermite(
            self.x[i],
            h,
            &self.y[i],
            &self.y[i + 1],
            &self.yp[i],
            &self.yp[i + 1],
            t,
            out,
            dout,
        );
    }
}
