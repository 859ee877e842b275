//! Publishing a staged folder: the staging folder takes the place of the output folder with
//! no moment at which the output folder's path leads nowhere or to a half folder.
//!
//! On Linux one `renameat2(RENAME_EXCHANGE)` trades the two folders' places atomically (the
//! old folder then sits at the staging path and is removed after). Where the exchange is not
//! available (`EINVAL`, `ENOSYS`, `ENOTSUP`: another OS, or a file system such as some network
//! ones that lacks it) the portable fallback renames the old folder aside and the staging
//! folder in: a moment (two `rename` calls, microseconds) with no folder at the path, the
//! old one restored if the second rename fails.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// How a folder was published.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Swap {
    /// There was no folder at the path: one rename.
    Renamed,
    /// The two folders traded places atomically (Linux `RENAME_EXCHANGE`).
    Exchanged,
    /// The old folder was renamed aside, then the staging folder in.
    AsideThenIn,
}

/// Puts the folder `staging` at `target`. An existing folder `target` (replaceable: checked
/// by the caller under the lock) ends up at `staging` (exchanged) or at `aside` (the
/// fallback); the caller removes it. Returns how, and where the old folder is (if any).
///
/// # Errors
/// The OS error of the rename that failed; the old folder is then back at `target`.
pub fn publish(staging: &Path, target: &Path, aside: &Path) -> io::Result<(Swap, Option<PathBuf>)> {
    if fs::symlink_metadata(target).is_err() {
        fs::rename(staging, target)?;
        return Ok((Swap::Renamed, None));
    }
    match exchange(staging, target) {
        Ok(()) => return Ok((Swap::Exchanged, Some(staging.to_path_buf()))),
        Err(e) if !unsupported(&e) => return Err(e),
        Err(_) => {}
    }
    aside_then_in(staging, target, aside)?;
    Ok((Swap::AsideThenIn, Some(aside.to_path_buf())))
}

/// The portable swap: `target` renamed to `aside`, `staging` to `target` (and `aside` back
/// if that fails).
///
/// # Errors
/// The OS error of the rename that failed.
pub fn aside_then_in(staging: &Path, target: &Path, aside: &Path) -> io::Result<()> {
    if fs::symlink_metadata(aside).is_ok() {
        fs::remove_dir_all(aside)?;
    }
    fs::rename(target, aside)?;
    if let Err(e) = fs::rename(staging, target) {
        let _ = fs::rename(aside, target);
        return Err(e);
    }
    Ok(())
}

/// Trades the places of `a` and `b` atomically (Linux `renameat2(RENAME_EXCHANGE)`).
///
/// # Errors
/// The OS error; `Unsupported` where there is no such call.
#[cfg(target_os = "linux")]
pub fn exchange(a: &Path, b: &Path) -> io::Result<()> {
    use rustix::fs::{renameat_with, RenameFlags, CWD};
    renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE).map_err(io::Error::from)
}

/// Trades the places of `a` and `b` atomically: not available here.
///
/// # Errors
/// Always `Unsupported`.
#[cfg(not(target_os = "linux"))]
pub fn exchange(_a: &Path, _b: &Path) -> io::Result<()> {
    Err(io::Error::from(io::ErrorKind::Unsupported))
}

/// Whether `e` says the exchange is not available (so the fallback is to be used).
fn unsupported(e: &io::Error) -> bool {
    const EINVAL: i32 = 22;
    const ENOSYS: i32 = 38;
    const EOPNOTSUPP: i32 = 95;
    e.kind() == io::ErrorKind::Unsupported
        || (cfg!(target_os = "linux")
            && matches!(e.raw_os_error(), Some(EINVAL | ENOSYS | EOPNOTSUPP)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(p: &Path, tag: &str) {
        fs::create_dir_all(p).unwrap();
        fs::write(p.join("tag"), tag).unwrap();
    }

    /// Both ways give the same result: the new folder at the path, the old one where the
    /// caller is told; a folder that did not exist is renamed in.
    #[test]
    fn the_new_folder_takes_the_place_of_the_old() {
        let dir = tempfile::tempdir().unwrap();
        let (s, t, a) = (
            dir.path().join(".s"),
            dir.path().join("t"),
            dir.path().join(".a"),
        );
        folder(&s, "new");
        assert_eq!(publish(&s, &t, &a).unwrap(), (Swap::Renamed, None));
        assert_eq!(fs::read_to_string(t.join("tag")).unwrap(), "new");
        folder(&s, "newer");
        let (how, old) = publish(&s, &t, &a).unwrap();
        if cfg!(target_os = "linux") {
            assert_eq!(how, Swap::Exchanged);
        }
        assert_eq!(fs::read_to_string(old.unwrap().join("tag")).unwrap(), "new");
        assert_eq!(fs::read_to_string(t.join("tag")).unwrap(), "newer");
        // the fallback, asked for directly
        fs::remove_dir_all(&s).unwrap();
        folder(&s, "newest");
        aside_then_in(&s, &t, &a).unwrap();
        assert_eq!(fs::read_to_string(t.join("tag")).unwrap(), "newest");
        assert_eq!(fs::read_to_string(a.join("tag")).unwrap(), "newer");
        // a staging folder that is gone: the old folder stays in place
        fs::remove_dir_all(&a).unwrap();
        assert!(aside_then_in(&s, &t, &a).is_err());
        assert_eq!(fs::read_to_string(t.join("tag")).unwrap(), "newest");
    }

    /// Readers that open the folder's file in a loop while it is replaced 200 times by
    /// exchange: never a moment without it.
    #[test]
    fn readers_never_find_no_folder() {
        let dir = tempfile::tempdir().unwrap();
        let (s, t, a) = (
            dir.path().join(".s"),
            dir.path().join("t"),
            dir.path().join(".a"),
        );
        folder(&t, "0");
        let done = std::sync::atomic::AtomicBool::new(false);
        let missing = std::sync::atomic::AtomicUsize::new(0);
        let mut exchanged = true;
        std::thread::scope(|sc| {
            sc.spawn(|| {
                while !done.load(std::sync::atomic::Ordering::Relaxed) {
                    if fs::read_to_string(t.join("tag")).is_err() {
                        missing.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    }
                }
            });
            for i in 1..=200 {
                folder(&s, &i.to_string());
                let (how, old) = publish(&s, &t, &a).unwrap();
                exchanged &= how == Swap::Exchanged;
                fs::remove_dir_all(old.unwrap()).unwrap();
            }
            done.store(true, std::sync::atomic::Ordering::Relaxed);
        });
        assert_eq!(fs::read_to_string(t.join("tag")).unwrap(), "200");
        // (the fallback has its moment without a folder: only the exchange is held to this)
        if exchanged {
            assert_eq!(missing.load(std::sync::atomic::Ordering::Relaxed), 0);
        }
    }
}
