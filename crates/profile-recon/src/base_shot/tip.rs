//! The tip look-alikes of a phase-A row: how far back from the tip a tangential (phase-B)
//! contact gives the same observables within the noise (read by
//! [`RowEval::tip_ambiguity`](super::RowEval::tip_ambiguity)).

use super::base_ode::BaseOde;
use super::base_run::BaseRun;
use super::context::{K_SIGMA, TIP_GRID};
use bvp_solvers::roots::bisect;

/// The first arc back from the tip checked for a look-alike.
const TIP_FIRST: f64 = 1e-5;
/// `(0.5 / 1e-5)^(1 / 15)`.
const TIP_RATIO: f64 = 2.057_143_874_950_285;

/// For the phase-A hypothesis: at `s = 1 - delta` on a grid of `delta`, the relative noise
/// level `max(|m(s)| / sd_m, |g(s)| / sd_g) / K_SIGMA` at which the phase-B conditions hold
/// there (`g = f sin(phi - psi) = -dm'/dphi`, [`BaseOde::rate`]; `sd_m`, `sd_g` the
/// standard deviations of `m(1)`, `g(1)` at unit noise; the cubic part of the interpolant is
/// accurate enough for a level).
pub(super) fn tip_levels(run: &BaseRun, ode: &BaseOde, sd_m: f64, sd_g: f64) -> Vec<(f64, f64)> {
    let mut out = vec![(0.0, f64::INFINITY); TIP_GRID];
    let mut u = [0.0; 4];
    let tiny = f64::MIN_POSITIVE;
    // the arcs walk back from the tip: each step found from the last one's
    let mut hint = usize::MAX;
    // (m, g) at 1 - d
    let mut at = |d: f64| -> Option<(f64, f64)> {
        let s = 1.0 - d;
        if !run.cubic_value_near(s, &mut hint, &mut u) {
            return None;
        }
        let (sp, cp) = ode.sin_cos(u[0]);
        Some((u[1], -ode.rate(s, sp, cp).dm_dphi))
    };
    let need = |m: f64, g: f64| (m.abs() / sd_m.max(tiny)).max(g.abs() / sd_g.max(tiny)) / K_SIGMA;
    let mut prev: Option<(f64, f64, f64)> = None;
    for (k, o) in out.iter_mut().enumerate() {
        let d = TIP_FIRST * TIP_RATIO.powi(k as i32);
        let Some((m, g)) = at(d) else {
            continue;
        };
        *o = (d, need(m, g));
        // g changes sign between grid points: the phase-B look-alike is where g = 0
        if let Some((d0, _, g0)) = prev {
            if g0 != 0.0 && g0.signum() != g.signum() {
                // 12 halvings on the sign of g, ended where g cannot be evaluated
                let c = bisect(|t| at(t).map(|v| v.1.signum() == g0.signum()), d0, d, 12);
                if let Some((mc, gc)) = at(c) {
                    let nc = need(mc, gc);
                    if nc < o.1 {
                        *o = (c.max(d), nc);
                    }
                }
            }
        }
        prev = Some((d, m, g));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_spans_1e_5_to_one_half() {
        let last = TIP_FIRST * TIP_RATIO.powi(TIP_GRID as i32 - 1);
        assert!((last - 0.5).abs() < 1e-13, "{last}");
    }
}
