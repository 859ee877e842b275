//! One row of a frictional log on its own: the shape integrated from the base (it needs no
//! contact law), the phase hypotheses (the tip, where `m(1) = 0` [6.6]; every root of
//! `m(s1) = 0` on `(0, 1)`), and for each the contact force `F` that the base reaction
//! balances with the flow on `[0, s1]` [6.8, 6.9], split along the whisker's tangent at `s1`
//! (phase B: the contour's tangent there) into its normal part `fn` and tangential part `ft`
//! (spec/model.md, "Friction at the contact"). The sensitivities of every quantity to the
//! observables `(Ax, Ay, MA, phi0)` are central differences of the whole evaluation (four
//! columns, eight integrations), which also tracks a root as the row moves.

use crate::base_shot::base_ivp;
use crate::common::force_components;
use crate::error::Result;
use crate::observables::ObservableRow;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::{Dop853, OdeSolution};

/// Samples of `m` on `[0, s_end]` scanned for sign changes.
pub const ROOT_SAMPLES: usize = 400;

/// The state of one hypothesis: `[s1, x, y, phi(s1), Fx, Fy]` and, at the tip, `m(1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Candidate {
    /// Contact arc length (1 at the tip).
    pub s1: f64,
    /// Contact point.
    pub x: f64,
    /// Contact point.
    pub y: f64,
    /// Whisker angle at `s1`.
    pub phi: f64,
    /// Contact force on the whisker, x part: `Fx = f sin psi` of [6.8].
    pub fx: f64,
    /// Contact force on the whisker, y part: `Fy = -f cos psi` of [6.9].
    pub fy: f64,
}

impl Candidate {
    /// `(fn, ft)`: the force on the whisker split along the tangent `t = (cos psi, sin psi)`
    /// and the normal `n = (sin psi, -cos psi)`, `F = fn n + ft t` (spec/model.md).
    pub fn split(&self, psi: f64) -> (f64, f64) {
        let (sp, cp) = psi.sin_cos();
        (self.fx * sp - self.fy * cp, self.fx * cp + self.fy * sp)
    }
}

/// What one integration from the base gives: `m(1)` and the tip (if reached) and the
/// phase-B roots.
#[derive(Clone, Debug)]
pub(crate) struct Shot {
    /// `m(1)` (NaN if the integration stopped short of the tip).
    pub m1: f64,
    /// The tip hypothesis (None if not reached).
    pub tip: Option<Candidate>,
    /// Every simple root of `m` on `(0, s_end)`.
    pub roots: Vec<Candidate>,
}

/// The candidate at arc `s` of the dense solution.
fn candidate(sol: &OdeSolution, row: &ObservableRow, flow: FluidLoad, s: f64) -> Option<Candidate> {
    let mut u = [0.0; 4];
    if !sol.eval_into(s, &mut u) {
        return None;
    }
    let (a, b) = force_components(row, flow, s);
    Some(Candidate {
        s1: s,
        x: u[2],
        y: u[3],
        phi: u[0],
        fx: a,
        fy: -b,
    })
}

/// `m` on the dense output (NaN outside).
fn m_at(sol: &OdeSolution, s: f64) -> f64 {
    let mut u = [0.0; 4];
    if sol.eval_into(s, &mut u) {
        u[1]
    } else {
        f64::NAN
    }
}

