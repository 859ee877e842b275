//! Atomic output: a file is either fully written or not there at all, and an output folder
//! is the earlier one or the complete new one, never a mix, never absent.
//!
//! - [`write_atomic`] ([`file`](mod@file)): one file through a temporary sibling
//!   (`tempfile::NamedTempFile::new_in` its folder), flushed (`fsync`) and persisted (renamed)
//!   over the final name; inside a staging folder, in place with its flush started at once.
//! - [`OutputDir`] ([`folder`]): the files of one command staged in a sibling folder and
//!   published as a whole by [`OutputDir::commit`].
//!
//! # The protocol of an output folder `P/NAME`
//!
//! 1. **Symbolic links are followed.** A `--out` that is a symbolic link to a folder writes
//!    into the folder it points to (its real path is staged, locked and swapped); the link
//!    stays a link, pointing at the new folder. A link to nothing or to a file is refused.
//! 2. **Lock.** `P/.NAME.lock` is locked with an operating-system lock
//!    (`fs4::FileExt::try_lock_exclusive`, `flock` on Unix) for the whole run ([`lock`]).
//!    The OS releases it when the process ends, however it ends, so a killed run blocks
//!    nothing; a second writer while the first lives is refused with
//!    [`IoError::Locked`] ("P/NAME is being written by another vibrissa process"). A run
//!    that ends removes the lock file while it still holds the lock (and a writer that
//!    locked a file meanwhile unlinked checks that its file is still the one at the path,
//!    and retries otherwise).
//! 3. **Only our folders are replaced.** Every output folder holds a manifest
//!    `.vibrissa-output` listing the files and folders vibrissa wrote there ([`manifest`]).
//!    An existing `P/NAME` is replaced only if it is empty or every entry in it is listed in
//!    its manifest; otherwise [`IoError::ForeignFile`] names one entry that is not, and
//!    nothing is touched. The check is made when the folder is opened and again just before
//!    the swap (a file added while the command ran is found).
//! 4. **Leftovers of a killed run.** A run killed (SIGKILL, SIGTERM, power loss) leaves its
//!    lock file, its staging folder `P/.NAME.staging-PID` and possibly the earlier folder
//!    set aside, `P/.NAME.old-PID`. The next run that takes the lock and finds the lock
//!    file already there removes every `P/.NAME.staging-*` and `P/.NAME.old-*` that is a
//!    folder holding a manifest (ours by name and by content; with the lock held, no live
//!    writer uses them). Nothing else beside the folder is touched.
//! 5. **Stage.** The command writes into `P/.NAME.staging-PID`; each file's flush
//!    (`fdatasync`) starts at once on a thread of its own ([`file`](mod@file)).
//! 6. **Publish.** [`OutputDir::commit`] writes the manifest, waits for the flushes, flushes
//!    the folders, and swaps the staging folder in ([`swap`]): on Linux by one
//!    `renameat2(RENAME_EXCHANGE)` (an existing `P/NAME` and the staging folder trade
//!    places atomically: a reader opening `P/NAME` finds the old folder or the new one, at
//!    no moment nothing), then the old folder, now at the staging path, is removed. Where
//!    the exchange is not supported (another OS, a file system without it) the portable
//!    fallback renames the old folder aside to `P/.NAME.old-PID` and the staging folder in
//!    (a moment of a few microseconds with no `P/NAME`), restoring the old one if the second
//!    rename fails. A folder that did not exist is published by one rename.
//! 7. A command that fails before the commit removes its staging folder, the parent folders
//!    it made and its lock; the earlier folder is untouched.
//!
//! Everything is flushed to disk before the rename that publishes it (files, folders, the
//! manifest), and the parent folder after it (best effort), so that once a command has
//! exited 0 its folder is on disk, and a power loss at any point leaves the old folder or
//! the complete new one.

pub mod file;
pub mod folder;
pub mod lock;
pub mod manifest;
mod names;
pub mod swap;

pub use file::write_atomic;
pub use folder::{refuse_over_inputs, OutputDir};
pub use manifest::MANIFEST;

#[cfg(doc)]
use crate::IoError;
