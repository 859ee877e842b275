//! The elastica of a scene whose tip angle is known, as dense output: one DOP853 integration
//! of the loaded part `[0, s1]` from its loaded end [3.25] and, beyond a tangential contact,
//! one of the load-free segment `(s1, 1]` ([`FreeSegment`]), both kept with their 7th-order
//! interpolants. A geometric check evaluates it where it needs to ([`ShapePath::at`]) and
//! learns from the integrator's step points ([`ShapePath::knots`]) where the shape is only
//! smooth, instead of sampling a fixed grid throughout.

use crate::equations::{FreeSegment, Sensitivities};
use crate::error::{ModelError, Result};
use crate::scene::Scene;
use crate::shot::{shoot_path, Integration, ShotPath};
use bvp_solvers::integrator::{Dop853, OdeSolution, StepInterpolant};

/// A point of the elastica, relative to the base.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    /// x - x0.
    pub x: f64,
    /// y (the base lies on y = 0).
    pub y: f64,
    /// The angle phi.
    pub phi: f64,
}

/// One integrator step of a [`ShapePath`] ([`ShapePath::pieces`]): the position relative
/// to the base is `poly(theta) + offset` for `theta` in `[0, 1]`, at arc length
/// `s = poly.start() + theta poly.h()`.
#[derive(Clone, Copy, Debug)]
pub struct ShapePiece {
    /// The interpolant of `(x, y)` without the offset.
    pub poly: StepInterpolant<2>,
    /// What the interpolant's positions are measured from.
    pub offset: (f64, f64),
    /// Whether the step belongs to the load-free segment beyond a tangential contact.
    pub free: bool,
}

/// The dense elastica of [`shape_path`].
#[derive(Clone, Debug)]
pub struct ShapePath {
    /// `(phi, m, x, y)` on `[0, s1]`, integrated from `s1` with `x = y = 0` there.
    loaded: OdeSolution,
    /// The loaded end relative to the base, `(x(s1) - x(0), y(s1))`.
    end: (f64, f64),
    /// `(x, y)` relative to the base on `[s1, 1]` (for `s1 < 1`), with its angle law.
    free: Option<(OdeSolution, FreeSegment)>,
    s1: f64,
}

/// The elastica of `scene` for the tip angle `phi1` at integration tolerance `tol`, without
/// validating the scene (trial states of a solver may exceed the bounds a user may ask for)
/// and without checking the base condition (the caller has solved it).
///
/// # Errors
/// An integration that fails (`ModelError::Solver`).
pub fn shape_path(scene: &Scene, phi1: f64, tol: f64) -> Result<ShapePath> {
    let (w, loads) = (&scene.whisker, &scene.loads);
    let integration = Integration::adaptive(tol);
    let (shot, path) = shoot_path(w, loads, phi1, Sensitivities::None, &integration, true)?;
    let Some(ShotPath::Dense(loaded)) = path else {
        unreachable!("a DOP853 shot with its path keeps a dense solution")
    };
    let s1 = loads.s1;
    let free = if s1 < 1.0 {
        let seg = FreeSegment {
            whisker: *w,
            s1,
            phi1,
        };
        let sol = Dop853::new(tol, tol)
            .with_dense(true)
            .integrate(&seg, s1, 1.0, &[shot.dx, shot.dy])
            .map_err(|source| ModelError::Solver {
                method: "shape",
                source,
            })?;
        Some((sol, seg))
    } else {
        None
    };
    Ok(ShapePath {
        loaded,
        end: (shot.dx, shot.dy),
        free,
        s1,
    })
}

impl ShapePath {
    /// The loaded length `s1`.
    pub fn s1(&self) -> f64 {
        self.s1
    }

    /// The point at arc length `s` in `[0, 1]` (`None` outside).
    pub fn at(&self, s: f64) -> Option<PathPoint> {
        self.at_near(s, &mut 0)
    }

