//! Contour reconstruction from an observables log (thesis 6.2): identification of the flow
//! and the pre-contact rows ([`identify`](crate::identify())), then one contact point per
//! contact row by the chosen method ([`accurate`](crate::accurate) or
//! [`thesis`](crate::thesis)).
//!
//! With `consistency_tol` set, a contact row whose best residual exceeds both it and the
//! noise (`K_SIGMA` standard deviations at the GIVEN noise level, `ReconSettings::noise`, or
//! at [`NOISE_FLOOR`] without one: an estimated level cannot excuse a wrong model) is an
//! error naming the row; otherwise every row gives a point with its residual and error
//! estimate (at the given or estimated level).

use crate::accurate::{evaluate, K_SIGMA};
use crate::common::{KnownFlow, ReconMethod, ReconPoint, ReconSettings, Reconstruction};
use crate::error::{ReconError, Result};
use crate::identify::{identify_rows, NOISE_FLOOR};
use crate::observables::ObservableRow;
use beam_model::Whisker;
use bvp_solvers::integrator::Dop853;
use contact_sim::Phase;

/// Reconstructs the contour from an observables log with the flow angle identified (or 0
/// when q is given and the log has no pre-contact row); see [`reconstruct_with`].
pub fn reconstruct(
    whisker: &Whisker,
    rows: &[ObservableRow],
    q: Option<f64>,
    settings: &ReconSettings,
) -> Result<Reconstruction> {
    reconstruct_with(whisker, rows, KnownFlow { q, alpha: None }, settings)
}

/// Checks a point against `consistency_tol` (module docs).
fn check(p: &ReconPoint, row: &ObservableRow, z: f64, level: f64, tol: Option<f64>) -> Result<()> {
    let Some(tol) = tol else { return Ok(()) };
    // NaN z (no hypothesis) is not consistent
    let consistent = z <= K_SIGMA * level;
    if p.residual > tol && !consistent {
        return Err(ReconError::InconsistentRow {
            row: p.row,
            x0: row.x0,
            residual: p.residual,
            phase: if p.phase == Phase::A { 'A' } else { 'B' },
        });
    }
    Ok(())
}

/// Reconstructs the contour from an observables log: identifies the flow `(q, alpha)`
/// (unless known), the noise level and the pre-contact rows from the model [6.1], then one
/// contact point per contact row [6.5-6.9], each row on its own (accurate) or in order of
/// `x0` (thesis, whose phase rule [6.10] needs the neighbours). The points come in the order
/// of the input rows; `ReconPoint::row` is the 0-based input index.
///
/// # Errors
/// [`ReconError::NoPreContactRows`] when the flow must be identified and no row is the free
/// whisker; [`ReconError::NoContactRows`] when every row is; [`ReconError::InconsistentRow`]
/// (with `consistency_tol`) for a row beyond both the tolerance and the noise; input and
/// solver errors as [`identify`](crate::identify()).
pub fn reconstruct_with(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: KnownFlow,
    settings: &ReconSettings,
) -> Result<Reconstruction> {
    let ided = identify_rows(whisker, rows, known, settings)?;
    let id = ided.id;
    let contact: Vec<usize> = (0..rows.len())
        .filter(|i| id.pre_contact.binary_search(i).is_err())
        .collect();
    if contact.is_empty() {
        return Err(ReconError::NoContactRows { rows: rows.len() });
    }
    let level = id.noise;
    let integrator = Dop853::new(settings.tol, settings.tol);
    // an identified flow is the mean of the pre-contact rows' forces: its components carry
    // the noise of one row over the square root of their number
    let flow_sd = if known.q.is_some() && known.alpha.is_some() {
        [0.0; 2]
    } else {
        let n = (id.pre_contact.len().max(1) as f64).sqrt();
        [level * ided.scales.0[0] / n, level * ided.scales.0[1] / n]
    };
    let mut points = Vec::with_capacity(contact.len());
    match settings.method {
        ReconMethod::Accurate => {
            for &i in &contact {
                let e = &ided.evals[i];
                let Some(p) = e.projected_point(
                    i,
                    &rows[i],
                    level,
                    whisker,
                    id.flow(),
                    flow_sd,
                    &ided.scales,
                    &integrator,
                )?
                else {
                    return Err(ReconError::InconsistentRow {
                        row: i,
                        x0: rows[i].x0,
                        residual: f64::NAN,
                        phase: 'A',
                    });
                };
                let told = settings.noise.unwrap_or(NOISE_FLOOR);
                check(&p, &rows[i], e.best_z(), told, settings.consistency_tol)?;
                points.push(p);
            }
        }
        ReconMethod::Thesis => {
            // the thesis's rule [6.10] reads the rows in the order of the sweep
            let mut order = contact.clone();
            order.sort_by(|&a, &b| rows[a].x0.total_cmp(&rows[b].x0).then(a.cmp(&b)));
            let mut pts =
                crate::thesis::reconstruct_rows(whisker, id.flow(), rows, &order, settings)?;
            // error estimate: distance to the accurate point of the same row plus its own
            // (the accurate method at its own tolerance, whatever the trust region's)
            let integrator = Dop853::new(1e-12, 1e-12);
            for p in &mut pts {
                let e = evaluate(whisker, id.flow(), &rows[p.row], &ided.scales, &integrator)?;
                if let Some(a) = e.point(p.row, &rows[p.row], level) {
                    p.sigma = (p.x - a.x).hypot(p.y - a.y) + a.sigma;
                }
            }
            pts.sort_by_key(|p| p.row);
            points = pts;
        }
    }
    Ok(Reconstruction {
        identification: id,
        q_given: known.q.is_some(),
        alpha_given: known.alpha.is_some(),
        points,
    })
}
