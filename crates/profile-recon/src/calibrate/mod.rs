//! Calibration: the whisker's own parameters (taper theta [3.8], pre-curvature A, B [3.5],
//! follicle spring k [3.21, 3.22], and the base stiffness E I_b [3.16-3.19] in physical
//! units) from logs of sweeps past objects of known contour.
//!
//! | module | concept |
//! |---|---|
//! | [`residual`] | the four residuals of a row (follicle law, free whisker or contact on the known contour) and their whitening by the sensor noise |
//! | `problem` | the parameter vector over all logs and the stacked whitened residuals |
//! | `fit` | bounded Levenberg-Marquardt with a finite-difference Jacobian |
//! | [`ident`] | standard errors, correlation and the identifiability verdict from the singular values of the scaled Jacobian |
//! | [`design`](mod@design) | advice before any experiment: the standard errors each candidate object would give |
//! | `screen` | the global search: designed and seeded candidates ranked by a phase-free objective |
//! | `result` | the result: covariance, estimates, flows, rows, warnings |
//! | `run` | the calibration itself: start values, rounds of fit and phase decision, multi-start, result |
//! | `polish` | the final fit: polish tolerance, projection, passes without the rows it cannot use |
//! | `friction_check` | what the contact law of a fit with `mu` found; friction in a log calibrated without it |
//!
//! **The fit.** Least squares over all rows of all logs of the whitened residuals of
//! [`residual`] (to first order the maximum-likelihood fit of the measured observables), in
//! the parameters asked for and the flow `(q cos alpha, q sin alpha)` of every log whose flow
//! is not given (fitted jointly, started from the pre-contact rows [6.1]). Start values: k from
//! all rows' `MA`, `phi0` by the follicle law (linear least squares), the flow from the
//! pre-contact rows, the others from the start whisker. The phase of each contact row is
//! decided at the current parameters (the hypothesis, tip contact or a root of `m` whose
//! contact force pushes the whisker off the obstacle, with the smallest whitened residual)
//! and decided again after each fit until it stays. The rows in the fit are those the fit
//! can use at the current parameters (evaluable, not degenerate, not an outlier beyond 6
//! times the fit's noise level): a row left out at earlier parameters comes back. The
//! whiteners of a round are frozen at its start; the rounds go on until a round lowers the
//! cost by less than 1 % (a fit crawling in a compromise stops for a new phase decision),
//! each descending on the cost with the point's own whiteners (a round
//! that raised it is cut back). The pre-contact rows are the largest group of equal rows
//! that can be the free whisker (every other row's force then pushes,
//! `run::pre_contact`); contact forces within 10 noise deviations of zero are
//! left out. The final polish refits without the rows it cannot use at its end, outliers
//! included (beyond 6 times the logs' noise level, at most 10 % of the contact rows); it
//! projects each row of a noisy log onto the model
//! ([`CalibSettings::projection`] chord-Newton steps): the residual becomes the exact
//! whitened distance of the measured observables to those the model admits at that base
//! position (the output error), whose first-order form leaves a bias of the order of the
//! noise squared per row that does not average out (at noise 1e-3 it put the truth beyond
//! 3 standard errors in 7.5 % of the battery's (case, parameter) pairs; 3.8 % with it).
//!
//! **Local minima: a global strategy that does not depend on a lucky start** (issue 37). The
//! cost is not convex in theta, A, B (a contact row's phase, tip or tangential, and its
//! root of `m` switch with the parameters), so a local fit from one start lands in whatever
//! basin holds it; a researcher with a clean log must not depend on where he started. The
//! strategy follows the model's structure, then searches globally, then proves its answer:
//! 1. *Structure first.* What the model lets the data give directly is taken from them,
//!    not searched: the compliance `1/k` by linear least squares of the follicle law over
//!    every row (`phi0 - pi/2 = -MA / k` [3.21, 3.22]: exact on exact logs, whatever the
//!    shape), each log's flow from its free rows (`Ax = -q cos alpha`, `Ay = q sin alpha`
//!    [6.1]; a single free row is recognised, `run::pre_contact`).
//! 2. *Continuation in the data.* A long log is searched on an evenly spread subsample of
//!    400 rows (`run::LONG_LOG`), then extended to every row (below, "Long logs").
//! 3. *Multi-start over a designed set.* The candidates are a grid over the whole range of
//!    the shape parameters (theta in {0.25, 0.45, 0.7, 1}, A in {-1, 0, 1}, B in {-0.6, 0,
//!    0.6}: a slender, strongly pre-curved truth is near one of them, however far from the
//!    start) and [`CalibSettings::screen`] seeded candidates around the start (theta within
//!    a factor 2, A, B within 75 % + 0.5, E I within a factor 2). All are ranked by a
//!    phase-free objective on a subsample of the rows (each row with its best hypothesis, no
//!    phase decision to go wrong), and the local fits start from the best-ranked ones.
//! 4. *A proof of the result.* A fit is accepted when the noise level it implies
//!    ([`Calibration::noise_level`]) is within 3 times a model-free noise level of the logs
//!    (third differences along x0, [`Calibration::log_noise`]) and no row was lost: on an
//!    exact log that is a cost at the integrator's floor, which only the global minimum
//!    reaches (every row's four conditions hold); on a noisy one, residuals at the noise of
//!    the logs. Every free parameter's curvature is checked by the singular values of the
//!    scaled Jacobian ([`ident`]): a flat direction is reported as not identifiable, with
//!    the combination that is determined. Otherwise the next candidate is fitted (up to
//!    [`CalibSettings::starts`] local fits), the fit with the fewest lost rows and then the
//!    lowest cost wins (a row the fitted whisker cannot evaluate or explain at all is lost,
//!    a pre-contact row included), and a fit that still fails the check is reported in
//!    [`Calibration::warnings`] with what was tried, never passed silently.
//!
//! **Refusals and warnings** (issue 34). A calibration that asks for more than `k` needs
//! contact rows: logs whose rows are all the free whisker, or whose contact rows no whisker
//! on the known contours can fit (rows of two whiskers mixed, all rows at one base
//! position), are refused ([`ReconError::CalibrationNoContact`]), never answered with the
//! start values and the distance of no row. Two or three rows are never grouped as free
//! rows by a noise level they are too few to estimate. [`Calibration::warnings`] names a log
//! without free rows (its flow fitted from contact rows alone), a log none of whose rows is
//! in the fit as a contact row, a log with more than a tenth of its contact rows left out,
//! the parameters not determined, and a fit above the logs' noise.
//!
//! **Long logs.** The search (screening, local fits, phase decisions) runs on at most
//! 400 rows (`run::LONG_LOG`) per log (the free rows, at most 20, and the contact rows
//! evenly spread in x0); then every row's phase is decided at the search's parameters and
//! the polish fits all rows. [`calibrate_with_progress`] reports each stage and iteration
//! (the CLI draws a progress bar from it).
//!
//! **Logs of any base motion** (issue 38; docs/whisking-recon.md, "Calibration from whisking
//! logs"). A log whose rows carry a pose ([`CalibLog::poses`]: `y0`, `gamma`) is calibrated
//! in the lab frame, where the system integrated from the base is covariant: the follicle
//! law turned by each row's `gamma` (`phi0 - gamma = pi/2 - MA/k`), each contact point lifted
//! by its `y0` before its distance to the known contour (a peg: the offset from it, two
//! residuals, the force's direction free; a disc: `r - |p - c|`), one lab-frame flow per
//! log (a free row's base forces are the flow's at any turn [6.1], so the flow residuals
//! are unchanged). The rows are ordered along the motion coordinate instead of `x0`; the
//! pre-contact rows of a posed log are the largest group of rows with equal base forces
//! `(Ax, Ay)` at an end of the motion (their `MA`, `phi0` differ row by row: each is the free
//! whisker at its own turn, fitted by its own residuals).
//!
//! **Friction: `mu`** (issue 39; docs/friction-calib.md). With [`CalibParam::Mu`] fitted,
//! each contact row's force obeys a contact law ([`residual::ContactLaw`]) in place of the
//! frictionless `ft = 0`: rows whose touching material point slides along the known contour
//! (decided from the reconstructed points' motion after every phase decision,
//! `CalibProblem::decide_laws`) give `ft + sign(u) mu fn = 0`; sticking rows leave the force
//! anywhere in the cone (no residual on its direction; the contact point on the known contour,
//! the moment and the tangency need no mu). Without a sliding row mu's Jacobian column is zero:
//! not identifiable, with the sticking rows' lower bound in the warnings
//! ([`Calibration::friction`]). Without `mu`, a log whose rows prove friction at the
//! calibrated whisker is warned about (`friction_check`).
//!
//! **E I.** In a dimensionless log the force unit IS E I_b / L^2: `ei` is then 1 by
//! definition (the CLI refuses to fit it). The library fits `lambda = E I_b / E I_nominal`,
//! the factor by which the log's forces and moments (in units of a nominal stiffness)
//! exceed the model's; it is determined only by contact with a known contour (the force
//! needed for a known deflection), never by the free whisker alone.
//!
//! ```
//! use beam_model::{FluidLoad, Whisker};
//! use contact_sim::{sweep, Profile, SweepSettings};
//! use profile_recon::calibrate::{calibrate, CalibLog, CalibParam, CalibSettings};
//! use profile_recon::{from_sweep, KnownFlow};
//!
//! let truth = Whisker::new(0.6, 0.0, 0.3, 20.0);
//! let settings = SweepSettings { points: 30, ..Default::default() };
//! let flow = FluidLoad { q: 2.0, alpha: 0.0 };
//! let log = sweep(&truth, flow, &Profile::g2(), &settings).unwrap();
//! let logs = [CalibLog { rows: from_sweep(&log), profile: Profile::g2(), flow: KnownFlow::default(), poses: Vec::new() }];
//! let start = Whisker::new(0.8, 0.0, 0.2, 30.0);
//! let fit = CalibSettings { fit: vec![CalibParam::Theta, CalibParam::B, CalibParam::K], ..Default::default() };
//! let cal = calibrate(&start, &logs, &fit).unwrap();
//! let theta = cal.parameter(CalibParam::Theta).unwrap();
//! assert!((theta.value.unwrap() - 0.6).abs() < 1e-7);
//! ```

