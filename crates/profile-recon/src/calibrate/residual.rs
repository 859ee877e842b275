//! The residuals of a calibration: what each row of a log says about the whisker.
//!
//! Every row's observables are the initial values of the first-order system at the base
//! (`accurate`'s [`BaseOde`](crate::accurate), spec/model.md), so one integration from the
//! base per row gives the whole whisker of that row for trial parameters. With the log in
//! the units of a nominal stiffness, the model's observables are `(Ax, Ay, MA) / lambda`
//! (`lambda = EI / EI_nominal`, [`Model::lambda`]) and `phi0`. Four residuals per row, all zero
//! for the true whisker:
//!
//! - every row: the follicle law [3.21, 3.22], `phi0 - pi/2 + MA c` (`c = 1/k`, 0 rigid);
//! - a pre-contact row (the free whisker under the flow [6.1]): `Ax + q cos alpha`,
//!   `Ay - q sin alpha` and the free-tip moment `m(1)`;
//! - a tip contact (phase A, `s1 = 1`): `m(1)` [6.6], the signed normal distance of the
//!   reconstructed point `r(1)` to the known contour, and `f sin(psi_f - psi_c)` (the contact
//!   force `f (sin psi_f, -cos psi_f)` of [6.8, 6.9] normal to the contour, frictionless);
//! - a tangential contact (phase B, `s1` the root of `m(s1) = 0` tracked from the previous
//!   parameters): the normal distance of `r(s1)`, `f sin(psi_f - psi_c)` and the tangency
//!   `f sin(phi(s1) - psi_f)`.
//!
//! Four residuals of four observables: the row's map from observables to residuals is locally
//! invertible, so the residuals whitened by their covariance under the sensor noise
//! ([`Whitener`], the noise of [`add_noise`](crate::add_noise): independent per column, standard
//! deviation proportional to the column's full scale) have, to first order, the squared norm
//! of the Mahalanobis distance between the measured observables and those the trial whisker
//! predicts at that base position: least squares on them is the maximum-likelihood fit of
//! the output error, without one forward contact solve per row.

use crate::accurate::base_ivp;
use crate::common::NoiseScales;
use crate::observables::ObservableRow;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::{Dop853, OdeSolution};
use bvp_solvers::roots::{brent, RootOptions};
use contact_sim::Profile;
use std::f64::consts::FRAC_PI_2;

/// Residuals per row.
pub const RESIDUALS_PER_ROW: usize = 4;

/// The whisker's own parameters in the form the fit works with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model {
    /// Conicity theta [3.8].
    pub theta: f64,
    /// Cesaro slope A [3.5].
    pub a: f64,
    /// Cesaro offset B [3.5].
    pub b: f64,
    /// Base compliance `c = 1/k` (0: rigid) [3.21, 3.22].
    pub c: f64,
    /// Stiffness ratio `lambda = EI_b / EI_nominal` (1 in a dimensionless log): the log's
    /// forces and moments, in units of the nominal stiffness, are `lambda` times the model's.
    pub lambda: f64,
}

impl Model {
    /// The model of a whisker at the nominal stiffness.
    pub fn of(w: &Whisker) -> Self {
        Model {
            theta: w.theta,
            a: w.a,
            b: w.b,
            c: w.support.compliance(),
            lambda: 1.0,
        }
    }

    /// The whisker (`k = 1/c`, rigid for `c <= 0`).
    pub fn whisker(&self) -> Whisker {
        let k = if self.c > 0.0 {
            1.0 / self.c
        } else {
            f64::INFINITY
        };
        Whisker::new(self.theta, self.a, self.b, k)
    }
}

/// A flow in Cartesian form `(q cos alpha, q sin alpha)`, fitted per log.
pub(crate) fn flow_of(qc: f64, qs: f64) -> FluidLoad {
    let q = qc.hypot(qs);
    FluidLoad {
        q,
        alpha: if q > 0.0 { qs.atan2(qc) } else { 0.0 },
    }
}

