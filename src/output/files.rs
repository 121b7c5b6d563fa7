//! Atomic output: every file of a command is written to a temporary file
//! in the output directory and renamed into place only when all of them
//! are written, so a failed command leaves nothing behind.

use anyhow::{Context, Result};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// Files staged for one output directory.
pub struct AtomicDir {
    dir: PathBuf,
    staged: Vec<(NamedTempFile, String)>,
}

impl AtomicDir {
    /// Creates `dir` (and its parents) if missing.
    pub fn create(dir: &Path) -> Result<Self> {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output directory `{}`", dir.display()))?;
        Ok(AtomicDir {
            dir: dir.to_path_buf(),
            staged: Vec::new(),
        })
    }

    /// Stages the file `name`, its content written by `write`.
    pub fn write(
        &mut self,
        name: &str,
        write: impl FnOnce(&mut dyn Write) -> Result<()>,
    ) -> Result<()> {
        let context = || format!("cannot write `{}`", self.dir.join(name).display());
        let mut builder = tempfile::Builder::new();
        builder.prefix(".dembound-").suffix(".tmp");
        // An ordinary file (rw-rw-rw- less the umask), not the owner-only
        // mode of temporary files.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let mut tmp = builder.tempfile_in(&self.dir).with_context(context)?;
        {
            let mut w = BufWriter::new(tmp.as_file_mut());
            write(&mut w).with_context(context)?;
            w.flush().with_context(context)?;
        }
        tmp.as_file().sync_all().with_context(context)?;
        self.staged.push((tmp, name.to_string()));
        Ok(())
    }

    /// Renames every staged file into place; returns their paths.
    pub fn commit(self) -> Result<Vec<PathBuf>> {
        let mut written = Vec::with_capacity(self.staged.len());
        for (tmp, name) in self.staged {
            let path = self.dir.join(&name);
            tmp.persist(&path)
                .with_context(|| format!("cannot write `{}`", path.display()))?;
            written.push(path);
        }
        Ok(written)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_is_left_unless_committed() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("a/b");
        {
            let mut out = AtomicDir::create(&dir).unwrap();
            out.write("x.txt", |w| Ok(writeln!(w, "hello")?)).unwrap();
        }
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        let mut out = AtomicDir::create(&dir).unwrap();
        out.write("x.txt", |w| Ok(writeln!(w, "hello")?)).unwrap();
        let written = out.commit().unwrap();
        assert_eq!(written, vec![dir.join("x.txt")]);
        assert_eq!(
            std::fs::read_to_string(dir.join("x.txt")).unwrap(),
            "hello\n"
        );
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    }
}
