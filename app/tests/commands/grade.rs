//! `raylab grade`: a class of submissions, right, crashing, hanging, flooding, talking
//! nonsense, deleting their input and forking without end, graded side by side: each gets its
//! own status, none stops or harms another, none leaves a process behind; bad input is
//! named.

use crate::common;

use common::binary::running;
use std::path::{Path, PathBuf};

crate::raylab_runner!();

/// Makes `dir` reachable by every user (a program runs as another uid when raylab is root).
pub(super) fn open_up(dir: &Path) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o755)).unwrap();
}

/// The class: every submission runs `run.sh`, beside the README's exact Python program.
const CLASS: &[(&str, &str)] = &[
    ("ada", "exec python3 exact.py \"$1\" \"$2\"\n"),
    ("bob-crashes", "echo 'bob: segfault (not really)' >&2; exit 3\n"),
    ("cy-hangs", "sleep 917001\n"),
    ("dee-floods", "yes hit 1 0\n"),
    ("eve-talks", "echo nonsense\n"),
    // Deletes the family's files, then answers from its own copy of them: the next family's
    // files are fresh, the suite is untouched.
    (
        "fay-deletes",
        "cp \"$1\" mine.txt && rm -f \"$1\" \"$2.gone\" && cp \"$2\" \"$2.gone\" && rm -f \"$2\" && exec python3 exact.py mine.txt \"$2.gone\"\n",
    ),
    ("gus-forks", "exec python3 bomb_917002.py\n"),
    ("hal-spawns", "exec python3 spawn_917003.py\n"),
    // Dies of a segmentation fault, as a program refused memory past the limit does.
    ("ivy-segfaults", "sh -c 'kill -SEGV $$'\n"),
];

/// Forks without end, each process too (a fork that fails is tried again a little later, so
/// the capped bomb leaves the test's other programs some of the machine).
const BOMB: &str = "import os, time\nwhile True:\n    try:\n        os.fork()\n    except OSError:\n        time.sleep(0.05)\n";

/// Starts sleepers until it cannot, then says how many and fails.
const SPAWN: &str = "import subprocess, sys\nn = 0\ntry:\n    while n < 500:\n        subprocess.Popen(['sleep', '917004'])\n        n += 1\nexcept OSError:\n    pass\nprint('started', n, file=sys.stderr)\nsys.exit(7)\n";

/// Writes the class and a suite into `root`; (class, suite).
fn class_and_suite(root: &Path) -> (PathBuf, PathBuf) {
    open_up(root);
    let (class, suite) = (root.join("class"), root.join("suite"));
    let exact = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/check/exact.py");
    for (name, run) in CLASS {
        let dir = class.join(name);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("run.sh"), run).unwrap();
        std::fs::copy(&exact, dir.join("exact.py")).unwrap();
    }
    std::fs::write(class.join("gus-forks/bomb_917002.py"), BOMB).unwrap();
    std::fs::write(class.join("hal-spawns/spawn_917003.py"), SPAWN).unwrap();
    // Not a submission: only directories are.
    std::fs::write(class.join("notes.txt"), "marks due friday\n").unwrap();
    let o = raylab(&["suite", "export", suite.to_str().unwrap()]);
    assert!(o.status.success(), "{}", common::binary::stderr(&o));
    (class, suite)
}

/// The class cut to the submissions `names`, and the suite to the families whose names
/// start with one of `families`, without the export's manifest (graded as they are).
pub(super) fn cut_class_and_suite(
    root: &Path,
    names: &[&str],
    families: &[&str],
) -> (PathBuf, PathBuf) {
    let (class, suite) = class_and_suite(root);
    for (name, _) in CLASS.iter().filter(|(n, _)| !names.contains(n)) {
        std::fs::remove_dir_all(class.join(name)).unwrap();
    }
    for family in std::fs::read_dir(&suite).unwrap().flatten() {
        let name = family.file_name().into_string().unwrap();
        if family.path().is_dir() && !families.iter().any(|k| name.starts_with(k)) {
            std::fs::remove_dir_all(family.path()).unwrap();
        }
    }
    std::fs::remove_file(suite.join("families.txt")).unwrap();
    (class, suite)
}

/// `raylab grade CLASS --suite SUITE --program 'sh run.sh {scene} {rays}'` and `more`.
pub(super) fn grade_class(class: &Path, suite: &Path, more: &[&str]) -> std::process::Output {
    let (class, suite) = (class.to_str().unwrap(), suite.to_str().unwrap());
    let args = [
        "grade",
        class,
        "--suite",
        suite,
        "--program",
        "sh run.sh {scene} {rays}",
    ];
    raylab(&[&args[..], more].concat())
}

