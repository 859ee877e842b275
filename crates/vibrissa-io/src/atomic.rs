//! Atomic file output: a file is either fully written or not there at all.
//!
//! [`write_atomic`] writes one file through a temporary sibling and a rename;
//! [`OutputDir`] stages all files of one command in a temporary sibling directory and swaps it
//! in for the output folder as a whole only when the command succeeded, under a lock file
//! that refuses a second concurrent writer.
//!
//! # What a staged output folder guarantees
//!
//! - **Atomicity**: the folder is published by one `rename` of the staging folder; a reader
//!   (or a crash) sees the earlier folder or the complete new one, never a mix of both and
//!   never a half-written file. A command that fails before [`OutputDir::commit`] leaves the
//!   earlier folder untouched and removes its staging folder (a killed run's staging folder
//!   is removed by the next run into the same place).
//! - **Durability**: before that rename, every file of the staging folder is flushed to
//!   disk (`fdatasync`: contents and size) and every staging directory too (`fsync`, best
//!   effort); after it, the parent directory is synced (best effort). So once the command
//!   has exited 0 the new folder is on disk, and a power loss at any point leaves the old
//!   folder or the complete new one.
//!
//! Inside the staging folder [`write_atomic`] writes a file in place, without a temporary
//! file or a rename: the staging folder is already the temporary, seen by no one until the
//! commit. Its flush starts at once on a thread of its own (a flush waits on the disk, not
//! on the processor), while the command goes on writing the other files and drawing its
//! figures; [`OutputDir::commit`] waits for these flushes, flushes the folder's other files
//! and its directories (together, one thread each), and only then renames the folder into
//! place. The flushes wait together instead of in turn (the block layer merges concurrent
//! cache flushes), each no longer behind the others and the disk's other traffic.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::thread::JoinHandle;

use crate::error::IoError;

/// At most this many files of one staging folder are flushed at once (a command that
/// writes hundreds of files, as `cargo xtask reproduce` does, does not start hundreds of
/// threads): a file written while as many flushes are under way is left to the commit,
/// which flushes the rest on as many threads.
const MAX_FLUSHES: usize = 16;

/// A flush under way: the file and the thread that flushes it.
type Flush = (PathBuf, JoinHandle<std::io::Result<()>>);

/// The staging folders of this process's uncommitted [`OutputDir`]s, each with the flushes
/// of its files started by [`write_atomic`].
static STAGING: Mutex<Vec<(PathBuf, Vec<Flush>)>> = Mutex::new(Vec::new());

fn staging_dirs() -> std::sync::MutexGuard<'static, Vec<(PathBuf, Vec<Flush>)>> {
    STAGING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Whether `path` lies in the staging folder of an uncommitted [`OutputDir`].
fn is_staged(path: &Path) -> bool {
    staging_dirs().iter().any(|(s, _)| path.starts_with(s))
}

