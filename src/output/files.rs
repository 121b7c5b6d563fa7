//! The one output mechanism of every subcommand: a set of files appears in
//! its directory whole or not at all.
//!
//! 1. [`AtomicDir::create`], called before anything is computed, makes the
//!    target directory if missing (remembering which directories it made)
//!    and a fresh staging directory `DIR/.dembound-staging-*` inside it.
//!    That proves the target writable early (the caller turns a failure
//!    into exit 2), and puts the staging on the target's file system, so
//!    publishing is a rename.
//! 2. [`AtomicDir::write`] and [`AtomicDir::path`] put files (also in
//!    subfolders) into the staging directory. Everything under it is part of
//!    the set.
//! 3. [`AtomicDir::commit`] publishes the set under an exclusive lock on
//!    DIR (so concurrent writers into one directory take turns and each
//!    leaves a complete set): every file of the previous version it
//!    replaces is first hard-linked aside, then each new file is renamed
//!    over its target. If any step fails, the renames are undone and the
//!    previous files restored, so DIR holds the previous set, whole. Last,
//!    the record `DIR/.dembound.json` (which files each subcommand wrote
//!    there) is replaced, and the files of this subcommand's previous set
//!    that the new set does not write are removed: DIR then holds exactly
//!    the new set, beside any unrelated files, which are never touched.
//! 4. Without a commit (an error, a panic unwinding, or SIGINT/SIGTERM/SIGHUP
//!    via [`super::interrupt`]) the staging directory and the directories
//!    `create` made are removed.
//!
//! A SIGKILL or a power loss can leave a `.dembound-staging-*` (removed by
//! the next commit into DIR, which finds its owner gone by its lock) or,
//! during the milliseconds of publishing, a mix of old and new files.

use super::interrupt::{self, Cleanup};
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs::{self, File};
use std::io::{BufWriter, ErrorKind, Write};
use std::path::{Component, Path, PathBuf};

/// Prefix of the staging directories inside DIR.
const STAGING_PREFIX: &str = ".dembound-staging-";
/// Prefix of the folder that holds the replaced files during a commit.
const PREVIOUS_PREFIX: &str = ".dembound-previous-";
/// The record of which files each subcommand published into DIR.
pub const RECORD: &str = ".dembound.json";

/// A set of output files being staged for one directory.
pub struct AtomicDir {
    dir: PathBuf,
    /// Which subcommand's set this is (its key in [`RECORD`]).
    set: String,
    staging: PathBuf,
    /// Holds an exclusive lock on the staging directory while we live, by
    /// which a later commit tells a live staging from one left by a killed
    /// process.
    _staging_lock: File,
    /// Files written through [`AtomicDir::write`], in order (they are
    /// reported first, in that order).
    written: Vec<PathBuf>,
    /// The id under which the staging is registered for signal cleanup.
    cleanup: u64,
    published: bool,
}

impl AtomicDir {
    /// Makes `dir` (and its missing parents) and a staging directory in it,
    /// for the set of subcommand `set`. Fails, before anything is computed,
    /// when `dir` is not a directory or cannot be written.
    pub fn create(dir: &Path, set: &str) -> Result<Self> {
        if dir.as_os_str().is_empty() {
            bail!("the path is empty");
        }
        if let Ok(meta) = fs::metadata(dir) {
            if !meta.is_dir() {
                bail!("`{}` exists and is not a directory", dir.display());
            }
        }
        let (cleanup, (staging, lock)) = interrupt::register(|| {
            let created = create_dirs(dir)?;
            // Under DIR's lock, so that a commit into DIR never sees the
            // new staging before it is locked (it would take it for one
            // left by a killed process).
            let staging = lock_dir(dir).and_then(|_dir_lock| make_staging(dir));
            match staging {
                Ok((staging, lock)) => Ok((
                    Cleanup {
                        staging: staging.clone(),
                        created,
                    },
                    (staging, lock),
                )),
                Err(e) => {
                    remove_empty_dirs(&created);
                    Err(e)
                }
            }
        })?;
        Ok(AtomicDir {
            dir: dir.to_path_buf(),
            set: set.to_string(),
            staging,
            _staging_lock: lock,
            written: Vec::new(),
            cleanup,
            published: false,
        })
    }

    /// The staging directory, for writers that fill a folder themselves:
    /// whatever they put there is published with the set.
    pub fn staging(&self) -> &Path {
        &self.staging
    }

    /// Where to write the file `name` (relative, may hold subfolders) so
    /// that it is published as `DIR/name`; for writers that take a path
    /// (figures). Missing subfolders are made.
    pub fn path(&self, name: &str) -> Result<PathBuf> {
        let rel = relative(name)?;
        let path = self.staging.join(rel);
        if let Some(parent) = path.parent() {
            fs::create_dir_all(parent)
                .with_context(|| format!("cannot write `{}`", self.dir.join(rel).display()))?;
        }
        Ok(path)
    }

