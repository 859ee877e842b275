//! `observables.csv`, the log of a sweep: its header, the quantities of its columns, one
//! row per sweep point ([`ObservableRecord`], also used by the Python bindings) and its
//! writer with the units sidecar.

use std::path::Path;

use contact_sim::{Phase, SlipState, SweepPoint, SweepResult};

use crate::csvio::CsvWriter;
use crate::error::IoError;
use crate::outputs::write_units_of;
use crate::units::{Quantity, UnitSystem};

/// The header of `observables.csv` (spec/cli.md): the thesis's observables, then, after
/// `psi`, the friction (`ft`, `slip`) and the base pose (`y0`, `gamma`) columns of every
/// sweep.
pub const OBSERVABLES_HEADER: [&str; 15] = [
    "x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "phase", "xc", "yc", "psi", "ft", "slip", "y0",
    "gamma",
];
/// The columns of `observables.csv` a log written before friction and base motions had
/// (readers accept logs with or without the later ones).
pub const OBSERVABLES_HEADER_V1: [&str; 11] = [
    "x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "phase", "xc", "yc", "psi",
];
/// The quantities of the `observables.csv` columns.
pub const OBSERVABLES_QUANTITIES: [Quantity; 15] = [
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
    Quantity::Force,
    Quantity::Text,
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
    /// Tangential part of the contact force along the boundary's tangent `(cos psi, sin
    /// psi)` (spec/model.md, "Friction at the contact"; 0 without friction); `f` is the
    /// normal part.
    pub ft: f64,
    /// `none`, `stick` or `slip` (written as [`SlipState::label`]; `none` before contact
    /// and without friction).
    #[serde(serialize_with = "serialize_slip")]
    pub slip: SlipState,
    /// The base's position across the sweep (0 for the translating sweep).
    pub y0: f64,
    /// The base's turn (radians; 0 for the translating sweep).
    pub gamma: f64,
}

/// The former name of [`SweepRow`].
pub type ObservableRecord = SweepRow;

/// Serialises a phase as its label in the CSV files (`none`, `A`, `B`).
pub fn serialize_phase<S: serde::Serializer>(p: &Phase, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(p.label())
}

/// Serialises a slip state as its label in the CSV files (`none`, `stick`, `slip`).
pub fn serialize_slip<S: serde::Serializer>(p: &SlipState, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(p.label())
}

/// The base pose `(y0, gamma)` of a row (spec/model.md, "Base motions"): the translating
/// sweep keeps `y0 = 0`, `gamma = 0` (its rows carry no pose of their own).
pub fn pose_of(_p: &SweepPoint) -> (f64, f64) {
    (0.0, 0.0)
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
            ft: p.ft * f,
            slip: p.slip,
            y0: pose_of(p).0 * l,
            gamma: pose_of(p).1,
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
