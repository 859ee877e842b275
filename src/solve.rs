//! [`Scene::solve`]: one configuration, its shape and base observables in the scene's units
//! (the numbers of `vibrissa solve`'s `elastica.csv`).

use beam_model::{BaseObservables, EndState, SolveStats};
use vibrissa_io::resolve::ModelFlags;
use vibrissa_io::units::{Quantity, UnitSystem};

use crate::{Error, Scene};

/// The deformed whisker's columns in the scene's units, base first (those of
/// `elastica.csv`): arc length, position, tangent angle, curvature and bending moment of
/// the elastica [3.25].
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct Elastica {
    /// Arc length s.
    pub s: Vec<f64>,
    /// x(s).
    pub x: Vec<f64>,
    /// y(s).
    pub y: Vec<f64>,
    /// Tangent angle phi(s) (rad).
    pub phi: Vec<f64>,
    /// Curvature kappa(s).
    pub kappa: Vec<f64>,
    /// Bending moment m(s).
    pub m: Vec<f64>,
}

/// A solved configuration in the scene's units: the shape, its ends and the base
/// observables, with the solver's statistics and error estimate.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Solution {
    /// The deformed shape.
    pub elastica: Elastica,
    /// The free end s = 1 (x, y in the scene's length unit; phi in rad).
    pub tip: EndState,
    /// The loaded end s = s1 (the tip when the whole whisker is loaded).
    pub loaded_end: EndState,
    /// The base observables [3.31]: forces Ax, Ay, moment MA in the scene's units, phi0
    /// in rad.
    pub base: BaseObservables,
    /// The solver's statistics, `error_estimate` (dimensionless) among them.
    pub stats: SolveStats,
    /// The unit system of the numbers above.
    #[serde(skip)]
    pub units: UnitSystem,
    /// The model's own solution, dimensionless (the thesis's variables).
    pub dimensionless: beam_model::Solution,
}

impl Solution {
    /// The model's solution `sol` in the unit system `units`: the one place where a solve is
    /// scaled for output (the CLI's `elastica.csv`, the Python package, this facade).
    pub fn in_units(sol: beam_model::Solution, units: UnitSystem) -> Self {
        let (l, f, m, k) = (
            units.scale(Quantity::Length),
            units.scale(Quantity::Force),
            units.scale(Quantity::Moment),
            units.scale(Quantity::Curvature),
        );
        let scaled = |v: &[f64], s: f64| v.iter().map(|x| x * s).collect::<Vec<_>>();
        let e = &sol.elastica;
        let end = |p: &EndState| EndState {
            x: p.x * l,
            y: p.y * l,
            phi: p.phi,
        };
        Solution {
            elastica: Elastica {
                s: scaled(&e.s, l),
                x: scaled(&e.x, l),
                y: scaled(&e.y, l),
                phi: e.phi.clone(),
                kappa: scaled(&e.kappa, k),
                m: scaled(&e.m, m),
            },
            tip: end(&sol.tip),
            loaded_end: end(&sol.loaded_end),
            base: BaseObservables {
                ax: sol.base.ax * f,
                ay: sol.base.ay * f,
                ma: sol.base.ma * m,
                phi0: sol.base.phi0,
            },
            stats: sol.stats,
            units,
            dimensionless: sol,
        }
    }
}

impl Scene {
    /// Solves the scene's whisker under its loads with its method [3.27] (as `vibrissa
    /// solve SCENE.ron`); the result in the scene's units. A value out of range is
    /// [`Error::InvalidInput`] naming the scene field; a solve that does not meet its
    /// accuracy is [`Error::Solver`] with the solver's numbers.
    pub fn solve(&self) -> Result<Solution, Error> {
        let (_, r) = self.resolved(&ModelFlags::default())?;
        let sol = beam_model::solve(&r.scene, &r.method).map_err(|e| r.culprit(&e))?;
        Ok(Solution::in_units(sol, r.units()))
    }
}
