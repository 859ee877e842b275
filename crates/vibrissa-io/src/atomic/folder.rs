//! [`OutputDir`]: the files of one command staged in a sibling folder and published as a
//! whole (the protocol is in the documentation of [`crate::atomic`]).

use std::ffi::{OsStr, OsString};
use std::fs;
use std::path::{Path, PathBuf};

use super::file::{staging_dirs, sync_batch, sync_dir, take_flushes};
use super::lock::FolderLock;
use super::manifest::{self, MANIFEST};
use super::swap;
use crate::error::IoError;

/// A staged output directory: the files of one command are written into a staging folder
/// beside the final one, which [`OutputDir::commit`] swaps in for it as a whole: nothing of
/// an earlier run is left mixed in, and a failure before the commit leaves the old folder
/// untouched. The folder's OS lock ([`super::lock`]) is held until the value is dropped; if
/// it is dropped without a commit, the staging folder and the parent folders made for it
/// are removed.
#[derive(Debug)]
pub struct OutputDir {
    /// The folder as the user named it (the files returned by the commit are under it).
    target: PathBuf,
    /// Where it really is (a symbolic link followed): what is locked, staged and swapped.
    real: PathBuf,
    staging: PathBuf,
    committed: bool,
    /// The parent folders made for it, deepest first: removed (where still empty) when
    /// the command fails, so that a failed command leaves nothing behind.
    made_parents: Vec<PathBuf>,
    /// Released in `drop` after the staging folder is gone (before another writer may
    /// start) and before the parent folders made for it are removed (it is a file in one).
    lock: Option<FolderLock>,
}

/// `P/.NAME<suffix>`, a sibling of `P/NAME`.
fn sibling(parent: &Path, name: &OsStr, suffix: &str) -> PathBuf {
    let mut n = OsString::from(".");
    n.push(name);
    n.push(suffix);
    parent.join(n)
}

/// Removes the leftovers of killed runs into `P/NAME`: the folders `P/.NAME.staging-*` and
/// `P/.NAME.old-*` that hold a manifest. Called with the lock held (so none of them is in
/// use). Returns how many were removed.
fn remove_leftovers(parent: &Path, name: &OsStr) -> usize {
    let prefixes = [
        format!(".{}.staging-", name.to_string_lossy()),
        format!(".{}.old-", name.to_string_lossy()),
    ];
    let Ok(entries) = fs::read_dir(parent) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let file = entry.file_name();
        let ours = file
            .to_str()
            .is_some_and(|f| prefixes.iter().any(|p| f.starts_with(p.as_str())));
        let path = entry.path();
        if ours
            && entry.file_type().is_ok_and(|t| t.is_dir())
            && manifest::has_manifest(&path)
            && fs::remove_dir_all(&path).is_ok()
        {
            removed += 1;
        }
    }
    removed
}

/// Refuses an output folder that holds one of the files the command reads (`inputs`: what
/// it is, its path): the output folder is replaced as a whole, so it would destroy its own
/// input.
///
/// # Errors
/// [`IoError::InvalidArgument`] for `--out`, naming the input.
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

/// The refusal of `path` as `--out` for `reason`.
fn refuse(path: &Path, reason: impl Into<String>) -> IoError {
    IoError::invalid_argument("--out", path.display().to_string(), reason)
}

/// Where the output folder `path` really is: itself, or the folder a symbolic link at
/// `path` leads to.
///
/// # Errors
/// A link that leads nowhere or to something that is not a folder; a path that exists and
/// is not a folder.
fn real_folder(path: &Path) -> Result<PathBuf, IoError> {
    let Ok(meta) = fs::symlink_metadata(path) else {
        return Ok(path.to_path_buf());
    };
    if meta.file_type().is_symlink() {
        let to = fs::read_link(path)
            .map(|t| t.display().to_string())
            .unwrap_or_default();
        return match fs::canonicalize(path) {
            Ok(real) if real.is_dir() => Ok(real),
            Ok(real) => Err(refuse(
                path,
                format!(
                    "it is a symbolic link to {}, which is not a folder",
                    real.display()
                ),
            )),
            Err(e) => Err(refuse(
                path,
                format!(
                    "it is a symbolic link to {to}, which cannot be followed ({e}); make the \
                     folder it points to, or choose another folder"
                ),
            )),
        };
    }
    if !meta.is_dir() {
        return Err(refuse(
            path,
            "it exists and is not a folder; an output folder is needed",
        ));
    }
    Ok(path.to_path_buf())
}

/// Refuses `real` (named `shown`) if it holds an entry its manifest does not list.
fn refuse_foreign(real: &Path, shown: &Path) -> Result<(), IoError> {
    if fs::symlink_metadata(real).is_err() {
        return Ok(());
    }
    match manifest::first_foreign(real)? {
        None => Ok(()),
        Some(file) => {
            let rel = file.strip_prefix(real).unwrap_or(&file);
            Err(IoError::ForeignFile {
                dir: shown.to_path_buf(),
                file: shown.join(rel),
            })
        }
    }
}

