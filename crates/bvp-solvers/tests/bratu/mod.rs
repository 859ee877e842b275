//! The Bratu problem `y'' + lambda e^y = 0`, `y(0) = y(1) = 0`, posed for shooting on
//! `p = y'(0)`, with its closed form (shared by the shooting and continuation tests).

use bvp_solvers::integrator::OdeSystem;
use bvp_solvers::shooting::ShootingProblem;

/// Bratu at `lambda`; unknown `p = y'(0)`.
pub struct Bratu {
    pub lambda: f64,
}
pub struct BratuOde {
    lambda: f64,
}
impl OdeSystem for BratuOde {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
        du[0] = u[1];
        du[1] = -self.lambda * u[0].exp();
    }
}
impl ShootingProblem for Bratu {
    type System = BratuOde;
    fn n_params(&self) -> usize {
        1
    }
    fn system(&self, _p: &[f64]) -> BratuOde {
        BratuOde {
            lambda: self.lambda,
        }
    }
    fn span(&self, _p: &[f64]) -> (f64, f64) {
        (0.0, 1.0)
    }
    fn initial_state(&self, p: &[f64], u0: &mut [f64]) {
        u0[0] = 0.0;
        u0[1] = p[0];
    }
    fn residual(&self, _p: &[f64], u_end: &[f64], r: &mut [f64]) {
        r[0] = u_end[0];
    }
}

/// Roots of theta = sqrt(2 lambda) cosh(theta/4) by bisection on [lo, hi] (independent of the
/// crate's root finders).
pub fn bratu_theta(lambda: f64, mut lo: f64, mut hi: f64) -> f64 {
    let f = |t: f64| t - (2.0 * lambda).sqrt() * (t / 4.0).cosh();
    assert!(f(lo) * f(hi) < 0.0);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if f(m) * f(lo) > 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    0.5 * (lo + hi)
}

/// `y'(0) = theta tanh(theta / 4)` of the solution with the given `theta`.
pub fn slope_at_zero(theta: f64) -> f64 {
    theta * (theta / 4.0).tanh()
}
