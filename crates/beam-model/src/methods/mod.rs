//! The three solution methods of the forward problem and their common entry point.
//!
//! | method | discretisation | order | thesis |
//! |---|---|---|---|
//! | [`Method::Fdm`] | central FDM [3.25, 3.27], Newton on the tridiagonal Jacobian | 2 | ch. 4 (its method) |
//! | [`Method::Rk4`] | RK4 shooting from the loaded end, exact Newton derivatives | 4 | ch. 4 (comparison) |
//! | [`Method::Accurate`] | adaptive DOP853 shooting from the loaded end | 8 | — |
//! | [`Method::MultipleShooting`] | DOP853 multiple shooting on `[0, s1]` with node insertion (`bvp_solvers::multiple_shooting`), from the FDM's branch; `accurate`'s last fallback | 8 | — |
//! | [`Method::Collocation`] | 3-point Lobatto IIIA collocation on `[0, s1]` with residual control and mesh refinement (`bvp_solvers::collocation`), its own load continuation from zero; `accurate`'s last fallback, `auto`'s rung for thin tips under tip forces | 4 | — |
//! | [`Method::Auto`] | the cheapest of: linear theory where its a-priori bound meets the tolerance, the spectral Picard iteration, a cheap shot, collocation where `sqrt(f)/theta >= 20` (DP, not pushing the tip), then `accurate` at the tolerance that suffices | spectral / 4 / 8 | — |

pub(crate) mod accurate;
pub(crate) mod collocation;
pub(crate) mod elastica;
pub(crate) mod fdm;
pub(crate) mod fixed;
pub(crate) mod global;
pub(crate) mod linear_rung;
pub(crate) mod load_path;
pub(crate) mod picard;
pub(crate) mod shooting;
#[cfg(test)]
mod test_scenes;
mod whisker_problem;

use crate::error::{ModelError, Result};
use crate::scene::Scene;
use crate::shot::Integration;
use crate::solution::{MethodKind, Solution};
use serde::{Deserialize, Serialize};

/// A solution method of the forward problem.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Method {
    /// Adaptive high-order shooting (DOP853) from the loaded end; `tol` is the integrator's
    /// relative and absolute tolerance, `samples` the number of elastica intervals returned.
    Accurate {
        /// Integrator tolerance (default 1e-12).
        tol: f64,
        /// Output intervals along the whisker (default 100).
        samples: usize,
    },
    /// Fixed-step RK4 shooting with step `1/n`.
    Rk4 {
        /// Steps per unit length.
        n: usize,
    },
    /// Finite differences with `n` intervals per unit length (the thesis's method).
    Fdm {
        /// Grid intervals per unit length.
        n: usize,
    },
    /// FDM on `n`, `2n`, `4n` intervals with two levels of Richardson extrapolation
    /// (order 6 in the tip, the loaded end and the base observables).
    FdmRichardson {
        /// Intervals of the coarsest grid per unit length.
        n: usize,
    },
    /// Multiple shooting on `[0, s1]` (module `global`): DOP853 with the variational
    /// equations on each segment, nodes inserted where a segment grows too much, from the
    /// FDM solution that loading from zero reaches; `tol` is the integrator tolerance, the
    /// estimate the difference from a second solve at `100 tol`. For slender whiskers under
    /// tip forces, where single shooting is ill-conditioned.
    MultipleShooting {
        /// Integrator tolerance (default 1e-12).
        tol: f64,
        /// Output intervals along the whisker (default 100).
        samples: usize,
    },
    /// Collocation on `[0, s1]` (module `collocation`: 3-point Lobatto IIIA with residual
    /// control and mesh refinement, `bvp_solvers::collocation::solve_bvp_problem`) with its
    /// own load continuation from zero load; `tol` is the accuracy asked for (absolute, as
    /// `auto`'s), the estimate the difference from a second solve at a residual 100 times
    /// smaller on the refined mesh. For slender whiskers under tip forces, where shooting
    /// is ill-conditioned and the FDM's continuation fails.
    Collocation {
        /// The accuracy asked for, in `[1e-12, 1e-2]` (default 1e-8).
        tol: f64,
        /// Output intervals along the whisker (default 100).
        samples: usize,
    },
    /// Accuracy on demand: the cheapest method whose a-posteriori estimate meets `tol`
    /// (absolute, the norm of [`SolveStats::error_estimate`](crate::SolveStats)). First
    /// linear small-deflection theory, where its a-priori bound (a closed-form contraction
    /// constant of the integral form) plus its grid estimate meets `tol`; then the spectral
    /// Picard iteration of the integral form (it contracts for weak and moderate loads);
    /// then `accurate` with the integrator tolerance that suffices (and its FDM +
    /// Richardson fallback); where the first shot fails on a thin tip under a
    /// direction-preserving tip force (`sqrt(f) / theta >=` [`COLLOCATION_GROWTH`], not
    /// pushing the tip: [`COLLOCATION_MIN_PULL`]),
    /// collocation ([`Method::Collocation`]) before the rest. `stats.model_used` says which
    /// model answered (`linear` or `elastica`), `stats.method_used` which method (`picard`
    /// for the first two rungs).
    Auto {
        /// The accuracy asked for, in `[1e-12, 1e-2]`.
        tol: f64,
        /// Output intervals along the whisker (default 100).
        samples: usize,
    },
}

