//! The contact branch: the one-parameter family of equilibria of a whisker in single-point
//! contact with the contour, followed in the base position x0 (spec/model.md, contact).
//!
//! In a phase the state is `u = (v, f, t)`: `v = phi1` in phase A (tip contact, `s1 = 1`) or
//! `v = s1` in phase B (tangential contact, `phi1 = psi`), the contact force `f` and the
//! contour parameter `t` of the contact point ([`Profile::at`]). Two equations hold on the
//! branch [5.4-5.10]:
//!
//! ```text
//! R0 = phi(0) - pi/2 - m(0)/k = 0     (base condition [3.21, 3.22])
//! R1 = y(s1) - y(0) - yc(t)   = 0     (the contact point lies on the contour)
//! ```
//!
//! so the branch is a curve in `(v, f, t)`; the base position on it is
//! `x0(u) = xc(t) - (x(s1) - x(0))`. A third equation picks one point: `x0(u) = X` (a row at
//! a prescribed base position), a hyperplane through a predicted point (pseudo-arclength), or
//! an event condition. Each is solved through the one interface of
//! [`bvp_solvers::nonlinear`] (the thesis's `fsolve`): Newton's method on the 3x3 system with
//! the exact sensitivities of the shot in `(phi1, f, s1, beta)` as the fast path, and where
//! the caller asks for it ([`Rescue`]), the trust region from the same start as the fallback.

use crate::contact_law::Tilt;
use crate::error::{ContactError, Result};
use crate::motion::Frame;
use crate::phase::{ContactState, ContourPoint, Phase};
use crate::profile::Profile;
use beam_model::equations::Sensitivities;
use beam_model::shot::{shoot, BaseValues, Integration};
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::newton::{Evaluation, JacobianUpdate, NewtonPolicy, NewtonSystem, Termination};
use bvp_solvers::nonlinear::{solve_square, NonlinearOptions, SquareReport};
use bvp_solvers::trust_region::TrustRegionOptions;
use std::cell::Cell;

/// A point of the contact branch: the phase, the state `u = (v, f, t)` and everything the
/// sweep needs from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Node {
    /// Phase A or B.
    pub phase: Phase,
    /// `(phi1 or s1, f, t)`.
    pub u: [f64; 3],
    /// The solved state (observables, contact point).
    pub state: ContactState,
    /// Rows `dR0, dR1, dx0` of the Jacobian with respect to `u`.
    pub jac: [[f64; 3]; 3],
}

impl Node {
    /// The base position.
    pub fn x0(&self) -> f64 {
        self.state.x0
    }

    /// The unit tangent of the branch (null vector of the 2x3 Jacobian of `R`), with the sign
    /// that makes it point along `dir` (any vector; the sign of `+dir` wins ties).
    pub fn tangent(&self, dir: &[f64; 3]) -> [f64; 3] {
        let (a, b) = (self.jac[0], self.jac[1]);
        let mut t = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        let n = norm(&t);
        for v in &mut t {
            *v /= n;
        }
        if dot(&t, dir) < 0.0 {
            for v in &mut t {
                *v = -*v;
            }
        }
        t
    }

    /// `dx0/dsigma` along the unit tangent `t`.
    pub fn x0_rate(&self, t: &[f64; 3]) -> f64 {
        dot(&self.jac[2], t)
    }

    /// `du/dx0` along the branch (the tangent scaled to unit rate in x0); meaningful where
    /// the Jacobian is exact and x0 is not at a turning point.
    pub fn slope(&self) -> [f64; 3] {
        let t = self.tangent(&[1.0, 0.0, 0.0]);
        let r = self.x0_rate(&t);
        [t[0] / r, t[1] / r, t[2] / r]
    }
}

/// The third equation of a corrector solve.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Constraint {
    /// `x0(u) = X`.
    BasePosition(f64),
    /// `n . (u - p) = 0`.
    Hyperplane {
        /// Unit normal.
        n: [f64; 3],
        /// A point of the plane.
        p: [f64; 3],
        /// How far from `p` the solution may lie: an iterate beyond it fails the solve
        /// (the prediction was too far from the branch), before a shot is spent there.
        radius: f64,
    },
    /// The end of the phase's validity: `phi1 = psi(t)` in phase A, `s1 = 1` in phase B.
    PhaseEnd,
    /// A vanishing contact force, `f = 0`.
    NoForce,
}

