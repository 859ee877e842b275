//! A long beam on a Winkler foundation, `EI w'''' + k w = q`, simply supported at both ends
//! (`w = w'' = 0`), uniform load `q`: collocation with the states `(w, w', w'', w''')`.
//! Shooting fails here (the solutions `e^{beta x}` grow by `e^{beta L}`, `1e13` at `L = 30`);
//! collocation does not care.
//!
//! Closed form (Hetenyi), `beta = (k / 4 EI)^(1/4)`: away from the coupling of the two ends
//! (`e^{-beta L}`, below `1e-13` here) `w = q/k (1 - e^{-beta x} cos(beta x) -
//! e^{-beta (L - x)} cos(beta (L - x)))`.
//!
//! `cargo run --example beam_winkler -p bvp-solvers`

use bvp_solvers::collocation::{solve_bvp, BvpOptions, BvpSolution};

/// Bending stiffness, foundation modulus, load.
pub const EI: f64 = 1.0;
/// Foundation modulus (`beta = 1`).
pub const K: f64 = 4.0;
/// Uniform load.
pub const Q: f64 = 1.0;

/// Solves the beam of length `l` to `tol`.
pub fn solve(l: f64, tol: f64) -> BvpSolution {
    let x: Vec<f64> = (0..5).map(|i| l * i as f64 / 4.0).collect();
    solve_bvp(
        |_x, y, _p, d| {
            d[0] = y[1];
            d[1] = y[2];
            d[2] = y[3];
            d[3] = (Q - K * y[0]) / EI;
        },
        |ya, yb, _p, r| {
            r[0] = ya[0];
            r[1] = ya[2];
            r[2] = yb[0];
            r[3] = yb[2];
        },
        &x,
        &vec![vec![0.0; 4]; 5],
        &[],
        &BvpOptions {
            tol,
            ..Default::default()
        },
    )
    .expect("the Winkler beam solves")
}

/// The closed-form deflection (see the module doc).
pub fn exact(l: f64, x: f64) -> f64 {
    let beta = (K / (4.0 * EI)).powf(0.25);
    let (u, v) = (beta * x, beta * (l - x));
    Q / K * (1.0 - (-u).exp() * u.cos() - (-v).exp() * v.cos())
}

#[allow(dead_code)]
fn main() {
    for l in [30.0, 50.0] {
        let sol = solve(l, 1e-6);
        let err = (0..=1000)
            .map(|i| l * i as f64 / 1000.0)
            .map(|x| (sol.eval(x)[0] - exact(l, x)).abs())
            .fold(0.0, f64::max);
        println!(
            "L = {l}: {} nodes, w(L/2) = {:.6} (q/k = {}), max error {err:.2e}, residual {:.1e}",
            sol.x.len(),
            sol.eval(l / 2.0)[0],
            Q / K,
            sol.max_rms_residual
        );
    }
}