impl OutputDir {
    /// Prepares the staging folder for the output folder `path` (which may or may not
    /// exist yet; its parent folders are made; a symbolic link is followed) and takes the
    /// folder's lock; removes what killed runs left there.
    ///
    /// # Errors
    /// `path` is `-` or no folder name, exists and is not a folder, is a link that leads
    /// nowhere or to a file, its parent cannot be written ([`IoError::InvalidArgument`] for
    /// `--out`); it holds a file vibrissa did not write ([`IoError::ForeignFile`]); another
    /// live process writes it ([`IoError::Locked`]).
    pub fn create(path: &Path) -> Result<Self, IoError> {
        if path.as_os_str() == "-" {
            return Err(refuse(
                path,
                "an output folder is needed, not standard output (--json prints the summary \
                 to standard output)",
            ));
        }
        if path.file_name().is_none() {
            return Err(refuse(
                path,
                "not usable as an output folder name (it would replace the folder it names \
                 a parent of); name a folder inside it",
            ));
        }
        let real = real_folder(path)?;
        let name = real
            .file_name()
            .ok_or_else(|| refuse(path, "it leads to a folder without a name"))?
            .to_os_string();
        refuse_foreign(&real, path)?;
        let parent = match real.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let made_parents: Vec<PathBuf> = parent
            .ancestors()
            .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
            .map(Path::to_path_buf)
            .collect();
        let remove_made = |made: &[PathBuf]| {
            for p in made {
                let _ = fs::remove_dir(p);
            }
        };
        fs::create_dir_all(&parent).map_err(|e| {
            remove_made(&made_parents);
            refuse(
                path,
                format!("cannot make the folder {} for it: {e}", parent.display()),
            )
        })?;
        let lock = match FolderLock::acquire(&sibling(&parent, &name, ".lock"), path) {
            Ok(l) => l,
            Err(e) => {
                remove_made(&made_parents);
                return Err(e);
            }
        };
        if lock.found_stale() {
            remove_leftovers(&parent, &name);
        }
        let staging = sibling(&parent, &name, &format!(".staging-{}", std::process::id()));
        let mut dir = OutputDir {
            target: path.to_path_buf(),
            real,
            staging,
            committed: false,
            made_parents,
            lock: Some(lock),
        };
        // (a failure from here drops `dir`: its staging folder, lock and parents go)
        dir.prepare()?;
        Ok(dir)
    }

    /// Makes the staging folder with an empty manifest (so that a killed run's staging
    /// folder is recognised as ours) and registers it for staged writes.
    fn prepare(&mut self) -> Result<(), IoError> {
        let staging = &self.staging;
        if fs::symlink_metadata(staging).is_ok() {
            fs::remove_dir_all(staging).map_err(|e| IoError::io(staging, e))?;
        }
        fs::create_dir(staging).map_err(|e| {
            refuse(
                &self.target,
                format!("cannot make its staging folder {}: {e}", staging.display()),
            )
        })?;
        staging_dirs().push((staging.clone(), Vec::new()));
        let m = staging.join(MANIFEST);
        fs::write(&m, manifest::manifest_text(&[])).map_err(|e| IoError::io(&m, e))
    }

    /// The final directory, as named by the caller.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Where to write the file `name` (relative, e.g. `observables.csv`) before the commit.
    pub fn path_for(&self, name: &str) -> PathBuf {
        self.staging.join(name)
    }

    /// Publishes the staged folder as a whole and returns the final paths of the files
    /// written (the manifest excluded), sorted, under the path given to
    /// [`OutputDir::create`]: writes the manifest, flushes everything, checks the existing
    /// folder again for files vibrissa did not write, swaps ([`super::swap`]) and removes
    /// the old folder.
    ///
    /// # Errors
    /// A file that cannot be flushed; [`IoError::ForeignFile`] if a file was put into the
    /// existing folder while the command ran (nothing is replaced); a swap that fails (the
    /// old folder stays).
    pub fn commit(mut self) -> Result<Vec<PathBuf>, IoError> {
        let entries = manifest::entries(&self.staging)?;
        let m = self.staging.join(MANIFEST);
        fs::write(&m, manifest::manifest_text(&entries)).map_err(|e| IoError::io(&m, e))?;
        let mut files = vec![m];
        let mut dirs = vec![self.staging.clone()];
        for e in &entries {
            match e.strip_suffix('/') {
                Some(d) => dirs.push(self.staging.join(d)),
                None => files.push(self.staging.join(e)),
            }
        }
        // every file and folder on disk before the rename publishes them
        let started = take_flushes(&self.staging, false);
        files.retain(|f| !started.iter().any(|(p, _)| p == f));
        sync_batch(started, &files, &dirs)?;
        refuse_foreign(&self.real, &self.target)?;
        let aside = self.staging.with_file_name({
            let mut n = OsString::from(".");
            n.push(self.real.file_name().unwrap_or_default());
            n.push(format!(".old-{}", std::process::id()));
            n
        });
        let (_, old) = swap::publish(&self.staging, &self.real, &aside)
            .map_err(|e| IoError::io(&self.target, e))?;
        self.committed = true;
        drop(take_flushes(&self.staging, true));
        if let Some(parent) = self.real.parent() {
            sync_dir(parent);
        }
        if let Some(old) = old {
            fs::remove_dir_all(&old).map_err(|e| IoError::io(&old, e))?;
        }
        Ok(entries
            .iter()
            .filter(|e| !e.ends_with('/'))
            .map(|e| self.target.join(e))
            .collect())
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        if !self.committed {
            // flushes still under way finish on their own (the staging folder is removed
            // under them)
            drop(take_flushes(&self.staging, true));
            let _ = fs::remove_dir_all(&self.staging);
        }
        drop(self.lock.take());
        if !self.committed {
            // deepest first; a folder something else wrote into meanwhile stays
            for p in &self.made_parents {
                let _ = fs::remove_dir(p);
            }
        }
    }
}
