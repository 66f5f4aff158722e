//! The failed families told apart: those rounding fails correct code on too, and those every
//! correct program of the precision passes (a bug's, to mend first). The C++ starter (correct,
//! in double) and it with one bug (open edges), `check`ed and `grade`d on a cube seen from
//! inside (every correct double program passes it) and an icosphere (rounding at its shared
//! vertices fails the starter).

use crate::common;

use super::grade::open_up;
use std::path::{Path, PathBuf};

crate::raylab_runner!();

/// The starter's closed edge test, and the bug: open edges.
const CLOSED: &str = "if (!(u >= 0 && v >= 0 && u + v <= 1)) return false;";
const OPEN: &str = "if (!(u > 0 && v > 0 && u + v < 1)) return false;";

/// Builds examples/check/cpp/intersect.cpp with `from` replaced by `to` into `dir`/intersect.
fn build(dir: &Path, from: &str, to: &str) -> PathBuf {
    let cpp = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/check/cpp/intersect.cpp");
    let source = std::fs::read_to_string(cpp).unwrap();
    assert!(source.contains(from), "the starter's edge test");
    std::fs::create_dir_all(dir).unwrap();
    open_up(dir);
    let (source_file, exe) = (dir.join("intersect.cpp"), dir.join("intersect"));
    std::fs::write(&source_file, source.replace(from, to)).unwrap();
    let o = std::process::Command::new("g++")
        .args(["-O2", "-std=c++17", "-o"])
        .args([&exe, &source_file])
        .output()
        .unwrap();
    assert!(o.status.success(), "g++: {}", common::binary::stderr(&o));
    exe
}

/// The suite cut to the cube seen from inside (01) and the icosphere seen from inside (03).
fn suite(root: &Path) -> PathBuf {
    let suite = root.join("suite");
    let o = raylab(&["suite", "export", suite.to_str().unwrap()]);
    assert!(o.status.success(), "{}", common::binary::stderr(&o));
    for family in std::fs::read_dir(&suite).unwrap().flatten() {
        let name = family.file_name().into_string().unwrap();
        let kept = ["01-cube-from-inside", "03-icosphere-from-inside"].contains(&&*name);
        if family.path().is_dir() && !kept {
            std::fs::remove_dir_all(family.path()).unwrap();
        }
    }
    std::fs::remove_file(suite.join("families.txt")).unwrap();
    suite
}