impl Default for Method {
    fn default() -> Self {
        Method::accurate()
    }
}

/// The thesis's grid: h = 0.01.
pub const DEFAULT_INTERVALS: usize = 100;

/// Largest number of grid intervals (`fdm`, `rk4`) or output intervals (`accurate`) a
/// method accepts: bounds the memory of one solve (a few MB).
pub const MAX_INTERVALS: usize = 100_000;

/// Smallest `accurate` integrator tolerance (DOP853 needs `tol >~ 10 eps`, and the error
/// estimate integrates once more at `tol / 10`, floored at [`MIN_CHECK_TOL`]).
pub const MIN_TOL: f64 = 1e-14;

/// Tolerance floor of the check integration of `accurate`'s error estimate.
pub const MIN_CHECK_TOL: f64 = 2.5e-15;

/// `accurate` estimates its error by a second solution: its search shot at
/// `tolerance / 100` where that is at least 100 times `tol` (no extra shot), else one more
/// shot at `tol * CHECK_TOL_RATIO` (module `accurate`).
pub const CHECK_TOL_RATIO: f64 = 0.1;

/// The bound on the error estimate of the fixed-grid methods (`fdm`, `rk4`,
/// `fdm-richardson` on a user's grid): 5 %, twice the thesis's FDM-ANSYS discrepancy (2.55 %);
/// beyond it the numbers are not the thesis's model.
pub const FIXED_GRID_TOLERANCE: f64 = 5e-2;

/// Right-hand-side evaluations `accurate`'s shooting may spend before it falls back to FDM
/// with Richardson extrapolation (single shooting is ill-conditioned for thin tips under
/// large loads and then needs many continuation steps).
pub const SHOOTING_BUDGET: usize = 300_000;

/// Right-hand-side evaluations the `rk4` continuation may spend (a few seconds at most).
pub const RK4_BUDGET: usize = 20_000_000;

/// Largest difference (tip, loaded end, base observables) between the FDM solutions on `n`
/// and `2n` intervals, each reached by its own continuation from zero load, for them to count
/// as the same equilibrium: same-branch solutions differ by the discretisation error (the
/// fixed-grid tolerance at most), another branch by O(0.1..1).
pub const BRANCH_AGREEMENT: f64 = FIXED_GRID_TOLERANCE;

/// Finest grid (intervals of `[0, 1]`) of `accurate`'s FDM + Richardson fallback.
pub const MAX_FALLBACK_INTERVALS: usize = 102_400;

impl Method {
    /// `accurate` with tolerance 1e-12 and 100 output intervals.
    pub fn accurate() -> Self {
        Method::Accurate {
            tol: 1e-12,
            samples: DEFAULT_INTERVALS,
        }
    }

