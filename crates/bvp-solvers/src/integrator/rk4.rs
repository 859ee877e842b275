//! The classical fourth-order Runge-Kutta method with equal steps.

use super::{all_finite, check_initial, check_span, OdeSystem};
use crate::{BvpError, Result};

/// The classical fourth-order Runge-Kutta method with `steps` equal steps `h = (s1 - s0)/steps`:
///
/// `k1 = G(s, u)`, `k2 = G(s + h/2, u + h k1/2)`, `k3 = G(s + h/2, u + h k2/2)`,
/// `k4 = G(s + h, u + h k3)`, `u <- u + h (k1 + 2 k2 + 2 k3 + k4)/6`.
///
/// The global error is `O(h^4)` for smooth `G`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rk4 {
    /// Number of equal steps (at least 1).
    pub steps: usize,
}

/// States at the nodes `s_0, ..., s_steps` of a fixed-step integration.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// Nodes (`steps + 1` values, `s[0] = s0`, last `= s1`).
    pub s: Vec<f64>,
    /// Row-major states: `u[i*dim .. (i+1)*dim]` is the state at `s[i]`.
    pub u: Vec<f64>,
    /// State dimension.
    pub dim: usize,
}

impl Trajectory {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.s.len()
    }
    /// `true` if there are no nodes (never the case for a trajectory returned by [`Rk4`]).
    pub fn is_empty(&self) -> bool {
        self.s.is_empty()
    }
    /// State at node `i` (panics if `i >= len()`, like slice indexing).
    pub fn state(&self, i: usize) -> &[f64] {
        &self.u[i * self.dim..(i + 1) * self.dim]
    }
    /// State at the last node (empty slice for an empty trajectory).
    pub fn last(&self) -> &[f64] {
        match self.s.len() {
            0 => &[],
            m => self.state(m - 1),
        }
    }
}

struct Rk4Work {
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    tmp: Vec<f64>,
}

impl Rk4Work {
    fn new(n: usize) -> Self {
        Self {
            k1: vec![0.0; n],
            k2: vec![0.0; n],
            k3: vec![0.0; n],
            k4: vec![0.0; n],
            tmp: vec![0.0; n],
        }
    }

    /// One classical RK4 step in place.
    #[inline]
    #[allow(clippy::needless_range_loop)]
    fn step<S: OdeSystem + ?Sized>(&mut self, sys: &S, s: f64, h: f64, u: &mut [f64]) {
        let n = u.len();
        sys.rhs(s, u, &mut self.k1);
        for i in 0..n {
            self.tmp[i] = u[i] + 0.5 * h * self.k1[i];
        }
        sys.rhs(s + 0.5 * h, &self.tmp, &mut self.k2);
        for i in 0..n {
            self.tmp[i] = u[i] + 0.5 * h * self.k2[i];
        }
        sys.rhs(s + 0.5 * h, &self.tmp, &mut self.k3);
        for i in 0..n {
            self.tmp[i] = u[i] + h * self.k3[i];
        }
        sys.rhs(s + h, &self.tmp, &mut self.k4);
        let h6 = h / 6.0;
        for i in 0..n {
            u[i] += h6 * (self.k1[i] + 2.0 * (self.k2[i] + self.k3[i]) + self.k4[i]);
        }
    }
}

impl Rk4 {
    fn check(&self, s0: f64, s1: f64) -> Result<()> {
        if self.steps == 0 {
            return Err(BvpError::InvalidInput {
                name: "steps",
                value: 0.0,
                reason: "RK4 needs at least one step",
            });
        }
        check_span(s0, s1)
    }