    /// [`ShapePath::at`] with the integrator's step looked for from `*hint` (updated; any
    /// value to start, e.g. 0): for points sampled in order, a step or two of walking
    /// instead of a binary search ([`OdeSolution::eval_near`]). The same values.
    pub fn at_near(&self, s: f64, hint: &mut usize) -> Option<PathPoint> {
        if s <= self.s1 {
            let mut u = [0.0; 4];
            self.loaded.eval_near(s, hint, &mut u).then(|| PathPoint {
                x: u[2] + self.end.0,
                y: u[3] + self.end.1,
                phi: u[0],
            })
        } else {
            let (sol, seg) = self.free.as_ref()?;
            let mut u = [0.0; 2];
            sol.eval_near(s, hint, &mut u).then(|| PathPoint {
                x: u[0],
                y: u[1],
                phi: seg.phi(s),
            })
        }
    }

    /// The integrators' steps as polynomials of the position `(x, y)` relative to the base,
    /// ordered outward from the loaded end `s1`: the loaded part's steps from `s1` towards
    /// the base, then (beyond a tangential contact) the free segment's from `s1` towards the
    /// tip. On each, the position is the step's 7th-order interpolant plus
    /// [`ShapePiece::offset`]; `theta = 0` is the end nearer `s1`.
    pub fn pieces(&self) -> Vec<ShapePiece> {
        let mut out = Vec::with_capacity(self.loaded.steps() + 8);
        for k in 0..self.loaded.steps() {
            if let Some(poly) = self.loaded.step_interpolant_of(k, |r| [r[2], r[3]]) {
                out.push(ShapePiece {
                    poly,
                    offset: self.end,
                    free: false,
                });
            }
        }
        if let Some((sol, _)) = &self.free {
            for k in 0..sol.steps() {
                if let Some(poly) = sol.step_interpolant_of(k, |r| [r[0], r[1]]) {
                    out.push(ShapePiece {
                        poly,
                        offset: (0.0, 0.0),
                        free: true,
                    });
                }
            }
        }
        out
    }

    /// The integrators' step points over `[0, 1]`, increasing (`s1` among them): between
    /// two neighbours the shape is one interpolant's polynomial.
    pub fn knots(&self) -> Vec<f64> {
        let mut k: Vec<f64> = self.loaded.step_points().iter().rev().copied().collect();
        if let Some((sol, _)) = &self.free {
            k.extend(sol.step_points().iter().skip(1));
        }
        k
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loads::{Loads, TipForce};
    use crate::whisker::Whisker;

    /// The path agrees with the sampled elastica of the same tip angle, on the loaded part and
    /// on the free segment beyond a contact at s1 = 0.6, and its knots span [0, 1] in order.
    #[test]
    fn the_path_is_the_sampled_elastica() {
        let mut loads = Loads::combined(TipForce::dp(1.5, 2.0), 2.0, 0.3);
        loads.s1 = 0.6;
        let scene = Scene::new(Whisker::new(0.6, 1.0, -0.5, 10.0), loads);
        let phi1 = 1.1;
        let path = shape_path(&scene, phi1, 1e-11).unwrap();
        let sol = crate::methods::shape_from_tip_angle(&scene, phi1, 1e-11, 50).unwrap();
        let el = &sol.elastica;
        for i in 0..el.len() {
            let p = path.at(el.s[i]).unwrap();
            assert!((p.x - el.x[i]).abs() < 1e-12, "x at {}", el.s[i]);
            assert!((p.y - el.y[i]).abs() < 1e-12, "y at {}", el.s[i]);
            assert!((p.phi - el.phi[i]).abs() < 1e-12, "phi at {}", el.s[i]);
        }
        let k = path.knots();
        assert_eq!((k[0], *k.last().unwrap()), (0.0, 1.0));
        assert!(k.windows(2).all(|w| w[0] < w[1]) && k.contains(&0.6));
        assert!(path.at(1.2).is_none());
    }
}