/// A family's files, to see that no submission changed them.
fn suite_files(suite: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = Vec::new();
    for family in std::fs::read_dir(suite).unwrap().flatten() {
        for name in ["scene.txt", "rays.txt"] {
            let path = family.path().join(name);
            if let Ok(bytes) = std::fs::read(&path) {
                files.push((path, bytes));
            }
        }
    }
    files.sort();
    files
}

#[test]
fn every_submission_gets_its_own_status_and_nothing_survives() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = class_and_suite(dir.path());
    let before = suite_files(&suite);
    let (csv, json, totals) = (
        dir.path().join("grades.csv"),
        dir.path().join("grades.json"),
        dir.path().join("totals.csv"),
    );
    let rubric = common::binary::write(
        dir.path(),
        "rubric.txt",
        "# points per family\n16 3  # the one graded\n* 2\n",
    );
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let o = grade_class(
        &class,
        &suite,
        &[
            // (The exact program answers its 200 rays in a fraction of a second.)
            "--family",
            "16",
            "--timeout",
            "5",
            "--max-processes",
            "64",
            "-j",
            "2",
            "--csv",
            &path(&csv),
            "--json",
            &path(&json),
            "--totals",
            &path(&totals),
            "--rubric",
            &rubric,
        ],
    );
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    let csv = std::fs::read_to_string(&csv).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some(
            "submission,family,rays,right,ties,leaks,false_hits,wrong,t_failures,ms,status,points"
        )
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let expected = [
        ("ada", "ok"),
        ("bob-crashes", "crashed"),
        ("cy-hangs", "timeout"),
        ("dee-floods", "flooded"),
        ("eve-talks", "garbage"),
        ("fay-deletes", "ok"),
        ("gus-forks", "timeout"),
        ("hal-spawns", "crashed"),
        ("ivy-segfaults", "crashed"),
    ];
    assert_eq!(rows.len(), expected.len(), "{csv}");
    for (row, (name, status)) in rows.iter().zip(expected) {
        assert_eq!((row[0], row[10]), (name, status), "{csv}\n{err}");
        assert!(row[1].starts_with("16-"), "{csv}");
        let points = if status == "ok" { "3" } else { "0" };
        assert_eq!(row[11], points, "{csv}");
        match status {
            // Graded: the counts; no mistake of the exact program.
            "ok" => assert_eq!(row[5..9], ["0"; 4], "{csv}"),
            _ => assert_eq!(row[3..9].concat(), "", "{csv}"),
        }
    }
    // The totals: a row per submission, for a gradebook (no counts where none was graded).
    let totals = std::fs::read_to_string(&totals).unwrap();
    let rows: Vec<Vec<&str>> = totals.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0].join(","),
        "submission,families,passed,leaks,false_hits,wrong,t_failures,seconds,status,points,max_points"
    );
    assert_eq!(rows.len(), 1 + expected.len(), "{totals}");
    let (ada, bob) = (&rows[1], &rows[2]);
    assert_eq!(
        (ada[..7].join(","), ada[8..].join(",")),
        ("ada,1,1,0,0,0,0".into(), "ok,3,3".into()),
        "{totals}"
    );
    assert_eq!(
        (bob[..7].join(","), bob[8..].join(",")),
        ("bob-crashes,1,0,,,,".into(), "crashed 1,0,3".into()),
        "{totals}"
    );
    // The table: a row per submission, the points of the rubric.
    let table: Vec<&str> = out.lines().collect();
    assert_eq!(table.len(), 1 + expected.len(), "{out}");
    assert!(
        table[1].starts_with("ada ") && table[1].contains("1/1") && table[1].contains("3/3"),
        "{out}"
    );
    assert!(
        table[2].contains("0/1") && table[2].ends_with("crashed 1"),
        "{out}"
    );
    // Counts of what was graded: none where nothing was (not 0, which reads as no mistake).
    let counts = |row: &str| {
        row.split_whitespace()
            .skip(2)
            .take(4)
            .collect::<Vec<_>>()
            .join(" ")
    };
    assert_eq!(
        (counts(table[1]), counts(table[2])),
        ("0 0 0 0".into(), "- - - -".into())
    );
    // The JSON: the same records, with why each was not graded.
    let json = std::fs::read_to_string(&json).unwrap();
    assert_eq!(
        json.matches("\"submission\": ").count(),
        expected.len(),
        "{json}"
    );
    assert!(json.contains("\"status\": \"crashed\", \"detail\": \"ended with exit status: 3; its last words: bob: segfault (not really)\""), "{json}");
    // The one killed by a signal: a word on the memory limit, which would do that.
    let ivy = json
        .lines()
        .find(|l| l.contains("ivy-segfaults"))
        .unwrap_or_default();
    assert!(
        ivy.contains(
            "ended with exit status: 139 (the shell's for a program killed by signal 11, \
             SIGSEGV)"
        )
            && ivy.contains("(a crash like this may be the memory limit: each process may write 2048 MiB of data, --max-memory)\""),
        "{json}"
    );
    let bob = json
        .lines()
        .find(|l| l.contains("bob-crashes"))
        .unwrap_or_default();
    assert!(
        !bob.contains("memory limit"),
        "an exit status is no signal: {bob}"
    );
    // The one that hangs: how far its answers came (none: where to look, and why).
    assert!(json.contains("\"status\": \"timeout\", \"detail\": \"ran out of time (5.0 s; --timeout sets another limit); no answer had reached raylab: it printed none, or kept them in its buffer"), "{json}");
    // The sleepers were capped by the process limit (64), far below the 500 asked for.
    let started = json
        .split("its last words: started ")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .unwrap_or_else(|| panic!("{json}"));
    let started: usize = started.parse().unwrap();
    assert!(started < 100, "{started} sleepers started");
    assert!(err.contains("[9/9]"), "{err}");
    for marker in ["917001", "bomb_917002.py", "spawn_917003.py", "917004"] {
        assert_eq!(running(marker), Vec::<String>::new(), "{marker} survived");
    }
    assert_eq!(
        suite_files(&suite),
        before,
        "a submission changed the suite"
    );
}

