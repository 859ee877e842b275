//! `auto`'s fast path: the elastica as a fixed point of its integral form, iterated on
//! Chebyshev points (a spectral Picard iteration).
//!
//! With the internal force known in closed form (`G(s) = F + q (s1 - s) (cos α, −sin α)`,
//! spec/model.md), the first-order system [3.25] integrates to
//!
//! ```text
//! m(s)   = −∫_s^{s1} (G_x sin φ − G_y cos φ) dt          (m(s1) = 0)
//! φ(s)   = φ(0) + ∫_0^s (m / e⁴ + A t + B) dt,  φ(0) = π/2 + m(0)/k
//! ```
//!
//! and `φ ← T(φ)` is iterated from the unloaded shape. The first iterate is linear
//! small-deflection theory (the moment of the loads on the unloaded whisker); each further
//! iterate adds one order in the loads. Where `T` contracts (weak and moderate loads, the
//! regime of a whisker sensing a flow) the iteration converges geometrically to the
//! equilibrium on the branch from zero load, and
//!
//! - the iteration error of the last iterate is bounded by `d c / (1 − c)` (`d` the last
//!   change, `c` the observed contraction, the larger of the last two ratios);
//! - the discretisation error on `N` points is estimated by the difference from the
//!   solution on `2N` points (spectral convergence: the finer one is far better);
//!
//! both in the norm of [`SolveStats::error_estimate`](crate::SolveStats). Where `T` does
//! not contract fast enough, [`solve`] says so and `auto` moves on to shooting.

use std::f64::consts::FRAC_PI_2;
use std::sync::OnceLock;

use crate::equations::MomentLaw;
use crate::scene::Scene;
use crate::solution::{BaseObservables, Elastica, EndState, MethodKind, Solution, SolveStats};

/// Chebyshev points of the second kind on `[0, 1]`, `t_j = (1 − cos(π j / N)) / 2`, with
/// the cumulative integration matrix `Q` (`(Q v)_i = ∫_0^{t_i} p`, `p` the interpolant of
/// `v`) and the barycentric weights.
pub(super) struct Cheb {
    pub(super) n: usize,
    pub(super) t: Vec<f64>,
    q: Vec<f64>,
    w: Vec<f64>,
}

/// Grid sizes tried, coarse to fine.
pub(super) const SIZES: [usize; 6] = [8, 16, 32, 64, 128, 256];

/// The Chebyshev grid with `n` intervals (one of [`SIZES`]), built once.
pub(super) fn cheb(n: usize) -> &'static Cheb {
    static GRIDS: [OnceLock<Cheb>; 6] = [
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
    ];
    let k = SIZES.iter().position(|&s| s == n).unwrap_or(0);
    GRIDS[k].get_or_init(|| Cheb::new(SIZES[k]))
}

impl Cheb {
    fn new(n: usize) -> Self {
        let nf = n as f64;
        let x: Vec<f64> = (0..=n)
            .map(|j| (std::f64::consts::PI * j as f64 / nf).cos())
            .collect();
        let t: Vec<f64> = x.iter().map(|x| (1.0 - x) / 2.0).collect();
        let half = |j: usize| if j == 0 || j == n { 0.5 } else { 1.0 };
        // Column j: the antiderivative of the Lagrange polynomial l_j in Chebyshev form,
        // F_j(x) = sum_k c_k ∫T_k, then Q_ij = (F_j(1) − F_j(x_i)) / 2 (dt = −dx/2).
        let mut q = vec![0.0; (n + 1) * (n + 1)];
        let mut c = vec![0.0; n + 1];
        // d[k]: coefficient of T_k in the antiderivative (k = 0..=n+1).
        let mut d = vec![0.0; n + 2];
        for j in 0..=n {
            for (k, ck) in c.iter_mut().enumerate() {
                *ck = 2.0 / nf
                    * half(j)
                    * half(k)
                    * (std::f64::consts::PI * (k * j) as f64 / nf).cos();
            }
            d.iter_mut().for_each(|v| *v = 0.0);
            for (k, &ck) in c.iter().enumerate() {
                match k {
                    0 => d[1] += ck,
                    1 => d[2] += ck / 4.0,
                    _ => {
                        d[k + 1] += ck / (2.0 * (k + 1) as f64);
                        d[k - 1] -= ck / (2.0 * (k - 1) as f64);
                    }
                }
            }
            let f_at = |xv: f64| -> f64 {
                // Clenshaw-free evaluation: T_k(cos θ) = cos(k θ).
                let th = xv.clamp(-1.0, 1.0).acos();
                d.iter()
                    .enumerate()
                    .map(|(k, &dk)| dk * (k as f64 * th).cos())
                    .sum()
            };
            let f1 = f_at(1.0);
            for (i, &xi) in x.iter().enumerate() {
                q[i * (n + 1) + j] = (f1 - f_at(xi)) / 2.0;
            }
        }
        let w = (0..=n)
            .map(|j| if j % 2 == 0 { half(j) } else { -half(j) })
            .collect();
        Cheb { n, t, q, w }
    }