    /// Classical RK4 with `steps` equal steps from `s0` to `s1` (`s1 < s0` allowed: backward).
    ///
    /// Node `i` is `s0 + i (s1 - s0)/steps` (the last node is exactly `s1`).
    ///
    /// # Errors
    /// `InvalidInput` for `steps == 0`, non-finite bounds or a non-finite `u0`;
    /// `DimensionMismatch` if `u0.len() != sys.dim()`; `NonFinite` if the state becomes NaN/inf.
    pub fn integrate<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
    ) -> Result<Trajectory> {
        self.check(s0, s1)?;
        let n = sys.dim();
        check_initial(n, u0)?;
        let m = self.steps;
        let h = (s1 - s0) / m as f64;
        let mut s = Vec::with_capacity(m + 1);
        let mut u = Vec::with_capacity((m + 1) * n);
        s.push(s0);
        u.extend_from_slice(u0);
        let mut work = Rk4Work::new(n);
        let mut cur = u0.to_vec();
        for i in 0..m {
            let si = s0 + i as f64 * h;
            work.step(sys, si, h, &mut cur);
            if !all_finite(&cur) {
                return Err(BvpError::NonFinite {
                    what: "RK4 state",
                    s: si + h,
                });
            }
            s.push(if i + 1 == m {
                s1
            } else {
                s0 + (i + 1) as f64 * h
            });
            u.extend_from_slice(&cur);
        }
        Ok(Trajectory { s, u, dim: n })
    }

    /// Like [`Rk4::integrate`] but keeps only the final state, written into `u_end`
    /// (length `sys.dim()`); no trajectory is stored (for shooting).
    ///
    /// # Errors
    /// As [`Rk4::integrate`]; `DimensionMismatch` also for a wrong `u_end` length.
    pub fn integrate_final<S: OdeSystem + ?Sized>(
        &self,
        sys: &S,
        s0: f64,
        s1: f64,
        u0: &[f64],
        u_end: &mut [f64],
    ) -> Result<()> {
        self.check(s0, s1)?;
        let n = sys.dim();
        check_initial(n, u0)?;
        if u_end.len() != n {
            return Err(BvpError::DimensionMismatch {
                name: "u_end",
                expected: n,
                found: u_end.len(),
            });
        }
        let h = (s1 - s0) / self.steps as f64;
        let mut work = Rk4Work::new(n);
        u_end.copy_from_slice(u0);
        for i in 0..self.steps {
            work.step(sys, s0 + i as f64 * h, h, u_end);
        }
        if !all_finite(u_end) {
            return Err(BvpError::NonFinite {
                what: "RK4 state",
                s: s1,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{loglog_slope, Harmonic};

    /// Non-autonomous: `y' = cos(s) y`, `y(0) = 1`: `y = exp(sin s)`.
    struct ExpSin;
    impl OdeSystem for ExpSin {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]) {
            du[0] = s.cos() * u[0];
        }
    }

    /// `y' = y`, `y(0) = 1`: `y = e^s`.
    struct Growth;
    impl OdeSystem for Growth {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, _s: f64, u: &[f64], du: &mut [f64]) {
            du[0] = u[0];
        }
    }

    /// On `y' = y` one step is the Taylor polynomial of `e^h` to fourth order, and the global
    /// error at `s = 1` falls as `h^4`.
    #[test]
    fn one_step_is_the_fourth_order_taylor_polynomial_and_the_order_is_four() {
        let mut u = [1.0];
        Rk4Work::new(1).step(&Growth, 0.0, 0.1, &mut u);
        let h: f64 = 0.1;
        let taylor = 1.0 + h + h * h / 2.0 + h.powi(3) / 6.0 + h.powi(4) / 24.0;
        assert!((u[0] - taylor).abs() < 1e-15, "{} vs {taylor}", u[0]);
        let (mut hs, mut errs) = (vec![], vec![]);
        for steps in [8, 16, 32, 64, 128] {
            let mut end = [0.0];
            Rk4 { steps }
                .integrate_final(&Growth, 0.0, 1.0, &[1.0], &mut end)
                .unwrap();
            hs.push(1.0 / steps as f64);
            errs.push((end[0] - 1f64.exp()).abs());
        }
        let p = loglog_slope(&hs, &errs);
        assert!((3.95..=4.05).contains(&p), "order {p}, errors {errs:?}");
        // the leading error constant: e h^4 / 120 per unit length (measured at h = 1/128)
        let c = errs[4] / hs[4].powi(4);
        assert!(
            c > 0.5 * 1f64.exp() / 120.0 && c < 2.0 * 1f64.exp() / 120.0,
            "{c}"
        );
    }

    #[test]
    fn rk4_is_fourth_order() {
        let mut hs = Vec::new();
        let mut errs = Vec::new();
        for steps in [10, 20, 40, 80, 160] {
            let tr = Rk4 { steps }
                .integrate(&Harmonic, 0.0, 2.0, &[0.0, 1.0])
                .unwrap();
            assert_eq!(tr.len(), steps + 1);
            assert_eq!(tr.s[steps], 2.0);
            let u = tr.last();
            let e = (u[0] - 2f64.sin()).abs().max((u[1] - 2f64.cos()).abs());
            hs.push(2.0 / steps as f64);
            errs.push(e);
            // interior node too
            let i = steps / 2;
            assert!((tr.state(i)[0] - tr.s[i].sin()).abs() < 1e-3);
        }
        let p = loglog_slope(&hs, &errs);
        println!("RK4 errors {errs:?}, order {p}");
        assert!((3.9..=4.1).contains(&p), "RK4 order {p}");
    }

    #[test]
    fn rk4_backward_and_final_only() {
        let rk = Rk4 { steps: 200 };
        let e1 = 1f64.sin().exp();
        let tr = rk
            .integrate(&ExpSin, 2.0, 1.0, &[2f64.sin().exp()])
            .unwrap();
        assert!((tr.last()[0] - e1).abs() < 1e-9, "{}", tr.last()[0] - e1);
        let mut out = [0.0];
        rk.integrate_final(&ExpSin, 2.0, 1.0, &[2f64.sin().exp()], &mut out)
            .unwrap();
        assert_eq!(out[0], tr.last()[0]);
    }
}
