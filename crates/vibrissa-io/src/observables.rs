//! `observables.csv`, the log of a sweep: its header, the quantities of its columns, one
//! row per sweep point ([`ObservableRecord`], also used by the Python bindings) and its
//! writer with the units sidecar.

use std::path::Path;

use contact_sim::{Phase, SweepPoint, SweepResult};

use crate::csvio::CsvWriter;
use crate::error::IoError;
use crate::outputs::write_units_of;
use crate::units::{Quantity, UnitSystem};

/// The header of `observables.csv` (spec/cli.md).
pub const OBSERVABLES_HEADER: [&str; 11] = [
    "x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "phase", "xc", "yc", "psi",
];
/// The quantities of the `observables.csv` columns.
pub const OBSERVABLES_QUANTITIES: [Quantity; 11] = [
    Quantity::Length,
    Quantity::Force,
    Quantity::Force,
    Quantity::Moment,
    Quantity::Angle,
    Quantity::Force,
    Quantity::Length,
    Quantity::Text,
    Quantity::Length,
    Quantity::Length,
    Quantity::Angle,
];
/// One row of `observables.csv` in the scene's units (serde names = the contract's column
/// names; the facade's `vibrissa::SweepRow`): NaN where the CSV cell is empty (the contact
/// point of a row before contact).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SweepRow {
    /// Base position.
    pub x0: f64,
    /// Horizontal base force.
    #[serde(rename = "Ax")]
    pub ax: f64,
    /// Vertical base force.
    #[serde(rename = "Ay")]
    pub ay: f64,
    /// Base moment.
    #[serde(rename = "MA")]
    pub ma: f64,
    /// Base angle.
    pub phi0: f64,
    /// Contact force.
    pub f: f64,
    /// Loaded arc length.
    pub s1: f64,
    /// `none`, `A` or `B` (written as [`Phase::label`]).
    #[serde(serialize_with = "serialize_phase")]
    pub phase: Phase,
    /// Contact point x.
    pub xc: f64,
    /// Contact point y.
    pub yc: f64,
    /// Contour angle at the contact point.
    pub psi: f64,
}

/// The former name of [`SweepRow`].
pub type ObservableRecord = SweepRow;

/// Serialises a phase as its label in the CSV files (`none`, `A`, `B`).
pub fn serialize_phase<S: serde::Serializer>(p: &Phase, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(p.label())
}

impl SweepRow {
    /// The row of the sweep point `p` in `units` (mm, N, N mm for a physical scene): the one
    /// place where a sweep row is scaled for output (CSV, Python).
    pub fn of(p: &SweepPoint, units: &UnitSystem) -> Self {
        let (l, f, m) = (
            units.scale(Quantity::Length),
            units.scale(Quantity::Force),
            units.scale(Quantity::Moment),
        );
        ObservableRecord {
            x0: p.x0 * l,
            ax: p.ax * f,
            ay: p.ay * f,
            ma: p.ma * m,
            phi0: p.phi0,
            f: p.f * f,
            s1: p.s1 * l,
            phase: p.phase,
            xc: p.xc * l,
            yc: p.yc * l,
            psi: p.psi,
        }
    }
}

/// The rows of `observables.csv` (header [`OBSERVABLES_HEADER`]) for sweep points,
/// dimensionless.
pub fn observables_csv(points: &[SweepPoint]) -> Result<CsvWriter, IoError> {
    observables_csv_in(points, &UnitSystem::DIMENSIONLESS)
}

/// The rows of `observables.csv` in `units` (mm, N, N mm for a physical scene).
pub fn observables_csv_in(points: &[SweepPoint], units: &UnitSystem) -> Result<CsvWriter, IoError> {
    let mut w = CsvWriter::new(&OBSERVABLES_HEADER);
    w.push_records(points.iter().map(|p| SweepRow::of(p, units)))?;
    Ok(w)
}
/// Writes `observables.csv` of a sweep in `units` and its units sidecar.
pub fn write_observables_csv(
    res: &SweepResult,
    units: &UnitSystem,
    path: &Path,
) -> Result<(), IoError> {
    observables_csv_in(&res.points, units)?.write(path)?;
    write_units_of(path, &OBSERVABLES_HEADER, &OBSERVABLES_QUANTITIES, units)
}
