//! Reconstruction of frictional logs (spec/model.md, "Friction at the contact"; issue 39,
//! items 3-4): each contact point, the normal and tangential parts `fn`, `ft` of the contact
//! force, and the friction coefficient `mu` from the sliding rows, from the base observables
//! alone.
//!
//! The shape needs no contact law: the observables are the initial values of the elastica at
//! the base [3.25], and the internal force at `s < s1` is the base reaction with the flow on
//! `[0, s]` [6.8, 6.9], whatever the direction of the contact force. So one integration from
//! the base ([`row`]) gives every phase hypothesis:
//! - phase A (the tip) where `m(1) = 0` [6.6] within `K_SIGMA` standard deviations of its
//!   noise;
//! - otherwise phase B at a root of `m(s1) = 0` (the segment beyond is unloaded): among the
//!   roots where the force pushes the whisker off the contour (`fn >= 0` within the noise) and
//!   lies in the cone of `mu <= MU_MAX`, the one that needs the least friction `|ft| / fn`;
//!   the others are counted as alternatives and widen the error estimate to cover them.
//!
//! The phase is decided without assuming a normal force (the frictionless reconstruction tests
//! the tangency `phi(s1) = psi` with `psi` from the force's direction). The contact force is
//! `F = (Fx, Fy)`, balanced with the flow on `[0, s1]` [6.8, 6.9], split as
//! `F = fn n + ft t` along the contour's tangent `t = (cos psi, sin psi)`: in phase B the
//! whisker's tangent at `s1` (tangency), in phase A from the contour traced by the contact
//! points of the log ([`contour`]).
//!
//! **mu.** Sliding rows (the material point moves between the neighbouring rows of the
//! motion, [`contour`]) satisfy `|ft| = mu fn`; `mu` is the mean of their ratios `|ft| / fn`
//! weighted by the inverse variances (each ratio's deviation: the noise level propagated
//! through the row's sensitivities, by central differences of the whole evaluation, and in
//! phase A the tangent's error estimate), its standard error `1 / sqrt(sum w)` times the
//! Birge ratio `sqrt(chi^2 / (n - 1))` where that exceeds 1 (the rows scatter more than their
//! deviations say), and the error of an identified flow, which every row shares: each ratio's
//! change per standard deviation of the flow's components `(q cos alpha, q sin alpha)`
//! (one-sided differences, two more integrations per row) averaged with the same weights,
//! added in quadrature. Rows with `fn` within `K_SIGMA` deviations of zero carry no ratio.
//!
//! **Evidence of friction** ([`FrictionEvidence`]): the row whose tangential force is the most
//! standard deviations away from zero. A frictionless reconstruction asked of a log with
//! evidence beyond `K_SIGMA` is biased: [`widen_frictionless`] says so and widens its error
//! estimates to cover the frictional points.
//!
//! | file | concept |
//! |---|---|
//! | `row` | one row: the integration from the base, the hypotheses, the force split |
//! | `contour` | the order of the motion, the tangent at tip contacts, the sliding rows |
//! | `stream` | the rows one at a time ([`stream::FrictionalStreamer`]) |

pub mod contour;
pub mod row;
pub mod stream;

use crate::base_shot::K_SIGMA;
use crate::common::{KnownFlow, NoiseScales, ReconSettings};
use crate::error::{ReconError, Result};
use crate::identify::identify_rows;
use crate::observables::ObservableRow;
use crate::result::{Identification, ReconPoint, Reconstruction};
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Dop853;
use contact_sim::{Phase, Profile, SlipState};
use contour::{distinct, motion_order, tangent_at, Sample};
use row::{moved, shoot, Candidate, Shot};
use serde::{Deserialize, Serialize};

/// Largest friction coefficient a phase-B root may need to count as a contact (contact-sim
/// refuses `mu > 10`).
pub const MU_MAX: f64 = 10.0;

/// Relative step of the central differences (of each column's noise scale).
pub const FD_STEP: f64 = 1e-5;

/// Where a point's contour angle `psi` comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum PsiSource {
    /// Phase B: the whisker's tangent at `s1` (tangency).
    Tangency,
    /// Phase A: the contour traced by the log's contact points.
    Contour,
    /// Phase A on a known contour (calibration against a known object): its angle at the
    /// reconstructed point's `x`.
    Known,
    /// Phase A with fewer than three distinct contact points: unknown (NaN), no `fn`, `ft`.
    Unknown,
}

