//! How `raylab check` grades: every kind of answer, bad answers refused by line, a program
//! that fails never a pass, a correct program never failed, the t tolerance, and `--image`, which paints a program's answers and refuses up front what it
//! cannot do.

use crate::common;

use common::binary::{count, last_line, text};
use raylab::check::{export, suite};
use std::path::Path;

crate::raylab_runner!();
crate::check_runner!();

/// A scene with a plane, its exact copy (exact ties), a plane behind and a sphere; one ray
/// per kind of answer.
fn graded_case(dir: &Path) -> (String, String) {
    let scene = dir.join("scene.txt");
    std::fs::write(
        &scene,
        "tri -1 -1 2 1 -1 2 0 1 2\ntri -1 -1 2 1 -1 2 0 1 2\ntri -1 -1 5 1 -1 5 0 1 5\nsphere 5 0 4 1\n",
    )
    .unwrap();
    let rays = dir.join("rays.txt");
    let ahead = "0 0 0 0 0 1 0 inf\n";
    let lines = [
        ahead,                 // hit 2 0
        ahead,                 // hit 2 0
        ahead,                 // hit 2 0
        ahead,                 // hit 2 0
        "0 0 0 0 1 0 0 inf\n", // miss
        ahead,                 // hit 2 0
        ahead,                 // hit 2 0
        ahead,                 // hit 2 0
        "0 0 0 0 0 1 3 inf\n", // hit 5 2 (tmin 3)
        "5 0 0 0 0 1 0 inf\n", // hit 3 3 (the sphere)
    ];
    std::fs::write(&rays, format!("# a comment\n{}", lines.concat())).unwrap();
    (scene.display().to_string(), rays.display().to_string())
}

/// The answers: right, tie, leak, wrong (a primitive behind), false hit, t 1 ulp off (f32),
/// 5e-6 off, 5e-7 off, wrong (a primitive outside tmin..tmax), right on the sphere.
const GRADED_ANSWERS: &str = "hit 2 0\nhit 2 1\nmiss\nhit 5 2\nhit 1 3\nhit 2.0000002 0\nhit 2.00001 0\nhit 2.000001 0\nhit 2 0\nhit 3 3\n";

#[test]
fn check_grades_every_kind_of_answer() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = graded_case(dir.path());
    let answers = dir.path().join("answers.txt");
    std::fs::write(&answers, GRADED_ANSWERS).unwrap();
    for (precision, within_ulp, within_micro) in [("f32", 4, 1), ("f64", 3, 2)] {
        let o = check_answers(&scene, &rays, &answers, &["--precision", precision]);
        let out = text(&o.stdout);
        assert_eq!(o.status.code(), Some(1), "{out}{}", text(&o.stderr));
        assert_eq!(
            last_line(&o),
            "check: rays 10 right 5 leaks 1 false_hits 1 wrong 2 ties 1 t_failures 1",
            "{precision}: {out}"
        );
        let t_line =
            format!("{within_ulp} within 1 ulp, {within_micro} within the tolerance, 1 beyond");
        assert!(out.contains(&t_line), "{precision}: '{t_line}' in {out}");
        // Reproducers: each wrong ray by its line in the ray file (the comment is line 1) and
        // its number among the rays (the line of its answer). (The leak's plane is met from
        // its back, as the answers right met it: no culling is hinted.)
        assert!(
            out.contains("rays.txt:4 (ray 3): 0 0 0 0 0 1 0 inf  exact: hit 2 0  given (")
                && out.contains(":3): miss  [leak]"),
            "{out}"
        );
        assert!(
            out.contains("rays.txt:6 (ray 5): 0 0 0 0 1 0 0 inf  exact: miss")
                && out.contains(
                    "[false hit: the ray misses sphere 3 (its discriminant is below 0): no hit]"
                ),
            "{out}"
        );
        assert!(
            out.contains("rays.txt:10 (ray 9): 0 0 0 0 0 1 3 inf  exact: hit 5 2")
                && out.contains(":9): hit 2 0  [wrong primitive: t 2 is not above tmin 3")
                && out.contains(":4): hit 5 2  [wrong primitive: the given t 5 is past the exact"),
            "{out}"
        );
        assert!(
            out.contains("[t failure: o + t·d off by 2.50e-6 of |o| + |t·d| + extent]"),
            "{out}"
        );
    }
    // The right answers everywhere pass, ties included.
    let right =
        "hit 2 0\nhit 2 1\nhit 2 0\nhit 2 0\nmiss\nhit 2 0\nhit 2 0\nhit 2 0\nhit 5 2\nhit 3 3\n";
    let answers = dir.path().join("right.txt");
    std::fs::write(&answers, right).unwrap();
    let o = check_answers(&scene, &rays, &answers, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stdout));
    assert_eq!(
        last_line(&o),
        "check: rays 10 right 9 leaks 0 false_hits 0 wrong 0 ties 1 t_failures 0"
    );
}

