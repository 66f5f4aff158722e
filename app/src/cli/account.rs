//! The accounts `raylab grade` runs submissions as when it runs as root: a free uid per
//! worker, given each run's directory, and swept of what its programs left behind.

use super::program::{self, Limits, RunDir};
use anyhow::{bail, Result};
use std::path::Path;
use std::time::Duration;

/// Where every user may create files: what a submission's programs leave there is removed
/// before its account runs the next submission.
const SHARED_DIRS: [&str; 5] = ["/tmp", "/var/tmp", "/dev/shm", "/run/lock", "/dev/mqueue"];

/// How deep [`Account::sweep`] follows world-writable directories within [`SHARED_DIRS`].
const SWEEP_DEPTH: usize = 8;

/// One account per worker when raylab runs as root, so the process limit holds (root is
/// exempt from it) and no program touches another's files; none when raylab is not root.
/// Where a program cannot run as one here (no free uid, a user namespace without the uid, a
/// TMPDIR others cannot enter) the grading is refused, naming why, unless `as_root` lets the
/// programs run as root (said on stderr).
pub(super) fn accounts(
    jobs: usize,
    limits: &Limits,
    as_root: bool,
) -> Result<Vec<Option<Account>>> {
    let none = || (0..jobs).map(|_| None).collect();
    if !rustix::process::geteuid().is_root() {
        return Ok(none());
    }
    let claimed = Account::claim(jobs).ok_or_else(|| "no free uid".to_string());
    // A program run as the first, in a directory of its own: what every run does (within a
    // time of its own: a --timeout too short for `true` must not decide this).
    let probe = |claimed: &[Account]| -> std::result::Result<(), String> {
        let dir = RunDir::new("grade").map_err(|e| e.to_string())?;
        claimed[0].give(dir.path()).map_err(|e| e.to_string())?;
        let limits = Limits {
            timeout: Duration::from_secs(30),
            max_output_bytes: 1024,
            dir: Some(dir.path().to_path_buf()),
            run_as: Some(claimed[0].uid()),
            ..limits.clone()
        };
        let ran = program::run_with(std::ffi::OsStr::new("true"), &limits);
        ran.map(|_| ())
            .map_err(|e| format!("as uid {}: {e}", claimed[0].uid()))
    };
    let why = match claimed {
        Ok(claimed) => match probe(&claimed) {
            Ok(()) => return Ok(claimed.into_iter().map(Some).collect()),
            Err(why) => why,
        },
        Err(why) => why,
    };
    if !as_root {
        bail!(
            "cannot run the programs as an unprivileged uid ({why}), and as root they could read \
             and change anything (TMPDIR must be a directory every user may enter; --as-root \
             runs them as root all the same)"
        );
    }
    eprintln!("warning: the programs run as root ({why}), and --max-processes does not hold");
    Ok(none())
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
    /// ([`SHARED_DIRS`], and the world-writable directories within them, as /tmp/.X11-unix)
    /// and in System V shared memory, semaphores and message queues, so that the next
    /// submission run as this uid finds nothing of this one's (its answers, say) and no memory
    /// stays held. Its processes have ended by then.
    pub(super) fn sweep(&self) {
        self.sweep_ipc();
        for dir in SHARED_DIRS {
            self.sweep_dir(Path::new(dir), 0);
        }
    }

    /// Removes the account's files and directories in `dir`, and in the world-writable
    /// directories there (not its links' targets), at most [`SWEEP_DEPTH`] deep. (A file a
    /// program wrote into /tmp/.X11-unix stayed for the next submission of its uid.)
    fn sweep_dir(&self, dir: &Path, depth: usize) {
        use std::os::unix::fs::MetadataExt;
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let Ok(meta) = std::fs::symlink_metadata(&path) else {
                continue;
            };
            if meta.uid() != self.uid {
                let open = meta.is_dir() && meta.mode() & 0o002 != 0;
                if open && depth < SWEEP_DEPTH {
                    self.sweep_dir(&path, depth + 1);
                }
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

    /// Removes the System V IPC objects (/proc/sysvipc: shm, sem, msg) the account made or
    /// owns, with `ipcrm` (util-linux).
    fn sweep_ipc(&self) {
        for (table, option) in [("shm", "-m"), ("sem", "-s"), ("msg", "-q")] {
            let text =
                std::fs::read_to_string(format!("/proc/sysvipc/{table}")).unwrap_or_default();
            for id in ipc_ids_of(&text, self.uid) {
                let removed = std::process::Command::new("ipcrm")
                    .args([option, &id])
                    .output();
                if !removed.is_ok_and(|o| o.status.success()) {
                    eprintln!(
                        "warning: cannot remove System V {table} {id} of uid {}",
                        self.uid
                    );
                }
            }
        }
    }
}

/// The ids of a /proc/sysvipc table's objects whose owner or creator is `uid` (the columns
/// found by the header's names: `shmid`, `semid` or `msqid`; `uid`; `cuid`).
fn ipc_ids_of(table: &str, uid: u32) -> Vec<String> {
    let mut lines = table.lines();
    let header: Vec<&str> = lines
        .next()
        .unwrap_or_default()
        .split_whitespace()
        .collect();
    let column = |name: &str| header.iter().position(|h| *h == name);
    let id = ["shmid", "semid", "msqid"].into_iter().find_map(column);
    let (Some(id), Some(owner), Some(creator)) = (id, column("uid"), column("cuid")) else {
        return Vec::new();
    };
    let uid = uid.to_string();
    lines
        .map(|l| l.split_whitespace().collect::<Vec<&str>>())
        .filter(|w| w.get(owner) == Some(&uid.as_str()) || w.get(creator) == Some(&uid.as_str()))
        .filter_map(|w| w.get(id).map(|s| s.to_string()))
        .collect()
}
