//! The quasi-static sweep (thesis ch. 5, Fig. 5.6): the whisker under the flow alone, the
//! first contact, phases A and B with their switches, and the separation by snap (x0 has a
//! local minimum) or release (f falls to zero), parametrised by the contact point moving
//! left along the contour.
//!
//! Every event (phase switch, snap, release) is located by bisection or golden-section search
//! on the contour parameter, so none is skipped however coarse the requested spacing.

use crate::error::{ContactError, Result};
use crate::phase::{ContactState, ContourPoint, Phase, PhaseProblem};
use crate::profile::Profile;
use beam_model::shot::Integration;
use beam_model::{shape_with, solve, FluidLoad, Loads, Method, Scene, Whisker};
use serde::{Deserialize, Serialize};

/// Settings of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepSettings {
    /// Contact points from first contact to separation, uniformly spaced in xc (event rows
    /// for phase switches are added).
    pub points: usize,
    /// Rows before contact (flow only), spaced `pre_contact_spacing` in x0.
    pub pre_contact_rows: usize,
    /// Spacing of the pre-contact rows in x0.
    pub pre_contact_spacing: f64,
    /// Integrator tolerance of the shots.
    pub integration_tol: f64,
    /// Residual tolerance of the phase solves.
    pub solve_tol: f64,
    /// Location tolerance of events in xc.
    pub event_tol: f64,
    /// Whether to check at every point that no other part of the whisker enters the obstacle.
    pub check_penetration: bool,
}

impl Default for SweepSettings {
    fn default() -> Self {
        SweepSettings {
            points: 200,
            pre_contact_rows: 10,
            pre_contact_spacing: 0.05,
            integration_tol: 1e-12,
            solve_tol: 1e-11,
            event_tol: 1e-10,
            check_penetration: true,
        }
    }
}

/// One row of the observables log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepPoint {
    /// Base position.
    pub x0: f64,
    /// Horizontal base reaction.
    pub ax: f64,
    /// Vertical base reaction.
    pub ay: f64,
    /// Base moment reaction.
    pub ma: f64,
    /// Base angle.
    pub phi0: f64,
    /// Contact force (0 before contact).
    pub f: f64,
    /// Contact arc length (1 before contact and in phase A).
    pub s1: f64,
    /// Tangent angle at s1 (`psi` in phase B; the free tip angle before contact).
    pub phi1: f64,
    /// Phase.
    pub phase: Phase,
    /// Contact point x (NaN before contact).
    pub xc: f64,
    /// Contact point y (NaN before contact).
    pub yc: f64,
    /// Contour angle at the contact point (NaN before contact).
    pub psi: f64,
}

/// How the contact began.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum FirstContact {
    /// The tip touched first (phi1 > psi).
    Tip,
    /// A point s1 < 1 touched tangentially first.
    Tangential,
}

/// How the contact ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Separation {
    /// Separation 1: x0 reached a local minimum and the whisker snaps off.
    Snap,
    /// Separation 2: the contact force fell to zero.
    Release,
    /// A second point of the whisker would enter the obstacle at this contour point; the
    /// single-contact model stops there.
    MultiContact {
        /// The contour point where it was detected.
        xc: f64,
    },
    /// The contour's domain ended (tabulated or circular contours) before separation.
    EndOfContour,
}

/// A complete sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepResult {
    /// Fluid load q.
    pub q: f64,
    /// Flow angle alpha (rad): the flow is `q (cos alpha, -sin alpha)` on `[0, s1]`.
    pub alpha: f64,
    /// The rows, pre-contact first, in the order of the motion (x0 decreasing in contact).
    pub points: Vec<SweepPoint>,
    /// How the contact began.
    pub first_contact: FirstContact,
    /// How it ended.
    pub separation: Separation,
}

impl SweepResult {
    /// The rows in contact.
    pub fn contact_points(&self) -> impl Iterator<Item = &SweepPoint> {
        self.points.iter().filter(|p| p.phase != Phase::None)
    }

    /// The sequence of phases in contact, e.g. `"AB"`, `"BA"`, `"A"`.
    pub fn phase_pattern(&self) -> String {
        let mut s = String::new();
        for p in self.contact_points() {
            let c = if p.phase == Phase::A { 'A' } else { 'B' };
            if !s.ends_with(c) {
                s.push(c);
            }
        }
        s
    }
}

