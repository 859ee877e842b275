//! `observables.csv`, the log of a sweep: its header, the quantities of its columns, one
//! row per sweep point ([`ObservableRecord`], also used by the Python bindings) and its
//! writer with the units sidecar.

use std::path::Path;

use contact_sim::{Phase, SlipState, SweepPoint, SweepResult};

use crate::csvio::CsvWriter;
use crate::error::IoError;
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
    /// The follicle stiffness at the row where the motion (a path) sets it, in the scene's
    /// stiffness unit (N m/rad physical, as the scene's `whisker.k`); the column `k` is
    /// written after `gamma` only when some row has it ([`observables_csv_in`]).
    #[serde(skip)]
    pub k: Option<f64>,
}

/// The column `k` of a log whose motion sets the follicle stiffness along the path.
pub const K_COLUMN: &str = "k";

/// The unit of the `k` column in `units`: the scene's stiffness unit (`N m/rad` in a
/// physical scene, as the scene file's `whisker.k`; `1` dimensionless).
pub fn stiffness_unit(units: &UnitSystem) -> &'static str {
    if units.is_physical() {
        "N m/rad"
    } else {
        "1"
    }
}

/// The factor from the model's dimensionless stiffness `k = K L / (E I_b)` [3.19] to the
/// scene's stiffness unit ([`stiffness_unit`]).
pub fn stiffness_scale(units: &UnitSystem) -> f64 {
    units.physical.map_or(1.0, |p| p.moment_scale())
}

/// The header of a log: [`OBSERVABLES_HEADER`], and `k` after it when `with_k`.
pub fn observables_header(with_k: bool) -> Vec<&'static str> {
    let mut h = OBSERVABLES_HEADER.to_vec();
    if with_k {
        h.push(K_COLUMN);
    }
    h
}

/// Writes the units sidecar of a log (header [`observables_header`]`(with_k)`) at `csv`.
pub fn write_observables_units(
    csv: &Path,
    units: &UnitSystem,
    with_k: bool,
) -> Result<(), IoError> {
    let mut u: Vec<&str> = OBSERVABLES_QUANTITIES
        .iter()
        .map(|q| units.unit(*q))
        .collect();
    if with_k {
        u.push(stiffness_unit(units));
    }
    crate::csvio::write_units_sidecar(
        &crate::csvio::units_sidecar_path(csv),
        &observables_header(with_k),
        &u,
    )
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

/// The base pose `(y0, gamma)` of a row (spec/model.md, "Base motions"), dimensionless:
/// the row's own (`y0 = 0`, `gamma = 0` throughout a translation; the base's fixed `y0` and
/// the turn of a rotation; the pose of a path).
pub fn pose_of(p: &SweepPoint) -> (f64, f64) {
    (p.y0, p.gamma)
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
            k: p.k.map(|k| k * stiffness_scale(units)),
        }
    }
}

/// The rows of `observables.csv` (header [`OBSERVABLES_HEADER`]) for sweep points,
/// dimensionless.
pub fn observables_csv(points: &[SweepPoint]) -> Result<CsvWriter, IoError> {
    observables_csv_in(points, &UnitSystem::DIMENSIONLESS)
}

/// The rows of `observables.csv` in `units` (mm, N, N mm for a physical scene); with the
/// column `k` after `gamma` when some row has the follicle stiffness of a path.
pub fn observables_csv_in(points: &[SweepPoint], units: &UnitSystem) -> Result<CsvWriter, IoError> {
    let with_k = points.iter().any(|p| p.k.is_some());
    let mut w = CsvWriter::new(&observables_header(with_k));
    let rows = points.iter().map(|p| SweepRow::of(p, units));
    if with_k {
        w.push_records(rows.map(|r| (r, r.k.unwrap_or(f64::NAN))))?;
    } else {
        w.push_records(rows)?;
    }
    Ok(w)
}
/// Writes `observables.csv` of a sweep in `units` and its units sidecar.
pub fn write_observables_csv(
    res: &SweepResult,
    units: &UnitSystem,
    path: &Path,
) -> Result<(), IoError> {
    observables_csv_in(&res.points, units)?.write(path)?;
    write_observables_units(path, units, res.points.iter().any(|p| p.k.is_some()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A log's pose columns carry each row's pose (`y0` in the length unit, `gamma` in
    /// radians) and, where a path sets it, `k` in the stiffness unit as the 16th column.
    #[test]
    fn pose_and_k_columns_carry_the_rows_values() {
        let p = beam_model::Preset::from_name("beta").unwrap().whisker();
        let u = UnitSystem::new(Some(p));
        let a = SweepPoint {
            x0: 0.1,
            ax: 0.0,
            ay: 0.0,
            ma: 0.0,
            phi0: 1.0,
            f: 0.0,
            s1: 1.0,
            phi1: 1.0,
            phase: Phase::None,
            xc: f64::NAN,
            yc: f64::NAN,
            psi: f64::NAN,
            ft: 0.0,
            slip: SlipState::None,
            slip_distance: 0.0,
            y0: -0.25,
            gamma: 0.3,
            k: None,
        };
        let text = observables_csv_in(&[a], &u).unwrap().as_str().to_string();
        let mut lines = text.lines();
        assert_eq!(lines.next().unwrap(), OBSERVABLES_HEADER.join(","));
        let cells: Vec<f64> = lines
            .next()
            .unwrap()
            .split(',')
            .filter_map(|c| c.parse().ok())
            .collect();
        let row = SweepRow::of(&a, &u);
        assert_eq!(row.y0, -0.25 * u.scale(Quantity::Length));
        assert_eq!(row.gamma, 0.3);
        assert!(cells.contains(&row.y0) && cells.contains(&0.3));
        let mut b = a;
        b.k = Some(20.0);
        let text = observables_csv_in(&[a, b], &u)
            .unwrap()
            .as_str()
            .to_string();
        let mut lines = text.lines();
        assert!(lines.next().unwrap().ends_with(",gamma,k"));
        let k_of = |l: &str| l.rsplit(',').next().unwrap().to_string();
        assert_eq!(k_of(lines.next().unwrap()), "NaN");
        let k: f64 = k_of(lines.next().unwrap()).parse().unwrap();
        // back through [3.19]: the dimensionless stiffness again
        assert!(
            (p.dimensionless_stiffness(k) / 20.0 - 1.0).abs() < 1e-15,
            "{k}"
        );
    }
}
