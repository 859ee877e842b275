//! The non-square step rules of the one Newton iteration (module docs of
//! [`newton`](super)): Gauss-Newton through the normal equations for least squares, and the
//! Gauss-Newton projection onto the solutions of an underdetermined system.

use super::{iterate, NewtonAnswer, NewtonPolicy, NewtonSystem, Safeguards};
#[cfg(doc)]
use super::{newton, Termination};
use crate::dense::solve;

/// Gauss-Newton on an overdetermined system (`M >= N`): steps through the normal equations
/// `J^T J du = J^T R` of `min |R(u)|^2`, under `policy` as [`newton`] (which it is for
/// `M = N`). It converges to a solution only where the system is consistent (`|R| <= tol`);
/// at a least-squares minimum above the tolerance it ends without descent.
///
/// # Errors
/// As [`newton`].
pub fn gauss_newton<const N: usize, const M: usize, S: NewtonSystem<N, M>>(
    sys: &S,
    u0: [f64; N],
    jac0: Option<[[f64; N]; M]>,
    policy: &NewtonPolicy,
) -> Result<NewtonAnswer<N, S::Point, M>, S::Error> {
    iterate(sys, u0, jac0, policy, &Safeguards::NONE, |jac, r, _| {
        let jtj: [[f64; N]; N] = std::array::from_fn(|a| {
            std::array::from_fn(|b| (0..M).map(|i| jac[i][a] * jac[i][b]).sum())
        });
        let jtr: [f64; N] = std::array::from_fn(|a| (0..M).map(|i| jac[i][a] * r[i]).sum());
        solve(&jtj, &jtr)
    })
}

/// The nearest point to the measured `meas` on which an underdetermined system (`M <= N`)
/// holds, `min (u - meas)^T W^-1 (u - meas)` subject to `R(u) = 0` with `W = diag(weights)`,
/// by Gauss-Newton steps of the constrained least-squares problem from `meas` (module docs):
/// the linearised condition `R(u) + J (u' - u) = 0` met at least cost,
///
/// `u' = meas - W J^T lambda`,  `(J W J^T) lambda = R(u) + J (meas - u)`,
///
/// under `policy` as [`newton`] ([`Termination::Singular`] where `J W J^T` is singular, e.g.
/// a condition blind to every weighted unknown).
///
/// # Errors
/// As [`newton`].
pub fn projection<const N: usize, const M: usize, S: NewtonSystem<N, M>>(
    sys: &S,
    meas: [f64; N],
    weights: &[f64; N],
    policy: &NewtonPolicy,
) -> Result<NewtonAnswer<N, S::Point, M>, S::Error> {
    iterate(sys, meas, None, policy, &Safeguards::NONE, |jac, r, u| {
        let jwj: [[f64; M]; M] = std::array::from_fn(|i| {
            std::array::from_fn(|k| (0..N).map(|j| weights[j] * jac[i][j] * jac[k][j]).sum())
        });
        let rhs: [f64; M] = std::array::from_fn(|i| {
            r[i] + (0..N).map(|j| jac[i][j] * (meas[j] - u[j])).sum::<f64>()
        });
        let lambda = solve(&jwj, &rhs)?;
        Some(std::array::from_fn(|j| {
            let next = meas[j] - weights[j] * (0..M).map(|i| jac[i][j] * lambda[i]).sum::<f64>();
            u[j] - next
        }))
    })
}

#[cfg(test)]
mod tests {
    use super::super::{Evaluation, JacobianUpdate, Termination};
    use super::*;
    use std::cell::Cell;

    /// `R(u) = (u0 + u1 - 3, u0 u1 - 2, u0 - 2 u1 + c)`: consistent (root `(2, 1)`) for `c = 0`.
    struct Overdetermined {
        c: f64,
    }

    impl NewtonSystem<2, 3> for Overdetermined {
        type Point = ();
        type Error = ();
        fn eval(&self, u: &[f64; 2], _jac: bool) -> Result<Evaluation<2, (), 3>, ()> {
            let r = [
                u[0] + u[1] - 3.0,
                u[0] * u[1] - 2.0,
                u[0] - 2.0 * u[1] + self.c,
            ];
            let jac = [[1.0, 1.0], [u[1], u[0]], [1.0, -2.0]];
            Ok(Evaluation {
                r,
                jac: Some(jac),
                point: (),
            })
        }
    }

