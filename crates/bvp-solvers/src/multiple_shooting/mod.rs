//! Multiple shooting for first-order two-point problems with unknown parameters,
//!
//! `y' = f(x, y, p)` on `[a, b]`, `bc(y(a), y(b), p) = 0` (`n` states, `k` parameters,
//! `n + k` boundary residuals; any boundary conditions: non-linear, non-separated),
//!
//! in the calling convention of scipy's `solve_bvp` (the user's mesh becomes the shooting
//! nodes `a = x_0 < ... < x_{m-1} = b`, the guesses the node states `s_j`).
//!
//! Each segment `[x_j, x_{j+1}]` is integrated by the crate's DOP853 from `s_j` at the
//! tolerances `rtol`, `atol` (the residuals) with its **variational equations**
//! `M' = (df/dy) M + [0 | df/dp]`, `M(x_j) = [I | 0]` for Newton's Jacobian integrated
//! along (or separately at a looser [`MultipleShooting::jac_tol`]) (with the user's analytic Jacobian, or
//! forward differences of `f` inside the right-hand side: `n + k` extra evaluations of `f`
//! per stage). So each segment gives its end `phi_j(s_j, p)` and its sensitivities
//! `G_j = d phi_j / d s_j`, `H_j = d phi_j / d p`, and Newton's method runs on the matching
//! conditions
//!
//! `c_j = phi_j(s_j, p) - s_{j+1} = 0` (`j = 0 .. m-2`), `bc(s_0, s_{m-1}, p) = 0`,
//!
//! whose Jacobian is the block staircase of `G_j`, `-I`, `H_j` and the boundary blocks
//! (those by forward differences of `bc`, which costs no integration), solved by its
//! structure (staircase elimination with partial pivoting, module `staircase`,
//! `O(m (n + k)^3)`), not as a dense matrix. The step is damped (halved until the scaled residual falls by Armijo's
//! factor); a trial point at which a segment fails to integrate only halves the step.
//!
//! **Node insertion**: a segment whose growth `|G_j|_inf` exceeds
//! [`MultipleShooting::max_growth`] (or which fails to integrate from its start) is split
//! at its midpoint, the new node's state interpolated linearly between its neighbours',
//! before the Newton step is taken; so the user's mesh may be coarse (two nodes), and the
//! conditioning of each segment, hence the amplification of the integrator's local errors,
//! stays bounded by `max_growth`.
//!
//! The answer has a continuous dense output ([`MultipleShootingSolution::eval`]: DOP853's
//! interpolant of order 7 on each segment).
//!
//! ```
//! use bvp_solvers::multiple_shooting::MultipleShooting;
//!
//! // y'' = 100^2 y, y(0) = 1, y(1) = 0: y = sinh(100 (1 - x)) / sinh(100), a boundary
//! // layer at x = 0 on which single shooting fails (the slope must be right to e^-100).
//! let k = 100.0;
//! let sol = MultipleShooting::default()
//!     .solve(
//!         |_x: f64, y: &[f64], _p: &[f64], dy: &mut [f64]| {
//!             dy[0] = y[1];
//!             dy[1] = k * k * y[0];
//!         },
//!         |ya: &[f64], yb: &[f64], _p: &[f64], r: &mut [f64]| {
//!             r[0] = ya[0] - 1.0;
//!             r[1] = yb[0];
//!         },
//!         &[0.0, 1.0],
//!         &[vec![1.0, 0.0], vec![0.0, 0.0]],
//!         &[],
//!     )
//!     .unwrap();
//! let exact = |x: f64| (-k * x).exp() * (1.0 - (-2.0 * k * (1.0 - x)).exp()) / (1.0 - (-2.0 * k).exp());
//! assert!((sol.eval(0.01)[0] - exact(0.01)).abs() < 1e-8);
//! ```

// `!(x > 0.0)` is used on purpose: it is true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod segment;
mod staircase;
#[cfg(test)]
mod tests;

pub use segment::Rhs;
use segment::{Analytic, Numeric};
use staircase::Staircase;

use crate::integrator::{Dop853, OdeSolution};
use crate::BvpError;

