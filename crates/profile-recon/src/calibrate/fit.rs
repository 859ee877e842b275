//! A small bounded Levenberg-Marquardt (Moré 1978: Marquardt's diagonal scaling, steps
//! projected onto the box of bounds) with a forward-difference Jacobian, for problems of a
//! few parameters and many residuals. Hand-written rather than argmin's trust region: the
//! calibration needs the bounds, a residual function that may fail for a trial point (the
//! step is then shortened, as for a rise of the cost), and a state carried from one accepted
//! point to the next (the tracked phase-B roots). Its linear algebra is
//! [`bvp_solvers::dense`]'s.

use bvp_solvers::dense;

/// A least-squares problem `min |r(p)|^2 / 2` for the fit.
pub(crate) trait Problem {
    /// The state an evaluation carries to the next (tracked roots).
    type State: Clone;
    /// Residuals at `p` starting from `state`, with the state reached; `None` where the
    /// model admits no solution.
    fn residuals(&self, p: &[f64], state: &Self::State) -> Option<(Vec<f64>, Self::State)>;
    /// Called after every iteration of [`levenberg_marquardt`] with its cost (progress).
    fn iterated(&self, _iteration: usize, _cost: f64) {}
}

/// Settings of [`levenberg_marquardt`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LmSettings {
    /// Iterations at most.
    pub max_iter: usize,
    /// Stop when a rejected step has every component below `xtol (|p_i| + scale_i)`.
    pub xtol: f64,
    /// Stop when the Gauss-Newton step would lower the cost by less than `ftol` times it.
    pub ftol: f64,
    /// Stop when the RMS residual is below this (the residuals' numerical floor).
    pub floor: f64,
    /// Stop when the last [`STALL_SPAN`] iterations lowered the cost by less than this
    /// fraction (0: never): a fit crawling in a compromise, whose phases are better decided
    /// again than followed further.
    pub stall: f64,
}

/// Iterations over which [`LmSettings::stall`] measures the progress.
pub(crate) const STALL_SPAN: usize = 5;

impl Default for LmSettings {
    fn default() -> Self {
        LmSettings {
            max_iter: 100,
            xtol: 1e-13,
            ftol: 1e-8,
            floor: 0.0,
            stall: 0.0,
        }
    }
}

/// The box and the typical sizes of the parameters.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Bounds {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// Typical size: finite-difference steps and the stopping test are relative to it.
    pub scale: Vec<f64>,
}

impl Bounds {
    fn clamp(&self, p: &mut [f64]) {
        for (i, v) in p.iter_mut().enumerate() {
            *v = v.clamp(self.lo[i], self.hi[i]);
        }
    }
}

/// The result of a fit.
#[derive(Clone, Debug)]
pub(crate) struct LmResult<S> {
    pub p: Vec<f64>,
    pub state: S,
    pub iterations: usize,
    pub evaluations: usize,
    /// The cost at `p`.
    pub cost: f64,
}

/// The finite-difference Jacobian's columns `column(i, h)` (`dr / dp_i`), each parameter's
/// step `h` `step_rel`-relative to its size plus its scale; `None` if a column is.
fn columns(
    p: &[f64],
    bounds: &Bounds,
    step_rel: f64,
    column: impl FnMut(usize, f64) -> Option<Vec<f64>>,
) -> Option<Vec<Vec<f64>>> {
    let mut column = column;
    (0..p.len())
        .map(|i| column(i, step_rel * (p[i].abs() + bounds.scale[i])))
        .collect()
}

/// Forward-difference Jacobian (column-major: `jac[i]` is `dr / dp_i`), steps
/// `sqrt(eps)`-relative to the parameter's scale, taken inwards at an upper bound.
pub(crate) fn jacobian<P: Problem>(
    prob: &P,
    p: &[f64],
    r: &[f64],
    state: &P::State,
    bounds: &Bounds,
    step_rel: f64,
) -> Option<Vec<Vec<f64>>> {
    columns(p, bounds, step_rel, |i, h| {
        let h = if p[i] + h > bounds.hi[i] { -h } else { h };
        // forwards, else backwards (a phase-B root may leave the whisker on one side)
        for sign in [1.0, -1.0] {
            let mut q = p.to_vec();
            q[i] = (p[i] + sign * h).clamp(bounds.lo[i], bounds.hi[i]);
            let d = q[i] - p[i];
            if d == 0.0 {
                continue;
            }
            if let Some((rq, _)) = prob.residuals(&q, state) {
                return Some(rq.iter().zip(r).map(|(a, b)| (a - b) / d).collect());
            }
        }
        None
    })
}

