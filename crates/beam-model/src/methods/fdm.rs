//! The thesis's method: central finite differences on the second-order form [3.25] with
//! Newton on the tridiagonal Jacobian [3.27], the spring base as a Robin condition, the free
//! end as a Neumann condition. For AP loads the tip angle `phi1 = phi(s1)` enters the
//! right-hand side (`m' = f cos(phi + beta - phi1)`), which the FDM handles as a right-end
//! (bordered) dependence solved together with the nodal angles.

use crate::equations::{MomentLaw, Sensitivities, WhiskerFdmProblem};
use crate::error::{ModelError, Result};
use crate::loads::Loads;
use crate::path::shape_path;
use crate::scene::Scene;
use crate::shot::{shoot, Integration};
use crate::solution::{BaseObservables, Elastica, EndState, LoadPath, Solution, SolveStats};
use crate::support::Support;
use crate::whisker::Whisker;
use bvp_solvers::continuation::{BranchGuard, Continuation};
use bvp_solvers::fdm::{BoundaryCondition, FdmOptions, FdmSolution, FdmSolver};
use bvp_solvers::grid::UniformGrid;
use std::f64::consts::FRAC_PI_2;

const METHOD: &str = "fdm";
/// Largest angle change (rad) accepted from a direct solve without continuation.
const DIRECT_JUMP: f64 = 0.5;

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