    /// The method's name as used by the CLI (`accurate`, `rk4`, `fdm`).
    pub fn name(&self) -> &'static str {
        match self {
            Method::Accurate { .. } => "accurate",
            Method::Rk4 { .. } => "rk4",
            Method::Fdm { .. } => "fdm",
            Method::FdmRichardson { .. } => "fdm-richardson",
            Method::Auto { .. } => "auto",
            Method::MultipleShooting { .. } => "multiple-shooting",
            Method::Collocation { .. } => "collocation",
        }
    }

    /// Grid intervals (fixed-step methods) or output intervals (`accurate`).
    pub fn intervals(&self) -> usize {
        match *self {
            Method::Accurate { samples, .. }
            | Method::Auto { samples, .. }
            | Method::MultipleShooting { samples, .. }
            | Method::Collocation { samples, .. } => samples,
            Method::Rk4 { n } | Method::Fdm { n } | Method::FdmRichardson { n } => n,
        }
    }

    /// A method by name with an optional number of intervals (default 100).
    pub fn from_name(name: &str, n: Option<usize>) -> Option<Method> {
        let n = n.unwrap_or(DEFAULT_INTERVALS);
        match name {
            "accurate" => Some(Method::Accurate {
                tol: 1e-12,
                samples: n,
            }),
            "rk4" => Some(Method::Rk4 { n }),
            "fdm" => Some(Method::Fdm { n }),
            "fdm-richardson" => Some(Method::FdmRichardson { n }),
            "multiple-shooting" => Some(Method::MultipleShooting {
                tol: 1e-12,
                samples: n,
            }),
            "collocation" => Some(Method::Collocation {
                tol: DEFAULT_AUTO_TOL,
                samples: n,
            }),
            "auto" => Some(Method::Auto {
                tol: DEFAULT_AUTO_TOL,
                samples: n,
            }),
            _ => None,
        }
    }

    /// The kind of this method, as reported in [`SolveStats::method_used`](crate::SolveStats).
    pub fn kind(&self) -> MethodKind {
        match self {
            Method::Accurate { .. } => MethodKind::Accurate,
            Method::Rk4 { .. } => MethodKind::Rk4,
            Method::Fdm { .. } => MethodKind::Fdm,
            Method::FdmRichardson { .. } => MethodKind::FdmRichardson,
            Method::Auto { .. } => MethodKind::Auto,
            Method::MultipleShooting { .. } => MethodKind::MultipleShooting,
            Method::Collocation { .. } => MethodKind::Collocation,
        }
    }

    /// The accuracy a solve must reach: its a-posteriori error estimate
    /// ([`SolveStats::error_estimate`](crate::SolveStats)) is checked against this bound.
    /// `accurate`: `max(1e4 tol, 1e-10)` (1e-8 at the default tol 1e-12); the fixed-grid
    /// methods promise their discretisation, not an accuracy, and are refused only beyond
    /// [`FIXED_GRID_TOLERANCE`].
    pub fn tolerance(&self) -> f64 {
        match *self {
            Method::Accurate { tol, .. } | Method::MultipleShooting { tol, .. } => {
                (1e4 * tol).max(1e-10)
            }
            Method::Auto { tol, .. } | Method::Collocation { tol, .. } => tol,
            _ => FIXED_GRID_TOLERANCE,
        }
    }

    fn validate(&self) -> Result<()> {
        let n = self.intervals();
        let max = match self {
            Method::FdmRichardson { .. } => MAX_INTERVALS / 4,
            _ => MAX_INTERVALS,
        };
        if n > max {
            return Err(ModelError::InvalidParameter {
                name: "n",
                value: n as f64,
                reason: "at most 100000 grid or output intervals (25000 for fdm-richardson, which also solves on 4n)",
            });
        }

        let n = self.intervals();
        if n < 4 {
            return Err(ModelError::InvalidParameter {
                name: "n",
                value: n as f64,
                reason: "at least 4 grid intervals are needed",
            });
        }
        if let Method::Auto { tol, .. } | Method::Collocation { tol, .. } = *self {
            if !(1e-12..=1e-2).contains(&tol) {
                return Err(ModelError::InvalidParameter {
                    name: "tol",
                    value: tol,
                    reason: "the accuracy asked for must be in [1e-12, 1e-2]",
                });
            }
        }
        if let Method::Accurate { tol, .. } | Method::MultipleShooting { tol, .. } = *self {
            if !(MIN_TOL..=1e-2).contains(&tol) {
                return Err(ModelError::InvalidParameter {
                    name: "tol",
                    value: tol,
                    reason: "the integrator tolerance must be in [1e-14, 1e-2]",
                });
            }
        }
        Ok(())
    }
}