/// One reconstructed contact point of a frictional log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrictionalPoint {
    /// 0-based input row.
    pub row: usize,
    /// The row's base position, copied exactly.
    pub x0: f64,
    /// Contact point x.
    pub x: f64,
    /// Contact point y.
    pub y: f64,
    /// Contact arc length (1 in phase A).
    pub s1: f64,
    /// Normal part `fn` of the contact force on the whisker (`F = fn n + ft t`).
    pub f: f64,
    /// Tangential part `ft`, along `t = (cos psi, sin psi)`.
    pub ft: f64,
    /// Contour angle at the contact point.
    pub psi: f64,
    /// Where `psi` comes from.
    pub psi_source: PsiSource,
    /// Decided phase.
    pub phase: Phase,
    /// Whether the touching material point slides (module docs), `stick` otherwise.
    pub slip: SlipState,
    /// Error estimate (one standard deviation) of the point `(x, y)`, widened to cover the
    /// alternatives.
    pub sigma: f64,
    /// Standard deviation of `fn`.
    pub sigma_f: f64,
    /// Standard deviation of `ft`.
    pub sigma_ft: f64,
    /// Error estimate of `psi`.
    pub sigma_psi: f64,
    /// Phase A: `|m(1)|` [6.6]; phase B: 0 (the root of `m`).
    pub residual: f64,
    /// Other phase-B roots that are admissible contacts too.
    pub alternatives: usize,
    /// The change of `|ft| / fn` per standard deviation of each component `(q cos alpha,
    /// q sin alpha)` of an identified flow (0 for a flow given): an error shared by every
    /// row, propagated into mu's standard error.
    pub dratio_flow: [f64; 2],
}

impl FrictionalPoint {
    /// `|ft| / fn` and its standard deviation (NaN without a tangent or a force).
    pub fn ratio(&self) -> (f64, f64) {
        if self.f <= 0.0 || !self.ft.is_finite() {
            return (f64::NAN, f64::NAN);
        }
        let r = self.ft.abs() / self.f;
        (r, self.sigma_ft.hypot(r * self.sigma_f) / self.f)
    }

    /// The point as the frictionless reconstruction's point (`f` the normal part; the
    /// residual and the error estimate as above).
    pub fn to_recon_point(&self) -> ReconPoint {
        ReconPoint {
            row: self.row,
            x0: self.x0,
            x: self.x,
            y: self.y,
            s1: self.s1,
            f: self.f,
            psi: self.psi,
            phase: self.phase,
            residual: self.residual,
            sigma: self.sigma,
            alternatives: self.alternatives,
            evaluations: 9,
        }
    }
}

/// The friction coefficient identified from the sliding rows (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MuEstimate {
    /// The weighted mean of the sliding rows' `|ft| / fn`.
    pub value: f64,
    /// Its standard error.
    pub stderr: f64,
    /// The sliding rows it is the mean of.
    pub rows: usize,
    /// `chi^2 / (n - 1)` of the ratios about the mean (about 1 when the rows' deviations are
    /// right; NaN for one row).
    pub chi2_dof: f64,
}

/// The strongest evidence of a tangential contact force in a log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrictionEvidence {
    /// 0-based input row.
    pub row: usize,
    /// Its base position.
    pub x0: f64,
    /// Its tangential force.
    pub ft: f64,
    /// The standard deviation of `ft`.
    pub sigma_ft: f64,
}

impl FrictionEvidence {
    /// `|ft|` in standard deviations.
    pub fn z(&self) -> f64 {
        self.ft.abs() / self.sigma_ft.max(f64::MIN_POSITIVE)
    }

    /// Whether the log proves friction (beyond `K_SIGMA` deviations).
    pub fn proves_friction(&self) -> bool {
        self.z() > K_SIGMA
    }
}

