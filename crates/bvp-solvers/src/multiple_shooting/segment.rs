//! One segment of multiple shooting: the problem's right-hand side with its Jacobian
//! (analytic, or forward differences of `f` inside the variational equations), and the
//! integration of a segment by DOP853 with the sensitivities of its end.

use std::cell::RefCell;

use crate::integrator::{Dop853, OdeSolution, OdeSystem};
use crate::BvpError;

/// The right-hand side `y' = f(x, y, p)` of a first-order system with `n` states and `k`
/// parameters, and its Jacobians `df/dy` (`n x n`) and `df/dp` (`n x k`), row-major.
pub trait Rhs {
    /// Writes `f(x, y, p)` into `dy`.
    fn f(&self, x: f64, y: &[f64], p: &[f64], dy: &mut [f64]);

    /// Writes `df/dy` and `df/dp` at `(x, y, p)`; `f0 = f(x, y, p)` is given. Default:
    /// forward differences, step `sqrt(eps) max(1, |v|)` in each component `v`.
    fn jacobian(
        &self,
        x: f64,
        y: &[f64],
        p: &[f64],
        f0: &[f64],
        dfdy: &mut [f64],
        dfdp: &mut [f64],
    ) {
        forward_jacobian(self, x, y, p, f0, dfdy, dfdp);
    }
}

/// Forward differences of `rhs.f` in `y` and `p` (the default of [`Rhs::jacobian`]).
fn forward_jacobian<R: Rhs + ?Sized>(
    rhs: &R,
    x: f64,
    y: &[f64],
    p: &[f64],
    f0: &[f64],
    dfdy: &mut [f64],
    dfdp: &mut [f64],
) {
    let (n, k) = (y.len(), p.len());
    let sq = f64::EPSILON.sqrt();
    let mut yt = y.to_vec();
    let mut pt = p.to_vec();
    let mut f1 = vec![0.0; n];
    for c in 0..n {
        let h = sq * y[c].abs().max(1.0);
        yt[c] = y[c] + h;
        let h = yt[c] - y[c];
        rhs.f(x, &yt, p, &mut f1);
        yt[c] = y[c];
        for i in 0..n {
            dfdy[i * n + c] = (f1[i] - f0[i]) / h;
        }
    }
    for c in 0..k {
        let h = sq * p[c].abs().max(1.0);
        pt[c] = p[c] + h;
        let h = pt[c] - p[c];
        rhs.f(x, y, &pt, &mut f1);
        pt[c] = p[c];
        for i in 0..n {
            dfdp[i * k + c] = (f1[i] - f0[i]) / h;
        }
    }
}

/// `f` alone: its Jacobians by forward differences.
pub(crate) struct Numeric<F>(pub F);

impl<F: Fn(f64, &[f64], &[f64], &mut [f64])> Rhs for Numeric<F> {
    fn f(&self, x: f64, y: &[f64], p: &[f64], dy: &mut [f64]) {
        (self.0)(x, y, p, dy)
    }
}

/// `f` with its analytic Jacobians `jac(x, y, p, dfdy, dfdp)`.
pub(crate) struct Analytic<F, J>(pub F, pub J);

impl<F, J> Rhs for Analytic<F, J>
where
    F: Fn(f64, &[f64], &[f64], &mut [f64]),
    J: Fn(f64, &[f64], &[f64], &mut [f64], &mut [f64]),
{
    fn f(&self, x: f64, y: &[f64], p: &[f64], dy: &mut [f64]) {
        (self.0)(x, y, p, dy)
    }
    fn jacobian(
        &self,
        x: f64,
        y: &[f64],
        p: &[f64],
        _f0: &[f64],
        dfdy: &mut [f64],
        dfdp: &mut [f64],
    ) {
        (self.1)(x, y, p, dfdy, dfdp)
    }
}

/// The state `y` alone, for trial points and the dense output.
struct Plain<'a, R: ?Sized> {
    rhs: &'a R,
    p: &'a [f64],
    n: usize,
}

