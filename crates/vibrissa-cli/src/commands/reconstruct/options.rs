//! The parse step of `vibrissa reconstruct`: its flags as the library's values
//! ([`ReconFlags`], checked by [`ReconOptions`]), and the whisker resolved from the scene file
//! under them ([`recon_model`]); the checks themselves live in `vibrissa_io::recon`.

pub use vibrissa_io::recon::{
    ReconFlags, ReconOptions, DEFAULT_TOLERANCE_ACCURATE, DEFAULT_TOLERANCE_THESIS,
};

use crate::cli::{text, ReconstructArgs};
use crate::error::CliError;
use crate::resolve::{LoadedScene, Resolved};

impl From<&ReconstructArgs> for ReconFlags {
    fn from(args: &ReconstructArgs) -> Self {
        ReconFlags {
            whisker: (&args.whisker).into(),
            q: text(&args.q),
            alpha_deg: text(&args.alpha_deg),
            noise: text(&args.noise),
            method: args.method.clone(),
            tolerance: text(&args.tolerance),
            tol: text(&args.tol),
        }
    }
}

/// The whisker of a reconstruction (and `--q`, if given): the scene file under the flags
/// ([`vibrissa_io::recon::recon_model`]).
pub fn recon_model(
    args: &ReconstructArgs,
    file: Option<LoadedScene>,
) -> Result<Resolved, CliError> {
    Ok(vibrissa_io::recon::recon_model(&args.into(), file)?)
}
