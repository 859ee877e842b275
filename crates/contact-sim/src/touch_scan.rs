//! The first touch along any base motion and obstacle ([`crate::motion`]): a rotation of the
//! base (whisking), or a translation towards a peg or a disc, where the right-flank
//! construction of [`crate::first_contact`] (a graph swept by a translation) does not apply.
//!
//! Along the motion's falling coordinate `c` (x0, or -gamma) the free whisker under the flow
//! (its base turned by gamma: `phi0 = pi/2 + gamma + m0/k`) has a clearance `G(c)` from the
//! obstacle: the least over the whisker of [`Profile::clearance`] (for a peg, the signed
//! distance of the point from the whisker, positive on the whisker's left, the side the
//! motion turns it to). The first touch is the first zero of `G` along the motion: `G` is
//! scanned from the start of the motion in steps of half the clearance (a point of the
//! whisker moves at most its distance from the base, at most 1, per radian of a rigid turn,
//! and exactly the step in a translation, so half the clearance cannot step over a touch
//! with a margin of 2 for the shape's own change under a turning flow; below a graph the
//! step is also divided by `1 + |g'|`), between [`SCAN_STEP_MIN`] and [`SCAN_STEP`]; the
//! first sign change is located by the Illinois variant of regula falsi to [`TOUCH_TOL`];
//! each `G` is the exact minimum over the dense free solution (the samples' least, refined
//! by golden section between its neighbours). The touching
//! point is the tip (phase A first) or a point inside (tangential, phase B first; a peg is
//! always touched so).

use crate::error::{ContactError, Result};
use crate::first_contact::{free_tip_angle, FirstContact, FirstTouch};
use crate::motion::Frame;
use crate::profile::Profile;
use beam_model::equations::{Sensitivities, WhiskerOde};
use beam_model::shot::Integration;
use beam_model::{FluidLoad, Loads, Whisker};
use bvp_solvers::integrator::{Dop853, OdeSolution};

/// Largest step of the scan in the motion's coordinate (x0, or gamma in rad).
pub const SCAN_STEP: f64 = 0.1;

/// Smallest step of the scan.
pub const SCAN_STEP_MIN: f64 = 1e-3;

/// The first touch's coordinate is bisected to this.
pub const TOUCH_TOL: f64 = 1e-13;

/// Samples of the free whisker whose least clearance is refined.
const SAMPLES: usize = 200;

/// The free whisker at one pose: its tip angle and its dense shape from the tip to the base.
struct Free {
    phi1: f64,
    sol: OdeSolution,
    /// The base relative to the tip's frame.
    base: (f64, f64),
}

impl Free {
    /// `(x, y, phi)` at arc length `s`, relative to the base.
    fn at(&self, s: f64) -> (f64, f64, f64) {
        let mut u = [0.0; 4];
        self.sol.eval_into(s, &mut u);
        (u[2] - self.base.0, u[3] - self.base.1, u[0])
    }
}

/// The scan's view of one whisker, flow, obstacle and motion.
struct Scan<'a> {
    whisker: &'a Whisker,
    flow: FluidLoad,
    profile: &'a Profile,
    frame: Frame,
    tol: f64,
    integration: Integration,
    /// The free whisker of a translation (one shape for all x0).
    fixed: Option<f64>,
}