    /// `out_i = len * ∫_0^{t_i} p` for values `v` at the points.
    fn integrate(&self, v: &[f64], len: f64, out: &mut [f64]) {
        let m = self.n + 1;
        for (i, o) in out.iter_mut().enumerate() {
            let row = &self.q[i * m..(i + 1) * m];
            *o = len * row.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
        }
    }

    /// The barycentric coefficients at `t` (normalised: the interpolant of any `v` is
    /// `sum c_j v_j`), written to `c`.
    fn coefficients(&self, t: f64, c: &mut [f64]) {
        let mut den = 0.0;
        for j in 0..=self.n {
            let d = t - self.t[j];
            if d == 0.0 {
                c.iter_mut().for_each(|v| *v = 0.0);
                c[j] = 1.0;
                return;
            }
            c[j] = self.w[j] / d;
            den += c[j];
        }
        c.iter_mut().for_each(|v| *v /= den);
    }

    /// The interpolant of `v` at `t` in `[0, 1]` (barycentric formula).
    fn eval(&self, v: &[f64], t: f64) -> f64 {
        let (mut num, mut den) = (0.0, 0.0);
        for ((tj, wj), vj) in self.t.iter().zip(&self.w).zip(v) {
            let d = t - tj;
            if d == 0.0 {
                return *vj;
            }
            let a = wj / d;
            num += a * vj;
            den += a;
        }
        num / den
    }
}

/// Calls `f` with the interpolation matrix from the points of `g` to `samples + 1` equal
/// steps of `[0, 1]` (column-major: one column of `samples + 1` weights per point),
/// cached per thread for the last `(N, samples)` asked.
fn with_sampling(g: &Cheb, samples: usize, f: impl FnOnce(&[f64])) {
    thread_local! {
        static CACHE: std::cell::RefCell<(usize, usize, Vec<f64>)> =
            const { std::cell::RefCell::new((0, 0, Vec::new())) };
    }
    CACHE.with(|cache| {
        let mut cache = cache.borrow_mut();
        if cache.0 != g.n || cache.1 != samples {
            let (m, k) = (g.n + 1, samples + 1);
            let mut cols = vec![0.0; k * m];
            let mut row = vec![0.0; m];
            for i in 0..k {
                g.coefficients(i as f64 / samples as f64, &mut row);
                for (j, c) in row.iter().enumerate() {
                    cols[j * k + i] = *c;
                }
            }
            *cache = (g.n, samples, cols);
        }
        f(&cache.2);
    });
}

/// The loaded part `[0, s1]` on Chebyshev points: the iterate and what it gives (x and y
/// only once the iteration is done, [`Iterate::positions`]).
#[derive(Clone, Debug, Default)]
pub(super) struct Iterate {
    pub(super) phi: Vec<f64>,
    /// `(sin, cos)` of phi ([`Iterate::trig`]): the next step and the observables share them.
    pub(super) sc: Vec<(f64, f64)>,
    pub(super) m: Vec<f64>,
    kappa: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    pub(super) base: BaseObservables,
}