pub mod design;
mod fit;
mod friction_check;
pub mod ident;
mod polish;
mod problem;
pub mod residual;
mod result;
mod run;
mod screen;
#[cfg(test)]
mod test_log;
pub mod whiten;

pub use design::{design, DesignPrediction, DesignSettings};

use crate::common::KnownFlow;
#[cfg(doc)]
use crate::error::ReconError;
use crate::observables::ObservableRow;
use crate::pose::{motion_coordinate, RowPose};
use beam_model::Whisker;
use contact_sim::Profile;
use serde::{Deserialize, Serialize};

/// A parameter of the whisker that a calibration can fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum CalibParam {
    /// Conicity theta [3.8].
    Theta,
    /// Cesaro slope A [3.5].
    A,
    /// Cesaro offset B [3.5].
    B,
    /// Follicle spring k [3.21, 3.22] (fitted as the compliance `1/k`; 0 is rigid).
    K,
    /// Base stiffness E I_b relative to the log's force unit (`lambda`, module docs).
    Ei,
    /// Coulomb friction coefficient at the contact (spec/model.md, "Friction at the
    /// contact"; issue 39): fitted through the slip rows' contact law
    /// ([`residual::ContactLaw`]), not identifiable from a log without sliding rows.
    Mu,
}

impl CalibParam {
    /// Every parameter, in the order of the CLI.
    pub const ALL: [CalibParam; 6] = [
        CalibParam::Theta,
        CalibParam::A,
        CalibParam::B,
        CalibParam::K,
        CalibParam::Ei,
        CalibParam::Mu,
    ];

