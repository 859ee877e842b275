//! The frictional contact equations of one scene in both phases: the state
//! `w = (v, fn, ft, t)` (`v = phi1` in tip contact, `v = s1` in tangential contact), the mode
//! (stick or slip) and its equation, the corrector and the curve's tangent.
//!
//! Two equations hold in every phase and mode, the base condition
//! `R0 = phi(0) - pi/2 - m(0)/k = 0` [3.21, 3.22] and the contact point on the contour
//! `R1 = y(s1) - y(0) - yc(t) = 0` [5.4-5.10], the force `F = fn n + ft t` applied at `s1` as a
//! direction-preserving force (the segment beyond `s1` unloaded, so `m(s1) = 0`); in phase B the
//! tangency `phi(s1) = psi(t)` is built in (the shot starts from `phi1 = psi(t)`). The mode adds
//! the third:
//! - phase A, stick: `t = t*` (the tip is the material point, pinned where it stuck);
//! - phase B, stick (rolling without sliding): `sigma(t) - s1 = sigma(t*) - s1*`, `sigma` the
//!   contour's arc length oriented with the whisker (`phi(s1) = psi`: the whisker's tangent at
//!   `s1` is the contour's `t`); the touching material point moves along `t` at
//!   `d sigma - d s1`, zero while it sticks;
//! - slip (both phases): `ft = s mu fn`, `s = -sign(u)`.

use super::contour::arc_length;
use crate::contact_law::force;
use crate::contact_law::SlipState;
use crate::error::{ContactError, Result};
use crate::motion::Frame;
use crate::phase::{ContactState, ContourPoint, Phase};
use crate::profile::{ContourGeom, Profile};
use beam_model::equations::Sensitivities;
use beam_model::shot::{shoot, BaseValues, Integration, Shot};
use beam_model::{FluidLoad, LoadKind, Loads, TipForce, Whisker};

/// The mode of a stretch of the frictional path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Mode {
    /// The material point stuck: in phase A the tip at contour parameter `anchor`; in phase
    /// B rolling from the contact point `anchor` at arc length `s1` (`sigma - s1` constant).
    Stick { anchor: f64, s1: f64 },
    /// Sliding with `ft = s mu fn`, `s = -sign(u)`.
    Slip { s: f64 },
}

impl Mode {
    pub(super) fn slip_state(&self) -> SlipState {
        match self {
            Mode::Stick { .. } => SlipState::Stick,
            Mode::Slip { .. } => SlipState::Slip,
        }
    }
}

/// A point of the frictional contact path.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    /// Tip (A) or tangential (B) contact.
    pub(super) phase: Phase,
    pub(super) mode: Mode,
    /// `(phi1 or s1, fn, ft, t)`.
    pub(super) w: [f64; 4],
    pub(super) x0: f64,
    pub(super) phi0: f64,
    pub(super) m0: f64,
    pub(super) geom: ContourGeom,
    /// Rows `dR0, dR1, dx0` with respect to `w` (zero on a row solved without them,
    /// `FrictionBranch::correct_near` with `want_jac` unset).
    pub(super) jac: [[f64; 4]; 3],
}

/// The frictional contact equations of one scene.
pub(super) struct FrictionBranch<'a> {
    pub(super) whisker: &'a Whisker,
    pub(super) flow: FluidLoad,
    pub(super) profile: &'a Profile,
    pub(super) integration: Integration,
    pub(super) tol: f64,
    pub(super) mu: f64,
    /// How the base moves ([`Frame`]): which two equations are `(R0, R1)` and which
    /// function of the state is the falling coordinate (the node's `x0`), as in the
    /// frictionless branch ([`crate::branch::Branch::frame`]; [`reframe`]).
    pub(super) frame: Frame,
}

/// Largest residual accepted from a corrector that stalls (the shots' noise floor).
pub(super) const NOISE_FLOOR: f64 = 1e-10;

/// Newton iterations of one corrector solve (twice as many simplified ones).
pub(super) const MAX_NEWTON: usize = 12;