/// A reconstructed frictional log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrictionalReconstruction {
    /// The identification (flow, pre-contact rows, noise level).
    pub identification: Identification,
    /// Whether q was given.
    pub q_given: bool,
    /// Whether alpha was given.
    pub alpha_given: bool,
    /// One point per contact row, in the input order.
    pub points: Vec<FrictionalPoint>,
    /// `mu` as identified (None when given, or without a sliding row with a force).
    pub mu: Option<MuEstimate>,
    /// `mu` as given.
    pub mu_given: Option<f64>,
    /// Sliding rows whose `|ft| / fn` differs from the given `mu` beyond `K_SIGMA` deviations,
    /// or any row outside its cone (0 without a given `mu`).
    pub violations: usize,
    /// The strongest evidence of friction (None without a row with a tangent).
    pub evidence: Option<FrictionEvidence>,
}

impl FrictionalReconstruction {
    /// The points as a frictionless reconstruction's (`ft` dropped; see
    /// [`FrictionalPoint::to_recon_point`]).
    pub fn to_reconstruction(&self) -> Reconstruction {
        Reconstruction {
            identification: self.identification.clone(),
            q_given: self.q_given,
            alpha_given: self.alpha_given,
            points: self.points.iter().map(|p| p.to_recon_point()).collect(),
            accuracy: None,
        }
    }
}

/// The chosen hypothesis of one row with the sensitivities (per unit relative noise) of
/// `[x, y, s1, phi, Fx, Fy]` to the observables.
#[derive(Clone, Copy, Debug)]
struct RowFit {
    row: usize,
    phase: Phase,
    c: Candidate,
    jac: [[f64; 4]; 6],
    m1: f64,
    alternatives: usize,
    /// Largest distance to an alternative.
    alt_dist: f64,
    /// The change of `[x, y, s1, phi, Fx, Fy]` per standard deviation of each flow
    /// component (one-sided differences; 0 for a flow given).
    jflow: [[f64; 2]; 6],
}

impl RowFit {
    fn sd(&self, k: usize, level: f64) -> f64 {
        level * self.jac[k].iter().map(|v| v * v).sum::<f64>().sqrt()
    }

    /// `(fn, ft, sd fn, sd ft)` along the tangent `psi`, whose noise is `dpsi` per column
    /// (correlated with the force's: phase B `dphi(s1)`, a known contour `psi'(x) dx`) plus
    /// an independent deviation `sd_psi` (a traced contour's).
    fn split(&self, psi: f64, dpsi: [f64; 4], sd_psi: f64, level: f64) -> [f64; 4] {
        let (fnn, ft) = self.c.split(psi);
        let (sp, cp) = psi.sin_cos();
        let (mut vf, mut vt) = (0.0, 0.0);
        for (j, dpsi) in dpsi.iter().enumerate() {
            let (dfx, dfy) = (self.jac[4][j], self.jac[5][j]);
            vf += (dfx * sp - dfy * cp + ft * dpsi).powi(2);
            vt += (dfx * cp + dfy * sp - fnn * dpsi).powi(2);
        }
        let (sf, st) = (level * vf.sqrt(), level * vt.sqrt());
        [fnn, ft, sf.hypot(ft * sd_psi), st.hypot(fnn * sd_psi)]
    }

    /// The change of `|ft| / fn` per standard deviation of each flow component, `psi`
    /// moving by `dpsi` per deviation (phase B: `dphi(s1)`, a known contour `psi'(x) dx`).
    fn ratio_flow(&self, psi: f64, dpsi: [f64; 2]) -> [f64; 2] {
        let (fnn, ft) = self.c.split(psi);
        let (sp, cp) = psi.sin_cos();
        let mut out = [0.0; 2];
        for (a, o) in out.iter_mut().enumerate() {
            let (dfx, dfy) = (self.jflow[4][a], self.jflow[5][a]);
            let dfn = dfx * sp - dfy * cp + ft * dpsi[a];
            let dft = dfx * cp + dfy * sp - fnn * dpsi[a];
            *o = ft.signum() * dft / fnn - ft.abs() * dfn / (fnn * fnn);
        }
        out
    }
}

/// The values `[x, y, s1, phi, Fx, Fy]` of a candidate.
fn values(c: &Candidate) -> [f64; 6] {
    [c.x, c.y, c.s1, c.phi, c.fx, c.fy]
}

/// The candidate of `shot` that tracks `c` (same phase; the nearest root).
fn track(shot: &Shot, phase: Phase, c: &Candidate) -> Option<Candidate> {
    if phase == Phase::A {
        shot.tip
    } else {
        shot.roots
            .iter()
            .min_by(|a, b| (a.s1 - c.s1).abs().total_cmp(&(b.s1 - c.s1).abs()))
            .copied()
    }
}