    /// The CLI name (`theta`, `a`, `b`, `k`, `ei`, `mu`).
    pub fn name(&self) -> &'static str {
        match self {
            CalibParam::Theta => "theta",
            CalibParam::A => "a",
            CalibParam::B => "b",
            CalibParam::K => "k",
            CalibParam::Ei => "ei",
            CalibParam::Mu => "mu",
        }
    }

    /// The parameter of a CLI name (case-insensitive).
    pub fn parse(name: &str) -> Option<Self> {
        let n = name.trim().to_ascii_lowercase();
        Self::ALL.into_iter().find(|p| p.name() == n)
    }
}

/// One log of a sweep past a known contour.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibLog {
    /// Its rows (any order; pre-contact rows are recognised as the largest group of equal
    /// rows).
    pub rows: Vec<ObservableRow>,
    /// The known contour.
    pub profile: Profile,
    /// The flow, if known: with both `q` and `alpha` given it is held fixed; otherwise the
    /// flow of the log is fitted (started from its pre-contact rows, or from a given `q`).
    pub flow: KnownFlow,
    /// The pose `(y0, gamma)` of each row's base (a turning or lifted base, issue 38; module
    /// docs, "Logs of any base motion"); empty: every row the translating sweep's.
    pub poses: Vec<RowPose>,
}

