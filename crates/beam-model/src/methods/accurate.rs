//! `accurate`: the equilibrium branch found by shooting at loose tolerances, then the answer
//! at the asked tolerance from one dense shot, and its error estimate from a second
//! integration at a tighter tolerance.
//!
//! Each stage is a Newton iteration on the tip angle `phi1` (the base condition
//! [3.21, 3.22], exact derivatives from the variational equations) started from the
//! previous stage's answer, on a tighter integration:
//!
//! 1. the branch search ([`find_branch`]: the direct solve from linear theory, or load
//!    continuation) on DOP853 at [`GUIDE_TOL`]: it decides the branch;
//! 2. Newton at [`SEARCH_TOL`] from there ([`TipTarget::SEARCH`]): `phi1` within the
//!    search integration's error of the root (~1e-8);
//! 3. one dense shot at `tol` with the tip-angle sensitivities, moved by its own Newton step
//!    `d = -R / R'` to its root ([`linearised_shape`]: the base values, the loaded end and
//!    the elastica along their sensitivities, an error `O(d^2)`); the returned solution;
//! 4. the check shot at `check_tol` at that root, moved to its own root by one Newton step
//!    with the dense shot's derivative: the second solution. The error estimate is the
//!    largest difference of the two (base values, loaded end, tip angle; as the former
//!    scheme's, [`corrected_difference`]).
//!
//! Where stage 3 does not come within [`root_step`] of its root in [`ROOT_SHOTS`] shots,
//! the former scheme answers: Newton at `tol` from stage 2, the elastica shot at its root,
//! the check shot there.

use super::elastica::Run;
use super::elastica::{linearised_shape, Linearised};
use super::load_path::{find_branch_by_rule, Polish};
use super::shooting::{
    corrected_difference, finished, polish_tip_angle, Search, TipSolve, TipTarget,
};
use crate::equations::Sensitivities;
use crate::error::Result;
use crate::scene::Scene;
use crate::shot::{shoot, Integration};
use crate::solution::{MethodKind, Solution, SolveStats};

/// The guiding tolerance of the branch search: the load steps only guide the branch (to
/// within far less than the jump guard's 0.2 rad).
pub(crate) const GUIDE_TOL: f64 = 1e-3;

/// The search tolerance of stage 2: it puts `phi1` within ~1e-8 of the root at `tol`, so
/// that stage 3's Newton step is small enough to be taken linearised.
pub(crate) const SEARCH_TOL: f64 = 1e-7;

/// Most dense shots (Newton steps at the tolerance) before the former scheme answers.
pub(crate) const ROOT_SHOTS: usize = 3;

/// The largest Newton step (rad) of the dense shot at `tol` whose linearisation is taken:
/// `0.1 sqrt(tol)`, so that its error `|V''| d^2 / 2` stays below the tolerance for base
/// values with `|V''| <= 200` (the search lands within ~1e-8 of the root: s18, whose
/// `m0'' ~ 2500`, sees `d = 2.4e-9`).
pub(crate) fn root_step(tol: f64) -> f64 {
    0.1 * tol.sqrt()
}