/// `--image` paints the program's answers as the flat step in grey: raylab's own answers give
/// the headless flat render's grey (its luminance) at every pixel; Möller–Trumbore's are
/// marked magenta exactly where it lets a ray through, the pixels the cracks view marks.
#[test]
fn the_image_marks_exactly_where_the_program_leaks() {
    let dir = tempfile::tempdir().unwrap();
    let exe = env!("CARGO_BIN_EXE_raylab");
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let size = ["--width", "320", "--height", "240"];
    let trace = format!("'{exe}' trace --scene {{scene}} --rays {{rays}}");
    let o = raylab(
        &[
            &["check", "--image", &path("own.png"), "--program", &trace][..],
            &size,
        ]
        .concat(),
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        text(&o.stdout),
        text(&o.stderr)
    );
    assert_eq!(
        last_line(&o),
        "check: rays 76800 right 76800 leaks 0 false_hits 0 wrong 0 ties 0 t_failures 0"
    );
    let o = raylab(
        &[
            &["render", "--step", "flat", "-o", &path("flat.png")][..],
            &size,
        ]
        .concat(),
    );
    assert!(o.status.success());
    let own = common::read_png(Path::new(&path("own.png")));
    let flat = common::read_png(Path::new(&path("flat.png")));
    assert_eq!((own.0, own.1), (flat.0, flat.1));
    let linear = |c: u8| {
        let c = c as f64 / 255.0;
        match c <= 0.04045 {
            true => c / 12.92,
            false => ((c + 0.055) / 1.055).powf(2.4),
        }
    };
    let srgb = |y: f64| match y <= 0.0031308 {
        true => 12.92 * y * 255.0,
        false => (1.055 * y.powf(1.0 / 2.4) - 0.055) * 255.0,
    };
    let mut greys = std::collections::BTreeSet::new();
    for (o, f) in own.2.chunks(4).zip(flat.2.chunks(4)) {
        let y = 0.2126 * linear(f[0]) + 0.7152 * linear(f[1]) + 0.0722 * linear(f[2]);
        assert!(o[0] == o[1] && o[1] == o[2], "not grey: {o:?} for {f:?}");
        assert!((o[0] as f64 - srgb(y)).abs() < 2.0, "{o:?} for {f:?}");
        greys.insert(o[0]);
    }
    // (The box's walls, floor and blocks in more than a few greys.)
    assert!(greys.len() >= 5, "{greys:?}");

    let moller = format!("'{exe}' trace --method moller --scene {{scene}} --rays {{rays}}");
    let o = raylab(
        &[
            &[
                "check",
                "--image",
                &path("moller.png"),
                "--program",
                &moller,
            ][..],
            &size,
        ]
        .concat(),
    );
    let line = last_line(&o);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stdout));
    let args = [
        "render",
        "--step",
        "flat",
        "--method",
        "moller",
        "--cracks",
        "-o",
        &path("cracks.png"),
    ];
    assert!(raylab(&[&args[..], &size].concat()).status.success());
    let marked = |file: &str, colour: [u8; 3]| -> Vec<usize> {
        let (_, _, px) = common::read_png(Path::new(&path(file)));
        px.chunks(4)
            .enumerate()
            .filter(|(_, p)| p[..3] == colour)
            .map(|(i, _)| i)
            .collect()
    };
    let magenta = marked("moller.png", [255, 0, 255]);
    assert!(
        !magenta.is_empty(),
        "Möller–Trumbore leaks on the Cornell box's diagonals: {line}"
    );
    assert_eq!(magenta.len(), count(&line, "leaks"), "{line}");
    let yellow = marked("moller.png", [255, 255, 0]);
    assert_eq!(yellow.len(), count(&line, "false_hits"), "{line}");
    let mut through = [magenta, yellow].concat();
    through.sort();
    assert_eq!(
        through,
        marked("cracks.png", [255, 0, 255]),
        "the pixels the cracks view marks"
    );
    assert_eq!(
        marked("moller.png", [0, 255, 255]).len(),
        count(&line, "wrong"),
        "{line}"
    );
}

