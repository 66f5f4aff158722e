//! What `raylab grade` writes for the teacher and the students: a failed family's first
//! mistake in the JSON, and each student's feedback file.

use crate::common;

use super::grade::{cut_class_and_suite, grade_class};
use std::path::Path;

#[test]
fn a_failed_familys_json_record_names_its_first_mistake() {
    // The JSON's `detail` was empty for a family graded `failed`: a teacher could not tell a
    // student which ray to look at without running `check` again. It holds the first mistake
    // as `check` shows it now: the ray's place in the suite, the ray and both answers.
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["02-"]);
    let last_hit = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/check/bugs/last_hit.py");
    std::fs::copy(last_hit, class.join("ada/exact.py")).unwrap();
    let json = dir.path().join("grades.json");
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let o = grade_class(&class, &suite, &["--json", &path(&json)]);
    assert_eq!(o.status.code(), Some(0), "{}", common::binary::stderr(&o));
    let json = std::fs::read_to_string(&json).unwrap();
    let detail = json
        .split("\"status\": \"failed\", \"detail\": \"")
        .nth(1)
        .and_then(|d| d.split("\"").next())
        .unwrap_or_else(|| panic!("no failed record with a detail: {json}"));
    let family = suite.join("02-cube-from-outside/rays.txt");
    assert!(
        detail.starts_with(&format!("{}:", family.display())),
        "{detail}"
    );
    assert!(
        detail.contains("exact: hit")
            && detail.contains("given (its output:")
            && detail.contains("[wrong primitive: the given t ")
            && detail.ends_with("the nearest hit wins]"),
        "{detail}"
    );
}

