//! Load continuation on the Bratu problem y'' + lambda e^y = 0, y(0) = y(1) = 0, solved by
//! shooting on p = y'(0). The lower branch exists up to lambda_c = 3.513830719...

use bvp_solvers::continuation::{BranchGuard, Continuation, ContinuationStats, StallCause};
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
        .run(0.0, lambda, vec![0.0], |l, p: &Vec<f64>| {
            solver.solve(&Bratu { lambda: l }, p).map(|s| s.params)
        })
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
    match cont.run(0.0, 4.0, vec![0.0], |l, p: &Vec<f64>| {
        solver.solve(&Bratu { lambda: l }, p).map(|s| s.params)
    }) {
        Err(BvpError::ContinuationStalled {
            reached,
            target,
            step,
        }) => {
            println!("stalled at {reached}, step {step}");
            assert_eq!(target, 4.0);
            assert!(
                reached <= lambda_c && reached > lambda_c - 0.05,
                "{reached}"
            );
            assert!(step < 2e-3);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn continuation_counts_and_validation() {
    // a solve that needs the previous solution within 0.3: x(l) = l, fails if |guess - l| > 0.3
    let cont = Continuation {
        initial_step: 1.0,
        min_step: 1e-3,
        max_step: 1.0,
    };
    let solve = |l: f64, g: &f64| -> Result<f64, BvpError> {
        if (g - l).abs() > 0.3 {
            Err(BvpError::InvalidInput {
                name: "guess",
                value: *g,
                reason: "too far",
            })
        } else {
            Ok(l)
        }
    };
    let (x, stats) = cont.run(0.0, 2.0, 0.0, solve).unwrap();
    assert_eq!(x, 2.0);
    // 1.0 fails, 0.5 fails, 0.25 ok, then (0.5 fails, 0.25 ok) x 6, and the last 0.25 is
    // clipped to the target and succeeds: 8 steps, 8 halvings
    assert_eq!(stats.steps, 8);
    assert_eq!(stats.halvings, 2 + 6);
    // backward direction
    let (x, _) = cont.run(2.0, 1.0, 2.0, solve).unwrap();
    assert_eq!(x, 1.0);
    assert!(matches!(
        Continuation {
            initial_step: 0.0,
            min_step: 1e-3,
            max_step: 1.0
        }
        .run(0.0, 1.0, 0.0, solve),
        Err(BvpError::InvalidInput { .. })
    ));
}

/// Newton on `y^3 + y = lambda` (one root for every lambda): `follow` reaches lambda = 10
/// and the answer solves the equation to rounding.
fn cubic_newton(lambda: f64, y0: f64) -> Result<f64, BvpError> {
    let mut y = y0;
    for it in 0..30 {
        let r = y * y * y + y - lambda;
        if r.abs() < 1e-13 * (1.0 + lambda.abs()) {
            return Ok(y);
        }
        y -= r / (3.0 * y * y + 1.0);
        if it == 29 {
            break;
        }
    }
    Err(BvpError::NoConvergence {
        method: "cubic",
        iterations: 30,
        residual: y * y * y + y - lambda,
    })
}

#[test]
fn follow_reaches_the_target_with_a_secant_predictor() {
    let cont = Continuation {
        initial_step: 0.1,
        min_step: 1e-6,
        max_step: 0.5,
    };
    let mut calls = 0;
    let (y, stats) = cont
        .follow(
            0.0,
            10.0,
            vec![0.0],
            &BranchGuard::default(),
            |l, p: &[f64]| {
                calls += 1;
                cubic_newton(l, p[0]).map(|y| vec![y])
            },
        )
        .unwrap();
    // y^3 + y = 10 has the root y = 2 exactly
    assert!((y[0] - 2.0).abs() < 1e-12, "{}", y[0]);
    assert_eq!(stats.halvings, 0);
    assert_eq!(stats.steps, calls);
}

#[test]
fn follow_fails_with_the_last_inner_error_or_the_jump() {
    let cont = Continuation {
        initial_step: 0.25,
        min_step: 0.01,
        max_step: 0.25,
    };
    // a corrector that fails beyond lambda = 0.5 with its own error
    let fail = cont
        .follow(
            0.0,
            1.0,
            vec![0.0],
            &BranchGuard::default(),
            |l, _p: &[f64]| {
                if l > 0.5 {
                    Err(BvpError::NoConvergence {
                        method: "inner",
                        iterations: 7,
                        residual: l,
                    })
                } else {
                    Ok(vec![l])
                }
            },
        )
        .unwrap_err();
    assert_eq!(fail.reached, 0.5);
    assert!(fail.step < 0.02 && fail.step >= 0.01, "{}", fail.step);
    match fail.cause {
        StallCause::Inner(BvpError::NoConvergence {
            method: "inner",
            iterations: 7,
            residual,
        }) => assert!(residual > 0.5 && residual < 0.52, "{residual}"),
        other => panic!("{other:?}"),
    }
    // a corrector that lands on another branch (y jumps by 1 at lambda > 0.5)
    let guard = BranchGuard {
        absolute: 0.2,
        relative: 0.5,
        max_attempts: 1000,
    };
    let fail = cont
        .follow(
            0.0,
            1.0,
            vec![0.0],
            &guard,
            |l, _p: &[f64]| -> Result<Vec<f64>, BvpError> {
                Ok(vec![if l > 0.5 { l + 1.0 } else { l }])
            },
        )
        .unwrap_err();
    assert_eq!(fail.reached, 0.5);
    match fail.cause {
        StallCause::Jump { distance, .. } => assert!(distance > 0.9, "{distance}"),
        other => panic!("{other:?}"),
    }
    // the corrector budget (a guard wide enough to accept the first, unpredicted step)
    let guard = BranchGuard {
        absolute: 1.0,
        relative: 0.5,
        max_attempts: 3,
    };
    let fail = cont
        .follow(
            0.0,
            1.0,
            vec![0.0],
            &guard,
            |l, _p: &[f64]| -> Result<Vec<f64>, BvpError> { Ok(vec![l]) },
        )
        .unwrap_err();
    assert_eq!(fail.cause, StallCause::Budget { max_attempts: 3 });
    assert_eq!(fail.steps, 3);
}
