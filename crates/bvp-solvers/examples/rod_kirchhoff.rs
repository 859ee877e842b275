//! A 3D Kirchhoff rod (inextensible, unshearable) clamped at `s = 0` along `e3`, with a tip
//! force `F` and tip moment `M` (twist and bending): 13 states
//! `(r (3), q (4, the unit quaternion of the directors), n (3), m (3))`, forces and moments
//! in the fixed frame:
//!
//! `r' = d3`, `q' = q (0, kappa) / 2`, `kappa = K^-1 R(q)^T m`, `n' = 0`, `m' = -d3 x n`,
//!
//! `K = diag(EI, EI, GJ)`, `d3 = R(q) e3`. Boundary rows: `r(0) = 0`, `q(0) = (1, 0, 0, 0)`,
//! `n(L) = F`, `m(L) = M`.
//!
//! Checks (tests/beam_examples.rs): a pure twist `M = (0, 0, T)` keeps the rod straight and
//! turns the tip by `T L / GJ`; a pure moment makes a helix about `M` (radius
//! `EI sin(alpha) / |M|`, turning at `|M| / EI` per unit length, `alpha` the angle between
//! `e3` and `M`); an in-plane tip force gives the planar elastica of `beam_reissner`.
//!
//! `cargo run --example rod_kirchhoff -p bvp-solvers`

use bvp_solvers::collocation::{solve_bvp, BvpOptions, BvpSolution};

/// Stiffnesses of the rod.
#[derive(Clone, Copy)]
pub struct Rod {
    /// Bending stiffness (both axes).
    pub ei: f64,
    /// Torsional stiffness.
    pub gj: f64,
}

/// `R(q) v` for a unit quaternion `q = (w, x, y, z)`.
pub fn rotate(q: &[f64], v: [f64; 3]) -> [f64; 3] {
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    [0, 1, 2].map(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2])
}

/// `R(q)^T v`.
pub fn rotate_back(q: &[f64], v: [f64; 3]) -> [f64; 3] {
    rotate(&[q[0], -q[1], -q[2], -q[3]], v)
}

/// The right-hand side of the 13 states.
pub fn rhs(rod: Rod, y: &[f64], d: &mut [f64]) {
    let q = &y[3..7];
    let nq = (q.iter().map(|v| v * v).sum::<f64>()).sqrt();
    let qn = [q[0] / nq, q[1] / nq, q[2] / nq, q[3] / nq];
    let d3 = rotate(&qn, [0.0, 0.0, 1.0]);
    let mb = rotate_back(&qn, [y[10], y[11], y[12]]);
    let k = [mb[0] / rod.ei, mb[1] / rod.ei, mb[2] / rod.gj];
    d[..3].copy_from_slice(&d3);
    // q' = q (0, k) / 2
    let (w, x, yy, z) = (q[0], q[1], q[2], q[3]);
    d[3] = 0.5 * (-x * k[0] - yy * k[1] - z * k[2]);
    d[4] = 0.5 * (w * k[0] + yy * k[2] - z * k[1]);
    d[5] = 0.5 * (w * k[1] + z * k[0] - x * k[2]);
    d[6] = 0.5 * (w * k[2] + x * k[1] - yy * k[0]);
    d[7] = 0.0;
    d[8] = 0.0;
    d[9] = 0.0;
    let n = [y[7], y[8], y[9]];
    d[10] = -(d3[1] * n[2] - d3[2] * n[1]);
    d[11] = -(d3[2] * n[0] - d3[0] * n[2]);
    d[12] = -(d3[0] * n[1] - d3[1] * n[0]);
}

/// The rod of length `l` under the tip force `f` and tip moment `m`, to `tol`, from the
/// straight, untwisted guess.
pub fn solve(rod: Rod, l: f64, f: [f64; 3], m: [f64; 3], tol: f64) -> BvpSolution {
    let nodes = 21;
    let x: Vec<f64> = (0..nodes)
        .map(|i| l * i as f64 / (nodes - 1) as f64)
        .collect();
    let y: Vec<Vec<f64>> = x
        .iter()
        .map(|&s| {
            vec![
                0.0, 0.0, s, 1.0, 0.0, 0.0, 0.0, f[0], f[1], f[2], m[0], m[1], m[2],
            ]
        })
        .collect();
    solve_bvp(
        move |_s, y, _p, d| rhs(rod, y, d),
        move |ya, yb, _p, r| {
            r[0] = ya[0];
            r[1] = ya[1];
            r[2] = ya[2];
            r[3] = ya[3] - 1.0;
            r[4] = ya[4];
            r[5] = ya[5];
            r[6] = ya[6];
            for i in 0..3 {
                r[7 + i] = yb[7 + i] - f[i];
                r[10 + i] = yb[10 + i] - m[i];
            }
        },
        &x,
        &y,
        &[],
        &BvpOptions {
            tol,
            max_nodes: 20_000,
            ..Default::default()
        },
    )
    .expect("the Kirchhoff rod solves")
}

#[allow(dead_code)]
fn main() {
    let rod = Rod { ei: 1.0, gj: 0.7 };
    let sol = solve(rod, 1.0, [0.0; 3], [0.0, 0.0, 0.5], 1e-8);
    let q = sol.y.last().unwrap();
    println!(
        "pure twist T = 0.5: tip angle {:.8} (T L / GJ = {:.8})",
        2.0 * q[6].atan2(q[3]),
        0.5 / 0.7
    );
    let sol = solve(rod, 1.0, [-1.0, 0.0, 0.0], [0.0, 0.0, 0.3], 1e-8);
    let tip = sol.y.last().unwrap();
    println!(
        "tip force -e1 and twist 0.3: tip at ({:.5}, {:.5}, {:.5}), {} nodes",
        tip[0],
        tip[1],
        tip[2],
        sol.x.len()
    );
}
