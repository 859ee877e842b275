//! The frictional contact equations of one scene: the state `w`, the mode (stick or slip)
//! and its equation, the corrector and the curve's tangent.

use crate::contact_law::force;
use crate::contact_law::SlipState;
use crate::error::{ContactError, Result};
use crate::phase::{ContactState, ContourPoint, Phase};
use crate::profile::{ContourGeom, Profile};
use beam_model::equations::Sensitivities;
use beam_model::shot::{shoot, BaseValues, Integration, Shot};
use beam_model::{FluidLoad, LoadKind, Loads, TipForce, Whisker};

/// The mode of a stretch of the frictional path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Mode {
    /// The tip pinned at contour parameter `anchor`.
    Stick { anchor: f64 },
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

/// A point of the frictional tip-contact path.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    pub(super) mode: Mode,
    /// `(phi1, fn, ft, t)`.
    pub(super) w: [f64; 4],
    pub(super) x0: f64,
    pub(super) phi0: f64,
    pub(super) m0: f64,
    pub(super) geom: ContourGeom,
    /// Rows `dR0, dR1, dx0` with respect to `w`.
    pub(super) jac: [[f64; 4]; 3],
}

/// The frictional tip-contact equations of one scene.
pub(super) struct TipBranch<'a> {
    pub(super) whisker: &'a Whisker,
    pub(super) flow: FluidLoad,
    pub(super) profile: &'a Profile,
    pub(super) integration: Integration,
    pub(super) tol: f64,
    pub(super) mu: f64,
}

/// Largest residual accepted from a corrector that stalls (the shots' noise floor).
pub(super) const NOISE_FLOOR: f64 = 1e-10;

/// Newton iterations of one corrector solve.
pub(super) const MAX_NEWTON: usize = 12;

pub(super) fn lin(a: f64, x: &BaseValues, b: f64, y: &BaseValues) -> BaseValues {
    BaseValues {
        phi0: a * x.phi0 + b * y.phi0,
        m0: a * x.m0 + b * y.m0,
        dx: a * x.dx + b * y.dx,
        dy: a * x.dy + b * y.dy,
    }
}

