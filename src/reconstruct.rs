//! [`Scene::reconstruct`]: the flow identified and the contour reconstructed from a log of
//! base observables [ch. 6], with the scene's whisker, in the scene's units (the numbers of
//! `vibrissa reconstruct`'s `reconstruction.csv`).

use std::collections::BTreeMap;
use std::path::PathBuf;

use contact_sim::Phase;
use profile_recon::{
    reconstruct_with, KnownFlow, ObservableRow, ReconError, ReconPoint, ReconSettings,
};
use vibrissa_io::csvio::Table;
use vibrissa_io::recon_io::{recon_values, to_model_units_with, REQUIRED_COLUMNS};
use vibrissa_io::resolve::{ModelFlags, Resolved};
use vibrissa_io::units::{Quantity, UnitSystem};
use vibrissa_io::IoError;

use crate::io::ObservableLog;
use crate::{Error, Scene, Sweep};

/// The consistency tolerance of a contact row (the command line's `--tolerance` default
/// for the method `accurate`).
pub const CONSISTENCY_TOLERANCE: f64 = 1e-6;

/// A log of base observables that can be reconstructed: a [`Sweep`] or an
/// [`ObservableLog`] read from any observables CSV ([`crate::io::read_observables`]).
pub trait Log {
    /// The log as a table of the columns x0, Ax, Ay, MA, phi0 as given, with the units of
    /// its columns where they are known (column -> unit, read from `origin`; a column not
    /// named is in the scene's units).
    fn table(&self) -> (Table, BTreeMap<String, String>, PathBuf);
}

impl Log for ObservableLog {
    fn table(&self) -> (Table, BTreeMap<String, String>, PathBuf) {
        (
            self.table.clone(),
            self.units.clone().unwrap_or_default(),
            self.sidecar.clone(),
        )
    }
}

/// A column of a sweep's rows.
type Column = fn(&vibrissa_io::observables::SweepRow) -> f64;

impl Log for Sweep {
    /// The sweep's rows in its units, as its `observables.csv` would be read back (the
    /// CSV's numbers are round-trip exact), its units those of the sweep.
    fn table(&self) -> (Table, BTreeMap<String, String>, PathBuf) {
        let rows = self.rows();
        let columns: [(&str, Column); 5] = [
            ("x0", |r| r.x0),
            ("Ax", |r| r.ax),
            ("Ay", |r| r.ay),
            ("MA", |r| r.ma),
            ("phi0", |r| r.phi0),
        ];
        let numeric = columns
            .iter()
            .map(|(n, f)| (n.to_string(), rows.iter().map(f).collect()))
            .collect();
        let units = columns
            .iter()
            .zip([
                Quantity::Length,
                Quantity::Force,
                Quantity::Force,
                Quantity::Moment,
                Quantity::Angle,
            ])
            .map(|((n, _), q)| (n.to_string(), self.units().unit(q).to_string()))
            .collect();
        let path = PathBuf::from("<sweep>");
        let table = Table {
            path: path.clone(),
            header: REQUIRED_COLUMNS.iter().map(|s| s.to_string()).collect(),
            numeric,
            text: BTreeMap::new(),
            lines: (2..rows.len() + 2).collect(),
            header_line: 1,
            delimiter: b',',
        };
        (table, units, path)
    }
}

/// One reconstructed contact point in the scene's units: a row of `reconstruction.csv`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ReconRow {
    /// The log row's base position, copied exactly.
    pub x0: f64,
    /// Contact point x.
    pub x: f64,
    /// Contact point y.
    pub y: f64,
    /// Contact arc length.
    pub s1: f64,
    /// Contact force.
    pub f: f64,
    /// Contour angle at the contact point (rad).
    pub psi: f64,
    /// The phase decided (A: tip contact, B: tangential).
    #[serde(serialize_with = "vibrissa_io::observables::serialize_phase")]
    pub phase: Phase,
    /// Error estimate of (x, y), one standard deviation, a length.
    pub sigma: f64,
    /// Consistency residual of the row (dimensionless).
    pub residual: f64,
    /// Other phase hypotheses consistent within the noise (> 0: ambiguous).
    pub hypotheses: usize,
}