/// Solves a scene with a method: the elastica [3.25] with its boundary conditions
/// [3.21, 3.22], on the equilibrium branch reached by loading from zero (load continuation
/// with a branch guard where the direct solve is not near-linear).
///
/// Every solution carries an a-posteriori error estimate (see [`SolveStats`](crate::SolveStats))
/// checked against [`Method::tolerance`]. `accurate` shoots with DOP853; where shooting fails,
/// exceeds [`SHOOTING_BUDGET`] or its estimate exceeds the tolerance (thin tips under large
/// loads), it falls back to FDM + Richardson on grids refined until the estimate meets the
/// tolerance; `stats.method_used` then says `fdm-richardson`.
///
/// # Errors
/// [`ModelError::InvalidParameter`] for a scene or method out of range;
/// [`ModelError::Inaccurate`] when the estimate exceeds the tolerance; the solver's failure
/// otherwise.
pub fn solve(scene: &Scene, method: &Method) -> Result<Solution> {
    scene.validate()?;
    method.validate()?;
    let scene = &scene.normalised();
    let tolerance = method.tolerance();
    let mut sol = match *method {
        Method::Accurate { tol, samples } => accurate(scene, tol, samples, tolerance, true)?,
        Method::Rk4 { n } => {
            let mut sol = fixed::solve(scene, &Integration::Rk4 { n }, n, "rk4", RK4_BUDGET)?;
            let fine = Integration::Rk4 {
                n: n.saturating_mul(2),
            };
            let (est, ev) = shooting::error_estimate(scene, &sol, &fine)?;
            // RK4 is of order 4: the error of the n-step solution is 16/15 of its
            // difference from the 2n-step one.
            sol.stats.error_estimate = est * 16.0 / 15.0;
            sol.stats.evaluations += ev;
            sol.stats.method_used = MethodKind::Rk4;
            sol
        }
        Method::Fdm { n } => {
            let (mut sol, y) = fdm::solve_from(scene, n, None)?;
            let fine_n = n.saturating_mul(2);
            let guess = prolong(&y, fdm::intervals(fine_n, scene.loads.s1));
            let (fine, _) = fdm::solve_from(scene, fine_n, Some(&guess))?;
            // Order 2: the error of the n-grid solution is 4/3 of its difference from 2n.
            sol.stats.error_estimate = sol.difference(&fine) * 4.0 / 3.0;
            sol.stats.evaluations += fine.stats.evaluations;
            sol
        }
        Method::FdmRichardson { n } => fdm_richardson_on(scene, n)?,
        Method::Auto { tol, samples } => auto(scene, tol, samples)?,
        Method::MultipleShooting { tol, samples } => {
            let n0 = ((2.0 / scene.whisker.theta).ceil() as usize).max(100);
            let (guess, _) = fdm::solve_from(scene, n0, None)?;
            let mut sol = global::solve(scene, tol, samples, &guess)?;
            sol.stats.evaluations += guess.stats.evaluations;
            sol.stats.continuation_steps = guess.stats.continuation_steps;
            sol
        }
        Method::Collocation { tol, samples } => collocation::solve(scene, tol, samples)?,
    };
    sol.stats.requested = method.kind();
    sol.stats.tolerance = tolerance;
    check_estimate(scene, &sol)?;
    Ok(sol)
}

/// Refuses a solution whose error estimate is not within its tolerance (NaN included).
fn check_estimate(scene: &Scene, sol: &Solution) -> Result<()> {
    let est = sol.stats.error_estimate;
    if est <= sol.stats.tolerance {
        return Ok(());
    }
    Err(ModelError::Inaccurate {
        method: sol.stats.method_used.name(),
        estimate: est,
        tolerance: sol.stats.tolerance,
        theta: scene.whisker.theta,
        hint: match sol.stats.requested {
            MethodKind::Accurate => "the tip boundary layer is not resolved within the budgets",
            _ => "use a finer grid (--n) or the accurate method",
        },
    })
}

/// `accurate`: DOP853 shooting with an independent estimate (a second solution at
/// `tolerance / 100`, or a second shot at `tol * CHECK_TOL_RATIO`);
/// the FDM + Richardson fallback where shooting fails or does not meet `tolerance`; then
/// multiple shooting and, with `collocation` (false where `auto` has tried it already),
/// collocation.
fn accurate(
    scene: &Scene,
    tol: f64,
    samples: usize,
    tolerance: f64,
    collocation: bool,
) -> Result<Solution> {
    let check_tol = (tol * CHECK_TOL_RATIO).max(MIN_CHECK_TOL);
    let shot = accurate::solve_accurate(
        scene,
        &accurate::Accurate {
            tol,
            check_tol,
            tolerance,
            samples,
            budget: SHOOTING_BUDGET,
            search_tol: None,
            loosest_tol: tol,
        },
    );
    let shooting_evaluations = match &shot {
        Ok(sol) if sol.stats.error_estimate <= tolerance => return shot,
        Ok(sol) => sol.stats.evaluations,
        Err(_) => 0,
    };
    let fallback = fdm_richardson_adaptive(scene, tolerance);
    // Where FDM + Richardson does not meet the tolerance either: multiple shooting from the
    // best solution at hand (the fallback's, else the shot's, else the FDM by continuation)
    let refused = match &fallback {
        Ok(sol) => sol.stats.error_estimate.is_nan() || sol.stats.error_estimate > tolerance,
        Err(_) => true,
    };
    if refused {
        if let Ok(mut sol) = multiple_shooting_fallback(scene, tol, samples, &shot, &fallback) {
            if sol.stats.error_estimate <= tolerance {
                sol.stats.evaluations += shooting_evaluations;
                return Ok(sol);
            }
        }
        // last: collocation, which needs no start (its own load continuation from zero);
        // not under a tip force pushing along the thin tip, where its branch guard can land
        // on a looped equilibrium ([`COLLOCATION_MIN_PULL`]): such a scene is refused
        if collocation && !pushes_the_tip(scene) {
            if let Ok(mut sol) = collocation::solve(scene, tolerance, samples) {
                if sol.stats.error_estimate <= tolerance {
                    sol.stats.evaluations += shooting_evaluations;
                    return Ok(sol);
                }
            }
        }
    }
    // Single shooting is ill-conditioned for thin tips under large loads (the linearised
    // equation grows like exp(sqrt(f)/theta^2) near the tip): fall back to the globally
    // discretised FDM with Richardson extrapolation, refined until its estimate meets the
    // tolerance.
    let mut sol = match fallback {
        Ok(sol) => sol,
        // nothing better: report the shooting failure (or its too large estimate)
        Err(e) => {
            return match shot {
                Ok(sol) => Err(ModelError::Inaccurate {
                    method: "accurate",
                    estimate: sol.stats.error_estimate,
                    tolerance,
                    theta: scene.whisker.theta,
                    hint: "the fdm-richardson fallback failed as well",
                }),
                Err(_) => Err(e.in_method("accurate (fdm-richardson fallback)")),
            }
        }
    };
    sol.stats.evaluations += shooting_evaluations;
    Ok(sol)
}

