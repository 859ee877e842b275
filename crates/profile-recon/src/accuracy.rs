//! Accuracy on demand for a reconstruction ([`reconstruct_to`]): the points at the
//! integrator tolerance the accuracy asked for needs, and each point's a-posteriori error
//! estimate.
//!
//! Method `accurate` only: a contact point is one integration from the base (its error is
//! the integrator's, measured at most ~5 times its tolerance on seeded sweeps), where the
//! FDM model of `thesis` cannot get below ~1e-5.
//!
//! The rows are reconstructed as [`reconstruct_with`] does, with the integrator at
//! [`integration_tol`] (1e-10 from `tol = 1e-6` up: a looser one is costlier); then every contact row is evaluated again under the identified flow
//! at an integration [`ESTIMATE_FACTOR`] times looser and judged at the same noise level.
//! The estimate of a point is twice the distance between the two points (the looser
//! integration's error is many times the point's), and never below the looser tolerance
//! (where both integrations happen to agree). A point whose estimate exceeds the accuracy
//! asked for is an error naming its row.

use crate::base_shot::{evaluate, RowCtx};
use crate::common::{KnownFlow, ReconMethod, ReconSettings};
use crate::error::{ReconError, Result};
use crate::judge::{flow_sd, Judge};
use crate::observables::ObservableRow;
#[cfg(doc)]
use crate::reconstruct::reconstruct_with;
use crate::result::Reconstruction;
use beam_model::AccuracyReport;
use beam_model::Whisker;
use bvp_solvers::integrator::Dop853;

/// Smallest accuracy a reconstruction can be asked for.
pub const ACCURACY_MIN: f64 = 1e-12;

/// Largest accuracy a reconstruction can be asked for.
pub const ACCURACY_MAX: f64 = 1e-2;

/// How much looser than the points' the integration of their estimates is.
pub const ESTIMATE_FACTOR: f64 = 100.0;

/// The estimate over the distance of a point and its looser twin.
pub const ESTIMATE_MARGIN: f64 = 2.0;

/// The integrator tolerance of the points for the accuracy `tol`: `tol / 1e4` (a point's
/// error is up to ~5 times its integrator tolerance, and its estimate, from an integration
/// 100 times looser, twice that error, must stay below `tol`), within [1e-13, 1e-10].
/// Looser is not cheaper: measured with callgrind on the g1 sweep's log (default 38.3 M
/// instructions), points at 1e-12 with their twins at 1e-10 cost 53.8 M, at 1e-10 (twins at
/// 1e-8) 46.9 M, at 1e-8 (twins at 1e-6) 74.3 M, the integration's error raising the
/// estimated noise level and with it the work of the ambiguity checks (and at 1e-8 an exact
/// log's residuals reach the default consistency tolerance, 1e-6).
pub fn integration_tol(tol: f64) -> f64 {
    (tol / 1e4).clamp(1e-13, 1e-10)
}

/// The accuracy of a reconstruction run by [`reconstruct_to`]: the workspace's one report
/// ([`AccuracyReport`]), its `integration_tol` the points' ([`integration_tol`]), one estimate
/// per point of `Reconstruction::points`. The name the report had before it was shared with
/// `contact_sim` (whose sweeps report the same shape).
pub type ReconAccuracy = AccuracyReport;

/// [`reconstruct_with`] at the accuracy `tol` (absolute error of every contact point, in
/// [1e-12, 1e-2]): the points at [`integration_tol`]`(tol)` (`settings.tol` is not used),
/// each with its error estimate (module docs) in `Reconstruction::accuracy`.
///
/// # Errors
/// [`ReconError::InvalidParameter`] (`tol`) for an accuracy out of range or the method
/// `thesis`; [`ReconError::AccuracyNotMet`] naming the row of the worst point when its
/// estimate exceeds `tol`; the errors of [`reconstruct_with`].
pub fn reconstruct_to(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: KnownFlow,
    settings: &ReconSettings,
    tol: f64,
) -> Result<Reconstruction> {
    let bad = |reason| {
        Err(ReconError::InvalidParameter {
            name: "tol",
            value: tol,
            reason,
        })
    };
    if !(ACCURACY_MIN..=ACCURACY_MAX).contains(&tol) {
        return bad("the accuracy asked for must lie in [1e-12, 1e-2]");
    }
    if settings.method != ReconMethod::Accurate {
        return bad("an accuracy is asked of the method accurate only (thesis stays near 1e-5)");
    }
    let tight = ReconSettings {
        tol: integration_tol(tol),
        ..*settings
    };
    let (mut rec, ided) = crate::reconstruct::reconstruct_identified(whisker, rows, known, &tight)?;
    let loose_tol = tight.tol * ESTIMATE_FACTOR;
    let integrator = Dop853::new(loose_tol, loose_tol);
    let id = &rec.identification;
    let loose = ReconSettings {
        consistency_tol: None,
        ..tight
    };
    let judge = Judge {
        ctx: RowCtx {
            whisker,
            flow: id.flow(),
            scales: &ided.scales,
            integrator: &integrator,
        },
        level: id.noise,
        flow_sd: flow_sd(&known, id.noise, &ided.scales, id.pre_contact.len()),
        settings: &loose,
    };
    let estimates: Vec<f64> = rec
        .points
        .iter()
        .map(|p| {
            let twin = evaluate(&judge.ctx, &rows[p.row])
                .and_then(|e| judge.judge(p.row, &rows[p.row], &e));
            match twin {
                // (at a phase switch both phases give the same point)
                Ok(Some(q)) => (ESTIMATE_MARGIN * (q.x - p.x).hypot(q.y - p.y)).max(loose_tol),
                _ => f64::INFINITY,
            }
        })
        .collect();
    let acc = AccuracyReport {
        tol,
        integration_tol: tight.tol,
        estimates,
    };
    if let Some((k, estimate)) = acc.worst() {
        if estimate > tol || estimate.is_nan() {
            let row = rec.points[k].row;
            return Err(ReconError::AccuracyNotMet {
                row,
                x0: rows[row].x0,
                estimate,
                tol,
            });
        }
    }
    rec.accuracy = Some(acc);
    Ok(rec)
}
