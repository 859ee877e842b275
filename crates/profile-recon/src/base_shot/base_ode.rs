//! The first-order system integrated from the base with a row's observables as initial
//! values [3.25, 6.8, 6.9], with its optional variational equations, and the one integration
//! from the base that every hypothesis of a row reads.

use super::context::MAX_WINDING;
use crate::common::force_components;
use crate::error::Result;
use crate::observables::ObservableRow;
use beam_model::equations::{state_rate, variational_rate, MomentLaw, MomentRate};
use beam_model::{FluidLoad, Loads, TipForce, Whisker};
use bvp_solvers::integrator::{Dop853, OdeSolution, OdeSystem};

/// The observables `(Ax, Ay, MA, phi0)` by which [`BaseOde`]'s variational equations
/// differentiate, as indices of [`sens_offset`] (and of the columns of the carried
/// sensitivities).
pub(crate) mod by {
    /// The horizontal base reaction `Ax`.
    pub const AX: usize = 0;
    /// The vertical base reaction `Ay`.
    pub const AY: usize = 1;
    /// The base moment `MA`.
    pub const MA: usize = 2;
    /// The base angle `phi0`.
    pub const PHI0: usize = 3;
}

/// The components of the state `(phi, m, x, y)` of [`BaseOde`] (and of each block of its
/// variational equations).
pub(crate) mod comp {
    /// The angle `phi`.
    pub const PHI: usize = 0;
    /// The internal moment `m`.
    pub const M: usize = 1;
}

/// Where the derivatives of the state `(phi, m, x, y)` by observable `j` ([`by`]) begin in
/// the state of [`BaseOde`] with sensitivities (after the state itself).
pub(crate) const fn sens_offset(j: usize) -> usize {
    4 * (j + 1)
}

/// The derivatives of the state `(phi, m, x, y)` by observable `j` ([`by`]) in the state `u`
/// of [`BaseOde`] with sensitivities.
#[cfg(test)]
pub(crate) fn sens_block(u: &[f64], j: usize) -> &[f64] {
    &u[sens_offset(j)..sens_offset(j) + 4]
}

/// The first-order system [3.25] integrated from the base with the base reaction of a row.
/// For a contact at `s1 >= s` the internal force at `s` is fixed by the base reaction and the
/// flow on `[0, s]` [6.8, 6.9], whatever `s1`; so the row's phase-A loads (the point force
/// `f (cos beta, sin beta)` at the tip that balances the reactions with the flow on `[0, 1]`,
/// [`Reactions::point_force`]) give the moment law of every hypothesis
/// ([`MomentLaw`], as in [`WhiskerOde`](beam_model::equations::WhiskerOde)):
///
/// ```text
/// phi' = m / e^4 + A s + B,  m' = f sin(phi + beta) + q (1 - s) sin(phi + alpha),
/// x' = cos phi,  y' = sin phi,
/// ```
///
/// with `(phi, m, x, y)(0) = (phi0, -MA, x0, 0)` ([`state_rate`] with the law's `m'`);
/// optionally followed by the variational equations with respect to `(Ax, Ay, MA, phi0)`
/// ([`variational_rate`], blocks at [`sens_offset`]; `Ax`, `Ay` enter the law through the force
/// `(f cos beta, f sin beta) = (-Ax - q cos alpha, Ay - q sin alpha)`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BaseOde {
    whisker: Whisker,
    law: MomentLaw,
    sens: bool,
    /// `sin` and `cos` of `phi` by [`beam_model::trig::sin_cos`] (the reconstruction's
    /// evaluations), or the library's, as the beam model's FDM computes them (the
    /// calibration, whose finite-difference Jacobians see the last bits).
    fast: bool,
}

impl BaseOde {
    pub(crate) fn new(whisker: &Whisker, flow: FluidLoad, row: &ObservableRow, sens: bool) -> Self {
        let (fc, fs) = force_components(row, flow, 1.0);
        let loads = Loads {
            tip: TipForce::dp(fc.hypot(fs), fs.atan2(fc)),
            fluid: flow,
            s1: 1.0,
        };
        BaseOde {
            whisker: *whisker,
            law: MomentLaw::new(&loads, 0.0),
            sens,
            fast: false,
        }
    }

