//! Load continuation on the Bratu problem y'' + lambda e^y = 0, y(0) = y(1) = 0, solved by
//! shooting on p = y'(0), from the known solution y = 0 at lambda = 0. The lower branch exists
//! up to lambda_c = 3.513830719...

use bvp_solvers::continuation::{BranchGuard, Continuation, ContinuationStats};
use bvp_solvers::integrator::Dop853;
use bvp_solvers::shooting::{Shooting, ShootingIntegrator};
use bvp_solvers::trust_region::TrustRegionOptions;
use bvp_solvers::BvpError;

use crate::bratu;
use bratu::{bratu_theta, slope_at_zero, Bratu};

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
    // the lower branch: theta below the fold's 4.7987
    let exact = slope_at_zero(bratu_theta(lambda, 0.0, 4.79));
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