impl Scan<'_> {
    /// The free whisker at coordinate `c` (tip angle from `guess`).
    fn free(&self, c: f64, guess: f64) -> Result<Free> {
        let phi1 = match self.fixed {
            Some(phi1) => phi1,
            None => {
                let gamma = self.frame.pose(c).gamma;
                let whisker = self.whisker_at(c);
                free_tip_angle(&whisker, self.flow, (guess, gamma), &self.integration)?
            }
        };
        let loads = Loads::fluid(self.flow.q, self.flow.alpha);
        let ode = WhiskerOde::new(self.whisker_at(c), loads, phi1, Sensitivities::None);
        let sol = Dop853::new(self.tol, self.tol).with_dense(true).integrate(
            &ode,
            1.0,
            0.0,
            &[phi1, 0.0, 0.0, 0.0],
        )?;
        let base = (sol.u_end[2], sol.u_end[3]);
        Ok(Free { phi1, sol, base })
    }

    /// The whisker at coordinate `c`: on a path, with the follicle's compliance there.
    fn whisker_at(&self, c: f64) -> Whisker {
        match self.frame {
            Frame::Path(seg) => with_compliance(self.whisker, seg.compliance(c)),
            _ => *self.whisker,
        }
    }

    /// The clearance of the point at `s` of `free` with its base at the pose of `c`.
    fn clearance(&self, free: &Free, c: f64, s: f64) -> f64 {
        let pose = self.frame.pose(c);
        let (x, y, phi) = free.at(s);
        let (px, py) = (pose.x0 + x, pose.y0 + y);
        match *self.profile {
            // the distance from the whisker to the point, signed by the side
            Profile::Peg { x: qx, y: qy } => {
                let d = (qx - px).hypot(qy - py);
                let (sn, cs) = phi.sin_cos();
                let cross = cs * (qy - py) - sn * (qx - px);
                if cross < 0.0 {
                    -d
                } else {
                    d
                }
            }
            _ => self.profile.clearance(px, py),
        }
    }

    /// The least clearance of `free` at `c` and where (arc length), refined by golden
    /// section around the least sample. For a peg only points whose nearest approach is
    /// inside the whisker count (beyond the tip the point is clear).
    fn least(&self, free: &Free, c: f64) -> (f64, f64) {
        let key = |s: f64| match *self.profile {
            // a peg: the nearest point (unsigned), the sign read there
            Profile::Peg { .. } => self.clearance(free, c, s).abs(),
            _ => self.clearance(free, c, s),
        };
        let (mut k, mut best) = (0, f64::INFINITY);
        for i in 0..=SAMPLES {
            let v = key(i as f64 / SAMPLES as f64);
            if v < best {
                (k, best) = (i, v);
            }
        }
        let h = 1.0 / SAMPLES as f64;
        let (mut a, mut b) = ((k as f64 - 1.0) * h, (k as f64 + 1.0) * h);
        (a, b) = (a.max(0.0), b.min(1.0));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut x1, mut x2) = (b - g * (b - a), a + g * (b - a));
        let (mut f1, mut f2) = (key(x1), key(x2));
        // the interval 2/SAMPLES shrinks to ~1e-10: the minimum's value to ~1e-20
        for _ in 0..40 {
            if f1 <= f2 {
                (b, x2, f2) = (x2, x1, f1);
                x1 = b - g * (b - a);
                f1 = key(x1);
            } else {
                (a, x1, f1) = (x1, x2, f2);
                x2 = a + g * (b - a);
                f2 = key(x2);
            }
        }
        let mut s = 0.5 * (a + b);
        // the ends themselves (the tip, the base) where they are nearer
        for end in [0.0, 1.0] {
            if key(end) <= key(s) {
                s = end;
            }
        }
        if self.profile.is_peg() && (s >= 1.0 || s <= 0.0) {
            // the point lies beyond an end: clear whichever side it is on
            return (key(s), s);
        }
        (self.clearance(free, c, s), s)
    }
}

/// The first touch of the free whisker with `profile` along the motion of `frame` from the
/// falling coordinate `start` (NaN: a translation from where the whisker is clear of the
/// obstacle), scanning at most `span` of the coordinate. The touch's `x0` is the falling
/// coordinate (x0, or -gamma); its pose is in `y0`, `gamma` ([`crate::sweep`] writes the
/// pose's x0 before returning it).
///
/// # Errors
/// [`ContactError::NoContact`] where the whisker starts inside the obstacle or does not
/// reach it within `span`; a free solve's error.
pub(crate) fn first_touch_along(
    whisker: &Whisker,
    flow: FluidLoad,
    (phi1, tol): (f64, f64),
    profile: &Profile,
    frame: Frame,
    start: f64,
) -> Result<FirstTouch> {
    scan_touch(whisker, flow, (phi1, tol), profile, frame, start)?.map_err(|(span, c0)| {
        ContactError::NoContact {
            reason: format!(
                "the whisker does not touch {} within {span:.3} of the motion's coordinate {} from {c0:.6}",
                profile.name(),
                frame.name()
            ),
        }
    })
}

/// A whisker with the follicle compliance `c` (rigid at 0).
pub(crate) fn with_compliance(whisker: &Whisker, c: f64) -> Whisker {
    let support = if c > 0.0 {
        beam_model::Support::Spring { k: 1.0 / c }
    } else {
        beam_model::Support::Rigid
    };
    Whisker {
        support,
        ..*whisker
    }
}