/// A correct program is never failed: a hit behind the origin in a scene large enough for a
/// hierarchy (whose walk once skipped a flat box at tmin < t < 0, so `check` expected a miss),
/// and a t that overflows f32 (`inf`, what `raylab trace` prints, is right where the exact t
/// rounds to infinity).
#[test]
fn a_correct_program_is_never_failed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.txt");
    let mut text_of_scene = String::from("tri -3 -3 0 3 -3 0 0 3 0\ntri -3 -3 1 3 -3 1 0 3 1\n");
    for k in 0..64 {
        let x = 100 + k;
        text_of_scene += &format!("tri {x} 0 50 {x}.5 0 50 {x} 0.5 50.5\n");
    }
    std::fs::write(&scene, text_of_scene).unwrap();
    let rays = dir.path().join("rays.txt");
    std::fs::write(
        &rays,
        "# ox oy oz dx dy dz tmin tmax\n0 0 -0.5 0 0 -1 -1 inf\n0 0 0 0 0 1e-45 0 inf\n0 0 -0.5 0 0 1 -1 1\n",
    )
    .unwrap();
    let answers = dir.path().join("answers.txt");
    let (scene_s, rays_s) = (scene.to_str().unwrap(), rays.to_str().unwrap());
    for (precision, given) in [
        ("f32", "hit -0.5 0\nhit inf 1\nhit 0.5 0\n"),
        ("f64", "hit -0.5 0\nhit 1e45 1\nhit 0.5 0\n"),
    ] {
        std::fs::write(&answers, given).unwrap();
        let o = check_answers(scene_s, rays_s, &answers, &["--precision", precision]);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{precision}: {}{}",
            text(&o.stdout),
            text(&o.stderr)
        );
        assert_eq!(count(&last_line(&o), "right"), 3, "{}", text(&o.stdout));
        // raylab's own answers, as trace prints them, are graded right too.
        let traced = raylab(&[
            "trace",
            "--precision",
            precision,
            "--scene",
            scene_s,
            "--rays",
            rays_s,
        ]);
        assert!(traced.status.success());
        std::fs::write(&answers, &traced.stdout).unwrap();
        let o = check_answers(scene_s, rays_s, &answers, &["--precision", precision]);
        assert_eq!(o.status.code(), Some(0), "{precision}: {}", text(&o.stdout));
        // A comment in Latin-1 ("résultats") before them, in the file and from a program.
        let mut latin1 = b"# r\xe9sultats\n".to_vec();
        latin1.extend_from_slice(&traced.stdout);
        std::fs::write(&answers, &latin1).unwrap();
        let o = check_answers(scene_s, rays_s, &answers, &["--precision", precision]);
        assert_eq!(o.status.code(), Some(0), "{precision}: {}", text(&o.stdout));
        let program = format!("cat '{}' # {{scene}} {{rays}}", answers.display());
        let o = check_program(scene_s, rays_s, &program, &["--precision", precision]);
        assert_eq!(o.status.code(), Some(0), "{precision}: {}", text(&o.stdout));
    }
    // `inf` where the exact t is finite, and a finite t where it is inf, are t failures.
    std::fs::write(&answers, "hit -0.5 0\nhit 3.4e38 1\nhit inf 0\n").unwrap();
    let o = check_answers(scene_s, rays_s, &answers, &[]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        count(&last_line(&o), "t_failures"),
        2,
        "{}",
        text(&o.stdout)
    );
}

