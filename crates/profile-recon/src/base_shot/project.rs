//! The projection of a noisy row onto the observables consistent with one of its
//! hypotheses: the most likely true observables, by Gauss-Newton steps of a constrained
//! least-squares problem in the noise metric ([`project`], on
//! [`bvp_solvers::newton::projection`]).

use super::context::{RowCtx, PROJECT_MIN};
use super::evaluate::evaluate;
use super::hypotheses::Hypothesis;
use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use bvp_solvers::newton::{
    projection, Evaluation, JacobianUpdate, NewtonPolicy, NewtonSystem, Termination,
};
use std::cell::{Cell, RefCell};

/// Gauss-Newton steps of [`project`] at most.
const PROJECT_STEPS: usize = 4;

/// The consistency condition `r = 0` of a hypothesis as a function of the observables
/// `(Ax, Ay, MA, phi0)` of a row (one equation, four unknowns): each evaluation a new
/// integration from the base at the moved observables ([`evaluate`]), followed to the
/// hypothesis nearest to the last one. Its points have settled when the hypothesis' point
/// moved by at most `1e-3 max(shift, PROJECT_MIN)`.
struct Consistency<'c, 'a> {
    ctx: &'c RowCtx<'a>,
    row: &'c ObservableRow,
    /// The hypothesis at the measured observables (evaluated already).
    h0: &'c Hypothesis,
    /// Whether the measured observables were asked for (the first evaluation).
    started: Cell<bool>,
    /// The hypothesis followed: that of the last evaluation (full steps: every evaluated
    /// trial is taken).
    current: Cell<Hypothesis>,
    /// Integrations spent.
    evals: Cell<usize>,
    /// An error of [`evaluate`] (it ends the projection).
    error: RefCell<Option<ReconError>>,
}

/// Why a trial of [`Consistency`] has no value: the hypothesis was lost, or [`evaluate`]
/// failed (kept in [`Consistency::error`]).
#[derive(Clone, Copy, Debug)]
struct Lost;

impl NewtonSystem<4, 1> for Consistency<'_, '_> {
    type Point = Hypothesis;
    type Error = Lost;

    fn eval(
        &self,
        u: &[f64; 4],
        _jacobian: bool,
    ) -> std::result::Result<Evaluation<4, Hypothesis, 1>, Lost> {
        let h = if self.started.replace(true) {
            let trial = ObservableRow {
                ax: u[0],
                ay: u[1],
                ma: u[2],
                phi0: u[3],
                ..*self.row
            };
            let e = evaluate(self.ctx, &trial).map_err(|e| {
                *self.error.borrow_mut() = Some(e);
                Lost
            })?;
            self.evals.set(self.evals.get() + e.evaluations);
            // (a projected hypothesis is a simple root or phase A, like `h0`)
            let hn = *self.current.get().nearest_in(&e.hyps).ok_or(Lost)?;
            self.current.set(hn);
            hn
        } else {
            *self.h0
        };
        Ok(Evaluation {
            r: [h.r],
            jac: Some([h.dr]),
            point: h,
        })
    }

    fn settled(&self, old: &Hypothesis, new: &Hypothesis) -> bool {
        let moved = (new.x - old.x).hypot(new.y - old.y);
        moved <= 1e-3 * new.shift.max(PROJECT_MIN)
    }
}

