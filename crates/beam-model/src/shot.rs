//! Shooting from the loaded end: the observables are the end values of an initial-value
//! problem started at `s1` with `m(s1) = 0` and a trial tip angle `phi1`.
//!
//! Integrating from the free end turns the whisker problem into a scalar equation in `phi1`
//! (the base condition [3.21, 3.22]), handles AP loads naturally (phi1 is known along the
//! integration) and is well conditioned for thin tips, where `EI = e^4` is small.

use crate::equations::{Sensitivities, WhiskerOde};
use crate::error::{ModelError, Result};
use crate::loads::Loads;
use crate::whisker::Whisker;
use bvp_solvers::integrator::{Dop853, OdeSolution, OdeSystem, Rk4, Trajectory};

/// The integrator used for a shot.
#[derive(Clone, Debug)]
pub enum Integration {
    /// Classical RK4 with step `1/n` (`ceil(n s1)` steps on `[0, s1]`).
    Rk4 {
        /// Steps per unit length.
        n: usize,
    },
    /// Adaptive Dormand-Prince 8(5,3).
    Dop853(Dop853),
}

impl Integration {
    /// DOP853 with `rtol = atol = tol`.
    pub fn adaptive(tol: f64) -> Self {
        Integration::Dop853(Dop853::new(tol, tol))
    }

    /// This integration starting with the natural first step `start` of an earlier shot
    /// from the same end, scaled to this tolerance by `(rtol / start.rtol)^(1/8)` (DOP853 is
    /// of order 8); unchanged for RK4, without a start, or above [`START_TOL`].
    pub fn started(&self, start: Option<StartStep>) -> Integration {
        match (self, start) {
            (Integration::Dop853(d), Some(st)) if d.rtol <= START_TOL => {
                let mut d = d.clone();
                d.h_init = Some(st.h * (d.rtol / st.rtol).powf(0.125));
                Integration::Dop853(d)
            }
            _ => self.clone(),
        }
    }
}

/// The loosest tolerance at which [`Integration::started`] applies a start: looser shots
/// take a few steps over the whisker, and a start from another shot changes those few steps
/// and with them the answer from shot to shot of one Newton iteration (measured: the
/// branch search's shots at 1e-3 then needed more iterations).
pub const START_TOL: f64 = 1e-6;

/// The natural first step `h` of a DOP853 shot at tolerance `rtol`
/// ([`bvp_solvers::integrator::Stepper::start_step`]): a start for the next shot of a
/// nearby problem ([`Integration::started`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StartStep {
    /// The step size.
    pub h: f64,
    /// The tolerance it was found at.
    pub rtol: f64,
}

/// The base values of a shot, `(phi(0), m(0), x(s1) - x(0), y(s1) - y(0))`, or their
/// derivatives with respect to one parameter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BaseValues {
    /// phi(0) (or its derivative).
    pub phi0: f64,
    /// m(0).
    pub m0: f64,
    /// x(s1) - x(0): horizontal offset of the loaded end from the base.
    pub dx: f64,
    /// y(s1) - y(0).
    pub dy: f64,
}

impl BaseValues {
    /// `[phi0, m0, dx, dy]`.
    pub fn to_array(&self) -> [f64; 4] {
        [self.phi0, self.m0, self.dx, self.dy]
    }

    /// From `[phi0, m0, dx, dy]`.
    pub fn from_array([phi0, m0, dx, dy]: [f64; 4]) -> Self {
        BaseValues { phi0, m0, dx, dy }
    }

    /// From the end state `u` of an integration from `s1` to 0 whose block starts at `o`:
    /// `(phi, m, x, y)` there, the offsets counted from the base.
    fn from_end(u: &[f64], o: usize) -> Self {
        BaseValues {
            phi0: u[o],
            m0: u[o + 1],
            dx: -u[o + 2],
            dy: -u[o + 3],
        }
    }
}

