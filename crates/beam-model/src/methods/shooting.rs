//! Shooting from the loaded end (methods `rk4` and `accurate`): a scalar Newton iteration on
//! the tip angle `phi1` with the exact derivative from the variational equations, load
//! continuation when the direct iteration fails, then the elastica from the final shot.

use super::elastica::{moved, shape, Run};
use crate::equations::Sensitivities;
use crate::error::{ModelError, Result};
use crate::loads::Loads;
use crate::scene::Scene;
use crate::shot::{shoot, BaseValues, Integration, StartStep};
use crate::solution::{Solution, SolveStats};
use crate::whisker::Whisker;
use bvp_solvers::continuation::{BranchGuard, Continuation};
use bvp_solvers::newton::{
    JacobianUpdate, NewtonPolicy, Safeguards, SmallStep, Stall, Termination,
};
use bvp_solvers::shooting::{solve_shooting, ShotProblem};
use std::cell::Cell;
use std::f64::consts::FRAC_PI_2;

/// Converged tip angle with its shot.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TipSolve {
    pub phi1: f64,
    pub iterations: usize,
    pub residual: f64,
    pub evaluations: usize,
    /// `(phi0, m0, dx, dy)` at `phi1` from the Newton shots (linearly extrapolated from the
    /// last shot when Newton's last step was not shot).
    pub values: BaseValues,
    /// Their derivatives with respect to `phi1` (from the last shot with sensitivities).
    pub sens: BaseValues,
    /// Continuation steps rejected as branch jumps.
    pub branch_jumps: usize,
    /// The Newton step from the last shot's angle to `phi1` when that step was not shot
    /// (`values` are the last shot's moved along it), else 0.
    pub step: f64,
    /// The last shot's natural first step: the next shots of the solve start with it.
    pub start: Option<StartStep>,
}

const MAX_NEWTON: usize = 40;
/// Newton iterations without halving the smallest residual after which the iteration fails
/// ([`Stall::patience`]).
const STALL: usize = 2;
/// The largest tip rotation (rad) the continuation's first step predicts by linear theory.
const LINEAR_STEP: f64 = 0.25;
const MAX_STEP: f64 = 0.5;
/// The base residual (relative to `1 + |m0|/k`) above which the final shot sends the tip
/// angle back to Newton: the plain 4-component shot at tolerance 1e-12 carries a noise of a
/// few 1e-12 in its base values (measured: 2e-12 on s18 where the 8-component Newton shot
/// at the same angle gives 8.5e-15), so a tighter bound re-solves a converged angle.
pub(crate) const VERIFY_TOL: f64 = 1e-11;

/// Newton on `R(phi1) = phi(0) - pi/2 - m(0)/k` [3.21, 3.22] from `guess`; with the
/// right-hand-side evaluations spent, failed or not.
pub(crate) fn newton_tip_angle(
    whisker: &Whisker,
    loads: &Loads,
    integration: &Integration,
    guess: f64,
    method: &'static str,
) -> (Result<TipSolve>, usize) {
    let problem = TipProblem::new(whisker, loads, integration, method);
    let t = newton_to(&problem, guess, &TipTarget::FINAL);
    (t, problem.spent.get())
}

/// The tip-angle equation of a scene: the whisker, its loads and the shots' integrator
/// (`method` names it in errors), as a [`ShotProblem`] in `phi1`: the residual
/// `R(phi1) = phi(0) - pi/2 - m(0)/k` [3.21, 3.22] relative to `1 + |m0|/k`, its derivative
/// from the shot's variational equations.
struct TipProblem<'a> {
    whisker: &'a Whisker,
    loads: &'a Loads,
    integration: &'a Integration,
    method: &'static str,
    /// Right-hand-side evaluations spent by every shot, also of a failed iteration.
    spent: Cell<usize>,
    /// `d(phi0, m0, dx, dy)/dphi1` of the last shot with sensitivities.
    sens: Cell<BaseValues>,
    /// The error of a shot that failed (the iteration stops there).
    error: Cell<Option<ModelError>>,
    /// The last shot's natural first step: each shot starts with it
    /// ([`Integration::started`]).
    start: Cell<Option<StartStep>>,
}

