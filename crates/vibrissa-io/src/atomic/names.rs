//! The name of an output folder's manifest, apart from the code that reads and writes it
//! ([`super::manifest`]): the error that refuses a folder names it ([`IoError::ForeignFile`]),
//! and the error type is what the manifest's code returns, so the name sits in a module that
//! depends on neither.

#[cfg(doc)]
use crate::IoError;

/// The manifest's file name, in the output folder itself.
pub const MANIFEST: &str = ".vibrissa-output";
