//! Coulomb friction at the contact (spec/model.md, "Friction at the contact"; beyond the
//! thesis, whose ch. 7 names frictional contact as the model's next step).
//!
//! **The contact law is a value of its own**, [`ContactLaw`], part of the sweep's settings
//! (`SweepSettings::contact_law`): [`ContactLaw::Frictionless`] (the default) and
//! [`ContactLaw::Coulomb`] with `mu = 0` run the frictionless sweep unchanged (same code path,
//! the same rows bit for bit; callgrind on the bench scene +0.65 %, docs/friction.md);
//! `mu > 0` runs the frictional sweep of this module. The base motion (translation towards -x) stays the sweep's, so a later change of
//! the base pose does not touch the law.
//!
//! **The model.** Boundary tangent `t = (cos psi, sin psi)`, outward normal
//! `n = (sin psi, -cos psi)`; the force on the whisker `F = fn n + ft t`, `fn >= 0`. It is
//! applied as a direction-preserving tip force of size `|F|` at angle `beta` with
//! `F = |F| (cos beta, -sin beta)`; with `ft = 0` this is the frictionless
//! `beta = pi/2 - psi` [5.4-5.10]. Quasi-static Coulomb law with `u` the velocity along `t` of
//! the whisker's touching material point relative to the obstacle as the base moves:
//! - stick (`u = 0`): `|ft| <= mu fn`;
//! - slip (`u != 0`): `ft = -mu fn sign(u)`.
//!
//! **Phase A (tip contact)** is what this module solves. The state is
//! `w = (phi1, fn, ft, t)` (tip angle, force components, contour parameter of the contact
//! point, [`Profile::at`]). Two equations hold in every mode, the base condition
//! `R0 = phi(0) - pi/2 - m(0)/k = 0` [3.21, 3.22] and the tip on the contour
//! `R1 = y(1) - y(0) - yc(t) = 0`; the mode adds a third:
//! - stick: `t = t*`, the anchor (the tip is the material point, pinned where it stuck);
//! - slip: `ft = s mu fn` with `s = -sign(u)`; in phase A `u` has the sign of `dt` along the
//!   path (the contour parameter rises with x, the direction of `t`).
//!
//! so each mode is a curve in `w`, followed by pseudo-arclength continuation in the direction
//! of falling base position `x0 = xc(t) - (x(1) - x(0))`, its Jacobian from the shot's exact
//! sensitivities (`d/dFx`, `d/dFy` from `d/df`, `d/dbeta`; at `F = 0` from two shots along
//! the axes).
//!
//! **Events**, each located on the curve by regula falsi along the chord (every trial an exact
//! equilibrium on a hyperplane across it) to `event_tol` in `w`:
//! - stick -> slip where `mu fn - |ft|` falls to zero (either edge of the cone: a sliding
//!   reversal is a slip -> stick -> slip sequence through the cone's interior);
//! - slip -> stick where the sliding velocity vanishes (`-s dt/dpath` falls to zero);
//! - release (`fn = 0`), snap (x0 at a turning point), a second contact (the depth of
//!   `events`), the segment next to the tip touching, the end of the contour — as in
//!   the frictionless sweep.
//!
//! At each switch the new mode is checked to be consistent (stick: the force moves into the
//! cone; slip: the sliding is against `ft`); where neither mode is, the quasi-static problem
//! has no continuation and the sweep says so ([`ContactError::FrictionIndeterminate`]) rather
//! than return a row that breaks the law. At the first touch (`F = 0`) the mode is the
//! stick branch's if its force direction lies in the cone (`|dft| <= mu dfn`), slip with
//! `s = sign(dft)` otherwise.
//!
//! **Phase B (tangential contact) with friction is not implemented**: a frictional sweep
//! whose tip contact reaches `phi1 = psi`, or whose first touch is tangential, ends with
//! [`ContactError::FrictionInTangentialContact`]. The decision for it (docs/friction.md):
//! the touching material point of an inextensible whisker on a fixed obstacle moves along `t`
//! at `d sigma - d s1` (sigma the contact point's arc length along the boundary), so stick in
//! phase B is rolling without sliding, `sigma - s1` constant, with the four unknowns
//! `fn, ft, s1, sigma` against position (2), tangency (1) and rolling (1); the spec's
//! "s1 and the contact point stay put" would add a fifth condition to four unknowns.
//!
//! **Rows** at evenly spaced base positions from the first touch to the separation, one more
//! at each stick/slip switch, each solved in the mode of its stretch of the path (the anchor
//! is the sweep's state) from the bracketing nodes; each row carries `ft`, the
//! [`SlipState`] and the tip's slip displacement, the signed arc length along the contour
//! from the first touch to the contact point (constant while stuck).

