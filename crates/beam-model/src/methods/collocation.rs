//! `collocation`: the elastica [3.25] on `[0, s1]` as a first-order two-point problem solved
//! by [`bvp_solvers::collocation::solve_bvp_problem`] (3-point Lobatto IIIA, residual control
//! with mesh refinement and removal), with its own load continuation from zero: the method
//! that needs no start from another method, for the slender scenes (a tip force on
//! `theta <= 0.02`) where single shooting is ill-conditioned and the FDM's load continuation
//! fails (the tip's boundary layer of width `theta^2 / sqrt(f)` is below any uniform grid's
//! step), so that multiple shooting has no guess either.
//!
//! The state `u = (phi, m, x, y)` obeys [3.25] split into first order
//! ([`state_rate`]):
//!
//! ```text
//! phi' = m / e^4 + A s + B,  m' = f sin(phi + c) + q (s1 - s) sin(phi + alpha),
//! x' = cos phi,  y' = sin phi,
//! ```
//!
//! with the base condition [3.21, 3.22] `phi(0) - pi/2 - m(0)/k = 0`, `x(0) = y(0) = 0` and
//! the free loaded end `m(s1) = 0`; for an AP force the tip angle `phi1` in `c` is an unknown
//! parameter with the condition `phi1 - phi(s1) = 0`. Jacobians are analytic.
//!
//! **Load continuation** (natural parameter, in the load scale `lambda` of
//! [`Loads::scaled`]): from the unloaded whisker (`phi = phi_unloaded`, `m = 0`, exact at
//! `lambda = 0`) each step is warm-started from the previous [`BvpSolution`] on its mesh,
//! solved at the loose residual tolerance [`STEP_TOL`]; a step that fails, or whose nodal
//! angles move by more than [`STEP_JUMP`] (the branch guard: a larger move is a jump to
//! another equilibrium or an under-resolved step), is halved; an accepted one doubles the
//! next. The first step is the whole load where the scene is near-linear (`severity <= 1`,
//! as the FDM's direct solve), else `1 / severity`. The branch is the one connected to the
//! unloaded whisker; a fold of the load path (the tip angle turning back) stops the
//! continuation ([`ModelError::ContinuationFailed`], use `accurate`, which follows folds).
//!
//! **Error estimate**: at full load, a solve at the residual tolerance `r = tolerance` (the
//! accuracy asked for, absolute) and a second one at `r / 100` warm-started from it (its
//! mesh refined further by the residual control); the second is the answer and the
//! difference of the two (tip, loaded end, base observables; [`Solution::difference`]),
//! i.e. the first one's error, is its estimate: with an order-4 scheme and a residual 100
//! times smaller the answer's own error is about a hundredth of it, so the estimate is
//! conservative. Where it exceeds `tolerance` the pair moves down by another factor 100
//! (down to the residual floor [`MIN_RESIDUAL_TOL`]).

use super::shooting::severity;
use super::whisker_problem::WhiskerProblem;
use crate::error::{ModelError, Result};
use crate::loads::LoadKind;
use crate::scene::Scene;
use crate::solution::{MethodKind, Solution, SolveStats};
use bvp_solvers::collocation::{solve_bvp_problem, BvpOptions, BvpSolution};

const METHOD: &str = "collocation";

/// Residual tolerance of the continuation's load steps (below full load).
pub const STEP_TOL: f64 = 1e-4;

/// Largest change of a nodal angle (rad) accepted in one load step (the branch guard).
pub const STEP_JUMP: f64 = 0.5;

/// Smallest load step before the continuation gives up.
pub const MIN_STEP: f64 = 1e-7;

/// Smallest residual tolerance of the final solves: below it the residual measure of the
/// thin tip meets rounding and the mesh grows without bound (measured: a relative residual
/// stuck at 2e-7 on 275,000 nodes at `1e-11`).
pub const MIN_RESIDUAL_TOL: f64 = 1e-10;

/// The first of the final pair of solves runs at this multiple of the accuracy asked for
/// (measured on moderate and slender scenes: the difference of the pair, the estimate, is
/// about `1.4e-2` times the first one's residual tolerance, so it lands near `0.4 tol`).
pub const RESIDUAL_PER_ERROR: f64 = 30.0;

