//! Shooting against closed-form BVP solutions.

use bvp_solvers::integrator::{Dop853, OdeSystem};
use bvp_solvers::newton::{JacobianUpdate, NewtonPolicy, Safeguards, Termination};
use bvp_solvers::shooting::{
    solve_shooting, Shooting, ShootingIntegrator, ShootingProblem, ShotProblem,
};
use bvp_solvers::trust_region::TrustRegionOptions;
use bvp_solvers::BvpError;

use crate::bratu;
use bratu::{bratu_theta, slope_at_zero, Bratu};

fn tr(tol: f64) -> TrustRegionOptions {
    TrustRegionOptions {
        tol,
        max_iters: 100,
        ..TrustRegionOptions::default()
    }
}

fn dop(tol: f64) -> Shooting {
    Shooting {
        integrator: ShootingIntegrator::Dop853(Dop853::new(tol, tol)),
        options: tr(1e-12),
    }
}

#[test]
fn bratu_both_branches_lambda_1() {
    let lambda = 1.0;
    // f(theta) = theta - sqrt2 cosh(theta/4): f(0) < 0, f(4) > 0, f(20) < 0
    for (lo, hi, guess) in [(0.0, 4.0, 0.5), (4.0, 20.0, 10.0)] {
        let theta = bratu_theta(lambda, lo, hi);
        let p_exact = slope_at_zero(theta);
        let sol = dop(1e-13).solve(&Bratu { lambda }, &[guess]).unwrap();
        println!(
            "Bratu theta {theta}: y'(0) = {} (exact {p_exact}), {} its",
            sol.params[0], sol.iterations
        );
        assert!((sol.params[0] - p_exact).abs() < 1e-9 * p_exact.max(1.0));
        // y'(1) = -y'(0) by symmetry
        assert!((sol.u_end[1] + p_exact).abs() < 1e-9 * p_exact.max(1.0));
    }
}

/// Euler elastica of a cantilever column: theta'' + P sin theta = 0, theta(0) = 0,
/// theta'(1) = 0. Shooting backwards from the tip with theta(1) = theta_tip given; unknown P.
pub struct Elastica {
    pub theta_tip: f64,
}
pub struct ElasticaOde {
    p: f64,
}
impl OdeSystem for ElasticaOde {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
        du[0] = u[1];
        du[1] = -self.p * u[0].sin();
    }
}
impl ShootingProblem for Elastica {
    type System = ElasticaOde;
    fn n_params(&self) -> usize {
        1
    }
    fn system(&self, p: &[f64]) -> ElasticaOde {
        ElasticaOde { p: p[0] }
    }
    fn span(&self, _p: &[f64]) -> (f64, f64) {
        (1.0, 0.0)
    }
    fn initial_state(&self, _p: &[f64], u0: &mut [f64]) {
        u0[0] = self.theta_tip;
        u0[1] = 0.0;
    }
    fn residual(&self, _p: &[f64], u_end: &[f64], r: &mut [f64]) {
        r[0] = u_end[0];
    }
}

/// Complete elliptic integral of the first kind by the arithmetic-geometric mean.
fn ellip_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        a = an;
        b = bn;
    }
    std::f64::consts::PI / (2.0 * a)
}

#[test]
fn elastica_load_matches_elliptic_integral() {
    let mut guess = 2.5;
    for theta_tip in [0.01, 0.5, 1.0, 2.0, 2.8] {
        let sol = dop(1e-13).solve(&Elastica { theta_tip }, &[guess]).unwrap();
        let exact = ellip_k((theta_tip / 2.0).sin()).powi(2);
        println!(
            "theta_tip {theta_tip}: P = {:.15}, K^2 = {exact:.15}",
            sol.params[0]
        );
        assert!(
            (sol.params[0] - exact).abs() < 1e-9 * exact,
            "{}",
            sol.params[0] - exact
        );
        guess = sol.params[0];
    }
    // small amplitude: the Euler load pi^2/4
    let sol = dop(1e-13)
        .solve(&Elastica { theta_tip: 1e-4 }, &[2.0])
        .unwrap();
    assert!((sol.params[0] - std::f64::consts::PI.powi(2) / 4.0).abs() < 1e-8);
}

/// Bratu with its variational equation `v'' = -lambda e^y v`, `v(0) = 0`, `v'(0) = 1`
/// (`v = dy/dp`): shot with the exact sensitivity for [`solve_shooting`].
struct BratuSensitive {
    lambda: f64,
    shots: std::cell::Cell<usize>,
}
struct BratuVariational {
    lambda: f64,
}
impl OdeSystem for BratuVariational {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
        let e = self.lambda * u[0].exp();
        du[0] = u[1];
        du[1] = -e;
        du[2] = u[3];
        du[3] = -e * u[2];
    }
}
impl ShotProblem<1> for BratuSensitive {
    type End = Vec<f64>;
    type Error = BvpError;
    fn shoot(&self, p: &[f64; 1], _sensitivities: bool) -> Result<Vec<f64>, BvpError> {
        self.shots.set(self.shots.get() + 1);
        let ode = BratuVariational {
            lambda: self.lambda,
        };
        let d = Dop853::new(1e-13, 1e-13);
        Ok(d.integrate(&ode, 0.0, 1.0, &[0.0, p[0], 0.0, 1.0])?.u_end)
    }
    fn residual(&self, _p: &[f64; 1], u: &Vec<f64>) -> [f64; 1] {
        [u[0]]
    }
    fn residual_jacobian(&self, _p: &[f64; 1], u: &Vec<f64>) -> Option<[[f64; 1]; 1]> {
        Some([[u[2]]])
    }
}

#[test]
fn bratu_both_branches_with_exact_sensitivities() {
    let lambda = 1.0;
    for (lo, hi, guess) in [(0.0, 4.0, 0.5), (4.0, 20.0, 10.0)] {
        let theta = bratu_theta(lambda, lo, hi);
        let p_exact = slope_at_zero(theta);
        let problem = BratuSensitive {
            lambda,
            shots: std::cell::Cell::new(0),
        };
        let policy = NewtonPolicy {
            update: JacobianUpdate::Reevaluate { keep_below: 0.0 },
            jacobian_at_solution: false,
            ..NewtonPolicy::new(1e-11)
        };
        let out = solve_shooting(&problem, [guess], &policy, &Safeguards::NONE).unwrap();
        assert_eq!(out.termination, Termination::Converged);
        assert!((out.u[0] - p_exact).abs() < 1e-9 * p_exact.max(1.0));
        // the end state is the last shot's: y'(1) = -y'(0)
        assert!((out.point[1] + p_exact).abs() < 1e-9 * p_exact.max(1.0));
        // one shot per step (the Jacobian comes with it), quadratic convergence
        assert_eq!(problem.shots.get(), out.iterations + 1);
        assert!(out.iterations <= 8, "{}", out.iterations);
    }
}