/// A t beyond the tolerance fails the run (t in the wrong units can never pass); the tolerance
/// is printed and set by --t-tolerance.
#[test]
fn a_t_beyond_the_tolerance_fails_and_the_tolerance_is_settable() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = graded_case(dir.path());
    let answers = dir.path().join("answers.txt");
    // Every answer right, one t 5e-6 off (ray 7, from the origin, on a triangle whose largest
    // coordinate is 2: 1e-5 / (0 + 2 + 2) = 2.5e-6 relative).
    let given = "hit 2 0\nhit 2 1\nhit 2 0\nhit 2 0\nmiss\nhit 2 0\nhit 2.00001 0\nhit 2 0\nhit 5 2\nhit 3 3\n";
    std::fs::write(&answers, given).unwrap();
    let o = check_answers(&scene, &rays, &answers, &[]);
    let out = text(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    assert!(out.contains("t tolerance 1e-6"), "{out}");
    assert!(
        out.contains("rays.txt:8 (ray 7): 0 0 0 0 0 1 0 inf  exact: hit 2 0")
            && out.contains("[t failure: o + t·d off by 2.50e-6 of |o| + |t·d| + extent]"),
        "{out}"
    );
    let o = check_answers(&scene, &rays, &answers, &["--t-tolerance", "1e-5"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stdout));
    // A t of the other sign, far off in f64, is a t failure (its distance in ulps once
    // overflowed and the grader crashed).
    let sphere = dir.path().join("sphere.txt");
    std::fs::write(&sphere, "sphere 0 0 0 4\n").unwrap();
    let ray = dir.path().join("ray.txt");
    std::fs::write(&ray, "# ox oy oz dx dy dz tmin tmax\n0 0 0 0 0 1 0 inf\n").unwrap();
    let behind = dir.path().join("behind.txt");
    std::fs::write(&behind, "hit -4 0\n").unwrap();
    let (sphere, ray) = (sphere.to_str().unwrap(), ray.to_str().unwrap());
    for precision in ["f32", "f64"] {
        let o = check_answers(sphere, ray, &behind, &["--precision", precision]);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
        assert_eq!(
            count(&last_line(&o), "t_failures"),
            1,
            "{}",
            text(&o.stdout)
        );
    }
    // A t of nan is a t failure said so, echoed as printed (it read "hit NaN 0 [t failure:
    // o + t·d off by inf ...]").
    let nan = dir.path().join("nan.txt");
    std::fs::write(&nan, "hit nan 0\n").unwrap();
    let o = check_answers(sphere, ray, &nan, &[]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("nan.txt:1): hit nan 0  [t failure: t is not a number]"),
        "{}",
        text(&o.stdout)
    );
    std::fs::write(&nan, "hit -inf 0\n").unwrap();
    let o = check_answers(sphere, ray, &nan, &[]);
    assert!(
        text(&o.stdout)
            .contains("hit -inf 0  [t failure: t is infinite, where the exact t is not]"),
        "{}",
        text(&o.stdout)
    );
    for bad in ["-1", "2", "nan"] {
        let o = check_answers(&scene, &rays, &answers, &["--t-tolerance", bad]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(
            text(&o.stderr).contains("--t-tolerance"),
            "{}",
            text(&o.stderr)
        );
    }
}

/// A t printed with too few digits (C's `%g` gives 6) is a t failure that says so: the exact
/// t to that many digits, and the digits to print in the precision (two t's written so: one
/// is no evidence of how the program prints). A t of as many digits that is not the exact
/// one's rounding is a t failure without it.
#[test]
fn a_t_printed_with_too_few_digits_is_named_so() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.txt");
    // A plane at z = 1.3839071 (its largest coordinate), met at t = z from the origin:
    // 1.38391 is 2.9e-6 off, some 1.04e-6 of 0 + 1.38 + 1.38.
    let z = "1.3839071";
    std::fs::write(&scene, format!("tri -1 -1 {z} 1 -1 {z} 0 1 {z}\n")).unwrap();
    let rays = dir.path().join("rays.txt");
    let ray = "0 0 0 0 0 1 0 inf\n";
    std::fs::write(&rays, format!("# ox oy oz dx dy dz tmin tmax\n{ray}{ray}")).unwrap();
    let answers = dir.path().join("answers.txt");
    let (scene, rays) = (scene.to_str().unwrap(), rays.to_str().unwrap());
    for (precision, digits) in [("f32", 9), ("f64", 17)] {
        std::fs::write(&answers, "hit 1.38391 0\n".repeat(2)).unwrap();
        let o = check_answers(scene, rays, &answers, &["--precision", precision]);
        let out = text(&o.stdout);
        assert_eq!(o.status.code(), Some(1), "{precision}: {out}");
        let hint = format!(
            "e-6 of |o| + |t·d| + extent; t is the exact one to 6 significant digits: \
             print {digits} (%.{digits}g)]"
        );
        assert!(out.contains(&hint), "{precision}: '{hint}' in {out}");
        std::fs::write(&answers, "hit 1.38392 0\n".repeat(2)).unwrap();
        let o = check_answers(scene, rays, &answers, &["--precision", precision]);
        let out = text(&o.stdout);
        assert_eq!(count(&last_line(&o), "t_failures"), 2, "{precision}: {out}");
        assert!(!out.contains("significant digits"), "{precision}: {out}");
        std::fs::write(&answers, "hit 1.3839071 0\n".repeat(2)).unwrap();
        let o = check_answers(scene, rays, &answers, &["--precision", precision]);
        assert_eq!(o.status.code(), Some(0), "{precision}: {}", text(&o.stdout));
    }
}