/// Largest mesh of one final solve.
pub const MAX_NODES: usize = 100_000;

/// Largest mesh of one load step of the continuation (at [`STEP_TOL`] the slender DP cases
/// need a few thousand nodes; an AP force on `theta <= 0.02` curls the tip into a spiral
/// that needs more than 50,000 and is given up early).
pub const MAX_STEP_NODES: usize = 20_000;

/// Largest number of collocation solves of one continuation (accepted and rejected steps):
/// bounds the time of a hopeless case (an AP force on `theta <= 0.02` curls the thin tip
/// into a spiral that no mesh below [`MAX_NODES`] resolves) to seconds.
pub const MAX_ATTEMPTS: usize = 40;

/// Nodes of the uniform starting mesh on `[0, s1]`.
const START_NODES: usize = 21;

/// A mesh with its nodal states and parameters: a warm start.
#[derive(Clone)]
struct Start {
    x: Vec<f64>,
    y: Vec<Vec<f64>>,
    p: Vec<f64>,
}

impl From<&BvpSolution> for Start {
    fn from(s: &BvpSolution) -> Self {
        Start {
            x: s.x.clone(),
            y: s.y.clone(),
            p: s.p.clone(),
        }
    }
}

/// The unloaded whisker on a uniform mesh (`phi = phi_unloaded`, `m = 0`, `(x, y)` by the
/// trapezoidal rule): the exact solution at load scale 0 up to the quadrature of `(x, y)`.
fn unloaded(scene: &Scene, ap: bool) -> Start {
    let w = &scene.whisker;
    let s1 = scene.loads.s1;
    let x: Vec<f64> = (0..START_NODES)
        .map(|i| s1 * i as f64 / (START_NODES - 1) as f64)
        .collect();
    let mut y = Vec::with_capacity(START_NODES);
    let (mut px, mut py) = (0.0, 0.0);
    for (i, &s) in x.iter().enumerate() {
        let phi = w.phi_unloaded(s);
        if i > 0 {
            let (h, prev) = (s - x[i - 1], w.phi_unloaded(x[i - 1]));
            px += 0.5 * h * (prev.cos() + phi.cos());
            py += 0.5 * h * (prev.sin() + phi.sin());
        }
        y.push(vec![phi, 0.0, px, py]);
    }
    let p = if ap { vec![w.phi_unloaded(s1)] } else { vec![] };
    Start { x, y, p }
}

/// Work of a solve: right-hand-side plus Jacobian evaluations.
fn work(s: &BvpSolution) -> usize {
    s.stats.rhs_evaluations + s.stats.jacobian_evaluations
}

fn solve_at(
    scene: &Scene,
    lambda: f64,
    start: &Start,
    tol: f64,
    max_nodes: usize,
) -> Result<BvpSolution> {
    let prob = WhiskerProblem::new(scene, lambda);
    debug_assert_eq!(start.p.len(), prob.k());
    let opts = BvpOptions {
        tol,
        max_nodes: max_nodes.max(start.x.len()),
        ..BvpOptions::default()
    };
    solve_bvp_problem(&prob, &start.x, &start.y, &start.p, &opts).map_err(|source| {
        ModelError::Solver {
            method: METHOD,
            source,
        }
    })
}

/// The branch guard's distance between two solutions: the largest change of the angle on
/// the stiffer half `[0, s1/2]` (over the nodes of `b`) and of the loaded end's position.
/// The thin tip's angle is left out: under a tip force it swings towards the force within
/// a boundary layer of width `theta^2 / sqrt(f)` at loads as small as `1e-4` of the scene's
/// (linear theory: a rotation of about `f / (2 theta^2)` per unit load), continuously but
/// far faster than any guard on it would let the continuation move.
fn angle_jump(a: &BvpSolution, b: &BvpSolution) -> f64 {
    let half = 0.5 * b.x.last().copied().unwrap_or(0.0);
    let shape =
        b.x.iter()
            .zip(&b.y)
            .take_while(|(&s, _)| s <= half)
            .map(|(&s, u)| (a.eval(s)[0] - u[0]).abs())
            .fold(0.0, f64::max);
    let (ea, eb) = (a.y.last(), b.y.last());
    match (ea, eb) {
        (Some(ea), Some(eb)) => shape.max((ea[2] - eb[2]).abs()).max((ea[3] - eb[3]).abs()),
        _ => f64::NAN,
    }
}