impl Iterate {
    pub(super) fn new(n: usize) -> Self {
        Iterate {
            phi: vec![0.0; n + 1],
            sc: Vec::with_capacity(n + 1),
            m: vec![0.0; n + 1],
            kappa: vec![0.0; n + 1],
            x: Vec::new(),
            y: Vec::new(),
            base: BaseObservables::default(),
        }
    }

    /// Fills `sc` from phi.
    pub(super) fn trig(&mut self) {
        self.sc.clear();
        self.sc.extend(self.phi.iter().map(|p| p.sin_cos()));
    }

    /// Fills x and y (the loaded part's positions) from phi.
    pub(super) fn positions(&mut self, g: &Cheb, s1: f64, work: &mut [f64]) {
        self.x.resize(g.n + 1, 0.0);
        self.y.resize(g.n + 1, 0.0);
        // one sin_cos per point: the sines wait in y until the cosines are integrated
        for ((w, sn), p) in work.iter_mut().zip(self.y.iter_mut()).zip(&self.phi) {
            (*sn, *w) = p.sin_cos();
        }
        g.integrate(work, s1, &mut self.x);
        work[..g.n + 1].copy_from_slice(&self.y);
        g.integrate(work, s1, &mut self.y);
    }
}

/// `∫_0^1 p` for values `v` at the points of `g` (the last row of its matrix).
fn total(g: &Cheb, v: impl Iterator<Item = f64>) -> f64 {
    let m = g.n + 1;
    g.q[g.n * m..].iter().zip(v).map(|(a, b)| a * b).sum()
}

/// The unloaded rest beyond s1 at the points of `g` on `[s1, 1]`: its angle.
fn free_angle(scene: &Scene, phi1: f64, t: f64) -> f64 {
    let w = &scene.whisker;
    let s1 = scene.loads.s1;
    w.phi_free(s1, phi1, s1 + (1.0 - s1) * t)
}

/// The numbers the error estimate compares (tip, loaded end, base observables), from an
/// iterate without its positions (its `sc` filled).
pub(super) fn observables(scene: &Scene, g: &Cheb, it: &Iterate) -> [f64; 10] {
    let s1 = scene.loads.s1;
    let n = g.n;
    let (x1, y1) = {
        let m = g.n + 1;
        let (sx, sy) = g.q[g.n * m..]
            .iter()
            .zip(&it.sc)
            .fold((0.0, 0.0), |(sx, sy), (a, &(sn, cs))| {
                (sx + a * cs, sy + a * sn)
            });
        (s1 * sx, s1 * sy)
    };
    let phi1 = it.phi[n];
    let rest = 1.0 - s1;
    let (mut xt, mut yt, mut pt) = (x1, y1, phi1);
    if rest > 0.0 {
        xt += rest * total(g, g.t.iter().map(|&t| free_angle(scene, phi1, t).cos()));
        yt += rest * total(g, g.t.iter().map(|&t| free_angle(scene, phi1, t).sin()));
        pt = free_angle(scene, phi1, 1.0);
    }
    let b = &it.base;
    [xt, yt, pt, x1, y1, phi1, b.ma, b.phi0, b.ax, b.ay]
}

pub(super) fn distance(a: &[f64; 10], b: &[f64; 10]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(u, v)| (u - v).abs())
        .fold(0.0, |m, d| if d.is_nan() { f64::NAN } else { m.max(d) })
}

