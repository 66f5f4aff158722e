//! `raylab grade` keeps submissions apart: each family's files fresh, nothing of one run left
//! for the next, only the environment it is given, and no run as root.

use crate::common;

use super::grade::{cut_class_and_suite, grade_class, open_up};
use common::binary::assert_fails;
use std::path::{Path, PathBuf};

crate::raylab_runner!();

/// Two families in one run: the submission that deletes its input gets fresh files for the
/// second and passes both.
#[test]
fn a_submission_that_deletes_its_input_gets_fresh_files_each_family() {
    let dir = tempfile::tempdir().unwrap();
    // Two families kept by hand: without the export's manifest, graded as they are.
    let (class, suite) = cut_class_and_suite(dir.path(), &["fay-deletes"], &["16-", "17-"]);
    let csv = dir.path().join("grades.csv");
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let o = grade_class(&class, &suite, &["--csv", &path(&csv)]);
    let out = common::binary::stdout(&o);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{out}{}",
        common::binary::stderr(&o)
    );
    let csv = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    assert!(
        rows.iter()
            .all(|r| r.starts_with("fay-deletes,") && r.ends_with(",ok")),
        "{csv}"
    );
}

/// As root, a class of one submission and a suite in `dir`, and a directory there only root
/// may enter: (class, suite, that directory); `None`, said, where not root.
fn as_root_with_a_private_dir(dir: &Path) -> Option<(PathBuf, PathBuf, PathBuf)> {
    use std::os::unix::fs::PermissionsExt;
    if !rustix::process::geteuid().is_root() {
        eprintln!("not root: every program runs as this user, with its PATH");
        return None;
    }
    let (class, suite) = cut_class_and_suite(dir, &["ada"], &["16-"]);
    let private = dir.join("private");
    std::fs::create_dir(&private).unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o700)).unwrap();
    Some((class, suite, private))
}

/// As root, a program that cannot run as an unprivileged uid (here: TMPDIR is a directory
/// only root may enter) stops the grading before any program runs, naming why; --as-root
/// runs it as root all the same, said on stderr.
#[test]
fn as_root_a_program_that_cannot_run_as_a_uid_stops_the_grading() {
    let dir = tempfile::tempdir().unwrap();
    let Some((class, suite, private)) = as_root_with_a_private_dir(dir.path()) else {
        return;
    };
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let (class, suite) = (path(&class), path(&suite));
    let args = [
        "grade",
        &class,
        "--suite",
        &suite,
        "--program",
        "sh run.sh {scene} {rays}",
    ];
    let tmpdir = [("TMPDIR", private.to_str().unwrap())];
    let o = raylab_env(&args, &tmpdir);
    common::binary::assert_fails(
        &o,
        2,
        &[
            "cannot run the programs as an unprivileged uid",
            "Permission denied",
            "--as-root",
        ],
    );
    let o = raylab_env(&[&args[..], &["--as-root"]].concat(), &tmpdir);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    assert!(err.contains("warning: the programs run as root"), "{err}");
    let row = out.lines().nth(1).unwrap_or_default();
    assert!(row.starts_with("ada ") && row.ends_with("ok"), "{out}");
}

/// As root, a command named without a `/` that the programs' PATH (the directories every
/// user may search) finds elsewhere than raylab's is warned of, naming both files, and one
/// only raylab's finds is refused: `python3`, a shim under /root with numpy for `check`, was
/// /usr/bin/python3 without it for every submission.
#[test]
fn as_root_a_command_the_programs_find_elsewhere_is_named() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let Some((class, suite, private)) = as_root_with_a_private_dir(dir.path()) else {
        return;
    };
    for name in ["sh", "wrapit"] {
        let file = private.join(name);
        std::fs::write(&file, "#!/bin/sh\nexec /bin/sh \"$@\"\n").unwrap();
        std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let (class, suite) = (path(&class), path(&suite));
    let searched = format!("{}:{}", path(&private), std::env::var("PATH").unwrap());
    let grade = |program: &str| {
        let args = ["grade", &class, "--suite", &suite, "--program", program];
        raylab_env(&args, &[("PATH", &searched)])
    };
    let o = grade("sh run.sh {scene} {rays}");
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    let yours = format!(
        "warning: --program: sh is {} on your PATH",
        path(&private.join("sh"))
    );
    assert!(err.contains(&yours) && err.contains("they run /"), "{err}");
    assert!(
        out.lines().nth(1).unwrap_or_default().ends_with("ok"),
        "{out}"
    );
    let o = grade("wrapit run.sh {scene} {rays}");
    let said = "on theirs it is not found (every submission would crash)";
    assert_fails(&o, 2, &["--program: wrapit is ", said]);
    let err = common::binary::stderr(&o);
    assert!(!err.contains("grading 1 submission"), "{err}");
    // A shim others may not run (700) in a directory they may enter: the same.
    let open = dir.path().join("open");
    std::fs::create_dir(&open).unwrap();
    open_up(&open);
    std::fs::copy(private.join("sh"), open.join("sh")).unwrap();
    std::fs::set_permissions(open.join("sh"), std::fs::Permissions::from_mode(0o700)).unwrap();
    let searched = format!("{}:{}", path(&open), std::env::var("PATH").unwrap());
    let args = [
        "grade",
        &class,
        "--suite",
        &suite,
        "--program",
        "sh run.sh {scene} {rays}",
    ];
    let o = raylab_env(&args, &[("PATH", &searched)]);
    let err = common::binary::stderr(&o);
    let yours = format!(
        "warning: --program: sh is {} on your PATH",
        path(&open.join("sh"))
    );
    let theirs = "cannot run it (its directory or it closed to them): they run /";
    assert!(err.contains(&yours) && err.contains(theirs), "{err}");
}

