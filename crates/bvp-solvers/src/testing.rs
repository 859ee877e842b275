//! What the unit tests share: test systems with closed-form solutions and the measured
//! order of a convergence study.

use crate::integrator::OdeSystem;

/// `u0' = u1, u1' = -u0`: `u = (sin s, cos s)` from `u(0) = (0, 1)`.
pub(crate) struct Harmonic;

impl OdeSystem for Harmonic {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
        du[0] = u[1];
        du[1] = -u[0];
    }
}

/// `u_i' = -sin(u_{i+1}) + s u_i` (cyclic): a non-linear, non-autonomous system of any
/// dimension whose components all differ.
pub(crate) struct Ring(pub usize);

impl OdeSystem for Ring {
    fn dim(&self) -> usize {
        self.0
    }
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]) {
        for i in 0..self.0 {
            du[i] = -u[(i + 1) % self.0].sin() + s * u[i];
        }
    }
}

/// The dimensions DOP853's loops are unrolled for (`by_dim!`: 2, 4, 8, 20), each with its
/// [`Ring`] and a start state `u_i = 0.1 i - 0.3`.
pub(crate) fn ring_cases() -> impl Iterator<Item = (usize, Ring, Vec<f64>)> {
    [2, 4, 8, 20]
        .into_iter()
        .map(|n| (n, Ring(n), (0..n).map(|i| 0.1 * i as f64 - 0.3).collect()))
}

/// Least-squares slope of `ln err` against `ln h`: the measured order of a method whose
/// error at step `h[i]` is `err[i]`.
pub(crate) fn loglog_slope(h: &[f64], err: &[f64]) -> f64 {
    let xs: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let ys: Vec<f64> = err.iter().map(|v| v.ln()).collect();
    let m = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / m;
    let my = ys.iter().sum::<f64>() / m;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn loglog_slope_of_a_power_law_is_its_exponent() {
    let h = [0.1, 0.05, 0.025, 0.0125];
    let err: Vec<f64> = h.iter().map(|h: &f64| 3.0 * h.powi(4)).collect();
    assert!((loglog_slope(&h, &err) - 4.0).abs() < 1e-12);
}
