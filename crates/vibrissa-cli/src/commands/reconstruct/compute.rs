//! The compute step of `vibrissa reconstruct`: the log's rows handed to the library
//! (identification of the flow, then every contact row on its own) and its errors mapped to
//! their culprits (a line of the log, a flag, a model parameter, the solver).

use profile_recon::{reconstruct_to, reconstruct_with, ObservableRow, ReconError, Reconstruction};

use super::options::ReconOptions;
use crate::cli::ReconstructArgs;
use crate::csvio::Table;
use crate::error::CliError;
use crate::resolve::Resolved;

/// Identifies the flow (unless given) and reconstructs every contact row of the log
/// `table` (columns [`REQUIRED_COLUMNS`](super::REQUIRED_COLUMNS), already in the model's dimensionless variables)
/// with the whisker of `r`; a failure names its culprit (a line of the log, a flag, the
/// solver).
pub fn reconstruct_log(
    args: &ReconstructArgs,
    opts: &ReconOptions,
    r: &Resolved,
    table: &Table,
) -> Result<Reconstruction, CliError> {
    let rows = rows_of(table)?;
    let (whisker, known, settings) = (&r.scene.whisker, opts.known_flow(args, r), opts.settings());
    match opts.accuracy {
        Some(t) => reconstruct_to(whisker, &rows, known, &settings, t),
        None => reconstruct_with(whisker, &rows, known, &settings),
    }
    .map_err(|e| recon_culprit(e, table, r, args, opts.tol))
}
/// The observable rows of a table read with [`REQUIRED_COLUMNS`](super::REQUIRED_COLUMNS).
pub fn rows_of(table: &Table) -> Result<Vec<ObservableRow>, CliError> {
    let col = |name: &str| {
        table.column(name).ok_or_else(|| CliError::Csv {
            path: table.path.clone(),
            line: 1,
            column: Some(name.to_string()),
            reason: "missing required column".to_string(),
        })
    };
    let (x0, ax, ay, ma, phi0) = (col("x0")?, col("Ax")?, col("Ay")?, col("MA")?, col("phi0")?);
    Ok((0..table.rows())
        .map(|i| ObservableRow {
            x0: x0[i],
            ax: ax[i],
            ay: ay[i],
            ma: ma[i],
            phi0: phi0[i],
        })
        .collect())
}

/// Maps a reconstruction error to its culprit: a line of the log, a flag, a model
/// parameter, or the solver.
fn recon_culprit(
    err: ReconError,
    table: &Table,
    r: &Resolved,
    args: &ReconstructArgs,
    tol: Option<f64>,
) -> CliError {
    let first_line = table.line_of(0).unwrap_or(1);
    let last_line = table
        .rows()
        .checked_sub(1)
        .and_then(|i| table.line_of(i))
        .unwrap_or(1);
    let at = |line: usize, column: Option<&str>, reason: String| CliError::Csv {
        path: table.path.clone(),
        line,
        column: column.map(str::to_string),
        reason,
    };
    // `row` of the library's errors is the 0-based index of the data row.
    let line_of = |row: usize| table.line_of(row).unwrap_or(first_line);
    match err {
        ReconError::NonFinite { row, column, value } => at(
            line_of(row),
            Some(column),
            format!("value `{value}` is not finite"),
        ),
        ReconError::InconsistentRow {
            row,
            x0,
            residual,
            phase,
        } => at(
            line_of(row),
            None,
            format!(
                "x0 = {x0}: no consistent contact point (best residual {residual:.3e} \
                 with phase {phase}, tolerance {}); check the whisker parameters, or pass \
                 --tolerance none for a noisy log",
                tol.map_or("none".to_string(), |t| format!("{t:e}"))
            ),
        ),
        ReconError::AccuracyNotMet {
            row,
            x0,
            estimate,
            tol,
        } => CliError::Solver {
            reason: format!(
                "{}:{}: x0 = {x0}: the contact point's error estimate {estimate:.3e} exceeds \
                 --tol {tol:e} (the best reached there)",
                table.path.display(),
                line_of(row)
            ),
            source: Some(Box::new(err)),
        },
        ReconError::TooFewRows { .. } => at(last_line, None, err.to_string()),
        ReconError::NoPreContactRows { .. } => at(
            first_line,
            None,
            "no row is the free whisker under a flow (no pre-contact row): the fluid load \
             cannot be identified; give it with --q and --alpha-deg (or check the whisker)"
                .to_string(),
        ),
        ReconError::NoContactRows { .. } => at(last_line, None, err.to_string()),
        ReconError::InvalidParameter {
            name: "q",
            value,
            reason,
        } => match &args.q {
            Some(raw) => CliError::invalid_argument("--q", raw.clone(), reason),
            None => at(
                first_line,
                Some("Ax"),
                format!("identified fluid load q = {value}: {reason}"),
            ),
        },
        ReconError::InvalidParameter {
            name: "alpha",
            reason,
            ..
        } => CliError::invalid_argument(
            "--alpha-deg",
            args.alpha_deg.clone().unwrap_or_default(),
            reason,
        ),
        ReconError::InvalidParameter {
            name: "noise",
            reason,
            ..
        } => CliError::invalid_argument("--noise", args.noise.clone().unwrap_or_default(), reason),
        ReconError::Model(e) => r.culprit(&e).into(),
        other => CliError::solver(other),
    }
}
