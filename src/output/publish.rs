//! Publishing a staged set into its directory (see [`super::files`]): under
//! an exclusive lock on DIR, the previous versions hard-linked aside, the
//! new files renamed over them, the record of the set replaced, the
//! previous set's leftovers removed; any failure undone.

use super::files::{create_dirs, relative, remove_empty_dirs, STAGING_PREFIX};
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs::{self, File};
use std::path::{Path, PathBuf};

/// Prefix of the folder that holds the replaced files during a commit.
const PREVIOUS_PREFIX: &str = ".dembound-previous-";
/// The record of which files each subcommand published into DIR.
pub const RECORD: &str = ".dembound.json";

/// The exclusive lock of DIR, held while publishing into it: a lock on the
/// directory itself where the system allows it (no file left behind).
#[cfg(unix)]
pub(super) fn lock_dir(dir: &Path) -> Result<File> {
    let f = File::open(dir).with_context(|| format!("cannot open `{}`", dir.display()))?;
    f.lock()
        .with_context(|| format!("cannot lock `{}`", dir.display()))?;
    Ok(f)
}

#[cfg(not(unix))]
pub(super) fn lock_dir(dir: &Path) -> Result<File> {
    let path = dir.join(".dembound.lock");
    let f = fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
        .with_context(|| format!("cannot open `{}`", path.display()))?;
    f.lock()
        .with_context(|| format!("cannot lock `{}`", path.display()))?;
    Ok(f)
}

/// Removes what killed processes left in `dir` (called with DIR locked):
/// staging directories no live process holds locked, and previous-file
/// folders of a commit that never finished.
pub(super) fn remove_abandoned(dir: &Path, own: &Path) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if path == own || !entry.file_type().is_ok_and(|t| t.is_dir()) {
            continue;
        }
        let abandoned = if name.starts_with(PREVIOUS_PREFIX) {
            true
        } else if name.starts_with(STAGING_PREFIX) {
            File::open(&path).is_ok_and(|f| f.try_lock().is_ok())
        } else {
            false
        };
        if abandoned {
            let _ = fs::remove_dir_all(&path);
        }
    }
}

/// `DIR/.dembound.json`: for each subcommand, the files of its last set.
#[derive(Debug, Default, Serialize, Deserialize)]
struct Record {
    sets: BTreeMap<String, Vec<String>>,
}

impl Record {
    /// The record in `dir`; a missing or unreadable one is empty (then
    /// nothing is removed as stale).
    fn read(dir: &Path) -> Record {
        fs::read(dir.join(RECORD))
            .ok()
            .and_then(|bytes| serde_json::from_slice(&bytes).ok())
            .unwrap_or_default()
    }
}

