//! Checking code that is not raylab's: the exported suite reads back exactly, `raylab check`
//! grades every kind of answer, and a program that fails is never a pass.

use crate::common;

use common::binary::{assert_fails, assert_passes, count, last_line, text};
use raylab::check::{export, suite};
use raylab::math::Real;
use raylab::tracefile;
use rayon::prelude::*;
use std::path::Path;

crate::raylab_runner!();
crate::check_runner!();

fn bits<T: Real>(v: &[T]) -> Vec<u64> {
    v.iter().map(|x| x.f64().to_bits()).collect()
}

/// Every exported family's files read back as the library's family, to the bit (signed
/// zeros and subnormals included), in f32 and, widened exactly, in f64.
#[test]
fn the_exported_suite_reads_back_exactly_in_f32_and_f64() {
    let dir = tempfile::tempdir().unwrap();
    let families = suite::all();
    let written = export::export(dir.path(), &families).unwrap();
    assert_eq!(written.len(), families.len());
    let readme = std::fs::read_to_string(dir.path().join("README.md")).unwrap();
    assert!(readme.starts_with(export::README_TITLE));
    for (family, family_dir) in families.iter().zip(&written) {
        let name = family_dir
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        assert!(
            readme.contains(&format!("`{name}`")),
            "{name} not in the README"
        );
        assert!(
            !family.probes.is_empty(),
            "{}: says what it probes",
            family.name
        );
        let scene_file = family_dir.join("scene.txt");
        let rays_file = family_dir.join("rays.txt");
        let scene_text = std::fs::read_to_string(&scene_file).unwrap();
        let rays_text = std::fs::read_to_string(&rays_file).unwrap();
        let file = scene_file.display().to_string();
        let shapes32 = tracefile::parse_scene::<f32>(&file, &scene_text).unwrap().0;
        let shapes64 = tracefile::parse_scene::<f64>(&file, &scene_text).unwrap().0;
        assert_eq!(shapes32.len(), family.shapes.len(), "{name}");
        for ((want, got32), got64) in family.shapes.iter().zip(&shapes32).zip(&shapes64) {
            assert_eq!(
                got32.key(),
                want.key(),
                "{name}: {want:?} read as {got32:?}"
            );
            assert_eq!(
                got32.scene_line(),
                got64.scene_line(),
                "{name}: f64 reads the same"
            );
        }
        let file = rays_file.display().to_string();
        let rays32 = tracefile::parse_rays::<f32>(&file, &rays_text).unwrap();
        let rays64 = tracefile::parse_rays::<f64>(&file, &rays_text).unwrap();
        assert_eq!(rays32.len(), family.rays.len(), "{name}");
        for ((want, got32), got64) in family.trace_rays().iter().zip(&rays32).zip(&rays64) {
            let (want, span) = (want.ray, (want.tmin, want.tmax));
            let want_bits = [bits(&want.o), bits(&want.d)];
            assert_eq!(
                [bits(&got32.ray.o), bits(&got32.ray.d)],
                want_bits,
                "{name}"
            );
            assert_eq!(
                [bits(&got64.ray.o), bits(&got64.ray.d)],
                want_bits,
                "{name}"
            );
            assert_eq!(
                [got32.tmin.to_bits(), got32.tmax.to_bits()],
                [span.0.to_bits(), span.1.to_bits()],
                "{name}"
            );
            assert_eq!((got64.tmin, got64.tmax), (span.0 as f64, span.1 as f64));
        }
    }
    // Signed zeros and subnormals are among them (the families that probe them).
    let all_rays: String = written
        .iter()
        .map(|d| std::fs::read_to_string(d.join("rays.txt")).unwrap())
        .collect();
    assert!(
        all_rays.contains(" -0 "),
        "a -0 direction component is written"
    );
    let names: Vec<String> = written.iter().map(|d| d.display().to_string()).collect();
    assert!(
        names.iter().any(|n| n.ends_with("tiny-cube-2-minus-17")),
        "{names:?}"
    );
    assert!(
        names.iter().any(|n| n.ends_with("huge-cube-2-17")),
        "{names:?}"
    );
}

