//! Linear small-deflection theory about the unloaded shape: the first-order response of the
//! whisker to its loads, `phi = phi_u + delta` with `phi_u` the unloaded shape (the free
//! segment from the base, [`Whisker::phi_unloaded`]).
//!
//! To first order in the loads the internal moment is the loads' moment on the unloaded
//! shape, `m(s) = -int_s^s1 m'(t) dt` with the moment law [3.25] evaluated at `phi_u`
//! ([`MomentLaw`]), and the rotation follows from the curvature and the follicle law
//! [3.21, 3.22]:
//!
//! ```text
//! delta(s) = m(0)/k + int_0^s m(t) / e(t)^4 dt.
//! ```
//!
//! The tip rotation `delta(s1)` is the slope `d phi1 / d lambda` at `lambda = 0` of the loads
//! scaled by `lambda`: the predictor of the load continuation's first step.
//!
//! `auto`'s cheapest rung answers with this theory (its angle `phi_u + delta` integrated to
//! positions, on Chebyshev points) where an a-priori bound proves it meets the accuracy
//! asked for (module `methods::linear_rung`, [`ModelKind::Linear`](crate::ModelKind)).

use crate::equations::MomentLaw;
use crate::loads::Loads;
use crate::whisker::Whisker;

/// Intervals of the quadrature (composite trapezoidal rule, exact for the straight
/// cantilever's force case and within 1e-4 for its flow case (tests): ample for a predictor).
const INTERVALS: usize = 64;

/// The linear-theory rotation `delta(s1)` of the loaded end under `loads` (module docs).
pub fn tip_rotation(whisker: &Whisker, loads: &Loads) -> f64 {
    rotations(whisker, loads).1
}

/// The linear-theory rotations `(delta(0), delta(s1))` of the base (in its spring) and of the
/// loaded end under `loads` (module docs).
pub fn rotations(whisker: &Whisker, loads: &Loads) -> (f64, f64) {
    rotations_on::<INTERVALS>(whisker, loads)
}

/// [`rotations`] on `N` intervals of the quadrature (a coarse `N` for a quick look: on 16,
/// a few per cent).
pub fn rotations_on<const N: usize>(whisker: &Whisker, loads: &Loads) -> (f64, f64) {
    let s1 = loads.s1;
    let law = MomentLaw::new(loads, whisker.phi_unloaded(s1));
    let h = s1 / N as f64;
    let rate = |i: usize| {
        let s = i as f64 * h;
        let (sp, cp) = crate::trig::sin_cos(whisker.phi_unloaded(s));
        law.at(s, sp, cp).dm
    };
    // m at the nodes from the loaded end (m(s1) = 0), then its integral over 1/e^4 from the
    // base
    const { assert!(N >= 1, "at least one interval") };
    // m at nodes 0..N-1 (m(s1) = 0 at node N): an array of N, nothing zeroed beyond it
    let mut m = [0.0; N];
    let (mut above, mut upper) = (0.0, rate(N));
    for i in (0..N).rev() {
        let lower = rate(i);
        m[i] = above - 0.5 * h * (lower + upper);
        (above, upper) = (m[i], lower);
    }
    let curvature = |i: usize| {
        m.get(i)
            .map_or(0.0, |mi| mi / whisker.stiffness(i as f64 * h))
    };
    let bend: f64 = (0..N)
        .map(|i| 0.5 * h * (curvature(i) + curvature(i + 1)))
        .sum();
    let base = m[0] * whisker.support.compliance();
    (base, base + bend)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{solve, Method, Scene, TipForce};

    /// Classical cantilever formulas: a force normal to a straight uniform whisker turns its
    /// tip by `f/2`, a uniform load by `q/6`; a spring adds `M_A / k`.
    #[test]
    fn straight_cantilever_formulas() {
        let w = Whisker::uniform();
        // beta = 0: the force f (1, 0) normal to the straight whisker (along +y)
        let tip = Loads::tip(TipForce::dp(2.0, 0.0));
        assert!((tip_rotation(&w, &tip).abs() - 1.0).abs() < 1e-4);
        let flow = Loads::fluid(3.0, 0.0);
        assert!((tip_rotation(&w, &flow).abs() - 0.5).abs() < 1e-4);
        let spring = Whisker::new(1.0, 0.0, 0.0, 4.0);
        // q = 3: base moment q/2 = 1.5, spring rotation 1.5 / 4
        assert!((tip_rotation(&spring, &flow).abs() - (0.5 + 0.375)).abs() < 1e-4);
    }

    /// The coarse quadrature is within a few per cent of the fine one (the trapezoidal
    /// rule's h^2 error: 16 times that of 64 intervals), on a tapered, pre-curved whisker
    /// on a spring under a force and an oblique flow.
    #[test]
    fn sixteen_intervals_are_within_a_few_per_cent() {
        let w = Whisker::new(0.3, 1.5, -0.8, 8.0);
        let loads = Loads::combined(TipForce::dp(2.0, 0.7), 3.0, -0.4);
        let (_, t64) = rotations(&w, &loads);
        let (b16, t16) = rotations_on::<16>(&w, &loads);
        let (b256, t256) = rotations_on::<256>(&w, &loads);
        assert!((t16 - t256).abs() <= 0.03 * t256.abs(), "{t16} vs {t256}");
        assert!((b16 - b256).abs() <= 0.03 * b256.abs(), "{b16} vs {b256}");
        // second order: 16 intervals err ~16 times as much as 64
        let ratio = (t16 - t256) / (t64 - t256);
        assert!((ratio - 16.0).abs() < 2.0, "{ratio}");
    }

    /// Against the non-linear solution at small loads: tapered, pre-curved, on a spring,
    /// under a tip force and an oblique flow.
    #[test]
    fn matches_the_elastica_at_small_loads() {
        let w = Whisker::new(0.4, 0.8, -0.5, 15.0);
        let loads = Loads::combined(TipForce::dp(0.7, 0.4), 2.0, 0.6);
        let lin = tip_rotation(&w, &loads);
        for eps in [1e-3, 1e-4] {
            let small = loads.scaled(eps);
            let sol = solve(&Scene::new(w, small), &Method::accurate()).unwrap();
            let delta = (sol.loaded_end.phi - w.phi_unloaded(1.0)) / eps;
            // first order: the difference is O(eps) relative
            assert!(
                (delta - lin).abs() <= 20.0 * eps * lin.abs(),
                "{eps}: {delta} vs {lin}"
            );
        }
    }
}
