//! Finite differences for the scalar two-point problem
//!
//! ```text
//! y'' = F(x, y, y'),   a <= x <= b,
//! alpha_a y(a) + beta_a y'(a) = gamma_a,   alpha_b y(b) + beta_b y'(b) = gamma_b
//! ```
//!
//! (thesis section 2.4). On a [`UniformGrid`] with nodes `x_i`, `i = 0..=n`, step `h`:
//!
//! - interior nodes use central differences,
//!   `(y_{i-1} - 2 y_i + y_{i+1}) / h^2 = F(x_i, y_i, (y_{i+1} - y_{i-1}) / (2h))`;
//! - a boundary condition with `beta != 0` is imposed by the ghost-point method: the
//!   central difference equation is also written at the end node, and the ghost value is
//!   eliminated with the central approximation of the condition, e.g. at `x_0`
//!   `y_{-1} = y_1 - 2h y'_0` with `y'_0 = (gamma - alpha y_0) / beta`; this keeps the
//!   scheme second order and reproduces quadratics exactly;
//! - a condition with `beta == 0` is the Dirichlet row `alpha y_0 = gamma`.
//!
//! Each equation is multiplied by `h^2` (ghost-point rows by `h^2 / 2`), so the discrete
//! residual `G(y)` is measured in units of `y` and its rounding level does not grow like
//! `1/h^2`. The system `G(y) = 0` is solved by (optionally damped) Newton,
//! `J(y_k) delta = -G(y_k)`, `y_{k+1} = y_k + damping * delta`, where the tridiagonal
//! Jacobian `J` is assembled from `F_y` and `F_{y'}` and factorised by the Thomas algorithm
//! ([`crate::tridiag`]). All buffers are allocated once per solve.
//!
//! **Right-end dependence.** When [`SecondOrderBvp::depends_on_right_end`] is true the
//! equation is `y'' = F(x, y, y', y(b))`, with `y(b) = y_n` the unknown end value (e.g. the
//! tip angle `phi1` of an angle-preserving load, thesis [3.25] with
//! `m' = f cos(phi + beta - phi1)`). Every row `i` then also depends on `y_n` through
//! `dG_i/dy_n = -h^2 F_{y(b)}(x_i)` (`-h^2/2 F_{y(b)}` in ghost-point rows), so the Newton
//! matrix is bordered, `J = T + c e_n^T`: tridiagonal plus one dense last column. It is
//! factorised in `O(n)` by Gaussian elimination with partial pivoting between the two
//! candidate rows of each column (the band grows by one superdiagonal, the last column stays
//! a column), which needs only `J` itself nonsingular, not `T` (Sherman–Morrison would fail
//! where the fixed-`y(b)` problem `T` has a fold while `J` is regular, exactly the AP case).

use crate::grid::UniformGrid;
use crate::tridiag::Tridiagonal;
use crate::{BvpError, Result};