impl<'a> TipProblem<'a> {
    fn new(
        whisker: &'a Whisker,
        loads: &'a Loads,
        integration: &'a Integration,
        method: &'static str,
    ) -> Self {
        TipProblem {
            whisker,
            loads,
            integration,
            method,
            spent: Cell::new(0),
            sens: Cell::new(BaseValues::default()),
            error: Cell::new(None),
            start: Cell::new(None),
        }
    }

    /// The problem with its shots starting with `start`.
    fn starting(self, start: Option<StartStep>) -> Self {
        self.start.set(start);
        self
    }
}

/// What a tip-angle shot reaches: the base values, with `d/dphi1` if it integrated them.
#[derive(Clone, Copy, Debug)]
struct TipEnd {
    values: BaseValues,
    d_phi1: Option<BaseValues>,
}

impl ShotProblem<1> for TipProblem<'_> {
    type End = TipEnd;
    /// The shot's error is kept in [`TipProblem::error`].
    type Error = ();

    /// One shot from the loaded end at `phi1 = p[0]`, with the tip-angle sensitivities (the
    /// variational equations) when asked for.
    fn shoot(&self, p: &[f64; 1], sensitivities: bool) -> std::result::Result<TipEnd, ()> {
        let sens = if sensitivities {
            Sensitivities::TipAngle
        } else {
            Sensitivities::None
        };
        let integration = self.integration.started(self.start.get());
        match shoot(self.whisker, self.loads, p[0], sens, &integration) {
            Ok(shot) => {
                self.spent.set(self.spent.get() + shot.evaluations);
                if shot.start.is_some() {
                    self.start.set(shot.start);
                }
                if sensitivities {
                    self.sens.set(shot.d_phi1);
                }
                Ok(TipEnd {
                    values: shot.values(),
                    d_phi1: sensitivities.then_some(shot.d_phi1),
                })
            }
            Err(e) => {
                self.error.set(Some(e));
                Err(())
            }
        }
    }

    /// The base condition `phi(0) - pi/2 - m(0)/k` [3.21, 3.22].
    fn residual(&self, _p: &[f64; 1], end: &TipEnd) -> [f64; 1] {
        [self
            .whisker
            .support
            .residual(end.values.phi0, end.values.m0)]
    }

    fn residual_jacobian(&self, _p: &[f64; 1], end: &TipEnd) -> Option<[[f64; 1]; 1]> {
        let support = &self.whisker.support;
        end.d_phi1.map(|d| [[support.residual_rate(d.phi0, d.m0)]])
    }

    fn scale(&self, end: &TipEnd) -> f64 {
        1.0 + end.values.m0.abs() * self.whisker.support.compliance()
    }
}

/// How far [`newton_to`] iterates.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TipTarget {
    /// Residual tolerance, relative to `1 + |m0|/k`.
    tol: f64,
    /// Return the step that follows a residual below this bound unshot (quadratic
    /// convergence puts the next residual near its square; the caller's next shot verifies
    /// it).
    predict_below: Option<f64>,
    /// The load scale reported with a failure.
    load_scale: f64,
}

impl TipTarget {
    /// The final solve at full load.
    pub(crate) const FINAL: TipTarget = TipTarget {
        tol: 1e-13,
        predict_below: None,
        load_scale: 1.0,
    };

    /// The final solve at full load after a continuation: the step after a residual of 1e-7
    /// is returned unshot (the elastica's shot verifies it).
    pub(crate) const POLISH: TipTarget = TipTarget {
        predict_below: Some(1e-7),
        ..TipTarget::FINAL
    };

    /// A continuation corrector: residual 1e-5, every shot verified (the load steps only
    /// guide the branch; the final Newton at full load restores the accuracy).
    pub(crate) const GUIDE: TipTarget = TipTarget {
        tol: 1e-5,
        predict_below: None,
        load_scale: 1.0,
    };

