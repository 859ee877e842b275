//! Small non-linear systems `r(x) = 0` by a Gauss-Newton trust-region method (the `fsolve`
//! equivalent), built on argmin's [`TrustRegion`] solver with a dogleg subproblem
//! ([`GaussNewtonDogleg`]) and `faer` column vectors.
//!
//! The merit function is `f(x) = 1/2 ||r(x)||_2^2` with gradient `J^T r` and the Gauss-Newton
//! Hessian `J^T J` (`J = dr/dx`). Each iteration solves the dogleg subproblem in the current
//! radius, accepts the step if the actual/predicted reduction ratio exceeds `1/8`, and
//! adapts the radius (argmin's rules). The solve succeeds when `||r||_2 <= tol`.
//!
//! Residual evaluations are cached by `x`: the residual computed for the cost at a trial point
//! is reused for the gradient there, and the Jacobian for the gradient is reused for the
//! Hessian, so an iteration costs one residual evaluation plus (when the step is accepted) one
//! Jacobian.

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::cell::{Cell, RefCell};

use argmin::core::{
    CostFunction, Error as ArgminError, Executor, Gradient, Hessian, IterState, OptimizationResult,
    Problem, Solver, State, TerminationReason, TerminationStatus, TrustRegionRadius, KV,
};
use argmin::solver::trustregion::TrustRegion;
use faer::Mat;

use crate::BvpError;

/// A system of `n_residuals` equations `r(x) = 0` in `n_unknowns` unknowns.
///
/// ```
/// use bvp_solvers::trust_region::{solve, NonlinearSystem, TrustRegionOptions};
/// use bvp_solvers::BvpError;
///
/// /// Rosenbrock's function as a system: 10 (y - x^2) = 0, 1 - x = 0.
/// struct Rosenbrock;
/// impl NonlinearSystem for Rosenbrock {
///     type Error = BvpError;
///     fn n_unknowns(&self) -> usize { 2 }
///     fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), BvpError> {
///         r[0] = 10.0 * (x[1] - x[0] * x[0]);
///         r[1] = 1.0 - x[0];
///         Ok(())
///     }
/// }
///
/// let sol = solve(&Rosenbrock, &[-1.2, 1.0], &TrustRegionOptions::default()).unwrap();
/// assert!((sol.x[0] - 1.0).abs() < 1e-9 && (sol.x[1] - 1.0).abs() < 1e-9);
/// ```
pub trait NonlinearSystem {
    /// The caller's error type; solver failures are converted into it from [`BvpError`].
    type Error: std::error::Error + From<BvpError> + Send + Sync + 'static;
    /// Number of unknowns `n`.
    fn n_unknowns(&self) -> usize;
    /// Number of residuals `m` (default `n`; `m > n` gives a least-squares problem that only
    /// "converges" if it is consistent).
    fn n_residuals(&self) -> usize {
        self.n_unknowns()
    }
    /// Writes `r(x)` (length `m`).
    ///
    /// # Errors
    /// Whatever the caller's model can fail with; it is returned unchanged by [`solve`].
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), Self::Error>;
    /// Writes the Jacobian `J_ij = dr_i/dx_j`, row-major `m x n`.
    ///
    /// Default: forward differences `J_ij = (r_i(x + h_j e_j) - r_i(x))/h_j` with
    /// `h_j = sqrt(eps) max(1, |x_j|)` (`n + 1` residual evaluations, first-order accurate).
    ///
    /// # Errors
    /// Errors of [`NonlinearSystem::residual`].
    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> Result<(), Self::Error> {
        forward_difference_jacobian(self, x, jac)
    }
}

