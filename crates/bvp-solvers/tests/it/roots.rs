//! Scalar root finders on roots known in closed form or to published digits.

use bvp_solvers::roots::{bisect, brent, Root, RootOptions};
use bvp_solvers::BvpError;

type R = Result<Root, BvpError>;

fn ok(x: f64) -> Result<f64, BvpError> {
    Ok(x)
}

#[test]
fn cos_x_equals_x() {
    // Dottie number
    let dottie = 0.739_085_133_215_160_6;
    let f = |x: f64| ok(x.cos() - x);
    let o = RootOptions::default();
    let rb: R = brent(f, 0.0, 1.0, &o);
    let rb = rb.unwrap();
    let mut calls = 0;
    let below = |x: f64| {
        calls += 1;
        Some(x.cos() > x)
    };
    let xs = bisect(below, 0.0, 1.0, 200);
    println!("brent {rb:?}\nbisect {xs} in {calls} calls");
    assert!((rb.x - dottie).abs() < 2e-15);
    assert!((xs - dottie).abs() < 2e-15);
    // Brent is superlinear: far fewer evaluations than bisection's ~53 (to adjacent floats)
    assert!(rb.iterations <= 8, "{}", rb.iterations);
    assert!(calls >= 40);
    assert!(3 * rb.iterations < calls);
}

#[test]
fn polynomials() {
    let o = RootOptions::default();
    // x^3 - 2x - 5 = 0 (Wallis): 2.0945514815423265
    let r: R = brent(|x| ok(x * x * x - 2.0 * x - 5.0), 2.0, 3.0, &o);
    assert!((r.unwrap().x - 2.094_551_481_542_326_5).abs() < 1e-14);
    // (x - 1/3)^3: a triple root (interpolation is slow there), still bracketed to xtol
    let f = |x: f64| ok((x - 1.0 / 3.0).powi(3));
    let r: R = brent(f, -1.0, 2.0, &o);
    let r = r.unwrap();
    assert!((r.x - 1.0 / 3.0).abs() < 1e-13, "{}", r.x); // the sign of (x - 1/3)^3 is exact
    let x = bisect(|x| Some(x * x < 2.0), 0.0, 2.0, 200);
    assert!((x - 2f64.sqrt()).abs() < 2e-14);
    // reversed bracket order is accepted
    let r: R = brent(|x| ok(x * x - 2.0), 2.0, 0.0, &o);
    assert!((r.unwrap().x - 2f64.sqrt()).abs() < 4e-16);
}

#[test]
fn ftol_and_exact_end_roots() {
    let o = RootOptions {
        ftol: 1e-3,
        ..RootOptions::default()
    };
    let r: R = brent(|x| ok(x - 0.5), 0.0, 1.0, &o);
    assert!((r.unwrap().x - 0.5).abs() < 1e-3);
    let r: R = brent(|x| ok(x - 1.0), 0.0, 1.0, &RootOptions::default());
    assert_eq!(r.unwrap().x, 1.0);
}

#[test]
fn errors() {
    let o = RootOptions::default();
    let r: R = brent(|x| ok(x * x + 1.0), -1.0, 1.0, &o);
    assert!(matches!(r, Err(BvpError::NotBracketed { a, b, .. }) if a == -1.0 && b == 1.0));
    let r: R = brent(
        |x| ok(x.cos() - x),
        0.0,
        1.0,
        &RootOptions { max_iter: 2, ..o },
    );
    assert!(matches!(
        r,
        Err(BvpError::NoConvergence {
            method: "brent",
            ..
        })
    ));
    let r: R = brent(|_| ok(f64::NAN), 0.0, 1.0, &o);
    assert!(matches!(r, Err(BvpError::NonFinite { .. })));
    let r: R = brent(ok, f64::NAN, 1.0, &o);
    assert!(matches!(r, Err(BvpError::InvalidInput { .. })));
}

#[derive(Debug, PartialEq)]
enum MyErr {
    Bvp(BvpError),
    Mine(u32),
}
impl From<BvpError> for MyErr {
    fn from(e: BvpError) -> Self {
        MyErr::Bvp(e)
    }
}

#[test]
fn user_errors_propagate() {
    let f = |x: f64| {
        if x > 0.6 {
            Err(MyErr::Mine(7))
        } else {
            Ok(x - 0.9)
        }
    };
    assert_eq!(
        brent(f, 0.0, 0.5, &RootOptions::default()),
        Err(MyErr::Bvp(BvpError::NotBracketed {
            a: 0.0,
            b: 0.5,
            fa: -0.9,
            fb: -0.4
        }))
    );
    assert_eq!(
        brent(f, 0.0, 1.0, &RootOptions::default()),
        Err(MyErr::Mine(7))
    );
}