/// A program that could not start a process (a shell's `Cannot fork` at --max-processes, Java's
/// thread it could not create) or was refused memory (Python's `MemoryError`, its own exit, no
/// signal): each crash names the limit that may have done it, the flag that sets it; one that
/// names a heap bug of its own (glibc's `realloc(): invalid next size`, then SIGABRT) is not
/// told of the memory limit.
#[test]
fn a_crash_at_a_limit_names_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-"]);
    let runs = [
        (
            "kit-forks",
            "for i in 1 2 3 4 5 6 7 8 9 10 11 12; do sleep 917011 & done; wait\n",
        ),
        ("lou-hoards", "exec python3 -c 'bytearray(1 << 44)'\n"),
        // (Its own heap bug, as glibc words it, and the abort: no word of the limit.)
        (
            "meg-corrupts",
            "echo 'realloc(): invalid next size' >&2; kill -ABRT $$\n",
        ),
        (
            "nat-unmaps",
            "echo 'munmap_chunk(): invalid pointer' >&2; kill -ABRT $$\n",
        ),
        // (A word of its own that is no heap bug's: the hint stays.)
        (
            "oz-segfaults",
            "echo 'warning: scene line 3 looks corrupted' >&2; kill -SEGV $$\n",
        ),
        // (Java's words for a thread it could not start, which name memory.)
        (
            "max-threads",
            "echo 'Exception in thread \"main\" java.lang.OutOfMemoryError: unable to create \
             native thread: possibly out of memory or process/resource limits reached' >&2\n\
             exit 1\n",
        ),
    ];
    for (name, run) in runs {
        std::fs::create_dir(class.join(name)).unwrap();
        std::fs::write(class.join(name).join("run.sh"), run).unwrap();
    }
    // Every answer right, then exit 1: graded all the same, its exit status alone failing it.
    let ends = class.join("ann-ends-1");
    std::fs::create_dir(&ends).unwrap();
    std::fs::copy(class.join("ada/exact.py"), ends.join("exact.py")).unwrap();
    let run = "python3 exact.py \"$1\" \"$2\"; exit 1\n";
    std::fs::write(ends.join("run.sh"), run).unwrap();
    let json = dir.path().join("grades.json");
    let json_arg = json.to_str().unwrap();
    let limits = ["--max-processes", "4", "--timeout", "5", "--json", json_arg];
    let o = grade_class(&class, &suite, &limits);
    assert_eq!(o.status.code(), Some(0), "{}", common::binary::stderr(&o));
    let json = std::fs::read_to_string(&json).unwrap();
    let detail = |name: &str| {
        (json.lines())
            .find(|l| l.contains(&format!("\"submission\": \"{name}\"")))
            .unwrap_or_else(|| panic!("{name}: {json}"))
            .to_string()
    };
    let forks = detail("kit-forks");
    assert!(
        forks.contains("a program may have 4 at once, --max-processes"),
        "{forks}"
    );
    let threads = detail("max-threads");
    assert!(
        threads.contains("could not start a process or thread")
            && !threads.contains("--max-memory"),
        "{threads}"
    );
    let hoards = detail("lou-hoards");
    assert!(
        hoards.contains("MemoryError")
            && hoards.contains("the memory limit")
            && hoards.contains("--max-memory"),
        "{hoards}"
    );
    assert!(!detail("ada").contains("limit"), "{json}");
    assert!(detail("oz-segfaults").contains("--max-memory"), "{json}");
    let ends = detail("ann-ends-1");
    assert!(
        ends.contains("\"status\": \"crashed\"")
            && ends.contains("every answer stands: its exit status alone fails it"),
        "{ends}"
    );
    for (name, words) in [
        ("meg-corrupts", "invalid next size"),
        ("nat-unmaps", "munmap_chunk"),
    ] {
        let corrupts = detail(name);
        assert!(
            corrupts.contains(words) && !corrupts.contains("--max-memory"),
            "{corrupts}"
        );
    }
    assert_eq!(
        running("917011"),
        Vec::<String>::new(),
        "a sleeper survived"
    );
}