/// A teacher's wrapper named by a path relative to where raylab runs (the command runs in
/// each submission's copy, where it is not), by its bare name (not on the PATH) or under `~`
/// (each program's HOME is its own),
/// or, as root, one the programs cannot run as the uids they run as: refused before any
/// program runs, saying how to mend it. (Each made every submission crash with the shell's
/// "not found" or "Permission denied".) A command that is not simple words is not read so:
/// its words may run elsewhere (`cd lab3 && ./x.py`) or not at all (a comment).
#[test]
fn a_wrapper_the_runs_cannot_reach_stops_the_grading() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-"]);
    let tools = dir.path().join("tools");
    std::fs::create_dir(&tools).unwrap();
    open_up(&tools);
    let wrap = tools.join("wrap.sh");
    std::fs::write(&wrap, "exec sh run.sh \"$1\" \"$2\"\n").unwrap();
    std::fs::set_permissions(&wrap, std::fs::Permissions::from_mode(0o755)).unwrap();
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let (class, suite) = (path(&class), path(&suite));
    let grade = |program: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_raylab"))
            .current_dir(dir.path())
            .env("HOME", dir.path())
            .args(["grade", &class, "--suite", &suite, "--program", program])
            .output()
            .unwrap()
    };
    let o = grade("tools/wrap.sh {scene} {rays}");
    let absolute = format!(
        "a wrapper of yours is named by its absolute path, {}",
        path(&wrap)
    );
    let why = [
        "--program: tools/wrap.sh is a file here",
        "no submission holds it",
    ];
    assert_fails(&o, 2, &[why[0], why[1], &absolute]);
    let err = common::binary::stderr(&o);
    assert!(!err.contains("grading 1 submission"), "{err}");
    // A script an interpreter reads, by its bare name, is a path too.
    std::fs::copy(&wrap, dir.path().join("mine.sh")).unwrap();
    let o = grade("sh mine.sh {scene} {rays}");
    assert_fails(
        &o,
        2,
        &[
            "--program: mine.sh is a file here",
            "no submission holds it",
        ],
    );
    // By its bare name (the shell looks it up on the PATH alone): refused; `sh` by its bare
    // name, on the PATH, is not, nor a name on the PATH that is a file here too.
    let o = grade("mine.sh {scene} {rays}");
    let bare = format!(
        "a command named without a `/` is looked up on the programs' PATH, where it is not \
         (every submission would crash \"not found\"): name it by its absolute path, {}",
        path(&dir.path().join("mine.sh"))
    );
    assert_fails(&o, 2, &["--program: mine.sh is a file here, but ", &bare]);
    std::fs::copy(&wrap, dir.path().join("sh")).unwrap();
    let o = grade("sh run.sh {scene} {rays}");
    assert_eq!(o.status.code(), Some(0), "{}", common::binary::stderr(&o));
    // Nor one the command's own PATH finds (a copy here too): it grades.
    std::fs::copy(&wrap, dir.path().join("wrap.sh")).unwrap();
    let own = format!(
        "env PATH={}:/usr/bin:/bin wrap.sh {{scene}} {{rays}}",
        path(&tools)
    );
    let o = grade(&own);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    assert!(
        out.lines().nth(1).unwrap_or_default().ends_with("ok"),
        "{out}{err}"
    );
    let o = grade("sh ~/tools/wrap.sh {scene} {rays}");
    let home = format!(
        "~ is each program's own directory (its HOME), not yours: name it by its absolute \
         path, {}",
        path(&wrap)
    );
    assert_fails(&o, 2, &["--program: ~/tools/wrap.sh: ", &home]);
    // A file here that the submissions hold too is theirs.
    std::fs::copy(
        Path::new(&class).join("ada/run.sh"),
        dir.path().join("run.sh"),
    )
    .unwrap();
    for graded in [
        "cd . && tools/wrap.sh {scene} {rays}",
        "sh run.sh {scene} {rays} # not tools/wrap.sh",
        "sh ./run.sh {scene} {rays}",
    ] {
        let o = grade(graded);
        let err = common::binary::stderr(&o);
        assert_eq!(o.status.code(), Some(0), "{graded}: {err}");
        assert!(err.contains("grading 1 submission"), "{graded}: {err}");
    }
    let by_path = format!("{} {{scene}} {{rays}}", path(&wrap));
    let o = grade(&by_path);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    let row = out.lines().nth(1).unwrap_or_default();
    assert!(row.starts_with("ada ") && row.ends_with("ok"), "{out}");
    if !rustix::process::geteuid().is_root() {
        eprintln!("not root: every program runs as this user");
        return;
    }
    let o = grade(&format!("env X=1 {by_path}"));
    assert_eq!(o.status.code(), Some(0), "{}", common::binary::stderr(&o));
    // Read by sh, a script needs only r: 744 runs.
    std::fs::set_permissions(&wrap, std::fs::Permissions::from_mode(0o744)).unwrap();
    let o = grade(&format!("sh {by_path}"));
    assert_eq!(o.status.code(), Some(0), "{}", common::binary::stderr(&o));
    // Run after `exec` or `env`'s assignments, it needs x too.
    let said = format!("--program: {}: the programs run as uid", path(&wrap));
    for run in ["exec", "env X=1", "X=1 exec"] {
        let o = grade(&format!("{run} {by_path}"));
        assert_fails(&o, 2, &[&said, "who cannot run it", "`chmod o+rx` it"]);
    }
    std::fs::set_permissions(&tools, std::fs::Permissions::from_mode(0o700)).unwrap();
    let o = grade(&by_path);
    let said = format!("--program: {}: the programs run as uid", path(&wrap));
    assert_fails(&o, 2, &[&said, "who cannot run it", "`chmod o+rx` it"]);
}

