//! Running programs that are not raylab's: a daemon that keeps the output pipes open does not
//! hold a run up and does not outlive it, a path is never read as code, a path that is not
//! UTF-8 reaches the program intact, a file raylab inherited open is not the program's, and
//! SIGTERM on raylab leaves no program running and no temporary directory behind.

use crate::common;

use common::binary::{running, KillOnDrop};
use std::ffi::OsString;
use std::os::unix::ffi::OsStringExt;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

crate::raylab_runner!();

/// A one-triangle scene and one ray that hits it at t = 1: `hit 1 0` is the right answer.
fn one_ray(dir: &Path) -> (String, String) {
    let scene = common::binary::write(dir, "scene.txt", "tri 0 0 0 1 0 0 0 1 0\n");
    let rays = common::binary::write(dir, "rays.txt", "0.25 0.25 -1 0 0 1 0 inf\n");
    (scene, rays)
}

/// `raylab check` of `program` on the one-ray files (with extra `env`) at `--timeout 2`: its
/// output and the exit code, once it has ended within 20 s (not a daemon's time, nor the
/// runner's 60 s).
fn check_program(
    scene: &str,
    rays: &str,
    program: &str,
    env: &[(&str, &str)],
) -> (String, Option<i32>) {
    check_program_within(scene, rays, program, env, "2")
}

/// [`check_program`] at `--timeout TIMEOUT`.
fn check_program_within(
    scene: &str,
    rays: &str,
    program: &str,
    env: &[(&str, &str)],
    timeout: &str,
) -> (String, Option<i32>) {
    let args = [
        "check",
        "--scene",
        scene,
        "--rays",
        rays,
        "--program",
        program,
        "--timeout",
        timeout,
    ];
    let start = Instant::now();
    let o: Output = raylab_env(&args, env);
    let took = start.elapsed();
    assert!(took < Duration::from_secs(20), "took {took:?}");
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    (format!("{out}{err}"), o.status.code())
}

/// Fails if a process with any of `args` as an argument is still running.
fn assert_none_running(args: &[&str]) {
    for arg in args {
        assert_eq!(running(arg), Vec::<String>::new(), "{arg} survived");
    }
}

/// A program that answers every ray and then fails (exit 1) is graded all the same, as its
/// words say, and still fails the run: every answer standing, its exit status alone fails it;
/// a wrong answer among them is counted. (It was told only that it had printed every answer.)
#[test]
fn a_run_that_fails_after_every_answer_is_graded_all_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = one_ray(dir.path());
    let (out, code) = check_program(&scene, &rays, "echo hit 1 0; exit 1 # {scene} {rays}", &[]);
    assert_eq!(code, Some(1), "{out}");
    let said = "it had printed an answer for every ray first: graded all the same, every answer \
                stands: its exit status alone fails it (end with status 0)";
    assert!(out.contains(said), "{out}");
    assert!(out.contains("failed_runs 1"), "{out}");
    let (out, code) = check_program(&scene, &rays, "echo miss; exit 1 # {scene} {rays}", &[]);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("graded all the same, 0 stand and 1 does not"),
        "{out}"
    );
    // One line too many, then exit 1: the answers' words, graded all the same.
    let two = "echo hit 1 0; echo miss; exit 1 # {scene} {rays}";
    let (out, code) = check_program(&scene, &rays, two, &[]);
    assert_eq!(code, Some(1), "{out}");
    let said = "graded all the same, its output: 2 answers for the 1 ray of ";
    let too_many = "they are the exact answers, and the 1 after the last ray's lines too many";
    assert!(out.contains(said) && out.contains(too_many), "{out}");
    // A script without x, run by its path: exit 126, said how to run it.
    let script = common::binary::write(dir.path(), "run.sh", "echo hit 1 0\n");
    let (out, code) = check_program(
        &scene,
        &rays,
        &format!("'{script}' {{scene}} {{rays}}"),
        &[],
    );
    assert_eq!(code, Some(1), "{out}");
    let said = "exit status: 126 (the shell's for a file it may not run: `chmod +x` it, or name \
                its interpreter, `sh run.sh`)";
    assert!(out.contains(said), "{out}");
}

