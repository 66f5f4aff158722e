//! Every flag a subcommand shows is one it uses: a flag it would ignore is refused (exit 2,
//! clap's message), and its help lists only what it uses.

use crate::common;

use common::binary::{assert_fails, stderr, stdout, write};

crate::raylab_runner!();

/// The render-only flags, each with a value where it takes one.
const RENDER_ONLY: [&[&str]; 6] = [
    &["--method", "moller"],
    &["--spp", "2"],
    &["--step", "shadows"],
    &["--cracks"],
    &["--accel", "bvh"],
    &["--no-tile-culling"],
];

#[test]
fn check_refuses_the_flags_it_would_ignore() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = write(d, "s.scene", "tri 0 0 0 1 0 0 0 1 0\n");
    let rays = write(d, "r.txt", "0.25 0.25 -1 0 0 1 0 inf\n");
    let answers = write(d, "a.txt", "hit 1 0\n");
    let graded = [
        "check",
        "--scene",
        &scene,
        "--rays",
        &rays,
        "--answers",
        &answers,
    ];
    let o = raylab(&graded);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o)
        .ends_with("check: rays 1 right 1 leaks 0 false_hits 0 wrong 0 ties 0 t_failures 0\n"));
    for flag in RENDER_ONLY {
        let o = raylab(&[&graded[..], flag].concat());
        assert_fails(&o, 2, &["unexpected argument", flag[0]]);
    }
    // The view's flags set the view of --image: with --rays or --suite they are refused.
    for flag in [
        &["--width", "5"][..],
        &["--height", "5"],
        &["--focal", "10"],
        &["--camera", "0,0,-3"],
        &["--yaw", "5"],
        &["--pitch", "5"],
        &["--light", "0,0,0"],
        &["--obj-frame", "lab"],
        &["--view", "x.view"],
    ] {
        let o = raylab(&[&graded[..], flag].concat());
        assert_fails(&o, 2, &["cannot be used with", flag[0]]);
        let program = ["check", "--program", "true {scene} {rays}"];
        let o = raylab(&[&program[..], flag].concat());
        assert_fails(&o, 2, &["--image"]);
    }
    // --timeout times a program: with an answer file it is refused.
    let o = raylab(&[&graded[..], &["--timeout", "5"]].concat());
    assert_fails(&o, 2, &["cannot be used with", "--timeout"]);
    // --budget bounds a suite's runs together: with one scene's rays it is refused.
    let program = [
        "check",
        "--rays",
        "r.txt",
        "--program",
        "true {scene} {rays}",
    ];
    let o = raylab(&[&program[..], &["--budget", "5"]].concat());
    assert_fails(&o, 2, &["cannot be used with", "--budget"]);
    // --image grades in f32 only; a suite's families hold their scenes.
    let program = "true {scene} {rays}";
    let image = d.join("x.png");
    let image = image.to_str().unwrap();
    let in_precision = |precision: &str| {
        let image_args = ["check", "--image", image, "--program", program];
        raylab(&[&image_args[..], &["--precision", precision]].concat())
    };
    let o = in_precision("f64");
    // (Said why: clap's conflict named the two flags only.)
    let why = [
        "--precision f64: --image grades in f32",
        "leave --precision out",
    ];
    assert_fails(&o, 2, &why);
    // In f32, as it grades, it runs.
    let err = stderr(&in_precision("f32"));
    assert!(
        err.contains("running the program") && !err.contains("--precision"),
        "{err}"
    );
    let o = raylab(&[
        "check",
        "--suite",
        ".",
        "--program",
        program,
        "--scene",
        &scene,
    ]);
    assert_fails(&o, 2, &["cannot be used with", "--scene"]);
    // --family picks a suite's family: with --rays or --image there is none to pick.
    let family = ["--family", "1"];
    let o = raylab(&[&graded[..], &family].concat());
    assert_fails(&o, 2, &["cannot be used with", "--family"]);
    let with_program = [
        "check",
        "--scene",
        &scene,
        "--rays",
        &rays,
        "--program",
        program,
    ];
    let o = raylab(&[&with_program[..], &family].concat());
    assert_fails(&o, 2, &["cannot be used with", "--family"]);
    let with_image = ["check", "--image", image, "--program", program];
    let o = raylab(&[&with_image[..], &family].concat());
    assert_fails(&o, 2, &["cannot be used with", "--family"]);
    assert!(!d.join("x.png").exists());
}

