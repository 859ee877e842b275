//! Fluid-load identification from the rows before contact (thesis 6.1, Table 6.1) and
//! detection of where contact starts, from the observables alone.
//!
//! Before contact the whisker carries the flow only, so every pre-contact row shows the same
//! observables with `Ax = -q`, `Ay = 0` [6.1]. Contact starts at the first row that departs
//! from them by more than the scatter of the leading rows allows.

use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use beam_model::{solve, Loads, Method, Scene, Whisker};
use serde::{Deserialize, Serialize};

/// The identified fluid load and the pre-contact part of the log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Identification {
    /// Identified fluid load q = -mean(Ax) over the pre-contact rows [6.1].
    pub q: f64,
    /// Index of the first contact row (= number of pre-contact rows).
    pub first_contact_row: usize,
    /// Threshold used to detect the contact start.
    pub threshold: f64,
    /// Model check: |MA_model - MA| and |phi0_model - phi0| of the whisker under the identified
    /// flow against the mean observed values (small when the whisker parameters are right).
    pub model_mismatch: f64,
    /// Free tip (x1 - x0, y1, phi1) under the identified flow: where the first tip contact
    /// will happen (thesis 6.1).
    pub free_tip: (f64, f64, f64),
}

/// Largest componentwise difference of the force/moment/angle observables of two rows.
fn distance(a: &ObservableRow, b: &ObservableRow) -> f64 {
    (a.ax - b.ax)
        .abs()
        .max((a.ay - b.ay).abs())
        .max((a.ma - b.ma).abs())
        .max((a.phi0 - b.phi0).abs())
}

/// Identifies q and the contact start. `noise_floor` is the smallest jump treated as contact
/// (e.g. 1e-9 for exact data); the detection threshold is the larger of it and 10 times the
/// largest scatter among the leading rows' successive differences.
pub fn identify(
    whisker: &Whisker,
    rows: &[ObservableRow],
    noise_floor: f64,
) -> Result<Identification> {
    whisker.validate()?;
    if rows.len() < 2 {
        return Err(ReconError::TooFewRows {
            found: rows.len(),
            needed: 2,
            what: "identification needs a pre-contact row and a contact row",
        });
    }
    for (i, r) in rows.iter().enumerate() {
        r.validate(i + 1)?;
    }
    // Noise scale: per column, the median of the absolute successive differences of the
    // leading rows (robust to one contact jump among them); the threshold is the larger of
    // the floor and 10 times the largest column scale.
    let lead = rows.len().min(7);
    let col = |f: fn(&ObservableRow) -> f64| {
        let mut d: Vec<f64> = rows[..lead]
            .windows(2)
            .map(|w| (f(&w[1]) - f(&w[0])).abs())
            .collect();
        d.sort_by(f64::total_cmp);
        d.get(d.len() / 2).copied().unwrap_or(0.0)
    };
    let scatter = col(|r| r.ax)
        .max(col(|r| r.ay))
        .max(col(|r| r.ma))
        .max(col(|r| r.phi0));
    let threshold = noise_floor.max(10.0 * scatter);
    // Before contact Ay = 0 [6.1]: a log whose first row has |Ay| above the noise starts in
    // contact.
    if rows[0].ay.abs() > threshold.max(1e-6) {
        return Err(ReconError::NoPreContactRows);
    }
    let mut start = rows.len();
    let mut mean = rows[0];
    for (i, r) in rows.iter().enumerate().skip(1) {
        if distance(r, &mean) > threshold {
            start = i;
            break;
        }
        let n = i as f64;
        mean = ObservableRow {
            x0: r.x0,
            ax: (mean.ax * n + r.ax) / (n + 1.0),
            ay: (mean.ay * n + r.ay) / (n + 1.0),
            ma: (mean.ma * n + r.ma) / (n + 1.0),
            phi0: (mean.phi0 * n + r.phi0) / (n + 1.0),
        };
    }
    if start == rows.len() {
        return Err(ReconError::NoContactRows { rows: rows.len() });
    }
    let q = -mean.ax;
    if q < -threshold.max(1e-12) {
        return Err(ReconError::InvalidParameter {
            name: "q",
            value: q,
            reason: "the pre-contact rows show Ax > 0, a flow towards -x, which the model excludes (alpha = 0)",
        });
    }
    let q = q.max(0.0);
    let free = solve(
        &Scene::new(*whisker, Loads::fluid(q, 0.0)),
        &Method::accurate(),
    )?;
    let model_mismatch = (free.base.ma - mean.ma)
        .abs()
        .max((free.base.phi0 - mean.phi0).abs());
    Ok(Identification {
        q,
        first_contact_row: start,
        threshold,
        model_mismatch,
        free_tip: (free.tip.x, free.tip.y, free.tip.phi),
    })
}
