//! What a reconstruction returns: the identification of the flow and the pre-contact rows,
//! one reconstructed point per contact row, and with an accuracy asked for the report of
//! every point's error estimate (the workspace's one [`AccuracyReport`], shared with
//! `contact_sim`'s sweeps).
//!
//! A module of its own, below every method: the results depend on no step of the pipeline
//! that fills them (before, `common::Reconstruction` held `accuracy::ReconAccuracy` while
//! `accuracy` imported `common`: one import circle, issue 35; `scripts/import_cycles.py`).
//! Row numbers are the crate's one convention ([`common`](crate::common)).

use beam_model::{AccuracyReport, FluidLoad};
use contact_sim::Phase;
use serde::{Deserialize, Serialize};

/// The identified flow and the pre-contact part of the log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Identification {
    /// Fluid load q [6.1] (given or identified).
    pub q: f64,
    /// Flow angle alpha (rad) [6.1] (given or identified).
    pub alpha: f64,
    /// Relative noise level used (given, or estimated from the log).
    pub noise: f64,
    /// Whether [`Identification::noise`] was estimated from the log.
    pub noise_estimated: bool,
    /// 0-based indices of the pre-contact rows (the free whisker under the flow).
    pub pre_contact: Vec<usize>,
    /// 0-based index of the first contact row in the input order (`rows.len()` if none).
    pub first_contact_row: usize,
    /// Model check: the largest `|m(1)|` of the free-whisker integration over the
    /// pre-contact rows (`MA`, `phi0` against the free solution; small when the whisker
    /// parameters are right), NaN without pre-contact rows.
    pub model_mismatch: f64,
    /// Free tip `(x1 - x0, y1, phi1)` under the flow: where the first tip contact will happen
    /// (thesis 6.1), NaN without pre-contact rows.
    pub free_tip: (f64, f64, f64),
}

impl Identification {
    /// The identified flow as a load.
    pub fn flow(&self) -> FluidLoad {
        FluidLoad {
            q: self.q,
            alpha: self.alpha,
        }
    }
}

/// One reconstructed contour point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReconPoint {
    /// 0-based index of the input row (the crate's one row convention, module docs).
    pub row: usize,
    /// The row's base position, copied exactly.
    pub x0: f64,
    /// Reconstructed contact point x.
    pub x: f64,
    /// Reconstructed contact point y.
    pub y: f64,
    /// Contact arc length.
    pub s1: f64,
    /// Contact force.
    pub f: f64,
    /// Contour angle at the contact point.
    pub psi: f64,
    /// Decided phase.
    pub phase: Phase,
    /// Consistency residual of the chosen hypothesis (A: `|m(1)|` [6.6]; B:
    /// `|phi(s1) - psi|`; thesis: the residual norm of [6.5-6.9]).
    pub residual: f64,
    /// Error estimate (one standard deviation) of the contact point `(x, y)`: the noise level
    /// propagated through the row's Jacobian `d(x, y)/d(Ax, Ay, MA, phi0)` (accurate); the
    /// FDM level of the residual for `thesis` (its points are biased by `O(h^2)`).
    pub sigma: f64,
    /// Other phase hypotheses (A, or another root of the phase-B moment condition) that are
    /// consistent within the noise too: `> 0` means the row is ambiguous at this noise level.
    pub alternatives: usize,
    /// Integrations (accurate) or solver iterations (thesis) spent on the row.
    pub evaluations: usize,
}

/// A reconstructed contour.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reconstruction {
    /// The identification (flow given or identified, pre-contact rows, noise level).
    pub identification: Identification,
    /// Whether q was given rather than identified.
    pub q_given: bool,
    /// Whether alpha was given rather than identified.
    pub alpha_given: bool,
    /// One point per contact row, in the order of the input rows.
    pub points: Vec<ReconPoint>,
    /// With an accuracy asked for ([`reconstruct_to`](crate::reconstruct_to)): the accuracy
    /// and every point's error estimate (`estimates[k]` that of `points[k]`).
    #[serde(default)]
    pub accuracy: Option<AccuracyReport>,
}
