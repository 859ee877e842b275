//! `auto`'s cheapest rung: linear small-deflection theory, answered only where an a-priori
//! bound proves it meets the accuracy asked for.
//!
//! # The map and its Lipschitz constant
//!
//! The spectral Picard iteration ([`picard`]) solves `φ = T(φ)` on the loaded part
//! `[0, s1]`, with the moment law [3.25] `m'(t) = f sin(φ(t) + c) + q (s1 − t) sin(φ(t) + α)`
//! (`c = β` for a direction-preserving force, `c = β − φ(s1) + π/2` for an angle-preserving
//! one):
//!
//! ```text
//! m(s) = −∫_s^{s1} m'(t) dt,    T(φ)(s) = π/2 + m(0)/k + ∫_0^s (m / e⁴ + A t + B) dt.
//! ```
//!
//! Its first iterate from the unloaded shape `φ_u`, `φ_1 = T(φ_u)`, is linear theory: the
//! loads' moment on the unloaded whisker ([`linear`](crate::linear)); its positions are
//! `∫ (cos φ_1, sin φ_1)`, its base moment `MA = −m(0)` and base angle `φ(0)` those of
//! that moment. For two shapes `a`, `b` with `δφ = a − b`, the mean value theorem bounds the
//! change of the moment law by `|δm'(t)| ≤ R(t) ‖δφ‖` (sup norm on `[0, s1]`) with
//!
//! ```text
//! R(t) = f' + q (s1 − t),    f' = f (DP),  f' = 2 f (AP: φ(t) and φ(s1) both move),
//! ```
//!
//! (for DP the derivative `f cos(φ + β) + q (s1 − t) cos(φ + α)` is at most the resultant
//! `|G(t)| ≤ R(t)`; the triangle inequality keeps `R` linear, so every integral below is
//! closed). Then `|δm(s)| ≤ g(s) ‖δφ‖` with `g(s) = ∫_s^{s1} R = (s1 − s)(f' + q (s1 − s)/2)`,
//! and `|δT(s)| ≤ (g(0)/k + ∫_0^s g / e⁴) ‖δφ‖`, largest at `s = s1`:
//!
//! ```text
//! ‖T(a) − T(b)‖ ≤ c ‖a − b‖,
//! c = g(0)/k + f' J1 + (q/2) J2,   g(0) = f' s1 + q s1²/2,
//! J1 = ∫_0^{s1} (s1 − t) / e⁴ dt = s1² (1 + 2 e1) / (6 e1²),
//! J2 = ∫_0^{s1} (s1 − t)² / e⁴ dt = s1³ / (3 e1),             e1 = e(s1) = 1 + (θ − 1) s1,
//! ```
//!
//! (substitute `u = e(t)`; the forms are free of cancellation at `θ → 1`, where `J1 = s1²/2`,
//! `J2 = s1³/3`). For the straight uniform cantilever `c = f/2 + q/6`, its linear tip
//! rotations.
//!
//! # The bound
//!
//! Where `c < 1`, `T` is a contraction of all of `C[0, s1]`: the equilibrium `φ*` is unique
//! (every method finds it) and, with `D = ‖φ_1 − φ_u‖`,
//!
//! ```text
//! ‖φ* − φ_u‖ ≤ D / (1 − c) =: E_u,     ‖φ* − φ_1‖ = ‖T φ* − T φ_u‖ ≤ c E_u =: E.
//! ```
//!
//! In the norm of [`SolveStats::error_estimate`](crate::SolveStats):
//!
//! - loaded end `x1, y1`: `≤ s1 E`; its angle `φ(s1)` and the base angle `φ(0)`: `≤ E`;
//! - tip (the unloaded rest turns rigidly with `φ(s1)`): `x, y` `≤ s1 E + (1 − s1) E = E`,
//!   `φ ≤ E`;
//! - `MA = −m(0)`, the moment on `φ_u`: `|δm(0)| ≤ g(0) E_u`;
//! - `Ax, Ay`: exact for DP; for AP taken at `φ_1(s1)`, `≤ f E`.
//!
//! The model bound is `max(E, g(0) E_u, [AP] f E)`. `D` is a supremum over `[0, s1]`: with
//! `δ = φ_1 − φ_u` known at the Chebyshev points `s_j`, `δ' = m / e⁴` and
//! `|m(s)| ≤ g_f(s) = (s1 − s)(f + q (s1 − s)/2)` (`|sin| ≤ 1`), between two points
//! `|δ| ≤ (|δ_j| + |δ_{j+1}| + g_f(s_j) (W(s_{j+1}) − W(s_j))) / 2` with
//! `W(s) = ∫_0^s e⁻⁴ = s (1 + e + e²) / (3 e³)`.
//!
//! The discretisation error of the computed `φ_1` (Chebyshev quadrature on `N` points) is
//! estimated, as the Picard iteration does, by the difference of the observables on `N`
//! and `2N` points; the estimate returned is the model bound plus that difference (plus 16
//! ulps of the largest observable for the rounding of the sums), and the
//! rung answers only where it meets the accuracy asked for (else `auto` goes on,
//! unchanged). Its cost is one application of `T` per grid, against the Picard iteration's
//! several; it is only taken when cheaper, which it always is when it qualifies.