/// FDM solve for fixed loads. For AP loads the tip angle `phi1 = phi(s1)` in
/// `m' = f cos(phi + beta - phi1)` is the last unknown of the discrete system itself (the
/// problem [depends on the right end](bvp_solvers::fdm::SecondOrderBvp::depends_on_right_end)),
/// so Newton acts on the bordered Jacobian [3.27] plus the column `dF/dphi1` and there is no
/// outer iteration on `phi1`. Returns the solution and its Newton iterations.
fn solve_fixed(
    whisker: &Whisker,
    loads: &Loads,
    grid: &UniformGrid,
    guess: &[f64],
) -> Result<(FdmSolution, usize)> {
    let problem = WhiskerFdmProblem::new(*whisker, *loads, last_or(guess));
    let sol = solver(whisker, loads.s1)
        .solve(&problem, grid, guess)
        .map_err(|source| ModelError::Solver {
            method: METHOD,
            source,
        })?;
    let it = sol.stats.iterations;
    Ok((sol, it))
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn last_or(v: &[f64]) -> f64 {
    v.last().copied().unwrap_or(FRAC_PI_2)
}

/// Grid intervals of `[0, s1]` for `n` intervals per unit length.
pub(crate) fn intervals(n: usize, s1: f64) -> usize {
    ((n as f64) * s1).ceil().max(4.0) as usize
}

/// Solves a scene with the FDM on `ceil(n s1)` intervals of `[0, s1]`, optionally warm-started from nodal angles `guess` on the same grid (e.g. a
/// coarser solution interpolated): the guess is accepted when Newton converges from it
/// within [`DIRECT_JUMP`] of it; otherwise the solve starts from zero load. Returns the
/// solution and its nodal angles.
pub(crate) fn solve_from(
    scene: &Scene,
    n: usize,
    guess: Option<&[f64]>,
) -> Result<(Solution, Vec<f64>)> {
    let w = &scene.whisker;
    let loads = &scene.loads;
    let s1 = loads.s1;
    let grid =
        UniformGrid::new(0.0, s1, intervals(n, s1)).map_err(|source| ModelError::Solver {
            method: METHOD,
            source,
        })?;
    if let Some(g) = guess.filter(|g| g.len() == grid.len()) {
        if let Ok((sol, it)) = solve_fixed(w, loads, &grid, g) {
            if max_diff(&sol.y, g) <= DIRECT_JUMP {
                let out = assemble(scene, &sol, it, 0, n);
                return Ok((out, sol.y));
            }
        }
    }
    let unloaded: Vec<f64> = grid.nodes().iter().map(|&s| w.phi_unloaded(s)).collect();
    let sev = super::shooting::severity(w, loads);
    // A direct solve from the unloaded shape is kept only when it stays in the near-linear
    // regime (max angle change <= DIRECT_JUMP): Newton from far away can land on another
    // branch (e.g. a soft spring base turned past pi), so larger changes are redone by
    // continuation, which follows the branch connected to the unloaded whisker.
    let direct = if sev <= 1.0 {
        solve_fixed(w, loads, &grid, &unloaded)
            .ok()
            .filter(|(sol, _)| max_diff(&sol.y, &unloaded) <= DIRECT_JUMP)
            .filter(|(sol, _)| !past_fold(scene, last_or(&sol.y)))
    } else {
        None
    };
    let (sol, iterations, continuation_steps, jumps, path) = match direct {
        Some((sol, it)) => (sol, it, 0, 0, None),
        None => from_zero(scene, &grid, unloaded, sev)?,
    };
    let mut out = assemble(scene, &sol, iterations, continuation_steps, n);
    out.stats.branch_jumps = jumps;
    out.load_path = path;
    Ok((out, sol.y))
}

/// What [`from_zero`] gives: the solution, its Newton iterations, the continuation steps,
/// the branch jumps and the load path where it decided.
type FromZero = (FdmSolution, usize, usize, usize, Option<LoadPath>);

/// The FDM solution on `grid` reached by loading from zero: load continuation from the
/// unloaded whisker (the one driver of bvp-solvers: secant predictor, jump guard), each
/// corrector a Newton solve on the grid; where that stalled or ended past a fold
/// ([`past_fold`]), the rule every method follows: the load path's first arrival at full
/// load ([`super::load_path::follow`], by accurate shots), sampled on the grid as Newton's
/// start.
fn from_zero(scene: &Scene, grid: &UniformGrid, unloaded: Vec<f64>, sev: f64) -> Result<FromZero> {
    let (w, loads) = (&scene.whisker, &scene.loads);
    let first = (1.0 / sev.ceil()).clamp(1e-3, 1.0);
    let cont = Continuation {
        initial_step: first,
        min_step: 1e-8,
        max_step: (2.0 * first).min(1.0),
    };
    let followed = cont
        .follow(
            0.0,
            1.0,
            unloaded,
            &BranchGuard::default(),
            |lambda, pred: &[f64]| {
                solve_fixed(w, &loads.scaled(lambda), grid, pred).map(|(sol, _)| sol.y)
            },
        )
        .map_err(|e| ModelError::from_continuation(METHOD, e));
    match followed {
        Ok((y, stats)) if !past_fold(scene, last_or(&y)) => {
            if stats.jumps > 0 {
                // the branch guard met other equilibria: a jump it let through would land
                // on one of them unnoticed; shooting by the rule settles the branch
                if let Some((guess, path)) = shooting_start(scene, grid, &y) {
                    let (sol, it) = solve_fixed(w, loads, grid, &guess)?;
                    return Ok((sol, it, stats.steps, stats.jumps, path));
                }
            }
            let (sol, it) = solve_fixed(w, loads, grid, &y)?;
            Ok((sol, it, stats.steps, stats.jumps, None))
        }
        followed => {
            let jumps = followed.as_ref().map_or(0, |(_, s)| s.jumps);
            let Some((guess, path)) = path_start(scene, grid) else {
                // no answer by the rule: the continuation's own error, or its past-fold
                // equilibrium refused
                let (y, _) = followed?;
                return Err(ModelError::FoldedPath {
                    method: METHOD,
                    phi1: last_or(&y),
                });
            };
            let (sol, it) = solve_fixed(w, loads, grid, &guess)?;
            Ok((sol, it, path.steps, jumps, Some(path)))
        }
    }
}

/// Whether the equilibrium with the loaded-end angle `phi1` lies past an odd number of folds
/// of the load path: `dR/dphi1 <= 0` in a shot from there (it is 1 on the unloaded whisker
/// and vanishes only at a fold, [`super::load_path`]). Judged only where the shot resolves
/// the equilibrium, landing within [`SHOT_RESOLVES`] of the base condition (thin tips make
/// the shot so ill-conditioned that the grid's angle misses it by far: no judgement).
fn past_fold(scene: &Scene, phi1: f64) -> bool {
    let (w, loads) = (&scene.whisker, &scene.loads);
    let integration = Integration::adaptive(1e-8);
    match shoot(w, loads, phi1, Sensitivities::TipAngle, &integration) {
        Ok(shot) => {
            let r = w.support.residual(shot.phi0, shot.m0);
            let scale = 1.0 + shot.m0.abs() * w.support.compliance();
            r.abs() <= SHOT_RESOLVES * scale
                && w.support.residual_rate(shot.d_phi1.phi0, shot.d_phi1.m0) <= 0.0
        }
        Err(_) => false,
    }
}

/// The base residual (relative to `1 + |m0|/k`) within which a shot from the grid's angle
/// resolves the grid's equilibrium ([`past_fold`]).
const SHOT_RESOLVES: f64 = 0.1;

/// Where `accurate` shooting by the rule ([`super::accurate::solve_accurate`] at 1e-10,
/// trusted only with an error estimate below 1e-6: thin tips make the shots
/// ill-conditioned) reaches another equilibrium than a continuation on the grid with the
/// nodal angles `y` (some node more than [`BRANCH_APART`] away: two branches may share
/// both end angles, a rigid base's and a tip aligned with a strong force): the nodal angles
/// of the shooting's equilibrium on `grid`, with its load path where that decided. `None`
/// when they agree or shooting has no trusted answer.
fn shooting_start(
    scene: &Scene,
    grid: &UniformGrid,
    y: &[f64],
) -> Option<(Vec<f64>, Option<LoadPath>)> {
    let budget = super::SHOOTING_BUDGET;
    let shooting = super::accurate::Accurate {
        tol: 1e-10,
        check_tol: 1e-11,
        tolerance: 1e-6,
        samples: 16,
        budget,
        search_tol: None,
        loosest_tol: 1e-10,
    };
    let sol = super::accurate::solve_accurate(scene, &shooting).ok()?;
    if sol.stats.error_estimate.is_nan() || sol.stats.error_estimate > 1e-6 {
        return None;
    }
    let angles = angles_on(scene, grid, sol.loaded_end.phi)?;
    let apart = angles
        .iter()
        .zip(y)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    (apart > BRANCH_APART).then_some((angles, sol.load_path))
}

/// Nodal angles farther apart than this are two equilibria, not one resolved on two
/// grids (the FDM's own error on a grid it resolves is far below it).
const BRANCH_APART: f64 = 0.05;

/// The nodal angles on `grid` of the load path's first arrival at full load, by accurate
/// shots at tolerance 1e-10, with the path (`None` where the path cannot be followed).
fn path_start(scene: &Scene, grid: &UniformGrid) -> Option<(Vec<f64>, LoadPath)> {
    let (w, loads) = (&scene.whisker, &scene.loads);
    let integration = Integration::adaptive(1e-10);
    let budget = super::SHOOTING_BUDGET;
    let (path, _) = super::load_path::follow(w, loads, &integration, METHOD, budget).ok()?;
    Some((angles_on(scene, grid, path.arrival.phi1)?, path))
}

/// The nodal angles on `grid` of the shot from the loaded-end angle `phi1` (tolerance 1e-10).
fn angles_on(scene: &Scene, grid: &UniformGrid, phi1: f64) -> Option<Vec<f64>> {
    let shape = shape_path(scene, phi1, 1e-10).ok()?;
    grid.nodes()
        .iter()
        .map(|&s| shape.at(s).map(|p| p.phi))
        .collect()
}

/// The FDM solution on `ceil(n s1)` intervals that starts from the arrival of `path` (the
/// load path another grid's solve followed), carrying that path.
pub(crate) fn solve_on_path(
    scene: &Scene,
    n: usize,
    path: &LoadPath,
) -> Result<(Solution, Vec<f64>)> {
    let (w, loads) = (&scene.whisker, &scene.loads);
    let grid = UniformGrid::new(0.0, loads.s1, intervals(n, loads.s1)).map_err(|source| {
        ModelError::Solver {
            method: METHOD,
            source,
        }
    })?;
    let guess = angles_on(scene, &grid, path.arrival.phi1).ok_or(ModelError::NoConvergence {
        method: METHOD,
        load_scale: 1.0,
        iterations: 0,
        residual: f64::NAN,
    })?;
    let (sol, it) = solve_fixed(w, loads, &grid, &guess)?;
    let mut out = assemble(scene, &sol, it, path.steps, n);
    out.load_path = Some(path.clone());
    Ok((out, sol.y))
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
        let phi_free = |s: f64| w.phi_free(s1, phi1, s);
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
    // The base moment from the moment equation, m(0) = -int_0^s1 m'(s) ds with
    // m' = f sin(phi + beta_eff) + q (s1 - s) sin(phi + alpha), by the trapezoidal rule: second
    // order with an even error expansion (unlike a one-sided difference of phi' at the base),
    // so that Richardson extrapolation applies to MA as well.
    let law = MomentLaw::new(&scene.loads, phi1);
    let dm = |i: usize| {
        let (sp, cp) = sol.y[i].sin_cos();
        law.at(sol.grid.x(i), sp, cp).dm
    };
    let n = sol.grid.len();
    let mut m0 = 0.0;
    for i in 1..n {
        m0 -= 0.5 * h * (dm(i - 1) + dm(i));
    }
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
            method_used: crate::solution::MethodKind::Fdm,
            requested: crate::solution::MethodKind::Fdm,
            ..SolveStats::default()
        },
        load_path: None,
    }
}
