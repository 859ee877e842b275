//! The report of an accuracy asked for: the tolerance, the integration that answers it and
//! one a-posteriori error estimate per item of a result.
//!
//! One shape for every caller that solves a list of problems to an accuracy asked for and
//! estimates each one's error by an independent second solution (the same one at an
//! integration `ESTIMATE_FACTOR` times looser, the estimate `ESTIMATE_MARGIN` times the
//! difference): the rows of a sweep (`contact_sim::accuracy`, one estimate per row of the
//! sweep's log) and the points of a reconstruction (`profile_recon::accuracy`, one estimate
//! per reconstructed contact point). A single solve reports its own estimate in
//! [`SolveStats`](crate::SolveStats) instead.

use serde::{Deserialize, Serialize};

/// An accuracy asked for and the error estimate of each item of the result that meets it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AccuracyReport {
    /// The accuracy asked for (absolute, dimensionless): every estimate is at most this.
    pub tol: f64,
    /// The integrator tolerance the items were solved at (derived from `tol` by the caller:
    /// a sweep's contact rows, a reconstruction's points).
    #[serde(alias = "row_integration_tol")]
    pub integration_tol: f64,
    /// The a-posteriori error estimate of each item, in the order of the result's items
    /// (absolute, dimensionless; `inf` where the second solution failed).
    pub estimates: Vec<f64>,
}

impl AccuracyReport {
    /// The worst item: its 0-based index in the result's items and its estimate (`None`
    /// without items). A NaN estimate is the worst: an estimate that failed is never
    /// mistaken for a small one.
    pub fn worst(&self) -> Option<(usize, f64)> {
        self.estimates.iter().copied().enumerate().reduce(|a, b| {
            if b.1 > a.1 || b.1.is_nan() {
                b
            } else {
                a
            }
        })
    }

    /// Whether every estimate is at most the accuracy asked for (true without items; false
    /// for a NaN estimate).
    pub fn met(&self) -> bool {
        self.worst().is_none_or(|(_, e)| e <= self.tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(estimates: Vec<f64>) -> AccuracyReport {
        AccuracyReport {
            tol: 1e-6,
            integration_tol: 1e-10,
            estimates,
        }
    }

    #[test]
    fn the_worst_item_is_the_largest_estimate_or_a_nan() {
        assert_eq!(report(vec![]).worst(), None);
        assert!(report(vec![]).met());
        let r = report(vec![1e-9, 3e-8, 2e-8]);
        assert_eq!(r.worst(), Some((1, 3e-8)));
        assert!(r.met());
        // the first of equal maxima
        assert_eq!(report(vec![2e-8, 2e-8]).worst(), Some((0, 2e-8)));
        // a NaN anywhere is the worst, and not met
        let (k, e) = report(vec![1e-9, f64::NAN, 5e-7]).worst().unwrap();
        assert!(k == 1 && e.is_nan());
        assert!(!report(vec![1e-9, f64::NAN, 5e-7]).met());
        // an estimate over the accuracy asked for, or infinite, is not met
        assert!(!report(vec![1e-9, 2e-6]).met());
        assert!(!report(vec![f64::INFINITY]).met());
    }

    #[test]
    fn a_report_reads_back_the_sweep_s_former_field_name() {
        let json = r#"{"tol":1e-6,"row_integration_tol":1e-10,"estimates":[1e-9,2e-9]}"#;
        let r: AccuracyReport = serde_json::from_str(json).unwrap();
        assert_eq!(r, report(vec![1e-9, 2e-9]));
        let back: AccuracyReport =
            serde_json::from_str(&serde_json::to_string(&r).unwrap()).unwrap();
        assert_eq!(back, r);
    }
}