/// The Jacobian of `sys` at `x` by forward differences (the default of
/// [`NonlinearSystem::jacobian`]): `J_ij = (r_i(x + h_j e_j) - r_i(x))/h_j` with
/// `h_j = sqrt(eps) max(1, |x_j|)`, row-major `m x n`.
///
/// # Errors
/// `DimensionMismatch` for a buffer or `x` of the wrong length; errors of
/// [`NonlinearSystem::residual`].
pub fn forward_difference_jacobian<S: NonlinearSystem + ?Sized>(
    sys: &S,
    x: &[f64],
    jac: &mut [f64],
) -> Result<(), S::Error> {
    let n = sys.n_unknowns();
    let m = sys.n_residuals();
    if jac.len() != m * n || x.len() != n {
        return Err(BvpError::DimensionMismatch {
            name: "jacobian buffer",
            expected: m * n,
            found: jac.len(),
        }
        .into());
    }
    let mut r0 = vec![0.0; m];
    let mut r1 = vec![0.0; m];
    let mut xp = x.to_vec();
    sys.residual(x, &mut r0)?;
    let sq = f64::EPSILON.sqrt();
    for j in 0..n {
        let h = sq * x[j].abs().max(1.0);
        xp[j] = x[j] + h;
        let hh = xp[j] - x[j]; // exactly representable step
        sys.residual(&xp, &mut r1)?;
        xp[j] = x[j];
        for i in 0..m {
            jac[i * n + j] = (r1[i] - r0[i]) / hh;
        }
    }
    Ok(())
}

/// The dogleg step for the model `m(p) = f + g^T p + 1/2 p^T H p` in `||p|| <= radius`, as an
/// argmin subproblem solver for [`TrustRegion`] (Nocedal & Wright, *Numerical Optimization*,
/// §4.1):
///
/// * full step `p_B = -H^{-1} g` (Cholesky of the Gauss-Newton `H = J^T J`) if `||p_B|| <= radius`;
/// * else the Cauchy point `p_U = -(g^T g / g^T H g) g`, scaled to the boundary if
///   `||p_U|| >= radius`;
/// * else `p_U + tau (p_B - p_U)` with `tau in [0, 1]` solving `||p|| = radius`.
///
/// If `H` is not numerically positive definite, the steepest-descent step to the boundary is used.
/// Unlike argmin's own `Dogleg` (which needs `H^{-1}` and returns a zero step whenever `p_U`
/// and `p_B` are collinear, e.g. for every one-unknown problem), this handles the collinear
/// and singular cases; it also avoids a general matrix inverse for these tiny systems.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussNewtonDogleg {
    radius: f64,
}

impl GaussNewtonDogleg {
    /// A new subproblem solver (the radius is set by [`TrustRegion`]).
    pub fn new() -> Self {
        Self { radius: f64::NAN }
    }

    /// The dogleg step for gradient `g` and symmetric `H` (column-major `n x n`).
    fn step(&self, g: &[f64], h: &[f64], p: &mut [f64]) {
        let n = g.len();
        let radius = self.radius;
        let gnorm = norm(g);
        if gnorm == 0.0 || !(radius > 0.0) {
            p.iter_mut().for_each(|v| *v = 0.0);
            return;
        }
        // Cholesky H = L L^T (lower, column-major in l)
        let mut l = h.to_vec();
        let mut spd = true;
        let scale = (0..n).map(|i| h[i * n + i].abs()).fold(0.0, f64::max);
        'chol: for j in 0..n {
            let mut d = l[j * n + j];
            for k in 0..j {
                d -= l[k * n + j] * l[k * n + j];
            }
            if !(d > 1e-14 * scale) {
                spd = false;
                break 'chol;
            }
            let d = d.sqrt();
            l[j * n + j] = d;
            for i in j + 1..n {
                let mut v = l[j * n + i];
                for k in 0..j {
                    v -= l[k * n + i] * l[k * n + j];
                }
                l[j * n + i] = v / d;
            }
        }
        let ghg: f64 = (0..n)
            .map(|i| g[i] * (0..n).map(|j| h[j * n + i] * g[j]).sum::<f64>())
            .sum();
        if !spd || !(ghg > 0.0) {
            for i in 0..n {
                p[i] = -radius * g[i] / gnorm;
            }
            return;
        }
        // p_B: L y = -g, L^T p = y
        for i in 0..n {
            let mut v = -g[i];
            for k in 0..i {
                v -= l[k * n + i] * p[k];
            }
            p[i] = v / l[i * n + i];
        }
        for i in (0..n).rev() {
            let mut v = p[i];
            for k in i + 1..n {
                v -= l[i * n + k] * p[k];
            }
            p[i] = v / l[i * n + i];
        }
        let pb_norm = norm(p);
        if pb_norm.is_finite() && pb_norm <= radius {
            return;
        }
        let alpha = gnorm * gnorm / ghg;
        let pu_norm = alpha * gnorm;
        if pu_norm >= radius || !pb_norm.is_finite() {
            for i in 0..n {
                p[i] = -radius * g[i] / gnorm;
            }
            return;
        }
        // ||pu + tau d||^2 = radius^2, d = pb - pu, 0 <= tau <= 1
        let (mut a, mut b) = (0.0, 0.0);
        for i in 0..n {
            let pu = -alpha * g[i];
            let d = p[i] - pu;
            a += d * d;
            b += 2.0 * pu * d;
        }
        let c = pu_norm * pu_norm - radius * radius; // < 0
        let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
        let tau = if b > 0.0 {
            -2.0 * c / (b + disc)
        } else {
            (-b + disc) / (2.0 * a)
        };
        let tau = if tau.is_finite() {
            tau.clamp(0.0, 1.0)
        } else {
            1.0
        };
        for pi in p.iter_mut().zip(g) {
            let pu = -alpha * pi.1;
            *pi.0 = pu + tau * (*pi.0 - pu);
        }
    }
}

