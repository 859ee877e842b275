//! The manifest of an output folder, `.vibrissa-output`: the files and folders vibrissa
//! wrote there, one relative path a line (`/` between components, a folder with a trailing
//! `/`), after comment lines starting with `#`.
//!
//! It is how the program knows its own files: an existing folder is replaced only if every
//! entry in it is listed ([`first_foreign`] finds the first one that is not, in sorted
//! order). A folder without a manifest is replaced only when empty; the marker of earlier
//! versions (one line `written by vibrissa`, no list) lists nothing, so such a folder is
//! refused naming one of its files.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use crate::error::IoError;

pub use super::names::MANIFEST;

/// The manifest's first line.
const HEADER: &str = "# vibrissa output folder: the files vibrissa wrote here, one a line; a \
                      later run replaces the folder only if it holds nothing else";

/// The text of a manifest listing `entries` (relative paths, folders ending in `/`).
pub fn manifest_text(entries: &[String]) -> String {
    let mut text = String::from(HEADER);
    text.push('\n');
    for e in entries {
        text.push_str(e);
        text.push('\n');
    }
    text
}

/// The entries listed in the manifest of `dir`; `None` when it has none (no regular file
/// of that name; a manifest that cannot be read counts as none).
pub fn listed(dir: &Path) -> Option<BTreeSet<String>> {
    let path = dir.join(MANIFEST);
    if !fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
        return None;
    }
    let text = fs::read_to_string(&path).ok()?;
    Some(
        text.lines()
            .filter(|l| !l.starts_with('#') && !l.is_empty())
            .map(str::to_string)
            .collect(),
    )
}

/// Whether `dir` holds a manifest (a regular file [`MANIFEST`]).
pub fn has_manifest(dir: &Path) -> bool {
    listed(dir).is_some()
}

/// The entries under `dir` as the manifest lists them, sorted (folders with a trailing
/// `/`, before what they hold), the manifest itself left out.
///
/// # Errors
/// A folder that cannot be read.
pub fn entries(dir: &Path) -> Result<Vec<String>, IoError> {
    let mut out = Vec::new();
    walk(dir, "", &mut |rel, _| {
        out.push(rel.to_string());
        true
    })?;
    Ok(out)
}

/// The first entry of `dir` (in sorted order, a folder before what it holds) that its
/// manifest does not list, as a path under `dir`; `None` when there is none (an empty
/// folder, or one holding only what its manifest lists).
///
/// # Errors
/// A folder that cannot be read.
pub fn first_foreign(dir: &Path) -> Result<Option<PathBuf>, IoError> {
    let listed = listed(dir).unwrap_or_default();
    let mut foreign = None;
    walk(dir, "", &mut |rel, path| {
        if listed.contains(rel) {
            true
        } else {
            foreign = Some(path.to_path_buf());
            false
        }
    })?;
    Ok(foreign)
}

/// Visits the entries under `dir` in sorted order (the manifest file at its top left out):
/// `visit(relative name, path)`; descends into a folder (not a link to one) when `visit`
/// returns `true`, stops at the first `false`. Returns whether it went through.
fn walk(
    dir: &Path,
    prefix: &str,
    visit: &mut dyn FnMut(&str, &Path) -> bool,
) -> Result<bool, IoError> {
    let mut items = Vec::new();
    for entry in fs::read_dir(dir).map_err(|e| IoError::io(dir, e))? {
        let entry = entry.map_err(|e| IoError::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        if prefix.is_empty() && name == MANIFEST && !is_dir {
            continue;
        }
        items.push((name, is_dir, entry.path()));
    }
    items.sort();
    for (name, is_dir, path) in items {
        let rel = format!("{prefix}{name}{}", if is_dir { "/" } else { "" });
        if !visit(&rel, &path) {
            return Ok(false);
        }
        if is_dir && !walk(&path, &rel, visit)? {
            return Ok(false);
        }
    }
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The manifest lists what is there and reads back; anything else is found, the first
    /// in sorted order, in any folder; a folder without a manifest is ours only when empty.
    #[test]
    fn entries_not_listed_are_found() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        assert_eq!(first_foreign(d).unwrap(), None, "an empty folder");
        fs::write(d.join("b.csv"), "1").unwrap();
        fs::create_dir(d.join("fig")).unwrap();
        fs::write(d.join("fig/f.svg"), "<svg/>").unwrap();
        assert_eq!(first_foreign(d).unwrap(), Some(d.join("b.csv")));
        let all = entries(d).unwrap();
        assert_eq!(all, ["b.csv", "fig/", "fig/f.svg"]);
        fs::write(d.join(MANIFEST), manifest_text(&all)).unwrap();
        assert_eq!(listed(d).unwrap().len(), 3);
        assert_eq!(first_foreign(d).unwrap(), None);
        // a user's file in a subfolder, a user's folder, a user's file on top
        fs::write(d.join("fig/notes.txt"), "mine").unwrap();
        assert_eq!(first_foreign(d).unwrap(), Some(d.join("fig/notes.txt")));
        fs::create_dir(d.join("a-mine")).unwrap();
        assert_eq!(first_foreign(d).unwrap(), Some(d.join("a-mine")));
        // the marker of earlier versions lists nothing
        fs::remove_dir(d.join("a-mine")).unwrap();
        fs::remove_file(d.join("fig/notes.txt")).unwrap();
        fs::write(d.join(MANIFEST), "written by vibrissa\n").unwrap();
        assert_eq!(first_foreign(d).unwrap(), Some(d.join("b.csv")));
        // a manifest that is a folder is no manifest (and is itself foreign)
        let e = d.join("e");
        fs::create_dir_all(e.join(MANIFEST)).unwrap();
        assert!(!has_manifest(&e));
        assert_eq!(first_foreign(&e).unwrap(), Some(e.join(MANIFEST)));
        assert!(first_foreign(&d.join("missing")).is_err());
    }
}