/// What a row is and, for phase B, where its contact currently sits on the whisker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RowKind {
    /// The free whisker under the flow.
    Pre,
    /// Tip contact, `s1 = 1`.
    A,
    /// Tangential contact at `s1` (the root of `m` followed from one evaluation to the next).
    B {
        /// The contact arc length.
        s1: f64,
    },
    /// Left out of the fit (a contact force below [`F_MIN_REL`] of the log's largest: a
    /// touch that carries no information on the contour, and a near-double root of `m`).
    Skipped,
}

/// Contact rows with a force below this fraction of the log's largest contact force are
/// left out of the fit ([`RowKind::Skipped`]).
pub const F_MIN_REL: f64 = 1e-3;

/// Rows whose whitener's [`Whitener::degeneracy`] falls below this are left out of the fit
/// (a fold of the contact branch: the snap row).
pub const DEGENERATE: f64 = 1e-6;

/// Largest distance in arc length over which a phase-B root is followed from one evaluation
/// to the next.
const TRACK_SPAN: f64 = 0.25;

/// The evaluation of one row: its residuals, the contact point and the tracked kind.
#[derive(Clone, Copy, Debug)]
pub struct RowResult {
    /// The four residuals (module docs).
    pub r: [f64; RESIDUALS_PER_ROW],
    /// The kind, with `s1` moved to the root found.
    pub kind: RowKind,
    /// Reconstructed contact point `(x, y)` (NaN for pre-contact rows).
    pub point: (f64, f64),
    /// Signed normal distance of the point to the contour (positive inside the obstacle;
    /// NaN for pre-contact rows).
    pub distance: f64,
}

/// Everything a row's evaluation needs besides the row and its kind.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowCtx<'a> {
    pub model: &'a Model,
    /// The flow `(q cos alpha, q sin alpha)` of the row's log.
    pub flow: (f64, f64),
    pub profile: &'a Profile,
    pub integrator: &'a Dop853,
}

/// Signed normal distance of `(x, y)` to the contour `y = g(x)` (first order:
/// `(y - g) / sqrt(1 + g'^2)`, positive inside the obstacle) and the contour angle there.
fn contour_distance(profile: &Profile, x: f64, y: f64) -> (f64, f64) {
    let (g, d, _) = profile.eval(x);
    ((y - g) / (1.0 + d * d).sqrt(), d.atan())
}

/// The residuals of `row` of kind `kind` (module docs); `None` where the trial whisker
/// admits no such row (the integration stopped short, the phase-B root was lost, the point
/// left the contour's domain).
pub(crate) fn row_residuals(
    ctx: &RowCtx<'_>,
    row: &ObservableRow,
    kind: RowKind,
) -> Option<RowResult> {
    let m = ctx.model;
    let obs = ObservableRow {
        x0: row.x0,
        ax: row.ax / m.lambda,
        ay: row.ay / m.lambda,
        ma: row.ma / m.lambda,
        phi0: row.phi0,
    };
    let (qc, qs) = ctx.flow;
    let follicle = obs.phi0 - FRAC_PI_2 + obs.ma * m.c;
    let whisker = Whisker {
        theta: m.theta,
        a: m.a,
        b: m.b,
        ..Whisker::default()
    };
    let flow = flow_of(qc, qs);
    let nan = (f64::NAN, f64::NAN);
    match kind {
        RowKind::Skipped => Some(RowResult {
            r: [0.0; RESIDUALS_PER_ROW],
            kind,
            point: nan,
            distance: f64::NAN,
        }),
        RowKind::Pre | RowKind::A => {
            let sol = base_ivp(&whisker, flow, &obs, ctx.integrator).ok()?;
            if sol.s_end < 1.0 {
                return None;
            }
            let u = &sol.u_end;
            let (phi1, m1, x1, y1) = (u[0], u[1], u[2], u[3]);
            if !(phi1.is_finite() && m1.is_finite()) {
                return None;
            }
            if kind == RowKind::Pre {
                return Some(RowResult {
                    r: [follicle, obs.ax + qc, obs.ay - qs, m1],
                    kind,
                    point: nan,
                    distance: f64::NAN,
                });
            }
            let (fa, fb) = (-obs.ax - qc, obs.ay - qs);
            let (dist, psi_c) = contour_distance(ctx.profile, x1, y1);
            let normal = fa * psi_c.cos() - fb * psi_c.sin();
            let r = [follicle, m1, dist, normal];
            r.iter().all(|v| v.is_finite()).then_some(RowResult {
                r,
                kind,
                point: (x1, y1),
                distance: dist,
            })
        }
        RowKind::B { s1 } => {
            let dense = Dop853 {
                dense: true,
                lazy_dense: false,
                ..ctx.integrator.clone()
            };
            let sol = base_ivp(&whisker, flow, &obs, &dense).ok()?;
            let root = track_root(&sol, s1)?;
            let mut u = [0.0; 4];
            if !sol.eval_into(root, &mut u) {
                return None;
            }
            let (phi, x, y) = (u[0], u[2], u[3]);
            let (fa, fb) = (-obs.ax - qc * root, obs.ay - qs * root);
            let (dist, psi_c) = contour_distance(ctx.profile, x, y);
            let normal = fa * psi_c.cos() - fb * psi_c.sin();
            let tangency = fb * phi.sin() - fa * phi.cos();
            let r = [follicle, dist, normal, tangency];
            r.iter().all(|v| v.is_finite()).then_some(RowResult {
                r,
                kind: RowKind::B { s1: root },
                point: (x, y),
                distance: dist,
            })
        }
    }
}