impl TipBranch<'_> {
    pub(super) fn loads(&self, fx: f64, fy: f64) -> Loads {
        Loads {
            tip: TipForce {
                f: fx.hypot(fy),
                beta: (-fy).atan2(fx),
                kind: LoadKind::Dp,
            },
            fluid: self.flow,
            s1: 1.0,
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

    /// The equations at `w`: residual `(R0, R1)`, and the node (Jacobian rows if `jac`).
    pub(super) fn eval(&self, mode: Mode, w: [f64; 4], jac: bool) -> Result<([f64; 2], Node)> {
        let [phi1, f, ft, t] = w;
        let (lo, hi) = self.profile.param_range();
        if !(t >= lo && t <= hi) {
            return Err(ContactError::LeftContour {
                profile: self.profile.name(),
                t,
            });
        }
        if !(phi1.is_finite() && f.is_finite() && ft.is_finite()) {
            return Err(ContactError::PhaseSolve {
                phase: Phase::A,
                xc: f64::NAN,
                iterations: 0,
                residual: f64::NAN,
            });
        }
        let g = self.profile.at(t);
        let (fx, fy) = force(g.psi, f, ft);
        let loads = self.loads(fx, fy);
        let shot = self.shot(&loads, phi1, jac)?;
        let support = &self.whisker.support;
        let mut jm = [[0.0; 4]; 3];
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
            let c_phi = col(shot.d_phi1);
            let c_f = col(lin(sp, &cx, -cp, &cy));
            let c_ft = col(lin(cp, &cx, sp, &cy));
            // d/dt: F turns with the contour, dF/dpsi = fn t - ft n; the contact point moves
            let (dfx, dfy) = (f * cp - ft * sp, f * sp + ft * cp);
            let mut c_t = col(lin(dfx * g.dpsi, &cx, dfy * g.dpsi, &cy));
            c_t[1] -= g.dy;
            c_t[2] += g.dx;
            for i in 0..3 {
                jm[i] = [c_phi[i], c_f[i], c_ft[i], c_t[i]];
            }
        }
        let r = [support.residual(shot.phi0, shot.m0), shot.dy - g.y];
        Ok((
            r,
            Node {
                mode,
                w,
                x0: g.x - shot.dx,
                phi0: shot.phi0,
                m0: shot.m0,
                geom: g,
                jac: jm,
            },
        ))
    }

    /// The mode's equation at `w` and its gradient.
    pub(super) fn mode_eq(&self, mode: Mode, w: &[f64; 4]) -> (f64, [f64; 4]) {
        match mode {
            Mode::Stick { anchor } => (w[3] - anchor, [0.0, 0.0, 0.0, 1.0]),
            Mode::Slip { s } => (w[2] - s * self.mu * w[1], [0.0, -s * self.mu, 1.0, 0.0]),
        }
    }

    /// Newton's method on `(R0, R1, mode, constraint)` from `w`, the Jacobian evaluated at
    /// every iterate, damped by halving where the residual grows.
    pub(super) fn correct(&self, mode: Mode, w: [f64; 4], con: Con) -> Result<Node> {
        let system = |w: [f64; 4]| -> Result<([f64; 4], [[f64; 4]; 4], Node)> {
            let (r, node) = self.eval(mode, w, true)?;
            let (m, gm) = self.mode_eq(mode, &w);
            let (c, gc) = match con {
                Con::Base(x) => (node.x0 - x, node.jac[2]),
                Con::Plane { n, p } => (dot4(&n, &sub4(&w, &p)), n),
            };
            Ok(([r[0], r[1], m, c], [node.jac[0], node.jac[1], gm, gc], node))
        };
        let mut w = w;
        let (mut r, mut j, mut node) = system(w)?;
        let mut best = norm4(&r);
        for it in 0..MAX_NEWTON {
            if best <= self.tol {
                return Ok(node);
            }
            let Some(dw) = solve4(j, [-r[0], -r[1], -r[2], -r[3]]) else {
                break;
            };
            let mut lambda = 1.0;
            let mut accepted = false;
            for _ in 0..6 {
                let trial = [
                    w[0] + lambda * dw[0],
                    w[1] + lambda * dw[1],
                    w[2] + lambda * dw[2],
                    w[3] + lambda * dw[3],
                ];
                if let Ok((rt, jt, nt)) = system(trial) {
                    let n = norm4(&rt);
                    if n < best || (n <= NOISE_FLOOR && lambda == 1.0) {
                        (w, r, j, node, best) = (trial, rt, jt, nt, n);
                        accepted = true;
                        break;
                    }
                }
                lambda *= 0.5;
            }
            if !accepted {
                if best <= NOISE_FLOOR && it > 0 {
                    return Ok(node);
                }
                break;
            }
        }
        if best <= self.tol || best <= NOISE_FLOOR {
            return Ok(node);
        }
        Err(ContactError::PhaseSolve {
            phase: Phase::A,
            xc: node.geom.x,
            iterations: MAX_NEWTON as u64,
            residual: best,
        })
    }

    /// The unit tangent of the mode's curve at `node` (null vector of `(R0, R1, mode)`'s
    /// Jacobian), oriented along `dir`.
    pub(super) fn tangent(&self, node: &Node, dir: &[f64; 4]) -> [f64; 4] {
        let (_, gm) = self.mode_eq(node.mode, &node.w);
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

/// The fourth equation of a corrector.
#[derive(Clone, Copy, Debug)]
pub(super) enum Con {
    /// `x0 = X`.
    Base(f64),
    /// `n . (w - p) = 0`.
    Plane { n: [f64; 4], p: [f64; 4] },
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

impl TipBranch<'_> {
    pub(super) fn clone_shallow(&self) -> Self {
        TipBranch {
            integration: self.integration.clone(),
            ..*self
        }
    }
}

/// The contact state of a node (its `f` the normal force).
pub(super) fn state_of(n: &Node) -> ContactState {
    ContactState {
        phase: Phase::A,
        point: ContourPoint {
            xc: n.geom.x,
            yc: n.geom.y,
            psi: n.geom.psi,
        },
        f: n.w[1],
        s1: 1.0,
        phi1: n.w[0],
        x0: n.x0,
        phi0: n.phi0,
        m0: n.m0,
        iterations: 0,
        residual: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Jacobian of `(R0, R1, x0)` in `w = (phi1, fn, ft, t)` (from the shot's
    /// sensitivities, and at `F = 0` from the two axis shots) matches central differences.
    #[test]
    fn the_jacobian_matches_central_differences() {
        let whisker = Whisker::new(0.4, 0.8, 0.3, 15.0);
        let profile = Profile::g2();
        let b = TipBranch {
            whisker: &whisker,
            flow: FluidLoad {
                q: 1.5,
                alpha: -0.4,
            },
            profile: &profile,
            integration: Integration::adaptive(1e-13),
            tol: 1e-11,
            mu: 0.5,
        };
        let mode = Mode::Slip { s: 1.0 };
        for w in [
            [2.1, 0.8, -0.3, 0.7],
            [1.9, 0.0, 0.0, 0.4],
            [2.4, 1.3, 0.6, -0.2],
        ] {
            let (_, n) = b.eval(mode, w, true).unwrap();
            let h = 1e-6;
            for k in 0..4 {
                let at = |d: f64| {
                    let mut v = w;
                    v[k] += d;
                    let (r, n) = b.eval(mode, v, false).unwrap();
                    [r[0], r[1], n.x0]
                };
                let (p, m) = (at(h), at(-h));
                for i in 0..3 {
                    let fd = (p[i] - m[i]) / (2.0 * h);
                    let err = (n.jac[i][k] - fd).abs();
                    assert!(
                        err < 1e-6 * (1.0 + fd.abs()),
                        "{w:?}: d{i}/dw{k} {} vs {fd}",
                        n.jac[i][k]
                    );
                }
            }
        }
    }
}
