//! [`Scene::reconstruct`]: the flow identified and the contour reconstructed from a log of
//! base observables [ch. 6], with the scene's whisker, in the scene's units (the numbers of
//! `vibrissa reconstruct`'s `reconstruction.csv`).

use std::collections::BTreeMap;
use std::path::PathBuf;

use contact_sim::Phase;
use profile_recon::ReconPoint;
use vibrissa_io::csvio::Table;
use vibrissa_io::recon::{reconstruct_log, ReconFlags, ReconOptions};
use vibrissa_io::recon_io::{recon_values, to_model_units_with, REQUIRED_COLUMNS};
use vibrissa_io::resolve::ModelFlags;
use vibrissa_io::units::{Quantity, UnitSystem};

use crate::io::ObservableLog;
use crate::{Error, Scene, Sweep};

/// The consistency tolerance of a contact row: the command line's `--tolerance` default for
/// the method `accurate` ([`vibrissa_io::recon::DEFAULT_TOLERANCE_ACCURATE`], the one value).
pub use vibrissa_io::recon::DEFAULT_TOLERANCE_ACCURATE as CONSISTENCY_TOLERANCE;

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
    /// sidecar, else the scene's. The computation and its failures are the command line's,
    /// with its defaults ([`vibrissa_io::recon::reconstruct_log`] with
    /// [`ReconFlags::default`]: method `accurate`, flow identified): a row with no consistent
    /// contact point (residual above [`CONSISTENCY_TOLERANCE`]) is [`Error::InvalidInput`]
    /// naming its line, as `vibrissa reconstruct` does.
    pub fn reconstruct(&self, log: &impl Log) -> Result<Reconstruction, Error> {
        let (_, r) = self.resolved(&ModelFlags::default())?;
        let units = r.units();
        let (mut table, given, origin) = log.table();
        let x0_given = to_model_units_with(&mut table, &given, &units, &origin)?;
        let flags = ReconFlags::default();
        let opts = ReconOptions::parse(&flags)?;
        let rec = reconstruct_log(&flags, &opts, &r, &table)?;
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