impl SweepPoint {
    fn from_state(st: &ContactState, flow: FluidLoad) -> Self {
        let (ax, ay, ma, phi0) = st.observables(flow);
        SweepPoint {
            x0: st.x0,
            ax,
            ay,
            ma,
            phi0,
            f: st.f,
            s1: st.s1,
            phi1: st.phi1,
            phase: st.phase,
            xc: st.point.xc,
            yc: st.point.yc,
            psi: st.point.psi,
        }
    }
}

struct Marcher<'a> {
    whisker: &'a Whisker,
    flow: FluidLoad,
    profile: &'a Profile,
    integration: Integration,
    settings: &'a SweepSettings,
}

enum Stop {
    Snap(ContactState),
    Release(ContactState),
    MultiContact(f64),
    EndOfContour,
}

impl Marcher<'_> {
    fn solve_phase(&self, xc: f64, phase: Phase, guess: [f64; 2]) -> Result<ContactState> {
        let point = ContourPoint::on(self.profile, xc);
        PhaseProblem::new(self.whisker, self.flow, point, phase, &self.integration)
            .solve(guess, self.settings.solve_tol)
    }

    /// The state at `xc` continuing from `prev`, switching phase where the current one
    /// becomes invalid (A: phi1 <= psi; B: s1 >= 1).
    fn step(&self, xc: f64, prev: &ContactState) -> Result<ContactState> {
        self.step_from(xc, prev, None)
    }

    /// Whether `st` continues `prev` on the same branch: the corrector may move the contact
    /// force from its prediction `f_pred` by at most `0.5 + 0.5 f_prev + 2 |f_pred - f_prev|`;
    /// a corrector that jumped to a far branch (e.g. past a fold) moves it much more.
    fn continues(st: &ContactState, prev: &ContactState, f_pred: f64) -> bool {
        (st.f - f_pred).abs() <= 0.5 + 0.5 * prev.f.abs() + 2.0 * (f_pred - prev.f).abs()
    }

    /// [`Marcher::step`] with a linear predictor through `before` and `prev` when both are in
    /// the same phase (the corrector then starts O(h^2) from the solution).
    fn step_from(
        &self,
        xc: f64,
        prev: &ContactState,
        before: Option<&ContactState>,
    ) -> Result<ContactState> {
        let unknowns = |s: &ContactState| match s.phase {
            Phase::B => [s.f, s.s1],
            _ => [s.phi1, s.f],
        };
        if let Some(b) = before.filter(|b| b.phase == prev.phase && b.point.xc != prev.point.xc) {
            let t = (xc - prev.point.xc) / (prev.point.xc - b.point.xc);
            let (u, v) = (unknowns(prev), unknowns(b));
            let pred = [u[0] + t * (u[0] - v[0]), u[1] + t * (u[1] - v[1])];
            if let Ok(st) = self.solve_phase(xc, prev.phase, pred) {
                let valid = match st.phase {
                    Phase::B => st.s1 < 1.0,
                    _ => st.phi1 > st.point.psi,
                };
                let f_pred = if prev.phase == Phase::B {
                    pred[0]
                } else {
                    pred[1]
                };
                if valid && Self::continues(&st, prev, f_pred) {
                    return Ok(st);
                }
            }
        }
        let psi = ContourPoint::on(self.profile, xc).psi;
        let try_a = |guess: [f64; 2]| {
            self.solve_phase(xc, Phase::A, guess)
                .ok()
                .filter(|s| s.phi1 > s.point.psi && Self::continues(s, prev, prev.f))
        };
        let try_b = |guess: [f64; 2]| {
            self.solve_phase(xc, Phase::B, guess)
                .ok()
                .filter(|s| s.s1 < 1.0 && Self::continues(s, prev, prev.f))
        };
        let found = match prev.phase {
            Phase::B => try_b([prev.f, prev.s1]).or_else(|| try_a([psi, prev.f])),
            _ => try_a([prev.phi1, prev.f])
                .or_else(|| try_b([prev.f, 1.0 - 1e-3]))
                .or_else(|| try_b([prev.f, 0.9])),
        };
        match found {
            Some(s) => Ok(s),
            None => {
                // Report the failure of the phase we were in.
                let guess = match prev.phase {
                    Phase::B => [prev.f, prev.s1],
                    _ => [prev.phi1, prev.f],
                };
                self.solve_phase(xc, prev.phase, guess)?;
                Err(ContactError::PhaseSolve {
                    phase: if prev.phase == Phase::B { 'B' } else { 'A' },
                    xc,
                    iterations: 0,
                    residual: f64::NAN,
                })
            }
        }
    }

    /// Whether a part of the whisker other than the contact point is inside the obstacle.
    fn penetrates(&self, st: &ContactState) -> Result<bool> {
        if !self.settings.check_penetration {
            return Ok(false);
        }
        let scene = Scene::new(*self.whisker, st.loads(self.flow));
        // A geometric check: RK4 with 80 steps is accurate to ~1e-8, far below the 1e-6
        // margin by which another point must enter the obstacle to count.
        let sol = shape_with(&scene, st.phi1, &Integration::Rk4 { n: 80 })?;
        let el = &sol.elastica;
        for i in 0..el.len() {
            if (el.s[i] - st.s1).abs() < 0.05 {
                continue;
            }
            let x = st.x0 + el.x[i];
            let g = self.profile.y(x);
            if g.is_finite() && el.y[i] > g + 1e-6 {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Bisection on xc in `[lo, hi]` (`lo` on the side where `side(state)` is true) to the
    /// event tolerance; returns the state nearest the event on the `true` side.
    fn bisect(
        &self,
        mut inside: ContactState,
        mut outside_xc: f64,
        side: impl Fn(&ContactState) -> bool,
    ) -> Result<ContactState> {
        while (inside.point.xc - outside_xc).abs() > self.settings.event_tol {
            let mid = 0.5 * (inside.point.xc + outside_xc);
            let st = self.step(mid, &inside)?;
            if side(&st) {
                inside = st;
            } else {
                outside_xc = mid;
            }
        }
        Ok(inside)
    }

    /// Locates the xc in `(inside, outside_xc)` where the event function `g` of the phase of
    /// `inside` changes sign (`g > 0` inside): the Illinois variant of regula falsi on the
    /// phase continued past its validity, falling back to bisection with phase switching
    /// when the continued phase cannot be solved. Returns the state at the event.
    fn locate(
        &self,
        inside: ContactState,
        outside_xc: f64,
        g: impl Fn(&ContactState) -> f64,
    ) -> Result<ContactState> {
        let guess = |s: &ContactState| match s.phase {
            Phase::B => [s.f, s.s1],
            _ => [s.phi1, s.f],
        };
        let tol = self.settings.event_tol;
        let (mut a, mut ga) = (inside, g(&inside));
        let Ok(b0) = self.solve_phase(outside_xc, inside.phase, guess(&inside)) else {
            return self.bisect(inside, outside_xc, |s| {
                s.phase == inside.phase && g(s) >= 0.0
            });
        };
        let (mut b, mut gb) = (b0, g(&b0));
        if !(ga > 0.0 && gb <= 0.0) {
            return self.bisect(inside, outside_xc, |s| {
                s.phase == inside.phase && g(s) >= 0.0
            });
        }
        let mut side = 0;
        for _ in 0..60 {
            if (a.point.xc - b.point.xc).abs() <= tol {
                break;
            }
            let xc = b.point.xc - gb * (b.point.xc - a.point.xc) / (gb - ga);
            let Ok(c) = self.solve_phase(xc, inside.phase, guess(&a)) else {
                return self.bisect(a, b.point.xc, |s| s.phase == inside.phase && g(s) >= 0.0);
            };
            let gc = g(&c);
            if gc.abs() <= 1e-14 && gc >= 0.0 {
                return Ok(c);
            }
            if gc > 0.0 {
                a = c;
                ga = gc;
                if side == 1 {
                    gb *= 0.5;
                }
                side = 1;
            } else {
                b = c;
                gb = gc;
                if side == -1 {
                    ga *= 0.5;
                }
                side = -1;
            }
        }
        // the state on the valid side (g >= 0), within the event tolerance of the event
        Ok(a)
    }

    /// Golden-section search for the minimum of x0(xc) on `[a, b]` (a < b).
    fn snap_point(&self, a: f64, b: f64, near: &ContactState) -> Result<ContactState> {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut a, mut b) = (a, b);
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let mut sc = self.step(c, near)?;
        let mut sd = self.step(d, &sc)?;
        while (b - a) > 1e-8 {
            if sc.x0 < sd.x0 {
                b = d;
                d = c;
                sd = sc;
                c = b - g * (b - a);
                sc = self.step(c, &sd)?;
            } else {
                a = c;
                c = d;
                sc = sd;
                d = a + g * (b - a);
                sd = self.step(d, &sc)?;
            }
        }
        Ok(if sc.x0 < sd.x0 { sc } else { sd })
    }

    /// The states from `last` to `xc`, halving the step towards `xc` when a solve fails. The
    /// states reached before a failure are returned with it, so that the event checks see
    /// them (beyond a snap the tip-contact branch ends in a fold the solver cannot pass).
    fn advance(
        &self,
        last: &ContactState,
        before: Option<&ContactState>,
        xc: f64,
    ) -> (Vec<ContactState>, Option<ContactError>) {
        match self.step_from(xc, last, before) {
            Ok(s) => (vec![s], None),
            Err(e) => {
                if (last.point.xc - xc).abs() < 1e-6 {
                    return (Vec::new(), Some(e));
                }
                let mid = 0.5 * (last.point.xc + xc);
                let (mut states, err) = self.advance(last, before, mid);
                if err.is_some() {
                    return (states, err);
                }
                let anchor = *states.last().unwrap_or(last);
                let prior = if states.len() >= 2 {
                    states[states.len() - 2]
                } else {
                    *last
                };
                let (rest, err) = self.advance(&anchor, Some(&prior), xc);
                states.extend(rest);
                (states, err)
            }
        }
    }

    /// Marches over the contour points `xcs` from `first`, recording them and the switch
    /// events; stops at the first separation. Steps longer than `max_step` are split into
    /// unrecorded sub-steps (which still enter the event checks), and failed steps are
    /// refined by halving.
    fn march(
        &self,
        first: ContactState,
        xcs: impl Iterator<Item = f64>,
        max_step: f64,
        progress: &mut dyn FnMut(usize),
    ) -> Result<(Vec<ContactState>, Option<Stop>)> {
        let mut states = vec![first];
        let mut trail = vec![first];
        let (dmin, _) = self.profile.domain();
        for (done, target) in xcs.enumerate() {
            progress(done);
            if target < dmin {
                return Ok((states, Some(Stop::EndOfContour)));
            }
            let from = *trail.last().unwrap_or(&first);
            let gap = from.point.xc - target;
            let pieces = (gap / max_step).ceil().max(1.0) as usize;
            for j in 1..=pieces {
                let xc = if j == pieces {
                    target
                } else {
                    from.point.xc - gap * j as f64 / pieces as f64
                };
                let anchor = *trail.last().unwrap_or(&first);
                let before = trail.len().checked_sub(2).map(|i| trail[i]);
                let (new_states, err) = self.advance(&anchor, before.as_ref(), xc);
                let n_new = new_states.len();
                for (k, st) in new_states.into_iter().enumerate() {
                    let record = j == pieces && k + 1 == n_new && err.is_none();
                    if let Some(stop) = self.check(&mut states, &mut trail, st, record)? {
                        return Ok((states, Some(stop)));
                    }
                }
                if let Some(e) = err {
                    // The contact branch ends in a fold in xc (the contact point cannot move
                    // on): the whisker leaves the contour there, a snap at the last state.
                    return match (e, trail.len()) {
                        (ContactError::PhaseSolve { .. }, n) if n >= 3 => {
                            let last = trail[n - 1];
                            while states.last().is_some_and(|s| s.point.xc <= last.point.xc) {
                                states.pop();
                            }
                            Ok((states, Some(Stop::Snap(last))))
                        }
                        (e, _) => Err(e),
                    };
                }
            }
        }
        Ok((states, None))
    }

    /// Event checks for a new state `st` against the last computed state; records switch
    /// events, and `st` itself when `record` is set.
    fn check(
        &self,
        states: &mut Vec<ContactState>,
        trail: &mut Vec<ContactState>,
        st: ContactState,
        record: bool,
    ) -> Result<Option<Stop>> {
        let Some(&last) = trail.last() else {
            trail.push(st);
            states.push(st);
            return Ok(None);
        };
        let xc = st.point.xc;
        if st.phase != last.phase {
            // an event that cannot be located (a solve fails inside the bracket) is kept at
            // the bracket end on the old phase's side rather than failing the sweep
            let ev = self
                .locate(last, xc, |s| match s.phase {
                    Phase::B => 1.0 - s.s1,
                    _ => s.phi1 - s.point.psi,
                })
                .unwrap_or(last);
            if ev.point.xc != last.point.xc {
                states.push(ev);
            }
        }
        if st.f < 0.0 {
            let ev = self.locate(last, xc, |s| s.f).unwrap_or(last);
            return Ok(Some(Stop::Release(ev)));
        }
        if st.x0 > last.x0 {
            let n = trail.len();
            let near = if n >= 2 { trail[n - 2] } else { last };
            let ev = self
                .snap_point(xc, near.point.xc, &near)
                .unwrap_or(if last.x0 <= st.x0 { last } else { st });
            while states.last().is_some_and(|s| s.point.xc <= ev.point.xc) {
                states.pop();
            }
            return Ok(Some(Stop::Snap(ev)));
        }
        if self.penetrates(&st)? {
            return Ok(Some(Stop::MultiContact(xc)));
        }
        trail.push(st);
        if record {
            states.push(st);
        }
        Ok(None)
    }

    /// The first contact from the whisker under the flow alone: the point of the elastica
    /// that reaches the contour first as the base moves left, i.e. the maximum over s of
    /// `x0(s) = g_R^{-1}(y(s)) - x(s)` (an interior maximum is a tangency, phase B).
    fn first_contact(&self, free: &beam_model::Solution) -> Result<(ContactState, FirstContact)> {
        let el = &free.elastica;
        let mut best: Option<(usize, f64, f64)> = None;
        for i in 1..el.len() {
            if let Some(xr) = self.profile.x_right_at(el.y[i]) {
                let x0 = xr - el.x[i];
                if best.is_none_or(|(_, b, _)| x0 > b) {
                    best = Some((i, x0, xr));
                }
            }
        }
        let (i, _, xc) = best.ok_or_else(|| ContactError::NoContact {
            reason: format!(
                "the whisker (highest point y = {:.4}) stays below the contour {}",
                el.y.iter().cloned().fold(f64::MIN, f64::max),
                self.profile.name()
            ),
        })?;
        if i == el.len() - 1 && free.tip.phi > self.profile.psi(xc) {
            let st = self.solve_phase(xc, Phase::A, [free.tip.phi, 0.0])?;
            Ok((st, FirstContact::Tip))
        } else {
            let st = self.solve_phase(xc, Phase::B, [0.0, el.s[i]])?;
            Ok((st, FirstContact::Tangential))
        }
    }
}

/// Progress of a running sweep, reported to [`sweep_with_progress`]'s callback.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepProgress {
    /// The coarse pass searching the separation: contour steps done so far.
    Coarse {
        /// Steps done.
        steps: usize,
    },
    /// The fine pass: contact points done out of the requested number.
    Fine {
        /// Points done.
        done: usize,
        /// Points requested.
        total: usize,
    },
}