/// A second-order scalar ODE `y'' = F(x, y, y')` together with the partial derivatives
/// that Newton's method needs.
///
/// ```
/// use bvp_solvers::fdm::{BoundaryCondition, FdmSolver, SecondOrderBvp};
/// use bvp_solvers::grid::UniformGrid;
///
/// /// The Bratu problem y'' + e^y = 0, y(0) = y(1) = 0; lower branch, closed form
/// /// y(1/2) = 2 ln cosh(t/4) = 0.1405392144 with t = 1.5171645990507543.
/// struct Bratu;
/// impl SecondOrderBvp for Bratu {
///     fn f(&self, _x: f64, y: f64, _yp: f64) -> f64 { -y.exp() }
///     fn f_y(&self, _x: f64, y: f64, _yp: f64) -> f64 { -y.exp() }
///     fn f_yp(&self, _x: f64, _y: f64, _yp: f64) -> f64 { 0.0 }
/// }
///
/// let grid = UniformGrid::new(0.0, 1.0, 200).unwrap();
/// let solver = FdmSolver::new(BoundaryCondition::Dirichlet(0.0), BoundaryCondition::Dirichlet(0.0));
/// let sol = solver.solve(&Bratu, &grid, &vec![0.0; grid.len()]).unwrap();
/// // second order: error ~ h^2 = 2.5e-5 times a small constant
/// assert!((sol.y[100] - 0.1405392144).abs() < 1e-5);
/// ```
pub trait SecondOrderBvp {
    /// The right-hand side `F(x, y, y')`.
    fn f(&self, x: f64, y: f64, yp: f64) -> f64;
    /// `dF/dy (x, y, y')`.
    fn f_y(&self, x: f64, y: f64, yp: f64) -> f64;
    /// `dF/dy' (x, y, y')`.
    fn f_yp(&self, x: f64, y: f64, yp: f64) -> f64;
    /// `(F, F_y, F_{y'})` at once. The default calls the three methods; override it when
    /// they share expensive sub-expressions (the solver only calls this method).
    fn eval(&self, x: f64, y: f64, yp: f64) -> (f64, f64, f64) {
        (self.f(x, y, yp), self.f_y(x, y, yp), self.f_yp(x, y, yp))
    }
    /// Whether `F` also depends on the right-end value `y(b)` (a non-local term, as in a
    /// follower load whose direction is the unknown end angle), i.e. the problem is
    /// `y'' = F(x, y, y', y(b))`. When `true` the solver calls only
    /// [`eval_with_right_end`](Self::eval_with_right_end) and adds the column `dG/dy_n` to the
    /// Jacobian (see the [module docs](self)). Default `false`.
    fn depends_on_right_end(&self) -> bool {
        false
    }
    /// `(F, F_y, F_{y'}, F_{y(b)})` at `(x, y, y', y(b))`. The default ignores `yb`, returns
    /// [`eval`](Self::eval) and `F_{y(b)} = 0`; override it together with
    /// [`depends_on_right_end`](Self::depends_on_right_end).
    fn eval_with_right_end(&self, x: f64, y: f64, yp: f64, yb: f64) -> (f64, f64, f64, f64) {
        let _ = yb;
        let (f, fy, fyp) = self.eval(x, y, yp);
        (f, fy, fyp, 0.0)
    }
}

/// A [`SecondOrderBvp`] built from three closures `F`, `F_y`, `F_{y'}` of `(x, y, y')`.
#[derive(Clone, Debug)]
pub struct FnBvp<F, Fy, Fyp> {
    /// `F(x, y, y')`.
    pub f: F,
    /// `dF/dy`.
    pub f_y: Fy,
    /// `dF/dy'`.
    pub f_yp: Fyp,
}

impl<F, Fy, Fyp> FnBvp<F, Fy, Fyp>
where
    F: Fn(f64, f64, f64) -> f64,
    Fy: Fn(f64, f64, f64) -> f64,
    Fyp: Fn(f64, f64, f64) -> f64,
{
    /// Wraps the closures `F`, `F_y`, `F_{y'}`.
    pub fn new(f: F, f_y: Fy, f_yp: Fyp) -> Self {
        Self { f, f_y, f_yp }
    }
}

impl<F, Fy, Fyp> SecondOrderBvp for FnBvp<F, Fy, Fyp>
where
    F: Fn(f64, f64, f64) -> f64,
    Fy: Fn(f64, f64, f64) -> f64,
    Fyp: Fn(f64, f64, f64) -> f64,
{
    fn f(&self, x: f64, y: f64, yp: f64) -> f64 {
        (self.f)(x, y, yp)
    }
    fn f_y(&self, x: f64, y: f64, yp: f64) -> f64 {
        (self.f_y)(x, y, yp)
    }
    fn f_yp(&self, x: f64, y: f64, yp: f64) -> f64 {
        (self.f_yp)(x, y, yp)
    }
}

/// Boundary condition `alpha y + beta y' = gamma` at one end.
/// `Dirichlet(v)` is `Robin { alpha: 1, beta: 0, gamma: v }`, `Neumann(v)` is
/// `Robin { alpha: 0, beta: 1, gamma: v }`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BoundaryCondition {
    /// `y = v`.
    Dirichlet(f64),
    /// `y' = v`.
    Neumann(f64),
    /// `alpha y + beta y' = gamma`.
    Robin {
        /// Coefficient of `y`.
        alpha: f64,
        /// Coefficient of `y'`.
        beta: f64,
        /// Right-hand side.
        gamma: f64,
    },
}

