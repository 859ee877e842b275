//! The thesis's method: central finite differences on the second-order form [3.25] with
//! Newton on the tridiagonal Jacobian [3.27], the spring base as a Robin condition, the free
//! end as a Neumann condition, and an outer secant iteration on the tip angle for AP loads.

use crate::equations::WhiskerFdmProblem;
use crate::error::{ModelError, Result};
use crate::loads::{LoadKind, Loads};
use crate::scene::Scene;
use crate::solution::{BaseObservables, Elastica, EndState, Solution, SolveStats};
use crate::support::Support;
use crate::whisker::Whisker;
use bvp_solvers::continuation::Continuation;
use bvp_solvers::fdm::{BoundaryCondition, FdmOptions, FdmSolution, FdmSolver};
use bvp_solvers::grid::UniformGrid;
use std::f64::consts::FRAC_PI_2;

const METHOD: &str = "fdm";
const MAX_OUTER: usize = 60;

fn solver(whisker: &Whisker, s1: f64) -> FdmSolver {
    let left = match whisker.support {
        Support::Rigid => BoundaryCondition::Dirichlet(FRAC_PI_2),
        // phi(0) - (phi'(0) - B)/k = pi/2  [3.21, 3.22]
        Support::Spring { k } => BoundaryCondition::Robin {
            alpha: 1.0,
            beta: -1.0 / k,
            gamma: FRAC_PI_2 - whisker.b / k,
        },
    };
    FdmSolver {
        left,
        // m(s1) = 0  <=>  phi'(s1) = A s1 + B
        right: BoundaryCondition::Neumann(whisker.kappa0(s1)),
        options: FdmOptions {
            tol: 1e-12,
            max_iter: 50,
            damping: 1.0,
        },
    }
}