    #[test]
    fn gauss_newton_solves_a_consistent_overdetermined_system() {
        let sys = Overdetermined { c: 0.0 };
        let out = gauss_newton(&sys, [2.5, 0.7], None, &NewtonPolicy::new(1e-13)).unwrap();
        assert_eq!(out.termination, Termination::Converged);
        assert!((out.u[0] - 2.0).abs() < 1e-13 && (out.u[1] - 1.0).abs() < 1e-13);
        // an inconsistent one has no solution: it stops at its least-squares minimum, unsolved
        let sys = Overdetermined { c: 0.1 };
        let out = gauss_newton(&sys, [2.5, 0.7], None, &NewtonPolicy::new(1e-13)).unwrap();
        assert!(!out.termination.is_solution(), "{:?}", out.termination);
        assert!(out.norm > 1e-3 && out.norm < 0.1, "{}", out.norm);
    }

    /// One condition on three unknowns: the unit sphere `|u|^2 = 1` (or, `linear`, the plane
    /// `g . u = 1`); the point is `u` itself, settled when it moves by less than `settle`.
    struct Condition {
        linear: Option<[f64; 3]>,
        settle: f64,
        evals: Cell<usize>,
    }

    impl NewtonSystem<3, 1> for Condition {
        type Point = [f64; 3];
        type Error = ();
        fn eval(&self, u: &[f64; 3], _jac: bool) -> Result<Evaluation<3, [f64; 3], 1>, ()> {
            self.evals.set(self.evals.get() + 1);
            let (r, jac) = match self.linear {
                Some(g) => (g[0] * u[0] + g[1] * u[1] + g[2] * u[2] - 1.0, g),
                None => (
                    u.iter().map(|v| v * v).sum::<f64>() - 1.0,
                    [2.0 * u[0], 2.0 * u[1], 2.0 * u[2]],
                ),
            };
            Ok(Evaluation {
                r: [r],
                jac: Some([jac]),
                point: *u,
            })
        }

        fn settled(&self, old: &[f64; 3], new: &[f64; 3]) -> bool {
            (0..3).map(|j| (new[j] - old[j]).abs()).fold(0.0, f64::max) <= self.settle
        }
    }

    fn projecting() -> NewtonPolicy {
        NewtonPolicy {
            tol: 0.0,
            max_iter: 30,
            halvings: 0,
            update: JacobianUpdate::Reevaluate {
                keep_below: f64::INFINITY,
            },
            jacobian_at_solution: false,
            noise_floor: 0.0,
        }
    }

    #[test]
    fn projection_onto_a_plane_is_one_step_at_least_cost() {
        let g = [2.0, -0.5, 4.0];
        let sys = Condition {
            linear: Some(g),
            settle: 1e-15,
            evals: Cell::new(0),
        };
        let meas = [0.3, -1.2, 0.05];
        let w = [0.25, 1.0, 0.01];
        let out = projection(&sys, meas, &w, &projecting()).unwrap();
        assert_eq!(out.termination, Termination::Converged);
        // on the plane after the first step (a second one, if any, only confirms it)
        assert!(out.r[0].abs() < 1e-15);
        assert!(out.iterations <= 2, "{}", out.iterations);
        // least cost (Lagrange): W^-1 (u - meas) is parallel to the gradient
        let lambda = (out.u[0] - meas[0]) / (w[0] * g[0]);
        for j in 0..3 {
            assert!(((out.u[j] - meas[j]) / w[j] - lambda * g[j]).abs() < 1e-14);
        }
    }

    #[test]
    fn projection_onto_a_sphere_finds_the_nearest_point() {
        // equal weights: the nearest point of the unit sphere is meas / |meas|
        let sys = Condition {
            linear: None,
            settle: 1e-14,
            evals: Cell::new(0),
        };
        let meas = [0.9, 0.6, -0.3];
        let out = projection(&sys, meas, &[1.0; 3], &projecting()).unwrap();
        assert_eq!(out.termination, Termination::Converged);
        let n = meas.iter().map(|v| v * v).sum::<f64>().sqrt();
        for (u, m) in out.u.iter().zip(meas) {
            assert!((u - m / n).abs() < 1e-13, "{:?}", out.u);
        }
        assert_eq!(sys.evals.get(), out.iterations + 1);
        // a condition blind to the weighted unknowns has no step
        let sys = Condition {
            linear: Some([1.0, 0.0, 0.0]),
            settle: 0.0,
            evals: Cell::new(0),
        };
        let out = projection(&sys, meas, &[0.0, 1.0, 1.0], &projecting()).unwrap();
        assert_eq!(out.termination, Termination::Singular);
    }
}
