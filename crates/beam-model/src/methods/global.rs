//! `multiple-shooting`: the elastica [3.25] on `[0, s1]` as a first-order two-point problem
//! solved on the whole interval at once, for the slender scenes on which single shooting
//! from the loaded end is ill-conditioned (a tip force on `theta <= 0.02`: the linearised
//! equation grows like `exp(sqrt(f) / theta^2)` across the tip's boundary layer of width
//! `theta^2 / sqrt(f)`).
//!
//! The state `u = (phi, m, x, y)` obeys [3.25] split into first order
//! ([`state_rate`](crate::equations::state_rate)):
//!
//! ```text
//! phi' = m / e^4 + A s + B,  m' = f sin(phi + c) + q (s1 - s) sin(phi + alpha),
//! x' = cos phi,  y' = sin phi,
//! ```
//!
//! with the base condition [3.21, 3.22] `phi(0) - pi/2 - m(0)/k = 0`, `x(0) = y(0) = 0` and
//! the free loaded end `m(s1) = 0`; for an AP force the tip angle `phi1` in `c` is an unknown
//! parameter with the condition `phi1 - phi(s1) = 0`. It is solved by
//! [`bvp_solvers::multiple_shooting`] (DOP853 on each segment with the variational
//! equations of the analytic Jacobian, nodes inserted where a segment's sensitivities grow
//! beyond 1e3, so about `sqrt(f) / (7 theta)` segments crowd into the boundary layer).
//!
//! The branch is the guess's: Newton starts from a solution that loading from zero reached
//! (the refused FDM + Richardson or shooting answer in `accurate`'s fallback, else the FDM
//! by continuation), and an answer farther than [`BRANCH_AGREEMENT`] from it is refused.
//!
//! **Error estimate**: two independent solves from the guess, at the integrator tolerance
//! `tol` (the answer) and at `CHECK_FACTOR tol` (at most 1e-6). Their difference (tip,
//! loaded end, base observables; [`Solution::difference`]) estimates the looser solve's
//! error, a hundred times the answer's in DOP853's regime; [`SAFETY`] times it (at least
//! the answer's matching residual) is the answer's estimate.

use super::accurate::SAFETY;
use super::whisker_problem::WhiskerProblem;
use super::BRANCH_AGREEMENT;
use crate::equations::FreeSegment;
use crate::error::{ModelError, Result};
use crate::scene::Scene;
use crate::solution::{BaseObservables, Elastica, EndState, MethodKind, Solution, SolveStats};
use bvp_solvers::collocation::BvpProblem;
use bvp_solvers::integrator::Dop853;
use bvp_solvers::multiple_shooting::{MultipleShooting, MultipleShootingSolution};

const METHOD: &str = "multiple-shooting";

/// The check solve runs at this multiple of the answer's integrator tolerance.
pub(crate) const CHECK_FACTOR: f64 = 100.0;

/// Largest sensitivity growth of one segment (node insertion beyond).
pub(crate) const MAX_GROWTH: f64 = 1e3;

/// Initial shooting nodes on `[0, s1]` (more are inserted where needed).
const NODES: usize = 9;

impl WhiskerProblem<'_> {
    /// One multiple-shooting solve at the integrator tolerance `tol` from `nodes` / `states`.
    fn solve(
        &self,
        tol: f64,
        nodes: &[f64],
        states: &[Vec<f64>],
        p: &[f64],
    ) -> Result<MultipleShootingSolution> {
        let ms = MultipleShooting {
            tol: 10.0 * tol,
            rtol: tol,
            atol: tol,
            max_growth: MAX_GROWTH,
            ..MultipleShooting::default()
        };
        ms.solve_with_jacobian(
            |s: f64, u: &[f64], p: &[f64], du: &mut [f64]| self.rhs(s, u, p, du),
            |s: f64, u: &[f64], p: &[f64], j: &mut [f64], jp: &mut [f64]| {
                self.rhs_jacobian(s, u, p, j, jp);
            },
            |ua: &[f64], ub: &[f64], p: &[f64], r: &mut [f64]| self.bc(ua, ub, p, r),
            nodes,
            states,
            p,
        )
        .map_err(|source| ModelError::Solver {
            method: METHOD,
            source,
        })
    }
}