/// Options of the root searches on the dense output.
const ROOT_OPTS: RootOptions = RootOptions {
    xtol: 1e-15,
    ftol: 0.0,
    max_iter: 200,
};

/// `m` on the dense output (NaN outside).
fn m_at(sol: &OdeSolution, s: f64) -> f64 {
    let mut u = [0.0; 4];
    if sol.eval_into(s, &mut u) {
        u[1]
    } else {
        f64::NAN
    }
}

/// The root of `m` on `(0, 1)` nearest to `guess`, within [`TRACK_SPAN`]: brackets grown
/// outwards from the guess on both sides.
fn track_root(sol: &OdeSolution, guess: f64) -> Option<f64> {
    let end = sol.s_end.min(1.0);
    let g = guess.clamp(1e-9, end - 1e-12);
    let mg = m_at(sol, g);
    if mg == 0.0 {
        return Some(g);
    }
    if !mg.is_finite() {
        return None;
    }
    let mut width = 1e-4;
    let (mut lo, mut hi) = (g, g);
    let (mut mlo, mut mhi) = (mg, mg);
    while width <= TRACK_SPAN {
        let nlo = (g - width).max(1e-12);
        let nhi = (g + width).min(end);
        let (a, b) = (m_at(sol, nlo), m_at(sol, nhi));
        // the nearer of the two sign changes
        let left = a.is_finite() && a.signum() != mlo.signum();
        let right = b.is_finite() && b.signum() != mhi.signum();
        let found = match (left, right) {
            (true, _) => brent(
                |s| Ok::<_, bvp_solvers::BvpError>(m_at(sol, s)),
                nlo,
                lo,
                &ROOT_OPTS,
            )
            .ok(),
            (false, true) => brent(
                |s| Ok::<_, bvp_solvers::BvpError>(m_at(sol, s)),
                hi,
                nhi,
                &ROOT_OPTS,
            )
            .ok(),
            _ => None,
        };
        if let Some(r) = found {
            return (r.x > 0.0 && r.x < 1.0).then_some(r.x);
        }
        (lo, hi, mlo, mhi) = (nlo, nhi, a, b);
        width *= 2.0;
    }
    None
}

/// Every root of `m` on `(0, 1)` of one base integration (sign changes on each step cut in
/// four, then Brent): the phase-B hypotheses of a row.
pub(crate) fn all_roots(sol: &OdeSolution) -> Vec<f64> {
    let mut roots = Vec::new();
    let pts = sol.step_points();
    let mut prev: Option<(f64, f64)> = None;
    for w in pts.windows(2) {
        for k in 0..4 {
            let s = w[0] + (w[1] - w[0]) * (k + 1) as f64 / 4.0;
            let m = m_at(sol, s);
            if let Some((sp, mp)) = prev {
                if mp != 0.0 && m.is_finite() && m.signum() != mp.signum() {
                    if let Ok(r) = brent(
                        |t| Ok::<_, bvp_solvers::BvpError>(m_at(sol, t)),
                        sp,
                        s,
                        &ROOT_OPTS,
                    ) {
                        if r.x > 0.0 && r.x < 1.0 {
                            roots.push(r.x);
                        }
                    }
                }
            }
            prev = Some((s, m));
        }
    }
    roots
}

