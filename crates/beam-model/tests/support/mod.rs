//! Independent reference solutions shared by the tests: Mattiasson's elliptic-integral
//! solution of the tip-loaded cantilever (via Carlson's symmetric integrals) and
//! high-resolution quadrature of load-free shapes.
#![allow(dead_code)]

/// Carlson's R_F(x, y, z) (duplication algorithm, relative accuracy ~1e-16).
pub fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    for _ in 0..200 {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * sy + sy * sz + sz * sx;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        let a = (x + y + z) / 3.0;
        let d = (a - x).abs().max((a - y).abs()).max((a - z).abs());
        if d < 1e-4 * a {
            let (dx, dy) = ((a - x) / a, (a - y) / a);
            let dz = -dx - dy;
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0)
                / a.sqrt();
        }
    }
    f64::NAN
}

/// Carlson's R_D(x, y, z).
pub fn carlson_rd(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    let mut sum = 0.0;
    let mut fac = 1.0;
    for _ in 0..200 {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * sy + sy * sz + sz * sx;
        sum += fac / (sz * (z + lam));
        fac *= 0.25;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        let a = (x + y + 3.0 * z) / 5.0;
        let d = (a - x).abs().max((a - y).abs()).max((a - z).abs());
        if d < 1e-4 * a {
            let (dx, dy) = ((a - x) / a, (a - y) / a);
            let dz = -(dx + dy) / 3.0;
            let ea = dx * dy;
            let eb = dz * dz;
            let ec = ea - eb;
            let ed = ea - 6.0 * eb;
            let ee = ed + ec + ec;
            let s = ed * (-3.0 / 14.0 + 9.0 / 88.0 * ed - 4.5 / 26.0 * dz * ee)
                + dz * (ee / 6.0 + dz * (-9.0 / 22.0 * ec + dz * 3.0 / 26.0 * ea));
            return 3.0 * sum + fac * (1.0 + s) / (a * a.sqrt());
        }
    }
    f64::NAN
}

/// Incomplete elliptic integral of the first kind F(phi | k).
pub fn ell_f(phi: f64, k: f64) -> f64 {
    let (s, c) = phi.sin_cos();
    s * carlson_rf(c * c, 1.0 - k * k * s * s, 1.0)
}

/// Incomplete elliptic integral of the second kind E(phi | k).
pub fn ell_e(phi: f64, k: f64) -> f64 {
    let (s, c) = phi.sin_cos();
    let (x, y) = (c * c, 1.0 - k * k * s * s);
    s * carlson_rf(x, y, 1.0) - k * k * s * s * s * carlson_rd(x, y, 1.0) / 3.0
}

/// Tip of a straight, uniform, clamped cantilever of length 1 under a perpendicular end load
/// f (Bisshopp & Drucker 1945; Mattiasson 1981): returns (lateral x1, axial y1, tip rotation).
/// The rotation t solves sqrt(f) = K(k) - F(phi_a, k) with k^2 = (1 + sin t)/2 and
/// sin phi_a = 1/(k sqrt 2); x1 = 1 - 2 (E(k) - E(phi_a, k))/sqrt(f), y1 = sqrt(2 sin t / f).
pub fn mattiasson(f: f64) -> (f64, f64, f64) {
    let g = |t: f64| {
        let k = ((1.0 + t.sin()) / 2.0).sqrt();
        let pa = (1.0 / (k * 2f64.sqrt())).asin();
        ell_f(std::f64::consts::FRAC_PI_2, k) - ell_f(pa, k) - f.sqrt()
    };
    // bisection to machine precision on (0, pi/2)
    let (mut a, mut b) = (1e-12, std::f64::consts::FRAC_PI_2 - 1e-15);
    let ga = g(a);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if (g(m) > 0.0) == (ga > 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    let t = 0.5 * (a + b);
    let k = ((1.0 + t.sin()) / 2.0).sqrt();
    let pa = (1.0 / (k * 2f64.sqrt())).asin();
    let x1 = 1.0 - 2.0 * (ell_e(std::f64::consts::FRAC_PI_2, k) - ell_e(pa, k)) / f.sqrt();
    let y1 = (2.0 * t.sin() / f).sqrt();
    (x1, y1, t)
}

/// Composite Simpson rule of `g` on [a, b] with `n` (even) intervals.
pub fn simpson(g: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = g(a) + g(b);
    for i in 1..n {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        s += w * g(a + i as f64 * h);
    }
    s * h / 3.0
}