use super::picard::{self, Cheb, Iterate, SIZES};
use crate::loads::LoadKind;
use crate::scene::Scene;
use crate::solution::{ModelKind, Solution};

/// The a-priori constants of the integral map `T` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Contraction {
    /// The Lipschitz constant `c` of `T` in the sup norm on `[0, s1]`.
    pub(crate) c: f64,
    /// `g(0) = ∫_0^{s1} R`: the base moment's Lipschitz constant.
    pub(crate) g0: f64,
}

/// The closed-form Lipschitz constant of `T` for `scene` (module docs).
pub(crate) fn contraction(scene: &Scene) -> Contraction {
    let (w, l) = (&scene.whisker, &scene.loads);
    let (s1, q) = (l.s1, l.fluid.q);
    let f = match l.tip.kind {
        LoadKind::Dp => l.tip.f,
        LoadKind::Ap => 2.0 * l.tip.f,
    };
    let e1 = w.diameter(s1);
    let j1 = s1 * s1 * (1.0 + 2.0 * e1) / (6.0 * e1 * e1);
    let j2 = s1 * s1 * s1 / (3.0 * e1);
    let g0 = f * s1 + 0.5 * q * s1 * s1;
    Contraction {
        c: g0 * w.support.compliance() + f * j1 + 0.5 * q * j2,
        g0,
    }
}

/// `W(s) = ∫_0^s e(t)⁻⁴ dt = s (1 + e + e²) / (3 e³)`, `e = e(s)`.
fn compliance_integral(scene: &Scene, s: f64) -> f64 {
    let e = scene.whisker.diameter(s);
    s * (1.0 + e + e * e) / (3.0 * e * e * e)
}

/// Linear theory on one grid: the first iterate, its observables, the bound on `D` and the
/// model bound (module docs).
struct OnGrid {
    it: Iterate,
    obs: [f64; 10],
    model: f64,
}

/// `φ_1 = T(φ_u)` on grid `g`, with the base reactions of an AP force at `φ_1(s1)`.
fn first_iterate(scene: &Scene, g: &Cheb) -> Iterate {
    let s1 = scene.loads.s1;
    let unloaded: Vec<f64> =
        g.t.iter()
            .map(|t| scene.whisker.phi_unloaded(s1 * t))
            .collect();
    let sc: Vec<(f64, f64)> = unloaded.iter().map(|p| p.sin_cos()).collect();
    let mut it = Iterate::new(g.n);
    let mut work = vec![0.0; g.n + 1];
    picard::step(scene, g, (&unloaded, &sc), &mut it, &mut work);
    it.trig();
    if scene.loads.tip.kind == LoadKind::Ap {
        (it.base.ax, it.base.ay) = scene.base_reactions(it.phi[g.n]);
    }
    it
}

