//! Running a program that is not raylab's (`raylab check --program`, `raylab grade`): through
//! the shell, with the scene's and the rays' paths in its command, its standard output read as
//! its answers. A program never holds raylab up, fills its memory or outlives its run: when
//! its time is up, its output passes a limit or its shell ends, it is stopped with every
//! process it started, those that left its process group or session included. Ctrl+C or
//! SIGTERM on raylab stops them too and removes the [`RunDir`]s. Linux (it reads /proc).
//!
//! Finding the processes: the shell leads a process group of its own; /proc is read while it
//! runs and every process below it is remembered with its group and session (a `setsid`
//! daemon keeps its pid, and its new session is its own); raylab is a child subreaper, so a
//! daemon whose parent died becomes raylab's child instead of init's, never lost; and a
//! program run as a uid of its own (`raylab grade` as root) is every process of that uid.

mod run_dir;
use run_dir::remove_tree;
pub use run_dir::RunDir;

use std::collections::{HashMap, HashSet};
use std::ffi::OsStr;
use std::fs::File;
use std::io::{Read, Write};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::{Mutex, MutexGuard, Once};
use std::time::{Duration, Instant};

use rustix::process::{Pid, Signal};

/// What a program printed, and how long it took.
#[derive(Debug)]
pub struct Ran {
    pub stdout: String,
    /// The end of its standard error, trimmed.
    pub stderr_tail: String,
    pub elapsed: Duration,
}

/// Why a program's answers could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("cannot start the shell: {0}")]
    Start(std::io::Error),
    /// The directory it runs in is gone (a program that removed its own copy: "cannot start
    /// the shell: No such file" read as if `sh` were missing).
    #[error(
        "its directory {0} is gone: a run of the program removed it (one copy of the \
         submission serves all its families)"
    )]
    NoDir(PathBuf),
    /// With what it had printed (how far its answers came).
    #[error("ran out of time ({secs:.1} s; --timeout sets another limit)")]
    Timeout { secs: f64, printed: Vec<u8> },
    #[error("printed more than {0} bytes, over 160 a ray and 1 MiB: not answers to these rays")]
    TooMuch(usize),
    /// With what it had printed (how far its answers came).
    #[error("ended with {}{stderr}", ended(status))]
    Failed {
        status: ExitStatus,
        stderr: String,
        printed: Vec<u8>,
    },
    #[error("printed {0}")]
    NotText(raylab::input::NotText),
}

/// An exit status as said: the shell's 128 + N of a program killed by signal N named so
/// ("exit status: 139" said nothing of a SIGSEGV: the command runs under `sh -c`).
fn ended(status: &ExitStatus) -> String {
    const NAMES: [(i32, &str); 10] = [
        (4, "SIGILL"),
        (6, "SIGABRT"),
        (7, "SIGBUS"),
        (8, "SIGFPE"),
        (9, "SIGKILL"),
        (11, "SIGSEGV"),
        (13, "SIGPIPE"),
        (15, "SIGTERM"),
        (24, "SIGXCPU"),
        (25, "SIGXFSZ"),
    ];
    let name = |n: i32| NAMES.iter().find(|(k, _)| *k == n).map(|(_, name)| *name);
    match status.code().and_then(|c| name(c - 128).map(|n| (c, n))) {
        Some((code, n)) => format!(
            "exit status: {code} (the shell's for a program killed by signal {}, {n})",
            code - 128
        ),
        // (A student's run.sh without x was "exit status: 126 … Permission denied", no more.)
        None if status.code() == Some(126) => "exit status: 126 (the shell's for a file it may \
            not run: `chmod +x` it, or name its interpreter, `sh run.sh`)"
            .into(),
        None => status.to_string(),
    }
}

