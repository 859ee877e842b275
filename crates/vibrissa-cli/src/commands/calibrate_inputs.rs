//! The parse and resolve steps of `vibrissa calibrate`: the start whisker and flow (scene
//! file under the flags), the parameters to fit (`--fit`), and each log argument
//! (`LOG` or `LOG=PROFILE`, a file or a sweep folder) read into a [`LogInput`].

use std::path::{Path, PathBuf};

use profile_recon::calibrate::CalibParam;
use profile_recon::ReconError;

use crate::cli::CalibrateArgs;
use crate::commands::recon_io;
use crate::commands::reconstruct::{rows_of, REQUIRED_COLUMNS};
use crate::csvio::read_table;
use crate::error::CliError;
use crate::resolve::{physical_whisker, LoadedScene, ProfileArg, Resolved};
use crate::units::UnitSystem;

pub use vibrissa_io::calibration::LogInput;

/// `LOG` or `LOG=PROFILE`: the argument, the path and the profile spec. An argument that
/// names an existing file or folder as a whole is a path (even with `=` in it).
pub(crate) fn split_log_arg(arg: &str) -> Result<(String, PathBuf, Option<String>), CliError> {
    let whole = PathBuf::from(arg);
    if whole.exists() {
        return Ok((arg.to_string(), whole, None));
    }
    if let Some((p, prof)) = arg.rsplit_once('=') {
        let path = PathBuf::from(p);
        if prof.trim().is_empty() {
            return Err(CliError::invalid_argument(
                "LOG",
                arg,
                format!(
                    "no contour after `=`: give `{p}=PROFILE` (e.g. `{p}=circle:0,1.4,0.5`), or \
                     `{p}` with --profile P"
                ),
            ));
        }
        if path.exists() {
            return Ok((arg.to_string(), path, Some(prof.to_string())));
        }
    }
    Err(CliError::io(
        arg,
        std::io::Error::new(
            std::io::ErrorKind::NotFound,
            "no such log (an observables CSV or a sweep folder, optionally LOG=PROFILE)",
        ),
    ))
}

/// Parses `--fit` (default `theta,a,b,k`; `ei` only in physical units).
pub(crate) fn parse_fit(
    raw: Option<&str>,
    units: &UnitSystem,
) -> Result<Vec<CalibParam>, CliError> {
    Ok(vibrissa_io::calibration::parse_fit(raw, units)?)
}

/// Reads one log: its observables (a sweep folder's `observables.csv`), converted to model
/// units, and its known contour (`LOG=PROFILE`, else `--profile`, else the folder's
/// `scene.ron`).
pub(crate) fn read_log(
    arg: &str,
    path: &Path,
    profile: Option<&str>,
    args: &CalibrateArgs,
    r: &Resolved,
) -> Result<LogInput, CliError> {
    let units = r.units();
    let (log_path, folder_scene) = if path.is_dir() {
        let (log, scene) = recon_io::resolve_input(path, None)?;
        (log, scene)
    } else {
        (path.to_path_buf(), None)
    };
    let folder = LoadedScene::load_opt(folder_scene.as_deref())?;
    if let Some(f) = &folder {
        if physical_whisker(f)? != r.physical {
            return Err(CliError::Io(vibrissa_io::IoError::Usage {
                reason: format!(
                    "log `{arg}`: its scene.ron has other units than the calibration's ({}); \
                     calibrate logs of one unit system together",
                    units.describe()
                ),
            }));
        }
    }
    let prof = match (profile, &args.profile) {
        (Some(p), _) => ProfileArg {
            spec: p.to_string(),
            file: None,
        },
        (None, Some(p)) => ProfileArg {
            spec: p.clone(),
            file: None,
        },
        (None, None) => match folder
            .as_ref()
            .or(r.file.as_ref())
            .and_then(|f| f.file.profile.clone().map(|p| (p, f.clone())))
        {
            Some((spec, f)) => ProfileArg {
                spec,
                file: Some(f),
            },
            None => {
                return Err(CliError::Io(vibrissa_io::IoError::Usage {
                    reason: format!(
                        "log `{arg}`: no known contour: give --profile P, `{arg}=PROFILE`, a \
                         sweep folder or a --scene whose scene.ron names its profile"
                    ),
                }))
            }
        },
    };
    let parsed = prof.parse(&units)?;
    let mut table = read_table(&log_path, &REQUIRED_COLUMNS, 2)?;
    let pose_given = recon_io::PoseColumns::of(&table);
    let x0_given = recon_io::to_model_units(&mut table, &units)?;
    let rows = rows_of(&table)?;
    for (i, row) in rows.iter().enumerate() {
        row.validate(i).map_err(|e| match e {
            ReconError::NonFinite { row, column, value } => {
                CliError::Io(vibrissa_io::IoError::Csv {
                    path: log_path.clone(),
                    line: table.line_of(row).unwrap_or(1),
                    column: Some(column.to_string()),
                    reason: format!("value `{value}` is not finite"),
                })
            }
            other => CliError::solver(other),
        })?;
    }
    // a log of any base motion (issue 38): every pose finite, named by line and column
    for (i, pose) in vibrissa_io::recon::poses_of(&table).iter().enumerate() {
        let culprit = match pose.validate(i) {
            Err(ReconError::NonFinite { column, value, .. }) => {
                Some((column, format!("value `{value}` is not finite")))
            }
            Err(ReconError::InvalidParameter {
                name,
                value,
                reason,
            }) => Some((name, format!("value `{value}`: {reason}"))),
            _ => None,
        };
        if let Some((column, reason)) = culprit {
            return Err(CliError::Io(vibrissa_io::IoError::Csv {
                path: log_path.clone(),
                line: table.line_of(i).unwrap_or(1),
                column: Some(column.to_string()),
                reason,
            }));
        }
    }
    Ok(LogInput {
        arg: arg.to_string(),
        path: log_path,
        table,
        x0_given,
        pose_given,
        profile: (prof.spec.clone(), parsed),
    })
}

/// The start whisker and flow of a calibration: the scene file at `scene` (if any) under
/// the whisker and flow flags.
pub(crate) fn calib_model(
    args: &CalibrateArgs,
    scene: Option<&Path>,
) -> Result<Resolved, CliError> {
    let file = LoadedScene::load_opt(scene)?;
    Ok(vibrissa_io::calibration::calib_model(&args.into(), file)?)
}
