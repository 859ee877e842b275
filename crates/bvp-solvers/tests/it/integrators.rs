//! Integrators against closed-form solutions.

use bvp_solvers::integrator::{Dop853, Interpolant, OdeSystem, Rk4};
use bvp_solvers::BvpError;

/// u0' = u1, u1' = -u0: u = (sin s, cos s) for u(0) = (0, 1).
struct Harmonic;
impl OdeSystem for Harmonic {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
        du[0] = u[1];
        du[1] = -u[0];
    }
}

/// Non-autonomous: y' = cos(s) y, y(0) = 1 -> y = exp(sin s).
struct ExpSin;
impl OdeSystem for ExpSin {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]) {
        du[0] = s.cos() * u[0];
    }
}

/// Projectile: (x, y, vx, vy)' = (vx, vy, 0, -g).
struct Projectile {
    g: f64,
}
impl OdeSystem for Projectile {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
        du[0] = u[2];
        du[1] = u[3];
        du[2] = 0.0;
        du[3] = -self.g;
    }
}

/// 6-dim smooth problem: three decoupled rotating pairs with different frequencies,
/// u_{2j} = sin(w_j s), u_{2j+1} = cos(w_j s).
struct Rot3;
const W: [f64; 3] = [1.0, 2.0, 3.5];
impl OdeSystem for Rot3 {
    fn dim(&self) -> usize {
        6
    }
    fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
        for j in 0..3 {
            du[2 * j] = W[j] * u[2 * j + 1];
            du[2 * j + 1] = -W[j] * u[2 * j];
        }
    }
}

struct NanRhs;
impl OdeSystem for NanRhs {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, s: f64, _u: &[f64], du: &mut [f64]) {
        du[0] = if s > 0.5 { f64::NAN } else { 1.0 };
    }
}

/// Least-squares slope of log(y) against log(x).
fn loglog_slope(x: &[f64], y: &[f64]) -> f64 {
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let m = lx.len() as f64;
    let mx = lx.iter().sum::<f64>() / m;
    let my = ly.iter().sum::<f64>() / m;
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn dop853_harmonic_reaches_1e12() {
    let sol = Dop853::new(1e-13, 1e-13)
        .integrate(&Harmonic, 0.0, 10.0, &[0.0, 1.0])
        .unwrap();
    let e = (sol.u_end[0] - 10f64.sin())
        .abs()
        .max((sol.u_end[1] - 10f64.cos()).abs());
    println!("harmonic err {e:e}, stats {:?}", sol.stats);
    assert!(e < 1e-12, "error {e:e}");
    assert_eq!(sol.s_end, 10.0);
    // 8th order: a handful of steps per unit length even at 1e-13
    assert!(sol.stats.steps < 120, "{:?}", sol.stats);
    assert_eq!(
        sol.stats.rhs_evals,
        2 + 12 * sol.stats.steps + 11 * sol.stats.rejected
    );
}

#[test]
fn dop853_nonautonomous_reaches_1e12() {
    for (s1, tol) in [(5.0, 1e-14), (20.0, 1e-14)] {
        let sol = Dop853::new(tol, tol)
            .integrate(&ExpSin, 0.0, s1, &[1.0])
            .unwrap();
        let exact = f64::sin(s1).exp();
        let e = (sol.u_end[0] - exact).abs() / exact;
        println!("exp(sin) to {s1}: rel err {e:e}, {:?}", sol.stats);
        assert!(e < 1e-12, "error {e:e}");
    }
}

#[test]
fn dop853_error_scales_with_tolerance() {
    let tols = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11];
    let mut errs = Vec::new();
    let mut evals = Vec::new();
    for &tol in &tols {
        let sol = Dop853::new(tol, tol)
            .integrate(&Rot3, 0.0, 10.0, &[0.0, 1.0, 0.0, 1.0, 0.0, 1.0])
            .unwrap();
        let mut e: f64 = 0.0;
        for (j, w) in W.iter().enumerate() {
            e = e.max((sol.u_end[2 * j] - (w * 10.0).sin()).abs());
            e = e.max((sol.u_end[2 * j + 1] - (w * 10.0).cos()).abs());
        }
        errs.push(e);
        evals.push(sol.stats.rhs_evals as f64);
        // global error within two orders of magnitude of the tolerance (10 units of length)
        assert!(e < 100.0 * tol && e > 1e-4 * tol, "tol {tol:e}: err {e:e}");
    }
    let p = loglog_slope(&tols, &errs);
    // work grows like tol^(-1/8) for an 8th-order method
    let q = loglog_slope(&tols, &evals);
    println!("errs {errs:?}\nevals {evals:?}\nerr ~ tol^{p}, work ~ tol^{q}");
    assert!((0.8..=1.25).contains(&p), "error-vs-tol slope {p}");
    assert!((-0.2..=-0.08).contains(&q), "work-vs-tol slope {q}");
}