/// What a run may use. `run` gives a time and an output limit; `raylab grade` all of them.
#[derive(Clone, Debug)]
pub struct Limits {
    /// Wall time from the start of the program to the end of its shell.
    pub timeout: Duration,
    /// Bytes of standard output; more ends the run ([`RunError::TooMuch`]).
    pub max_output_bytes: usize,
    /// Data (heap and written memory) of each process: RLIMIT_DATA, not the address space, so
    /// a runtime that reserves much and uses little (the JVM, .NET) still starts.
    pub max_memory_bytes: Option<u64>,
    /// Processes (threads count) at once: RLIMIT_NPROC, which counts every process of the
    /// user, so as a normal user the limit is the user's count at the start plus this; as
    /// root it holds only with `run_as` (root is exempt from RLIMIT_NPROC).
    pub max_processes: Option<u64>,
    /// The working directory (default: raylab's).
    pub dir: Option<PathBuf>,
    /// The uid (and gid) to run as, one no other process has; HOME and TMPDIR become `dir`,
    /// PATH the entries it may search.
    pub run_as: Option<u32>,
    /// The only variables of raylab's environment the program gets, where not all (`grade`:
    /// a submission does not see the teacher's); HOME and TMPDIR become `dir` then too.
    pub env: Option<Vec<String>>,
}

impl Limits {
    /// A time and an output limit, nothing else.
    pub fn new(timeout: Duration, max_output_bytes: usize) -> Self {
        Self {
            timeout,
            max_output_bytes,
            max_memory_bytes: None,
            max_processes: None,
            dir: None,
            run_as: None,
            env: None,
        }
    }
}

/// How long the pipes are read after the program itself ended: what it wrote last is still
/// in them, but a daemon it left holding them never holds the run up.
const GRACE: Duration = Duration::from_millis(200);

/// How often /proc is read for the processes the program started.
const SCAN_EVERY: Duration = Duration::from_millis(50);

/// The longest wait for the pipes between two checks of the program's state.
const TICK: Duration = Duration::from_millis(5);

/// The bytes of standard error kept for the message of a failed run.
const STDERR_TAIL: usize = 2000;

/// The shell raylab starts: it waits for one line on its standard input before it runs the
/// command (`$1`), so the limits are in place and the run is registered for Ctrl+C before any
/// of the program runs; if raylab dies first, the pipe closes and nothing runs.
const GATE: &str = r#"read -r _ && exec sh -c "$1" </dev/null"#;

