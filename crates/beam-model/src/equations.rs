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
    /// State and its derivatives with respect to `(phi1, f, s1)`, in that order.
    All,
}

impl Sensitivities {
    /// Number of parameters differentiated.
    pub fn count(&self) -> usize {
        match self {
            Sensitivities::None => 0,
            Sensitivities::TipAngle => 1,
            Sensitivities::All => 3,
        }
    }
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
}

impl WhiskerOde {
    /// The system for a whisker, its loads and (for AP loads) the tip angle `phi1`.
    pub fn new(whisker: Whisker, loads: Loads, phi1: f64, sens: Sensitivities) -> Self {
        WhiskerOde {
            whisker,
            loads,
            phi1,
            sens,
        }
    }

    /// Angle `c` with `m' = f sin(c) + ...`: `phi + beta` (DP) or `phi + beta - phi1 + pi/2` (AP).
    #[inline]
    fn force_angle(&self, phi: f64) -> f64 {
        match self.loads.tip.kind {
            LoadKind::Dp => phi + self.loads.tip.beta,
            LoadKind::Ap => phi + self.loads.tip.beta - self.phi1 + FRAC_PI_2,
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
        let c = self.force_angle(phi);
        let (sc, cc) = c.sin_cos();
        let arm = l.s1 - s;
        let (sa, ca) = (phi + l.fluid.alpha).sin_cos();
        let (sp, cp) = phi.sin_cos();
        du[0] = m * inv_e4 + w.a * s + w.b;
        du[1] = l.tip.f * sc + l.fluid.q * arm * sa;
        du[2] = cp;
        du[3] = sp;
        if self.sens == Sensitivities::None {
            return;
        }
        // d m'/d phi
        let jm = l.tip.f * cc + l.fluid.q * arm * ca;
        let n = self.sens.count();
        for j in 0..n {
            let o = 4 * (j + 1);
            let (dphi, dm) = (u[o], u[o + 1]);
            let explicit = match j {
                // phi1 enters AP loads only: d/dphi1 f sin(c) = -f cos(c)
                0 => match l.tip.kind {
                    LoadKind::Dp => 0.0,
                    LoadKind::Ap => -l.tip.f * cc,
                },
                1 => sc,
                _ => l.fluid.q * sa,
            };
            du[o] = dm * inv_e4;
            du[o + 1] = jm * dphi + explicit;
            du[o + 2] = -sp * dphi;
            du[o + 3] = cp * dphi;
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
/// `dF/dphi' = -4 (theta - 1)/e`. For AP loads `sin(phi+beta)` becomes `cos(phi+beta-phi1)`
/// with the tip angle `phi1` held fixed (an outer iteration makes it consistent).
#[derive(Clone, Copy, Debug)]
pub struct WhiskerFdmProblem {
    ode: WhiskerOde,
}

impl WhiskerFdmProblem {
    /// The FDM problem; `phi1` is the (current estimate of the) tip angle for AP loads.
    pub fn new(whisker: Whisker, loads: Loads, phi1: f64) -> Self {
        WhiskerFdmProblem {
            ode: WhiskerOde::new(whisker, loads, phi1, Sensitivities::None),
        }
    }
}

impl SecondOrderBvp for WhiskerFdmProblem {
    #[inline]
    fn f(&self, s: f64, phi: f64, dphi: f64) -> f64 {
        let w = &self.ode.whisker;
        let l = &self.ode.loads;
        let e = w.diameter(s);
        let e2 = e * e;
        let load = l.tip.f * self.ode.force_angle(phi).sin()
            + l.fluid.q * (l.s1 - s) * (phi + l.fluid.alpha).sin();
        load / (e2 * e2) - 4.0 * (w.theta - 1.0) / e * (dphi - w.kappa0(s)) + w.a
    }

    #[inline]
    fn f_y(&self, s: f64, phi: f64, _dphi: f64) -> f64 {
        let w = &self.ode.whisker;
        let l = &self.ode.loads;
        let e = w.diameter(s);
        let e2 = e * e;
        (l.tip.f * self.ode.force_angle(phi).cos()
            + l.fluid.q * (l.s1 - s) * (phi + l.fluid.alpha).cos())
            / (e2 * e2)
    }

    #[inline]
    fn f_yp(&self, s: f64, _phi: f64, _dphi: f64) -> f64 {
        let w = &self.ode.whisker;
        -4.0 * (w.theta - 1.0) / w.diameter(s)
    }
}
