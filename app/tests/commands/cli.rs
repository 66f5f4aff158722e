//! The `raylab` binary from outside: render, trace, and bad input.

use crate::common;

use common::binary::{assert_fails, stderr, stdout, write};
use common::read_png;
use raylab::geometry::Triangle;
use std::path::Path;
use std::process::Command;

crate::raylab_runner!();

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
    // A pyramid: a quad base (fan-triangulated), four sides, and one face of zero area (kept,
    // never hit, named with its line).
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
        stderr(&o).contains("tet.obj:13: triangle 6 has zero area"),
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
fn one_primitive_is_counted_in_the_singular() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "one.scene", "tri -1 -1 2 1 -1 2 0 1 2\n");
    let out = dir.path().join("one.png");
    let o = raylab(&["render", "--scene", &scene, "-o", out.to_str().unwrap()]);
    assert!(
        stdout(&o).contains("one.scene (1 primitive, "),
        "{}",
        stdout(&o)
    );
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
    let o = common::window::one_window()
        .xvfb_run()
        .args([
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
fn bench_shows_the_angles_it_was_given() {
    let o = raylab(&[
        "bench", "--width", "16", "--height", "16", "--frames", "1", "--yaw", "7.3", "--pitch",
        "-12",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let view = text.lines().find(|l| l.starts_with("view: ")).expect(&text);
    assert!(view.contains(" yaw=7.3 pitch=-12 "), "{view}");
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
    assert_fails(
        &raylab(&["bench", "--frames", "0"]),
        2,
        &["0 is not in 1..=10000"],
    );
    assert_fails(
        &raylab(&["bench", "--threads", "0"]),
        2,
        &["0 is not in 1..=1024"],
    );
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
    // In f64 the same primitive; t within the stated bound (tests/library/rounded_t.rs holds it to
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
    // image is whole (app/tests/commands/outputs.rs).
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
        let Some(raylab::geometry::Shape::Triangle(Triangle(v))) =
            scene.shapes.get(prim[k] as usize)
        else {
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

/// D as the step takes it: at a pixel whose shadow ray primitive 20 blocks, D is 0 in the
/// shadows step (README, step 4) and the colour with it, D before the shadow test beside it;
/// in the direct step, which casts no shadows, D is the unshadowed one.
#[test]
fn inspect_shows_d_as_the_step_takes_it() {
    let nums = |v: &str| -> Vec<f32> { v.split(' ').map(|x| x.parse().unwrap()).collect() };
    let inspect = |step: &str| {
        let o = raylab(&["inspect", "--step", step, "--pixel", "150,420"]);
        assert!(o.status.success(), "{}", stderr(&o));
        fields(&String::from_utf8_lossy(&o.stdout))
    };
    let f = inspect("shadows");
    assert_eq!(f["blocked_by"], "20");
    let unshadowed = nums(&f["D_unshadowed"]);
    assert!(unshadowed.iter().all(|&d| d > 0.1), "{unshadowed:?}");
    assert_eq!(
        (nums(&f["D"]), nums(&f["colour"])),
        (vec![0.0; 3], vec![0.0; 3])
    );
    let f = inspect("direct");
    assert_eq!(nums(&f["D"]), unshadowed);
    assert_eq!(nums(&f["D_unshadowed"]), unshadowed);
    let (rho, colour) = (nums(&f["rho"]), nums(&f["colour"]));
    for k in 0..3 {
        assert_eq!(colour[k], rho[k] * unshadowed[k], "{k}");
    }
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
        assert_eq!(f["colour_terms"], "rho D", "the colour leaves N out");
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