/// The export's README names the length of its longest number, as its files hold it (a C
/// program reading `%63s` cut the subnormal family's and failed it for no bug of its own).
#[test]
fn the_exported_readme_names_the_longest_number() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("suite");
    let o = raylab(&["suite", "export", target.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let mut longest = 0;
    for family in std::fs::read_dir(&target).unwrap().flatten() {
        for file in ["scene.txt", "rays.txt"].map(|f| family.path().join(f)) {
            let Ok(text) = std::fs::read_to_string(file) else {
                continue;
            };
            let numbers = text.lines().filter(|l| !l.starts_with('#'));
            let most = numbers.flat_map(str::split_whitespace).map(str::len).max();
            longest = longest.max(most.unwrap_or(0));
        }
    }
    assert!(longest > 63, "{longest}");
    let readme = std::fs::read_to_string(target.join("README.md")).unwrap();
    let said = format!("The longest is {longest} characters");
    assert!(readme.contains(&said), "{said}: {readme}");
    let manual = Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md");
    let manual = std::fs::read_to_string(manual)
        .unwrap()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        manual.contains(&format!("up to {longest} characters")),
        "the README's figure"
    );
}

/// An earlier export is written over; a directory holding anything else is refused and left
/// as it was.
#[test]
fn export_writes_over_an_earlier_export_only() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("suite");
    let target_s = target.to_str().unwrap();
    let o = raylab(&["suite", "export", target_s]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains(&format!("wrote {} families", suite::all().len())));
    let o = raylab(&["suite", "export", target_s]);
    assert!(o.status.success(), "again: {}", text(&o.stderr));
    // A directory whose parent is missing (a mistyped path) is refused, and nothing made.
    let stray = dir.path().join("no-such/suite");
    let o = raylab(&["suite", "export", stray.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let said = format!("{}: No such file or directory", stray.display());
    assert!(text(&o.stderr).contains(&said), "{}", text(&o.stderr));
    assert!(!dir.path().join("no-such").exists());

    let other = dir.path().join("notes");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("lab.cpp"), "int main() {}\n").unwrap();
    let o = raylab(&["suite", "export", other.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("is not an exported suite"),
        "{}",
        text(&o.stderr)
    );
    let left: Vec<_> = std::fs::read_dir(&other).unwrap().collect();
    assert_eq!(left.len(), 1, "nothing written beside lab.cpp");
    assert_eq!(
        std::fs::read_to_string(other.join("lab.cpp")).unwrap(),
        "int main() {}\n"
    );
}

/// raylab's own `trace` as the program passes every family in f32 and f64; Möller–Trumbore
/// (no watertightness) leaks, and the run says so by its status.
#[test]
fn trace_as_the_program_passes_the_suite_and_moller_leaks() {
    let dir = tempfile::tempdir().unwrap();
    let suite_dir = dir.path().join("suite");
    export::export(&suite_dir, &suite::all()).unwrap();
    let suite_s = suite_dir.to_str().unwrap();
    let exe = env!("CARGO_BIN_EXE_raylab");
    let rays: usize = suite::all().iter().map(|f| f.rays.len()).sum();
    for precision in ["f32", "f64"] {
        let program =
            format!("'{exe}' trace --precision {precision} --scene {{scene}} --rays {{rays}}");
        let o = raylab(&[
            "check",
            "--suite",
            suite_s,
            "--program",
            &program,
            "--precision",
            precision,
        ]);
        let out = text(&o.stdout);
        assert_eq!(o.status.code(), Some(0), "{out}{}", text(&o.stderr));
        let line = last_line(&o);
        assert_eq!(count(&line, "rays"), rays, "{line}");
        assert_eq!(count(&line, "right") + count(&line, "ties"), rays, "{line}");
        assert_eq!(count(&line, "t_failures"), 0, "{line}");
        assert_eq!(
            out.lines()
                .filter(|l| l.contains("-cube-from-inside "))
                .count(),
            1,
            "{out}"
        );
    }
    let program = format!("'{exe}' trace --method moller --scene {{scene}} --rays {{rays}}");
    let o = raylab(&["check", "--suite", suite_s, "--program", &program]);
    let line = last_line(&o);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stdout));
    assert!(
        count(&line, "leaks") > 0 && count(&line, "wrong") > 0,
        "{line}"
    );
}

