//! The input of the inverse problem: the base observables `(x0, Ax, Ay, MA, phi0)` per row,
//! the only quantities a sensor (or an animal) measures (thesis ch. 5-6).

use crate::error::{ReconError, Result};
use serde::{Deserialize, Serialize};

/// One row of an observables log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObservableRow {
    /// Base position.
    pub x0: f64,
    /// Horizontal base reaction.
    pub ax: f64,
    /// Vertical base reaction.
    pub ay: f64,
    /// Base moment reaction.
    pub ma: f64,
    /// Base angle.
    pub phi0: f64,
}

impl ObservableRow {
    /// Checks that every value is finite, naming the row (0-based index, the crate's row
    /// convention) and the column otherwise.
    pub fn validate(&self, row: usize) -> Result<()> {
        for (column, value) in [
            ("x0", self.x0),
            ("Ax", self.ax),
            ("Ay", self.ay),
            ("MA", self.ma),
            ("phi0", self.phi0),
        ] {
            if !value.is_finite() {
                return Err(ReconError::NonFinite { row, column, value });
            }
        }
        Ok(())
    }
}

/// The observables of a simulated sweep (hidden values such as f, s1 and the contact point
/// are dropped: reconstruction never sees them).
pub fn from_sweep(sweep: &contact_sim::SweepResult) -> Vec<ObservableRow> {
    sweep
        .points
        .iter()
        .map(|p| ObservableRow {
            x0: p.x0,
            ax: p.ax,
            ay: p.ay,
            ma: p.ma,
            phi0: p.phi0,
        })
        .collect()
}
