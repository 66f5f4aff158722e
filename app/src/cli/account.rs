//! The accounts `raylab grade` runs submissions as when it runs as root: a free uid per
//! worker, given each run's directory, and swept of what its programs left behind.

use super::program::{self, Limits, RunDir};
use std::path::Path;

/// Where every user may create files: what a submission's programs leave there is removed
/// before its account runs the next submission.
const SHARED_DIRS: [&str; 3] = ["/tmp", "/var/tmp", "/dev/shm"];

/// One account per worker when raylab runs as root, so the process limit holds (root is
/// exempt from it) and no program touches another's files; none otherwise, or when a program
/// cannot run as one here (a user namespace without the uid, a TMPDIR others cannot enter):
/// then programs run as root, said with the reason.
pub(super) fn accounts(jobs: usize, limits: &Limits) -> Vec<Option<Account>> {
    let none = || (0..jobs).map(|_| None).collect();
    if !rustix::process::geteuid().is_root() {
        return none();
    }
    let Some(claimed) = Account::claim(jobs) else {
        eprintln!("warning: no free uid to run the programs as: they run as root, and --max-processes does not hold");
        return none();
    };
    // A program run as the first, in a directory of its own: what every run does.
    let probe = || -> std::result::Result<(), String> {
        let dir = RunDir::new("grade").map_err(|e| e.to_string())?;
        claimed[0].give(dir.path()).map_err(|e| e.to_string())?;
        let limits = Limits {
            max_output_bytes: 1024,
            dir: Some(dir.path().to_path_buf()),
            run_as: Some(claimed[0].uid()),
            ..limits.clone()
        };
        program::run_with(std::ffi::OsStr::new("true"), &limits).map_err(|e| e.to_string())?;
        Ok(())
    };
    match probe() {
        Ok(()) => claimed.into_iter().map(Some).collect(),
        Err(e) => {
            eprintln!("warning: cannot run a program as uid {} ({e}): the programs run as root, and --max-processes does not hold", claimed[0].uid());
            none()
        }
    }
}

/// An unprivileged uid (and gid of the same number) that runs one submission at a time when
/// raylab runs as root: RLIMIT_NPROC counts its processes alone (root is exempt from it),
/// its processes are found by their uid, and it cannot touch root's files or another
/// account's directory. Never a uid of /etc/passwd or /etc/group or of a running process;
/// held, system-wide, by binding the abstract socket `raylab-uid-<uid>` (released when
/// raylab ends, however it ends), so two graders never share one.
pub(super) struct Account {
    uid: u32,
    _held: std::os::unix::net::UnixListener,
}

impl Account {
    /// The uids tried.
    const RANGE: std::ops::Range<u32> = 61_000..65_000;

    /// `n` free accounts, or none.
    fn claim(n: usize) -> Option<Vec<Account>> {
        use std::os::linux::net::SocketAddrExt;
        use std::os::unix::net::{SocketAddr, UnixListener};
        let taken = |file: &str| -> Vec<u32> {
            let text = std::fs::read_to_string(file).unwrap_or_default();
            let ids = text
                .lines()
                .filter_map(|l| l.split(':').nth(2)?.parse().ok());
            ids.collect()
        };
        let (users, groups) = (taken("/etc/passwd"), taken("/etc/group"));
        let running = program::uids_running();
        let free = Self::RANGE
            .filter(|u| !(users.contains(u) || groups.contains(u) || running.contains(u)));
        let held = free.filter_map(|uid| {
            let name = SocketAddr::from_abstract_name(format!("raylab-uid-{uid}")).ok()?;
            let _held = UnixListener::bind_addr(&name).ok()?;
            Some(Account { uid, _held })
        });
        let accounts: Vec<Account> = held.take(n).collect();
        (accounts.len() == n).then_some(accounts)
    }

    pub(super) fn uid(&self) -> u32 {
        self.uid
    }

    /// Gives `path` and everything below it to the account (links themselves, not followed).
    pub(super) fn give(&self, path: &Path) -> std::io::Result<()> {
        std::os::unix::fs::lchown(path, Some(self.uid), Some(self.uid))?;
        if std::fs::symlink_metadata(path)?.is_dir() {
            for entry in std::fs::read_dir(path)? {
                self.give(&entry?.path())?;
            }
        }
        Ok(())
    }

    /// Removes what the account's programs left in the directories every user may write
    /// ([`SHARED_DIRS`]), so that the next submission run as this uid finds nothing of this
    /// one's (its answers, say). Its processes have ended by then.
    pub(super) fn sweep(&self) {
        use std::os::unix::fs::MetadataExt;
        for dir in SHARED_DIRS {
            let Ok(entries) = std::fs::read_dir(dir) else {
                continue;
            };
            for entry in entries.flatten() {
                let path = entry.path();
                let Ok(meta) = std::fs::symlink_metadata(&path) else {
                    continue;
                };
                if meta.uid() != self.uid {
                    continue;
                }
                let removed = match meta.is_dir() {
                    true => std::fs::remove_dir_all(&path),
                    false => std::fs::remove_file(&path),
                };
                if let Err(e) = removed {
                    eprintln!(
                        "warning: cannot remove {} left by uid {}: {e}",
                        path.display(),
                        self.uid
                    );
                }
            }
        }
    }
}
