//! The `raylab` binary's limits: special files refused without blocking, every input capped,
//! structures a file builds capped at their line, and memory in proportion to the input
//! (peak resident memory measured with GNU time on large generated inputs).

use crate::common;

use common::binary::{assert_fails, stderr, write};
use common::read_png;
use std::process::{Command, Output};

crate::raylab_runner!();

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
fn files_that_report_no_size_are_read_to_a_mebibyte() {
    // /proc/self/pagemap reports size 0 but reads to gigabytes: as a scene, rays or a material
    // library it was read to the 1 GiB cap (1 GB of memory) before its error. A small such
    // file (/proc/cpuinfo) is read whole: its error is a parse error at its first line.
    let pagemap = "/proc/self/pagemap";
    if !std::path::Path::new(pagemap).exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let said = format!("{pagemap}: reports no size");
    let scene = write(dir.path(), "s.scene", "tri -1 -1 2 1 -1 2 0 1 2\n");
    let rays = write(dir.path(), "r.txt", "0 0 0 0 0 1 0 inf\n");
    let obj = write(
        dir.path(),
        "m.obj",
        &format!("mtllib {pagemap}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    );
    let png = dir.path().join("x.png");
    let png = png.to_str().unwrap();
    let runs: [(&[&str], bool); 3] = [
        (&["render", "--scene", pagemap, "-o", png], false),
        (&["trace", "--scene", &scene, "--rays", pagemap], false),
        (&["render", "--scene", &obj, "-o", png], true),
    ];
    for (args, renders) in runs {
        let o = raylab(args);
        match renders {
            true => assert!(stderr(&o).contains(&said), "{}", stderr(&o)),
            false => assert_fails(&o, 2, &[&said, "1048576 bytes"]),
        }
        if have_gnu_time() {
            let (o, peak) = peak_kib(args, &[]);
            assert_eq!(o.status.success(), renders, "{}", stderr(&o));
            assert!(peak < 64 << 10, "{args:?}: peak {peak} KiB");
        }
    }
    let o = raylab(&["trace", "--scene", "/proc/cpuinfo", "--rays", &rays]);
    assert_fails(&o, 2, &["/proc/cpuinfo:1:"]);
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

/// The reference loop flattens every mesh: the copies of a mesh used again may hold the
/// file's room for flattened copies plus the meshes' own triangles, refused at the line that
/// passes it (16,000 uses of a 1,000-triangle mesh took 822 MB for 157 KB); through a
/// structure the same file places them as instances.
#[test]
fn the_reference_loop_flattens_copies_in_proportion_to_the_input() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.obj", &strip_obj(1000));
    let rays = write(dir.path(), "rays.txt", "0 0 -10 0 0 1 0 inf\n");
    let scene = write(dir.path(), "s.scene", &"mesh m.obj\n".repeat(16_000));
    let o = raylab(&["trace", "--scene", &scene, "--rays", &rays]);
    // Room: 2^15, one for every 2 of the 176,000 bytes, and the mesh's 1,000: 121,768; the
    // 122nd copy passes it, at line 123.
    assert_fails(
        &o,
        2,
        &["s.scene:123:", "pass 121768 triangles", "--accel auto"],
    );
    let o = raylab(&[
        "trace", "--scene", &scene, "--rays", &rays, "--accel", "auto",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A mesh used a few times is flattened as before.
    let few = write(dir.path(), "few.scene", &"mesh m.obj\n".repeat(30));
    let o = raylab(&["trace", "--scene", &few, "--rays", &rays]);
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

#[test]
fn aovs_cost_a_band_of_memory_not_the_image() {
    // Peak memory of `render --aov` at 2048×1024 and 4096×2048: the 6.3 million pixels more
    // may cost the frame's 4 bytes a pixel and little else; the arrays (20 bytes a pixel, held
    // whole twice over) took 41.
    if !have_gnu_time() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.png");
    let peak = |w: &str, h: &str| {
        let args = ["render", "--width", w, "--height", h, "--aov", "-o"];
        let (o, peak) = peak_kib(&[&args[..], &[out.to_str().unwrap()]].concat(), &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        let t = std::fs::metadata(dir.path().join("a.t.npy")).unwrap().len();
        assert_eq!(
            t,
            128 + 4 * w.parse::<u64>().unwrap() * h.parse::<u64>().unwrap()
        );
        peak
    };
    let (small, large) = (peak("2048", "1024"), peak("4096", "2048"));
    let per_pixel = (large.saturating_sub(small) * 1024) as f64 / (6 << 20) as f64;
    println!("{small} KiB, {large} KiB: {per_pixel:.1} bytes a pixel");
    assert!(per_pixel <= 8.0, "{per_pixel:.1} bytes a pixel");
}

#[test]
fn check_image_holds_a_bounded_amount_a_ray() {
    // Peak memory of `check --image` at 256×256 and 512×512 with a program that answers every
    // ray: the 196,608 rays more may cost at most 160 bytes each (the ray, the exact answer,
    // the program's answer and its grade; the rays file is streamed to disk).
    if !have_gnu_time() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let image = dir.path().join("c.png");
    let program = "grep -v '^#' {rays} | sed 's/.*/hit 2.7182817 12/' # {scene}";
    let peak = |side: &str| {
        let args = [
            "check",
            "--width",
            side,
            "--height",
            side,
            "--program",
            program,
        ];
        let image = ["--image", image.to_str().unwrap()];
        let (o, peak) = peak_kib(&[&args[..], &image].concat(), &[]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        peak
    };
    let (small, large) = (peak("256"), peak("512"));
    let per_ray = (large.saturating_sub(small) * 1024) as f64 / 196_608.0;
    println!("{small} KiB, {large} KiB: {per_ray:.0} bytes a ray");
    assert!(per_ray <= 160.0, "{per_ray:.0} bytes a ray");
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
    // line 7 is the first left out: 8 listed, the limit (the top level, every file's, is
    // not one of them: the message said 9).)
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
        said.contains("s.scene:7: the scene tree lists the first 8 push levels and statements"),
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

#[test]
fn memory_stays_under_a_hundred_bytes_per_byte_of_input() {
    // The costliest inputs per byte, about 2 MB each: a material library of repeated
    // `newmtl` lines (each a material of ~700 bytes for 9 bytes of input), sequential
    // push/pop pairs (scene tree entries), mesh placements, and OBJ faces of 100 vertices
    // (98 triangles for a 292-byte line). A run's peak memory above a tiny render's stays
    // under 100 bytes per byte of the files it reads, the README's bound.
    if !have_gnu_time() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let size = |paths: &[&str]| -> u64 {
        let bytes = paths.iter().map(|p| std::fs::metadata(p).unwrap().len());
        bytes.sum()
    };
    let tiny = write(d, "tiny.scene", "tri 0 0 1 1 0 1 0 1 1\n");
    let base = peak_render_kib(&tiny, &[]);
    let mtl = write(d, "m.mtl", &"newmtl a\n".repeat(250_000));
    let materials = write(
        d,
        "mats.obj",
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let pairs = "push\npop\n".repeat(230_000);
    let tree = write(d, "tree.scene", &format!("sphere 0 0 0 1\n{pairs}"));
    let strip = write(d, "strip.obj", &strip_obj(80));
    let placed = "translate 0.1 0 0\nmesh strip.obj\n".repeat(60_000);
    let placements = write(d, "placed.scene", &placed);
    let ring: String = (0..100)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 100.0;
            format!("v {:.4} {:.4} 2\n", a.cos(), a.sin())
        })
        .collect();
    let face = format!(
        "f {}\n",
        (1..=100)
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    );
    let faces = write(d, "faces.obj", &(ring + &face.repeat(7_000)));
    let cases = [
        ("repeated newmtl", &materials, size(&[&materials, &mtl])),
        ("push/pop pairs", &tree, size(&[&tree])),
        ("mesh placements", &placements, size(&[&placements, &strip])),
        ("100-vertex faces", &faces, size(&[&faces])),
    ];
    for (what, input, bytes) in cases {
        let peak = peak_render_kib(input, &[]);
        let per_byte = (peak.saturating_sub(base) * 1024) as f64 / bytes as f64;
        println!("{what}: {bytes} bytes read, peak {peak} KiB ({base} KiB tiny): {per_byte:.1} bytes a byte");
        assert!(
            per_byte < 100.0,
            "{what}: {per_byte:.1} bytes a byte of input"
        );
    }
}