/// The residual's contraction per simplified Newton step below which the kept Jacobian is
/// evaluated afresh (as the frictionless corrector's 20x).
pub(super) const CONTRACTION: f64 = 0.05;

/// Diameter ratio below which every shot carries sensitivities (the frictionless branch's:
/// slender tips put a noise floor on the plain shots).
const SLENDER: f64 = 0.15;

pub(super) fn lin(a: f64, x: &BaseValues, b: f64, y: &BaseValues) -> BaseValues {
    BaseValues {
        phi0: a * x.phi0 + b * y.phi0,
        m0: a * x.m0 + b * y.m0,
        dx: a * x.dx + b * y.dx,
        dy: a * x.dy + b * y.dy,
    }
}

impl FrictionBranch<'_> {
    pub(super) fn loads(&self, fx: f64, fy: f64, s1: f64) -> Loads {
        Loads {
            tip: TipForce {
                f: fx.hypot(fy),
                beta: (-fy).atan2(fx),
                kind: LoadKind::Dp,
            },
            fluid: self.flow,
            s1,
        }
    }

    pub(super) fn shot(&self, loads: &Loads, phi1: f64, jac: bool) -> Result<Shot> {
        let sens = if jac {
            Sensitivities::All
        } else {
            Sensitivities::None
        };
        Ok(shoot(self.whisker, loads, phi1, sens, &self.integration)?)
    }

    /// The equations at `w` in `phase`: residual `(R0, R1)`, and the node (Jacobian rows if
    /// `jac`).
    pub(super) fn eval(
        &self,
        phase: Phase,
        mode: Mode,
        w: [f64; 4],
        jac: bool,
    ) -> Result<([f64; 2], Node)> {
        let [v, f, ft, t] = w;
        let (lo, hi) = self.profile.param_range();
        if !(t >= lo && t <= hi) {
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
        if !(phi1.is_finite() && f.is_finite() && ft.is_finite() && s1 > 1e-6 && s1 <= 1.5) {
            return Err(ContactError::PhaseSolve {
                phase,
                xc: f64::NAN,
                iterations: 0,
                residual: f64::NAN,
            });
        }
        let (fx, fy) = force(g.psi, f, ft);
        let loads = self.loads(fx, fy, s1);
        let shot = self.shot(&loads, phi1, jac)?;
        let support = &self.whisker.support;
        let mut jm = [[0.0; 4]; 3];
        // the shot's raw rates per column (phi0, m0, dx, dy), which a path's follicle law
        // reads ([`reframe`])
        let mut raw = [BaseValues::default(); 4];
        if jac {
            // d(shot)/dFx and d(shot)/dFy
            let big = loads.tip.f;
            let (cx, cy) = if big > 0.0 {
                let (sb, cb) = loads.tip.beta.sin_cos();
                let db = lin(1.0 / big, &shot.d_beta, 0.0, &shot.d_beta);
                (lin(cb, &shot.d_f, -sb, &db), lin(-sb, &shot.d_f, -cb, &db))
            } else {
                // no force: the responses to unit forces along x and y, one shot each
                let along = |beta: f64| -> Result<BaseValues> {
                    let mut l = loads;
                    l.tip.beta = beta;
                    Ok(self.shot(&l, phi1, true)?.d_f)
                };
                (along(0.0)?, along(-std::f64::consts::FRAC_PI_2)?)
            };
            let (sp, cp) = g.psi.sin_cos();
            let col = |d: BaseValues| [support.residual_rate(d.phi0, d.m0), d.dy, -d.dx];
            // d/dv: the tip angle in phase A; in phase B the contact arc length
            let c_v = match phase {
                Phase::B => col(shot.d_s1),
                _ => col(shot.d_phi1),
            };
            let c_f = col(lin(sp, &cx, -cp, &cy));
            let c_ft = col(lin(cp, &cx, sp, &cy));
            // d/dt: F turns with the contour, dF/dpsi = fn t - ft n; the contact point moves
            let (dfx, dfy) = (f * cp - ft * sp, f * sp + ft * cp);
            let mut dt = lin(dfx * g.dpsi, &cx, dfy * g.dpsi, &cy);
            if phase == Phase::B {
                // and the tangency turns the whisker at s1: phi1 = psi(t)
                dt = lin(1.0, &dt, g.dpsi, &shot.d_phi1);
            }
            let mut c_t = col(dt);
            c_t[1] -= g.dy;
            c_t[2] += g.dx;
            for i in 0..3 {
                jm[i] = [c_v[i], c_f[i], c_ft[i], c_t[i]];
            }
            let d_v = match phase {
                Phase::B => shot.d_s1,
                _ => shot.d_phi1,
            };
            raw = [d_v, lin(sp, &cx, -cp, &cy), lin(cp, &cx, sp, &cy), dt];
        }
        let mut r = [support.residual(shot.phi0, shot.m0), shot.dy - g.y];
        let mut x0 = g.x - shot.dx;
        if self.frame != Frame::Translate {
            let base = (shot.phi0, shot.m0, g.y - shot.dy);
            (r, x0) = reframe(self.frame, (r, x0), base, &raw, &mut jm);
        }
        Ok((
            r,
            Node {
                phase,
                mode,
                w,
                x0,
                phi0: shot.phi0,
                m0: shot.m0,
                geom: g,
                jac: jm,
            },
        ))
    }

    /// The mode's equation at `w` in `phase` and its gradient: stick in phase A `t - t*`, in
    /// phase B `sigma(t) - sigma(t*) - (s1 - s1*)` (rolling); slip `ft - s mu fn`.
    pub(super) fn mode_eq(&self, phase: Phase, mode: Mode, w: &[f64; 4]) -> (f64, [f64; 4]) {
        match mode {
            Mode::Stick { anchor, s1 } => match phase {
                Phase::B => (
                    arc_length(self.profile, anchor, w[3]) - (w[0] - s1),
                    [-1.0, 0.0, 0.0, self.speed(w[3])],
                ),
                _ => (w[3] - anchor, [0.0, 0.0, 0.0, 1.0]),
            },
            Mode::Slip { s } => (w[2] - s * self.mu * w[1], [0.0, -s * self.mu, 1.0, 0.0]),
        }
    }

    /// `d sigma / dt`: the contour's speed at parameter `t`.
    pub(super) fn speed(&self, t: f64) -> f64 {
        let g = self.profile.at(t);
        g.dx.hypot(g.dy)
    }

    /// The corrector on `(R0, R1, mode, constraint)` from `w` in `phase`
    /// ([`Self::correct_near`] without a nearby Jacobian; the node returned carries its
    /// Jacobian).
    pub(super) fn correct(&self, phase: Phase, mode: Mode, w: [f64; 4], con: Con) -> Result<Node> {
        self.correct_near(phase, mode, w, con, None, true)
    }

    /// Simplified Newton on `(R0, R1, mode, constraint)` from `w` in `phase`, damped by
    /// halving where the residual grows. The rows `dR0, dR1, dx0` of the Jacobian start as
    /// `near`'s (a nearby node's, no shot spent) or are evaluated at `w`; after every step
    /// they get Broyden's update along it, and they are evaluated afresh where a step
    /// contracts the residual less than [`CONTRACTION`]; the mode's and the constraint's rows
    /// are always exact. Trial points are shot without sensitivities (a fifth to a tenth of
    /// a shot with them), the solution once more with them if `want_jac` (the curve's tangent
    /// needs it). Every shot carries sensitivities (Newton) for slender tips (theta < 0.15,
    /// as the frictionless corrector) and where the integrator's tolerance is above ten times
    /// the residual's (an estimate's loose solve: plain shots and shots with sensitivities
    /// differ at the integrator's tolerance); and a solve that fails with plain shots is run
    /// again that way from `w`. A corrector that stalls within [`NOISE_FLOOR`] is accepted.
    pub(super) fn correct_near(
        &self,
        phase: Phase,
        mode: Mode,
        w: [f64; 4],
        con: Con,
        near: Option<&[[f64; 4]; 3]>,
        want_jac: bool,
    ) -> Result<Node> {
        // plain shots and shots with sensitivities differ at the integrator's tolerance: where
        // that is far above the residual's (an estimate's loose solve), or the tip slender,
        // every shot carries sensitivities (Newton as before)
        let rtol = match &self.integration {
            Integration::Dop853(d) => d.rtol,
            Integration::Rk4 { .. } => 0.0,
        };
        let always = self.whisker.theta < SLENDER || rtol > 10.0 * self.tol;
        match self.solve(phase, mode, w, con, near, want_jac, always) {
            // where the plain shots' noise stops it above the tolerance (or the kept
            // Jacobian leads astray): Newton with every shot's sensitivities from `w`
            Err(_) if !always => self.solve(phase, mode, w, con, None, want_jac, true),
            r => r,
        }
    }

    /// [`Self::correct_near`]'s iteration, every shot with sensitivities if `always`.
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &self,
        phase: Phase,
        mode: Mode,
        w: [f64; 4],
        con: Con,
        near: Option<&[[f64; 4]; 3]>,
        want_jac: bool,
        always: bool,
    ) -> Result<Node> {
        let near = if always { None } else { near };
        let system = |w: [f64; 4], jac: bool| -> Result<([f64; 4], Node)> {
            let (r, node) = self.eval(phase, mode, w, jac || always)?;
            let (m, _) = self.mode_eq(phase, mode, &w);
            Ok(([r[0], r[1], m, self.constraint(&con, &node).0], node))
        };
        let matrix = |jr: &[[f64; 4]; 3], node: &Node| -> [[f64; 4]; 4] {
            let (_, gm) = self.mode_eq(phase, mode, &node.w);
            let gc = match con {
                Con::Base(_) => jr[2],
                _ => self.constraint(&con, node).1,
            };
            [jr[0], jr[1], gm, gc]
        };
        let mut w = w;
        let (mut r, mut node) = system(w, near.is_none())?;
        // the Jacobian rows in use, and whether they (and the node's) are evaluated at `w`
        let mut jm = matrix(near.unwrap_or(&node.jac), &node);
        let mut fresh = near.is_none() || always;
        if always {
            jm = matrix(&node.jac, &node);
        }
        let mut best = norm4(&r);
        let mut converged = best <= self.tol;
        for it in 0..2 * MAX_NEWTON {
            if converged {
                break;
            }
            let dw = solve4(jm, [-r[0], -r[1], -r[2], -r[3]]);
            let mut accepted = None;
            if let Some(dw) = dw {
                let mut lambda = 1.0;
                for _ in 0..6 {
                    let trial = [
                        w[0] + lambda * dw[0],
                        w[1] + lambda * dw[1],
                        w[2] + lambda * dw[2],
                        w[3] + lambda * dw[3],
                    ];
                    if let Ok((rt, nt)) = system(trial, false) {
                        let n = norm4(&rt);
                        if n < best || (n <= NOISE_FLOOR && lambda == 1.0) {
                            accepted = Some((trial, rt, nt, n));
                            break;
                        }
                    }
                    lambda *= 0.5;
                }
            }
            match accepted {
                Some((trial, rt, nt, n)) => {
                    let contracted = n <= CONTRACTION * best;
                    // Broyden's update of the kept Jacobian along the step (the mode's and
                    // the constraint's rows then exact again)
                    let (dw, dr) = (sub4(&trial, &w), sub4(&rt, &r));
                    let dd = dot4(&dw, &dw);
                    if dd > 0.0 {
                        for i in 0..4 {
                            let u = (dr[i] - dot4(&jm[i], &dw)) / dd;
                            for (j, d) in dw.iter().enumerate() {
                                jm[i][j] += u * d;
                            }
                        }
                    }
                    (w, r, node, best) = (trial, rt, nt, n);
                    jm[2] = self.mode_eq(phase, mode, &node.w).1;
                    if !matches!(con, Con::Base(_)) {
                        jm[3] = self.constraint(&con, &node).1;
                    }
                    fresh = always;
                    if always {
                        jm = matrix(&node.jac, &node);
                    }
                    converged = best <= self.tol;
                    if !converged && !contracted && !fresh {
                        (r, node) = system(w, true)?;
                        (jm, fresh, best) = (matrix(&node.jac, &node), true, norm4(&r));
                        converged = best <= self.tol;
                    }
                }
                None if !fresh => {
                    // the kept Jacobian failed: once more with the Jacobian at `w`
                    (r, node) = system(w, true)?;
                    (jm, fresh, best) = (matrix(&node.jac, &node), true, norm4(&r));
                    converged = best <= self.tol;
                }
                None => {
                    converged = best <= NOISE_FLOOR && it > 0;
                    break;
                }
            }
        }
        if !(converged || best <= NOISE_FLOOR) {
            return Err(ContactError::PhaseSolve {
                phase,
                xc: node.geom.x,
                iterations: MAX_NEWTON as u64,
                residual: best,
            });
        }
        if want_jac && !fresh {
            node = system(w, true)?.1;
        }
        Ok(node)
    }

    /// The corrector's fourth equation at `node` and its gradient in `w`.
    pub(super) fn constraint(&self, con: &Con, node: &Node) -> (f64, [f64; 4]) {
        let w = &node.w;
        match *con {
            Con::Base(x) => (node.x0 - x, node.jac[2]),
            Con::Plane { n, p } => (dot4(&n, &sub4(w, &p)), n),
            Con::Mode(m) => self.mode_eq(node.phase, m, w),
            Con::PhaseEnd => match node.phase {
                Phase::B => (w[0] - 1.0, [1.0, 0.0, 0.0, 0.0]),
                _ => (w[0] - node.geom.psi, [1.0, 0.0, 0.0, -node.geom.dpsi]),
            },
        }
    }

    /// The unit tangent of the mode's curve at `node` (null vector of `(R0, R1, mode)`'s
    /// Jacobian), oriented along `dir`.
    pub(super) fn tangent(&self, node: &Node, dir: &[f64; 4]) -> [f64; 4] {
        let (_, gm) = self.mode_eq(node.phase, node.mode, &node.w);
        let rows = [node.jac[0], node.jac[1], gm];
        let mut t = [0.0; 4];
        for (k, tk) in t.iter_mut().enumerate() {
            let cols: Vec<usize> = (0..4).filter(|&c| c != k).collect();
            let m = |i: usize, j: usize| rows[i][cols[j]];
            let d = m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1))
                - m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0))
                + m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
            *tk = if k % 2 == 0 { d } else { -d };
        }
        let n = norm4(&t);
        let s = if dot4(&t, dir) < 0.0 { -1.0 } else { 1.0 };
        t.map(|v| s * v / n)
    }

    /// The tangent oriented so that x0 falls.
    pub(super) fn falling(&self, node: &Node) -> [f64; 4] {
        let t = self.tangent(node, &[0.0; 4]);
        if dot4(&node.jac[2], &t) > 0.0 {
            t.map(|v| -v)
        } else {
            t
        }
    }
}