/// `check --image` says what it cannot do before the program runs: an image in a directory
/// that does not exist, an image that is the program's own script, an image larger than it
/// grades; the program never ran (its mark file is absent) and the script is intact.
#[test]
fn check_image_refuses_up_front_what_it_cannot_do() {
    let dir = tempfile::tempdir().unwrap();
    let mark = dir.path().join("ran");
    let script = dir.path().join("my_lab.sh");
    let body = format!("touch '{}'\n", mark.display());
    std::fs::write(&script, &body).unwrap();
    let program = format!("sh '{}' {{scene}} {{rays}}", script.display());
    let missing = dir.path().join("no/such/dir/out.png");
    for (image, more, message) in [
        (missing.to_str().unwrap(), &[][..], "no/such/dir/out.png"),
        (script.to_str().unwrap(), &[][..], "which --program runs"),
        (
            dir.path().join("big.png").to_str().unwrap(),
            &["--width", "2048", "--height", "1024"][..],
            "at most 1048576",
        ),
    ] {
        let o = raylab(
            &[
                &["check", "--image", image, "--program", &program][..],
                more,
            ]
            .concat(),
        );
        assert_eq!(o.status.code(), Some(2), "{image}: {}", text(&o.stdout));
        assert!(
            text(&o.stderr).contains(message),
            "{image}: {}",
            text(&o.stderr)
        );
        assert!(!mark.exists(), "{image}: the program did not run");
    }
    assert_eq!(std::fs::read_to_string(&script).unwrap(), body);
}

