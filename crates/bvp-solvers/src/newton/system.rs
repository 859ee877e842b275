//! The system a Newton iteration solves and what it answers: [`NewtonSystem`] (the
//! residual `R(u)` with `dR/du` on request, [`Evaluation`]), [`NewtonAnswer`] with its
//! [`Termination`], shared by the iteration (the parent module), its safeguards and its
//! least-squares variants.

#[cfg(doc)]
use super::{gauss_newton, newton, projection, Safeguards, SmallStep, Stall};

/// One evaluation of the system at a point (`N` unknowns, `M` equations).
#[derive(Clone, Debug)]
pub struct Evaluation<const N: usize, P, const M: usize = N> {
    /// The residual `R(u)`.
    pub r: [f64; M],
    /// The Jacobian `dR/du` (rows by equation) when it was asked for.
    pub jac: Option<[[f64; N]; M]>,
    /// What the domain computed along with the residual.
    pub point: P,
}

/// A system of `M` equations in `N` unknowns (square by default) for [`newton`],
/// [`gauss_newton`] and [`projection`].
pub trait NewtonSystem<const N: usize, const M: usize = N> {
    /// What an evaluation carries besides the residual.
    type Point;
    /// The error of an evaluation.
    type Error;

    /// `R(u)`, with `dR/du` if `jacobian` is set (a system may return it anyway).
    ///
    /// # Errors
    /// Whatever keeps the system from being evaluated at `u`; at a trial point such an
    /// error only rejects the step.
    fn eval(
        &self,
        u: &[f64; N],
        jacobian: bool,
    ) -> Result<Evaluation<N, Self::Point, M>, Self::Error>;

    /// Whether a trial point may be evaluated at all (e.g. within a radius); a trial outside
    /// is halved towards the current point without an evaluation.
    fn admissible(&self, _u: &[f64; N]) -> bool {
        true
    }

    /// Whether the step from the point `old` to `new` moved what the domain computes by too
    /// little to matter: the iteration ends there as [`Termination::Converged`] (default:
    /// never; convergence by the residual's tolerance only).
    fn settled(&self, _old: &Self::Point, _new: &Self::Point) -> bool {
        false
    }

    /// The residual's scale at a point: every residual bound of the policy and the guards
    /// (`tol`, `noise_floor`, [`Stall::floor`], [`SmallStep::check`], `predict_below`) is
    /// relative to it (default 1: absolute bounds).
    fn scale(&self, _point: &Self::Point) -> f64 {
        1.0
    }
}

/// Why [`newton`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The residual norm reached the tolerance (or the system's points settled,
    /// [`NewtonSystem::settled`]).
    Converged,
    /// The iteration failed above the tolerance but within the noise floor.
    NoiseFloor,
    /// The Jacobian is singular (or not finite) at the iterate.
    Singular,
    /// No step (halved as allowed) reduced the residual, or a Broyden step contracted it too
    /// little.
    NoDescent,
    /// The step budget ran out.
    MaxIterations,
    /// The residual stopped falling ([`Safeguards::stall`]).
    Stalled,
    /// The last step's trial is returned unevaluated, predicted to converge
    /// ([`Safeguards::predict_below`], [`SmallStep::check`] `None`).
    Predicted,
}

impl Termination {
    /// Whether the answer is a solution (converged, within the noise floor, or predicted to
    /// converge).
    pub fn is_solution(&self) -> bool {
        matches!(
            self,
            Termination::Converged | Termination::NoiseFloor | Termination::Predicted
        )
    }
}

/// The answer of [`newton`]: the last iterate (the best: every accepted step lowers the
/// residual) with its evaluation.
#[derive(Clone, Debug)]
pub struct NewtonAnswer<const N: usize, P, const M: usize = N> {
    /// The iterate.
    pub u: [f64; N],
    /// Its residual.
    pub r: [f64; M],
    /// The residual's Euclidean norm.
    pub norm: f64,
    /// The Jacobian: at `u` if evaluated there, else the last one used.
    pub jac: [[f64; N]; M],
    /// The system's point at `u`.
    pub point: P,
    /// Steps taken.
    pub iterations: usize,
    /// The last step taken, `u - u_previous` as intended (before the rounding of the
    /// addition); zero before the first.
    pub step: [f64; N],
    /// Why the iteration stopped.
    pub termination: Termination,
}

/// Euclidean norm.
pub(super) fn norm<const N: usize>(v: &[f64; N]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// `ans` evaluated again at its point (with the Jacobian if `jacobian`): its residual, norm,
/// point and, where one came, Jacobian replaced by that evaluation's; whether one came.
pub(super) fn evaluate_again<const N: usize, const M: usize, S: NewtonSystem<N, M>>(
    sys: &S,
    ans: &mut NewtonAnswer<N, S::Point, M>,
    jacobian: bool,
) -> Result<bool, S::Error> {
    let e = sys.eval(&ans.u, jacobian)?;
    ans.r = e.r;
    ans.norm = norm(&e.r);
    ans.point = e.point;
    Ok(e.jac.map(|j| ans.jac = j).is_some())
}
