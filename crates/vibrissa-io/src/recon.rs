//! A reconstruction's request and compute, without a command line [ch. 6]: the values
//! given over a scene file ([`ReconFlags`]: whisker, flow, noise, method, tolerances), each
//! checked against its flag ([`ReconOptions`]), the whisker resolved ([`recon_model`]), and
//! the log's rows handed to `profile_recon` ([`reconstruct_log`]) with every failure mapped
//! to its culprit (a line of the log, a flag, a model parameter, the solver).
//!
//! The command line (`vibrissa reconstruct`) and the Python package
//! (`vibrissa.reconstruct`, `vibrissa.Streamer`) both fill a [`ReconFlags`] and call these.

use profile_recon::{
    reconstruct_posed, reconstruct_posed_to, KnownFlow, ObservableRow, ReconError, ReconMethod,
    ReconSettings, Reconstruction, RowPose,
};

use crate::csvio::Table;
use crate::error::IoError;
use crate::resolve::{resolve_model, LoadedScene, ModelFlags, Resolved, Value, WhiskerFlags};

/// Default consistency tolerance of the accurate method (exact logs).
pub const DEFAULT_TOLERANCE_ACCURATE: f64 = 1e-6;

/// Default consistency tolerance of the thesis method (its least-squares residual stays at
/// about 1e-5..1e-4).
pub const DEFAULT_TOLERANCE_THESIS: f64 = 1e-3;

/// The values of a reconstruction given over a scene file (each named by its flag in
/// messages): the whisker, the flow if known, the noise level, the method and tolerances.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReconFlags {
    /// The whisker (`--theta`, `--a`, `--b`, `--k`) over the scene's.
    pub whisker: WhiskerFlags,
    /// `--q`: the fluid load, known (in the scene's units).
    pub q: Option<Value>,
    /// `--alpha-deg`: the flow angle, known (degrees, in (-90, 90)).
    pub alpha_deg: Option<Value>,
    /// `--noise`: the relative noise level of the log (>= 0).
    pub noise: Option<Value>,
    /// `--method`: `accurate` (default) or `thesis`.
    pub method: Option<String>,
    /// `--tolerance`: the consistency tolerance of a contact row (a positive number, or the
    /// word `none` for no check).
    pub tolerance: Option<Value>,
    /// `--tol`: the accuracy asked for of every point (method accurate), in [1e-12, 1e-2].
    pub tol: Option<Value>,
}

/// The options of a reconstruction, checked: method, consistency tolerance, flow angle,
/// noise level and the accuracy asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReconOptions {
    /// `--method`.
    pub method: ReconMethod,
    /// `--tolerance` (`None`: no consistency check).
    pub tol: Option<f64>,
    /// `--alpha-deg` in radians, if given.
    pub alpha: Option<f64>,
    /// `--noise`, if given.
    pub noise: Option<f64>,
    /// `--tol`, the accuracy asked for of every point, if given.
    pub accuracy: Option<f64>,
}

impl ReconOptions {
    /// Checks the values of `flags`, each refusal naming its flag and value as given.
    pub fn parse(flags: &ReconFlags) -> Result<Self, IoError> {
        let method = parse_method(flags.method.as_deref())?;
        Ok(ReconOptions {
            method,
            tol: parse_tolerance(flags.tolerance.as_ref(), method)?,
            alpha: parse_alpha(flags.alpha_deg.as_ref())?,
            noise: parse_noise(flags.noise.as_ref())?,
            accuracy: parse_accuracy(flags.tol.as_ref(), method)?,
        })
    }

    /// The options of a stream: as [`ReconOptions::parse`], the method `accurate` only (each
    /// row on its own) and no `--tol`.
    pub fn parse_stream(flags: &ReconFlags) -> Result<Self, IoError> {
        let opts = Self::parse(flags)?;
        if let Some(raw) = &flags.tol {
            return Err(IoError::invalid_argument(
                "--tol",
                raw.raw(),
                "the stream returns each point as soon as it is known, at the integrator \
                 tolerance 1e-12, without the second evaluation an estimate needs; leave \
                 --tol out with --stream",
            ));
        }
        if opts.method != ReconMethod::Accurate {
            return Err(IoError::invalid_argument(
                "--method",
                opts.method.name(),
                "the stream reconstructs each row on its own: method accurate only",
            ));
        }
        Ok(opts)
    }

