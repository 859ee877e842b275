//! Unit tests of the Newton iteration and its policies.

use super::*;
use std::cell::Cell;

/// `R(u) = (u0^2 - 2, u1 - u0^3)`: the root `(sqrt 2, 2 sqrt 2)`; counts evaluations.
struct Cubic {
    evals: Cell<usize>,
    jacs: Cell<usize>,
    /// Added to the residual: a noise floor.
    noise: f64,
}

impl NewtonSystem<2> for Cubic {
    type Point = usize;
    type Error = &'static str;
    fn eval(&self, u: &[f64; 2], jacobian: bool) -> Result<Evaluation<2, usize>, &'static str> {
        if !u[0].is_finite() {
            return Err("not finite");
        }
        self.evals.set(self.evals.get() + 1);
        let n = self.evals.get();
        let wiggle = if n.is_multiple_of(2) {
            self.noise
        } else {
            -self.noise
        };
        let r = [u[0] * u[0] - 2.0 + wiggle, u[1] - u[0].powi(3)];
        let jac = jacobian.then(|| {
            self.jacs.set(self.jacs.get() + 1);
            [[2.0 * u[0], 0.0], [-3.0 * u[0] * u[0], 1.0]]
        });
        Ok(Evaluation { r, jac, point: n })
    }
}

fn cubic(noise: f64) -> Cubic {
    Cubic {
        evals: Cell::new(0),
        jacs: Cell::new(0),
        noise,
    }
}

#[test]
fn converges_quadratically_to_the_root() {
    let sys = cubic(0.0);
    let out = newton(&sys, [1.0, 1.0], None, &NewtonPolicy::new(1e-13)).unwrap();
    assert_eq!(out.termination, Termination::Converged);
    let s2 = 2f64.sqrt();
    assert!((out.u[0] - s2).abs() < 1e-14 && (out.u[1] - 2.0 * s2).abs() < 1e-13);
    assert!(out.iterations <= 7, "{}", out.iterations);
    // the Jacobian at the solution
    assert!((out.jac[0][0] - 2.0 * s2).abs() < 1e-12);
    // the point is the last evaluation's
    assert_eq!(out.point, sys.evals.get());
}

#[test]
fn simplified_newton_keeps_the_jacobian_and_broyden_never_evaluates_one() {
    let sys = cubic(0.0);
    let policy = NewtonPolicy {
        update: JacobianUpdate::Reevaluate { keep_below: 0.5 },
        jacobian_at_solution: false,
        ..NewtonPolicy::new(1e-12)
    };
    let out = newton(&sys, [1.4, 2.8], None, &policy).unwrap();
    assert_eq!(out.termination, Termination::Converged);
    assert!(
        sys.jacs.get() < out.iterations + 1,
        "{} jacobians",
        sys.jacs.get()
    );
    let sys = cubic(0.0);
    let s2 = 2f64.sqrt();
    let jac0 = [[2.0 * 1.4, 0.0], [-3.0 * 1.96, 1.0]];
    let policy = NewtonPolicy {
        update: JacobianUpdate::Broyden {
            min_contraction: 0.5,
        },
        halvings: 0,
        jacobian_at_solution: false,
        ..NewtonPolicy::new(1e-12)
    };
    let out = newton(&sys, [1.4, 2.8], Some(jac0), &policy).unwrap();
    assert_eq!(out.termination, Termination::Converged);
    assert_eq!(sys.jacs.get(), 0);
    assert!((out.u[0] - s2).abs() < 1e-12);
}

/// A start that already meets the tolerance, given a Jacobian from elsewhere: with a
/// Jacobian wanted at the solution, the answer carries the one evaluated there, not the
/// one given (a continuation's tangent is taken from it).
#[test]
fn a_converged_start_still_brings_the_jacobian_at_the_solution() {
    let s2 = 2f64.sqrt();
    let root = [s2, 2.0 * s2];
    let far = [[1.0, 0.0], [0.0, 1.0]];
    for update in [
        JacobianUpdate::Broyden {
            min_contraction: 0.5,
        },
        JacobianUpdate::Reevaluate { keep_below: 0.05 },
    ] {
        let sys = cubic(0.0);
        let policy = NewtonPolicy {
            update,
            ..NewtonPolicy::new(1e-12)
        };
        let out = newton(&sys, root, Some(far), &policy).unwrap();
        assert_eq!(out.termination, Termination::Converged);
        assert_eq!(out.iterations, 0);
        assert!((out.jac[0][0] - 2.0 * s2).abs() < 1e-12, "{:?}", out.jac);
        assert!((out.jac[1][0] + 6.0).abs() < 1e-12, "{:?}", out.jac);
        assert_eq!(sys.jacs.get(), 1);
    }
}

/// With a Jacobian wanted at the solution, the trial the last contraction predicts to
/// converge brings it along: no evaluation after convergence, and the Jacobian is the
/// exact one at the root.
#[test]
fn the_jacobian_at_the_solution_comes_with_the_converging_trial() {
    let sys = cubic(0.0);
    let policy = NewtonPolicy {
        update: JacobianUpdate::Reevaluate { keep_below: 0.5 },
        ..NewtonPolicy::new(1e-12)
    };
    let out = newton(&sys, [1.4, 2.8], None, &policy).unwrap();
    assert_eq!(out.termination, Termination::Converged);
    // one evaluation per step and the start, none at the solution afterwards
    assert_eq!(sys.evals.get(), out.iterations + 1);
    let s2 = 2f64.sqrt();
    let exact = [[2.0 * out.u[0], 0.0], [-3.0 * out.u[0] * out.u[0], 1.0]];
    assert_eq!(out.jac, exact);
    assert!((out.u[0] - s2).abs() < 1e-12);
}

#[test]
fn a_noisy_system_stops_at_its_floor_and_says_so() {
    let sys = cubic(1e-9);
    let policy = NewtonPolicy {
        noise_floor: 1e-7,
        ..NewtonPolicy::new(1e-13)
    };
    let out = newton(&sys, [1.0, 1.0], None, &policy).unwrap();
    assert_eq!(out.termination, Termination::NoiseFloor);
    assert!(out.norm <= 1e-7 && out.norm > 1e-13);
    assert!(out.termination.is_solution());
    let strict = NewtonPolicy::new(1e-13);
    let out = newton(&cubic(1e-9), [1.0, 1.0], None, &strict).unwrap();
    assert!(!out.termination.is_solution(), "{:?}", out.termination);
}

#[test]
fn a_singular_jacobian_is_reported() {
    // at u0 = 0 the first row of the Jacobian vanishes
    let out = newton(&cubic(0.0), [0.0, 1.0], None, &NewtonPolicy::new(1e-12)).unwrap();
    assert_eq!(out.termination, Termination::Singular);
}

#[test]
fn gauss_newton_of_a_square_system_is_newton() {
    let (a, b) = (cubic(0.0), cubic(0.0));
    let p = NewtonPolicy::new(1e-13);
    let n = newton(&a, [1.0, 1.0], None, &p).unwrap();
    let g = gauss_newton(&b, [1.0, 1.0], None, &p).unwrap();
    assert_eq!(g.termination, Termination::Converged);
    assert!((n.u[0] - g.u[0]).abs() < 1e-14 && (n.u[1] - g.u[1]).abs() < 1e-13);
}