/// One application of the integral map `T` on grid `g` (module docs): `out` from `phi`
/// (with its sines and cosines `sc`).
pub(super) fn step(
    scene: &Scene,
    g: &Cheb,
    (phi, sc): (&[f64], &[(f64, f64)]),
    out: &mut Iterate,
    work: &mut [f64],
) {
    let w = &scene.whisker;
    let l = &scene.loads;
    let s1 = l.s1;
    let n = g.n;
    // m' [3.25] on the nodes, from the tip angle phi(s1) = phi[n] of the iterate; m(s1) = 0.
    let law = MomentLaw::new(l, phi[n]);
    for (j, v) in work.iter_mut().enumerate() {
        let (sn, cs) = sc[j];
        *v = law.at(s1 * g.t[j], sn, cs).dm;
    }
    g.integrate(work, s1, &mut out.m);
    let top = out.m[n];
    for v in out.m.iter_mut() {
        *v -= top;
    }
    for j in 0..=n {
        let s = s1 * g.t[j];
        out.kappa[j] = out.m[j] / w.stiffness(s) + w.kappa0(s);
    }
    // the follicle law [3.21, 3.22]
    let phi0 = FRAC_PI_2 + out.m[0] * w.support.compliance();
    g.integrate(&out.kappa, s1, &mut out.phi);
    for v in out.phi.iter_mut() {
        *v += phi0;
    }
    let (ax, ay) = scene.base_reactions(phi[n]);
    out.base = BaseObservables {
        ax,
        ay,
        ma: -out.m[0],
        phi0,
    };
}

/// The whole whisker from a converged iterate (positions filled): the loaded part on the
/// grid and, beyond s1, the unloaded rest (`φ' = A s + B`, integrated on the same points),
/// sampled at `samples + 1` equal steps of `[0, 1]`.
pub(super) fn solution(scene: &Scene, g: &Cheb, it: &Iterate, samples: usize) -> Solution {
    let w = &scene.whisker;
    let s1 = scene.loads.s1;
    let n = g.n;
    let end = EndState {
        x: it.x[n],
        y: it.y[n],
        phi: it.phi[n],
    };
    let rest = 1.0 - s1;
    let mut el = Elastica::with_capacity(samples + 1);
    let dot = |c: &[f64], v: &[f64]| c.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
    let tip;
    if s1 == 1.0 {
        // no unloaded rest: the tip is the loaded end
        tip = EndState {
            phi: free_angle(scene, end.phi, 1.0),
            ..end
        };
        // The whole whisker is loaded: a cached interpolation matrix, applied column by
        // column (the five quantities updated in one pass over the samples, vectorised
        // over them; each column's weight loaded once).
        let k = samples + 1;
        let mut out = vec![0.0; 5 * k];
        let (x, rest5) = out.split_at_mut(k);
        let (y, rest5) = rest5.split_at_mut(k);
        let (phi, rest5) = rest5.split_at_mut(k);
        let (kappa, m) = rest5.split_at_mut(k);
        with_sampling(g, samples, |cols| {
            for (j, col) in cols.chunks_exact(k).enumerate() {
                let (vx, vy, vp, vk, vm) = (it.x[j], it.y[j], it.phi[j], it.kappa[j], it.m[j]);
                let lanes = x.iter_mut().zip(y.iter_mut()).zip(phi.iter_mut());
                let lanes = lanes.zip(kappa.iter_mut()).zip(m.iter_mut()).zip(col);
                for (((((x, y), p), kp), mm), c) in lanes {
                    *x += c * vx;
                    *y += c * vy;
                    *p += c * vp;
                    *kp += c * vk;
                    *mm += c * vm;
                }
            }
        });
        for i in 0..k {
            el.push(
                i as f64 / samples as f64,
                x[i],
                y[i],
                phi[i],
                kappa[i],
                m[i],
            );
        }
    } else {
        let free_phi: Vec<f64> = g.t.iter().map(|&t| free_angle(scene, end.phi, t)).collect();
        let (mut fx, mut fy) = (vec![0.0; n + 1], vec![0.0; n + 1]);
        if rest > 0.0 {
            let c: Vec<f64> = free_phi.iter().map(|p| p.cos()).collect();
            let sn: Vec<f64> = free_phi.iter().map(|p| p.sin()).collect();
            g.integrate(&c, rest, &mut fx);
            g.integrate(&sn, rest, &mut fy);
        }
        tip = EndState {
            x: end.x + fx[n],
            y: end.y + fy[n],
            phi: free_phi[n],
        };
        let mut c = vec![0.0; n + 1];
        for i in 0..=samples {
            let s = i as f64 / samples as f64;
            if s <= s1 && s1 > 0.0 {
                g.coefficients(s / s1, &mut c);
                el.push(
                    s,
                    dot(&c, &it.x),
                    dot(&c, &it.y),
                    dot(&c, &it.phi),
                    dot(&c, &it.kappa),
                    dot(&c, &it.m),
                );
            } else {
                g.coefficients((s - s1) / rest, &mut c);
                el.push(
                    s,
                    end.x + dot(&c, &fx),
                    end.y + dot(&c, &fy),
                    dot(&c, &free_phi),
                    w.kappa0(s),
                    0.0,
                );
            }
        }
    }
    Solution {
        elastica: el,
        tip,
        loaded_end: end,
        base: it.base,
        stats: SolveStats {
            method_used: MethodKind::Picard,
            ..SolveStats::default()
        },
        load_path: None,
    }
}

