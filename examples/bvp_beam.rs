//! The boundary-value solvers under vibrissa reused for problems that have nothing to do with
//! whiskers, through the facade (`vibrissa::bvp_solvers`), each checked against its closed
//! form.
//!
//! ```sh
//! cargo run --release --example bvp_beam
//! ```
//!
//! 1. **A beam on an elastic (Winkler) foundation** under a uniform load, simply supported at
//!    both ends: `w'''' + 4 beta^4 w = 1` on `[0, 1]`, `w = w'' = 0` at `x = 0, 1` (lengths
//!    in the span, `w` in `q L^4 / EI`, `4 beta^4 = k L^4 / EI`), as the first-order system
//!    `(w, w', w'', w''')` by collocation
//!    ([`vibrissa::bvp_solvers::collocation::solve_bvp`], the scheme of scipy's `solve_bvp`).
//!    The closed form (Hetenyi 1946; with `xi = x - 1/2`, `c = beta / 2`):
//!    `w = (1 - 2 (cosh c cos c cosh(beta xi) cos(beta xi) + sinh c sin c sinh(beta xi)
//!    sin(beta xi)) / (cosh 2c + cos 2c)) / (4 beta^4)`,
//!    itself checked against the sine series `sum_{n odd} 4 sin(n pi x) / (n pi ((n pi)^4 +
//!    4 beta^4))`.
//! 2. **Euler buckling** of a pinned-pinned column, `w'' + p w = 0`, `w(0) = w(1) = 0`,
//!    `w'(0) = 1`, with the load `p = P L^2 / EI` an unknown parameter of the BVP: the first
//!    two modes against `p_j = j^2 pi^2`.
//!
//! Each answer is printed with its error against the closed form and the solver's own
//! residual (its error estimate); a failed check prints one line on stderr and exits with 1.

// `!(error <= tolerance)` on purpose: a NaN fails every check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::error::Error;
use std::f64::consts::PI;
use std::process::ExitCode;

use vibrissa::bvp_solvers::collocation::{solve_bvp, BvpOptions};

/// The foundation's stiffness parameter beta: `4 beta^4 = k L^4 / EI` (boundary layers
/// about `1 / beta` wide at the supports).
const BETA: f64 = 4.0;

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The Winkler beam's deflection in closed form (module docs).
fn winkler_exact(x: f64, beta: f64) -> f64 {
    let (c, xi) = (beta / 2.0, beta * (x - 0.5));
    let d = (2.0 * c).cosh() + (2.0 * c).cos();
    let shape =
        c.cosh() * c.cos() * xi.cosh() * xi.cos() + c.sinh() * c.sin() * xi.sinh() * xi.sin();
    (1.0 - 2.0 * shape / d) / (4.0 * beta.powi(4))
}

/// The same deflection by its sine series (odd terms up to `n_max`; truncation error below
/// `1 / (pi^5 n_max^4)`).
fn winkler_series(x: f64, beta: f64, n_max: usize) -> f64 {
    (1..=n_max)
        .step_by(2)
        .map(|n| {
            let k = n as f64 * PI;
            4.0 * (k * x).sin() / (k * (k.powi(4) + 4.0 * beta.powi(4)))
        })
        .sum()
}

/// Solves the Winkler beam to `tol`; returns (largest error against the closed form on 401
/// points, the solver's largest relative residual, mesh nodes).
fn winkler(tol: f64) -> Result<(f64, f64, usize), Box<dyn Error>> {
    let b4 = 4.0 * BETA.powi(4);
    let x: Vec<f64> = (0..11).map(|i| f64::from(i) / 10.0).collect();
    let guess = vec![vec![0.0; 4]; x.len()];
    let sol = solve_bvp(
        |_x, y, _p, dy| {
            dy[0] = y[1];
            dy[1] = y[2];
            dy[2] = y[3];
            dy[3] = 1.0 - b4 * y[0];
        },
        |ya, yb, _p, r| {
            r[0] = ya[0];
            r[1] = ya[2];
            r[2] = yb[0];
            r[3] = yb[2];
        },
        &x,
        &guess,
        &[],
        &BvpOptions {
            tol,
            ..BvpOptions::default()
        },
    )?;
    let err = (0..=400)
        .map(|i| f64::from(i) / 400.0)
        .map(|t| (sol.eval(t)[0] - winkler_exact(t, BETA)).abs())
        .fold(0.0, f64::max);
    Ok((err, sol.max_rms_residual, sol.x.len()))
}

