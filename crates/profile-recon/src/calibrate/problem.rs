//! The least-squares problem of a calibration: the parameter vector (the whisker's free
//! parameters, then the flow of every log whose flow is not given), the rows in use with
//! their kinds and whiteners, and the stacked whitened residuals of every row of every log.

use super::fit::{Bounds, Problem};
use super::residual::{
    contour_angle, row_residuals, tip_force, ContactLaw, Model, RowCtx, RowKind, RowResult,
    DEGENERATE, F_MIN_REL,
};
use super::whiten::{judge, projected, whitener, Whitener};
use super::{CalibLog, CalibParam, Progress, ProgressFn, Stage};
use crate::common::NoiseScales;
use beam_model::support::K_MIN;
use beam_model::whisker::{PRECURVATURE_MAX, THETA_MIN};
use bvp_solvers::integrator::Dop853;
use std::cell::{Cell, RefCell};

/// Contact forces below this many standard deviations of their noise are left out
/// ([`CalibProblem::min_force`]).
pub const F_MIN_NOISE: f64 = 10.0;

/// Bounds of the stiffness ratio `lambda` (its logarithm is fitted).
pub const LAMBDA_RANGE: (f64, f64) = (1e-3, 1e3);

/// The least-squares problem over all logs (module docs).
#[derive(Clone, Debug)]
pub(crate) struct CalibProblem<'a> {
    pub logs: &'a [CalibLog],
    /// The whisker parameters fitted, in the order of the parameter vector.
    pub free: Vec<CalibParam>,
    /// The fixed values of everything not fitted.
    pub base: Model,
    /// Per log: its flow `(q cos alpha, q sin alpha)` if fixed (given), `None` if fitted.
    pub fixed_flow: Vec<Option<(f64, f64)>>,
    /// Per log: the rows in use (indices into its rows).
    pub used: Vec<Vec<usize>>,
    /// Per log and used row: the whitener (frozen during a fit round).
    pub whiteners: Vec<Vec<Whitener>>,
    /// Per log: the shift of each row's points back to the lab (empty: none; the framed
    /// logs of `calibrate`, `RowCtx::shift`).
    pub shifts: Vec<Vec<f64>>,
    /// Per log: the noise scales of its columns.
    pub scales: Vec<NoiseScales>,
    pub integrator: Dop853,
    /// The largest model-free noise level of the logs (the residual check's reference).
    pub log_noise: f64,
    /// Chord-Newton steps that project each row onto the model ([`projected`]; 0: the
    /// first-order whitened residuals).
    pub projection: usize,
    /// Where progress is reported.
    pub progress: Reporter<'a>,
    /// Per log and row (all its rows): the law of its contact force (issue 39), decided with
    /// the phases when `mu` is fitted ([`CalibProblem::decide_laws`]); every row
    /// [`ContactLaw::Normal`] otherwise (the frictionless calibration, unchanged).
    pub laws: RefCell<Vec<Vec<ContactLaw>>>,
}

/// The laws of a problem's start: [`ContactLaw::Stick`] (no assumption on the force's
/// direction) for every row of an unposed log when `mu` is fitted, else
/// [`ContactLaw::Normal`].
pub(crate) fn start_laws(logs: &[CalibLog], free: &[CalibParam]) -> RefCell<Vec<Vec<ContactLaw>>> {
    let fits_mu = free.contains(&CalibParam::Mu);
    RefCell::new(
        logs.iter()
            .map(|log| {
                let law = if fits_mu && frictional_log(log) {
                    ContactLaw::Stick
                } else {
                    ContactLaw::Normal
                };
                vec![law; log.rows.len()]
            })
            .collect(),
    )
}

/// Whether a log's contact force may be frictional in the fit: a translating sweep past a
/// contour with a tangent (not a peg). Logs of other motions keep the frictionless law
/// (their order of motion is the pose's, not yet followed here).
fn frictional_log(log: &CalibLog) -> bool {
    log.poses.is_empty() && !matches!(log.profile, contact_sim::Profile::Peg { .. })
}

