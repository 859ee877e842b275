//! What both reconstruction methods and the identification take and share: settings, what
//! is known of the flow, the force balance of a contact row [6.8, 6.9], the quality measure
//! [6.11] and the noise scales of a log. The results they return are in
//! [`result`](crate::result). This module imports none of the crate's methods: they all
//! import it.
//!
//! **Row numbers.** Everywhere in this crate (`ReconPoint::row`, the `row` of every
//! [`ReconError`](crate::ReconError), `Identification::pre_contact`) a row number is the
//! 0-based index of the row in the slice given to the library. Front ends map it to their own
//! numbering (the CLI names the line of the file).

use crate::observables::ObservableRow;
use crate::result::ReconPoint;
use beam_model::{FluidLoad, Reactions};
use serde::{Deserialize, Serialize};

/// Smallest relative noise level assumed for a log: an exact (simulated) log carries its
/// solver's tolerance (the sweep solves to 1e-11; the free rows of one sweep differ by ~1e-12).
pub const NOISE_FLOOR: f64 = 1e-11;

/// Reconstruction method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ReconMethod {
    /// Initial-value route from the base (spec/model.md): one integration per row, all
    /// phase-B roots bracketed, ~1e-12 on exact logs.
    Accurate,
    /// The thesis's five equations [6.5-6.9] around FDM solves with a trust region and the
    /// slope-jump phase rule [6.10].
    Thesis,
}

impl ReconMethod {
    /// The CLI name.
    pub fn name(&self) -> &'static str {
        match self {
            ReconMethod::Accurate => "accurate",
            ReconMethod::Thesis => "thesis",
        }
    }
}

/// Settings of a reconstruction; each method honours every field.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReconSettings {
    /// The method.
    pub method: ReconMethod,
    /// Solver tolerance: the integrator tolerance of `accurate` (and of the identification's
    /// free-whisker checks), the trust-region tolerance on the residual norm of `thesis`
    /// [6.5-6.9] (which its FDM model cannot get below ~1e-5: a smaller value only costs time).
    pub tol: f64,
    /// Relative noise level of the log (standard deviation of each of `Ax, Ay, MA, phi0` over
    /// that column's largest magnitude, the convention of [`add_noise`](crate::add_noise));
    /// `None` estimates it from the log (the rows' model residuals).
    pub noise: Option<f64>,
    /// Fail on a contact row whose best residual exceeds this and is not explained by the
    /// GIVEN noise level (`noise`, else the exact-log floor): None never fails and reports
    /// residuals and error estimates (the setting for noisy logs of unknown noise).
    pub consistency_tol: Option<f64>,
}

impl Default for ReconSettings {
    fn default() -> Self {
        ReconSettings {
            method: ReconMethod::Accurate,
            tol: 1e-12,
            noise: None,
            consistency_tol: Some(1e-6),
        }
    }
}

/// What is known about the flow before the log is read: `None` is identified from the
/// pre-contact rows [6.1].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct KnownFlow {
    /// The fluid load q >= 0.
    pub q: Option<f64>,
    /// The flow angle alpha (rad), in (-pi/2, pi/2).
    pub alpha: Option<f64>,
}

/// Contact force and contour angle `(f, psi)` for a contact at `s1` [6.8, 6.9] with the flow
/// `(q, alpha)` acting on `[0, s1]`: `f sin psi = -Ax - q s1 cos alpha`,
/// `f cos psi = Ay - q s1 sin alpha` (the base reaction balances the force
/// `f (sin psi, -cos psi)` and the flow `q (cos alpha, -sin alpha)` per length).
pub fn contact_force(row: &ObservableRow, flow: FluidLoad, s1: f64) -> (f64, f64) {
    let (a, b) = force_components(row, flow, s1);
    (a.hypot(b), a.atan2(b))
}

/// `(f sin psi, f cos psi)` of [6.8, 6.9]: the point force the row's reactions balance with
/// the flow on `[0, s1]` ([`Reactions::point_force`]).
pub(crate) fn force_components(row: &ObservableRow, flow: FluidLoad, s1: f64) -> (f64, f64) {
    Reactions {
        ax: row.ax,
        ay: row.ay,
    }
    .point_force(flow, s1)
}