/// A number written by `exact_decimal` is the value itself: as an exact rational, and read
/// back in f32 and f64 (signed zero, subnormals and the extremes included).
#[test]
fn numbers_are_written_exactly() {
    use num_rational::BigRational;
    use raylab::math::real::exact_decimal;
    let mut rng = common::Rng(11);
    let mut values = vec![
        0.0f32,
        -0.0,
        0.1,
        -2.5,
        1.0,
        f32::MIN_POSITIVE,
        1e-45,
        2f32.powi(-130),
        f32::MAX,
        -f32::MAX,
        3.0e7,
    ];
    values.extend(
        (0..2000)
            .map(|_| f32::from_bits(rng.next_u64() as u32))
            .filter(|x| x.is_finite()),
    );
    for x in values {
        let s = exact_decimal(x as f64);
        assert_eq!(
            s.parse::<f32>().unwrap().to_bits(),
            x.to_bits(),
            "{x:e} written {s}"
        );
        assert_eq!(
            s.parse::<f64>().unwrap().to_bits(),
            (x as f64).to_bits(),
            "{s}"
        );
        assert!(!s.contains('e') && s.len() <= 160, "{s}");
        // As a rational: the digits over a power of ten.
        let (digits, places) = match s.trim_start_matches('-').split_once('.') {
            Some((whole, frac)) => (format!("{whole}{frac}"), frac.len()),
            None => (s.trim_start_matches('-').to_string(), 0),
        };
        let ten = num_bigint::BigInt::from(10);
        let value = BigRational::new(digits.parse().unwrap(), ten.pow(places as u32));
        assert_eq!(value, BigRational::from_float(x.abs()).unwrap(), "{s}");
    }
    assert_eq!(
        exact_decimal(0.1f32 as f64),
        "0.100000001490116119384765625"
    );
    assert_eq!(exact_decimal(-0.0), "-0");
    assert_eq!(exact_decimal(f64::INFINITY), "inf");
}

