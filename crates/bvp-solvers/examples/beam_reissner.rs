//! The extensible and shearable (Reissner) elastica: a planar cantilever of length `L` under
//! a tip force `(P_x, P_y)`, six states `(x, y, theta, n_x, n_y, m)` along the undeformed arc
//! length `s`:
//!
//! `x' = (1 + eps) cos(theta) - gamma sin(theta)`, `y' = (1 + eps) sin(theta) + gamma cos(theta)`,
//! `theta' = m / EI`, `n' = 0`, `m' = -(x' n_y - y' n_x)`,
//!
//! with the axial and shear strains `eps = N / EA`, `gamma = V / GA`, `N = n . d1`,
//! `V = n . d2`, `d1 = (cos, sin)`, `d2 = (-sin, cos)`. Clamped at `s = 0`
//! (`x = y = theta = 0`), loaded at `s = L` (`n = P`, `m = 0`).
//!
//! Checks (tests/beam_examples.rs): the linear limit `v = P L^3 / 3EI + P L / GA` (bending
//! plus shear), the axial stretch `L (1 + T / EA)`, the first integral
//! `m^2 / 2EI + n . d1 = const` of the inextensible elastica, and the published tip
//! deflection of the elastica at `P L^2 / EI = 1` (Bisshopp & Drucker 1945: `0.3017 L`).
//!
//! `cargo run --example beam_reissner -p bvp-solvers`

use bvp_solvers::collocation::{solve_bvp, BvpOptions, BvpSolution};

/// Section stiffnesses of a Reissner beam.
#[derive(Clone, Copy)]
pub struct Section {
    /// Bending stiffness.
    pub ei: f64,
    /// Axial stiffness.
    pub ea: f64,
    /// Shear stiffness.
    pub ga: f64,
}

/// The cantilever of length `l` under the tip force `(px, py)`, to `tol`; the guess is the
/// straight beam.
pub fn cantilever(sec: Section, l: f64, px: f64, py: f64, tol: f64) -> BvpSolution {
    let m = 11;
    let x: Vec<f64> = (0..m).map(|i| l * i as f64 / (m - 1) as f64).collect();
    let y: Vec<Vec<f64>> = x.iter().map(|&s| vec![s, 0.0, 0.0, px, py, 0.0]).collect();
    solve_bvp(
        move |_s, y, _p, d| {
            let (c, sn) = (y[2].cos(), y[2].sin());
            let nn = y[3] * c + y[4] * sn;
            let v = -y[3] * sn + y[4] * c;
            let (eps, gam) = (nn / sec.ea, v / sec.ga);
            d[0] = (1.0 + eps) * c - gam * sn;
            d[1] = (1.0 + eps) * sn + gam * c;
            d[2] = y[5] / sec.ei;
            d[3] = 0.0;
            d[4] = 0.0;
            d[5] = -(d[0] * y[4] - d[1] * y[3]);
        },
        move |ya, yb, _p, r| {
            r[0] = ya[0];
            r[1] = ya[1];
            r[2] = ya[2];
            r[3] = yb[3] - px;
            r[4] = yb[4] - py;
            r[5] = yb[5];
        },
        &x,
        &y,
        &[],
        &BvpOptions {
            tol,
            ..Default::default()
        },
    )
    .expect("the Reissner cantilever solves")
}

#[allow(dead_code)]
fn main() {
    let stiff = Section {
        ei: 1.0,
        ea: 1e9,
        ga: 1e9,
    };
    let sol = cantilever(stiff, 1.0, 0.0, -1.0, 1e-8);
    let tip = sol.y.last().unwrap();
    println!(
        "elastica, PL^2/EI = 1: tip deflection {:.5} L (published 0.3017), shortening {:.5} L, {} nodes",
        -tip[1],
        1.0 - tip[0],
        sol.x.len()
    );
    let soft = Section {
        ei: 1.0,
        ea: 50.0,
        ga: 20.0,
    };
    let sol = cantilever(soft, 1.0, 0.0, -1e-4, 1e-10);
    let tip = sol.y.last().unwrap();
    println!(
        "linear limit with shear: v = {:.6e} (P L^3/3EI + P L/GA = {:.6e})",
        -tip[1],
        1e-4 / 3.0 + 1e-4 / 20.0
    );
}
