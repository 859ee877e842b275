//! The elastica, tip and observables for a solved tip angle: one dense shot from the loaded
//! end (no iteration), sampled along the whisker, and the load-free segment beyond `s1`.
//! `accurate` takes the shot with the tip-angle sensitivities and moves everything by that
//! shot's own Newton step ([`linearised_shape`]); the other methods and the contact phases
//! take the plain shot ([`shape`]).

use crate::equations::{FreeSegment, Sensitivities};
use crate::error::{ModelError, Result};
use crate::scene::Scene;
use crate::shot::{shoot_path, BaseValues, Integration, Shot, ShotPath};
use crate::solution::{BaseObservables, Elastica, EndState, Solution, SolveStats};
use crate::whisker::Whisker;
use bvp_solvers::integrator::{OdeSolution, Rk4, StepInterpolant};

/// The elastica, tip and observables for a known tip angle `phi1` (one integration from
/// the loaded end, no iteration): used once the boundary conditions are solved, by the
/// shooting methods and by the contact phases.
pub(crate) fn shape(
    scene: &Scene,
    phi1: f64,
    integration: &Integration,
    samples: usize,
    stats: SolveStats,
    method: &'static str,
) -> Result<Solution> {
    let (w, loads) = (&scene.whisker, &scene.loads);
    let (shot, path) = shoot_path(w, loads, phi1, Sensitivities::None, integration, true)?;
    let run = Run {
        integration,
        samples,
        method,
        budget: 0,
    };
    assemble(scene, &run, &Moved::plain(phi1, shot, path), stats)
}

/// [`shape`] from one dense shot at `phi1` with the tip-angle sensitivities, moved by that
/// shot's Newton step `d = -R / R'` on the base condition [3.21, 3.22] to its own root
/// `phi1 + d` (the base values, the loaded end and every sample of the elastica along their
/// sensitivities: exact to first order, an error `O(d^2)`), unless the step is not finite
/// or `accept(d, sens)` refuses it.
pub(crate) fn linearised_shape(
    scene: &Scene,
    phi1: f64,
    run: &Run<'_>,
    stats: SolveStats,
    accept: impl Fn(f64, &BaseValues) -> bool,
) -> Result<Linearised> {
    let (w, loads) = (&scene.whisker, &scene.loads);
    let sens = Sensitivities::TipAngle;
    let (shot, path) = shoot_path(w, loads, phi1, sens, run.integration, true)?;
    let d = -w.support.residual(shot.phi0, shot.m0)
        / w.support.residual_rate(shot.d_phi1.phi0, shot.d_phi1.m0);
    if !(d.is_finite() && accept(d, &shot.d_phi1)) {
        return Ok(Linearised::Far {
            d,
            sens: shot.d_phi1,
            evaluations: shot.evaluations,
        });
    }
    let sens = shot.d_phi1;
    let steps = match &path {
        Some(ShotPath::Dense(sol)) => sol.steps(),
        Some(ShotPath::Fixed(traj)) => traj.len().saturating_sub(1),
        None => 0,
    };
    let moved = Moved {
        phi1,
        d,
        shot,
        path,
    };
    let sol = assemble(scene, run, &moved, stats)?;
    Ok(Linearised::Root {
        sol: Box::new(sol),
        sens,
        steps,
    })
}

/// What [`linearised_shape`] gives.
pub(crate) enum Linearised {
    /// The solution at the shot's root, with the shot's sensitivities
    /// `d(phi0, m0, dx, dy)/dphi1` and its accepted integration steps.
    Root {
        sol: Box<Solution>,
        sens: BaseValues,
        steps: usize,
    },
    /// The step `d` to the root was not finite or refused; the shot's sensitivities and the
    /// evaluations spent.
    Far {
        d: f64,
        sens: BaseValues,
        evaluations: usize,
    },
}

/// A dense shot at `phi1` and the step `d` its values are moved by along their tip-angle
/// sensitivities (0 for a shot without them).
struct Moved {
    phi1: f64,
    d: f64,
    shot: Shot,
    path: Option<ShotPath>,
}

impl Moved {
    fn plain(phi1: f64, shot: Shot, path: Option<ShotPath>) -> Self {
        Moved {
            phi1,
            d: 0.0,
            shot,
            path,
        }
    }

    /// The base values moved by `d`.
    fn values(&self) -> BaseValues {
        let (v, s, d) = (self.shot.values(), self.shot.d_phi1, self.d);
        if d == 0.0 {
            return v;
        }
        moved(v, s, d)
    }
}