/// The state `(phi, m, x, y)` of `guess`'s elastica at `s`, linearly interpolated.
fn guess_state(guess: &Solution, s: f64) -> Vec<f64> {
    let el = &guess.elastica;
    let i =
        el.s.partition_point(|&v| v < s)
            .clamp(1, el.len().max(2) - 1);
    let (s0, s1) = (el.s[i - 1], el.s[i]);
    let t = if s1 > s0 { (s - s0) / (s1 - s0) } else { 0.0 };
    let lerp = |v: &[f64]| v[i - 1] + t * (v[i] - v[i - 1]);
    vec![lerp(&el.phi), lerp(&el.m), lerp(&el.x), lerp(&el.y)]
}

/// Solves `scene` by multiple shooting from `guess` (a solution on the branch to follow):
/// the answer at the integrator tolerance `tol`, its estimate from the check solve at
/// `CHECK_FACTOR tol` (module docs); `samples` output intervals along the whisker.
///
/// # Errors
/// The solver's failure; [`ModelError::BranchJump`] (at load scale 1) where the answer is
/// farther than [`BRANCH_AGREEMENT`] from the guess.
pub(crate) fn solve(scene: &Scene, tol: f64, samples: usize, guess: &Solution) -> Result<Solution> {
    let bvp = WhiskerProblem::new(scene, 1.0);
    let s1 = scene.loads.s1;
    if guess.elastica.len() < 2 {
        return Err(ModelError::InvalidParameter {
            name: "guess",
            value: guess.elastica.len() as f64,
            reason: "multiple shooting needs a guess with at least 2 samples",
        });
    }
    let nodes: Vec<f64> = (0..NODES)
        .map(|i| s1 * i as f64 / (NODES - 1) as f64)
        .collect();
    let states: Vec<Vec<f64>> = nodes.iter().map(|&s| guess_state(guess, s)).collect();
    let p: Vec<f64> = if bvp.ap {
        vec![guess.loaded_end.phi]
    } else {
        vec![]
    };
    let check_tol = (tol * CHECK_FACTOR).min(1e-6);
    let check = bvp.solve(check_tol, &nodes, &states, &p)?;
    // from the guess too, not from the check's nodes: two independent solves
    let answer = bvp.solve(tol, &nodes, &states, &p)?;
    let evaluations = check.evaluations + answer.evaluations;
    let iterations = answer.iterations;
    let check_sol = assemble(scene, &check, check_tol, samples, SolveStats::default())?;
    let stats = SolveStats {
        iterations,
        residual: answer.residual,
        evaluations,
        method_used: MethodKind::MultipleShooting,
        requested: MethodKind::MultipleShooting,
        ..SolveStats::default()
    };
    let mut sol = assemble(scene, &answer, tol, samples, stats)?;
    // at least the answer's own matching residual (a zero difference only says that both
    // solves converged to the same nodes)
    sol.stats.error_estimate = (SAFETY * sol.difference(&check_sol)).max(answer.residual);
    let jump = sol.difference(guess);
    if jump.is_nan() || jump > BRANCH_AGREEMENT {
        return Err(ModelError::BranchJump {
            method: METHOD,
            load_scale: 1.0,
            distance: jump,
            allowed: BRANCH_AGREEMENT,
        });
    }
    Ok(sol)
}

/// The solution from a multiple-shooting answer ([`assemble_dense`] on its nodes and its
/// dense output).
fn assemble(
    scene: &Scene,
    ms: &MultipleShootingSolution,
    tol: f64,
    samples: usize,
    stats: SolveStats,
) -> Result<Solution> {
    let last = ms.y.last().cloned().unwrap_or_default();
    let eval = |s: f64| ms.eval(s);
    assemble_dense(
        scene,
        (&ms.y[0], &last),
        &eval,
        (tol, samples),
        stats,
        METHOD,
    )
}

