//! Bad input to the `raylab` binary: every value and every hostile OBJ line refused with a
//! clear error naming the value, or the file and line, exit code 2 and no panic.

use crate::common;

use common::binary::{assert_fails, stderr, write};

crate::raylab_runner!();

/// `raylab render --scene SCENE EXTRA… --out /dev/null` with extra environment variables.
fn render_scene(
    scene: impl AsRef<std::path::Path>,
    extra: &[&str],
    env: &[(&str, &str)],
) -> std::process::Output {
    let scene = scene.as_ref().to_str().unwrap();
    let mut args = vec!["render", "--scene", scene];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--out", "/dev/null"]);
    raylab_env(&args, env)
}

#[test]
fn render_rejects_bad_values_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let out = out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--width", "0"], "0 is not in 1..=16384"),
        (&["--width", "100000"], "100000 is not in 1..=16384"),
        (&["--focal", "0"], "focal length 0"),
        (&["--focal", "-5"], "focal length -5"),
        (&["--focal", "NaN"], "focal length NaN"),
        (&["--focal", "1e300"], "focal length"),
        (&["--spp", "0"], "0 is not in 1..=16"),
        (&["--spp", "1000"], "1000 is not in 1..=16"),
        // (A negative count is named with its range, not a u32's nor as "invalid digit".)
        (&["--spp", "-1"], "-1 is not in 1..=16"),
        (&["--width", "-5"], "-5 is not in 1..=16384"),
        (&["--camera", "1,2"], "x,y,z"),
        (&["--camera", "1,nan,2"], "not finite"),
        (&["--scene", "/no/such/file.obj"], "/no/such/file.obj"),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["render", "--height", "48", "--out", out];
        args.extend_from_slice(extra);
        let o = raylab(&args);
        assert_fails(&o, 2, &[needle]);
    }
    let counts: &[(&[&str], &str)] = &[
        (
            &["render", "--width", "16384", "--height", "16384", "-o", out],
            "16384x16384 is out of range",
        ),
        (&["bench", "--threads", "-1"], "-1 is not in 1..=1024"),
        (&["bench", "--frames", "0"], "0 is not in 1..=10000"),
        (&["check", "--show", "-1"], "-1 is not in 0..=4294967295"),
        (&["grade", "-j", "-2"], "-2 is not in 1..=1024"),
        (
            &["grade", "--max-memory", "8"],
            "8 is not in 16..=4294967295",
        ),
    ];
    for (args, needle) in counts {
        assert_fails(&raylab(args), 2, &[needle]);
    }
    let o = raylab(&["render", "--step", "bogus", "--out", out]);
    assert_fails(&o, 2, &["bogus", "flat"]);
    let o = raylab(&["render", "--method", "exact", "--out", out]);
    assert_fails(&o, 2, &["exact", "watertight"]);
    let o = raylab(&[
        "render",
        "--width",
        "8",
        "--height",
        "8",
        "--out",
        "/no/such/dir/x.png",
    ]);
    assert_fails(&o, 2, &["/no/such/dir/x.png"]);
}