/// A program that removes its own copy: its later families crash, said so (not "cannot start
/// the shell: No such file", which read as if `sh` were missing).
#[test]
fn a_program_that_removes_its_copy_is_told_so() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-", "17-"]);
    let ned = class.join("ned-removes");
    std::fs::create_dir(&ned).unwrap();
    let run = "python3 exact.py \"$1\" \"$2\"; rm -rf \"$PWD\"\n";
    std::fs::write(ned.join("run.sh"), run).unwrap();
    let exact = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/check/exact.py");
    std::fs::copy(&exact, ned.join("exact.py")).unwrap();
    let json = dir.path().join("grades.json");
    let o = grade_class(&class, &suite, &["--json", json.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", common::binary::stderr(&o));
    let json = std::fs::read_to_string(&json).unwrap();
    let record = |family: &str| {
        (json.lines())
            .find(|l| l.contains("\"submission\": \"ned-removes\"") && l.contains(family))
            .unwrap_or_else(|| panic!("{family}: {json}"))
            .to_string()
    };
    assert!(record("\"16-").contains("\"status\": \"ok\""), "{json}");
    let later = record("\"17-");
    assert!(
        later.contains("\"status\": \"crashed\"")
            && later.contains("is gone: a run of the program removed it"),
        "{later}"
    );
    assert!(ned.join("run.sh").exists(), "the original stays");
}

/// Two submissions whose folder names differ only in a byte that is not UTF-8 (`caf\xe9`,
/// `caf\xe8`): each shown with that byte as its escape, not both as `caf�`.
#[test]
fn names_that_are_not_utf8_stay_apart() {
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada", "bob-crashes"], &["16-"]);
    for (from, to) in [("ada", &b"caf\xe9"[..]), ("bob-crashes", &b"caf\xe8"[..])] {
        let to = class.join(std::ffi::OsStr::from_bytes(to));
        std::fs::rename(class.join(from), to).unwrap();
    }
    let csv = dir.path().join("grades.csv");
    let o = grade_class(&class, &suite, &["--csv", csv.to_str().unwrap()]);
    let out = common::binary::stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{out}");
    let csv = std::fs::read_to_string(&csv).unwrap();
    for text in [&out, &csv] {
        assert!(!text.contains('\u{fffd}'), "{text}");
    }
    let row = |name: &str| {
        csv.lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_default()
    };
    assert!(row("caf\\xe8,16-").ends_with(",crashed"), "{csv}");
    assert!(row("caf\\xe9,16-").ends_with(",ok"), "{csv}");
}

/// Bad input: exit 2 and the path named, before anything runs.
#[test]
fn bad_input_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = class_and_suite(dir.path());
    let (class, suite) = (class.to_str().unwrap(), suite.to_str().unwrap());
    let missing = dir.path().join("no-such-class");
    let missing = missing.to_str().unwrap();
    let program = "sh run.sh {scene} {rays}";
    let grade = |more: &[&str]| raylab(&[&["grade"], more].concat());
    common::binary::assert_fails(
        &grade(&[missing, "--suite", suite, "--program", program]),
        2,
        &[missing],
    );
    common::binary::assert_fails(
        &grade(&[class, "--suite", missing, "--program", program]),
        2,
        &[missing],
    );
    common::binary::assert_fails(
        &grade(&[class, "--suite", suite, "--program", "sh run.sh"]),
        2,
        &["{scene}"],
    );
    let rubric = common::binary::write(dir.path(), "rubric.txt", "99-no-such-family 1\n");
    common::binary::assert_fails(
        &grade(&[
            class,
            "--suite",
            suite,
            "--program",
            program,
            "--rubric",
            &rubric,
        ]),
        2,
        &["rubric.txt:1", "99-no-such-family"],
    );
    let inside = format!("{class}/ada/grades.csv");
    common::binary::assert_fails(
        &grade(&[
            class,
            "--suite",
            suite,
            "--program",
            program,
            "--csv",
            &inside,
        ]),
        2,
        &[&inside],
    );
    assert!(!Path::new(&inside).exists());
    common::binary::assert_fails(
        &grade(&[
            class,
            "--suite",
            suite,
            "--program",
            program,
            "--budget",
            "0",
        ]),
        2,
        &["--budget 0"],
    );
    // A rubric of comments only gives no points: refused, not a grading out of 0.
    let empty = common::binary::write(dir.path(), "empty.txt", "# to do\n");
    let o = grade(&[
        class,
        "--suite",
        suite,
        "--program",
        program,
        "--rubric",
        &empty,
    ]);
    common::binary::assert_fails(&o, 2, &["empty.txt: no points"]);
    // An output in a missing directory: the flag and the path.
    let stray = dir.path().join("no-such/grades.csv");
    let stray = stray.to_str().unwrap();
    let o = grade(&[
        class,
        "--suite",
        suite,
        "--program",
        program,
        "--csv",
        stray,
    ]);
    common::binary::assert_fails(&o, 2, &["--csv: ", stray]);
}

