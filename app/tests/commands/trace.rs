//! `raylab trace` from outside: the text formats answered exactly, every per-ray, instanced
//! and packet path answering as the reference loop, the hard-case suite through each, and
//! malformed input named by file and line.

use crate::common;

use common::binary::{assert_fails, stderr, stdout, write};
use raylab::geometry::{Sphere, Triangle};
use rayon::prelude::*;
use std::path::Path;

crate::raylab_runner!();

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

/// `--scene cornell` names the built-in lab box, as everywhere a scene is named (it was read
/// as a file: "cornell: No such file or directory"); a file of that one statement is the same.
#[test]
fn trace_takes_the_built_in_cornell_box_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let rays = write(
        dir.path(),
        "rays.txt",
        "0 0 -3 0 0 1 0 inf\n0.2 0.3 -3 0 0 1 0 inf\n0 0 -3 0 0 -1 0 inf\n",
    );
    let file = write(dir.path(), "box.scene", "cornell\n");
    let by_name = raylab(&["trace", "--scene", "cornell", "--rays", &rays]);
    assert!(by_name.status.success(), "{}", stderr(&by_name));
    let from_file = raylab(&["trace", "--scene", &file, "--rays", &rays]);
    assert_eq!(stdout(&by_name), stdout(&from_file));
    let lines: Vec<String> = stdout(&by_name).lines().map(String::from).collect();
    assert_eq!(lines.len(), 3, "{lines:?}");
    assert!(
        lines[0].starts_with("hit ") && lines[2] == "miss",
        "{lines:?}"
    );
    // An OBJ, which `render --scene` takes: refused with why, and the way (a `mesh` line).
    let obj = write(
        dir.path(),
        "tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let o = raylab(&["trace", "--scene", &obj, "--rays", &rays]);
    assert_fails(
        &o,
        2,
        &["raylab trace reads the .scene format", "`mesh FILE.obj`"],
    );
    let mesh = write(dir.path(), "mesh.scene", "mesh tri.obj\n");
    let o = raylab(&["trace", "--scene", &mesh, "--rays", &rays]);
    assert!(o.status.success(), "{}", stderr(&o));
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
    let zeros = format!("{}\n", "0".repeat(5000));
    let nines = format!("sphere 0 0 {}x 1\n", "9".repeat(5000));
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
        // A long word is quoted by its start and length, not whole (a megabyte of error).
        (
            &zeros,
            "unknown statement '0000000000000000000000000000000000000000… (5000 characters)'",
        ),
        (
            &nines,
            "'9999999999999999999999999999999999999999… (5001 characters)' is not a number",
        ),
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
        // (A trailing comment was counted as numbers, and no more said.)
        (
            "0 0 0 0 0 1 0 inf # note\n",
            ":1: ray needs 8 numbers, found 10 words (a `#` comment takes a line of its own)",
        ),
        // A byte-order mark past the start, shown (it named '0' as not a number).
        (
            "0 0 0 0 0 1 0 inf\n\u{feff}0 0 0 0 0 1 0 inf\n",
            ":2: '\\u{feff}0' is not a number",
        ),
        (
            "0 0 0 0 0 1 0 inf\n0 0 0 0 0 0 0 inf\n",
            ":2: direction is zero",
        ),
        ("0 0 0 0 0 1 5 1\n", ":1: tmin 5 > tmax 1"),
        ("0 0 0 0 0 1 nan inf\n", "'nan' is NaN"),
        ("0 0 inf 0 0 1 0 inf\n", "not finite"),
        // Overflow named as written (it said `inf`).
        (
            "0 0 1e39 0 0 1 0 inf\n",
            ":1: ray coordinate 1e39 is not finite in this precision",
        ),
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
fn trace_answers_through_every_per_ray_path_alike() {
    // A cube of 4x4 quads per face (its shared edges and vertices the hard cases) with a
    // sphere in and beside it; rays from several origins through every vertex and edge
    // midpoint. The reference loop, the flat SIMD loop and the BVH name the same primitive
    // for every ray, with t equal to within the stated bound.
    use raylab::geometry::Shape;
    let dir = tempfile::tempdir().unwrap();
    let mut shapes = common::cube(4, 1.0, [-0.5, -0.5, -0.5]);
    shapes.push(Shape::Sphere(Sphere {
        centre: [0.0, 0.0, 0.0],
        radius: 0.25,
    }));
    shapes.push(Shape::Sphere(Sphere {
        centre: [1.5, 0.0, 0.0],
        radius: 0.5,
    }));
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
    // The value as the user writes it, not the enum's Rust name.
    assert_fails(&o, 2, &["--accel bvh runs in f32 only"]);
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
        let Shape::Triangle(Triangle(v)) = s else {
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
        let Shape::Triangle(Triangle(v)) = s else {
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
        // (On every core: the exact reference is much of the test's time.)
        let exact: Vec<_> = (family.rays.par_iter())
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

/// A scene's warnings (a triangle of zero area, kept, never hit) are the command's to print:
/// `raylab trace` on every path and `raylab check` print each once on stderr as
/// `warning: …`, as `raylab render` does, and stdout holds the answers alone.
#[test]
fn trace_and_check_print_a_scene_s_warnings_once() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "zero.scene",
        "tri 0 0 0 1 1 1 2 2 2\ntri -1 -1 2 1 -1 2 0 1 2\n",
    );
    let rays = write(dir.path(), "rays.txt", "0 0 0 0 0 1 0 inf\n");
    let answers = write(dir.path(), "answers.txt", "hit 2 1\n");
    let warning = "zero.scene:1: triangle 0 has zero area";
    let once = |o: &std::process::Output, what: &str| {
        let err = stderr(o);
        assert!(o.status.success(), "{what}: {err}");
        let lines: Vec<&str> = err.lines().filter(|l| l.contains(warning)).collect();
        assert_eq!(lines.len(), 1, "{what}: {err}");
        assert!(lines[0].starts_with("warning: "), "{what}: {err}");
    };
    for more in [
        &["--precision", "f32"][..],
        &["--precision", "f64"],
        &["--precision", "f64", "--method", "moller"],
        &["--accel", "auto"],
        &["--accel", "bvh", "--method", "watertight"],
        &["--accel", "packets"],
    ] {
        let args = [&["trace", "--scene", &scene, "--rays", &rays][..], more].concat();
        let o = raylab(&args);
        once(&o, &more.join(" "));
        assert_eq!(stdout(&o), "hit 2 1\n", "{more:?}");
    }
    for precision in ["f32", "f64"] {
        let o = raylab(&[
            "check",
            "--scene",
            &scene,
            "--rays",
            &rays,
            "--answers",
            &answers,
            "--precision",
            precision,
        ]);
        once(&o, precision);
    }
}

/// A structure keeps a primitive that repeats an earlier one once: `raylab trace` through a
/// structure says so, once, as `raylab render` does; the reference loop keeps every
/// primitive and says nothing. The answers are the same on every path.
#[test]
fn trace_through_a_structure_says_what_it_left_out_as_copies() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "copies.scene",
        "tri -1 -1 2 1 -1 2 0 1 2\nsphere 0 0 5 1\ntri -1 -1 2 1 -1 2 0 1 2\nsphere 0 0 5 1\n",
    );
    let rays = write(
        dir.path(),
        "rays.txt",
        "0 0 0 0 0 1 0 inf\n0 0 3 0 0 1 0 inf\n",
    );
    let warning = "copies.scene: 1 triangle repeats an earlier triangle's vertices exactly, \
                   and 1 sphere repeats an earlier sphere exactly: each is kept once";
    for (accel, told) in [
        ("reference", 0),
        ("flat", 1),
        ("bvh", 1),
        ("auto", 1),
        ("packets", 1),
    ] {
        let o = raylab(&[
            "trace", "--scene", &scene, "--rays", &rays, "--accel", accel,
        ]);
        let err = stderr(&o);
        assert!(o.status.success(), "{accel}: {err}");
        assert_eq!(stdout(&o), "hit 2 0\nhit 1 1\n", "{accel}: {err}");
        let lines: Vec<&str> = err.lines().filter(|l| l.contains(warning)).collect();
        assert_eq!(lines.len(), told, "{accel}: {err}");
        assert!(
            lines.iter().all(|l| l.starts_with("warning: ")),
            "{accel}: {err}"
        );
    }
}