/// `{scene}` and `{rays}` go in absolute: a program that changes directory first, given a
/// suite or files by relative paths, still finds them (as `grade` runs it).
#[test]
fn a_program_that_changes_directory_still_finds_its_files() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.txt"), "tri -1 -1 2 1 -1 2 0 1 2\n").unwrap();
    std::fs::write(
        dir.path().join("rays.txt"),
        "# o d tmin tmax\n0 0 0 0 0 1 0 inf\n",
    )
    .unwrap();
    let program = "cd / && test -f {scene} && test -f {rays} && echo 'hit 2 0'";
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args([
            "check",
            "--scene",
            "scene.txt",
            "--rays",
            "rays.txt",
            "--program",
            program,
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_passes(&o);
}

/// The README's Python program answers rays whose tmin is `-inf`, as the README allows and
/// `raylab trace` answers them.
#[test]
fn the_readme_python_program_reads_an_open_tmin() {
    if !common::tool_for(
        "python3",
        "python3",
        "the_readme_python_program_reads_an_open_tmin",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = (dir.path().join("scene.txt"), dir.path().join("rays.txt"));
    std::fs::write(&scene, "tri -1 -1 2 1 -1 2 0 1 2\nsphere 0 0 0 1\n").unwrap();
    let lines = "# o d tmin tmax\n0 0 0 0 0 1 -inf inf\n0 0 5 0 0 1 -inf 1\n0 0 5 0 0 1 -inf -7\n";
    std::fs::write(&rays, lines).unwrap();
    let (scene, rays) = (scene.to_str().unwrap(), rays.to_str().unwrap());
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/check/exact.py");
    let program = format!("python3 '{}' {{scene}} {{rays}}", script.display());
    let o = check_program(scene, rays, &program, &["--precision", "f64"]);
    assert_passes(&o);
    assert_eq!(count(&last_line(&o), "right"), 3, "{}", text(&o.stdout));
}

/// The README's Python program reads each number rounded to the precision graded in, as
/// raylab does: a ray 0.1 long in a file of one's own (not an f32 or f64 value) read as exactly
/// 1/10 missed the triangle at t = 0.1 that raylab's rounded tmax lets the ray reach.
#[test]
fn the_readme_python_program_reads_numbers_as_raylab_does() {
    if !common::tool_for(
        "python3",
        "python3",
        "the_readme_python_program_reads_numbers_as_raylab_does",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = (dir.path().join("scene.txt"), dir.path().join("rays.txt"));
    std::fs::write(
        &scene,
        "tri -1 -1 1 1 -1 1 0 1 1
sphere 0.1 0 5 0.3
",
    )
    .unwrap();
    let lines = "0 0 0 0 0 10 0 0.1
0 0 0 0 0 10 0.1 inf
0.1 0.2 0 0 0 1 1.5 inf
";
    std::fs::write(&rays, lines).unwrap();
    let (scene, rays) = (scene.to_str().unwrap(), rays.to_str().unwrap());
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/check/exact.py");
    for precision in ["f32", "f64"] {
        let program = format!(
            "python3 '{}' {{scene}} {{rays}} {precision}",
            script.display()
        );
        let o = check_program(scene, rays, &program, &["--precision", precision]);
        assert_passes(&o);
        assert_eq!(count(&last_line(&o), "right"), 3, "{}", text(&o.stdout));
    }
}

/// The README's Python program (examples/check/exact.py), in exact rationals, passes every
/// family in f32 and f64.
#[test]
fn the_readme_python_program_passes_every_family() {
    if !common::tool_for(
        "python3",
        "python3",
        "the_readme_python_program_passes_every_family",
    ) {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    assert!(
        readme.contains("examples/check/exact.py"),
        "README names the program"
    );
    let dir = tempfile::tempdir().unwrap();
    let suite_dir = dir.path().join("suite");
    export::export(&suite_dir, &suite::all()).unwrap();
    let rays: usize = suite::all().iter().map(|f| f.rays.len()).sum();
    // The program runs once per family; its answers are graded in both precisions.
    let script = root.join("examples/check/exact.py");
    // The families on every core (one Python process each).
    let families: Vec<_> = (std::fs::read_dir(&suite_dir).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|family| family.is_dir())
        .collect();
    let graded_one = |family: &std::path::PathBuf| {
        let mut graded = [0usize; 2];
        let (scene, rays) = (family.join("scene.txt"), family.join("rays.txt"));
        let out = std::process::Command::new("python3")
            .arg(&script)
            .arg(&scene)
            .arg(&rays)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}: {}",
            family.display(),
            text(&out.stderr)
        );
        let answers = family.join("answers.txt");
        std::fs::write(&answers, &out.stdout).unwrap();
        for (k, precision) in ["f32", "f64"].into_iter().enumerate() {
            let (scene, rays) = (scene.to_str().unwrap(), rays.to_str().unwrap());
            let o = check_answers(scene, rays, &answers, &["--precision", precision]);
            let line = last_line(&o);
            assert_eq!(
                o.status.code(),
                Some(0),
                "{} {precision}: {}",
                family.display(),
                text(&o.stdout)
            );
            graded[k] += count(&line, "right") + count(&line, "ties");
        }
        graded
    };
    let graded =
        (families.par_iter().map(graded_one)).reduce(|| [0; 2], |a, b| [a[0] + b[0], a[1] + b[1]]);
    assert_eq!(graded, [rays; 2], "every ray of every family graded right");
}

/// `--show N` prints N reproducers under each heading of a failing family (3 without it), each
/// a ray of the family; 0 prints none and no heading, the table and counts as before.
#[test]
fn show_sets_how_many_reproducers_a_failing_family_prints() {
    let dir = tempfile::tempdir().unwrap();
    let suite_dir = dir.path().join("suite");
    export::export(&suite_dir, &suite::all()).unwrap();
    let exe = env!("CARGO_BIN_EXE_raylab");
    // Möller–Trumbore in f32 gets the cube from inside wrong on more than 7 rays.
    let moller = format!("'{exe}' trace --method moller --scene {{scene}} --rays {{rays}}");
    let check = |show: &[&str]| {
        let suite_s = suite_dir.to_str().unwrap();
        let args = [&["check", "--suite", suite_s, "--family", "1"], show].concat();
        let o = raylab(&[&args[..], &["--program", &moller]].concat());
        assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
        let out = text(&o.stdout);
        let shown = out.lines().filter(|l| l.contains("rays.txt:")).count();
        (shown, out.contains("the first of the"), last_line(&o), out)
    };
    let (three, seven, none) = (check(&[]), check(&["--show", "7"]), check(&["--show", "0"]));
    assert_eq!((three.0, three.1), (3, true));
    assert_eq!((seven.0, seven.1), (7, true));
    assert_eq!((none.0, none.1), (0, false));
    assert!(
        three.2.contains(" wrong ") && three.2 == none.2,
        "{} vs {}",
        three.2,
        none.2
    );
    // Under the rays shown, the commands that check the first of them alone: run from
    // another directory, they grade that one ray as the family's run did.
    let alone = |out: &str| {
        let prefix = "    the first ray above, alone: ";
        (out.lines().find_map(|l| l.strip_prefix(prefix))).map(str::to_owned)
    };
    assert_eq!(alone(&none.3), None, "{}", none.3);
    let command = alone(&three.3).unwrap_or_else(|| panic!("{}", three.3));
    assert!(command.starts_with("sed -n "), "{command}");
    let command = command.replace("&& raylab check", &format!("&& '{exe}' check"));
    let elsewhere = tempfile::tempdir().unwrap();
    let o = std::process::Command::new("sh")
        .args(["-c", &command])
        .current_dir(elsewhere.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{command}\n{}", text(&o.stderr));
    assert!(
        last_line(&o).starts_with("check: rays 1 right 0 "),
        "{}",
        text(&o.stdout)
    );
    let head = text(&o.stdout)
        .lines()
        .next()
        .unwrap_or_default()
        .to_owned();
    assert!(head.contains(" (1 ray), "), "{head}");
    // (The ray, its exact answer, the answer given and the hint, after where each was read.)
    let shown = |out: &str| {
        let line = out
            .lines()
            .find(|l| l.contains(".txt:"))
            .unwrap()
            .to_owned();
        let (ray, rest) = line.split_once("exact: ").unwrap();
        let ray = ray.split_once("): ").unwrap().1.to_owned();
        let (exact, given) = rest.split_once("given (its output:").unwrap();
        (
            ray,
            exact.to_owned(),
            given.split_once("): ").unwrap().1.to_owned(),
        )
    };
    assert_eq!(shown(&text(&o.stdout)), shown(&three.3));
    let o = raylab(&["check", "--suite", "x", "--program", "p", "--show", "many"]);
    assert_fails(&o, 2, &["--show", "'many'"]);
}

/// `--family` checks one family, by name or number; under a failing family its first rays
/// are printed as reproducers whose line numbers match the exported files; a family whose
/// rays.txt is missing, or whose scene.txt is not a regular file, is named, never skipped.
#[test]
fn suite_families_one_at_a_time_with_reproducers_and_none_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let suite_dir = dir.path().join("suite");
    export::export(&suite_dir, &suite::all()).unwrap();
    let suite_s = suite_dir.to_str().unwrap();
    let exe = env!("CARGO_BIN_EXE_raylab");
    let moller = format!("'{exe}' trace --method moller --scene {{scene}} --rays {{rays}}");
    let o = raylab(&[
        "check",
        "--suite",
        suite_s,
        "--family",
        "1",
        "--program",
        &moller,
    ]);
    let out = text(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}{}", text(&o.stderr));
    assert!(out.contains("(1 family)"), "{out}");
    // The reproducer's line is that ray's line in the exported file.
    let repro = out
        .lines()
        .find(|l| l.contains("01-cube-from-inside/rays.txt:"))
        .unwrap_or_else(|| panic!("a reproducer in {out}"));
    let at = repro.split("rays.txt:").nth(1).unwrap();
    let line_no: usize = at.split(' ').next().unwrap().parse().unwrap();
    let ray_no: usize = at
        .split("(ray ")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(line_no, ray_no + 1, "{repro}");
    let file = std::fs::read_to_string(suite_dir.join("01-cube-from-inside/rays.txt")).unwrap();
    let ray_text = file.lines().nth(line_no - 1).unwrap();
    assert!(
        repro.contains(&format!("): {ray_text}  exact: ")),
        "{repro} vs {ray_text}"
    );

    let trace = format!("'{exe}' trace --scene {{scene}} --rays {{rays}}");
    let name = "34-directions-not-of-unit-length";
    let o = raylab(&[
        "check",
        "--suite",
        suite_s,
        "--family",
        name,
        "--program",
        &trace,
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stdout));
    let o = raylab(&[
        "check",
        "--suite",
        suite_s,
        "--family",
        "99-none",
        "--program",
        &trace,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("no family '99-none'"),
        "{}",
        text(&o.stderr)
    );
    // A family's directory given as the suite: how to check it instead.
    let family = suite_dir.join(name);
    let o = raylab(&[
        "check",
        "--suite",
        family.to_str().unwrap(),
        "--program",
        &trace,
    ]);
    assert_eq!(o.status.code(), Some(2));
    let hint = format!("a family, not a suite; check it with `--suite {suite_s} --family {name}`");
    assert!(text(&o.stderr).contains(&hint), "{}", text(&o.stderr));

    std::fs::remove_file(suite_dir.join("02-cube-from-outside/rays.txt")).unwrap();
    let o = raylab(&["check", "--suite", suite_s, "--program", &trace]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stdout));
    assert!(
        text(&o.stderr)
            .contains("02-cube-from-outside/rays.txt: a family of the suite without its rays.txt"),
        "{}",
        text(&o.stderr)
    );
    std::fs::write(suite_dir.join("02-cube-from-outside/rays.txt"), "").unwrap();
    let scene = suite_dir.join("03-icosphere-from-inside/scene.txt");
    std::fs::remove_file(&scene).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &scene).unwrap();
    let o = raylab(&["check", "--suite", suite_s, "--program", &trace]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("without its scene.txt (not a regular file)"),
        "{}",
        text(&o.stderr)
    );
}

/// Every family says which classic bug it catches, and the exported README's table says it.
#[test]
fn every_family_says_which_classic_bug_it_catches() {
    let families = suite::all();
    let readme = export::readme(&families);
    for f in &families {
        assert!(!f.catches.is_empty(), "{}", f.name);
        assert!(readme.contains(&export::cell(&f.catches)), "{}", f.name);
    }
}

/// An export cut short (families gone, or a family's rays): `check --suite` and `grade
/// --suite` name what the manifest lists and is not there, and fail; `--family` grades an
/// intact family; a suite without a manifest (made by hand) is graded as it is, with a
/// warning that says so.
#[test]
fn a_cut_short_export_is_named_and_failed_and_a_suite_without_manifest_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let suite_dir = dir.path().join("suite");
    let suite_s = suite_dir.to_str().unwrap();
    let o = raylab(&["suite", "export", suite_s]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let manifest = std::fs::read_to_string(suite_dir.join(export::MANIFEST)).unwrap();
    let mut families: Vec<String> = std::fs::read_dir(&suite_dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_dir())
        .map(|e| e.file_name().into_string().unwrap())
        .collect();
    families.sort();
    let listed = export::read_manifest(&manifest).unwrap();
    assert_eq!(listed.len(), suite::all().len());
    for ((name, rays), family) in listed.iter().zip(suite::all()) {
        assert!(families.contains(name), "{name}");
        assert_eq!(*rays, family.rays.len(), "{name}");
    }
    let exe = env!("CARGO_BIN_EXE_raylab");
    let program = format!("'{exe}' trace --scene {{scene}} --rays {{rays}}");
    let class = dir.path().join("class");
    std::fs::create_dir_all(class.join("ada")).unwrap();
    let class_s = class.to_str().unwrap();
    // All but two families gone.
    for name in &families[2..] {
        std::fs::remove_dir_all(suite_dir.join(name)).unwrap();
    }
    let check = ["check", "--suite", suite_s, "--program", &program];
    let grade = ["grade", class_s, "--suite", suite_s, "--program", &program];
    for args in [&check[..], &grade[..]] {
        let o = raylab(args);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        for name in [&families[2], families.last().unwrap()] {
            assert!(err.contains(&format!("{name} is missing")), "{err}");
        }
        assert!(err.contains("families.txt"), "{err}");
        assert!(
            !err.contains(&format!("{} is missing", families[1])),
            "{err}"
        );
    }
    // One family's last ray gone: that family fails, the one beside it is graded.
    let rays = suite_dir.join(&families[1]).join("rays.txt");
    let text_of = std::fs::read_to_string(&rays).unwrap();
    let kept = text_of.lines().count() - 1;
    let cut: String = text_of
        .lines()
        .take(kept)
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&rays, cut).unwrap();
    let o = raylab(&[&check[..], &["--family", "2"]].concat());
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    let count_of = listed[1].1;
    let said = format!("{} has {} rays, not {count_of}", families[1], count_of - 1);
    assert!(err.contains(&said), "{err}");
    let o = raylab(&[&check[..], &["--family", "1"]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(text(&o.stderr), "");
    // A manifest line that is not NAME COUNT: the file and its line, as every file's error.
    let bad = format!("# families\n{} x\n", families[0]);
    std::fs::write(suite_dir.join(export::MANIFEST), bad).unwrap();
    let o = raylab(&check);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("families.txt:2: 'x' is not a number of rays"),
        "{err}"
    );
    // An empty manifest: the family directories it does not list are graded, and named.
    std::fs::write(suite_dir.join(export::MANIFEST), "# families\n").unwrap();
    let o = raylab(&[&check[..], &["--family", "1"]].concat());
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let said = format!(
        "1 family directory not listed in its families.txt, graded as found: {}",
        families[0]
    );
    assert!(err.contains(&said), "{err}");
    // No manifest: what is there is graded, and that it may be cut short is said.
    std::fs::remove_file(suite_dir.join(export::MANIFEST)).unwrap();
    for args in [&check[..], &grade[..]] {
        let o = raylab(args);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
        assert!(
            err.contains("no families.txt") && err.contains("cut short"),
            "{err}"
        );
        assert!(
            err.contains("grading what it holds (2 family directories)"),
            "{err}"
        );
    }
}
