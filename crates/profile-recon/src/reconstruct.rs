//! Contour reconstruction from the observables (thesis 6.2).
//!
//! Method `accurate` (spec/model.md, last section): the observables ARE the initial values of
//! the first-order system at the base, `(x0, 0, phi0, m(0) = -MA)`, once the contact force is
//! known, and force balance gives it for any hypothesis on `s1` [6.8, 6.9]:
//! `f sin psi = -Ax - q s1`, `f cos psi = Ay`.
//! - Phase A (s1 = 1): one integration from the base to the tip; consistent when `m(1) = 0`
//!   and `phi(1) > psi`; the contact point is `r(1)`.
//! - Phase B: `s1` is the root of `m(s1; s1) = 0` (a scalar root, secant then Brent);
//!   consistent when `phi(s1) = psi`; the contact point is `r(s1)`.
//!
//! The phase is decided from these residuals themselves, not from the slope-jump heuristic of
//! the thesis [6.10]. With noisy observables no hypothesis is exactly consistent: the one with
//! the smaller residual is kept and its residual reported (graceful degradation); with
//! `consistency_tol` set, a row whose best residual exceeds it is an error naming the row.

use crate::error::{ReconError, Result};
use crate::identify::{identify, Identification};
use crate::observables::ObservableRow;
use beam_model::equations::{Sensitivities, WhiskerOde};
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Dop853;
use bvp_solvers::roots::{brent, RootOptions};
use contact_sim::phase::contact_loads;
use contact_sim::Phase;
use serde::{Deserialize, Serialize};

/// Reconstruction method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ReconMethod {
    /// Initial-value route from the base (spec/model.md), ~1e-12.
    Accurate,
    /// The thesis's five equations [6.5-6.9] around FDM solves with a trust region and the
    /// slope-jump phase rule [6.10].
    Thesis,
}

impl ReconMethod {
    /// The CLI name.
    pub fn name(&self) -> &'static str {
        match self {
            ReconMethod::Accurate => "accurate",
            ReconMethod::Thesis => "thesis",
        }
    }
}

/// Settings of a reconstruction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReconSettings {
    /// The method.
    pub method: ReconMethod,
    /// Integrator tolerance (accurate) .
    pub tol: f64,
    /// Smallest jump of the observables treated as the start of contact.
    pub noise_floor: f64,
    /// Fail on a row whose best residual exceeds this (None: never fail, report residuals).
    pub consistency_tol: Option<f64>,
}

impl Default for ReconSettings {
    fn default() -> Self {
        ReconSettings {
            method: ReconMethod::Accurate,
            tol: 1e-12,
            noise_floor: 1e-9,
            consistency_tol: Some(1e-6),
        }
    }
}

/// One reconstructed contour point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReconPoint {
    /// 0-based index of the input row.
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
    /// Consistency residual of the chosen hypothesis (A: |m(1)|, B: |phi(s1) - psi|).
    pub residual: f64,
    /// Integrations (accurate) or solver iterations (thesis) spent on the row.
    pub evaluations: usize,
}

/// A reconstructed contour.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reconstruction {
    /// The identification (q given or identified, contact start).
    pub identification: Identification,
    /// Whether q was given rather than identified.
    pub q_given: bool,
    /// One point per contact row.
    pub points: Vec<ReconPoint>,
}

/// End state of an integration from the base.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Forward {
    pub phi: f64,
    pub m: f64,
    pub x: f64,
    pub y: f64,
    pub f: f64,
    pub psi: f64,
}

/// Contact force and angle for a hypothesis on s1 [6.8, 6.9].
pub(crate) fn force(row: &ObservableRow, q: f64, s1: f64) -> (f64, f64) {
    let a = -row.ax - q * s1;
    let b = row.ay;
    (a.hypot(b), a.atan2(b))
}

/// Integrates the first-order system from the base (initial values = observables) to s1.
pub(crate) fn forward(
    whisker: &Whisker,
    q: f64,
    row: &ObservableRow,
    s1: f64,
    integrator: &Dop853,
) -> Result<Forward> {
    let (f, psi) = force(row, q, s1);
    let loads = contact_loads(FluidLoad { q, alpha: 0.0 }, psi, f, s1);
    let ode = WhiskerOde::new(*whisker, loads, 0.0, Sensitivities::None);
    let u0 = [row.phi0, -row.ma, row.x0, 0.0];
    let sol = integrator.integrate(&ode, 0.0, s1, &u0)?;
    let u = &sol.u_end;
    Ok(Forward {
        phi: u[0],
        m: u[1],
        x: u[2],
        y: u[3],
        f,
        psi,
    })
}

