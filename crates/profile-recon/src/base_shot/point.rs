//! The reconstructed point of an evaluated row: the chosen hypothesis, projected onto the
//! consistent observables where the noise moves it, with its error estimate (the noise
//! level, the identified flow's uncertainty and the row's ambiguity).

use super::context::{RowCtx, PROJECT_MIN};
use super::evaluate::evaluate;
use super::hypotheses::{Hypothesis, RowEval};
use super::project::project;
use crate::common::free_flow;
use crate::error::Result;
use crate::observables::ObservableRow;
use crate::result::ReconPoint;
use contact_sim::Phase;

/// A row of the log at the relative noise level of its point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowAt<'a> {
    /// 0-based index of the row (the crate's row convention).
    pub i: usize,
    /// The row.
    pub row: &'a ObservableRow,
    /// Relative noise level.
    pub level: f64,
}

impl RowEval {
    /// The reconstructed point of row `i` at relative noise `level`, from the linear
    /// projection of the chosen hypothesis (no further integration).
    pub fn point(&self, i: usize, row: &ObservableRow, level: f64) -> Option<ReconPoint> {
        let b = self.chosen(level)?;
        Some(self.make_point(RowAt { i, row, level }, b, b, (0, 0.0)))
    }

    /// As [`RowEval::point`], with the chosen hypothesis projected to the consistent
    /// observables by [`project`] where its linear projection moves the point by more than
    /// [`PROJECT_MIN`] (noisy logs); the error estimate then also carries the uncertainty of
    /// an identified flow, `flow_sd` = standard deviations of `(q cos alpha, q sin alpha)`
    /// (each perturbation one more evaluation of the row).
    pub(crate) fn projected_point(
        &self,
        at: RowAt<'_>,
        ctx: &RowCtx<'_>,
        flow_sd: [f64; 2],
    ) -> Result<Option<ReconPoint>> {
        let Some(b) = self.chosen(at.level) else {
            return Ok(None);
        };
        if b.shift <= PROJECT_MIN {
            return Ok(Some(self.make_point(at, b, b, (0, 0.0))));
        }
        let (p, evals) = project(ctx, at.row, b)?;
        let (flow_var, flow_evals) = self.flow_variance(at.row, ctx, flow_sd, b)?;
        Ok(Some(self.make_point(
            at,
            b,
            &p.unwrap_or(*b),
            (evals + flow_evals, flow_var),
        )))
    }

    /// The flow's own uncertainty at hypothesis `b`: the squared moves of its point under the
    /// flow moved by one standard deviation `flow_sd` in each component of
    /// `(q cos alpha, q sin alpha)`, and the integrations spent.
    fn flow_variance(
        &self,
        row: &ObservableRow,
        ctx: &RowCtx<'_>,
        flow_sd: [f64; 2],
        b: &Hypothesis,
    ) -> Result<(f64, usize)> {
        let (sa, ca) = ctx.flow.alpha.sin_cos();
        let (qc, qs) = (ctx.flow.q * ca, ctx.flow.q * sa);
        let (mut flow_var, mut evals) = (0.0, 0);
        for (k, sd) in flow_sd.iter().enumerate() {
            if *sd <= 0.0 {
                continue;
            }
            let (c, s) = if k == 0 { (qc + sd, qs) } else { (qc, qs + sd) };
            let moved = RowCtx {
                flow: free_flow(-c, s),
                ..*ctx
            };
            let e = evaluate(&moved, row)?;
            evals += e.evaluations;
            flow_var += match b.nearest_in(&e.hyps) {
                Some(h) => (h.x - b.x).powi(2) + (h.y - b.y).powi(2),
                // the hypothesis does not survive the flow's uncertainty: the row's
                // point is as uncertain as its spread of hypotheses says
                None => self.ambiguity(b, f64::INFINITY).powi(2),
            };
        }
        Ok((flow_var, evals))
    }

    /// The point of hypothesis `b` (its values from `v`, its projection), with `extra`
    /// integrations spent on it and the flow's variance of it: `(extra, flow_var)`.
    fn make_point(
        &self,
        at: RowAt<'_>,
        b: &Hypothesis,
        v: &Hypothesis,
        (extra, flow_var): (usize, f64),
    ) -> ReconPoint {
        let level = at.level;
        ReconPoint {
            row: at.i,
            x0: at.row.x0,
            x: v.x,
            y: v.y,
            s1: v.s1,
            f: v.f,
            psi: v.psi,
            phase: b.phase,
            residual: b.residual,
            // an inconsistent row implies its own noise level z; an ambiguous row is known to
            // within the spread of the hypotheses that fit it
            sigma: v
                .sigma(level.max(b.z))
                .hypot(flow_var.sqrt())
                .max(self.ambiguity(b, level))
                .max(if b.phase == Phase::A {
                    self.tip_ambiguity(level)
                } else {
                    0.0
                }),
            alternatives: self.alternatives(b, level),
            evaluations: self.evaluations + extra,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::hypotheses::tests::a_and_b;
    use super::*;

    #[test]
    fn an_exact_row_gives_the_chosen_hypothesis_with_its_spread() {
        let row = ObservableRow {
            x0: 0.25,
            ax: -1.0,
            ay: 0.5,
            ma: 0.1,
            phi0: 1.5,
        };
        // A and B agree to 1e-4; B is the better determined; level 1e-3
        let e = a_and_b(0.9, 0.5001);
        let p = e.point(7, &row, 1e-3).unwrap();
        assert_eq!(
            (p.row, p.x0, p.phase, p.alternatives),
            (7, 0.25, Phase::B, 1)
        );
        assert_eq!((p.x, p.s1, p.evaluations), (0.5001, 0.9, 1));
        // sigma: z = 4e-3 > level, so 4e-3 * 0.5 = 2e-3, above the ambiguity 1e-4
        assert!((p.sigma - 2e-3).abs() < 1e-15, "{}", p.sigma);
    }
}
