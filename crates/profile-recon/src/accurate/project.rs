//! The projection of a noisy row onto the observables consistent with one of its
//! hypotheses: the most likely true observables, by Gauss-Newton steps of a constrained
//! least-squares problem in the noise metric ([`project`]).

use super::context::{RowCtx, PROJECT_MIN};
use super::evaluate::evaluate;
use super::hypotheses::Hypothesis;
use crate::error::Result;
use crate::observables::ObservableRow;

/// Gauss-Newton steps of [`project`] at most.
const PROJECT_STEPS: usize = 4;

/// One Gauss-Newton step of `min (obs - meas)^T W^-1 (obs - meas)` subject to the linearised
/// condition `r + dr . (obs' - obs) = 0` at `obs` (`r`, `dr` of the hypothesis there):
/// `obs' = meas - W dr (r + dr . (meas - obs)) / (dr W dr)`, `W = diag(w)`. `None` where the
/// condition does not depend on the observables (`dr W dr` zero or NaN).
fn constrained_step(
    meas: &[f64; 4],
    obs: &[f64; 4],
    w: &[f64],
    (r, dr): (f64, &[f64; 4]),
) -> Option<[f64; 4]> {
    let sdr: f64 = (0..4).map(|j| w[j] * dr[j] * dr[j]).sum();
    if sdr.is_nan() || sdr <= 0.0 {
        return None;
    }
    let num = r + (0..4).map(|j| dr[j] * (meas[j] - obs[j])).sum::<f64>();
    let mut next = [0.0; 4];
    for (j, n) in next.iter_mut().enumerate() {
        *n = meas[j] - w[j] * dr[j] * num / sdr;
    }
    Some(next)
}

/// The most likely true observables of a noisy row under hypothesis `h`: the nearest (in the
/// noise metric of `ctx.scales`) to the measured ones on which the consistency condition
/// `r = 0` holds, by Gauss-Newton steps of the constrained least-squares problem (each a new
/// integration from the base at the moved observables, [`evaluate`]):
/// `obs' = meas - W dr (r + dr . (meas - obs)) / (dr W dr)` with `W = diag(scales^2)`.
/// Returns `h` with the point, `s1`, `f`, `psi` and the error estimate of the projected
/// observables (the consistency residual and `z` stay the measured row's), or `None` if the
/// hypothesis is lost on the way (then the linear projection stands).
pub(crate) fn project(
    ctx: &RowCtx<'_>,
    row: &ObservableRow,
    h0: &Hypothesis,
) -> Result<(Option<Hypothesis>, usize)> {
    let meas = [row.ax, row.ay, row.ma, row.phi0];
    let mut evals = 0;
    let mut obs = meas;
    let mut h = *h0;
    let w: Vec<f64> = (0..4).map(|j| ctx.scales.0[j] * ctx.scales.0[j]).collect();
    for _ in 0..PROJECT_STEPS {
        let Some(next) = constrained_step(&meas, &obs, &w, (h.r, &h.dr)) else {
            return Ok((None, evals));
        };
        let trial = ObservableRow {
            ax: next[0],
            ay: next[1],
            ma: next[2],
            phi0: next[3],
            ..*row
        };
        let e = evaluate(ctx, &trial)?;
        evals += e.evaluations;
        // (a projected hypothesis is a simple root or phase A, like `h`)
        let Some(hn) = h.nearest_in(&e.hyps) else {
            return Ok((None, evals));
        };
        let moved = (hn.x - h.x).hypot(hn.y - h.y);
        obs = next;
        h = *hn;
        if moved <= 1e-3 * h.shift.max(PROJECT_MIN) {
            break;
        }
    }
    Ok((
        Some(Hypothesis {
            residual: h0.residual,
            z: h0.z,
            r: h0.r,
            dr: h0.dr,
            shift: h0.shift,
            ..h
        }),
        evals,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear condition `r(obs) = r0 + g . (obs - meas)`.
    fn linear(r0: f64, g: &[f64; 4], meas: &[f64; 4], obs: &[f64; 4]) -> f64 {
        r0 + (0..4).map(|j| g[j] * (obs[j] - meas[j])).sum::<f64>()
    }

    #[test]
    fn one_step_solves_a_linear_condition_at_least_cost() {
        let meas = [0.3, -1.2, 0.05, 1.4];
        let g = [2.0, -0.5, 4.0, 1.0];
        let w = [0.25, 1.0, 0.01, 4.0];
        let next = constrained_step(&meas, &meas, &w, (0.2, &g)).unwrap();
        // on the constraint
        assert!(linear(0.2, &g, &meas, &next).abs() < 1e-15);
        // least cost (Lagrange): W^-1 (next - meas) is parallel to the gradient
        let lambda = (next[0] - meas[0]) / (w[0] * g[0]);
        for j in 0..4 {
            assert!(((next[j] - meas[j]) / w[j] - lambda * g[j]).abs() < 1e-15);
        }
        // closed form lambda = -r0 / (g W g)
        let gwg: f64 = (0..4).map(|j| w[j] * g[j] * g[j]).sum();
        assert!((lambda + 0.2 / gwg).abs() < 1e-15);
        // a fixed point: the step from the solution, with r = 0 there, stays
        let again = constrained_step(&meas, &next, &w, (0.0, &g)).unwrap();
        for j in 0..4 {
            assert!((again[j] - next[j]).abs() < 1e-15);
        }
    }

    #[test]
    fn a_condition_blind_to_the_observables_has_no_step() {
        let meas = [1.0; 4];
        // the gradient only where the scale is zero
        let w = [0.0, 1.0, 1.0, 1.0];
        assert!(constrained_step(&meas, &meas, &w, (0.1, &[1.0, 0.0, 0.0, 0.0])).is_none());
        assert!(constrained_step(&meas, &meas, &w, (0.1, &[f64::NAN; 4])).is_none());
    }
}
