//! Streaming reconstruction: rows arrive one at a time, as a sensor sends them, and each
//! contact row's point is returned as soon as it is known (method `accurate`, each row on its
//! own [6.5-6.9]).
//!
//! With the flow known (`q` and `alpha` given), every row is decided at once: pre-contact
//! (the free whisker under the flow within the noise [6.1]) or a contact point. Otherwise the
//! rows are held back until the first row that is the free whisker under its own flow
//! (`q = hypot(Ax, Ay)`, `alpha = atan2(Ay, -Ax)`, `m(1) = 0` within the noise) fixes the
//! flow; the held rows are then reconstructed and returned together. A row that is no
//! free whisker under its own flow is held whatever its judge says under that flow (no
//! consistent contact point there is no verdict: the flow is not that row's), so a log whose
//! contact rows all come before its free rows reads as the batch reads it. Later pre-contact rows
//! do not change the flow (the points already returned stay valid). At the end of the stream
//! ([`Streamer::finish`]) rows still held are reconstructed as a batch log. Without a given
//! flow the stream therefore depends on the order of the rows (a release row with a force at
//! the noise level, arriving first, would fix the flow); a sensor's stream starts free, and a
//! robot that knows its flow should give it.
//!
//! Rows of any base motion come with their pose ([`Streamer::push_posed`], [`crate::pose`]):
//! each is judged as it is and its point moved to the lab frame by its base's `y0`.
//!
//! The noise level is `ReconSettings::noise` ([`STREAM_NOISE`] if not given: a stream cannot
//! be estimated ahead); the noise scales of the columns are the largest magnitudes seen so
//! far.

use crate::base_shot::{evaluate, RowCtx};
use crate::common::{free_flow, KnownFlow, NoiseScales, ReconSettings, NOISE_FLOOR};
#[cfg(doc)]
use crate::error::ReconError;
use crate::error::Result;
use crate::identify::check_known;
use crate::judge::{flow_sd, Judge};
use crate::observables::ObservableRow;
use crate::pose::{in_base_frame, RowPose};
use crate::reconstruct::reconstruct_with;
use crate::result::ReconPoint;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Dop853;

/// Relative noise level of a stream when none is given: the exact-log floor of the batch
/// identification (a noisy sensor must say its level, `ReconSettings::noise`).
pub const STREAM_NOISE: f64 = NOISE_FLOOR;

/// An incremental reconstruction (module docs).
pub struct Streamer {
    whisker: Whisker,
    known: KnownFlow,
    settings: ReconSettings,
    level: f64,
    flow: Option<FluidLoad>,
    integrator: Dop853,
    scales: [f64; 4],
    /// Rows received (the next row's 0-based index).
    count: usize,
    /// Rows held back until the flow is known: (index, row).
    held: Vec<(usize, ObservableRow)>,
    /// The pose of every row received ([`Streamer::push_posed`]).
    poses: Vec<RowPose>,
}

impl Streamer {
    /// A stream for `whisker`; `known` fixes q and/or alpha, `settings.noise` the noise
    /// level (else [`STREAM_NOISE`]).
    ///
    /// # Errors
    /// [`ReconError::InvalidParameter`] / [`ReconError::Model`] for bad parameters.
    pub fn new(whisker: &Whisker, known: KnownFlow, settings: &ReconSettings) -> Result<Self> {
        whisker.validate()?;
        check_known(&known)?;
        let flow = match (known.q, known.alpha) {
            (Some(q), Some(alpha)) => Some(FluidLoad { q, alpha }),
            _ => None,
        };
        Ok(Streamer {
            whisker: *whisker,
            known,
            settings: *settings,
            level: settings.noise.unwrap_or(STREAM_NOISE),
            flow,
            integrator: Dop853::new(settings.tol, settings.tol).with_dense(true),
            scales: [0.0; 4],
            count: 0,
            held: Vec::new(),
            poses: Vec::new(),
        })
    }

    /// The flow, once known.
    pub fn flow(&self) -> Option<FluidLoad> {
        self.flow
    }

    /// Rows received so far.
    pub fn rows(&self) -> usize {
        self.count
    }