/// The covariance square root of a row's residuals under unit relative noise:
/// `C = J D J^T` with `J = d r / d(Ax, Ay, MA, phi0)` (finite differences) and
/// `D = diag(scale_j^2)`; the whitened residuals are `L^-1 r` with `C = L L^T`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Whitener {
    /// Lower-triangular Cholesky factor `L` of `C`.
    pub l: [[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW],
    /// The smallest pivot of the correlation matrix of `C` (1: independent residuals; near
    /// 0: the row's residuals are nearly dependent under the noise, as at a fold of the
    /// contact branch where the whisker snaps off, and the linearised whitening fails).
    pub degeneracy: f64,
    /// The row's residual Jacobian `R = d r / d u` in the noise-scaled observables
    /// `u_j = o_j / scale_j` and the orthogonal `Q = L^-1 R` (`R R^T = C = L L^T`), for the
    /// projection ([`projected`]); `None` if `R` is singular (a column without noise).
    pub map: Option<RowMap>,
}

/// The linear map of a row's observables to its residuals (see [`Whitener::map`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowMap {
    /// `R^-1`.
    pub r_inv: [[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW],
    /// `Q = L^-1 R`.
    pub q: [[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW],
}

impl Whitener {
    /// The identity (a skipped row).
    pub fn identity() -> Self {
        let mut l = [[0.0; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW];
        for (i, row) in l.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        Whitener {
            l,
            degeneracy: 1.0,
            map: None,
        }
    }

    /// `L^-1 r` by forward substitution.
    pub fn apply(&self, r: &[f64; RESIDUALS_PER_ROW]) -> [f64; RESIDUALS_PER_ROW] {
        let mut z = [0.0; RESIDUALS_PER_ROW];
        for i in 0..RESIDUALS_PER_ROW {
            let s: f64 = (0..i).map(|j| self.l[i][j] * z[j]).sum();
            z[i] = (r[i] - s) / self.l[i][i];
        }
        z
    }

    /// The standard deviation of residual `i` at unit relative noise.
    pub fn sd(&self, i: usize) -> f64 {
        (0..=i).map(|j| self.l[i][j].powi(2)).sum::<f64>().sqrt()
    }
}

/// The [`Whitener`] of `row` at `ctx` (`None` if a perturbed row cannot be evaluated).
// `j` indexes the observables in the scales, the perturbation and the Jacobian's columns
#[allow(clippy::needless_range_loop)]
pub(crate) fn whitener(
    ctx: &RowCtx<'_>,
    row: &ObservableRow,
    base: &RowResult,
    scales: &NoiseScales,
) -> Option<Whitener> {
    if base.kind == RowKind::Skipped {
        return Some(Whitener::identity());
    }
    let n = RESIDUALS_PER_ROW;
    let mut jac = [[0.0; 4]; RESIDUALS_PER_ROW];
    for j in 0..4 {
        let sc = scales.0[j];
        if sc == 0.0 {
            continue;
        }
        let h = 1e-6 * sc;
        let mut moved = *row;
        match j {
            0 => moved.ax += h,
            1 => moved.ay += h,
            2 => moved.ma += h,
            _ => moved.phi0 += h,
        }
        let e = row_residuals(ctx, &moved, base.kind)?;
        for i in 0..n {
            jac[i][j] = (e.r[i] - base.r[i]) / h * sc;
        }
    }
    let mut c = [[0.0; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW];
    for i in 0..n {
        for k in 0..n {
            c[i][k] = (0..4).map(|j| jac[i][j] * jac[k][j]).sum();
        }
    }
    let trace: f64 = (0..n).map(|i| c[i][i]).sum();
    let ridge = 1e-14 * trace + f64::MIN_POSITIVE;
    let mut w = cholesky(&c, ridge)?;
    w.degeneracy = degeneracy(&c);
    w.map = invert(&jac).map(|r_inv| {
        let mut q = [[0.0; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW];
        for j in 0..n {
            let col = w.apply(&[jac[0][j], jac[1][j], jac[2][j], jac[3][j]]);
            for i in 0..n {
                q[i][j] = col[i];
            }
        }
        RowMap { r_inv, q }
    });
    Some(w)
}

/// `m^-1` by Gauss-Jordan elimination with partial pivoting (`None` when a pivot falls
/// below `1e-12` of the largest entry).
#[allow(clippy::needless_range_loop)]
fn invert(
    m: &[[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW],
) -> Option<[[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW]> {
    let n = RESIDUALS_PER_ROW;
    let big = m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    let mut a = *m;
    let mut inv = [[0.0; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for col in 0..n {
        let piv = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[piv][col].abs() < 1e-12 * big {
            return None;
        }
        a.swap(col, piv);
        inv.swap(col, piv);
        let d = a[col][col];
        for j in 0..n {
            a[col][j] /= d;
            inv[col][j] /= d;
        }
        for i in 0..n {
            if i != col {
                let f = a[i][col];
                for j in 0..n {
                    a[i][j] -= f * a[col][j];
                    inv[i][j] -= f * inv[col][j];
                }
            }
        }
    }
    Some(inv)
}

/// `m v`.
fn mul(
    m: &[[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW],
    v: &[f64; RESIDUALS_PER_ROW],
) -> [f64; RESIDUALS_PER_ROW] {
    let mut out = [0.0; RESIDUALS_PER_ROW];
    for (o, row) in out.iter_mut().zip(m) {
        *o = row.iter().zip(v).map(|(a, b)| a * b).sum();
    }
    out
}

/// The whitened residuals of `row` projected onto the model (the output error).
///
/// The four residuals of a row are four equations in its four noisy observables, so for
/// given parameters the observables the model admits at that base position, `o*`, are
/// isolated: `r(o*) = 0`. The maximum-likelihood residual is the whitened distance
/// `(o - o*) / scale`; [`Whitener::apply`] gives it to first order (`L^-1 r`, the first
/// Newton step from `o`), with an error of the order of the noise squared that does not
/// average out over rows (a bias of the estimate that outgrows its standard error on long
/// logs at high noise). `steps` chord-Newton steps with the row's frozen `R` move `o` onto
/// `r = 0` (each step one integration) and give `-Q delta`, `delta = (o* - o) / scale`:
/// equal to `L^-1 r` to first order, exact as the steps converge. A step whose integration
/// fails, or a row without [`Whitener::map`], keeps the first-order residual.
pub(crate) fn projected(
    ctx: &RowCtx<'_>,
    row: &ObservableRow,
    res: &RowResult,
    w: &Whitener,
    scales: &NoiseScales,
    steps: usize,
) -> [f64; RESIDUALS_PER_ROW] {
    let first = w.apply(&res.r);
    let Some(map) = w.map.filter(|_| steps > 0 && res.kind != RowKind::Skipped) else {
        return first;
    };
    let mut delta = mul(&map.r_inv, &res.r).map(|v| -v);
    let mut kind = res.kind;
    for _ in 0..steps {
        let sc = &scales.0;
        let moved = ObservableRow {
            x0: row.x0,
            ax: row.ax + sc[0] * delta[0],
            ay: row.ay + sc[1] * delta[1],
            ma: row.ma + sc[2] * delta[2],
            phi0: row.phi0 + sc[3] * delta[3],
        };
        let Some(e) = row_residuals(ctx, &moved, kind) else {
            return first;
        };
        kind = e.kind;
        let step = mul(&map.r_inv, &e.r);
        for (d, s) in delta.iter_mut().zip(step) {
            *d -= s;
        }
    }
    let z = mul(&map.q, &delta).map(|v| -v);
    if z.iter().all(|v| v.is_finite()) {
        z
    } else {
        first
    }
}

/// The smallest Cholesky pivot (squared) of the correlation matrix of `c`: 1 for
/// uncorrelated residuals, 0 when one is a combination of the others.
fn degeneracy(c: &[[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW]) -> f64 {
    let n = RESIDUALS_PER_ROW;
    let d: Vec<f64> = (0..n)
        .map(|i| c[i][i].max(f64::MIN_POSITIVE).sqrt())
        .collect();
    let mut r = [[0.0; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW];
    for i in 0..n {
        for k in 0..n {
            r[i][k] = c[i][k] / (d[i] * d[k]);
        }
    }
    match cholesky(&r, 0.0) {
        Some(w) if w.degeneracy.is_finite() => {
            (0..n).map(|i| w.l[i][i].powi(2)).fold(1.0, f64::min)
        }
        _ => 0.0,
    }
}

/// Cholesky factor of `c + ridge I`, with the ridge raised until it succeeds.
fn cholesky(c: &[[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW], ridge: f64) -> Option<Whitener> {
    let n = RESIDUALS_PER_ROW;
    let mut ridge = ridge;
    for _ in 0..40 {
        let mut l = [[0.0; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW];
        let mut ok = true;
        for i in 0..n {
            for j in 0..=i {
                let s: f64 = (0..j).map(|k| l[i][k] * l[j][k]).sum();
                if i == j {
                    let d = c[i][i] + ridge - s;
                    if !(d > 0.0 && d.is_finite()) {
                        ok = false;
                        break;
                    }
                    l[i][i] = d.sqrt();
                } else {
                    l[i][j] = (c[i][j] - s) / l[j][j];
                }
            }
            if !ok {
                break;
            }
        }
        if ok {
            return Some(Whitener {
                l,
                degeneracy: 1.0,
                map: None,
            });
        }
        ridge = (ridge * 100.0).max(1e-300);
    }
    None
}

/// The hypotheses of a contact row at `ctx`: tip contact (if the integration reaches the tip)
/// and every root of `m` (phase B), each with its residuals; the phase of the row is the
/// hypothesis with the smallest whitened residual ([`judge`]).
pub(crate) fn hypotheses(ctx: &RowCtx<'_>, row: &ObservableRow) -> Vec<RowResult> {
    let m = ctx.model;
    let obs = ObservableRow {
        ax: row.ax / m.lambda,
        ay: row.ay / m.lambda,
        ma: row.ma / m.lambda,
        ..*row
    };
    let whisker = Whisker {
        theta: m.theta,
        a: m.a,
        b: m.b,
        ..Whisker::default()
    };
    let dense = Dop853 {
        dense: true,
        lazy_dense: false,
        ..ctx.integrator.clone()
    };
    let Ok(sol) = base_ivp(&whisker, flow_of(ctx.flow.0, ctx.flow.1), &obs, &dense) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    if sol.s_end >= 1.0 {
        out.extend(row_residuals(ctx, row, RowKind::A));
    }
    for s in all_roots(&sol) {
        out.extend(row_residuals(ctx, row, RowKind::B { s1: s }));
    }
    out
}

/// The phase of a contact row at `ctx`: among its [`hypotheses`], the one whose residuals,
/// whitened, are smallest (`None` without any).
pub(crate) fn judge(
    ctx: &RowCtx<'_>,
    row: &ObservableRow,
    scales: &NoiseScales,
) -> Option<RowResult> {
    let hyps = hypotheses(ctx, row);
    if hyps.len() <= 1 {
        return hyps.into_iter().next();
    }
    hyps.into_iter()
        .filter_map(|h| {
            let w = whitener(ctx, row, &h, scales)?;
            let z = w.apply(&h.r);
            Some((z.iter().map(|v| v * v).sum::<f64>(), h))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, h)| h)
}

/// The contact force of `row` at the tip under the flow, `|(-Ax - qc, Ay - qs)|` (model
/// units): what decides [`RowKind::Skipped`].
pub(crate) fn tip_force(model: &Model, flow: (f64, f64), row: &ObservableRow) -> f64 {
    (-row.ax / model.lambda - flow.0).hypot(row.ay / model.lambda - flow.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whitener_inverts_its_factor() {
        let c = [
            [4.0, 1.0, 0.0, 0.5],
            [1.0, 3.0, 0.2, 0.0],
            [0.0, 0.2, 2.0, 0.1],
            [0.5, 0.0, 0.1, 1.0],
        ];
        let w = cholesky(&c, 0.0).unwrap();
        // L L^T = C
        for (i, ci) in c.iter().enumerate() {
            for (k, cik) in ci.iter().enumerate() {
                let v: f64 = (0..4).map(|j| w.l[i][j] * w.l[k][j]).sum();
                assert!((v - cik).abs() < 1e-12);
            }
        }
        let z = w.apply(&[w.l[0][0], w.l[1][0], w.l[2][0], w.l[3][0]]);
        assert!((z[0] - 1.0).abs() < 1e-14 && z[1..].iter().all(|v| v.abs() < 1e-14));
        assert!((w.sd(0) - 2.0).abs() < 1e-14);
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn invert_gives_the_inverse_and_refuses_a_singular_matrix() {
        let m = [
            [0.0, 2.0, 1.0, 0.0],
            [1.0, 0.5, 0.0, 3.0],
            [4.0, 0.0, 1.0, 1.0],
            [0.0, 1.0, 0.0, 2.0],
        ];
        let inv = invert(&m).unwrap();
        for i in 0..4 {
            for j in 0..4 {
                let v: f64 = (0..4).map(|k| m[i][k] * inv[k][j]).sum();
                assert!(
                    (v - f64::from(u8::from(i == j))).abs() < 1e-14,
                    "{i} {j} {v}"
                );
            }
        }
        let mut sing = m;
        sing[3] = [0.0; 4];
        assert!(invert(&sing).is_none());
    }

    /// A pre-contact row moved off the model by `d` (in units of the noise scales): the
    /// projected residual has the norm `|d|` of that move (the exact output error, to the
    /// third order in `d`), the first-order one only to the second.
    #[test]
    fn projection_recovers_the_distance_to_the_model() {
        let truth = Whisker::new(0.4, 0.8, -0.6, 10.0);
        let flow = FluidLoad { q: 3.0, alpha: 0.3 };
        let scene = beam_model::Scene::new(truth, beam_model::Loads::fluid(flow.q, flow.alpha));
        let base = beam_model::solve(&scene, &beam_model::Method::default())
            .unwrap()
            .base;
        let exact = ObservableRow {
            x0: 0.0,
            ax: base.ax,
            ay: base.ay,
            ma: base.ma,
            phi0: base.phi0,
        };
        let scales = NoiseScales([3.0, 1.0, base.ma.abs(), 1.5]);
        let model = Model::of(&truth);
        let integrator = Dop853::new(1e-13, 1e-13);
        let profile = Profile::g1();
        let ctx = RowCtx {
            model: &model,
            flow: (flow.q * flow.alpha.cos(), flow.q * flow.alpha.sin()),
            profile: &profile,
            integrator: &integrator,
        };
        for eps in [1e-2, 1e-3] {
            let d = [0.6 * eps, -0.3 * eps, 0.7 * eps, -0.2 * eps];
            let row = ObservableRow {
                ax: exact.ax + scales.0[0] * d[0],
                ay: exact.ay + scales.0[1] * d[1],
                ma: exact.ma + scales.0[2] * d[2],
                phi0: exact.phi0 + scales.0[3] * d[3],
                ..exact
            };
            let res = row_residuals(&ctx, &row, RowKind::Pre).unwrap();
            let w = whitener(&ctx, &row, &res, &scales).unwrap();
            let norm = |z: [f64; 4]| z.iter().map(|v| v * v).sum::<f64>().sqrt();
            let want = norm(d);
            let first = (norm(w.apply(&res.r)) - want).abs() / want;
            let exact_err = (norm(projected(&ctx, &row, &res, &w, &scales, 2)) - want).abs() / want;
            assert!(
                exact_err < 0.1 * eps * eps && first > 0.1 * eps,
                "{eps}: {exact_err:e} vs {first:e}"
            );
        }
    }

    #[test]
    fn flow_round_trip() {
        let f = flow_of(3.0 * 0.3f64.cos(), 3.0 * 0.3f64.sin());
        assert!((f.q - 3.0).abs() < 1e-14 && (f.alpha - 0.3).abs() < 1e-14);
        assert_eq!(flow_of(0.0, 0.0).alpha, 0.0);
    }

    #[test]
    fn model_whisker_round_trip() {
        let w = Whisker::new(0.5, 0.2, -0.3, 20.0);
        let m = Model::of(&w);
        assert_eq!(m.whisker(), w);
        assert_eq!(Model::of(&Whisker::uniform()).whisker(), Whisker::uniform());
    }
}
