//! `accurate`: the equilibrium branch found by shooting at loose tolerances, then the answer
//! at the asked tolerance from one dense shot, and its error estimate from a second
//! solution at another tolerance.
//!
//! Each stage is a Newton iteration on the tip angle `phi1` (the base condition
//! [3.21, 3.22], exact derivatives from the variational equations) started from the
//! previous stage's answer, on a tighter integration:
//!
//! 1. the branch search ([`find_branch`]: the direct solve from linear theory, or load
//!    continuation) on DOP853 at [`GUIDE_TOL`]: it decides the branch;
//! 2. Newton from there at the estimate's tolerance `e = min(tolerance / 100, SEARCH_TOL)`
//!    ([`TipTarget::SEARCH`]): `phi1` within that integration's error of the root;
//! 3. one dense shot at `tol` (where the caller allows a looser one, `auto`, at the
//!    loosest whose resolution floor leaves room for the estimate, [`dense_tol`], and at
//!    `tol` only where that one's estimate fails) with the tip-angle sensitivities, moved
//!    by its own Newton step
//!    `d = -R / R'` to its root ([`linearised_shape`]: the base values, the loaded end and
//!    the elastica along their sensitivities, an error `O(d^2)`); the returned solution;
//! 4. the second solution, where `e >= 100 tol`: stage 2's last shot (at `e`) moved to its
//!    own root by the trapezoidal step
//!
//!    ```text
//!    D = -2 R / (R'_2 + R'_3),   V(phi1 + D) = V + D (V'_2 + V'_3) / 2
//!    ```
//!
//!    with the derivatives of both shots (error `O(D^3)`: stage 2 lands within ~1e-5 of the
//!    root, so `D^3 ~ 1e-15`). Its error is that of the looser integration, a hundred
//!    times the answer's at least: the estimate (the largest difference of the two: base
//!    values, loaded end, tip angle; [`difference`]) bounds the answer's error with that
//!    margin, at no extra shot. Where `e < 100 tol`, or that estimate exceeds the
//!    tolerance, the check shot at `check_tol` at the answer's root, moved to its own root
//!    by one Newton step with the dense shot's derivative, is the second solution
//!    ([`corrected_difference`]). Where the dense shot took fewer than
//!    [`ASYMPTOTIC_STEPS`] steps, DOP853's error need not scale with its tolerance (a
//!    plateau over a band of tolerances, issue 34 item 3): the check shot is taken as well
//!    and the estimate is the larger of the two.
//!
//! Where stage 3 does not come within [`root_step`] of its root in [`ROOT_SHOTS`] shots,
//! the former scheme answers: Newton at `tol` from stage 2, the elastica shot at its root,
//! the check shot there.

use super::elastica::moved;
use super::elastica::Run;
use super::elastica::{linearised_shape, Linearised};
use super::load_path::{find_branch_by_rule, Polish};
use super::shooting::{
    corrected_difference, difference, finished, polish_tip_angle, Search, TipSolve, TipTarget,
};
use crate::equations::Sensitivities;
use crate::error::Result;
use crate::loads::{LoadKind, Loads};
use crate::scene::Scene;
use crate::shot::{shoot, BaseValues, Integration};
use crate::solution::{MethodKind, Solution, SolveStats};

/// The guiding tolerance of the branch search: the load steps only guide the branch (to
/// within far less than the jump guard's 0.2 rad).
pub(crate) const GUIDE_TOL: f64 = 1e-3;

/// The loosest tolerance of the load path (where the direct solve from linear theory jumps
/// branches): measured on a thin whisker (theta 0.157) under a strong flow and tip force,
/// paths traced at 1e-6 and 1e-8 reached other equilibria at the full load than those at
/// 1e-7 and 1e-9..1e-14, whose base angles agree to 1e-8.
pub(crate) const PATH_TOL: f64 = 1e-12;

/// The loosest search tolerance of stage 2: it puts `phi1` within ~1e-8 of the root at
/// `tol`, so that stage 3's Newton step is small enough to be taken linearised.
pub(crate) const SEARCH_TOL: f64 = 1e-7;

