//! The whitening of a row's residuals by their covariance under the sensor noise
//! ([`Whitener`]: the finite-difference Jacobian of the residuals in the observables and its
//! Cholesky factor, by [`bvp_solvers::dense`]), the projection of a noisy
//! row onto the model (`projected`) and the phase of a contact row by its smallest whitened
//! residual (`judge`).

use super::residual::{
    hypotheses, row_residuals, ContactLaw, RowCtx, RowKind, RowResult, RESIDUALS_PER_ROW,
};
use crate::common::NoiseScales;
use crate::observables::ObservableRow;
use bvp_solvers::dense;

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
    /// projection (`projected`); `None` if `R` is singular (a column without noise).
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
        let mut z = *r;
        dense::forward_substitute(self.l.as_flattened(), &mut z);
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
    if ctx.law == ContactLaw::Stick && !matches!(ctx.profile, contact_sim::Profile::Peg { .. }) {
        if let Some(ix) = ContactLaw::index(base.kind) {
            orthogonal_row(&mut jac, ix);
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
    w.map = dense::inverse(&jac).map(|r_inv| {
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

/// Replaces row `ix` of a row's residual Jacobian (a stick row's law residual, identically
/// 0: [`ContactLaw::Stick`]) by a direction orthogonal to the other three rows, of their mean
/// norm: the whitened law residual is then 0 and independent of the others, so the row
/// counts by its three real conditions (its whitened norm the distance to their manifold)
/// and its covariance stays regular.
// index loops over a 4 x 4 matrix read as Gram-Schmidt
#[allow(clippy::needless_range_loop)]
pub(crate) fn orthogonal_row(jac: &mut [[f64; 4]; RESIDUALS_PER_ROW], ix: usize) {
    let mut basis: Vec<[f64; 4]> = Vec::new();
    let mut norm_sum = 0.0;
    for (i, row) in jac.iter().enumerate() {
        if i == ix {
            continue;
        }
        let n0 = row.iter().map(|v| v * v).sum::<f64>().sqrt();
        norm_sum += n0;
        let mut v = *row;
        for b in &basis {
            let d: f64 = (0..4).map(|k| v[k] * b[k]).sum();
            for k in 0..4 {
                v[k] -= d * b[k];
            }
        }
        let nv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if nv > 1e-12 * n0.max(f64::MIN_POSITIVE) {
            basis.push(v.map(|x| x / nv));
        }
    }
    // the unit vector with the largest part outside the span
    let mut best = [0.0; 4];
    let mut best_n = -1.0;
    for j in 0..4 {
        let mut v = [0.0; 4];
        v[j] = 1.0;
        for b in &basis {
            let d = b[j];
            for k in 0..4 {
                v[k] -= d * b[k];
            }
        }
        let nv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if nv > best_n {
            best_n = nv;
            best = v.map(|x| x / nv);
        }
    }
    let scale = (norm_sum / 3.0).max(f64::MIN_POSITIVE);
    jac[ix] = best.map(|x| x * scale);
}

/// The chord-Newton iteration of `projected` stops when a step is below this fraction of
/// the distance (the output error then known to about this relative accuracy).
pub const PROJECTION_TOL: f64 = 1e-6;

/// The whitened residuals of `row` projected onto the model (the output error).
///
/// The four residuals of a row are four equations in its four noisy observables, so for
/// given parameters the observables the model admits at that base position, `o*`, are
/// isolated: `r(o*) = 0`. The maximum-likelihood residual is the whitened distance
/// `(o - o*) / scale`; [`Whitener::apply`] gives it to first order (`L^-1 r`, the first
/// Newton step from `o`), with an error of the order of the noise squared that does not
/// average out over rows (a bias of the estimate that outgrows its standard error on long
/// logs at high noise). Chord-Newton steps with the row's frozen `R` (at most `steps`, until
/// one is below [`PROJECTION_TOL`] of the distance) move `o` onto `r = 0` (each step one
/// integration) and give `-Q delta`, `delta = (o* - o) / scale`: equal to `L^-1 r` to first
/// order, exact as the steps converge (a slender tip needs more than two at noise 1e-4: with
/// two, case 29 of the battery ended 4-8 standard errors off). A step whose integration
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
    let mut delta = dense::mul_vec(&map.r_inv, &res.r).map(|v| -v);
    let mut kind = res.kind;
    for _ in 0..steps {
        let size = delta.iter().fold(0.0f64, |a, v| a.max(v.abs()));
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
        let step = dense::mul_vec(&map.r_inv, &e.r);
        for (d, s) in delta.iter_mut().zip(step) {
            *d -= s;
        }
        // converged: what is left changes the residual by a negligible part of itself
        if step.iter().all(|v| v.abs() <= PROJECTION_TOL * size) {
            break;
        }
    }
    let z = dense::mul_vec(&map.q, &delta).map(|v| -v);
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

/// Cholesky factor of `c + ridge I` ([`dense::cholesky`]), with the ridge raised until it
/// succeeds.
fn cholesky(c: &[[f64; RESIDUALS_PER_ROW]; RESIDUALS_PER_ROW], ridge: f64) -> Option<Whitener> {
    let mut ridge = ridge;
    for _ in 0..40 {
        let mut a = *c;
        for (i, row) in a.iter_mut().enumerate() {
            row[i] += ridge;
        }
        if let Some(l) = dense::cholesky(&a) {
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

#[cfg(test)]
mod tests {
    use super::super::residual::Model;
    use super::*;
    use beam_model::{FluidLoad, Whisker};
    use bvp_solvers::integrator::Dop853;
    use contact_sim::Profile;

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
            pose: crate::pose::RowPose::TRANSLATE,
            shift: 0.0,
            law: ContactLaw::Normal,
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
}