    /// A corrector of a load step of `accurate`'s branch search, on DOP853 at its guiding
    /// tolerance (1e-3): residual 1e-4, or the Newton step from a residual of 1e-2 returned
    /// unshot (its residual near 1e-4: the steps only guide the branch, to within far less
    /// than the jump guard's 0.2 rad).
    pub(crate) const GUIDE_LOOSE: TipTarget = TipTarget {
        tol: 1e-4,
        predict_below: Some(1e-2),
        load_scale: 1.0,
    };

    /// A corrector of a load step below full load of `accurate`'s branch search: as
    /// [`TipTarget::GUIDE_LOOSE`], but the Newton step from a residual of 0.2 is returned
    /// unshot (quadratic convergence puts it within a few 1e-2 rad of the equilibrium, far
    /// inside the jump guard's 0.2 rad; the next step's prediction only needs the branch).
    /// Measured: 3-7 % fewer instructions on the reference scenes and s18.
    pub(crate) const GUIDE_STEP: TipTarget = TipTarget {
        predict_below: Some(0.2),
        ..TipTarget::GUIDE_LOOSE
    };

    /// The Newton solve at the search tolerance that starts `accurate`'s answer: residual
    /// 1e-8, or the Newton step from a residual of 1e-4 returned unshot (quadratic
    /// convergence lands it near 1e-8, within the search integration's own error).
    pub(crate) const SEARCH: TipTarget = TipTarget {
        tol: 1e-8,
        predict_below: Some(1e-4),
        load_scale: 1.0,
    };

    /// Newton's policy: at most [`MAX_NEWTON`] shots, each with its derivative, full steps.
    fn policy(&self) -> NewtonPolicy {
        NewtonPolicy {
            tol: self.tol,
            max_iter: MAX_NEWTON - 1,
            halvings: 0,
            update: JacobianUpdate::Reevaluate { keep_below: 0.0 },
            jacobian_at_solution: false,
            noise_floor: 0.0,
        }
    }

    /// The safeguards: steps of at most [`MAX_STEP`]; failure once the best residual has not
    /// halved [`STALL`] times running (cycling, diverging or crawling along limited steps
    /// from a bad prediction: a continuation then shortens its load step), unless the
    /// residual is at the rounding floor 1e-9; a step below 4 ulp of the angle has converged
    /// to rounding (one more shot, without sensitivities, accepts it within 1e-9); with
    /// `predict_below`, the step after a residual below it is returned unshot.
    fn guards(&self) -> Safeguards {
        Safeguards {
            max_step: MAX_STEP,
            stall: Some(Stall {
                factor: 0.5,
                patience: STALL,
                floor: 1e-9,
            }),
            small_step: Some(SmallStep {
                rel: 4.0 * f64::EPSILON,
                shift: 0.0,
                floor: 1.0,
                check: Some(1e-9),
            }),
            predict_below: self.predict_below,
        }
    }
}

/// Newton on the tip angle of `problem` from `guess` to `target`: generic shooting with the
/// exact sensitivity ([`bvp_solvers::shooting::solve_shooting`]) under [`TipTarget::policy`]
/// and [`TipTarget::guards`].
fn newton_to(problem: &TipProblem<'_>, guess: f64, target: &TipTarget) -> Result<TipSolve> {
    let spent = problem.spent.get();
    let out = solve_shooting(problem, [guess], &target.policy(), &target.guards());
    if let Some(e) = problem.error.take() {
        return Err(e);
    }
    let fail = |iterations, residual| ModelError::NoConvergence {
        method: problem.method,
        load_scale: target.load_scale,
        iterations,
        residual,
    };
    let Ok(ans) = out else {
        return Err(fail(0, f64::NAN));
    };
    let sens = problem.sens.get();
    let mut t = TipSolve {
        phi1: ans.u[0],
        iterations: ans.iterations,
        residual: ans.norm,
        evaluations: problem.spent.get() - spent,
        values: ans.point.values,
        sens,
        branch_jumps: 0,
        step: 0.0,
        start: problem.start.get(),
    };
    match ans.termination {
        Termination::Converged => Ok(t),
        Termination::Predicted => {
            // the base values moved along the step by their sensitivities
            t.step = ans.step[0];
            t.values = moved(t.values, sens, t.step);
            t.residual = f64::NAN;
            Ok(t)
        }
        // the rounding shot's residual, after the step it checked
        Termination::NoDescent => Err(fail(ans.iterations, ans.norm)),
        // at the iterate's own shot
        _ => Err(fail(ans.iterations + 1, ans.norm)),
    }
}

