//! The two uses of the driver together: the natural path on the graph part of a folding
//! branch, and pseudo-arclength taking over where it stalls at the fold.

use super::*;
use crate::BvpError;

/// Newton on `x^3 - 3x = lambda` from `x`.
fn cubic_root(lambda: f64, mut x: f64) -> Result<f64, BvpError> {
    for _ in 0..60 {
        let r = x * x * x - 3.0 * x - lambda;
        if r.abs() <= 1e-14 * (1.0 + lambda.abs()) {
            return Ok(x);
        }
        x -= r / (3.0 * x * x - 3.0);
    }
    Err(BvpError::NoConvergence {
        method: "cubic",
        iterations: 60,
        residual: x * x * x - 3.0 * x - lambda,
    })
}

/// The lowest root of `x^3 - 3x = lambda` for `|lambda| <= 2` (trigonometric form).
fn lower(lambda: f64) -> f64 {
    let third = (0.5 * lambda).acos() / 3.0;
    2.0 * (third - 4.0 * std::f64::consts::FRAC_PI_3).cos()
}

/// The curve `x^3 - 3x - lambda = 0` in `u = (x, lambda)`, corrected by Newton on the
/// bordered 2x2 system.
struct Cubic;

impl Curve<2> for Cubic {
    type Point = [f64; 2];
    type Error = &'static str;
    fn coords(&self, p: &[f64; 2]) -> [f64; 2] {
        *p
    }
    fn correct(
        &self,
        _from: &[f64; 2],
        p: [f64; 2],
        n: [f64; 2],
        radius: f64,
    ) -> Result<[f64; 2], &'static str> {
        let mut u = p;
        for _ in 0..30 {
            let r0 = u[0] * u[0] * u[0] - 3.0 * u[0] - u[1];
            let r1 = n[0] * (u[0] - p[0]) + n[1] * (u[1] - p[1]);
            if r0.abs() < 1e-14 && r1.abs() < 1e-14 {
                return Ok(u);
            }
            let (a, b, c, d) = (3.0 * u[0] * u[0] - 3.0, -1.0, n[0], n[1]);
            let det = a * d - b * c;
            u[0] -= (d * r0 - b * r1) / det;
            u[1] -= (a * r1 - c * r0) / det;
            if (u[0] - p[0]).hypot(u[1] - p[1]) > radius {
                return Err("left the radius");
            }
        }
        Err("no convergence")
    }
    fn tangent(&self, p: &[f64; 2], dir: &[f64; 2]) -> [f64; 2] {
        let rate = 3.0 * p[0] * p[0] - 3.0;
        let norm = rate.hypot(1.0);
        let t = [1.0 / norm, rate / norm];
        if t[0] * dir[0] + t[1] * dir[1] < 0.0 {
            [-t[0], -t[1]]
        } else {
            t
        }
    }
    fn iterations(&self, _p: &[f64; 2]) -> usize {
        3
    }
}

/// `x^3 - 3x = lambda` from `(0, -sqrt 3)` to `lambda = 3`: natural continuation follows the
/// lower branch (a graph over lambda, equal to its closed form) up to its fold at
/// `lambda = 2` and stalls there; pseudo-arclength restarted where it stalled passes both
/// folds (located at `x = -1, lambda = 2` and `x = 1, lambda = -2`) and arrives at
/// `lambda = 3` on the upper branch, at the one real root of `x^3 - 3x - 3` (Cardano).
#[test]
fn arclength_takes_over_where_the_natural_path_folds() {
    let natural = Continuation {
        initial_step: 0.25,
        min_step: 1e-6,
        max_step: 0.25,
    };
    let guard = BranchGuard::default();
    let solve = |l: f64, p: &[f64]| cubic_root(l, p[0]).map(|x| vec![x]);
    let start = vec![-(3.0f64.sqrt())];
    let (x, _) = natural
        .follow(0.0, 1.5, start.clone(), &guard, solve)
        .unwrap();
    assert!(
        (x[0] - lower(1.5)).abs() < 1e-14,
        "{} vs {}",
        x[0],
        lower(1.5)
    );
    let stall = natural.follow(0.0, 3.0, start, &guard, solve).unwrap_err();
    assert!(
        stall.reached > 2.0 - 1e-5 && stall.reached <= 2.0,
        "{stall}"
    );

    let ctl = ArcControl {
        initial: 1e-3,
        max: 0.1,
        ..ArcControl::default()
    };
    // taken over a little short of the stall (here the natural path ends on the fold itself,
    // where the tangent is vertical in lambda)
    let back = stall.reached - 0.1;
    let from = [lower(back), back];
    // onwards as the natural path went: x rising into the fold
    let mut arc = Arclength::new(&Cubic, from, [1.0, 0.0], ctl);
    let mut folds = Vec::new();
    let mut arrival = None;
    for _ in 0..10_000 {
        let Attempt::Point(p, t) = arc.attempt(&Cubic) else {
            continue;
        };
        let (cur, rate) = (*arc.current(), arc.tangent()[1]);
        if (t[1] > 0.0) != (rate > 0.0) {
            let sign = rate.signum();
            let g = |q: &[f64; 2]| Ok(sign * (3.0 * q[0] * q[0] - 3.0));
            folds.push(locate(&Cubic, &cur, &p, &g, 1e-13).unwrap());
        }
        if p[1] >= 3.0 {
            let g = |q: &[f64; 2]| Ok(3.0 - q[1]);
            arrival = Some(locate(&Cubic, &cur, &p, &g, 1e-13).unwrap());
            break;
        }
        arc.accept(&Cubic, p, t);
    }
    assert_eq!(folds.len(), 2, "{folds:?}");
    for (fold, x) in folds.iter().zip([-1.0, 1.0]) {
        let lambda = -2.0 * x;
        assert!(
            (fold[0] - x).abs() < 1e-10 && (fold[1] - lambda).abs() < 1e-13,
            "{fold:?}"
        );
    }
    let at = arrival.unwrap();
    let s5 = 5.0f64.sqrt();
    let upper = (1.5 + 0.5 * s5).cbrt() + (1.5 - 0.5 * s5).cbrt();
    assert!((at[1] - 3.0).abs() < 1e-12, "{at:?}");
    assert!((at[0] - upper).abs() < 1e-12, "{} vs {upper}", at[0]);
}
