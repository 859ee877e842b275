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
use super::system::{Colloc, System};
use crate::BvpError;

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
) -> Result<(), BvpError> {
    let (n, k) = (sys.n, sys.k);
    let m = x.len();
    const MAX_NJEV: usize = 4;
    const MAX_ITER: usize = 8;
    const SIGMA: f64 = 0.2;
    const TAU: f64 = 0.5;
    const N_TRIAL: usize = 4;
    let nr = n + k;
    let mut bc_res = vec![0.0; nr];
    sys.collocation(x, y, p, col);
    sys.bc(&y[..n], &y[(m - 1) * n..], p, &mut bc_res);
    let mut res = vec![0.0; m * n + k];
    let fill = |res: &mut [f64], col: &Colloc, bc: &[f64]| {
        res[..(m - 1) * n].copy_from_slice(&col.res);
        res[(m - 1) * n..].copy_from_slice(bc);
    };
    fill(&mut res, col, &bc_res);
    let mut tmp = Vec::new();
    let mut njev = 0;
    let mut recompute = true;
    let mut lu = AbdLu::default();
    let mut step = vec![0.0; m * n + k];
    let mut cost = 0.0;
    let mut y_new = vec![0.0; m * n];
    let mut p_new = vec![0.0; k];
    let mut step_new = vec![0.0; m * n + k];
    let mut proj = vec![0.0; n];
    for _ in 0..MAX_ITER {
        sys.stats.newton_iterations += 1;
        if recompute {
            sys.jacobian(x, y, p, col, &bc_res, mat);
            njev += 1;
            lu = AbdLu::factor(mat)?;
            step.copy_from_slice(&res);
            lu.solve_in_place(&mut step, &mut tmp);
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
                y_new[..n].copy_from_slice(&proj);
            }
            for i in 0..k {
                p_new[i] = p[i] - alpha * step[m * n + i];
            }
            sys.collocation(x, &y_new, &p_new, col);
            sys.bc(&y_new[..n], &y_new[(m - 1) * n..], &p_new, &mut bc_res);
            fill(&mut res, col, &bc_res);
            step_new.copy_from_slice(&res);
            lu.solve_in_place(&mut step_new, &mut tmp);
            cost_new = step_new.iter().map(|v| v * v).sum();
            if cost_new < (1.0 - 2.0 * alpha * SIGMA) * cost {
                break;
            }
            if trial < N_TRIAL {
                alpha *= TAU;
            }
        }
        // the last trial is kept even when it failed the Armijo test, as scipy does
        std::mem::swap(y, &mut y_new);
        std::mem::swap(p, &mut p_new);
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
            std::mem::swap(&mut step, &mut step_new);
            cost = cost_new;
            recompute = false;
        } else {
            recompute = true;
        }
    }
    Ok(())
}