/// One contact row: its shots, the phase decision and the sensitivities (module docs).
#[allow(clippy::needless_range_loop, clippy::too_many_arguments)]
fn fit_row(
    whisker: &Whisker,
    flow: FluidLoad,
    i: usize,
    row: &ObservableRow,
    scales: &NoiseScales,
    level: f64,
    flow_sd: [f64; 2],
    integrator: &Dop853,
) -> Result<RowFit> {
    let base = shoot(whisker, flow, row, integrator)?;
    // one-sided differences in each flow component (q cos alpha, q sin alpha), by its
    // standard deviation: the error every row shares when the flow is identified
    let mut flow_shots: Vec<Option<(Shot, f64)>> = Vec::with_capacity(2);
    for (a, &sd) in flow_sd.iter().enumerate() {
        if sd == 0.0 {
            flow_shots.push(None);
            continue;
        }
        let (mut qc, mut qs) = (flow.q * flow.alpha.cos(), flow.q * flow.alpha.sin());
        let d = FD_STEP * flow.q.max(sd);
        if a == 0 {
            qc += d;
        } else {
            qs += d;
        }
        let moved_flow = FluidLoad {
            q: qc.hypot(qs),
            alpha: qs.atan2(qc),
        };
        flow_shots.push(Some((shoot(whisker, moved_flow, row, integrator)?, d / sd)));
    }
    let flow_sens = |phase: Phase, c: &Candidate| -> [[f64; 2]; 6] {
        let mut jf = [[0.0; 2]; 6];
        for (a, p) in flow_shots.iter().enumerate() {
            let Some((shot, h)) = p else { continue };
            let Some(m) = track(shot, phase, c) else {
                continue;
            };
            let (vm, v0) = (values(&m), values(c));
            for k in 0..6 {
                jf[k][a] = (vm[k] - v0[k]) / h;
            }
        }
        jf
    };
    // central differences of every shot: +-d in each column
    let mut pm: Vec<Option<(Shot, Shot, f64)>> = Vec::with_capacity(4);
    for (j, &sc) in scales.0.iter().enumerate() {
        if sc == 0.0 {
            pm.push(None);
            continue;
        }
        let d = FD_STEP * sc;
        let up = shoot(whisker, flow, &moved(row, j, d), integrator)?;
        let dn = shoot(whisker, flow, &moved(row, j, -d), integrator)?;
        pm.push(Some((up, dn, d)));
    }
    // per unit relative noise: d(value)/d(column) * scale
    let sens = |phase: Phase, c: &Candidate| -> [[f64; 4]; 6] {
        let mut jac = [[0.0; 4]; 6];
        for (j, p) in pm.iter().enumerate() {
            let Some((up, dn, d)) = p else { continue };
            let (Some(a), Some(b)) = (track(up, phase, c), track(dn, phase, c)) else {
                continue;
            };
            let (va, vb) = (values(&a), values(&b));
            for k in 0..6 {
                jac[k][j] = (va[k] - vb[k]) / (2.0 * d) * scales.0[j];
            }
        }
        jac
    };
    let sd_m1 = level
        * pm.iter()
            .enumerate()
            .filter_map(|(j, p)| {
                p.as_ref()
                    .map(|(u, d, h)| (u.m1 - d.m1) / (2.0 * h) * scales.0[j])
            })
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt();
    let fit = |phase, c: Candidate, alternatives, alt_dist| RowFit {
        row: i,
        phase,
        c,
        jac: sens(phase, &c),
        m1: base.m1,
        alternatives,
        alt_dist,
        jflow: flow_sens(phase, &c),
    };
    if let Some(tip) = base.tip {
        if base.m1.abs() <= K_SIGMA * sd_m1 {
            return Ok(fit(Phase::A, tip, 0, 0.0));
        }
    }
    // phase B: admissible roots, the least friction first
    let mut adm: Vec<(f64, Candidate)> = Vec::new();
    for c in &base.roots {
        let jac = sens(Phase::B, c);
        let probe = RowFit {
            row: i,
            phase: Phase::B,
            c: *c,
            jac,
            m1: base.m1,
            alternatives: 0,
            alt_dist: 0.0,
            jflow: [[0.0; 2]; 6],
        };
        let [fnn, ft, sf, st] = probe.split(c.phi, probe.jac[3], 0.0, level);
        if fnn >= -K_SIGMA * sf && ft.abs() <= MU_MAX * fnn.max(0.0) + K_SIGMA * st {
            adm.push((ft.abs() / fnn.max(f64::MIN_POSITIVE), *c));
        }
    }
    adm.sort_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((_, c)) = adm.first() {
        let alt_dist = adm[1..]
            .iter()
            .map(|(_, a)| (a.x - c.x).hypot(a.y - c.y))
            .fold(0.0, f64::max);
        return Ok(fit(Phase::B, *c, adm.len() - 1, alt_dist));
    }
    match base.tip {
        // no admissible contact but the tip: the tip with its residual
        Some(tip) => Ok(fit(Phase::A, tip, 0, 0.0)),
        None => Err(ReconError::InconsistentRow {
            row: i,
            x0: row.x0,
            residual: f64::NAN,
            phase: Phase::B,
        }),
    }
}