/// `accurate`'s last fallback: multiple shooting ([`Method::MultipleShooting`]) at the
/// integrator tolerance `tol` from the FDM + Richardson answer (refused), else the shot's,
/// else the FDM on `max(100, 2/theta)` intervals by continuation from zero load.
fn multiple_shooting_fallback(
    scene: &Scene,
    tol: f64,
    samples: usize,
    shot: &Result<Solution>,
    fallback: &Result<Solution>,
) -> Result<Solution> {
    let fdm_guess;
    let guess = match (fallback, shot) {
        (Ok(sol), _) | (Err(_), Ok(sol)) => sol,
        (Err(_), Err(_)) => {
            let n0 = ((2.0 / scene.whisker.theta).ceil() as usize).max(100);
            fdm_guess = fdm::solve_from(scene, n0, None)?.0;
            &fdm_guess
        }
    };
    let mut sol = global::solve(scene, tol.max(MIN_TOL), samples, guess)?;
    sol.stats.evaluations += guess.stats.evaluations;
    Ok(sol)
}

/// The largest linear-theory rotation (rad, of the base or the loaded end; the quadrature on
/// 16 intervals, within a few per cent) at which `auto` tries the Picard iteration: it contracts only under moderate deflection (measured over
/// 7990 random `auto` solves of the command line's space, it answered none whose rotation
/// exceeded 3.14); beyond, its failed attempt was ~15 % of the shooting that answers.
pub const PICARD_ROTATION: f64 = 4.0;

/// The loosest dense shot of `auto`'s shooting: a tenth of the accuracy asked for, where
/// the scene's resolution floor leaves room for it (module `accurate`, `dense_tol`);
/// else as tight as a hundredth.
pub const AUTO_DENSE_MARGIN: f64 = 10.0;

/// The default accuracy of `--method auto` (the default `accurate`'s tolerance).
pub const DEFAULT_AUTO_TOL: f64 = 1e-8;

/// The growth exponent `sqrt(f) / theta` of a direction-preserving tip force from which
/// `auto` tries collocation ([`Method::Collocation`]) where its cheap shot failed, before
/// the tight shot and the fallbacks. The linearised elastica [3.25] near the loaded end,
/// `m'' = f m / e(s)^4`, has modes growing like `exp(sqrt(f) integral of ds / e(s)^2)`,
/// and with the taper `e(s) = 1 - (1 - theta) s` [3.8] that integral over `[0, 1]` is
/// exactly `1 / theta`: single shooting integrates through `exp(sqrt(f) / theta)`, and
/// the FDM's uniform grids must resolve a boundary layer of width `theta^2 / sqrt(f)`.
/// Measured (`docs/bvp-auto.md`, `tests/colloc.rs`, 108 tip-force scenes at `1e-8`): every
/// direction-preserving scene from 20 up whose cheap shot failed went to FDM + Richardson or
/// multiple shooting (0.13-0.8 s), where collocation answered in 0.002-0.065 s.
pub const COLLOCATION_GROWTH: f64 = 20.0;

/// Smallest `cos(phi_unloaded(s1) + beta)` of a direction-preserving tip force for
/// `auto`'s collocation rung: `m' = f sin(phi + beta)` [3.25] pulls the tip along itself
/// where this is positive and pushes it where negative. Under a push the thin tip passes
/// many of its buckling loads (the phase of the linearised tip, `sqrt(f) / theta`, counts
/// them in units of `pi`), and collocation's branch guard, which leaves the tip's angle out
/// (module `collocation`), can arrive on a looped equilibrium: measured on theta 0.03,
/// rigid, `f = 10` at 90 degrees with `q = 10` at -30 degrees, a tip angle `2 pi` from the
/// FDM's continuation (which guards every node). Such scenes keep the old chain.
pub const COLLOCATION_MIN_PULL: f64 = -0.25;