    /// Stages the file `name`, its content written by `write`.
    pub fn write(
        &mut self,
        name: &str,
        write: impl FnOnce(&mut dyn Write) -> Result<()>,
    ) -> Result<()> {
        let context = || format!("cannot write `{}`", self.dir.join(name).display());
        let path = self.path(name)?;
        let file = File::create(&path).with_context(context)?;
        let mut w = BufWriter::new(file);
        write(&mut w).with_context(context)?;
        w.flush().with_context(context)?;
        let file = w
            .into_inner()
            .map_err(|e| e.into_error())
            .with_context(context)?;
        file.sync_all().with_context(context)?;
        self.written.push(PathBuf::from(name));
        Ok(())
    }

    /// Publishes the staged set into DIR (see the module's doc); returns
    /// the paths written, those of [`AtomicDir::write`] first, in order.
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        let mut files = Vec::new();
        list_files(&self.staging, Path::new(""), &mut files)
            .with_context(|| format!("cannot read `{}`", self.staging.display()))?;
        // Files written by path have not been synced yet.
        for rel in &files {
            if !self.written.contains(rel) {
                File::open(self.staging.join(rel))
                    .and_then(|f| f.sync_all())
                    .with_context(|| format!("cannot write `{}`", self.dir.join(rel).display()))?;
            }
        }
        files.sort_by_key(|rel| {
            (
                self.written
                    .iter()
                    .position(|w| w == rel)
                    .unwrap_or(usize::MAX),
                rel.clone(),
            )
        });
        let published = interrupt::hold(|| {
            let _lock = lock_dir(&self.dir)?;
            remove_abandoned(&self.dir, &self.staging);
            publish(&self.dir, &self.staging, &self.set, &files)
        })?;
        self.published = true;
        // Best effort: everything of value is in place.
        let _ = File::open(&self.dir).and_then(|d| d.sync_all());
        Ok(published)
    }
}

impl Drop for AtomicDir {
    fn drop(&mut self) {
        let published = self.published;
        let staging = &self.staging;
        interrupt::deregister(self.cleanup, |cleanup| {
            let _ = fs::remove_dir_all(staging);
            if let (false, Some(cleanup)) = (published, cleanup) {
                remove_empty_dirs(&cleanup.created);
            }
        });
    }
}

/// `name` as a relative path of ordinary components.
fn relative(name: &str) -> Result<&Path> {
    let path = Path::new(name);
    if name.is_empty() || !path.components().all(|c| matches!(c, Component::Normal(_))) {
        bail!("`{name}` is not a plain relative file name");
    }
    Ok(path)
}

/// Makes `dir` and its missing parents; returns those it made, outermost
/// first.
fn create_dirs(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut missing = Vec::new();
    let mut p = dir;
    while !p.as_os_str().is_empty() && fs::symlink_metadata(p).is_err() {
        missing.push(p.to_path_buf());
        match p.parent() {
            Some(parent) => p = parent,
            None => break,
        }
    }
    missing.reverse();
    let mut created = Vec::new();
    for d in missing {
        match fs::create_dir(&d) {
            Ok(()) => created.push(d),
            Err(e) if e.kind() == ErrorKind::AlreadyExists && d.is_dir() => {}
            Err(e) => {
                remove_empty_dirs(&created);
                let why = match e.kind() {
                    ErrorKind::NotADirectory => "a parent is not a directory".to_string(),
                    _ => e.to_string(),
                };
                bail!("cannot create `{}`: {why}", d.display());
            }
        }
    }
    Ok(created)
}

/// Removes the directories in `dirs` (outermost first) that are empty.
fn remove_empty_dirs(dirs: &[PathBuf]) {
    for d in dirs.iter().rev() {
        let _ = fs::remove_dir(d);
    }
}

/// A fresh staging directory in `dir`, locked by this process.
fn make_staging(dir: &Path) -> Result<(PathBuf, File)> {
    let staging = tempfile::Builder::new()
        .prefix(STAGING_PREFIX)
        .tempdir_in(dir)
        .with_context(|| format!("cannot create files in `{}`", dir.display()))?
        .keep();
    let lock = File::open(&staging)
        .and_then(|f| f.lock().map(|()| f))
        .with_context(|| format!("cannot lock `{}`", staging.display()));
    match lock {
        Ok(lock) => Ok((staging, lock)),
        Err(e) => {
            let _ = fs::remove_dir_all(&staging);
            Err(e)
        }
    }
}

/// The exclusive lock of DIR, held while publishing into it: a lock on the
/// directory itself where the system allows it (no file left behind).
#[cfg(unix)]
fn lock_dir(dir: &Path) -> Result<File> {
    let f = File::open(dir).with_context(|| format!("cannot open `{}`", dir.display()))?;
    f.lock()
        .with_context(|| format!("cannot lock `{}`", dir.display()))?;
    Ok(f)
}

