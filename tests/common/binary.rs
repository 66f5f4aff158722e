//! Running the `raylab` binary from a test: its output whole, a hang a failure.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `exe` (the test's `env!("CARGO_BIN_EXE_raylab")`) with `args` and extra `env`; a run
/// over 60 s is a hang and fails the test (it is killed).
pub fn run(exe: &str, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut child = Command::new(exe)
        .args(args)
        .envs(env.iter().copied())
        .env("RUST_LOG", "warn")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run raylab");
    // Drain the pipes on threads so a chatty child cannot block on a full pipe.
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let out_t = std::thread::spawn(move || {
        let mut b = Vec::new();
        std::io::Read::read_to_end(&mut out, &mut b).unwrap();
        b
    });
    let err_t = std::thread::spawn(move || {
        let mut b = Vec::new();
        std::io::Read::read_to_end(&mut err, &mut b).unwrap();
        b
    });
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > std::time::Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("raylab {args:?} hung for 60 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    Output {
        status,
        stdout: out_t.join().unwrap(),
        stderr: err_t.join().unwrap(),
    }
}

/// A run's standard error, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A run's standard output, as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A failed run: the given exit code, a message holding every `needle`, and no panic.
pub fn assert_fails(o: &Output, code: i32, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "'{n}' not in: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

/// Writes `text` to `name` in `dir`; its path.
pub fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// Defines `raylab(args)` and `raylab_env(args, env)` in a test of the app package: its
/// `raylab` binary run through [`run`] (the binary's path is known only there).
#[macro_export]
macro_rules! raylab_runner {
    () => {
        /// Runs the binary ([`common::binary::run`]).
        #[allow(dead_code)]
        fn raylab(args: &[&str]) -> std::process::Output {
            raylab_env(args, &[])
        }

        /// [`raylab`] with extra environment variables.
        #[allow(dead_code)]
        fn raylab_env(args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
            common::binary::run(env!("CARGO_BIN_EXE_raylab"), args, env)
        }
    };
}