/// A contact row as [`CalibProblem::decide_laws`] follows it along the motion.
#[derive(Clone, Copy, Debug)]
struct Touching {
    /// The row (index into its log's rows).
    row: usize,
    /// Its base position.
    x0: f64,
    /// The contact point (lab frame).
    p: (f64, f64),
    /// The contact's arc length (1 in phase A).
    s1: f64,
    /// The whisker's angle at the contact.
    tau: f64,
    /// The contour's tangent angle at the point.
    psi_c: f64,
    /// Phase B.
    b: bool,
}

/// The base moves between two rows by less than this fraction of the step in `x0` along the
/// contour for a material point counted as staying put ([`CalibProblem::decide_laws`]).
pub const SLIDE_REL: f64 = 0.1;

/// ... or by less than this many times the logs' model-free noise level.
pub const SLIDE_NOISE: f64 = 10.0;

/// The receiver of a calibration's [`Progress`] and the stage it is at.
#[derive(Clone)]
pub(crate) struct Reporter<'a> {
    to: Option<ProgressFn<'a>>,
    at: Cell<(Stage, usize, usize)>,
}

impl std::fmt::Debug for Reporter<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Reporter")
            .field("at", &self.at.get())
            .finish()
    }
}

impl<'a> Reporter<'a> {
    /// Reports to `to` (nowhere for `None`).
    pub fn new(to: Option<ProgressFn<'a>>) -> Self {
        Reporter {
            to,
            at: Cell::new((Stage::Screen, 0, 0)),
        }
    }

    /// Enters `stage` at step `done` of `total`, and reports it with `rows` and `cost`.
    pub fn stage(&self, stage: Stage, done: usize, total: usize, rows: usize, cost: f64) {
        self.at.set((stage, done, total));
        self.report(rows, cost);
    }

    /// Reports the current stage with `rows` in use and the cost `cost`.
    pub fn report(&self, rows: usize, cost: f64) {
        if let Some(f) = self.to {
            let (stage, done, total) = self.at.get();
            f(&Progress {
                stage,
                done,
                total,
                rows,
                cost,
            });
        }
    }
}

/// Per log and used row: the row's kind (`s1` of phase B tracked).
pub(crate) type Kinds = Vec<Vec<RowKind>>;

impl<'a> CalibProblem<'a> {
    /// Number of flow parameters.
    fn flow_params(&self) -> usize {
        2 * self.fixed_flow.iter().filter(|f| f.is_none()).count()
    }

    /// Length of the parameter vector.
    pub fn dim(&self) -> usize {
        self.free.len() + self.flow_params()
    }

    /// The model and the flows of a parameter vector.
    pub fn unpack(&self, p: &[f64]) -> (Model, Vec<(f64, f64)>) {
        let mut m = self.base;
        for (v, param) in p.iter().zip(&self.free) {
            match param {
                CalibParam::Theta => m.theta = *v,
                CalibParam::A => m.a = *v,
                CalibParam::B => m.b = *v,
                CalibParam::K => m.c = *v,
                CalibParam::Ei => m.lambda = v.exp(),
                CalibParam::Mu => m.mu = *v,
            }
        }
        let mut k = self.free.len();
        let flows = self
            .fixed_flow
            .iter()
            .map(|f| {
                f.unwrap_or_else(|| {
                    k += 2;
                    (p[k - 2], p[k - 1])
                })
            })
            .collect();
        (m, flows)
    }

    /// The parameter vector of a model and flows.
    pub fn pack(&self, m: &Model, flows: &[(f64, f64)]) -> Vec<f64> {
        let mut p: Vec<f64> = self
            .free
            .iter()
            .map(|param| match param {
                CalibParam::Theta => m.theta,
                CalibParam::A => m.a,
                CalibParam::B => m.b,
                CalibParam::K => m.c,
                CalibParam::Ei => m.lambda.ln(),
                CalibParam::Mu => m.mu,
            })
            .collect();
        for (f, fixed) in flows.iter().zip(&self.fixed_flow) {
            if fixed.is_none() {
                p.extend([f.0, f.1]);
            }
        }
        p
    }