/// `--feedback DIR` writes a file per submission for its student: every family's status and
/// counts, and where it did not pass, why: a failed family's first mistake as `check` shows
/// it (the ray's file and line in the suite, the exact answer, the one given), a crash's
/// message. (The CSV had no detail, the table counts only: a teacher had to parse the JSON.)
#[test]
fn feedback_gives_each_student_their_families_and_first_mistakes() {
    let dir = tempfile::tempdir().unwrap();
    // (Two small families: the Cornell box's 3,147 rays took exact.py 6 s a submission.)
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada", "bob-crashes"], &["16-", "37-"]);
    // One bug: a miss where the exact ray meets a triangle beyond t = 3.
    let buggy = class.join("zoe-misses-far");
    std::fs::create_dir(&buggy).unwrap();
    std::fs::copy(class.join("ada/exact.py"), buggy.join("exact.py")).unwrap();
    std::fs::write(
        buggy.join("run.sh"),
        "python3 exact.py \"$1\" \"$2\" | awk '$1 == \"hit\" && $2 > 3 { print \"miss\"; next } { print }'\n",
    )
    .unwrap();
    let feedback = dir.path().join("feedback");
    let more = [
        "--feedback",
        feedback.to_str().unwrap(),
        "--t-tolerance",
        "1e-5",
        "--timeout",
        "30",
    ];
    let o = grade_class(&class, &suite, &more);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    let read = |name: &str| std::fs::read_to_string(feedback.join(name)).unwrap();
    let ada = read("ada.txt");
    assert!(
        ada.starts_with("raylab grade: ada\n2 of 2 families passed\n"),
        "{ada}"
    );
    // The command that runs a family again as graded: the program, tolerance and timeout.
    let again = "  raylab check --suite SUITE --family NAME --program 'sh run.sh {scene} {rays}' \
                 --t-tolerance 0.00001 --timeout 30\n";
    assert!(ada.contains(again), "{ada}");
    assert_eq!(ada.matches(": ok (").count(), 2, "{ada}");
    let bob = read("bob-crashes.txt");
    assert!(bob.contains("0 of 2 families passed"), "{bob}");
    // (Its second family's crash as the first's: said once.)
    assert_eq!(
        bob.matches("bob: segfault (not really)").count(),
        1,
        "{bob}"
    );
    assert!(
        bob.contains("    (the same as the family above)\n"),
        "{bob}"
    );
    let zoe = read("zoe-misses-far.txt");
    let failed = (zoe.lines())
        .position(|l| l.contains(": failed ("))
        .unwrap_or_else(|| panic!("{zoe}"));
    let mistake = zoe.lines().nth(failed + 1).unwrap();
    // The ray's file in the student's suite, as the command names it, not the teacher's.
    let family = zoe.lines().nth(failed).unwrap().split(':').next().unwrap();
    assert!(
        mistake.starts_with(&format!("    SUITE/{family}/rays.txt:"))
            && !zoe.contains(suite.to_str().unwrap())
            && mistake.contains("given (its output:")
            && mistake.contains("  [leak: the exact hit is the sphere's far root"),
        "{zoe}"
    );
    // Under it, the command that checks that ray alone, run in the student's folder with
    // their suite: one ray, the same leak.
    let alone = (zoe
        .lines()
        .nth(failed + 2)
        .unwrap()
        .strip_prefix("    this ray alone: "))
    .unwrap_or_else(|| panic!("{zoe}"));
    let line: usize = mistake
        .split(':')
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let expected = format!(
        "sed -n {line}p SUITE/{family}/rays.txt > one.txt && raylab check --scene \
         SUITE/{family}/scene.txt --rays one.txt --program 'sh run.sh {{scene}} {{rays}}' \
         --t-tolerance 0.00001 --timeout 30"
    );
    assert_eq!(alone, expected, "{zoe}");
    let command = (alone.replace("SUITE/", &format!("{}/", suite.display()))).replace(
        "&& raylab ",
        &format!("&& '{}' ", env!("CARGO_BIN_EXE_raylab")),
    );
    let o = std::process::Command::new("sh")
        .args(["-c", &command])
        .current_dir(class.join("zoe-misses-far"))
        .output()
        .unwrap();
    let out = common::binary::stdout(&o);
    assert_eq!(o.status.code(), Some(1), "{command}\n{out}");
    assert!(
        out.trim_end()
            .ends_with("rays 1 right 0 leaks 1 false_hits 0 wrong 0 ties 0 t_failures 0"),
        "{out}"
    );
    assert_eq!(std::fs::read_dir(&feedback).unwrap().count(), 3);
    // Made private: each student's feedback is that student's (it was 755, as the umask
    // left it).
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(&feedback).unwrap().permissions().mode();
    assert_eq!(mode & 0o777, 0o700, "{mode:o}");
    // Graded again without bob into the same folder: his old file is named (handed out with
    // the folder, it sent a dropped student an old grade), and kept (a grading of a few late
    // submissions into the class's folder leaves everyone else's); a file not raylab's is not
    // named.
    std::fs::remove_dir_all(class.join("bob-crashes")).unwrap();
    std::fs::write(feedback.join("notes.txt"), "the rubric's notes\n").unwrap();
    let o = grade_class(&class, &suite, &more);
    let err = common::binary::stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let said = format!(
        "warning: --feedback {}: 1 file of an earlier grading, of no submission graded now: \
         bob-crashes.txt (kept: a grading of late submissions leaves the others' feedback; of a \
         student no longer in the class, remove it before handing the folder out)",
        feedback.display()
    );
    assert!(err.contains(&said), "{said} in {err}");
    assert!(feedback.join("bob-crashes.txt").exists());
    // Inside the class it would be graded as a submission, inside a submission copied with
    // it: refused, through a link too; a file is no directory. Before any program runs.
    let link = dir.path().join("link");
    std::os::unix::fs::symlink(class.join("ada"), &link).unwrap();
    let file = dir.path().join("notes.txt");
    std::fs::write(&file, "").unwrap();
    for (out, why) in [
        (class.join("feedback"), "inside the input"),
        (link, "inside the input"),
        (file, "not a directory"),
    ] {
        let o = grade_class(&class, &suite, &["--feedback", out.to_str().unwrap()]);
        let err = common::binary::stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{out:?}: {err}");
        assert!(err.contains("--feedback") && err.contains(why), "{err}");
        assert!(!err.contains("grading "), "{err}");
    }
}

