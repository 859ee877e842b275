//! The three solution methods of the forward problem and their common entry point.
//!
//! | method | discretisation | order | thesis |
//! |---|---|---|---|
//! | [`Method::Fdm`] | central FDM [3.25, 3.27], Newton on the tridiagonal Jacobian | 2 | ch. 4 (its method) |
//! | [`Method::Rk4`] | RK4 shooting from the loaded end, exact Newton derivatives | 4 | ch. 4 (comparison) |
//! | [`Method::Accurate`] | adaptive DOP853 shooting from the loaded end | 8 | — |

pub(crate) mod fdm;
pub(crate) mod shooting;

use crate::error::{ModelError, Result};
use crate::scene::Scene;
use crate::solution::Solution;
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
}

impl Default for Method {
    fn default() -> Self {
        Method::accurate()
    }
}

/// The thesis's grid: h = 0.01.
pub const DEFAULT_INTERVALS: usize = 100;

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
        }
    }

    /// Grid intervals (fixed-step methods) or output intervals (`accurate`).
    pub fn intervals(&self) -> usize {
        match *self {
            Method::Accurate { samples, .. } => samples,
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
            _ => None,
        }
    }

    fn validate(&self) -> Result<()> {
        let n = self.intervals();
        if n < 4 {
            return Err(ModelError::InvalidParameter {
                name: "n",
                value: n as f64,
                reason: "at least 4 grid intervals are needed",
            });
        }
        if let Method::Accurate { tol, .. } = *self {
            if !(tol > 0.0 && tol < 1.0) {
                return Err(ModelError::InvalidParameter {
                    name: "tol",
                    value: tol,
                    reason: "the integrator tolerance must be in (0, 1)",
                });
            }
        }
        Ok(())
    }
}

/// Solves a scene with a method: the elastica [3.25] with its boundary conditions
/// [3.21, 3.22], load continuation where the direct solve fails.
pub fn solve(scene: &Scene, method: &Method) -> Result<Solution> {
    scene.validate()?;
    method.validate()?;
    match *method {
        Method::Accurate { tol, samples } => {
            match shooting::solve(
                scene,
                &crate::shot::Integration::adaptive(tol),
                samples,
                "accurate",
            ) {
                Ok(sol) => Ok(sol),
                // Single shooting is ill-conditioned for thin tips under large loads (the
                // linearised equation grows like exp(sqrt(f)/theta^2) near the tip): fall
                // back to the globally discretised FDM with Richardson extrapolation.
                Err(e @ (ModelError::NoConvergence { .. } | ModelError::Solver { .. })) => {
                    fdm_richardson(scene).map_err(|_| e)
                }
                Err(e) => Err(e),
            }
        }
        Method::Rk4 { n } => shooting::solve(scene, &crate::shot::Integration::Rk4 { n }, n, "rk4"),
        Method::Fdm { n } => fdm::solve(scene, n),
        Method::FdmRichardson { n } => fdm_richardson_on(scene, n),
    }
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
    shooting::shape(
        scene,
        phi1,
        &crate::shot::Integration::adaptive(tol),
        samples,
        crate::solution::SolveStats::default(),
        "accurate",
    )
}

/// Like [`shape_from_tip_angle`] with any integrator, e.g. a cheap fixed-step RK4 for
/// geometric checks (`Integration::Rk4 { n }` samples the RK4 nodes).
pub fn shape_with(
    scene: &Scene,
    phi1: f64,
    integration: &crate::shot::Integration,
) -> Result<Solution> {
    let samples = match integration {
        crate::shot::Integration::Rk4 { n } => *n,
        crate::shot::Integration::Dop853(_) => DEFAULT_INTERVALS,
    };
    shooting::shape(
        scene,
        phi1,
        integration,
        samples,
        crate::solution::SolveStats::default(),
        "shape",
    )
}

/// FDM on `n, 2n, 4n` intervals (`n = max(200, 40/theta)`, fine enough to resolve a thin tip)
/// with two levels of Richardson extrapolation (the central scheme and the trapezoidal
/// positions expand in even powers of h: order 2 -> 6) of the tip, the loaded end and the
/// base observables; the elastica is the finest grid's. `stats.residual` holds the
/// extrapolation's error estimate. The fallback of `accurate` where shooting fails.
pub fn fdm_richardson(scene: &Scene) -> Result<Solution> {
    let n0 = ((40.0 / scene.whisker.theta).ceil() as usize).max(200);
    fdm_richardson_on(scene, n0)
}

/// FDM with two Richardson levels from a coarsest grid of `n0` intervals per unit length
/// (method [`Method::FdmRichardson`]).
fn fdm_richardson_on(scene: &Scene, n0: usize) -> Result<Solution> {
    scene.validate()?;
    let sols = [
        fdm::solve(scene, n0)?,
        fdm::solve(scene, 2 * n0)?,
        fdm::solve(scene, 4 * n0)?,
    ];
    let extrapolate = |get: &dyn Fn(&Solution) -> f64| -> Result<(f64, f64)> {
        let v: Vec<f64> = sols.iter().map(get).collect();
        let e = bvp_solvers::richardson::richardson(&v, 2, 2)?;
        Ok((e.value, e.error_estimate.abs()))
    };
    let mut best = sols[2].clone();
    let mut err: f64 = 0.0;
    let mut set = |slot: &mut f64, get: &dyn Fn(&Solution) -> f64| -> Result<()> {
        let (v, e) = extrapolate(get)?;
        *slot = v;
        err = err.max(e);
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
    let (ax, ay) = scene.base_reactions(best.loaded_end.phi);
    best.base.ax = ax;
    best.base.ay = ay;
    best.stats.residual = err;
    best.stats.evaluations = sols.iter().map(|s| s.stats.evaluations).sum();
    Ok(best)
}