/// Correct double code that fails only where rounding fails it is told so, and nothing else
/// failed; one bug's family is named first, to mend, the other apart; `grade` counts them in
/// its status and its feedback says the same; the exported README gives each family's column.
#[test]
fn failed_families_are_told_apart_from_those_rounding_fails_correct_code_on() {
    if !common::tool_for("g++", "build-essential", "the starter and its bug") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    open_up(dir.path());
    let suite = suite(dir.path());
    let readme = std::fs::read_to_string(suite.join("README.md")).unwrap();
    assert!(readme.contains("| correct code passes it in |"), "{readme}");
    for (family, needs) in [
        ("01-cube-from-inside", "f64"),
        ("03-icosphere-from-inside", "exact only"),
    ] {
        let row = readme
            .lines()
            .find(|l| l.starts_with(&format!("| `{family}`")))
            .unwrap();
        assert!(row.ends_with(&format!("| {needs} |")), "{row}");
    }
    let class = dir.path().join("class");
    let starter = build(&class.join("starter"), CLOSED, CLOSED);
    let open = build(&class.join("open-edges"), CLOSED, OPEN);
    open_up(&class);
    let check = |exe: &Path| {
        let program = format!("'{}' {{scene}} {{rays}}", exe.display());
        let args = [
            "check",
            "--suite",
            suite.to_str().unwrap(),
            "--program",
            &program,
        ];
        let o = raylab(&[&args[..], &["--precision", "f64"]].concat());
        assert_eq!(o.status.code(), Some(1), "{}", common::binary::stderr(&o));
        String::from_utf8(o.stdout).unwrap()
    };
    let rounding = "where rounding fails some correct f64 programs too";
    let out = check(&starter);
    let said = "no family failed that every correct f64 program measured passes; those failed \
                (03) are ones ";
    assert!(
        out.contains(&format!("{said}{rounding} (the suite's README.md")),
        "{out}"
    );
    assert!(
        out.contains("their hints say which mistakes lie within rounding"),
        "{out}"
    );
    let out = check(&open);
    let said = "to mend first: 01, failed where every correct f64 program measured passes; \
                failed besides: 03, ";
    assert!(out.contains(&format!("{said}{rounding}")), "{out}");

    // Two families' directories swapped: their scenes name their own families, and the
    // failed ones are not sorted, said so (it sorted a bug's family as rounding's).
    let swapped = dir.path().join("swapped");
    std::fs::create_dir(&swapped).unwrap();
    for (from, to) in [
        ("01-cube-from-inside", "03-icosphere-from-inside"),
        ("03-icosphere-from-inside", "01-cube-from-inside"),
    ] {
        std::fs::create_dir(swapped.join(to)).unwrap();
        for file in ["scene.txt", "rays.txt"] {
            std::fs::copy(suite.join(from).join(file), swapped.join(to).join(file)).unwrap();
        }
    }
    let args = ["check", "--suite", swapped.to_str().unwrap(), "--program"];
    let program = format!("'{}' {{scene}} {{rays}}", starter.display());
    let o = raylab(&[&args[..], &[&program, "--precision", "f64"]].concat());
    let out = String::from_utf8(o.stdout).unwrap();
    let not_sorted = "not sorted: 01-cube-from-inside (not a family of this raylab's suite, or \
                      its scene.txt is another's";
    assert!(out.contains(not_sorted) && !out.contains(rounding), "{out}");
    // A double program graded in float: its t's digits say so.
    let program = format!("'{}' {{scene}} {{rays}}", starter.display());
    let o = raylab(&[
        "check",
        "--suite",
        suite.to_str().unwrap(),
        "--program",
        &program,
    ]);
    let out = String::from_utf8(o.stdout).unwrap();
    let digits = "its t's have 15 significant digits or more, as a double program prints them: \
                  if it computes in double, check it with --precision f64";
    assert!(out.contains(digits), "{out}");
    // A family whose run did not end well is said first: not "nothing failed but rounding's".
    let crash = format!(
        "head -1 {{scene}} | grep -q 'cube, from inside' && exit 3; '{}' {{scene}} {{rays}}",
        starter.display()
    );
    let args = [
        "check",
        "--suite",
        suite.to_str().unwrap(),
        "--program",
        &crash,
    ];
    let o = raylab(&[&args[..], &["--precision", "f64"]].concat());
    let out = String::from_utf8(o.stdout).unwrap();
    let ungraded = "1 family's run did not end well: mend it first; of the others, no family \
                    failed that every correct f64 program measured passes";
    assert!(out.contains(ungraded), "{out}");
    assert!(out.contains("1 of 2 families' runs did not end well (FAILED or SKIPPED above)"));
    // The exact answers a line late: said under the total, before the sort.
    let exe = env!("CARGO_BIN_EXE_raylab");
    let late = format!("(echo miss; '{exe}' trace --scene {{scene}} --rays {{rays}} | sed '$d')");
    let o = raylab(&[
        "check",
        "--suite",
        suite.to_str().unwrap(),
        "--program",
        &late,
    ]);
    let out = String::from_utf8(o.stdout).unwrap();
    let off = "answers a line off in families 01, 03: mend their order first";
    assert!(out.contains(off), "{out}");
    let feedback = dir.path().join("feedback");
    let args = [
        "grade",
        class.to_str().unwrap(),
        "--suite",
        suite.to_str().unwrap(),
    ];
    let more = [
        "--program",
        "./intersect {scene} {rays}",
        "--precision",
        "f64",
        "--feedback",
    ];
    let o = raylab(&[&args[..], &more, &[feedback.to_str().unwrap()]].concat());
    let out = String::from_utf8(o.stdout.clone()).unwrap();
    assert!(o.status.success(), "{out}{}", common::binary::stderr(&o));
    let status = |name: &str| {
        let line = out.lines().find(|l| l.starts_with(name)).unwrap();
        line.split("  ").last().unwrap().trim().to_string()
    };
    assert_eq!(status("starter"), "failed 1 (rounding 1)", "{out}");
    assert_eq!(status("open-edges"), "failed 2 (rounding 1)", "{out}");
    let text = std::fs::read_to_string(feedback.join("open-edges.txt")).unwrap();
    assert!(text.contains(&format!("{said}{rounding}")), "{text}");
}