/// Sweeps a whisker under the fluid load `flow` past `profile` (thesis Fig. 5.6).
pub fn sweep(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
) -> Result<SweepResult> {
    sweep_with_progress(whisker, flow, profile, settings, &mut |_| {})
}

/// [`sweep`] reporting its progress to `progress` (e.g. for a progress bar).
pub fn sweep_with_progress(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<SweepResult> {
    whisker.validate()?;
    Loads::fluid(flow.q, flow.alpha).validate()?;
    if settings.points < 2 {
        return Err(ContactError::InvalidParameter {
            name: "points",
            value: settings.points as f64,
            reason: "a sweep needs at least 2 contact points",
        });
    }
    let marcher = Marcher {
        whisker,
        flow,
        profile,
        integration: Integration::adaptive(settings.integration_tol),
        settings,
    };
    let free = solve(
        &Scene::new(*whisker, Loads::fluid(flow.q, flow.alpha)),
        &Method::Accurate {
            tol: settings.integration_tol,
            samples: 2000,
        },
    )?;
    // Finite domains (tabulated, circular) are checked inside their ends, where a natural
    // spline is flat and a circle's slope is infinite.
    let (dmin, dmax) = profile.domain();
    if dmin.is_finite() && dmax.is_finite() {
        let w = dmax - dmin;
        profile.check_convex(dmin + 1e-2 * w, dmax - 1e-2 * w)?;
    }
    let (first, first_contact) = marcher.first_contact(&free)?;
    let xv = profile.vertex();
    let span = (first.point.xc - xv).abs().max(0.5);
    profile
        .check_convex(first.point.xc - 3.0 * span, first.point.xc)
        .or_else(|e| match profile.domain() {
            (a, _) if a.is_finite() => profile.check_convex(a, first.point.xc),
            _ => Err(e),
        })?;
    // Pass 1: coarse march to find the separation.
    let h1 = span / 20.0;
    let coarse = (1..=400).map(|k| first.point.xc - k as f64 * h1);
    let (coarse_states, stop) = marcher.march(first, coarse, h1, &mut |steps| {
        progress(SweepProgress::Coarse { steps })
    })?;
    let (sep_xc, final_state, separation) = match stop {
        Some(Stop::Snap(s)) => (s.point.xc, Some(s), Separation::Snap),
        Some(Stop::Release(s)) => (s.point.xc, Some(s), Separation::Release),
        Some(Stop::MultiContact(xc)) => {
            let last = coarse_states.last().map_or(first.point.xc, |s| s.point.xc);
            (last, None, Separation::MultiContact { xc })
        }
        Some(Stop::EndOfContour) | None => {
            let last = coarse_states.last().map_or(first.point.xc, |s| s.point.xc);
            (last, None, Separation::EndOfContour)
        }
    };
    // Pass 2: the requested number of points between first contact and separation, the last
    // one at the separation found by pass 1 (so every event in between is located by the
    // fine march itself, however few the points).
    let n = settings.points;
    let step = (first.point.xc - sep_xc) / (n - 1) as f64;
    let fine = (1..n).map(|k| {
        if k == n - 1 {
            sep_xc
        } else {
            first.point.xc - k as f64 * step
        }
    });
    let (mut states, stop2) = marcher.march(first, fine, h1, &mut |done| {
        progress(SweepProgress::Fine {
            done: done + 1,
            total: n,
        })
    })?;
    let separation = match stop2 {
        // A snap or release found on the fine grid (normally at its last point) wins.
        Some(Stop::Snap(s)) => {
            states.push(s);
            Separation::Snap
        }
        Some(Stop::Release(s)) => {
            states.push(s);
            Separation::Release
        }
        Some(Stop::MultiContact(xc)) => Separation::MultiContact { xc },
        Some(Stop::EndOfContour) => Separation::EndOfContour,
        None => {
            // The fine march reached pass 1's separation point: keep pass 1's exactly located
            // event state there.
            if let Some(s) = final_state {
                if states
                    .last()
                    .is_some_and(|l| l.point.xc == s.point.xc && l.phase == s.phase)
                {
                    states.pop();
                }
                if states.last().is_none_or(|l| l.point.xc > s.point.xc) {
                    states.push(s);
                }
            }
            separation
        }
    };
    let mut points = Vec::with_capacity(settings.pre_contact_rows + states.len());
    for k in (1..=settings.pre_contact_rows).rev() {
        points.push(SweepPoint {
            x0: first.x0 + k as f64 * settings.pre_contact_spacing,
            ax: free.base.ax,
            ay: free.base.ay,
            ma: free.base.ma,
            phi0: free.base.phi0,
            f: 0.0,
            s1: 1.0,
            phi1: free.tip.phi,
            phase: Phase::None,
            xc: f64::NAN,
            yc: f64::NAN,
            psi: f64::NAN,
        });
    }
    points.extend(states.iter().map(|s| SweepPoint::from_state(s, flow)));
    Ok(SweepResult {
        q: flow.q,
        alpha: flow.alpha,
        points,
        first_contact,
        separation,
    })
}