/// The factor on the difference of the two solutions: the second solution's own error is
/// not always a tenth (a hundredth) of the answer's, DOP853's global error does not scale
/// with its tolerance on every scene (measured: the check shot's difference 0.99 of the
/// answer's error, auto battery case 345, an AP force of 23.6 amplifying a tip-angle
/// error of 1e-12 in the reactions).
pub(crate) const SAFETY: f64 = 2.0;

/// Stage 2 runs at `tolerance / ESTIMATE_MARGIN` (at most [`SEARCH_TOL`]) and gives the
/// second solution where that is at least `ESTIMATE_MARGIN` times the dense shot's
/// tolerance (module docs, stage 4).
pub(crate) const ESTIMATE_MARGIN: f64 = 100.0;

/// The fewest accepted steps of the dense shot at which the second solution from stage 2
/// (an integration `ESTIMATE_MARGIN` times looser) gives the estimate alone; below, the check
/// shot (tighter) confirms it. DOP853's global error is proportional to its tolerance only
/// once its steps are asymptotic: on a few large steps it plateaus. Measured (issue 34
/// item 3, an AP force 3.52 at -82 deg on a spring k 0.545, `tests/auto.rs` case 90 of the
/// 300-scene run): shots at the solution's tip angle miss the base condition by 3.6e-7,
/// 1.9e-7, 1.3e-7 at tolerances 1e-6, 1e-7, 1e-8 (3 to 4 steps), 9.2e-9 at 1e-9; `auto`
/// at 1e-6 answered from a dense shot at 1e-8 (3 steps) whose tip angle was 7.1e-7 off,
/// stage 2's at 1e-6 7.7e-7 off, so that their difference (5.8e-8) estimated 6.0e-7 for
/// an error of 2.0e-6 (`Ax`, an AP force's reactions carry `f` times the tip angle's
/// error). Over the 780 answers of that run, the ratio error / estimate of the estimates
/// from stage 2 reached 3.4, 0.19, 0.18, 0.46, 0.25 on dense shots of 3 to 7 steps and
/// at most 0.041 from 8 steps on (95 answers); the common path (`accurate` at 1e-12 on
/// the reference scenes and s18) takes 11 to 32 steps. The plateau:
/// `tests::few_step_shots_do_not_scale_with_their_tolerance`.
pub(crate) const ASYMPTOTIC_STEPS: usize = 8;

/// Most dense shots (Newton steps at the tolerance) before the former scheme answers.
pub(crate) const ROOT_SHOTS: usize = 3;

/// The largest Newton step (rad) of the dense shot at `tol` whose linearisation is taken:
/// `0.1 sqrt(tol)`, so that its error `|V''| d^2 / 2` stays below the tolerance for base
/// values with `|V''| <= 200` (the search lands within ~1e-8 of the root: s18, whose
/// `m0'' ~ 2500`, sees `d = 2.4e-9`).
pub(crate) fn root_step(tol: f64) -> f64 {
    0.1 * tol.sqrt()
}

/// How `accurate` (module docs) shoots: the dense shot's tolerance `tol`, the check shot's
/// `check_tol`, the `tolerance` its estimate must meet, the elastica's `samples` and the
/// continuation's `budget` of right-hand-side evaluations (beyond it,
/// [`ModelError::Budget`](crate::ModelError)).
pub(crate) struct Accurate {
    pub tol: f64,
    pub check_tol: f64,
    pub tolerance: f64,
    pub samples: usize,
    pub budget: usize,
    /// Stage 2's tolerance where the caller chooses it (`auto`, at its accuracy); `None`:
    /// `tolerance / ESTIMATE_MARGIN`, at most [`SEARCH_TOL`].
    pub search_tol: Option<f64>,
    /// The loosest tolerance the caller allows the dense shot (`auto`: a tenth of its
    /// accuracy; else `tol`): the dense shot runs at the loosest tolerance in
    /// `[tol, loosest_tol]` whose resolution floor is at most half of `tolerance`
    /// ([`dense_tol`]), and once more at `tol` where that answer's estimate from stage 2
    /// does not meet `tolerance`.
    pub loosest_tol: f64,
}