#[test]
fn render_rejects_hostile_obj_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, &str)] = &[
        (
            "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n",
            ":3: coordinate 'nan'",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n",
            ":3: coordinate '1e39' is not a finite",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
            ":4: face '4': vertex index 4 is out of range",
        ),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ":4: face '0'"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",
            ":4: face needs at least 3",
        ),
        ("v 0 0\n", ":1: vertex takes 3 numbers"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "vertex index -4"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n",
            "'x' is not an integer",
        ),
        ("", "no triangles"),
        (
            "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n",
            "has no triangle of nonzero area (1 of zero area)",
        ),
        ("v 0 0 0\n\u{0}\u{1}binary", ":2: not a text OBJ"),
    ];
    for (k, (text, needle)) in cases.iter().enumerate() {
        let obj = dir.path().join(format!("bad{k}.obj"));
        std::fs::write(&obj, text).unwrap();
        let o = render_scene(&obj, &[], &[]);
        assert_fails(&o, 2, &[&format!("bad{k}.obj"), needle]);
    }
    // A file of a scene's `tri` lines named other than `.scene` is read as OBJ: the message
    // says so (it said "no triangles" alone). An empty `.obj` does not get the hint.
    let txt = dir.path().join("mine.txt");
    std::fs::write(&txt, "tri 0 0 5 1 0 5 0 1 5\n").unwrap();
    let o = render_scene(&txt, &[], &[]);
    assert_fails(
        &o,
        2,
        &["mine.txt: no triangles (read as an OBJ file", ".scene"],
    );
    let empty = dir.path().join("empty.obj");
    std::fs::write(&empty, "").unwrap();
    let o = render_scene(&empty, &[], &[]);
    assert_fails(&o, 2, &["empty.obj: no triangles"]);
    assert!(!stderr(&o).contains("read as an OBJ"), "{}", stderr(&o));
    // A 2 GiB file (sparse: no disk used) is refused before anything is read.
    let big = dir.path().join("big.obj");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(2 << 30)
        .unwrap();
    let o = render_scene(&big, &[], &[]);
    assert_fails(&o, 2, &["big.obj", "larger than the 1073741824-byte limit"]);
    // 20,000 repeated `mtllib` lines read the library once (cached), quickly.
    let obj = dir.path().join("repeat.obj");
    let mut text = "mtllib r.mtl\n".repeat(20_000);
    text.push_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl r\nf 1 2 3\n");
    std::fs::write(&obj, text).unwrap();
    std::fs::write(dir.path().join("r.mtl"), "newmtl r\nKd 1 0 0\n").unwrap();
    let o = render_scene(&obj, &["--width", "8", "--height", "8"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A face line with thousands of vertices is fan-triangulated, not a problem.
    let polygon = dir.path().join("polygon.obj");
    let obj = polygon.clone();
    let n = 2000;
    let mut text: String = (0..n)
        .map(|k| {
            let a = k as f64 / n as f64 * std::f64::consts::TAU;
            format!("v {} {} 0\n", a.cos(), a.sin())
        })
        .collect();
    text.push_str(&format!(
        "f {}\n",
        (1..=n).map(|k| k.to_string()).collect::<Vec<_>>().join(" ")
    ));
    std::fs::write(&obj, text).unwrap();
    let o = render_scene(&obj, &["--width", "16", "--height", "16"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A file that asks for millions of triangles: one 17M-vertex polygon over 3 vertices
    // (34 MB) is refused by the first pass, before tobj or the scene allocate anything.
    let obj = dir.path().join("millions.obj");
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    text.push_str(&" 1 2 3".repeat((17 << 20) / 3 + 1));
    text.push('\n');
    std::fs::write(&obj, &text).unwrap();
    let start = std::time::Instant::now();
    let o = render_scene(&obj, &[], &[]);
    assert_fails(&o, 2, &["millions.obj:4", "more than 16777216 triangles"]);
    println!("17M-triangle claim refused in {:?}", start.elapsed());
    // The limit can be lowered (and raised) for one run.
    let o = render_scene(&polygon, &[], &[("RAYLAB_MAX_TRIANGLES", "1000")]);
    assert_fails(&o, 2, &["polygon.obj:2001", "more than 1000 triangles"]);
    // A polyline is never drawn, but its references count towards the same limit: one long
    // `l` line cannot ask for memory the face limit would refuse.
    let obj = dir.path().join("polyline.obj");
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl");
    text.push_str(&" 1 2 3".repeat(400));
    text.push('\n');
    std::fs::write(&obj, &text).unwrap();
    let o = render_scene(&obj, &[], &[("RAYLAB_MAX_TRIANGLES", "1000")]);
    assert_fails(&o, 2, &["polyline.obj:5", "more than 1000 elements"]);
    // A directory named .obj.
    let d = dir.path().join("dir.obj");
    std::fs::create_dir(&d).unwrap();
    let o = render_scene(&d, &[], &[]);
    assert_fails(&o, 2, &["dir.obj", "not a regular file"]);
    // A broken material library (tobj 4 panics on a short Kd) is a warning naming its line.
    let obj = dir.path().join("badmtl.obj");
    std::fs::write(
        &obj,
        "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("bad.mtl"), "newmtl x\nKd 0.5\n").unwrap();
    let o = render_scene(&obj, &["--width", "8", "--height", "8"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("bad.mtl:2: Kd needs 3 numbers"),
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("panicked"));
    // A missing material library is a warning, not an error.
    let obj = dir.path().join("nomtl.obj");
    std::fs::write(
        &obj,
        "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n",
    )
    .unwrap();
    let o = render_scene(&obj, &["--width", "8", "--height", "8"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("missing.mtl"), "{}", stderr(&o));
}

#[test]
fn values_the_f32_core_cannot_hold_are_refused_naming_them() {
    // Finite in f64 but not in f32, or beyond the range the f32 kernels compute in without
    // overflow (scene 2^38, camera and light 2^40): refused before any work, with the value.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let huge_obj = write(
        d,
        "huge.obj",
        "v -3e38 -3e38 0\nv 3e38 -3e38 0\nv 0 3e38 0\nf 1 2 3\n",
    );
    let scaled = write(d, "scaled.scene", "scale 1e12\ntri 0 0 0 1 0 0 0 1 0\n");
    // A sphere whose centre is in range but not its bounds, after another: named by its line.
    let ball = write(
        d,
        "ball.scene",
        "push\nsphere 0 0 0 1\npop\n\nsphere 0 0 0 3e11\nsphere 0 0 5 1\n",
    );
    let placed = write(d, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let mesh = write(
        d,
        "mesh.scene",
        &format!("sphere 0 0 0 1\nmesh {placed}\nscale 1e12\nmesh {placed}\n"),
    );
    // A mesh used often enough to be placed as instances: the placement's line.
    let ico = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../assets/meshes/icosphere.obj"
    );
    let placements = write(
        d,
        "placed.scene",
        &format!(
            "sphere 0 0 0 1\nmesh {ico}\nscale 1e12\n{}",
            format!("mesh {ico}\n").repeat(3)
        ),
    );
    let far_camera = write(d, "cam.scene", "cornell\ncamera 0 0 -2e12\n");
    let far_light = write(d, "light.scene", "cornell\n\nlight 1e13 0 0\n");
    let view = write(d, "far.view", "scene cornell\nlight 0 0 -5e12\n");
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["--camera", "1e39,0,0"],
            &["camera position", "1e39", "beyond"],
        ),
        (
            &["--camera", "0,0,-2e12"],
            &[
                "camera position",
                "-2000000000000",
                "beyond ±1.099511627776e12",
            ],
        ),
        (
            &["--light", "1e13,0,0"],
            &["light position", "10000000000000"],
        ),
        (
            &["--scene", &huge_obj],
            &[
                "huge.obj",
                "triangle 0",
                "-3e38",
                "beyond ±2.74877906944e11",
            ],
        ),
        (
            &["--scene", &scaled],
            &["scaled.scene:2:", "triangle 0", "1000000000000"],
        ),
        (
            &["--scene", &ball],
            &["ball.scene:5:", "sphere 1", "-300000000000"],
        ),
        (
            &["--scene", &mesh],
            &["mesh.scene:4:", "triangle 2", "1000000000000"],
        ),
        (
            &["--scene", &placements],
            &["placed.scene:4:", "icosphere.obj placed at primitive 1281"],
        ),
        (
            &["--scene", &far_camera],
            &["cam.scene:2", "camera position", "-2000000000000"],
        ),
        (
            &["--scene", &far_light],
            &["light.scene:3", "light position", "10000000000000"],
        ),
        (
            &["--view", &view],
            &["far.view", "light position", "-5000000000000"],
        ),
    ];
    for (args, needles) in cases {
        let mut all = vec!["render", "-o", "/dev/null"];
        if args[0] != "--view" {
            all.extend_from_slice(&["--width", "64", "--height", "48"]);
        }
        all.extend_from_slice(args);
        let start = std::time::Instant::now();
        let o = raylab(&all);
        assert_fails(&o, 2, needles);
        assert!(
            start.elapsed().as_secs() < 20,
            "{args:?} took {:?}",
            start.elapsed()
        );
    }
    // Within range: a scene at 2e11 renders (lit: its normals no longer overflow).
    let big = write(
        d,
        "big.obj",
        "v -2e11 -2e11 0\nv 2e11 -2e11 0\nv 0 2e11 0\nf 1 2 3\n",
    );
    let o = render_scene(
        &big,
        &["--step", "shadows", "--width", "64", "--height", "48"],
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The command line speaks with one voice: a mistyped command suggests the nearest, an
/// output named .jpg is refused (raylab writes PNG), each OS error is said once with its
/// path, and a bad view named on the command line is its `file:line` error before any window.
#[test]
fn a_typo_a_jpg_an_os_error_and_a_bad_view_are_each_said_once_and_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let o = raylab(&["rendr"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("did you mean `raylab render`?"),
        "{}",
        stderr(&o)
    );

    let jpg = dir.path().join("x.jpg");
    let o = raylab(&[
        "render",
        "--width",
        "8",
        "--height",
        "8",
        "-o",
        jpg.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("PNG images only"), "{}", stderr(&o));
    assert!(!jpg.exists());

    let o = raylab(&["render", "-o", "/nonexistent/dir/o.png"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.contains("/nonexistent/dir/o.png"), "{err}");
    let missing = "there is no directory /nonexistent/dir to write it in";
    assert_eq!(err.matches(missing).count(), 1, "{err}");

    let view = write(dir.path(), "bad.view", "scene cornell\ncamera 0 0\n");
    let o = raylab(&[view.as_str()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bad.view:2"), "{}", stderr(&o));
}

#[test]
fn a_scene_name_that_is_not_utf8_is_refused_naming_the_flag() {
    use std::os::unix::ffi::OsStrExt;
    let name = std::ffi::OsStr::from_bytes(b"\xff.scene");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(["render", "-o", "/dev/null", "--scene"])
        .arg(name)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.contains("'--scene <SCENE>'"), "{err}");
    assert!(
        err.contains("is not UTF-8") && err.contains("rename the file"),
        "{err}"
    );
}
