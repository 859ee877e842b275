//! The events of the frictional path and their location on it.

use super::branch::{dot4, norm4, state_of, sub4, Con, FrictionBranch, Mode, Node};
use super::kinds::{Ev, PENETRATION_MARGIN};
use super::trace::Sweeper;
use crate::contact_law::frictional_loads;
use crate::continuation::BASE_CONTACT;
use crate::error::Result;
use crate::phase::Phase;

impl Sweeper<'_> {
    pub(super) fn condition(&self, ev: Ev, n: &Node, dir: &[f64; 4]) -> Result<f64> {
        let [_, f, ft, t] = n.w;
        let (phi1, tangential) = (n.phi1(), n.phase == Phase::B);
        Ok(match ev {
            Ev::Cone => self.b.mu * f - ft.abs(),
            Ev::Sliding => match n.mode {
                Mode::Slip { s } => {
                    let tn = self.b.tangent(n, dir);
                    if tangential {
                        -s * (self.b.speed(t) * tn[3] - tn[0])
                    } else {
                        -s * tn[3]
                    }
                }
                Mode::Stick { .. } => 1.0,
            },
            Ev::Release => f,
            Ev::PhaseEnd if tangential => 1.0 - n.w[0],
            Ev::PhaseEnd => phi1 - n.geom.psi,
            Ev::Touch if tangential => {
                self.b.profile.curvature_at(t) - self.b.whisker.kappa0(n.w[0])
            }
            Ev::Touch => (0.5 * (phi1 - n.geom.psi)).cos(),
            Ev::AtBase if tangential => n.w[0] - BASE_CONTACT,
            Ev::AtBase => 1.0,
            Ev::Snap => -dot4(&n.jac[2], &self.b.tangent(n, dir)),
            Ev::Corner => self.b.frame.floor().map_or(1.0, |c| n.x0 - c),
            Ev::Depth => {
                if self.check_penetration {
                    PENETRATION_MARGIN - self.depth(n)?
                } else {
                    1.0
                }
            }
        })
    }

    pub(super) fn depth(&self, n: &Node) -> Result<f64> {
        let st = state_of(n);
        let loads = frictional_loads(self.b.flow, n.geom.psi, n.w[1], n.w[2], n.s1());
        crate::events::penetration_under(self.b.whisker, &loads, self.b.profile, &st)
    }

    pub(super) fn events_of(&self, mode: Mode) -> &'static [Ev] {
        match mode {
            Mode::Stick { .. } => &[
                Ev::Cone,
                Ev::Release,
                Ev::PhaseEnd,
                Ev::Touch,
                Ev::Snap,
                Ev::Depth,
                Ev::AtBase,
                Ev::Corner,
            ],
            Mode::Slip { .. } => &[
                Ev::Sliding,
                Ev::Release,
                Ev::PhaseEnd,
                Ev::Touch,
                Ev::Snap,
                Ev::Depth,
                Ev::AtBase,
                Ev::Corner,
            ],
        }
    }

    /// The node on the chord's hyperplane at fraction `th` from `a` to `b`, solved on `br`.
    pub(super) fn on_chord(
        &self,
        br: &FrictionBranch,
        a: &Node,
        b: &Node,
        th: f64,
    ) -> Result<Node> {
        let d = sub4(&b.w, &a.w);
        let len = norm4(&d);
        let n = d.map(|v| v / len);
        let p = [
            a.w[0] + th * d[0],
            a.w[1] + th * d[1],
            a.w[2] + th * d[2],
            a.w[3] + th * d[3],
        ];
        br.correct_near(a.phase, a.mode, p, Con::Plane { n, p }, Some(&a.jac), true)
    }

    /// Locates the zero of `ev`'s condition between `a` (>= 0) and `b` (< 0) by regula
    /// falsi (Illinois) along the chord; the located node and its chord fraction.
    pub(super) fn locate(
        &self,
        ev: Ev,
        a: &Node,
        b: &Node,
        ca: f64,
        cb: f64,
    ) -> Result<(f64, Node)> {
        let dir = sub4(&b.w, &a.w);
        let len = norm4(&dir);
        // a second contact's trial points at the sweep's tolerances (the trace's shots are
        // looser than its depth margin)
        let br = if ev == Ev::Depth {
            &self.tight
        } else {
            &self.b
        };
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
            let n = self.on_chord(br, a, b, th)?;
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
        let n = self.on_chord(br, a, b, best.0)?;
        Ok((best.0, n))
    }
}