    /// The library's settings of these options.
    pub fn settings(&self) -> ReconSettings {
        ReconSettings {
            method: self.method,
            consistency_tol: self.tol,
            noise: self.noise,
            ..ReconSettings::default()
        }
    }

    /// The flow as far as it is given: `--q` (resolved in the scene's units by `r`) and
    /// `--alpha-deg`.
    pub fn known_flow(&self, flags: &ReconFlags, r: &Resolved) -> KnownFlow {
        KnownFlow {
            q: flags.q.as_ref().map(|_| r.q()),
            alpha: self.alpha,
        }
    }
}

/// The whisker of a reconstruction (and `--q`, if given): the scene file under the values,
/// through the same resolution as `solve` so that physical units and range checks apply.
pub fn recon_model(flags: &ReconFlags, file: Option<LoadedScene>) -> Result<Resolved, IoError> {
    let mut model = ModelFlags {
        whisker: flags.whisker.clone(),
        ..ModelFlags::default()
    };
    model.fluid.q = flags.q.clone();
    resolve_model(&model, file)
}

/// Identifies the flow (unless given) and reconstructs every contact row of the log
/// `table` (columns [`REQUIRED_COLUMNS`](crate::recon_io::REQUIRED_COLUMNS), already in the
/// model's dimensionless variables) with the whisker of `r` [6.1-6.11]; a failure names its
/// culprit (a line of the log, a flag, the solver).
pub fn reconstruct_log(
    flags: &ReconFlags,
    opts: &ReconOptions,
    r: &Resolved,
    table: &Table,
) -> Result<Reconstruction, IoError> {
    let rows = rows_of(table)?;
    let poses = poses_of(table);
    let (whisker, known, settings) = (&r.scene.whisker, opts.known_flow(flags, r), opts.settings());
    match opts.accuracy {
        Some(t) => reconstruct_posed_to(whisker, &rows, &poses, known, &settings, t),
        None => reconstruct_posed(whisker, &rows, &poses, known, &settings),
    }
    .map_err(|e| recon_culprit(e, table, r, flags, opts.tol))
}