/// Runs `command` (a shell command's bytes, [`super::template::command_line`]) with `sh -c`,
/// standard input empty, within `limits`; returns its standard output. It is stopped, with
/// every process it started, after the timeout or once it has printed more than its limit; a
/// status other than success is an error quoting the end of its standard error.
pub fn run_with(command: &OsStr, limits: &Limits) -> Result<Ran, RunError> {
    init();
    let mut shell = Command::new("sh");
    shell
        .arg("-c")
        .arg(GATE)
        .arg("sh")
        .arg(command)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .process_group(0);
    if let Some(dir) = &limits.dir {
        shell.current_dir(dir);
    }
    if let Some(names) = &limits.env {
        shell.env_clear();
        for name in names {
            if let Some(value) = std::env::var_os(name) {
                shell.env(name, value);
            }
        }
    }
    if let Some(uid) = limits.run_as {
        // setgroups(0) comes with it: none of root's groups stay.
        shell.uid(uid).gid(uid);
        let path = std::env::var_os("PATH").unwrap_or_default();
        shell.env("PATH", super::access::searchable_path(&path));
    }
    let own_home = limits.run_as.is_some() || limits.env.is_some();
    if let Some(dir) = limits.dir.as_ref().filter(|_| own_home) {
        shell.env("HOME", dir).env("TMPDIR", dir);
    }
    // Started and registered at once, so no sweep takes the new shell for a stray.
    let (mut child, id) = {
        let mut registry = registry();
        let child = shell.spawn().map_err(|e| match &limits.dir {
            Some(dir) if !dir.is_dir() => RunError::NoDir(dir.clone()),
            _ => RunError::Start(e),
        })?;
        let id = registry.add(child.id() as i32, limits.run_as);
        (child, id)
    };
    let shell_pid = child.id() as i32;
    let end = |child: &mut std::process::Child| {
        stop(id);
        let _ = child.kill();
        let _ = child.wait();
        registry().remove(id);
    };
    if let Err(e) = set_limits(shell_pid, limits) {
        end(&mut child);
        return Err(RunError::Start(e));
    }
    let mut stdout = child
        .stdout
        .take()
        .map(|p| File::from(std::os::fd::OwnedFd::from(p)));
    let mut stderr = child
        .stderr
        .take()
        .map(|p| File::from(std::os::fd::OwnedFd::from(p)));
    let (mut out, mut err, mut overflow) = (Vec::new(), Vec::new(), false);
    let start = Instant::now();
    if let Some(mut gate) = child.stdin.take() {
        // (A shell already gone shows as its status below.)
        let _ = gate.write_all(b"\n");
    }
    let deadline = start + limits.timeout;
    let mut ended: Option<(ExitStatus, Instant)> = None;
    let mut next_scan = start + Duration::from_millis(20);
    loop {
        let now = Instant::now();
        if ended.is_none() {
            if let Ok(Some(status)) = child.try_wait() {
                ended = Some((status, now));
            }
        }
        let limit = match ended {
            Some((_, at)) => at + GRACE,
            None => deadline,
        };
        let pipes_done = stdout.is_none() && stderr.is_none();
        if overflow || now >= limit || (pipes_done && ended.is_some()) {
            break;
        }
        if now >= next_scan && ended.is_none() {
            track();
            next_scan = now + SCAN_EVERY;
        }
        let wait = TICK.min(limit - now);
        let mut sink = Sink {
            out: &mut out,
            err: &mut err,
            max: limits.max_output_bytes,
        };
        overflow = read_ready(&mut stdout, &mut stderr, &mut sink, wait);
    }
    let elapsed = match ended {
        Some((_, at)) => at - start,
        None => start.elapsed(),
    };
    end(&mut child);
    // What is left in the pipes (the writers are gone, or will never be waited for again).
    while !overflow && (stdout.is_some() || stderr.is_some()) {
        let before = (out.len(), err.len(), stdout.is_some(), stderr.is_some());
        let mut sink = Sink {
            out: &mut out,
            err: &mut err,
            max: limits.max_output_bytes,
        };
        overflow = read_ready(&mut stdout, &mut stderr, &mut sink, Duration::ZERO);
        if before == (out.len(), err.len(), stdout.is_some(), stderr.is_some()) {
            break;
        }
    }
    if overflow {
        return Err(RunError::TooMuch(limits.max_output_bytes));
    }
    let Some((status, _)) = ended else {
        let secs = limits.timeout.as_secs_f64();
        return Err(RunError::Timeout { secs, printed: out });
    };
    if !status.success() {
        let err = String::from_utf8_lossy(&err);
        let err = err.trim();
        let stderr = match err.is_empty() {
            true => String::new(),
            false => format!("; its last words: {}", err.replace('\n', " | ")),
        };
        return Err(RunError::Failed {
            status,
            stderr,
            printed: out,
        });
    }
    let stdout = raylab::input::text_of(out).map_err(RunError::NotText)?;
    let stderr_tail = String::from_utf8_lossy(&err).trim().to_string();
    Ok(Ran {
        stdout,
        stderr_tail,
        elapsed,
    })
}

/// Where the pipes' bytes go: all of standard output up to `max`, the end of standard error.
struct Sink<'a> {
    out: &'a mut Vec<u8>,
    err: &'a mut Vec<u8>,
    max: usize,
}

/// Waits up to `wait` for either pipe to have data (or to close), reads what came and drops
/// a pipe at its end; true once standard output passed the limit.
fn read_ready(
    stdout: &mut Option<File>,
    stderr: &mut Option<File>,
    sink: &mut Sink,
    wait: Duration,
) -> bool {
    use rustix::event::{poll, PollFd, PollFlags, Timespec};
    let ready = {
        let mut fds: Vec<PollFd> = [&*stdout, &*stderr]
            .into_iter()
            .flatten()
            .map(|f| PollFd::new(f, PollFlags::IN))
            .collect();
        let timeout = Timespec {
            tv_sec: wait.as_secs() as i64,
            tv_nsec: wait.subsec_nanos() as i64,
        };
        if poll(&mut fds, Some(&timeout)).is_err() {
            return false; // (interrupted: looked at again on the next turn)
        }
        let mut ready = fds.iter().map(|f| !f.revents().is_empty());
        let out = stdout.is_some() && ready.next().unwrap_or(false);
        let err = stderr.is_some() && ready.next().unwrap_or(false);
        (out, err)
    };
    let mut buf = [0u8; 64 * 1024];
    if ready.0 {
        match stdout.as_ref().map(|mut f| f.read(&mut buf)) {
            Some(Ok(0)) | Some(Err(_)) | None => *stdout = None,
            Some(Ok(n)) if sink.out.len() + n > sink.max => return true,
            Some(Ok(n)) => sink.out.extend_from_slice(&buf[..n]),
        }
    }
    if ready.1 {
        match stderr.as_ref().map(|mut f| f.read(&mut buf)) {
            Some(Ok(0)) | Some(Err(_)) | None => *stderr = None,
            Some(Ok(n)) => {
                sink.err.extend_from_slice(&buf[..n]);
                if sink.err.len() > 2 * STDERR_TAIL {
                    sink.err.drain(..sink.err.len() - STDERR_TAIL);
                }
            }
        }
    }
    false
}