/// FDM solve for fixed loads; AP loads get an outer secant iteration on `phi1`.
fn solve_fixed(
    whisker: &Whisker,
    loads: &Loads,
    grid: &UniformGrid,
    guess: &[f64],
) -> Result<(FdmSolution, usize)> {
    let solver = solver(whisker, loads.s1);
    let err = |source| ModelError::Solver {
        method: METHOD,
        source,
    };
    let run = |phi1: f64, guess: &[f64]| {
        solver
            .solve(&WhiskerFdmProblem::new(*whisker, *loads, phi1), grid, guess)
            .map_err(err)
    };
    let last = |sol: &FdmSolution| sol.y.last().copied().unwrap_or(f64::NAN);
    match loads.tip.kind {
        LoadKind::Dp => {
            let sol = run(0.0, guess)?;
            let it = sol.stats.iterations;
            Ok((sol, it))
        }
        LoadKind::Ap => {
            // Fixed point phi1 = phi_h(s1; phi1), solved by the secant method.
            let mut p0 = last_or(guess);
            let mut sol0 = run(p0, guess)?;
            let mut r0 = last(&sol0) - p0;
            let mut p1 = last(&sol0);
            let mut iterations = sol0.stats.iterations;
            for _ in 0..MAX_OUTER {
                let sol1 = run(p1, &sol0.y)?;
                iterations += sol1.stats.iterations;
                let r1 = last(&sol1) - p1;
                if r1.abs() <= 1e-12 {
                    return Ok((sol1, iterations));
                }
                let denom = r1 - r0;
                let next = if denom != 0.0 && denom.is_finite() {
                    p1 - r1 * (p1 - p0) / denom
                } else {
                    last(&sol1)
                };
                let next = p1 + (next - p1).clamp(-0.5, 0.5);
                p0 = p1;
                r0 = r1;
                p1 = next;
                sol0 = sol1;
            }
            Err(ModelError::NoConvergence {
                method: METHOD,
                load_scale: 1.0,
                iterations,
                residual: r0.abs(),
            })
        }
    }
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

fn last_or(v: &[f64]) -> f64 {
    v.last().copied().unwrap_or(FRAC_PI_2)
}

/// Solves a scene with the FDM on `ceil(n s1)` intervals of `[0, s1]`.
pub(crate) fn solve(scene: &Scene, n: usize) -> Result<Solution> {
    let w = &scene.whisker;
    let loads = &scene.loads;
    let s1 = loads.s1;
    let intervals = ((n as f64) * s1).ceil().max(4.0) as usize;
    let grid = UniformGrid::new(0.0, s1, intervals).map_err(|source| ModelError::Solver {
        method: METHOD,
        source,
    })?;
    let unloaded: Vec<f64> = grid.nodes().iter().map(|&s| w.phi_unloaded(s)).collect();
    let sev = super::shooting::severity(w, loads);
    let direct = if sev <= 1.0 {
        solve_fixed(w, loads, &grid, &unloaded).ok()
    } else {
        None
    };
    let (sol, iterations, continuation_steps) = match direct {
        Some((sol, it)) => (sol, it, 0),
        None => {
            // Load continuation with a secant predictor; a corrector that lands far from its
            // prediction has jumped to another branch and counts as a failure.
            let first = (1.0 / sev.ceil()).clamp(1e-3, 1.0);
            let cont = Continuation {
                initial_step: first,
                min_step: 1e-4,
                max_step: (2.0 * first).min(1.0),
            };
            let mut reached = 0.0;
            let zero = vec![0.0; unloaded.len()];
            type State = (f64, Vec<f64>, Vec<f64>);
            let r = cont.run(
                0.0,
                1.0,
                (0.0, unloaded.clone(), zero),
                |lambda, (l0, y0, slope): &State| {
                    if lambda == 0.0 {
                        return Ok((0.0, y0.clone(), slope.clone()));
                    }
                    let pred: Vec<f64> = y0
                        .iter()
                        .zip(slope)
                        .map(|(y, d)| y + d * (lambda - l0))
                        .collect();
                    let (sol, it) = solve_fixed(w, &loads.scaled(lambda), &grid, &pred)?;
                    let jump = max_diff(&sol.y, &pred);
                    if jump > 0.2 + 0.5 * max_diff(&pred, y0) {
                        return Err(ModelError::NoConvergence {
                            method: METHOD,
                            load_scale: lambda,
                            iterations: it,
                            residual: jump,
                        });
                    }
                    reached = lambda;
                    let slope = sol
                        .y
                        .iter()
                        .zip(y0)
                        .map(|(a, b)| (a - b) / (lambda - l0))
                        .collect();
                    Ok((lambda, sol.y, slope))
                },
            );
            match r {
                Ok(((_, y, _), stats)) => {
                    let (sol, it) = solve_fixed(w, loads, &grid, &y)?;
                    (sol, it, stats.steps)
                }
                Err(e) => {
                    let (iterations, residual) = match e {
                        ModelError::NoConvergence {
                            iterations,
                            residual,
                            ..
                        } => (iterations, residual),
                        _ => (0, f64::NAN),
                    };
                    return Err(ModelError::NoConvergence {
                        method: METHOD,
                        load_scale: reached,
                        iterations,
                        residual,
                    });
                }
            }
        }
    };
    Ok(assemble(scene, &sol, iterations, continuation_steps, n))
}

/// Positions by the trapezoidal rule (second order, like the FDM), moments
/// `m = e^4 (phi' - kappa0)`, the free segment beyond `s1` and the observables.
fn assemble(
    scene: &Scene,
    sol: &FdmSolution,
    iterations: usize,
    continuation_steps: usize,
    n: usize,
) -> Solution {
    let w = &scene.whisker;
    let s1 = scene.loads.s1;
    let h = sol.grid.h();
    let mut el = Elastica::default();
    let (mut x, mut y) = (0.0, 0.0);
    for i in 0..sol.grid.len() {
        let s = sol.grid.x(i);
        let phi = sol.y[i];
        if i > 0 {
            let p0 = sol.y[i - 1];
            x += 0.5 * h * (p0.cos() + phi.cos());
            y += 0.5 * h * (p0.sin() + phi.sin());
        }
        let kappa = sol.yp[i];
        el.push(s, x, y, phi, kappa, w.stiffness(s) * (kappa - w.kappa0(s)));
    }
    let phi1 = last_or(&sol.y);
    let loaded_end = EndState { x, y, phi: phi1 };
    let mut tip = loaded_end;
    if s1 < 1.0 {
        let steps = ((n as f64) * (1.0 - s1)).ceil().max(1.0) as usize;
        let hs = (1.0 - s1) / steps as f64;
        let phi_free = |s: f64| phi1 + 0.5 * w.a * (s * s - s1 * s1) + w.b * (s - s1);
        for i in 1..=steps {
            let (sa, sb) = (s1 + (i - 1) as f64 * hs, s1 + i as f64 * hs);
            let (pa, pb) = (phi_free(sa), phi_free(sb));
            x += 0.5 * hs * (pa.cos() + pb.cos());
            y += 0.5 * hs * (pa.sin() + pb.sin());
            el.push(sb, x, y, pb, w.kappa0(sb), 0.0);
        }
        tip = EndState {
            x,
            y,
            phi: phi_free(1.0),
        };
    }
    let (ax, ay) = scene.base_reactions(phi1);
    let m0 = el.m.first().copied().unwrap_or(0.0);
    Solution {
        elastica: el,
        tip,
        loaded_end,
        base: BaseObservables {
            ax,
            ay,
            ma: -m0,
            phi0: sol.y.first().copied().unwrap_or(FRAC_PI_2),
        },
        stats: SolveStats {
            iterations,
            residual: sol.stats.residual,
            continuation_steps,
            evaluations: iterations * sol.grid.len(),
        },
    }
}
