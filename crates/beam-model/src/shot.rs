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
    /// Derivatives of `(phi0, m0, dx, dy)` with respect to `(phi1, f, s1)` (rows by parameter;
    /// only the rows of the requested [`Sensitivities`] are filled).
    pub sens: [[f64; 4]; 3],
    /// Right-hand-side evaluations spent.
    pub evaluations: usize,
}

/// The result of a shot with its full trajectory (for sampling the elastica).
pub(crate) enum ShotPath {
    Fixed(Trajectory),
    Dense(OdeSolution),
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
    let mut u0 = [0.0; 16];
    u0[0] = phi1;
    let np = sens.count();
    if np >= 1 {
        u0[4] = 1.0; // d phi(s1) / d phi1
    }
    if np == 3 {
        // d u(s; s1)/d s1 at s = s1 is -G(s1, u(s1)) for the state part; the variational
        // parts of G are not needed (they start at zero).
        let mut g = [0.0; 16];
        let plain = WhiskerOde::new(*whisker, *loads, phi1, Sensitivities::None);
        plain.rhs(s1, &u0[..4], &mut g[..4]);
        for i in 0..4 {
            u0[12 + i] = -g[i];
        }
    }
    let u0 = &u0[..dim];
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
            (end, ev, keep_path.then_some(ShotPath::Dense(sol)))
        }
    };
    let mut shot = Shot {
        phi0: end[0],
        m0: end[1],
        dx: -end[2],
        dy: -end[3],
        sens: [[0.0; 4]; 3],
        evaluations,
    };
    let rows: &[usize] = match sens {
        Sensitivities::None => &[],
        Sensitivities::TipAngle => &[0],
        Sensitivities::All => &[0, 1, 2],
    };
    for (j, &row) in rows.iter().enumerate() {
        let o = 4 * (j + 1);
        shot.sens[row] = [end[o], end[o + 1], -end[o + 2], -end[o + 3]];
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