/// Contact force below which the contact angle is treated as unobservable.
const F_ANGLE: f64 = 1e-6;

/// Phase-B consistency `|phi(s1) - psi|`, weighted by `min(1, f / F_ANGLE)`.
fn angle_residual(fw: &Forward) -> f64 {
    (fw.phi - fw.psi).abs() * (fw.f / F_ANGLE).min(1.0)
}

struct RowSolver<'a> {
    whisker: &'a Whisker,
    q: f64,
    integrator: Dop853,
}

impl RowSolver<'_> {
    /// A reconstructed point from the forward integration `fw` to `s1` and the verdict
    /// `(phase, residual, evaluations)`.
    fn point(
        &self,
        i: usize,
        row: &ObservableRow,
        s1: f64,
        fw: &Forward,
        (phase, residual, evaluations): (Phase, f64, usize),
    ) -> ReconPoint {
        ReconPoint {
            row: i,
            x0: row.x0,
            x: fw.x,
            y: fw.y,
            s1,
            f: fw.f,
            psi: fw.psi,
            phase,
            residual,
            evaluations,
        }
    }

    /// Phase B: the root of m(s1; s1) near `guess` (secant), else all roots on (0, 1) by a
    /// scan and Brent, keeping the one with the smallest |phi(s1) - psi|; without any root
    /// (noise) the least-squares point of the scan.
    fn phase_b(
        &self,
        row: &ObservableRow,
        guess: f64,
        second: f64,
    ) -> Result<(f64, Forward, f64, usize)> {
        let mut evals = 0;
        let mut eval = |s: f64| -> Result<Forward> {
            evals += 1;
            forward(self.whisker, self.q, row, s, &self.integrator)
        };
        // secant from the guess
        let (mut s0, mut s1) = (second.clamp(1e-3, 1.0), guess.clamp(1e-3, 1.0));
        if s0 == s1 {
            s0 = (s1 - 1e-3).max(1e-3);
        }
        let mut m0 = eval(s0)?.m;
        for _ in 0..30 {
            let fw = eval(s1)?;
            if fw.m.abs() <= 1e-14 || (s1 - s0).abs() <= 1e-10 {
                if s1 > 0.0 && s1 <= 1.0 {
                    let r = angle_residual(&fw);
                    if r <= 1e-6 {
                        return Ok((s1, fw, r, evals));
                    }
                }
                break;
            }
            let d = fw.m - m0;
            if d == 0.0 || !d.is_finite() {
                break;
            }
            let next = s1 - fw.m * (s1 - s0) / d;
            if !(next > 1e-3 && next <= 1.0 + 1e-12) {
                break;
            }
            s0 = s1;
            m0 = fw.m;
            s1 = next.min(1.0);
        }
        // scan
        let n = 60;
        let grid: Vec<f64> = (1..=n).map(|k| k as f64 / n as f64).collect();
        let mut vals = Vec::with_capacity(n);
        for &s in &grid {
            vals.push(eval(s)?);
        }
        let mut best: Option<(f64, Forward, f64)> = None;
        for k in 1..n {
            let (a, b) = (grid[k - 1], grid[k]);
            if vals[k - 1].m.signum() == vals[k].m.signum() {
                continue;
            }
            let opts = RootOptions {
                xtol: 1e-15,
                ftol: 0.0,
                max_iter: 100,
            };
            let root = brent(
                |s| -> Result<f64> {
                    Ok(forward(self.whisker, self.q, row, s, &self.integrator)?.m)
                },
                a,
                b,
                &opts,
            )?;
            let fw = eval(root.x)?;
            let r = angle_residual(&fw);
            if best.as_ref().is_none_or(|(_, _, br)| r < *br) {
                best = Some((root.x, fw, r));
            }
        }
        if let Some((s, fw, r)) = best {
            return Ok((s, fw, r, evals));
        }
        // no root: least squares over the scan
        let (k, _) = vals
            .iter()
            .enumerate()
            .map(|(k, v)| (k, v.m * v.m + (v.phi - v.psi).powi(2)))
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        let fw = vals[k];
        let r = (fw.m * fw.m + (fw.phi - fw.psi).powi(2)).sqrt();
        Ok((grid[k], fw, r, evals))
    }

    /// One row; `prev` are the points reconstructed so far (for the s1 predictor).
    fn row(&self, i: usize, row: &ObservableRow, prev: &[ReconPoint]) -> Result<ReconPoint> {
        let a = forward(self.whisker, self.q, row, 1.0, &self.integrator)?;
        let ra = a.m.abs();
        // As f -> 0 (a release) the contact angle psi = atan2(-Ax - q s1, Ay) is no longer
        // observable; the angle conditions are then weighted by f / F_ANGLE.
        let a_valid = a.phi >= a.psi - 1e-9 || a.f < F_ANGLE;
        if ra <= 1e-9 && a_valid {
            return Ok(self.point(i, row, 1.0, &a, (Phase::A, ra, 1)));
        }
        // secant start: the last two phase-B rows extrapolated linearly, else the last one
        let (guess, second) = match prev {
            [.., p, q] if p.phase == Phase::B && q.phase == Phase::B => {
                let pred = (2.0 * q.s1 - p.s1).clamp(1e-3, 1.0);
                (pred, q.s1)
            }
            [.., q] if q.phase == Phase::B => (q.s1, q.s1 - 1e-3),
            _ => (1.0 - 1e-6, 1.0 - 1e-3),
        };
        let (s1, b, rb, evals) = self.phase_b(row, guess, second)?;
        if a_valid && ra <= rb {
            Ok(self.point(i, row, 1.0, &a, (Phase::A, ra, evals + 1)))
        } else {
            Ok(self.point(i, row, s1, &b, (Phase::B, rb, evals + 1)))
        }
    }
}

