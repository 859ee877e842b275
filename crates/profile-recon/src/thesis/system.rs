//! The thesis's system of one row and one phase hypothesis: the five unknowns [6.3, 6.4],
//! the FDM solve of [3.25] on `[0, s1]` and the six residuals [6.5-6.9], solved by the trust
//! region of [`bvp_solvers::nonlinear`] with the stall rule ([`STALL_TRIALS`]); a solved
//! hypothesis and the conversion of a solution of one phase into a start of the other.

use crate::common::force_components;
use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use beam_model::equations::WhiskerFdmProblem;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::fdm::{BoundaryCondition, FdmOptions, FdmSolver};
use bvp_solvers::grid::UniformGrid;
use bvp_solvers::nonlinear::{self, NonlinearOptions};
use bvp_solvers::trust_region::{NonlinearSystem, TrustRegionOptions};
use bvp_solvers::BvpError;
use contact_sim::phase::contact_loads;
use contact_sim::Phase;
use std::cell::{Cell, RefCell};

/// FDM intervals on `[0, s1]` (the thesis's `h = 0.01` for `s1 = 1`).
pub const INTERVALS: usize = 100;
/// Trust-region iteration budget per row and phase.
const MAX_ITERS: u64 = 100;
/// Residual above the FDM level (`<= 1e-3` on the chapter-5 cases) that makes a hypothesis
/// suspect: the other phase is tried too and the smaller residual kept.
pub const SUSPECT: f64 = 1e-3;
/// Trial points without a relative improvement of [`IMPROVEMENT`] after which a least-squares
/// solve that cannot reach `ReconSettings::tol` ends at its best point.
pub const STALL_TRIALS: usize = 12;
/// Relative improvement of the residual norm that counts as progress.
pub const IMPROVEMENT: f64 = 1e-10;
/// Admissible range of the contact arc length during the iteration (phase B).
const S1_MIN: f64 = 0.02;

/// The model quantities of one FDM solve.
#[derive(Clone, Copy, Debug)]
pub(super) struct Fdm {
    kappa0: f64,
    kappa1: f64,
    x1: f64,
    y1: f64,
}

/// Best point of a trust-region run.
#[derive(Clone, Debug)]
pub(super) struct Track {
    best: f64,
    best_x: Vec<f64>,
    /// Trial points (residual evaluations outside the Jacobian) so far.
    trials: usize,
    /// Trial at which `best` last improved by a relative [`IMPROVEMENT`].
    trial_at_best: usize,
    /// FDM solution at the best point: the start of every FDM Newton solve, so that all
    /// evaluations follow one branch of the BVP (under large forces the Dirichlet problem has
    /// several solutions, and a warm start from the last trial point could switch branches and
    /// make the residuals discontinuous).
    reference: Vec<f64>,
    /// FDM solution of the last evaluation.
    last: Vec<f64>,
}

/// Rows of [6.5-6.9] for one observable row and one phase hypothesis.
pub(super) struct RowSystem<'a> {
    whisker: &'a Whisker,
    flow: FluidLoad,
    tol: f64,
    row: &'a ObservableRow,
    phase: Phase,
    track: RefCell<Track>,
    in_jacobian: Cell<bool>,
}

impl<'a> RowSystem<'a> {
    /// The system of one row and phase; `reference` is the FDM solution of the previous row
    /// (nodes at `s = i s1 / INTERVALS`), empty for a linear start.
    pub(super) fn new(
        whisker: &'a Whisker,
        (flow, tol): (FluidLoad, f64),
        row: &'a ObservableRow,
        phase: Phase,
        reference: Vec<f64>,
    ) -> Self {
        RowSystem {
            whisker,
            flow,
            tol,
            row,
            phase,
            track: RefCell::new(Track {
                best: f64::INFINITY,
                best_x: Vec::new(),
                trials: 0,
                trial_at_best: 0,
                reference,
                last: Vec::new(),
            }),
            in_jacobian: Cell::new(false),
        }
    }

    /// `(psi, f, s1, phi1)` of the unknowns `u` [6.3, 6.4].
    fn parts(&self, u: &[f64]) -> (f64, f64, f64, f64) {
        match self.phase {
            Phase::B => (u[2], u[3], u[4], u[2]),
            _ => (u[2], u[3], 1.0, u[4]),
        }
    }

    /// Largest admissible `s1` (the cone must keep a positive diameter).
    fn s1_max(&self) -> f64 {
        let t = 1.0 - self.whisker.theta;
        if t > 0.0 {
            (0.9 / t).min(1.5)
        } else {
            1.5
        }
    }

