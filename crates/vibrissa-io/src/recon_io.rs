//! The inputs and outputs of `vibrissa reconstruct` that concern folders and units: a sweep
//! folder as input (`reconstruct DIR`), a log's units (its `NAME.units.csv` sidecar, else
//! the scene's units) and the reconstruction written in the scene's units with its own
//! sidecar and `scene.ron`. The one definition of a row of `reconstruction.csv`
//! ([`recon_cells`]) lives here: the file writer and the stream both use it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use profile_recon::ReconPoint;

use crate::csvio::{read_units_sidecar, units_sidecar_path, Cell, CsvWriter, Table};
use crate::error::IoError;
use crate::outputs::{output_scene, scene_unit_notes, write_scene_ron, write_units_of};
use crate::resolve::Resolved;
use crate::units::{column_factors, Quantity, UnitSystem};

/// The columns an observables log must have.
pub const REQUIRED_COLUMNS: [&str; 5] = ["x0", "Ax", "Ay", "MA", "phi0"];

/// The file name of a sweep folder's log.
pub const OBSERVABLES_CSV: &str = "observables.csv";

/// The file name of a folder's scene.
pub const SCENE_RON: &str = "scene.ron";

/// The log and the scene to read for `reconstruct INPUT [SCENE]`: a folder gives its
/// `observables.csv` and, unless a scene is given, its `scene.ron`.
pub fn resolve_input(
    input: &Path,
    scene: Option<&Path>,
) -> Result<(PathBuf, Option<PathBuf>), IoError> {
    if !input.is_dir() {
        return Ok((input.to_path_buf(), scene.map(Path::to_path_buf)));
    }
    let log = input.join(OBSERVABLES_CSV);
    if !log.is_file() {
        return Err(IoError::io(
            &log,
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!(
                    "a sweep folder needs {OBSERVABLES_CSV} (written by `vibrissa sweep --out DIR`)"
                ),
            ),
        ));
    }
    let scene = match scene {
        Some(s) => Some(s.to_path_buf()),
        None => {
            let s = input.join(SCENE_RON);
            if !s.is_file() {
                return Err(IoError::io(
                    &s,
                    std::io::Error::new(
                        std::io::ErrorKind::NotFound,
                        "a sweep folder needs its scene.ron for the whisker (or give SCENE.ron)",
                    ),
                ));
            }
            Some(s)
        }
    };
    Ok((log, scene))
}

/// The file name of the reconstruction table.
pub const RECON_CSV: &str = "reconstruction.csv";

/// The header of `reconstruction.csv` (spec/cli.md); `error` is appended with a profile.
pub const RECONSTRUCTION_HEADER: [&str; 7] = ["x0", "x", "y", "s1", "f", "psi", "phase"];

/// The quantities of the columns `reconstruct` reads.
const INPUT_QUANTITIES: [(&str, Quantity); 5] = [
    ("x0", Quantity::Length),
    ("Ax", Quantity::Force),
    ("Ay", Quantity::Force),
    ("MA", Quantity::Moment),
    ("phi0", Quantity::Angle),
];

/// The quantities of the pose columns a log of any base motion carries besides `x0`
/// (spec/cli.md: `y0`, and `gamma` in radians), read where present.
pub const POSE_QUANTITIES: [(&str, Quantity); 2] =
    [("y0", Quantity::Length), ("gamma", Quantity::Angle)];

/// Converts the columns x0, Ax, Ay, MA, phi0 (and the pose columns y0, gamma where present,
/// and a path's `k` from the scene's stiffness unit) of a log to the model's dimensionless
/// variables:
/// by the units of its sidecar `NAME.units.csv` if there is one, else from the scene's units
/// (`units`). Returns the x0 column as given, to be copied exactly into the outputs.
pub fn to_model_units(table: &mut Table, units: &UnitSystem) -> Result<Vec<f64>, IoError> {
    let sidecar = units_sidecar_path(&table.path);
    let given = read_units_sidecar(&sidecar)?.unwrap_or_default();
    to_model_units_with(table, &given, units, &sidecar)
}