/// Options of multiple shooting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultipleShooting {
    /// Newton converges when every matching and boundary residual is at most
    /// `tol (1 + |s|)` (`s` the node state component it matches; 1 for the boundary
    /// residuals).
    pub tol: f64,
    /// DOP853's relative tolerance on each segment.
    pub rtol: f64,
    /// DOP853's absolute tolerance on each segment.
    pub atol: f64,
    /// Newton steps at most.
    pub max_iter: usize,
    /// Halvings of a Newton step at most.
    pub halvings: usize,
    /// A segment whose sensitivity `|G_j|_inf` exceeds this is split (node insertion).
    pub max_growth: f64,
    /// Most nodes (the insertion stops there with an error).
    pub max_nodes: usize,
    /// DOP853's tolerance (relative and absolute) of the variational integrations, which
    /// give Newton's Jacobian only (the residuals are integrated at `rtol`, `atol`): an
    /// approximate Jacobian slows Newton down but does not move the solution, and a
    /// forward-difference `df/dy` carries rounding noise of `sqrt(eps)` relative, which an
    /// error control tighter than that chases with ever smaller steps. At most `rtol` and
    /// `atol` (the default, 0): one integration of state and sensitivities at `rtol`, `atol`.
    pub jac_tol: f64,
    /// DOP853's step budget per segment: a segment that needs more (far from a solution,
    /// or stiff) is split like one that grows too much.
    pub max_steps: usize,
}

impl Default for MultipleShooting {
    /// `tol = 1e-9`, DOP853 at `1e-11`, 50 Newton steps of 30 halvings, growth at most
    /// `1e3` per segment, at most 20000 nodes, 2000 steps per segment, the variational
    /// equations integrated with the state.
    fn default() -> Self {
        MultipleShooting {
            tol: 1e-9,
            rtol: 1e-11,
            atol: 1e-11,
            max_iter: 50,
            halvings: 30,
            max_growth: 1e3,
            max_nodes: 20_000,
            max_steps: 2_000,
            jac_tol: 0.0,
        }
    }
}

/// The solution of [`MultipleShooting::solve`].
#[derive(Clone, Debug)]
pub struct MultipleShootingSolution {
    /// The final shooting nodes (the user's mesh with the inserted nodes).
    pub x: Vec<f64>,
    /// The state at each node.
    pub y: Vec<Vec<f64>>,
    /// The parameters found.
    pub p: Vec<f64>,
    /// Newton steps.
    pub iterations: usize,
    /// The largest scaled matching / boundary residual at the solution.
    pub residual: f64,
    /// Nodes inserted into the user's mesh.
    pub inserted: usize,
    /// Unknowns of the last Newton system (`n m + k`).
    pub unknowns: usize,
    /// Right-hand-side evaluations of all integrations (augmented systems counted once per
    /// evaluation).
    pub evaluations: usize,
    /// The dense output of each segment.
    segments: Vec<OdeSolution>,
}

impl MultipleShootingSolution {
    /// `y(x)` for `x` in `[a, b]` (DOP853's interpolant on the segment that holds `x`;
    /// clamped to `[a, b]`).
    pub fn eval(&self, x: f64) -> Vec<f64> {
        let j = self.x[1..self.x.len() - 1].partition_point(|&xj| xj <= x);
        let seg = &self.segments[j];
        let (lo, hi) = (self.x[j], self.x[j + 1]);
        seg.eval(x.clamp(lo.min(hi), hi.max(lo)))
            .unwrap_or_else(|| self.y[j].clone())
    }
}

/// The state of the iteration: nodes, node states, parameters.
struct Iterate {
    x: Vec<f64>,
    s: Vec<Vec<f64>>,
    p: Vec<f64>,
}

/// Residuals (and with sensitivities the segment ends' `M`) at an iterate.
struct Evaluated {
    /// `c_0, .., c_{m-2}` then `bc`, raw.
    r: Vec<f64>,
    /// The scaled max-norm of `r`.
    norm: f64,
    /// Per segment: `M_j` (`n x (n + k)`), when asked for.
    m: Vec<Vec<f64>>,
}

impl MultipleShooting {
    /// Solves the problem `y' = f(x, y, p)`, `bc(y(a), y(b), p) = 0` from the nodes `mesh`
    /// (increasing, at least 2), the guesses `y_guess[j]` (length `n`) at them and
    /// `p_guess` (length `k`); `df/dy`, `df/dp` by forward differences inside the
    /// variational equations (module docs).
    ///
    /// # Errors
    /// See [`MultipleShooting::solve_with_jacobian`].
    pub fn solve<F, B>(
        &self,
        f: F,
        bc: B,
        mesh: &[f64],
        y_guess: &[Vec<f64>],
        p_guess: &[f64],
    ) -> Result<MultipleShootingSolution, BvpError>
    where
        F: Fn(f64, &[f64], &[f64], &mut [f64]),
        B: Fn(&[f64], &[f64], &[f64], &mut [f64]),
    {
        self.run(&Numeric(f), &bc, mesh, y_guess, p_guess)
    }

