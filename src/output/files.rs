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
//! 3. [`AtomicDir::commit`] publishes the set ([`super::publish`]) under an exclusive lock on
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
use super::publish::{lock_dir, publish, remove_abandoned};
use anyhow::{bail, Context, Result};
use std::fs::{self, File};
use std::io::{BufWriter, ErrorKind, Write};
use std::path::{Component, Path, PathBuf};

/// Prefix of the staging directories inside DIR.
pub(super) const STAGING_PREFIX: &str = ".dembound-staging-";

/// A set of output files being staged for one directory.
pub struct AtomicDir {
    dir: PathBuf,
    /// Which subcommand's set this is (its key in [`super::publish::RECORD`]).
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
    ///
    /// The staging directory itself is never made again here: once the
    /// signal handler has removed it ([`super::interrupt`]), a writer still
    /// running fails instead of recreating it (with `create_dir_all` it did,
    /// between the handler's removal and the process's exit, and left a
    /// `.dembound-staging-*` with snapshots behind).
    pub fn path(&self, name: &str) -> Result<PathBuf> {
        let rel = relative(name)?;
        let context = || format!("cannot write `{}`", self.dir.join(rel).display());
        let mut folder = self.staging.clone();
        if let Some(parent) = rel.parent() {
            for part in parent.components() {
                folder.push(part);
                match fs::create_dir(&folder) {
                    Ok(()) => {}
                    Err(e) if e.kind() == ErrorKind::AlreadyExists && folder.is_dir() => {}
                    Err(e) => return Err(e).with_context(context),
                }
            }
        }
        if !self.staging.is_dir() {
            bail!(
                "{}: the staging directory is gone (stopped by a signal)",
                context()
            );
        }
        Ok(self.staging.join(rel))
    }

    /// Stages the file `name`, its content written by `write`.
    pub fn write(
        &mut self,
        name: &str,
        write: impl FnOnce(&mut dyn Write) -> Result<()>,
    ) -> Result<()> {
        let context = || format!("cannot write `{}`", self.dir.join(name).display());
        let path = self.path(name)?;
        // Fails (ENOENT) once the staging is removed: never recreates it.
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
pub(super) fn relative(name: &str) -> Result<&Path> {
    let path = Path::new(name);
    if name.is_empty() || !path.components().all(|c| matches!(c, Component::Normal(_))) {
        bail!("`{name}` is not a plain relative file name");
    }
    Ok(path)
}

/// Makes `dir` and its missing parents; returns those it made, outermost
/// first.
pub(super) fn create_dirs(dir: &Path) -> Result<Vec<PathBuf>> {
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
pub(super) fn remove_empty_dirs(dirs: &[PathBuf]) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::publish::RECORD;

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
        assert_eq!(names(&dir), [".dembound.json", "x.txt"]);
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
    fn a_write_after_the_staging_is_removed_fails_and_makes_nothing() {
        // The signal handler removes the staging while the main thread may
        // still be writing snapshots: a write after that must fail, never
        // make the staging again (the process exits a moment later and a
        // remade staging would be left behind).
        let root = tempfile::tempdir().unwrap();
        let dir = root.path();
        let mut out = AtomicDir::create(dir, "test").unwrap();
        let staging = out.staging().to_path_buf();
        fs::remove_dir_all(&staging).unwrap();
        let write = |out: &mut AtomicDir, name: &str| out.write(name, |w| Ok(w.write_all(b"x")?));
        assert!(write(&mut out, "snapshot_000001.vtp").is_err());
        assert!(write(&mut out, "sub/fig.svg").is_err());
        assert!(!staging.exists());
        drop(out);
        assert_eq!(names(dir), Vec::<String>::new());
    }

    #[test]
    fn only_plain_relative_names() {
        for bad in ["", "/etc/x", "../x", "a/../b", "./a"] {
            assert!(relative(bad).is_err(), "{bad}");
        }
        assert!(relative("restitution/fig.png").is_ok());
    }
}