impl BoundaryCondition {
    /// The coefficients `(alpha, beta, gamma)` of `alpha y + beta y' = gamma`.
    pub fn coefficients(&self) -> (f64, f64, f64) {
        match *self {
            Self::Dirichlet(v) => (1.0, 0.0, v),
            Self::Neumann(v) => (0.0, 1.0, v),
            Self::Robin { alpha, beta, gamma } => (alpha, beta, gamma),
        }
    }

    fn validated(&self, name: &'static str) -> Result<Bc> {
        let (alpha, beta, gamma) = self.coefficients();
        for v in [alpha, beta, gamma] {
            if !v.is_finite() {
                return Err(BvpError::InvalidInput {
                    name,
                    value: v,
                    reason: "boundary-condition coefficients must be finite",
                });
            }
        }
        Ok(Bc { alpha, beta, gamma })
    }
}

/// Validated coefficients.
#[derive(Clone, Copy, Debug)]
struct Bc {
    alpha: f64,
    beta: f64,
    gamma: f64,
}

impl Bc {
    /// `y'` implied by the condition (only meaningful for `beta != 0`).
    #[inline]
    fn slope(&self, y: f64) -> f64 {
        (self.gamma - self.alpha * y) / self.beta
    }
}

/// Newton options of [`FdmSolver`].
#[derive(Clone, Debug)]
pub struct FdmOptions {
    /// Tolerance on the max-norm of the Newton step AND of the (`h^2`-scaled) residual.
    /// Both tests are floored at the rounding level of the discrete system (see
    /// [`FdmSolver::solve`]), so a tolerance below what `f64` resolves on a fine grid
    /// still terminates.
    pub tol: f64,
    /// Maximum number of Newton iterations (at least 1).
    pub max_iter: usize,
    /// Newton step factor in `(0, 1]`; `1` is full Newton.
    pub damping: f64,
}

impl Default for FdmOptions {
    /// `tol = 1e-12`, `max_iter = 100`, `damping = 1`.
    fn default() -> Self {
        Self {
            tol: 1e-12,
            max_iter: 100,
            damping: 1.0,
        }
    }
}

impl FdmOptions {
    /// Checks `tol` finite and positive, `max_iter >= 1`, `damping` in `(0, 1]`.
    ///
    /// # Errors
    /// [`BvpError::InvalidInput`] naming the offending field.
    pub fn validate(&self) -> Result<()> {
        if !(self.tol.is_finite() && self.tol > 0.0) {
            return Err(BvpError::InvalidInput {
                name: "tol",
                value: self.tol,
                reason: "tolerance must be finite and positive",
            });
        }
        if self.max_iter == 0 {
            return Err(BvpError::InvalidInput {
                name: "max_iter",
                value: 0.0,
                reason: "at least one Newton iteration is required",
            });
        }
        if !(self.damping > 0.0 && self.damping <= 1.0) {
            return Err(BvpError::InvalidInput {
                name: "damping",
                value: self.damping,
                reason: "damping must lie in (0, 1]",
            });
        }
        Ok(())
    }
}

/// Convergence record of a solve.
#[derive(Clone, Debug)]
pub struct FdmStats {
    /// Newton iterations performed (each one linear solve).
    pub iterations: usize,
    /// Max-norm of the `h^2`-scaled discrete residual at the returned solution.
    pub residual: f64,
    /// Max-norm of the last (undamped) Newton step.
    pub step_norm: f64,
}

/// Result of [`FdmSolver::solve`].
#[derive(Clone, Debug)]
pub struct FdmSolution {
    /// The grid solved on.
    pub grid: UniformGrid,
    /// Nodal values `y_i`.
    pub y: Vec<f64>,
    /// Second-order estimates of `y'(x_i)` at every node: central differences inside;
    /// at an end with `beta != 0` the value `(gamma - alpha y) / beta` implied by the
    /// boundary condition; at a Dirichlet end the one-sided
    /// `(-3 y_0 + 4 y_1 - y_2) / (2h)` (mirrored at `x_n`).
    pub yp: Vec<f64>,
    /// Convergence record.
    pub stats: FdmStats,
}