impl Default for GaussNewtonDogleg {
    fn default() -> Self {
        Self::new()
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

impl TrustRegionRadius<f64> for GaussNewtonDogleg {
    fn set_radius(&mut self, radius: f64) {
        self.radius = radius;
    }
}

type TrState = IterState<Mat<f64>, Mat<f64>, (), Mat<f64>, (), f64>;

/// What argmin's executor returns for the trust region on a [`Wrapper`].
type TrResult<'a, 'b, S> =
    OptimizationResult<Wrapper<'a, 'b, S>, TrustRegion<GaussNewtonDogleg, f64>, TrState>;

impl<O> Solver<O, TrState> for GaussNewtonDogleg
where
    O: Gradient<Param = Mat<f64>, Gradient = Mat<f64>>
        + Hessian<Param = Mat<f64>, Hessian = Mat<f64>>,
{
    fn name(&self) -> &str {
        "Gauss-Newton dogleg"
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<O>,
        mut state: TrState,
    ) -> Result<(TrState, Option<KV>), ArgminError> {
        let param = state
            .take_param()
            .ok_or_else(|| ArgminError::msg("dogleg: no parameter vector"))?;
        let g = match state.take_gradient() {
            Some(g) => g,
            None => problem.gradient(&param)?,
        };
        let h = match state.take_hessian() {
            Some(h) => h,
            None => problem.hessian(&param)?,
        };
        let n = g.nrows();
        let gs = g.col_as_slice(0);
        let mut hs = Vec::with_capacity(n * n);
        for j in 0..n {
            hs.extend_from_slice(h.col_as_slice(j));
        }
        let mut p = vec![0.0; n];
        self.step(gs, &hs, &mut p);
        let pstar = Mat::from_fn(n, 1, |i, _| p[i]);
        Ok((state.param(pstar).gradient(g).hessian(h), None))
    }

    fn terminate(&mut self, state: &TrState) -> TerminationStatus {
        if state.get_iter() >= 1 {
            TerminationStatus::Terminated(TerminationReason::MaxItersReached)
        } else {
            TerminationStatus::NotTerminated
        }
    }
}

/// Options of [`solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrustRegionOptions {
    /// Stop successfully when `||r||_2 <= tol`.
    pub tol: f64,
    /// Maximum number of trust-region iterations.
    pub max_iters: u64,
    /// Initial trust-region radius (in the units of `x`).
    pub initial_radius: f64,
    /// Largest radius.
    pub max_radius: f64,
}

impl Default for TrustRegionOptions {
    /// `tol = 1e-10`, `max_iters = 200`, `initial_radius = 1`, `max_radius = 100`.
    fn default() -> Self {
        Self {
            tol: 1e-10,
            max_iters: 200,
            initial_radius: 1.0,
            max_radius: 100.0,
        }
    }
}

/// A converged solution of [`solve`].
#[derive(Clone, Debug, PartialEq)]
pub struct SystemSolution {
    /// The solution `x`.
    pub x: Vec<f64>,
    /// `||r(x)||_2` (`<= tol`).
    pub residual_norm: f64,
    /// Trust-region iterations.
    pub iterations: u64,
    /// Residual evaluations made by the solver (not counting those inside
    /// [`NonlinearSystem::jacobian`]).
    pub evaluations: usize,
    /// Jacobian evaluations.
    pub jacobian_evaluations: usize,
}

struct Cache {
    rx: Vec<f64>,
    r: Vec<f64>,
    r_ok: bool,
    jx: Vec<f64>,
    jac: Vec<f64>,
    j_ok: bool,
}

/// State shared between [`solve`] and the argmin problem (which argmin owns while running).
struct Shared<'a, S: NonlinearSystem> {
    sys: &'a S,
    n: usize,
    m: usize,
    cache: RefCell<Cache>,
    user_error: RefCell<Option<S::Error>>,
    evals: Cell<usize>,
    jevals: Cell<usize>,
    cost_calls: Cell<u64>,
    best_norm: Cell<f64>,
}