/// The branch equations of one whisker, flow and contour.
#[derive(Clone, Copy)]
pub(crate) struct Branch<'a> {
    pub whisker: &'a Whisker,
    pub flow: FluidLoad,
    pub profile: &'a Profile,
    pub integration: &'a Integration,
    /// Residual tolerance of the corrector (norm of `R` and of the constraint).
    pub tol: f64,
    /// How the base moves: which two equations hold and which function of the state is the
    /// motion's falling coordinate (`x0` of a translation, `-gamma` of a rotation; the
    /// node's `state.x0`, [`crate::motion`]).
    pub frame: Frame,
    /// The force's tilt: [`Tilt::NONE`] for the frictionless force `f n` [5.4-5.10]; a
    /// sliding frictional contact's `F = f (n + s mu t)` (spec/model.md, "Friction at the
    /// contact"), whose branch is this one with the tip force turned by `atan(s mu)` and
    /// stretched by `sqrt(1 + mu^2)`; `f` stays the normal force.
    pub tilt: Tilt,
}

/// Diameter ratio below which every shot carries sensitivities (see [`Branch::eval`]).
const SLENDER: f64 = 0.15;

/// The largest residual norm accepted from a corrector that cannot reduce it further.
const NOISE_FLOOR: f64 = 1e-10;

/// Newton iterations per corrector solve (from a prediction Newton converges in 2-4; a
/// corrector that needs more is failed fast and the caller shortens its step).
const MAX_NEWTON: usize = 10;

/// Trust-region iterations of a rescue ([`Rescue::TrustRegion`]).
const MAX_TRUST_REGION: u64 = 50;

/// What a corrector does where Newton does not reach a solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Rescue {
    /// The trust region from the same start ([`bvp_solvers::nonlinear::solve_square`]): for
    /// solves whose failure ends the sweep (no smaller step, no other start to try).
    TrustRegion,
    /// Newton alone, its failure the answer: for a continuation corrector, whose failure is
    /// the signal to shorten the step (a globalised solve there would spend shots on every
    /// rejected step and could land on another part of the branch, a jump the short step
    /// exists to prevent), and for a fast attempt whose caller has its own follow-up.
    NewtonOnly,
}