/// The `j`-th buckling load of the pinned-pinned column, from the guess `sin(j pi x)` and
/// `p = 0.8 (j pi)^2`, to `tol`; returns (p, the solver's largest relative residual).
fn buckling(j: u32, tol: f64) -> Result<(f64, f64), Box<dyn Error>> {
    let w = f64::from(j) * PI;
    let m = 4 * j + 3;
    let x: Vec<f64> = (0..m).map(|i| f64::from(i) / f64::from(m - 1)).collect();
    let guess: Vec<Vec<f64>> = x
        .iter()
        .map(|&t| vec![(w * t).sin() / w, (w * t).cos()])
        .collect();
    let sol = solve_bvp(
        |_x, y, p, dy| {
            dy[0] = y[1];
            dy[1] = -p[0] * y[0];
        },
        |ya, yb, _p, r| {
            r[0] = ya[0];
            r[1] = yb[0];
            r[2] = ya[1] - 1.0;
        },
        &x,
        &guess,
        &[0.8 * w * w],
        &BvpOptions {
            tol,
            ..BvpOptions::default()
        },
    )?;
    Ok((sol.p[0], sol.max_rms_residual))
}

fn run() -> Result<(), Box<dyn Error>> {
    // The closed form against the series: independent of the solver, and of each other.
    let series_gap = (0..=100)
        .map(|i| f64::from(i) / 100.0)
        .map(|t| (winkler_exact(t, BETA) - winkler_series(t, BETA, 4001)).abs())
        .fold(0.0, f64::max);
    let w_mid = winkler_exact(0.5, BETA);
    println!(
        "Winkler beam, beta = {BETA}: w(1/2) = {w_mid:.12e} (closed form; its sine series agrees \
         to {series_gap:.1e})"
    );
    if !(series_gap <= 1e-12 * w_mid.abs().max(1e-300)) {
        return Err(format!("closed form and series differ by {series_gap:e}").into());
    }
    let mut errors = Vec::new();
    for tol in [1e-4, 1e-6, 1e-8] {
        let (err, residual, nodes) = winkler(tol)?;
        println!(
            "  collocation tol {tol:.0e}: {nodes:>4} nodes, residual {residual:.1e}, \
             max |w - exact| {err:.2e} ({:.1e} of w(1/2))",
            err / w_mid
        );
        errors.push((tol, err));
    }
    // Each answer within its tolerance (relative to w), and the error falling with it.
    for &(tol, err) in &errors {
        if !(err <= tol * w_mid) {
            return Err(format!("Winkler beam at tol {tol:e}: error {err:e}").into());
        }
    }
    if !(errors[2].1 < errors[0].1 / 100.0) {
        return Err(format!("the error does not fall with the tolerance: {errors:?}").into());
    }

    println!("Euler buckling, pinned-pinned column (p = P L^2 / EI):");
    for j in 1..=2 {
        let (p, residual) = buckling(j, 1e-8)?;
        let exact = f64::from(j * j) * PI * PI;
        let rel = (p - exact).abs() / exact;
        println!("  mode {j}: p = {p:.12} (j^2 pi^2 = {exact:.12}, rel. error {rel:.1e}, residual {residual:.1e})");
        if !(rel <= 1e-7) {
            return Err(format!("buckling mode {j}: p = {p}, relative error {rel:e}").into());
        }
    }
    println!("checks passed");
    Ok(())
}

#[test]
fn example_checks_pass() {
    run().expect("the example's checks");
}