use crate::accuracy::{row_integration_tol, row_solve_tol, ESTIMATE_FACTOR, ESTIMATE_MARGIN};
use crate::contact_law::{force, frictional_loads, frictional_observables};
pub use crate::contact_law::{ContactLaw, FrictionEvent, FrictionEventKind, SlipState, MAX_MU};
use crate::error::{ContactError, Result};
use crate::first_contact::{FirstContact, FirstTouch};
use crate::phase::{ContactState, ContourPoint, Phase};
use crate::profile::{ContourGeom, Profile};
use crate::sweep::{
    check_accuracy, pre_contact_rows, Separation, SweepPoint, SweepResult, SweepSettings,
};
use beam_model::equations::Sensitivities;
use beam_model::shot::{shoot, BaseValues, Integration, Shot};
use beam_model::{FluidLoad, LoadKind, Loads, TipForce, Whisker};

/// The mode of a stretch of the frictional path.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    /// The tip pinned at contour parameter `anchor`.
    Stick { anchor: f64 },
    /// Sliding with `ft = s mu fn`, `s = -sign(u)`.
    Slip { s: f64 },
}

impl Mode {
    fn slip_state(&self) -> SlipState {
        match self {
            Mode::Stick { .. } => SlipState::Stick,
            Mode::Slip { .. } => SlipState::Slip,
        }
    }
}

/// A point of the frictional tip-contact path.
#[derive(Clone, Copy, Debug)]
struct Node {
    mode: Mode,
    /// `(phi1, fn, ft, t)`.
    w: [f64; 4],
    x0: f64,
    phi0: f64,
    m0: f64,
    geom: ContourGeom,
    /// Rows `dR0, dR1, dx0` with respect to `w`.
    jac: [[f64; 4]; 3],
}

/// The frictional tip-contact equations of one scene.
struct TipBranch<'a> {
    whisker: &'a Whisker,
    flow: FluidLoad,
    profile: &'a Profile,
    integration: Integration,
    tol: f64,
    mu: f64,
}

/// Largest residual accepted from a corrector that stalls (the shots' noise floor).
const NOISE_FLOOR: f64 = 1e-10;

/// Newton iterations of one corrector solve.
const MAX_NEWTON: usize = 12;

/// How far in x0 the candidate modes of the first touch are followed to decide between
/// them ([`Sweeper::first_mode`]).
const PROBE: f64 = 1e-3;

/// How far in x0 the new mode at a stick/slip switch is followed to check that it keeps the
/// law ([`Sweeper::probe`]).
const SWITCH_PROBE: f64 = 1e-4;

/// Penetration depth from which a second contact counts (as in the frictionless sweep).
const PENETRATION_MARGIN: f64 = 1e-10;

fn lin(a: f64, x: &BaseValues, b: f64, y: &BaseValues) -> BaseValues {
    BaseValues {
        phi0: a * x.phi0 + b * y.phi0,
        m0: a * x.m0 + b * y.m0,
        dx: a * x.dx + b * y.dx,
        dy: a * x.dy + b * y.dy,
    }
}