/// As root each worker's programs run as one account, a submission after another: the next
/// finds nothing the last left where every user may write, a command missing from PATH is
/// "not found" even beside a directory only root may enter, and a name that reads as a
/// formula stays text in the CSV.
#[test]
fn the_next_submission_finds_nothing_of_the_last() {
    if !rustix::process::geteuid().is_root() {
        eprintln!("not root: every program runs as this user, with no account to sweep");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    open_up(dir.path());
    let (class, suite) = (dir.path().join("class"), dir.path().join("suite"));
    let exact = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/check/exact.py");
    let left = [
        "/tmp/raylab-left-917005",
        "/dev/shm/raylab-left-917005",
        "/tmp/raylab-left-dir-917005",
        "/run/lock/raylab-left-917005",
        "/tmp/raylab-open-917005/left",
    ];
    for f in left {
        let _ = std::fs::remove_dir_all(f).or_else(|_| std::fs::remove_file(f));
    }
    // A world-writable directory of root's in /tmp, as /tmp/.X11-unix: a file left in it
    // stayed for the next submission.
    let open = Path::new("/tmp/raylab-open-917005");
    let _ = std::fs::create_dir(open);
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(open, std::fs::Permissions::from_mode(0o1777)).unwrap();
    }
    // Files where every user may write (/run/lock where there is one), and a System V shared
    // memory segment, which outlives its process and holds memory.
    let leaves = format!(
        "echo answers > {0} && echo answers > {1} && mkdir -p {2} && echo x > {2}/f && \
         {{ [ ! -d /run/lock ] || echo x > {3}; }} && echo answers > {4} && \
         ipcmk -M 65536 >&2 && exec python3 exact.py \"$1\" \"$2\"\n",
        left[0], left[1], left[2], left[3], left[4]
    );
    let looks = format!(
        "for f in {} {} {} {} {}; do [ -e $f ] && echo found $f >&2 && exit 9; done; \
         awk -v u=$(id -u) 'NR > 1 && $8 == u {{ print \"found shm\"; exit 9 }}' /proc/sysvipc/shm >&2 \
         || exit 9; exec python3 exact.py \"$1\" \"$2\"\n",
        left[0], left[1], left[2], left[3], left[4]
    );
    let class_of = [
        ("=1+2", "exec python3 exact.py \"$1\" \"$2\"\n".to_string()),
        ("a-leaves", leaves),
        ("b-looks", looks),
        (
            "c-missing",
            "exec no-such-command-917006 \"$1\"\n".to_string(),
        ),
    ];
    for (name, run) in &class_of {
        let sub = class.join(name);
        std::fs::create_dir_all(&sub).unwrap();
        std::fs::write(sub.join("run.sh"), run).unwrap();
        std::fs::copy(&exact, sub.join("exact.py")).unwrap();
    }
    let o = raylab(&["suite", "export", suite.to_str().unwrap()]);
    assert!(o.status.success(), "{}", common::binary::stderr(&o));
    // A directory of root's that others cannot enter, first in PATH (as root's ~/.cargo/bin).
    let locked = dir.path().join("locked");
    std::fs::create_dir(&locked).unwrap();
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
    let path_env = format!("{}:/usr/local/bin:/usr/bin:/bin", locked.display());
    let (csv, json) = (
        dir.path().join("grades.csv"),
        dir.path().join("grades.json"),
    );
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let o = raylab_env(
        &[
            "grade",
            &path(&class),
            "--suite",
            &path(&suite),
            "--family",
            "01",
            "-j",
            "1",
            "--program",
            "sh run.sh {scene} {rays}",
            "--csv",
            &path(&csv),
            "--json",
            &path(&json),
        ],
        &[("PATH", &path_env)],
    );
    let err = common::binary::stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    // The class's originals are open to the accounts: the teacher is told so.
    let open = format!("warning: {}: other users may enter it", class.display());
    assert!(err.contains(&open), "{err}");
    for f in left {
        assert!(!Path::new(f).exists(), "{f} left behind");
    }
    let _ = std::fs::remove_dir(open);
    // No segment of the accounts' uids is left either.
    let shm = std::fs::read_to_string("/proc/sysvipc/shm").unwrap();
    let of_accounts = shm.lines().skip(1).filter(|l| {
        let uid: u32 = l.split_whitespace().nth(7).unwrap().parse().unwrap();
        (61_000..65_000).contains(&uid)
    });
    assert_eq!(of_accounts.count(), 0, "{shm}");
    let csv = std::fs::read_to_string(&csv).unwrap();
    let status = |name: &str| {
        let row = csv.lines().find(|l| l.starts_with(&format!("{name},")));
        row.and_then(|r| r.rsplit(',').next()).map(str::to_string)
    };
    assert_eq!(status("'=1+2").as_deref(), Some("ok"), "{csv}");
    assert_eq!(status("a-leaves").as_deref(), Some("ok"), "{csv}");
    assert_eq!(status("b-looks").as_deref(), Some("ok"), "{csv}\n{err}");
    assert_eq!(status("c-missing").as_deref(), Some("crashed"), "{csv}");
    let json = std::fs::read_to_string(&json).unwrap();
    assert!(
        json.contains("no-such-command-917006: not found") && !json.contains("Permission denied"),
        "{json}"
    );
}