/// Central-difference Jacobian (for the final covariance: error `O(h^2)`), one-sided at a
/// bound.
pub(crate) fn jacobian_central<P: Problem>(
    prob: &P,
    p: &[f64],
    state: &P::State,
    bounds: &Bounds,
    step_rel: f64,
) -> Option<Vec<Vec<f64>>> {
    columns(p, bounds, step_rel, |i, h| {
        let mut up = p.to_vec();
        let mut down = p.to_vec();
        up[i] = (p[i] + h).min(bounds.hi[i]);
        down[i] = (p[i] - h).max(bounds.lo[i]);
        let ru = prob.residuals(&up, state).map(|x| x.0);
        let rd = prob.residuals(&down, state).map(|x| x.0);
        let (ru, rd, d) = match (ru, rd) {
            (Some(u), Some(d)) => (u, d, up[i] - down[i]),
            (Some(u), None) => (u, prob.residuals(p, state)?.0, up[i] - p[i]),
            (None, Some(d)) => (prob.residuals(p, state)?.0, d, p[i] - down[i]),
            (None, None) => return None,
        };
        Some(ru.iter().zip(&rd).map(|(a, b)| (a - b) / d).collect())
    })
}

/// `sum r^2 / 2`.
pub(crate) fn cost(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|v| v * v).sum::<f64>()
}