/// The argmin problem: cost, gradient and Gauss-Newton Hessian of `1/2 ||r||^2`, with a
/// one-point cache for `r` and `J`, and a slot for the user's error.
struct Wrapper<'s, 'a, S: NonlinearSystem>(&'s Shared<'a, S>);

impl<'a, S: NonlinearSystem> std::ops::Deref for Wrapper<'_, 'a, S> {
    type Target = Shared<'a, S>;
    fn deref(&self) -> &Shared<'a, S> {
        self.0
    }
}

const USER_ERROR: &str = "user residual/jacobian failed";

impl<S: NonlinearSystem> Shared<'_, S> {
    fn stash(&self, e: S::Error) -> ArgminError {
        *self.user_error.borrow_mut() = Some(e);
        ArgminError::msg(USER_ERROR)
    }

    /// Makes sure `cache.r` holds `r(x)`.
    fn ensure_r(&self, x: &[f64], c: &mut Cache) -> Result<(), ArgminError> {
        if c.r_ok && c.rx == x {
            return Ok(());
        }
        c.r_ok = false;
        self.evals.set(self.evals.get() + 1);
        self.sys.residual(x, &mut c.r).map_err(|e| self.stash(e))?;
        c.rx.copy_from_slice(x);
        c.r_ok = true;
        Ok(())
    }

    /// Makes sure `cache.jac` holds `J(x)`.
    fn ensure_j(&self, x: &[f64], c: &mut Cache) -> Result<(), ArgminError> {
        if c.j_ok && c.jx == x {
            return Ok(());
        }
        c.j_ok = false;
        self.jevals.set(self.jevals.get() + 1);
        self.sys
            .jacobian(x, &mut c.jac)
            .map_err(|e| self.stash(e))?;
        if c.jac.iter().any(|v| !v.is_finite()) {
            return Err(ArgminError::msg("non-finite Jacobian"));
        }
        c.jx.copy_from_slice(x);
        c.j_ok = true;
        Ok(())
    }
}

impl<S: NonlinearSystem> CostFunction for Wrapper<'_, '_, S> {
    type Param = Mat<f64>;
    type Output = f64;
    fn cost(&self, p: &Mat<f64>) -> Result<f64, ArgminError> {
        let x = p.col_as_slice(0);
        let mut c = self.cache.borrow_mut();
        self.ensure_r(x, &mut c)?;
        let f = 0.5 * c.r.iter().map(|v| v * v).sum::<f64>();
        self.cost_calls.set(self.cost_calls.get() + 1);
        let norm = (2.0 * f).sqrt();
        if norm < self.best_norm.get() {
            self.best_norm.set(norm);
        }
        // a NaN cost would stall argmin's radius update: treat it as an infinitely bad point
        Ok(if f.is_nan() { f64::INFINITY } else { f })
    }
}

