//! The one per-row judge of method `accurate`, used by the identification, the batch
//! reconstruction and the stream alike: an evaluated row is pre-contact (the free whisker
//! under the flow within the noise [6.1]: no contact force in the balance [6.8, 6.9] at
//! `s1 = 1` and `m(1) = 0` [6.6]), or a contact row with its point, the point's statistics
//! (error estimate, alternatives, evaluations) and the check against
//! `ReconSettings::consistency_tol`.

use crate::base_shot::{RowAt, RowCtx, RowEval, K_SIGMA};
use crate::common::{KnownFlow, NoiseScales, ReconSettings, NOISE_FLOOR};
use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use crate::result::ReconPoint;
use contact_sim::Phase;

/// Whether an evaluated row is pre-contact at relative noise `level`: its phase-A contact
/// force [6.8, 6.9] and its phase-A residual `m(1)` [6.6] are both within [`K_SIGMA`]
/// standard deviations of zero.
pub(crate) fn is_pre_contact(e: &RowEval, level: f64) -> bool {
    let za = e.hyps.iter().find(|h| h.phase == Phase::A);
    e.f_z <= K_SIGMA * level && za.is_some_and(|h| h.z <= K_SIGMA * level)
}

/// Standard deviations of the flow's components `(q cos alpha, q sin alpha)`: zero for a
/// flow given in full, else the noise of one row's `(Ax, Ay)` at `level` over the square root
/// of the number of pre-contact rows the flow is the mean of (`pre_rows`, at least 1).
pub(crate) fn flow_sd(
    known: &KnownFlow,
    level: f64,
    scales: &NoiseScales,
    pre_rows: usize,
) -> [f64; 2] {
    if known.q.is_some() && known.alpha.is_some() {
        [0.0; 2]
    } else {
        let n = (pre_rows.max(1) as f64).sqrt();
        [level * scales.0[0] / n, level * scales.0[1] / n]
    }
}

/// How the rows of one log are judged.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Judge<'a> {
    /// Whisker, flow, noise scales and integrator of the projections.
    pub ctx: RowCtx<'a>,
    /// Relative noise level of the log (given or estimated).
    pub level: f64,
    /// Standard deviations of the flow's components ([`flow_sd`]).
    pub flow_sd: [f64; 2],
    /// The settings (`noise` and `consistency_tol` for the check).
    pub settings: &'a ReconSettings,
}

impl Judge<'_> {
    /// Row `i` evaluated as `e` under the flow: `None` if it is pre-contact, else its
    /// projected point ([`RowEval::projected_point`]).
    ///
    /// # Errors
    /// [`ReconError::InconsistentRow`] without any hypothesis, or (with `consistency_tol`) when
    /// the point's residual exceeds the tolerance and the row is not consistent at the GIVEN
    /// noise level ([`NOISE_FLOOR`] without one: an estimated level cannot excuse a wrong
    /// model); solver errors of the projection.
    pub fn judge(&self, i: usize, row: &ObservableRow, e: &RowEval) -> Result<Option<ReconPoint>> {
        if is_pre_contact(e, self.level) {
            return Ok(None);
        }
        let at = RowAt {
            i,
            row,
            level: self.level,
        };
        let p =
            e.projected_point(at, &self.ctx, self.flow_sd)?
                .ok_or(ReconError::InconsistentRow {
                    row: i,
                    x0: row.x0,
                    residual: f64::NAN,
                    phase: Phase::A,
                })?;
        check(&p, row, e.best_z(), self.settings)?;
        Ok(Some(p))
    }
}

/// Checks a point against `settings.consistency_tol` (see [`Judge::judge`]); `z` is the row's
/// best `z` (NaN, no hypothesis, is not consistent).
fn check(p: &ReconPoint, row: &ObservableRow, z: f64, settings: &ReconSettings) -> Result<()> {
    let Some(tol) = settings.consistency_tol else {
        return Ok(());
    };
    let told = settings.noise.unwrap_or(NOISE_FLOOR);
    let consistent = z <= K_SIGMA * told;
    if p.residual > tol && !consistent {
        return Err(ReconError::InconsistentRow {
            row: p.row,
            x0: row.x0,
            residual: p.residual,
            phase: p.phase,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base_shot::evaluate;
    use crate::base_shot::tests::g2_sweep;
    use bvp_solvers::integrator::Dop853;

    #[test]
    fn flow_sd_is_the_mean_of_the_pre_contact_rows() {
        let scales = NoiseScales([2.0, 3.0, 1.0, 1.0]);
        let known = KnownFlow::default();
        // 4 rows: sd / 2
        assert_eq!(flow_sd(&known, 1e-3, &scales, 4), [1e-3, 1.5e-3]);
        // a stream's flow is one row's
        assert_eq!(flow_sd(&known, 1e-3, &scales, 1), [2e-3, 3e-3]);
        assert_eq!(flow_sd(&known, 1e-3, &scales, 0), [2e-3, 3e-3]);
        let given = KnownFlow {
            q: Some(1.0),
            alpha: Some(0.0),
        };
        assert_eq!(flow_sd(&given, 1e-3, &scales, 4), [0.0; 2]);
    }

    /// The judge of a sweep's rows under the true flow.
    fn judged(
        noise: Option<f64>,
        consistency_tol: Option<f64>,
        tamper: f64,
    ) -> Vec<Result<Option<ReconPoint>>> {
        let (w, flow, truth) = g2_sweep(10);
        let mut rows = crate::observables::from_sweep(&truth);
        for r in &mut rows {
            r.ma += tamper;
        }
        let scales = NoiseScales::of(&rows);
        let integrator = Dop853::new(1e-12, 1e-12);
        let settings = ReconSettings {
            noise,
            consistency_tol,
            ..Default::default()
        };
        let judge = Judge {
            ctx: RowCtx {
                whisker: &w,
                flow,
                scales: &scales,
                integrator: &integrator,
            },
            level: noise.unwrap_or(NOISE_FLOOR),
            flow_sd: [0.0; 2],
            settings: &settings,
        };
        rows.iter()
            .enumerate()
            .map(|(i, r)| {
                let e = evaluate(&judge.ctx, r)?;
                if tamper == 0.0 {
                    assert_eq!(is_pre_contact(&e, judge.level), truth.points[i].f <= 1e-9);
                }
                judge.judge(i, r, &e)
            })
            .collect()
    }

    #[test]
    fn a_sweep_is_judged_row_by_row() {
        let (_, _, truth) = g2_sweep(10);
        let out = judged(None, Some(1e-6), 0.0);
        for (res, p) in out.into_iter().zip(&truth.points) {
            match res.unwrap() {
                None => assert!(p.f <= 1e-9),
                Some(q) => {
                    assert!((q.x - p.xc).abs() < 1e-9 && (q.y - p.yc).abs() < 1e-9);
                    assert_eq!(q.phase, p.phase);
                    assert!(q.sigma < 1e-8, "{}", q.sigma);
                }
            }
        }
    }

    #[test]
    fn a_wrong_moment_fails_the_consistency_check_naming_its_row() {
        // MA off by 1e-3: far beyond the exact-log floor and the tolerance
        let out = judged(None, Some(1e-6), 1e-3);
        let first = out.into_iter().find_map(|r| r.err()).unwrap();
        assert!(
            matches!(first, ReconError::InconsistentRow { .. }),
            "{first:?}"
        );
        // without a tolerance every row gets its point
        assert!(judged(None, None, 1e-3).into_iter().all(|r| r.is_ok()));
    }
}