impl Branch<'_> {
    /// Evaluates the branch equations at `u` in `phase`: residual `R`, the node (state and
    /// Jacobian).
    pub fn eval(&self, phase: Phase, u: [f64; 3]) -> Result<([f64; 2], Node)> {
        self.eval_with(phase, u, true)
    }

    /// [`Branch::eval`], with the Jacobian only if `jac` is set (zero otherwise).
    pub(crate) fn eval_with(
        &self,
        phase: Phase,
        u: [f64; 3],
        jac: bool,
    ) -> Result<([f64; 2], Node)> {
        let (v, f, t) = (u[0], u[1], u[2]);
        let (t_lo, t_hi) = self.profile.param_range();
        if !(t >= t_lo && t <= t_hi) {
            return Err(ContactError::LeftContour {
                profile: self.profile.name(),
                t,
            });
        }
        let g = self.profile.at(t);
        let (phi1, s1) = match phase {
            Phase::B => (g.psi, v),
            _ => (v, 1.0),
        };
        if !(s1 > 1e-6 && s1 <= 1.5 && f.is_finite() && phi1.is_finite()) {
            return Err(ContactError::PhaseSolve {
                phase,
                xc: g.x,
                iterations: 0,
                residual: f64::NAN,
            });
        }
        let loads = self.tilt.loads(self.flow, g.psi, f, s1);
        // Slender tips (theta < SLENDER) form a boundary layer where the plain 4-component
        // shot's adaptive steps lose accuracy (measured: 1e-6 against the shot with
        // sensitivities, whose error control sees the variational components, at theta 0.05;
        // at theta = 0.1, g1, q = 8, rigid, a corrector mixing both kinds stalled at a residual
        // of 3.4e-9); they are always shot with sensitivities.
        let sens = if jac || self.whisker.theta < SLENDER {
            Sensitivities::All
        } else {
            Sensitivities::None
        };
        let shot = shoot(self.whisker, &loads, phi1, sens, self.integration)?;
        // d(shot)/d(beta) at fixed f (zero without a force)
        let dbeta = if f == 0.0 || !jac {
            BaseValues::default()
        } else {
            shot.d_beta
        };
        // d(shot)/d(f): the tip force is f sqrt(1 + mu^2) under a tilt
        let d_f = if self.tilt.is_none() {
            shot.d_f
        } else {
            let c = self.tilt.scale();
            let d = shot.d_f;
            BaseValues {
                phi0: c * d.phi0,
                m0: c * d.m0,
                dx: c * d.dx,
                dy: c * d.dy,
            }
        };
        let support = &self.whisker.support;
        // a column of the Jacobian: the rates of R0 (the follicle law), R1 and x0
        let col = |d: BaseValues| [support.residual_rate(d.phi0, d.m0), d.dy, -d.dx];
        // d/dt: the force angle beta = pi/2 - psi(t) turns, and in phase B phi1 = psi(t).
        let dpsi = g.dpsi;
        let turn = |beta: f64, phi1: f64| {
            let r = -beta * dpsi;
            if phase == Phase::B {
                r + phi1 * dpsi
            } else {
                r
            }
        };
        let (b, p) = (dbeta, shot.d_phi1);
        let dt = BaseValues {
            phi0: turn(b.phi0, p.phi0),
            m0: turn(b.m0, p.m0),
            dx: turn(b.dx, p.dx),
            dy: turn(b.dy, p.dy),
        };
        let (c0, c1) = match phase {
            Phase::B => (col(shot.d_s1), col(d_f)),
            _ => (col(shot.d_phi1), col(d_f)),
        };
        let mut c2 = col(dt);
        c2[1] -= g.dy;
        c2[2] += g.dx;
        let mut jac = [
            [c0[0], c1[0], c2[0]],
            [c0[1], c1[1], c2[1]],
            [c0[2], c1[2], c2[2]],
        ];
        let mut r = [
            self.whisker.support.residual(shot.phi0, shot.m0),
            shot.dy - g.y,
        ];
        let mut x0 = g.x - shot.dx;
        if let Frame::Rotate { x0: bx, y0: by } = self.frame {
            // the base held at (bx, by): R = (xc - dx - bx, dy - yc + by); the coordinate
            // -gamma = -R0 (the base condition turned by gamma, [3.21, 3.22])
            let gamma = r[0];
            r = [x0 - bx, r[1] + by];
            x0 = -gamma;
            let row0 = jac[0];
            jac[0] = jac[2];
            jac[2] = [-row0[0], -row0[1], -row0[2]];
        }
        if let Frame::Path(seg) = self.frame {
            // Q(u) = w D(u) on the segment, w read from the pivot (crate::motion's notes)
            let raw = match phase {
                Phase::B => [shot.d_s1, d_f, dt],
                _ => [shot.d_phi1, d_f, dt],
            };
            let q = [
                x0 - seg.from.x0,
                g.y - shot.dy - seg.from.y0,
                shot.phi0 - std::f64::consts::FRAC_PI_2 - shot.m0 * seg.c0 - seg.from.gamma,
            ];
            let d = [seg.rate.x0, seg.rate.y0, seg.rate.gamma + shot.m0 * seg.dc];
            let dq = [
                jac[2],
                [-jac[1][0], -jac[1][1], -jac[1][2]],
                std::array::from_fn(|k| raw[k].phi0 - seg.c0 * raw[k].m0),
            ];
            let dd3: [f64; 3] = std::array::from_fn(|k| seg.dc * raw[k].m0);
            let dd = |i: usize, k: usize| if i == 2 { dd3[k] } else { 0.0 };
            let j = seg.pivot;
            let w = q[j] / d[j];
            let dw: [f64; 3] = std::array::from_fn(|k| (dq[j][k] - w * dd(j, k)) / d[j]);
            let (a, b) = match j {
                0 => (1, 2),
                1 => (0, 2),
                _ => (0, 1),
            };
            r = [q[a] - w * d[a], q[b] - w * d[b]];
            let row = |i: usize| std::array::from_fn(|k| dq[i][k] - dw[k] * d[i] - w * dd(i, k));
            jac = [row(a), row(b), [-dw[0], -dw[1], -dw[2]]];
            x0 = -(seg.index as f64 + w);
        }
        let state = ContactState {
            phase,
            point: ContourPoint {
                xc: g.x,
                yc: g.y,
                psi: g.psi,
            },
            f,
            s1,
            phi1,
            x0,
            phi0: shot.phi0,
            m0: shot.m0,
            iterations: 0,
            residual: r[0].hypot(r[1]),
            tilt: self.tilt,
        };
        Ok((
            r,
            Node {
                phase,
                u,
                state,
                jac,
            },
        ))
    }

    /// Newton's method on `R(u) = 0` with the third equation `constraint`, from `u`, until the
    /// residual norm is at most the tolerance ([`bvp_solvers::newton`]): damped by step
    /// halving when it grows; trial points are shot without sensitivities, but the one
    /// predicted to converge; the Jacobian is kept while it contracts the residual by 20x per
    /// step (simplified Newton) and recomputed otherwise, and always at the solution (for the
    /// branch's tangent). Slender tips put a noise floor on the shots (adaptive steps): a
    /// corrector that stalls just above the tolerance but within [`NOISE_FLOOR`] is accepted,
    /// its residual recorded in the state. Where Newton does not converge, `rescue` says
    /// whether the trust region tries from `u` ([`Rescue`]; at most [`MAX_TRUST_REGION`]
    /// iterations, initial radius 0.1, to the same tolerance). Fails with Newton's last
    /// residual.
    pub fn correct(
        &self,
        phase: Phase,
        u: [f64; 3],
        constraint: Constraint,
        rescue: Rescue,
    ) -> Result<Node> {
        self.correct_near(phase, u, constraint, None, rescue)
    }

    /// [`Branch::correct`] started with the branch Jacobian `near` of a nearby node (rows
    /// `dR0, dR1, dx0`) in place of one evaluated at `u`, where the constraint's gradient
    /// does not depend on the point (a hyperplane, a base position): Broyden's method from it
    /// first (full steps, the Jacobian evaluated only with the trial predicted to converge),
    /// then Newton from `u` where it fails.
    pub fn correct_near(
        &self,
        phase: Phase,
        u: [f64; 3],
        constraint: Constraint,
        near: Option<&[[f64; 3]; 3]>,
        rescue: Rescue,
    ) -> Result<Node> {
        let jac0 = near.and_then(|j| match constraint {
            Constraint::Hyperplane { n, .. } => Some([j[0], j[1], n]),
            Constraint::BasePosition(_) => Some(*j),
            _ => None,
        });
        let sys = Corrector {
            branch: self,
            phase,
            constraint,
            last_jac: Cell::new(None),
        };
        let policy = NewtonPolicy {
            tol: self.tol,
            max_iter: MAX_NEWTON,
            halvings: 5,
            update: JacobianUpdate::Reevaluate { keep_below: 0.05 },
            jacobian_at_solution: true,
            noise_floor: NOISE_FLOOR,
        };
        // From a nearby node's Jacobian: Broyden's method, full steps, the Jacobian
        // evaluated only with the trial predicted to converge; Newton from `u` if it fails.
        let opts = NonlinearOptions {
            start: Some(NewtonPolicy {
                halvings: 0,
                update: JacobianUpdate::Broyden {
                    min_contraction: 0.5,
                },
                ..policy
            }),
            newton: Some(policy),
            trust_region: (rescue == Rescue::TrustRegion).then_some(TrustRegionOptions {
                tol: self.tol,
                max_iters: MAX_TRUST_REGION,
                initial_radius: 0.1,
                max_radius: 10.0,
            }),
        };
        let ans = solve_square(&sys, u, jac0, &opts, &mut SquareReport::default())?;
        let mut node = sys.node(ans.point);
        match ans.termination {
            Termination::Converged => {
                node.state.iterations = ans.iterations as u64;
                Ok(node)
            }
            Termination::NoiseFloor => {
                node.state.residual = ans.norm;
                node.state.iterations = MAX_NEWTON as u64;
                Ok(node)
            }
            _ => Err(ContactError::PhaseSolve {
                phase,
                xc: node.state.point.xc,
                iterations: MAX_NEWTON as u64,
                residual: ans.norm,
            }),
        }
    }
}