/// As [`to_model_units`] with the columns' units `given` (column name -> unit; a column not
/// named is in the scene's units), read from `origin` (named in messages).
pub fn to_model_units_with(
    table: &mut Table,
    given: &BTreeMap<String, String>,
    units: &UnitSystem,
    origin: &Path,
) -> Result<Vec<f64>, IoError> {
    let factors = input_factors(given, units, origin)?;
    let x0 = table.column("x0").map(<[f64]>::to_vec).unwrap_or_default();
    let pose = column_factors(given, &POSE_QUANTITIES, units, origin)?;
    let columns = INPUT_QUANTITIES.iter().chain(&POSE_QUANTITIES);
    for ((name, _), f) in columns.zip(factors.into_iter().chain(pose)) {
        if f != 1.0 {
            if let Some(col) = table.numeric.get_mut(*name) {
                col.iter_mut().for_each(|v| *v *= f);
            }
        }
    }
    // a path's follicle stiffness, in the scene's stiffness unit as the sweep writes it
    let fk = crate::observables::stiffness_scale(units);
    if fk != 1.0 {
        if let Some(col) = table.numeric.get_mut(crate::observables::K_COLUMN) {
            col.iter_mut().for_each(|v| *v /= fk);
        }
    }
    Ok(x0)
}

/// The factors that take the input columns x0, Ax, Ay, MA, phi0 to the model's
/// dimensionless variables (a value times its factor): by the columns' units `given` (column
/// name -> unit, read from `origin`, named in messages), `1 / scale` of the scene's `units`
/// for a column not named. The one conversion of a log's values: a file's columns
/// ([`to_model_units_with`]) and the stream's rows (no units given) alike.
pub fn input_factors(
    given: &BTreeMap<String, String>,
    units: &UnitSystem,
    origin: &Path,
) -> Result<[f64; 5], IoError> {
    let f = column_factors(given, &INPUT_QUANTITIES, units, origin)?;
    Ok([f[0], f[1], f[2], f[3], f[4]])
}

/// The quantities of the `reconstruction.csv` columns (`error` last, if present): x0, x, y,
/// s1, f, psi, phase, sigma, residual, hypotheses, error.
pub(crate) const RECON_QUANTITIES: [Quantity; 11] = [
    Quantity::Length,
    Quantity::Length,
    Quantity::Length,
    Quantity::Length,
    Quantity::Force,
    Quantity::Angle,
    Quantity::Text,
    Quantity::Length,
    Quantity::Number,
    Quantity::Number,
    Quantity::Length,
];

/// The columns of `reconstruction.csv` after the contract's (spec/cli.md): each point's
/// error estimate (a length), its consistency residual and the number of other phase
/// hypotheses that fit the row within the noise.
pub const RECON_EXTRA_COLUMNS: [&str; 3] = ["sigma", "residual", "hypotheses"];

/// The numbers of a reconstructed point in `units`, in the order of
/// [`RECONSTRUCTION_HEADER`] (x0, x, y, s1, f,
/// psi), x0 copied exactly from `x0_given` (the log's x0 column as given): the one place
/// where a point is scaled for output (CSV, Python).
pub fn recon_values(p: &ReconPoint, units: &UnitSystem, x0_given: &[f64]) -> [f64; 6] {
    let (l, fs) = (units.scale(Quantity::Length), units.scale(Quantity::Force));
    let x0 = x0_given.get(p.row).copied().unwrap_or(p.x0 * l);
    [x0, p.x * l, p.y * l, p.s1 * l, p.f * fs, p.psi]
}

/// The header of `reconstruction.csv`: the contract's columns, [`RECON_EXTRA_COLUMNS`] and
/// `error` if the true contour is known.
pub fn reconstruction_header(with_error: bool) -> Vec<&'static str> {
    let mut header: Vec<&str> = RECONSTRUCTION_HEADER.to_vec();
    header.extend(RECON_EXTRA_COLUMNS);
    if with_error {
        header.push("error");
    }
    header
}

/// One row of `reconstruction.csv` in `units` (header [`reconstruction_header`]): the
/// numbers of [`recon_values`], the phase, sigma, residual, hypotheses and, if given, the
/// error (a length). The one definition of a row, for the file and the stream.
pub fn recon_cells(
    p: &ReconPoint,
    units: &UnitSystem,
    x0_given: &[f64],
    error: Option<f64>,
) -> Vec<Cell<'static>> {
    let l = units.scale(Quantity::Length);
    let mut row: Vec<Cell<'static>> = recon_values(p, units, x0_given)
        .iter()
        .map(|&x| Cell::Num(x))
        .collect();
    row.push(Cell::Text(p.phase.label()));
    row.push(Cell::Num(p.sigma * l));
    row.push(Cell::Num(p.residual));
    row.push(Cell::Num(p.alternatives as f64));
    if let Some(e) = error {
        row.push(Cell::Num(e * l));
    }
    row
}

