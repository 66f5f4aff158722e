//! A run's private directory, removed when dropped and at a signal.

use super::{init, registry};
use std::path::{Path, PathBuf};

/// A new private directory for a run, removed when dropped and at Ctrl+C or SIGTERM:
/// `raylab-<what>-<pid>-<n>-<nanos>` in the temporary directory, mode 0700, its name never
/// one that existed (created exclusively, a new name on a clash).
#[derive(Debug)]
pub struct RunDir {
    path: PathBuf,
}

impl RunDir {
    pub fn new(what: &str) -> std::io::Result<RunDir> {
        use std::os::unix::fs::DirBuilderExt;
        use std::sync::atomic::{AtomicU64, Ordering};
        static NEXT: AtomicU64 = AtomicU64::new(0);
        init();
        let base = std::env::temp_dir();
        loop {
            let nanos = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.subsec_nanos());
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let name = format!("raylab-{what}-{}-{n}-{nanos:08x}", std::process::id());
            let path = base.join(name);
            // Created and registered under the lock the signal handler takes: never left.
            let mut registry = registry();
            match std::fs::DirBuilder::new().mode(0o700).create(&path) {
                Ok(()) => {
                    registry.dirs.push(path.clone());
                    return Ok(RunDir { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for RunDir {
    fn drop(&mut self) {
        remove_tree(&self.path);
        registry().dirs.retain(|d| *d != self.path);
    }
}

/// Removes `path` and everything in it, also what a program made unreadable (as the same
/// user: its directories are given their owner's permissions back first).
pub(super) fn remove_tree(path: &Path) {
    if std::fs::symlink_metadata(path).is_ok_and(|m| !m.is_dir()) {
        let _ = std::fs::remove_file(path);
        return;
    }
    if std::fs::remove_dir_all(path).is_ok() || !path.exists() {
        return;
    }
    fn open_up(path: &Path) {
        use std::os::unix::fs::PermissionsExt;
        let Ok(meta) = std::fs::symlink_metadata(path) else {
            return;
        };
        if meta.is_dir() {
            let _ = std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o700));
            for entry in std::fs::read_dir(path).into_iter().flatten().flatten() {
                open_up(&entry.path());
            }
        }
    }
    open_up(path);
    let _ = std::fs::remove_dir_all(path);
}