/// The state `(phi, m, x, y)` at `s` (relative to the loaded end) of a dense shot, moved by
/// `d` along its tip-angle sensitivities when it carries them; `None` outside its span.
fn state_at(
    sol: &OdeSolution,
    (s, hint): (f64, &mut usize),
    d: f64,
    buf: &mut [f64; 8],
) -> Option<[f64; 4]> {
    let n = sol.u_end.len();
    if !sol.eval_near(s, hint, &mut buf[..n]) {
        return None;
    }
    let mut u = [buf[0], buf[1], buf[2], buf[3]];
    if n == 8 && d != 0.0 {
        for (i, ui) in u.iter_mut().enumerate() {
            *ui += d * buf[4 + i];
        }
    }
    Some(u)
}

/// The state `(phi, m, x, y)` of a dense shot at the elastica's samples, moved by `d` along
/// its tip-angle sensitivities when it carries them: each step's interpolant of the moved
/// state is made once ([`OdeSolution::step_interpolant_of`]), and a sample evaluates its 4
/// components instead of the shot's 8 (measured: 24 k of a pre-curved solve's 411 k
/// instructions went to the samples).
struct Sampler<'a> {
    sol: &'a OdeSolution,
    d: f64,
    /// The step of the last sample ([`OdeSolution::step_near`]).
    hint: usize,
    /// The moved state's interpolant on step `.0`.
    step: Option<(usize, StepInterpolant<4>)>,
}

impl<'a> Sampler<'a> {
    fn new(sol: &'a OdeSolution, d: f64) -> Self {
        Sampler {
            sol,
            d,
            hint: usize::MAX,
            step: None,
        }
    }

    /// The moved state at `s` (`None` outside the shot's span).
    fn state(&mut self, s: f64) -> Option<[f64; 4]> {
        let sol = self.sol;
        if s == sol.s_end || sol.steps() == 0 {
            // the end state exactly, as the dense output gives it
            let mut buf = [0.0; 8];
            return state_at(sol, (s, &mut self.hint), self.d, &mut buf);
        }
        let k = sol.step_near(s, &mut self.hint)?;
        if self.step.as_ref().map(|p| p.0) != Some(k) {
            let (n, d) = (sol.dim(), self.d);
            let moved = |r: &[f64]| {
                if n == 8 && d != 0.0 {
                    std::array::from_fn(|i| r[i] + d * r[4 + i])
                } else {
                    [r[0], r[1], r[2], r[3]]
                }
            };
            self.step = Some((k, sol.step_interpolant_of(k, moved)?));
        }
        let p = &self.step.as_ref()?.1;
        let mut u = [0.0; 4];
        p.eval((s - p.start()) / p.h(), &mut u).then_some(u)
    }
}

/// The solution of a (moved) dense shot: the elastica sampled on `run.samples` intervals,
/// the loaded end, the free segment beyond `s1` and the base observables.
fn assemble(scene: &Scene, run: &Run<'_>, m: &Moved, mut stats: SolveStats) -> Result<Solution> {
    let w = &scene.whisker;
    let s1 = scene.loads.s1;
    let phi1 = m.phi1 + m.d;
    let base = m.values();
    stats.evaluations += m.shot.evaluations;
    let mut el = Elastica::with_capacity(run.samples + 2);
    let sample = |el: &mut Elastica, s: f64, u: &[f64]| {
        let kappa = u[1] / w.stiffness(s) + w.kappa0(s);
        el.push(s, u[2] + base.dx, u[3] + base.dy, u[0], kappa, u[1]);
    };
    match &m.path {
        Some(ShotPath::Dense(sol)) => {
            let mut at = Sampler::new(sol, m.d);
            for i in 0..=run.samples {
                let s = (i as f64 / run.samples as f64).min(1.0);
                if s > s1 {
                    break;
                }
                if let Some(u) = at.state(s) {
                    sample(&mut el, s, &u);
                }
            }
            if el.s.last().is_none_or(|&l| l < s1) {
                sample(&mut el, s1, &[phi1, 0.0, 0.0, 0.0]);
            }
        }
        Some(ShotPath::Fixed(traj)) => {
            for i in (0..traj.len()).rev() {
                sample(&mut el, traj.s[i], traj.state(i));
            }
        }
        None => {}
    }
    let loaded_end = EndState {
        x: base.dx,
        y: base.dy,
        phi: phi1,
    };
    let tip = if s1 < 1.0 {
        free_segment(w, s1, &loaded_end, run, &mut el)?
    } else {
        loaded_end
    };
    let (ax, ay) = scene.base_reactions(phi1);
    Ok(Solution {
        elastica: el,
        tip,
        loaded_end,
        base: BaseObservables {
            ax,
            ay,
            ma: -base.m0,
            phi0: base.phi0,
        },
        stats,
        load_path: None,
    })
}

