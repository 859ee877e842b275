//! Sensor noise: reconstruction from observables with added Gaussian noise (seeded), and
//! the study of the reconstruction error against the noise level.

use crate::common::{contour_error, NoiseScales, ReconSettings};
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
    let sd = NoiseScales::of(rows).0.map(|s| level * s);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` rows with the columns `(Ax, Ay, MA, phi0) = (2, -1, 0.5, 0)` (phi0 zero: a
    /// rigid support's).
    fn rows(n: usize) -> Vec<ObservableRow> {
        (0..n)
            .map(|i| ObservableRow {
                x0: i as f64,
                ax: 2.0,
                ay: -1.0,
                ma: 0.5,
                phi0: 0.0,
            })
            .collect()
    }

    #[test]
    fn noise_has_the_full_scale_deviation_per_column() {
        let clean = rows(4000);
        let noisy = add_noise(&clean, 1e-2, 7);
        assert_eq!(noisy, add_noise(&clean, 1e-2, 7), "seeded");
        assert_ne!(noisy, add_noise(&clean, 1e-2, 8));
        let col = |f: fn(&ObservableRow) -> f64| -> (f64, f64) {
            let d: Vec<f64> = noisy.iter().zip(&clean).map(|(a, b)| f(a) - f(b)).collect();
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (d.len() - 1) as f64;
            (mean, var.sqrt())
        };
        // standard deviation 1e-2 times the column's largest magnitude (2, 1, 0.5); the
        // sample's within 5 % (its standard error is 1.1 %), the mean within 4 errors
        for (f, scale) in [
            ((|r| r.ax) as fn(&ObservableRow) -> f64, 2.0),
            (|r| r.ay, 1.0),
            (|r| r.ma, 0.5),
        ] {
            let (mean, sd) = col(f);
            let want = 1e-2 * scale;
            assert!((sd / want - 1.0).abs() < 0.05, "{sd} vs {want}");
            assert!(mean.abs() < 4.0 * want / 4000f64.sqrt(), "{mean}");
        }
        // the drive position and a zero column stay exact
        assert!(noisy
            .iter()
            .zip(&clean)
            .all(|(a, b)| a.x0 == b.x0 && a.phi0 == 0.0));
    }
}
