//! Streaming reconstruction of a frictional log: rows arrive one at a time and each contact
//! row's [`FrictionalPoint`] is returned as soon as it is known, as the frictionless
//! [`Streamer`] does (whose judge decides which rows are before contact, and whose flow,
//! given or fixed by the first free row, the rows are fitted under).
//!
//! What a row gives on its own is the batch's: the point `(x, y)`, `s1`, the phase, and in
//! phase B the force split along the whisker's tangent (`fn`, `ft`, `psi`), the same
//! numbers as [`reconstruct_frictional`](super::reconstruct_frictional) (one integration
//! from the base and its central differences, row by row). What needs the other rows is
//! causal: a tip contact's tangent is read from the contour traced by the points so far
//! (the batch reads it from all of them), and a row's slip state from its predecessor only.
//! The noise scales are the largest magnitudes seen so far (the batch's: over the whole log),
//! so the error estimates of early rows are those of a smaller scale.
//!
//! [`FrictionalStreamer::finish`] gives the batch's answer over every row received: the
//! sensitivities rescaled to the final noise scales (they are linear in them), the tangents
//! read from the whole contour, the slip states from both neighbours, and mu identified with
//! its standard error (or the given mu's violations).

use super::{fit_row, frictional_points, mu_of, FrictionalPoint, MuEstimate, RowFit, MU_MAX};
use crate::common::{KnownFlow, NoiseScales, ReconSettings};
use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use crate::result::ReconPoint;
use crate::stream::{Streamer, STREAM_NOISE};
use beam_model::Whisker;
use bvp_solvers::integrator::Dop853;

/// An incremental frictional reconstruction (module docs).
pub struct FrictionalStreamer {
    inner: Option<Streamer>,
    whisker: Whisker,
    known: KnownFlow,
    settings: ReconSettings,
    mu: Option<f64>,
    level: f64,
    integrator: Dop853,
    /// Largest magnitudes of the columns so far.
    scales: [f64; 4],
    /// Every row received.
    rows: Vec<ObservableRow>,
    /// The fitted contact rows, with the noise scales they were fitted at.
    fits: Vec<(RowFit, [f64; 4])>,
}

/// The end of a frictional stream ([`FrictionalStreamer::finish`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionalStreamEnd {
    /// Points of rows still held at the end (the flow never fixed by a free row), in the
    /// order of the rows.
    pub held: Vec<FrictionalPoint>,
    /// The batch's points over every contact row received, in the order of the rows.
    pub points: Vec<FrictionalPoint>,
    /// mu identified from the sliding rows (None when given or without a sliding row).
    pub mu: Option<MuEstimate>,
    /// Rows that break a given mu (0 without one).
    pub violations: usize,
}

impl FrictionalStreamer {
    /// A stream for `whisker`; `known` fixes q and/or alpha, `settings.noise` the noise level
    /// (else [`STREAM_NOISE`]), `mu` the friction coefficient (None: identified at the end).
    ///
    /// # Errors
    /// [`ReconError::InvalidParameter`] for a `mu` outside `[0, MU_MAX]` and as
    /// [`Streamer::new`].
    pub fn new(
        whisker: &Whisker,
        known: KnownFlow,
        settings: &ReconSettings,
        mu: Option<f64>,
    ) -> Result<Self> {
        if let Some(m) = mu {
            if !(0.0..=MU_MAX).contains(&m) {
                return Err(ReconError::InvalidParameter {
                    name: "mu",
                    value: m,
                    reason: "the friction coefficient must lie in [0, 10]",
                });
            }
        }
        // the phases of a frictional log are not tangency-consistent: no consistency check
        let settings = ReconSettings {
            consistency_tol: None,
            ..*settings
        };
        Ok(FrictionalStreamer {
            inner: Some(Streamer::new(whisker, known, &settings)?),
            whisker: *whisker,
            known,
            settings,
            mu,
            level: settings.noise.unwrap_or(STREAM_NOISE),
            integrator: Dop853::new(settings.tol, settings.tol).with_dense(true),
            scales: [0.0; 4],
            rows: Vec::new(),
            fits: Vec::new(),
        })
    }

