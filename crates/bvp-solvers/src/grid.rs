//! Uniform grids on an interval `[a, b]`, and the interval of sorted knots holding a point
//! ([`locate_from`]).
//!
//! A grid with `n` intervals has the `n + 1` nodes `x_i = a + i h`, `h = (b - a) / n`,
//! `i = 0, ..., n`; the last node is exactly `b`.

use crate::{BvpError, Result};

/// The interval of `n >= 1` sorted knots holding `t`: the last `k < n` with `key(k) <= t`
/// (0 if there is none; `key` strictly increasing), what a binary search
/// (`partition_point`) finds, walked to from `*hint` (updated; any value to start). For
/// points asked in order (sampling a shape along its integrator's steps) that is a step or
/// two, where a binary search's branches are unpredictable: measured, a tenth of an
/// `accurate` solve's time went to 100 such searches.
pub fn locate_from(n: usize, key: impl Fn(usize) -> f64, t: f64, hint: &mut usize) -> usize {
    let mut k = (*hint).min(n.saturating_sub(1));
    while k > 0 && key(k) > t {
        k -= 1;
    }
    while k + 1 < n && key(k + 1) <= t {
        k += 1;
    }
    *hint = k;
    k
}

/// A uniform grid of `n` intervals (`n + 1` nodes) on `[a, b]`.
///
/// Invariants (checked by [`UniformGrid::new`]): `a`, `b` finite, `b > a`, `n >= 2`.
#[derive(Clone, Debug, PartialEq)]
pub struct UniformGrid {
    a: f64,
    b: f64,
    n: usize,
}

impl UniformGrid {
    /// Grid of `n` intervals on `[a, b]`.
    ///
    /// # Errors
    /// [`BvpError::InvalidInput`] if `a` or `b` is not finite, `b <= a`, `n < 2`, or the
    /// step `h = (b - a) / n` underflows to zero or overflows.
    pub fn new(a: f64, b: f64, n: usize) -> Result<Self> {
        if !a.is_finite() {
            return Err(BvpError::InvalidInput {
                name: "a",
                value: a,
                reason: "grid end must be finite",
            });
        }
        if !b.is_finite() {
            return Err(BvpError::InvalidInput {
                name: "b",
                value: b,
                reason: "grid end must be finite",
            });
        }
        if b <= a {
            return Err(BvpError::InvalidInput {
                name: "b",
                value: b,
                reason: "grid requires b > a",
            });
        }
        if n < 2 {
            return Err(BvpError::InvalidInput {
                name: "n",
                value: n as f64,
                reason: "grid needs at least 2 intervals",
            });
        }
        let h = (b - a) / n as f64;
        if !(h.is_finite() && h > 0.0) {
            return Err(BvpError::InvalidInput {
                name: "h",
                value: h,
                reason: "grid step must be finite and positive",
            });
        }
        Ok(Self { a, b, n })
    }

    /// Left end `a`.
    pub fn a(&self) -> f64 {
        self.a
    }

    /// Right end `b`.
    pub fn b(&self) -> f64 {
        self.b
    }

    /// Number of intervals `n`.
    pub fn intervals(&self) -> usize {
        self.n
    }

    /// Number of nodes, `n + 1`.
    pub fn len(&self) -> usize {
        self.n + 1
    }

    /// Always `false`: a valid grid has at least three nodes.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Step `h = (b - a) / n`.
    pub fn h(&self) -> f64 {
        (self.b - self.a) / self.n as f64
    }

    /// Node `x_i = a + (b - a) i / n`; `x_n == b` exactly. Indices `i > n` extrapolate
    /// linearly (no panic).
    pub fn x(&self, i: usize) -> f64 {
        if i == self.n {
            self.b
        } else {
            self.a + (self.b - self.a) * (i as f64 / self.n as f64)
        }
    }

    /// All `n + 1` nodes.
    pub fn nodes(&self) -> Vec<f64> {
        (0..=self.n).map(|i| self.x(i)).collect()
    }

    /// The grid with twice as many intervals on the same interval (step `h / 2`); its even
    /// nodes coincide with this grid's nodes.
    pub fn refined(&self) -> Result<Self> {
        let n = self.n.checked_mul(2).ok_or(BvpError::InvalidInput {
            name: "n",
            value: self.n as f64,
            reason: "refinement overflows the interval count",
        })?;
        Self::new(self.a, self.b, n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Walking from any hint finds the binary search's interval, in and out of order.
    #[test]
    fn locating_from_a_hint_is_the_binary_search() {
        let knots = [0.0, 0.1, 0.25, 0.3, 0.7, 0.71, 1.0];
        let n = knots.len();
        let mut hint = usize::MAX;
        for i in 0..=120 {
            // in order, then backwards, then scattered; the knots themselves among them
            let t = match i {
                0..=40 => i as f64 / 40.0,
                41..=80 => (80 - i) as f64 / 40.0,
                _ => ((i * 37) % 41) as f64 / 40.0,
            };
            let expected = knots
                .partition_point(|&k| k <= t)
                .saturating_sub(1)
                .min(n - 1);
            assert_eq!(
                locate_from(n, |k| knots[k], t, &mut hint),
                expected,
                "t = {t}"
            );
            assert_eq!(hint, expected);
        }
        // below the first knot: the first interval; one knot: it
        assert_eq!(locate_from(n, |k| knots[k], -1.0, &mut 5), 0);
        assert_eq!(locate_from(1, |_| 0.0, 3.0, &mut 9), 0);
    }

    #[test]
    fn grid_basics() {
        let g = UniformGrid::new(-1.0, 0.1, 3).unwrap();
        assert_eq!(g.len(), 4);
        assert_eq!(g.intervals(), 3);
        assert_eq!(g.x(3), 0.1);
        assert!((g.h() - 1.1 / 3.0).abs() < 1e-16);
        let nodes = g.nodes();
        assert_eq!(nodes.len(), 4);
        assert_eq!(nodes[0], -1.0);
        assert!((nodes[1] - (-1.0 + 1.1 / 3.0)).abs() < 1e-15);
        let r = g.refined().unwrap();
        assert_eq!(r.intervals(), 6);
        for i in 0..4 {
            assert!((r.x(2 * i) - g.x(i)).abs() < 1e-15);
        }
        assert!(UniformGrid::new(0.0, 1.0, 1).is_err());
        assert!(UniformGrid::new(1.0, 1.0, 4).is_err());
        assert!(UniformGrid::new(0.0, f64::NAN, 4).is_err());
        assert!(UniformGrid::new(f64::NEG_INFINITY, 0.0, 4).is_err());
    }
}
