//! The summary step of `vibrissa reconstruct`: the one-line text summary, the `--json`
//! object, and the counts they share (phases, rows without a contact point, row ranges).

use std::path::Path;

use contact_sim::Phase;
use profile_recon::{ReconMethod, ReconPoint, Reconstruction};

use crate::commands::json::json_number;
use crate::units::{Quantity, UnitSystem};

/// Number of phase-A and phase-B points.
pub fn phase_counts(points: &[ReconPoint]) -> (usize, usize) {
    let na = points.iter().filter(|p| p.phase == Phase::A).count();
    let nb = points.iter().filter(|p| p.phase == Phase::B).count();
    (na, nb)
}

/// The largest value (NaN if any value is NaN, 0 for none).
pub fn max_of(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m: f64, &v| {
        if v.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(v)
        }
    })
}
/// `" mm"` etc., or nothing for dimensionless values.
pub(crate) fn unit_suffix(units: &UnitSystem, q: Quantity) -> String {
    match units.unit(q) {
        "1" | "" => String::new(),
        u => format!(" {u}"),
    }
}

/// The one-line summary of a reconstruction of a log of `rows` rows, q in `units`; rows
/// numbered from 1 as in the log (row r on line r + 1).
pub fn summary_line(
    rec: &Reconstruction,
    method: ReconMethod,
    rows: usize,
    units: &UnitSystem,
) -> String {
    let (na, nb) = phase_counts(&rec.points);
    let qs = units.scale(Quantity::LineLoad);
    let qu = unit_suffix(units, Quantity::LineLoad);
    let q = match (rec.q_given, units.is_physical()) {
        (true, _) => format!("q = {}{qu} (given)", rec.identification.q * qs),
        (false, true) => format!("q = {:.10e}{qu} (identified)", rec.identification.q * qs),
        (false, false) => format!("q = {:.10}{qu} (identified)", rec.identification.q * qs),
    };
    let free = rows_without_points(&rec.points, rows);
    let with: Vec<usize> = rec.points.iter().map(|p| p.row).collect();
    format!(
        "{q}; {rows} rows: {} without contact force (the free whisker under the flow: before \
         contact, at a touch or release with f = 0; rows {}), {} contact points (rows {}; \
         {method} method), phases A {na} / B {nb}, max residual {:.2e}{}",
        free.len(),
        row_ranges(&free),
        rec.points.len(),
        row_ranges(&with),
        max_of(&rec.points.iter().map(|p| p.residual).collect::<Vec<_>>()),
        accuracy_note(rec),
        method = method.name(),
    )
}

/// `; worst point error estimate E (row r) for --tol T` for a reconstruction run with an
/// accuracy asked for; nothing otherwise. Rows numbered from 1 as in the log.
pub fn accuracy_note(rec: &Reconstruction) -> String {
    match rec
        .accuracy
        .as_ref()
        .and_then(|a| a.worst().map(|w| (a.tol, w)))
    {
        Some((tol, (k, e))) => format!(
            "; worst point error estimate {e:.2e} (row {}) for --tol {tol:e}",
            rec.points[k].row + 1
        ),
        None => String::new(),
    }
}

/// The 0-based rows of a log of `rows` rows that yield no contact point (the free whisker
/// under the flow: before contact, and a touch or release with f = 0).
pub fn rows_without_points(points: &[ReconPoint], rows: usize) -> Vec<usize> {
    let mut contact = vec![false; rows];
    for p in points {
        if let Some(c) = contact.get_mut(p.row) {
            *c = true;
        }
    }
    (0..rows).filter(|&i| !contact[i]).collect()
}

/// 0-based row indices as 1-based ranges, `1-11, 133` (`none` if empty).
pub fn row_ranges(rows: &[usize]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < rows.len() {
        let mut j = i;
        while j + 1 < rows.len() && rows[j + 1] == rows[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            format!("{}", rows[i] + 1)
        } else {
            format!("{}-{}", rows[i] + 1, rows[j] + 1)
        });
        i = j + 1;
    }
    if parts.is_empty() {
        "none".to_string()
    } else {
        parts.join(", ")
    }
}

/// The `--json` object of a reconstruction of a log of `rows` rows (q, the largest error
/// `max_error` if the contour is known, in `units`), written to `out`.
pub fn recon_json(
    rec: &Reconstruction,
    method: ReconMethod,
    rows: usize,
    units: &UnitSystem,
    max_error: Option<f64>,
    out: &Path,
) -> serde_json::Value {
    let (na, nb) = phase_counts(&rec.points);
    let max_residual = max_of(&rec.points.iter().map(|p| p.residual).collect::<Vec<_>>());
    let max_sigma = max_of(&rec.points.iter().map(|p| p.sigma).collect::<Vec<_>>());
    let mut v = serde_json::json!({
        "q": rec.identification.q * units.scale(Quantity::LineLoad),
        "q_dimensionless": rec.identification.q,
        "q_given": rec.q_given,
        "units": if units.is_physical() { "physical" } else { "dimensionless" },
        "alpha_deg": rec.identification.alpha.to_degrees(),
        "alpha_given": rec.alpha_given,
        "noise": json_number(rec.identification.noise),
        "noise_estimated": rec.identification.noise_estimated,
        "max_sigma": json_number(max_sigma),
        "points": rec.points.len(),
        "rows": rows,
        "first_contact_row": rec.identification.first_contact_row + 1,
        "rows_without_force": row_ranges(&rows_without_points(&rec.points, rows)),
        "method": method.name(),
        "max_residual": json_number(max_residual),
        "phases": {"A": na, "B": nb},
        "out": out.display().to_string(),
    });
    if let Some(e) = max_error {
        v["max_error"] = json_number(e * units.scale(Quantity::Length));
    }
    if let Some(acc) = &rec.accuracy {
        v["tol"] = json_number(acc.tol);
        // the contact rows are always the elastica's (no linear rung): spec/cli.md's
        // `model_used` of the accuracy asked for
        v["model_used"] = serde_json::Value::from(beam_model::ModelKind::Elastica.name());
        v["integration_tol"] = json_number(acc.integration_tol);
        if let Some((k, e)) = acc.worst() {
            v["max_estimate"] = json_number(e);
            v["max_estimate_row"] = serde_json::Value::from(rec.points[k].row + 1);
        }
    }
    if !rec.q_given {
        v["model_mismatch"] = json_number(rec.identification.model_mismatch);
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_and_ranges_are_numbered_from_one() {
        assert_eq!(row_ranges(&[]), "none");
        assert_eq!(row_ranges(&[0, 1, 2, 5, 7, 8]), "1-3, 6, 8-9");
        assert_eq!(max_of(&[]), 0.0);
        assert_eq!(max_of(&[1.0, 3.0, 2.0]), 3.0);
        assert!(max_of(&[1.0, f64::NAN]).is_nan());
        assert_eq!(
            unit_suffix(&UnitSystem::DIMENSIONLESS, Quantity::Length),
            ""
        );
    }
}