impl<S: NonlinearSystem> Gradient for Wrapper<'_, '_, S> {
    type Param = Mat<f64>;
    type Gradient = Mat<f64>;
    fn gradient(&self, p: &Mat<f64>) -> Result<Mat<f64>, ArgminError> {
        let x = p.col_as_slice(0);
        let mut c = self.cache.borrow_mut();
        self.ensure_r(x, &mut c)?;
        self.ensure_j(x, &mut c)?;
        if c.r.iter().any(|v| !v.is_finite()) {
            return Err(ArgminError::msg("non-finite residual"));
        }
        let (n, m) = (self.n, self.m);
        let c = &*c;
        Ok(Mat::from_fn(n, 1, |j, _| {
            (0..m).map(|i| c.jac[i * n + j] * c.r[i]).sum::<f64>()
        }))
    }
}

impl<S: NonlinearSystem> Hessian for Wrapper<'_, '_, S> {
    type Param = Mat<f64>;
    type Hessian = Mat<f64>;
    fn hessian(&self, p: &Mat<f64>) -> Result<Mat<f64>, ArgminError> {
        let x = p.col_as_slice(0);
        let mut c = self.cache.borrow_mut();
        self.ensure_j(x, &mut c)?;
        let (n, m) = (self.n, self.m);
        let c = &*c;
        Ok(Mat::from_fn(n, n, |a, b| {
            (0..m)
                .map(|i| c.jac[i * n + a] * c.jac[i * n + b])
                .sum::<f64>()
        }))
    }
}

fn invalid(name: &'static str, value: f64, reason: &'static str) -> BvpError {
    BvpError::InvalidInput {
        name,
        value,
        reason,
    }
}

/// Checks the dimensions, `x0` and the options.
fn check<S: NonlinearSystem>(
    sys: &S,
    x0: &[f64],
    opts: &TrustRegionOptions,
) -> Result<(), BvpError> {
    let n = sys.n_unknowns();
    let m = sys.n_residuals();
    if x0.len() != n {
        return Err(BvpError::DimensionMismatch {
            name: "x0",
            expected: n,
            found: x0.len(),
        });
    }
    if n == 0 || m < n {
        return Err(invalid(
            "n_residuals",
            m as f64,
            "need n_unknowns >= 1 and n_residuals >= n_unknowns",
        ));
    }
    if let Some(&v) = x0.iter().find(|v| !v.is_finite()) {
        return Err(invalid("x0", v, "initial guess must be finite"));
    }
    if !(opts.tol > 0.0 && opts.tol.is_finite()) {
        return Err(invalid("tol", opts.tol, "must be finite and > 0"));
    }
    if !(opts.initial_radius > 0.0 && opts.initial_radius.is_finite()) {
        return Err(invalid(
            "initial_radius",
            opts.initial_radius,
            "must be finite and > 0",
        ));
    }
    if !(opts.max_radius >= opts.initial_radius && opts.max_radius.is_finite()) {
        return Err(invalid(
            "max_radius",
            opts.max_radius,
            "must be finite and >= initial_radius",
        ));
    }

    Ok(())
}