    /// The FDM solve of [3.25] on `[0, s1]` with `phi(0) = phi0`, `phi(s1) = phi1`.
    fn fdm(&self, psi: f64, f: f64, s1: f64, phi1: f64) -> Result<Fdm> {
        let grid = UniformGrid::new(0.0, s1, INTERVALS)?;
        let loads = contact_loads(self.flow, psi, f, s1);
        let problem = WhiskerFdmProblem::new(*self.whisker, loads, phi1);
        let phi0 = self.row.phi0;
        let guess: Vec<f64> = {
            let t = self.track.borrow();
            if t.reference.len() == grid.len() {
                t.reference.clone()
            } else {
                let n = INTERVALS as f64;
                (0..grid.len())
                    .map(|i| phi0 + (phi1 - phi0) * i as f64 / n)
                    .collect()
            }
        };
        let solver = FdmSolver::new(
            BoundaryCondition::Dirichlet(phi0),
            BoundaryCondition::Dirichlet(phi1),
        )
        .with_options(FdmOptions {
            tol: 1e-12,
            max_iter: 50,
            damping: 1.0,
        });
        let sol = solver.solve(&problem, &grid, &guess)?;
        let h = grid.h();
        let (mut x, mut y) = (self.row.x0, 0.0);
        for w in sol.y.windows(2) {
            x += 0.5 * h * (w[0].cos() + w[1].cos());
            y += 0.5 * h * (w[0].sin() + w[1].sin());
        }
        let kappa0 = sol.yp.first().copied().unwrap_or(f64::NAN);
        let kappa1 = sol.yp.last().copied().unwrap_or(f64::NAN);
        self.track.borrow_mut().last = sol.y;
        Ok(Fdm {
            kappa0,
            kappa1,
            x1: x,
            y1: y,
        })
    }

    /// The six residuals [6.5-6.9]; NaN (a rejected trial point) where the model cannot be
    /// evaluated (`s1` out of range, FDM failure).
    fn eval(&self, u: &[f64], r: &mut [f64]) {
        let (psi, f, s1, phi1) = self.parts(u);
        let w = self.whisker;
        let model = if (S1_MIN..=self.s1_max()).contains(&s1) && u.iter().all(|v| v.is_finite()) {
            self.fdm(psi, f, s1, phi1).ok()
        } else {
            None
        };
        let Some(m) = model else {
            r.iter_mut().for_each(|v| *v = f64::NAN);
            return;
        };
        let (sp, cp) = psi.sin_cos();
        r[0] = m.x1 - u[0]; // [6.5], x component
        r[1] = m.y1 - u[1]; // [6.5], y component
        r[2] = w.stiffness(s1) * (m.kappa1 - w.kappa0(s1)); // [6.6]
        r[3] = self.row.ma + w.stiffness(0.0) * (m.kappa0 - w.b); // [6.7]
                                                                  // the contact force (f sin psi, f cos psi) against the point force the base
                                                                  // reactions balance with the flow on [0, s1]
        let (fa, fb) = force_components(self.row, self.flow, s1);
        r[4] = f * sp - fa; // [6.8]
        r[5] = fb - f * cp; // [6.9]
    }

    /// Solves the row from `start` ([`nonlinear::solve`] with the trust region alone: the six
    /// residuals have a least-squares minimum at the FDM level, above any useful tolerance,
    /// where a Newton fast path could only fail, and its evaluations would move the FDM warm
    /// start and the stall count of [`Track`] that the trust region's run depends on).
    pub(super) fn run(self, start: &[f64]) -> Result<Solved> {
        let opts = NonlinearOptions {
            start: None,
            newton: None,
            trust_region: Some(TrustRegionOptions {
                tol: self.tol,
                max_iters: MAX_ITERS,
                initial_radius: 0.1,
                max_radius: 10.0,
            }),
        };
        let (u, residual, iterations) = match nonlinear::solve::<5, 6, _>(&self, start, &opts) {
            Ok(sol) => (sol.x, sol.residual_norm, sol.iterations),
            // The least-squares minimum above the tolerance (the FDM level), or a run stalled
            // on the way ([`STALL_TRIALS`]): the best point found.
            Err(ReconError::Bvp(BvpError::NoConvergence { .. }))
                if self.track.borrow().best.is_finite() =>
            {
                let t = self.track.borrow();
                (t.best_x.clone(), t.best, t.trial_at_best)
            }
            Err(e) => return Err(e),
        };
        Ok(Solved {
            phase: self.phase,
            u,
            residual,
            iterations,
            shape: self.track.into_inner().reference,
        })
    }
}