/// Finite-difference solver for `y'' = F(x, y, y')` with the two boundary conditions.
#[derive(Clone, Debug)]
pub struct FdmSolver {
    /// Condition at `x = a`.
    pub left: BoundaryCondition,
    /// Condition at `x = b`.
    pub right: BoundaryCondition,
    /// Newton options.
    pub options: FdmOptions,
}

impl FdmSolver {
    /// Solver with the given conditions and [`FdmOptions::default`].
    pub fn new(left: BoundaryCondition, right: BoundaryCondition) -> Self {
        Self {
            left,
            right,
            options: FdmOptions::default(),
        }
    }

    /// Replaces the options (builder style).
    pub fn with_options(mut self, options: FdmOptions) -> Self {
        self.options = options;
        self
    }

    /// Solves the discrete problem described in the [module docs](self): central
    /// differences `(y_{i-1} - 2y_i + y_{i+1})/h^2 = F(x_i, y_i, (y_{i+1}-y_{i-1})/(2h))`,
    /// derivative conditions by the ghost-point method (second order), Newton on the
    /// tridiagonal Jacobian assembled from `F_y`, `F_{y'}`, damped by `options.damping`,
    /// starting from `guess` (`grid.len()` values).
    ///
    /// Convergence: after iteration `k` the solver stops when the undamped step satisfies
    /// `|delta|_inf <= max(tol, 2 kappa e_G + 4 eps |y|_inf)` and the new residual
    /// `|G|_inf <= max(tol, e_G)`, where `e_G = 8 eps max_i(sum of |terms| of row i)` is the
    /// rounding level of the residual and `kappa = max_k |delta_k| / |G_k|` is the observed
    /// lower estimate of `|J^{-1}|_inf` (about `(b - a)^2 / (8 h^2)` for `y'' = 0`), so the
    /// floors only matter when `tol` is below what the grid resolves in `f64`. A linear
    /// problem therefore takes two iterations, a non-linear one converges quadratically.
    ///
    /// # Errors
    /// - [`BvpError::InvalidInput`]: invalid options, non-finite boundary coefficients or
    ///   guess values;
    /// - [`BvpError::DimensionMismatch`]: `guess.len() != grid.len()`;
    /// - [`BvpError::NonFinite`]: `F` or its derivatives produced NaN/inf (`s` is the node
    ///   `x_i`), or the Newton step did (`s` is the iteration number);
    /// - [`BvpError::SingularJacobian`]: zero pivot in the Thomas factorisation (`row` is
    ///   the node index), e.g. `alpha = beta = 0` or pure Neumann data for `y'' = f(x)`;
    /// - [`BvpError::NoConvergence`] `{ method: "fdm-newton", .. }` after `max_iter`
    ///   iterations, with the last residual.
    pub fn solve<P: SecondOrderBvp + ?Sized>(
        &self,
        problem: &P,
        grid: &UniformGrid,
        guess: &[f64],
    ) -> Result<FdmSolution> {
        self.options.validate()?;
        let left = self.left.validated("left boundary condition")?;
        let right = self.right.validated("right boundary condition")?;
        let len = grid.len();
        if guess.len() != len {
            return Err(BvpError::DimensionMismatch {
                name: "guess",
                expected: len,
                found: guess.len(),
            });
        }
        if let Some(&v) = guess.iter().find(|v| !v.is_finite()) {
            return Err(BvpError::InvalidInput {
                name: "guess",
                value: v,
                reason: "initial guess must be finite",
            });
        }

        let tol = self.options.tol;
        let damping = self.options.damping;
        let mut y = guess.to_vec();
        let mut g = vec![0.0; len];
        let mut jac = Tridiagonal::new(len);
        let mut scratch = vec![0.0; len];
        let bordered = problem.depends_on_right_end();
        let mut border = if bordered { vec![0.0; len] } else { Vec::new() };
        let mut lu = if bordered {
            BorderedLu::new(len)
        } else {
            BorderedLu::new(0)
        };
        let asm = Assembler {
            problem,
            grid,
            left,
            right,
            bordered,
        };

        let (mut res, _) = asm.assemble(&y, &mut g, &mut jac, &mut border)?;
        let mut kappa = 0.0_f64;
        for k in 1..=self.options.max_iter {
            g.iter_mut().for_each(|v| *v = -*v);
            if bordered {
                lu.solve_in_place(&jac, &border, &mut g)?;
            } else {
                jac.solve_in_place(&mut g, &mut scratch)?;
            }
            let step = max_abs(&g);
            if !step.is_finite() {
                return Err(BvpError::NonFinite {
                    what: "fdm newton step",
                    s: k as f64,
                });
            }
            if res > 0.0 {
                kappa = kappa.max(step / res);
            }
            y.iter_mut()
                .zip(&g)
                .for_each(|(yi, di)| *yi += damping * di);
            let (new_res, noise) = asm.assemble(&y, &mut g, &mut jac, &mut border)?;
            res = new_res;

            let e_g = 8.0 * f64::EPSILON * noise;
            let tol_res = tol.max(e_g);
            let tol_step = tol.max(2.0 * kappa * e_g + 4.0 * f64::EPSILON * max_abs(&y));
            if step <= tol_step && res <= tol_res {
                let yp = derivative(grid, &y, left, right);
                return Ok(FdmSolution {
                    grid: grid.clone(),
                    y,
                    yp,
                    stats: FdmStats {
                        iterations: k,
                        residual: res,
                        step_norm: step,
                    },
                });
            }
        }
        Err(BvpError::NoConvergence {
            method: "fdm-newton",
            iterations: self.options.max_iter,
            residual: res,
        })
    }
}