/// `psi` wrapped to `(-pi, pi]`.
fn wrap(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let r = a.rem_euclid(t);
    if r > std::f64::consts::PI {
        r - t
    } else {
        r
    }
}

/// Reconstructs a frictional log (module docs): the flow, noise level and pre-contact rows
/// as [`identify`](crate::identify()) finds them (they involve no contact force), then one
/// [`FrictionalPoint`] per contact row, and `mu` from the sliding rows unless `mu` is given.
///
/// # Errors
/// [`ReconError::InvalidParameter`] (`mu`) for a given `mu` outside `[0, MU_MAX]`; those of
/// [`identify`](crate::identify()); [`ReconError::NoContactRows`];
/// [`ReconError::InconsistentRow`] for a row with no contact hypothesis at all.
pub fn reconstruct_frictional(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: KnownFlow,
    settings: &ReconSettings,
    mu: Option<f64>,
) -> Result<FrictionalReconstruction> {
    reconstruct_frictional_on(whisker, rows, known, settings, mu, None)
}

/// [`reconstruct_frictional`] of a log of sweeps past a KNOWN contour (calibration: the
/// friction coefficient of a whisker on a known object): the tangent at a tip contact is the
/// contour's at the reconstructed point (`psi = atan g'(x)`, its error the point's error
/// estimate times the curvature) instead of the traced contour's; phase B as before (the
/// contour is not used to place the points, so a wrong contour shows as points off it).
///
/// # Errors
/// As [`reconstruct_frictional`].
pub fn reconstruct_frictional_on(
    whisker: &Whisker,
    rows: &[ObservableRow],
    known: KnownFlow,
    settings: &ReconSettings,
    mu: Option<f64>,
    profile: Option<&Profile>,
) -> Result<FrictionalReconstruction> {
    if let Some(m) = mu {
        if !(0.0..=MU_MAX).contains(&m) {
            return Err(ReconError::InvalidParameter {
                name: "mu",
                value: m,
                reason: "the friction coefficient must lie in [0, 10]",
            });
        }
    }
    let ided = identify_rows(whisker, rows, known, settings)?;
    let id = &ided.id;
    let contact: Vec<usize> = (0..rows.len())
        .filter(|i| id.pre_contact.binary_search(i).is_err())
        .collect();
    if contact.is_empty() {
        return Err(ReconError::NoContactRows { rows: rows.len() });
    }
    let level = id.noise;
    let scales = ided.scales;
    let flow = id.flow();
    let integrator = Dop853::new(settings.tol, settings.tol).with_dense(true);
    let flow_sd = crate::judge::flow_sd(&known, level, &scales, id.pre_contact.len());
    let fits = crate::rows_par::map_rows(contact.len(), |k| {
        let i = contact[k];
        fit_row(
            whisker,
            flow,
            i,
            &rows[i],
            &scales,
            level,
            flow_sd,
            &integrator,
        )
    })?;
    let points = frictional_points(rows, &fits, level, profile);
    let (mu_est, violations) = mu_of(&points, mu);
    let evidence = points
        .iter()
        .filter(|p| p.ft.is_finite())
        .map(|p| FrictionEvidence {
            row: p.row,
            x0: p.x0,
            ft: p.ft,
            sigma_ft: p.sigma_ft,
        })
        .max_by(|a, b| a.z().total_cmp(&b.z()));
    Ok(FrictionalReconstruction {
        identification: ided.id.clone(),
        q_given: known.q.is_some(),
        alpha_given: known.alpha.is_some(),
        points,
        mu: mu_est,
        mu_given: mu,
        violations,
        evidence,
    })
}

