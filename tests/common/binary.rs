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

/// A run that passed (exit 0); else what it printed on both outputs.
pub fn assert_passes(o: &Output) {
    assert_eq!(o.status.code(), Some(0), "{}{}", stdout(o), stderr(o));
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

/// The processes that have `arg` as one of their arguments (zombies have none).
pub fn running(arg: &str) -> Vec<String> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(cmdline) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let args: Vec<&[u8]> = cmdline.split(|&b| b == 0).collect();
        if args.contains(&arg.as_bytes()) {
            found.push(String::from_utf8_lossy(&cmdline).replace('\0', " "));
        }
    }
    found
}

/// A child process killed (and reaped) when dropped: a failing test leaves nothing running.
pub struct KillOnDrop(pub std::process::Child);

impl std::ops::Deref for KillOnDrop {
    type Target = std::process::Child;
    fn deref(&self) -> &Self::Target {
        &self.0
    }
}

impl std::ops::DerefMut for KillOnDrop {
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut self.0
    }
}

impl Drop for KillOnDrop {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Bytes as text (invalid UTF-8 replaced).
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A run's last line of standard output.
pub fn last_line(o: &Output) -> String {
    text(&o.stdout)
        .lines()
        .last()
        .unwrap_or_default()
        .to_string()
}

/// The value `name` of the `check:` line's `name value` pairs.
pub fn count(line: &str, name: &str) -> usize {
    let words: Vec<&str> = line.split_whitespace().collect();
    let at = words
        .iter()
        .position(|w| *w == name)
        .unwrap_or_else(|| panic!("{name} in {line}"));
    words[at + 1].parse().unwrap()
}

/// Defines `check_answers`, `check_program` and `check_scene`: `raylab check` of an answer
/// file or a program on a scene and rays file, with more arguments (after
/// [`raylab_runner`], whose `raylab` they run).
#[macro_export]
macro_rules! check_runner {
    () => {
        /// `raylab check` of an answer file for `scene` and `rays`, with `more` arguments.
        #[allow(dead_code)]
        fn check_answers(
            scene: &str,
            rays: &str,
            answers: &std::path::Path,
            more: &[&str],
        ) -> std::process::Output {
            check_scene(scene, rays, &["--answers", answers.to_str().unwrap()], more)
        }

        /// `raylab check` of `program` run on `scene` and `rays`, with `more` arguments.
        #[allow(dead_code)]
        fn check_program(
            scene: &str,
            rays: &str,
            program: &str,
            more: &[&str],
        ) -> std::process::Output {
            check_scene(scene, rays, &["--program", program], more)
        }

        /// `raylab check --scene scene --rays rays`, then `source` and `more`.
        #[allow(dead_code)]
        fn check_scene(
            scene: &str,
            rays: &str,
            source: &[&str],
            more: &[&str],
        ) -> std::process::Output {
            raylab(&[&["check", "--scene", scene, "--rays", rays], source, more].concat())
        }
    };
}
