//! One file written atomically ([`write_atomic`]), and the files of a staging folder,
//! written in place with their flushes started at once.
//!
//! Outside a staging folder a file goes through a temporary sibling
//! (`tempfile::NamedTempFile::new_in` its folder: a unique name, removed if anything fails),
//! is flushed to disk (`fsync`) and persisted over the final name (a rename), and the folder
//! is flushed so that the rename is durable: a reader or a crash sees the old file or the
//! new one, never a half-written one.
//!
//! Inside the staging folder of an [`OutputDir`] a file is written in place,
//! without a temporary or a rename: the staging folder is already the temporary, seen by no
//! one until the commit. Its flush starts at once on a thread of its own (a flush waits on the
//! disk, not on the processor; such threads are not a compute pool's work), while the command
//! goes on writing the other files and drawing its figures; the commit waits for these
//! flushes, flushes the folder's other files and its directories (together, one thread each),
//! and only then publishes the folder. The flushes wait together instead of in turn (the block
//! layer merges concurrent cache flushes), each no longer behind the others and the disk's
//! other traffic (measured in `docs/performance.md`: the 200-point sweep's process).

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::thread::JoinHandle;

#[cfg(doc)]
use super::OutputDir;
use crate::error::IoError;

/// At most this many files of one staging folder are flushed at once (a command that
/// writes hundreds of files, as `cargo xtask reproduce` does, does not start hundreds of
/// threads): a file written while as many flushes are under way is left to the commit,
/// which flushes the rest on as many threads.
pub(crate) const MAX_FLUSHES: usize = 16;

/// A flush under way: the file and the thread that flushes it.
pub(crate) type Flush = (PathBuf, JoinHandle<std::io::Result<()>>);

/// The staging folders of this process's uncommitted [`OutputDir`]s, each with the flushes
/// of its files started by [`write_atomic`].
static STAGING: Mutex<Vec<(PathBuf, Vec<Flush>)>> = Mutex::new(Vec::new());

pub(crate) fn staging_dirs() -> std::sync::MutexGuard<'static, Vec<(PathBuf, Vec<Flush>)>> {
    STAGING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Whether `path` lies in the staging folder of an uncommitted [`OutputDir`].
pub(crate) fn is_staged(path: &Path) -> bool {
    staging_dirs().iter().any(|(s, _)| path.starts_with(s))
}

/// The flushes started in the staging folder `staging`, taken out of the registry (and
/// the folder with them if `unregister`).
pub(crate) fn take_flushes(staging: &Path, unregister: bool) -> Vec<Flush> {
    let mut staged = staging_dirs();
    let Some(i) = staged.iter().position(|(s, _)| s == staging) else {
        return Vec::new();
    };
    if unregister {
        staged.swap_remove(i).1
    } else {
        std::mem::take(&mut staged[i].1)
    }
}

/// Writes `contents` to `path` atomically: the bytes go to a temporary sibling
/// (`tempfile::NamedTempFile::new_in` the same folder), are flushed to disk, and the
/// temporary is persisted (renamed) over `path`; the folder is then flushed (best effort).
/// On failure the temporary file is removed and `path` is untouched.
///
/// A path in the staging folder of an [`OutputDir`] ([`OutputDir::path_for`], also in a
/// folder made there) is written in place, its flush started on a thread of its own
/// and waited for by [`OutputDir::commit`] (see the module's documentation); on failure
/// the partial file is removed.
///
/// # Errors
/// [`IoError::Io`] naming `path` (a path without a file name, a folder that does not
/// exist or cannot be written, a full disk).
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), IoError> {
    if is_staged(path) {
        return write_staged(path, contents);
    }
    let name = path.file_name().ok_or_else(|| {
        IoError::io(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
        )
    })?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(name);
    prefix.push(".");
    let mut tmp = tempfile::Builder::new()
        .prefix(&prefix)
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(|e| IoError::io(path, e))?;
    tmp.write_all(contents).map_err(|e| IoError::io(path, e))?;
    tmp.as_file().sync_all().map_err(|e| IoError::io(path, e))?;
    // (a failed persist drops the temporary, which removes it)
    tmp.persist(path).map_err(|e| IoError::io(path, e.error))?;
    sync_dir(dir);
    Ok(())
}

/// Writes a file of a staging folder in place and starts its flush (see [`write_atomic`]);
/// on failure the partial file is removed. A flush that cannot be started on a thread is
/// left to the commit.
pub(crate) fn write_staged(path: &Path, contents: &[u8]) -> Result<(), IoError> {
    let written = fs::File::create(path).and_then(|mut f| {
        f.write_all(contents)?;
        Ok(f)
    });
    let file = written.map_err(|e| {
        let _ = fs::remove_file(path);
        IoError::io(path, e)
    })?;
    let mut staged = staging_dirs();
    let Some((_, flushes)) = staged.iter_mut().find(|(s, _)| path.starts_with(s)) else {
        return Ok(());
    };
    if flushes.iter().filter(|(_, h)| !h.is_finished()).count() >= MAX_FLUSHES {
        return Ok(());
    }
    let flush = std::thread::Builder::new()
        .name("vibrissa-flush".to_string())
        .spawn(move || file.sync_data());
    if let Ok(handle) = flush {
        flushes.push((path.to_path_buf(), handle));
    }
    Ok(())
}