/// Only directories are submissions: a file, a broken link, a hidden directory (`.git`),
/// macOS's `__MACOSX` and a suite exported there (it was graded as a student who crashed) are
/// each named on stderr, not dropped unseen; a name with a line break or an escape sequence
/// shows escaped, one row of the table, driving no terminal.
#[test]
fn what_is_not_a_submission_is_named_and_names_stay_on_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-"]);
    std::fs::create_dir(class.join(".git")).unwrap();
    // (macOS's zip metadata: a folder of `._` files, graded as a student who crashed.)
    std::fs::create_dir_all(class.join("__MACOSX/ada")).unwrap();
    std::fs::write(class.join("__MACOSX/ada/._run.sh"), [0u8, 5, 22, 7]).unwrap();
    std::os::unix::fs::symlink("nowhere", class.join("gone")).unwrap();
    let suite_here = class.join("lab-suite");
    std::fs::create_dir(&suite_here).unwrap();
    std::fs::write(
        suite_here.join("families.txt"),
        "# what raylab suite export lists\n",
    )
    .unwrap();
    // A student's copy of families.txt beside their code leaves them a submission.
    std::fs::copy(
        suite_here.join("families.txt"),
        class.join("ada/families.txt"),
    )
    .unwrap();
    // (A right-to-left override too: it reversed the rest of the row.)
    let odd = class.join("eve\nada        ok\u{1b}[31m\u{202e}x");
    // A name of wide characters (two columns each on a terminal), and a learning platform's
    // long folder name (cut to fit the table, whole in the files).
    let wide = class.join("李雷");
    let long = class.join("Fatima Zahra El Idrissi_1243_assignsubmission_file_");
    for dir in [&odd, &wide, &long] {
        std::fs::create_dir_all(dir).unwrap();
        for file in ["run.sh", "exact.py"] {
            std::fs::copy(class.join("ada").join(file), dir.join(file)).unwrap();
        }
    }
    let o = grade_class(&class, &suite, &[]);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    for (name, why) in [
        ("notes.txt", "not a directory"),
        ("gone", "not a directory"),
        (".git", "hidden"),
        ("__MACOSX", "macOS's zip metadata"),
        ("lab-suite", "a suite (raylab suite export's files only)"),
    ] {
        let said = format!("{name}: {why}, so not a submission (not graded)");
        assert!(err.contains(&said), "{said} in {err}");
    }
    assert!(err.contains("grading 4 submissions"), "{err}");
    let rows: Vec<&str> = out.lines().collect();
    assert_eq!(rows.len(), 5, "{out}");
    // (In name order, case aside: ada, eve, Fatima, 李雷.)
    assert!(
        rows[2].starts_with("eve\\nada        ok\\u{1b}[31m\\u{202e}x "),
        "{out}"
    );
    assert!(
        rows[3].starts_with("Fatima Zahra El Idrissi_1243_as…submission_file_ "),
        "{out}"
    );
    // Every row's "passed" column ends at the same terminal column, 李雷's too.
    let columns = |row: &str| {
        let end = (row.find("passed").map(|i| i + "passed".len()))
            .or_else(|| row.find("/1 ").map(|i| i + "/1".len()))
            .unwrap();
        let wide = row[..end]
            .chars()
            .filter(|c| *c == '李' || *c == '雷')
            .count();
        row[..end].chars().count() + wide
    };
    assert!(rows[4].starts_with("李雷 "), "{out}");
    let at: Vec<usize> = rows.iter().map(|r| columns(r)).collect();
    assert!(at.iter().all(|c| *c == at[0]), "{at:?}\n{out}");
    assert!(
        !out.contains(['\u{1b}', '\u{202e}']) && !err.contains('\u{1b}'),
        "{out}{err}"
    );
}