#[test]
fn dop853_stepper_interpolants_equal_the_dense_output() {
    let eager = Dop853::new(1e-12, 1e-12)
        .with_dense(true)
        .integrate(&ExpSin, 0.0, 6.0, &[1.0])
        .unwrap();
    let opts = Dop853::new(1e-12, 1e-12);
    let mut st = opts.stepper(&ExpSin, 0.0, 6.0, &[1.0]).unwrap();
    let (mut u, mut du) = ([0.0], [0.0]);
    let mut cubic_err: f64 = 0.0;
    let mut i = 0;
    while st.step().unwrap() {
        let (a, b) = (eager.step_points()[i], eager.step_points()[i + 1]);
        // the same steps as the driver's
        assert_eq!(st.start(), a);
        // nothing prepared: no interpolant; the cubic part costs no evaluation
        assert!(!st
            .interpolant::<1>()
            .unwrap()
            .eval_cubic(0.5, &mut u, &mut du));
        let evals = st.stats().rhs_evals;
        st.prepare(Interpolant::Cubic);
        assert_eq!(st.stats().rhs_evals, evals);
        let cubic = st.interpolant::<1>().unwrap();
        assert_eq!(cubic.level(), Interpolant::Cubic);
        assert!(!cubic.eval(0.5, &mut u));
        // the cubic Hermite interpolant: exact at the ends, O(h^4) inside
        assert!(cubic.eval_cubic(0.0, &mut u, &mut du));
        assert!((u[0] - a.sin().exp()).abs() < 1e-11);
        assert!((du[0] - a.cos() * a.sin().exp()).abs() < 1e-10);
        let mid = 0.5 * (a + b);
        assert!(cubic.eval_cubic(0.5, &mut u, &mut du));
        cubic_err = cubic_err.max((u[0] - mid.sin().exp()).abs());
        // in full (three evaluations): bit for bit the driver's dense output
        st.prepare(Interpolant::Full);
        assert_eq!(st.stats().rhs_evals, evals + 3);
        let full = st.interpolant::<1>().unwrap();
        assert!(st.interpolant::<2>().is_none());
        for frac in [0.1, 0.5, 0.9] {
            let s = a + frac * (b - a);
            assert!(full.eval((s - full.start()) / full.h(), &mut u));
            assert_eq!(Some(u.to_vec()), eager.eval(s), "step {i} at {s}");
        }
        i += 1;
    }
    assert_eq!(i, eager.steps());
    assert_eq!(st.state(), &eager.u_end[..]);
    // the cubic is O(h^4): far from the 7th-order accuracy, close enough to scan with
    assert!(cubic_err > 1e-10 && cubic_err < 1e-3, "{cubic_err:e}");
    // a step no longer held has no interpolant
    assert!(st.interpolant::<1>().is_none());
}

#[test]
fn dop853_backward() {
    let u2 = [2f64.sin().exp()];
    let sol = Dop853::new(1e-13, 1e-13)
        .with_dense(true)
        .integrate(&ExpSin, 2.0, -1.0, &u2)
        .unwrap();
    let exact = (-1f64).sin().exp();
    assert!((sol.u_end[0] - exact).abs() < 1e-12);
    assert_eq!(sol.s_end, -1.0);
    // dense output also works backward
    for i in 0..=60 {
        let s = 2.0 - 3.0 * i as f64 / 60.0;
        let v = sol.eval(s).unwrap()[0];
        assert!(
            (v - s.sin().exp()).abs() < 1e-11,
            "s {s}: {}",
            v - s.sin().exp()
        );
    }
    assert!(sol.eval(2.1).is_none());
    assert!(sol.eval(-1.1).is_none());
}

