//! # bvp-solvers
//!
//! A generic toolkit for non-linear two-point boundary-value problems, written for beam
//! problems but knowing nothing about whiskers:
//!
//! | module | concept |
//! |---|---|
//! | [`grid`] | uniform grids on `[a, b]` |
//! | [`dense`] | small dense linear algebra: pivoted Gaussian elimination (any `N x N`, 2x2 included), the inverse, Cholesky factor and solves of symmetric positive definite systems |
//! | [`tridiag`] | the Thomas algorithm for tridiagonal systems |
//! | [`fdm`] | finite differences for `y'' = F(x, y, y')` with Newton on the tridiagonal Jacobian |
//! | [`richardson`] | Richardson extrapolation of FDM results on `h, h/2, ...` |
//! | [`integrator`] | first-order systems `u' = G(s, u)`: fixed-step RK4, adaptive Dormand-Prince 8(5,3) with dense output and events |
//! | [`newton`] | Newton's method for small systems with one convergence policy (damping, Jacobian reuse or Broyden, noise floor, termination reason; safeguards: largest step, stall detection, early exits): square, least squares (Gauss-Newton) and the nearest point of an underdetermined one (projection) |
//! | [`nonlinear`] | one interface for small non-linear systems: Newton the fast path, the trust region the fallback, which one ran and why it stopped; [`nonlinear::SquareNewton`] for square systems of run-time size (pivoted LU / truncated QR of J, damping, failed trial points shrink the step) |
//! | [`roots`] | scalar roots: bisection, Brent (the `fzero` equivalents) and Cauchy |
//! | [`trust_region`] | small non-linear systems by argmin's trust region (the `fsolve` equivalent) |
//! | [`shooting`] | shooting: unknown initial values / parameters found so that boundary residuals vanish; Newton with the problem's own sensitivities (what the domain runs), or forward differences and the trust region for bare ODEs |
//! | [`collocation`] | `solve_bvp`: collocation (3-point Lobatto IIIA, bvp4c/scipy) for first-order systems with unknown parameters, any boundary residuals and a singular term, residual control with mesh refinement, analytic or differenced Jacobians, dense output |
//! | [`multiple_shooting`] | multiple shooting for first-order systems with parameters: DOP853 with variational equations per segment, the staircase Newton system by structured elimination, node insertion where a segment grows too much |
//! | [`continuation`] | continuation of a solution branch: pseudo-arclength through folds with located events ([`continuation::Arclength`] on a [`continuation::Curve`]), and natural-parameter continuation ([`continuation::Continuation::follow`]) as its special case with the parameter as the one coordinate |
//!
//! Every fallible routine returns [`BvpError`], whose variants carry the numbers
//! (iterations, residual, row, offending value).

pub mod collocation;
pub mod continuation;
pub mod dense;
pub mod error;
pub mod fdm;
pub mod grid;
pub mod integrator;
pub mod interp;
pub mod multiple_shooting;
pub mod newton;
pub mod nonlinear;
pub mod parallel;
pub mod richardson;
pub mod roots;
pub mod shooting;
#[cfg(test)]
mod testing;
pub mod tridiag;
pub mod trust_region;

pub use error::BvpError;

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, BvpError>;