/// Base values of one shot from `s1` to `0`, and their sensitivities.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Shot {
    /// phi(0).
    pub phi0: f64,
    /// m(0).
    pub m0: f64,
    /// x(s1) - x(0): horizontal offset of the loaded end from the base.
    pub dx: f64,
    /// y(s1) - y(0).
    pub dy: f64,
    /// Derivatives with respect to the tip angle `phi1` (filled with
    /// [`Sensitivities::TipAngle`] and [`Sensitivities::All`]).
    pub d_phi1: BaseValues,
    /// Derivatives with respect to the tip force `f` ([`Sensitivities::All`]).
    pub d_f: BaseValues,
    /// Derivatives with respect to the loaded length `s1` ([`Sensitivities::All`]).
    pub d_s1: BaseValues,
    /// Derivatives with respect to the force angle `beta` at fixed `f`
    /// ([`Sensitivities::All`]).
    pub d_beta: BaseValues,
    /// Right-hand-side evaluations spent.
    pub evaluations: usize,
    /// The shot's natural first step (DOP853 only).
    pub start: Option<StartStep>,
}

impl Shot {
    /// The base values themselves.
    pub fn values(&self) -> BaseValues {
        BaseValues {
            phi0: self.phi0,
            m0: self.m0,
            dx: self.dx,
            dy: self.dy,
        }
    }
}

/// The result of a shot with its full trajectory (for sampling the elastica).
pub(crate) enum ShotPath {
    Fixed(Trajectory),
    Dense(OdeSolution),
}

/// The base condition [3.21, 3.22] `R = phi(0) - pi/2 - m(0)/k` of a DOP853 shot at
/// tolerance `tol` from the tip angle `phi1` under `loads` scaled by `lambda`
/// ([`Loads::scaled`]), with its slope `dR/dphi1` from the variational equations: zero at
/// an equilibrium; the slope is 1 on the unloaded whisker and zero at a fold of the load
/// path (an independent check of an answer's branch and of a reported fold).
///
/// # Errors
/// The shot's.
pub fn base_residual(
    whisker: &Whisker,
    loads: &Loads,
    phi1: f64,
    lambda: f64,
    tol: f64,
) -> Result<(f64, f64)> {
    let shot = shoot(
        whisker,
        &loads.scaled(lambda),
        phi1,
        Sensitivities::TipAngle,
        &Integration::adaptive(tol),
    )?;
    let support = &whisker.support;
    Ok((
        support.residual(shot.phi0, shot.m0),
        support.residual_rate(shot.d_phi1.phi0, shot.d_phi1.m0),
    ))
}

/// Integrates from `(s1, phi1, m = 0, x = 0, y = 0)` to `s = 0`.
pub fn shoot(
    whisker: &Whisker,
    loads: &Loads,
    phi1: f64,
    sens: Sensitivities,
    integration: &Integration,
) -> Result<Shot> {
    shoot_path(whisker, loads, phi1, sens, integration, false).map(|(shot, _)| shot)
}