/// The branch's two equations and falling coordinate in the motion's frame (spec/model.md,
/// "Base motions"; the frictionless branch's reading, [`crate::branch::Branch`], on `N`
/// columns): from the translation's `R = (R0, R1)` [3.21, 3.22; 5.4-5.10] and `x0 = xc - dx`
/// at the base `(phi0, m0, yb = yc - dy)`, their rows `jm` (`dR0, dR1, dx0`) and the shot's
/// raw rates `raw` per column:
/// - a rotation about `(bx, by)` holds `xb = bx`, `yb = by`, its coordinate `-gamma = -R0`
///   (the follicle law turned by gamma, `phi0 = pi/2 + gamma + m0/k`);
/// - a path segment holds `Q_a = w D_a` for the two rows but its pivot `j`, its coordinate
///   `-p = -(i + Q_j / D_j)` with `Q = (xb - X_i, yb - Y_i, phi0 - pi/2 - m0 c_i - G_i)`,
///   `D = (DX, DY, DG + m0 dc)` ([`crate::motion`]'s notes).
///
/// The friction law does not enter: the sliding velocity of the touching material point is
/// the contact point's motion along the fixed contour less `ds1` (lab frame, any motion).
pub(super) fn reframe<const N: usize>(
    frame: Frame,
    (r, x0): ([f64; 2], f64),
    (phi0, m0, yb): (f64, f64, f64),
    raw: &[BaseValues; N],
    jm: &mut [[f64; N]; 3],
) -> ([f64; 2], f64) {
    match frame {
        Frame::Translate => (r, x0),
        Frame::Rotate { x0: bx, y0: by } => {
            let row0 = jm[0];
            jm[0] = jm[2];
            jm[2] = row0.map(|v| -v);
            ([x0 - bx, r[1] + by], -r[0])
        }
        Frame::Path(seg) => {
            let q = [
                x0 - seg.from.x0,
                yb - seg.from.y0,
                phi0 - std::f64::consts::FRAC_PI_2 - m0 * seg.c0 - seg.from.gamma,
            ];
            let d = [seg.rate.x0, seg.rate.y0, seg.rate.gamma + m0 * seg.dc];
            let dq: [[f64; N]; 3] = [
                jm[2],
                jm[1].map(|v| -v),
                std::array::from_fn(|k| raw[k].phi0 - seg.c0 * raw[k].m0),
            ];
            let dd3: [f64; N] = std::array::from_fn(|k| seg.dc * raw[k].m0);
            let dd = |i: usize, k: usize| if i == 2 { dd3[k] } else { 0.0 };
            let j = seg.pivot;
            let w = q[j] / d[j];
            let dw: [f64; N] = std::array::from_fn(|k| (dq[j][k] - w * dd(j, k)) / d[j]);
            let (a, b) = match j {
                0 => (1, 2),
                1 => (0, 2),
                _ => (0, 1),
            };
            let row = |i: usize| std::array::from_fn(|k| dq[i][k] - dw[k] * d[i] - w * dd(i, k));
            *jm = [row(a), row(b), dw.map(|v| -v)];
            ([q[a] - w * d[a], q[b] - w * d[b]], -(seg.index as f64 + w))
        }
    }
}