    /// The box of the parameters and their typical sizes.
    pub fn bounds(&self) -> Bounds {
        let mut b = Bounds {
            lo: Vec::new(),
            hi: Vec::new(),
            scale: Vec::new(),
        };
        for param in &self.free {
            let (lo, hi, sc) = match param {
                CalibParam::Theta => (THETA_MIN, 1.0, 1.0),
                CalibParam::A | CalibParam::B => (-PRECURVATURE_MAX, PRECURVATURE_MAX, 1.0),
                CalibParam::K => (0.0, 1.0 / K_MIN, 0.01),
                CalibParam::Ei => (LAMBDA_RANGE.0.ln(), LAMBDA_RANGE.1.ln(), 1.0),
                CalibParam::Mu => (0.0, crate::friction::MU_MAX, 0.1),
            };
            b.lo.push(lo);
            b.hi.push(hi);
            b.scale.push(sc);
        }
        for _ in 0..self.flow_params() {
            b.lo.push(-1e3);
            b.hi.push(1e3);
            b.scale.push(1.0);
        }
        b
    }

    /// The context of log `l` at `model` and `flow`.
    pub fn ctx<'b>(&'b self, l: usize, model: &'b Model, flow: (f64, f64)) -> RowCtx<'b> {
        RowCtx {
            model,
            flow,
            profile: &self.logs[l].profile,
            integrator: &self.integrator,
            pose: crate::pose::RowPose::TRANSLATE,
            shift: 0.0,
            law: ContactLaw::Normal,
        }
    }