/// The flushes started in the staging folder `staging`, taken out of the registry (and
/// the folder with them if `unregister`).
fn take_flushes(staging: &Path, unregister: bool) -> Vec<Flush> {
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

/// Writes `contents` to `path` atomically: the bytes go to `<name>.tmp-<pid>` in the same
/// directory, are flushed to disk, and the temporary file is renamed over `path`.
/// On failure the temporary file is removed and `path` is untouched.
///
/// A path in the staging folder of an [`OutputDir`] ([`OutputDir::path_for`], also in a
/// folder made there) is written in place, its flush started on a thread of its own
/// and waited for by [`OutputDir::commit`] (see the module's documentation); on failure
/// the partial file is removed.
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
    let mut tmp_name = name.to_os_string();
    tmp_name.push(format!(".tmp-{}", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let result = (|| {
        let mut file = fs::File::create(&tmp).map_err(|e| IoError::io(&tmp, e))?;
        file.write_all(contents).map_err(|e| IoError::io(&tmp, e))?;
        file.sync_all().map_err(|e| IoError::io(&tmp, e))?;
        drop(file);
        fs::rename(&tmp, path).map_err(|e| IoError::io(path, e))
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    } else if let Some(parent) = path.parent() {
        sync_dir(parent);
    }
    result
}

/// Writes a file of a staging folder in place and starts its flush (see [`write_atomic`]);
/// on failure the partial file is removed. A flush that cannot be started on a thread is
/// left to the commit.
fn write_staged(path: &Path, contents: &[u8]) -> Result<(), IoError> {
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
fn sync_batch(started: Vec<Flush>, files: &[PathBuf], dirs: &[PathBuf]) -> Result<(), IoError> {
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
fn sync_dir(dir: &Path) {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// The marker file of a folder written by `vibrissa`: only such a folder (or an empty one)
/// is replaced by a later run; any other existing folder is refused, so that `--out ~` cannot
/// delete a user's files.
pub const MARKER: &str = ".vibrissa-output";

/// A staged output directory: the files of one command are written into a temporary sibling
/// directory, which [`OutputDir::commit`] swaps in for the final directory as a whole (the
/// old folder is renamed aside, the staging folder renamed into place, the old one removed):
/// nothing of an earlier run is left mixed in, and a failure before the commit leaves the old
/// folder untouched. A lock file `.<name>.lock` beside the folder, created exclusively with
/// the writer's pid, refuses a second concurrent writer (a lock whose process is gone is
/// taken over). If the value is dropped without a commit, the staging directory and the
/// lock are removed.
#[derive(Debug)]
pub struct OutputDir {
    target: PathBuf,
    staging: PathBuf,
    lock: PathBuf,
    committed: bool,
    /// The parent folders made for it, deepest first: removed (where still empty) when
    /// the command fails, so that a failed command leaves nothing behind.
    made_parents: Vec<PathBuf>,
}

/// Whether a process with this pid exists (Linux `/proc`; elsewhere assumed alive).
fn process_alive(pid: u32) -> bool {
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        true
    }
}

/// Takes the lock file `lock` exclusively for this process; `true` if it took over the
/// stale lock of a process that is gone (a killed run, which may have left its staging
/// folder behind).
fn acquire_lock(lock: &Path, target: &Path) -> Result<bool, IoError> {
    // two attempts: the second after removing a stale lock
    for attempt in 0..2 {
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(lock)
        {
            Ok(mut f) => {
                let _ = write!(f, "{}", std::process::id());
                return Ok(attempt > 0);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let holder = fs::read_to_string(lock)
                    .ok()
                    .and_then(|s| s.trim().parse::<u32>().ok());
                match holder {
                    Some(pid) if !process_alive(pid) => {
                        let _ = fs::remove_file(lock);
                    }
                    _ => {
                        return Err(IoError::io(
                            target,
                            std::io::Error::new(
                                std::io::ErrorKind::WouldBlock,
                                format!(
                                    "is being written by another vibrissa process{} (lock file {}); wait for it or choose another --out",
                                    holder.map_or(String::new(), |p| format!(" (pid {p})")),
                                    lock.display()
                                ),
                            ),
                        ));
                    }
                }
            }
            Err(e) => {
                return Err(IoError::invalid_argument(
                    "--out",
                    target.display().to_string(),
                    format!(
                        "cannot write an output folder there (its lock file {}: {e})",
                        lock.display()
                    ),
                ))
            }
        }
    }
    Err(IoError::io(
        lock,
        std::io::Error::new(std::io::ErrorKind::WouldBlock, "could not take the lock"),
    ))
}

/// Removes the staging folders `.NAME.staging-PID` beside the output `NAME` whose process is
/// gone (a run that was killed); called with the output's lock held, after taking over a
/// stale lock: a run removes its staging folder before its lock, so a killed run leaves
/// both, and a folder without a stale lock beside it needs no scan of its parent.
fn remove_stale_staging(parent: &Path, name: &std::ffi::OsStr) {
    let prefix = format!(".{}.staging-", name.to_string_lossy());
    let Ok(entries) = fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(pid) = file
            .to_str()
            .and_then(|f| f.strip_prefix(&prefix))
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        if pid != std::process::id() && !process_alive(pid) {
            let _ = fs::remove_dir_all(entry.path());
        }
    }
}

/// Refuses an output folder that holds one of the files the command reads (`inputs`: what
/// it is, its path): the output folder is replaced as a whole, so it would destroy its own
/// input.
pub fn refuse_over_inputs(out_dir: &Path, inputs: &[(&str, &Path)]) -> Result<(), IoError> {
    let Ok(out) = out_dir.canonicalize() else {
        // a folder that does not exist yet holds no input
        return Ok(());
    };
    for (what, input) in inputs {
        if input.canonicalize().is_ok_and(|i| i.starts_with(&out)) {
            return Err(IoError::invalid_argument(
                "--out",
                out_dir.display().to_string(),
                format!(
                    "it holds the {what} being read ({}); the output folder is replaced as a \
                     whole: choose another folder",
                    input.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Whether `dir` may be replaced: empty, or written by vibrissa (has [`MARKER`]).
fn replaceable(dir: &Path) -> Result<bool, IoError> {
    if dir.join(MARKER).is_file() {
        return Ok(true);
    }
    let mut entries = fs::read_dir(dir).map_err(|e| IoError::io(dir, e))?;
    Ok(entries.next().is_none())
}

impl OutputDir {
    /// Prepares the staging directory for the final directory `path` (which may or may not
    /// exist yet; its parent directories are created) and takes the folder's lock.
    ///
    /// # Errors
    /// `path` is not a usable directory name, exists as a file, exists as a non-empty folder
    /// not written by vibrissa, or is locked by another running writer.
    pub fn create(path: &Path) -> Result<Self, IoError> {
        if path.as_os_str() == "-" {
            return Err(IoError::invalid_argument(
                "--out",
                "-",
                "an output folder is needed, not standard output (--json prints the summary \
                 to standard output)",
            ));
        }
        let name = path
            .file_name()
            .ok_or_else(|| {
                IoError::io(
                    path,
                    std::io::Error::new(
                        std::io::ErrorKind::InvalidInput,
                        "not usable as an output directory name",
                    ),
                )
            })?
            .to_os_string();
        if path.exists() && !path.is_dir() {
            return Err(IoError::io(
                path,
                std::io::Error::new(
                    std::io::ErrorKind::AlreadyExists,
                    "exists and is not a directory",
                ),
            ));
        }
        if path.is_dir() && !replaceable(path)? {
            return Err(IoError::io(
                path,
                std::io::Error::new(
                    std::io::ErrorKind::AlreadyExists,
                    "exists, is not empty and was not written by vibrissa; refusing to replace it",
                ),
            ));
        }
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let made_parents: Vec<PathBuf> = parent
            .ancestors()
            .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
            .map(Path::to_path_buf)
            .collect();
        fs::create_dir_all(&parent).map_err(|e| {
            IoError::invalid_argument(
                "--out",
                path.display().to_string(),
                format!("cannot create the folder {} for it: {e}", parent.display()),
            )
        })?;
        let sibling = |suffix: &str| {
            let mut n = std::ffi::OsString::from(".");
            n.push(&name);
            n.push(suffix);
            parent.join(n)
        };
        let lock = sibling(".lock");
        if acquire_lock(&lock, path)? {
            remove_stale_staging(&parent, &name);
        }
        let staging = sibling(&format!(".staging-{}", std::process::id()));
        let prepared = (|| {
            if staging.exists() {
                fs::remove_dir_all(&staging).map_err(|e| IoError::io(&staging, e))?;
            }
            fs::create_dir(&staging).map_err(|e| IoError::io(&staging, e))?;
            staging_dirs().push((staging.clone(), Vec::new()));
            write_staged(&staging.join(MARKER), b"written by vibrissa\n")
        })();
        let dir = OutputDir {
            target: path.to_path_buf(),
            staging,
            lock,
            committed: false,
            made_parents,
        };
        // (a failure here drops `dir`: its staging folder, lock and parents go)
        prepared.map(|()| dir)
    }

    /// The final directory.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Where to write the file `name` (relative, e.g. `observables.csv`) before the commit.
    pub fn path_for(&self, name: &str) -> PathBuf {
        self.staging.join(name)
    }

    /// Swaps the staged folder in for the final directory as a whole and returns the final
    /// paths of the files written (the marker excluded), sorted. The earlier folder is
    /// renamed aside first and restored if the swap fails.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, IoError> {
        let mut files = Vec::new();
        let mut dirs = vec![self.staging.clone()];
        collect_files(&self.staging, &mut files, &mut dirs)?;
        files.sort();
        // every file and directory on disk before the rename publishes them
        let started = take_flushes(&self.staging, false);
        let rest: Vec<PathBuf> = files
            .iter()
            .filter(|f| !started.iter().any(|(p, _)| p == *f))
            .cloned()
            .collect();
        sync_batch(started, &rest, &dirs)?;
        let old = self.staging.with_file_name(format!(
            ".{}.old-{}",
            self.target_name(),
            std::process::id()
        ));
        let had_old = self.target.exists();
        if had_old {
            if old.exists() {
                fs::remove_dir_all(&old).map_err(|e| IoError::io(&old, e))?;
            }
            fs::rename(&self.target, &old).map_err(|e| IoError::io(&self.target, e))?;
        }
        if let Err(e) = fs::rename(&self.staging, &self.target) {
            if had_old {
                let _ = fs::rename(&old, &self.target);
            }
            return Err(IoError::io(&self.target, e));
        }
        self.committed = true;
        if let Some(parent) = self.target.parent() {
            sync_dir(parent);
        }
        if had_old {
            fs::remove_dir_all(&old).map_err(|e| IoError::io(&old, e))?;
        }
        let out = files
            .iter()
            .filter(|f| f.file_name().is_none_or(|n| n != MARKER))
            .map(|f| {
                let rel = f.strip_prefix(&self.staging).unwrap_or(f);
                self.target.join(rel)
            })
            .collect();
        Ok(out)
    }

    fn target_name(&self) -> String {
        self.target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        // flushes still under way finish on their own (a failed command's staging
        // folder is removed under them)
        drop(take_flushes(&self.staging, true));
        if !self.committed {
            let _ = fs::remove_dir_all(&self.staging);
        }
        let _ = fs::remove_file(&self.lock);
        if !self.committed {
            // deepest first; a folder something else wrote into meanwhile stays
            for p in &self.made_parents {
                let _ = fs::remove_dir(p);
            }
        }
    }
}

/// The files under `dir` into `out` and its subdirectories into `dirs` (parents first).
fn collect_files(
    dir: &Path,
    out: &mut Vec<PathBuf>,
    dirs: &mut Vec<PathBuf>,
) -> Result<(), IoError> {
    for entry in fs::read_dir(dir).map_err(|e| IoError::io(dir, e))? {
        let entry = entry.map_err(|e| IoError::io(dir, e))?;
        let p = entry.path();
        let ty = entry.file_type().map_err(|e| IoError::io(&p, e))?;
        if ty.is_dir() {
            dirs.push(p.clone());
            collect_files(&p, out, dirs)?;
        } else {
            out.push(p);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
        // the marker's, a.csv's and f.svg's flushes are under way, for the commit to wait for
        let under_way = |dir: &Path| {
            staging_dirs()
                .iter()
                .find(|(s, _)| s == dir)
                .map(|(_, f)| f.iter().map(|(p, _)| p.clone()).collect::<Vec<_>>())
        };
        assert_eq!(
            under_way(&out.path_for("")),
            Some(vec![
                out.path_for(MARKER),
                staged.clone(),
                sub.join("f.svg")
            ])
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

    #[test]
    fn only_a_stale_lock_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let lock = dir.path().join(".d.lock");
        assert!(!acquire_lock(&lock, dir.path()).unwrap());
        // held by this (live) process: refused
        assert!(acquire_lock(&lock, dir.path()).is_err());
        if cfg!(target_os = "linux") {
            // pid 4194304 is above Linux's pid_max: no live process has it
            fs::write(&lock, "4194304").unwrap();
            assert!(acquire_lock(&lock, dir.path()).unwrap());
        }
    }
}