#[inline]
fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// Residual and Jacobian assembly for one problem/grid/condition set.
struct Assembler<'a, P: ?Sized> {
    problem: &'a P,
    grid: &'a UniformGrid,
    left: Bc,
    right: Bc,
    /// `problem.depends_on_right_end()`.
    bordered: bool,
}

impl<P: SecondOrderBvp + ?Sized> Assembler<'_, P> {
    /// `(F, F_y, F_{y'}, F_{y(b)})` at node `x` with right-end value `yb`.
    #[inline]
    fn eval(&self, x: f64, y: f64, yp: f64, yb: f64) -> (f64, f64, f64, f64) {
        if self.bordered {
            self.problem.eval_with_right_end(x, y, yp, yb)
        } else {
            let (f, fy, fyp) = self.problem.eval(x, y, yp);
            (f, fy, fyp, 0.0)
        }
    }

    /// Fills `g` with the scaled residual and `jac` with its tridiagonal Jacobian at `y`, and
    /// (bordered problems only) `border[i] = dG_i/dy_n` from the `y(b)` dependence of `F`
    /// (not including the tridiagonal entries in column `n`); returns
    /// `(|G|_inf, max_i sum_j |term_ij|)` (the latter sizes the rounding level of `G`).
    fn assemble(
        &self,
        y: &[f64],
        g: &mut [f64],
        jac: &mut Tridiagonal,
        border: &mut [f64],
    ) -> Result<(f64, f64)> {
        let n = self.grid.intervals();
        let h = self.grid.h();
        let h2 = h * h;
        let inv2h = 0.5 / h;
        let yb = y[n];
        let mut res = 0.0_f64;
        let mut scale = 0.0_f64;
        let mut set_border = |i: usize, v: f64| -> Result<()> {
            if let Some(b) = border.get_mut(i) {
                if !v.is_finite() {
                    return Err(BvpError::NonFinite {
                        what: "fdm jacobian",
                        s: self.grid.x(i),
                    });
                }
                *b = v;
            }
            Ok(())
        };

        // Left end, node 0.
        {
            let bc = self.left;
            let x = self.grid.a();
            if bc.beta == 0.0 {
                g[0] = bc.alpha * y[0] - bc.gamma;
                jac.diag[0] = bc.alpha;
                jac.upper[0] = 0.0;
                set_border(0, 0.0)?;
                scale = scale.max((bc.alpha * y[0]).abs() + bc.gamma.abs());
            } else {
                let s = bc.slope(y[0]);
                let ds = -bc.alpha / bc.beta;
                let (f, fy, fyp, fyb) = self.eval(x, y[0], s, yb);
                set_border(0, -0.5 * h2 * fyb)?;
                g[0] = y[1] - y[0] - h * s - 0.5 * h2 * f;
                jac.diag[0] = -1.0 + h * bc.alpha / bc.beta - 0.5 * h2 * (fy + fyp * ds);
                jac.upper[0] = 1.0;
                scale = scale.max(y[1].abs() + y[0].abs() + (h * s).abs() + (0.5 * h2 * f).abs());
            }
            jac.lower[0] = 0.0;
            res = res.max(g[0].abs());
            check_row(g[0], jac.diag[0], x)?;
        }

        // Interior nodes.
        for i in 1..n {
            let x = self.grid.x(i);
            let yp = (y[i + 1] - y[i - 1]) * inv2h;
            let (f, fy, fyp, fyb) = self.eval(x, y[i], yp, yb);
            set_border(i, -h2 * fyb)?;
            let gi = y[i - 1] - 2.0 * y[i] + y[i + 1] - h2 * f;
            g[i] = gi;
            let t = 0.5 * h * fyp;
            jac.lower[i] = 1.0 + t;
            jac.diag[i] = -2.0 - h2 * fy;
            jac.upper[i] = 1.0 - t;
            res = res.max(gi.abs());
            scale = scale.max(y[i - 1].abs() + 2.0 * y[i].abs() + y[i + 1].abs() + (h2 * f).abs());
            check_row(gi, jac.diag[i] + t, x)?;
        }

        // Right end, node n.
        {
            let bc = self.right;
            let x = self.grid.b();
            if bc.beta == 0.0 {
                g[n] = bc.alpha * y[n] - bc.gamma;
                jac.diag[n] = bc.alpha;
                jac.lower[n] = 0.0;
                set_border(n, 0.0)?;
                scale = scale.max((bc.alpha * y[n]).abs() + bc.gamma.abs());
            } else {
                let s = bc.slope(y[n]);
                let ds = -bc.alpha / bc.beta;
                let (f, fy, fyp, fyb) = self.eval(x, y[n], s, yb);
                set_border(n, -0.5 * h2 * fyb)?;
                g[n] = y[n - 1] - y[n] + h * s - 0.5 * h2 * f;
                jac.diag[n] = -1.0 - h * bc.alpha / bc.beta - 0.5 * h2 * (fy + fyp * ds);
                jac.lower[n] = 1.0;
                scale =
                    scale.max(y[n - 1].abs() + y[n].abs() + (h * s).abs() + (0.5 * h2 * f).abs());
            }
            jac.upper[n] = 0.0;
            res = res.max(g[n].abs());
            check_row(g[n], jac.diag[n], x)?;
        }
        Ok((res, scale))
    }
}

