//! The obstacle of a command: `--profile` or the scene file's `profile` ([`ProfileArg`]),
//! parsed into a contour in the scene's units, and a points file (`points:FILE.csv`) read
//! with its columns' units.

use std::path::{Path, PathBuf};

use contact_sim::{ContactError, Profile};

use super::LoadedScene;
use crate::csvio::{parse_f64, parse_table};
use crate::error::IoError;
use crate::units::{split_name_unit, Quantity, UnitSystem};

/// A profile spec with its origin.
#[derive(Debug, Clone)]
pub struct ProfileArg {
    /// The spec as given.
    pub spec: String,
    /// The scene file it came from, if not from `--profile`.
    pub file: Option<LoadedScene>,
}

impl ProfileArg {
    /// An error about this profile, against `--profile` or the scene's `profile` field.
    pub fn error(&self, reason: String) -> IoError {
        match &self.file {
            Some(f) => f.error_at("profile", format!("`{}`: {reason}", self.spec)),
            None => IoError::invalid_argument("--profile", self.spec.clone(), reason),
        }
    }

    /// The path of a `points:FILE.csv` profile (relative to the scene file it came from),
    /// or `None` for the other kinds.
    pub fn points_path(&self) -> Option<PathBuf> {
        let file = self.spec.trim().strip_prefix("points:")?;
        let mut path = PathBuf::from(file.trim());
        if let Some(scene) = &self.file {
            if path.is_relative() {
                if let Some(dir) = scene.path.parent() {
                    path = dir.join(path);
                }
            }
        }
        Some(path)
    }

    /// Parses the profile in the unit system `units` (see
    /// [`UnitSystem::dimensionless_profile`]). `points:FILE.csv` reads a table whose header
    /// names the x and y columns, units allowed (`x,y`, `x_mm;y_mm`, `x [mm]<TAB>y [mm]`;
    /// see [`read_points_file`]); a relative path in a scene file is taken relative to the
    /// scene file. Convexity is the sweep's business: it checks the part the whisker
    /// touches.
    pub fn parse(&self, units: &UnitSystem) -> Result<Profile, IoError> {
        if let Some(path) = self.points_path() {
            if self.spec.trim()["points:".len()..].trim().is_empty() {
                // not the empty path's "No such file or directory" (issue #34)
                return Err(self.error(
                    "names no table: expected points:FILE.csv, a CSV file whose header names \
                     the x and y columns"
                        .to_string(),
                ));
            }
            let (x, y) = read_points_file(&path, units)?;
            return Profile::points(x, y).map_err(|e| match e {
                ContactError::ProfileSpec { reason, .. } => IoError::Csv {
                    path: path.clone(),
                    line: 1,
                    column: None,
                    reason,
                },
                other => self.error(other.to_string()),
            });
        }
        let spec = self.spec.trim();
        Profile::parse(spec)
            .map(|p| units.dimensionless_profile(spec, p))
            .map_err(|e| match e {
                ContactError::ProfileSpec { reason, .. } => self.error(reason),
                other => self.error(other.to_string()),
            })
    }
}

/// Reads a tabulated contour: a CSV file (comma, tab or semicolon separated) whose header
/// names the two columns, x then y, with optional units in the names (`x_mm`, `y (mm)`,
/// `x [m]`); other columns are ignored. Without units the values are in the scene's units
/// (mm in a physical scene, whisker lengths otherwise). Returns the dimensionless (x, y),
/// x strictly increasing; every problem names the file, line and column.
pub fn read_points_file(path: &Path, units: &UnitSystem) -> Result<(Vec<f64>, Vec<f64>), IoError> {
    let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
    let head = parse_table(&text, path, &[], 0)?;
    let err = |line: usize, column: Option<&str>, reason: String| IoError::Csv {
        path: path.to_path_buf(),
        line,
        column: column.map(str::to_string),
        reason,
    };
    let find = |sym: &str| {
        head.header
            .iter()
            .find(|h| split_name_unit(h).0.eq_ignore_ascii_case(sym))
            .cloned()
    };
    let (Some(xname), Some(yname)) = (find("x"), find("y")) else {
        let numeric_header = head
            .header
            .iter()
            .all(|h| parse_f64(h, head.delimiter).is_some());
        let reason = if numeric_header {
            format!(
                "the first line holds numbers, not a header: a points file starts with a \
                 header naming its columns, x then y (e.g. `x,y` or `x_mm;y_mm`), found `{}`",
                head.header.join(",")
            )
        } else {
            format!(
                "the header must name an x and a y column (e.g. `x,y`, `x_mm;y_mm`, \
                 `x [mm]<TAB>y [mm]`), found `{}`",
                head.header.join(",")
            )
        };
        return Err(err(head.header_line, None, reason));
    };
    let table = parse_table(&text, path, &[xname.as_str(), yname.as_str()], 4)?;
    let (xs, ys) = match (table.column(&xname), table.column(&yname)) {
        (Some(x), Some(y)) => (x, y),
        _ => {
            return Err(err(
                table.header_line,
                None,
                "the x and y columns must hold numbers".to_string(),
            ))
        }
    };
    for i in 1..xs.len() {
        if xs[i] <= xs[i - 1] {
            return Err(err(
                table.lines[i],
                Some(&xname),
                format!(
                    "x = {} does not increase (x = {} on line {}): the rows must be sorted by \
                     strictly increasing x",
                    xs[i],
                    xs[i - 1],
                    table.lines[i - 1]
                ),
            ));
        }
    }
    let factor = |name: &str| {
        let unit = split_name_unit(name).1;
        let f = if unit.is_empty() {
            1.0 / units.scale(Quantity::Length)
        } else {
            units
                .factor_from(&unit, Quantity::Length)
                .map_err(|r| err(table.header_line, Some(name), r))?
        };
        Ok::<f64, IoError>(f)
    };
    let (fx, fy) = (factor(&xname)?, factor(&yname)?);
    Ok((
        xs.iter().map(|v| v * fx).collect(),
        ys.iter().map(|v| v * fy).collect(),
    ))
}

/// The profile from `--profile`, else the scene file's `profile`.
pub fn profile_arg(flag: &Option<String>, file: Option<&LoadedScene>) -> Option<ProfileArg> {
    match (flag, file) {
        (Some(spec), _) => Some(ProfileArg {
            spec: spec.clone(),
            file: None,
        }),
        (None, Some(f)) => f.file.profile.as_ref().map(|spec| ProfileArg {
            spec: spec.clone(),
            file: Some(f.clone()),
        }),
        (None, None) => None,
    }
}
