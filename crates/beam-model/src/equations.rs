//! The whisker's equations: the first-order system integrated by shooting and the
//! second-order form [3.25] with its Jacobian [3.27] discretised by the FDM.

use crate::loads::{LoadKind, Loads};
use crate::whisker::Whisker;
use bvp_solvers::fdm::SecondOrderBvp;
use bvp_solvers::integrator::OdeSystem;
use std::f64::consts::FRAC_PI_2;

/// Which parameter sensitivities the first-order system carries along (variational
/// equations), for Newton iterations with exact derivatives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sensitivities {
    /// State only: `(phi, m, x, y)`.
    None,
    /// State and its derivative with respect to the tip angle `phi1`.
    TipAngle,
    /// State and its derivatives with respect to `(phi1, f, s1, beta)`, in that order.
    All,
}

impl Sensitivities {
    /// Number of parameters differentiated.
    pub fn count(&self) -> usize {
        match self {
            Sensitivities::None => 0,
            Sensitivities::TipAngle => 1,
            Sensitivities::All => 4,
        }
    }
}

/// The moment law of the loaded part `[0, s1]` [3.25] (spec/model.md): the internal moment's
/// rate
///
/// ```text
/// m' = f sin(phi + c) + q (s1 - s) sin(phi + alpha),
/// c = beta (DP)  or  beta - phi1 + pi/2 (AP: m' = f cos(phi + beta - phi1) + ...),
/// ```
///
/// the one place every method evaluates it: the shots' first-order system, the FDM's
/// second-order form and its base moment. The load angles enter through addition theorems:
/// one `sin_cos` of `phi` per evaluation.
#[derive(Clone, Copy, Debug)]
pub struct MomentLaw {
    f: f64,
    q: f64,
    s1: f64,
    /// `(sin, cos)` of the force angle `c`.
    force: (f64, f64),
    /// `(sin, cos)` of alpha.
    flow: (f64, f64),
}

/// [`MomentLaw::at`]: the rate and the trigonometric values it was made of.
#[derive(Clone, Copy, Debug)]
pub struct MomentRate {
    /// `m'`.
    pub dm: f64,
    /// `d m' / d phi = f cos(phi + c) + q (s1 - s) cos(phi + alpha)`.
    pub dm_dphi: f64,
    /// `sin(phi + c)`, `cos(phi + c)`.
    pub force: (f64, f64),
    /// `sin(phi + alpha)`.
    pub flow_sin: f64,
}

impl MomentLaw {
    /// The law of `loads`, with the tip angle `phi1` for AP forces (ignored for DP).
    pub fn new(loads: &Loads, phi1: f64) -> Self {
        let c = match loads.tip.kind {
            LoadKind::Dp => loads.tip.beta,
            LoadKind::Ap => loads.tip.beta - phi1 + FRAC_PI_2,
        };
        MomentLaw {
            f: loads.tip.f,
            q: loads.fluid.q,
            s1: loads.s1,
            force: c.sin_cos(),
            flow: loads.fluid.alpha.sin_cos(),
        }
    }

    /// The law with the tip angle `phi1` (for AP forces; `self` for DP).
    #[inline]
    pub fn at_tip_angle(&self, loads: &Loads, phi1: f64) -> Self {
        match loads.tip.kind {
            LoadKind::Dp => *self,
            LoadKind::Ap => MomentLaw {
                force: (loads.tip.beta - phi1 + FRAC_PI_2).sin_cos(),
                ..*self
            },
        }
    }

    /// `m'` alone at arc length `s` where `(sin phi, cos phi) = (sp, cp)`: [`MomentLaw::at`]'s
    /// sum regrouped as `sin phi (f cos c + (s1 - s) q cos alpha) + cos phi (f sin c +
    /// (s1 - s) q sin alpha)`, fewer operations after `sin_cos` (the reconstruction's state
    /// runs are bound by that latency: 8 % of the stream's time).
    #[inline]
    pub fn dm(&self, s: f64, sp: f64, cp: f64) -> f64 {
        let ((sb, cb), (sal, cal)) = (self.force, self.flow);
        let arm = (self.s1 - s) * self.q;
        sp * (self.f * cb + arm * cal) + cp * (self.f * sb + arm * sal)
    }

