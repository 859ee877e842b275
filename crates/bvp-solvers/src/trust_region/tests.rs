//! The trust-region system solver on classical test problems (Moré, Garbow & Hillstrom 1981).

use super::{solve, NonlinearSystem, TrustRegionOptions};
use crate::BvpError;

#[derive(Debug, PartialEq)]
enum MyError {
    Bvp(BvpError),
    Model(&'static str),
}
impl std::fmt::Display for MyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{self:?}")
    }
}
impl std::error::Error for MyError {}
impl From<BvpError> for MyError {
    fn from(e: BvpError) -> Self {
        MyError::Bvp(e)
    }
}

/// Rosenbrock as a system: r = (10 (y - x^2), 1 - x), root (1, 1).
struct Rosenbrock {
    analytic: bool,
}
impl NonlinearSystem for Rosenbrock {
    type Error = MyError;
    fn n_unknowns(&self) -> usize {
        2
    }
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), MyError> {
        r[0] = 10.0 * (x[1] - x[0] * x[0]);
        r[1] = 1.0 - x[0];
        Ok(())
    }
    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> Result<(), MyError> {
        if !self.analytic {
            // the trait's forward differences
            let mut j = [0.0; 4];
            struct Fd;
            impl NonlinearSystem for Fd {
                type Error = MyError;
                fn n_unknowns(&self) -> usize {
                    2
                }
                fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), MyError> {
                    Rosenbrock { analytic: true }.residual(x, r)
                }
            }
            Fd.jacobian(x, &mut j)?;
            jac.copy_from_slice(&j);
            return Ok(());
        }
        jac.copy_from_slice(&[-20.0 * x[0], 10.0, -1.0, 0.0]);
        Ok(())
    }
}

/// Powell's badly scaled function: r = (1e4 x y - 1, e^-x + e^-y - 1.0001).
struct PowellBadlyScaled;
impl NonlinearSystem for PowellBadlyScaled {
    type Error = MyError;
    fn n_unknowns(&self) -> usize {
        2
    }
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), MyError> {
        r[0] = 1e4 * x[0] * x[1] - 1.0;
        r[1] = (-x[0]).exp() + (-x[1]).exp() - 1.0001;
        Ok(())
    }
    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> Result<(), MyError> {
        jac.copy_from_slice(&[1e4 * x[1], 1e4 * x[0], -(-x[0]).exp(), -(-x[1]).exp()]);
        Ok(())
    }
}

/// Inconsistent over-determined system r = (x - 1, x + 1): least-squares minimum sqrt(2) at 0.
struct Inconsistent;
impl NonlinearSystem for Inconsistent {
    type Error = MyError;
    fn n_unknowns(&self) -> usize {
        1
    }
    fn n_residuals(&self) -> usize {
        2
    }
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), MyError> {
        r[0] = x[0] - 1.0;
        r[1] = x[0] + 1.0;
        Ok(())
    }
}

/// r = x^2 + 1: no real root; min |r| = 1 at x = 0.
struct NoRoot;
impl NonlinearSystem for NoRoot {
    type Error = MyError;
    fn n_unknowns(&self) -> usize {
        1
    }
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), MyError> {
        r[0] = x[0] * x[0] + 1.0;
        Ok(())
    }
}

/// r = x - 3, but the "model" fails for x > 1.5.
struct Fails;
impl NonlinearSystem for Fails {
    type Error = MyError;
    fn n_unknowns(&self) -> usize {
        1
    }
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<(), MyError> {
        if x[0] > 1.5 {
            return Err(MyError::Model("out of range"));
        }
        r[0] = x[0] - 3.0;
        Ok(())
    }
}

fn opts(tol: f64, max_iters: u64) -> TrustRegionOptions {
    TrustRegionOptions {
        tol,
        max_iters,
        ..TrustRegionOptions::default()
    }
}

#[test]
fn rosenbrock_system() {
    for analytic in [true, false] {
        let sol = solve(&Rosenbrock { analytic }, &[-1.2, 1.0], &opts(1e-12, 200)).unwrap();
        println!("Rosenbrock analytic={analytic}: {sol:?}");
        assert!(
            (sol.x[0] - 1.0).abs() < 1e-12 && (sol.x[1] - 1.0).abs() < 1e-11,
            "{:?}",
            sol.x
        );
        assert!(sol.residual_norm <= 1e-12);
        assert!(sol.iterations < 50);
        // one residual evaluation per iteration (+ the initial one): the cache works
        assert!(sol.evaluations as u64 <= sol.iterations + 2, "{sol:?}");
    }
}