/// The solution at full load reached by continuation from the unloaded whisker (module
/// docs), at residual tolerance [`STEP_TOL`]; with the accepted steps and the work spent.
fn continuation(scene: &Scene) -> Result<(BvpSolution, usize, usize)> {
    let ap = scene.loads.tip.kind == LoadKind::Ap && scene.loads.tip.f != 0.0;
    let start = unloaded(scene, ap);
    let mut current = solve_at(scene, 0.0, &start, STEP_TOL, MAX_STEP_NODES)?;
    let mut spent = work(&current);
    let sev = severity(&scene.whisker, &scene.loads);
    let mut lambda = 0.0;
    let mut step = if sev <= 1.0 { 1.0 } else { 1.0 / sev };
    let mut steps = 0;
    let mut last_err: Option<ModelError> = None;
    let mut attempts = 0;
    while lambda < 1.0 {
        step = step.min(1.0 - lambda);
        attempts += 1;
        if step < MIN_STEP || attempts > MAX_ATTEMPTS {
            return Err(ModelError::ContinuationFailed {
                method: METHOD,
                load_scale: lambda,
                step,
                cause: Box::new(last_err.unwrap_or(ModelError::BranchJump {
                    method: METHOD,
                    load_scale: lambda,
                    distance: f64::NAN,
                    allowed: STEP_JUMP,
                })),
            });
        }
        let next = lambda + step;
        let tried = solve_at(
            scene,
            next,
            &Start::from(&current),
            STEP_TOL,
            MAX_STEP_NODES,
        );
        match tried {
            Ok(sol) => {
                spent += work(&sol);
                let jump = angle_jump(&current, &sol);
                if jump <= STEP_JUMP {
                    current = sol;
                    lambda = next;
                    steps += 1;
                    step *= 2.0;
                    continue;
                }
                last_err = Some(ModelError::BranchJump {
                    method: METHOD,
                    load_scale: next,
                    distance: jump,
                    allowed: STEP_JUMP,
                });
            }
            Err(e) => last_err = Some(e),
        }
        step *= 0.5;
    }
    Ok((current, steps, spent))
}

/// Solves `scene` (normalised) by collocation with load continuation: the answer's
/// estimate (module docs) is checked by the caller against `tolerance`; `samples` output
/// intervals along the whisker.
///
/// # Errors
/// [`ModelError::ContinuationFailed`] where no load step reaches full load;
/// [`ModelError::Solver`] for a failed final solve.
pub(crate) fn solve(scene: &Scene, tolerance: f64, samples: usize) -> Result<Solution> {
    let (reached, steps, mut spent) = continuation(scene)?;
    let mut r = (RESIDUAL_PER_ERROR * tolerance).clamp(100.0 * MIN_RESIDUAL_TOL, STEP_TOL);
    let mut coarse = solve_at(scene, 1.0, &Start::from(&reached), r, MAX_NODES)?;
    spent += work(&coarse);
    loop {
        let r_fine = (r * 1e-2).max(MIN_RESIDUAL_TOL);
        let fine = solve_at(scene, 1.0, &Start::from(&coarse), r_fine, MAX_NODES)?;
        spent += work(&fine);
        let stats = SolveStats {
            iterations: fine.stats.newton_iterations,
            residual: fine.max_bc_residual,
            continuation_steps: steps,
            evaluations: spent,
            method_used: MethodKind::Collocation,
            requested: MethodKind::Collocation,
            ..SolveStats::default()
        };
        let a = assemble(scene, &coarse, r, samples, SolveStats::default())?;
        let mut sol = assemble(scene, &fine, r_fine, samples, stats)?;
        let diff = sol.difference(&a);
        sol.stats.error_estimate = if diff.is_nan() {
            f64::NAN
        } else {
            diff.max(fine.max_bc_residual)
        };
        if sol.stats.error_estimate <= tolerance || r_fine <= MIN_RESIDUAL_TOL {
            return Ok(sol);
        }
        r = r_fine;
        coarse = fine;
    }
}

