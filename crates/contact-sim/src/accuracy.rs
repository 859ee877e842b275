//! Accuracy on demand for a sweep (`SweepSettings::accuracy`): the contact rows solved at
//! tolerances derived from the accuracy asked for, and each row's a-posteriori error
//! estimate.
//!
//! The traced branch (first contact, nodes, events, separation) stays at the sweep's own
//! tolerances whatever the accuracy asked for: it fixes the rows' base positions, which are
//! then the default sweep's (to the rows' accuracy). The rows are what a looser accuracy
//! makes cheaper: callgrind on `sweep --profile g1 --q 5 --points 200 --figures none`
//! counts 57.2 M instructions, the trace 15.4 M of them whatever T; 56.2 M with `--tol 1e-6`
//! and 48.8 M with `--tol 1e-4` (the rows' estimates included). A contact row at base position `x0` is solved with the integrator at
//! [`row_integration_tol`] and the corrector at [`row_solve_tol`]. Where a row's estimate
//! exceeds the accuracy asked for, the rows are solved once more at the tolerances of an
//! accuracy [`TIGHTER`](crate::sweep::TIGHTER) times smaller (their estimates' integration
//! too), and only then is the sweep refused, naming that row.
//!
//! **The estimate of a row.** Its equations are evaluated again at an integration
//! [`ESTIMATE_FACTOR`] times looser, from the row's converged state: one shot there, one
//! Newton step with the row's Jacobian to the looser integration's root (at the row's base
//! position; at its contour point for a node of the traced branch, where `x0` may turn), one
//! shot at that root. The estimate is twice the largest difference of the row's observables
//! `x0, Ax, Ay, MA, phi0` and contact point `xc, yc` between the two: the looser solution's
//! error is about ten times the row's (the integrator's error is proportional to its
//! tolerance), so the estimate bounds the row's error about twenty times over. The rows
//! before contact are the free whisker, the first contact row's shape (`f = 0`): they carry
//! its estimate.
//!
//! The frictionless sweeps along every motion (`translate`/`rotate` in `crate::sweep`,
//! `path` in [`crate::path`]) solve their rows through the one `rows_within_accuracy`
//! (the rows, the tighter pass where needed, the phase check) and report them through
//! `rows_accuracy`.

use crate::branch::{Branch, Node};
use crate::error::Result;
use crate::phase::ContactState;
use beam_model::shot::Integration;
use beam_model::AccuracyReport;
use bvp_solvers::dense;

/// Smallest accuracy a sweep can be asked for.
pub const ACCURACY_MIN: f64 = 1e-12;

/// Largest accuracy a sweep can be asked for.
pub const ACCURACY_MAX: f64 = 1e-2;

/// How much looser than a row's the integration of its estimate is.
pub const ESTIMATE_FACTOR: f64 = 100.0;

/// The estimate over the difference of the row and its looser solution.
pub const ESTIMATE_MARGIN: f64 = 2.0;

/// How much tighter than the accuracy asked for the rows' integration is.
pub const ROW_FACTOR: f64 = 1e4;

/// The integrator tolerance of the contact rows for the accuracy `tol`: `tol / 1e4`, at
/// least 1e-14 (measured on seeded scenes: a row's error is up to ~15 times its integrator
/// tolerance, and its estimate, from an integration 100 times looser, must stay below `tol`).
pub fn row_integration_tol(tol: f64) -> f64 {
    (tol / ROW_FACTOR).max(1e-14)
}

/// The corrector's residual tolerance of the contact rows for the accuracy `tol`: `tol / 1e4`
/// within [1e-12, 1e-10] (a looser residual left errors of 10-100 times it in the rows;
/// from the rows' predictions Newton reaches it in a step more at most).
pub fn row_solve_tol(tol: f64) -> f64 {
    (tol / ROW_FACTOR).clamp(1e-12, 1e-10)
}

/// The accuracy of a sweep run with `SweepSettings::accuracy`: the workspace's one report
/// ([`AccuracyReport`]), its `integration_tol` the contact rows' ([`row_integration_tol`]),
/// one estimate per row of `SweepResult::points` (the rows before contact carry the first
/// contact row's, module docs). The name the report had before it was shared with
/// `profile_recon`.
pub type SweepAccuracy = AccuracyReport;

/// How a row's estimate holds its row in place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Hold {
    /// At its base position (a row solved there).
    BasePosition(f64),
    /// At its contour point (a node of the traced branch).
    ContourPoint,
    /// At zero contact force (the release, solved there): its own defining condition. Held
    /// at its contour point instead, the release's estimate came out up to ~1e7 times its
    /// error (3.8e-5 against a row 1e-12 from a sweep at 1e-14: seeded random `--tol`
    /// sweeps, g1, theta 0.47 under q = 5.2 at -45 degrees).
    NoForce,
}