/// An upper bound on `D = sup |φ_1 − φ_u|` over `[0, s1]` from its values at the points of
/// `g` and the bound on its slope between them (module docs).
fn rotation_bound(scene: &Scene, g: &Cheb, it: &Iterate) -> f64 {
    let (w, l) = (&scene.whisker, &scene.loads);
    let s1 = l.s1;
    let gf = |s: f64| (s1 - s) * (l.tip.f + 0.5 * l.fluid.q * (s1 - s));
    let delta: Vec<(f64, f64)> =
        g.t.iter()
            .zip(&it.phi)
            .map(|(t, p)| (s1 * t, (p - w.phi_unloaded(s1 * t)).abs()))
            .collect();
    let mut d = delta.iter().map(|v| v.1).fold(0.0, f64::max);
    for pair in delta.windows(2) {
        let ((sa, da), (sb, db)) = (pair[0], pair[1]);
        let slope = gf(sa) * (compliance_integral(scene, sb) - compliance_integral(scene, sa));
        d = d.max(0.5 * (da + db + slope));
    }
    d
}

/// Linear theory on grid `g` with its model bound under `k`.
fn on_grid(scene: &Scene, g: &Cheb, k: &Contraction) -> OnGrid {
    let it = first_iterate(scene, g);
    let obs = picard::observables(scene, g, &it);
    let d = rotation_bound(scene, g, &it);
    let model = model_bound(scene, k, d);
    OnGrid { it, obs, model }
}

/// The bound on the error of linear theory's observables given `D` (module docs).
pub(crate) fn model_bound(scene: &Scene, k: &Contraction, d: f64) -> f64 {
    if k.c.is_nan() || k.c >= 1.0 {
        return f64::INFINITY;
    }
    let eu = d / (1.0 - k.c);
    let e = k.c * eu;
    let ap = match scene.loads.tip.kind {
        LoadKind::Dp => 0.0,
        LoadKind::Ap => scene.loads.tip.f * e,
    };
    e.max(k.g0 * eu).max(ap)
}

/// Linear theory for `scene` where its bound plus the discretisation estimate meets `tol`
/// (module docs), on the Chebyshev grids of the Picard iteration: `None` where it does not
/// (`auto` goes on). `rotation`, the larger linear rotation of the base and the loaded end
/// by [`rotations_on::<16>`](crate::linear::rotations_on) (a few per cent off; `auto`
/// computes it anyway), is a lower bound on `D` to within that: where even half of it
/// gives a model bound beyond `tol` the rung gives up before any grid work (a few dozen
/// instructions, where the grids cost ~10,000; a scene skipped wrongly would cost speed,
/// never accuracy: the 2000-scene battery of `tests/auto.rs` answers as many scenes by
/// linear theory at every accuracy with as without this test).
pub(crate) fn solve(scene: &Scene, tol: f64, samples: usize, rotation: f64) -> Option<Solution> {
    let k = contraction(scene);
    if k.c.is_nan() || k.c >= 1.0 || exceeds(model_bound(scene, &k, 0.5 * rotation), tol) {
        return None;
    }
    let first = cheb(SIZES[0]);
    let mut coarse = on_grid(scene, first, &k);
    let mut evaluations = first.n + 1;
    // the bound hardly moves with the grid: far beyond tol on the coarsest one, give up
    if exceeds(coarse.model, 2.0 * tol) {
        return None;
    }
    for &n in &SIZES[1..] {
        let g = cheb(n);
        let mut fine = on_grid(scene, g, &k);
        evaluations += g.n + 1;
        if exceeds(fine.model, tol) {
            return None;
        }
        let disc = picard::distance(&fine.obs, &coarse.obs);
        let estimate = fine.model + disc + rounding(&fine.obs);
        if estimate <= tol {
            let mut work = vec![0.0; g.n + 1];
            fine.it.positions(g, scene.loads.s1, &mut work);
            let mut sol = picard::solution(scene, g, &fine.it, samples);
            sol.stats.model_used = ModelKind::Linear;
            sol.stats.iterations = 1;
            sol.stats.evaluations = evaluations;
            sol.stats.error_estimate = estimate;
            return Some(sol);
        }
        if !disc.is_finite() {
            return None;
        }
        coarse = fine;
    }
    None
}

/// Whether `v` is beyond `bound` or NaN.
fn exceeds(v: f64, bound: f64) -> bool {
    v.is_nan() || v > bound
}

/// The rounding of the observables' sums: 16 ulps of the largest (at loads of 1e-6 and
/// below the model bound and the grids' difference fall beneath it).
fn rounding(obs: &[f64; 10]) -> f64 {
    16.0 * f64::EPSILON * obs.iter().fold(1.0, |m: f64, v| m.max(v.abs()))
}

