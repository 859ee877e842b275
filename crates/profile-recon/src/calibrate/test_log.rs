//! An exact calibration log and its problem for the unit tests of the calibration's
//! numerical pieces: a tapered whisker swept past the contour g1 under a flow.

use super::problem::CalibProblem;
use super::residual::{Model, RowKind};
use super::{CalibLog, CalibParam};
use crate::common::{KnownFlow, NoiseScales};
use crate::observables::from_sweep;
use beam_model::{FluidLoad, Whisker};
use bvp_solvers::integrator::Dop853;
use contact_sim::{sweep, Phase, Profile, SweepSettings};

/// The truth and its exact log.
pub(crate) struct Exact {
    pub truth: Whisker,
    pub flow: FluidLoad,
    pub log: CalibLog,
    /// The row kinds of the truth (the sweep's phases; `s1` of phase B).
    pub kinds: Vec<RowKind>,
}

/// The whisker `(0.5, 0.4, -0.3, k = 20)` swept past g1 under `q = 2`, `alpha = 0.2`: `pre`
/// rows before contact, `points` contact rows; the flow unknown to the log.
pub(crate) fn exact(pre: usize, points: usize) -> Exact {
    let truth = Whisker::new(0.5, 0.4, -0.3, 20.0);
    let flow = FluidLoad { q: 2.0, alpha: 0.2 };
    let settings = SweepSettings {
        points,
        pre_contact_rows: pre,
        ..SweepSettings::default()
    };
    let res = sweep(&truth, flow, &Profile::g1(), &settings).expect("the sweep of the test log");
    let kinds = res
        .points
        .iter()
        .map(|p| match p.phase {
            Phase::None => RowKind::Pre,
            Phase::A => RowKind::A,
            Phase::B => RowKind::B { s1: p.s1 },
        })
        .collect();
    Exact {
        truth,
        flow,
        log: CalibLog {
            rows: from_sweep(&res),
            profile: Profile::g1(),
            flow: KnownFlow::default(),
            poses: Vec::new(),
        },
        kinds,
    }
}

/// The problem of `logs` fitting `free` (and every log's flow) from `start`, every row used,
/// no whiteners yet.
pub(crate) fn problem<'a>(
    logs: &'a [CalibLog],
    free: Vec<CalibParam>,
    start: &Whisker,
) -> CalibProblem<'a> {
    CalibProblem {
        laws: super::problem::start_laws(logs, &free),
        logs,
        free,
        base: Model::of(start),
        fixed_flow: vec![None; logs.len()],
        used: logs.iter().map(|l| (0..l.rows.len()).collect()).collect(),
        whiteners: Vec::new(),
        shifts: Vec::new(),
        scales: logs.iter().map(|l| NoiseScales::of(&l.rows)).collect(),
        integrator: Dop853 {
            h_init: Some(0.05),
            ..Dop853::new(1e-12, 1e-12)
        },
        log_noise: 0.0,
        projection: 0,
        progress: super::problem::Reporter::new(None),
    }
}
