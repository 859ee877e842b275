//! Reading and writing the library's tables: an observables log from any CSV file
//! ([`read_observables`]), a sweep's `observables.csv` ([`write_observables`]); the
//! lower layers (scene files, units, CSV, output folders) are [`vibrissa_io`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use vibrissa_io::csvio::{read_table, read_units_sidecar, units_sidecar_path, Table};
use vibrissa_io::observables::write_observables_csv;
use vibrissa_io::recon_io::REQUIRED_COLUMNS;

use crate::{Error, Sweep};

/// A log of base observables read from a CSV file: the columns x0, Ax, Ay, MA, phi0 (any
/// order, other columns ignored; comma, tab or semicolon separated), as given, with the
/// units of its sidecar `NAME.units.csv` if it has one. [`crate::Scene::reconstruct`]
/// converts it with them (else with the scene's units).
#[derive(Debug, Clone, PartialEq)]
pub struct ObservableLog {
    pub(crate) table: Table,
    pub(crate) units: Option<BTreeMap<String, String>>,
    pub(crate) sidecar: PathBuf,
}

impl ObservableLog {
    /// The file read.
    pub fn path(&self) -> &Path {
        &self.table.path
    }

    /// The number of data rows.
    pub fn len(&self) -> usize {
        self.table.rows()
    }

    /// Whether the log has no data row.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A numeric column by its header name (`x0`, `Ax`, ...), as given in the file.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.table.column(name)
    }

    /// The units of the columns from the sidecar (column -> unit), if there is one.
    pub fn units(&self) -> Option<&BTreeMap<String, String>> {
        self.units.as_ref()
    }
}

/// Reads an observables log (at least two rows of x0, Ax, Ay, MA, phi0) and its units
/// sidecar; a malformed file is [`Error::InvalidInput`] naming its line and column.
///
/// ```no_run
/// let log = vibrissa::io::read_observables("out/g1/observables.csv")?;
/// let scene = vibrissa::Scene::load("out/g1/scene.ron")?;
/// let rec = scene.reconstruct(&log)?;
/// println!("q = {}, {} contact points", rec.q, rec.rows.len());
/// # Ok::<(), vibrissa::Error>(())
/// ```
pub fn read_observables(path: impl AsRef<Path>) -> Result<ObservableLog, Error> {
    let path = path.as_ref();
    let table = read_table(path, &REQUIRED_COLUMNS, 2)?;
    let sidecar = units_sidecar_path(path);
    let units = read_units_sidecar(&sidecar)?;
    Ok(ObservableLog {
        table,
        units,
        sidecar,
    })
}

/// Writes a sweep's `observables.csv` at `path` (atomically) with its units sidecar, as
/// `vibrissa sweep` writes it.
pub fn write_observables(sweep: &Sweep, path: impl AsRef<Path>) -> Result<(), Error> {
    Ok(write_observables_csv(
        sweep.result(),
        sweep.units(),
        path.as_ref(),
    )?)
}