/// A rough measure of how non-linear a load case is: the linear-theory tip rotation
/// `f/2 + q/6`, amplified for thin tips (the curvature near a tapered tip grows like
/// `1/(16 theta^2)`).
pub(crate) fn severity(whisker: &Whisker, loads: &Loads) -> f64 {
    let rot = loads.tip.f / 2.0 + loads.fluid.q / 6.0;
    let taper = (1.0 / (16.0 * whisker.theta * whisker.theta)).max(1.0);
    rot * taper
}

/// How the branch search of [`find_branch`] runs: the integrator and target of the direct
/// attempt, and those of the continuation's correctors (`guide`; `step_target` below full
/// load, `guide_target` at it; the target's load scale is set per step).
pub(crate) struct Search<'a> {
    pub direct: &'a Integration,
    pub direct_target: TipTarget,
    pub guide: &'a Integration,
    pub step_target: TipTarget,
    pub guide_target: TipTarget,
}

/// The tip angle reached by [`find_branch`]: at the search's integrator and target.
pub(crate) struct Found {
    /// The last solve (its `evaluations` count every attempt of the search).
    pub tip: TipSolve,
    /// Accepted continuation steps (0: the direct solve answered).
    pub steps: usize,
}

/// The loose integrator of a continuation's load steps: DOP853 at `max(tol, 1e-6)`, RK4 as
/// given.
pub(crate) fn loose(integration: &Integration) -> Integration {
    match integration {
        Integration::Dop853(d) => Integration::adaptive(d.rtol.max(1e-6)),
        other => other.clone(),
    }
}