/// The solution from a collocation answer ([`super::global::assemble_dense`] on its nodes
/// and its dense output; the load-free segment at no less than `MIN_TOL`).
fn assemble(
    scene: &Scene,
    bs: &BvpSolution,
    tol: f64,
    samples: usize,
    stats: SolveStats,
) -> Result<Solution> {
    let last = bs.y.last().cloned().unwrap_or_default();
    let eval = |s: f64| bs.eval(s);
    let tol = tol.max(super::MIN_TOL);
    super::global::assemble_dense(
        scene,
        (&bs.y[0], &last),
        &eval,
        (tol, samples),
        stats,
        METHOD,
    )
}

#[cfg(test)]
mod tests {
    use super::super::test_scenes::{against_accurate, moderate, slender_against_fdm_richardson};
    use crate::{solve, Loads, Method, Scene, TipForce, Whisker};

    fn colloc(tol: f64) -> Method {
        Method::Collocation { tol, samples: 100 }
    }

    /// On moderate whiskers (DP and AP forces, flows, spring and rigid bases,
    /// pre-curvature, a partly loaded whisker) the method agrees with `accurate` (single
    /// shooting, an independent discretisation, estimate <= 1e-8) within its own estimate.
    #[test]
    fn agrees_with_single_shooting_where_that_works() {
        let mut partial = Loads::tip(TipForce::dp(2.0, 0.3));
        partial.s1 = 0.7;
        let mut scenes = moderate();
        scenes.push(Scene::new(Whisker::new(0.4, 1.0, 0.5, 30.0), partial));
        for tol in [1e-6, 1e-9] {
            for (i, scene) in scenes.iter().enumerate() {
                let (c, acc, d) = against_accurate(scene, &colloc(tol))
                    .unwrap_or_else(|e| panic!("scene {i}: {e}"));
                println!(
                    "tol {tol:e} scene {i}: error {d:.1e}, estimate {:.1e}, {} evaluations, {} steps",
                    c.stats.error_estimate, c.stats.evaluations, c.stats.continuation_steps
                );
                assert!(c.stats.error_estimate <= tol, "scene {i}");
                assert!(
                    d <= c.stats.error_estimate + acc.stats.error_estimate + 1e-12,
                    "scene {i}: error {d:e} above the estimates {:e} + {:e}",
                    c.stats.error_estimate,
                    acc.stats.error_estimate
                );
            }
        }
    }

    /// A slender scene `accurate`'s shooting refuses (theta = 0.01, rigid, f = 5), reached
    /// by the method's own continuation from zero load: within its estimate of FDM + two
    /// Richardson levels on 3200..12800 intervals (an independent discretisation).
    #[test]
    fn slender_scene_under_a_tip_force_needs_no_start() {
        let (c, r, d) = slender_against_fdm_richardson(&colloc(1e-8));
        println!(
            "theta 0.01 f 5: estimate {:.1e}, difference from fdm-richardson {d:.1e} (its estimate {:.1e}), {} evaluations, {} steps",
            c.stats.error_estimate, r.stats.error_estimate, c.stats.evaluations, c.stats.continuation_steps
        );
        assert!(c.stats.error_estimate <= 1e-8);
        assert!(d <= 1e-8 + r.stats.error_estimate, "{d:e}");
    }

    /// The CLI's name and the accuracy's range: `collocation` with the default accuracy
    /// 1e-8, refused outside `[1e-12, 1e-2]` with the culprit named.
    #[test]
    fn name_and_tolerance() {
        let m = Method::from_name("collocation", Some(50)).unwrap();
        assert_eq!(m, colloc_n(1e-8, 50));
        assert_eq!(m.name(), "collocation");
        assert_eq!(m.tolerance(), 1e-8);
        let scene = Scene::new(Whisker::uniform(), Loads::tip(TipForce::dp(1.0, 0.0)));
        let e = solve(&scene, &colloc(1e-13)).unwrap_err().to_string();
        assert!(e.contains("tol"), "{e}");
    }

    fn colloc_n(tol: f64, samples: usize) -> Method {
        Method::Collocation { tol, samples }
    }
}