/// Why fitting `k` is refused when every row of every log has its own `k` (a path's `k`
/// column, issue 38: a known column, not a parameter of the whisker;
/// [`RowPose::support_or`]).
pub const K_IS_KNOWN: &str = "every row's k is given by its log (a path's k column): k is known, not fitted; leave it out of the parameters";

impl CalibLog {
    /// Whether some row has a pose other than the translating sweep's.
    pub fn is_posed(&self) -> bool {
        self.poses.iter().any(|p| !p.is_translate())
    }
}

/// A log of any base motion in the calibration's frame: a log whose rows carry a pose has
/// its `x0` replaced by the motion coordinate ([`motion_coordinate`]: a rotation's rows share
/// one `x0`, and every step that orders rows along the motion reads `x0`), the difference
/// kept per row as the shift of its points back to the lab (`x - c + x0`,
/// [`point_to_lab`](crate::pose::point_to_lab)); a translate log as it is (no shift).
fn framed(logs: &[CalibLog]) -> crate::error::Result<(Vec<CalibLog>, Vec<Vec<f64>>)> {
    let mut out = Vec::with_capacity(logs.len());
    let mut shifts = Vec::with_capacity(logs.len());
    for log in logs {
        if !log.is_posed() {
            out.push(log.clone());
            shifts.push(Vec::new());
            continue;
        }
        crate::pose::check_poses(&log.rows, &log.poses)?;
        let c = motion_coordinate(&log.rows, &log.poses);
        let mut framed = log.clone();
        for (r, &ci) in framed.rows.iter_mut().zip(&c) {
            r.x0 = ci;
        }
        shifts.push(log.rows.iter().zip(&c).map(|(r, ci)| r.x0 - ci).collect());
        out.push(framed);
    }
    Ok((out, shifts))
}

/// Settings of a calibration.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibSettings {
    /// The parameters fitted (the others keep the start whisker's values).
    pub fit: Vec<CalibParam>,
    /// Integrator tolerance of the base integrations during the search.
    pub tol: f64,
    /// Integrator tolerance of the final polish (the fit's last digits).
    pub polish_tol: f64,
    /// Seeded candidate starts ranked by the screening objective (module docs).
    pub screen: usize,
    /// Local fits at most, from the best-ranked candidates (module docs), at least 1.
    pub starts: usize,
    /// Seed of the further starts.
    pub seed: u64,
    /// Levenberg-Marquardt iterations per round at most.
    pub max_iter: usize,
    /// Rounds of (fit, phase decision) at most.
    pub rounds: usize,
    /// Chord-Newton steps at most of the final polish that project each row onto the model
    /// (the exact output error instead of its first-order form; module docs; the steps stop
    /// once converged, [`whiten::PROJECTION_TOL`]), 0 for none; used when the logs' noise
    /// level squared exceeds the polish tolerance.
    pub projection: usize,
}

impl Default for CalibSettings {
    fn default() -> Self {
        CalibSettings {
            fit: vec![
                CalibParam::Theta,
                CalibParam::A,
                CalibParam::B,
                CalibParam::K,
            ],
            tol: 1e-10,
            polish_tol: 1e-12,
            screen: 96,
            starts: 4,
            seed: 19,
            max_iter: 60,
            rounds: 8,
            projection: 8,
        }
    }
}

/// The estimate of one parameter.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParamEstimate {
    /// The parameter.
    pub param: CalibParam,
    /// The estimate (`k`: the stiffness, infinite for a rigid fit; `ei`: the ratio
    /// `lambda`); `None` when not identifiable.
    pub value: Option<f64>,
    /// Its standard error (`k`: by the delta method from that of `1/k`); `None` when not
    /// identifiable.
    pub stderr: Option<f64>,
    /// Whether the logs determine it.
    pub identifiable: bool,
    /// The start value.
    pub start: f64,
}