/// The points of the fitted rows: tangents, force split, sliding rows.
fn frictional_points(
    rows: &[ObservableRow],
    fits: &[RowFit],
    level: f64,
    profile: Option<&Profile>,
) -> Vec<FrictionalPoint> {
    let sigma_of = |f: &RowFit| f.sd(0, level).hypot(f.sd(1, level)) + f.alt_dist;
    let samples: Vec<Sample> = fits
        .iter()
        .map(|f| Sample {
            x: f.c.x,
            y: f.c.y,
            sigma: sigma_of(f),
        })
        .collect();
    let contour = distinct(&samples, K_SIGMA);
    let mut points: Vec<FrictionalPoint> = fits
        .iter()
        .map(|f| {
            // psi, its noise correlated with the force's (per column), its own deviation
            // (the traced contour moves with the flow as a whole: its tangent's share of
            // the flow's error is left out, its own deviation being conservative)
            let (psi, dpsi, dpsi_flow, sd_psi, source) = match (f.phase, profile) {
                (Phase::B, _) => (
                    wrap(f.c.phi),
                    f.jac[3],
                    f.jflow[3],
                    0.0,
                    PsiSource::Tangency,
                ),
                (_, Some(g)) => {
                    let (_, d1, d2) = g.eval(f.c.x);
                    let k = d2 / (1.0 + d1 * d1);
                    (
                        g.psi(f.c.x),
                        f.jac[0].map(|dx| k * dx),
                        f.jflow[0].map(|dx| k * dx),
                        0.0,
                        PsiSource::Known,
                    )
                }
                _ => match tangent_at(&contour, f.c.x) {
                    Some((psi, e)) => (psi, [0.0; 4], [0.0; 2], e, PsiSource::Contour),
                    None => (f64::NAN, [0.0; 4], [0.0; 2], f64::NAN, PsiSource::Unknown),
                },
            };
            let [fnn, ft, sf, st] = if psi.is_finite() {
                f.split(psi, dpsi, sd_psi, level)
            } else {
                [f64::NAN; 4]
            };
            let dratio_flow = if psi.is_finite() {
                f.ratio_flow(psi, dpsi_flow)
            } else {
                [0.0; 2]
            };
            let sd_psi = level * dpsi.iter().map(|v| v * v).sum::<f64>().sqrt() + sd_psi;
            FrictionalPoint {
                row: f.row,
                x0: rows[f.row].x0,
                x: f.c.x,
                y: f.c.y,
                s1: f.c.s1,
                f: fnn,
                ft,
                psi,
                psi_source: source,
                phase: f.phase,
                slip: SlipState::Stick,
                sigma: sigma_of(f),
                sigma_f: sf,
                sigma_ft: st,
                sigma_psi: sd_psi,
                residual: if f.phase == Phase::A { f.m1.abs() } else { 0.0 },
                alternatives: f.alternatives,
                dratio_flow,
            }
        })
        .collect();
    mark_sliding(rows, &mut points, fits, level);
    points
}