    /// The rate at arc length `s` where `(sin phi, cos phi) = (sp, cp)`.
    #[inline]
    pub fn at(&self, s: f64, sp: f64, cp: f64) -> MomentRate {
        let (sb, cb) = self.force;
        let (sc, cc) = (sp * cb + cp * sb, cp * cb - sp * sb);
        let arm = self.s1 - s;
        let (sal, cal) = self.flow;
        let (sa, ca) = (sp * cal + cp * sal, cp * cal - sp * sal);
        MomentRate {
            dm: self.f * sc + self.q * arm * sa,
            dm_dphi: self.f * cc + self.q * arm * ca,
            force: (sc, cc),
            flow_sin: sa,
        }
    }
}

/// The rates of the state `(phi, m, x, y)` of the first-order system [3.25] at `s`
/// (`inv_e4 = 1 / e(s)^4`, `(sin phi, cos phi) = (sp, cp)`, `dm = m'` from the
/// [`MomentLaw`]) written into `du[..4]`:
/// `phi' = m / e^4 + A s + B`, `m'`, `x' = cos phi`, `y' = sin phi`. Shared by
/// [`WhiskerOde`] and the integrations from the base of the reconstruction.
#[inline(always)]
pub fn state_rate(
    w: &Whisker,
    s: f64,
    m: f64,
    inv_e4: f64,
    (sp, cp): (f64, f64),
    dm: f64,
    du: &mut [f64],
) {
    du[0] = m * inv_e4 + w.a * s + w.b;
    du[1] = dm;
    du[2] = cp;
    du[3] = sp;
}

/// The rates of one block of variational equations of [3.25], the derivatives
/// `(dphi, dm, dx, dy) = u[o..o + 4]` of the state by one parameter, written into
/// `du[o..o + 4]`: `dphi' = dm / e^4`, `dm' = jm dphi + explicit`, `dx' = -sin phi dphi`,
/// `dy' = cos phi dphi` (`jm = d m' / d phi`, `explicit` the parameter's own derivative of
/// `m'`).
#[inline(always)]
pub fn variational_rate(
    u: &[f64],
    du: &mut [f64],
    o: usize,
    inv_e4: f64,
    (sp, cp): (f64, f64),
    jm: f64,
    explicit: f64,
) {
    let (dphi, dm) = (u[o], u[o + 1]);
    du[o] = dm * inv_e4;
    du[o + 1] = jm * dphi + explicit;
    du[o + 2] = -sp * dphi;
    du[o + 3] = cp * dphi;
}

/// The first-order system of the elastica, written for integration from the loaded end
/// `s1` towards the base (any direction works):
///
/// ```text
/// x' = cos phi,  y' = sin phi,  phi' = m / e^4 + A s + B,
/// m' = f sin(phi + beta) + q (s1 - s) sin(phi + alpha)           (DP)
/// m' = f cos(phi + beta - phi1) + q (s1 - s) sin(phi + alpha)    (AP)
/// ```
///
/// (thesis [3.25] split into first order, signs of spec/model.md). The state is
/// `(phi, m, x, y)` followed by 4 variational components per sensitivity parameter.
#[derive(Clone, Copy, Debug)]
pub struct WhiskerOde {
    whisker: Whisker,
    loads: Loads,
    /// Tip angle used by AP loads (ignored for DP).
    phi1: f64,
    sens: Sensitivities,
    law: MomentLaw,
}

impl WhiskerOde {
    /// The system for a whisker, its loads and (for AP loads) the tip angle `phi1`.
    pub fn new(whisker: Whisker, loads: Loads, phi1: f64, sens: Sensitivities) -> Self {
        WhiskerOde {
            whisker,
            loads,
            phi1,
            sens,
            law: MomentLaw::new(&loads, phi1),
        }
    }
}

impl OdeSystem for WhiskerOde {
    fn dim(&self) -> usize {
        4 * (1 + self.sens.count())
    }