/// Sets the limits on the waiting shell (they pass to everything it starts), never above
/// raylab's own hard limits (only CAP_SYS_RESOURCE may raise one).
fn set_limits(pid: i32, limits: &Limits) -> std::io::Result<()> {
    use rustix::process::{getrlimit, getuid, prlimit, Resource, Rlimit};
    // (`None` would be raylab itself.)
    let pid = Some(Pid::from_raw(pid).ok_or(std::io::ErrorKind::InvalidInput)?);
    let cap = |resource: Resource, value: u64| {
        let value = getrlimit(resource)
            .maximum
            .map_or(value, |hard| value.min(hard));
        let limit = Rlimit {
            current: Some(value),
            maximum: Some(value),
        };
        prlimit(pid, resource, limit).map(|_| ())
    };
    let nproc = limits.max_processes.map(|n| match limits.run_as {
        // An account's processes are all the program's; as root without one the limit does
        // not hold (root is exempt from it).
        Some(_) => n,
        None if getuid().is_root() => n,
        None => user_tasks(getuid().as_raw()).saturating_add(n),
    });
    as_real_ids(limits.run_as, || {
        if limits.max_memory_bytes.is_some() || limits.max_processes.is_some() {
            // No core files of a crash in the submission's directory.
            cap(Resource::Core, 0)?;
        }
        if let Some(bytes) = limits.max_memory_bytes {
            cap(Resource::Data, bytes)?;
        }
        if let Some(n) = nproc {
            cap(Resource::Nproc, n)?;
        }
        Ok(())
    })
}

/// Runs `f` with this thread's real uid and gid `id` (its effective ids stay root's, and
/// with them its capabilities), then puts them back: prlimit(2) on a process of another
/// user needs CAP_SYS_RESOURCE, which root in a container often lacks, unless the caller's
/// real ids are the target's. Linux's ids are per thread: no other thread sees the change.
/// (Meanwhile the account could signal this thread, but only the gate runs as it then.)
fn as_real_ids(id: Option<u32>, f: impl FnOnce() -> std::io::Result<()>) -> std::io::Result<()> {
    use rustix::process::{Gid, Uid};
    use rustix::thread::{set_thread_res_gid, set_thread_res_uid};
    let Some(id) = id else {
        return f();
    };
    let (uid, gid) = (rustix::process::getuid(), rustix::process::getgid());
    set_thread_res_gid(Gid::from_raw(id), None, None)?;
    if let Err(e) = set_thread_res_uid(Uid::from_raw(id), None, None) {
        set_thread_res_gid(gid, None, None).expect("the real gid back");
        return Err(e.into());
    }
    let result = f();
    // The effective uid, root's, keeps CAP_SETUID: this cannot fail, and must not.
    set_thread_res_uid(uid, None, None).expect("the real uid back");
    set_thread_res_gid(gid, None, None).expect("the real gid back");
    result
}

/// A process as /proc shows it.
#[derive(Clone, Copy, Debug)]
struct Proc {
    pid: i32,
    ppid: i32,
    pgid: i32,
    sid: i32,
    /// Clock ticks from boot to its start: with the pid, its identity (pids are reused).
    start: u64,
    zombie: bool,
    /// Real, effective, saved and file uids (read only when asked for).
    uids: [u32; 4],
    threads: u64,
}

/// Every process (`with_uids`: with its uids and thread count, from its status file).
fn scan(with_uids: bool) -> Vec<Proc> {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    dir.filter_map(|e| {
        let pid = e.ok()?.file_name().to_str()?.parse().ok()?;
        read_proc(pid, with_uids)
    })
    .collect()
}