/// Bounded Levenberg-Marquardt from `p0` (clamped into the box): each iteration solves
/// `(J^T J + mu diag(J^T J)) d = -J^T r`, projects `p + d` onto the box and accepts it if the
/// cost falls (then `mu` shrinks by 3), else raises `mu` by 4 (a failed evaluation counts
/// as a rise). `None` if the start itself cannot be evaluated.
pub(crate) fn levenberg_marquardt<P: Problem>(
    prob: &P,
    p0: &[f64],
    state0: &P::State,
    bounds: &Bounds,
    settings: &LmSettings,
) -> Option<LmResult<P::State>> {
    let n = p0.len();
    let mut p = p0.to_vec();
    bounds.clamp(&mut p);
    let (mut r, mut state) = prob.residuals(&p, state0)?;
    let mut c = cost(&r);
    let mut evaluations = 1;
    let mut mu = 1e-3;
    let mut iterations = 0;
    if n == 0 {
        return Some(LmResult {
            p,
            state,
            iterations,
            evaluations,
            cost: c,
        });
    }
    let mut history = vec![c];
    'outer: while iterations < settings.max_iter {
        if history.len() > STALL_SPAN
            && c > (1.0 - settings.stall) * history[history.len() - 1 - STALL_SPAN]
        {
            break;
        }
        iterations += 1;
        let Some(jac) = jacobian(prob, &p, &r, &state, bounds, 1e-7) else {
            break;
        };
        evaluations += n;
        let jtj: Vec<Vec<f64>> = (0..n)
            .map(|i| (0..n).map(|k| dot(&jac[i], &jac[k])).collect())
            .collect();
        let g: Vec<f64> = (0..n).map(|i| dot(&jac[i], &r)).collect();
        if g.iter().all(|v| *v == 0.0) {
            break;
        }
        let dmax = (0..n).map(|i| jtj[i][i]).fold(0.0, f64::max);
        // active set: a parameter at a bound that the descent direction pushes outwards
        // stays there this iteration
        let blocked: Vec<bool> = (0..n)
            .map(|i| (p[i] <= bounds.lo[i] && g[i] > 0.0) || (p[i] >= bounds.hi[i] && g[i] < 0.0))
            .collect();
        let step = |mu: f64| -> Option<Vec<f64>> {
            let mut a = jtj.clone();
            for (i, row) in a.iter_mut().enumerate() {
                row[i] += mu * row[i].max(1e-12 * dmax).max(f64::MIN_POSITIVE);
            }
            let mut neg: Vec<f64> = g.iter().map(|v| -v).collect();
            for i in (0..n).filter(|&i| blocked[i]) {
                a[i].iter_mut().for_each(|v| *v = 0.0);
                for row in a.iter_mut() {
                    row[i] = 0.0;
                }
                a[i][i] = 1.0;
                neg[i] = 0.0;
            }
            dense::solve_spd(&a, &neg)
        };
        // converged: the Gauss-Newton step would lower the cost by a negligible amount
        if let Some(d) = step(1e-10) {
            let pred = -0.5 * dot(&g, &d);
            let floor = 0.5 * r.len() as f64 * settings.floor * settings.floor;
            if pred <= settings.ftol * c || c <= floor {
                break;
            }
        }
        loop {
            let Some(d) = step(mu) else {
                mu *= 4.0;
                if mu > 1e20 {
                    break 'outer;
                }
                continue;
            };
            let mut trial: Vec<f64> = p.iter().zip(&d).map(|(a, b)| a + b).collect();
            bounds.clamp(&mut trial);
            let small = (0..n)
                .all(|i| (trial[i] - p[i]).abs() <= settings.xtol * (p[i].abs() + bounds.scale[i]));
            evaluations += 1;
            match prob.residuals(&trial, &state) {
                Some((rt, st)) if cost(&rt) < c => {
                    let ct = cost(&rt);
                    (p, r, state, c) = (trial, rt, st, ct);
                    history.push(c);
                    prob.iterated(iterations, c);
                    mu = (mu / 3.0).max(1e-12);
                    break;
                }
                _ => {
                    if small {
                        break 'outer;
                    }
                    mu *= 4.0;
                    if mu > 1e20 {
                        break 'outer;
                    }
                }
            }
        }
    }
    let _ = r;
    Some(LmResult {
        p,
        state,
        iterations,
        evaluations,
        cost: c,
    })
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock as residuals, with a bound that cuts off the minimum in one test.
    struct Rosen;
    impl Problem for Rosen {
        type State = ();
        fn residuals(&self, p: &[f64], _: &()) -> Option<(Vec<f64>, ())> {
            Some((vec![10.0 * (p[1] - p[0] * p[0]), 1.0 - p[0]], ()))
        }
    }

    /// Levenberg-Marquardt on Rosenbrock from (-1.2, 1), p0 bounded above by `hi0`.
    fn fit_rosen(hi0: f64) -> Vec<f64> {
        let bounds = Bounds {
            lo: vec![-5.0, -5.0],
            hi: vec![hi0, 5.0],
            scale: vec![1.0, 1.0],
        };
        levenberg_marquardt(&Rosen, &[-1.2, 1.0], &(), &bounds, &LmSettings::default())
            .unwrap()
            .p
    }

    #[test]
    fn rosenbrock_minimum() {
        let p = fit_rosen(5.0);
        assert!(
            (p[0] - 1.0).abs() < 1e-9 && (p[1] - 1.0).abs() < 1e-9,
            "{p:?}"
        );
    }

    #[test]
    fn bound_is_respected() {
        // the bound cuts off the minimum: the best point on it, (0.5, 0.25)
        let p = fit_rosen(0.5);
        assert!(p[0] <= 0.5);
        assert!(
            (p[0] - 0.5).abs() < 1e-6 && (p[1] - 0.25).abs() < 1e-6,
            "{p:?}"
        );
    }

    #[test]
    fn difference_jacobians_match_the_analytic_one() {
        // d r / d p of Rosen at (0.3, -0.2): columns (-20 p0, -1) and (10, 0)
        let p = [0.3, -0.2];
        let want = [[-6.0, -1.0], [10.0, 0.0]];
        let r = Rosen.residuals(&p, &()).unwrap().0;
        // an upper bound just above p0: the forward step for p0 is taken backwards
        let bounds = Bounds {
            lo: vec![-5.0, -5.0],
            hi: vec![0.3 + 1e-9, 5.0],
            scale: vec![1.0, 1.0],
        };
        let fwd = jacobian(&Rosen, &p, &r, &(), &bounds, 1e-7).unwrap();
        let cen = jacobian_central(&Rosen, &p, &(), &bounds, 1e-5).unwrap();
        for (i, w) in want.iter().enumerate() {
            for (k, v) in w.iter().enumerate() {
                assert!((fwd[i][k] - v).abs() < 1e-5, "forward {i} {k}: {fwd:?}");
            }
        }
        // central: one-sided at the bound (from p0 - 1.3e-5 to the bound: the secant of
        // -10 p0^2 is -10 (up + down)), symmetric and exact for the linear residual of p1
        let (up, down) = (0.3 + 1e-9, 0.3 - 1e-5 * 1.3);
        assert!((cen[0][0] + 10.0 * (up + down)).abs() < 1e-8, "{cen:?}");
        assert!((cen[0][1] + 1.0).abs() < 1e-9 && (cen[1][1]).abs() < 1e-12);
        assert!((cen[1][0] - 10.0).abs() < 1e-9);
    }
}