/// [`first_touch_along`], with `Err((span, from))` (the coordinate scanned) for a whisker that does
/// not reach the obstacle. On a path's segment the scan covers the segment (`span` 1 from
/// its first row), its last step landing on the segment's end, so that the next segment's
/// scan starts where this one ended.
pub(crate) fn scan_touch(
    whisker: &Whisker,
    flow: FluidLoad,
    (phi1, tol): (f64, f64),
    profile: &Profile,
    frame: Frame,
    start: f64,
) -> Result<std::result::Result<FirstTouch, (f64, f64)>> {
    let mut scan = Scan {
        whisker,
        flow,
        profile,
        frame,
        tol,
        integration: Integration::adaptive(tol),
        fixed: None,
    };
    let (c0, span) = match frame {
        Frame::Translate => {
            scan.fixed = Some(phi1);
            let free = scan.free(0.0, phi1)?;
            let xs: Vec<f64> = (0..=SAMPLES)
                .map(|i| free.at(i as f64 / SAMPLES as f64).0)
                .collect();
            let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let (left, right) = profile.domain();
            // from clear of the obstacle's right side until past its left side
            (right - lo + 0.05, (right - lo) - (left - hi) + 0.1)
        }
        Frame::Rotate { .. } => (start, std::f64::consts::TAU),
        Frame::Path(seg) => (-(seg.index as f64), 1.0),
    };
    // the free whisker along the scan, its tip angle the next one's guess
    let mut guess = match frame {
        Frame::Translate => phi1,
        Frame::Rotate { .. } | Frame::Path(_) => phi1 + frame.pose(c0).gamma,
    };
    // how far a point of the whisker moves per unit of the coordinate, at most
    let speed = match frame {
        Frame::Path(seg) => seg.speed(flow.q),
        _ => 1.0,
    };
    let at = |c: f64, guess: &mut f64| -> Result<(f64, f64, Free)> {
        let free = scan.free(c, *guess)?;
        *guess = free.phi1;
        let (g, s) = scan.least(&free, c);
        Ok((g, s, free))
    };
    // the step from clearance `g` at the point `s` of `free` (see the module's notes)
    let step = |g: f64, s: f64, free: &Free, c: f64| {
        let slope = match *profile {
            Profile::Peg { .. } | Profile::Disc { .. } => 0.0,
            _ => {
                let (x, _, _) = free.at(s);
                let d = profile.eval(frame.pose(c).x0 + x).1.abs();
                if d.is_finite() {
                    d
                } else {
                    0.0
                }
            }
        };
        (0.5 * g / (1.0 + slope) / speed).clamp(SCAN_STEP_MIN, SCAN_STEP)
    };
    let (g0, s0, free0) = at(c0, &mut guess)?;
    if g0 <= 0.0 {
        return Err(ContactError::NoContact {
            reason: format!(
                "the whisker starts inside {} (clearance {g0:.3e} at {} = {c0:.6})",
                profile.name(),
                frame.name()
            ),
        });
    }
    let mut prev = (c0, guess, g0);
    let mut hit = None;
    let mut h = step(g0, s0, &free0, c0);
    let mut c = c0;
    while c0 - (c - h) <= span || frame.floor().is_some() && c0 - c < span {
        if frame.floor().is_some() {
            // a path's segment: the last step lands on its end
            h = h.min(span - (c0 - c));
        }
        c -= h;
        let (g, s, free) = at(c, &mut guess)?;
        if g <= 0.0 {
            hit = Some((c, g));
            break;
        }
        prev = (c, guess, g);
        h = step(g, s, &free, c);
    }
    let Some((mut lo, mut g_lo)) = hit else {
        return Ok(Err((span, c0)));
    };
    // Illinois: G > 0 at `hi`, G <= 0 at `lo` (the coordinate falls along the motion); the
    // weight of an end that stays is halved; bisection where the secant point is not inside
    let (mut hi, mut guess_hi, mut g_hi) = prev;
    let mut side = 0;
    for _ in 0..200 {
        if hi - lo <= TOUCH_TOL * (1.0 + hi.abs()) {
            break;
        }
        let mut mid = hi - g_hi * (hi - lo) / (g_hi - g_lo);
        if !(mid > lo && mid < hi) {
            mid = 0.5 * (hi + lo);
        }
        if mid <= lo || mid >= hi {
            break;
        }
        let mut g = guess_hi;
        let (gm, _, _) = at(mid, &mut g)?;
        if gm > 0.0 {
            (hi, guess_hi, g_hi) = (mid, g, gm);
            if side == 1 {
                g_lo *= 0.5;
            }
            side = 1;
        } else {
            (lo, g_lo) = (mid, gm);
            if side == -1 {
                g_hi *= 0.5;
            }
            side = -1;
        }
        if gm == 0.0 {
            break;
        }
    }
    if g_lo == 0.0 {
        // a point where the clearance vanishes exactly is the touch itself
        hi = lo;
    }
    let mut g = guess_hi;
    let (_, s, free) = at(hi, &mut g)?;
    let pose = frame.pose(hi);
    let (x, y, phi) = free.at(s);
    let (px, py) = (pose.x0 + x, pose.y0 + y);
    let kind = if s >= 1.0 && !profile.is_peg() {
        FirstContact::Tip
    } else {
        FirstContact::Tangential
    };
    // the contour parameter of the touched point
    let t = match *profile {
        Profile::Peg { .. } => phi,
        Profile::Disc { x: cx, y: cy, .. } | Profile::Circle { xc: cx, yc: cy, .. } => {
            (px - cx).atan2(cy - py)
        }
        _ => px,
    };
    let geom = profile.at(t);
    Ok(Ok(FirstTouch {
        kind,
        s: if kind == FirstContact::Tip { 1.0 } else { s },
        t,
        xc: geom.x,
        yc: geom.y,
        psi: geom.psi,
        x0: hi,
        phi1: free.phi1,
        y0: pose.y0,
        gamma: pose.gamma,
    }))
}