/// Reconstructs the contour from an observables log: identifies q (unless given) and the
/// contact start, then one contact point per contact row.
pub fn reconstruct(
    whisker: &Whisker,
    rows: &[ObservableRow],
    q: Option<f64>,
    settings: &ReconSettings,
) -> Result<Reconstruction> {
    whisker.validate()?;
    if let Some(q) = q {
        if !(q.is_finite() && q >= 0.0) {
            return Err(ReconError::InvalidParameter {
                name: "q",
                value: q,
                reason: "the fluid load must be finite and >= 0",
            });
        }
    }
    let mut ident = match (identify(whisker, rows, settings.noise_floor), q) {
        (Ok(id), _) => id,
        (Err(ReconError::NoPreContactRows), Some(q)) => Identification {
            q,
            first_contact_row: 0,
            threshold: settings.noise_floor,
            model_mismatch: f64::NAN,
            free_tip: (f64::NAN, f64::NAN, f64::NAN),
        },
        (Err(e), _) => return Err(e),
    };
    if let Some(q) = q {
        ident.q = q;
    }
    let contact = &rows[ident.first_contact_row..];
    let points = match settings.method {
        ReconMethod::Accurate => {
            let solver = RowSolver {
                whisker,
                q: ident.q,
                integrator: Dop853::new(settings.tol, settings.tol),
            };
            let mut points: Vec<ReconPoint> = Vec::with_capacity(contact.len());
            for (k, row) in contact.iter().enumerate() {
                let i = ident.first_contact_row + k;
                let p = solver.row(i, row, &points)?;
                if let Some(tol) = settings.consistency_tol {
                    if p.residual > tol {
                        return Err(ReconError::InconsistentRow {
                            row: i + 1,
                            x0: row.x0,
                            residual: p.residual,
                            phase: if p.phase == Phase::A { 'A' } else { 'B' },
                        });
                    }
                }
                points.push(p);
            }
            points
        }
        ReconMethod::Thesis => crate::thesis::reconstruct_rows(
            whisker,
            ident.q,
            rows,
            ident.first_contact_row,
            settings,
        )?,
    };
    Ok(Reconstruction {
        identification: ident,
        q_given: q.is_some(),
        points,
    })
}

/// The quality measure [6.11]: `e = |y_rec - g(x_rec)|` per reconstructed point.
pub fn contour_error(points: &[ReconPoint], profile: &contact_sim::Profile) -> Vec<f64> {
    points
        .iter()
        .map(|p| (p.y - profile.y(p.x)).abs())
        .collect()
}
