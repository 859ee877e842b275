//! The lock of an output folder: an operating-system lock on `P/.NAME.lock`
//! (`fs4::FileExt::try_lock_exclusive`; `flock` on Unix), held for the whole run.
//!
//! The OS releases the lock when its process ends, however it ends (SIGKILL included), so a
//! dead writer blocks nothing: the next run locks the file it left. A second writer while
//! the first is alive is refused at once ([`IoError::Locked`]). A run that ends removes the
//! lock file *while it still holds the lock*; a writer that opened the file before it was
//! removed and locked it after finds that the path no longer leads to its file (another
//! inode, or none) and starts again on the path's file, so two writers never hold locks on
//! two different files of one path.

use std::fs;
use std::path::{Path, PathBuf};

use fs4::fs_std::FileExt;

use crate::error::IoError;

/// How many times a lock is tried on a lock file removed under the writer before giving up
/// (each retry follows a writer that finished meanwhile).
const ATTEMPTS: usize = 8;

/// An output folder's lock, held until dropped (then its file is removed, then unlocked).
#[derive(Debug)]
pub struct FolderLock {
    path: PathBuf,
    file: fs::File,
    /// The lock file was there before this run made it: a run before it did not end
    /// normally (its staging folder may be left).
    found: bool,
}

impl FolderLock {
    /// Locks `path` (made if missing) for the output folder `target` (named in errors).
    ///
    /// # Errors
    /// [`IoError::Locked`] if another live process holds it; [`IoError::InvalidArgument`]
    /// (`--out`) if the lock file cannot be made or opened (a read-only folder).
    pub fn acquire(path: &Path, target: &Path) -> Result<Self, IoError> {
        let cannot = |e: std::io::Error| {
            IoError::invalid_argument(
                "--out",
                target.display().to_string(),
                format!(
                    "cannot write an output folder there: its lock file {}: {e}",
                    path.display()
                ),
            )
        };
        for _ in 0..ATTEMPTS {
            let (file, found) = match fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create_new(true)
                .open(path)
            {
                Ok(f) => (f, false),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    match fs::OpenOptions::new().read(true).write(true).open(path) {
                        Ok(f) => (f, true),
                        // removed between the two opens: a writer just finished
                        Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                        Err(e) => return Err(cannot(e)),
                    }
                }
                Err(e) => return Err(cannot(e)),
            };
            match FileExt::try_lock_exclusive(&file) {
                Ok(true) => {}
                Ok(false) => {
                    return Err(IoError::Locked {
                        dir: target.to_path_buf(),
                    })
                }
                Err(e) => return Err(cannot(e)),
            }
            if same_file(&file, path) {
                return Ok(FolderLock {
                    path: path.to_path_buf(),
                    file,
                    found,
                });
            }
            // the file locked was removed by the writer that held it: try the path's file
        }
        Err(IoError::Locked {
            dir: target.to_path_buf(),
        })
    }

    /// Whether the lock file was found there (a run before did not end normally).
    pub fn found_stale(&self) -> bool {
        self.found
    }
}

/// Whether the open `file` is the one at `path` now.
#[cfg(unix)]
fn same_file(file: &fs::File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Whether the open `file` is the one at `path` now (without inode numbers: the path
/// exists; the lock file is then never removed, see [`FolderLock`]'s `Drop`).
#[cfg(not(unix))]
fn same_file(_file: &fs::File, path: &Path) -> bool {
    path.exists()
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // removed while held (see the module's documentation); the lock goes with the file
        // handle. Without inode checks (not Unix) the file stays.
        if cfg!(unix) {
            let _ = fs::remove_file(&self.path);
        }
        let _ = FileExt::unlock(&self.file);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One holder at a time (also within one process: the lock is per open file); released
    /// on drop with its file removed; a lock file left by a dead run is taken and reported.
    #[test]
    fn one_holder_and_a_left_lock_file_is_taken() {
        let dir = tempfile::tempdir().unwrap();
        let lock = dir.path().join(".d.lock");
        let held = FolderLock::acquire(&lock, &dir.path().join("d")).unwrap();
        assert!(!held.found_stale());
        let err = FolderLock::acquire(&lock, &dir.path().join("d")).unwrap_err();
        assert!(matches!(err, IoError::Locked { .. }));
        assert!(
            err.to_string()
                .ends_with("d is being written by another vibrissa process; wait for it to end or choose another --out"),
            "{err}"
        );
        drop(held);
        assert!(!lock.exists());
        // a file left by a killed run: no process holds a lock on it
        fs::write(&lock, "").unwrap();
        let held = FolderLock::acquire(&lock, &dir.path().join("d")).unwrap();
        assert!(held.found_stale());
    }

    /// Writers that take and release the lock in a loop: never two holders at once.
    #[test]
    fn never_two_holders() {
        let dir = tempfile::tempdir().unwrap();
        let lock = dir.path().join(".d.lock");
        let holders = std::sync::atomic::AtomicUsize::new(0);
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| {
                    for _ in 0..200 {
                        if let Ok(l) = FolderLock::acquire(&lock, dir.path()) {
                            let n = holders.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                            assert_eq!(n, 0, "two holders");
                            std::thread::yield_now();
                            holders.fetch_sub(1, std::sync::atomic::Ordering::SeqCst);
                            drop(l);
                        }
                    }
                });
            }
        });
    }
}