/// The corrector's square system: `R0`, `R1` and the constraint's value, with the
/// constraint's gradient as the Jacobian's third row. The point is the node with whether its
/// Jacobian was evaluated there; `last_jac` keeps the branch Jacobian of the last node that
/// had one (a simplified-Newton node carries it).
struct Corrector<'b, 'a> {
    branch: &'b Branch<'a>,
    phase: Phase,
    constraint: Constraint,
    last_jac: Cell<Option<[[f64; 3]; 3]>>,
}

impl Corrector<'_, '_> {
    /// The constraint's value at `node`.
    fn value(&self, node: &Node) -> f64 {
        match self.constraint {
            Constraint::BasePosition(x) => node.state.x0 - x,
            Constraint::Hyperplane { n, p, .. } => dot(&n, &sub(&node.u, &p)),
            Constraint::PhaseEnd => match self.phase {
                Phase::B => node.state.s1 - 1.0,
                _ => node.state.phi1 - node.state.point.psi,
            },
            Constraint::NoForce => node.state.f,
        }
    }

    /// The constraint's gradient at `node` (its branch Jacobian for the base position).
    fn gradient(&self, node: &Node) -> [f64; 3] {
        match self.constraint {
            Constraint::BasePosition(_) => node.jac[2],
            Constraint::Hyperplane { n, .. } => n,
            Constraint::PhaseEnd => match self.phase {
                Phase::B => [1.0, 0.0, 0.0],
                _ => [1.0, 0.0, -self.branch.profile.at(node.u[2]).dpsi],
            },
            Constraint::NoForce => [0.0, 1.0, 0.0],
        }
    }