/// An index past the last primitive (a count from 1) is an answer, graded wrong for its ray,
/// which is shown with the index named; every other ray is graded. (The whole file was refused,
/// as a malformed one: no ray, no exact answer, the family's rays left out of the counts.)
#[test]
fn an_index_past_the_last_primitive_is_a_wrong_answer_shown_with_its_ray() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = graded_case(dir.path());
    let lines: Vec<&str> = GRADED_ANSWERS.lines().collect();
    for (index, said) in [
        (
            "4",
            "index 4 is past the last primitive, 3 (indices count from 0)]",
        ),
        ("77", "index 77 is past the last primitive, 3]"),
    ] {
        let mut given = lines.clone();
        let line = format!("hit 2 {index}");
        given[0] = &line;
        let file = dir.path().join("answers.txt");
        std::fs::write(&file, given.join("\n") + "\n").unwrap();
        let o = check_answers(&scene, &rays, &file, &[]);
        let out = text(&o.stdout);
        assert_eq!(o.status.code(), Some(1), "{out}{}", text(&o.stderr));
        let shown = (out.lines()).find(|l| l.contains("answers.txt:1): hit 2"));
        assert!(
            shown.is_some_and(|l| l.ends_with(&format!("[wrong primitive: {said}"))),
            "{out}"
        );
        // The right answer of line 1 became a wrong one; the other nine are graded as before.
        assert_eq!(
            last_line(&o),
            "check: rays 10 right 4 leaks 1 false_hits 1 wrong 3 ties 1 t_failures 1",
            "{out}"
        );
    }
    // An answer is shown as written, not as read (`hit 1e39 0` read `hit inf 0`).
    let file = dir.path().join("answers.txt");
    std::fs::write(
        &file,
        GRADED_ANSWERS.replacen("hit 2 0", " hit  2.000  4 ", 1),
    )
    .unwrap();
    let out = text(&check_answers(&scene, &rays, &file, &[]).stdout);
    assert!(
        out.contains("answers.txt:1): hit  2.000  4  [wrong primitive"),
        "{out}"
    );
    // `-0` is index 0, as `00` is: line 1's right answer stays right.
    let file = dir.path().join("answers.txt");
    std::fs::write(&file, GRADED_ANSWERS.replacen("hit 2 0", "hit 2 -0", 1)).unwrap();
    let o = check_answers(&scene, &rays, &file, &[]);
    assert_eq!(
        last_line(&o),
        "check: rays 10 right 5 leaks 1 false_hits 1 wrong 2 ties 1 t_failures 1",
        "{}",
        text(&o.stderr)
    );
}

/// A malformed answer file, a count that does not match the rays, an index that is no whole
/// number and a program without its placeholders: exit 2, the error naming the file and line,
/// nothing on standard output.
#[test]
fn bad_answers_are_refused_by_line_with_nothing_else_written() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = graded_case(dir.path());
    let lines: Vec<&str> = GRADED_ANSWERS.lines().collect();
    let with_line_3 = |line: &str| {
        let mut l = lines.clone();
        l[2] = line;
        l.join("\n") + "\n"
    };
    for (answers, message) in [
        (
            with_line_3("hit x 0"),
            "answers.txt:3: t 'x' is not a number",
        ),
        // The two forms a right program prints by its language's defaults are named.
        (
            with_line_3("hit 0x1.8p+1 0"),
            "answers.txt:3: t '0x1.8p+1' is hexadecimal (C's %a): print it in decimal",
        ),
        (
            with_line_3("hit 2,50000000 0"),
            "answers.txt:3: t '2,50000000' has a decimal comma, as a locale writes it",
        ),
        (
            with_line_3("hit 2 3.0"),
            "answers.txt:3: '3.0' is not a primitive index, a whole number 0 to 3",
        ),
        (
            with_line_3("hit 2 18446744073709551615"),
            "answers.txt:3: index 18446744073709551615 is past any scene's last primitive \
             (indices up to 4294967295; this scene's last is 3)",
        ),
        (
            with_line_3("hot 2 0"),
            // (A program's debugging line is told where such lines go.)
            "answers.txt:3: expected 'hit <t> <index>' or 'miss', found 'hot 2 0' (other lines \
             go to stderr, or start with #)",
        ),
        (with_line_3("hit 2 0 extra"), "answers.txt:3: expected"),
        (
            lines[..9].join("\n"),
            "answers.txt: 9 answers for the 10 rays of",
        ),
        (
            // UTF-16 as PowerShell writes it, without a byte-order mark.
            GRADED_ANSWERS.chars().flat_map(|c| [c, '\0']).collect(),
            "answers.txt: UTF-16 text (as Windows PowerShell's pipes and `>` write it), not UTF-8",
        ),
        // Control bytes from a NUL on: no answer (they were called UTF-16).
        (
            "\0\u{1}\u{2}\n".into(),
            "answers.txt:1: expected 'hit <t> <index>' or 'miss', found '\\u{0}\\u{1}\\u{2}'",
        ),
    ] {
        let file = dir.path().join("answers.txt");
        std::fs::write(&file, &answers).unwrap();
        let o = check_answers(&scene, &rays, &file, &[]);
        assert_eq!(o.status.code(), Some(2), "{message}: {}", text(&o.stdout));
        assert!(
            text(&o.stderr).contains(message),
            "'{message}' in {}",
            text(&o.stderr)
        );
        assert!(
            o.stdout.is_empty(),
            "nothing else written: {}",
            text(&o.stdout)
        );
    }
    let o = raylab(&[
        "check",
        "--scene",
        &scene,
        "--rays",
        &rays,
        "--program",
        "cat answers.txt",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("must name {scene} and {rays}"),
        "{}",
        text(&o.stderr)
    );
}

