//! Running a program that is not raylab's (`raylab check --program`): through the shell, with
//! the scene's and the rays' paths in its command, its standard output read as its answers.
//! A program never holds raylab up or fills its memory: it is stopped, with every process it
//! started, when its time is up or its output passes a limit.

use std::io::Read;
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// What a program printed, and how long it took.
#[derive(Debug)]
pub struct Ran {
    pub stdout: String,
    pub elapsed: Duration,
}

/// Why a program's answers could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("cannot start the shell: {0}")]
    Start(std::io::Error),
    #[error("ran out of time ({0:.1} s; --timeout sets another limit)")]
    Timeout(f64),
    #[error("printed more than {0} bytes (not answers to these rays)")]
    TooMuch(usize),
    #[error("ended with {status}{stderr}")]
    Failed { status: ExitStatus, stderr: String },
    #[error("printed something that is not UTF-8 text")]
    NotText,
}

/// The command with `{scene}` and `{rays}` replaced by the paths (quoted for the shell).
pub fn command_for(template: &str, scene: &Path, rays: &Path) -> String {
    template
        .replace("{scene}", &shell_quoted(scene))
        .replace("{rays}", &shell_quoted(rays))
}

/// `path` as one shell word: in single quotes, a quote within written `'\''`.
fn shell_quoted(path: &Path) -> String {
    format!("'{}'", path.display().to_string().replace('\'', r"'\''"))
}

/// Runs `command` with `sh -c` (standard input empty) and returns its standard output. It is
/// stopped, with its process group, after `timeout` or once it has printed more than
/// `max_bytes`; a status other than success is an error quoting the end of its standard error.
pub fn run(command: &str, timeout: Duration, max_bytes: usize) -> Result<Ran, RunError> {
    let mut shell = Command::new("sh");
    shell
        .arg("-c")
        .arg(command)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut shell, 0);
    let start = Instant::now();
    let mut child = shell.spawn().map_err(RunError::Start)?;
    let overflow = Arc::new(AtomicBool::new(false));
    let stdout = child.stdout.take().expect("piped");
    let stderr = child.stderr.take().expect("piped");
    let out_reader = {
        let overflow = overflow.clone();
        std::thread::spawn(move || read_at_most(stdout, max_bytes, &overflow))
    };
    let err_reader = std::thread::spawn(move || tail(stderr, 2000));
    let mut pause = Duration::from_micros(200);
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if start.elapsed() > timeout || overflow.load(Ordering::Relaxed) => {
                break None
            }
            Ok(None) => {}
            Err(_) => break None,
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(5));
    };
    let elapsed = start.elapsed();
    // Whatever it started that still runs (and holds the pipes) goes with it.
    stop_group(&child);
    let _ = child.kill();
    let _ = child.wait();
    let out = out_reader.join().expect("the reader does not panic");
    let err = err_reader.join().expect("the reader does not panic");
    let Some(status) = status else {
        return Err(match overflow.load(Ordering::Relaxed) {
            true => RunError::TooMuch(max_bytes),
            false => RunError::Timeout(timeout.as_secs_f64()),
        });
    };
    if overflow.load(Ordering::Relaxed) {
        return Err(RunError::TooMuch(max_bytes));
    }
    if !status.success() {
        let err = String::from_utf8_lossy(&err);
        let err = err.trim();
        let stderr = match err.is_empty() {
            true => String::new(),
            false => format!("; its last words: {}", err.replace('\n', " | ")),
        };
        return Err(RunError::Failed { status, stderr });
    }
    let stdout = String::from_utf8(out).map_err(|_| RunError::NotText)?;
    Ok(Ran { stdout, elapsed })
}

/// Reads until the end or until more than `max` bytes came (then sets `overflow` and stops
/// reading, so the writer gets a broken pipe).
fn read_at_most(mut from: impl Read, max: usize, overflow: &AtomicBool) -> Vec<u8> {
    let mut out = Vec::new();
    let mut buf = [0u8; 64 * 1024];
    loop {
        match from.read(&mut buf) {
            Ok(0) | Err(_) => return out,
            Ok(n) if out.len() + n > max => {
                overflow.store(true, Ordering::Relaxed);
                return out;
            }
            Ok(n) => out.extend_from_slice(&buf[..n]),
        }
    }
}

/// Reads everything and keeps the last `keep` bytes.
fn tail(mut from: impl Read, keep: usize) -> Vec<u8> {
    let mut out = Vec::new();
    let mut buf = [0u8; 16 * 1024];
    loop {
        match from.read(&mut buf) {
            Ok(0) | Err(_) => return out,
            Ok(n) => {
                out.extend_from_slice(&buf[..n]);
                if out.len() > 2 * keep {
                    out.drain(..out.len() - keep);
                }
            }
        }
    }
}

/// Sends SIGKILL to the child's process group (it leads one of its own).
#[cfg(unix)]
fn stop_group(child: &std::process::Child) {
    use rustix::process::{kill_process_group, Pid, Signal};
    if let Some(pid) = Pid::from_raw(child.id() as i32) {
        let _ = kill_process_group(pid, Signal::KILL);
    }
}

#[cfg(not(unix))]
fn stop_group(_: &std::process::Child) {}
