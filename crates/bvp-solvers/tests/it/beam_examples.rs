//! The beam examples (crates/bvp-solvers/examples/beam_*.rs, rod_kirchhoff.rs) against
//! closed forms and published values.

#[path = "../../examples/beam_buckling.rs"]
#[allow(dead_code)]
mod beam_buckling;
#[path = "../../examples/beam_reissner.rs"]
#[allow(dead_code)]
mod beam_reissner;
#[path = "../../examples/beam_winkler.rs"]
#[allow(dead_code)]
mod beam_winkler;
#[path = "../../examples/rod_kirchhoff.rs"]
#[allow(dead_code)]
mod rod_kirchhoff;

use beam_reissner::Section;
use rod_kirchhoff::Rod;
use std::f64::consts::PI;

/// Winkler beams of length 30 and 50 (where single shooting's residual was 6e4): the
/// closed form to 1e-7 (4e-7 of the deflection q/k) at tol 1e-6 over 1001 points.
#[test]
fn winkler_beam_lengths_30_and_50() {
    for l in [30.0, 50.0] {
        let sol = beam_winkler::solve(l, 1e-6);
        let err = (0..=1000)
            .map(|i| l * i as f64 / 1000.0)
            .map(|x| (sol.eval(x)[0] - beam_winkler::exact(l, x)).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-7, "L = {l}: error {err:e}, {} nodes", sol.x.len());
        // mid-span: the foundation carries the load, w = q / k up to the ends' e^(-L/2)
        let mid = (sol.eval(l / 2.0)[0] - 0.25).abs();
        assert!(
            mid < 1e-7 + 0.5 * (-l / 2.0f64).exp(),
            "L = {l}: mid-span off by {mid:e}"
        );
    }
}

/// Euler's loads `j^2 pi^2` for the first four modes to 1e-7 relative at tol 1e-6.
#[test]
fn euler_buckling_loads() {
    for j in 1..=4 {
        let p = beam_buckling::buckling_load(j, 1e-6);
        let e = (j * j) as f64 * PI * PI;
        assert!((p - e).abs() / e < 1e-7, "mode {j}: {p} vs {e}");
    }
}

/// Reissner beam, linear limit: tip deflection `P L^3 / 3EI + P L / GA` (relative 1e-3 at
/// `P = 1e-4`, the non-linear correction being O(P^2)); axial load: `L (1 + T / EA)` exactly
/// (the beam stays straight).
#[test]
fn reissner_linear_limits() {
    let sec = Section {
        ei: 1.0,
        ea: 50.0,
        ga: 20.0,
    };
    let p = 1e-4;
    let sol = beam_reissner::cantilever(sec, 1.0, 0.0, -p, 1e-10);
    let v = -sol.y.last().unwrap()[1];
    let exact = p / 3.0 + p / 20.0;
    assert!((v - exact).abs() / exact < 1e-3, "{v:e} vs {exact:e}");
    let sol = beam_reissner::cantilever(sec, 2.0, 5.0, 0.0, 1e-10);
    let tip = sol.y.last().unwrap();
    assert!((tip[0] - 2.0 * (1.0 + 5.0 / 50.0)).abs() < 1e-10 && tip[1].abs() < 1e-12);
}

/// Reissner beam with large `EA`, `GA` (the elastica): the first integral
/// `m^2 / 2EI + n . d1` is constant along the beam (to 1e-7), and the tip deflection at
/// `P L^2 / EI = 1` is Bisshopp & Drucker's 0.3017 L (tabulated to 4 digits).
#[test]
fn reissner_elastica_first_integral_and_published_deflection() {
    let sec = Section {
        ei: 1.0,
        ea: 1e10,
        ga: 1e10,
    };
    let sol = beam_reissner::cantilever(sec, 1.0, 0.0, -1.0, 1e-8);
    let h = |y: &[f64]| y[5] * y[5] / 2.0 + y[3] * y[2].cos() + y[4] * y[2].sin();
    let h0 = h(&sol.y[0]);
    for s in (0..=100).map(|i| i as f64 / 100.0) {
        let y = sol.eval(s);
        assert!((h(&y) - h0).abs() < 1e-7, "s = {s}: {} vs {h0}", h(&y));
    }
    let v = -sol.y.last().unwrap()[1];
    assert!((v - 0.3017).abs() < 1e-4, "tip deflection {v}");
}

/// Kirchhoff rod, pure twist: straight, tip angle `T L / GJ` (1e-9).
#[test]
fn kirchhoff_rod_pure_twist() {
    let rod = Rod { ei: 1.0, gj: 0.7 };
    let sol = rod_kirchhoff::solve(rod, 1.0, [0.0; 3], [0.0, 0.0, 0.5], 1e-8);
    let q = sol.y.last().unwrap();
    let ang = 2.0 * q[6].atan2(q[3]);
    assert!((ang - 0.5 / 0.7).abs() < 1e-9, "{ang}");
    assert!(q[0].abs() < 1e-12 && q[1].abs() < 1e-12 && (q[2] - 1.0).abs() < 1e-12);
}

/// Kirchhoff rod under a pure moment `M` (no force): the centreline is a helix about `M`:
/// `r . M^ = s cos(alpha)`, and its projection normal to `M` is a circle through the origin of
/// radius `R = EI sin(alpha) / |M|` swept at `|M| / EI`, so `|r_perp(s)| = 2 R sin(|M| s / 2EI)`.
#[test]
fn kirchhoff_rod_pure_moment_is_a_helix() {
    let rod = Rod { ei: 1.0, gj: 0.6 };
    let m = [1.5, 0.5, 2.0];
    let sol = rod_kirchhoff::solve(rod, 2.0, [0.0; 3], m, 1e-8);
    let mn = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    let mh = m.map(|v| v / mn);
    let ca = mh[2];
    let r_h = rod.ei * (1.0 - ca * ca).sqrt() / mn;
    for s in (0..=40).map(|i| i as f64 * 0.05) {
        let y = sol.eval(s);
        let along = y[0] * mh[0] + y[1] * mh[1] + y[2] * mh[2];
        assert!(
            (along - s * ca).abs() < 1e-7,
            "s = {s}: {along} vs {}",
            s * ca
        );
        let perp = [
            y[0] - along * mh[0],
            y[1] - along * mh[1],
            y[2] - along * mh[2],
        ];
        let chord = (perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2]).sqrt();
        let exact = 2.0 * r_h * (mn * s / (2.0 * rod.ei)).sin().abs();
        assert!((chord - exact).abs() < 1e-7, "s = {s}: {chord} vs {exact}");
    }
}

/// Kirchhoff rod with an in-plane tip force: the planar elastica of the 6-state Reissner
/// beam with large `EA`, `GA` (two formulations, quaternions vs an angle), to 1e-6.
#[test]
fn kirchhoff_rod_in_plane_matches_planar_elastica() {
    let rod = Rod { ei: 1.0, gj: 0.8 };
    let sol3 = rod_kirchhoff::solve(rod, 1.0, [-2.0, 0.0, 0.0], [0.0; 3], 1e-8);
    let sec = Section {
        ei: 1.0,
        ea: 1e10,
        ga: 1e10,
    };
    // the planar beam along x with the force along -y: (x, y) <-> (z, x)
    let sol2 = beam_reissner::cantilever(sec, 1.0, 0.0, -2.0, 1e-8);
    for s in (0..=20).map(|i| i as f64 / 20.0) {
        let a = sol3.eval(s);
        let b = sol2.eval(s);
        assert!((a[2] - b[0]).abs() < 1e-6 && (a[0] - b[1]).abs() < 1e-6 && a[1].abs() < 1e-12);
    }
}