    /// The system with `sin`, `cos` by [`beam_model::trig::sin_cos`] (the shots' own, within
    /// 2e-16 of the library's): the reconstruction's evaluations.
    pub(crate) fn fast(self) -> Self {
        BaseOde { fast: true, ..self }
    }

    /// The moment law at `s` where `(sin phi, cos phi) = (sp, cp)`: `m'`, `dm'/dphi` (the
    /// tangency residual `g = f sin(phi - psi)` of a contact at `s` is `-dm'/dphi`).
    #[inline]
    pub(super) fn rate(&self, s: f64, sp: f64, cp: f64) -> MomentRate {
        self.law.at(s, sp, cp)
    }

    /// `(sin x, cos x)`, by [`beam_model::trig::sin_cos`] in the [`BaseOde::fast`] system.
    #[inline(always)]
    pub(super) fn sin_cos(&self, x: f64) -> (f64, f64) {
        if self.fast {
            beam_model::trig::sin_cos(x)
        } else {
            x.sin_cos()
        }
    }

    /// `1 / e(s)^4`, the compliance of the whisker at `s` [3.8].
    #[inline]
    pub(super) fn compliance(&self, s: f64) -> f64 {
        if self.whisker.theta == 1.0 {
            // a cylinder (e = 1: the division's own value, without the division)
            return 1.0;
        }
        let e = self.whisker.diameter(s);
        let e2 = e * e;
        1.0 / (e2 * e2)
    }

    /// `phi''` at `s` from the state `(phi, m)` and `m'` there: the derivative of
    /// `phi' = m / e^4 + A s + B`, `m' / e^4 - 4 m e' / e^5 + A`.
    #[inline]
    pub(super) fn phi_curvature_rate(&self, s: f64, m: f64, dm: f64) -> f64 {
        let w = &self.whisker;
        let inv_e4 = self.compliance(s);
        dm * inv_e4 - 4.0 * (w.theta - 1.0) * inv_e4 / w.diameter(s) * m + w.a
    }

    /// Initial state for `row`.
    pub(super) fn initial(&self, row: &ObservableRow) -> Vec<f64> {
        let mut u = vec![0.0; self.dim()];
        u[..4].copy_from_slice(&[row.phi0, -row.ma, row.x0, 0.0]);
        if self.sens {
            u[sens_offset(by::MA) + comp::M] = -1.0;
            u[sens_offset(by::PHI0) + comp::PHI] = 1.0;
        }
        u
    }
}

impl OdeSystem for BaseOde {
    fn dim(&self) -> usize {
        if self.sens {
            20
        } else {
            4
        }
    }

    #[inline(always)]
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]) {
        let inv_e4 = self.compliance(s);
        let (sp, cp) = self.sin_cos(u[comp::PHI]);
        // the state alone in the fast system: the law's m' regrouped (latency-bound)
        let dm = if self.fast && !self.sens {
            self.law.dm(s, sp, cp)
        } else {
            self.rate(s, sp, cp).dm
        };
        state_rate(&self.whisker, s, u[comp::M], inv_e4, (sp, cp), dm, du);
        if self.sens {
            variational(u, du, (sp, cp), inv_e4, self.rate(s, sp, cp).dm_dphi);
        }
    }
}

/// The variational part of [`BaseOde`]'s right-hand side at a state with `(sin phi, cos phi)
/// = (sp, cp)`, compliance `inv_e4` and `d m' / d phi = jm` (out of the state's hot path).
#[cold]
#[inline(never)]
fn variational(u: &[f64], du: &mut [f64], (sp, cp): (f64, f64), inv_e4: f64, jm: f64) {
    for j in [by::AX, by::AY, by::MA, by::PHI0] {
        // d(f cos beta)/dAx = -1, d(f sin beta)/dAy = 1
        let explicit = match j {
            by::AX => -sp,
            by::AY => cp,
            _ => 0.0,
        };
        variational_rate(u, du, sens_offset(j), inv_e4, (sp, cp), jm, explicit);
    }
}