/// Writes `reconstruction.csv` in `units` (x0 copied exactly from `x0_given`, the log's x0
/// column as given; `&[]` for none) and its units sidecar: the one writer of the file.
pub fn write_reconstruction_csv(
    points: &[ReconPoint],
    errors: Option<&[f64]>,
    units: &UnitSystem,
    x0_given: &[f64],
    path: &Path,
) -> Result<(), IoError> {
    write_reconstruction_csv_posed(
        points,
        errors,
        units,
        x0_given,
        &PoseColumns::default(),
        path,
    )
}

/// [`write_reconstruction_csv`] with the log's pose columns `pose` ([`PoseColumns`]: `y0`,
/// `gamma`, `k` of a log of any base motion, issue 38) appended to each row as given, so
/// that a reader can plot the points against the turn; without them (a translate log) the
/// file of [`write_reconstruction_csv`] byte for byte.
pub fn write_reconstruction_csv_posed(
    points: &[ReconPoint],
    errors: Option<&[f64]>,
    units: &UnitSystem,
    x0_given: &[f64],
    pose: &PoseColumns,
    path: &Path,
) -> Result<(), IoError> {
    let mut header = reconstruction_header(errors.is_some());
    let n = header.len();
    header.extend(pose.names());
    let mut w = CsvWriter::new(&header);
    for (i, p) in points.iter().enumerate() {
        let error = errors.map(|e| e.get(i).copied().unwrap_or(f64::NAN));
        let mut cells = recon_cells(p, units, x0_given, error);
        cells.extend(pose.cells(p.row));
        w.push_row(&cells)?;
    }
    w.write(path)?;
    if pose.is_empty() {
        return write_units_of(path, &header, &RECON_QUANTITIES[..n], units);
    }
    let mut u: Vec<&str> = RECON_QUANTITIES[..n]
        .iter()
        .map(|q| units.unit(*q))
        .collect();
    u.extend(pose.units(units));
    crate::csvio::write_units_sidecar(&crate::csvio::units_sidecar_path(path), &header, &u)
}

/// The pose columns of a log of any base motion (issue 38; spec/cli.md `--motion`), as the
/// log gave them: `y0`, `gamma` (radians) and the path's follicle stiffness `k`, those the
/// log has, in that order, copied exactly into `reconstruction.csv` and `residuals.csv`
/// (like `x0`) so that a reader can plot the points against the turn. A log whose every
/// `y0` and `gamma` is 0 and that has no `k` (the translating sweep's, whose logs carry
/// `y0 = gamma = 0` columns) has none: its outputs keep the contract's columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PoseColumns {
    columns: Vec<(&'static str, Vec<f64>)>,
}

impl PoseColumns {
    /// The pose columns, in the order written.
    pub const NAMES: [&'static str; 3] = ["y0", "gamma", crate::observables::K_COLUMN];

    /// The pose columns of `table` as given (read them before converting the table to model
    /// units); none for a translate log (type docs).
    pub fn of(table: &Table) -> Self {
        Self::from_columns(
            Self::NAMES
                .iter()
                .filter_map(|&n| table.column(n).map(|c| (n, c.to_vec())))
                .collect(),
        )
    }

    /// From columns given in code (`(name, values)`, names among [`Self::NAMES`], in that
    /// order), with the rule of [`Self::of`].
    pub fn from_columns(columns: Vec<(&'static str, Vec<f64>)>) -> Self {
        let moves = columns
            .iter()
            .any(|(n, c)| *n == crate::observables::K_COLUMN || c.iter().any(|v| *v != 0.0));
        PoseColumns {
            columns: if moves { columns } else { Vec::new() },
        }
    }

    /// Whether there are none (a translate log).
    pub fn is_empty(&self) -> bool {
        self.columns.is_empty()
    }

    /// The names of the columns written.
    pub fn names(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.columns.iter().map(|(n, _)| *n)
    }

    /// The values of row `row` (0-based row of the log), as given (NaN past the end).
    pub fn values(&self, row: usize) -> impl Iterator<Item = f64> + '_ {
        self.columns
            .iter()
            .map(move |(_, c)| c.get(row).copied().unwrap_or(f64::NAN))
    }

    /// The cells of row `row` ([`Self::values`]).
    pub fn cells(&self, row: usize) -> impl Iterator<Item = Cell<'static>> + '_ {
        self.values(row).map(Cell::Num)
    }

    /// The columns by name with their values, as given.
    pub fn columns(&self) -> &[(&'static str, Vec<f64>)] {
        &self.columns
    }

    /// The units of the columns in `units` (`y0` a length, `gamma` rad, `k` the scene's
    /// stiffness unit).
    pub fn units(&self, units: &UnitSystem) -> Vec<&'static str> {
        self.columns
            .iter()
            .map(|(n, _)| Self::unit_of(n, units))
            .collect()
    }

    /// The unit of the pose column `name` in `units` (`y0` a length, `gamma` rad, `k` the
    /// scene's stiffness unit).
    pub fn unit_of(name: &str, units: &UnitSystem) -> &'static str {
        match name {
            "y0" => units.unit(Quantity::Length),
            "gamma" => units.unit(Quantity::Angle),
            _ => crate::observables::stiffness_unit(units),
        }
    }
}

