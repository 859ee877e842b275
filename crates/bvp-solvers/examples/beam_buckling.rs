//! Euler buckling loads as eigenvalues: a pinned-pinned column `EI w'' + P w = 0`,
//! `w(0) = w(L) = 0`, with `p = P L^2 / EI` an unknown parameter and the amplitude fixed by
//! `w'(0) = 1`. The mode is chosen by the guess (`sin(j pi x)`); the loads are
//! `p_j = j^2 pi^2` (Euler: `pi^2`, `4 pi^2`, `9 pi^2`, ...).
//!
//! `cargo run --example beam_buckling -p bvp-solvers`

use bvp_solvers::collocation::{solve_bvp, BvpOptions};
use std::f64::consts::PI;

/// The `j`-th buckling load `p = P L^2 / EI` found from the guess `sin(j pi x)` and
/// `p = 0.8 (j pi)^2`, to `tol`.
pub fn buckling_load(j: usize, tol: f64) -> f64 {
    let m = 4 * j + 3;
    let w = j as f64 * PI;
    let x: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
    let y: Vec<Vec<f64>> = x
        .iter()
        .map(|&t| vec![(w * t).sin() / w, (w * t).cos()])
        .collect();
    let sol = solve_bvp(
        |_x, y, p, d| {
            d[0] = y[1];
            d[1] = -p[0] * y[0];
        },
        |ya, yb, _p, r| {
            r[0] = ya[0];
            r[1] = yb[0];
            r[2] = ya[1] - 1.0;
        },
        &x,
        &y,
        &[0.8 * w * w],
        &BvpOptions {
            tol,
            ..Default::default()
        },
    )
    .expect("the buckling eigenproblem solves");
    sol.p[0]
}

#[allow(dead_code)]
fn main() {
    for j in 1..=4 {
        let p = buckling_load(j, 1e-6);
        let e = (j * j) as f64 * PI * PI;
        println!(
            "mode {j}: p = {p:.8} (j^2 pi^2 = {e:.8}, rel. error {:.1e})",
            (p - e).abs() / e
        );
    }
}