    /// Decides row `i` under `flow` with the batch's judge ([`Judge::judge`]): `None` if
    /// pre-contact, else its point. A flow not given is one row's own (the first free row of
    /// the stream): its uncertainty is that row's noise.
    fn decide(&self, flow: FluidLoad, i: usize, row: &ObservableRow) -> Result<Option<ReconPoint>> {
        let scales = NoiseScales(self.scales);
        let judge = Judge {
            ctx: RowCtx {
                whisker: &self.whisker,
                flow,
                scales: &scales,
                integrator: &self.integrator,
            },
            level: self.level,
            flow_sd: flow_sd(&self.known, self.level, &scales, 1),
            settings: &self.settings,
        };
        let e = evaluate(&judge.ctx, row)?;
        judge.judge(i, row, &e)
    }

    /// Takes the next row; returns the points that became known (none, this row's, or the
    /// held rows' once the flow is fixed), in the order of the rows.
    ///
    /// # Errors
    /// [`ReconError::NonFinite`] for a non-finite value; [`ReconError::InconsistentRow`] with
    /// `consistency_tol`; solver errors.
    pub fn push(&mut self, row: ObservableRow) -> Result<Vec<ReconPoint>> {
        self.push_posed(row, RowPose::TRANSLATE)
    }

    /// [`Streamer::push`] for a row of any base motion, with its pose `(y0, gamma)`
    /// ([`crate::pose`]): the row is judged as it is (its shape does not depend on the pose)
    /// and its point moved to the lab frame by `y0`.
    ///
    /// # Errors
    /// As [`Streamer::push`]; [`ReconError::NonFinite`] for a non-finite pose.
    pub fn push_posed(&mut self, row: ObservableRow, pose: RowPose) -> Result<Vec<ReconPoint>> {
        let i = self.count;
        row.validate(i)?;
        pose.validate(i)?;
        self.poses.push(pose);
        let mut out = self.push_row(i, row)?;
        for p in &mut out {
            let x0 = p.x0;
            crate::pose::point_to_lab(p, x0, x0, &self.poses[p.row]);
        }
        Ok(out)
    }

    /// Takes row `i` (validated), the points that became known in the base frame.
    fn push_row(&mut self, i: usize, row: ObservableRow) -> Result<Vec<ReconPoint>> {
        self.count += 1;
        for (k, v) in [row.ax, row.ay, row.ma, row.phi0].into_iter().enumerate() {
            self.scales[k] = self.scales[k].max(v.abs());
        }
        if let Some(flow) = self.flow {
            return Ok(self.decide(flow, i, &row)?.into_iter().collect());
        }
        // the flow is not known yet: is this row the free whisker under its own flow?
        let own = free_flow(row.ax, row.ay);
        let flow = FluidLoad {
            q: self.known.q.unwrap_or(own.q),
            alpha: self.known.alpha.unwrap_or(own.alpha),
        };
        // A contact row judged under its own (wrong) flow may find no consistent point: that
        // is no verdict on the row, which waits for the true flow as the batch's rows do
        // (a log whose contact rows come before its free rows).
        if matches!(self.decide(flow, i, &row), Ok(None)) {
            self.flow = Some(flow);
            let held = std::mem::take(&mut self.held);
            let mut out = Vec::new();
            for (j, r) in held {
                if let Some(p) = self.decide(flow, j, &r)? {
                    out.push(p);
                }
            }
            return Ok(out);
        }
        self.held.push((i, row));
        Ok(Vec::new())
    }

    /// Ends the stream: rows still held (the flow never fixed by a pre-contact row) are
    /// reconstructed as a batch log ([`reconstruct_with`]).
    ///
    /// # Errors
    /// As [`reconstruct_with`] on the held rows.
    pub fn finish(self) -> Result<Vec<ReconPoint>> {
        if self.held.is_empty() {
            return Ok(Vec::new());
        }
        let rows: Vec<ObservableRow> = self.held.iter().map(|(_, r)| *r).collect();
        let poses: Vec<RowPose> = self.held.iter().map(|(i, _)| self.poses[*i]).collect();
        let rec = in_base_frame(&rows, &poses, |r| {
            reconstruct_with(&self.whisker, r, self.known, &self.settings)
        })?;
        Ok(rec
            .points
            .into_iter()
            .map(|mut p| {
                p.row = self.held[p.row].0;
                p
            })
            .collect())
    }
}
