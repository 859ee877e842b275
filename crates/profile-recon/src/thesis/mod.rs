//! The thesis's reconstruction (section 6.2, eqs. 6.3-6.10), faithfully: per contact row five
//! unknowns, solved by a trust region (`fsolve` in the thesis, the trust region of
//! [`bvp_solvers::nonlinear::solve`] here) around finite-difference solves of the
//! elastica [3.25] (the thesis's solver of Fig. 4.2), warm-started from the previous row.
//!
//! **Unknowns** [6.3, 6.4]: phase A (tip contact, `s1 = 1`): `(xc, yc, psi, f, phi1)`;
//! phase B (tangential contact, `phi1 = psi`): `(xc, yc, psi, f, s1)`.
//!
//! **Model evaluation.** For given `(psi, f, s1, phi1)` the BVP [3.25] on `[0, s1]` is solved
//! by central finite differences with Dirichlet conditions at both ends, `phi(0) = phi0` (the
//! observed base angle: the support model is not needed) and `phi(s1) = phi1`, under the
//! contact loads (DP force at `beta = pi/2 - psi`, flow `q` at `alpha` on `[0, s1]`). It
//! gives the curvatures `kappa0 = phi'(0)`, `kappa1 = phi'(s1)` and, by the trapezoidal rule,
//! the contact point `(x1, y1)`. The grid has 100 intervals on `[0, s1]` (`h = s1/100 <= 0.01`,
//! the thesis's `h = 0.01` for `s1 = 1`): a fixed count rather than `ceil(100 s1)` keeps the
//! residuals smooth in `s1`, which the finite-difference Jacobian of the trust region needs.
//!
//! **Residuals** (six, in five unknowns; a least-squares problem):
//! - [6.5] as two smooth components `x1 - xc`, `y1 - yc` (instead of the distance `d`, which is
//!   not differentiable at its zero);
//! - [6.6] `m1 = e(s1)^4 (kappa1 - A s1 - B) = 0`;
//! - [6.7] `MA + m(0) = 0` with `m(0) = kappa0 - B`;
//! - [6.8] `Ax + q s1 cos alpha + f sin psi = 0`;
//! - [6.9] `Ay - q s1 sin alpha - f cos psi = 0`.
//!
//! The exact model satisfies all six at the true contact, but the FDM one does so only up to
//! its `O(h^2)` discretisation error (both `phi0` and `MA` are imposed, one condition more than
//! a BVP takes): the least-squares minimum keeps a residual of about `1e-5..1e-4`. This is the
//! thesis's observation that "only a tolerance of 1e-4 is achievable". The trust region runs
//! with tolerance `1e-8`; when it cannot get there, the run is ended once [`STALL_TRIALS`]
//! trial points bring no progress (the next trial point stops it without an FDM solve) and
//! the best point found is the reconstruction, with its residual norm reported in
//! [`ReconPoint::residual`] and the trust-region iterations up to it in
//! [`ReconPoint::evaluations`].
//!
//! **Phase** [6.10]: the first contact phase from section 6.2.1 / Remark 6.3 (B when `Ax`
//! rises above `-q` at the first contact row, i.e. the flow acts on `s1 < 1` only, else A);
//! afterwards the phase switches for row `k + 1` when the slope of `Ay` against `x0` jumps,
//! `|dAy/dx0|_{k+1} - dAy/dx0|_k| > a_diff = 1`, evaluated from the observables ahead of the
//! step (one-sided slopes between successive contact rows). A kink between two rows shows in
//! two successive slope differences, so the test is skipped on the row right after a switch.
//! Each solution must also satisfy its phase's conditions (A: `phi1 >= psi`; B: `s1 <= 1`,
//! section 6.2.2); when it does not, or its residual is above the FDM level ([`SUSPECT`]), or
//! the solve fails, the row is solved again in the other phase, from the previous row's
//! solution, and a hypothesis that satisfies its condition at the FDM level is kept (otherwise
//! the smaller residual). The kept phase is the current phase of the next row. On the
//! chapter-5 cases the slope rule alone misplaces some switches (and with `theta < 1` fires
//! spuriously); the retry corrects them.
//!
//! Every FDM solve starts from the FDM solution at the best point so far (the previous row's at
//! the start of a row), which keeps the evaluations on one branch of the Dirichlet problem.

mod rows;
mod system;

use crate::common::ReconSettings;
#[cfg(doc)]
use crate::error::ReconError;
use crate::error::Result;
use crate::observables::ObservableRow;
use crate::result::ReconPoint;
use beam_model::{FluidLoad, Whisker};
use rows::{first_row, first_start, RowSolve, SlopeRule, Warm};

pub use rows::A_DIFF;
pub use system::{IMPROVEMENT, INTERVALS, STALL_TRIALS, SUSPECT};

/// Reconstructs the contact rows `rows[order[k]]` (`order`: 0-based indices sorted by `x0`,
/// the order of a sweep) by the thesis's method (module docs): five unknowns per row
/// [6.3, 6.4] from the six residuals of [6.5-6.9] by the trust region (tolerance
/// `settings.tol`) around FDM solves of [3.25], warm-started from the previous row, phases by
/// [6.10]. The flow `(q, alpha)` enters the loads and the force balance [6.8, 6.9].
///
/// The first row starts from force balance with `s1 = 1` [6.8, 6.9] and the free tip of the
/// whisker under the flow (thesis 6.1); if neither phase is consistent there, phase B is
/// restarted from a few `s1 < 1` with the contact point on the free whisker (a tangential first
/// contact far from the tip).
///
/// # Errors
/// - [`ReconError::TooFewRows`] without contact rows (`order` empty);
/// - [`ReconError::NonFinite`] for a non-finite observable;
/// - [`ReconError::Model`] if the free whisker cannot be solved;
/// - [`ReconError::InconsistentRow`] if neither phase can be solved at a row, or (with
///   `settings.consistency_tol`) the best residual of a row exceeds it;
/// - [`ReconError::Bvp`] for other solver failures.
pub fn reconstruct_rows(
    whisker: &Whisker,
    flow: FluidLoad,
    rows: &[ObservableRow],
    order: &[usize],
    settings: &ReconSettings,
) -> Result<Vec<ReconPoint>> {
    let first = first_row(rows, order)?;
    let (mut warm, free) = first_start(whisker, flow, &rows[first], settings)?;
    let mut phase = warm.phase;
    let mut rule = SlopeRule::default();
    let mut points = Vec::with_capacity(order.len());
    for (k, &i) in order.iter().enumerate() {
        // [6.10]: slope jump of Ay ahead of the step (contact rows only).
        phase = rule.phase_at(rows, order, k, phase);
        let solve = RowSolve {
            whisker,
            system: (flow, settings.tol),
            i,
            row: &rows[i],
        };
        let mut chosen = solve.solve(&warm, phase)?;
        if k == 0 && !chosen.good() {
            chosen = solve.restart(&warm, &free, chosen);
        }
        points.push(solve.point(&chosen, settings.consistency_tol)?);
        phase = chosen.phase;
        warm = Warm {
            u: chosen.u,
            phase: chosen.phase,
            shape: chosen.shape,
        };
    }
    Ok(points)
}