/// A combination `sum c_i p_i` of unidentifiable parameters that the logs determine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Combination {
    /// The coefficients (largest 1) with their parameters (`k` enters as `1/k`, `ei` as
    /// `ln lambda`).
    pub terms: Vec<(CalibParam, f64)>,
    /// Its value.
    pub value: f64,
    /// Its standard error.
    pub stderr: f64,
}

impl Combination {
    /// As text, e.g. `1·a + 0.42·b = 0.713 ± 1.2e-5`.
    pub fn describe(&self) -> String {
        let terms: Vec<String> = self
            .terms
            .iter()
            .map(|(p, c)| {
                let name = match p {
                    CalibParam::K => "(1/k)",
                    CalibParam::Ei => "ln(ei)",
                    other => other.name(),
                };
                format!("{c:+.6}·{name}")
            })
            .collect();
        format!(
            "{} = {:.9} ± {:.2e}",
            terms.join(" "),
            self.value,
            self.stderr
        )
    }
}

/// The fitted flow of one log.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogFit {
    /// Fluid load q (model units of the fitted whisker).
    pub q: f64,
    /// Flow angle (rad).
    pub alpha: f64,
    /// Standard errors of q and alpha (0 when given).
    pub q_stderr: f64,
    /// Standard error of alpha (rad).
    pub alpha_stderr: f64,
    /// Whether the flow was given rather than fitted.
    pub given: bool,
    /// Rows of the log.
    pub rows: usize,
    /// Pre-contact rows.
    pub pre_contact: usize,
    /// Contact rows in the fit.
    pub contact: usize,
    /// Rows left out (force below [`residual::F_MIN_REL`] of the largest, or no hypothesis).
    pub skipped: usize,
}

/// The fit at one row.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RowFit {
    /// Index of the log.
    pub log: usize,
    /// 0-based row of the log (the crate's row convention).
    pub row: usize,
    /// `-` pre-contact, `A`, `B`, or `x` left out.
    pub kind: char,
    /// Contact arc length (1 for A, NaN otherwise).
    pub s1: f64,
    /// Reconstructed contact point with the fitted whisker (NaN for pre-contact rows).
    pub x: f64,
    /// Reconstructed contact point y.
    pub y: f64,
    /// Signed normal distance of that point to the known contour (positive inside).
    pub distance: f64,
    /// Its standard deviation at the fitted noise level.
    pub sigma: f64,
    /// Norm of the row's whitened residuals over the fitted noise level (~2 for a row that
    /// fits as well as the others).
    pub chi: f64,
}

/// The result of a calibration.
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    /// The calibrated whisker (unidentifiable parameters keep their start values).
    pub whisker: Whisker,
    /// The stiffness ratio `lambda` (1 unless `ei` was fitted).
    pub lambda: f64,
    /// One estimate per fitted parameter, in the order asked for.
    pub parameters: Vec<ParamEstimate>,
    /// Correlation matrix of the fitted parameters (NaN rows for unidentifiable ones).
    pub correlation: Vec<Vec<f64>>,
    /// The combinations of unidentifiable parameters that the logs determine.
    pub determined: Vec<Combination>,
    /// Relative singular values of the scaled Jacobian (whisker and flow parameters).
    pub singular_values: Vec<f64>,
    /// The flow of every log.
    pub logs: Vec<LogFit>,
    /// Every row of every log.
    pub rows: Vec<RowFit>,
    /// RMS of the contact rows' normal distances to their contours (model lengths).
    pub rms_distance: f64,
    /// Relative noise level the fit implies (RMS of the whitened residuals).
    pub noise_level: f64,
    /// Model-free relative noise level of the logs (third differences along x0; an upper
    /// reference on exact logs).
    pub log_noise: f64,
    /// Levenberg-Marquardt iterations (all rounds of the main fit).
    pub iterations: usize,
    /// Residual evaluations (all fits, the multi-start included).
    pub evaluations: usize,
    /// The final cost of every local fit made (module docs), in order.
    pub fits: Vec<f64>,
    /// What the checks found (another minimum, a residual above the noise, rows left out,
    /// friction in a log calibrated without `mu`).
    pub warnings: Vec<String>,
    /// The contact law of the fit when `mu` was fitted (issue 39), None otherwise.
    pub friction: Option<FrictionFit>,
}

