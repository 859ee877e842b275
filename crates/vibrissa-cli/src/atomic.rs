//! Atomic file output: a file is either fully written or not there at all.
//!
//! [`write_atomic`] writes one file through a temporary sibling and a rename;
//! [`OutputDir`] stages all files of one command in a temporary sibling directory and swaps it
//! in for the output folder as a whole only when the command succeeded, under a lock file
//! that refuses a second concurrent writer.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::CliError;

/// Writes `contents` to `path` atomically: the bytes go to `<name>.tmp-<pid>` in the same
/// directory, are flushed to disk, and the temporary file is renamed over `path`.
/// On failure the temporary file is removed and `path` is untouched.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), CliError> {
    let name = path.file_name().ok_or_else(|| {
        CliError::io(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
        )
    })?;
    let mut tmp_name = name.to_os_string();
    tmp_name.push(format!(".tmp-{}", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let result = (|| {
        let mut file = fs::File::create(&tmp).map_err(|e| CliError::io(&tmp, e))?;
        file.write_all(contents)
            .map_err(|e| CliError::io(&tmp, e))?;
        file.sync_all().map_err(|e| CliError::io(&tmp, e))?;
        drop(file);
        fs::rename(&tmp, path).map_err(|e| CliError::io(path, e))
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    } else if let Some(parent) = path.parent() {
        sync_dir(parent);
    }
    result
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
}

/// Whether a process with this pid exists (Linux `/proc`; elsewhere assumed alive).
fn process_alive(pid: u32) -> bool {
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        true
    }
}

/// Takes the lock file `lock` exclusively for this process.
fn acquire_lock(lock: &Path, target: &Path) -> Result<(), CliError> {
    // two attempts: the second after removing a stale lock
    for _ in 0..2 {
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(lock)
        {
            Ok(mut f) => {
                let _ = write!(f, "{}", std::process::id());
                return Ok(());
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
                        return Err(CliError::io(
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
                return Err(CliError::invalid_argument(
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
    Err(CliError::io(
        lock,
        std::io::Error::new(std::io::ErrorKind::WouldBlock, "could not take the lock"),
    ))
}

/// Removes the staging folders `.NAME.staging-PID` beside the output `NAME` whose process is
/// gone (a run that was killed); called with the output's lock held.
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
pub fn refuse_over_inputs(out_dir: &Path, inputs: &[(&str, &Path)]) -> Result<(), CliError> {
    let Ok(out) = out_dir.canonicalize() else {
        // a folder that does not exist yet holds no input
        return Ok(());
    };
    for (what, input) in inputs {
        if input.canonicalize().is_ok_and(|i| i.starts_with(&out)) {
            return Err(CliError::invalid_argument(
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
fn replaceable(dir: &Path) -> Result<bool, CliError> {
    if dir.join(MARKER).is_file() {
        return Ok(true);
    }
    let mut entries = fs::read_dir(dir).map_err(|e| CliError::io(dir, e))?;
    Ok(entries.next().is_none())
}

impl OutputDir {
    /// Prepares the staging directory for the final directory `path` (which may or may not
    /// exist yet; its parent directories are created) and takes the folder's lock.
    ///
    /// # Errors
    /// `path` is not a usable directory name, exists as a file, exists as a non-empty folder
    /// not written by vibrissa, or is locked by another running writer.
    pub fn create(path: &Path) -> Result<Self, CliError> {
        if path.as_os_str() == "-" {
            return Err(CliError::invalid_argument(
                "--out",
                "-",
                "an output folder is needed, not standard output (--json prints the summary \
                 to standard output)",
            ));
        }
        let name = path
            .file_name()
            .ok_or_else(|| {
                CliError::io(
                    path,
                    std::io::Error::new(
                        std::io::ErrorKind::InvalidInput,
                        "not usable as an output directory name",
                    ),
                )
            })?
            .to_os_string();
        if path.exists() && !path.is_dir() {
            return Err(CliError::io(
                path,
                std::io::Error::new(
                    std::io::ErrorKind::AlreadyExists,
                    "exists and is not a directory",
                ),
            ));
        }
        if path.is_dir() && !replaceable(path)? {
            return Err(CliError::io(
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
        fs::create_dir_all(&parent).map_err(|e| {
            CliError::invalid_argument(
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
        acquire_lock(&lock, path)?;
        remove_stale_staging(&parent, &name);
        let staging = sibling(&format!(".staging-{}", std::process::id()));
        let prepared = (|| {
            if staging.exists() {
                fs::remove_dir_all(&staging).map_err(|e| CliError::io(&staging, e))?;
            }
            fs::create_dir(&staging).map_err(|e| CliError::io(&staging, e))?;
            fs::write(staging.join(MARKER), b"written by vibrissa\n")
                .map_err(|e| CliError::io(&staging, e))
        })();
        if let Err(e) = prepared {
            let _ = fs::remove_dir_all(&staging);
            let _ = fs::remove_file(&lock);
            return Err(e);
        }
        Ok(OutputDir {
            target: path.to_path_buf(),
            staging,
            lock,
            committed: false,
        })
    }

    /// The final directory.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Where to write the file `name` (relative, e.g. `observables.csv`) before the commit.
    pub fn path_for(&self, name: &str) -> PathBuf {
        self.staging.join(name)
    }

    /// Creates the staged subdirectory `name` and returns its staging path.
    pub fn subdir(&self, name: &str) -> Result<PathBuf, CliError> {
        let p = self.staging.join(name);
        fs::create_dir_all(&p).map_err(|e| CliError::io(&p, e))?;
        Ok(p)
    }

    /// Swaps the staged folder in for the final directory as a whole and returns the final
    /// paths of the files written (the marker excluded), sorted. The earlier folder is
    /// renamed aside first and restored if the swap fails.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, CliError> {
        let mut files = Vec::new();
        collect_files(&self.staging, &mut files)?;
        files.sort();
        sync_dir(&self.staging);
        let old = self.staging.with_file_name(format!(
            ".{}.old-{}",
            self.target_name(),
            std::process::id()
        ));
        let had_old = self.target.exists();
        if had_old {
            if old.exists() {
                fs::remove_dir_all(&old).map_err(|e| CliError::io(&old, e))?;
            }
            fs::rename(&self.target, &old).map_err(|e| CliError::io(&self.target, e))?;
        }
        if let Err(e) = fs::rename(&self.staging, &self.target) {
            if had_old {
                let _ = fs::rename(&old, &self.target);
            }
            return Err(CliError::io(&self.target, e));
        }
        self.committed = true;
        if let Some(parent) = self.target.parent() {
            sync_dir(parent);
        }
        if had_old {
            fs::remove_dir_all(&old).map_err(|e| CliError::io(&old, e))?;
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
        if !self.committed {
            let _ = fs::remove_dir_all(&self.staging);
        }
        let _ = fs::remove_file(&self.lock);
    }
}

fn collect_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), CliError> {
    for entry in fs::read_dir(dir).map_err(|e| CliError::io(dir, e))? {
        let entry = entry.map_err(|e| CliError::io(dir, e))?;
        let p = entry.path();
        let ty = entry.file_type().map_err(|e| CliError::io(&p, e))?;
        if ty.is_dir() {
            collect_files(&p, out)?;
        } else {
            out.push(p);
        }
    }
    Ok(())
}