    #[inline]
    fn rhs(&self, s: f64, u: &[f64], du: &mut [f64]) {
        let w = &self.whisker;
        let l = &self.loads;
        let (phi, m) = (u[0], u[1]);
        let e = w.diameter(s);
        let e2 = e * e;
        let inv_e4 = 1.0 / (e2 * e2);
        let (sp, cp) = crate::trig::sin_cos(phi);
        let rate = self.law.at(s, sp, cp);
        state_rate(w, s, m, inv_e4, (sp, cp), rate.dm, du);
        let jm = rate.dm_dphi;
        let (sc, cc) = rate.force;
        // phi1 enters AP loads only: d/dphi1 f sin(c) = -f cos(c)
        let explicit_phi1 = match l.tip.kind {
            LoadKind::Dp => 0.0,
            LoadKind::Ap => -l.tip.f * cc,
        };
        match self.sens {
            Sensitivities::None => return,
            Sensitivities::TipAngle => {
                // the one block of the Newton shots
                variational_rate(u, du, 4, inv_e4, (sp, cp), jm, explicit_phi1);
                return;
            }
            Sensitivities::All => {}
        }
        let sa = rate.flow_sin;
        let n = self.sens.count();
        for j in 0..n {
            let explicit = match j {
                0 => explicit_phi1,
                1 => sc,
                2 => l.fluid.q * sa,
                // the force angle c moves with beta for DP and AP alike
                _ => l.tip.f * cc,
            };
            variational_rate(u, du, 4 * (j + 1), inv_e4, (sp, cp), jm, explicit);
        }
    }
}

/// The second-order form [3.25] for the FDM, on `[0, s1]`:
///
/// ```text
/// phi'' = [f sin(phi+beta) + q (s1-s) sin(phi+alpha)] / e^4 - 4 (theta-1)/e (phi' - A s - B) + A
/// ```
///
/// with Jacobian [3.27] `dF/dphi = [f cos(phi+beta) + q (s1-s) cos(phi+alpha)] / e^4`,
/// `dF/dphi' = -4 (theta - 1)/e`. For AP loads `sin(phi+beta)` becomes
/// `cos(phi + beta - phi1)` with `phi1 = phi(s1)` the unknown tip angle: the problem then
/// [depends on the right end](SecondOrderBvp::depends_on_right_end), and
/// [`eval_with_right_end`](SecondOrderBvp::eval_with_right_end) takes `phi1 = y(b)` from the
/// current iterate, with the extra derivative
/// `dF/dphi1 = f sin(phi + beta - phi1) / e^4` (so the FDM Newton matrix is bordered and
/// `phi1` is solved for together with the nodal angles, no outer iteration).
/// The plain [`f`](SecondOrderBvp::f), [`f_y`](SecondOrderBvp::f_y) and
/// [`eval`](SecondOrderBvp::eval) use the fixed `phi1` given to [`WhiskerFdmProblem::new`]
/// (the fixed-direction problem).
#[derive(Clone, Copy, Debug)]
pub struct WhiskerFdmProblem {
    ode: WhiskerOde,
}

impl WhiskerFdmProblem {
    /// The FDM problem; `phi1` is the tip angle used by the fixed-direction evaluations
    /// (`f`, `f_y`, `eval`) for AP loads; the FDM solver uses the iterate's own tip angle.
    pub fn new(whisker: Whisker, loads: Loads, phi1: f64) -> Self {
        WhiskerFdmProblem {
            ode: WhiskerOde::new(whisker, loads, phi1, Sensitivities::None),
        }
    }