#[test]
fn dop853_dense_output_between_steps() {
    let sol = Dop853::new(1e-12, 1e-12)
        .with_dense(true)
        .integrate(&Harmonic, 0.0, 10.0, &[0.0, 1.0])
        .unwrap();
    let pts = sol.step_points();
    assert_eq!(pts.len(), sol.stats.steps + 1);
    assert_eq!(pts[0], 0.0);
    assert_eq!(*pts.last().unwrap(), 10.0);
    let mut max_err: f64 = 0.0;
    // quarter and midpoints of every step, where the interpolant is least accurate
    for w in pts.windows(2) {
        for frac in [0.25, 0.5, 0.77] {
            let s = w[0] + frac * (w[1] - w[0]);
            let u = sol.eval(s).unwrap();
            max_err = max_err
                .max((u[0] - s.sin()).abs())
                .max((u[1] - s.cos()).abs());
        }
    }
    println!("dense max err {max_err:e} over {} steps", pts.len() - 1);
    assert!(max_err < 1e-10, "{max_err:e}");
    // step ends are reproduced exactly by the interpolant (theta = 0)
    let mut out = [0.0; 2];
    assert!(sol.eval_into(10.0, &mut out));
    assert_eq!(out.to_vec(), sol.u_end);
    assert!(sol.eval(10.5).is_none());
    // not dense -> None
    let nd = Dop853::new(1e-12, 1e-12)
        .integrate(&Harmonic, 0.0, 1.0, &[0.0, 1.0])
        .unwrap();
    assert!(nd.eval(0.5).is_none());
    assert!(nd.step_points().is_empty());
}

#[test]
fn dop853_event_first_zero_of_sin() {
    let (sol, ev) = Dop853::new(1e-14, 1e-14)
        .integrate_until(
            &Harmonic,
            0.5,
            20.0,
            &[0.5f64.sin(), 0.5f64.cos()],
            |_, u| u[0],
        )
        .unwrap();
    let ev = ev.expect("event");
    println!(
        "event at {:.17}, err {:e}",
        ev.s,
        ev.s - std::f64::consts::PI
    );
    assert!((ev.s - std::f64::consts::PI).abs() < 1e-12);
    assert!((ev.u[1] + 1.0).abs() < 1e-12);
    // the located point is a zero of the event function on the dense output
    assert!(ev.u[0].abs() < 1e-15, "{:e}", ev.u[0]);
    assert_eq!(sol.s_end, ev.s);
    assert_eq!(sol.u_end, ev.u);
}

#[test]
fn dop853_event_projectile_landing() {
    // launched at 45 degrees with speed 20, g = 9.81: lands at t = 2 vy/g, x = vx t
    let g = 9.81;
    let v = 20.0 / 2f64.sqrt();
    let (sol, ev) = Dop853::new(1e-10, 1e-10)
        .with_dense(true)
        .integrate_until(&Projectile { g }, 0.0, 100.0, &[0.0, 0.0, v, v], |_, u| {
            u[1]
        })
        .unwrap();
    let ev = ev.unwrap();
    let t = 2.0 * v / g;
    assert!((ev.s - t).abs() < 1e-12 * t, "{:e}", ev.s - t);
    assert!((ev.u[0] - v * t).abs() < 1e-11 * v * t);
    // dense output stops at the event
    assert!(sol.eval(t + 1e-6).is_none());
    assert!(sol.eval(0.5 * t).is_some());
    // no event when the span ends before landing
    let (sol2, ev2) = Dop853::new(1e-10, 1e-10)
        .integrate_until(&Projectile { g }, 0.0, 1.0, &[0.0, 0.0, v, v], |_, u| u[1])
        .unwrap();
    assert!(ev2.is_none());
    assert_eq!(sol2.s_end, 1.0);
    assert!((sol2.u_end[1] - (v - 0.5 * g)).abs() < 1e-12);
}