/// The estimate's branch equations: those of the rows at an integration
/// [`ESTIMATE_FACTOR`] times looser.
pub(crate) struct Estimator<'a> {
    /// The branch equations at the looser integration.
    pub loose: Branch<'a>,
    /// The looser integration's tolerance: the smallest estimate (a row's error was
    /// measured at most ~15 times its own integration's tolerance, a hundredth of this).
    pub floor: f64,
}

/// Contact rows, each with its error estimate (NaN without an accuracy asked for).
pub(crate) type Rows = Vec<(ContactState, f64)>;

/// The integrations of the contact rows at the accuracy `tol` ([`row_integration_tol`])
/// and of their estimates ([`ESTIMATE_FACTOR`] times looser).
pub(crate) struct RowIntegration {
    tol: f64,
    rows: Integration,
    loose: Integration,
}

impl RowIntegration {
    pub(crate) fn new(tol: f64) -> Self {
        RowIntegration {
            tol,
            rows: Integration::adaptive(row_integration_tol(tol)),
            loose: Integration::adaptive(row_integration_tol(tol) * ESTIMATE_FACTOR),
        }
    }
}

/// The branch equations the rows are solved with and their estimator: `base` at the
/// integration and corrector tolerances of the accuracy `at` ([`row_integration_tol`],
/// [`row_solve_tol`]); `base` itself, without estimates, where no accuracy is asked for.
pub(crate) fn row_branch<'a>(
    base: &Branch<'a>,
    at: Option<&'a RowIntegration>,
) -> (Branch<'a>, Option<Estimator<'a>>) {
    match at {
        Some(at) => (
            Branch {
                integration: &at.rows,
                tol: row_solve_tol(at.tol),
                ..*base
            },
            Some(Estimator {
                loose: Branch {
                    integration: &at.loose,
                    ..*base
                },
                floor: row_integration_tol(at.tol) * ESTIMATE_FACTOR,
            }),
        ),
        None => (*base, None),
    }
}

/// The error estimate of the row `node` (module docs) by `est`.
///
/// # Errors
/// The shots' errors.
pub(crate) fn estimate(est: &Estimator, node: &Node, hold: Hold) -> Result<f64> {
    let loose = &est.loose;
    let (r, at) = loose.eval_with(node.phase, node.u, false)?;
    let at = at.state;
    let j = &node.jac;
    let du = match hold {
        Hold::BasePosition(x0) => dense::solve(j, &[-r[0], -r[1], x0 - at.x0]),
        Hold::ContourPoint => {
            let m = [[j[0][0], j[0][1]], [j[1][0], j[1][1]]];
            dense::solve(&m, &[-r[0], -r[1]]).map(|d| [d[0], d[1], 0.0])
        }
        Hold::NoForce => {
            // u = (phi1 or s1, f, t): f stays at the row's (zero)
            let m = [[j[0][0], j[0][2]], [j[1][0], j[1][2]]];
            dense::solve(&m, &[-r[0], -r[1]]).map(|d| [d[0], 0.0, d[1]])
        }
    };
    let Some(du) = du else {
        return Ok(f64::INFINITY);
    };
    let u = [node.u[0] + du[0], node.u[1] + du[1], node.u[2] + du[2]];
    let moved = loose.eval_with(node.phase, u, false)?.1.state;
    Ok((ESTIMATE_MARGIN * difference(&node.state, &moved, loose)).max(est.floor))
}

/// The largest difference of the observables, base position and contact point of two states.
fn difference(a: &ContactState, b: &ContactState, branch: &Branch) -> f64 {
    let (oa, ob) = (a.observables(branch.flow), b.observables(branch.flow));
    [
        a.x0 - b.x0,
        oa.0 - ob.0,
        oa.1 - ob.1,
        oa.2 - ob.2,
        oa.3 - ob.3,
        a.point.xc - b.point.xc,
        a.point.yc - b.point.yc,
    ]
    .iter()
    .fold(
        0.0f64,
        |m, d| if d.is_nan() { f64::NAN } else { m.max(d.abs()) },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerances_follow_the_accuracy_asked_for() {
        assert!((row_integration_tol(1e-6) / 1e-10 - 1.0).abs() < 1e-12);
        assert_eq!(row_integration_tol(1e-12), 1e-14);
        assert_eq!(row_solve_tol(1e-12), 1e-12);
        assert_eq!(row_solve_tol(1e-2), 1e-10);
        let acc = SweepAccuracy {
            tol: 1e-6,
            integration_tol: 1e-8,
            estimates: vec![1e-9, 3e-8, 2e-8],
        };
        assert_eq!(acc.worst(), Some((1, 3e-8)));
    }
}