    /// [`MultipleShooting::solve`] with the analytic Jacobians
    /// `jac(x, y, p, dfdy, dfdp)` (`n x n` and `n x k`, row-major).
    ///
    /// # Errors
    /// `InvalidInput` (a mesh that is not increasing or has fewer than 2 nodes, a
    /// non-finite guess, options out of range), `DimensionMismatch` (guesses of the wrong
    /// length); `NoConvergence { method: "multiple-shooting", .. }` with the scaled residual
    /// reached where Newton does not converge, or `method: "multiple-shooting node
    /// insertion"` (iterations = nodes, residual = the growth) at the node budget;
    /// `SingularJacobian` where the Newton system is singular; a segment's integrator error
    /// where it fails at an accepted point.
    pub fn solve_with_jacobian<F, J, B>(
        &self,
        f: F,
        jac: J,
        bc: B,
        mesh: &[f64],
        y_guess: &[Vec<f64>],
        p_guess: &[f64],
    ) -> Result<MultipleShootingSolution, BvpError>
    where
        F: Fn(f64, &[f64], &[f64], &mut [f64]),
        J: Fn(f64, &[f64], &[f64], &mut [f64], &mut [f64]),
        B: Fn(&[f64], &[f64], &[f64], &mut [f64]),
    {
        self.run(&Analytic(f, jac), &bc, mesh, y_guess, p_guess)
    }

    fn check(&self, mesh: &[f64], y_guess: &[Vec<f64>], p_guess: &[f64]) -> Result<(), BvpError> {
        let bad = |name, value, reason| {
            Err(BvpError::InvalidInput {
                name,
                value,
                reason,
            })
        };
        if mesh.len() < 2 {
            return bad("mesh length", mesh.len() as f64, "at least 2 nodes");
        }
        if let Some(w) = mesh
            .windows(2)
            .find(|w| !(w[1] > w[0]) || !w[1].is_finite())
        {
            return bad("mesh", w[1], "nodes must be finite and strictly increasing");
        }
        if y_guess.len() != mesh.len() {
            return Err(BvpError::DimensionMismatch {
                name: "y_guess (one per node)",
                expected: mesh.len(),
                found: y_guess.len(),
            });
        }
        let n = y_guess[0].len();
        if n == 0 {
            return bad("states n", 0.0, "at least one state");
        }
        if let Some(g) = y_guess.iter().find(|g| g.len() != n) {
            return Err(BvpError::DimensionMismatch {
                name: "y_guess[j]",
                expected: n,
                found: g.len(),
            });
        }
        if let Some(v) = y_guess
            .iter()
            .flatten()
            .chain(p_guess)
            .find(|v| !v.is_finite())
        {
            return bad("guess", *v, "guesses must be finite");
        }
        for (name, v) in [("tol", self.tol), ("max_growth", self.max_growth - 1.0)] {
            if !(v > 0.0) {
                return bad(name, v, "must be positive (max_growth above 1)");
            }
        }
        Ok(())
    }

    fn run<R: Rhs + ?Sized, B>(
        &self,
        rhs: &R,
        bc: &B,
        mesh: &[f64],
        y_guess: &[Vec<f64>],
        p_guess: &[f64],
    ) -> Result<MultipleShootingSolution, BvpError>
    where
        B: Fn(&[f64], &[f64], &[f64], &mut [f64]),
    {
        self.check(mesh, y_guess, p_guess)?;
        let dop = Dop853 {
            max_steps: self.max_steps,
            ..Dop853::new(self.rtol, self.atol)
        };
        let n = y_guess[0].len();
        let mut it = Iterate {
            x: mesh.to_vec(),
            s: y_guess.to_vec(),
            p: p_guess.to_vec(),
        };
        let mut evaluations = 0;
        let mut iterations = 0;
        loop {
            let e = loop {
                match self.evaluate(rhs, bc, &dop, &it, true, &mut evaluations) {
                    Ok(e) => {
                        let split = self.split(&mut it, Some(&e.m), &[])?;
                        if !split {
                            break e;
                        }
                    }
                    Err(Failed(bad)) => {
                        if !self.split(&mut it, None, &bad)? {
                            return Err(BvpError::NonFinite {
                                what:
                                    "a segment's integration at the current iterate (s = its start)",
                                s: it.x[bad[0]],
                            });
                        }
                    }
                }
            };
            if e.norm <= self.tol {
                return self.finish(rhs, &dop, it, iterations, e.norm, mesh.len(), evaluations);
            }
            if iterations >= self.max_iter {
                return Err(BvpError::NoConvergence {
                    method: "multiple-shooting",
                    iterations,
                    residual: e.norm,
                });
            }
            let dz = self.newton_step(bc, &it, &e, n)?;
            let mut lambda = 1.0;
            let mut accepted = false;
            for _ in 0..=self.halvings {
                let trial = step(&it, &dz, lambda, n);
                if let Ok(t) = self.evaluate(rhs, bc, &dop, &trial, false, &mut evaluations) {
                    if t.norm <= (1.0 - 1e-4 * lambda) * e.norm {
                        it = trial;
                        accepted = true;
                        break;
                    }
                }
                lambda *= 0.5;
            }
            iterations += 1;
            if !accepted {
                return Err(BvpError::NoConvergence {
                    method: "multiple-shooting",
                    iterations,
                    residual: e.norm,
                });
            }
        }
    }