/// Newton on the tip angle, on the branch connected to the unloaded whisker: a direct solve
/// from the linear-theory tip angle ([`crate::linear`]) for mild loads, otherwise load
/// continuation in a scale factor lambda in [0, 1] on f and q
/// ([`Continuation::follow_from`]: the linear-theory slope on the first step, then the secant
/// predictor, each corrector warm-started from the prediction, a corrector that lands far
/// from its prediction has jumped branches and counts as a failure), stopped after `budget`
/// right-hand-side evaluations. Every solve runs to `search.target` (the caller refines the
/// answer at its own tolerance).
pub(crate) fn find_branch(
    whisker: &Whisker,
    loads: &Loads,
    search: &Search<'_>,
    method: &'static str,
    budget: usize,
) -> Result<Found> {
    let unloaded = whisker.phi_unloaded(loads.s1);
    let sev = severity(whisker, loads);
    // evaluations of attempts that did not give the answer
    let mut evaluations = 0;
    // the natural first step of the last shot: the next one starts with it
    let mut start = None;
    if sev <= 1.0 {
        // From the linear-theory tip angle. A direct solve is kept only near the unloaded
        // shape (at most 0.5 rad of rotation at either end); otherwise it may have landed on
        // another branch and continuation decides.
        let linear = unloaded + crate::linear::tip_rotation(whisker, loads);
        let problem = TipProblem::new(whisker, loads, search.direct, method);
        let t = newton_to(&problem, linear, &search.direct_target);
        match t {
            Ok(t)
                if (t.phi1 - unloaded).abs() <= 0.5 && (t.values.phi0 - FRAC_PI_2).abs() <= 0.5 =>
            {
                return Ok(Found { tip: t, steps: 0 });
            }
            _ => {
                evaluations += problem.spent.get();
                start = problem.start.get();
            }
        }
    }
    let first = (1.0 / sev.ceil()).clamp(1e-3, 1.0);
    // the first step predicts along the linear-theory slope d phi1 / d lambda, which holds
    // while the rotation it predicts is small: that step is kept to LINEAR_STEP rad
    let (base_slope, slope) = crate::linear::rotations(whisker, loads);
    let initial = if slope.abs() * first > LINEAR_STEP {
        (LINEAR_STEP / slope.abs()).max(1e-3)
    } else {
        first
    };
    let cont = Continuation {
        initial_step: initial,
        min_step: 1e-8,
        max_step: (2.0 * first).min(1.0),
    };
    // the last corrector's solve: at lambda = 1 once the continuation has arrived
    let mut last = None;
    let (_, stats) = cont
        // the branch is followed in (phi1, phi0): under a strong force the tip aligns with
        // it on several branches (phi1 alike), the base angle tells them apart
        .follow_from(
            0.0,
            1.0,
            vec![unloaded, FRAC_PI_2],
            vec![slope, base_slope],
            &BranchGuard::default(),
            |lambda, pred: &[f64]| {
                if evaluations > budget {
                    return Err(ModelError::Budget {
                        method,
                        what: "right-hand-side evaluations",
                        limit: budget,
                    });
                }
                // intermediate load steps only guide the branch: residual 1e-5 on DOP853 at
                // 1e-6, far below the next step's prediction error (s18: 6104 -> 4376
                // evaluations, tip unchanged to 1e-15); the full accuracy is restored at
                // lambda = 1 by the caller
                let scaled = loads.scaled(lambda);
                let problem =
                    TipProblem::new(whisker, &scaled, search.guide, method).starting(start);
                let target = TipTarget {
                    load_scale: lambda,
                    ..if lambda < 1.0 {
                        search.step_target
                    } else {
                        search.guide_target
                    }
                };
                let t = newton_to(&problem, pred[0], &target);
                evaluations += problem.spent.get();
                start = problem.start.get();
                let t = t?;
                last = Some(t);
                Ok(vec![t.phi1, t.values.phi0])
            },
        )
        .map_err(|e| {
            // the budget stops the run at once, whatever the step size
            ModelError::from_continuation(method, e)
        })?;
    let Some(mut tip) = last else {
        unreachable!("a continuation that arrives has run its correctors")
    };
    tip.evaluations = evaluations;
    tip.branch_jumps = stats.jumps;
    Ok(Found {
        tip,
        steps: stats.steps,
    })
}

/// Newton at `integration` from the tip angle `from` of a branch search to `target`
/// (load scale 1), its first shot starting with `start` (the search's last natural first
/// step); with its own evaluations, also of a failed iteration.
pub(crate) fn polish_tip_angle(
    whisker: &Whisker,
    loads: &Loads,
    integration: &Integration,
    method: &'static str,
    (from, start): (f64, Option<StartStep>),
    target: &TipTarget,
) -> (Result<TipSolve>, usize) {
    let problem = TipProblem::new(whisker, loads, integration, method).starting(start);
    let t = newton_to(&problem, from, target);
    (t, problem.spent.get())
}

