//! Damped Newton on the collocation system as scipy's `solve_newton` (after BVP_SOLVER and
//! bvp4c): the criterion is the affine-invariant `|J^-1 F|^2` with the current factors
//! (Deuflhard's natural level function), Armijo backtracking (`sigma = 0.2`, `tau = 0.5`, at
//! most 4 halvings), at most 4 Jacobians and 8 iterations per mesh; a full step keeps the
//! factors for the next iteration ("simplified Newton"). It stops when every collocation
//! residual is below `tol_r (1 + |f_mid|)` with `tol_r = (2/3) h 0.05 tol` (the midpoint
//! residual `1.5 r / h` 1.5 orders below `tol`) and the boundary residuals below `bc_tol`.

// Index arithmetic on flat row-major blocks (`a[r * n + c]`) reads as the equations do.
#![allow(clippy::needless_range_loop)]

use super::abd::{AbdLu, AbdMatrix};
use super::problem::BvpProblem;
use super::separated::SeparatedLu;
use super::system::{Colloc, System};
use crate::BvpError;

/// The buffers of [`solve_newton`]: its residuals, steps, trial point and the factors of the
/// Jacobian, kept across Newton iterations and meshes so that a solve allocates them once
/// (resized, never cleared: every entry is written before it is read).
#[derive(Debug, Default)]
pub struct NewtonWork {
    bc_res: Vec<f64>,
    res: Vec<f64>,
    tmp: Vec<f64>,
    lu: AbdLu,
    sep: SeparatedLu,
    /// Whether the current factors are `sep`'s (separated boundary rows) or `lu`'s.
    separated: bool,
    step: Vec<f64>,
    y_new: Vec<f64>,
    p_new: Vec<f64>,
    step_new: Vec<f64>,
    proj: Vec<f64>,
}

impl NewtonWork {
    /// Bytes held (capacities).
    pub fn bytes(&self) -> usize {
        let v = [
            &self.bc_res,
            &self.res,
            &self.tmp,
            &self.step,
            &self.y_new,
            &self.p_new,
            &self.step_new,
            &self.proj,
        ];
        v.iter().map(|b| b.capacity()).sum::<usize>() * std::mem::size_of::<f64>()
            + self.lu.bytes()
            + self.sep.bytes()
    }
}

/// Solves with the current factors: [`SeparatedLu`]'s where the boundary rows are separated,
/// else the bordered [`AbdLu`]'s.
fn solve_with(lu: &AbdLu, sep: &SeparatedLu, separated: bool, b: &mut [f64], tmp: &mut Vec<f64>) {
    if separated {
        sep.solve_in_place(b, tmp);
    } else {
        lu.solve_in_place(b, tmp);
    }
}

/// Runs Newton on the mesh `x` from `(y, p)`, updating them; `Err` only for a singular
/// Jacobian (the caller reports it after evaluating the residuals, as scipy).
#[allow(clippy::too_many_arguments)]
pub fn solve_newton<P: BvpProblem + ?Sized>(
    sys: &mut System<'_, P>,
    x: &[f64],
    y: &mut Vec<f64>,
    p: &mut Vec<f64>,
    tol: f64,
    bc_tol: f64,
    col: &mut Colloc,
    mat: &mut AbdMatrix,
    work: &mut NewtonWork,
) -> Result<(), BvpError> {
    let (n, k) = (sys.n, sys.k);
    let m = x.len();
    const MAX_NJEV: usize = 4;
    const MAX_ITER: usize = 8;
    const SIGMA: f64 = 0.2;
    const TAU: f64 = 0.5;
    const N_TRIAL: usize = 4;
    let nr = n + k;
    let NewtonWork {
        bc_res,
        res,
        tmp,
        lu,
        sep,
        separated,
        step,
        y_new,
        p_new,
        step_new,
        proj,
    } = work;
    bc_res.resize(nr, 0.0);
    res.resize(m * n + k, 0.0);
    step.resize(m * n + k, 0.0);
    step_new.resize(m * n + k, 0.0);
    y_new.resize(m * n, 0.0);
    p_new.resize(k, 0.0);
    proj.resize(n, 0.0);
    sys.collocation(x, y, p, col);
    sys.bc(&y[..n], &y[(m - 1) * n..], p, bc_res);
    let fill = |res: &mut [f64], col: &Colloc, bc: &[f64]| {
        res[..(m - 1) * n].copy_from_slice(&col.res);
        res[(m - 1) * n..].copy_from_slice(bc);
    };
    fill(res, col, bc_res);
    let mut njev = 0;
    let mut recompute = true;
    let mut cost = 0.0;
    for _ in 0..MAX_ITER {
        sys.stats.newton_iterations += 1;
        if recompute {
            sys.jacobian(x, y, p, col, bc_res, mat);
            njev += 1;
            *separated = sep.factor_into(mat)?;
            if !*separated {
                lu.factor_into(mat)?;
            }
            step.copy_from_slice(res);
            solve_with(lu, sep, *separated, step, tmp);
            cost = step.iter().map(|v| v * v).sum();
        }
        let mut alpha = 1.0;
        let mut cost_new = f64::INFINITY;
        for trial in 0..=N_TRIAL {
            for i in 0..m * n {
                y_new[i] = y[i] - alpha * step[i];
            }
            if let Some(sg) = &sys.sing {
                for r in 0..n {
                    proj[r] = (0..n).map(|c| sg.b[r * n + c] * y_new[c]).sum();
                }
                y_new[..n].copy_from_slice(proj);
            }
            for i in 0..k {
                p_new[i] = p[i] - alpha * step[m * n + i];
            }
            sys.collocation(x, y_new, p_new, col);
            sys.bc(&y_new[..n], &y_new[(m - 1) * n..], p_new, bc_res);
            fill(res, col, bc_res);
            step_new.copy_from_slice(res);
            solve_with(lu, sep, *separated, step_new, tmp);
            cost_new = step_new.iter().map(|v| v * v).sum();
            if cost_new < (1.0 - 2.0 * alpha * SIGMA) * cost {
                break;
            }
            if trial < N_TRIAL {
                alpha *= TAU;
            }
        }
        // the last trial is kept even when it failed the Armijo test, as scipy does
        std::mem::swap(y, y_new);
        std::mem::swap(p, p_new);
        if njev == MAX_NJEV {
            break;
        }
        let mut done = bc_res.iter().all(|r| r.abs() < bc_tol);
        if done {
            'outer: for i in 0..m - 1 {
                let tol_r = 2.0 / 3.0 * (x[i + 1] - x[i]) * 5e-2 * tol;
                for c in 0..n {
                    let ok = col.res[i * n + c].abs() < tol_r * (1.0 + col.f_mid[i * n + c].abs());
                    if !ok {
                        done = false;
                        break 'outer;
                    }
                }
            }
        }
        if done {
            break;
        }
        if alpha == 1.0 {
            std::mem::swap(step, step_new);
            cost = cost_new;
            recompute = false;
        } else {
            recompute = true;
        }
    }
    Ok(())
}