/// Marks the sliding rows (module docs of [`contour`]).
fn mark_sliding(
    rows: &[ObservableRow],
    points: &mut [FrictionalPoint],
    fits: &[RowFit],
    level: f64,
) {
    let x0: Vec<f64> = rows.iter().map(|r| r.x0).collect();
    let idx: Vec<usize> = points.iter().map(|p| p.row).collect();
    let at: std::collections::HashMap<usize, usize> =
        idx.iter().enumerate().map(|(k, &r)| (r, k)).collect();
    let order: Vec<usize> = motion_order(&x0, &idx)
        .into_iter()
        .map(|r| at[&r])
        .collect();
    let moved = |a: usize, b: usize| -> bool {
        let (p, q) = (&points[a], &points[b]);
        let tol = K_SIGMA * (p.sigma + q.sigma) + 1e-10;
        let chord = (p.x - q.x).hypot(p.y - q.y);
        match (p.phase, q.phase) {
            (Phase::A, Phase::A) => chord > tol,
            (Phase::B, Phase::B) => {
                let ds = (p.s1 - q.s1).abs();
                let sd = fits[a].sd(2, level) + fits[b].sd(2, level);
                (chord - ds).abs() > tol + K_SIGMA * sd + 1e-3 * chord
            }
            _ => chord > tol,
        }
    };
    let steps: Vec<bool> = order.windows(2).map(|p| moved(p[0], p[1])).collect();
    for w in 0..order.len() {
        let prev = w.checked_sub(1).map(|v| steps[v]);
        let next = steps.get(w).copied();
        let slides = match (prev, next) {
            (None, None) => false,
            (a, b) => a.unwrap_or(true) && b.unwrap_or(true),
        };
        points[order[w]].slip = if slides {
            SlipState::Slip
        } else {
            SlipState::Stick
        };
    }
}

/// `mu` from the sliding rows, or the violations of a given `mu` (module docs).
fn mu_of(points: &[FrictionalPoint], given: Option<f64>) -> (Option<MuEstimate>, usize) {
    let ratios: Vec<(f64, f64, bool, [f64; 2])> = points
        .iter()
        .filter(|p| p.f > K_SIGMA * p.sigma_f)
        .map(|p| {
            let (r, sd) = p.ratio();
            (r, sd, p.slip == SlipState::Slip, p.dratio_flow)
        })
        .filter(|(r, sd, _, _)| r.is_finite() && sd.is_finite())
        .collect();
    if let Some(mu) = given {
        let tiny = 1e-12;
        let v = ratios
            .iter()
            .filter(|(r, sd, slides, _)| {
                let off = (r - mu) / sd.max(tiny);
                off > K_SIGMA || (*slides && off < -K_SIGMA)
            })
            .count();
        return (None, v);
    }
    let sliding: Vec<(f64, f64)> = ratios
        .iter()
        .filter(|t| t.2)
        .map(|t| (t.0, t.1.max(1e-15)))
        .collect();
    let flow_share: Vec<[f64; 2]> = ratios.iter().filter(|t| t.2).map(|t| t.3).collect();
    if sliding.is_empty() {
        return (None, 0);
    }
    let sw: f64 = sliding.iter().map(|(_, s)| 1.0 / (s * s)).sum();
    let mean = sliding.iter().map(|(r, s)| r / (s * s)).sum::<f64>() / sw;
    let n = sliding.len();
    let chi2_dof = if n > 1 {
        sliding
            .iter()
            .map(|(r, s)| ((r - mean) / s).powi(2))
            .sum::<f64>()
            / (n - 1) as f64
    } else {
        f64::NAN
    };
    let birge = if chi2_dof.is_finite() {
        chi2_dof.sqrt().max(1.0)
    } else {
        1.0
    };
    // the flow's error, shared by every row: d(mu) = sum w_i d(r_i) / sum w per deviation
    let var_flow: f64 = (0..2)
        .map(|a| {
            let g: f64 = sliding
                .iter()
                .zip(&flow_share)
                .map(|((_, s), d)| d[a] / (s * s))
                .sum::<f64>()
                / sw;
            g * g
        })
        .sum();
    (
        Some(MuEstimate {
            value: mean,
            stderr: (birge * birge / sw + var_flow).sqrt(),
            rows: n,
            chi2_dof,
        }),
        0,
    )
}

/// A frictionless reconstruction `rec` of a log whose frictional reconstruction is `fr`: when
/// the log proves friction ([`FrictionEvidence::proves_friction`]), every point's error
/// estimate is widened to cover its distance to the frictional point of the same row (the
/// frictionless points are biased), and the evidence is returned for a warning; otherwise
/// `rec` is left as it is.
pub fn widen_frictionless(
    rec: &mut Reconstruction,
    fr: &FrictionalReconstruction,
) -> Option<FrictionEvidence> {
    let ev = fr.evidence.filter(|e| e.proves_friction())?;
    for p in &mut rec.points {
        if let Some(q) = fr.points.iter().find(|q| q.row == p.row) {
            p.sigma = p.sigma.max((p.x - q.x).hypot(p.y - q.y) + q.sigma);
        }
    }
    Some(ev)
}
