//! Atomic file output: a file is either fully written or not there at all.
//!
//! [`write_atomic`] writes one file through a temporary sibling and a rename;
//! [`OutputDir`] stages all files of one command in a temporary sibling directory and moves
//! them into place only when the command succeeded.

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

/// A staged output directory: the files of one command are written into a temporary sibling
/// directory and moved into the final directory by [`OutputDir::commit`]. If the value is
/// dropped without a commit (an error happened), the staging directory is removed and the
/// final directory is left as it was.
#[derive(Debug)]
pub struct OutputDir {
    target: PathBuf,
    staging: PathBuf,
    committed: bool,
}

impl OutputDir {
    /// Prepares the staging directory for the final directory `path` (which may or may not
    /// exist yet; its parent directories are created).
    pub fn create(path: &Path) -> Result<Self, CliError> {
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
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        fs::create_dir_all(&parent).map_err(|e| CliError::io(&parent, e))?;
        let mut staging_name = std::ffi::OsString::from(".");
        staging_name.push(&name);
        staging_name.push(format!(".staging-{}", std::process::id()));
        let staging = parent.join(staging_name);
        if staging.exists() {
            fs::remove_dir_all(&staging).map_err(|e| CliError::io(&staging, e))?;
        }
        fs::create_dir(&staging).map_err(|e| CliError::io(&staging, e))?;
        Ok(OutputDir {
            target: path.to_path_buf(),
            staging,
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

    /// Moves every staged file into the final directory (replacing files of the same name,
    /// leaving others alone) and returns the final paths, sorted.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, CliError> {
        let mut files = Vec::new();
        collect_files(&self.staging, &mut files)?;
        files.sort();
        fs::create_dir_all(&self.target).map_err(|e| CliError::io(&self.target, e))?;
        let mut out = Vec::with_capacity(files.len());
        for f in files {
            let rel = f.strip_prefix(&self.staging).unwrap_or(&f);
            let dest = self.target.join(rel);
            if let Some(parent) = dest.parent() {
                fs::create_dir_all(parent).map_err(|e| CliError::io(parent, e))?;
            }
            fs::rename(&f, &dest).map_err(|e| CliError::io(&dest, e))?;
            out.push(dest);
        }
        sync_dir(&self.target);
        self.committed = true;
        fs::remove_dir_all(&self.staging).map_err(|e| CliError::io(&self.staging, e))?;
        Ok(out)
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.staging);
        }
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