/// A submission sees none of the teacher's environment but PATH, the locale, the time zone
/// and what `--env` names: a variable set for raylab (a token, say) is not passed on, one
/// named by `--env` is. (Every variable was passed on.)
#[test]
fn a_submission_sees_only_the_environment_it_is_given() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-"]);
    let run = "[ -z \"$RAYLAB_TEST_TOKEN\" ] || { echo \"saw the token\" >&2; exit 3; }\n\
               [ \"$RAYLAB_TEST_GIVEN\" = yes ] || { echo 'not given' >&2; exit 4; }\n\
               exec python3 exact.py \"$1\" \"$2\"\n";
    std::fs::write(class.join("ada/run.sh"), run).unwrap();
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let json = dir.path().join("grades.json");
    let (class, suite, json_path) = (path(&class), path(&suite), path(&json));
    let program = "sh run.sh {scene} {rays}";
    let args = [
        "grade",
        &class,
        "--suite",
        &suite,
        "--program",
        program,
        "--json",
        &json_path,
    ];
    let env = [("RAYLAB_TEST_TOKEN", "hush"), ("RAYLAB_TEST_GIVEN", "yes")];
    let graded = |more: &[&str]| {
        let o = raylab_env(&[&args[..], more].concat(), &env);
        assert_eq!(o.status.code(), Some(0), "{}", common::binary::stderr(&o));
        std::fs::read_to_string(&json).unwrap()
    };
    let given = graded(&["--env", "RAYLAB_TEST_GIVEN"]);
    assert!(given.contains("\"status\": \"ok\""), "{given}");
    // Without --env, the variable it needs is not there either: the failed run says why.
    let not_given = graded(&[]);
    assert!(
        not_given.contains("\"status\": \"crashed\"") && not_given.contains("not given"),
        "{not_given}"
    );
    let o = raylab(&[&args[..], &["--env", "A=B"]].concat());
    assert_fails(&o, 2, &["--env 'A=B' is not a variable's name"]);
}