    /// The residuals at `it`, with the segments' sensitivities if `sens`; the segments
    /// that failed to integrate otherwise.
    fn evaluate<R: Rhs + ?Sized, B>(
        &self,
        rhs: &R,
        bc: &B,
        dop: &Dop853,
        it: &Iterate,
        sens: bool,
        evaluations: &mut usize,
    ) -> Result<Evaluated, Failed>
    where
        B: Fn(&[f64], &[f64], &[f64], &mut [f64]),
    {
        let m = it.x.len();
        let n = it.s[0].len();
        let k = it.p.len();
        let mut r = Vec::with_capacity((m - 1) * n + n + k);
        let mut ms = Vec::new();
        let mut norm: f64 = 0.0;
        let mut failed = Vec::new();
        let loose = Dop853 {
            rtol: self.jac_tol.max(dop.rtol),
            atol: self.jac_tol.max(dop.atol),
            ..dop.clone()
        };
        for j in 0..m - 1 {
            let span = (it.x[j], it.x[j + 1]);
            let together = sens && self.jac_tol <= dop.rtol.min(dop.atol);
            let shot = segment::shoot(rhs, dop, span, &it.s[j], &it.p, together).and_then(|end| {
                if !sens || together {
                    return Ok(end);
                }
                let with = segment::shoot(rhs, &loose, span, &it.s[j], &it.p, true)?;
                Ok(segment::End {
                    evaluations: end.evaluations + with.evaluations,
                    m: with.m,
                    ..end
                })
            });
            match shot {
                Ok(end) => {
                    *evaluations += end.evaluations;
                    for i in 0..n {
                        let c = end.y[i] - it.s[j + 1][i];
                        norm = norm.max(c.abs() / (1.0 + it.s[j + 1][i].abs()));
                        r.push(c);
                    }
                    if let Some(mj) = end.m {
                        ms.push(mj);
                    }
                }
                Err(_) => {
                    failed.push(j);
                    r.extend(std::iter::repeat_n(f64::NAN, n));
                }
            }
        }
        if !failed.is_empty() {
            return Err(Failed(failed));
        }
        let mut g = vec![0.0; n + k];
        bc(&it.s[0], &it.s[m - 1], &it.p, &mut g);
        for v in &g {
            norm = norm.max(v.abs());
        }
        r.extend_from_slice(&g);
        if !norm.is_finite() {
            return Err(Failed(vec![0]));
        }
        Ok(Evaluated { r, norm, m: ms })
    }

    /// Splits the segments whose growth exceeds `max_growth` (from `m`) or that are listed
    /// in `failed`; whether any was split.
    fn split(
        &self,
        it: &mut Iterate,
        m: Option<&Vec<Vec<f64>>>,
        failed: &[usize],
    ) -> Result<bool, BvpError> {
        let n = it.s[0].len();
        let w = n + it.p.len();
        let mut worst: f64 = 0.0;
        let too_big: Vec<usize> = match m {
            Some(ms) => (0..ms.len())
                .filter(|&j| {
                    let g = (0..n)
                        .map(|i| (0..n).map(|c| ms[j][i * w + c].abs()).sum::<f64>())
                        .fold(0.0, f64::max);
                    worst = worst.max(g);
                    !(g <= self.max_growth)
                })
                .collect(),
            None => failed.to_vec(),
        };
        if too_big.is_empty() {
            return Ok(false);
        }
        if it.x.len() + too_big.len() > self.max_nodes {
            return Err(BvpError::NoConvergence {
                method: "multiple-shooting node insertion",
                iterations: it.x.len(),
                residual: worst,
            });
        }
        for &j in too_big.iter().rev() {
            let xm = 0.5 * (it.x[j] + it.x[j + 1]);
            if !(xm > it.x[j] && xm < it.x[j + 1]) {
                return Err(BvpError::StepSizeUnderflow {
                    s: it.x[j],
                    h: it.x[j + 1] - it.x[j],
                });
            }
            let sm: Vec<f64> = it.s[j]
                .iter()
                .zip(&it.s[j + 1])
                .map(|(a, b)| 0.5 * (a + b))
                .collect();
            it.x.insert(j + 1, xm);
            it.s.insert(j + 1, sm);
        }
        Ok(true)
    }