    /// The answer's node, carrying the last evaluated branch Jacobian if its own was not.
    fn node(&self, (mut node, fresh): (Node, bool)) -> Node {
        if !fresh {
            if let Some(j) = self.last_jac.get() {
                node.jac = j;
            }
        }
        node
    }
}

impl NewtonSystem<3> for Corrector<'_, '_> {
    type Point = (Node, bool);
    type Error = ContactError;

    fn eval(&self, u: &[f64; 3], jacobian: bool) -> Result<Evaluation<3, (Node, bool)>> {
        let (r, node) = self.branch.eval_with(self.phase, *u, jacobian)?;
        let jac = jacobian.then(|| {
            self.last_jac.set(Some(node.jac));
            [node.jac[0], node.jac[1], self.gradient(&node)]
        });
        Ok(Evaluation {
            r: [r[0], r[1], self.value(&node)],
            jac,
            point: (node, jacobian),
        })
    }

    fn admissible(&self, u: &[f64; 3]) -> bool {
        match self.constraint {
            Constraint::Hyperplane { p, radius, .. } => norm(&sub(u, &p)) <= radius,
            _ => true,
        }
    }
}

/// The rows `x0 = X` of [`Branch::broyden_at_base`]: `R0`, `R1`, `x0 - X`, never with a
/// Jacobian.
struct AtBase<'b, 'a> {
    branch: &'b Branch<'a>,
    phase: Phase,
    x0: f64,
}

impl NewtonSystem<3> for AtBase<'_, '_> {
    type Point = Node;
    type Error = ContactError;

    fn eval(&self, u: &[f64; 3], _jacobian: bool) -> Result<Evaluation<3, Node>> {
        let (r, node) = self.branch.eval_with(self.phase, *u, false)?;
        Ok(Evaluation {
            r: [r[0], r[1], node.state.x0 - self.x0],
            jac: None,
            point: node,
        })
    }
}