/// The flow of a free whisker with these base forces [6.1]: `q = hypot(Ax, Ay)`,
/// `alpha = atan2(Ay, -Ax)` (alpha = 0 for q = 0; [`Reactions::free_flow`]).
pub fn free_flow(ax: f64, ay: f64) -> FluidLoad {
    Reactions { ax, ay }.free_flow()
}

/// The quality measure [6.11]: `e = |y_rec - g(x_rec)|` per reconstructed point (for a peg
/// or a disc, touched from any side, the distance to it, [`contact_sim::Profile::clearance`]).
pub fn contour_error(points: &[ReconPoint], profile: &contact_sim::Profile) -> Vec<f64> {
    points
        .iter()
        .map(|p| {
            if profile.is_closed() {
                // a peg or a disc touched from any side: the distance to it
                profile.clearance(p.x, p.y).abs()
            } else {
                (p.y - profile.y(p.x)).abs()
            }
        })
        .collect()
}

/// Full-scale magnitudes of the columns `Ax, Ay, MA, phi0`: the noise of column `j` at
/// relative level `l` has standard deviation `l * scale[j]` (the convention of
/// [`add_noise`](crate::add_noise)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct NoiseScales(pub [f64; 4]);

impl NoiseScales {
    /// The largest magnitude of each column over `rows` (as [`add_noise`](crate::add_noise):
    /// a column that is zero throughout, such as `phi0` on a rigid support, carries no noise).
    pub fn of(rows: &[ObservableRow]) -> Self {
        let mut s = [0.0f64; 4];
        for r in rows {
            for (k, v) in [r.ax, r.ay, r.ma, r.phi0].into_iter().enumerate() {
                s[k] = s[k].max(v.abs());
            }
        }
        NoiseScales(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use contact_sim::Phase;

    #[test]
    fn contact_force_inverts_the_force_balance() {
        // the reactions to the contact force f (sin psi, -cos psi) at s1 with the flow on
        // [0, s1]: the point force (f sin psi, f cos psi) of [6.8, 6.9]
        let flow = FluidLoad { q: 1.5, alpha: 0.3 };
        let (f, psi, s1) = (2.5, -0.4f64, 0.7);
        let reactions = Reactions::balancing((f * psi.sin(), f * psi.cos()), flow, s1);
        let row = ObservableRow {
            x0: 0.1,
            ax: reactions.ax,
            ay: reactions.ay,
            ma: 0.3,
            phi0: 1.5,
        };
        let (fr, psir) = contact_force(&row, flow, s1);
        assert!(
            (fr - f).abs() < 1e-14 && (psir - psi).abs() < 1e-14,
            "{fr} {psir}"
        );
        // Ax = -(f sin psi + q s1 cos alpha) by hand
        let ax = -(f * psi.sin() + flow.q * s1 * flow.alpha.cos());
        assert!((row.ax - ax).abs() < 1e-15);
        // a free whisker's reactions are the flow's [6.1]
        let free = Reactions::balancing((0.0, 0.0), flow, 1.0);
        let back = free_flow(free.ax, free.ay);
        assert!((back.q - flow.q).abs() < 1e-15 && (back.alpha - flow.alpha).abs() < 1e-15);
    }

    #[test]
    fn noise_scales_and_contour_errors() {
        let row = |ax: f64, ay: f64, ma: f64, phi0: f64| ObservableRow {
            x0: 0.0,
            ax,
            ay,
            ma,
            phi0,
        };
        let s = NoiseScales::of(&[row(-3.0, 1.0, 0.0, 1.5), row(2.0, -4.0, 0.0, 1.6)]);
        assert_eq!(s.0, [3.0, 4.0, 0.0, 1.6]);
        // g1 at two points: one on the contour, one 0.01 above it
        let g1 = contact_sim::Profile::g1();
        let point = |x: f64, dy: f64| ReconPoint {
            row: 0,
            x0: 0.0,
            x,
            y: g1.y(x) + dy,
            s1: 1.0,
            f: 1.0,
            psi: 0.0,
            phase: Phase::A,
            residual: 0.0,
            sigma: 0.0,
            alternatives: 0,
            evaluations: 0,
        };
        let e = contour_error(&[point(0.2, 0.0), point(-0.1, 0.01)], &g1);
        assert!(e[0] == 0.0 && (e[1] - 0.01).abs() < 1e-15, "{e:?}");
    }
}