impl TipBranch<'_> {
    fn loads(&self, fx: f64, fy: f64) -> Loads {
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

    fn shot(&self, loads: &Loads, phi1: f64, jac: bool) -> Result<Shot> {
        let sens = if jac {
            Sensitivities::All
        } else {
            Sensitivities::None
        };
        Ok(shoot(self.whisker, loads, phi1, sens, &self.integration)?)
    }

    /// The equations at `w`: residual `(R0, R1)`, and the node (Jacobian rows if `jac`).
    fn eval(&self, mode: Mode, w: [f64; 4], jac: bool) -> Result<([f64; 2], Node)> {
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
    fn mode_eq(&self, mode: Mode, w: &[f64; 4]) -> (f64, [f64; 4]) {
        match mode {
            Mode::Stick { anchor } => (w[3] - anchor, [0.0, 0.0, 0.0, 1.0]),
            Mode::Slip { s } => (w[2] - s * self.mu * w[1], [0.0, -s * self.mu, 1.0, 0.0]),
        }
    }

    /// Newton's method on `(R0, R1, mode, constraint)` from `w`, the Jacobian evaluated at
    /// every iterate, damped by halving where the residual grows.
    fn correct(&self, mode: Mode, w: [f64; 4], con: Con) -> Result<Node> {
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
    fn tangent(&self, node: &Node, dir: &[f64; 4]) -> [f64; 4] {
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
    fn falling(&self, node: &Node) -> [f64; 4] {
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
enum Con {
    /// `x0 = X`.
    Base(f64),
    /// `n . (w - p) = 0`.
    Plane { n: [f64; 4], p: [f64; 4] },
}

fn dot4(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn sub4(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
}

fn norm4(a: &[f64; 4]) -> f64 {
    dot4(a, a).sqrt()
}

/// Gaussian elimination with partial pivoting; `None` if singular.
fn solve4(mut a: [[f64; 4]; 4], mut b: [f64; 4]) -> Option<[f64; 4]> {
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

/// The events checked after each step of the frictional trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ev {
    /// `mu fn - |ft|` (stick only).
    Cone,
    /// `-s dt/dpath` (slip only).
    Sliding,
    /// `fn`.
    Release,
    /// `phi1 - psi`: the tip contact ends (tangential contact follows).
    PhaseEnd,
    /// `cos((phi1 - psi) / 2)`: the segment next to the tip touches.
    Touch,
    /// `-dx0/dpath`.
    Snap,
    /// `margin - depth`.
    Depth,
}

/// How the frictional trace ended.
enum End {
    Separated(Separation),
    Tangential,
}

/// The traced path: nodes in the order of the motion (a switch node appears twice, once in
/// each mode), the switch events, and the end.
struct Trace {
    nodes: Vec<Node>,
    events: Vec<FrictionEvent>,
    end: End,
}

struct Sweeper<'a> {
    b: TipBranch<'a>,
    event_tol: f64,
    max_step: f64,
    max_steps: usize,
    check_penetration: bool,
}

impl Sweeper<'_> {
    fn condition(&self, ev: Ev, n: &Node, dir: &[f64; 4]) -> Result<f64> {
        let [phi1, f, ft, _] = n.w;
        Ok(match ev {
            Ev::Cone => self.b.mu * f - ft.abs(),
            Ev::Sliding => match n.mode {
                Mode::Slip { s } => -s * self.b.tangent(n, dir)[3],
                Mode::Stick { .. } => 1.0,
            },
            Ev::Release => f,
            Ev::PhaseEnd => phi1 - n.geom.psi,
            Ev::Touch => (0.5 * (phi1 - n.geom.psi)).cos(),
            Ev::Snap => -dot4(&n.jac[2], &self.b.tangent(n, dir)),
            Ev::Depth => {
                if self.check_penetration {
                    PENETRATION_MARGIN - self.depth(n)?
                } else {
                    1.0
                }
            }
        })
    }

    fn depth(&self, n: &Node) -> Result<f64> {
        let st = state_of(n);
        let loads = frictional_loads(self.b.flow, n.geom.psi, n.w[1], n.w[2], 1.0);
        crate::events::penetration_under(self.b.whisker, &loads, self.b.profile, &st)
    }

    fn events_of(&self, mode: Mode) -> &'static [Ev] {
        match mode {
            Mode::Stick { .. } => &[
                Ev::Cone,
                Ev::Release,
                Ev::PhaseEnd,
                Ev::Touch,
                Ev::Snap,
                Ev::Depth,
            ],
            Mode::Slip { .. } => &[
                Ev::Sliding,
                Ev::Release,
                Ev::PhaseEnd,
                Ev::Touch,
                Ev::Snap,
                Ev::Depth,
            ],
        }
    }

    /// The node on the chord's hyperplane at fraction `th` from `a` to `b`.
    fn on_chord(&self, a: &Node, b: &Node, th: f64) -> Result<Node> {
        let d = sub4(&b.w, &a.w);
        let len = norm4(&d);
        let n = d.map(|v| v / len);
        let p = [
            a.w[0] + th * d[0],
            a.w[1] + th * d[1],
            a.w[2] + th * d[2],
            a.w[3] + th * d[3],
        ];
        self.b.correct(a.mode, p, Con::Plane { n, p })
    }

    /// Locates the zero of `ev`'s condition between `a` (>= 0) and `b` (< 0) by regula
    /// falsi (Illinois) along the chord; the located node and its chord fraction.
    fn locate(&self, ev: Ev, a: &Node, b: &Node, ca: f64, cb: f64) -> Result<(f64, Node)> {
        let dir = sub4(&b.w, &a.w);
        let len = norm4(&dir);
        let (mut lo, mut hi, mut flo, mut fhi) = (0.0, 1.0, ca, cb);
        let mut best = (1.0, *b, cb.abs());
        let mut side = 0i32;
        for _ in 0..80 {
            if (hi - lo) * len <= self.event_tol {
                break;
            }
            let mut th = (lo * fhi - hi * flo) / (fhi - flo);
            if !(th > lo && th < hi) || (hi - lo) * len > 0.05 {
                th = if (hi - lo) * len > 0.05 {
                    0.5 * (lo + hi)
                } else {
                    th.clamp(lo, hi)
                };
            }
            let n = self.on_chord(a, b, th)?;
            let c = self.condition(ev, &n, &dir)?;
            if c.abs() <= best.2 || (c < 0.0 && best.2 > 0.0 && c.abs() < 1e-14) {
                best = (th, n, c.abs());
            }
            if c == 0.0 {
                return Ok((th, n));
            }
            if c > 0.0 {
                lo = th;
                flo = c;
                if side == 1 {
                    fhi *= 0.5;
                }
                side = 1;
            } else {
                hi = th;
                fhi = c;
                if side == -1 {
                    flo *= 0.5;
                }
                side = -1;
            }
        }
        // the bracket's end on the event's far side at the tolerance; the best point
        let n = self.on_chord(a, b, best.0)?;
        Ok((best.0, n))
    }

    /// Follows the path from `first` (in `mode`) to the separation.
    fn trace(&self, first: Node) -> Result<Trace> {
        let mut nodes = vec![first];
        let mut events = Vec::new();
        let mut cur = first;
        let mut dir = self.b.falling(&cur);
        let mut h = 0.01f64.min(self.max_step);
        let mut steps = 0;
        let mut zero_stretch = 0;
        loop {
            if steps >= self.max_steps {
                return Ok(Trace {
                    nodes,
                    events,
                    end: End::Separated(Separation::NotReached { steps }),
                });
            }
            steps += 1;
            let scale = [1.0, 1.0 / cur.w[1].abs().max(1.0), 1.0, 1.0];
            let scale = [scale[0], scale[1], scale[1], scale[3]];
            let tn = self.b.tangent(&cur, &dir);
            let sn = norm4(&[
                tn[0] * scale[0],
                tn[1] * scale[1],
                tn[2] * scale[2],
                tn[3] * scale[3],
            ]);
            let raw = h / sn;
            let p = [
                cur.w[0] + raw * tn[0],
                cur.w[1] + raw * tn[1],
                cur.w[2] + raw * tn[2],
                cur.w[3] + raw * tn[3],
            ];
            let next = match self.b.correct(cur.mode, p, Con::Plane { n: tn, p }) {
                Ok(n) if dot4(&self.b.tangent(&n, &tn), &tn) > 0.95 => Ok(n),
                Ok(_) => Err(None),
                Err(e) => Err(Some(e)),
            };
            let next = match next {
                Ok(n) => n,
                Err(e) => {
                    h *= 0.5;
                    if h < 1e-9 {
                        return match e {
                            Some(ContactError::LeftContour { .. }) => Ok(Trace {
                                nodes,
                                events,
                                end: End::Separated(Separation::EndOfContour),
                            }),
                            Some(e) => Err(e),
                            None => Err(self.stalled(&cur, h, "the path turns too sharply")),
                        };
                    }
                    continue;
                }
            };
            // events between cur and next: the earliest
            let chord = sub4(&next.w, &cur.w);
            let mut first_ev: Option<(f64, Ev, Node)> = None;
            for &ev in self.events_of(cur.mode) {
                let cb = self.condition(ev, &next, &chord)?;
                if cb >= 0.0 {
                    continue;
                }
                let ca = self.condition(ev, &cur, &chord)?;
                if ca < 0.0 {
                    // already across at the start: only a switch that was just made
                    continue;
                }
                let (th, at) = self.locate(ev, &cur, &next, ca, cb)?;
                if first_ev.as_ref().is_none_or(|f| th < f.0) {
                    first_ev = Some((th, ev, at));
                }
            }
            let Some((_, ev, at)) = first_ev else {
                dir = self.b.tangent(&next, &tn);
                nodes.push(next);
                cur = next;
                zero_stretch = 0;
                h = (h * 1.5).min(self.max_step);
                continue;
            };
            nodes.push(at);
            let end = |s| {
                Ok(Trace {
                    nodes: nodes.clone(),
                    events: events.clone(),
                    end: End::Separated(s),
                })
            };
            match ev {
                Ev::Release => {
                    // on fn = 0 itself (as the frictionless sweep's release)
                    let p = [at.w[0], 0.0, at.w[2], at.w[3]];
                    let n = [0.0, 1.0, 0.0, 0.0];
                    let on = self.b.correct(at.mode, p, Con::Plane { n, p })?;
                    let mut nodes = nodes.clone();
                    nodes.pop();
                    nodes.push(on);
                    return Ok(Trace {
                        nodes,
                        events,
                        end: End::Separated(Separation::Release),
                    });
                }
                Ev::Snap => return end(Separation::Snap),
                Ev::Touch | Ev::Depth => return end(Separation::MultiContact { xc: at.geom.x }),
                Ev::PhaseEnd => {
                    return Ok(Trace {
                        nodes,
                        events,
                        end: End::Tangential,
                    })
                }
                Ev::Cone | Ev::Sliding => {
                    zero_stretch += 1;
                    if zero_stretch > 2 {
                        return Err(self.indeterminate(&at, "stick and slip alternate on the spot"));
                    }
                    let (kind, mode) = if ev == Ev::Cone {
                        let s = at.w[2].signum();
                        (FrictionEventKind::StickToSlip, Mode::Slip { s })
                    } else {
                        (
                            FrictionEventKind::SlipToStick,
                            Mode::Stick { anchor: at.w[3] },
                        )
                    };
                    let start = self.b.correct(mode, at.w, Con::Base(at.x0))?;
                    if !self.probe(&start, SWITCH_PROBE) {
                        let reason = match kind {
                            FrictionEventKind::StickToSlip => {
                                "the force leaves the cone, and sliding against it does not follow the base (a dynamic slip)"
                            }
                            FrictionEventKind::SlipToStick => {
                                "the sliding stops, and sticking does not keep the force in the cone"
                            }
                        };
                        return Err(self.indeterminate(&start, reason));
                    }
                    events.push(FrictionEvent {
                        kind,
                        x0: start.x0,
                        xc: start.geom.x,
                        f: start.w[1],
                        ft: start.w[2],
                    });
                    nodes.push(start);
                    dir = self.b.falling(&start);
                    cur = start;
                    h = 0.01f64.min(self.max_step);
                }
            }
        }
    }

    /// Whether the mode of `n` (a switch's first node, or the first touch) continues with
    /// the law: stick moves the force into the cone, slip slides against `ft`.
    /// The mode the contact starts in at the first touch `n0` (`w0`, `F = 0`): the first of
    /// stick, slip with `s = +1`, slip with `s = -1` that keeps the law a short way along
    /// its curve ([`Sweeper::probe`], [`PROBE`] in x0). The probe decides where the tangent
    /// cannot: a straight whisker's tip starts to slide at zero speed (its motion along the
    /// contour is second order in the base's), so both slip curves are tangent to the stick
    /// curve there.
    fn first_mode(&self, n0: &Node, w0: [f64; 4]) -> Result<Node> {
        let anchor = w0[3];
        for mode in [
            Mode::Stick { anchor },
            Mode::Slip { s: 1.0 },
            Mode::Slip { s: -1.0 },
        ] {
            let (_, n) = self.b.eval(mode, w0, true)?;
            if self.probe(&n, PROBE) {
                return Ok(n);
            }
        }
        Err(self.indeterminate(n0, "neither stick nor slip starts the contact"))
    }

    /// Whether the law holds along the mode's curve from `n` a step `dx` on in x0 (one
    /// corrector solve from the tangent's prediction): `fn >= 0`; stick: `|ft| <= mu fn`;
    /// slip: the tip has moved against `ft`, `-s (t - t(n)) >= 0`. At a switch the two modes'
    /// curves are tangent (slip -> stick: the sliding speed is zero; the first touch), so
    /// the tangent alone cannot tell; the step sees the second-order terms.
    fn probe(&self, n: &Node, dx: f64) -> bool {
        let t = self.b.tangent(n, &[0.0; 4]);
        let rate = dot4(&n.jac[2], &t);
        if rate.abs() < 1e-9 {
            return false;
        }
        let h = -dx / rate;
        let p = [
            n.w[0] + h * t[0],
            n.w[1] + h * t[1],
            n.w[2] + h * t[2],
            n.w[3] + h * t[3],
        ];
        let Ok(m) = self.b.correct(n.mode, p, Con::Base(n.x0 - dx)) else {
            return false;
        };
        let [_, f, ft, tt] = m.w;
        f >= 0.0
            && match n.mode {
                Mode::Stick { .. } => ft.abs() <= self.b.mu * f + 1e-13,
                Mode::Slip { s } => -s * (tt - n.w[3]) >= 0.0,
            }
    }

    fn indeterminate(&self, n: &Node, reason: &str) -> ContactError {
        ContactError::FrictionIndeterminate {
            x0: n.x0,
            xc: n.geom.x,
            mu: self.b.mu,
            reason: reason.into(),
        }
    }

    fn stalled(&self, n: &Node, step: f64, reason: &str) -> ContactError {
        ContactError::BranchStalled {
            phase: Phase::A,
            x0: n.x0,
            xc: n.geom.x,
            step,
            reason: reason.into(),
        }
    }
}

/// The contact state of a node (its `f` the normal force).
fn state_of(n: &Node) -> ContactState {
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

/// Signed arc length of the contour from parameter `a` to `b` (Gauss-Legendre, 5 points on
/// pieces of at most 0.05 in `t`).
fn arc_length(profile: &Profile, a: f64, b: f64) -> f64 {
    const X: [f64; 5] = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.236_926_885_056_189,
        0.478_628_670_499_366,
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
    ];
    let pieces = ((b - a).abs() / 0.05).ceil().max(1.0) as usize;
    let h = (b - a) / pieces as f64;
    let mut s = 0.0;
    for k in 0..pieces {
        let mid = a + (k as f64 + 0.5) * h;
        for (x, w) in X.iter().zip(W) {
            let g = profile.at(mid + 0.5 * h * x);
            s += w * 0.5 * h * g.dx.hypot(g.dy);
        }
    }
    s
}

/// What the frictional sweep returns to [`crate::driver::sweep`].
pub(crate) struct FrictionalRows {
    /// The contact rows and their estimates (NaN without an accuracy asked for).
    pub rows: Vec<(SweepPoint, f64)>,
    pub events: Vec<FrictionEvent>,
    pub separation: Separation,
    /// x0 of the first touch.
    pub first_x0: f64,
}

/// Settings of the frictional sweep handed down from [`crate::sweep::SweepSettings`].
pub(crate) struct FrictionSettings {
    pub mu: f64,
    pub points: usize,
    pub integration_tol: f64,
    pub solve_tol: f64,
    pub event_tol: f64,
    pub check_penetration: bool,
    pub max_steps: usize,
    pub max_step: f64,
    /// Rows' integrator and residual tolerances and the estimate's integrator tolerance,
    /// with an accuracy asked for.
    pub rows_at: Option<(f64, f64, f64)>,
}

/// The frictional sweep's contact rows from the first touch `touch` (phase A only).
pub(crate) fn frictional_rows(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    touch: &FirstTouch,
    set: &FrictionSettings,
) -> Result<FrictionalRows> {
    if touch.kind == FirstContact::Tangential {
        return Err(ContactError::FrictionInTangentialContact {
            x0: touch.x0,
            xc: touch.xc,
        });
    }
    let sw = Sweeper {
        b: TipBranch {
            whisker,
            flow,
            profile,
            integration: Integration::adaptive(set.integration_tol),
            tol: set.solve_tol,
            mu: set.mu,
        },
        event_tol: set.event_tol,
        max_step: set.max_step.min(0.05),
        max_steps: set.max_steps,
        check_penetration: set.check_penetration,
    };
    // the free whisker at its touch: F = 0; its mode from the stick curve's direction
    let w0 = [touch.phi1, 0.0, 0.0, touch.t];
    let (_, n0) = sw.b.eval(Mode::Stick { anchor: touch.t }, w0, true)?;
    let first = sw.first_mode(&n0, w0)?;
    let tr = sw.trace(first)?;
    let separation = match tr.end {
        End::Tangential => {
            let at = tr.nodes.last().copied().unwrap_or(first);
            return Err(ContactError::FrictionInTangentialContact {
                x0: at.x0,
                xc: at.geom.x,
            });
        }
        End::Separated(s) => s,
    };
    let rows = rows(&sw, &tr, set, touch)?;
    Ok(FrictionalRows {
        rows,
        events: tr.events,
        separation,
        first_x0: first.x0,
    })
}

/// The frictional sweep (`mu > 0`) from the free whisker's tip angle `phi1` and its first
/// touch: the pre-contact rows of the frictionless sweep, then the frictional contact rows
/// ([`frictional_rows`]), with the accuracy asked for (`SweepSettings::accuracy`) every row's
/// estimate, the sweep refused where one exceeds it (no second, tighter pass here).
pub(crate) fn sweep(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
    (phi1, touch): (f64, &FirstTouch),
    mu: f64,
) -> Result<SweepResult> {
    let set = FrictionSettings {
        mu,
        points: settings.points,
        integration_tol: settings.integration_tol,
        solve_tol: settings.solve_tol,
        event_tol: settings.event_tol,
        check_penetration: settings.check_penetration,
        max_steps: settings.max_steps,
        max_step: settings.max_step,
        rows_at: settings.accuracy.map(|t| {
            (
                row_integration_tol(t),
                row_solve_tol(t),
                row_integration_tol(t) * ESTIMATE_FACTOR,
            )
        }),
    };
    let fr = frictional_rows(whisker, flow, profile, touch, &set)?;
    let mut points = pre_contact_rows(whisker, flow, phi1, fr.first_x0, settings)?;
    let pre = points.len();
    points.extend(fr.rows.iter().map(|r| r.0));
    let accuracy = settings
        .accuracy
        .map(|tol| {
            let first = fr.rows.first().map_or(f64::NAN, |r| r.1);
            let mut estimates = vec![first; pre];
            estimates.extend(fr.rows.iter().map(|r| r.1));
            check_accuracy(&points, estimates, tol, row_integration_tol(tol))
        })
        .transpose()?;
    Ok(SweepResult {
        q: flow.q,
        alpha: flow.alpha,
        points,
        first_contact: touch.kind,
        first_touch: *touch,
        separation: fr.separation,
        accuracy,
        friction_events: fr.events,
    })
}

/// The rows: `points` evenly spaced in x0 from the first touch to the end, and one at every
/// switch (the new mode's node); each solved in its stretch's mode from the bracketing
/// nodes (linear prediction in x0, Newton at the row's base position).
fn rows(
    sw: &Sweeper,
    tr: &Trace,
    set: &FrictionSettings,
    touch: &FirstTouch,
) -> Result<Vec<(SweepPoint, f64)>> {
    let nodes = &tr.nodes;
    let last = nodes.len() - 1;
    let (xa, xb) = (nodes[0].x0, nodes[last].x0);
    let row_branch = set.rows_at.map(|(it, st, _)| TipBranch {
        integration: Integration::adaptive(it),
        tol: st,
        ..sw.b.clone_shallow()
    });
    let loose = set.rows_at.map(|(_, _, lt)| TipBranch {
        integration: Integration::adaptive(lt),
        ..sw.b.clone_shallow()
    });
    let rb = row_branch.as_ref().unwrap_or(&sw.b);
    // targets: (x0, the node index of a switch or of the ends)
    let n = set.points;
    let mut targets: Vec<(f64, Option<usize>)> = (0..n)
        .map(|k| match k {
            0 => (xa, Some(0)),
            _ if k + 1 == n => (xb, Some(last)),
            _ => (xa + (xb - xa) * k as f64 / (n - 1) as f64, None),
        })
        .collect();
    for i in 1..last {
        if nodes[i].mode != nodes[i + 1].mode {
            targets.push((nodes[i + 1].x0, Some(i + 1)));
        }
    }
    targets.sort_by(|a, b| b.0.total_cmp(&a.0));
    targets.dedup_by(|b, a| {
        if a.0 == b.0 {
            a.1 = a.1.or(b.1);
            true
        } else {
            false
        }
    });
    let mut out: Vec<(SweepPoint, f64)> = Vec::with_capacity(targets.len());
    let mut seg = 0;
    for (x, at) in targets {
        let (node, hold) = match at {
            Some(i) if i == last => {
                let n = &nodes[i];
                (
                    rb.correct(n.mode, n.w, end_hold(n, &tr.end))?,
                    end_hold(n, &tr.end),
                )
            }
            Some(i) => (
                rb.correct(nodes[i].mode, nodes[i].w, Con::Base(x))?,
                Con::Base(x),
            ),
            None => {
                while seg + 1 < last
                    && (nodes[seg + 1].x0 > x || nodes[seg].mode != nodes[seg + 1].mode)
                {
                    seg += 1;
                }
                let (a, b) = (&nodes[seg], &nodes[seg + 1]);
                let wth = (x - a.x0) / (b.x0 - a.x0);
                let p = [
                    a.w[0] + wth * (b.w[0] - a.w[0]),
                    a.w[1] + wth * (b.w[1] - a.w[1]),
                    a.w[2] + wth * (b.w[2] - a.w[2]),
                    a.w[3] + wth * (b.w[3] - a.w[3]),
                ];
                (rb.correct(a.mode, p, Con::Base(x))?, Con::Base(x))
            }
        };
        let est = match &loose {
            Some(l) => estimate(l, &node, hold)?,
            None => f64::NAN,
        };
        out.push((row_of(sw.b.flow, sw.b.profile, touch, &node), est));
    }
    Ok(out)
}

/// How the row at the end of the path is held when it is solved again: the release at
/// `fn = 0`, any other end at its contour point (in stick, whose contour point the mode
/// holds, at its normal force).
fn end_hold(n: &Node, end: &End) -> Con {
    let release = matches!(end, End::Separated(Separation::Release));
    let axis = match n.mode {
        Mode::Slip { .. } if !release => [0.0, 0.0, 0.0, 1.0],
        _ => [0.0, 1.0, 0.0, 0.0],
    };
    Con::Plane { n: axis, p: n.w }
}

/// A row's error estimate: the row solved again with the looser integration of `loose`
/// (Newton from the row, at its base position; at its contour point where the row ends the
/// path), twice the largest change of its observables and contact point.
fn estimate(loose: &TipBranch, n: &Node, hold: Con) -> Result<f64> {
    let m = loose.correct(n.mode, n.w, hold)?;
    let obs = |n: &Node| {
        let (ax, ay, ma) =
            frictional_observables(loose.flow, n.geom.psi, n.w[1], n.w[2], 1.0, n.m0);
        [n.x0, ax, ay, ma, n.phi0, n.geom.x, n.geom.y]
    };
    let (a, b) = (obs(n), obs(&m));
    Ok(ESTIMATE_MARGIN
        * a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max))
}

impl TipBranch<'_> {
    fn clone_shallow(&self) -> Self {
        TipBranch {
            integration: self.integration.clone(),
            ..*self
        }
    }
}

/// A log row of a node: the observables of `F = fn n + ft t`, the slip state and the tip's
/// slip displacement along the contour since the first touch.
fn row_of(flow: FluidLoad, profile: &Profile, touch: &FirstTouch, n: &Node) -> SweepPoint {
    let [phi1, f, ft, t] = n.w;
    let (ax, ay, ma) = frictional_observables(flow, n.geom.psi, f, ft, 1.0, n.m0);
    SweepPoint {
        x0: n.x0,
        ax,
        ay,
        ma,
        phi0: n.phi0,
        f,
        s1: 1.0,
        phi1,
        phase: Phase::A,
        xc: n.geom.x,
        yc: n.geom.y,
        psi: n.geom.psi,
        ft,
        slip: n.mode.slip_state(),
        slip_distance: arc_length(profile, touch.t, t),
        y0: 0.0,
        gamma: 0.0,
        k: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `F = fn n + ft t` as a tip force: the loads' vector is the force, and `ft = 0` gives
    /// the frictionless loads bit for bit.
    #[test]
    fn the_frictional_force_is_the_tip_force() {
        let flow = FluidLoad { q: 1.0, alpha: 0.2 };
        for (psi, f, ft) in [(0.3, 2.0, 0.5), (-0.7, 1.0, -0.9), (1.2, 0.4, 0.0)] {
            let l = frictional_loads(flow, psi, f, ft, 1.0);
            let (fx, fy) = force(psi, f, ft);
            let (sb, cb) = l.tip.beta.sin_cos();
            assert!((l.tip.f * cb - fx).abs() < 1e-15 && (-l.tip.f * sb - fy).abs() < 1e-15);
            // the normal and tangential parts of the force
            let (sp, cp) = psi.sin_cos();
            assert!((fx * sp - fy * cp - f).abs() < 1e-15);
            assert!((fx * cp + fy * sp - ft).abs() < 1e-15);
        }
        let l = frictional_loads(flow, 0.4, 1.5, 0.0, 0.8);
        assert_eq!(l, crate::phase::contact_loads(flow, 0.4, 1.5, 0.8));
    }

    /// The contour's arc length: a circle's is `r dt`, a parabola's the closed form
    /// `[x sqrt(1 + x^2) + asinh x] / 2` (g2: `y = 1/2 + x^2/2`).
    #[test]
    fn arc_lengths_are_the_closed_forms() {
        let c = Profile::parse("circle:0.2,1.3,0.5").unwrap();
        assert!((arc_length(&c, -0.3, 0.9) - 0.5 * 1.2).abs() < 1e-14);
        let g2 = Profile::g2();
        let exact = |x: f64| 0.5 * (x * (1.0 + x * x).sqrt() + x.asinh());
        let s = arc_length(&g2, -0.4, 1.3);
        assert!((s - (exact(1.3) - exact(-0.4))).abs() < 1e-13, "{s}");
    }

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

    /// `ContactLaw` refuses a negative or non-finite coefficient and names it.
    #[test]
    fn the_law_refuses_bad_coefficients() {
        assert!(ContactLaw::Coulomb { mu: 0.5 }.validate().is_ok());
        assert_eq!(ContactLaw::Coulomb { mu: 0.0 }.friction(), None);
        assert_eq!(ContactLaw::default().mu(), 0.0);
        for mu in [-0.1, f64::NAN, f64::INFINITY, 11.0] {
            let e = ContactLaw::Coulomb { mu }.validate().unwrap_err();
            assert!(e.to_string().contains("mu"), "{e}");
        }
    }
}