/// Integrates the load-free segment beyond `s1`, appending samples; returns the tip.
fn free_segment(
    w: &Whisker,
    s1: f64,
    start: &EndState,
    run: &Run<'_>,
    el: &mut Elastica,
) -> Result<EndState> {
    let (integration, samples, method) = (run.integration, run.samples, run.method);
    let seg = FreeSegment {
        whisker: *w,
        s1,
        phi1: start.phi,
    };
    let err = |source| ModelError::Solver { method, source };
    let u0 = [start.x, start.y];
    let push = |el: &mut Elastica, s: f64, x: f64, y: f64| {
        el.push(s, x, y, seg.phi(s), w.kappa0(s), 0.0);
    };
    match integration {
        Integration::Rk4 { n } => {
            let steps = ((*n as f64) * (1.0 - s1)).ceil().max(1.0) as usize;
            let traj = Rk4 { steps }.integrate(&seg, s1, 1.0, &u0).map_err(err)?;
            for i in 1..traj.len() {
                let u = traj.state(i);
                push(el, traj.s[i], u[0], u[1]);
            }
            let u = traj.last();
            Ok(EndState {
                x: u[0],
                y: u[1],
                phi: seg.phi(1.0),
            })
        }
        Integration::Dop853(d) => {
            // from the loaded end outwards: not the shots' problem, nor their first step
            let mut d = d.clone().with_dense(true);
            d.h_init = None;
            let sol = d.integrate(&seg, s1, 1.0, &u0).map_err(err)?;
            let (mut u, mut hint) = ([0.0; 2], 0);
            for i in 0..=samples {
                let s = i as f64 / samples as f64;
                if s > s1 && sol.eval_near(s, &mut hint, &mut u) {
                    push(el, s, u[0], u[1]);
                }
            }
            Ok(EndState {
                x: sol.u_end[0],
                y: sol.u_end[1],
                phi: seg.phi(1.0),
            })
        }
    }
}

/// How a shooting solve runs: its integrator, the elastica's samples, the method's name
/// (in errors) and the evaluation budget of the load continuation.
pub(crate) struct Run<'a> {
    pub integration: &'a Integration,
    pub samples: usize,
    pub method: &'static str,
    pub budget: usize,
}

/// Base values `v` moved by the step `d` in the tip angle along `sens = dv/dphi1`.
pub(crate) fn moved(v: BaseValues, sens: BaseValues, d: f64) -> BaseValues {
    BaseValues {
        phi0: v.phi0 + sens.phi0 * d,
        m0: v.m0 + sens.m0 * d,
        dx: v.dx + sens.dx * d,
        dy: v.dy + sens.dy * d,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{solve, Method};

    /// A dense shot a little off the root, moved to its root, gives the plain shot's
    /// solution there: base values, loaded end, tip and every elastica sample to O(d^2).
    #[test]
    fn the_linearised_shot_is_the_shot_at_its_root() {
        for (name, scene) in crate::scenarios::reference_scenes() {
            let scene = scene.normalised();
            let phi1 = solve(&scene, &Method::accurate()).unwrap().loaded_end.phi;
            let integration = Integration::adaptive(1e-12);
            let plain = shape(&scene, phi1, &integration, 50, SolveStats::default(), "t").unwrap();
            let run = Run {
                integration: &integration,
                samples: 50,
                method: "t",
                budget: 0,
            };
            let off = phi1 + 1e-7;
            let Linearised::Root { sol, sens, .. } =
                linearised_shape(&scene, off, &run, SolveStats::default(), |d, _| {
                    d.abs() <= 1e-6
                })
                .unwrap()
            else {
                panic!("{name}: a step of 1e-7 is within the bound");
            };
            assert!((sol.loaded_end.phi - phi1).abs() < 1e-12, "{name}");
            assert!(sens.phi0.is_finite() && sens.m0 != 0.0, "{name}");
            let d = sol.difference(&plain);
            assert!(d < 1e-10, "{name}: {d:e}");
            assert_eq!(sol.elastica.len(), plain.elastica.len());
            for (a, b) in sol.elastica.phi.iter().zip(&plain.elastica.phi) {
                assert!((a - b).abs() < 1e-10, "{name}: {a} {b}");
            }
            for (a, b) in sol.elastica.x.iter().zip(&plain.elastica.x) {
                assert!((a - b).abs() < 1e-10, "{name}: {a} {b}");
            }
            // beyond the bound: the step is reported, nothing is assembled
            let within = |d: f64, _: &BaseValues| d.abs() <= 1e-6;
            let far = linearised_shape(&scene, phi1 + 1e-3, &run, SolveStats::default(), within);
            assert!(matches!(far, Ok(Linearised::Far { d, .. }) if (d + 1e-3).abs() < 1e-4));
        }
    }
}