/// Integrates [`BaseOde`] from the base to `s_end` (at most 1; the state part stops early
/// if `phi` winds by [`MAX_WINDING`]) with dense output.
pub(crate) fn base_ivp(
    whisker: &Whisker,
    flow: FluidLoad,
    row: &ObservableRow,
    integrator: &Dop853,
) -> Result<OdeSolution> {
    integrate(&BaseOde::new(whisker, flow, row, false), row, integrator)
}

/// As [`base_ivp`], the system [`fast`](BaseOde::fast) (the reconstruction's).
pub(crate) fn base_ivp_fast(
    whisker: &Whisker,
    flow: FluidLoad,
    row: &ObservableRow,
    integrator: &Dop853,
) -> Result<OdeSolution> {
    integrate(
        &BaseOde::new(whisker, flow, row, false).fast(),
        row,
        integrator,
    )
}

/// [`base_ivp`] of the system `ode`.
fn integrate(ode: &BaseOde, row: &ObservableRow, integrator: &Dop853) -> Result<OdeSolution> {
    let u0 = ode.initial(row);
    let phi0 = row.phi0;
    let (sol, _) =
        integrator.integrate_until(ode, 0.0, 1.0, &u0, |_, u| MAX_WINDING - (u[0] - phi0).abs())?;
    Ok(sol)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A row at x0 = 0.3 with the given observables.
    pub(crate) fn row(ax: f64, ay: f64, ma: f64, phi0: f64) -> ObservableRow {
        ObservableRow {
            x0: 0.3,
            ax,
            ay,
            ma,
            phi0,
        }
    }

    /// The cylinder without force from the base moment `ma` and angle `phi0`.
    fn unloaded(ma: f64, phi0: f64) -> OdeSolution {
        let flow = FluidLoad { q: 0.0, alpha: 0.0 };
        let r = row(0.0, 0.0, ma, phi0);
        base_ivp(&Whisker::uniform(), flow, &r, &Dop853::new(1e-12, 1e-12)).unwrap()
    }

    #[test]
    fn unloaded_cylinder_bends_into_a_circular_arc() {
        // no force, constant moment m = -MA: phi = phi0 - MA s, a circle of radius 1/MA
        let sol = unloaded(-0.7, 1.2);
        assert_eq!(sol.s_end, 1.0);
        let (c, p0) = (0.7, 1.2);
        let u = &sol.u_end;
        assert!((u[0] - (p0 + c)).abs() < 1e-11);
        assert!((u[1] - 0.7).abs() < 1e-12);
        assert!((u[2] - (0.3 + ((p0 + c).sin() - p0.sin()) / c)).abs() < 1e-11);
        assert!((u[3] - (p0.cos() - (p0 + c).cos()) / c).abs() < 1e-11);
    }

    #[test]
    fn winding_stops_the_integration_early() {
        // a moment of 20 winds phi by 20 rad over the whisker: stopped at 12 rad, s = 0.6
        let sol = unloaded(-20.0, 0.0);
        assert!(
            (sol.s_end - MAX_WINDING / 20.0).abs() < 1e-9,
            "{}",
            sol.s_end
        );
    }

    #[test]
    fn variational_equations_match_finite_differences() {
        let w = Whisker::new(0.4, 0.3, 0.2, f64::INFINITY);
        let flow = FluidLoad { q: 0.8, alpha: 0.3 };
        let r0 = row(-0.5, 0.9, 0.2, 1.4);
        let tight = Dop853::new(1e-12, 1e-12);
        let sode = BaseOde::new(&w, flow, &r0, true);
        let jac = tight
            .integrate(&sode, 0.0, 1.0, &sode.initial(&r0))
            .unwrap();
        let h = 1e-6;
        for j in 0..4 {
            let at = |d: f64| {
                let mut r = r0;
                match j {
                    0 => r.ax += d,
                    1 => r.ay += d,
                    2 => r.ma += d,
                    _ => r.phi0 += d,
                }
                base_ivp(&w, flow, &r, &tight).unwrap().u_end
            };
            let (up, um) = (at(h), at(-h));
            for c in 0..4 {
                let fd = (up[c] - um[c]) / (2.0 * h);
                let v = sens_block(&jac.u_end, j)[c];
                assert!(
                    (fd - v).abs() < 1e-6 * (1.0 + v.abs()),
                    "d{c}/d{j}: {fd} vs {v}"
                );
            }
        }
    }
}