    /// Takes the next row; returns the points that became known (none, this row's, or the
    /// held rows' once the flow is fixed), in the order of the rows.
    ///
    /// # Errors
    /// As [`Streamer::push`]; [`ReconError::InconsistentRow`] for a contact row with no
    /// contact hypothesis at all.
    pub fn push(&mut self, row: ObservableRow) -> Result<Vec<FrictionalPoint>> {
        let Some(inner) = self.inner.as_mut() else {
            return Ok(Vec::new());
        };
        let decided = inner.push(row)?;
        self.rows.push(row);
        for (k, v) in [row.ax, row.ay, row.ma, row.phi0].into_iter().enumerate() {
            self.scales[k] = self.scales[k].max(v.abs());
        }
        self.fit(&decided)
    }

    /// Fits the decided rows under the stream's flow; their points over the fits so far.
    fn fit(&mut self, decided: &[ReconPoint]) -> Result<Vec<FrictionalPoint>> {
        let Some(flow) = self.inner.as_ref().and_then(Streamer::flow) else {
            return Ok(Vec::new());
        };
        if decided.is_empty() {
            return Ok(Vec::new());
        }
        let scales = NoiseScales(self.scales);
        let flow_sd = crate::judge::flow_sd(&self.known, self.level, &scales, 1);
        for p in decided {
            let fit = fit_row(
                &self.whisker,
                flow,
                p.row,
                &self.rows[p.row],
                &scales,
                self.level,
                flow_sd,
                &self.integrator,
            )?;
            self.fits.push((fit, self.scales));
        }
        let fits: Vec<RowFit> = self.fits.iter().map(|(f, _)| *f).collect();
        Ok(frictional_points(&self.rows, &fits, self.level, None)
            .into_iter()
            .filter(|q| decided.iter().any(|p| p.row == q.row))
            .collect())
    }

    /// Ends the stream: rows still held (the flow never fixed by a free row) reconstructed
    /// as a batch log, and the batch's answer over every contact row (module docs).
    ///
    /// # Errors
    /// As [`Streamer::finish`] and [`reconstruct_frictional`](super::reconstruct_frictional)
    /// on the held rows.
    pub fn finish(mut self) -> Result<FrictionalStreamEnd> {
        let mut held = Vec::new();
        if let Some(inner) = self.inner.take() {
            if inner.flow().is_none() && self.rows.len() >= 2 {
                // no free row fixed the flow: the held rows as a batch log
                let rec = super::reconstruct_frictional(
                    &self.whisker,
                    &self.rows,
                    self.known,
                    &self.settings,
                    self.mu,
                )?;
                return Ok(FrictionalStreamEnd {
                    held: rec.points.clone(),
                    points: rec.points,
                    mu: rec.mu,
                    violations: rec.violations,
                });
            }
            held = inner.finish()?;
        }
        let mut out = self.fit(&held)?;
        out.sort_by_key(|p| p.row);
        // the batch's sensitivities: rescaled to the final noise scales
        // (the flow's deviations are the level times the scales of Ax, Ay: rescaled too)
        let mut fits: Vec<RowFit> = self
            .fits
            .iter()
            .map(|(f, at)| {
                let mut f = *f;
                for (j, (&now, &then)) in self.scales.iter().zip(at).enumerate() {
                    let ratio = if then > 0.0 { now / then } else { 0.0 };
                    for k in 0..6 {
                        f.jac[k][j] *= ratio;
                        if j < 2 {
                            f.jflow[k][j] *= ratio;
                        }
                    }
                }
                f
            })
            .collect();
        fits.sort_by_key(|f| f.row);
        let mut points = frictional_points(&self.rows, &fits, self.level, None);
        points.sort_by_key(|p| p.row);
        let (mu, violations) = mu_of(&points, self.mu);
        Ok(FrictionalStreamEnd {
            held: out,
            points,
            mu,
            violations,
        })
    }
}
