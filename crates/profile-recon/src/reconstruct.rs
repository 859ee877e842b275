//! Contour reconstruction from an observables log (thesis 6.2): identification of the flow
//! and the pre-contact rows ([`identify`](crate::identify())), then one contact point per
//! contact row by the chosen method (`accurate`: [`base_shot`](crate::base_shot), or
//! [`thesis`](crate::thesis)).
//!
//! With `consistency_tol` set, a contact row whose best residual exceeds both it and the
//! noise (`K_SIGMA` standard deviations at the GIVEN noise level, `ReconSettings::noise`, or
//! at [`NOISE_FLOOR`](crate::identify::NOISE_FLOOR) without one: an estimated level cannot
//! excuse a wrong model) is an error naming the row; otherwise every row gives a point with its residual and error
//! estimate (at the given or estimated level).

use crate::base_shot::{evaluate, RowCtx};
use crate::common::{KnownFlow, ReconMethod, ReconSettings};
use crate::error::{ReconError, Result};
use crate::identify::{identify_rows, Identified};
use crate::judge::{flow_sd, Judge};
use crate::observables::ObservableRow;
use crate::result::{ReconPoint, Reconstruction};
use beam_model::Whisker;
use bvp_solvers::integrator::Dop853;

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
    reconstruct_identified(whisker, rows, known, settings).map(|(rec, _)| rec)
}

/// [`reconstruct_with`], with the identification's evaluations and noise scales.
pub(crate) fn reconstruct_identified(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: KnownFlow,
    settings: &ReconSettings,
) -> Result<(Reconstruction, Identified)> {
    let ided = identify_rows(whisker, rows, known, settings)?;
    let id = &ided.id;
    let contact: Vec<usize> = (0..rows.len())
        .filter(|i| id.pre_contact.binary_search(i).is_err())
        .collect();
    if contact.is_empty() {
        return Err(ReconError::NoContactRows { rows: rows.len() });
    }
    let points = match settings.method {
        ReconMethod::Accurate => accurate_points(whisker, rows, &known, settings, &ided)?,
        ReconMethod::Thesis => thesis_points(whisker, rows, contact, settings, &ided)?,
    };
    let rec = Reconstruction {
        identification: ided.id.clone(),
        q_given: known.q.is_some(),
        alpha_given: known.alpha.is_some(),
        points,
        accuracy: None,
    };
    Ok((rec, ided))
}

/// Method `accurate`: every row judged on its own ([`Judge::judge`]; the pre-contact rows
/// give no point).
fn accurate_points(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: &KnownFlow,
    settings: &ReconSettings,
    ided: &Identified,
) -> Result<Vec<ReconPoint>> {
    let id = &ided.id;
    let level = id.noise;
    let integrator = Dop853::new(settings.tol, settings.tol);
    let judge = Judge {
        ctx: RowCtx {
            whisker,
            flow: id.flow(),
            scales: &ided.scales,
            integrator: &integrator,
        },
        level,
        // an identified flow is the mean of the pre-contact rows' forces: its components
        // carry the noise of one row over the square root of their number
        flow_sd: flow_sd(known, level, &ided.scales, id.pre_contact.len()),
        settings,
    };
    // each row on its own ([`crate::rows_par`])
    let judged =
        crate::rows_par::map_rows(rows.len(), |i| judge.judge(i, &rows[i], &ided.evals[i]))?;
    Ok(judged.into_iter().flatten().collect())
}

/// Method `thesis` on the contact rows (in the order of `x0`, as its rule [6.10] reads them),
/// each point's error estimate its distance to the accurate point of the same row plus that
/// point's own.
fn thesis_points(
    whisker: &Whisker,
    rows: &[ObservableRow],
    mut order: Vec<usize>,
    settings: &ReconSettings,
    ided: &Identified,
) -> Result<Vec<ReconPoint>> {
    let flow = ided.id.flow();
    // the thesis's rule [6.10] reads the rows in the order of the sweep
    order.sort_by(|&a, &b| rows[a].x0.total_cmp(&rows[b].x0).then(a.cmp(&b)));
    let mut pts = crate::thesis::reconstruct_rows(whisker, flow, rows, &order, settings)?;
    // (the accurate method at its own tolerance, whatever the trust region's)
    let integrator = Dop853::new(1e-12, 1e-12);
    let ctx = RowCtx {
        whisker,
        flow,
        scales: &ided.scales,
        integrator: &integrator,
    };
    for p in &mut pts {
        let e = evaluate(&ctx, &rows[p.row])?;
        if let Some(a) = e.point(p.row, &rows[p.row], ided.id.noise) {
            p.sigma = (p.x - a.x).hypot(p.y - a.y) + a.sigma;
        }
    }
    pts.sort_by_key(|p| p.row);
    Ok(pts)
}