impl ReconRow {
    /// The point `p` in `units`, x0 copied from `x0_given` (the log's column as given).
    pub fn of(p: &ReconPoint, units: &UnitSystem, x0_given: &[f64]) -> Self {
        let [x0, x, y, s1, f, psi] = recon_values(p, units, x0_given);
        ReconRow {
            x0,
            x,
            y,
            s1,
            f,
            psi,
            phase: p.phase,
            sigma: p.sigma * units.scale(Quantity::Length),
            residual: p.residual,
            hypotheses: p.alternatives,
        }
    }
}

/// A reconstruction in the scene's units: the contact points and the flow.
#[derive(Debug, Clone)]
pub struct Reconstruction {
    /// The contact points, one per contact row of the log, in its order.
    pub rows: Vec<ReconRow>,
    /// The fluid load identified from the rows before contact (the scene's line-load unit).
    pub q: f64,
    /// The flow angle identified (rad).
    pub alpha: f64,
    /// The unit system of the numbers above.
    pub units: UnitSystem,
    /// The model's result, dimensionless.
    pub dimensionless: profile_recon::Reconstruction,
}

impl Scene {
    /// Identifies the flow from the log's rows before contact and reconstructs the contact
    /// point of every contact row with the scene's whisker (as `vibrissa reconstruct LOG
    /// SCENE.ron`; the scene's loads are not used). The log's units come from its units
    /// sidecar, else the scene's. A row with no consistent contact point (residual above
    /// [`CONSISTENCY_TOLERANCE`]) is [`Error::InvalidInput`] naming its line.
    pub fn reconstruct(&self, log: &impl Log) -> Result<Reconstruction, Error> {
        let (_, r) = self.resolved(&ModelFlags::default())?;
        let units = r.units();
        let (mut table, given, origin) = log.table();
        let x0_given = to_model_units_with(&mut table, &given, &units, &origin)?;
        let rows = rows_of(&table)?;
        let settings = ReconSettings {
            consistency_tol: Some(CONSISTENCY_TOLERANCE),
            ..ReconSettings::default()
        };
        let rec = reconstruct_with(&r.scene.whisker, &rows, KnownFlow::default(), &settings)
            .map_err(|e| culprit(e, &table, &r))?;
        Ok(Reconstruction {
            rows: rec
                .points
                .iter()
                .map(|p| ReconRow::of(p, &units, &x0_given))
                .collect(),
            q: rec.identification.q * units.scale(Quantity::LineLoad),
            alpha: rec.identification.alpha,
            units,
            dimensionless: rec,
        })
    }
}

/// The observable rows of a table with the columns [`REQUIRED_COLUMNS`].
fn rows_of(table: &Table) -> Result<Vec<ObservableRow>, IoError> {
    let col = |name: &str| {
        table.column(name).ok_or_else(|| IoError::Csv {
            path: table.path.clone(),
            line: table.header_line,
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

/// A reconstruction error against its culprit: a line of the log, a scene field, the solver.
fn culprit(err: ReconError, table: &Table, r: &Resolved) -> Error {
    let line_of = |row: usize| table.line_of(row).unwrap_or(table.header_line + 1);
    let at = |line: usize, column: Option<&str>, reason: String| {
        Error::InvalidInput(IoError::Csv {
            path: table.path.clone(),
            line,
            column: column.map(str::to_string),
            reason,
        })
    };
    match err {
        ReconError::NonFinite { row, column, value } => at(
            line_of(row),
            Some(column),
            format!("value `{value}` is not finite"),
        ),
        ReconError::InconsistentRow { row, .. } => at(line_of(row), None, err.to_string()),
        ReconError::TooFewRows { .. }
        | ReconError::NoPreContactRows { .. }
        | ReconError::NoContactRows { .. } => at(line_of(0), None, err.to_string()),
        ReconError::Model(e) => r.culprit(&e).into(),
        other => IoError::solver(other).into(),
    }
}
