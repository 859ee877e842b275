//! Richardson extrapolation on sequences with known asymptotic expansions.

use bvp_solvers::richardson::{richardson, richardson_grid, richardson_grid_levels};
use bvp_solvers::BvpError;

fn loglog_slope(h: &[f64], err: &[f64]) -> f64 {
    let xs: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let ys: Vec<f64> = err.iter().map(|v| v.ln()).collect();
    let m = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / m;
    let my = ys.iter().sum::<f64>() / m;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Composite trapezoid rule for the integral of e^x over [0, 1] with n panels.
fn trapezoid_exp(n: usize) -> f64 {
    let h = 1.0 / n as f64;
    let inner: f64 = (1..n).map(|i| (i as f64 * h).exp()).sum();
    h * (0.5 + 0.5 * 1f64.exp() + inner)
}

#[test]
fn polynomial_expansion_eliminated_exactly() {
    // A(h) = 3 + 5 h^2 - 7 h^4: two levels (three values) remove both terms exactly.
    let a = |h: f64| 3.0 + 5.0 * h * h - 7.0 * h.powi(4);
    let vals = [a(0.5), a(0.25), a(0.125)];
    let ex = richardson(&vals, 2, 2).unwrap();
    assert!((ex.value - 3.0).abs() < 1e-14, "{}", ex.value);
    assert_eq!(ex.table.len(), 3);
    assert_eq!(
        ex.table.iter().map(Vec::len).collect::<Vec<_>>(),
        vec![3, 2, 1]
    );
    // First column: A + c h^4 terms only; T[1][j] = 3 - 7 h_j^4 (1 - 4)/... checked in closed
    // form: T[1][j] = (4 A(h/2) - A(h)) / 3 = 3 + (-7)(4 h^4/16 - h^4)/3 = 3 + 7 h^4 / 4.
    for (j, h) in [0.5f64, 0.25].iter().enumerate() {
        let expect = 3.0 + 7.0 * h.powi(4) / 4.0;
        assert!((ex.table[1][j] - expect).abs() < 1e-14);
    }
    // The estimate is |T[2][0] - T[1][1]| = 7 (0.25)^4 / 4.
    assert!((ex.error_estimate - 7.0 * 0.25f64.powi(4) / 4.0).abs() < 1e-14);
}

#[test]
fn romberg_integration_of_exp() {
    // Trapezoid error expands in h^2, h^4, ...: Romberg = Richardson(2, 2).
    let vals: Vec<f64> = (0..6).map(|k| trapezoid_exp(1 << k)).collect();
    let ex = richardson(&vals, 2, 2).unwrap();
    let exact = 1f64.exp() - 1.0;
    let err = (ex.value - exact).abs();
    assert!(err < 1e-14, "{err:e}");
    assert!(ex.error_estimate >= err);
    assert!(ex.error_estimate < 1e-11, "{:e}", ex.error_estimate);
}

#[test]
fn measured_orders_of_each_column() {
    // Forward difference (e^h - 1)/h -> 1 has a full expansion h, h^2, h^3...: column k
    // of the table with (base 1, step 1) is of order k + 1.
    let d = |h: f64| h.exp_m1() / h;
    for (levels, order) in [(1usize, 1.0), (2, 2.0), (3, 3.0)] {
        let (mut hs, mut es) = (vec![], vec![]);
        for k in 2..7 {
            let h0 = 0.5f64.powi(k);
            let vals: Vec<f64> = (0..levels).map(|j| d(h0 / f64::from(1 << j))).collect();
            let v = if levels == 1 {
                vals[0]
            } else {
                richardson(&vals, 1, 1).unwrap().value
            };
            hs.push(h0);
            es.push((v - 1.0).abs());
        }
        let s = loglog_slope(&hs, &es);
        assert!((s - order).abs() < 0.15, "{levels} levels: order {s}");
    }
}

#[test]
fn grid_extrapolation_formula() {
    // coarse / fine grid functions of c + K h^2 with h_fine = h/2: one step is exact.
    let coarse = [1.0 + 4.0, 2.0 + 4.0, 3.0 + 4.0];
    let fine = [1.0 + 1.0, 9.0, 2.0 + 1.0, -9.0, 3.0 + 1.0];
    let r = richardson_grid(&coarse, &fine, 2).unwrap();
    assert_eq!(r.len(), 3);
    for (i, v) in r.iter().enumerate() {
        assert!((v - (i as f64 + 1.0)).abs() < 1e-15, "{v}");
    }
    // Order 4: (16 f - c) / 15.
    let r4 = richardson_grid(&[17.0, 0.0], &[2.0, 5.0, 0.0], 4).unwrap();
    assert!((r4[0] - 1.0).abs() < 1e-15);

    // Multi-level: c + K h^2 + L h^4 on n = 2, 4, 8 intervals.
    let f = |x: f64, h: f64| x * x + 3.0 * h * h - 2.0 * h.powi(4);
    let lev = |n: usize| -> Vec<f64> {
        let h = 1.0 / n as f64;
        (0..=n).map(|i| f(i as f64 * h, h)).collect()
    };
    let (l0, l1, l2) = (lev(2), lev(4), lev(8));
    let r = richardson_grid_levels(&[&l0, &l1, &l2], 2, 2).unwrap();
    for (i, v) in r.iter().enumerate() {
        let x = i as f64 * 0.5;
        assert!((v - x * x).abs() < 1e-14, "{v}");
    }
}

#[test]
fn invalid_inputs() {
    assert!(matches!(
        richardson(&[1.0], 2, 2),
        Err(BvpError::InvalidInput { .. })
    ));
    assert!(matches!(
        richardson(&[1.0, f64::NAN], 2, 2),
        Err(BvpError::InvalidInput { name: "values", .. })
    ));
    assert!(matches!(
        richardson(&[1.0, 2.0], 0, 2),
        Err(BvpError::InvalidInput { .. })
    ));
    assert!(matches!(
        richardson(&[1.0, 2.0], 2, 0),
        Err(BvpError::InvalidInput { .. })
    ));
    assert!(matches!(
        richardson(&[1.0, 2.0, 3.0], 999, 5),
        Err(BvpError::InvalidInput { .. })
    ));
    assert_eq!(
        richardson_grid(&[1.0, 2.0], &[1.0, 2.0], 2),
        Err(BvpError::DimensionMismatch {
            name: "fine",
            expected: 3,
            found: 2
        })
    );
    assert!(richardson_grid(&[1.0, 2.0], &[1.0, 2.0, 3.0], 0).is_err());
    assert!(richardson_grid(&[1.0], &[1.0], 2).is_err());
    let a = [0.0; 3];
    let b = [0.0; 4];
    assert!(matches!(
        richardson_grid_levels(&[&a, &b], 2, 2),
        Err(BvpError::DimensionMismatch { .. })
    ));
    assert!(richardson_grid_levels(&[&a], 2, 2).is_err());
}
