//! Richardson extrapolation of results computed with steps `h, h/2, h/4, ...`.
//!
//! If `A(h) = A + c_1 h^{p_1} + c_2 h^{p_2} + ...` with `p_k = base_order + (k-1) order_step`
//! (the central FDM has an even expansion: `base_order = 2`, `order_step = 2`), the table
//!
//! ```text
//! T[0][j] = A(h / 2^j)
//! T[k][j] = T[k-1][j+1] + (T[k-1][j+1] - T[k-1][j]) / (2^{p_k} - 1)
//! ```
//!
//! eliminates one term per column: `T[k][j] = A + O((h/2^j)^{p_{k+1}})`.

use crate::{BvpError, Result};

/// Largest order accepted (keeps `2^p` finite and meaningful).
const MAX_ORDER: u64 = 1000;

/// Result of [`richardson`].
#[derive(Clone, Debug, PartialEq)]
pub struct Extrapolation {
    /// The best estimate, the last column `T[m-1][0]`.
    pub value: f64,
    /// `|T[m-1][0] - T[m-2][1]|`: the difference between the best estimate and the most
    /// accurate entry of the previous column (a conservative estimate of the error of the
    /// latter, and typically pessimistic for `value`).
    pub error_estimate: f64,
    /// The full table: `table[k]` is column `k` (length `m - k`), `table[0]` the inputs.
    pub table: Vec<Vec<f64>>,
}

fn validate_order(name: &'static str, p: u64) -> Result<f64> {
    if p == 0 || p > MAX_ORDER {
        return Err(BvpError::InvalidInput {
            name,
            value: p as f64,
            reason: "order must lie in 1..=1000",
        });
    }
    // Exact for p <= 1000: a power of two.
    Ok(2.0_f64.powi(p as i32) - 1.0)
}

/// Richardson table of `values` computed with `h, h/2, h/4, ...` (coarse to fine) by a
/// method whose error expands in `h^{base_order}, h^{base_order + order_step}, ...`; see
/// the [module docs](self). With `m` values the result is accurate to
/// `O(h_finest^{base_order + (m-1) order_step})`.
///
/// # Errors
/// [`BvpError::InvalidInput`] for fewer than two values, a non-finite value, or an order
/// `base_order + k order_step` outside `1..=1000` (`order_step = 0` is rejected).
pub fn richardson(values: &[f64], base_order: u32, order_step: u32) -> Result<Extrapolation> {
    let m = values.len();
    if m < 2 {
        return Err(BvpError::InvalidInput {
            name: "values.len()",
            value: m as f64,
            reason: "Richardson extrapolation needs at least two values",
        });
    }
    if let Some(&v) = values.iter().find(|v| !v.is_finite()) {
        return Err(BvpError::InvalidInput {
            name: "values",
            value: v,
            reason: "values must be finite",
        });
    }
    if order_step == 0 {
        return Err(BvpError::InvalidInput {
            name: "order_step",
            value: 0.0,
            reason: "order step must be positive",
        });
    }
    let mut table: Vec<Vec<f64>> = Vec::with_capacity(m);
    table.push(values.to_vec());
    for k in 1..m {
        let p = u64::from(base_order) + (k as u64 - 1) * u64::from(order_step);
        let denom = validate_order("order", p)?;
        let prev = &table[k - 1];
        let col: Vec<f64> = prev
            .windows(2)
            .map(|w| w[1] + (w[1] - w[0]) / denom)
            .collect();
        table.push(col);
    }
    let value = table[m - 1][0];
    let error_estimate = (value - table[m - 2][1]).abs();
    Ok(Extrapolation {
        value,
        error_estimate,
        table,
    })
}

/// Richardson extrapolation on sequences with known asymptotic expansions.
#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::loglog_slope;

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
    }
}