#[cfg(not(unix))]
fn lock_dir(dir: &Path) -> Result<File> {
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
fn remove_abandoned(dir: &Path, own: &Path) {
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

/// Every regular file under `root/rel`, as paths relative to `root`.
fn list_files(root: &Path, rel: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in fs::read_dir(root.join(rel))? {
        let entry = entry?;
        let rel = rel.join(entry.file_name());
        let kind = entry.file_type()?;
        if kind.is_dir() {
            list_files(root, &rel, out)?;
        } else {
            out.push(rel);
        }
    }
    Ok(())
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
fn publish(dir: &Path, staging: &Path, set: &str, files: &[PathBuf]) -> Result<Vec<PathBuf>> {
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

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    fn set(dir: &Path, files: &[(&str, &str)]) -> Result<Vec<PathBuf>> {
        let mut out = AtomicDir::create(dir, "test")?;
        for (name, text) in files {
            out.write(name, |w| Ok(w.write_all(text.as_bytes())?))?;
        }
        out.commit()
    }

    #[test]
    fn nothing_is_left_unless_committed() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("a/b");
        {
            let mut out = AtomicDir::create(&dir, "test").unwrap();
            out.write("x.txt", |w| Ok(writeln!(w, "hello")?)).unwrap();
            assert!(dir.is_dir());
        }
        // The directories it made went too.
        assert!(!root.path().join("a").exists());
        let written = set(&dir, &[("x.txt", "hello\n")]).unwrap();
        assert_eq!(written, vec![dir.join("x.txt")]);
        assert_eq!(fs::read_to_string(dir.join("x.txt")).unwrap(), "hello\n");
        assert_eq!(names(&dir), [RECORD, "x.txt"]);
    }

    #[test]
    fn a_new_set_replaces_the_previous_one_and_leaves_other_files() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path();
        fs::write(dir.join("notes.txt"), "mine").unwrap();
        set(dir, &[("a.csv", "1"), ("sub/fig.svg", "2")]).unwrap();
        set(dir, &[("a.csv", "3"), ("b.csv", "4")]).unwrap();
        assert_eq!(names(dir), [RECORD, "a.csv", "b.csv", "notes.txt"]);
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "3");
        assert_eq!(fs::read_to_string(dir.join("notes.txt")).unwrap(), "mine");
    }

    #[test]
    fn a_failed_publish_restores_the_previous_set() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path();
        set(dir, &[("a.csv", "old a"), ("b.csv", "old b")]).unwrap();
        // A directory where the new set wants a file: refused before
        // anything moves.
        fs::create_dir(dir.join("c.csv")).unwrap();
        let err = set(dir, &[("a.csv", "new a"), ("c.csv", "new c")]).unwrap_err();
        assert!(format!("{err:#}").contains("c.csv"), "{err:#}");
        assert_eq!(names(dir), [RECORD, "a.csv", "b.csv", "c.csv"]);
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "old a");

        // A failure in the middle of the renames is undone: a subfolder
        // whose name is taken by a file that appears too late for the check
        // is simulated by undoing a publish by hand.
        let staging = tempfile::tempdir_in(dir).unwrap();
        let previous = tempfile::tempdir_in(dir).unwrap();
        fs::write(staging.path().join("a.csv"), "new a").unwrap();
        fs::hard_link(dir.join("a.csv"), previous.path().join("a.csv")).unwrap();
        fs::rename(staging.path().join("a.csv"), dir.join("a.csv")).unwrap();
        let steps = [Step {
            rel: "a.csv".into(),
            previous: Some(true),
            renamed: true,
        }];
        undo(dir, staging.path(), previous.path(), &steps, &[]);
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "old a");
    }

    #[test]
    fn a_file_as_target_is_refused_at_create() {
        let root = tempfile::tempdir().unwrap();
        let file = root.path().join("f");
        fs::write(&file, "x").unwrap();
        assert!(AtomicDir::create(&file, "test").is_err());
        assert!(AtomicDir::create(&file.join("sub"), "test").is_err());
        assert_eq!(names(root.path()), ["f"]);
    }

    #[test]
    fn abandoned_staging_is_removed_live_staging_kept() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path();
        let live = AtomicDir::create(dir, "other").unwrap();
        let dead = dir.join(format!("{STAGING_PREFIX}dead"));
        fs::create_dir(&dead).unwrap();
        set(dir, &[("a.csv", "1")]).unwrap();
        assert!(!dead.exists());
        assert!(live.staging().exists());
    }

    #[test]
    fn only_plain_relative_names() {
        for bad in ["", "/etc/x", "../x", "a/../b", "./a"] {
            assert!(relative(bad).is_err(), "{bad}");
        }
        assert!(relative("restitution/fig.png").is_ok());
    }
}