    /// `ctx` (of log `l`) placed at the pose of row `i` (`RowCtx::pose`, `RowCtx::shift`),
    /// with the row's contact law ([`CalibProblem::laws`]).
    pub fn placed<'b>(&self, ctx: &RowCtx<'b>, l: usize, i: usize) -> RowCtx<'b> {
        let log = &self.logs[l];
        let law = self
            .laws
            .borrow()
            .get(l)
            .and_then(|v| v.get(i))
            .copied()
            .unwrap_or_default();
        let ctx = RowCtx { law, ..*ctx };
        if log.poses.is_empty() {
            return ctx;
        }
        RowCtx {
            pose: log.poses[i],
            shift: self
                .shifts
                .get(l)
                .and_then(|s| s.get(i))
                .copied()
                .unwrap_or(0.0),
            ..ctx
        }
    }

    /// Every used row evaluated at `p` with `kinds` (unwhitened), `None` if one fails.
    pub fn evaluate(&self, p: &[f64], kinds: &Kinds) -> Option<Vec<Vec<RowResult>>> {
        let (model, flows) = self.unpack(p);
        self.used
            .iter()
            .enumerate()
            .map(|(l, used)| {
                let ctx = self.ctx(l, &model, flows[l]);
                used.iter()
                    .zip(&kinds[l])
                    .map(|(&i, &kind)| {
                        row_residuals(&self.placed(&ctx, l, i), &self.logs[l].rows[i], kind)
                    })
                    .collect()
            })
            .collect()
    }

    /// The whitened residuals of used row `k` of log `l` evaluated as `res` at `ctx`
    /// ([`projected`] with [`CalibProblem::projection`] steps).
    pub fn whitened(
        &self,
        ctx: &RowCtx<'_>,
        l: usize,
        k: usize,
        res: &RowResult,
    ) -> [f64; super::residual::RESIDUALS_PER_ROW] {
        let i = self.used[l][k];
        let row = &self.logs[l].rows[i];
        let w = &self.whiteners[l][k];
        projected(
            &self.placed(ctx, l, i),
            row,
            res,
            w,
            &self.scales[l],
            self.projection,
        )
    }

    /// Freezes the whiteners at `p` (per row, at its kind).
    pub fn reweight(&mut self, p: &[f64], kinds: &Kinds) -> bool {
        let Some(results) = self.evaluate(p, kinds) else {
            return false;
        };
        let (model, flows) = self.unpack(p);
        let mut all = Vec::with_capacity(self.used.len());
        for (l, used) in self.used.iter().enumerate() {
            let ctx = self.ctx(l, &model, flows[l]);
            let mut w = Vec::with_capacity(used.len());
            for (k, &i) in used.iter().enumerate() {
                let ctx = self.placed(&ctx, l, i);
                match whitener(&ctx, &self.logs[l].rows[i], &results[l][k], &self.scales[l]) {
                    Some(x) => w.push(x),
                    None => return false,
                }
            }
            all.push(w);
        }
        self.whiteners = all;
        true
    }

    /// Marks the contact rows of `judged` (kinds at `p`) as skipped that the fit cannot
    /// use at `p`: not evaluable or not whitenable there, with a degenerate whitener
    /// ([`DEGENERATE`]), or with a whitened residual norm beyond `limit` (an outlier). A row
    /// whose kind is that of `state` (the kinds the whiteners were made for) keeps its
    /// whitener; the others are whitened at `p`. Returns how many were.
    pub fn admit(&self, p: &[f64], judged: &mut Kinds, state: &Kinds, limit: f64) -> usize {
        let (model, flows) = self.unpack(p);
        let mut n = 0;
        for (l, used) in self.used.iter().enumerate() {
            let ctx = self.ctx(l, &model, flows[l]);
            for (k, &i) in used.iter().enumerate() {
                let kind = judged[l][k];
                let ctx = self.placed(&ctx, l, i);
                if matches!(kind, RowKind::Skipped | RowKind::Pre) {
                    continue;
                }
                let same = match (kind, state[l][k]) {
                    (RowKind::B { .. }, RowKind::B { .. }) => true,
                    (a, b) => a == b,
                };
                let row = &self.logs[l].rows[i];
                let w = |res: &RowResult| {
                    if same {
                        Some(self.whiteners[l][k])
                    } else {
                        whitener(&ctx, row, res, &self.scales[l])
                    }
                };
                let ok = row_residuals(&ctx, row, kind).is_some_and(|res| {
                    w(&res).is_some_and(|w| {
                        let z = w.apply(&res.r);
                        w.degeneracy >= DEGENERATE
                            && z.iter().map(|v| v * v).sum::<f64>().sqrt() <= limit
                    })
                });
                if !ok {
                    judged[l][k] = RowKind::Skipped;
                    n += 1;
                }
            }
        }
        n
    }

    /// [`CalibProblem::reweight`], with the rows that cannot be evaluated or whitened at `p`
    /// skipped ([`CalibProblem::skip_failing`]) if it fails at first.
    pub fn reweight_or_skip(&mut self, p: &[f64], kinds: &mut Kinds) -> bool {
        if self.reweight(p, kinds) {
            return true;
        }
        self.skip_failing(p, kinds);
        self.reweight(p, kinds)
    }

    /// Marks the rows that cannot be evaluated at `p` (or not whitened there) as skipped;
    /// returns how many were. For a start far off, where the trial whisker admits no
    /// solution for some rows: they come back at the next phase decision.
    pub fn skip_failing(&self, p: &[f64], kinds: &mut Kinds) -> usize {
        let (model, flows) = self.unpack(p);
        let mut n = 0;
        for (l, used) in self.used.iter().enumerate() {
            let ctx = self.ctx(l, &model, flows[l]);
            for (k, &i) in used.iter().enumerate() {
                let row = &self.logs[l].rows[i];
                let ctx = self.placed(&ctx, l, i);
                let ok = row_residuals(&ctx, row, kinds[l][k])
                    .and_then(|res| whitener(&ctx, row, &res, &self.scales[l]))
                    .is_some();
                if !ok {
                    kinds[l][k] = RowKind::Skipped;
                    n += 1;
                }
            }
        }
        n
    }

    /// Marks the rows whose whiteners are degenerate ([`DEGENERATE`]) as skipped; returns
    /// how many were.
    pub fn skip_degenerate(&self, kinds: &mut Kinds) -> usize {
        let mut n = 0;
        for (l, ks) in kinds.iter_mut().enumerate() {
            for (k, kind) in ks.iter_mut().enumerate() {
                let bad = self.whiteners[l][k].degeneracy < DEGENERATE;
                if bad && *kind != RowKind::Skipped && *kind != RowKind::Pre {
                    *kind = RowKind::Skipped;
                    n += 1;
                }
            }
        }
        n
    }

    /// The kinds of every used row at `p`: pre-contact rows stay so; a contact row takes the
    /// hypothesis with the smallest whitened residual ([`judge`]), or is skipped when its
    /// contact force is below [`F_MIN_REL`] of the log's largest or no hypothesis exists.
    /// `pre[l]` marks the pre-contact rows of log `l`. Returns the kinds and the number of
    /// contact rows without any hypothesis.
    pub fn judge_all(&self, p: &[f64], pre: &[Vec<bool>]) -> (Kinds, usize) {
        let (model, flows) = self.unpack(p);
        let mut lost = 0;
        let kinds = self
            .used
            .iter()
            .enumerate()
            .map(|(l, used)| {
                let ctx = self.ctx(l, &model, flows[l]);
                let rows = &self.logs[l].rows;
                let fmax = used
                    .iter()
                    .filter(|&&i| !pre[l][i])
                    .map(|&i| tip_force(&model, flows[l], &rows[i]))
                    .fold(0.0, f64::max);
                used.iter()
                    .map(|&i| {
                        if pre[l][i] {
                            return RowKind::Pre;
                        }
                        if tip_force(&model, flows[l], &rows[i]) < self.min_force(l, &model, fmax) {
                            return RowKind::Skipped;
                        }
                        match judge(&self.placed(&ctx, l, i), &rows[i], &self.scales[l]) {
                            Some(h) => h.kind,
                            None => {
                                lost += 1;
                                RowKind::Skipped
                            }
                        }
                    })
                    .collect()
            })
            .collect();
        self.decide_laws(p, &kinds);
        (kinds, lost)
    }

    /// Decides the contact law of every contact row at `p` and `kinds` when `mu` is fitted
    /// (issue 39; spec/model.md "Friction at the contact"), from the motion of the touching
    /// material point alone (no force, so no circularity with `mu`): in the order of the
    /// motion (falling `x0`) each contact row's point `p` on the whisker, and between two
    /// rows of the same phase the displacement of the material point that touched first,
    /// `d = p_b - p_a - (s1_b - s1_a) tau_b` (`tau` the whisker's tangent at the contact:
    /// the contact moves along the whisker by `delta s1`; 0 in phase A, where the tip
    /// touches), along the contour's tangent `t`: `u = d . t`. A pair moves when
    /// `|u| > SLIDE_REL |delta x0| + SLIDE_NOISE * log_noise`; a row whose pairs with both
    /// neighbours move in the same direction slides ([`ContactLaw::Slip`] with that sign);
    /// the others, where sliding starts, stops or turns, and rows with one neighbour, are
    /// [`ContactLaw::Stick`]. Does nothing when `mu` is not fitted.
    pub fn decide_laws(&self, p: &[f64], kinds: &Kinds) {
        if !self.free.contains(&CalibParam::Mu) {
            return;
        }
        let (model, flows) = self.unpack(p);
        let mut laws = self.laws.borrow().clone();
        for (l, used) in self.used.iter().enumerate() {
            let log = &self.logs[l];
            if !frictional_log(log) {
                continue;
            }
            let ctx = self.ctx(l, &model, flows[l]);
            let mut pts: Vec<Touching> = Vec::new();
            for (k, &i) in used.iter().enumerate() {
                let kind = kinds[l][k];
                let (s1, b) = match kind {
                    RowKind::A => (1.0, false),
                    RowKind::B { s1 } => (s1, true),
                    _ => continue,
                };
                let placed = RowCtx {
                    law: ContactLaw::Normal,
                    ..self.placed(&ctx, l, i)
                };
                if let Some(res) = row_residuals(&placed, &log.rows[i], kind) {
                    let psi_c = contour_angle(&log.profile, res.point.0, res.point.1);
                    let s1 = match res.kind {
                        RowKind::B { s1 } => s1,
                        _ => s1,
                    };
                    if psi_c.is_finite() {
                        pts.push(Touching {
                            row: i,
                            x0: log.rows[i].x0,
                            p: res.point,
                            s1,
                            tau: res.phi,
                            psi_c,
                            b,
                        });
                    }
                }
            }
            pts.sort_by(|a, b| b.x0.total_cmp(&a.x0).then(a.row.cmp(&b.row)));
            let tol_noise = SLIDE_NOISE * self.log_noise;
            // the signed slide of each consecutive pair (0: stays put, NaN: a change of phase)
            let steps: Vec<f64> = pts
                .windows(2)
                .map(|w| {
                    let (a, b) = (&w[0], &w[1]);
                    if a.b != b.b {
                        return f64::NAN;
                    }
                    let ds = b.s1 - a.s1;
                    let dx = b.p.0 - a.p.0 - ds * b.tau.cos();
                    let dy = b.p.1 - a.p.1 - ds * b.tau.sin();
                    let psi = 0.5 * (a.psi_c + b.psi_c);
                    let u = dx * psi.cos() + dy * psi.sin();
                    if u.abs() > SLIDE_REL * (b.x0 - a.x0).abs() + tol_noise {
                        u.signum()
                    } else {
                        0.0
                    }
                })
                .collect();
            let row_laws = &mut laws[l];
            for law in row_laws.iter_mut() {
                *law = ContactLaw::Stick;
            }
            for (w, pt) in pts.iter().enumerate() {
                let prev = w.checked_sub(1).map(|v| steps[v]);
                let next = steps.get(w).copied();
                row_laws[pt.row] = match (prev, next) {
                    (Some(a), Some(b)) if a == b && a != 0.0 => ContactLaw::Slip { sign: a },
                    _ => ContactLaw::Stick,
                };
            }
        }
        *self.laws.borrow_mut() = laws;
    }

    /// Per log and used row: whether it is a contact row (not in `pre`) whose force at `p`
    /// reaches [`CalibProblem::min_force`] (the rows the data say the fit should explain).
    pub fn usable_contact(&self, p: &[f64], pre: &[Vec<bool>]) -> Vec<Vec<bool>> {
        let (model, flows) = self.unpack(p);
        self.used
            .iter()
            .enumerate()
            .map(|(l, used)| {
                let rows = &self.logs[l].rows;
                let force = |i: usize| tip_force(&model, flows[l], &rows[i]);
                let fmax = used
                    .iter()
                    .filter(|&&i| !pre[l][i])
                    .map(|&i| force(i))
                    .fold(0.0, f64::max);
                let floor = self.min_force(l, &model, fmax);
                used.iter()
                    .map(|&i| !pre[l][i] && force(i) >= floor)
                    .collect()
            })
            .collect()
    }

    /// The norm of every used row's whitened residuals at `p` (NaN for skipped rows or if
    /// the evaluation fails).
    pub fn row_norms(&self, p: &[f64], kinds: &Kinds) -> Vec<Vec<f64>> {
        let results = self.evaluate(p, kinds);
        let (model, flows) = self.unpack(p);
        kinds
            .iter()
            .enumerate()
            .map(|(l, ks)| {
                let ctx = self.ctx(l, &model, flows[l]);
                ks.iter()
                    .enumerate()
                    .map(|(k, kind)| match (&results, kind) {
                        (Some(res), RowKind::A | RowKind::B { .. } | RowKind::Pre) => {
                            let z = self.whitened(&ctx, l, k, &res[l][k]);
                            z.iter().map(|v| v * v).sum::<f64>().sqrt()
                        }
                        _ => f64::NAN,
                    })
                    .collect()
            })
            .collect()
    }

    /// The leverage of every used row at `p` (`sum over its residuals of
    /// J_i (J^T J)^-1 J_i^T`, the row's share of the Fisher information; the shares add up to
    /// the number of parameters), with the residual Jacobian `cols` (column-major) of the
    /// rows in `kinds`; NaN for skipped rows.
    pub fn leverages(&self, cols: &[Vec<f64>], kinds: &Kinds) -> Vec<Vec<f64>> {
        let n = cols.len();
        let jtj: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|k| super::fit::dot(&cols[i], &cols[k]))
                    .collect()
            })
            .collect();
        let dmax = (0..n).map(|i| jtj[i][i]).fold(0.0, f64::max);
        let mut reg = jtj.clone();
        for (i, row) in reg.iter_mut().enumerate() {
            row[i] += 1e-12 * dmax + f64::MIN_POSITIVE;
        }
        let mut idx = 0;
        kinds
            .iter()
            .map(|ks| {
                ks.iter()
                    .map(|k| {
                        if *k == RowKind::Skipped {
                            return f64::NAN;
                        }
                        let mut h = 0.0;
                        for _ in 0..super::residual::RESIDUALS_PER_ROW {
                            let ji: Vec<f64> = cols.iter().map(|c| c[idx]).collect();
                            if let Some(x) = bvp_solvers::dense::solve_spd(&reg, &ji) {
                                h += super::fit::dot(&ji, &x);
                            }
                            idx += 1;
                        }
                        h
                    })
                    .collect()
            })
            .collect()
    }

    /// Contact rows of log `l` with a force (model units at `model`) below this are left
    /// out: [`F_MIN_REL`] of the log's largest force `fmax`, or [`F_MIN_NOISE`] standard
    /// deviations of the force's noise if that is larger (a contact force within a few noise
    /// deviations of zero fixes neither the phase nor the force's direction, and the
    /// linearised whitening fails there).
    pub fn min_force(&self, l: usize, model: &Model, fmax: f64) -> f64 {
        let sc = &self.scales[l].0;
        let f_sd = self.log_noise * sc[0].max(sc[1]) / model.lambda;
        (F_MIN_REL * fmax).max(F_MIN_NOISE * f_sd)
    }

    /// Number of residuals at `kinds`.
    pub fn residual_count(&self, kinds: &Kinds) -> usize {
        kinds
            .iter()
            .flatten()
            .filter(|k| **k != RowKind::Skipped)
            .count()
            * super::residual::RESIDUALS_PER_ROW
    }
}