#[test]
fn inspect_refuses_what_its_one_ray_does_not_use() {
    let o = raylab(&[
        "inspect", "--pixel", "320,240", "--method", "moller", "--step", "shadows",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("method: moller"), "{}", stdout(&o));
    for flag in [&["--spp", "2"][..], &["--cracks"], &["--no-tile-culling"]] {
        let o = raylab(&[&["inspect", "--pixel", "1,1"][..], flag].concat());
        assert_fails(&o, 2, &["unexpected argument", flag[0]]);
    }
}

#[test]
fn inspect_at_traces_the_ray_through_an_image_position() {
    // `--at X,Y`: the ray through an image position, as a supersampled pixel's sample is
    // traced; a pixel's centre is `--pixel`'s ray, field for field.
    let inspect = |ray: &[&str]| raylab(&[&["inspect"][..], ray].concat());
    let (centre, pixel) = (
        inspect(&["--at", "100.5,80.5"]),
        inspect(&["--pixel", "100,80"]),
    );
    assert!(pixel.status.success(), "{}", stderr(&pixel));
    assert_eq!(stdout(&centre), stdout(&pixel));
    // Off the centre: the pixel holding the position, and u = x - W/2, v = y - H/2 (640x480).
    let o = inspect(&["--at", "100.25,80.75"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.starts_with("pixel: 100 80\n"), "{out}");
    assert!(out.contains("\nuvf: -219.75 -159.25 "), "{out}");
    assert_ne!(out, stdout(&pixel));
    let refused: [(&[&str], &[&str]); 6] = [
        (
            &["--at", "640,3"],
            &["position 640,3 is outside the 640x480 image"],
        ),
        (&["--at", "-0.001,3"], &["position -0.001,3 is outside"]),
        (&["--at", "1e300, 0"], &["position 1e300, 0 is outside"]),
        (
            &["--at", "nan,3"],
            &["'nan,3' is not an image position x,y"],
        ),
        (&["--at", "1,1", "--pixel", "1,1"], &["cannot be used with"]),
        (&[], &["required", "--pixel", "--at"]),
    ];
    for (ray, said) in refused {
        assert_fails(&inspect(ray), 2, said);
    }
}

/// The `--flag`s a help text lists.
fn flags_in_help(command: &str) -> Vec<String> {
    let o = raylab(&[command, "--help"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut flags: Vec<String> = stdout(&o)
        .lines()
        .map(str::trim_start)
        // `--flag` or `-f, --flag` at the start of a line.
        .map(|l| match l.get(2..4) {
            Some(", ") if l.starts_with('-') => &l[4..],
            _ => l,
        })
        .filter_map(|l| l.strip_prefix("--"))
        .map(|l| l.split([' ', ',']).next().unwrap().to_string())
        .collect();
    flags.sort();
    flags
}

#[test]
fn each_help_lists_only_the_flags_its_command_uses() {
    let view = [
        "camera",
        "focal",
        "height",
        "light",
        "obj-frame",
        "pitch",
        "scene",
        "view",
        "width",
        "yaw",
    ];
    let image = [
        "accel",
        "cracks",
        "method",
        "no-tile-culling",
        "spp",
        "step",
    ];
    let mut check = vec![
        "answers",
        "budget",
        "family",
        "help",
        "image",
        "precision",
        "program",
        "rays",
        "show",
        "suite",
        "t-tolerance",
        "timeout",
    ];
    check.extend(view);
    check.sort();
    assert_eq!(flags_in_help("check"), check);
    let mut inspect = vec!["accel", "at", "help", "method", "pixel", "step"];
    inspect.extend(view);
    inspect.sort();
    assert_eq!(flags_in_help("inspect"), inspect);
    let mut render = vec!["aov", "help", "out"];
    render.extend(view.iter().chain(&image));
    render.sort();
    assert_eq!(flags_in_help("render"), render);
    let mut bench = vec!["frames", "help", "simd", "threads"];
    bench.extend(view.iter().chain(&image));
    bench.sort();
    assert_eq!(flags_in_help("bench"), bench);
}

/// A focal length out of range is named in its shortest form (`0.000000e0` had read as a
/// number's rounding, `-5.000000e0` as another number than the one typed).
#[test]
fn a_focal_length_out_of_range_is_named_as_a_number() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    for (focal, named) in [("0", "0.0"), ("-5", "-5.0"), ("1e-300", "1e-300")] {
        let flag = format!("--focal={focal}");
        let o = raylab(&["render", &flag, "-o", out.to_str().unwrap()]);
        let message = format!("focal length {named} px is out of range");
        assert_fails(&o, 2, &[&message]);
    }
}

/// A number out of range is refused naming it as given, however large (1e300 was written
/// out in 301 digits).
#[test]
fn check_names_a_number_out_of_range_as_given() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = write(d, "s.scene", "tri 0 0 0 1 0 0 0 1 0\n");
    let rays = write(d, "r.txt", "0.25 0.25 -1 0 0 1 0 inf\n");
    let program = "cat {scene} {rays}";
    for (flag, message) in [
        (
            "--timeout",
            "--timeout 1e300 must be > 0 and at most 1e6 seconds",
        ),
        (
            "--t-tolerance",
            "--t-tolerance 1e300 must be a number from 0 to 1",
        ),
    ] {
        let args = [
            "check",
            "--scene",
            &scene,
            "--rays",
            &rays,
            "--program",
            program,
        ];
        let o = raylab(&[&args[..], &[flag, "1e300"]].concat());
        assert_fails(&o, 2, &[message]);
        assert!(stderr(&o).len() < 200, "{}", stderr(&o));
    }
}

/// A negative number given to a flag that takes a count is refused naming the flag (it was
/// clap's "unexpected argument '-5' found", which names none).
#[test]
fn a_negative_count_is_refused_naming_its_flag() {
    for (args, flag) in [
        (
            &["render", "--height", "-5", "-o", "x.png"][..],
            "'--height <HEIGHT>'",
        ),
        (&["render", "--spp", "-2", "-o", "x.png"][..], "'--spp <N>'"),
        (&["inspect", "--pixel", "-1,0"][..], "'--pixel <PIXEL>'"),
        (&["bench", "--frames", "-1"][..], "'--frames <FRAMES>'"),
    ] {
        let o = raylab(args);
        assert_fails(&o, 2, &["invalid value '-", flag]);
    }
}
