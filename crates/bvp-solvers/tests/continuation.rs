//! Load continuation on the Bratu problem y'' + lambda e^y = 0, y(0) = y(1) = 0, solved by
//! shooting on p = y'(0), from the known solution y = 0 at lambda = 0. The lower branch exists
//! up to lambda_c = 3.513830719...

use bvp_solvers::continuation::{BranchGuard, Continuation, ContinuationStats};
use bvp_solvers::integrator::{Dop853, OdeSystem};
use bvp_solvers::shooting::{Shooting, ShootingIntegrator, ShootingProblem};
use bvp_solvers::trust_region::TrustRegionOptions;
use bvp_solvers::BvpError;

struct Bratu {
    lambda: f64,
}
struct BratuOde {
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

/// Lower-branch theta of theta = sqrt(2 lambda) cosh(theta/4) by bisection on [0, 4.8]
/// (the fold is at theta ~ 4.7987).
fn lower_theta(lambda: f64) -> f64 {
    let f = |t: f64| t - (2.0 * lambda).sqrt() * (t / 4.0).cosh();
    let (mut lo, mut hi) = (0.0, 4.79);
    assert!(f(lo) < 0.0 && f(hi) > 0.0);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if f(m) < 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    0.5 * (lo + hi)
}

/// A corrector with a budget of `max_iters` trust-region iterations per solve (from the
/// trivial guess at lambda = 3.5 the solve needs 8).
fn solver(max_iters: u64) -> Shooting {
    Shooting {
        integrator: ShootingIntegrator::Dop853(Dop853::new(1e-13, 1e-13)),
        options: TrustRegionOptions {
            tol: 1e-11,
            max_iters,
            ..TrustRegionOptions::default()
        },
    }
}

#[test]
fn continuation_reaches_lambda_3_5_where_direct_solve_fails() {
    let lambda = 3.5;
    let solver = solver(4);
    // direct from the trivial guess: not within the budget
    let direct = solver.solve(&Bratu { lambda }, &[0.0]);
    assert!(
        matches!(direct, Err(BvpError::NoConvergence { .. })),
        "{direct:?}"
    );

    let cont = Continuation {
        initial_step: 0.5,
        min_step: 1e-4,
        max_step: 1.0,
    };
    let (p, stats): (Vec<f64>, ContinuationStats) = cont
        .follow(
            0.0,
            lambda,
            vec![0.0],
            &BranchGuard::default(),
            |l, p: &[f64]| solver.solve(&Bratu { lambda: l }, p).map(|s| s.params),
        )
        .unwrap();
    let theta = lower_theta(lambda);
    let exact = theta * (theta / 4.0).tanh();
    println!("lambda 3.5: y'(0) = {} exact {exact}, {stats:?}", p[0]);
    assert!((p[0] - exact).abs() < 1e-9 * exact, "{}", p[0] - exact);
    assert!(stats.steps >= 3);
}

#[test]
fn continuation_stalls_at_the_fold() {
    let solver = solver(30);
    let cont = Continuation {
        initial_step: 0.5,
        min_step: 1e-3,
        max_step: 0.5,
    };
    let lambda_c = 3.513_830_719_125_162;
    let fail = cont
        .follow(
            0.0,
            4.0,
            vec![0.0],
            &BranchGuard::default(),
            |l, p: &[f64]| solver.solve(&Bratu { lambda: l }, p).map(|s| s.params),
        )
        .unwrap_err();
    let (reached, step) = (fail.reached, fail.step);
    println!("stalled at {reached}, step {step}: {fail}");
    assert_eq!(fail.target, 4.0);
    assert!(
        reached <= lambda_c && reached > lambda_c - 0.05,
        "{reached}"
    );
    assert!(step < 2e-3);
}
