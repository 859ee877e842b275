//! The load path from zero, followed through its folds: the one rule every method follows
//! where loading from zero is not monotone.
//!
//! Scaling the loads by `lambda` (tip force and fluid load, [`Loads::scaled`]), the
//! equilibria of the shot's tip angle `phi1` form the curve
//!
//! ```text
//! R(phi1, lambda) = phi(0) - pi/2 - m(0)/k = 0        [3.21, 3.22]
//! ```
//!
//! through the unloaded whisker at `lambda = 0`. Natural-parameter continuation in `lambda`
//! stops (or jumps to another equilibrium) where that curve turns back in `lambda`: a fold,
//! where the physical whisker would snap through. This module follows the curve by
//! pseudo-arclength ([`bvp_solvers::continuation::Arclength`]) from `(phi1_unloaded, 0)`, passing its folds
//! (located where `dR/dphi1 = 0`), to its **first arrival at full load** (`lambda = 1`,
//! located, then Newton at full accuracy): that equilibrium is the answer of every method
//! whose own load continuation stalled or ended past a fold (`dR/dphi1 <= 0` there: it is 1
//! on the unloaded whisker and vanishes only at folds, so an odd number of folds was passed
//! by jumps; an even number passed that way is not detected). The trace then goes on a
//! bounded distance (at most 100 steps, load scales in `[0, 2]`) to list the other
//! equilibria at full load on the same path.
//!
//! `dR/dphi1` comes from the shot's variational equations; `dR/dlambda` from a forward
//! difference in `lambda` (one more shot; the corrector only needs it approximately, and the
//! final Newton at `lambda = 1` uses the exact derivative).

use super::shooting::{
    find_branch, newton_tip_angle, polish_tip_angle, Found, Search, TipSolve, TipTarget,
};
use crate::equations::Sensitivities;
use crate::error::{ModelError, Result};
use crate::loads::Loads;
use crate::shot::{shoot, Integration};
use crate::solution::{LoadFold, LoadPath, PathEquilibrium};
use crate::whisker::Whisker;
use bvp_solvers::continuation::{locate, ArcControl, Arclength, Attempt, Curve, Predictor};
use std::cell::Cell;
use std::f64::consts::FRAC_PI_2;

/// Most other equilibria listed.
pub(crate) const MAX_OTHERS: usize = 3;
/// Steps followed past the arrival looking for other equilibria.
pub(crate) const AFTER_STEPS: usize = 100;
/// The range of load scales `[0, AFTER_LAMBDA]` the search past the arrival stays in.
const AFTER_LAMBDA: f64 = 2.0;
/// Step budget before the arrival.
const MAX_STEPS: usize = 2000;
/// Residual tolerance of the path's corrector (relative to `1 + |m0|/k`): the path only
/// guides to the arrival, which Newton then solves at full accuracy.
const PATH_TOL: f64 = 1e-7;
/// The shots' tolerance along the path (at most the method's own).
const PATH_RTOL: f64 = 1e-9;
/// Newton iterations of one corrector solve.
const MAX_CORRECT: usize = 12;
/// Forward-difference step in `lambda`.
const DLAMBDA: f64 = 1e-5;
/// Location tolerance of folds and arrivals along the chord.
const EVENT_TOL: f64 = 1e-9;

/// A point of the load path.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathPoint {
    /// `(phi1, lambda)`.
    u: [f64; 2],
    /// `(dR/dphi1, dR/dlambda)`.
    grad: [f64; 2],
    /// The base angle.
    phi0: f64,
    /// Corrector iterations.
    iterations: usize,
}

/// The curve `R(phi1, lambda) = 0` of one whisker and load case.
struct LoadCurve<'a> {
    whisker: &'a Whisker,
    loads: &'a Loads,
    integration: &'a Integration,
    method: &'static str,
    /// Right-hand-side evaluations spent.
    spent: Cell<usize>,
}