/// `O(n)` solver for the bordered Newton matrix `J = T + c e_n^T` (tridiagonal `T` of size
/// `N = n + 1` plus the dense last column `c`), by Gaussian elimination with partial
/// pivoting. At step `k` only rows `k` (already updated) and `k + 1` have a nonzero in column
/// `k`; the larger one is the pivot, so each `U` row holds columns `k, k+1, k+2` (one fill-in
/// superdiagonal) and `n`. Buffers are allocated once per solve.
struct BorderedLu {
    /// `U` rows: entries in columns `k`, `k+1`, `k+2` and `n` (column `n` kept separate).
    u0: Vec<f64>,
    u1: Vec<f64>,
    u2: Vec<f64>,
    uc: Vec<f64>,
}

impl BorderedLu {
    fn new(len: usize) -> Self {
        Self {
            u0: vec![0.0; len],
            u1: vec![0.0; len],
            u2: vec![0.0; len],
            uc: vec![0.0; len],
        }
    }

    /// Overwrites `rhs` with the solution of `(T + border e_n^T) x = rhs`.
    ///
    /// # Errors
    /// [`BvpError::SingularJacobian`] `{ row, pivot }` when the pivot of column `row` is not
    /// above `max(1e-300, 8 eps |J|_inf)` (or is NaN).
    fn solve_in_place(&mut self, t: &Tridiagonal, border: &[f64], rhs: &mut [f64]) -> Result<()> {
        let len = rhs.len();
        let n = len - 1;
        // Original row i split as band entries (columns i-1, i, i+1, all < n) and column n.
        let row = |i: usize| -> (f64, f64, f64, f64) {
            let mut c = border[i];
            let l = if i > 0 { t.lower[i] } else { 0.0 };
            let mut d = t.diag[i];
            let mut u = if i < n { t.upper[i] } else { 0.0 };
            if i == n {
                c += d;
                d = 0.0;
            }
            if i + 1 == n {
                c += u;
                u = 0.0;
            }
            (l, d, u, c)
        };
        let norm = (0..len).fold(0.0_f64, |m, i| {
            let (l, d, u, c) = row(i);
            m.max(l.abs() + d.abs() + u.abs() + c.abs())
        });
        let tiny = (8.0 * f64::EPSILON * norm).max(1e-300);
        let check = |k: usize, p: f64| -> Result<()> {
            // NaN pivots fail the comparison and are reported too.
            if p.abs().partial_cmp(&tiny) != Some(std::cmp::Ordering::Greater) {
                return Err(BvpError::SingularJacobian { row: k, pivot: p });
            }
            Ok(())
        };
        // Working row: entries in columns k, k+1, k+2, n and its right-hand side.
        let (_, d0, u0, c0) = row(0);
        let mut cur = [d0, u0, 0.0, c0, rhs[0]];
        for k in 0..n {
            let (l, d, u, c) = row(k + 1);
            let mut nxt = [l, d, u, c, rhs[k + 1]];
            if nxt[0].abs() > cur[0].abs() {
                std::mem::swap(&mut cur, &mut nxt);
            }
            check(k, cur[0])?;
            let m = nxt[0] / cur[0];
            self.u0[k] = cur[0];
            self.u1[k] = cur[1];
            self.u2[k] = cur[2];
            self.uc[k] = cur[3];
            rhs[k] = cur[4];
            // Remaining row shifts one column to the right: columns k+1, k+2, (k+3 = 0), n.
            cur = [
                nxt[1] - m * cur[1],
                nxt[2] - m * cur[2],
                0.0,
                nxt[3] - m * cur[3],
                nxt[4] - m * cur[4],
            ];
        }
        // Last row: only column n (band entries in column n were moved to `c`).
        check(n, cur[3])?;
        let xn = cur[4] / cur[3];
        rhs[n] = xn;
        for k in (0..n).rev() {
            let mut v = rhs[k] - self.uc[k] * xn;
            if k + 1 < n {
                v -= self.u1[k] * rhs[k + 1];
            }
            if k + 2 < n {
                v -= self.u2[k] * rhs[k + 2];
            }
            rhs[k] = v / self.u0[k];
        }
        Ok(())
    }
}