/// The share of the tolerance asked for that the dense shot's resolution floor may take
/// where its tolerance is chosen ([`dense_tol`]); the rest is the second solution's.
pub(crate) const FLOOR_SHARE: f64 = 0.5;

/// The dense shot's tolerance (field [`Accurate::loosest_tol`]): the loosest in
/// `[a.tol, a.loosest_tol]` whose [`resolution`] at stage 2's answer `tip` (its values
/// within ~1e-5 of the answer's) is at most [`FLOOR_SHARE`] of `a.tolerance`.
fn dense_tol(a: &Accurate, tip: &TipSolve, loads: &Loads) -> f64 {
    if a.loosest_tol <= a.tol {
        return a.tol;
    }
    let v = &tip.values;
    let per_tol = resolution(scale([v.phi0, v.m0, v.dx, v.dy, tip.phi1]), 1.0, loads);
    let t = FLOOR_SHARE * a.tolerance / per_tol;
    if t.is_nan() {
        a.tol
    } else {
        t.clamp(a.tol, a.loosest_tol)
    }
}

impl Accurate {
    /// The tolerance of stage 2, and whether its shot gives the second solution: where the
    /// caller chose stage 2's tolerance, whenever it is looser than the dense shot's (the
    /// caller chose the margin); else where it is [`ESTIMATE_MARGIN`] times looser.
    fn estimate_tol(&self) -> (f64, bool) {
        if let Some(e) = self.search_tol {
            return (e, e > self.tol);
        }
        let e = (self.tolerance / ESTIMATE_MARGIN).min(SEARCH_TOL);
        // (the margin met up to the rounding of a tolerance divided by it)
        if e >= ESTIMATE_MARGIN * self.tol * (1.0 - 1e-9) {
            (e, true)
        } else {
            (SEARCH_TOL.max(self.tol), false)
        }
    }
}