/// `accurate` (module docs): DOP853 shooting at `tol` with the error estimate from a second
/// integration at `check_tol`; the continuation stops with
/// [`ModelError::Budget`](crate::ModelError) after `budget` right-hand-side evaluations.
pub(crate) fn solve_accurate(
    scene: &Scene,
    tol: f64,
    check_tol: f64,
    samples: usize,
    budget: usize,
) -> Result<Solution> {
    let w = &scene.whisker;
    let loads = &scene.loads;
    let integration = Integration::adaptive(tol);
    let check = Integration::adaptive(check_tol);
    let search_integration = Integration::adaptive(SEARCH_TOL.max(tol));
    let guide_integration = Integration::adaptive(GUIDE_TOL.max(tol));
    let search = Search {
        direct: &guide_integration,
        direct_target: TipTarget::GUIDE_LOOSE,
        guide: &guide_integration,
        guide_target: TipTarget::GUIDE_LOOSE,
    };
    let polish = Polish {
        integration: &search_integration,
        target: TipTarget::SEARCH,
        direct_too: true,
    };
    let (found, path) =
        find_branch_by_rule(w, loads, &search, &polish, &integration, "accurate", budget)?;
    let stats = SolveStats {
        method_used: MethodKind::Accurate,
        iterations: found.tip.iterations,
        continuation_steps: found.steps,
        evaluations: found.tip.evaluations,
        branch_jumps: found.tip.branch_jumps,
        ..SolveStats::default()
    };
    let run = Run {
        integration: &integration,
        samples,
        method: "accurate",
        budget,
    };
    let spent = match refine(scene, &found.tip, &run, &check, stats)? {
        Ok(mut sol) => {
            sol.load_path = path;
            return Ok(sol);
        }
        Err(spent) => spent,
    };
    // Newton at `tol` from the search's answer, the elastica at its root and the second
    // solution from the check shot there
    let mut tip = polish_tip_angle(
        w,
        loads,
        &integration,
        "accurate",
        found.tip.phi1,
        &TipTarget::POLISH,
    )
    .0?;
    tip.evaluations += found.tip.evaluations + spent;
    tip.branch_jumps = found.tip.branch_jumps;
    let (mut sol, sens) = finished(scene, &run, &tip, found.steps, stats)?;
    let shot = shoot(w, loads, sol.loaded_end.phi, Sensitivities::None, &check)?;
    sol.stats.evaluations += shot.evaluations;
    let r = w.support.residual(shot.phi0, shot.m0);
    let dr = w.support.residual_rate(sens.phi0, sens.m0);
    let d = if dr.is_finite() && dr != 0.0 {
        -r / dr
    } else {
        f64::INFINITY
    };
    sol.stats.error_estimate = corrected_difference(&shot, sens, d, &sol, loads);
    sol.load_path = path;
    Ok(sol)
}

/// Steps 1 and 2 of the module docs from the search's answer `tip`: the solution with its
/// error estimate, or (`Err`) the evaluations spent when the dense shots' Newton steps do
/// not come within [`root_step`] of their root.
fn refine(
    scene: &Scene,
    tip: &TipSolve,
    run: &Run<'_>,
    check: &Integration,
    mut stats: SolveStats,
) -> Result<std::result::Result<Solution, usize>> {
    let w = &scene.whisker;
    let support = &w.support;
    let loads = &scene.loads;
    let Integration::Dop853(d853) = run.integration else {
        return Ok(Err(0));
    };
    let bound = root_step(d853.rtol);
    let mut phi1 = tip.phi1;
    let mut spent = 0;
    for _ in 0..ROOT_SHOTS {
        stats.iterations += 1;
        match linearised_shape(scene, phi1, run, stats, bound)? {
            Linearised::Root { mut sol, sens } => {
                // the second solution: the check integration at the root, moved to its own
                // root by one Newton step with the dense shot's derivative
                let shot = shoot(w, loads, sol.loaded_end.phi, Sensitivities::None, check)?;
                sol.stats.evaluations += shot.evaluations;
                let r = support.residual(shot.phi0, shot.m0);
                let dr = support.residual_rate(sens.phi0, sens.m0);
                let d = if dr.is_finite() && dr != 0.0 {
                    -r / dr
                } else {
                    f64::INFINITY
                };
                sol.stats.error_estimate = corrected_difference(&shot, sens, d, &sol, loads);
                sol.stats.residual = support.residual(sol.base.phi0, -sol.base.ma).abs();
                return Ok(Ok(*sol));
            }
            Linearised::Far { d, evaluations } => {
                spent += evaluations;
                stats.evaluations += evaluations;
                if !d.is_finite() {
                    break;
                }
                phi1 += d;
            }
        }
    }
    Ok(Err(spent))
}
