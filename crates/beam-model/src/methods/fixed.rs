//! Method `rk4` (and any shooting at a fixed integrator): the tip angle by the branch
//! search under the fold rule ([`find_branch_by_rule`]), Newton at the method's integrator,
//! then the elastica from the final shot ([`finished`]).

use super::elastica::Run;
use super::load_path::{find_branch_by_rule, Polish};
use super::shooting::{finished, loose, Search, TipSolve, TipTarget};
use crate::error::Result;
use crate::loads::Loads;
use crate::scene::Scene;
use crate::shot::{BaseValues, Integration};
use crate::solution::{LoadPath, Solution, SolveStats};
use crate::whisker::Whisker;

/// [`find_branch_by_rule`] with the direct attempt at `integration` and the continuation's
/// correctors on [`loose`], then (after a continuation) Newton at `integration` from its
/// answer; returns the tip angle, the continuation steps and the load path where it
/// decided.
pub(crate) fn solve_tip_angle_within(
    whisker: &Whisker,
    loads: &Loads,
    integration: &Integration,
    method: &'static str,
    budget: usize,
) -> Result<(TipSolve, usize, Option<LoadPath>)> {
    let loose = loose(integration);
    let search = Search {
        direct: integration,
        direct_target: TipTarget::FINAL,
        guide: &loose,
        step_target: TipTarget::GUIDE,
        guide_target: TipTarget::GUIDE,
    };
    let polish = Polish {
        integration,
        target: TipTarget::POLISH,
        direct_too: false,
    };
    let (found, path) = find_branch_by_rule(
        whisker,
        loads,
        &search,
        &polish,
        integration,
        method,
        budget,
    )?;
    Ok((found.tip, found.steps, path))
}

/// Solves a scene by shooting and samples the elastica; the continuation stops with
/// [`ModelError::Budget`] after `budget` right-hand-side evaluations. `stats.residual` is
/// the base residual [3.21, 3.22] of the returned (final) shot.
pub(crate) fn solve(
    scene: &Scene,
    integration: &Integration,
    samples: usize,
    method: &'static str,
    budget: usize,
) -> Result<Solution> {
    let run = Run {
        integration,
        samples,
        method,
        budget,
    };
    verified(scene, &run, SolveStats::default()).map(|(sol, _)| sol)
}

/// The tip angle by Newton (with load continuation as needed), then [`finished`].
fn verified(scene: &Scene, run: &Run<'_>, stats: SolveStats) -> Result<(Solution, BaseValues)> {
    let (tip, continuation_steps, path) = solve_tip_angle_within(
        &scene.whisker,
        &scene.loads,
        run.integration,
        run.method,
        run.budget,
    )?;
    let (mut sol, sens) = finished(scene, run, &tip, continuation_steps, stats)?;
    sol.load_path = path;
    Ok((sol, sens))
}
