//! The constants of method `accurate` and the context of a row's evaluation ([`RowCtx`]),
//! shared by its files (re-exported at [`base_shot`](super)).

use crate::common::NoiseScales;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Dop853;

/// Sub-intervals per integration step scanned for sign changes of `m`.
pub const SAMPLES: usize = 3;
/// Winding of `phi` away from `phi0` (rad) beyond which the integration stops: no physical
/// contact lies beyond (this keeps a thin tip under a wrong hypothesis from spiralling).
pub const MAX_WINDING: f64 = 12.0;
/// Number of standard deviations within which a hypothesis counts as consistent.
pub const K_SIGMA: f64 = 6.0;
/// Arcs back from the tip at which a phase-A row is checked for a phase-B look-alike:
/// `TIP_FIRST * TIP_RATIO^k`, `k < TIP_GRID`, from 1e-5 to 0.5 of the whisker (and the
/// zeros of the tangency residual between them).
pub const TIP_GRID: usize = 16;
/// Linear projection moves larger than this (whisker lengths) are iterated to the manifold of
/// consistent observables (`project`); exact logs move by ~1e-12 and are left as they are.
pub const PROJECT_MIN: f64 = 1e-9;

/// What the evaluation of a row needs besides the row itself: the whisker, the flow, the
/// noise scales of the log's columns and the integrator of the base integration.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowCtx<'a> {
    /// The whisker.
    pub whisker: &'a Whisker,
    /// The flow `(q, alpha)` [6.1].
    pub flow: FluidLoad,
    /// Noise scales of the columns `Ax, Ay, MA, phi0`.
    pub scales: &'a NoiseScales,
    /// Integrator of the base integration (its tolerance is the method's).
    pub integrator: &'a Dop853,
}