    /// The Newton step `dz = (ds_0 .. ds_{m-1}, dp)` by the staircase elimination.
    fn newton_step<B>(
        &self,
        bc: &B,
        it: &Iterate,
        e: &Evaluated,
        n: usize,
    ) -> Result<Vec<f64>, BvpError>
    where
        B: Fn(&[f64], &[f64], &[f64], &mut [f64]),
    {
        let m = it.x.len();
        let k = it.p.len();
        let w = n + k;
        let nc = (m - 1) * n;
        let nb = n + k;
        // rows: bc (window at 0), then c_j (window at j n)
        let mut off = vec![0; nb];
        off.extend((0..m - 1).flat_map(|j| std::iter::repeat_n(j * n, n)));
        let mut sys = Staircase::new(nc, nb, 2 * n, off);
        // boundary blocks by forward differences of bc: columns of s_0, s_{m-1}, p
        let g0 = &e.r[nc..];
        let sq = f64::EPSILON.sqrt();
        let mut g1 = vec![0.0; nb];
        let (mut ya, mut yb, mut p) = (it.s[0].clone(), it.s[m - 1].clone(), it.p.clone());
        for col in 0..n + n + k {
            let (v, target) = match col {
                c if c < n => (&mut ya[c], c),
                c if c < 2 * n => (&mut yb[c - n], nc + c - n),
                c => (&mut p[c - 2 * n], nc + n + c - 2 * n),
            };
            let old = *v;
            *v = old + sq * old.abs().max(1.0);
            let h = *v - old;
            bc(&ya, &yb, &p, &mut g1);
            match col {
                c if c < n => ya[c] = old,
                c if c < 2 * n => yb[c - n] = old,
                c => p[c - 2 * n] = old,
            }
            for i in 0..nb {
                sys.add(i, target, (g1[i] - g0[i]) / h);
            }
        }
        for (i, g) in g0.iter().enumerate() {
            sys.set_rhs(i, -g);
        }
        for j in 0..m - 1 {
            let mj = &e.m[j];
            for i in 0..n {
                let row = nb + j * n + i;
                for c in 0..n {
                    sys.add(row, j * n + c, mj[i * w + c]);
                }
                sys.add(row, (j + 1) * n + i, -1.0);
                for c in 0..k {
                    sys.add(row, nc + n + c, mj[i * w + n + c]);
                }
                sys.set_rhs(row, -e.r[j * n + i]);
            }
        }
        sys.solve()
    }

    /// The answer: each segment's dense output from its node.
    #[allow(clippy::too_many_arguments)]
    fn finish<R: Rhs + ?Sized>(
        &self,
        rhs: &R,
        dop: &Dop853,
        it: Iterate,
        iterations: usize,
        residual: f64,
        user_nodes: usize,
        mut evaluations: usize,
    ) -> Result<MultipleShootingSolution, BvpError> {
        let m = it.x.len();
        let n = it.s[0].len();
        let mut segments = Vec::with_capacity(m - 1);
        for j in 0..m - 1 {
            let sol = segment::dense(rhs, dop, (it.x[j], it.x[j + 1]), &it.s[j], &it.p)?;
            evaluations += sol.stats.rhs_evals;
            segments.push(sol);
        }
        Ok(MultipleShootingSolution {
            unknowns: m * n + it.p.len(),
            inserted: m - user_nodes,
            x: it.x,
            y: it.s,
            p: it.p,
            iterations,
            residual,
            evaluations,
            segments,
        })
    }
}

/// The segments that failed to integrate.
struct Failed(Vec<usize>);

/// `it + lambda dz`.
fn step(it: &Iterate, dz: &[f64], lambda: f64, n: usize) -> Iterate {
    let m = it.x.len();
    Iterate {
        x: it.x.clone(),
        s: (0..m)
            .map(|j| {
                it.s[j]
                    .iter()
                    .enumerate()
                    .map(|(i, v)| v + lambda * dz[j * n + i])
                    .collect()
            })
            .collect(),
        p: it
            .p
            .iter()
            .enumerate()
            .map(|(i, v)| v + lambda * dz[m * n + i])
            .collect(),
    }
}
