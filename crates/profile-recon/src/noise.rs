//! Sensor noise: reconstruction from observables with added Gaussian noise (seeded), and
//! the study of the reconstruction error against the noise level.

use crate::common::{contour_error, ReconSettings};
use crate::error::Result;
use crate::observables::ObservableRow;
use crate::reconstruct::reconstruct;
use beam_model::Whisker;
use contact_sim::Profile;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// Adds zero-mean Gaussian noise to `Ax, Ay, MA, phi0` of every row: the standard deviation
/// of each column is `level` times the column's largest magnitude (a sensor's full-scale
/// relative noise). `x0`, the drive position, stays exact. Deterministic for a given seed.
pub fn add_noise(rows: &[ObservableRow], level: f64, seed: u64) -> Vec<ObservableRow> {
    let scale = |f: fn(&ObservableRow) -> f64| rows.iter().map(|r| f(r).abs()).fold(0.0, f64::max);
    let sd = [
        level * scale(|r| r.ax),
        level * scale(|r| r.ay),
        level * scale(|r| r.ma),
        level * scale(|r| r.phi0),
    ];
    let mut rng = StdRng::seed_from_u64(seed);
    let unit = Normal::new(0.0, 1.0).unwrap_or_else(|_| unreachable!("unit normal is valid"));
    rows.iter()
        .map(|r| ObservableRow {
            x0: r.x0,
            ax: r.ax + sd[0] * unit.sample(&mut rng),
            ay: r.ay + sd[1] * unit.sample(&mut rng),
            ma: r.ma + sd[2] * unit.sample(&mut rng),
            phi0: r.phi0 + sd[3] * unit.sample(&mut rng),
        })
        .collect()
}

/// Reconstruction quality at one noise level.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct NoiseResult {
    /// Relative noise level.
    pub level: f64,
    /// Identified q minus the true q.
    pub q_error: f64,
    /// Largest contour error e [6.11].
    pub max_error: f64,
    /// Median contour error.
    pub median_error: f64,
    /// Reconstructed points.
    pub points: usize,
    /// Largest consistency residual.
    pub max_residual: f64,
}

/// Reconstructs noisy copies of `rows` at each level (never failing on inconsistency: the
/// residuals are reported; the noise level is estimated from each log, not told) and measures the contour error against `profile`.
pub fn noise_study(
    whisker: &Whisker,
    rows: &[ObservableRow],
    q_true: f64,
    profile: &Profile,
    levels: &[f64],
    seed: u64,
) -> Result<Vec<NoiseResult>> {
    let settings = ReconSettings {
        consistency_tol: None,
        ..ReconSettings::default()
    };
    levels
        .iter()
        .map(|&level| {
            let noisy = add_noise(rows, level, seed);
            let rec = reconstruct(whisker, &noisy, None, &settings)?;
            let mut e = contour_error(&rec.points, profile);
            e.retain(|v| v.is_finite());
            e.sort_by(f64::total_cmp);
            Ok(NoiseResult {
                level,
                q_error: rec.identification.q - q_true,
                max_error: e.last().copied().unwrap_or(f64::NAN),
                median_error: e.get(e.len() / 2).copied().unwrap_or(f64::NAN),
                points: rec.points.len(),
                max_residual: rec.points.iter().map(|p| p.residual).fold(0.0, f64::max),
            })
        })
        .collect()
}