/// A program that starts daemons (their own session, out of its process group), one of them
/// holding the output pipes, then answers and ends: its answers are graded at once, not when
/// the daemon ends, and no daemon outlives the run; one whose shell hangs ends at --timeout.
#[test]
fn a_daemon_neither_holds_the_run_up_nor_outlives_it() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = one_ray(dir.path());
    let program =
        "setsid sleep 913571 & setsid sleep 913575 >/dev/null 2>&1 & echo hit 1 0 # {scene} {rays}";
    let (out, code) = check_program(&scene, &rays, program, &[]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("check: rays 1 right 1 leaks 0"), "{out}");
    assert_none_running(&["913571", "913575"]);

    let program = "setsid sleep 913572 & sleep 913573 # {scene} {rays}";
    let (out, code) = check_program(&scene, &rays, program, &[]);
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("ran out of time (2.0 s"), "{out}");
    assert_none_running(&["913572", "913573"]);
}

/// A file's path that holds `{rays}` and shell code is one quoted word in the command: the
/// program reads the file and nothing in the path runs.
#[test]
fn a_placeholder_or_code_in_a_path_runs_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let family = dir.path().join("{rays}$(touch \"$PWNED_AT\")'{scene}'");
    std::fs::create_dir(&family).unwrap();
    let (scene, rays) = one_ray(&family);
    // (The program reads copies of the files under their own names: hostile names too.)
    let hostile = |path: &str, name: &str| {
        let to = family.join(name);
        std::fs::rename(path, &to).unwrap();
        to.to_str().unwrap().to_string()
    };
    let scene = hostile(&scene, "{rays}$(touch \"$PWNED_AT\").txt");
    let rays = hostile(&rays, "'{scene}'`touch \"$PWNED_AT\"`");
    let pwned = dir.path().join("PWNED");
    let program = "cat {scene} {rays} >/dev/null && echo hit 1 0";
    let pwned_at = [("PWNED_AT", pwned.to_str().unwrap())];
    let (out, code) = check_program(&scene, &rays, program, &pwned_at);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("check: rays 1 right 1 leaks 0"), "{out}");
    assert!(!pwned.exists(), "the path ran as code");
}

/// A program that empties its scene file (`open(path, "w")` where it meant "r") and says
/// `miss` to every ray: it reads a copy, so the next check still grades it against the
/// scene as written (the second run graded every `miss` right against the emptied file).
#[test]
fn a_program_that_writes_to_its_input_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = one_ray(dir.path());
    let program =
        "python3 -c 'import sys; open(sys.argv[1], \"w\"); print(\"miss\")' {scene} {rays}";
    for run in 1..=2 {
        let (out, code) = check_program(&scene, &rays, program, &[]);
        assert_eq!(code, Some(1), "run {run}: {out}");
        assert!(
            out.contains("check: rays 1 right 0 leaks 1"),
            "run {run}: {out}"
        );
    }
    let written = std::fs::read_to_string(&scene).unwrap();
    assert_eq!(written, "tri 0 0 0 1 0 0 0 1 0\n");
}

/// A class directory with one submission running `run.sh` with `text` (mode 0755 dirs, so a
/// program run as another uid when raylab is root reaches them), and a one-family suite.
fn class_of(root: &Path, text: &str) -> (String, String) {
    use std::os::unix::fs::PermissionsExt;
    let open =
        |p: &Path| std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o755)).unwrap();
    open(root);
    let (class, suite) = (root.join("class"), root.join("suite"));
    std::fs::create_dir_all(class.join("ada")).unwrap();
    std::fs::write(class.join("ada/run.sh"), text).unwrap();
    let exact = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/check/exact.py");
    std::fs::copy(exact, class.join("ada/exact.py")).unwrap();
    let o = raylab(&["suite", "export", suite.to_str().unwrap()]);
    assert!(o.status.success(), "{}", common::binary::stderr(&o));
    (
        class.to_str().unwrap().into(),
        suite.to_str().unwrap().into(),
    )
}

/// The temporary directory's name is not UTF-8, so are the paths of the files the program
/// gets: they reach it byte for byte (the exact Python program reads them and passes).
#[test]
fn a_path_that_is_not_utf8_reaches_the_program_intact() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = class_of(dir.path(), "exec python3 exact.py \"$1\" \"$2\"\n");
    let tmp = dir
        .path()
        .join(OsString::from_vec(b"tmp-\xff\xfe".to_vec()));
    std::fs::create_dir(&tmp).unwrap();
    std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o755)).unwrap();
    let csv = dir.path().join("grades.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args([
            "grade",
            &class,
            "--suite",
            &suite,
            "--family",
            "16",
            "--timeout",
            "30",
        ])
        .args([
            "--program",
            "sh run.sh {scene} {rays}",
            "--csv",
            csv.to_str().unwrap(),
        ])
        .env("TMPDIR", &tmp)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let csv = std::fs::read_to_string(csv).unwrap();
    let row = csv.lines().nth(1).unwrap();
    assert!(
        row.starts_with("ada,16-") && row.ends_with(",ok"),
        "{csv}{err}"
    );
    assert_eq!(
        std::fs::read_dir(&tmp).unwrap().count(),
        0,
        "a run directory was left"
    );
}