/// `accurate` (module docs): DOP853 shooting at `a.tol` with an error estimate.
pub(crate) fn solve_accurate(scene: &Scene, a: &Accurate) -> Result<Solution> {
    let w = &scene.whisker;
    let loads = &scene.loads;
    let (tol, samples, budget) = (a.tol, a.samples, a.budget);
    let integration = Integration::adaptive(tol);
    let check = Integration::adaptive(a.check_tol);
    let (search_tol, second) = a.estimate_tol();
    let search_integration = Integration::adaptive(search_tol);
    let guide_integration = Integration::adaptive(GUIDE_TOL.max(tol));
    let search = Search {
        direct: &guide_integration,
        direct_target: TipTarget::GUIDE_LOOSE,
        guide: &guide_integration,
        step_target: TipTarget::GUIDE_STEP,
        guide_target: TipTarget::GUIDE_LOOSE,
    };
    let polish = Polish {
        integration: &search_integration,
        target: TipTarget::SEARCH,
        direct_too: true,
    };
    // the load path where the direct solve jumps, traced at the default tolerance whatever
    // the asked accuracy: on ill-conditioned scenes (thin tips under strong loads) a looser
    // integration reaches another equilibrium at the full load
    let path_integration = Integration::adaptive(tol.min(PATH_TOL));
    let (found, path) = find_branch_by_rule(
        w,
        loads,
        &search,
        &polish,
        &path_integration,
        "accurate",
        budget,
    )?;
    let stats = SolveStats {
        method_used: MethodKind::Accurate,
        iterations: found.tip.iterations,
        continuation_steps: found.steps,
        evaluations: found.tip.evaluations,
        branch_jumps: found.tip.branch_jumps,
        ..SolveStats::default()
    };
    // the dense shot at the loosest tolerance allowed whose floor leaves room for the
    // estimate, then (where its estimate from stage 2 fails) at `tol`
    let loose = dense_tol(a, &found.tip, loads);
    let mut stats = stats;
    for at in [loose, tol] {
        let dense = Integration::adaptive(at);
        let run = Run {
            integration: &dense,
            samples,
            method: "accurate",
            budget,
        };
        let estimate = Estimate {
            check: &check,
            second: second.then_some(&found.tip),
            tolerance: a.tolerance,
            tighten: at > tol,
        };
        match refine(scene, &found.tip, &run, &estimate, stats)? {
            Refined::Answer(mut sol) => {
                sol.load_path = path;
                return Ok(*sol);
            }
            Refined::Loose(spent) => stats.evaluations += spent,
            Refined::Far(spent) => {
                stats.evaluations += spent;
                break;
            }
        }
        if loose <= tol {
            break;
        }
    }
    let spent = stats.evaluations - found.tip.evaluations;
    let run = Run {
        integration: &integration,
        samples,
        method: "accurate",
        budget,
    };
    // Newton at `tol` from the search's answer, the elastica at its root and the second
    // solution from the check shot there
    let mut tip = polish_tip_angle(
        w,
        loads,
        &integration,
        "accurate",
        (found.tip.phi1, found.tip.start),
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

/// Where the second solution of stage 4 comes from.
struct Estimate<'a> {
    /// The check shot's integration.
    check: &'a Integration,
    /// Stage 2's answer, where its shot gives the second solution.
    second: Option<&'a TipSolve>,
    /// The tolerance that estimate must meet (else the check shot gives it).
    tolerance: f64,
    /// Where that estimate does not meet it: give up ([`Refined::Loose`]) for a tighter
    /// dense shot instead of taking the check shot.
    tighten: bool,
}

/// The largest second derivative `|V''|` of the base values `V = (phi0, m0, dx, dy)` in the
/// tip angle: the difference quotient of two shots' derivatives `(phi1, V')`; infinite
/// where the quotient is not defined (one angle, or derivatives not finite).
fn curvature((p, a): (f64, BaseValues), (q, b): (f64, BaseValues)) -> f64 {
    let (a, b) = (a.to_array(), b.to_array());
    (0..4)
        .map(|i| ((b[i] - a[i]) / (q - p)).abs())
        .try_fold(0.0_f64, |m, c| (!c.is_nan()).then_some(m.max(c)))
        .unwrap_or(f64::INFINITY)
}

/// The second solution of stage 4 from stage 2's answer `tip` (its last shot at
/// `tip.phi1 - tip.step`): that shot moved to its own root by the trapezoidal step with its
/// derivatives and the dense shot's, `sens`; its difference from the answer `sol`.
fn trapezoidal_difference(scene: &Scene, tip: &TipSolve, sens: BaseValues, sol: &Solution) -> f64 {
    let support = &scene.whisker.support;
    let last = moved(tip.values, tip.sens, -tip.step);
    let r = support.residual(last.phi0, last.m0);
    let rate = support.residual_rate(tip.sens.phi0, tip.sens.m0)
        + support.residual_rate(sens.phi0, sens.m0);
    let step = -2.0 * r / rate;
    let (a, b) = (tip.sens.to_array(), sens.to_array());
    let mean = BaseValues::from_array(std::array::from_fn(|i| 0.5 * (a[i] + b[i])));
    let second = moved(last, mean, step);
    let phi1 = tip.phi1 - tip.step + step;
    difference(second, phi1 - sol.loaded_end.phi, sol, &scene.loads)
}

/// The largest magnitude among integrated values `(phi0, m0, x1, y1, phi1)`.
fn scale(values: [f64; 5]) -> f64 {
    values.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// The smallest error an answer of a dense shot at `tol` can claim: its tolerance relative
/// to the largest integrated value `scale` ([`scale`]; DOP853 controls each step's error to
/// `tol (1 + |y|)`; below that the difference of two integrations says nothing: measured,
/// answers at 1e-12 1e-13 off where the two solutions agreed to 1e-14, on 6 of 279 random
/// scenes), carried into the answer as [`difference`] carries a tip-angle error: the rest
/// beyond `s1` by `(1 - s1)`, an AP force's reactions by `f`. The reactions of a
/// fixed-direction load are its balance [5.1] and carry no integration error.
fn resolution(scale: f64, tol: f64, loads: &Loads) -> f64 {
    let ap = if loads.tip.kind == LoadKind::Ap {
        loads.tip.f
    } else {
        0.0
    };
    tol * (1.0 + scale) * (1.0 + (1.0 - loads.s1)).max(ap)
}

/// [`resolution`] at a solution's integrated values.
fn resolution_of(sol: &Solution, tol: f64, loads: &Loads) -> f64 {
    let (b, e) = (&sol.base, &sol.loaded_end);
    resolution(scale([b.phi0, b.ma, e.x, e.y, e.phi]), tol, loads)
}

/// What [`refine`] gives.
enum Refined {
    /// The solution with its error estimate.
    Answer(Box<Solution>),
    /// The estimate from stage 2 did not meet the tolerance and the caller asked to
    /// tighten the dense shot rather than take the check shot: the evaluations spent.
    Loose(usize),
    /// The dense shots' Newton steps did not come within reach of their root: the
    /// evaluations spent.
    Far(usize),
}

/// Steps 3 and 4 of the module docs from the search's answer `tip`: the solution with its
/// error estimate, or (`Err`) the evaluations spent when the dense shots' Newton steps do
/// not come within reach of their root: `|d| <= root_step(tol)`, or within the interval
/// from the previous shot where two shots give the curvature `|V''|` (measured: stage 2
/// at 1e-12 lands 2.3e-8 from the root at 1e-14, beyond `root_step` = 1e-8, on the
/// conical reference scene), and a linearisation error `|V''| d^2 / 2` below
/// `tolerance / ESTIMATE_MARGIN` (that bound is added to the estimate).
fn refine(
    scene: &Scene,
    tip: &TipSolve,
    run: &Run<'_>,
    estimate: &Estimate<'_>,
    mut stats: SolveStats,
) -> Result<Refined> {
    let w = &scene.whisker;
    let support = &w.support;
    let loads = &scene.loads;
    let Integration::Dop853(d853) = run.integration else {
        return Ok(Refined::Far(0));
    };
    let before = stats.evaluations;
    // the dense and check shots start with stage 2's natural first step
    let dense = run.integration.started(tip.start);
    let run = &Run {
        integration: &dense,
        ..*run
    };
    let check = estimate.check.started(tip.start);
    let bound = root_step(d853.rtol);
    let linear_error = estimate.tolerance / ESTIMATE_MARGIN;
    // the last shot with sensitivities before the dense one: stage 2's, where it was not
    // at the dense shot's angle
    let mut prev = Some((tip.phi1 - tip.step, tip.sens)).filter(|_| tip.step != 0.0);
    let mut phi1 = tip.phi1;
    let mut spent = 0;
    for _ in 0..ROOT_SHOTS {
        stats.iterations += 1;
        // the linearisation error |V''| d^2 / 2 (none without a move)
        let linearisation = |sens: &BaseValues, d: f64| match prev {
            Some(p) if d != 0.0 => 0.5 * curvature(p, (phi1, *sens)) * d * d,
            _ => 0.0,
        };
        // within reach: the step below the bound, or inside the interval over which the
        // curvature was measured (the previous shot to this one)
        let reach =
            |d: f64| d.abs() <= bound || prev.is_some_and(|(p, _)| d.abs() <= (phi1 - p).abs());
        let accept = |d: f64, sens: &BaseValues| reach(d) && linearisation(sens, d) <= linear_error;
        match linearised_shape(scene, phi1, run, stats, accept)? {
            Linearised::Root {
                mut sol,
                sens,
                steps,
            } => {
                sol.stats.residual = support.residual(sol.base.phi0, -sol.base.ma).abs();
                // the linearisation's bound and the dense shot's own resolution
                let floor = linearisation(&sens, sol.loaded_end.phi - phi1)
                    + resolution_of(&sol, d853.rtol, loads);
                // the second solution: stage 2's shot, where it was not at this angle; it
                // answers alone where the dense shot is asymptotic ([`ASYMPTOTIC_STEPS`]),
                // else the check shot must confirm it (the larger of the two estimates)
                let mut looser = None;
                if let Some(second) = estimate.second.filter(|t| t.step != 0.0) {
                    let est = SAFETY * trapezoidal_difference(scene, second, sens, &sol) + floor;
                    if est <= estimate.tolerance && steps >= ASYMPTOTIC_STEPS {
                        sol.stats.error_estimate = est;
                        return Ok(Refined::Answer(sol));
                    }
                    if est <= estimate.tolerance {
                        looser = Some(est);
                    } else if estimate.tighten {
                        return Ok(Refined::Loose(sol.stats.evaluations - before));
                    }
                }
                // ... else (or to confirm it) the check integration at the root, moved to its
                // own root by one Newton step with the dense shot's derivative
                let shot = shoot(w, loads, sol.loaded_end.phi, Sensitivities::None, &check)?;
                sol.stats.evaluations += shot.evaluations;
                let r = support.residual(shot.phi0, shot.m0);
                let dr = support.residual_rate(sens.phi0, sens.m0);
                let d = if dr.is_finite() && dr != 0.0 {
                    -r / dr
                } else {
                    f64::INFINITY
                };
                let est = SAFETY * corrected_difference(&shot, sens, d, &sol, loads) + floor;
                let est = looser.map_or(est, |l| est.max(l));
                if looser.is_some() && est > estimate.tolerance && estimate.tighten {
                    return Ok(Refined::Loose(sol.stats.evaluations - before));
                }
                sol.stats.error_estimate = est;
                return Ok(Refined::Answer(sol));
            }
            Linearised::Far {
                d,
                sens,
                evaluations,
            } => {
                spent += evaluations;
                stats.evaluations += evaluations;
                if !d.is_finite() {
                    break;
                }
                prev = Some((phi1, sens));
                phi1 += d;
            }
        }
    }
    Ok(Refined::Far(spent))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::{CHECK_TOL_RATIO, SHOOTING_BUDGET};

    /// `auto`'s scheme at 1e-12 (stage 2 at 1e-12, the dense shot allowed up to 1e-13):
    /// cheaper than the dense shot at 1e-14, and its error against a solve at 1e-14 (with
    /// that one's estimate) within its estimate, itself within 1e-12.
    #[test]
    fn a_looser_dense_shot_where_the_floor_leaves_room_is_cheaper_and_honest() {
        for (name, scene) in crate::scenarios::reference_scenes() {
            let scene = scene.normalised();
            let run = |tol: f64, tolerance: f64, search_tol: Option<f64>, loosest_tol: f64| {
                let a = Accurate {
                    tol,
                    check_tol: (tol * CHECK_TOL_RATIO).max(crate::methods::MIN_CHECK_TOL),
                    tolerance,
                    samples: 20,
                    budget: SHOOTING_BUDGET,
                    search_tol,
                    loosest_tol,
                };
                solve_accurate(&scene, &a).unwrap()
            };
            let truth = run(1e-14, 1e-10, None, 1e-14);
            let loose = run(1e-14, 1e-12, Some(1e-12), 1e-13);
            let tight = run(1e-14, 1e-12, Some(1e-12), 1e-14);
            let (est, err) = (loose.stats.error_estimate, loose.difference(&truth));
            assert!(
                err <= est + truth.stats.error_estimate && est <= 1e-12,
                "{name}: error {err:e}, estimate {est:e}"
            );
            assert!(
                loose.stats.evaluations < tight.stats.evaluations,
                "{name}: {} vs {}",
                loose.stats.evaluations,
                tight.stats.evaluations
            );
        }
    }

    /// The plateau behind [`ASYMPTOTIC_STEPS`] (case 90 of the 300-scene run of
    /// `tests/auto.rs`): plain shots at the exact tip angle (RK4 on 4000 steps, its estimate
    /// below 1e-11) miss the base condition by 3.7e-7 at 1e-6 and still 1.4e-7 at 1e-8, a
    /// hundred times the tolerance, on a few steps; by 7.2e-10 at 1e-10.
    #[test]
    fn few_step_shots_do_not_scale_with_their_tolerance() {
        use crate::{solve, Method, TipForce, Whisker};
        let w = Whisker::new(
            0.9783224388196412,
            0.6443987228592805,
            0.3360533451296168,
            0.5446785868752674,
        );
        let loads = Loads::tip(TipForce::ap(3.5249865454096883, -1.4304555629011306));
        assert_eq!(loads.tip.kind, LoadKind::Ap);
        let truth = solve(&Scene::new(w, loads), &Method::Rk4 { n: 4000 }).unwrap();
        assert!(truth.stats.error_estimate < 1e-11);
        let phi1 = truth.loaded_end.phi;
        let miss = |tol: f64| {
            let integration = Integration::adaptive(tol);
            let shot = shoot(&w, &loads, phi1, Sensitivities::None, &integration).unwrap();
            (
                w.support.residual(shot.phi0, shot.m0).abs(),
                shot.evaluations,
            )
        };
        let ((m6, e6), (m8, e8), (m10, _)) = (miss(1e-6), miss(1e-8), miss(1e-10));
        // a few steps (12 evaluations each) at 1e-6 and 1e-8
        assert!(e6 <= 5 * 12 && e8 <= 6 * 12, "{e6} {e8}");
        assert!(
            m6 < 1e-6 && m8 > 10.0 * 1e-8 && m8 > 0.2 * m6,
            "{m6:e} {m8:e}"
        );
        assert!(m10 < 1e-2 * m8 && m10 < 1e-8, "{m10:e}");
    }

    /// `V = (phi^2, 2 phi^2, -phi^2 / 2, 0)`: the difference quotient of `V'` is `V''`,
    /// whose largest component is 4, wherever the two shots lie.
    #[test]
    fn curvature_of_a_parabola() {
        let sens = |p: f64| BaseValues::from_array([2.0 * p, 4.0 * p, -p, 0.0]);
        for (p, q) in [(1.0, 1.5), (-0.3, 0.2), (2.0, 2.0 + 1e-6)] {
            let c = curvature((p, sens(p)), (q, sens(q)));
            assert!((c - 4.0).abs() < 1e-9, "{p} {q}: {c}");
        }
        // no quotient from one angle: infinite, never zero
        assert_eq!(curvature((1.0, sens(1.0)), (1.0, sens(1.0))), f64::INFINITY);
    }

    /// The second solution from stage 2's shot (no extra shot) bounds the answer's error
    /// (against a solve at 1e-14), and the answer agrees with the one whose estimate comes
    /// from the check shot (a tolerance too tight for stage 2 to give it).
    #[test]
    fn the_estimate_from_stage_two_bounds_the_error_at_no_extra_shot() {
        for (name, scene) in crate::scenarios::reference_scenes() {
            let scene = scene.normalised();
            let run = |tol: f64, tolerance: f64| {
                let a = Accurate {
                    tol,
                    check_tol: tol * CHECK_TOL_RATIO,
                    tolerance,
                    samples: 20,
                    budget: SHOOTING_BUDGET,
                    search_tol: None,
                    loosest_tol: tol,
                };
                solve_accurate(&scene, &a).unwrap()
            };
            let truth = run(1e-14, 1e-10);
            let sol = run(1e-12, 1e-8);
            let checked = run(1e-12, 1e-11);
            let err = sol.difference(&truth);
            let est = sol.stats.error_estimate;
            assert!(
                err <= est && est <= 1e-9,
                "{name}: error {err:e}, estimate {est:e}"
            );
            assert!(sol.difference(&checked) < 1e-12, "{name}");
            assert!(
                sol.stats.evaluations < checked.stats.evaluations,
                "{name}: {} vs {}",
                sol.stats.evaluations,
                checked.stats.evaluations
            );
        }
    }
}