/// Why the fixed-point iteration gave no answer within the tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NotContracting {
    /// The observed contraction ratio (>= 1 diverges).
    pub(crate) ratio: f64,
    /// The best estimate reached.
    pub(crate) estimate: f64,
}

/// A converged iterate on one grid.
struct Converged {
    it: Iterate,
    obs: [f64; 10],
    bound: f64,
    ratio: f64,
    steps: usize,
}

/// Iterates `T` on grid `g` from `start` until the iteration error is below `tol`. The
/// bound uses the larger of this grid's own contraction (from [`OWN_CHANGES`] changes on)
/// and a coarser grid's `known_ratio`, if known.
fn iterate(
    scene: &Scene,
    g: &Cheb,
    start: &[f64],
    tol: f64,
    known_ratio: f64,
) -> Result<Converged, NotContracting> {
    let mut work = vec![0.0; g.n + 1];
    let mut cur = Iterate::new(g.n);
    let mut next = Iterate::new(g.n);
    let start_sc: Vec<(f64, f64)> = start.iter().map(|p| p.sin_cos()).collect();
    step(scene, g, (start, &start_sc), &mut cur, &mut work);
    cur.trig();
    let mut prev_obs = observables(scene, g, &cur);
    let (mut d_prev, mut last_r) = (f64::NAN, f64::NAN);
    let mut ratio = known_ratio;
    let noise = 1e-15 * (1.0 + scene.loads.tip.f + scene.loads.fluid.q);
    for k in 1..=MAX_ITERATIONS {
        step(scene, g, (&cur.phi, &cur.sc), &mut next, &mut work);
        next.trig();
        let obs = observables(scene, g, &next);
        let dphi = next
            .phi
            .iter()
            .zip(&cur.phi)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let d = distance(&obs, &prev_obs).max(dphi);
        std::mem::swap(&mut cur, &mut next);
        prev_obs = obs;
        if !d.is_finite() {
            break;
        }
        if d_prev.is_finite() && d_prev > 0.0 {
            // The contraction: the larger of the last two ratios of changes (and of the
            // coarser grid's).
            let r = d / d_prev;
            ratio = r.max(if last_r.is_finite() { last_r } else { r });
            if known_ratio.is_finite() {
                ratio = ratio.max(known_ratio);
            }
            last_r = r;
        }
        d_prev = d;
        let done = |bound: f64, cur: Iterate| {
            Ok(Converged {
                it: cur,
                obs,
                bound,
                ratio,
                steps: k + 1,
            })
        };
        if d <= noise {
            // Converged to rounding: the last change is the noise of the sums.
            return done(d, cur);
        }
        // the bound needs this grid's own contraction: at least two changes here
        if ratio.is_finite() && k >= OWN_CHANGES {
            if ratio >= MAX_RATIO {
                return Err(NotContracting {
                    ratio,
                    estimate: f64::INFINITY,
                });
            }
            let bound = d * ratio / (1.0 - ratio);
            if bound <= tol {
                return done(bound, cur);
            }
        }
    }
    Err(NotContracting {
        ratio,
        estimate: d_prev,
    })
}

