//! Uniform grids on an interval `[a, b]`.
//!
//! A grid with `n` intervals has the `n + 1` nodes `x_i = a + i h`, `h = (b - a) / n`,
//! `i = 0, ..., n`; the last node is exactly `b`.

use crate::{BvpError, Result};

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