/// A submission that hangs on every family costs its --budget, not a --timeout per family:
/// the family where the budget runs out is stopped there, the rest are skipped. A correct
/// program beside it passes every family within the same budget.
#[test]
fn a_hanging_submission_costs_its_budget_and_no_more() {
    let dir = tempfile::tempdir().unwrap();
    // Five small families (the exact program answers them in about a second in all).
    let small = ["16-", "17-", "18-", "25-", "31-"];
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada", "cy-hangs"], &small);
    // (Its own sleeper, told apart from the other tests'.)
    std::fs::write(class.join("cy-hangs/run.sh"), "sleep 917005\n").unwrap();
    let json = dir.path().join("grades.json");
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let o = raylab(&[
        "grade",
        &path(&class),
        "--suite",
        &path(&suite),
        "--program",
        "sh run.sh {scene} {rays}",
        "--timeout",
        "2",
        "--budget",
        "5",
        "--json",
        &path(&json),
    ]);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    let json = std::fs::read_to_string(&json).unwrap();
    let statuses = |name: &str| -> Vec<String> {
        (json.split("{\"submission\": ").skip(1))
            .filter(|r| r.starts_with(&format!("\"{name}\"")))
            .map(|r| {
                r.split("\"status\": \"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap()
                    .to_string()
            })
            .collect()
    };
    assert_eq!(statuses("ada"), ["ok"; 5], "{json}");
    // 2 s, 2 s, then the 1 s left: two timeouts, the budget out in the third family (told
    // apart: a slow program is not a hung one), two families skipped.
    assert_eq!(
        statuses("cy-hangs"),
        ["timeout", "timeout", "budget", "skipped", "skipped"],
        "{json}"
    );
    assert!(
        json.contains("ran out of time: the submission's --budget of 5 s ran out")
            && json.contains("not run: the submission's --budget of 5 s ran out"),
        "{json}"
    );
    let row = out.lines().find(|l| l.starts_with("cy-hangs")).unwrap();
    assert!(row.ends_with("timeout 2, budget 1, skipped 2"), "{out}");
    assert_eq!(
        running("917005"),
        Vec::<String>::new(),
        "the sleeper survived"
    );
}

/// A rubric without a `*` line gives the families it does not name no points, and says so
/// (a forgotten `*` line read as a class that earned little).
#[test]
fn a_rubric_without_a_star_line_says_what_it_leaves_at_0() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-", "17-"]);
    let rubric = common::binary::write(dir.path(), "rubric.txt", "16 3\n");
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let (class, suite) = (path(&class), path(&suite));
    let program = "sh run.sh {scene} {rays}";
    let args = [
        "grade",
        &class,
        "--suite",
        &suite,
        "--program",
        program,
        "--rubric",
        &rubric,
    ];
    let o = raylab(&args);
    let err = common::binary::stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let warning = "rubric.txt: no `*` line: the families it does not name (1) are worth 0 points";
    assert!(err.contains(warning), "{err}");
    assert!(
        common::binary::stdout(&o).contains(" 3/3 "),
        "{}",
        common::binary::stdout(&o)
    );
}