/// What the contact rows of a calibration with `mu` say about friction (issue 39;
/// [`residual::ContactLaw`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionFit {
    /// Contact rows in the fit that slide: the rows whose law `|ft| = mu fn` determines mu.
    pub sliding_rows: usize,
    /// Contact rows in the fit that stick (or where sliding starts, stops or turns): their
    /// force is only bounded by the cone.
    pub stick_rows: usize,
    /// The largest `|ft| / fn` of the stick rows at the fit (NaN without one): a lower bound
    /// of mu (`|ft| <= mu fn`), the one thing a log without sliding rows says about it.
    pub stick_ratio: f64,
    /// Stick rows outside the fitted cone: `|ft| - mu fn` beyond 6 standard deviations of
    /// `ft`'s noise (0 when mu is not identifiable).
    pub cone_violations: usize,
}

impl Calibration {
    /// The estimate of `param`, if it was fitted.
    pub fn parameter(&self, param: CalibParam) -> Option<&ParamEstimate> {
        self.parameters.iter().find(|p| p.param == param)
    }
}

/// The stage of a calibration that a [`Progress`] report comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Ranking the designed and seeded candidate starts (module docs, "Local minima").
    Screen,
    /// A local fit from a candidate (`done` of `total` local fits at most).
    Search,
    /// The fit extended from the subsample to every row of a long log (module docs,
    /// "Long logs").
    AllRows,
    /// The final polish.
    Polish,
}

/// A progress report of [`calibrate_with_progress`]: the stage, how far it is (`done` of
/// `total` steps of that stage: candidates screened, local fits made, iterations) and the
/// current cost (half the sum of the squared whitened residuals; NaN before any fit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// The stage.
    pub stage: Stage,
    /// Steps of the stage done.
    pub done: usize,
    /// Steps of the stage at most.
    pub total: usize,
    /// Rows in use at this stage.
    pub rows: usize,
    /// Current cost.
    pub cost: f64,
}

/// A receiver of [`Progress`] reports (a progress bar); `&dyn Fn` so that a calibration
/// needs no mutable access to it.
pub type ProgressFn<'a> = &'a dyn Fn(&Progress);

/// Fits the whisker's parameters `settings.fit` to `logs`, starting from `start` (module
/// docs of [`calibrate`](self)).
///
/// # Errors
/// [`ReconError::TooFewRows`] without logs or rows, [`ReconError::NonFinite`] for a bad
/// value, [`ReconError::CalibrationRequest`] for an empty or repeated parameter list,
/// [`ReconError::Model`] for a start whisker out of range, [`ReconError::CalibrationStart`]
/// when the start whisker cannot evaluate a pre-contact row,
/// [`ReconError::CalibrationNoContact`] when no row of any log is in contact, or none of
/// them can be fitted (and a parameter other than `k` is asked for),
/// [`ReconError::CalibrationUnderdetermined`] with fewer residuals than parameters.
pub fn calibrate(
    start: &Whisker,
    logs: &[CalibLog],
    settings: &CalibSettings,
) -> crate::error::Result<Calibration> {
    calibrate_with_progress(start, logs, settings, &|_| {})
}

/// [`calibrate()`], reporting its progress to `progress` (at every candidate screened, every
/// Levenberg-Marquardt iteration and every stage; a long log takes a while).
///
/// # Errors
/// Those of [`calibrate()`].
pub fn calibrate_with_progress(
    start: &Whisker,
    logs: &[CalibLog],
    settings: &CalibSettings,
    progress: ProgressFn<'_>,
) -> crate::error::Result<Calibration> {
    let given = logs;
    let (logs, shifts) = framed(logs)?;
    // an error names a row by its own x0, not by the motion coordinate that replaced it
    let own_x0 = |e: crate::error::ReconError| match e {
        crate::error::ReconError::CalibrationStart { log, row, x0 } => {
            crate::error::ReconError::CalibrationStart {
                log,
                row,
                x0: given
                    .get(log)
                    .and_then(|l| l.rows.get(row))
                    .map_or(x0, |r| r.x0),
            }
        }
        other => other,
    };
    let (mut prob, mut fit, costs) =
        run::fit(start, &logs, shifts, settings, progress).map_err(own_x0)?;
    polish::polish(&mut prob, &mut fit, settings).map_err(own_x0)?;
    run::check_contact(&prob, &fit)?;
    result::summarize(&mut prob, &fit, &costs, start)
}