/// Writes the `scene.ron` of a reconstruction folder: the whisker used, the identified (or
/// given) fluid load `q` (dimensionless; written in the scene's units) and the true contour
/// if one was given.
pub fn write_recon_scene(
    r: &Resolved,
    q: f64,
    profile: Option<String>,
    log: &Path,
    path: &Path,
) -> Result<(), IoError> {
    let units = r.units();
    let mut scene = output_scene(r, profile, None);
    scene.loads.q = q * units.scale(Quantity::LineLoad);
    let mut notes = vec![
        format!(
            "Written by vibrissa {} (`reconstruct`): the whisker that reconstructed {}.",
            env!("CARGO_PKG_VERSION"),
            log.display()
        ),
        "loads.q is the fluid load identified from the log (or given with --q).".to_string(),
    ];
    notes.extend(scene_unit_notes(&units));
    notes.push(format!(
        "reconstruction.csv: x0, x, y, s1 (and error) in {}; f in {}; psi in rad \
         (reconstruction.units.csv).",
        units.unit(Quantity::Length),
        units.unit(Quantity::Force)
    ));
    write_scene_ron(path, &scene, &notes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use contact_sim::Phase;

    fn point() -> ReconPoint {
        ReconPoint {
            row: 1,
            x0: 0.5,
            x: 0.25,
            y: 1.0,
            s1: 1.0,
            f: 0.125,
            psi: 0.5,
            phase: Phase::B,
            residual: 1e-12,
            sigma: 2e-10,
            alternatives: 1,
            evaluations: 3,
        }
    }

    #[test]
    fn a_row_has_the_columns_of_its_header_and_copies_x0_as_given() {
        let p = point();
        let units = UnitSystem::DIMENSIONLESS;
        for (error, n) in [(None, 10), (Some(0.5), 11)] {
            let cells = recon_cells(&p, &units, &[], error);
            assert_eq!(cells.len(), n);
            assert_eq!(reconstruction_header(error.is_some()).len(), n);
        }
        let cells = recon_cells(&p, &units, &[7.0, 0.1 + 0.2], Some(0.5));
        assert_eq!(cells[0], Cell::Num(0.1 + 0.2), "x0 of row 1 as given");
        assert_eq!(cells[6], Cell::Text("B"));
        assert_eq!(cells[9], Cell::Num(1.0));
        assert_eq!(cells[10], Cell::Num(0.5));
        let none = BTreeMap::new();
        assert_eq!(
            input_factors(&none, &units, Path::new("-")).unwrap(),
            [1.0; 5]
        );
        assert_eq!(
            reconstruction_header(true).join(","),
            "x0,x,y,s1,f,psi,phase,sigma,residual,hypotheses,error"
        );
    }

    /// A physical scene's log (no sidecar) is divided by its output scales, through the
    /// reciprocal factors; a sidecar unit names its own factor (mm to the whisker length).
    #[test]
    fn input_factors_invert_the_scene_scales() {
        let p = beam_model::Preset::from_name("beta").unwrap().whisker();
        let units = UnitSystem::new(Some(p));
        let origin = Path::new("log.units.csv");
        let f = input_factors(&BTreeMap::new(), &units, origin).unwrap();
        // (to the last bit or two: optimised builds may fold the scales' powers differently)
        for ((_, q), f) in INPUT_QUANTITIES.iter().zip(f) {
            assert!((f * units.scale(*q) - 1.0).abs() < 1e-15, "{q:?}: {f}");
        }
        assert!((f[0] * units.scale(Quantity::Length) - 1.0).abs() < 1e-15);
        let given = BTreeMap::from([("x0".to_string(), "m".to_string())]);
        let g = input_factors(&given, &units, origin).unwrap();
        assert!((g[0] / f[0] - 1e3).abs() < 1e-9, "{}", g[0] / f[0]);
        assert_eq!(g[1..], f[1..]);
    }
}
