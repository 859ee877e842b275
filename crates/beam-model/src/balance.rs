//! The force balance of the whole whisker [5.1, 6.1, 6.8, 6.9]: the base reactions
//! `(Ax, Ay)` (support on whisker) balance a point force `f (cos beta, sin beta)` at the
//! loaded end `s1` and the flow `q (cos alpha, -sin alpha)` per length on `[0, s1]`
//! (spec/model.md):
//!
//! ```text
//! Ax = -(f cos beta + q s1 cos alpha),   Ay = f sin beta + q s1 sin alpha.
//! ```
//!
//! Forward (loads to reactions: a scene's observables, a contact row's) and backward (a
//! row's reactions to the point force that the flow leaves over, or to the flow of a free
//! whisker) in one place. A contact force `f (sin psi, -cos psi)` normal to a contour at
//! angle psi is the point force at `beta = pi/2 - psi`: components `(f sin psi, f cos psi)`.

use crate::loads::FluidLoad;

/// Base reactions (support on whisker).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reactions {
    /// Horizontal reaction `Ax`.
    pub ax: f64,
    /// Vertical reaction `Ay`.
    pub ay: f64,
}

impl Reactions {
    /// The reactions to the point force with components `force = (f cos beta, f sin beta)` at
    /// `s1` and the flow on `[0, s1]` [5.1, 6.8, 6.9].
    pub fn balancing(force: (f64, f64), flow: FluidLoad, s1: f64) -> Self {
        let (sa, ca) = flow.alpha.sin_cos();
        Reactions {
            ax: -(force.0 + flow.q * s1 * ca),
            ay: force.1 + flow.q * s1 * sa,
        }
    }

    /// The point force `(f cos beta, f sin beta)` at `s1` that these reactions balance
    /// together with the flow on `[0, s1]` (the inverse of [`Reactions::balancing`];
    /// `(f sin psi, f cos psi)` for a contact force [6.8, 6.9]).
    pub fn point_force(&self, flow: FluidLoad, s1: f64) -> (f64, f64) {
        let (sa, ca) = flow.alpha.sin_cos();
        (-self.ax - flow.q * s1 * ca, self.ay - flow.q * s1 * sa)
    }

    /// The flow of a free whisker with these reactions [6.1]: `q = hypot(Ax, Ay)`,
    /// `alpha = atan2(Ay, -Ax)` (`alpha = 0` for `q = 0`).
    pub fn free_flow(&self) -> FluidLoad {
        let q = self.ax.hypot(self.ay);
        let alpha = if q > 0.0 {
            self.ay.atan2(-self.ax)
        } else {
            0.0
        };
        FluidLoad { q, alpha }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balance_round_trips_and_the_free_flow_is_the_reaction() {
        let flow = FluidLoad { q: 2.5, alpha: 0.4 };
        let (f, beta, s1): (f64, f64, f64) = (1.7, -0.9, 0.8);
        let force = (f * beta.cos(), f * beta.sin());
        let r = Reactions::balancing(force, flow, s1);
        // the total load: f (cos b, sin b) + q s1 (cos a, -sin a) = (-Ax, Ay) componentwise
        let total_x = force.0 + flow.q * s1 * flow.alpha.cos();
        assert!((r.ax + total_x).abs() < 1e-15);
        let back = r.point_force(flow, s1);
        assert!((back.0 - force.0).abs() < 1e-14 && (back.1 - force.1).abs() < 1e-14);
        let free = Reactions::balancing((0.0, 0.0), flow, 1.0).free_flow();
        assert!((free.q - flow.q).abs() < 1e-14 && (free.alpha - flow.alpha).abs() < 1e-14);
        let none = Reactions { ax: 0.0, ay: 0.0 }.free_flow();
        assert_eq!((none.q, none.alpha), (0.0, 0.0));
    }
}