/// A direction-preserving tip force that pushes along the unloaded tip
/// (`cos(phi_unloaded(s1) + beta) <` [`COLLOCATION_MIN_PULL`]): collocation is not trusted
/// there, neither as `auto`'s rung nor as `accurate`'s last fallback (measured: a tip angle
/// `2 pi` off under an estimate of 3.0e-9 on theta 0.03, and an unverified answer on
/// theta 0.01; `docs/bvp-auto.md`).
fn pushes_the_tip(scene: &Scene) -> bool {
    let tip = &scene.loads.tip;
    tip.kind == crate::loads::LoadKind::Dp
        && tip.f > 0.0
        && (scene.whisker.phi_unloaded(scene.loads.s1) + tip.beta).cos() < COLLOCATION_MIN_PULL
}

/// `auto`'s collocation rung applies: a direction-preserving tip force (an angle-preserving
/// one curls a thin tip into a spiral where collocation's continuation needs seconds or
/// fails, while shooting answers from `theta = 0.015` up) that does not push the unloaded
/// tip ([`COLLOCATION_MIN_PULL`]) and whose growth exponent `sqrt(f) / theta` is at least
/// [`COLLOCATION_GROWTH`]. A rule on the scene's numbers, no solve.
pub(crate) fn collocation_first(scene: &Scene) -> bool {
    let tip = &scene.loads.tip;
    let pull = (scene.whisker.phi_unloaded(scene.loads.s1) + tip.beta).cos();
    tip.kind == crate::loads::LoadKind::Dp
        && tip.f > 0.0
        && pull >= COLLOCATION_MIN_PULL
        && tip.f.sqrt() / scene.whisker.theta >= COLLOCATION_GROWTH
}

/// `auto`: linear theory where its a-priori bound proves it meets `tol` (module
/// `linear_rung`: one application of the integral map per grid, cheaper than any other
/// rung; `stats.model_used` linear), else the spectral Picard iteration where it
/// contracts, else `accurate` with stage 2
/// at the asked accuracy `tol` (its shot the estimate's second solution) and the dense
/// shot at `tol / 10` where the scene's resolution floor leaves room (else tighter, down
/// to `tol / 100`), again at `tol / 100` where that estimate does not meet `tol`; where
/// that one does not either, collocation where [`collocation_first`] (its own estimate
/// against `tol`), else or then `accurate` at `1e-4 tol`
/// (at most 1e-12; the estimate's tolerance floored at 1e-10). Measured against the lower
/// envelope of every method's work-precision curve (`cargo xtask reproduce chapter4`) and
/// for its honesty over 1000 random scenes (`tests/auto.rs`: the estimate bounds every
/// error, the worst at 0.56 of it).
fn auto(scene: &Scene, tol: f64, samples: usize) -> Result<Solution> {
    let (base, tip) = crate::linear::rotations_on::<16>(&scene.whisker, &scene.loads);
    let rotation = base.abs().max(tip.abs());
    if let Some(sol) = linear_rung::solve(scene, tol, samples, rotation) {
        return Ok(sol);
    }
    if rotation <= PICARD_ROTATION {
        if let Ok(sol) = picard::solve(scene, tol, samples) {
            return Ok(sol);
        }
    }
    // Shooting with the estimate's second solution from stage 2's shot at `tol` itself
    // and the dense shot ten to a hundred times tighter; where that estimate does not meet
    // `tol`, the tight scheme (the dense shot at 1e-12 or below).
    let margin = accurate::ESTIMATE_MARGIN;
    let itol = (tol / margin).max(MIN_TOL);
    let cheap = accurate::solve_accurate(
        scene,
        &accurate::Accurate {
            tol: itol,
            check_tol: (itol * CHECK_TOL_RATIO).max(MIN_CHECK_TOL),
            tolerance: tol,
            samples,
            budget: SHOOTING_BUDGET,
            search_tol: Some(tol),
            loosest_tol: (tol / AUTO_DENSE_MARGIN).max(itol),
        },
    );
    let mut sol = match cheap {
        Ok(sol) if sol.stats.error_estimate <= tol => sol,
        cheap => {
            let mut spent = cheap.map_or(0, |s| s.stats.evaluations);
            // Where the cheap shot failed on a thin tip under a direction-preserving tip
            // force: collocation, before the tight shot, the FDM's ladder and multiple
            // shooting (measured 5-100 times cheaper there, `docs/bvp-auto.md`)
            let tried_collocation = collocation_first(scene);
            if tried_collocation {
                match collocation::solve(scene, tol, samples) {
                    Ok(mut sol) if sol.stats.error_estimate <= tol => {
                        sol.stats.evaluations += spent;
                        sol.stats.tolerance = tol;
                        return Ok(sol);
                    }
                    Ok(sol) => spent += sol.stats.evaluations,
                    Err(_) => {}
                }
            }
            let itol = (tol * 1e-4).clamp(MIN_TOL, 1e-12);
            let mut sol = accurate(scene, itol, samples, tol.max(1e-10), !tried_collocation)?;
            sol.stats.evaluations += spent;
            sol
        }
    };
    if sol.stats.error_estimate > tol {
        return Err(ModelError::Inaccurate {
            method: "auto",
            estimate: sol.stats.error_estimate,
            tolerance: tol,
            theta: scene.whisker.theta,
            hint: "no method reaches this accuracy here (shooting's floor is about 1e-10)",
        });
    }
    sol.stats.tolerance = tol;
    Ok(sol)
}