#[test]
fn a_file_raylab_inherited_open_is_not_passed_on() {
    // The shell that starts raylab holds a private file open as descriptor 7 (a teacher's
    // `exec 7>>notes`, a CI runner's log): a program that writes there wrote into it.
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = one_ray(dir.path());
    let notes = common::binary::write(dir.path(), "notes", "teacher's notes\n");
    let program = "echo written >&7; echo hit 1 0 # {scene} {rays}";
    let command = format!(
        "exec 7>>{notes}; exec raylab check --scene {scene} --rays {rays} --program '{program}'"
    );
    let o = common::run_in_shell(&command, dir.path(), env!("CARGO_BIN_EXE_raylab"));
    let out = common::binary::stdout(&o);
    assert!(
        out.contains("check: rays 1 right 1"),
        "{out}{}",
        common::binary::stderr(&o)
    );
    assert_eq!(
        std::fs::read_to_string(&notes).unwrap(),
        "teacher's notes\n"
    );
}

/// SIGTERM (or Ctrl+C) while a program runs: raylab stops it, with the daemon it started,
/// removes its directory and exits with 130.
#[test]
fn sigterm_stops_the_program_and_removes_its_directory() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = class_of(dir.path(), "setsid sleep 913576 & sleep 913574\n");
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o755)).unwrap();
    // The outputs' temporary files, beside them from the start, go too.
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let (csv, json) = (out.join("grades.csv"), out.join("grades.json"));
    // (Killed if the test fails before raylab ends.)
    let mut raylab = KillOnDrop(
        Command::new(env!("CARGO_BIN_EXE_raylab"))
            .args(["grade", &class, "--suite", &suite, "--family", "16"])
            .args(["--program", "sh run.sh {scene} {rays}"])
            .arg("--csv")
            .arg(&csv)
            .arg("--json")
            .arg(&json)
            .env("TMPDIR", &tmp)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let start = Instant::now();
    while running("913574").is_empty() || running("913576").is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "the program never started"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(
        std::fs::read_dir(&tmp).unwrap().count(),
        1,
        "one run directory"
    );
    let pid = rustix::process::Pid::from_raw(raylab.id() as i32).unwrap();
    rustix::process::kill_process(pid, rustix::process::Signal::TERM).unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = raylab.try_wait().unwrap() {
            break status;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "raylab did not end at SIGTERM"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut raylab.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    assert_none_running(&["913574", "913576"]);
    assert_eq!(
        std::fs::read_dir(&tmp).unwrap().count(),
        0,
        "a run directory was left"
    );
    let left: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert!(left.is_empty(), "left beside the outputs: {left:?}");
}

/// A run past two seconds goes to a low priority (nice 10), all its processes: a hang takes
/// little of the CPU from the programs graded beside it till its --timeout, so their grades
/// do not hang on it. (A busy hang beside a correct JVM program ran its budget out.)
#[test]
fn a_long_run_is_lowered_to_a_low_priority() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = one_ray(dir.path());
    let d = dir.path().display();
    let nice = |name: &str| format!("awk '{{print $19}}' /proc/$$/stat > '{d}/{name}'");
    let program = format!(
        "{}; sleep 2.6; {}; echo hit 1 0 # {{scene}} {{rays}}",
        nice("before"),
        nice("after")
    );
    let (out, code) = check_program_within(&scene, &rays, &program, &[], "20");
    assert_eq!(code, Some(0), "{out}");
    let read = |name: &str| -> i32 {
        let text = std::fs::read_to_string(dir.path().join(name)).unwrap();
        text.trim().parse().unwrap()
    };
    let (before, after) = (read("before"), read("after"));
    println!("nice {before} at the start, {after} after 2.6 s");
    if before > 10 {
        println!("(the tests run at nice {before} already, past the long run's)");
        return;
    }
    assert_eq!(after, 10, "nice {before} at the start");
}