fn read_proc(pid: i32, with_uids: bool) -> Option<Proc> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // `pid (comm) state ppid pgrp session …`: comm may hold spaces and parentheses.
    let f: Vec<&str> = stat
        .get(stat.rfind(')')? + 1..)?
        .split_whitespace()
        .collect();
    let mut p = Proc {
        pid,
        ppid: f.get(1)?.parse().ok()?,
        pgid: f.get(2)?.parse().ok()?,
        sid: f.get(3)?.parse().ok()?,
        start: f.get(19)?.parse().ok()?,
        zombie: matches!(f[0], "Z" | "X"),
        uids: [u32::MAX; 4],
        threads: 1,
    };
    if with_uids {
        let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
        for line in status.lines() {
            if let Some(ids) = line.strip_prefix("Uid:") {
                for (k, id) in ids.split_whitespace().take(4).enumerate() {
                    p.uids[k] = id.parse().unwrap_or(u32::MAX);
                }
            } else if let Some(n) = line.strip_prefix("Threads:") {
                p.threads = n.trim().parse().unwrap_or(1);
            }
        }
    }
    Some(p)
}

/// The tasks (threads) of `uid`, which RLIMIT_NPROC counts.
fn user_tasks(uid: u32) -> u64 {
    scan(true)
        .iter()
        .filter(|p| p.uids[0] == uid)
        .map(|p| p.threads)
        .sum()
}

/// raylab's own pid, process group and session: never a program's, never killed.
fn own() -> Proc {
    static OWN: std::sync::OnceLock<Proc> = std::sync::OnceLock::new();
    *OWN.get_or_init(|| {
        let pid = rustix::process::getpid().as_raw_nonzero().get();
        read_proc(pid, false).unwrap_or(Proc {
            pid,
            ppid: 0,
            pgid: pid,
            sid: pid,
            start: 0,
            zombie: false,
            uids: [u32::MAX; 4],
            threads: 1,
        })
    })
}

/// A program running: its shell and every process, group and session seen below it.
struct Live {
    id: u64,
    since: Instant,
    shell: i32,
    run_as: Option<u32>,
    pids: HashSet<(i32, u64)>,
    groups: HashSet<i32>,
    sessions: HashSet<i32>,
}

/// The programs running, and the directories to remove at Ctrl+C.
struct Registry {
    runs: Vec<Live>,
    /// The run directories, and files, to remove at a signal.
    dirs: Vec<PathBuf>,
    next: u64,
}

/// Has `path` (an output's temporary file, say) removed at Ctrl+C or SIGTERM, with the run
/// directories (from now on: the signals are caught here).
pub fn remove_at_signal(path: &Path) {
    init();
    registry().dirs.push(path.to_path_buf());
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    runs: Vec::new(),
    dirs: Vec::new(),
    next: 0,
});

/// The registry, even after a panic elsewhere (its data stays consistent between calls).
fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY.lock().unwrap_or_else(|e| e.into_inner())
}

/// Whose a process is, by [`Registry::owners`].
#[derive(Clone, Copy, PartialEq, Eq)]
enum Owner {
    Run(usize),
    /// Adopted by raylab (its parent died) before it was seen, while several programs run:
    /// a program's, but not known whose.
    Stray,
}

/// Which processes [`Registry::sweep`] kills, besides the strays.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Scope {
    Strays,
    Run(u64),
    All,
}

impl Registry {
    fn add(&mut self, shell: i32, run_as: Option<u32>) -> u64 {
        self.next += 1;
        let start = read_proc(shell, false).map_or(0, |p| p.start);
        self.runs.push(Live {
            id: self.next,
            since: Instant::now(),
            shell,
            run_as,
            pids: HashSet::from([(shell, start)]),
            groups: HashSet::from([shell]),
            sessions: HashSet::new(),
        });
        self.next
    }

    fn remove(&mut self, id: u64) {
        self.runs.retain(|r| r.id != id);
    }