/// A program that crashes, hangs (with a child of its own still running), prints garbage,
/// too few lines, endless output or bytes that are not text is reported for its scene, and
/// the run is not a pass.
#[test]
fn a_program_that_fails_is_never_a_pass() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, rays) = graded_case(dir.path());
    let exe = env!("CARGO_BIN_EXE_raylab");
    let trace = format!("'{exe}' trace --scene {{scene}} --rays {{rays}}");
    for (program, message) in [
        (
            "echo oops >&2; exit 3 # {scene} {rays}".to_string(),
            "ended with exit status: 3; its last words: oops",
        ),
        (
            "sleep 30 & sleep 30 # {scene} {rays}".to_string(),
            "ran out of time (0.5 s; --timeout sets another limit); no answer had reached raylab",
        ),
        // How far it came: the ray it stalled on (or a later one, output kept in a buffer).
        (
            format!("{trace} | head -3; sleep 30"),
            "3 answers had reached raylab: the first ray without one is ",
        ),
        (
            format!("{trace} | head -3; sleep 30"),
            "rays.txt:5 (ray 4) (or a later one, where the program keeps output in a buffer)",
        ),
        // How far a crash came: the answers before it (and a signal named by the shell's
        // 128 + N).
        (
            format!("{trace} | head -3; sh -c 'kill -SEGV $$'"),
            "ended with exit status: 139 (the shell's for a program killed by signal 11, \
             SIGSEGV)",
        ),
        (
            format!("{trace} | head -3; sh -c 'kill -SEGV $$'"),
            "; 3 answers had reached raylab before it ended: the first ray without one is ",
        ),
        (
            "echo garbage # {scene} {rays}".to_string(),
            "its output:1: expected 'hit <t> <index>' or 'miss'",
        ),
        (
            format!("{trace} | head -3"),
            "its output: 3 answers for the 10 rays",
        ),
        (
            format!("{trace} >&2"),
            "(it printed nothing on standard output, where the answers go, and wrote to standard error",
        ),
        // (A fork bomb that put itself in the background: its shell's words are quoted.)
        (
            "echo 'sh: fork: Resource temporarily unavailable' >&2 # {scene} {rays}".to_string(),
            "which is not read; its last words: sh: fork: Resource temporarily unavailable)",
        ),
        ("yes miss # {scene} {rays}".to_string(), "printed more than"),
        (
            "printf 'miss\\n\\377\\n' # {scene} {rays}".to_string(),
            "printed something that is not UTF-8 text (on line 2)",
        ),
        // Control bytes quoted from its output or its last words drive no terminal.
        (
            "printf '\\033[31mRED\\033[0m\\n' # {scene} {rays}".to_string(),
            "found '\\u{1b}[31mRED\\u{1b}[0m'",
        ),
        (
            "printf 'bad\\rworse\\033[2J' >&2; exit 1 # {scene} {rays}".to_string(),
            "its last words: bad\\rworse\\u{1b}[2J",
        ),
        (
            "printf 'm\\000i\\000s\\000s\\000\\n\\000' # {scene} {rays}".to_string(),
            "printed UTF-16 text (as Windows PowerShell's pipes and `>` write it), not UTF-8",
        ),
    ] {
        let o = check_program(&scene, &rays, &program, &["--timeout", "0.5"]);
        let out = text(&o.stdout);
        assert_eq!(
            o.status.code(),
            Some(1),
            "{program}: {out}{}",
            text(&o.stderr)
        );
        assert!(
            out.contains("FAILED: ") && out.contains(message),
            "{program}: '{message}' in {out}"
        );
        assert!(!out.contains('\u{1b}') && !out.contains('\r'), "{out:?}");
        assert!(last_line(&o).ends_with("failed_runs 1"), "{out}");
    }
    // A child left running after the program's answers does not hold the check up.
    let program = format!("(sleep 30 &); {trace}");
    let o = check_program(&scene, &rays, &program, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stdout));

    // In a suite, the failing families are rows of their own; the others are graded.
    let suite_dir = dir.path().join("suite");
    export::export(&suite_dir, &suite::all()).unwrap();
    // (Told apart by the scene's first line, the family's title: the program reads a copy.)
    let program = format!(
        "case \"$(head -n 1 {{scene}})\" in *'cube, from outside'*) exit 3;; \
         *'tiny cube'*) sleep 30;; esac; {trace}"
    );
    let o = raylab(&[
        "check",
        "--suite",
        suite_dir.to_str().unwrap(),
        "--program",
        &program,
        "--timeout",
        "2",
    ]);
    let out = text(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    assert_eq!(
        out.lines().filter(|l| l.contains("FAILED:")).count(),
        2,
        "{out}"
    );
    // Under each, the command that checks that family alone, as this run did (its timeout
    // too: a family that outlived 2 s would pass the default 60 s), by the path raylab ran
    // by (a student without raylab on PATH pasted `raylab check …`: command not found).
    let alone = format!(
        "    this family alone: {} check --suite {} --family 02-cube-from-outside --program {} \
         --timeout 2",
        raylab::view::shell_quote(env!("CARGO_BIN_EXE_raylab")),
        raylab::view::shell_quote(suite_dir.to_str().unwrap()),
        raylab::view::shell_quote(&program)
    );
    assert!(out.lines().any(|l| l == alone), "{alone}\n{out}");
    let line = last_line(&o);
    assert!(line.ends_with("failed_runs 2"), "{line}");
    let graded: usize = suite::all()
        .iter()
        .enumerate()
        .filter(|(i, _)| ![1, 4].contains(i))
        .map(|(_, f)| f.rays.len())
        .sum();
    assert_eq!(count(&line, "rays"), graded, "{line}");
    assert_eq!(
        count(&line, "leaks") + count(&line, "wrong") + count(&line, "false_hits"),
        0,
        "{line}"
    );

    // A program that hangs costs the --budget, not a --timeout per family: the family where
    // it runs out is stopped there, the rest are skipped; each is a failed run.
    let o = raylab(&[
        "check",
        "--suite",
        suite_dir.to_str().unwrap(),
        "--program",
        "sleep 30 # {scene} {rays}",
        "--timeout",
        "1",
        "--budget",
        "2.5",
    ]);
    let out = text(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    let rows = |what: &str| out.lines().filter(|l| l.contains(what)).count();
    let families = suite::all().len();
    assert_eq!(rows("FAILED: ran out of time (1.0 s"), 2, "{out}");
    assert_eq!(
        rows("FAILED: ran out of time: the --budget of 2.5 s ran out"),
        1,
        "{out}"
    );
    assert_eq!(
        rows("SKIPPED: not run: the --budget of 2.5 s ran out"),
        families - 3,
        "{out}"
    );
    let failed = format!("failed_runs {families}");
    assert!(last_line(&o).ends_with(&failed), "{out}");
}