/// Linear interpolation of nodal values on a uniform grid onto a uniform grid of the same
/// interval with `intervals` intervals (a warm start for a finer FDM grid).
fn prolong(y: &[f64], intervals: usize) -> Vec<f64> {
    let nc = y.len().saturating_sub(1);
    if nc == 0 {
        return vec![y.first().copied().unwrap_or(0.0); intervals + 1];
    }
    (0..=intervals)
        .map(|i| {
            let t = i as f64 * nc as f64 / intervals as f64;
            let j = (t.floor() as usize).min(nc - 1);
            let w = t - j as f64;
            (1.0 - w) * y[j] + w * y[j + 1]
        })
        .collect()
}

/// The solution of a scene whose tip angle `phi1` is already known (e.g. from a contact
/// solve): one DOP853 integration at tolerance `tol` from the loaded end, `samples` output
/// intervals, no check of the base condition (the caller has solved it).
pub fn shape_from_tip_angle(
    scene: &Scene,
    phi1: f64,
    tol: f64,
    samples: usize,
) -> Result<Solution> {
    scene.validate()?;
    Method::Accurate { tol, samples }.validate()?;
    elastica::shape(
        &scene.normalised(),
        phi1,
        &crate::shot::Integration::adaptive(tol),
        samples,
        crate::solution::SolveStats {
            method_used: MethodKind::Shape,
            requested: MethodKind::Shape,
            ..Default::default()
        },
        "accurate",
    )
}

/// FDM on `n, 2n, 4n` intervals (`n = max(200, 40/theta)`, fine enough to resolve a thin tip)
/// with two levels of Richardson extrapolation (the central scheme and the trapezoidal
/// positions expand in even powers of h: order 2 -> 6) of the tip, the loaded end and the
/// base observables; the elastica is the finest grid's. `stats.error_estimate` holds the
/// extrapolation's error estimate.
pub fn fdm_richardson(scene: &Scene) -> Result<Solution> {
    scene.validate()?;
    let n0 = ((40.0 / scene.whisker.theta).ceil() as usize).clamp(200, MAX_INTERVALS / 4);
    let mut sol = fdm_richardson_on(&scene.normalised(), n0)?;
    sol.stats.requested = MethodKind::FdmRichardson;
    sol.stats.tolerance = FIXED_GRID_TOLERANCE;
    check_estimate(scene, &sol)?;
    Ok(sol)
}

/// FDM solutions on `n0 2^j`, the first by continuation from zero load, each next one
/// warm-started from the previous one interpolated (no second continuation).
struct GridLadder<'a> {
    scene: &'a Scene,
    levels: Vec<(Solution, Vec<f64>)>,
    n: usize,
}

impl<'a> GridLadder<'a> {
    /// The grids `n0` and `2 n0`, each solved by its own continuation from zero load: on a
    /// grid that does not resolve the tip's boundary layer the discrete load path can reach
    /// another equilibrium than the continuous one, and two grids that disagree by more than
    /// [`BRANCH_AGREEMENT`] expose it ([`ModelError::BranchAmbiguous`]).
    fn new(scene: &'a Scene, n0: usize, method: &'static str) -> Result<Self> {
        let mut first = fdm::solve_from(scene, n0, None)?;
        let mut second = fdm::solve_from(scene, n0.saturating_mul(2), None)?;
        // where one grid's load path decided (a fold), the other follows the same path
        match (&first.0.load_path, &second.0.load_path) {
            (Some(p), None) => second = fdm::solve_on_path(scene, n0.saturating_mul(2), p)?,
            (None, Some(p)) => first = fdm::solve_on_path(scene, n0, p)?,
            _ => {}
        }
        let distance = first.0.difference(&second.0);
        // NaN counts as a disagreement
        if distance.is_nan() || distance > BRANCH_AGREEMENT {
            return Err(ModelError::BranchAmbiguous {
                method,
                n: n0,
                distance,
            });
        }
        Ok(GridLadder {
            scene,
            levels: vec![first, second],
            n: n0.saturating_mul(2),
        })
    }