impl NonlinearSystem for RowSystem<'_> {
    type Error = ReconError;

    fn n_unknowns(&self) -> usize {
        5
    }

    fn n_residuals(&self) -> usize {
        6
    }

    /// The residuals [6.5-6.9]; after [`STALL_TRIALS`] trial points without progress the
    /// next trial point ends the run without an FDM solve: `NoConvergence` with the best
    /// residual, the error that [`RowSystem::run`] answers with the best point ([`Track`]).
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<()> {
        let trial = !self.in_jacobian.get();
        if trial {
            let mut t = self.track.borrow_mut();
            t.trials += 1;
            if t.trials - t.trial_at_best > STALL_TRIALS {
                return Err(BvpError::NoConvergence {
                    method: "trust region (stalled)",
                    iterations: t.trials,
                    residual: t.best,
                }
                .into());
            }
        }
        self.eval(x, r);
        let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut t = self.track.borrow_mut();
        if norm.is_finite() && norm < t.best {
            if trial && norm < t.best * (1.0 - IMPROVEMENT) {
                t.trial_at_best = t.trials;
            }
            t.best = norm;
            t.best_x = x.to_vec();
            t.reference = std::mem::take(&mut t.last);
        }
        Ok(())
    }

    /// Forward differences, as the default of the trait (marked so that the perturbed points
    /// do not count as trial points).
    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> Result<()> {
        const N: usize = 5;
        const M: usize = 6;
        self.in_jacobian.set(true);
        let mut r0 = [0.0; M];
        let mut r1 = [0.0; M];
        let mut xp = x.to_vec();
        let mut out = self.residual(x, &mut r0);
        let sq = f64::EPSILON.sqrt();
        for j in 0..N {
            if out.is_err() {
                break;
            }
            let h = sq * x[j].abs().max(1.0);
            xp[j] = x[j] + h;
            let hh = xp[j] - x[j];
            out = self.residual(&xp, &mut r1);
            xp[j] = x[j];
            for i in 0..M {
                jac[i * N + j] = (r1[i] - r0[i]) / hh;
            }
        }
        self.in_jacobian.set(false);
        out
    }
}

/// A solved hypothesis.
#[derive(Clone, Debug)]
pub(super) struct Solved {
    pub(super) phase: Phase,
    pub(super) u: Vec<f64>,
    pub(super) residual: f64,
    pub(super) iterations: usize,
    /// FDM solution at the point (warm start of the next row).
    pub(super) shape: Vec<f64>,
}

impl Solved {
    /// Whether the phase's conditions hold (A: `phi1 >= psi`; B: `s1 <= 1`) [6.2.2].
    fn valid(&self) -> bool {
        match self.phase {
            Phase::B => self.u[4] <= 1.0 + 1e-9,
            _ => self.u[4] >= self.u[2] - 1e-9,
        }
    }

    /// Acceptable without trying the other phase: valid and consistent to the FDM level.
    pub(super) fn good(&self) -> bool {
        self.valid() && self.residual <= SUSPECT
    }

    pub(super) fn s1(&self) -> f64 {
        if self.phase == Phase::B {
            self.u[4]
        } else {
            1.0
        }
    }
}

/// Start of the other phase from a solution of one: B from A with `s1` just below 1, A from B
/// with `phi1 = psi`.
pub(super) fn convert(u: &[f64], to: Phase) -> Vec<f64> {
    let mut v = u.to_vec();
    v[4] = match to {
        Phase::B => 1.0 - 1e-3,
        _ => u[2],
    };
    v
}

pub(super) fn other(phase: Phase) -> Phase {
    if phase == Phase::B {
        Phase::A
    } else {
        Phase::B
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phases_convert_into_each_other() {
        let u = [1.0, 2.0, 0.3, 4.0, 0.7];
        // B from A: s1 just below the tip; A from B: phi1 = psi
        assert_eq!(convert(&u, Phase::B), vec![1.0, 2.0, 0.3, 4.0, 1.0 - 1e-3]);
        assert_eq!(convert(&u, Phase::A), vec![1.0, 2.0, 0.3, 4.0, 0.3]);
        assert_eq!(other(Phase::A), Phase::B);
        assert_eq!(other(Phase::B), Phase::A);
    }
}