impl<R: Rhs + ?Sized> OdeSystem for Plain<'_, R> {
    fn dim(&self) -> usize {
        self.n
    }
    fn rhs(&self, x: f64, u: &[f64], du: &mut [f64]) {
        self.rhs.f(x, u, self.p, du)
    }
}

/// The state with its variational equations: `u = (y, M)`, `M = d y / d(s, p)` (`n` rows of
/// `n + k`, row-major), `M' = (df/dy) M + [0 | df/dp]`, `M(x_j) = [I | 0]`.
struct Variational<'a, R: ?Sized> {
    rhs: &'a R,
    p: &'a [f64],
    n: usize,
    /// Work space: `df/dy`, `df/dp`.
    work: RefCell<(Vec<f64>, Vec<f64>)>,
}

impl<R: Rhs + ?Sized> OdeSystem for Variational<'_, R> {
    fn dim(&self) -> usize {
        self.n * (1 + self.n + self.p.len())
    }
    fn rhs(&self, x: f64, u: &[f64], du: &mut [f64]) {
        let (n, k) = (self.n, self.p.len());
        let w = n + k;
        let (y, m) = u.split_at(n);
        let (dy, dm) = du.split_at_mut(n);
        self.rhs.f(x, y, self.p, dy);
        let mut work = self.work.borrow_mut();
        let (jy, jp) = &mut *work;
        self.rhs.jacobian(x, y, self.p, dy, jy, jp);
        for i in 0..n {
            for c in 0..w {
                let mut v = if c >= n { jp[i * k + c - n] } else { 0.0 };
                for l in 0..n {
                    v += jy[i * n + l] * m[l * w + c];
                }
                dm[i * w + c] = v;
            }
        }
    }
}

/// A segment's end: the state, and with sensitivities `M` (`n x (n + k)`, row-major).
pub(crate) struct End {
    pub y: Vec<f64>,
    pub m: Option<Vec<f64>>,
    /// Right-hand-side evaluations of the augmented system.
    pub evaluations: usize,
}

/// Integrates `y' = f` on `[x0, x1]` from `y0` (with the sensitivities if `sens`).
pub(crate) fn shoot<R: Rhs + ?Sized>(
    rhs: &R,
    dop: &Dop853,
    (x0, x1): (f64, f64),
    y0: &[f64],
    p: &[f64],
    sens: bool,
) -> Result<End, BvpError> {
    let n = y0.len();
    let k = p.len();
    if !sens {
        let sol = dop.integrate(&Plain { rhs, p, n }, x0, x1, y0)?;
        return Ok(End {
            y: sol.u_end,
            m: None,
            evaluations: sol.stats.rhs_evals,
        });
    }
    let w = n + k;
    let mut u0 = vec![0.0; n * (1 + w)];
    u0[..n].copy_from_slice(y0);
    for i in 0..n {
        u0[n + i * w + i] = 1.0;
    }
    let sys = Variational {
        rhs,
        p,
        n,
        work: RefCell::new((vec![0.0; n * n], vec![0.0; n * k])),
    };
    let sol = dop.integrate(&sys, x0, x1, &u0)?;
    let mut u = sol.u_end;
    let m = u.split_off(n);
    Ok(End {
        y: u,
        m: Some(m),
        evaluations: sol.stats.rhs_evals,
    })
}

/// The dense output of a segment (the state alone).
pub(crate) fn dense<R: Rhs + ?Sized>(
    rhs: &R,
    dop: &Dop853,
    (x0, x1): (f64, f64),
    y0: &[f64],
    p: &[f64],
) -> Result<OdeSolution, BvpError> {
    let dop = Dop853 {
        dense: true,
        ..dop.clone()
    };
    dop.integrate(
        &Plain {
            rhs,
            p,
            n: y0.len(),
        },
        x0,
        x1,
        y0,
    )
}
