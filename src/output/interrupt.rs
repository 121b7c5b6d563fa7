//! Removing staged output when the process is told to stop: SIGINT
//! (Ctrl-C), SIGTERM and SIGHUP end the process with 128 + the signal's
//! number (130, 143, 129) after removing every staging directory (and the
//! output directories made for it) that is not yet published.
//!
//! Staging directories are registered here by [`super::files`]; a commit
//! publishes while holding the registry, so a signal arriving then waits
//! until the set is in place: the directory holds the new set or the
//! previous one, never a mix.

use anyhow::Result;
use std::fs::{self, File};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

/// What to remove if the process is stopped before a commit.
pub struct Cleanup {
    pub staging: PathBuf,
    /// Output directories made for this set, outermost first; removed if
    /// empty.
    pub created: Vec<PathBuf>,
}

impl Cleanup {
    /// Removes the staging directory and the directories made for it.
    fn remove(&self) {
        // Renamed first, and a file put in its place, so that the other
        // threads, which may still be writing into it, cannot recreate it
        // while it is being removed (their writes fail instead).
        let mut tomb = self.staging.clone().into_os_string();
        tomb.push(".removing");
        let tomb = PathBuf::from(tomb);
        if fs::rename(&self.staging, &tomb).is_ok() {
            let placeholder = File::create(&self.staging).is_ok();
            let _ = fs::remove_dir_all(&tomb);
            if placeholder {
                let _ = fs::remove_file(&self.staging);
            }
        } else {
            let _ = fs::remove_dir_all(&self.staging);
        }
        for d in self.created.iter().rev() {
            let _ = fs::remove_dir(d);
        }
    }
}

static REGISTRY: Mutex<Vec<(u64, Cleanup)>> = Mutex::new(Vec::new());
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

fn registry() -> MutexGuard<'static, Vec<(u64, Cleanup)>> {
    // A panic elsewhere while holding it leaves the list itself intact.
    REGISTRY.lock().unwrap_or_else(|e| e.into_inner())
}

/// Runs `make` (which creates what its [`Cleanup`] names) and registers the
/// result, both while holding the registry, so that a signal cannot fall
/// between the creation and the registration.
pub fn register<T>(make: impl FnOnce() -> Result<(Cleanup, T)>) -> Result<(u64, T)> {
    let mut list = registry();
    let (cleanup, value) = make()?;
    let id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
    list.push((id, cleanup));
    Ok((id, value))
}

/// Unregisters `id` and hands its [`Cleanup`] to `finish` while still
/// holding the registry (a signal then waits until `finish` is done).
pub fn deregister(id: u64, finish: impl FnOnce(Option<Cleanup>)) {
    let mut list = registry();
    let cleanup = list
        .iter()
        .position(|(i, _)| *i == id)
        .map(|at| list.remove(at).1);
    finish(cleanup);
}

/// Runs `f` (a commit) while holding the registry: a signal arriving
/// meanwhile is acted on once `f` is done.
pub fn hold<T>(f: impl FnOnce() -> T) -> T {
    let _list = registry();
    f()
}

/// Removes every registered staging directory.
fn remove_all(list: &mut Vec<(u64, Cleanup)>) {
    for (_, cleanup) in list.drain(..) {
        cleanup.remove();
    }
}

/// Installs the handler of SIGINT, SIGTERM and SIGHUP (not of those the
/// process was started with ignored, as `nohup` does): a thread that,
/// on the first of them, removes every registered staging directory and
/// exits with 128 + the signal's number. Call once, at start.
#[cfg(unix)]
pub fn install() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let wanted: Vec<i32> = [SIGINT, SIGTERM, SIGHUP]
        .into_iter()
        .filter(|&s| !ignored(s))
        .collect();
    // Without the handler the signals keep their default action (the
    // process ends at once); staged files are then left, as before.
    let Ok(mut signals) = signal_hook::iterator::Signals::new(&wanted) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            // Held until the process ends: nothing registers or publishes
            // after this.
            let mut list = registry();
            remove_all(&mut list);
            std::process::exit(128 + signal);
        }
    });
}

#[cfg(not(unix))]
pub fn install() {}

/// Whether `signal` is ignored (set so by whoever started the process).
#[cfg(unix)]
fn ignored(signal: i32) -> bool {
    let mut old = std::mem::MaybeUninit::<libc::sigaction>::zeroed();
    // SAFETY: a query only (the new action is null); `old` is a valid,
    // writable sigaction that the call fills in on success.
    let rc = unsafe { libc::sigaction(signal, std::ptr::null(), old.as_mut_ptr()) };
    // SAFETY: zero-initialised, and filled in by the successful call.
    rc == 0 && unsafe { old.assume_init() }.sa_sigaction == libc::SIG_IGN
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removal_takes_the_staging_and_the_empty_made_dirs() {
        let root = tempfile::tempdir().unwrap();
        let made = root.path().join("a");
        let staging = made.join(".dembound-staging-x");
        fs::create_dir_all(staging.join("sub")).unwrap();
        fs::write(staging.join("sub/f"), "x").unwrap();
        Cleanup {
            staging,
            created: vec![made.clone()],
        }
        .remove();
        assert!(!made.exists());
    }

    #[test]
    fn registered_until_deregistered() {
        let (id, ()) = register(|| {
            Ok((
                Cleanup {
                    staging: PathBuf::from("/nonexistent/x"),
                    created: Vec::new(),
                },
                (),
            ))
        })
        .unwrap();
        let mut found = false;
        deregister(id, |c| found = c.is_some());
        assert!(found);
        deregister(id, |c| found = c.is_some());
        assert!(!found);
    }

    #[cfg(unix)]
    #[test]
    fn default_actions_are_not_ignored() {
        assert!(!ignored(signal_hook::consts::SIGTERM));
    }
}
