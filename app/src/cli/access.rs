//! What every user may reach: the directories a program run as another account can enter,
//! for the PATH it gets and the class folder `grade` reads.

use std::path::Path;

/// The entries of `path` (a PATH) that any user may search: every directory from the root
/// down open to others. A program run as an account gets this PATH, so that a command in a
/// directory it cannot enter (root's ~/.cargo/bin, say) is "not found", not "permission
/// denied", as it would be on the student's own machine.
pub fn searchable_path(path: &std::ffi::OsStr) -> std::ffi::OsString {
    let kept: Vec<std::path::PathBuf> = std::env::split_paths(path)
        .filter(|dir| dir.is_absolute() && open_to_others(dir))
        .collect();
    std::env::join_paths(kept).unwrap_or_default()
}

/// Whether every user may enter `dir` (absolute): every directory from the root down open to
/// others, as a program run as an account needs.
pub fn open_to_others(dir: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    dir.ancestors().all(|d| {
        std::fs::metadata(d).is_ok_and(|m| m.is_dir() && m.permissions().mode() & 0o001 != 0)
    })
}