/// The observable rows of a table read with
/// [`REQUIRED_COLUMNS`](crate::recon_io::REQUIRED_COLUMNS).
pub fn rows_of(table: &Table) -> Result<Vec<ObservableRow>, IoError> {
    let col = |name: &str| {
        table.column(name).ok_or_else(|| IoError::Csv {
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

/// The base pose of every row of a log of any motion (spec/model.md, "Base motions"): the
/// columns `y0` and `gamma` (radians) where present, 0 where absent (a log without them is a
/// translation's; [`profile_recon::pose`]), and the path's follicle stiffness `k` (model
/// units, as [`to_model_units`](crate::recon_io::to_model_units) leaves it) where the log has it.
pub fn poses_of(table: &Table) -> Vec<RowPose> {
    let (y0, gamma) = (table.column("y0"), table.column("gamma"));
    let k = table.column(crate::observables::K_COLUMN);
    (0..table.rows())
        .map(|i| RowPose {
            y0: y0.map_or(0.0, |c| c[i]),
            gamma: gamma.map_or(0.0, |c| c[i]),
            k: k.map(|c| c[i]).filter(|v| !v.is_nan()),
        })
        .collect()
}

/// Maps a reconstruction error to its culprit: a line of the log, a flag, a model
/// parameter, or the solver.
pub(crate) fn recon_culprit(
    err: ReconError,
    table: &Table,
    r: &Resolved,
    flags: &ReconFlags,
    tol: Option<f64>,
) -> IoError {
    let first_line = table.line_of(0).unwrap_or(1);
    let last_line = table
        .rows()
        .checked_sub(1)
        .and_then(|i| table.line_of(i))
        .unwrap_or(1);
    let at = |line: usize, column: Option<&str>, reason: String| IoError::Csv {
        path: table.path.clone(),
        line,
        column: column.map(str::to_string),
        reason,
    };
    let raw = |v: &Option<Value>| v.as_ref().map(Value::raw).unwrap_or_default();
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
        } => IoError::Solver {
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
        } => match &flags.q {
            Some(v) => IoError::invalid_argument("--q", v.raw(), reason),
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
        } => IoError::invalid_argument("--alpha-deg", raw(&flags.alpha_deg), reason),
        ReconError::InvalidParameter {
            name: "noise",
            reason,
            ..
        } => IoError::invalid_argument("--noise", raw(&flags.noise), reason),
        ReconError::Model(e) => r.culprit(&e),
        other => IoError::solver(other),
    }
}

fn parse_method(raw: Option<&str>) -> Result<ReconMethod, IoError> {
    match raw.map(str::trim) {
        None | Some("accurate") => Ok(ReconMethod::Accurate),
        Some("thesis") => Ok(ReconMethod::Thesis),
        Some(other) => Err(IoError::invalid_argument(
            "--method",
            other,
            "unknown reconstruction method: expected accurate or thesis",
        )),
    }
}

fn parse_tolerance(raw: Option<&Value>, method: ReconMethod) -> Result<Option<f64>, IoError> {
    let Some(raw) = raw else {
        return Ok(Some(match method {
            ReconMethod::Accurate => DEFAULT_TOLERANCE_ACCURATE,
            ReconMethod::Thesis => DEFAULT_TOLERANCE_THESIS,
        }));
    };
    if raw.is_word("none") {
        return Ok(None);
    }
    let t = raw.number("--tolerance")?;
    if !(t.is_finite() && t > 0.0) {
        return Err(IoError::invalid_argument(
            "--tolerance",
            raw.raw(),
            "must be a positive number or `none`",
        ));
    }
    Ok(Some(t))
}

fn parse_accuracy(raw: Option<&Value>, method: ReconMethod) -> Result<Option<f64>, IoError> {
    let Some(raw) = raw else { return Ok(None) };
    let t = raw.number("--tol")?;
    if !(profile_recon::accuracy::ACCURACY_MIN..=profile_recon::accuracy::ACCURACY_MAX).contains(&t)
    {
        return Err(IoError::invalid_argument(
            "--tol",
            raw.raw(),
            "the accuracy asked for must be in [1e-12, 1e-2]",
        ));
    }
    if method != ReconMethod::Accurate {
        return Err(IoError::invalid_argument(
            "--tol",
            raw.raw(),
            "an accuracy is asked of the method accurate only (thesis, on FDM grids, stays \
             near 1e-5); leave --method at accurate",
        ));
    }
    Ok(Some(t))
}

fn parse_alpha(raw: Option<&Value>) -> Result<Option<f64>, IoError> {
    let Some(raw) = raw else { return Ok(None) };
    let d = raw.number("--alpha-deg")?;
    if !(d.is_finite() && d.abs() < 90.0) {
        return Err(IoError::invalid_argument(
            "--alpha-deg",
            raw.raw(),
            "the flow angle must lie in (-90, 90) degrees",
        ));
    }
    Ok(Some(d.to_radians()))
}

fn parse_noise(raw: Option<&Value>) -> Result<Option<f64>, IoError> {
    let Some(raw) = raw else { return Ok(None) };
    let l = raw.number("--noise")?;
    if !(l.is_finite() && l >= 0.0) {
        return Err(IoError::invalid_argument(
            "--noise",
            raw.raw(),
            "the relative noise level must be a number >= 0",
        ));
    }
    Ok(Some(l))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_name_their_flag_as_given() {
        let flags = ReconFlags {
            noise: Some(Value::Number(-1.0)),
            ..ReconFlags::default()
        };
        let e = ReconOptions::parse(&flags).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid value `-1.0` for `--noise`: the relative noise level must be a number >= 0"
        );
        let flags = ReconFlags {
            alpha_deg: Some("95".into()),
            ..ReconFlags::default()
        };
        let e = ReconOptions::parse(&flags).unwrap_err();
        assert!(e
            .to_string()
            .starts_with("invalid value `95` for `--alpha-deg`"));
        // a number given in code and the same number typed resolve to the same bits
        let typed = ReconOptions::parse(&ReconFlags {
            alpha_deg: Some("12.345".into()),
            tolerance: Some("none".into()),
            ..ReconFlags::default()
        })
        .unwrap();
        let given = ReconOptions::parse(&ReconFlags {
            alpha_deg: Some(12.345.into()),
            tolerance: Some("NONE".into()),
            ..ReconFlags::default()
        })
        .unwrap();
        assert_eq!(typed, given);
        assert_eq!(given.tol, None);
        assert_eq!(given.alpha, Some(12.345f64.to_radians()));
        let d = ReconOptions::parse(&ReconFlags::default()).unwrap();
        assert_eq!(d.tol, Some(DEFAULT_TOLERANCE_ACCURATE));
    }
}