    /// The owner of each process of `procs` that is a program's, and what is seen is
    /// remembered (so a process stays its program's after it leaves the group or session,
    /// or its parent dies).
    fn owners(&mut self, procs: &[Proc]) -> Vec<(Proc, Owner)> {
        let me = own();
        let by_pid: HashMap<i32, &Proc> = procs.iter().map(|p| (p.pid, p)).collect();
        let shells: HashSet<i32> = self.runs.iter().map(|r| r.shell).collect();
        let mut found = Vec::new();
        for p in procs.iter().filter(|p| p.pid != me.pid) {
            let owner = self.runs.iter().position(|r| {
                r.run_as.is_some_and(|uid| p.uids.contains(&uid))
                    || r.pids.contains(&(p.pid, p.start))
                    || (p.pgid != me.pgid && r.groups.contains(&p.pgid))
                    || (p.sid != me.sid && r.sessions.contains(&p.sid))
                    || ancestors(p, &by_pid, me.pid).any(|a| r.pids.contains(&(a.pid, a.start)))
            });
            let owner = match owner {
                Some(k) => Owner::Run(k),
                None if p.ppid == me.pid && self.runs.len() == 1 => Owner::Run(0),
                None if p.ppid == me.pid => Owner::Stray,
                None => continue,
            };
            if let Owner::Run(k) = owner {
                let r = &mut self.runs[k];
                r.pids.insert((p.pid, p.start));
                // Only a group the run leads (its shell's, or one an owned process made with
                // setsid or setpgid(0, 0)): a process may join another group of raylab's
                // session, which is not the run's to kill.
                let leads = p.pgid == r.shell || (p.pgid == p.pid && !shells.contains(&p.pgid));
                if p.pgid != me.pgid && leads {
                    r.groups.insert(p.pgid);
                }
                if p.sid != me.sid {
                    r.sessions.insert(p.sid);
                }
            }
            found.push((*p, owner));
        }
        found
    }

    /// Kills the strays and the processes of the runs in `scope`, and reaps raylab's adopted
    /// children that ended; the number of processes signalled.
    fn sweep(&mut self, procs: &[Proc], scope: Scope) -> usize {
        let owners = self.owners(procs);
        self.sweep_owned(&owners, scope)
    }

    /// [`Registry::sweep`] with the owners known.
    fn sweep_owned(&mut self, owners: &[(Proc, Owner)], scope: Scope) -> usize {
        use rustix::process::{kill_process, kill_process_group, waitpid, WaitOptions};
        let me = own();
        let shells: HashSet<i32> = self.runs.iter().map(|r| r.shell).collect();
        let target = match scope {
            Scope::Run(id) => self.runs.iter().position(|r| r.id == id),
            Scope::Strays | Scope::All => None,
        };
        let chosen = |k: usize| scope == Scope::All || Some(k) == target;
        let mut groups = HashSet::new();
        let mut pids = Vec::new();
        for &(p, owner) in owners {
            if p.zombie {
                // An adopted process that ended; the shells are std's to wait for.
                if let Some(pid) = Pid::from_raw(p.pid).filter(|_| p.ppid == me.pid) {
                    if !shells.contains(&p.pid) {
                        let _ = waitpid(Some(pid), WaitOptions::NOHANG);
                    }
                }
                continue;
            }
            let mine = match owner {
                Owner::Stray => true,
                Owner::Run(k) => chosen(k),
            };
            if mine {
                pids.extend(Pid::from_raw(p.pid));
                if p.pgid == p.pid || shells.contains(&p.pgid) {
                    groups.insert(p.pgid);
                }
            }
        }
        for (_, r) in self.runs.iter().enumerate().filter(|(k, _)| chosen(*k)) {
            groups.extend(r.groups.iter().copied());
        }
        // Whole groups first, at once: a fork bomb in one cannot outpace them.
        for g in groups.into_iter().filter(|&g| g != me.pgid) {
            if let Some(g) = Pid::from_raw(g) {
                let _ = kill_process_group(g, Signal::KILL);
            }
        }
        for &pid in &pids {
            let _ = kill_process(pid, Signal::KILL);
        }
        pids.len()
    }

    /// Whether any run goes as an account (then /proc is read with the uids).
    fn with_uids(&self) -> bool {
        self.runs.iter().any(|r| r.run_as.is_some())
    }
}