fn cheb(n: usize) -> &'static Cheb {
    picard::cheb(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{solve as solve_scene, Loads, Method, Scene, TipForce, Whisker};
    use rand::{rngs::StdRng, Rng, SeedableRng};

    /// `T` applied to `phi` on grid `g` (the values at its points).
    fn apply(scene: &Scene, g: &Cheb, phi: &[f64]) -> Vec<f64> {
        let sc: Vec<(f64, f64)> = phi.iter().map(|p| p.sin_cos()).collect();
        let mut out = Iterate::new(g.n);
        let mut work = vec![0.0; g.n + 1];
        picard::step(scene, g, (phi, &sc), &mut out, &mut work);
        out.phi
    }

    /// The closed-form integrals J1, J2 and W against a fine midpoint rule.
    #[test]
    fn the_closed_forms_match_quadrature() {
        for theta in [1.0, 0.5, 0.05] {
            let w = Whisker::new(theta, 0.0, 0.0, f64::INFINITY);
            let mut loads = Loads::combined(TipForce::dp(1.0, 0.0), 1.0, 0.0);
            loads.s1 = 0.8;
            let scene = Scene::new(w, loads);
            let n = 200_000;
            let h = 0.8 / n as f64;
            let (mut j1, mut j2, mut wi) = (0.0, 0.0, 0.0);
            for i in 0..n {
                let t = (i as f64 + 0.5) * h;
                let inv = 1.0 / w.stiffness(t);
                j1 += h * (0.8 - t) * inv;
                j2 += h * (0.8 - t) * (0.8 - t) * inv;
                wi += h * inv;
            }
            // f = q = 1, rigid: c = J1 + J2 / 2
            let k = contraction(&scene);
            assert!((k.c - (j1 + 0.5 * j2)).abs() < 1e-8 * k.c, "{theta}: {k:?}");
            assert!((k.g0 - (0.8 + 0.32)).abs() < 1e-15);
            let exact = compliance_integral(&scene, 0.8);
            assert!((exact - wi).abs() < 1e-8 * wi, "{exact} vs {wi}");
        }
    }

    /// The measured Lipschitz ratio `‖T(a) − T(b)‖ / ‖a − b‖` of random smooth pairs never
    /// exceeds the a-priori `c`, and comes within 0.1 % of it on the pair that makes every
    /// `cos` one (straight cantilever on a spring, the force along its axis, a small uniform
    /// shift).
    #[test]
    fn measured_lipschitz_ratios_stay_below_c() {
        let g = cheb(64);
        let mut rng = StdRng::seed_from_u64(0x11B5_C0DE);
        let mut worst: f64 = 0.0;
        for _ in 0..300 {
            let w = Whisker::new(
                rng.gen_range(0.05..1.0),
                rng.gen_range(-2.0..2.0),
                rng.gen_range(-2.0..2.0),
                if rng.gen::<f64>() < 0.5 {
                    f64::INFINITY
                } else {
                    rng.gen_range(1.0..50.0)
                },
            );
            let beta = rng.gen_range(-3.0..3.0);
            let f = rng.gen_range(0.0..2.0);
            let tip = if rng.gen::<f64>() < 0.4 {
                TipForce::ap(f, beta)
            } else {
                TipForce::dp(f, beta)
            };
            let mut loads = Loads::combined(tip, rng.gen_range(0.0..3.0), rng.gen_range(-1.5..1.5));
            if rng.gen::<f64>() < 0.3 {
                loads.s1 = rng.gen_range(0.5..1.0);
            }
            let scene = Scene::new(w, loads);
            let c = contraction(&scene).c;
            // smooth shapes: the unloaded one plus a few random modes of any amplitude
            let mut shape = || -> Vec<f64> {
                let modes: Vec<(f64, f64, f64)> = (0..3)
                    .map(|_| {
                        (
                            rng.gen_range(-2.0..2.0),
                            rng.gen_range(0.0..6.0),
                            rng.gen_range(0.0..6.3),
                        )
                    })
                    .collect();
                g.t.iter()
                    .map(|t| {
                        let s = loads.s1 * t;
                        w.phi_unloaded(s)
                            + modes
                                .iter()
                                .map(|(a, k, p)| a * (k * s + p).sin())
                                .sum::<f64>()
                    })
                    .collect()
            };
            let (a, b) = (shape(), shape());
            let (ta, tb) = (apply(&scene, g, &a), apply(&scene, g, &b));
            let sup = |u: &[f64], v: &[f64]| {
                u.iter()
                    .zip(v)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max)
            };
            let ratio = sup(&ta, &tb) / sup(&a, &b);
            assert!(ratio <= c * (1.0 + 1e-12), "{scene:?}: {ratio} > c = {c}");
            worst = worst.max(ratio / c);
        }
        println!("random pairs: worst ratio / c = {worst:.3}");
        assert!(worst > 0.2, "random pairs reach {worst} of c");
        // the near-worst pair: cos(φ + β) = 1 along a straight whisker, a small uniform shift
        let scene = Scene::new(
            Whisker::new(1.0, 0.0, 0.0, 4.0),
            Loads::tip(TipForce::dp(0.6, -std::f64::consts::FRAC_PI_2)),
        );
        let c = contraction(&scene).c;
        assert!((c - (0.6 / 4.0 + 0.3)).abs() < 1e-15);
        let a: Vec<f64> = g.t.iter().map(|_| std::f64::consts::FRAC_PI_2).collect();
        let b: Vec<f64> = a.iter().map(|p| p + 1e-6).collect();
        let (ta, tb) = (apply(&scene, g, &a), apply(&scene, g, &b));
        let ratio = (ta[64] - tb[64]).abs() / 1e-6;
        assert!(ratio <= c && ratio > 0.999 * c, "{ratio} vs {c}");
    }

    /// The straight uniform rigid cantilever: linear theory's tip deflection is `F/3` under
    /// a normal tip force and `q/8` under a uniform load (to O(load³) from the exact
    /// positions of the linear angle), with the estimate bounding its error from the
    /// elastica.
    #[test]
    fn the_straight_cantilever_gives_the_classical_deflections() {
        let w = Whisker::uniform();
        for (loads, closed) in [
            (Loads::tip(TipForce::dp(1e-3, 0.0)), 1e-3 / 3.0),
            (Loads::fluid(1e-3, 0.0), 1e-3 / 8.0),
        ] {
            let scene = Scene::new(w, loads);
            let sol = solve(&scene, 1e-5, 100, 0.0).expect("linear theory meets 1e-5");
            assert_eq!(sol.stats.model_used, ModelKind::Linear);
            assert!((sol.tip.x / closed - 1.0).abs() < 1e-6, "{}", sol.tip.x);
            let exact = solve_scene(&scene, &Method::accurate()).unwrap();
            let err = sol.difference(&exact);
            assert!(err <= sol.stats.error_estimate, "{err} vs {:?}", sol.stats);
        }
    }

    /// On a tapered, pre-curved whisker on a spring under an oblique force and flow, the
    /// error of linear theory from the elastica falls as the square of the load (measured
    /// order 2 over four halvings), and the bound with it.
    #[test]
    fn the_error_of_linear_theory_is_second_order_in_the_load() {
        let w = Whisker::new(0.4, 0.8, -0.5, 15.0);
        let base = Loads::combined(TipForce::dp(0.7, 0.4), 2.0, 0.6);
        let mut last: Option<(f64, f64)> = None;
        for i in 0..5 {
            let scene = Scene::new(w, base.scaled(0.05 / f64::powi(2.0, i)));
            // (a loose accuracy: only the rung's numbers matter here)
            let sol = solve(&scene, 1.0, 100, 0.0).expect("the bound is finite");
            let exact = solve_scene(&scene, &Method::accurate()).unwrap();
            let err = sol.difference(&exact);
            let est = sol.stats.error_estimate;
            assert!(err <= est, "{err} vs {est}");
            if let Some((e0, b0)) = last {
                let order = (e0 / err).log2();
                let bound_order = (b0 / est).log2();
                println!(
                    "error {err:.3e} (order {order:.3}), bound {est:.3e} (order {bound_order:.3})"
                );
                assert!((order - 2.0).abs() < 0.15, "order {order}");
                assert!(
                    (bound_order - 2.0).abs() < 0.15,
                    "bound order {bound_order}"
                );
            }
            last = Some((err, est));
        }
    }
}
