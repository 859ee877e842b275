//! The thesis's reconstruction [6.5-6.10] (filled by the profile-recon work).

use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use crate::reconstruct::{ReconPoint, ReconSettings};
use beam_model::Whisker;

/// Reconstructs the contact rows `rows[first..]` by the thesis's method.
pub fn reconstruct_rows(
    _whisker: &Whisker,
    _q: f64,
    rows: &[ObservableRow],
    first: usize,
    _settings: &ReconSettings,
) -> Result<Vec<ReconPoint>> {
    Err(ReconError::TooFewRows {
        found: rows.len() - first,
        needed: usize::MAX,
        what: "the thesis method is not implemented yet",
    })
}