/// The solution from a dense answer on the loaded segment `[0, s1]` (states `(phi, m, x,
/// y)`, `first` at s = 0 and `last` at s1, `eval` between): the elastica sampled on
/// `samples` intervals of `[0, 1]` (`kappa = m / e^4 + kappa0` [3.8] on `[0, s1]`, the
/// load-free segment beyond by DOP853 at `tol`), the ends and the base observables
/// (`MA = -m(0)`, `phi0 = phi(0)`, the reactions from the balance at `phi1`). Shared by
/// multiple shooting and collocation.
pub(super) fn assemble_dense(
    scene: &Scene,
    (first, last): (&[f64], &[f64]),
    eval: &dyn Fn(f64) -> Vec<f64>,
    (tol, samples): (f64, usize),
    stats: SolveStats,
    method: &'static str,
) -> Result<Solution> {
    let w = &scene.whisker;
    let s1 = scene.loads.s1;
    let end = last;
    let phi1 = end[0];
    let loaded_end = EndState {
        x: end[2],
        y: end[3],
        phi: phi1,
    };
    let free = FreeSegment {
        whisker: *w,
        s1,
        phi1,
    };
    let free_sol = if s1 < 1.0 {
        Some(
            Dop853::new(tol, tol)
                .with_dense(true)
                .integrate(&free, s1, 1.0, &[end[2], end[3]])
                .map_err(|source| ModelError::Solver { method, source })?,
        )
    } else {
        None
    };
    let mut el = Elastica::with_capacity(samples + 1);
    for i in 0..=samples {
        let s = i as f64 / samples as f64;
        if s <= s1 {
            let u = eval(s);
            let e2 = w.diameter(s).powi(2);
            let kappa = u[1] / (e2 * e2) + w.kappa0(s);
            el.push(s, u[2], u[3], u[0], kappa, u[1]);
        } else if let Some(fs) = &free_sol {
            let xy = fs.eval(s).unwrap_or_else(|| vec![f64::NAN; 2]);
            el.push(s, xy[0], xy[1], free.phi(s), w.kappa0(s), 0.0);
        }
    }
    let tip = match &free_sol {
        Some(fs) => EndState {
            x: fs.u_end[0],
            y: fs.u_end[1],
            phi: free.phi(1.0),
        },
        None => loaded_end,
    };
    let (ax, ay) = scene.base_reactions(phi1);
    Ok(Solution {
        elastica: el,
        tip,
        loaded_end,
        base: BaseObservables {
            ax,
            ay,
            ma: -first[1],
            phi0: first[0],
        },
        stats,
        load_path: None,
    })
}

#[cfg(test)]
mod tests {
    use super::super::test_scenes::{against_accurate, moderate, slender_against_fdm_richardson};
    use crate::Method;

    /// On moderate whiskers (theta 0.2..1, DP and AP forces, flows, spring and rigid bases,
    /// pre-curvature) the method agrees with `accurate` (single shooting, independent) to
    /// their tolerances, and its estimate is below its tolerance.
    #[test]
    fn agrees_with_single_shooting_where_that_works() {
        let ms_method = Method::from_name("multiple-shooting", None).unwrap();
        for (i, scene) in moderate().iter().enumerate() {
            let (ms, acc, d) =
                against_accurate(scene, &ms_method).unwrap_or_else(|e| panic!("scene {i}: {e}"));
            assert!(
                d <= ms.stats.tolerance + acc.stats.tolerance,
                "scene {i}: differs by {d:e}"
            );
            assert!(ms.stats.error_estimate <= ms.stats.tolerance, "scene {i}");
            assert!(
                d <= 10.0 * (ms.stats.error_estimate + acc.stats.error_estimate) + 1e-12,
                "scene {i}: {d:e} not bounded by the estimates {:e} + {:e}",
                ms.stats.error_estimate,
                acc.stats.error_estimate
            );
        }
    }

    /// A scene `accurate` refused (the battery's theta = 0.01, rigid, f = 5): answered
    /// within its tolerance against FDM + two Richardson levels on 3200..12800 intervals
    /// (an independent discretisation).
    #[test]
    fn a_slender_scene_under_a_tip_force_is_answered() {
        let (ms, r, d) =
            slender_against_fdm_richardson(&Method::from_name("multiple-shooting", None).unwrap());
        println!(
            "theta 0.01 f 5: estimate {:.1e}, difference from fdm-richardson {d:.1e} (its estimate {:.1e}), {} evaluations",
            ms.stats.error_estimate, r.stats.error_estimate, ms.stats.evaluations
        );
        assert!(ms.stats.error_estimate <= ms.stats.tolerance);
        assert!(d <= ms.stats.tolerance + r.stats.error_estimate, "{d:e}");
    }
}
