//! The one error type of the crate.

use thiserror::Error;

/// Everything that can go wrong in a BVP solve. Variants carry the numbers needed to act on
/// the failure: where it happened, after how many iterations, with which residual.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BvpError {
    /// An iterative method stopped without meeting its tolerance.
    #[error("{method} did not converge after {iterations} iterations (residual {residual:.3e})")]
    NoConvergence {
        /// The method that failed, e.g. `"fdm-newton"`, `"brent"`, `"trust-region"`.
        method: &'static str,
        /// Iterations performed.
        iterations: usize,
        /// Final residual norm (max-norm unless the method documents otherwise).
        residual: f64,
    },
    /// A (tridiagonal or dense) Jacobian is singular: zero pivot in `row`.
    #[error("singular Jacobian: zero pivot in row {row} (pivot {pivot:.3e})")]
    SingularJacobian {
        /// Row of the zero pivot (0-based).
        row: usize,
        /// The pivot value found.
        pivot: f64,
    },
    /// An input is out of its admissible range or not finite.
    #[error("invalid input: {name} = {value} ({reason})")]
    InvalidInput {
        /// Name of the offending parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What was expected.
        reason: &'static str,
    },
    /// Two arrays that must match in length do not.
    #[error("dimension mismatch for {name}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// What was measured.
        name: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// A scalar root finder was given an interval whose ends do not bracket a sign change.
    #[error("no sign change on [{a}, {b}]: f(a) = {fa:.3e}, f(b) = {fb:.3e}")]
    NotBracketed {
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
        /// f at the left end.
        fa: f64,
        /// f at the right end.
        fb: f64,
    },
    /// An adaptive integrator's step size fell below what floating point resolves.
    #[error("step size underflow at s = {s} (h = {h:.3e})")]
    StepSizeUnderflow {
        /// Where the integration stalled.
        s: f64,
        /// The step size attempted.
        h: f64,
    },
    /// An adaptive integrator used up its step budget.
    #[error("step budget of {max_steps} exhausted at s = {s}")]
    TooManySteps {
        /// The budget.
        max_steps: usize,
        /// Where the integration stopped.
        s: f64,
    },
    /// A right-hand side, residual or Jacobian produced a NaN or infinity.
    #[error("non-finite value in {what} at s = {s}")]
    NonFinite {
        /// Which quantity.
        what: &'static str,
        /// Independent variable (or iteration index) where it appeared.
        s: f64,
    },
    /// Mesh refinement would exceed the node budget before the residual met its tolerance.
    #[error("mesh limit: {needed} nodes needed, max_nodes = {max_nodes}; largest relative residual {max_rms_residual:.3e} (tol {tol:.1e})")]
    MeshLimit {
        /// The budget (`max_nodes`).
        max_nodes: usize,
        /// Nodes the next refinement would have needed.
        needed: usize,
        /// The largest relative residual on the last mesh.
        max_rms_residual: f64,
        /// The tolerance asked for.
        tol: f64,
    },
}