    fn refine(&mut self) -> Result<()> {
        let n = self.n.saturating_mul(2);
        let guess = self
            .levels
            .last()
            .map(|(_, y)| prolong(y, fdm::intervals(n, self.scene.loads.s1)));
        self.levels
            .push(fdm::solve_from(self.scene, n, guess.as_deref())?);
        self.n = n;
        Ok(())
    }

    /// Richardson extrapolation (two levels, order 2 -> 6) of the last three grids.
    fn extrapolate(&self) -> Result<Solution> {
        let k = self.levels.len();
        let sols = [
            &self.levels[k - 3].0,
            &self.levels[k - 2].0,
            &self.levels[k - 1].0,
        ];
        let mut best = sols[2].clone();
        let mut err: f64 = 0.0;
        let mut set = |slot: &mut f64, get: &dyn Fn(&Solution) -> f64| -> Result<()> {
            let v: Vec<f64> = sols.iter().map(|s| get(s)).collect();
            let e = bvp_solvers::richardson::richardson(&v, 2, 2)?;
            *slot = e.value;
            err = if e.error_estimate.is_nan() {
                f64::NAN
            } else {
                err.max(e.error_estimate.abs())
            };
            Ok(())
        };
        set(&mut best.tip.x, &|s| s.tip.x)?;
        set(&mut best.tip.y, &|s| s.tip.y)?;
        set(&mut best.tip.phi, &|s| s.tip.phi)?;
        set(&mut best.loaded_end.x, &|s| s.loaded_end.x)?;
        set(&mut best.loaded_end.y, &|s| s.loaded_end.y)?;
        set(&mut best.loaded_end.phi, &|s| s.loaded_end.phi)?;
        set(&mut best.base.ma, &|s| s.base.ma)?;
        set(&mut best.base.phi0, &|s| s.base.phi0)?;
        let (ax, ay) = self.scene.base_reactions(best.loaded_end.phi);
        best.base.ax = ax;
        best.base.ay = ay;
        // the extrapolated phi1 moves an AP force's reactions by up to f |dphi1|
        best.stats.error_estimate = err * (1.0 + self.scene.loads.tip.f);
        best.stats.residual = sols[2].stats.residual;
        best.stats.evaluations = self.levels.iter().map(|(s, _)| s.stats.evaluations).sum();
        best.stats.continuation_steps = self.levels[0].0.stats.continuation_steps;
        best.stats.branch_jumps = self.levels[0].0.stats.branch_jumps;
        best.load_path = self.levels[0].0.load_path.clone();
        best.stats.method_used = MethodKind::FdmRichardson;
        Ok(best)
    }
}

/// FDM with two Richardson levels from a coarsest grid of `n0` intervals per unit length
/// (method [`Method::FdmRichardson`]).
fn fdm_richardson_on(scene: &Scene, n0: usize) -> Result<Solution> {
    let mut ladder = GridLadder::new(scene, n0, "fdm-richardson")?;
    ladder.refine()?;
    ladder.extrapolate()
}

/// `accurate`'s fallback: FDM + Richardson on the last three of the grids `n0 2^j`
/// (`n0 = max(100, 2/theta)`: two nodes across the tip's boundary layer), the first two by
/// independent continuations from zero load that must reach the same equilibrium (else
/// `n0` is doubled, up to a quarter of [`MAX_FALLBACK_INTERVALS`]), adding grids until the
/// extrapolation's estimate meets `tolerance` or the finest grid reaches
/// [`MAX_FALLBACK_INTERVALS`].
fn fdm_richardson_adaptive(scene: &Scene, tolerance: f64) -> Result<Solution> {
    let mut n0 = ((2.0 / scene.whisker.theta).ceil() as usize).max(100);
    let mut ladder = loop {
        match GridLadder::new(scene, n0, "fdm-richardson") {
            Err(ModelError::BranchAmbiguous { .. }) if 8 * n0 <= MAX_FALLBACK_INTERVALS => {
                n0 *= 2;
            }
            other => break other?,
        }
    };
    ladder.refine()?;
    loop {
        let sol = ladder.extrapolate()?;
        if sol.stats.error_estimate <= tolerance
            || ladder.n.saturating_mul(2) > MAX_FALLBACK_INTERVALS
        {
            return Ok(sol);
        }
        ladder.refine()?;
    }
}