/// The most likely true observables of a noisy row under hypothesis `h`: the nearest (in the
/// noise metric of `ctx.scales`) to the measured ones on which the consistency condition
/// `r = 0` holds, by Gauss-Newton steps of the constrained least-squares problem (each a new
/// integration from the base at the moved observables, [`evaluate`]):
/// `obs' = meas - W dr (r + dr . (meas - obs)) / (dr W dr)` with `W = diag(scales^2)`
/// ([`projection`]: full steps, at most [`PROJECT_STEPS`], until the point settles).
/// Returns `h` with the point, `s1`, `f`, `psi` and the error estimate of the projected
/// observables (the consistency residual and `z` stay the measured row's), or `None` if the
/// hypothesis is lost on the way, or the condition does not depend on the observables (then
/// the linear projection stands).
pub(crate) fn project(
    ctx: &RowCtx<'_>,
    row: &ObservableRow,
    h0: &Hypothesis,
) -> Result<(Option<Hypothesis>, usize)> {
    let sys = Consistency {
        ctx,
        row,
        h0,
        started: Cell::new(false),
        current: Cell::new(*h0),
        evals: Cell::new(0),
        error: RefCell::new(None),
    };
    let meas = [row.ax, row.ay, row.ma, row.phi0];
    let w: [f64; 4] = std::array::from_fn(|j| ctx.scales.0[j] * ctx.scales.0[j]);
    let policy = NewtonPolicy {
        // converged when the point settles (the condition's own residual is noise-sized)
        tol: 0.0,
        max_iter: PROJECT_STEPS,
        halvings: 0,
        // every evaluation brings its gradient
        update: JacobianUpdate::Reevaluate {
            keep_below: f64::INFINITY,
        },
        jacobian_at_solution: false,
        noise_floor: 0.0,
    };
    let out = projection(&sys, meas, &w, &policy);
    if let Some(e) = sys.error.take() {
        return Err(e);
    }
    let evals = sys.evals.get();
    let h = match out {
        Ok(a)
            if matches!(
                a.termination,
                Termination::Converged | Termination::MaxIterations
            ) =>
        {
            a.point
        }
        _ => return Ok((None, evals)),
    };
    Ok((
        Some(Hypothesis {
            residual: h0.residual,
            z: h0.z,
            r: h0.r,
            dr: h0.dr,
            shift: h0.shift,
            ..h
        }),
        evals,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base_shot::evaluate::tests::G2Rows;

    #[test]
    fn a_noisy_row_is_projected_onto_its_consistent_observables() {
        // a contact row of a simulated sweep with its Ay moved by noise
        let g2 = G2Rows::new(12);
        let (truth, rows, scales, ctx) = (&g2.truth, &g2.rows, &g2.scales, g2.ctx());
        let k = truth.points.iter().position(|p| p.f > 1e-3).unwrap();
        let mut row = rows[k];
        row.ay += 1e-5 * scales.0[1];
        let e = evaluate(&ctx, &row).unwrap();
        let h0 = e.chosen(1e-5).unwrap();
        assert!(h0.shift > PROJECT_MIN);
        let (h, evals) = project(&ctx, &row, h0).unwrap();
        let h = h.expect("projected");
        assert!(evals >= 2, "{evals}");
        // the measured row's residual is kept
        assert_eq!((h.r, h.z), (h0.r, h0.z));
        // the Gauss-Newton iteration written out (the loop `project` had before it ran on
        // bvp_solvers::newton): the same point up to round-off
        let meas = [row.ax, row.ay, row.ma, row.phi0];
        let w: Vec<f64> = (0..4).map(|j| scales.0[j] * scales.0[j]).collect();
        let (mut obs, mut hr) = (meas, *h0);
        for _ in 0..PROJECT_STEPS {
            let sdr: f64 = (0..4).map(|j| w[j] * hr.dr[j] * hr.dr[j]).sum();
            let num = hr.r + (0..4).map(|j| hr.dr[j] * (meas[j] - obs[j])).sum::<f64>();
            let next: [f64; 4] = std::array::from_fn(|j| meas[j] - w[j] * hr.dr[j] * num / sdr);
            let trial = ObservableRow {
                ax: next[0],
                ay: next[1],
                ma: next[2],
                phi0: next[3],
                ..row
            };
            let hn = *hr
                .nearest_in(&evaluate(&ctx, &trial).unwrap().hyps)
                .unwrap();
            let moved = (hn.x - hr.x).hypot(hn.y - hr.y);
            (obs, hr) = (next, hn);
            if moved <= 1e-3 * hr.shift.max(PROJECT_MIN) {
                break;
            }
        }
        assert!((h.x - hr.x).abs() < 1e-13 && (h.y - hr.y).abs() < 1e-13);
        assert!((h.s1 - hr.s1).abs() < 1e-12 && (h.f - hr.f).abs() < 1e-12);
        // the nonlinear correction of the linear projection is of second order
        let moved = (h.x - h0.x).hypot(h.y - h0.y);
        assert!(moved < 0.1 * h0.shift, "{moved} vs {}", h0.shift);
    }
}