/// The parents of `p`, nearest first, up to raylab or init.
fn ancestors<'a>(
    p: &Proc,
    by_pid: &'a HashMap<i32, &'a Proc>,
    me: i32,
) -> impl Iterator<Item = &'a Proc> + 'a {
    let mut next = by_pid.get(&p.ppid).copied();
    std::iter::from_fn(move || {
        let q = next.filter(|q| q.pid > 1 && q.pid != me)?;
        next = by_pid.get(&q.ppid).copied();
        Some(q)
    })
    .take(256)
}

/// A program with more processes than this at once runs at the lowest priority.
const CROWD: usize = 8;

/// A run longer than this runs at [`LONG_RUN_NICE`].
const LONG_RUN: Duration = Duration::from_secs(2);

/// The priority of a long run: about a tenth of a core's share against a run at the usual
/// priority (nice 19, a seventieth, could starve a correct slow program on a teacher's busy
/// machine past its --timeout).
const LONG_RUN_NICE: i32 = 10;

/// Reads /proc and remembers the programs' processes; kills the strays (adopted while several
/// programs run and not yet seen: nobody waits for them); and a program with more than
/// [`CROWD`] processes goes to nice 19, a run past [`LONG_RUN`] to [`LONG_RUN_NICE`], all of
/// its processes and what they start after: a fork bomb, even capped, takes about one
/// process's share of the CPU from the programs graded beside it, not 64, and a hang, till its
/// --timeout, little of a neighbour's (a correct program's grade does not hang on who it is
/// graded beside).
fn track() {
    let procs = scan(registry().with_uids());
    let mut registry = registry();
    let owners = registry.owners(&procs);
    registry.sweep_owned(&owners, Scope::Strays);
    let mut counts = vec![0; registry.runs.len()];
    for (p, owner) in &owners {
        if let (Owner::Run(k), false) = (owner, p.zombie) {
            counts[*k] += 1;
        }
    }
    let long: Vec<bool> = (registry.runs.iter())
        .map(|r| r.since.elapsed() > LONG_RUN)
        .collect();
    for (p, owner) in &owners {
        if let (Owner::Run(k), false) = (owner, p.zombie) {
            let nice = match (counts[*k] > CROWD, long[*k]) {
                (true, _) => 19,
                (false, true) => LONG_RUN_NICE,
                (false, false) => continue,
            };
            // (`None` would be raylab.)
            if let Some(pid) = Pid::from_raw(p.pid) {
                let _ = rustix::process::setpriority_process(Some(pid), nice);
            }
        }
    }
}

/// Kills run `id`'s processes until none is left (a bounded number of rounds: a capped fork
/// bomb ends in a few).
fn stop(id: u64) {
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut pause = Duration::from_micros(200);
    loop {
        let procs = scan(registry().with_uids());
        let killed = registry().sweep(&procs, Scope::Run(id));
        if killed == 0 || Instant::now() > deadline {
            return;
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(20));
    }
}

/// Once per process: raylab adopts the programs' orphans, and Ctrl+C, SIGTERM or SIGHUP stop
/// every program and remove every [`RunDir`] before raylab exits with 130.
fn init() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // Files raylab inherited open (a teacher's shell may hold one as descriptor 7) would
        // pass on to every program, which could then write to them as whoever opened them.
        close_fds::set_fds_cloexec(3, &[]);
        #[cfg(target_os = "linux")]
        let _ = rustix::process::set_child_subreaper(Some(rustix::process::getpid()));
        // (Fails only if a handler is set already: then these are left to the default.)
        let _ = ctrlc::set_handler(on_signal);
    });
}

/// The signal handler's work (on the ctrlc crate's thread): the registry stays locked to the
/// end, so no program starts meanwhile.
fn on_signal() {
    let mut registry = registry();
    for _ in 0..1000 {
        let procs = scan(registry.with_uids());
        if registry.sweep(&procs, Scope::All) == 0 {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    for dir in std::mem::take(&mut registry.dirs) {
        remove_tree(&dir);
    }
    eprintln!("interrupted: the programs stopped, their directories removed");
    std::process::exit(130);
}

/// The uids of the processes running (real, effective, saved and file ones).
pub fn uids_running() -> HashSet<u32> {
    scan(true).iter().flat_map(|p| p.uids).collect()
}
