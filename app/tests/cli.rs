//! The `raylab` binary from outside: render, trace, and bad input.

#[path = "../../tests/common/mod.rs"]
mod common;

use common::read_png;
use std::path::Path;
use std::process::{Command, Output};

/// Runs the binary ([`common::binary::run`]).
fn raylab(args: &[&str]) -> Output {
    raylab_env(args, &[])
}

/// [`raylab`] with extra environment variables.
fn raylab_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    common::binary::run(env!("CARGO_BIN_EXE_raylab"), args, env)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A failed run: the given exit code, a message holding every `needle`, and no panic.
fn assert_fails(o: &Output, code: i32, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "'{n}' not in: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn render_writes_the_cornell_box_for_every_step() {
    let dir = tempfile::tempdir().unwrap();
    for step in ["flat", "direct", "shadows", "indirect"] {
        let out = dir.path().join(format!("{step}.png"));
        let o = raylab(&[
            "render",
            "--width",
            "64",
            "--height",
            "48",
            "--step",
            step,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = stdout(&o);
        assert!(text.contains("Mrays/s") && text.contains("64x48"), "{text}");
        let (w, h, px) = read_png(&out);
        assert_eq!((w, h, px.len()), (64, 48, 64 * 48 * 4));
        // Left wall purple-ish, right wall yellow-ish in the middle row (not black).
        let at = |i: usize, j: usize| &px[4 * (j * 64 + i)..4 * (j * 64 + i) + 3];
        let (l, r) = (at(2, 24), at(61, 24));
        assert!(l[0] > l[1] && l[2] > l[1], "{step}: left {l:?}");
        assert!(r[0] > r[2] && r[1] > r[2], "{step}: right {r:?}");
    }
}

#[test]
fn render_camera_flags_move_the_view() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.png");
    let b = dir.path().join("b.png");
    let o = raylab(&[
        "render",
        "--width",
        "48",
        "--height",
        "32",
        "--out",
        a.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = raylab(&[
        "render",
        "--width",
        "48",
        "--height",
        "32",
        "--camera",
        "0.2,-0.1,-2",
        "--yaw",
        "-10",
        "--pitch",
        "5",
        "--focal",
        "30",
        "--spp",
        "2",
        "--method",
        "moller",
        "--out",
        b.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(read_png(&a).2, read_png(&b).2);
}

#[test]
fn render_loads_an_obj_and_frames_it() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("tet.obj");
    // A pyramid: a quad base (fan-triangulated), four sides, and one degenerate face.
    std::fs::write(
        &obj,
        "mtllib tet.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 1\nusemtl red\n\
         f 1 2 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\nf 1 1 2\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("tet.mtl"), "newmtl red\nKd 1 0 0\n").unwrap();
    let out = dir.path().join("tet.png");
    let o = raylab(&[
        "render",
        "--scene",
        obj.to_str().unwrap(),
        "--width",
        "32",
        "--height",
        "32",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("dropped 1 degenerate"),
        "{}",
        stderr(&o)
    );
    let (_, _, px) = read_png(&out);
    // Framed: the centre pixel sees the red model, a corner sees the background.
    let c = &px[4 * (16 * 32 + 16)..][..3];
    assert!(c[0] > 200 && c[1] == 0 && c[2] == 0, "{c:?}");
    assert_eq!(&px[..3], &[0, 0, 0]);
}

#[test]
fn render_rejects_bad_values_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let out = out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--width", "0"], "0x48"),
        (&["--width", "100000"], "100000x48"),
        (&["--focal", "0"], "focal length 0"),
        (&["--focal", "-5"], "focal length -5"),
        (&["--focal", "NaN"], "focal length NaN"),
        (&["--focal", "1e300"], "focal length"),
        (&["--spp", "0"], "supersampling 0"),
        (&["--spp", "1000"], "supersampling 1000"),
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
            "no triangles (after dropping 1",
        ),
        ("v 0 0 0\n\u{0}\u{1}binary", ":2: not a text OBJ"),
    ];
    for (k, (text, needle)) in cases.iter().enumerate() {
        let obj = dir.path().join(format!("bad{k}.obj"));
        std::fs::write(&obj, text).unwrap();
        let o = raylab(&[
            "render",
            "--scene",
            obj.to_str().unwrap(),
            "--out",
            "/dev/null",
        ]);
        assert_fails(&o, 2, &[&format!("bad{k}.obj"), needle]);
    }
    // A 2 GiB file (sparse: no disk used) is refused before anything is read.
    let big = dir.path().join("big.obj");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(2 << 30)
        .unwrap();
    let o = raylab(&[
        "render",
        "--scene",
        big.to_str().unwrap(),
        "--out",
        "/dev/null",
    ]);
    assert_fails(&o, 2, &["big.obj", "larger than the 1073741824-byte limit"]);
    // 20,000 repeated `mtllib` lines read the library once (cached), quickly.
    let obj = dir.path().join("repeat.obj");
    let mut text = "mtllib r.mtl\n".repeat(20_000);
    text.push_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl r\nf 1 2 3\n");
    std::fs::write(&obj, text).unwrap();
    std::fs::write(dir.path().join("r.mtl"), "newmtl r\nKd 1 0 0\n").unwrap();
    let o = raylab(&[
        "render",
        "--scene",
        obj.to_str().unwrap(),
        "--width",
        "8",
        "--height",
        "8",
        "--out",
        "/dev/null",
    ]);
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
    let o = raylab(&[
        "render",
        "--scene",
        obj.to_str().unwrap(),
        "--width",
        "16",
        "--height",
        "16",
        "--out",
        "/dev/null",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A file that asks for millions of triangles: one 17M-vertex polygon over 3 vertices
    // (34 MB) is refused by the first pass, before tobj or the scene allocate anything.
    let obj = dir.path().join("millions.obj");
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    text.push_str(&" 1 2 3".repeat((17 << 20) / 3 + 1));
    text.push('\n');
    std::fs::write(&obj, &text).unwrap();
    let start = std::time::Instant::now();
    let o = raylab(&[
        "render",
        "--scene",
        obj.to_str().unwrap(),
        "--out",
        "/dev/null",
    ]);
    assert_fails(&o, 2, &["millions.obj:4", "more than 16777216 triangles"]);
    println!("17M-triangle claim refused in {:?}", start.elapsed());
    // The limit can be lowered (and raised) for one run.
    let o = raylab_env(
        &[
            "render",
            "--scene",
            polygon.to_str().unwrap(),
            "--out",
            "/dev/null",
        ],
        &[("RAYLAB_MAX_TRIANGLES", "1000")],
    );
    assert_fails(&o, 2, &["polygon.obj:2001", "more than 1000 triangles"]);
    // A polyline is never drawn, but its references count towards the same limit: one long
    // `l` line cannot ask for memory the face limit would refuse.
    let obj = dir.path().join("polyline.obj");
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl");
    text.push_str(&" 1 2 3".repeat(400));
    text.push('\n');
    std::fs::write(&obj, &text).unwrap();
    let o = raylab_env(
        &[
            "render",
            "--scene",
            obj.to_str().unwrap(),
            "--out",
            "/dev/null",
        ],
        &[("RAYLAB_MAX_TRIANGLES", "1000")],
    );
    assert_fails(&o, 2, &["polyline.obj:5", "more than 1000 elements"]);
    // A directory named .obj.
    let d = dir.path().join("dir.obj");
    std::fs::create_dir(&d).unwrap();
    let o = raylab(&[
        "render",
        "--scene",
        d.to_str().unwrap(),
        "--out",
        "/dev/null",
    ]);
    assert_fails(&o, 2, &["dir.obj", "not a regular file"]);
    // A broken material library (tobj 4 panics on a short Kd) is a warning naming its line.
    let obj = dir.path().join("badmtl.obj");
    std::fs::write(
        &obj,
        "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("bad.mtl"), "newmtl x\nKd 0.5\n").unwrap();
    let o = raylab(&[
        "render",
        "--scene",
        obj.to_str().unwrap(),
        "--width",
        "8",
        "--height",
        "8",
        "--out",
        "/dev/null",
    ]);
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
    let o = raylab(&[
        "render",
        "--scene",
        obj.to_str().unwrap(),
        "--width",
        "8",
        "--height",
        "8",
        "--out",
        "/dev/null",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("missing.mtl"), "{}", stderr(&o));
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn trace_answers_the_text_format_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "scene.txt",
        "# a triangle at z = 2, a sphere behind it, a triangle at z = 1 off to the side\n\
         tri -1 -1 2  1 -1 2  0 1 2\n\
         \n\
         sphere 0 0 5 1\n\
         tri 5 5 1 7 5 1 5 7 1\n",
    );
    let rays = write(
        dir.path(),
        "rays.txt",
        "0 0 0 0 0 1 0 inf\n\
         # unnormalised: t is in units of |d|\n\
         0 0 0 0 0 4 0 inf\n\
         0 0 0 0 0 1 2.5 inf\n\
         0 0 0 0 0 1 0 2\n\
         0 0 0 0 0 1 4 7\n\
         5.5 5.5 0 0 0 1 0 inf\n\
         0 0 0 0 1 0 0 inf\n\
         0 0 3 0 0 1 0 inf\n\
         0 0 0 0.1 0.1 1 0 inf\n",
    );
    let expected = "hit 2 0\nhit 0.5 0\nhit 4 1\nmiss\nhit 6 1\nhit 1 2\nmiss\nhit 1 1\n";
    for method in ["watertight", "moller", "cramer"] {
        for precision in ["f32", "f64"] {
            let o = raylab(&[
                "trace",
                "--scene",
                &scene,
                "--rays",
                &rays,
                "--method",
                method,
                "--precision",
                precision,
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            let out = stdout(&o);
            let lines: Vec<&str> = out.lines().collect();
            assert_eq!(lines.len(), 9, "{method} {precision}: {out}");
            assert_eq!(
                lines[..8].join("\n") + "\n",
                expected,
                "{method} {precision}"
            );
            // The last ray's t prints with full round-trip precision in its own precision.
            let last: Vec<&str> = lines[8].split(' ').collect();
            assert_eq!((last[0], last[2]), ("hit", "0"));
            let t = last[1];
            match precision {
                "f32" => {
                    let v: f32 = t.parse().unwrap();
                    assert_eq!(v.to_string(), t);
                    assert!((v - 2.0).abs() < 1e-6);
                }
                _ => {
                    let v: f64 = t.parse().unwrap();
                    assert_eq!(v.to_string(), t);
                    assert!((v - 2.0).abs() < 1e-14);
                }
            }
        }
    }
}

#[test]
fn trace_f64_sees_what_f32_cannot() {
    // Two triangles 1e-10 apart at z = 1: f32 parses both to the same plane (a tie, the lower
    // index wins); f64 keeps them apart and finds the nearer one.
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "s.txt",
        "tri -1 -1 1.0000000001 1 -1 1.0000000001 0 1 1.0000000001\ntri -1 -1 1 1 -1 1 0 1 1\n",
    );
    let rays = write(dir.path(), "r.txt", "0 0 0 0 0 1 0 inf\n");
    let f32_out = stdout(&raylab(&["trace", "--scene", &scene, "--rays", &rays]));
    let f64_out = stdout(&raylab(&[
        "trace",
        "--scene",
        &scene,
        "--rays",
        &rays,
        "--precision",
        "f64",
    ]));
    assert_eq!(f32_out, "hit 1 0\n");
    assert_eq!(f64_out, "hit 1 1\n");
}

#[test]
fn trace_rejects_malformed_input_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let good_scene = write(dir.path(), "good_scene.txt", "tri 0 0 1 1 0 1 0 1 1\n");
    let good_rays = write(dir.path(), "good_rays.txt", "0 0 0 0 0 1 0 inf\n");
    let scene_cases: &[(&str, &str)] = &[
        ("tri 0 0 1 1 0 1 0 1\n", ":1: tri needs 9 numbers, found 8"),
        (
            "\n# c\ntri 0 0 1 1 0 1 0 1 1 5\n",
            ":3: tri needs 9 numbers, found 10",
        ),
        ("sphere 0 0 0 -1\n", ":1: sphere radius -1 must be > 0"),
        ("sphere 0 0 0 0\n", "radius 0 must be > 0"),
        ("sphere 0 0 nan 1\n", ":1: 'nan' is NaN"),
        ("sphere 0 0 inf 1\n", "not finite"),
        ("tri 0 0 1 1 0 1 0 x 1\n", "'x' is not a number"),
        ("cube 1 2 3\n", "unknown statement 'cube'"),
        ("push\npop\npop\n", ":3: pop without a matching push"),
        (
            "scale 1 2 3\nsphere 0 0 0 1\n",
            ":2: a sphere under a non-uniform scale",
        ),
    ];
    for (text, needle) in scene_cases {
        let s = write(dir.path(), "bad_scene.txt", text);
        let o = raylab(&["trace", "--scene", &s, "--rays", &good_rays]);
        assert_fails(&o, 2, &["bad_scene.txt", needle]);
        assert!(o.stdout.is_empty(), "nothing half-printed");
    }
    let ray_cases: &[(&str, &str)] = &[
        ("0 0 0 0 0 1 0\n", ":1: ray needs 8 numbers, found 7"),
        ("0 0 0 0 0 1 0 inf 9\n", "found 9"),
        (
            "0 0 0 0 0 1 0 inf\n0 0 0 0 0 0 0 inf\n",
            ":2: direction is zero",
        ),
        ("0 0 0 0 0 1 5 1\n", ":1: tmin 5 > tmax 1"),
        ("0 0 0 0 0 1 nan inf\n", "'nan' is NaN"),
        ("0 0 inf 0 0 1 0 inf\n", "not finite"),
        ("0 0 0 0 0 1 0 junk\n", "'junk' is not a number"),
    ];
    for (text, needle) in ray_cases {
        let r = write(dir.path(), "bad_rays.txt", text);
        let o = raylab(&["trace", "--scene", &good_scene, "--rays", &r]);
        assert_fails(&o, 2, &["bad_rays.txt", needle]);
        assert!(o.stdout.is_empty(), "nothing half-printed");
    }
    let o = raylab(&["trace", "--scene", "/no/such/scene", "--rays", &good_rays]);
    assert_fails(&o, 2, &["/no/such/scene"]);
    let o = raylab(&[
        "trace",
        "--scene",
        &good_scene,
        "--rays",
        &good_rays,
        "--precision",
        "f16",
    ]);
    assert_fails(&o, 2, &["f16"]);
}

#[test]
fn the_window_without_a_display_or_adapter_fails_clearly() {
    // No display at all.
    let o = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_ne!(o.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("cannot open a window") && err.contains("DISPLAY"),
        "{err}"
    );
    // One line a user can act on, without a dependency's source path.
    assert!(
        !err.contains(".rs:") && err.trim().lines().count() == 1,
        "{err}"
    );
    assert!(err.contains("raylab render"), "{err}");
    // --frames needs --screenshot; --script needs --frames.
    assert_fails(&raylab(&["--frames", "3"]), 2, &["--screenshot"]);
    assert_fails(&raylab(&["--script", "x.txt"]), 2, &["--frames"]);
}

#[test]
fn the_window_without_a_graphics_adapter_fails_clearly() {
    // A display but no Vulkan driver: Xvfb with the Vulkan loader pointed at nothing.
    if !common::tool_for(
        "xvfb-run",
        "xvfb",
        "the_window_without_a_graphics_adapter_fails_clearly",
    ) {
        return;
    }
    let o = Command::new("xvfb-run")
        .args([
            "-a",
            env!("CARGO_BIN_EXE_raylab"),
            "--frames",
            "2",
            "--screenshot",
            "/dev/null",
        ])
        .env("VK_ICD_FILENAMES", "/nonexistent.json")
        .env("VK_DRIVER_FILES", "/nonexistent.json")
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_ne!(o.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("cannot open a graphics device"), "{err}");
}

#[test]
fn help_explains_every_flag() {
    let o = raylab(&["render", "--help"]);
    let text = stdout(&o);
    for flag in [
        "--scene", "--width", "--height", "--focal", "--camera", "--yaw", "--pitch", "--step",
        "--spp", "--method", "--out",
    ] {
        assert!(text.contains(flag), "{flag} missing from help");
    }
    let o = raylab(&["trace", "--help"]);
    let text = stdout(&o);
    for flag in ["--scene", "--rays", "--method", "--precision"] {
        assert!(text.contains(flag), "{flag} missing from help");
    }
}

#[test]
fn bench_prints_the_machine_the_runs_and_mrays_last() {
    let o = raylab(&[
        "bench",
        "--width",
        "32",
        "--height",
        "24",
        "--frames",
        "3",
        "--threads",
        "2",
        "--step",
        "shadows",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("machine:") && text.contains("threads: 2"),
        "{text}"
    );
    assert!(
        text.contains("accel: flat") && text.contains("build"),
        "{text}"
    );
    assert_eq!(text.matches("\nframe ").count(), 3, "{text}");
    assert!(
        text.contains("median frame") && text.contains("hits"),
        "{text}"
    );
    let last = text.lines().last().unwrap();
    let v: f64 = last
        .strip_prefix("mrays_per_s=")
        .expect(last)
        .parse()
        .unwrap();
    assert!(v > 0.0);
    assert_fails(&raylab(&["bench", "--frames", "0"]), 2, &["--frames 0"]);
    assert_fails(&raylab(&["bench", "--threads", "0"]), 2, &["--threads 0"]);
    assert_fails(&raylab(&["bench", "--accel", "kd"]), 2, &["kd", "bvh"]);
    assert_fails(
        &raylab(&["bench", "--simd", "sse9"]),
        2,
        &["sse9", "avx512"],
    );
}

#[test]
fn bench_runs_each_simd_level_the_cpu_has_and_refuses_the_others() {
    use raylab::math::simd::{detected, SimdLevel};
    let small = [
        "bench", "--width", "16", "--height", "16", "--frames", "1", "--simd",
    ];
    for level in SimdLevel::ALL {
        let o = raylab(&[&small[..], &[level.name()]].concat());
        if level <= detected() {
            assert!(o.status.success(), "{level}: {}", stderr(&o));
            let text = stdout(&o);
            let limited = text.contains("(limited; the CPU has");
            assert_eq!(limited, level < detected(), "{level}: {text}");
        } else {
            assert_fails(&o, 2, &[&format!("--simd {level}"), detected().name()]);
        }
    }
}

#[test]
fn every_accelerator_renders_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let mut images = Vec::new();
    for accel in ["flat", "bvh", "auto", "brute"] {
        let out = dir.path().join(format!("{accel}.png"));
        let o = raylab(&[
            "render",
            "--width",
            "64",
            "--height",
            "48",
            "--step",
            "shadows",
            "--accel",
            accel,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        images.push(read_png(&out).2);
    }
    assert_eq!(images[0], images[1]);
    assert_eq!(images[0], images[2]);
    assert_eq!(
        images[0], images[3],
        "brute, the old name of flat, still works"
    );
}

#[test]
fn scene_files_render_and_trace_through_the_transform_stack() {
    let dir = tempfile::tempdir().unwrap();
    let example = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../assets/scenes/cornell_spheres.scene"
    );
    let out = dir.path().join("spheres.png");
    let o = raylab(&[
        "render",
        "--scene",
        example,
        "--width",
        "64",
        "--height",
        "48",
        "--step",
        "shadows",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (w, h, px) = read_png(&out);
    assert_eq!((w, h), (64, 48));
    // The white sphere on the short block: the image differs from the plain Cornell box.
    let plain = dir.path().join("plain.png");
    let args = [
        "render", "--width", "64", "--height", "48", "--step", "shadows", "--out",
    ];
    let o = raylab(&[&args[..], &[plain.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let differ = (px.chunks(4).zip(read_png(&plain).2.chunks(4)))
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        differ > 100,
        "{differ} pixels differ from the box without spheres"
    );

    // A bad scene: exit 2, file and line, no image.
    let bad = write(
        dir.path(),
        "bad.scene",
        "cornell\npush\nscale 1 2 1\nsphere 0 0 0 1\n",
    );
    let out = dir.path().join("bad.png");
    let o = raylab(&["render", "--scene", &bad, "--out", out.to_str().unwrap()]);
    assert_fails(&o, 2, &["bad.scene:4:", "non-uniform scale"]);
    assert!(!out.exists());

    // trace: the triangle z = 0 moved to z = 5 by the stack, then turned a quarter about z
    // (exact); the ray along +z from the origin hits it at t = 5 exactly.
    let scene = write(
        dir.path(),
        "moved.scene",
        "translate 0 0 5\nrotate z 90\ntri -1 -1 0 1 -1 0 0 1 0\n",
    );
    let rays = write(
        dir.path(),
        "rays.txt",
        "0 0 0 0 0 1 0 inf\n0 0 0 0 0 -1 0 inf\n",
    );
    let o = raylab(&["trace", "--scene", &scene, "--rays", &rays]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout), "hit 5 0\nmiss\n");
    // In f64 the same primitive; t within the stated bound (tests/rounded_t.rs holds it to
    // the correctly rounded t).
    let o = raylab(&[
        "trace",
        "--scene",
        &scene,
        "--rays",
        &rays,
        "--precision",
        "f64",
    ]);
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let t: f64 = text.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!(
        text.ends_with(" 0\nmiss\n") && (t - 5.0).abs() < 1e-14,
        "{text}"
    );
}

#[test]
fn test_only_flags_stay_out_of_the_help_and_out_has_a_short_form() {
    let help = String::from_utf8_lossy(&raylab(&["--help"]).stdout).into_owned();
    for hidden in ["--frames", "--screenshot", "--script"] {
        assert!(!help.contains(hidden), "{hidden} in the help:\n{help}");
    }
    assert!(help.contains(".scene"), "{help}");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    let o = raylab(&[
        "render",
        "--width",
        "16",
        "--height",
        "8",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_png(&out).0, 16);
}

/// Runs raylab with a deadline: a hang fails the test instead of stalling it.
fn raylab_within(args: &[&str], seconds: u64) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs() >= seconds {
            child.kill().unwrap();
            panic!("raylab {args:?} still running after {seconds} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn special_files_are_refused_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        assert!(std::env::var("CI").is_err(), "CI=true but mkfifo failed");
        eprintln!("*** SKIPPED: mkfifo is not available ***");
        return;
    }
    let fifo = fifo.to_str().unwrap();
    let rays = write(dir.path(), "rays.txt", "0 0 0 0 0 1 0 inf\n");
    let scene = write(dir.path(), "s.scene", "tri 0 0 1 1 0 1 0 1 1\n");
    let png = dir.path().join("o.png");
    let png = png.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["trace", "--scene", fifo, "--rays", &rays], "is a FIFO"),
        (&["trace", "--scene", &scene, "--rays", fifo], "is a FIFO"),
        (
            &["trace", "--scene", "/dev/zero", "--rays", &rays],
            "is a device",
        ),
        (&["render", "--scene", fifo, "-o", png], "is a FIFO"),
        (
            &["render", "--scene", "/dev/zero", "-o", png],
            "is a device",
        ),
        (
            &["render", "--width", "8", "--height", "8", "-o", fifo],
            "is a FIFO",
        ),
    ];
    for (args, needle) in cases {
        let o = raylab_within(args, 20);
        assert_fails(&o, 2, &[needle, "not a regular file"]);
    }
    // A material library that is a FIFO or a device: a warning naming it, the model loads.
    for mtl in [fifo, "/dev/zero"] {
        let obj = write(
            dir.path(),
            "m.obj",
            &format!("mtllib {mtl}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        );
        let o = raylab_within(&["render", "--scene", &obj, "-o", png], 20);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("material library skipped"),
            "{}",
            stderr(&o)
        );
    }
    // /dev/null stays a fine place to write to.
    let o = raylab_within(
        &["render", "--width", "8", "--height", "8", "-o", "/dev/null"],
        20,
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn every_input_is_capped_and_a_byte_order_mark_is_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let rays = write(dir.path(), "rays.txt", "0 0 0 0 0 1 0 inf\n");
    let scene = write(dir.path(), "s.scene", "tri -1 -1 2 1 -1 2 0 1 2\n");
    let o = raylab_env(
        &["trace", "--scene", &scene, "--rays", &rays],
        &[("RAYLAB_MAX_INPUT_BYTES", "10")],
    );
    assert_fails(&o, 2, &["s.scene", "larger than the 10-byte limit"]);
    // A limit that is not a whole number is refused, naming the variable and the value.
    for (var, value) in [
        ("RAYLAB_MAX_INPUT_BYTES", "10k"),
        ("RAYLAB_MAX_TRIANGLES", "-5"),
        ("RAYLAB_MAX_TRIANGLES", ""),
        ("RAYLAB_MAX_PLACEMENTS", "1e6"),
    ] {
        let o = raylab_env(
            &["trace", "--scene", &scene, "--rays", &rays],
            &[(var, value)],
        );
        assert_fails(&o, 2, &[var, &format!("'{value}'"), "not a whole number"]);
    }
    // A UTF-8 BOM at the start of a scene, ray or OBJ file is not part of the first line.
    let scene = write(
        dir.path(),
        "bom.scene",
        "\u{feff}tri -1 -1 2 1 -1 2 0 1 2\n",
    );
    let rays = write(dir.path(), "bom.txt", "\u{feff}0 0 0 0 0 1 0 inf\n");
    let o = raylab(&["trace", "--scene", &scene, "--rays", &rays]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout), "hit 2 0\n");
    let obj = write(
        dir.path(),
        "bom.obj",
        "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let png = dir.path().join("bom.png");
    let o = raylab(&["render", "--scene", &obj, "-o", png.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn ctrl_c_stops_a_long_render_cleanly_and_no_progress_bar_is_drawn_off_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("big.png");
    // Seconds of work: 4096x4096, 2x2 samples, the lecture's method per ray.
    let child = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args([
            "render", "--width", "4096", "--height", "4096", "--spp", "2",
        ])
        .args(["--method", "cramer", "-o", out.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Past the loading, into the render (the handler is set); nothing is written until the
    // image is whole (tests/outputs.rs).
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let start = std::time::Instant::now();
    let o = child.wait_with_output().unwrap();
    assert!(
        start.elapsed().as_secs() < 20,
        "stopped within a band or two"
    );
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("interrupted: nothing written"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists(), "no half-written or empty PNG is left");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nor a temporary file"
    );
    // Not a terminal: no progress bar or escape codes in the output of a large render.
    let o = raylab(&[
        "render",
        "--width",
        "2048",
        "--height",
        "2048",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !stderr(&o).contains('\u{1b}') && !stderr(&o).contains("ETA"),
        "{}",
        stderr(&o)
    );
}

/// A little `.npy` reader (format 1.0, little-endian, C order): (descr, shape, data bytes).
fn read_npy(path: &Path) -> (String, Vec<usize>, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00", "magic and version");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!((10 + len) % 64, 0, "header padded to 64 bytes");
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(header.contains("'fortran_order': False") && header.ends_with('\n'));
    let descr = header
        .split("'descr': '")
        .nth(1)
        .unwrap()
        .split('\'')
        .next()
        .unwrap();
    let shape = header
        .split("'shape': (")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap();
    let shape = (shape.split(',').map(str::trim).filter(|s| !s.is_empty()))
        .map(|s| s.parse().unwrap())
        .collect();
    (descr.to_string(), shape, bytes[10 + len..].to_vec())
}

#[test]
fn aovs_say_what_each_pixel_saw() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("box.png");
    let (w, h) = (40usize, 30usize);
    let o = raylab(&[
        "render",
        "--width",
        "40",
        "--height",
        "30",
        "--aov",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (descr, shape, prim) = read_npy(&dir.path().join("box.prim.npy"));
    assert_eq!((descr.as_str(), shape), ("<u4", vec![h, w]));
    let prim: Vec<u32> = prim
        .chunks(4)
        .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let (descr, shape, t) = read_npy(&dir.path().join("box.t.npy"));
    assert_eq!((descr.as_str(), shape), ("<f4", vec![h, w]));
    let t: Vec<f32> = t
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let (descr, shape, n) = read_npy(&dir.path().join("box.normal.npy"));
    assert_eq!((descr.as_str(), shape), ("<f4", vec![h, w, 3]));
    let n: Vec<f32> = n
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let (_, _, png) = read_png(&out);
    let scene = raylab::Scene::cornell();
    let o_cam = [0.0, 0.0, -3.001f32 as f64];
    let mut hits = 0;
    for k in 0..w * h {
        // The flat image shows each pixel's primitive colour.
        let colour = prim.get(k).and_then(|p| scene.colors().get(*p as usize));
        let expect = colour.map_or([0, 0, 0], |c| c.map(raylab::render::linear_to_srgb8));
        assert_eq!(&png[4 * k..4 * k + 3], &expect, "pixel {k}");
        let Some(raylab::geometry::Shape::Triangle(v)) = scene.shapes.get(prim[k] as usize) else {
            assert!(prim[k] == u32::MAX && t[k].is_nan());
            continue;
        };
        hits += 1;
        // t against the plane of that triangle, in f64, along the unit pixel-centre ray.
        let (i, j) = ((k % w) as f64, (k / w) as f64);
        let d = [i + 0.5 - w as f64 / 2.0, j + 0.5 - h as f64 / 2.0, w as f64];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let d = d.map(|c| c / len);
        let v = v.map(|p| p.map(f64::from));
        let e1 = [0, 1, 2].map(|a| v[1][a] - v[0][a]);
        let e2 = [0, 1, 2].map(|a| v[2][a] - v[0][a]);
        let nn = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let t_ref = dot([0, 1, 2].map(|a| v[0][a] - o_cam[a]), nn) / dot(d, nn);
        assert!(
            (t[k] as f64 - t_ref).abs() <= 1e-5 * t_ref,
            "pixel {k}: t {} vs {t_ref}",
            t[k]
        );
        let nk = [n[3 * k] as f64, n[3 * k + 1] as f64, n[3 * k + 2] as f64];
        assert!((dot(nk, nk) - 1.0).abs() < 1e-6, "unit normal");
        assert!(dot(nk, d) < 0.0, "facing the camera");
        let nn_len = dot(nn, nn).sqrt();
        assert!(
            (dot(nk, nn) / nn_len).abs() > 1.0 - 1e-6,
            "the triangle's normal"
        );
    }
    assert!(hits > w * h / 2, "{hits} hits");
}

#[test]
fn trace_answers_through_every_per_ray_path_alike() {
    // A cube of 4x4 quads per face (its shared edges and vertices the hard cases) with a
    // sphere in and beside it; rays from several origins through every vertex and edge
    // midpoint. The reference loop, the flat SIMD loop and the BVH name the same primitive
    // for every ray, with t equal to within the stated bound.
    use raylab::geometry::Shape;
    let dir = tempfile::tempdir().unwrap();
    let mut shapes = common::cube(4, 1.0, [-0.5, -0.5, -0.5]);
    shapes.push(Shape::Sphere {
        centre: [0.0, 0.0, 0.0],
        radius: 0.25,
    });
    shapes.push(Shape::Sphere {
        centre: [1.5, 0.0, 0.0],
        radius: 0.5,
    });
    let scene = common::scene_text(&shapes);
    let mut rays = String::new();
    for o in [
        [0.0f32, 0.0, -3.0],
        [2.0, 1.5, -2.5],
        [0.1, 0.2, 0.05],
        [-3.0, 0.25, 0.5],
    ] {
        for p in common::vertices_and_edge_midpoints(&shapes) {
            let d = [0, 1, 2].map(|k| p[k] - o[k]);
            rays += &format!(
                "{} {} {} {} {} {} 0 inf\n",
                o[0], o[1], o[2], d[0], d[1], d[2]
            );
        }
    }
    let scene = write(dir.path(), "cube.scene", &scene);
    let rays = write(dir.path(), "rays.txt", &rays);
    let run = |accel: &str| {
        let o = raylab(&[
            "trace", "--scene", &scene, "--rays", &rays, "--accel", accel,
        ]);
        assert!(o.status.success(), "{accel}: {}", stderr(&o));
        String::from_utf8(o.stdout).unwrap()
    };
    let reference = run("reference");
    let lines = reference.lines().count();
    assert!(lines > 400, "{lines} rays");
    assert!(reference.lines().filter(|l| l.starts_with("hit")).count() > lines / 2);
    for accel in ["flat", "bvh", "auto", "packets"] {
        same_answers(accel, &reference, &run(accel));
    }
    let o = raylab(&[
        "trace",
        "--scene",
        &scene,
        "--rays",
        &rays,
        "--accel",
        "bvh",
        "--precision",
        "f64",
    ]);
    assert_fails(&o, 2, &["f32 only"]);
}

#[test]
fn the_light_can_be_set_as_the_panel_sets_it() {
    let dir = tempfile::tempdir().unwrap();
    let png = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args = vec![
            "render", "--width", "48", "--height", "36", "--step", "shadows",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", out.to_str().unwrap()]);
        let o = raylab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        read_png(&out).2
    };
    let default = png("default.png", &[]);
    // The lab's light, given explicitly: the same image.
    assert!(default == png("lab.png", &["--light", "0,-0.5,-0.7"]));
    let moved = png("moved.png", &["--light", "0.6,-0.5,-0.7"]);
    let differ = default
        .chunks(4)
        .zip(moved.chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > 200, "{differ} pixels changed with the light");
    assert_fails(
        &raylab(&["render", "--light", "1e39,0,0", "-o", "x.png"]),
        2,
        &["light position", "1e39", "beyond"],
    );
}

#[test]
fn view_files_render_and_round_trip() {
    use raylab::view::View;
    let dir = tempfile::tempdir().unwrap();
    let text = "# a view\nscene cornell\ncamera 0.25 -0.1 -2.5 yaw 12.5 pitch -3 fov 61\n\
                light 0.3 -0.6 -0.5\nsize 48 36\nstep shadows\nspp 2\nmethod watertight\ncracks off\n";
    let view = View::parse("v.view", text).unwrap();
    assert_eq!(
        View::parse("again", &view.to_text()).unwrap(),
        view,
        "round trip"
    );
    let path = write(dir.path(), "v.view", text);
    let out = dir.path().join("v.png");
    let o = raylab(&["render", "--view", &path, "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The same through flags: the same image.
    let flags = dir.path().join("f.png");
    let o = raylab(&[
        "render",
        "--camera",
        "0.25,-0.1,-2.5",
        "--yaw",
        "12.5",
        "--pitch",
        "-3",
        "--focal",
        &(48.0 / (2.0 * (61f64.to_radians() / 2.0).tan())).to_string(),
        "--light",
        "0.3,-0.6,-0.5",
        "--width",
        "48",
        "--height",
        "36",
        "--step",
        "shadows",
        "--spp",
        "2",
        "--method",
        "watertight",
        "-o",
        flags.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(read_png(&out) == read_png(&flags));
    // Flags that the view sets conflict with it; a bad line names itself.
    let o = raylab(&["render", "--view", &path, "--width", "10", "-o", "x.png"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--width") && stderr(&o).contains("--view"),
        "{}",
        stderr(&o)
    );
    let bad = write(dir.path(), "bad.view", "scene cornell\n\nzoom 2\n");
    assert_fails(
        &raylab(&["render", "--view", &bad, "-o", "x.png"]),
        2,
        &["bad.view:3:", "zoom"],
    );
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
            &["scaled.scene", "triangle 0", "1000000000000"],
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
    let o = raylab(&[
        "render",
        "--scene",
        &big,
        "--step",
        "shadows",
        "--width",
        "64",
        "--height",
        "48",
        "-o",
        "/dev/null",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_closed_pipe_ends_the_output_quietly() {
    // `raylab trace … | head -1`: the reader goes away while 2 MB of answers are still to
    // come. The program stops with the shell's SIGPIPE status, without a panic message.
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "tri.txt", "tri 0 0 5 1 0 5 0 1 5\n");
    let rays = write(
        dir.path(),
        "rays.txt",
        &"0.1 0.1 0 0 0 1 0 inf\n".repeat(200_000),
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(["trace", "--scene", &scene, "--rays", &rays])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = child.stdout.take().unwrap();
    let mut first = [0u8; 10];
    std::io::Read::read_exact(&mut out, &mut first).unwrap();
    assert_eq!(&first, b"hit 5 0\nhi");
    drop(out);
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(141), "{}", stderr(&o));
    assert_eq!(stderr(&o), "");
}

/// The `name: value` lines of `raylab inspect`.
fn fields(out: &str) -> std::collections::HashMap<String, String> {
    out.lines()
        .filter_map(|l| l.split_once(": "))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

#[test]
fn inspect_prints_one_pixels_ray_as_the_lecture_writes_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let args = ["--width", "64", "--height", "48", "--step", "shadows"];
    // The centre pixel of the lab view hits the back wall; its numbers against the render's
    // AOVs for the same pixel.
    let mut render = vec!["render", "-o", out.to_str().unwrap(), "--aov"];
    render.extend_from_slice(&args);
    assert!(raylab(&render).status.success());
    let prim = std::fs::read(dir.path().join("x.prim.npy")).unwrap();
    let t = std::fs::read(dir.path().join("x.t.npy")).unwrap();
    let at = |bytes: &[u8], k: usize| {
        let data = &bytes[bytes.len() - 4 * 64 * 48..];
        [
            data[4 * k],
            data[4 * k + 1],
            data[4 * k + 2],
            data[4 * k + 3],
        ]
    };
    for (i, j) in [(32u32, 24u32), (5, 40), (50, 10), (20, 30)] {
        let mut cmd = vec!["inspect".to_string(), "--pixel".into(), format!("{i},{j}")];
        cmd.extend(args.iter().map(|s| s.to_string()));
        let o = raylab(&cmd.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(o.status.success(), "{}", stderr(&o));
        let f = fields(&String::from_utf8_lossy(&o.stdout));
        assert_eq!(f["pixel"], format!("{i} {j}"));
        let uvf: Vec<f64> = f["uvf"].split(' ').map(|x| x.parse().unwrap()).collect();
        assert_eq!(uvf, [i as f64 + 0.5 - 32.0, j as f64 + 0.5 - 24.0, 64.0]);
        let k = (j * 64 + i) as usize;
        assert_eq!(
            f["hit"].parse::<u32>().unwrap(),
            u32::from_le_bytes(at(&prim, k))
        );
        assert_eq!(
            f["t"].parse::<f32>().unwrap(),
            f32::from_le_bytes(at(&t, k))
        );
        assert_eq!(f["shape"], "triangle");
        // The exact t as `raylab trace` prints it for the same ray.
        let (o, d) = (&f["origin"], &f["d_world"]);
        let rays = dir.path().join("ray.txt");
        std::fs::write(&rays, format!("{o} {d} 0 inf\n")).unwrap();
        let scene = dir.path().join("box.scene");
        std::fs::write(&scene, "cornell\n").unwrap();
        let o = raylab(&[
            "trace",
            "--scene",
            scene.to_str().unwrap(),
            "--rays",
            rays.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(
            stdout(&o).trim(),
            format!("hit {} {}", f["t_exact"], f["hit"])
        );
        for key in [
            "A_row0", "b", "x_tuv", "point", "normal", "rho", "D", "N", "colour",
        ] {
            assert!(f.contains_key(key), "{key} missing");
        }
        assert_eq!(f["step"], "shadows");
    }
    // A sphere shows its quadratic.
    let scene = write(dir.path(), "s.scene", "sphere 0 0 0 1\n");
    let o = raylab(&["inspect", "--scene", &scene, "--pixel", "320,240"]);
    let f = fields(&String::from_utf8_lossy(&o.stdout));
    assert_eq!(f["shape"], "sphere", "{}", stderr(&o));
    assert!(f["discriminant"].parse::<f64>().unwrap() > 0.0);
    // A pixel outside the image is an error naming it.
    let o = raylab(&["inspect", "--pixel", "640,3"]);
    assert_fails(&o, 2, &["pixel (640, 3) is outside the 640x480 image"]);
    let o = raylab(&["inspect", "--pixel", "a,3"]);
    assert_fails(&o, 2, &["'a,3'"]);
}

#[test]
fn a_views_command_line_renders_the_view_through_a_shell() {
    // "Copy as command": the line a view turns into, run by a POSIX shell, renders what
    // `--view` renders, with a scene path holding a space and a quote, a negative position,
    // a turned camera, a moved light and a field of view.
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("it's here");
    std::fs::create_dir(&sub).unwrap();
    let scene = write(&sub, "s.scene", "cornell\nsphere 0.3 0.4 0.2 0.25\n");
    let view_text = format!(
        "scene {scene}\ncamera -0.25 -0.1 -2.5 yaw -12.5 pitch 3 fov 61\nlight 0.2 -0.6 -0.5\n\
         size 96 72\nstep shadows\nspp 2\nmethod adaptive\n"
    );
    let view = raylab::view::View::parse("v.view", &view_text).unwrap();
    let command = view.to_command("from command.png");
    assert!(
        command.contains("'") && command.contains("--yaw=-12.5"),
        "{command}"
    );
    let o = common::run_in_shell(&command, dir.path(), env!("CARGO_BIN_EXE_raylab"));
    assert!(o.status.success(), "{command}\n{}", stderr(&o));
    let view_file = write(dir.path(), "v.view", &view_text);
    let from_view = dir.path().join("from view.png");
    let o = raylab(&[
        "render",
        "--view",
        &view_file,
        "-o",
        from_view.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let a = std::fs::read(dir.path().join("from command.png")).unwrap();
    let b = std::fs::read(&from_view).unwrap();
    assert!(a == b, "the command and the view render the same PNG");
    assert_eq!(raylab::view::shell_quote("a'b c"), "'a'\\''b c'");
    assert_eq!(
        raylab::view::shell_quote("plain/path-1.obj"),
        "plain/path-1.obj"
    );
}

#[test]
fn every_image_control_reaches_the_image_through_the_view_file_and_the_command() {
    // The controls table drives the `.view` file, copy-as-command and the flags: each value of
    // each control, set in a view, renders through `--view` and through the view's command
    // line to the same PNG, and the render's report names the value.
    let dir = tempfile::tempdir().unwrap();
    let base = "scene cornell\nsize 40 30\nstep shadows\n";
    let help = stdout(&raylab(&["render", "--help"]));
    for control in &raylab::render::CONTROLS {
        assert!(
            help.contains(&format!("--{}", control.name)),
            "{}",
            control.name
        );
        for value in control.sample_values() {
            let text = format!("{base}{} {value}\n", control.name);
            let view = raylab::view::View::parse("v.view", &text).unwrap();
            assert_eq!(control.text(&view.settings), value);
            let file = write(dir.path(), "v.view", &view.to_text());
            let (a, b) = (dir.path().join("view.png"), dir.path().join("command.png"));
            let o = raylab(&["render", "--view", &file, "-o", a.to_str().unwrap()]);
            assert!(o.status.success(), "{}", stderr(&o));
            let said = format!("{}={value} ", control.name);
            assert!(stdout(&o).contains(&said), "{said}\n{}", stdout(&o));
            let command = view.to_command(b.to_str().unwrap());
            let words: Vec<&str> = command.split(' ').skip(1).collect();
            let o = raylab(&words);
            assert!(o.status.success(), "{command}\n{}", stderr(&o));
            assert!(stdout(&o).contains(&said), "{command}\n{}", stdout(&o));
            assert!(read_png(&a) == read_png(&b), "{command}");
        }
    }
    // A bad value in a view names the line and what the control takes.
    let bad = write(dir.path(), "bad.view", &format!("{base}spp 0\n"));
    assert_fails(
        &raylab(&["render", "--view", &bad, "-o", "x.png"]),
        2,
        &["bad.view:4:", "supersampling 0 is out of range"],
    );
    let bad = write(dir.path(), "bad.view", &format!("{base}cracks maybe\n"));
    assert_fails(
        &raylab(&["render", "--view", &bad, "-o", "x.png"]),
        2,
        &["bad.view:4:", "cracks is on or off, not 'maybe'"],
    );
}

#[test]
fn trace_answers_through_instances_as_the_reference_loop() {
    // A mesh (a cube of 4x4 quads per face, 96 triangles) used three times, turned by any
    // angle: `trace --accel ...` places it as instances (one stored mesh), `--accel reference`
    // flattens it. Rays through every world vertex and edge midpoint: the same primitives,
    // t within the stated bound.
    use raylab::geometry::Shape;
    let dir = tempfile::tempdir().unwrap();
    let cube = common::cube(4, 1.0, [-0.5, -0.5, -0.5]);
    let mut obj = String::new();
    for (i, s) in cube.iter().enumerate() {
        let Shape::Triangle(v) = s else {
            unreachable!()
        };
        for p in v {
            obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
        }
        obj += &format!("f {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3);
    }
    write(dir.path(), "cube.obj", &obj);
    let text = "sphere 0 0 0 0.3\n\
                push\nrotate y 30\nmesh cube.obj\npop\n\
                push\ntranslate 1.2 0 0.4\nrotate x 17\nscale 0.5\nmesh cube.obj\npop\n\
                tri -3 -3 2 3 -3 2 0 3 2\n\
                push\ntranslate -1.1 0.2 0\nrotate z 90\nmesh cube.obj\npop\n";
    let scene_path = write(dir.path(), "cubes.scene", text);
    let scene = raylab::scene::load_scene_file(std::path::Path::new(&scene_path)).unwrap();
    assert_eq!(scene.instances().len(), 3);
    let flat = scene.flattened();
    let mut rays = String::new();
    for o in [[0.0f32, 0.0, -4.0], [2.5, 1.5, -2.5], [-3.0, 0.25, 0.5]] {
        for p in common::vertices_and_edge_midpoints(&flat.shapes) {
            let d = [0, 1, 2].map(|k| p[k] - o[k]);
            rays += &format!(
                "{} {} {} {} {} {} 0 inf\n",
                o[0], o[1], o[2], d[0], d[1], d[2]
            );
        }
    }
    let rays = write(dir.path(), "rays.txt", &rays);
    let run = |accel: &str| {
        let o = raylab(&[
            "trace",
            "--scene",
            &scene_path,
            "--rays",
            &rays,
            "--accel",
            accel,
        ]);
        assert!(o.status.success(), "{accel}: {}", stderr(&o));
        String::from_utf8(o.stdout).unwrap()
    };
    let reference = run("reference");
    let lines = reference.lines().count();
    assert!(lines > 1000, "{lines} rays");
    let instanced_hits = reference
        .lines()
        .filter_map(|l| l.split(' ').nth(2))
        .filter(|p| p.parse::<u32>().unwrap() >= 1)
        .count();
    assert!(instanced_hits > lines / 2, "{instanced_hits} of {lines}");
    for accel in ["flat", "bvh", "auto", "packets"] {
        same_answers(accel, &reference, &run(accel));
    }
    // With at most 200 primitives stored one by one: the flattened reference refuses the
    // scene (3 x 96 triangles), naming the line where the limit is passed; the instanced
    // structure answers as before.
    let limit = [("RAYLAB_MAX_TRIANGLES", "200")];
    let args = ["trace", "--scene", &scene_path, "--rays", &rays, "--accel"];
    let refused = raylab_env(&[&args[..], &["reference"]].concat(), &limit);
    assert_fails(&refused, 2, &["cubes.scene:", "more than 200 primitives"]);
    let placed = raylab_env(&[&args[..], &["auto"]].concat(), &limit);
    assert!(placed.status.success(), "{}", stderr(&placed));
    assert_eq!(String::from_utf8(placed.stdout).unwrap(), run("auto"));
}

#[test]
fn trace_packets_answer_as_the_reference_loop() {
    // `--accel packets`: rays sharing an origin go 8 at a time through the renderer's camera
    // packets. The Cornell box (30 triangles: the small scene's prepared triangles and the
    // exact-edge resolver) and a 96-triangle cube mesh (the BVH packets, triangles prepared
    // for the origin), rays from two origins through every vertex and edge midpoint (where
    // the packets leave lanes ambiguous) and a few with other tmin/tmax (per ray).
    use raylab::geometry::Shape;
    let dir = tempfile::tempdir().unwrap();
    let cube = common::cube(4, 1.0, [-0.5, -0.5, -0.5]);
    let mut text = String::new();
    for s in &cube {
        let Shape::Triangle(v) = s else {
            unreachable!()
        };
        let nums: Vec<String> = v.iter().flatten().map(|x| x.to_string()).collect();
        text += &format!("tri {}\n", nums.join(" "));
    }
    let cases = [
        (
            "cornell.scene",
            "cornell\n".to_string(),
            raylab::Scene::cornell().shapes,
            [[0.0f32, 0.0, -3.001], [0.3, -0.2, -2.0]],
        ),
        (
            "cube.scene",
            text,
            cube,
            [[0.0, 0.0, -3.0], [2.0, 1.5, -2.5]],
        ),
    ];
    for (name, scene_text, shapes, origins) in cases {
        let scene = write(dir.path(), name, &scene_text);
        let mut rays = String::new();
        for o in origins {
            for p in common::vertices_and_edge_midpoints(&shapes) {
                let d = [0, 1, 2].map(|k| p[k] - o[k]);
                rays += &format!(
                    "{} {} {} {} {} {} 0 inf\n",
                    o[0], o[1], o[2], d[0], d[1], d[2]
                );
            }
        }
        rays += "0 0 -3 0.1 0.1 1 0.5 inf\n0 0 -3 0.1 0.1 1 0 3\n";
        let rays = write(dir.path(), "rays.txt", &rays);
        let run = |accel: &str| {
            let o = raylab(&[
                "trace", "--scene", &scene, "--rays", &rays, "--accel", accel,
            ]);
            assert!(o.status.success(), "{accel}: {}", stderr(&o));
            String::from_utf8(o.stdout).unwrap()
        };
        let reference = run("reference");
        let packets = run("packets");
        let lines = reference.lines().count();
        assert!(lines > 100, "{name}: {lines} rays");
        assert!(reference.lines().filter(|l| l.starts_with("hit")).count() > lines / 2);
        same_answers(name, &reference, &packets);
        // The same rays as shadow segments (tmin 0, tmax 1) through the shadow packets: ending
        // on the vertex or edge midpoint they were aimed at, and halfway there.
        let mut segments = String::new();
        for line in std::fs::read_to_string(&rays).unwrap().lines() {
            let w: Vec<f32> = line
                .split(' ')
                .take(6)
                .map(|x| x.parse().unwrap())
                .collect();
            for s in [1.0, 0.5] {
                let (o, d) = (&w[..3], w[3..].iter().map(|c| c * s));
                let d: Vec<String> = d.map(|c| c.to_string()).collect();
                segments += &format!("{} {} {} {} 0 1\n", o[0], o[1], o[2], d.join(" "));
            }
        }
        let segments = write(dir.path(), "segments.txt", &segments);
        let any = |accel: &str| {
            let o = raylab(&[
                "trace", "--scene", &scene, "--rays", &segments, "--accel", accel, "--query", "any",
            ]);
            assert!(o.status.success(), "{accel}: {}", stderr(&o));
            String::from_utf8(o.stdout).unwrap()
        };
        let (reference, packets) = (any("reference"), any("packets"));
        let blocked = reference.lines().filter(|l| *l == "hit").count();
        let lines = reference.lines().count();
        assert!(
            blocked > 10 && lines - blocked > 10,
            "{name}: {blocked} of {lines} blocked"
        );
        same_answers(&format!("{name} segments"), &reference, &packets);
    }
    let scene = write(dir.path(), "c.scene", "cornell\n");
    let rays = write(dir.path(), "r.txt", "0 0 -3 0 0 1 0 inf\n");
    let o = raylab(&[
        "trace", "--scene", &scene, "--rays", &rays, "--accel", "packets", "--method", "moller",
    ]);
    assert_fails(&o, 2, &["adaptive method only"]);
}

/// Two `trace` outputs are the same: the same primitive (or miss) for every ray, the same t.
fn same_answers(what: &str, reference: &str, other: &str) {
    // The adaptive method prints the exact t correctly rounded through every path, so the
    // answers are the same text, t to the last bit.
    assert_eq!(
        reference.lines().count(),
        other.lines().count(),
        "{what}: line count"
    );
    for (a, b) in reference.lines().zip(other.lines()) {
        assert_eq!(a, b, "{what}");
    }
}

#[test]
fn the_hard_case_suite_through_every_trace_path() {
    // Every family of the hard-case suite (tests/common/suite.rs) written as a scene file and
    // a ray file (f32 values in shortest round-trip form, so they parse to the same bits),
    // answered by `raylab trace` through each path, and scored against the suite's exact
    // rational reference: the adaptive method gives 0 wrong answers through all of them, and
    // every t printed is the exact t correctly rounded to f32.
    use common::suite::{self, exact_nearest, Counts};
    let dir = tempfile::tempdir().unwrap();
    let paths = ["reference", "flat", "bvh", "auto", "packets"];
    let (mut rays_total, mut segment_ends) = (0, (0, 0, 0));
    for family in suite::all() {
        let scene = common::scene_text(&family.shapes);
        let mut rays = String::new();
        for r in &family.rays {
            let (o, d) = (r.o, r.d);
            rays += &format!(
                "{} {} {} {} {} {} 0 inf\n",
                o[0], o[1], o[2], d[0], d[1], d[2]
            );
        }
        let scene = write(dir.path(), "family.scene", &scene);
        let rays = write(dir.path(), "family.rays", &rays);
        let exact: Vec<_> = family
            .rays
            .iter()
            .map(|r| exact_nearest(&family.shapes, r))
            .collect();
        for path in paths {
            let o = raylab(&["trace", "--scene", &scene, "--rays", &rays, "--accel", path]);
            assert!(o.status.success(), "{} {path}: {}", family.name, stderr(&o));
            let out = String::from_utf8(o.stdout).unwrap();
            assert_eq!(
                out.lines().count(),
                family.rays.len(),
                "{} {path}",
                family.name
            );
            let (mut counts, mut not_rounded) = (Counts::default(), 0);
            for ((line, ray), exact) in out.lines().zip(&family.rays).zip(&exact) {
                let words: Vec<&str> = line.split(' ').collect();
                let got = (words[0] == "hit").then(|| {
                    (
                        words[1].parse::<f64>().unwrap(),
                        words[2].parse::<u32>().unwrap(),
                    )
                });
                counts.add(&family.shapes, ray, exact, got);
                if let (Some((t, prim)), Some((_, gprim))) = (exact, got) {
                    let printed: f32 = words[1].parse().unwrap();
                    if *prim == gprim && t.rounded::<f32>() != Some(printed) {
                        not_rounded += 1;
                    }
                }
            }
            assert_eq!(
                not_rounded, 0,
                "{} through {path}: t not correctly rounded",
                family.name
            );
            assert_eq!(
                counts.wrong(),
                0,
                "{} through {path}: {} leaks, {} false hits, {} wrong nearest, {} pass-through",
                family.name,
                counts.leaks,
                counts.false_hits,
                counts.wrong_nearest,
                counts.pass_through
            );
        }
        rays_total += family.rays.len();
        let ends = shadow_segments_through_every_path(dir.path(), &scene, &family, &exact, paths);
        segment_ends.0 += ends.0;
        segment_ends.1 += ends.1;
        segment_ends.2 += ends.2;
    }
    assert!(rays_total > 10_000, "{rays_total} rays");
    let (hits, misses, on_the_hit) = segment_ends;
    println!("segments: {hits} blocked, {misses} clear, {on_the_hit} ending exactly on the hit");
    assert!(hits > 5_000 && misses > 5_000 && on_the_hit > 100);
}

/// The family's rays as shadow segments (`--query any`, tmin 0, tmax 1): the direction scaled
/// by 2ᵏ (exactly) so the segment ends at t = 2ᵏ of the ray, for the two powers of two around
/// the exact nearest t (1 for a miss); a segment is blocked exactly where the nearest t < 2ᵏ.
/// Rays from one origin go through the renderer's shadow packets (`--accel packets`). Returns
/// (blocked, clear, ending exactly on the nearest hit) segments.
fn shadow_segments_through_every_path(
    dir: &Path,
    scene: &str,
    family: &common::suite::Family,
    exact: &[Option<(common::suite::RefT, u32)>],
    paths: [&str; 5],
) -> (usize, usize, usize) {
    use common::suite::{q, RefT};
    let (mut text, mut want) = (String::new(), Vec::new());
    let mut on_the_hit = 0;
    for (r, exact) in family.rays.iter().zip(exact) {
        let powers = match exact {
            Some((t, _)) => {
                let k = t.f64().log2().floor().clamp(-140.0, 120.0) as i32;
                vec![k, k + 1]
            }
            None => vec![0],
        };
        for k in powers {
            let scale = 2f32.powi(k);
            let d = r.d.map(|c| c * scale);
            let exact_scaling = d
                .iter()
                .zip(r.d)
                .all(|(a, b)| a / scale == b && a.is_finite());
            if !exact_scaling || d == [0.0; 3] || !scale.is_finite() || scale == 0.0 {
                continue;
            }
            let end = RefT::Exact(q(scale));
            let blocked = exact
                .as_ref()
                .is_some_and(|(t, _)| t.cmp(&end) == std::cmp::Ordering::Less);
            on_the_hit += exact
                .as_ref()
                .is_some_and(|(t, _)| t.cmp(&end) == std::cmp::Ordering::Equal)
                as usize;
            let o = r.o;
            text += &format!(
                "{} {} {} {} {} {} 0 1\n",
                o[0], o[1], o[2], d[0], d[1], d[2]
            );
            want.push(if blocked { "hit" } else { "miss" });
        }
    }
    let rays = write(dir, "family.segments", &text);
    for path in paths {
        let o = raylab(&[
            "trace", "--scene", scene, "--rays", &rays, "--accel", path, "--query", "any",
        ]);
        assert!(o.status.success(), "{} {path}: {}", family.name, stderr(&o));
        let out = String::from_utf8(o.stdout).unwrap();
        let got: Vec<&str> = out.lines().collect();
        assert_eq!(got.len(), want.len(), "{} {path}", family.name);
        let wrong = got.iter().zip(&want).filter(|(g, w)| g != w).count();
        assert_eq!(
            wrong, 0,
            "{} segments through {path}: wrong blocked/clear",
            family.name
        );
    }
    let hits = want.iter().filter(|w| **w == "hit").count();
    (hits, want.len() - hits, on_the_hit)
}

#[test]
fn worker_threads_the_system_cannot_give_are_an_error_not_a_panic() {
    // One worker's 8 GiB stack (std's threads take RUST_MIN_STACK) does not fit in 2 GB of
    // address space, while the binary does: the first spawn fails, before any worker runs.
    // (Many small stacks instead race: a worker that started can abort allocating its signal
    // stack once the last spawn took the memory.)
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let o = Command::new("bash")
        .arg("-c")
        .arg(r#"ulimit -v 2000000 && exec "$0" render --width 8 --height 8 -o "$1""#)
        .arg(env!("CARGO_BIN_EXE_raylab"))
        .arg(&out)
        .env("RAYON_NUM_THREADS", "2")
        .env("RUST_MIN_STACK", (8u64 << 30).to_string())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("cannot start the worker threads"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists());
}

#[test]
fn any_scene_file_name_round_trips_through_a_view() {
    // Names with runs of spaces, '#', quotes and backslashes: a saved view names the same file
    // (quoted), renders the same image as the scene itself, and a `.scene` mesh path in quotes
    // loads.
    use raylab::view::View;
    let dir = tempfile::tempdir().unwrap();
    let tri = "camera 0 0 -3\ntri -1 -1 2 1 -1 2 0 1 2\n";
    for name in [
        "two  spaces.scene",
        "x#y.scene",
        "say \"hi\" \\ there.scene",
    ] {
        let scene = write(dir.path(), name, tri);
        let decoy = dir.path().join("x"); // what '#' used to cut "x#y.scene" down to
        std::fs::write(&decoy, "camera 0 0 -3\nsphere 0 0 2 1\n").unwrap();
        let mut view = View::parse("v.view", "size 32 24\n").unwrap();
        view.scene = scene.clone();
        let text = view.to_text();
        assert_eq!(View::parse("again", &text).unwrap(), view, "{text}");
        let view_file = write(dir.path(), "v.view", &text);
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        let o = raylab(&["render", "--view", &view_file, "-o", a.to_str().unwrap()]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let o = raylab(&[
            "render",
            "--scene",
            &scene,
            "--width",
            "32",
            "--height",
            "24",
            "-o",
            b.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        assert_eq!(
            std::fs::read(&a).unwrap(),
            std::fs::read(&b).unwrap(),
            "{name}"
        );
    }
    // A mesh path in quotes, and a broken quote named by its line.
    write(
        dir.path(),
        "my mesh.obj",
        "v -1 -1 2\nv 1 -1 2\nv 0 1 2\nf 1 2 3\n",
    );
    let s = write(
        dir.path(),
        "m.scene",
        "camera 0 0 -3\nmesh \"my mesh.obj\" lab # placed\n",
    );
    let out = dir.path().join("m.png");
    let o = raylab(&["render", "--scene", &s, "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = write(
        dir.path(),
        "bad.scene",
        "camera 0 0 -3\nmesh \"my mesh.obj\n",
    );
    let o = raylab(&["render", "--scene", &s, "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("bad.scene:2: a quoted word has no closing quote"),
        "{}",
        stderr(&o)
    );
}

/// An OBJ strip of `n` triangles (enough, from 64, for a repeated mesh to be placed as
/// instances).
fn strip_obj(n: usize) -> String {
    let mut text = String::new();
    for i in 0..n + 2 {
        text += &format!("v {} {} 0\n", i as f32 * 0.01, (i % 2) as f32 * 0.01);
    }
    for i in 1..=n {
        text += &format!("f {} {} {}\n", i, i + 1, i + 2);
    }
    text
}

#[test]
fn mesh_placements_are_capped_at_their_line() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.obj", &strip_obj(80));
    let scene = write(
        dir.path(),
        "s.scene",
        &"translate 0.1 0 0\nmesh m.obj\n".repeat(101),
    );
    let out = dir.path().join("s.png");
    let args = ["render", "--scene", &scene, "-o", out.to_str().unwrap()];
    let o = raylab_env(&args, &[("RAYLAB_MAX_PLACEMENTS", "100")]);
    assert_fails(&o, 2, &["s.scene:202:", "more than 100 mesh placements"]);
    assert!(!out.exists());
    let o = raylab_env(&args, &[("RAYLAB_MAX_PLACEMENTS", "101")]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn memory_grows_in_proportion_to_the_placements() {
    // Peak memory (GNU time's maximum resident set) of rendering 20,000 and 80,000 placements
    // of one mesh, each at its own spot: the 60,000 more may cost at most the stated budget,
    // 1 KiB a placement (for a 28-byte pair of lines).
    if !have_gnu_time() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.obj", &strip_obj(80));
    let peak_kib = |placements: usize| {
        let text = "translate 0.1 0 0\nmesh m.obj\n".repeat(placements);
        let scene = write(dir.path(), &format!("p{placements}.scene"), &text);
        peak_render_kib(&scene, &[])
    };
    let (small, large) = (peak_kib(20_000), peak_kib(80_000));
    let per_placement = (large.saturating_sub(small) * 1024) as f64 / 60_000.0;
    println!("{small} KiB, {large} KiB: {per_placement:.0} bytes a placement");
    assert!(
        per_placement <= 1024.0,
        "{per_placement:.0} bytes a placement"
    );
}

#[test]
fn repeated_cornell_boxes_cost_what_placements_cost() {
    // `cornell` is a mesh like any other: past the copies that are flattened (2^20 triangles),
    // 40,000 and 100,000 boxes each at its own spot differ by at most the placement budget,
    // 1 KiB a box (for a 26-byte pair of lines); flattened, a box took 3.3 KB.
    if !have_gnu_time() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let peak_kib = |boxes: usize| {
        let text = "translate 1.5 0 0\ncornell\n".repeat(boxes);
        let scene = write(dir.path(), &format!("c{boxes}.scene"), &text);
        peak_render_kib(&scene, &[])
    };
    let (small, large) = (peak_kib(40_000), peak_kib(100_000));
    let per_box = (large.saturating_sub(small) * 1024) as f64 / 60_000.0;
    println!("{small} KiB, {large} KiB: {per_box:.0} bytes a box");
    assert!(per_box <= 1024.0, "{per_box:.0} bytes a box");
}

/// Whether GNU time is there to measure peak memory.
fn have_gnu_time() -> bool {
    common::tool_for("/usr/bin/time", "time", "a memory test")
}

/// raylab run with `args` under GNU time: its output and its peak resident memory in KiB.
fn peak_kib(args: &[&str], env: &[(&str, &str)]) -> (Output, u64) {
    let o = Command::new("/usr/bin/time")
        .args(["-f", "peak_kib=%M", env!("CARGO_BIN_EXE_raylab")])
        .args(args)
        .envs(env.iter().copied())
        .output()
        .unwrap();
    let err = stderr(&o);
    let line = err.lines().find_map(|l| l.strip_prefix("peak_kib="));
    let peak = line.expect("GNU time's report").trim().parse().unwrap();
    (o, peak)
}

/// The peak resident memory (GNU time's) of rendering `scene` at 16x16, in KiB.
fn peak_render_kib(scene: &str, env: &[(&str, &str)]) -> u64 {
    let out = std::path::Path::new(scene).with_extension("png");
    let args = [
        "render", "--scene", scene, "--width", "16", "--height", "16", "-o",
    ];
    let (o, peak) = peak_kib(&[&args[..], &[out.to_str().unwrap()]].concat(), env);
    assert!(o.status.success(), "{}", stderr(&o));
    peak
}

#[test]
fn a_line_too_long_is_refused_at_its_line_before_it_is_split() {
    // A 32 MB `tri` line of 16 million numbers: refused naming the file, the line and its
    // length, in memory about the file's own size (splitting it into words took 30 times
    // that); a `.view` line the same.
    let dir = tempfile::tempdir().unwrap();
    let numbers = "1 ".repeat(16 << 20);
    let said = |line: &str| {
        let n = line.len();
        format!("line is {n} bytes long, more than the 1048576 a line may have")
    };
    let tri = format!("tri {numbers}");
    let scene = write(dir.path(), "s.scene", &format!("camera 0 0 -3\n{tri}\n"));
    let o = raylab(&["render", "--scene", &scene, "-o", "x.png"]);
    assert_fails(&o, 2, &["s.scene:2:", &said(&tri)]);
    let method = format!("method {numbers}");
    let view = write(
        dir.path(),
        "v.view",
        &format!("scene cornell\n\n{method}\n"),
    );
    let o = raylab(&["render", "--view", &view, "-o", "x.png"]);
    assert_fails(&o, 2, &["v.view:3:", &said(&method)]);
    let bytes = tri.len();
    if !have_gnu_time() {
        return;
    }
    let (o, peak_kib) = peak_kib(&["render", "--scene", &scene, "-o", "x.png"], &[]);
    assert_fails(&o, 2, &["s.scene:2:"]);
    println!("peak {peak_kib} KiB for a {bytes}-byte line");
    assert!(peak_kib * 1024 < 3 * bytes as u64, "{peak_kib} KiB");
}

#[test]
fn a_ray_line_of_millions_of_words_is_refused_without_splitting_it_all() {
    // `raylab trace` keeps at most 9 words of a ray line and counts the rest: 16 million
    // numbers on one line are refused at that line, in memory about the file's own size
    // (holding every word took 16 bytes a word, 8 times the file).
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "s.txt", "tri 0 0 1 1 0 1 0 1 1\n");
    let line = "1 ".repeat(16 << 20);
    let rays = write(dir.path(), "r.txt", &format!("0 0 0 0 0 1 0 inf\n{line}\n"));
    let args = ["trace", "--scene", &scene, "--rays", &rays];
    let o = raylab(&args);
    assert_fails(&o, 2, &["r.txt:2: ray needs 8 numbers, found 16777216"]);
    if !have_gnu_time() {
        return;
    }
    let (o, peak_kib) = peak_kib(&args, &[]);
    assert_fails(&o, 2, &["r.txt:2:"]);
    println!("peak {peak_kib} KiB for a {}-byte line", line.len());
    assert!(peak_kib * 1024 < 3 * line.len() as u64, "{peak_kib} KiB");
}

#[test]
fn the_scene_tree_stops_at_its_limit_and_the_file_renders_the_same() {
    // Ten levels of a sphere each, the tree limited to 8 entries: the render is the one
    // without a limit, and a warning names the line where the tree stopped. (The camera,
    // push, its level, sphere, pop, push, its level and sphere fill the 8 entries; the pop on
    // line 7 is the first left out, and the top level makes 9 listed.)
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("camera 0 0 -6\n");
    for k in 0..10 {
        text += &format!("push\nsphere {} 0 0 0.3\npop\n", k as f32 * 0.7 - 3.0);
    }
    let scene = write(dir.path(), "s.scene", &text);
    let render = |env: &[(&str, &str)], out: &str| {
        let out = dir.path().join(out);
        let args = [
            "render", "--scene", &scene, "--width", "64", "--height", "32", "-o",
        ];
        let o = raylab_env(&[&args[..], &[out.to_str().unwrap()]].concat(), env);
        assert!(o.status.success(), "{}", stderr(&o));
        (read_png(&out), stderr(&o))
    };
    let (whole, quiet) = render(&[], "a.png");
    assert!(!quiet.contains("scene tree"), "{quiet}");
    let (limited, said) = render(&[("RAYLAB_MAX_TREE_ENTRIES", "8")], "b.png");
    assert!(whole == limited, "the tree's limit changed the image");
    assert!(
        said.contains("s.scene:7: the scene tree lists the first 9 push levels and statements"),
        "{said}"
    );
    let o = raylab_env(
        &["render", "--scene", &scene, "-o", "x.png"],
        &[("RAYLAB_MAX_TREE_ENTRIES", "many")],
    );
    assert_fails(
        &o,
        2,
        &["RAYLAB_MAX_TREE_ENTRIES='many' is not a whole number of scene tree entries"],
    );
    if !have_gnu_time() {
        return;
    }
    // Sequential push/pop pairs (9 bytes each) cost about their own bytes once the tree is
    // full: 900,000 more pairs may cost at most 64 bytes each (the tree cost ~200).
    let peak_kib = |pairs: usize| {
        let scene = write(
            dir.path(),
            &format!("p{pairs}.scene"),
            &format!("sphere 0 0 0 1\n{}", "push\npop\n".repeat(pairs)),
        );
        peak_render_kib(&scene, &[("RAYLAB_MAX_TREE_ENTRIES", "1000")])
    };
    let (small, large) = (peak_kib(100_000), peak_kib(1_000_000));
    let per_pair = (large.saturating_sub(small) * 1024) as f64 / 900_000.0;
    println!("{small} KiB, {large} KiB: {per_pair:.0} bytes a push/pop pair");
    assert!(per_pair <= 64.0, "{per_pair:.0} bytes a pair");
}