pub(crate) fn shoot_path(
    whisker: &Whisker,
    loads: &Loads,
    phi1: f64,
    sens: Sensitivities,
    integration: &Integration,
    keep_path: bool,
) -> Result<(Shot, Option<ShotPath>)> {
    let ode = WhiskerOde::new(*whisker, *loads, phi1, sens);
    let dim = ode.dim();
    let s1 = loads.s1;
    let mut u0 = [0.0; 20];
    u0[0] = phi1;
    let np = sens.count();
    if np >= 1 {
        u0[4] = 1.0; // d phi(s1) / d phi1
    }
    if np == 4 {
        // d u(s; s1)/d s1 at s = s1 is -G(s1, u(s1)) for the state part; the variational
        // parts of G are not needed (they start at zero).
        let mut g = [0.0; 4];
        let plain = WhiskerOde::new(*whisker, *loads, phi1, Sensitivities::None);
        plain.rhs(s1, &u0[..4], &mut g);
        for i in 0..4 {
            u0[12 + i] = -g[i];
        }
    }
    let u0 = &u0[..dim];
    let mut start = None;
    let (end, evaluations, path): (Vec<f64>, usize, Option<ShotPath>) = match integration {
        Integration::Rk4 { n } => {
            let steps = ((*n as f64) * s1).ceil().max(1.0) as usize;
            let traj = Rk4 { steps }
                .integrate(&ode, s1, 0.0, u0)
                .map_err(|source| ModelError::Solver {
                    method: "rk4",
                    source,
                })?;
            let end = traj.last().to_vec();
            (end, 4 * steps, keep_path.then_some(ShotPath::Fixed(traj)))
        }
        Integration::Dop853(d) => {
            let d = d.clone().with_dense(keep_path);
            let sol = d
                .integrate(&ode, s1, 0.0, u0)
                .map_err(|source| ModelError::Solver {
                    method: "accurate",
                    source,
                })?;
            let end = sol.u_end.clone();
            let ev = sol.stats.rhs_evals;
            start = sol.start_step.map(|h| StartStep { h, rtol: d.rtol });
            (end, ev, keep_path.then_some(ShotPath::Dense(sol)))
        }
    };
    let base = BaseValues::from_end(&end, 0);
    let mut shot = Shot {
        phi0: base.phi0,
        m0: base.m0,
        dx: base.dx,
        dy: base.dy,
        evaluations,
        start,
        ..Shot::default()
    };
    // the variational blocks follow the state in the order of `Sensitivities`
    match sens {
        Sensitivities::None => {}
        Sensitivities::TipAngle => shot.d_phi1 = BaseValues::from_end(&end, 4),
        Sensitivities::All => {
            shot.d_phi1 = BaseValues::from_end(&end, 4);
            shot.d_f = BaseValues::from_end(&end, 8);
            shot.d_s1 = BaseValues::from_end(&end, 12);
            shot.d_beta = BaseValues::from_end(&end, 16);
        }
    }
    if !(shot.phi0.is_finite() && shot.m0.is_finite() && shot.dx.is_finite()) {
        return Err(ModelError::Solver {
            method: "shooting",
            source: bvp_solvers::BvpError::NonFinite {
                what: "whisker state",
                s: 0.0,
            },
        });
    }
    Ok((shot, path))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A shot started with an earlier shot's natural first step (at another tolerance)
    /// reaches the same base values within its tolerance, with fewer evaluations than one
    /// that guesses its first step; above `START_TOL` the start is not applied.
    #[test]
    fn a_started_shot_saves_evaluations_not_accuracy() {
        for (name, scene) in crate::scenarios::reference_scenes() {
            let scene = scene.normalised();
            let (w, loads) = (&scene.whisker, &scene.loads);
            let phi1 = w.phi_unloaded(loads.s1) - 0.3;
            let sens = Sensitivities::TipAngle;
            let earlier =
                shoot(w, loads, phi1 + 1e-3, sens, &Integration::adaptive(1e-10)).unwrap();
            let start = earlier.start.expect("a DOP853 shot records its first step");
            assert!(start.h > 0.0 && start.rtol == 1e-10, "{name}: {start:?}");
            let tight = Integration::adaptive(1e-12);
            let plain = shoot(w, loads, phi1, sens, &tight).unwrap();
            let started = shoot(w, loads, phi1, sens, &tight.started(Some(start))).unwrap();
            let d = plain
                .values()
                .to_array()
                .iter()
                .zip(started.values().to_array())
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(d < 1e-10, "{name}: {d:e}");
            assert!(
                started.evaluations < plain.evaluations,
                "{name}: {} vs {}",
                started.evaluations,
                plain.evaluations
            );
            let Integration::Dop853(loose) = Integration::adaptive(1e-3).started(Some(start))
            else {
                unreachable!()
            };
            assert_eq!(loose.h_init, None, "{name}");
        }
    }
}
