//! The compute step of `vibrissa reconstruct`: the log's rows handed to the library
//! (`vibrissa_io::recon::reconstruct_log`: identification of the flow, then every contact
//! row on its own, each failure named by its culprit).

use profile_recon::Reconstruction;

use super::options::ReconOptions;
use crate::cli::ReconstructArgs;
use crate::csvio::Table;
use crate::error::CliError;
use crate::resolve::Resolved;

pub use vibrissa_io::recon::rows_of;

/// Identifies the flow (unless given) and reconstructs every contact row of the log
/// `table` (already in the model's dimensionless variables) with the whisker of `r`.
pub fn reconstruct_log(
    args: &ReconstructArgs,
    opts: &ReconOptions,
    r: &Resolved,
    table: &Table,
) -> Result<Reconstruction, CliError> {
    Ok(vibrissa_io::recon::reconstruct_log(
        &args.into(),
        opts,
        r,
        table,
    )?)
}