/// Changes of the iterate on a grid before its bound `d c / (1 - c)` is trusted: the
/// contraction `c` must be one this grid has shown. The first change after a coarser grid's
/// solution is prolonged measures `(I - T') e` of its distance `e` to this grid's fixed
/// point, not `e`, and the coarser grid's ratio is no contraction constant of this one
/// (issue 34: an AP force of 7.36 at beta = -89.3 degrees on a spring k = 2, `--tol 1e-6`:
/// the 8-point iteration's ratios fell 0.56 -> 0.044 as it converged; on 16 points the
/// first change, 3.9e-7, was accepted under that ratio with a bound of 1.8e-8, where the
/// second change is 2.1e-6 (ratio 5.3) and the answer was 4.7e-6 off).
const OWN_CHANGES: usize = 2;

/// Iterations per grid before giving up.
const MAX_ITERATIONS: usize = 60;

/// Contraction ratios at or beyond this are too slow to be worth iterating: shooting
/// takes over.
const MAX_RATIO: f64 = 0.7;

/// Solves `scene` by the spectral Picard iteration to absolute accuracy `tol` (the norm of
/// [`SolveStats::error_estimate`](crate::SolveStats)): on 8, 16, 32, ... Chebyshev points
/// until the solutions on `N` and `2N` points differ by less than what remains of `tol`
/// after the iteration error. The estimate returned is the iteration bound plus that
/// difference.
pub(crate) fn solve(scene: &Scene, tol: f64, samples: usize) -> Result<Solution, NotContracting> {
    let inner = tol / 4.0;
    let w = &scene.whisker;
    let s1 = scene.loads.s1;
    let g0 = cheb(SIZES[0]);
    let unloaded: Vec<f64> = g0.t.iter().map(|t| w.phi_unloaded(s1 * t)).collect();
    let mut c = iterate(scene, g0, &unloaded, inner, f64::NAN)?;
    let (mut steps, mut evaluations) = (c.steps, c.steps * (g0.n + 1));
    for pair in SIZES.windows(2) {
        let (gc, gf) = (cheb(pair[0]), cheb(pair[1]));
        let start: Vec<f64> = gf.t.iter().map(|&t| gc.eval(&c.it.phi, t)).collect();
        let fine = iterate(scene, gf, &start, inner, c.ratio)?;
        steps += fine.steps;
        evaluations += fine.steps * (gf.n + 1);
        let disc = distance(&fine.obs, &c.obs);
        let estimate = fine.bound + disc;
        c = fine;
        if estimate <= tol {
            let mut work = vec![0.0; gf.n + 1];
            c.it.positions(gf, s1, &mut work);
            let mut sol = solution(scene, gf, &c.it, samples);
            sol.stats.iterations = steps;
            sol.stats.evaluations = evaluations;
            sol.stats.error_estimate = estimate;
            return Ok(sol);
        }
        if !disc.is_finite() {
            break;
        }
    }
    Err(NotContracting {
        ratio: c.ratio,
        estimate: c.bound,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_integration_matrix_is_exact_for_polynomials() {
        let g = cheb(16);
        let v: Vec<f64> = g.t.iter().map(|t| 3.0 * t * t - 2.0 * t + 1.0).collect();
        let mut out = vec![0.0; 17];
        g.integrate(&v, 1.0, &mut out);
        for (t, o) in g.t.iter().zip(&out) {
            let exact = t * t * t - t * t + t;
            assert!((o - exact).abs() < 1e-14, "{t}: {o} vs {exact}");
        }
        // Smooth functions converge spectrally: ∫_0^1 cos(3t) = sin(3)/3.
        let g = cheb(32);
        let v: Vec<f64> = g.t.iter().map(|t| (3.0 * t).cos()).collect();
        let mut out = vec![0.0; 33];
        g.integrate(&v, 1.0, &mut out);
        assert!((out[32] - 3f64.sin() / 3.0).abs() < 1e-15);
        assert!((g.eval(&v, 0.3) - 0.9f64.cos()).abs() < 1e-14);
    }
}