/// Rejects a non-finite residual row or Jacobian row (`jac_sum` is any sum of the row's
/// Jacobian entries that is finite iff all of them are).
#[inline]
fn check_row(g: f64, jac_sum: f64, x: f64) -> Result<()> {
    if !g.is_finite() {
        return Err(BvpError::NonFinite {
            what: "fdm residual",
            s: x,
        });
    }
    if !jac_sum.is_finite() {
        return Err(BvpError::NonFinite {
            what: "fdm jacobian",
            s: x,
        });
    }
    Ok(())
}

/// Second-order derivative estimates at every node (see [`FdmSolution::yp`]).
fn derivative(grid: &UniformGrid, y: &[f64], left: Bc, right: Bc) -> Vec<f64> {
    let n = grid.intervals();
    let h = grid.h();
    let mut yp = vec![0.0; n + 1];
    for i in 1..n {
        yp[i] = (y[i + 1] - y[i - 1]) / (2.0 * h);
    }
    yp[0] = if left.beta != 0.0 {
        left.slope(y[0])
    } else {
        (-3.0 * y[0] + 4.0 * y[1] - y[2]) / (2.0 * h)
    };
    yp[n] = if right.beta != 0.0 {
        right.slope(y[n])
    } else {
        (3.0 * y[n] - 4.0 * y[n - 1] + y[n - 2]) / (2.0 * h)
    };
    yp
}

#[cfg(test)]
mod tests;