/// The fourth equation of a corrector.
#[derive(Clone, Copy, Debug)]
pub(super) enum Con {
    /// `x0 = X`.
    Base(f64),
    /// `n . (w - p) = 0`.
    Plane { n: [f64; 4], p: [f64; 4] },
    /// Another mode's equation (a stick/slip switch's row on both legs at once).
    Mode(Mode),
    /// The phase's end: `phi1 = psi` in phase A, `s1 = 1` in phase B.
    PhaseEnd,
}

pub(super) fn dot4(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(super) fn sub4(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
}

pub(super) fn norm4(a: &[f64; 4]) -> f64 {
    dot4(a, a).sqrt()
}

/// Gaussian elimination with partial pivoting; `None` if singular.
pub(super) fn solve4(mut a: [[f64; 4]; 4], mut b: [f64; 4]) -> Option<[f64; 4]> {
    for c in 0..4 {
        let p = (c..4).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c] == 0.0 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        let pivot = a[c];
        for r in c + 1..4 {
            let m = a[r][c] / pivot[c];
            for (x, y) in a[r].iter_mut().zip(pivot).skip(c) {
                *x -= m * y;
            }
            b[r] -= m * b[c];
        }
    }
    let mut x = [0.0; 4];
    for c in (0..4).rev() {
        let s: f64 = (c + 1..4).map(|k| a[c][k] * x[k]).sum();
        x[c] = (b[c] - s) / a[c][c];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

impl FrictionBranch<'_> {
    pub(super) fn clone_shallow(&self) -> Self {
        FrictionBranch {
            integration: self.integration.clone(),
            ..*self
        }
    }
}

impl Node {
    /// Whether `o` lies on the same leg of the path (phase and mode).
    pub(super) fn same_leg(&self, o: &Node) -> bool {
        self.phase == o.phase && self.mode == o.mode
    }

    /// The contact arc length: `s1` in phase B, 1 (the tip) in phase A.
    pub(super) fn s1(&self) -> f64 {
        match self.phase {
            Phase::B => self.w[0],
            _ => 1.0,
        }
    }

    /// The tangent angle at the contact: `phi1` in phase A, `psi` in phase B.
    pub(super) fn phi1(&self) -> f64 {
        match self.phase {
            Phase::B => self.geom.psi,
            _ => self.w[0],
        }
    }
}

/// The contact state of a node (its `f` the normal force).
pub(super) fn state_of(n: &Node) -> ContactState {
    ContactState {
        phase: n.phase,
        point: ContourPoint {
            xc: n.geom.x,
            yc: n.geom.y,
            psi: n.geom.psi,
        },
        f: n.w[1],
        s1: n.s1(),
        phi1: n.phi1(),
        x0: n.x0,
        phi0: n.phi0,
        m0: n.m0,
        iterations: 0,
        residual: 0.0,
        tilt: crate::contact_law::Tilt::NONE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Jacobian of `(R0, R1, x0)` in `w = (phi1 or s1, fn, ft, t)` (from the shot's
    /// sensitivities, and at `F = 0` from the two axis shots) matches central differences in
    /// both phases, and so does the gradient of the rolling equation of phase B's stick.
    #[test]
    fn the_jacobian_matches_central_differences() {
        let whisker = Whisker::new(0.4, 0.8, 0.3, 15.0);
        let profile = Profile::g2();
        let b = FrictionBranch {
            whisker: &whisker,
            flow: FluidLoad {
                q: 1.5,
                alpha: -0.4,
            },
            profile: &profile,
            integration: Integration::adaptive(1e-13),
            tol: 1e-11,
            mu: 0.5,
            frame: Frame::Translate,
        };
        let mode = Mode::Slip { s: 1.0 };
        for (phase, w) in [
            (Phase::A, [2.1, 0.8, -0.3, 0.7]),
            (Phase::A, [1.9, 0.0, 0.0, 0.4]),
            (Phase::A, [2.4, 1.3, 0.6, -0.2]),
            (Phase::B, [0.7, 0.8, -0.3, 0.3]),
            (Phase::B, [0.85, 0.0, 0.0, 0.5]),
            (Phase::B, [0.6, 1.3, 0.6, -0.2]),
        ] {
            let (_, n) = b.eval(phase, mode, w, true).unwrap();
            let h = 1e-6;
            for k in 0..4 {
                let at = |d: f64| {
                    let mut v = w;
                    v[k] += d;
                    let (r, n) = b.eval(phase, mode, v, false).unwrap();
                    [r[0], r[1], n.x0]
                };
                let (p, m) = (at(h), at(-h));
                for i in 0..3 {
                    let fd = (p[i] - m[i]) / (2.0 * h);
                    let err = (n.jac[i][k] - fd).abs();
                    assert!(
                        err < 1e-6 * (1.0 + fd.abs()),
                        "{phase} {w:?}: d{i}/dw{k} {} vs {fd}",
                        n.jac[i][k]
                    );
                }
            }
            // the rolling equation: zero at its anchor, its gradient the differences'
            let stick = Mode::Stick {
                anchor: 0.1,
                s1: 0.9,
            };
            let (m, g) = b.mode_eq(Phase::B, stick, &w);
            let (m0, _) = b.mode_eq(Phase::B, stick, &[0.9, 0.0, 0.0, 0.1]);
            assert_eq!(m0, 0.0);
            for k in 0..4 {
                let mut v = w;
                v[k] += 1e-6;
                let (mp, _) = b.mode_eq(Phase::B, stick, &v);
                v[k] -= 2e-6;
                let (mm, _) = b.mode_eq(Phase::B, stick, &v);
                let fd = (mp - mm) / 2e-6;
                assert!(
                    (g[k] - fd).abs() < 1e-8 * (1.0 + fd.abs()),
                    "{m} {g:?} {k} {fd}"
                );
            }
        }
    }
}