#[test]
fn powell_badly_scaled() {
    // published root: x = 1.098159329699759e-5, y = 9.106146739867318
    let sol = solve(&PowellBadlyScaled, &[0.0, 1.0], &opts(1e-13, 2000)).unwrap();
    println!("Powell: {sol:?}");
    let mut r = [0.0; 2];
    PowellBadlyScaled.residual(&sol.x, &mut r).unwrap();
    assert!(r[0].hypot(r[1]) <= 1e-13);
    // the system is symmetric in (x, y): either ordering of the root is a solution
    let (lo, hi) = (sol.x[0].min(sol.x[1]), sol.x[0].max(sol.x[1]));
    assert!((lo - 1.098159329699759e-5).abs() < 1e-13, "{lo:e}");
    assert!((hi - 9.106146739867318).abs() < 1e-8, "{hi}");
}

#[test]
fn inconsistent_gives_no_convergence_with_residual() {
    match solve(&Inconsistent, &[3.0], &opts(1e-10, 50)) {
        Err(MyError::Bvp(BvpError::NoConvergence {
            method: "trust-region",
            residual,
            ..
        })) => assert!((residual - 2f64.sqrt()).abs() < 1e-8, "{residual}"),
        other => panic!("{other:?}"),
    }
    match solve(&NoRoot, &[2.0], &opts(1e-10, 100)) {
        Err(MyError::Bvp(BvpError::NoConvergence { residual, .. })) => {
            assert!((1.0..1.0 + 1e-6).contains(&residual), "{residual}")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn user_error_propagates() {
    // the first (Newton) step lands at x = 3 where the model fails
    assert_eq!(
        solve(&Fails, &[0.0], &opts(1e-12, 50)),
        Err(MyError::Model("out of range"))
    );
    // already failing at x0
    assert_eq!(
        solve(&Fails, &[2.0], &opts(1e-12, 50)),
        Err(MyError::Model("out of range"))
    );
}

#[test]
fn exact_start_and_bad_inputs() {
    let sol = solve(
        &Rosenbrock { analytic: true },
        &[1.0, 1.0],
        &opts(1e-12, 10),
    )
    .unwrap();
    assert_eq!(sol.iterations, 0);
    assert_eq!(sol.x, vec![1.0, 1.0]);
    assert!(matches!(
        solve(&Rosenbrock { analytic: true }, &[1.0], &opts(1e-12, 10)),
        Err(MyError::Bvp(BvpError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        solve(
            &Rosenbrock { analytic: true },
            &[f64::NAN, 1.0],
            &opts(1e-12, 10)
        ),
        Err(MyError::Bvp(BvpError::InvalidInput { name: "x0", .. }))
    ));
    assert!(matches!(
        solve(&Rosenbrock { analytic: true }, &[0.0, 1.0], &opts(-1.0, 10)),
        Err(MyError::Bvp(BvpError::InvalidInput { name: "tol", .. }))
    ));
}

#[test]
fn timing_small_system() {
    let reps = 2000;
    let t0 = std::time::Instant::now();
    let mut it = 0;
    for k in 0..reps {
        let x0 = [-1.2 + 1e-4 * (k % 7) as f64, 1.0];
        let sol = solve(&Rosenbrock { analytic: true }, &x0, &opts(1e-12, 200)).unwrap();
        it += sol.iterations;
    }
    let dt = t0.elapsed().as_secs_f64() / reps as f64;
    println!(
        "2x2 Rosenbrock: {:.2} us per solve, {:.1} iterations",
        dt * 1e6,
        it as f64 / reps as f64
    );
}

#[test]
fn budget_boundary_is_exact() {
    // Rosenbrock from (-1.2, 1) needs exactly 14 iterations: a budget of 14 succeeds (argmin
    // reports MaxItersReached there, which must still count as converged), 13 does not.
    let sys = Rosenbrock { analytic: true };
    let sol = solve(&sys, &[-1.2, 1.0], &opts(1e-12, 14)).unwrap();
    assert_eq!(sol.iterations, 14);
    match solve(&sys, &[-1.2, 1.0], &opts(1e-12, 13)) {
        Err(MyError::Bvp(BvpError::NoConvergence {
            iterations: 13,
            residual,
            ..
        })) => {
            assert!(residual > 1e-12 && residual < 1.0, "{residual}")
        }
        other => panic!("{other:?}"),
    }
}
