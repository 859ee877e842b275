//! The one error type of the crate.

use beam_model::ModelError;
use bvp_solvers::BvpError;
use contact_sim::Phase;
use thiserror::Error;

/// Everything that can go wrong in identification and reconstruction.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ReconError {
    /// The whisker model rejected a parameter or failed to solve.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An underlying BVP routine failed.
    #[error(transparent)]
    Bvp(#[from] BvpError),
    /// Too few observable rows to work with.
    #[error("too few observable rows: {found} given, at least {needed} needed ({what})")]
    TooFewRows {
        /// Rows given.
        found: usize,
        /// Rows needed.
        needed: usize,
        /// For what.
        what: &'static str,
    },
    /// A value of the log is not finite.
    #[error("row {row}: {column} is not a finite number ({value})")]
    NonFinite {
        /// 0-based index of the row (the crate's row convention).
        row: usize,
        /// The column name.
        column: &'static str,
        /// The value.
        value: f64,
    },
    /// No row is the free whisker under a flow: the fluid load cannot be identified [6.1].
    #[error("none of the {rows} rows is the free whisker under a flow (no pre-contact row): the fluid load cannot be identified (give q and alpha explicitly)")]
    NoPreContactRows {
        /// Rows in the log.
        rows: usize,
    },
    /// No contact row in the log.
    #[error("the log has no contact rows (all {rows} rows show the flow alone)")]
    NoContactRows {
        /// Rows in the log.
        rows: usize,
    },
    /// A contact row admits no consistent contact point.
    #[error("row {row} (x0 = {x0}): no consistent contact point (best residual {residual:.3e} with phase {phase})")]
    InconsistentRow {
        /// 0-based index of the row (the crate's row convention).
        row: usize,
        /// Its base position.
        x0: f64,
        /// The best residual found.
        residual: f64,
        /// The phase hypothesis that came closest.
        phase: Phase,
    },
    /// A point's error estimate exceeds the accuracy asked for
    /// ([`reconstruct_to`](crate::reconstruct_to)).
    #[error("row {row} (x0 = {x0}): error estimate {estimate:.3e} of the contact point exceeds the accuracy asked for, {tol:e} (the best reached there)")]
    AccuracyNotMet {
        /// 0-based index of the row (the crate's row convention).
        row: usize,
        /// Its base position.
        x0: f64,
        /// The point's error estimate.
        estimate: f64,
        /// The accuracy asked for.
        tol: f64,
    },
    /// A parameter is out of range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is admissible.
        reason: &'static str,
    },
    /// A calibration asked for the same parameter twice, or for none.
    #[error("calibration: {reason} (asked for {requested} parameter(s))")]
    CalibrationRequest {
        /// What is wrong with the request.
        reason: &'static str,
        /// Parameters asked for.
        requested: usize,
    },
    /// The start whisker admits no solution for a row of a calibration log.
    #[error("calibration log {log}, row {row} (x0 = {x0}): the start whisker admits no solution for this row (its integration from the base stops short); start closer to the truth")]
    CalibrationStart {
        /// 0-based index of the log.
        log: usize,
        /// 0-based index of the row (the crate's row convention).
        row: usize,
        /// Its base position.
        x0: f64,
    },
    /// Too few residuals for the parameters of a calibration.
    #[error("calibration: {residuals} residuals from {rows} usable rows cannot determine {parameters} parameters (whisker and flows)")]
    CalibrationUnderdetermined {
        /// Residuals available.
        residuals: usize,
        /// Rows in use.
        rows: usize,
        /// Parameters to fit.
        parameters: usize,
    },
    /// No contact row of any calibration log is in the fit: what the contact with the known
    /// contour determines (theta, A, B, E I [3.5, 3.8, 3.16]) and the distance to it are
    /// not determined by the logs.
    #[error("calibration: {reason}: {fitted} of {contact} contact row(s) of {rows} row(s) in {logs} log(s) could be fitted; theta, a, b and ei need rows in contact with the known contour")]
    CalibrationNoContact {
        /// Why no contact row is in the fit.
        reason: &'static str,
        /// Logs.
        logs: usize,
        /// Rows of all logs.
        rows: usize,
        /// Rows that are not the free whisker (contact rows by the data).
        contact: usize,
        /// Contact rows in the fit.
        fitted: usize,
    },
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, ReconError>;