impl LoadCurve<'_> {
    /// `R`, its gradient and `(phi0, 1 + |m0|/k)` at `u`.
    fn eval(&self, u: [f64; 2]) -> Result<(f64, [f64; 2], f64, f64)> {
        let support = &self.whisker.support;
        let at = |lambda: f64, sens| {
            let s = shoot(
                self.whisker,
                &self.loads.scaled(lambda),
                u[0],
                sens,
                self.integration,
            )?;
            self.spent.set(self.spent.get() + s.evaluations);
            Ok::<_, ModelError>(s)
        };
        let shot = at(u[1], Sensitivities::TipAngle)?;
        let r = support.residual(shot.phi0, shot.m0);
        let nudged = at(u[1] + DLAMBDA, Sensitivities::None)?;
        let r_lambda = (support.residual(nudged.phi0, nudged.m0) - r) / DLAMBDA;
        let r_phi1 = support.residual_rate(shot.d_phi1.phi0, shot.d_phi1.m0);
        let scale = 1.0 + shot.m0.abs() * support.compliance();
        Ok((r, [r_phi1, r_lambda], shot.phi0, scale))
    }

    /// Newton on `R = 0, n . (u - p) = 0` from `p`.
    fn newton(&self, p: [f64; 2], n: [f64; 2], radius: f64) -> Result<PathPoint> {
        let mut u = p;
        let mut last = f64::NAN;
        for it in 0..MAX_CORRECT {
            let (r, g, phi0, scale) = self.eval(u)?;
            let c = n[0] * (u[0] - p[0]) + n[1] * (u[1] - p[1]);
            last = r.abs() / scale;
            if last <= PATH_TOL && c.abs() <= PATH_TOL {
                return Ok(PathPoint {
                    u,
                    grad: g,
                    phi0,
                    iterations: it,
                });
            }
            // the bordered Newton step [R'; n] du = [R; c]
            let Some(du) = bvp_solvers::dense::solve(&[g, n], &[r, c]) else {
                break;
            };
            u[0] -= du[0];
            u[1] -= du[1];
            if (u[0] - p[0]).hypot(u[1] - p[1]) > radius {
                break;
            }
        }
        Err(ModelError::NoConvergence {
            method: self.method,
            load_scale: u[1],
            iterations: MAX_CORRECT,
            residual: last,
        })
    }
}

impl Curve<2> for LoadCurve<'_> {
    type Point = PathPoint;
    type Error = ModelError;

    fn coords(&self, p: &PathPoint) -> [f64; 2] {
        p.u
    }

    fn correct(
        &self,
        _from: &PathPoint,
        p: [f64; 2],
        n: [f64; 2],
        radius: f64,
    ) -> Result<PathPoint> {
        self.newton(p, n, radius)
    }

    fn tangent(&self, p: &PathPoint, dir: &[f64; 2]) -> [f64; 2] {
        let (a, b) = (p.grad[0], p.grad[1]);
        let n = a.hypot(b);
        let t = [-b / n, a / n];
        if t[0] * dir[0] + t[1] * dir[1] < 0.0 {
            [-t[0], -t[1]]
        } else {
            t
        }
    }

    fn iterations(&self, p: &PathPoint) -> usize {
        p.iterations
    }
}

/// The equilibrium at full load between the path points `a` and `b` (on either side):
/// located on the path, then solved by Newton at full accuracy (`integration`) where that
/// resolves it, else kept at the path's own (the caller's solve polishes it at its
/// tolerance).
fn full_load(
    curve: &LoadCurve<'_>,
    (a, b): (&PathPoint, &PathPoint),
    integration: &Integration,
) -> Result<PathEquilibrium> {
    let side = (1.0 - a.u[1]).signum();
    let g = |q: &PathPoint| Ok::<f64, ModelError>((1.0 - q.u[1]) * side);
    let at = locate(curve, a, b, &g, EVENT_TOL)?;
    let (t, _) = newton_tip_angle(
        curve.whisker,
        curve.loads,
        integration,
        at.u[0],
        curve.method,
    );
    Ok(t.map_or(
        PathEquilibrium {
            phi1: at.u[0],
            phi0: at.phi0,
        },
        |t| PathEquilibrium {
            phi1: t.phi1,
            phi0: t.values.phi0,
        },
    ))
}