impl Branch<'_> {
    /// Broyden's method for the equations `R = 0`, `x0 = X` from `u`, started with the
    /// Jacobian `jac` of a nearby row or node (rows `dR0, dR1, dx0`) and improved by a rank-one
    /// update after every step; shots without sensitivities only. Used from good predictions;
    /// `None` if the residual does not halve at every step or the tolerance is not reached in
    /// seven steps. The node carries the updated Jacobian, a good start for the next row.
    ///
    /// Through [`bvp_solvers::nonlinear::solve_square`] with its start stage only, no
    /// fallback: this is the row's fast attempt, and its caller follows a failure up with
    /// [`Branch::correct`] from its own starts (`rows::solve_row`); a trust region here would
    /// only repeat that work at a higher price.
    pub fn broyden_at_base(
        &self,
        phase: Phase,
        u: [f64; 3],
        x0: f64,
        jac: &[[f64; 3]; 3],
    ) -> Option<Node> {
        let sys = AtBase {
            branch: self,
            phase,
            x0,
        };
        // the start stage alone: no Newton with evaluated Jacobians (the caller's follow-up,
        // the corrector from its own starts), no trust region
        let opts = NonlinearOptions {
            start: Some(NewtonPolicy {
                max_iter: 7,
                halvings: 0,
                update: JacobianUpdate::Broyden {
                    min_contraction: 0.5,
                },
                jacobian_at_solution: false,
                ..NewtonPolicy::new(self.tol)
            }),
            newton: None,
            trust_region: None,
        };
        let ans = solve_square(&sys, u, Some(*jac), &opts, &mut SquareReport::default()).ok()?;
        (ans.termination == Termination::Converged).then(|| {
            let mut node = ans.point;
            node.jac = ans.jac;
            node.state.iterations = ans.iterations as u64;
            node
        })
    }
}

/// The cubic Hermite interpolant at `x` through `(xa, ua)` and `(xb, ub)` with slopes `da`,
/// `db` (`du/dx`), componentwise.
pub(crate) fn hermite(
    a: (f64, &[f64; 3], &[f64; 3]),
    b: (f64, &[f64; 3], &[f64; 3]),
    x: f64,
) -> [f64; 3] {
    let (xa, ua, da) = a;
    let (xb, ub, db) = b;
    let h = xb - xa;
    let [h00, h10, h01, h11] = bvp_solvers::interp::hermite_basis((x - xa) / h);
    let mut out = [0.0; 3];
    for i in 0..3 {
        out[i] = h00 * ua[i] + h10 * h * da[i] + h01 * ub[i] + h11 * h * db[i];
    }
    out
}

/// `a + w (b - a)`.
pub(crate) fn lerp(a: &[f64; 3], b: &[f64; 3], w: f64) -> [f64; 3] {
    [
        a[0] + w * (b[0] - a[0]),
        a[1] + w * (b[1] - a[1]),
        a[2] + w * (b[2] - a[2]),
    ]
}