/// The elastica from a shot at the solved tip angle `tip`, and that final shot's
/// verification of the base condition [3.21, 3.22] (one more Newton solve from it if its
/// residual exceeds [`VERIFY_TOL`]); `stats` seeds the solution's statistics. Returns the
/// solution and the derivatives `d(phi0, m0, dx, dy)/dphi1` of the last Newton shot.
pub(crate) fn finished(
    scene: &Scene,
    run: &Run<'_>,
    tip: &TipSolve,
    continuation_steps: usize,
    stats: SolveStats,
) -> Result<(Solution, BaseValues)> {
    let w = &scene.whisker;
    let loads = &scene.loads;
    let (integration, samples, method) = (run.integration, run.samples, run.method);
    let mut stats = SolveStats {
        iterations: tip.iterations,
        residual: tip.residual,
        continuation_steps,
        evaluations: tip.evaluations,
        branch_jumps: tip.branch_jumps,
        ..stats
    };
    let mut sens = tip.sens;
    let mut sol = shape(scene, tip.phi1, integration, samples, stats, method)?;
    // The final shot verifies the base condition [3.21, 3.22] of the last Newton step.
    let residual = |sol: &Solution| w.support.residual(sol.base.phi0, -sol.base.ma).abs();
    if residual(&sol) > VERIFY_TOL * residual_scale(w, &sol) {
        let t = newton_tip_angle(w, loads, integration, tip.phi1, method).0?;
        stats.iterations += t.iterations;
        stats.evaluations += t.evaluations;
        sens = t.sens;
        sol = shape(scene, t.phi1, integration, samples, stats, method)?;
    }
    sol.stats.residual = residual(&sol);
    Ok((sol, sens))
}

/// The scale `1 + |m0|/k` of the base residual [3.21, 3.22] of a solution.
pub(crate) fn residual_scale(w: &Whisker, sol: &Solution) -> f64 {
    1.0 + sol.base.ma.abs() * w.support.compliance()
}

/// The largest difference between `sol` and a second solution with base values `second`
/// whose tip angle differs by `dphi1` (and `dphi1` itself), plus the tip's move beyond
/// `s1`, `(1 - s1) |dphi1|`; an AP force's reactions move by `f |dphi1|`.
pub(crate) fn difference(second: BaseValues, dphi1: f64, sol: &Solution, loads: &Loads) -> f64 {
    let diffs = [
        second.phi0 - sol.base.phi0,
        second.m0 + sol.base.ma,
        second.dx - sol.loaded_end.x,
        second.dy - sol.loaded_end.y,
        dphi1,
    ];
    let mut est = diffs.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    if !est.is_finite() {
        est = f64::INFINITY;
    }
    est += dphi1.abs() * (1.0 - loads.s1);
    if loads.tip.kind == crate::loads::LoadKind::Ap {
        est = est.max(dphi1.abs() * loads.tip.f);
    }
    est
}

/// The largest difference between `sol` and the second shot `shot` moved by the Newton step
/// `d` in the tip angle along `sens = d(phi0, m0, x, y)/dphi1` ([`difference`]).
pub(crate) fn corrected_difference(
    shot: &crate::shot::Shot,
    sens: BaseValues,
    d: f64,
    sol: &Solution,
    loads: &Loads,
) -> f64 {
    difference(moved(shot.values(), sens, d), d, sol, loads)
}

/// A-posteriori error estimate of a shooting solution, independent of its residual: a
/// second shot from the same tip angle with the integrator `check` (tighter tolerance or
/// finer grid), corrected by one Newton step on the base condition [3.21, 3.22] with the
/// exact derivative `dR/dphi1`, gives a second solution `(phi1', phi0', m0', x', y')`; the
/// estimate is the largest difference from `sol` (the tip beyond `s1` moves with phi1 by at
/// most `(1 - s1) |dphi1|`, an AP force's reactions by `f |dphi1|`). Returns the estimate
/// and the evaluations spent.
pub(crate) fn error_estimate(
    scene: &Scene,
    sol: &Solution,
    check: &Integration,
) -> Result<(f64, usize)> {
    let w = &scene.whisker;
    let loads = &scene.loads;
    let phi1 = sol.loaded_end.phi;
    let shot = shoot(w, loads, phi1, Sensitivities::TipAngle, check)?;
    let r = w.support.residual(shot.phi0, shot.m0);
    let dr = w.support.residual_rate(shot.d_phi1.phi0, shot.d_phi1.m0);
    if !(dr.is_finite() && dr != 0.0) {
        return Ok((f64::INFINITY, shot.evaluations));
    }
    let d = -r / dr;
    let est = corrected_difference(&shot, shot.d_phi1, d, sol, loads);
    Ok((est, shot.evaluations))
}