/// A student who handed nothing in (an empty directory, or empty directories only) is
/// `empty` on every family, and nothing runs for them; a directory with one file in it is
/// run (and its program, missing, crashes). (An empty directory was graded as 38 crashes of
/// a program not found.) The feedback goes through a link to a directory not made yet.
#[test]
fn an_empty_submission_is_empty_and_not_run() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-", "37-"]);
    std::fs::create_dir_all(class.join("kim-empty/src/lab")).unwrap();
    // (What a Mac leaves in a folder it zips is no submission.)
    std::fs::create_dir_all(class.join("max-zipped/__MACOSX/lab")).unwrap();
    std::fs::write(class.join("max-zipped/.DS_Store"), "\0\0\0\x01Bud1").unwrap();
    std::fs::write(
        class.join("max-zipped/__MACOSX/lab/._run.sh"),
        "\0\x05\x16\x07",
    )
    .unwrap();
    for junk in ["thumbs.db", "Desktop.ini", "Icon\r"] {
        std::fs::write(class.join("max-zipped").join(junk), "").unwrap();
    }
    std::fs::create_dir_all(class.join("lou-notes")).unwrap();
    // (Named as a class list reads, case and accents aside.)
    std::fs::create_dir_all(class.join("Ned-empty")).unwrap();
    std::fs::create_dir_all(class.join("Émile-empty")).unwrap();
    // (An archive alone: graded, and warned of.)
    std::fs::create_dir_all(class.join("oli-zipped")).unwrap();
    std::fs::write(class.join("oli-zipped/lab3.zip"), "PK\x05\x06").unwrap();
    std::fs::write(class.join("pam.zip"), "PK\x05\x06").unwrap();
    std::fs::create_dir_all(class.join("Ørjan-empty")).unwrap();
    std::fs::write(class.join("lou-notes/notes.txt"), "").unwrap();
    // (The feedback through a link to a directory not made yet: made through it, as a
    // missing one is; it said "File exists".)
    let (csv, feedback) = (dir.path().join("grades.csv"), dir.path().join("feedback"));
    std::os::unix::fs::symlink(dir.path().join("later/feedback"), &feedback).unwrap();
    let more = [
        "--csv",
        csv.to_str().unwrap(),
        "--feedback",
        feedback.to_str().unwrap(),
    ];
    let o = grade_class(&class, &suite, &more);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    let row = |name: &str| {
        (out.lines())
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("{name}: {out}"))
    };
    assert!(row("ada ").ends_with(" ok"), "{out}");
    assert!(row("kim-empty ").ends_with(" empty 2"), "{out}");
    assert!(row("max-zipped ").ends_with(" empty 2"), "{out}");
    let names: Vec<&str> = (out.lines().skip(1))
        .filter_map(|l| l.split(' ').next())
        .collect();
    let order = [
        "ada",
        "Émile-empty",
        "kim-empty",
        "lou-notes",
        "max-zipped",
        "Ned-empty",
        "oli-zipped",
        "Ørjan-empty",
    ];
    assert_eq!(names, order, "{out}");
    let zipped = "oli-zipped: holds archives alone (lab3.zip): unpack them where the program";
    assert!(err.contains(zipped), "{err}");
    let zip = "pam.zip: an archive, not a directory (unpack each into a folder of its own), so \
               not a submission";
    assert!(err.contains(zip), "{err}");
    assert!(row("lou-notes ").ends_with(" crashed 2"), "{out}");
    let csv = std::fs::read_to_string(&csv).unwrap();
    let kim: Vec<&str> = csv
        .lines()
        .filter(|l| l.starts_with("kim-empty,"))
        .collect();
    assert_eq!(kim.len(), 2, "{csv}");
    // No counts (nothing graded), no time (nothing ran).
    assert!(kim.iter().all(|l| l.ends_with(",,,,,,0.0,empty")), "{csv}");
    let kim = std::fs::read_to_string(feedback.join("kim-empty.txt")).unwrap();
    assert!(
        kim.contains("0 of 2 families passed")
            && kim
                .matches("holds no file (nothing handed in; a system's")
                .count()
                == 1,
        "{kim}"
    );
}