/// Follows the load path of `whisker` under `loads` from zero load through its folds to the
/// first arrival at full load, solved there by Newton on the tip angle at `integration`'s
/// accuracy; lists the folds passed and the other equilibria at full load further along.
/// Returns the path and the right-hand-side evaluations spent.
///
/// # Errors
/// [`ModelError::NoConvergence`] (with the load scale reached) when the path does not reach
/// full load within its step budget, turns back below zero load, or its corrector fails at
/// the smallest step; [`ModelError::Budget`] after `budget` right-hand-side evaluations.
pub(crate) fn follow(
    whisker: &Whisker,
    loads: &Loads,
    integration: &Integration,
    method: &'static str,
    budget: usize,
) -> Result<(LoadPath, usize)> {
    let loose = match integration {
        Integration::Dop853(d) => Integration::adaptive(d.rtol.max(PATH_RTOL)),
        other => other.clone(),
    };
    let curve = LoadCurve {
        whisker,
        loads,
        integration: &loose,
        method,
        spent: Cell::new(0),
    };
    let unloaded = whisker.phi_unloaded(loads.s1);
    let (_, grad, _, _) = curve.eval([unloaded, 0.0])?;
    let start = PathPoint {
        u: [unloaded, 0.0],
        grad,
        phi0: FRAC_PI_2,
        iterations: 0,
    };
    let ctl = ArcControl {
        initial: 0.05,
        max: 0.2,
        min: 1e-8,
        // the tangent predictor: the Hermite one's longer steps were measured to jump to
        // another equilibrium in one of the 300 scenes of the fold battery
        predictor: Predictor::Tangent,
        ..ArcControl::default()
    };
    let mut arc = Arclength::new(&curve, start, [0.0, 1.0], ctl);
    let mut folds = Vec::new();
    let mut arrival: Option<PathEquilibrium> = None;
    let mut others = Vec::new();
    let (mut steps, mut after) = (0, 0);
    let stalled = |lambda: f64, steps: usize| ModelError::NoConvergence {
        method,
        load_scale: lambda,
        iterations: steps,
        residual: f64::NAN,
    };
    for _ in 0..MAX_STEPS + AFTER_STEPS {
        if curve.spent.get() > budget {
            if arrival.is_some() {
                break;
            }
            return Err(ModelError::Budget {
                method,
                what: "right-hand-side evaluations on the load path",
                limit: budget,
            });
        }
        let lambda = arc.current().u[1];
        let far = !(0.0..=AFTER_LAMBDA).contains(&lambda);
        if arrival.is_some() && (others.len() >= MAX_OTHERS || after >= AFTER_STEPS || far) {
            break;
        }
        let (p, t) = match arc.attempt(&curve) {
            Attempt::Point(p, t) => (p, t),
            Attempt::Retry => continue,
            Attempt::Failed(e) if arrival.is_none() => return Err(e),
            Attempt::Failed(_) => break,
        };
        let cur = *arc.current();
        // a fold: the lambda-component of the oriented tangent changes sign
        if arrival.is_none() && (t[1] > 0.0) != (arc.tangent()[1] > 0.0) {
            let sign = cur.grad[0].signum();
            let g = |q: &PathPoint| Ok::<f64, ModelError>(q.grad[0] * sign);
            let at = locate(&curve, &cur, &p, &g, EVENT_TOL)?;
            folds.push(LoadFold {
                lambda: at.u[1],
                phi1: at.u[0],
                phi0: at.phi0,
            });
        }
        // a crossing of full load (either way)
        if (cur.u[1] - 1.0) * (p.u[1] - 1.0) <= 0.0 && p.u[1] != cur.u[1] {
            let eq = full_load(&curve, (&cur, &p), integration)?;
            match &arrival {
                None => arrival = Some(eq),
                Some(a) if (eq.phi1 - a.phi1).abs() > 1e-6 => others.push(eq),
                _ => {}
            }
        }
        if arrival.is_none() && p.u[1] < 0.0 {
            return Err(stalled(p.u[1], steps));
        }
        arc.accept(&curve, p, t);
        if arrival.is_some() {
            after += 1;
        } else {
            steps += 1;
        }
    }
    let Some(arrival) = arrival else {
        let at = arc.current().u[1];
        return Err(stalled(at, steps));
    };
    let path = LoadPath {
        folds,
        arrival,
        others,
        steps,
    };
    Ok((path, curve.spent.get()))
}