/// Bisection-secant (Illinois) root of `m` in `[a, b]` with `m(a) m(b) < 0`.
fn root_in(sol: &OdeSolution, mut a: f64, mut b: f64) -> f64 {
    let (mut fa, mut fb) = (m_at(sol, a), m_at(sol, b));
    let mut side = 0;
    for _ in 0..200 {
        let c = (a * fb - b * fa) / (fb - fa);
        let c = if c.is_finite() && c > a && c < b {
            c
        } else {
            0.5 * (a + b)
        };
        let fc = m_at(sol, c);
        if fc == 0.0 || (b - a) < 1e-15 {
            return c;
        }
        if (fc > 0.0) == (fb > 0.0) {
            b = c;
            fb = fc;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            a = c;
            fa = fc;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    0.5 * (a + b)
}

/// One integration from the base of `row` under `flow`: the tip and the roots of `m`.
///
/// # Errors
/// The integrator's failure.
pub(crate) fn shoot(
    whisker: &Whisker,
    flow: FluidLoad,
    row: &ObservableRow,
    integrator: &Dop853,
) -> Result<Shot> {
    let sol = base_ivp(whisker, flow, row, integrator)?;
    let reached = sol.s_end >= 1.0;
    let tip = if reached {
        candidate(&sol, row, flow, 1.0).map(|mut c| {
            // the end state itself (no interpolation)
            c.phi = sol.u_end[0];
            c.x = sol.u_end[2];
            c.y = sol.u_end[3];
            c
        })
    } else {
        None
    };
    let end = sol.s_end;
    let mut roots = Vec::new();
    let h = end / ROOT_SAMPLES as f64;
    let mut prev = (0.0, m_at(&sol, 0.0));
    for k in 1..=ROOT_SAMPLES {
        let s = if k == ROOT_SAMPLES { end } else { k as f64 * h };
        let m = m_at(&sol, s);
        // a root at the very tip is phase A's; at the base none
        if prev.1 != 0.0 && m.is_finite() && prev.1.is_finite() && (prev.1 > 0.0) != (m > 0.0) {
            let r = root_in(&sol, prev.0, s);
            if r > 1e-9 && r < end - 1e-9 {
                roots.extend(candidate(&sol, row, flow, r));
            }
        }
        prev = (s, m);
    }
    Ok(Shot {
        m1: if reached { sol.u_end[1] } else { f64::NAN },
        tip,
        roots,
    })
}

/// The four observable columns of a row, in the order `(Ax, Ay, MA, phi0)`, moved by `d` in
/// column `j`.
pub(crate) fn moved(row: &ObservableRow, j: usize, d: f64) -> ObservableRow {
    let mut r = *row;
    match j {
        0 => r.ax += d,
        1 => r.ay += d,
        2 => r.ma += d,
        _ => r.phi0 += d,
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_model::Reactions;

    #[test]
    fn the_split_is_the_force_along_tangent_and_normal() {
        // F = fn n + ft t with n = (sin psi, -cos psi), t = (cos psi, sin psi)
        let (fnn, ft, psi) = (2.0, -0.7, 0.4f64);
        let (sp, cp) = psi.sin_cos();
        let c = Candidate {
            s1: 1.0,
            x: 0.0,
            y: 0.0,
            phi: 0.0,
            fx: fnn * sp + ft * cp,
            fy: -fnn * cp + ft * sp,
        };
        let (a, b) = c.split(psi);
        assert!((a - fnn).abs() < 1e-15 && (b - ft).abs() < 1e-15);
    }

    #[test]
    fn a_straight_whisker_under_a_tip_force_has_its_tip_as_the_only_contact() {
        // straight uniform rigid whisker along +y, tip force (-1e-3, 0) small: m(1) = 0
        // exactly at the tip for the base moment of the force; no interior root of m
        let w = Whisker::new(1.0, 0.0, 0.0, f64::INFINITY);
        let flow = FluidLoad { q: 0.0, alpha: 0.0 };
        let fx = -1e-3;
        let r = Reactions::balancing((fx, 0.0), flow, 1.0);
        // MA = -m(0); m(0) = -(moment of F about the base) ~ fx * 1 for the straight rod
        let shot_of = |ma: f64| {
            let row = ObservableRow {
                x0: 0.0,
                ax: r.ax,
                ay: r.ay,
                ma,
                phi0: std::f64::consts::FRAC_PI_2,
            };
            shoot(&w, flow, &row, &Dop853::new(1e-12, 1e-12).with_dense(true)).unwrap()
        };
        // secant on MA for m(1) = 0
        let (mut a, mut b) = (0.0, 2e-3);
        let (mut fa, mut fb) = (shot_of(a).m1, shot_of(b).m1);
        for _ in 0..30 {
            let c = b - fb * (b - a) / (fb - fa);
            (a, fa) = (b, fb);
            b = c;
            fb = shot_of(b).m1;
            if fb.abs() < 1e-15 {
                break;
            }
        }
        let shot = shot_of(b);
        assert!(shot.m1.abs() < 1e-13, "{}", shot.m1);
        assert!(shot.roots.is_empty(), "{:?}", shot.roots);
        let tip = shot.tip.unwrap();
        // the force balanced at the tip is the one applied
        assert!((tip.fx - fx).abs() < 1e-15 && tip.fy.abs() < 1e-15);
        // linear deflection fx / 3
        assert!((tip.x - fx / 3.0).abs() < 1e-6, "{}", tip.x);
    }
}