    /// `(F, dF/dphi, dF/dphi', dF/dphi1)` of [3.25]/[3.27] with tip angle `phi1` (used by
    /// AP loads only; `dF/dphi1 = 0` for DP), sharing one `sin_cos` per angle.
    #[inline]
    fn parts(&self, s: f64, phi: f64, dphi: f64, phi1: f64) -> (f64, f64, f64, f64) {
        let w = &self.ode.whisker;
        let l = &self.ode.loads;
        let e = w.diameter(s);
        let e2 = e * e;
        let inv_e4 = 1.0 / (e2 * e2);
        let (sp, cp) = phi.sin_cos();
        let rate = self.ode.law.at_tip_angle(l, phi1).at(s, sp, cp);
        let damp = -4.0 * (w.theta - 1.0) / e;
        let f = rate.dm * inv_e4 + damp * (dphi - w.kappa0(s)) + w.a;
        let f_y = rate.dm_dphi * inv_e4;
        let f_phi1 = match l.tip.kind {
            LoadKind::Dp => 0.0,
            LoadKind::Ap => -l.tip.f * rate.force.1 * inv_e4,
        };
        (f, f_y, damp, f_phi1)
    }
}

impl SecondOrderBvp for WhiskerFdmProblem {
    #[inline]
    fn f(&self, s: f64, phi: f64, dphi: f64) -> f64 {
        self.parts(s, phi, dphi, self.ode.phi1).0
    }

    #[inline]
    fn f_y(&self, s: f64, phi: f64, dphi: f64) -> f64 {
        self.parts(s, phi, dphi, self.ode.phi1).1
    }

    #[inline]
    fn f_yp(&self, s: f64, _phi: f64, _dphi: f64) -> f64 {
        let w = &self.ode.whisker;
        -4.0 * (w.theta - 1.0) / w.diameter(s)
    }

    #[inline]
    fn eval(&self, s: f64, phi: f64, dphi: f64) -> (f64, f64, f64) {
        let (f, f_y, f_yp, _) = self.parts(s, phi, dphi, self.ode.phi1);
        (f, f_y, f_yp)
    }

    #[inline]
    fn depends_on_right_end(&self) -> bool {
        self.ode.loads.tip.kind == LoadKind::Ap && self.ode.loads.tip.f != 0.0
    }

    #[inline]
    fn eval_with_right_end(&self, s: f64, phi: f64, dphi: f64, phi1: f64) -> (f64, f64, f64, f64) {
        self.parts(s, phi, dphi, phi1)
    }
}

/// The load-free segment `(s1, 1]` beyond a tangential contact (m = 0 in [3.25], so
/// `phi' = A s + B`): the angle in closed
/// form, `phi = phi1 + A (s^2 - s1^2)/2 + B (s - s1)` ([`Whisker::phi_free`]), and the
/// position by integration of `x' = cos phi`, `y' = sin phi` (state `(x, y)`).
#[derive(Clone, Copy, Debug)]
pub struct FreeSegment {
    /// The whisker (its pre-curvature).
    pub whisker: Whisker,
    /// Where the segment starts (the contact point).
    pub s1: f64,
    /// The angle there.
    pub phi1: f64,
}

impl FreeSegment {
    /// The angle at `s`.
    pub fn phi(&self, s: f64) -> f64 {
        self.whisker.phi_free(self.s1, self.phi1, s)
    }
}

impl OdeSystem for FreeSegment {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, s: f64, _u: &[f64], du: &mut [f64]) {
        let (sp, cp) = crate::trig::sin_cos(self.phi(s));
        du[0] = cp;
        du[1] = sp;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loads::TipForce;

    /// The regrouped `m'` is the law's sum in another order: equal to rounding, for DP and
    /// AP forces with a flow, at every arc length and angle tried.
    #[test]
    fn the_regrouped_rate_is_the_law() {
        for tip in [TipForce::dp(3.0, 0.7), TipForce::ap(2.0, -1.1)] {
            let loads = Loads {
                s1: 0.8,
                ..Loads::combined(tip, 5.0, 0.4)
            };
            let law = MomentLaw::new(&loads, 0.3);
            for i in 0..50 {
                let (s, phi) = (i as f64 / 49.0 * 0.8, -3.0 + 0.13 * i as f64);
                let (sp, cp) = phi.sin_cos();
                let (a, b) = (law.at(s, sp, cp).dm, law.dm(s, sp, cp));
                assert!(
                    (a - b).abs() <= 1e-14 * (1.0 + a.abs()),
                    "{s} {phi}: {a} vs {b}"
                );
            }
        }
    }
}