/// How [`find_branch_by_rule`] polishes the search's answer before judging it: Newton at
/// `integration` to `target`, also after a direct solve when `direct_too` (a search on
/// loose shots).
pub(crate) struct Polish<'a> {
    pub integration: &'a Integration,
    pub target: TipTarget,
    pub direct_too: bool,
}

/// [`find_branch`] by the rule every method follows where loading from zero is not
/// monotone, its answer polished ([`Polish`]): where the search stalled, its branch guard
/// met other equilibria (a jump it let through would land on one unnoticed: two branches
/// may share the tip angle and differ at the base), or its polished answer lies past a
/// fold (`dR/dphi1 <= 0`: it is 1 on the unloaded whisker and vanishes only at folds),
/// the load path is followed through its folds to its first arrival at full load
/// ([`super::load_path::follow`], solved there at `path_integration`), and the answer is
/// that arrival polished. A search out of its evaluation budget stays out of it. Where the
/// path cannot be followed, an unfolded answer of a search that only met other equilibria
/// stands (flagged by its branch jumps); otherwise the path's error (the caller's fallback
/// follows the rule by its own method).
pub(crate) fn find_branch_by_rule(
    whisker: &Whisker,
    loads: &Loads,
    search: &Search<'_>,
    polish: &Polish<'_>,
    path_integration: &Integration,
    method: &'static str,
    budget: usize,
) -> Result<(Found, Option<LoadPath>)> {
    let support = &whisker.support;
    let unfolded = |tip: &TipSolve| support.residual_rate(tip.sens.phi0, tip.sens.m0) > 0.0;
    // (a solved polish counts its own evaluations)
    let polished = |phi1: f64, start| {
        polish_tip_angle(
            whisker,
            loads,
            polish.integration,
            method,
            (phi1, start),
            &polish.target,
        )
        .0
    };
    let found = match find_branch(whisker, loads, search, method, budget) {
        Ok(found) if found.steps == 0 && !polish.direct_too => Ok(found),
        Ok(found) => polished(found.tip.phi1, found.tip.start).map(|mut tip| {
            tip.evaluations += found.tip.evaluations;
            tip.branch_jumps = found.tip.branch_jumps;
            Found {
                tip,
                steps: found.steps,
            }
        }),
        Err(e) => Err(e),
    };
    match found {
        Ok(found) if found.tip.branch_jumps == 0 && unfolded(&found.tip) => Ok((found, None)),
        Err(e @ ModelError::Budget { .. }) => Err(e),
        found => {
            let (path, spent) = match follow(whisker, loads, path_integration, method, budget) {
                Ok(p) => p,
                // an unfolded answer of a search that only met other equilibria stands
                // where the path cannot be followed (thin tips: shots too ill-conditioned
                // for the path's corrector); its branch jumps say so
                Err(_) if found.as_ref().is_ok_and(|f| unfolded(&f.tip)) => {
                    return found.map(|f| (f, None));
                }
                Err(e) => return Err(e),
            };
            let mut tip = polished(path.arrival.phi1, None)?;
            tip.evaluations += spent + found.as_ref().map_or(0, |f| f.tip.evaluations);
            tip.branch_jumps = found.map_or(0, |f| f.tip.branch_jumps);
            let steps = path.steps;
            Ok((Found { tip, steps }, Some(path)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{solve, Method, Scene, TipForce};

    /// A scene whose load path from zero folds (six times; found by a random search over the
    /// command line's parameter space): an elastic, pre-curved whisker under an
    /// angle-preserving tip force and a strong flow.
    fn folding() -> Scene {
        Scene::new(
            Whisker::new(
                0.7323434944791731,
                2.222275368972509,
                1.7358338258877062,
                0.7089498786012104,
            ),
            Loads::combined(
                TipForce::ap(18.79416057674968, -0.473166133066333),
                13.17037091699504,
                1.3236317660145445,
            ),
        )
    }

    /// `(R, dR/dphi1)` of a shot at `(phi1, lambda)` at tolerance 1e-12.
    fn residual_at(scene: &Scene, phi1: f64, lambda: f64) -> (f64, f64) {
        crate::shot::base_residual(&scene.whisker, &scene.loads, phi1, lambda, 1e-12).unwrap()
    }

    /// Every method follows the same path to the same equilibrium and says where it folded:
    /// the folds are true folds (an equilibrium where `dR/dphi1` vanishes, checked by an
    /// independent shot at 1e-12), the other equilibria at full load are equilibria and
    /// differ from the one returned, and `fdm-richardson` (its own grids, started on the
    /// path) agrees with `accurate` within their estimates.
    #[test]
    fn a_folding_load_path_is_followed_to_its_first_arrival_by_every_method() {
        let scene = folding();
        let acc = solve(&scene, &Method::accurate()).unwrap();
        let path = acc.load_path.clone().expect("the path folds");
        // an even number: the arrival has dR/dphi1 > 0 like the unloaded whisker
        let n = path.folds.len();
        assert!(n >= 2 && n.is_multiple_of(2), "{path:?}");
        for f in &path.folds {
            assert!(f.lambda > 0.0 && f.lambda < 1.0, "{f:?}");
            let (r, dr) = residual_at(&scene, f.phi1, f.lambda);
            // the slope dR/dphi1 ~ 1 on the unloaded whisker; at the fold it vanishes to
            // the path's accuracy
            assert!(
                r.abs() < 1e-6 && dr.abs() < 1e-2,
                "fold {f:?}: R {r:e}, dR {dr:e}"
            );
        }
        for e in &path.others {
            let (r, _) = residual_at(&scene, e.phi1, 1.0);
            assert!(r.abs() < 1e-9, "{e:?}: {r:e}");
            assert!((e.phi1 - path.arrival.phi1).abs() > 1e-6);
        }
        // the returned equilibrium is the arrival, past an even number of folds: dR/dphi1 > 0
        let (r, dr) = residual_at(&scene, path.arrival.phi1, 1.0);
        assert!(r.abs() < 1e-9 && dr > 0.0, "{r:e} {dr:e}");
        assert!((acc.tip.phi - path.arrival.phi1).abs() < 1e-9);
        let fdm = solve(&scene, &Method::FdmRichardson { n: 100 }).unwrap();
        assert!(fdm.load_path.is_some());
        let d = fdm.difference(&acc);
        assert!(
            d <= fdm.stats.error_estimate + acc.stats.error_estimate,
            "fdm-richardson {d:e} from accurate (estimates {:e}, {:e})",
            fdm.stats.error_estimate,
            acc.stats.error_estimate
        );
    }

    /// A monotone load path (a moderate tip force on a straight whisker) keeps the plain
    /// continuation: no load path is reported.
    #[test]
    fn a_monotone_load_path_reports_nothing() {
        let scene = Scene::new(
            Whisker::new(0.5, 0.0, 0.0, f64::INFINITY),
            Loads::tip(TipForce::dp(3.0, 0.0)),
        );
        let sol = solve(&scene, &Method::accurate()).unwrap();
        assert!(sol.load_path.is_none());
        assert!(sol.stats.branch_jumps == 0);
    }
}