#[test]
fn event_backward_direction() {
    // backward from 5 to 0: first zero of sin met is 3*pi/2? no: zeros of sin below 5 are pi, 0
    let (_, ev) = Dop853::new(1e-12, 1e-12)
        .integrate_until(&Harmonic, 5.0, 0.5, &[5f64.sin(), 5f64.cos()], |_, u| u[0])
        .unwrap();
    assert!((ev.unwrap().s - std::f64::consts::PI).abs() < 1e-12);
}

#[test]
fn invalid_inputs_and_nan() {
    let d = Dop853::new(1e-10, 1e-10);
    assert!(matches!(
        d.integrate(&Harmonic, 0.0, 1.0, &[f64::NAN, 1.0]),
        Err(BvpError::InvalidInput { name: "u0", .. })
    ));
    assert!(matches!(
        d.integrate(&Harmonic, 0.0, f64::INFINITY, &[0.0, 1.0]),
        Err(BvpError::InvalidInput { .. })
    ));
    assert!(matches!(
        d.integrate(&Harmonic, 0.0, 1.0, &[0.0]),
        Err(BvpError::DimensionMismatch {
            expected: 2,
            found: 1,
            ..
        })
    ));
    assert!(matches!(
        Dop853::new(-1.0, 1e-10).integrate(&Harmonic, 0.0, 1.0, &[0.0, 1.0]),
        Err(BvpError::InvalidInput { name: "rtol", .. })
    ));
    match d.integrate(&NanRhs, 0.0, 1.0, &[0.0]) {
        Err(BvpError::NonFinite { s, .. }) => assert!(s > 0.4 && s <= 0.5 + 1e-9, "{s}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        Rk4 { steps: 10 }.integrate(&NanRhs, 0.0, 1.0, &[0.0]),
        Err(BvpError::NonFinite { .. })
    ));
    assert!(matches!(
        Rk4 { steps: 0 }.integrate(&Harmonic, 0.0, 1.0, &[0.0, 1.0]),
        Err(BvpError::InvalidInput { name: "steps", .. })
    ));
    assert!(matches!(
        Rk4 { steps: 3 }.integrate(&Harmonic, 0.0, 1.0, &[0.0, f64::INFINITY]),
        Err(BvpError::InvalidInput { .. })
    ));
    let mut few = Dop853::new(1e-12, 1e-12);
    few.max_steps = 5;
    assert!(matches!(
        few.integrate(&Harmonic, 0.0, 100.0, &[0.0, 1.0]),
        Err(BvpError::TooManySteps { max_steps: 5, .. })
    ));
    // a NaN event function is reported
    assert!(matches!(
        d.integrate_until(&Harmonic, 0.0, 1.0, &[0.0, 1.0], |_, _| f64::NAN),
        Err(BvpError::NonFinite { .. })
    ));
}

#[test]
fn empty_span_is_identity() {
    let sol = Dop853::new(1e-10, 1e-10)
        .with_dense(true)
        .integrate(&Harmonic, 1.0, 1.0, &[0.3, 0.4])
        .unwrap();
    assert_eq!(sol.u_end, vec![0.3, 0.4]);
    assert_eq!(sol.eval(1.0), Some(vec![0.3, 0.4]));
    assert_eq!(sol.stats.steps, 0);
}

#[test]
fn timing_6dim_unit_interval() {
    // Not an assertion on speed (machine-dependent), only a report; the accuracy is asserted.
    let d = Dop853::new(1e-12, 1e-12);
    let u0 = [0.0, 1.0, 0.0, 1.0, 0.0, 1.0];
    let reps = 2000;
    let t0 = std::time::Instant::now();
    let mut acc = 0.0;
    let mut stats = None;
    for _ in 0..reps {
        let sol = d.integrate(&Rot3, 0.0, 1.0, &u0).unwrap();
        acc += sol.u_end[4];
        stats = Some(sol.stats);
    }
    let dt = t0.elapsed().as_secs_f64() / reps as f64;
    println!(
        "6-dim [0,1] at 1e-12: {:.2} us per solve, {:?}",
        dt * 1e6,
        stats
    );
    assert!((acc / reps as f64 - 3.5f64.sin()).abs() < 1e-11);
}