/// A submission whose files hold over 1 GiB (a sparse file: no disk in the class) is not
/// copied, and says why; the others are graded. (Its copy wrote the file's whole size: a
/// 20 GiB one took 83 s and 20 GiB of the temporary directory.) A class directory that is
/// the suite itself is refused (its families were graded as submissions).
#[test]
fn a_submission_too_big_to_copy_is_not_run_and_the_suite_is_no_class() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-"]);
    let big = class.join("max-sparse");
    std::fs::create_dir(&big).unwrap();
    std::fs::copy(class.join("ada/run.sh"), big.join("run.sh")).unwrap();
    let sparse = std::fs::File::create(big.join("data.bin")).unwrap();
    sparse.set_len(3 << 30).unwrap();
    let feedback = dir.path().join("feedback");
    let o = grade_class(&class, &suite, &["--feedback", feedback.to_str().unwrap()]);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    assert!(
        out.lines()
            .any(|l| l.starts_with("ada ") && l.ends_with(" ok")),
        "{out}"
    );
    assert!(
        (out.lines()).any(|l| l.starts_with("max-sparse ") && l.ends_with(" crashed 1")),
        "{out}"
    );
    let said = std::fs::read_to_string(feedback.join("max-sparse.txt")).unwrap();
    assert!(
        said.contains("its files hold over 1 GiB (at ")
            && said.contains("data.bin), more than a submission may: not copied to be graded"),
        "{said}"
    );
    let o = grade_class(&suite, &suite, &[]);
    common::binary::assert_fails(&o, 2, &["CLASS_DIR and --suite name the same directory"]);
}

/// An output that cannot be written (a full disk: /dev/full) is said, and the other files and
/// the table are still written, the run failing after them (the whole grading's table was
/// lost to it).
#[test]
fn an_output_that_cannot_be_written_leaves_the_others_and_the_table() {
    if !Path::new("/dev/full").exists() {
        eprintln!("no /dev/full here");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada"], &["16-"]);
    let json = dir.path().join("grades.json");
    let more = ["--csv", "/dev/full", "--json", json.to_str().unwrap()];
    let o = grade_class(&class, &suite, &more);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(2), "{out}{err}");
    assert!(
        err.contains("error: /dev/full: No space left on device"),
        "{err}"
    );
    assert!(
        err.contains("1 output file not written (above); the table is"),
        "{err}"
    );
    assert!(
        out.lines()
            .any(|l| l.starts_with("ada ") && l.ends_with(" ok")),
        "{out}"
    );
    let json = std::fs::read_to_string(&json).unwrap();
    assert!(json.contains("\"submission\": \"ada\""), "{json}");
}

/// `--only NAME` grades that submission alone (repeatable), and its outputs hold it alone; a
/// name no submission has is refused before any program runs, naming it.
#[test]
fn only_grades_the_submissions_named() {
    let dir = tempfile::tempdir().unwrap();
    let (class, suite) = cut_class_and_suite(dir.path(), &["ada", "bob-crashes"], &["16-"]);
    let csv = dir.path().join("one.csv");
    // (As tab completes it, with a slash.)
    let more = ["--only", "bob-crashes/", "--csv", csv.to_str().unwrap()];
    let o = grade_class(&class, &suite, &more);
    let (out, err) = (common::binary::stdout(&o), common::binary::stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{out}{err}");
    let rows: Vec<&str> = out.lines().skip(1).collect();
    assert!(
        rows.len() == 1 && rows[0].starts_with("bob-crashes "),
        "{out}"
    );
    let csv = std::fs::read_to_string(&csv).unwrap();
    assert!(
        csv.lines().skip(1).all(|l| l.starts_with("bob-crashes,")),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 2, "{csv}");
    // A name unzipped from a Mac (é as e and a combining accent), typed composed: found.
    std::fs::create_dir(class.join("Jose\u{301}")).unwrap();
    let o = grade_class(&class, &suite, &["--only", "Jos\u{e9}"]);
    let out = common::binary::stdout(&o);
    let rows: Vec<&str> = out.lines().skip(1).collect();
    assert!(
        rows.len() == 1 && rows[0].starts_with("Jose\u{301} "),
        "{out}"
    );
    // One family again into the feedback folder: said to replace each file whole.
    let feedback = dir.path().join("feedback");
    let more = [
        "--only",
        "ada",
        "--family",
        "16",
        "--feedback",
        feedback.to_str().unwrap(),
    ];
    let o = grade_class(&class, &suite, &more);
    let said = "with --family 16: each student's file there is written anew, of that family alone";
    assert!(
        common::binary::stderr(&o).contains(said),
        "{}",
        common::binary::stderr(&o)
    );
    let o = grade_class(&class, &suite, &["--only", "ada", "--only", "zed"]);
    let said = format!(
        "--only zed: no submission of that name in {}",
        class.display()
    );
    common::binary::assert_fails(&o, 2, &[&said]);
    assert!(
        !common::binary::stderr(&o).contains("grading"),
        "nothing ran"
    );
}
