//! Unit tests of [`solve_square`].

use super::*;
use crate::newton::{Evaluation, JacobianUpdate};
use std::cell::Cell;

/// `R(u) = (atan(u0 - 1), u1 - 2 u0)`: the root `(1, 2)`; full Newton steps overshoot from
/// `|u0 - 1| > 1.39` and diverge. The point is the evaluation's number; trial points farther
/// than `radius` from the origin are inadmissible, and evaluating one is counted.
struct Atan {
    evals: Cell<usize>,
    radius: f64,
    outside: Cell<usize>,
}

impl NewtonSystem<2> for Atan {
    type Point = usize;
    type Error = BvpError;
    fn eval(&self, u: &[f64; 2], jacobian: bool) -> Result<Evaluation<2, usize>, BvpError> {
        if !(u[0].is_finite() && u[1].is_finite()) {
            return Err(BvpError::InvalidInput {
                name: "u",
                value: u[0],
                reason: "not finite",
            });
        }
        if !self.admissible(u) {
            self.outside.set(self.outside.get() + 1);
        }
        self.evals.set(self.evals.get() + 1);
        let d = u[0] - 1.0;
        let jac = jacobian.then_some([[1.0 / (1.0 + d * d), 0.0], [-2.0, 1.0]]);
        Ok(Evaluation {
            r: [d.atan(), u[1] - 2.0 * u[0]],
            jac,
            point: self.evals.get(),
        })
    }
    fn admissible(&self, u: &[f64; 2]) -> bool {
        u[0].hypot(u[1]) <= self.radius
    }
}

fn atan(radius: f64) -> Atan {
    Atan {
        evals: Cell::new(0),
        radius,
        outside: Cell::new(0),
    }
}

/// [`solve_square`] with its report.
fn run(
    sys: &Atan,
    u0: [f64; 2],
    jac0: Option<[[f64; 2]; 2]>,
    opts: &NonlinearOptions,
) -> (Result<NewtonAnswer<2, usize>, BvpError>, SquareReport) {
    let mut report = SquareReport {
        solver: Solver::TrustRegion,
        newton_iterations: 99,
    };
    let result = solve_square(sys, u0, jac0, opts, &mut report);
    (result, report)
}

/// Full Newton steps (no halving): diverges from afar.
fn full_steps(tol: f64) -> NewtonPolicy {
    NewtonPolicy {
        halvings: 0,
        ..NewtonPolicy::new(tol)
    }
}

#[test]
fn the_newton_path_is_newtons_bit_for_bit() {
    let opts = NonlinearOptions::new(1e-13);
    let (a, b) = (atan(f64::INFINITY), atan(f64::INFINITY));
    let (result, report) = run(&a, [1.5, 0.0], None, &opts);
    let direct = newton(&b, [1.5, 0.0], None, &opts.newton.unwrap()).unwrap();
    assert_eq!(
        (report.solver, report.newton_iterations),
        (Solver::Newton, 0)
    );
    let ans = result.unwrap();
    assert_eq!(ans.u, direct.u);
    assert_eq!(ans.jac, direct.jac);
    assert_eq!(
        (ans.iterations, ans.point, ans.termination),
        (direct.iterations, direct.point, Termination::Converged)
    );
    assert!((ans.u[0] - 1.0).abs() < 1e-13 && (ans.u[1] - 2.0).abs() < 1e-13);
}

#[test]
fn broyden_from_a_start_jacobian_comes_first_and_newton_follows_where_it_fails() {
    let broyden = NewtonPolicy {
        halvings: 0,
        update: JacobianUpdate::Broyden {
            min_contraction: 0.5,
        },
        ..NewtonPolicy::new(1e-12)
    };
    let opts = NonlinearOptions {
        start: Some(broyden),
        ..NonlinearOptions::new(1e-12)
    };
    // the exact Jacobian near the root: Broyden converges, no Jacobian evaluated but at the end
    let near = [[1.0, 0.0], [-2.0, 1.0]];
    let (a, b) = (atan(f64::INFINITY), atan(f64::INFINITY));
    let (result, report) = run(&a, [1.2, 2.3], Some(near), &opts);
    let direct = newton(&b, [1.2, 2.3], Some(near), &broyden).unwrap();
    assert_eq!(report.solver, Solver::Newton);
    let ans = result.unwrap();
    assert_eq!((ans.u, ans.point), (direct.u, direct.point));
    // a wrong start Jacobian: Broyden stops (no contraction), Newton from the start solves
    let wrong = [[-1.0, 0.0], [0.0, -1.0]];
    let (result, report) = run(&atan(f64::INFINITY), [1.2, 2.3], Some(wrong), &opts);
    assert_eq!(report.solver, Solver::Newton);
    assert!(report.newton_iterations >= 1);
    assert!((result.unwrap().u[0] - 1.0).abs() < 1e-12);
    // without a start Jacobian the start policy does not apply
    let (result, report) = run(&atan(f64::INFINITY), [1.2, 2.3], None, &opts);
    assert_eq!(report.newton_iterations, 0);
    assert!(result.is_ok());
}

#[test]
fn the_trust_region_rescues_a_diverging_newton() {
    let opts = NonlinearOptions {
        newton: Some(full_steps(1e-12)),
        ..NonlinearOptions::new(1e-12)
    };
    // Newton alone diverges from u0 = 6: its failed answer comes back without the fallback
    let alone = NonlinearOptions {
        trust_region: None,
        ..opts
    };
    let (result, report) = run(&atan(f64::INFINITY), [6.0, 0.0], None, &alone);
    assert_eq!(report.solver, Solver::Newton);
    let ans = result.unwrap();
    assert!(!ans.termination.is_solution(), "{ans:?}");
    assert!(ans.iterations >= 1 && ans.norm > 1.0);
    // with it, the trust region reaches the root (1, 2), its point evaluated there with
    // the Jacobian, inside an admissible disc that Newton's first full step leaves (it ends
    // there without descent)
    let sys = atan(8.0);
    let (result, report) = run(&sys, [6.0, 0.0], None, &opts);
    assert_eq!(
        (report.solver, report.newton_iterations),
        (Solver::TrustRegion, 0)
    );
    let ans = result.unwrap();
    assert_eq!(ans.termination, Termination::Converged);
    let u = ans.u;
    assert!(
        (u[0] - 1.0).abs() < 1e-11 && (u[1] - 2.0).abs() < 1e-11,
        "{u:?}"
    );
    assert!(ans.norm <= 1e-12);
    assert_eq!(ans.point, sys.evals.get());
    assert_eq!(
        ans.jac,
        [[1.0 / (1.0 + (u[0] - 1.0).powi(2)), 0.0], [-2.0, 1.0]]
    );
    assert_eq!(
        sys.outside.get(),
        0,
        "the trust region evaluated an inadmissible point"
    );
}

#[test]
fn options_without_a_solver_are_rejected() {
    let opts = NonlinearOptions {
        start: None,
        newton: None,
        trust_region: None,
    };
    let (out, _) = run(&atan(1.0), [0.0, 0.0], None, &opts);
    assert!(matches!(out, Err(BvpError::InvalidInput { .. })), "{out:?}");
    // the trust region alone, failing: its error
    let tr = TrustRegionOptions {
        tol: 1e-12,
        max_iters: 1,
        ..TrustRegionOptions::default()
    };
    let alone = NonlinearOptions {
        trust_region: Some(tr),
        ..opts
    };
    let (out, _) = run(&atan(f64::INFINITY), [6.0, 0.0], None, &alone);
    assert!(
        matches!(out, Err(BvpError::NoConvergence { .. })),
        "{out:?}"
    );
}