pub(crate) fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn norm(a: &[f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// A whisker, flow, contour and integrator to build a branch on in the crate's tests.
    pub(crate) struct TestScene {
        pub whisker: Whisker,
        pub flow: FluidLoad,
        pub profile: Profile,
        pub integration: Integration,
    }

    impl TestScene {
        /// A tapered, pre-curved whisker on a spring under a slanted flow past `g2`, shot
        /// at tolerance `tol`.
        pub(crate) fn bent(tol: f64) -> Self {
            TestScene {
                whisker: Whisker::new(0.6, 0.3, 0.2, 20.0),
                flow: FluidLoad { q: 2.0, alpha: 0.3 },
                profile: Profile::g2(),
                integration: Integration::adaptive(tol),
            }
        }

        /// A straight rigid whisker (no pre-curvature) without flow past `profile`.
        pub(crate) fn straight(profile: Profile) -> Self {
            TestScene {
                whisker: Whisker::new(0.6, 0.0, 0.0, f64::INFINITY),
                flow: FluidLoad { q: 0.0, alpha: 0.0 },
                profile,
                integration: Integration::adaptive(1e-12),
            }
        }

        /// The branch equations of the scene (corrector tolerance 1e-11).
        pub(crate) fn branch(&self) -> Branch<'_> {
            Branch {
                whisker: &self.whisker,
                flow: self.flow,
                profile: &self.profile,
                integration: &self.integration,
                tol: 1e-11,
                frame: Frame::Translate,
                tilt: Tilt::NONE,
            }
        }
    }

    /// The trust region rescues a contact solve that Newton alone does not converge: a
    /// straight whisker (no pre-curvature, no flow, clamped) with its base at the first tip
    /// touch of the circle of centre `(0.2, 1.3)` and radius 0.5, `x0 = 0.2 + sqrt(0.16) = 0.6`,
    /// from a start far off in tip angle and contour point. The truth is the free whisker
    /// itself: no force, tip angle `pi/2`, the tip on the circle at `(0.6, 1)`, contour
    /// parameter `psi = asin(0.8)`.
    #[test]
    fn the_trust_region_rescues_a_tip_contact_newton_misses() {
        let scene = TestScene::straight(Profile::parse("circle:0.2,1.3,0.5").unwrap());
        let branch = scene.branch();
        let (u, at) = ([2.6, 0.0, 1.5], Constraint::BasePosition(0.6));
        let alone = branch.correct(Phase::A, u, at, Rescue::NewtonOnly);
        assert!(
            matches!(alone, Err(ContactError::PhaseSolve { .. })),
            "{alone:?}"
        );
        let node = branch
            .correct(Phase::A, u, at, Rescue::TrustRegion)
            .unwrap();
        let [phi1, f, t] = node.u;
        let err = [phi1 - FRAC_PI_2, f, t - 0.8f64.asin(), node.x0() - 0.6];
        assert!(err.iter().all(|e| e.abs() < 1e-11), "{err:?}");
        assert!((node.state.point.yc - 1.0).abs() < 1e-11);
        assert!(node.state.residual <= branch.tol && node.state.iterations > 0);
        // the node carries the Jacobian at the solution: its tangent is the branch's
        let (_, fresh) = branch.eval(Phase::A, node.u).unwrap();
        assert_eq!(node.jac, fresh.jac);
    }

    /// The branch Jacobian (rows `dR0, dR1, dx0` in `(v, f, t)`), assembled from the shot's
    /// sensitivities, matches central differences of the branch equations in both phases,
    /// on a spring base (the follicle law's rate) under a slanted flow; the tangent is the
    /// unit null vector of its first two rows, the slope has unit rate in x0.
    #[test]
    fn the_branch_jacobian_matches_central_differences() {
        let scene = TestScene::bent(1e-13);
        let branch = scene.branch();
        for (phase, u) in [(Phase::A, [1.2, 0.8, 0.3]), (Phase::B, [0.7, 0.8, 0.3])] {
            let (_, node) = branch.eval(phase, u).unwrap();
            let h = 1e-5;
            for k in 0..3 {
                let at = |d: f64| {
                    let mut v = u;
                    v[k] += d;
                    let (r, n) = branch.eval(phase, v).unwrap();
                    [r[0], r[1], n.x0()]
                };
                let (p, m) = (at(h), at(-h));
                for i in 0..3 {
                    let fd = (p[i] - m[i]) / (2.0 * h);
                    let err = (node.jac[i][k] - fd).abs();
                    assert!(err < 1e-7 * (1.0 + fd.abs()), "{phase}: d{i}/du{k} {err:e}");
                }
            }
            let t = node.tangent(&[1.0, 0.0, 0.0]);
            assert!(dot(&node.jac[0], &t).abs() < 1e-12 && dot(&node.jac[1], &t).abs() < 1e-12);
            assert!((norm(&t) - 1.0).abs() < 1e-15 && t[0] >= 0.0);
            assert!((dot(&node.jac[2], &node.slope()) - 1.0).abs() < 1e-12);
        }
    }
}