/// Solves `r(x) = 0` from `x0` by the Gauss-Newton dogleg trust-region method (see the module
/// documentation): argmin's `TrustRegion<GaussNewtonDogleg>` on `1/2 ||r||^2` with target cost
/// `tol^2/2`.
///
/// # Errors
/// * the user's own error from `residual`/`jacobian`, unchanged;
/// * `NoConvergence { method: "trust-region", iterations, residual }` (residual = best
///   `||r||_2`) if `||r||_2 <= tol` is not reached within `max_iters`, or the iteration breaks
///   down (non-finite Jacobian);
/// * `InvalidInput` / `DimensionMismatch` for bad options or `x0`.
pub fn solve<S: NonlinearSystem>(
    sys: &S,
    x0: &[f64],
    opts: &TrustRegionOptions,
) -> Result<SystemSolution, S::Error> {
    check(sys, x0, opts)?;
    let (n, m) = (sys.n_unknowns(), sys.n_residuals());
    let wrapper = Shared {
        sys,
        n,
        m,
        cache: RefCell::new(Cache {
            rx: vec![f64::NAN; n],
            r: vec![0.0; m],
            r_ok: false,
            jx: vec![f64::NAN; n],
            jac: vec![0.0; m * n],
            j_ok: false,
        }),
        user_error: RefCell::new(None),
        evals: Cell::new(0),
        jevals: Cell::new(0),
        cost_calls: Cell::new(0),
        best_norm: Cell::new(f64::INFINITY),
    };

    // Fast path: the initial guess already solves the system.
    {
        let mut c = wrapper.cache.borrow_mut();
        if let Err(e) = wrapper.ensure_r(x0, &mut c) {
            drop(c);
            return Err(take_user_error(&wrapper, e));
        }
        let norm = c.r.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm <= opts.tol {
            return Ok(SystemSolution {
                x: x0.to_vec(),
                residual_norm: norm,
                iterations: 0,
                evaluations: wrapper.evals.get(),
                jacobian_evaluations: 0,
            });
        }
    }

    let solver = TrustRegion::new(GaussNewtonDogleg::new())
        .with_radius(opts.initial_radius)
        .and_then(|s| s.with_max_radius(opts.max_radius))
        .map_err(|_| invalid("initial_radius", opts.initial_radius, "rejected by argmin"))?;
    let p0 = Mat::from_fn(n, 1, |i, _| x0[i]);
    let target = 0.5 * opts.tol * opts.tol;
    let result = Executor::new(Wrapper(&wrapper), solver)
        .configure(|state| {
            state
                .param(p0)
                .max_iters(opts.max_iters)
                .target_cost(target)
        })
        .timer(false)
        .ctrlc(false)
        .run();

    outcome(&wrapper, result, opts, target)
}

/// The solution from argmin's result, or the failure with the best residual.
fn outcome<S: NonlinearSystem>(
    wrapper: &Shared<'_, S>,
    result: Result<TrResult<'_, '_, S>, ArgminError>,
    opts: &TrustRegionOptions,
    target: f64,
) -> Result<SystemSolution, S::Error> {
    match result {
        Err(e) => {
            if wrapper.user_error.borrow().is_some() {
                return Err(take_user_error(wrapper, e));
            }
            // argmin broke down (e.g. non-finite Jacobian)
            Err(BvpError::NoConvergence {
                method: "trust-region",
                iterations: usize::try_from(wrapper.cost_calls.get().saturating_sub(1))
                    .unwrap_or(usize::MAX),
                residual: wrapper.best_norm.get(),
            }
            .into())
        }
        Ok(res) => {
            let state = res.state;
            let iterations = state.get_iter();
            let cost = state.get_best_cost();
            let residual = (2.0f64 * cost).sqrt();
            // argmin checks the iteration budget before the target cost, so a solve that
            // reaches the target in its last allowed iteration reports `MaxItersReached`:
            // that case is a success too. Every other status is a failure.
            let reached = match state.get_termination_status() {
                TerminationStatus::Terminated(TerminationReason::TargetCostReached) => true,
                TerminationStatus::Terminated(TerminationReason::MaxItersReached) => cost <= target,
                _ => false,
            };
            match state.get_best_param() {
                Some(p) if reached && residual <= opts.tol => Ok(SystemSolution {
                    x: p.col_as_slice(0).to_vec(),
                    residual_norm: residual,
                    iterations,
                    evaluations: wrapper.evals.get(),
                    jacobian_evaluations: wrapper.jevals.get(),
                }),
                _ => Err(BvpError::NoConvergence {
                    method: "trust-region",
                    iterations: usize::try_from(iterations).unwrap_or(usize::MAX),
                    residual,
                }
                .into()),
            }
        }
    }
}

fn take_user_error<S: NonlinearSystem>(w: &Shared<'_, S>, _e: ArgminError) -> S::Error {
    match w.user_error.borrow_mut().take() {
        Some(user) => user,
        None => BvpError::NoConvergence {
            method: "trust-region",
            iterations: 0,
            residual: w.best_norm.get(),
        }
        .into(),
    }
}

#[cfg(test)]
mod tests;
