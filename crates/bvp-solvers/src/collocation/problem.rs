//! The problem: `y' = f(x, y, p)` (plus the singular term `S y / (x - a)`) with `n + k`
//! boundary residuals `bc(y(a), y(b), p) = 0`, and its Jacobians, analytic or by forward
//! differences with scipy's step `sqrt(eps) (1 + |y_i|)`.

/// A two-point boundary-value problem `y' = f(x, y, p)`, `bc(y(a), y(b), p) = 0` with `n`
/// states and `k` unknown parameters (`bc` returns `n + k` residuals).
///
/// Only [`rhs`](BvpProblem::rhs) and [`bc`](BvpProblem::bc) are required; the Jacobians
/// return `false` by default, and the solver then differences numerically.
///
/// ```
/// use bvp_solvers::collocation::{solve_bvp_problem, BvpOptions, BvpProblem};
/// /// y'' = -y on [0, pi/2], y(0) = 0, y(pi/2) = 1: y = sin x, with its exact Jacobians.
/// struct Sine;
/// impl BvpProblem for Sine {
///     fn rhs(&self, _x: f64, y: &[f64], _p: &[f64], dy: &mut [f64]) {
///         dy[0] = y[1];
///         dy[1] = -y[0];
///     }
///     fn bc(&self, ya: &[f64], yb: &[f64], _p: &[f64], res: &mut [f64]) {
///         res[0] = ya[0];
///         res[1] = yb[0] - 1.0;
///     }
///     fn rhs_jacobian(&self, _x: f64, _y: &[f64], _p: &[f64], dfdy: &mut [f64], _dfdp: &mut [f64]) -> bool {
///         dfdy.copy_from_slice(&[0.0, 1.0, -1.0, 0.0]);
///         true
///     }
///     fn bc_jacobian(&self, _ya: &[f64], _yb: &[f64], _p: &[f64], dya: &mut [f64], dyb: &mut [f64], _dp: &mut [f64]) -> bool {
///         dya.copy_from_slice(&[1.0, 0.0, 0.0, 0.0]);
///         dyb.copy_from_slice(&[0.0, 0.0, 1.0, 0.0]);
///         true
///     }
/// }
/// let x: Vec<f64> = (0..5).map(|i| i as f64 * std::f64::consts::FRAC_PI_8).collect();
/// let y = vec![vec![0.0, 0.0]; 5];
/// let sol = solve_bvp_problem(&Sine, &x, &y, &[], &BvpOptions { tol: 1e-8, ..Default::default() }).unwrap();
/// assert!((sol.eval(0.5)[0] - 0.5f64.sin()).abs() < 1e-8);
/// assert_eq!(sol.stats.rhs_evaluations_for_jacobian, 0);
/// ```
pub trait BvpProblem {
    /// `dy = f(x, y, p)`, without the singular term (the solver adds `S y / (x - a)`).
    fn rhs(&self, x: f64, y: &[f64], p: &[f64], dy: &mut [f64]);
    /// `res = bc(ya, yb, p)`, `n + k` residuals.
    fn bc(&self, ya: &[f64], yb: &[f64], p: &[f64], res: &mut [f64]);
    /// `dfdy` (`n x n`, row-major) and `dfdp` (`n x k`) of `f` at `(x, y, p)` (both come
    /// zeroed: writing the non-zero entries suffices); return `false` (the default) to have
    /// the solver difference `f` numerically.
    fn rhs_jacobian(
        &self,
        _x: f64,
        _y: &[f64],
        _p: &[f64],
        _dfdy: &mut [f64],
        _dfdp: &mut [f64],
    ) -> bool {
        false
    }
    /// `dya`, `dyb` (`(n+k) x n`, row-major) and `dp` (`(n+k) x k`) of `bc` (all come
    /// zeroed); return `false` (the default) to have the solver difference `bc` numerically.
    fn bc_jacobian(
        &self,
        _ya: &[f64],
        _yb: &[f64],
        _p: &[f64],
        _dya: &mut [f64],
        _dyb: &mut [f64],
        _dp: &mut [f64],
    ) -> bool {
        false
    }
}

/// A [`BvpProblem`] from two closures (what [`super::solve_bvp`] wraps).
pub struct FnProblem<F, B> {
    /// `f(x, y, p, dy)`.
    pub f: F,
    /// `bc(ya, yb, p, res)`.
    pub bc: B,
}

impl<F, B> BvpProblem for FnProblem<F, B>
where
    F: Fn(f64, &[f64], &[f64], &mut [f64]),
    B: Fn(&[f64], &[f64], &[f64], &mut [f64]),
{
    fn rhs(&self, x: f64, y: &[f64], p: &[f64], dy: &mut [f64]) {
        (self.f)(x, y, p, dy)
    }
    fn bc(&self, ya: &[f64], yb: &[f64], p: &[f64], res: &mut [f64]) {
        (self.bc)(ya, yb, p, res)
    }
}

/// A [`BvpProblem`] from four closures: `f`, `bc` and their Jacobians (what
/// [`super::solve_bvp_with_jacobian`] wraps). The Jacobian closures take the layouts of
/// [`BvpProblem::rhs_jacobian`] and [`BvpProblem::bc_jacobian`].
pub struct FnProblemJac<F, B, FJ, BJ> {
    /// `f(x, y, p, dy)`.
    pub f: F,
    /// `bc(ya, yb, p, res)`.
    pub bc: B,
    /// `f_jac(x, y, p, dfdy, dfdp)`.
    pub f_jac: FJ,
    /// `bc_jac(ya, yb, p, dya, dyb, dp)`.
    pub bc_jac: BJ,
}

impl<F, B, FJ, BJ> BvpProblem for FnProblemJac<F, B, FJ, BJ>
where
    F: Fn(f64, &[f64], &[f64], &mut [f64]),
    B: Fn(&[f64], &[f64], &[f64], &mut [f64]),
    FJ: Fn(f64, &[f64], &[f64], &mut [f64], &mut [f64]),
    BJ: Fn(&[f64], &[f64], &[f64], &mut [f64], &mut [f64], &mut [f64]),
{
    fn rhs(&self, x: f64, y: &[f64], p: &[f64], dy: &mut [f64]) {
        (self.f)(x, y, p, dy)
    }
    fn bc(&self, ya: &[f64], yb: &[f64], p: &[f64], res: &mut [f64]) {
        (self.bc)(ya, yb, p, res)
    }
    fn rhs_jacobian(
        &self,
        x: f64,
        y: &[f64],
        p: &[f64],
        dfdy: &mut [f64],
        dfdp: &mut [f64],
    ) -> bool {
        (self.f_jac)(x, y, p, dfdy, dfdp);
        true
    }
    fn bc_jacobian(
        &self,
        ya: &[f64],
        yb: &[f64],
        p: &[f64],
        dya: &mut [f64],
        dyb: &mut [f64],
        dp: &mut [f64],
    ) -> bool {
        (self.bc_jac)(ya, yb, p, dya, dyb, dp);
        true
    }
}

/// scipy's forward-difference step for a variable of value `v`: `sqrt(eps) (1 + |v|)`.
pub fn fd_step(v: f64) -> f64 {
    f64::EPSILON.sqrt() * (1.0 + v.abs())
}