#[test]
fn trace_answers_a_scene_whose_light_or_camera_only_a_render_refuses() {
    // `trace` uses neither the light nor the camera: one beyond the range the renderer's f32
    // core takes (±2⁴⁰) is refused by `render`, naming its line, and not by `trace`, on every
    // path.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rays = write(d, "rays.txt", "0 0 0  0.2 0.2 1  0 inf\n");
    let triangle = "tri 0 0 1  1 0 1  0 1 1\n";
    for (name, far, line) in [
        ("light.scene", "light 0 0 1e13\n", 2),
        ("camera.scene", "camera 0 0 -2e12 yaw 10\n", 2),
    ] {
        let scene = write(d, name, &format!("# far\n{far}{triangle}"));
        for accel in ["reference", "bvh", "auto"] {
            for precision in ["f32", "f64"] {
                if accel != "reference" && precision == "f64" {
                    continue; // (The structures run in f32 only.)
                }
                let o = raylab(&[
                    "trace",
                    "--scene",
                    &scene,
                    "--rays",
                    &rays,
                    "--accel",
                    accel,
                    "--precision",
                    precision,
                ]);
                assert!(o.status.success(), "{name} {accel}: {}", stderr(&o));
                assert_eq!(stdout(&o), "hit 1 0\n", "{name} {accel} {precision}");
            }
        }
        let o = raylab(&["render", "--scene", &scene, "-o", "/dev/null"]);
        assert_fails(
            &o,
            2,
            &[&format!("{name}:{line}: "), "beyond ±1.099511627776e12"],
        );
    }
}
