//! The whisker as a first-order two-point problem, solved by the collocation method
//! ([`super::collocation`], at each load scale of its continuation) and by multiple
//! shooting ([`super::global`], at the scene's loads) alike.

use crate::equations::{state_rate, MomentLaw};
use crate::loads::{LoadKind, Loads};
use crate::scene::Scene;
use bvp_solvers::collocation::BvpProblem;
use std::f64::consts::FRAC_PI_2;

/// The whisker at load scale `lambda` as a first-order two-point problem on `[0, s1]`
/// (`collocation`'s and `multiple-shooting`'s module docs): the state `u = (phi, m, x, y)`
/// (`phi' = m / e^4 + A s + B`, [`state_rate`]), with the tip angle `phi1` as
/// the parameter `p[0]` of an AP force; the boundary conditions the base law
/// (`Support::residual`), `x(0) = y(0) = 0`, `m(s1) = 0`, and for AP `p[0] = phi(s1)`.
pub(super) struct WhiskerProblem<'a> {
    scene: &'a Scene,
    loads: Loads,
    law: MomentLaw,
    /// An AP force (the tip angle a parameter).
    pub(super) ap: bool,
}

impl<'a> WhiskerProblem<'a> {
    /// The problem at load scale `lambda` (1: the scene's loads).
    pub(super) fn new(scene: &'a Scene, lambda: f64) -> Self {
        let loads = scene.loads.scaled(lambda);
        WhiskerProblem {
            scene,
            loads,
            law: MomentLaw::new(&loads, FRAC_PI_2),
            ap: scene.loads.tip.kind == LoadKind::Ap && scene.loads.tip.f != 0.0,
        }
    }

    /// The law at the tip angle `p[0]` (AP) or the fixed one (DP).
    fn law(&self, p: &[f64]) -> MomentLaw {
        match self.ap {
            true => self.law.at_tip_angle(&self.loads, p[0]),
            false => self.law,
        }
    }

    /// The number of parameters: 1 for an AP force, else 0.
    pub(super) fn k(&self) -> usize {
        usize::from(self.ap)
    }
}

impl BvpProblem for WhiskerProblem<'_> {
    fn rhs(&self, s: f64, u: &[f64], p: &[f64], du: &mut [f64]) {
        let w = &self.scene.whisker;
        let e2 = w.diameter(s).powi(2);
        let (sp, cp) = crate::trig::sin_cos(u[0]);
        let dm = self.law(p).dm(s, sp, cp);
        state_rate(w, s, u[1], 1.0 / (e2 * e2), (sp, cp), dm, du);
    }

    fn bc(&self, ua: &[f64], ub: &[f64], p: &[f64], r: &mut [f64]) {
        r[0] = self.scene.whisker.support.residual(ua[0], ua[1]);
        r[1] = ua[2];
        r[2] = ua[3];
        r[3] = ub[1];
        if self.ap {
            r[4] = p[0] - ub[0];
        }
    }

    fn rhs_jacobian(&self, s: f64, u: &[f64], p: &[f64], j: &mut [f64], jp: &mut [f64]) -> bool {
        let w = &self.scene.whisker;
        let e2 = w.diameter(s).powi(2);
        let (sp, cp) = crate::trig::sin_cos(u[0]);
        let rate = self.law(p).at(s, sp, cp);
        j.fill(0.0);
        j[1] = 1.0 / (e2 * e2);
        j[4] = rate.dm_dphi;
        j[8] = -sp;
        j[12] = cp;
        if self.ap {
            // d/dphi1 f sin(phi + beta - phi1 + pi/2) = -f cos(phi + c)
            jp.fill(0.0);
            jp[1] = -self.loads.tip.f * rate.force.1;
        }
        true
    }

    fn bc_jacobian(
        &self,
        _ua: &[f64],
        _ub: &[f64],
        _p: &[f64],
        dya: &mut [f64],
        dyb: &mut [f64],
        dp: &mut [f64],
    ) -> bool {
        let support = &self.scene.whisker.support;
        dya.fill(0.0);
        dyb.fill(0.0);
        dp.fill(0.0);
        dya[0] = support.residual_rate(1.0, 0.0);
        dya[1] = support.residual_rate(0.0, 1.0);
        dya[4 + 2] = 1.0;
        dya[2 * 4 + 3] = 1.0;
        dyb[3 * 4 + 1] = 1.0;
        if self.ap {
            dyb[4 * 4] = -1.0;
            dp[4] = 1.0;
        }
        true
    }
}
