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

/// One Richardson step on grid functions: `coarse` on `n` intervals (`n + 1` values) and
/// `fine` on `2n` intervals (`2n + 1` values) of a method of order `order`; returns at the
/// coarse nodes `fine[2i] + (fine[2i] - coarse[i]) / (2^order - 1)`, i.e.
/// `(4 fine[2i] - coarse[i]) / 3` for `order = 2`.
///
/// # Errors
/// - [`BvpError::DimensionMismatch`] unless `fine.len() == 2 coarse.len() - 1`;
/// - [`BvpError::InvalidInput`] for `coarse.len() < 2` or `order` outside `1..=1000`.
pub fn richardson_grid(coarse: &[f64], fine: &[f64], order: u32) -> Result<Vec<f64>> {
    if coarse.len() < 2 {
        return Err(BvpError::InvalidInput {
            name: "coarse.len()",
            value: coarse.len() as f64,
            reason: "a grid function needs at least two nodes",
        });
    }
    let expected = 2 * coarse.len() - 1;
    if fine.len() != expected {
        return Err(BvpError::DimensionMismatch {
            name: "fine",
            expected,
            found: fine.len(),
        });
    }
    let denom = validate_order("order", u64::from(order))?;
    Ok(coarse
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            let f = fine[2 * i];
            f + (f - c) / denom
        })
        .collect())
}

/// Several Richardson levels on grid functions: `levels[j]` is the solution on
/// `n 2^j` intervals (`n 2^j + 1` values); every level is restricted to the coarsest
/// nodes and the table of [`richardson`] is applied node by node, giving values of order
/// `base_order + (m-1) order_step` at the `n + 1` coarsest nodes.
///
/// # Errors
/// - [`BvpError::InvalidInput`] for fewer than two levels, a coarsest level with fewer
///   than two values, or invalid orders (as [`richardson`]);
/// - [`BvpError::DimensionMismatch`] if `levels[j].len() != n 2^j + 1`.
pub fn richardson_grid_levels(
    levels: &[&[f64]],
    base_order: u32,
    order_step: u32,
) -> Result<Vec<f64>> {
    if levels.len() < 2 {
        return Err(BvpError::InvalidInput {
            name: "levels.len()",
            value: levels.len() as f64,
            reason: "Richardson extrapolation needs at least two levels",
        });
    }
    let nc = levels[0].len();
    if nc < 2 {
        return Err(BvpError::InvalidInput {
            name: "levels[0].len()",
            value: nc as f64,
            reason: "a grid function needs at least two nodes",
        });
    }
    let n = nc - 1;
    for (j, lev) in levels.iter().enumerate() {
        let expected = n
            .checked_shl(j as u32)
            .and_then(|v| v.checked_add(1))
            .ok_or(BvpError::InvalidInput {
                name: "levels.len()",
                value: levels.len() as f64,
                reason: "too many levels",
            })?;
        if lev.len() != expected {
            return Err(BvpError::DimensionMismatch {
                name: "levels[j]",
                expected,
                found: lev.len(),
            });
        }
    }
    let mut column = vec![0.0; levels.len()];
    let mut out = Vec::with_capacity(nc);
    for i in 0..nc {
        for (j, lev) in levels.iter().enumerate() {
            column[j] = lev[i << j];
        }
        out.push(richardson(&column, base_order, order_step)?.value);
    }
    Ok(out)
}