fn slash_path(rel: &Path) -> String {
    rel.components()
        .map(|c| c.as_os_str().to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

/// One file moved into DIR, for undoing.
struct Step {
    rel: PathBuf,
    /// The previous file was hard-linked (true) or moved (false) aside.
    previous: Option<bool>,
    renamed: bool,
}

/// Publishes `files` (relative to `staging`) into `dir` with the record;
/// all or, on failure, the previous state restored. DIR is locked.
pub(super) fn publish(
    dir: &Path,
    staging: &Path,
    set: &str,
    files: &[PathBuf],
) -> Result<Vec<PathBuf>> {
    let mut record = Record::read(dir);
    let old: Vec<String> = record.sets.get(set).cloned().unwrap_or_default();
    let new: Vec<String> = files.iter().map(|p| slash_path(p)).collect();
    record.sets.insert(set.to_string(), new.clone());
    let record_json = serde_json::to_vec_pretty(&record)?;
    fs::write(staging.join(RECORD), record_json)
        .and_then(|()| File::open(staging.join(RECORD))?.sync_all())
        .with_context(|| format!("cannot write `{}`", dir.join(RECORD).display()))?;

    let mut all: Vec<PathBuf> = files.to_vec();
    all.push(PathBuf::from(RECORD));
    check_targets(dir, &all)?;

    let previous = tempfile::Builder::new()
        .prefix(PREVIOUS_PREFIX)
        .tempdir_in(dir)
        .with_context(|| format!("cannot create files in `{}`", dir.display()))?;
    let mut steps: Vec<Step> = Vec::with_capacity(all.len());
    let mut made: Vec<PathBuf> = Vec::new();
    let outcome = (|| -> Result<()> {
        for rel in &all {
            let target = dir.join(rel);
            if let Some(parent) = rel.parent().filter(|p| !p.as_os_str().is_empty()) {
                made.extend(
                    create_dirs(&dir.join(parent))
                        .with_context(|| format!("cannot write `{}`", target.display()))?,
                );
            }
            let mut step = Step {
                rel: rel.clone(),
                previous: None,
                renamed: false,
            };
            if fs::symlink_metadata(&target).is_ok() {
                let aside = previous.path().join(rel);
                if let Some(parent) = aside.parent() {
                    fs::create_dir_all(parent)?;
                }
                // A link keeps the previous file in place until the rename
                // replaces it; where links are not possible it is moved.
                let linked = fs::hard_link(&target, &aside).is_ok();
                if !linked {
                    fs::rename(&target, &aside)
                        .with_context(|| format!("cannot replace `{}`", target.display()))?;
                }
                step.previous = Some(linked);
            }
            steps.push(step);
            let step = steps.last_mut().expect("just pushed");
            fs::rename(staging.join(rel), &target)
                .with_context(|| format!("cannot write `{}`", target.display()))?;
            step.renamed = true;
        }
        Ok(())
    })();
    if let Err(e) = outcome {
        undo(dir, staging, previous.path(), &steps, &made);
        return Err(e);
    }
    drop(previous);

    // The previous set's files that the new one does not write, unless
    // another subcommand's set in DIR names them.
    for stale in old.iter().filter(|o| !new.contains(o)) {
        if record.sets.values().any(|files| files.contains(stale)) {
            continue;
        }
        let Ok(rel) = relative(stale) else { continue };
        if fs::remove_file(dir.join(rel)).is_ok() {
            let mut parent = rel.parent();
            while let Some(p) = parent.filter(|p| !p.as_os_str().is_empty()) {
                if fs::remove_dir(dir.join(p)).is_err() {
                    break;
                }
                parent = p.parent();
            }
        }
    }
    Ok(files.iter().map(|rel| dir.join(rel)).collect())
}

/// Refuses, before anything moves, targets that a file cannot replace: a
/// directory in the way of a file, or a file in the way of a folder.
fn check_targets(dir: &Path, files: &[PathBuf]) -> Result<()> {
    for rel in files {
        let mut prefix = PathBuf::new();
        let parts: Vec<_> = rel.components().collect();
        for (i, part) in parts.iter().enumerate() {
            prefix.push(part);
            let path = dir.join(&prefix);
            let last = i + 1 == parts.len();
            match fs::metadata(&path) {
                Ok(m) if last && m.is_dir() => bail!(
                    "cannot write `{}`: a directory of that name is in the way",
                    path.display()
                ),
                Ok(m) if !last && !m.is_dir() => bail!(
                    "cannot write `{}`: `{}` is not a directory",
                    dir.join(rel).display(),
                    path.display()
                ),
                _ => {}
            }
        }
    }
    Ok(())
}

/// Undoes a partial publish: new files back into staging, the previous
/// ones back into place, the folders made removed.
fn undo(dir: &Path, staging: &Path, previous: &Path, steps: &[Step], made: &[PathBuf]) {
    for step in steps.iter().rev() {
        let target = dir.join(&step.rel);
        if step.renamed {
            let _ = fs::rename(&target, staging.join(&step.rel));
        }
        if step.previous.is_some() && (step.renamed || step.previous == Some(false)) {
            let _ = fs::rename(previous.join(&step.rel), &target);
        }
    }
    remove_empty_dirs(made);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failure_in_the_renames_is_undone() {
        // A failure in the middle of the renames (a file in the way that
        // appears after the check) is simulated by a publish by hand.
        let root = tempfile::tempdir().unwrap();
        let dir = root.path();
        fs::write(dir.join("a.csv"), "old a").unwrap();
        let staging = tempfile::tempdir_in(dir).unwrap();
        let previous = tempfile::tempdir_in(dir).unwrap();
        fs::write(staging.path().join("a.csv"), "new a").unwrap();
        fs::write(staging.path().join("b.csv"), "new b").unwrap();
        fs::hard_link(dir.join("a.csv"), previous.path().join("a.csv")).unwrap();
        fs::rename(staging.path().join("a.csv"), dir.join("a.csv")).unwrap();
        fs::rename(staging.path().join("b.csv"), dir.join("b.csv")).unwrap();
        let steps = [
            Step {
                rel: "a.csv".into(),
                previous: Some(true),
                renamed: true,
            },
            Step {
                rel: "b.csv".into(),
                previous: None,
                renamed: true,
            },
        ];
        undo(dir, staging.path(), previous.path(), &steps, &[]);
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "old a");
        assert!(!dir.join("b.csv").exists());
    }

    #[test]
    fn the_record_names_each_subcommands_set() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path();
        let staging = tempfile::tempdir_in(dir).unwrap();
        fs::write(staging.path().join("x.csv"), "x").unwrap();
        publish(dir, staging.path(), "run", &[PathBuf::from("x.csv")]).unwrap();
        let record = Record::read(dir);
        assert_eq!(record.sets["run"], ["x.csv"]);
    }
}