impl Problem for CalibProblem<'_> {
    type State = Kinds;

    fn iterated(&self, _iteration: usize, cost: f64) {
        let rows = self.used.iter().map(Vec::len).sum();
        self.progress.report(rows, cost);
    }

    fn residuals(&self, p: &[f64], state: &Kinds) -> Option<(Vec<f64>, Kinds)> {
        let results = self.evaluate(p, state)?;
        let (model, flows) = self.unpack(p);
        let mut r = Vec::with_capacity(self.residual_count(state));
        let mut kinds = Vec::with_capacity(results.len());
        for (l, rows) in results.iter().enumerate() {
            let ctx = self.ctx(l, &model, flows[l]);
            let mut k = Vec::with_capacity(rows.len());
            for (j, res) in rows.iter().enumerate() {
                k.push(res.kind);
                if res.kind != RowKind::Skipped {
                    r.extend(self.whitened(&ctx, l, j, res));
                }
            }
            kinds.push(k);
        }
        Some((r, kinds))
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_log::{exact, problem};
    use super::*;
    use beam_model::Whisker;

    #[test]
    fn packing_is_inverted_by_unpacking() {
        let e = exact(3, 8);
        let logs = [e.log.clone(), e.log.clone()];
        let mut prob = problem(
            &logs,
            vec![CalibParam::Theta, CalibParam::K, CalibParam::Ei],
            &e.truth,
        );
        prob.fixed_flow[1] = Some((1.0, 0.5));
        assert_eq!(prob.dim(), 5);
        let m = Model {
            lambda: 2.5,
            theta: 0.3,
            c: 0.05,
            ..prob.base
        };
        let p = prob.pack(&m, &[(1.5, -0.3), (9.0, 9.0)]);
        // E I through its logarithm; the fixed flow is not a parameter
        assert_eq!(p[..2], [0.3, 0.05]);
        assert!((p[2] - 2.5f64.ln()).abs() < 1e-15 && p[3..] == [1.5, -0.3]);
        let (back, flows) = prob.unpack(&p);
        assert!((back.lambda / 2.5 - 1.0).abs() < 1e-15);
        assert_eq!((back.theta, back.c, back.a, back.b), (0.3, 0.05, m.a, m.b));
        assert_eq!(flows, [(1.5, -0.3), (1.0, 0.5)]);
        let b = prob.bounds();
        assert_eq!(b.lo.len(), 5);
        assert!((b.hi[2] - 1e3f64.ln()).abs() < 1e-14 && (b.lo[2] + 1e3f64.ln()).abs() < 1e-14);
        assert!(b.lo[1] == 0.0 && (b.hi[1] - 1.0 / K_MIN).abs() < 1e-12);
    }

    #[test]
    fn the_exact_log_has_no_residual_at_the_truth() {
        let e = exact(3, 12);
        let logs = [e.log.clone()];
        let prob = problem(&logs, vec![CalibParam::A, CalibParam::B], &e.truth);
        let qf = (e.flow.q * e.flow.alpha.cos(), e.flow.q * e.flow.alpha.sin());
        let p = prob.pack(&prob.base, &[qf]);
        let kinds = vec![e.kinds.clone()];
        let res = prob
            .evaluate(&p, &kinds)
            .expect("every row evaluates at the truth");
        let worst = res[0]
            .iter()
            .flat_map(|r| r.r)
            .fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(worst < 1e-8, "{worst:e}");
        assert_eq!(prob.residual_count(&kinds), 4 * e.log.rows.len());
        // moved off the truth, the residuals grow
        let moved = prob
            .evaluate(&[p[0] + 0.01, p[1], p[2], p[3]], &kinds)
            .unwrap();
        let worst = moved[0]
            .iter()
            .flat_map(|r| r.r)
            .fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(worst > 1e-5, "{worst:e}");
    }

    #[test]
    fn leverages_add_up_to_the_parameter_count() {
        // three rows in use (twelve residuals), one skipped; two parameters
        let prob = problem(&[], vec![CalibParam::A, CalibParam::B], &Whisker::uniform());
        let kinds = vec![vec![
            RowKind::Pre,
            RowKind::Skipped,
            RowKind::A,
            RowKind::B { s1: 0.5 },
        ]];
        let cols: Vec<Vec<f64>> = (0..2)
            .map(|c| {
                (0..12)
                    .map(|i| ((i * (c + 2)) as f64 * 0.7).sin() + c as f64)
                    .collect()
            })
            .collect();
        let h = prob.leverages(&cols, &kinds);
        assert!(h[0][1].is_nan());
        let total: f64 = [0, 2, 3].iter().map(|&k| h[0][k]).sum();
        assert!((total - 2.0).abs() < 1e-9, "{h:?}");
        assert!([0, 2, 3].iter().all(|&k| h[0][k] > 0.0 && h[0][k] < 2.0));
    }
}