/// Waits for the flushes `started` and flushes `files` (contents and size) and `dirs`
/// (their entries), all at once: the files shared out over at most [`MAX_FLUSHES`]
/// threads, the directories on this one.
///
/// # Errors
/// The first file (of `started`, then of `files`) that cannot be opened or flushed;
/// directory syncs are best effort.
pub(crate) fn sync_batch(
    started: Vec<Flush>,
    files: &[PathBuf],
    dirs: &[PathBuf],
) -> Result<(), IoError> {
    let sync = |f: &PathBuf| {
        fs::File::open(f)
            .and_then(|file| file.sync_data())
            .map_err(|e| IoError::io(f, e))
    };
    let chunk = files.len().div_ceil(MAX_FLUSHES).max(1);
    std::thread::scope(|s| {
        // a chunk whose thread cannot be started is flushed on this one
        let files: Vec<_> = files
            .chunks(chunk)
            .map(|c| {
                std::thread::Builder::new()
                    .spawn_scoped(s, move || c.iter().try_for_each(sync))
                    .map_err(|_| c)
            })
            .collect();
        // the directories on this thread, which would only wait otherwise
        dirs.iter().for_each(|d| sync_dir(d));
        let mut result = Ok(());
        for (path, h) in started {
            let r = h.join().unwrap_or_else(|p| std::panic::resume_unwind(p));
            result = result.and(r.map_err(|e| IoError::io(path, e)));
        }
        for h in files {
            result = result.and(match h {
                Ok(h) => h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
                Err(c) => c.iter().try_for_each(sync),
            });
        }
        result
    })
}

/// Best-effort fsync of a directory so that a rename in it is durable.
pub(crate) fn sync_dir(dir: &Path) {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atomic::OutputDir;

    #[test]
    fn staged_files_are_written_in_place_and_others_through_a_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let out = OutputDir::create(&dir.path().join("run")).unwrap();
        let staged = out.path_for("a.csv");
        assert!(is_staged(&staged));
        assert!(!is_staged(&dir.path().join("a.csv")));
        write_atomic(&staged, b"x,y\n").unwrap();
        let sub = out.path_for("fig");
        fs::create_dir_all(&sub).unwrap();
        assert!(is_staged(&sub.join("f.svg")));
        write_atomic(&sub.join("f.svg"), b"<svg/>").unwrap();
        // a failed staged write names the file and leaves none behind
        let err = write_atomic(&out.path_for("missing/b.csv"), b"1").unwrap_err();
        assert!(err.to_string().contains("missing/b.csv"), "{err}");
        assert!(!out.path_for("missing/b.csv").exists());
        // a.csv's and f.svg's flushes are under way, for the commit to wait for
        let under_way = |dir: &Path| {
            staging_dirs()
                .iter()
                .find(|(s, _)| s == dir)
                .map(|(_, f)| f.iter().map(|(p, _)| p.clone()).collect::<Vec<_>>())
        };
        assert_eq!(
            under_way(&out.path_for("")),
            Some(vec![staged.clone(), sub.join("f.svg")])
        );
        let files = out.commit().unwrap();
        assert_eq!(
            files,
            vec![
                dir.path().join("run/a.csv"),
                dir.path().join("run/fig/f.svg")
            ]
        );
        // committed: the folder is no longer a staging folder
        assert!(!is_staged(&staged));
        assert_eq!(fs::read(dir.path().join("run/a.csv")).unwrap(), b"x,y\n");
    }

    /// Hundreds of files: never more than [`MAX_FLUSHES`] flushes under way; the commit
    /// flushes the others and publishes them all.
    #[test]
    fn flushes_under_way_are_bounded() {
        let dir = tempfile::tempdir().unwrap();
        let out = OutputDir::create(&dir.path().join("many")).unwrap();
        for i in 0..200 {
            write_atomic(&out.path_for(&format!("f{i}.csv")), b"1\n").unwrap();
            let under_way = staging_dirs()
                .iter()
                .find(|(s, _)| *s == out.path_for(""))
                .map_or(0, |(_, f)| {
                    f.iter().filter(|(_, h)| !h.is_finished()).count()
                });
            assert!(under_way <= MAX_FLUSHES, "{under_way}");
        }
        assert_eq!(out.commit().unwrap().len(), 200);
    }

    #[test]
    fn a_batch_sync_names_a_file_it_cannot_open() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a");
        fs::write(&a, "1").unwrap();
        sync_batch(
            Vec::new(),
            std::slice::from_ref(&a),
            &[dir.path().to_path_buf()],
        )
        .unwrap();
        let gone = dir.path().join("gone");
        let err = sync_batch(Vec::new(), &[a, gone], &[])
            .unwrap_err()
            .to_string();
        assert!(err.contains("gone"), "{err}");
    }

    /// A file outside a staging folder: replaced whole, no temporary left beside it, and a
    /// failure names the file and leaves nothing.
    #[test]
    fn a_file_is_replaced_whole_through_a_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "two");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
        let err = write_atomic(&dir.path().join("missing/a.txt"), b"x").unwrap_err();
        assert!(err.to_string().contains("missing/a.txt"), "{err}");
        assert!(matches!(err, IoError::Io { .. }));
        // a read-only folder: refused, the file there untouched
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            fs::set_permissions(dir.path(), fs::Permissions::from_mode(0o555)).unwrap();
            let refused = write_atomic(&p, b"three");
            fs::set_permissions(dir.path(), fs::Permissions::from_mode(0o755)).unwrap();
            // (root may write anyway)
            if refused.is_err() {
                assert_eq!(fs::read_to_string(&p).unwrap(), "two");
            }
            assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
        }
    }
}
