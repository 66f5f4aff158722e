//! The `.scene` format: every statement, the fixed transform order, push/pop restoring
//! exactly, exact quarter turns, spheres under scales, every error with its line, meshes
//! relative to the file, and the `trace` files of before meaning what they meant.

use raylab::geometry::{Shape, Sphere, Triangle};
use raylab::scene::file::{parse, Description, FileError, SceneCamera};
use raylab::scene::ObjFrame;
use raylab::Scene;
use std::path::Path;

fn no_meshes(p: &Path, _: ObjFrame, _: [f32; 3]) -> Result<Scene, String> {
    Err(format!("{}: no meshes in this test", p.display()))
}

fn parse32(text: &str) -> Result<Description<f32>, FileError> {
    parse::<f32>("t.scene", text, Path::new(""), &no_meshes)
}

fn tri(d: &Description<f32>, i: usize) -> [[f32; 3]; 3] {
    match d.shapes[i] {
        Shape::Triangle(Triangle(v)) => v,
        Shape::Sphere(_) => panic!("primitive {i} is a sphere"),
    }
}

fn sphere(d: &Description<f32>, i: usize) -> ([f32; 3], f32) {
    match d.shapes[i] {
        Shape::Sphere(Sphere { centre, radius }) => (centre, radius),
        Shape::Triangle(_) => panic!("primitive {i} is a triangle"),
    }
}

/// The error of `text`: its line and message.
fn error(text: &str) -> (usize, String) {
    let e = parse32(text).expect_err("an error");
    assert_eq!(e.file, "t.scene");
    assert!(e.to_string().starts_with(&format!("t.scene:{}: ", e.line)));
    (e.line, e.message)
}

#[test]
fn every_statement_is_read() {
    let d = parse32(
        "# a comment line\n\
         tri 0 0 0 1 0 0 0 1 0   # a comment after a statement\n\
         \n\
         color 0.1 0.2 0.3\n\
         sphere 1 2 3 0.5\n\
         light 0 -1 0 20\n\
         ambient 0.25 0.5 1\n\
         camera 1 2 -3 yaw 10 pitch -5 fov 60\n\
         cornell\n",
    )
    .unwrap();
    assert_eq!(d.shapes.len(), 2 + 30);
    assert_eq!(
        tri(&d, 0),
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
    assert_eq!(sphere(&d, 1), ([1.0, 2.0, 3.0], 0.5));
    assert_eq!(d.colors[0], [0.75; 3], "the default colour");
    assert_eq!(d.colors[1], [0.1, 0.2, 0.3]);
    let light = d.light.unwrap();
    assert_eq!((light.position, light.power), ([0.0, -1.0, 0.0], [20.0; 3]));
    assert_eq!(d.ambient, Some([0.25, 0.5, 1.0]));
    assert_eq!(
        d.camera,
        Some(SceneCamera {
            position: [1.0, 2.0, -3.0],
            yaw: 10.0,
            pitch: -5.0,
            fov: Some(60.0),
        })
    );
    // `cornell` adds the lab box's 30 triangles with their own colours, in file order.
    let lab = Scene::cornell();
    assert_eq!(&d.shapes[2..], &lab.shapes[..]);
    assert_eq!(&d.colors[2..], lab.colors());
    assert!(d.has_cornell && d.warnings.is_empty());
}

#[test]
fn translate_rotate_scale_is_the_lectures_t_r_s() {
    // Scale first, then rotate, then translate: (1, 0, 0) -> (2, 0, 0) -> Rz 90: (0, 2, 0)
    // -> (1, 4, 3). Quarter turns and these numbers are exact.
    let d = parse32(
        "translate 1 2 3\nrotate z 90\nscale 2\n\
         tri 1 0 0 0 1 0 0 0 1\n",
    )
    .unwrap();
    assert_eq!(
        tri(&d, 0),
        [[1.0, 4.0, 3.0], [-1.0, 2.0, 3.0], [1.0, 2.0, 5.0]]
    );
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
    // The same ops written in the other order give the other matrix, with a warning per
    // out-of-order line.
    let d = parse32("scale 2\nrotate z 90\ntranslate 1 2 3\ntri 1 0 0 0 1 0 0 0 1\n").unwrap();
    // M = S * Rz * T: (1,0,0) -> T: (2,2,3) -> Rz: (-2,2,3) -> S: (-4,4,6).
    assert_eq!(tri(&d, 0)[0], [-4.0, 4.0, 6.0]);
    assert_eq!(d.warnings.len(), 2, "{:?}", d.warnings);
    assert!(d.warnings[0].starts_with("t.scene:2: rotate after scale (line 1)"));
    assert!(d.warnings[1].starts_with("t.scene:3: translate after rotate (line 2)"));
    // A new push level starts its own order.
    let d = parse32("scale 2\npush\ntranslate 1 0 0\npop\ntri 0 0 0 1 0 0 0 1 0\n").unwrap();
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
}

#[test]
fn rotations_are_right_handed_as_the_readme_says() {
    // A quarter turn about each axis takes the next axis to the one after it (x -> y -> z -> x).
    for (axis, from, to) in [
        ("x", [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
        ("y", [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
        ("z", [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ] {
        let [x, y, z] = from;
        let d = parse32(&format!("rotate {axis} 90\ntri {x} {y} {z} 0 0 0 1 1 1\n")).unwrap();
        assert_eq!(tri(&d, 0)[0], to, "rotate {axis} 90 of {from:?}");
    }
}

#[test]
fn push_and_pop_restore_the_transform_and_colour_exactly() {
    let d = parse32(
        "color 0.5 0.5 0.5\n\
         tri 0.1 0.2 0.3 1.1 0.2 0.3 0.1 1.7 0.3\n\
         push\n  color 1 0 0\n  translate 0.1 0.2 0.3\n  rotate y 33\n  scale 1.7\n\
           push\n    rotate x 12.5\n    tri 1 2 3 4 5 6 7 8 9\n  pop\n  tri 1 2 3 4 5 6 7 8 9\n\
         pop\n\
         tri 0.1 0.2 0.3 1.1 0.2 0.3 0.1 1.7 0.3\n",
    )
    .unwrap();
    assert_eq!(tri(&d, 0), tri(&d, 3), "bit for bit after the pop");
    assert_eq!(d.colors[3], [0.5; 3]);
    assert_eq!(d.colors[1], [1.0, 0.0, 0.0]);
    assert_ne!(
        tri(&d, 1),
        tri(&d, 2),
        "the inner rotation applied only inside"
    );
    // The levels for the inspector: the file, then two pushes, with their primitives and
    // matrices.
    assert_eq!(d.levels.len(), 3);
    assert_eq!((d.levels[1].line, d.levels[1].depth), (3, 1));
    assert_eq!((d.levels[2].line, d.levels[2].depth), (8, 2));
    assert_eq!(d.levels[0].primitives, vec![0..1, 3..4]);
    assert_eq!(d.levels[1].primitives, vec![2..3]);
    assert_eq!(d.levels[2].primitives, vec![1..2]);
    let m = d.levels[1].world_from_object;
    assert_eq!([m[0][3], m[1][3], m[2][3], m[3][3]], [0.1, 0.2, 0.3, 1.0]);
}

#[test]
fn quarter_turns_are_exact() {
    let cube = "tri 0 0 0 1 0 0 1 1 0\ntri 0.5 0.25 0.75 1 0 1 0 1 1\n";
    for axis in ["x", "y", "z"] {
        for deg in [90, 180, 270, -90, 450, -720] {
            let d = parse32(&format!("rotate {axis} {deg}\n{cube}")).unwrap();
            for i in 0..2 {
                for c in tri(&d, i).iter().flatten() {
                    assert!(
                        [0.0, 1.0, -1.0, 0.5, -0.5, 0.25, -0.25, 0.75, -0.75].contains(c),
                        "rotate {axis} {deg}: coordinate {c} is not exact"
                    );
                }
            }
            // Four quarter turns are the identity, to the bit.
            let d4 = parse32(&format!(
                "rotate {axis} {deg}\nrotate {axis} {deg}\nrotate {axis} {deg}\nrotate {axis} {deg}\n{cube}"
            ))
            .unwrap();
            let d0 = parse32(cube).unwrap();
            assert_eq!(d4.shapes, d0.shapes, "rotate {axis} {deg} four times");
        }
    }
}

#[test]
fn spheres_take_uniform_scales_and_refuse_others() {
    let d = parse32("translate 1 0 0\nrotate y 30\nscale -2\nsphere 0 0 0 0.25\n").unwrap();
    let (centre, radius) = sphere(&d, 0);
    assert_eq!(centre, [1.0, 0.0, 0.0]);
    assert_eq!(radius, 0.5, "|s| times the radius");
    let (line, m) = error("tri 0 0 0 1 0 0 0 1 0\nscale 1 2 1\n\nsphere 0 0 0 1\n");
    assert_eq!(line, 4);
    assert!(m.contains("non-uniform scale"), "{m}");
    // Inside a push level the scale is undone by the pop.
    let d = parse32("push\nscale 1 2 1\npop\nsphere 0 0 0 1\n").unwrap();
    assert_eq!(sphere(&d, 0).1, 1.0);
}

#[test]
fn every_error_names_its_line() {
    let cases: &[(&str, usize, &str)] = &[
        ("tri 0 0 0\n", 1, "tri needs 9 numbers, found 3"),
        (
            "\n\ntri 0 0 0 1 0 0 0 1 0 5\n",
            3,
            "tri needs 9 numbers, found 10",
        ),
        ("sphere 0 0 0 -1\n", 1, "sphere radius -1 must be > 0"),
        ("tri 0 0 0 1 0 0 0 x 0\n", 1, "'x' is not a number"),
        ("tri 0 0 0 1 0 0 0 NaN 0\n", 1, "is NaN"),
        ("tri 0 0 0 1 0 0 0 inf 0\n", 1, "not finite"),
        (
            "tri 0 0 0 1 0 0 0 1e39 0\n",
            1,
            "not finite in this precision",
        ),
        ("cube 1 2 3\n", 1, "unknown statement 'cube'"),
        ("push\npop\npop\n", 3, "pop without a matching push"),
        ("rotate w 10\n", 1, "rotate axis 'w'"),
        ("rotate x\n", 1, "rotate needs an axis"),
        ("scale 1 2\n", 1, "scale needs 1 or 3 numbers, found 2"),
        ("scale 0\n", 1, "a scale of 0"),
        (
            "light 0 0 0\nlight 1 1 1\n",
            2,
            "one light (given on line 1)",
        ),
        (
            "camera 0 0 5\n# a second view\ncamera 0 1 5 yaw 10\n",
            3,
            "one camera (given on line 1)",
        ),
        (
            "ambient 0 0 0\nambient 1 1 1\n",
            2,
            "one ambient (given on line 1)",
        ),
        ("color 1 -1 0\n", 1, "negative"),
        ("camera 0 0\n", 1, "camera needs x y z"),
        (
            "camera 0 0 0 roll 3\n",
            1,
            "'roll' is not yaw, pitch or fov",
        ),
        ("camera 0 0 0 fov 200\n", 1, "fov 200"),
        ("mesh\n", 1, "mesh needs a path"),
        // (An empty quoted path read as a file named nothing: "mesh '': : No such file".)
        ("mesh \"\"\n", 1, "mesh '': the path is empty"),
        ("mesh a.obj sideways\n", 1, "sideways"),
        (
            "\n\nmesh model.obj\n",
            3,
            "mesh 'model.obj': model.obj: no meshes in this test",
        ),
        (
            "translate 1e308 0 0\nscale 10\ntri 1 0 0 0 1 0 0 0 1\n",
            3,
            "the point [1.0, 0.0, 0.0], placed at [1e308, 0.0, 0.0] by the transform, is \
             beyond f32's range ([inf, 0.0, 0.0])",
        ),
        // (Finite, with no transform: it was "not finite in the world after the transform".)
        (
            "light 1e300 0 0\n",
            1,
            "the point [1e300, 0.0, 0.0] is beyond f32's range ([inf, 0.0, 0.0])",
        ),
        ("cornell 1\n", 1, "cornell takes no numbers"),
    ];
    for (text, line, needle) in cases {
        let (got_line, message) = error(text);
        assert_eq!(got_line, *line, "{text:?}: {message}");
        assert!(
            message.contains(needle),
            "{text:?}: '{message}' lacks '{needle}'"
        );
    }
    // An unbalanced push is a warning, not an error.
    let d = parse32("push\ntri 0 0 0 1 0 0 0 1 0\n").unwrap();
    assert_eq!(d.warnings.len(), 1);
    assert!(d.warnings[0].starts_with("t.scene:1: push without a matching pop"));
}

#[test]
fn trace_files_read_their_numbers_straight_in_the_precision() {
    // 1 + 2^-24 + a little: f32 rounds it up to 1 + 2^-23 directly, but through f64 (which
    // rounds it to 1 + 2^-24, a tie) it would become 1. With no transform, no double rounding.
    let x = "1.00000005960464477550";
    let direct: f32 = x.parse().unwrap();
    assert_eq!(direct, 1.0 + f32::EPSILON);
    assert_eq!((x.parse::<f64>().unwrap()) as f32, 1.0);
    let d = parse32(&format!("tri {x} 0 0 0 1 0 0 0 1\n")).unwrap();
    assert_eq!(tri(&d, 0)[0][0], direct);
    // The same file in f64 keeps every digit f64 can.
    let d64 = parse::<f64>(
        "t.scene",
        &format!("sphere 0 0 {x} 1\n"),
        Path::new(""),
        &no_meshes,
    )
    .unwrap();
    assert_eq!(
        d64.shapes[0],
        Shape::Sphere(Sphere {
            centre: [0.0, 0.0, x.parse::<f64>().unwrap()],
            radius: 1.0
        })
    );
}

#[test]
fn meshes_load_relative_to_the_file_in_the_current_frame_and_colour() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("models")).unwrap();
    std::fs::write(
        dir.path().join("models/tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n",
    )
    .unwrap();
    let scene_path = dir.path().join("a.scene");
    std::fs::write(
        &scene_path,
        "color 0.2 0.4 0.6\npush\ntranslate 10 0 0\nmesh models/tri.obj lab\npop\n\
         mesh models/tri.obj yup\n",
    )
    .unwrap();
    let scene = raylab::scene::load_scene_file(&scene_path).unwrap();
    assert_eq!(scene.len(), 4);
    assert_eq!(
        scene.shapes[0],
        Shape::from([[10.0, 0.0, 0.0], [11.0, 0.0, 0.0], [10.0, 1.0, 0.0]])
    );
    // yup negates y and z.
    assert_eq!(
        scene.shapes[2],
        Shape::from([[0.0, -0.0, -0.0], [1.0, -0.0, -0.0], [0.0, -1.0, -0.0]])
    );
    assert!(
        scene.colors().iter().all(|c| *c == [0.2, 0.4, 0.6]),
        "faces without material"
    );
    // The mesh files it names, once each (what the window watches beside it).
    assert_eq!(scene.mesh_files, [dir.path().join("models/tri.obj")]);
    // A mesh that fails to load: the scene's line, then the mesh's own error.
    std::fs::write(&scene_path, "\nmesh models/missing.obj\n").unwrap();
    let e = raylab::scene::load_scene_file(&scene_path).unwrap_err();
    assert!(e.contains("a.scene:2: mesh 'models/missing.obj'"), "{e}");
    std::fs::write(
        dir.path().join("models/bad.obj"),
        "v 0 0 0\nv 1 0 0\nf 1 2 9\n",
    )
    .unwrap();
    std::fs::write(&scene_path, "mesh models/bad.obj\n").unwrap();
    let e = raylab::scene::load_scene_file(&scene_path).unwrap_err();
    assert!(
        e.contains("a.scene:1: mesh 'models/bad.obj'") && e.contains("bad.obj:3"),
        "{e}"
    );
}

#[test]
fn the_example_scenes_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let spheres = raylab::scene::load_scene_file(&dir.join("cornell_spheres.scene")).unwrap();
    assert_eq!(spheres.len(), 32);
    assert!(spheres.warnings.is_empty(), "{:?}", spheres.warnings);
    assert_eq!(
        spheres.camera,
        Some(SceneCamera::LAB),
        "cornell brings the lab camera"
    );
    assert_eq!(spheres.shapes[31], {
        Shape::Sphere(Sphere {
            centre: [-0.5, 0.7, -0.5],
            radius: 0.3,
        })
    });
    let stack = raylab::scene::load_scene_file(&dir.join("transform_stack.scene")).unwrap();
    assert_eq!(stack.len(), 2 + 3 * 12 + 1);
    assert_eq!(stack.levels.len(), 5);
    assert_eq!(stack.warnings.len(), 1, "the one the file explains");
    assert!(stack.warnings[0].contains("transform_stack.scene:45: translate after scale"));
}

#[test]
fn a_sphere_keeps_its_radius_under_any_uniform_scale_f64_holds() {
    // 2^±600: the columns' squared lengths would overflow or underflow f64; their radius does
    // not (r·s = 1 exactly), and the scale is uniform.
    for (s, r) in [(600, -600), (-600, 600), (1000, -1000), (-1000, 1000)] {
        let text = format!(
            "scale {:e}\nsphere 0 0 0 {:e}\n",
            2f64.powi(s),
            2f64.powi(r)
        );
        let d = parse::<f64>("t.scene", &text, Path::new(""), &no_meshes)
            .unwrap_or_else(|e| panic!("2^{s}: {e}"));
        match d.shapes[0] {
            Shape::Sphere(Sphere { centre, radius }) => {
                assert_eq!((centre, radius), ([0.0; 3], 1.0), "2^{s}");
            }
            _ => panic!("not a sphere"),
        }
    }
    // Non-uniform at such scales is still an ellipsoid.
    let text = format!(
        "scale {:e} {:e} {:e}\nsphere 0 0 0 1\n",
        2f64.powi(600),
        2f64.powi(600),
        2f64.powi(601)
    );
    let e = parse::<f64>("t.scene", &text, Path::new(""), &no_meshes).unwrap_err();
    assert!(e.to_string().contains("ellipsoid"), "{e}");
}

#[test]
fn colours_and_powers_f32_cannot_hold_are_refused_and_colours_above_1_clamped() {
    for (text, what) in [
        ("color 1e39 0 0\ntri 0 0 1 1 0 1 0 1 1\n", "color"),
        ("ambient 0 1e40 0\ntri 0 0 1 1 0 1 0 1 1\n", "ambient"),
        ("tri 0 0 1 1 0 1 0 1 1\nlight 0 0 0 1e39\n", "light power"),
    ] {
        let e = parse32(text).unwrap_err().to_string();
        let line = if what == "light power" { 2 } else { 1 };
        assert!(e.starts_with(&format!("t.scene:{line}:")), "{e}");
        assert!(
            e.contains(what) && e.contains("beyond what f32 holds"),
            "{e}"
        );
    }
    // Named as a number is written, not in 40 digits.
    let e = parse32("color 1e39 0 0\n").unwrap_err().to_string();
    assert!(e.contains("color 1e39 is beyond"), "{e}");
    // The largest f32 itself is held, clamped to 1 as a reflectance is (as an MTL's Kd),
    // with a warning naming the line.
    let d = parse32("color 3.4028235e38 0.5 1\ntri 0 0 1 1 0 1 0 1 1\n").unwrap();
    assert_eq!(d.colors, [[1.0, 0.5, 1.0]]);
    assert_eq!(
        d.warnings,
        ["t.scene:1: color 3.4028235e38 0.5 1 is outside 0…1: clamped"]
    );
    let d = parse32("color 1 0 1\ntri 0 0 1 1 0 1 0 1 1\n").unwrap();
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
}

#[test]
fn a_field_of_view_no_image_size_can_take_is_refused_naming_the_line() {
    let e = parse32("tri 0 0 1 1 0 1 0 1 1\ncamera 0 0 -3 fov 1e-300\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("t.scene:2:") && e.contains("fov 1e-300"),
        "{e}"
    );
    assert!(e.len() < 300, "no 300-digit number: {e}");
    assert!(parse32("tri 0 0 1 1 0 1 0 1 1\ncamera 0 0 -3 fov 0.5\n").is_ok());
    assert!(parse32("tri 0 0 1 1 0 1 0 1 1\ncamera 0 0 -3 fov 170\n").is_ok());
}

#[test]
fn push_nesting_is_bounded_at_its_line() {
    // As deep as the limit parses, and its levels pop back to the identity; one more is
    // refused at its own line, before it is stored.
    let depth = raylab::limits::MAX_PUSH_DEPTH;
    let text = "push\n".repeat(depth) + "tri 0 0 0 1 0 0 0 1 0\n" + &"pop\n".repeat(depth);
    let d = parse32(&text).unwrap();
    assert_eq!(d.levels.len(), depth + 1);
    assert_eq!(
        tri(&d, 0),
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
    let (line, msg) = error(&("push\n".repeat(depth + 1) + "pop\n"));
    assert_eq!(line, depth + 1, "{msg}");
    assert!(
        msg.contains(&format!("deeper than {depth} levels")),
        "{msg}"
    );
}

#[test]
fn transformed_coordinates_are_rounded_to_f64_then_to_f32() {
    // The rule the module docs and the README state: the matrix is applied in f64, then the
    // result is rounded to f32, two roundings. The vertex 1 translated by 2⁻²⁴ + 2⁻⁶⁰ (exact
    // in the file and in f64) is 1 + 2⁻²⁴ + 2⁻⁶⁰, just above the f32 midpoint 1 + 2⁻²⁴: rounded
    // once it would be 1 + 2⁻²³; f64 makes it the midpoint, which rounds to even: 1.
    let shift = "0.000000059604644776257986737988403547205962240695953369140625";
    assert_eq!(
        shift.parse::<f64>().unwrap(),
        2f64.powi(-24) + 2f64.powi(-60)
    );
    let text = format!("translate {shift} 0 0\ntri 1 0 0 0 1 0 0 0 1\n");
    assert_eq!(tri(&parse32(&text).unwrap(), 0)[0][0], 1.0);
    // f64 (`raylab trace --precision f64`) keeps the f64 sum.
    let d = parse::<f64>("t.scene", &text, Path::new(""), &no_meshes).unwrap();
    let Shape::Triangle(Triangle(v)) = d.shapes[0] else {
        panic!("a triangle")
    };
    assert_eq!(v[0][0], 1.0 + 2f64.powi(-24));
    // An instance's world vertex is the same arithmetic.
    let m = glam::DMat4::from_translation(glam::DVec3::new(shift.parse().unwrap(), 0.0, 0.0));
    assert_eq!(
        raylab::scene::Instance::world_vertex(&m, [1.0, 0.0, 0.0]),
        [1.0, 0.0, 0.0]
    );
}

/// `n` Cornell boxes, each one step further along x.
fn cornell_row(n: usize) -> String {
    "translate 1.5 0 0\ncornell\n".repeat(n)
}

fn parse_default(text: &str) -> Result<Description<f32>, FileError> {
    let instancing = raylab::scene::file::Instancing::DEFAULT;
    raylab::scene::file::parse_with::<f32>("t.scene", text, Path::new(""), &no_meshes, instancing)
}

#[test]
fn repeated_cornell_boxes_are_flattened_while_their_copies_fit_then_placed() {
    // The box is a small mesh (30 triangles): a few copies are flattened (their rays walk
    // faster), but copies past the room for flattened ones (2^15 triangles and one per 2
    // bytes of the file) are placed as instances, one copy of the box in memory (flattened,
    // 34,952 boxes took 120 MB for 280 KB of lines).
    let room = |n: usize| raylab::limits::flattened_copies_room(cornell_row(n).len());
    let fits = (1..)
        .take_while(|&n| 30 * n as u64 <= room(n))
        .last()
        .unwrap();
    assert_eq!(fits, (1 << 15) / (30 - 13));
    for (n, placed) in [(4, 0), (fits, 0), (fits + 1, fits + 1)] {
        let text = cornell_row(n);
        let d = parse_default(&text).unwrap();
        assert_eq!(d.instances.len(), placed, "{n} boxes");
        assert_eq!(d.shapes.len() + placed * 30, n * 30, "{n} boxes");
        assert!(d.has_cornell);
        if placed == 0 {
            continue;
        }
        // The same primitives, in the same order, as the file flattened.
        let flat = parse32(&text).unwrap();
        let scene = Scene::from_description("t.scene", d).unwrap();
        assert_eq!(scene.len(), flat.shapes.len());
        for p in (0..flat.shapes.len()).step_by(7) {
            assert_eq!(scene.shape(p as u32), flat.shapes[p], "primitive {p}");
            assert_eq!(scene.color(p as u32), flat.colors[p], "colour of {p}");
        }
    }
}

#[test]
fn copies_only_flattening_can_hold_are_refused_past_the_absolute_limit() {
    // Under a scale 10^7 times thinner along z no instance can be placed (rays carried into
    // the box's frame would lose too much): the copies are flattened, past the file's room
    // for copies flattened by choice, up to MAX_FLATTENED_COPIES, and the line that passes
    // it is refused.
    let limit = raylab::limits::MAX_FLATTENED_COPIES as usize;
    let boxes = limit / 30 + 1;
    let text = format!("scale 1 1 1e-7\n{}", "cornell\n".repeat(boxes));
    let room = raylab::limits::flattened_copies_room(text.len()) as usize;
    assert!(room < limit, "the file's room is not what refuses");
    let e = parse_default(&text).expect_err("past the limit");
    assert_eq!(e.line, 1 + limit / 30 + 1);
    assert!(e
        .message
        .contains("too ill-conditioned to place mesh 'cornell'"));
    assert!(e.message.contains(&format!("passes the {limit} triangles")));
    // (It advised a push/pop around the scale, to a file whose scale already had one.)
    assert!(
        e.message.ends_with(
            "(a scale this uneven places no instance: scale less unevenly, or \
                             place fewer meshes under it)"
        ),
        "{}",
        e.message
    );
    // 2000 boxes, past the file's room (it once refused them), load.
    let text = format!("scale 1 1 1e-7\n{}", "cornell\n".repeat(2000));
    assert!(2000 * 30 > raylab::limits::flattened_copies_room(text.len()));
    let d = parse_default(&text).unwrap();
    assert_eq!((d.shapes.len(), d.instances.len()), (2000 * 30, 0));
}

#[test]
fn a_large_mesh_under_an_ill_conditioned_scale_is_flattened_past_the_file_s_room() {
    // A 20,000-triangle mesh used twice under a scale 10^7 times thinner along z: too
    // ill-conditioned to place, so both copies are flattened (40,000 triangles, past a short
    // file's room of 2^15 and a few, which only decides what is flattened by choice).
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::new();
    let n = 100;
    for j in 0..=n {
        for i in 0..=n {
            obj += &format!("v {i} {j} {}\n", (i * j) % 7);
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    std::fs::write(dir.path().join("big.obj"), obj).unwrap();
    let text = "scale 1 1 1e-7\nmesh big.obj\ntranslate 3 0 0\nmesh big.obj\n";
    assert!(40_000 > raylab::limits::flattened_copies_room(text.len()));
    let load = raylab::scene::file::load_obj_mesh;
    let instancing = raylab::scene::file::Instancing::DEFAULT;
    let d = raylab::scene::file::parse_with::<f32>("t.scene", text, dir.path(), &load, instancing)
        .unwrap();
    assert_eq!((d.shapes.len(), d.instances.len()), (40_000, 0));
    // Well conditioned, the same file places its two copies.
    let text = "scale 1 1 2\nmesh big.obj\ntranslate 3 0 0\nmesh big.obj\n";
    let d = raylab::scene::file::parse_with::<f32>("t.scene", text, dir.path(), &load, instancing)
        .unwrap();
    assert_eq!((d.shapes.len(), d.instances.len()), (0, 2));
}

#[test]
fn a_transform_that_leaves_the_matrix_singular_or_infinite_is_refused_at_its_line() {
    // `scale 0` is refused at once; scales whose product leaves f64's range are refused at
    // the line that makes it so, naming it.
    for (text, line, needle) in [
        (
            "scale 1e-200\nscale 1e-200\ntri 0 0 0 1 0 0 0 1 0\n",
            2,
            "'scale 1e-200' makes the transform's matrix singular in f64",
        ),
        (
            "push\nrotate x 30\nscale 1 1e-300 1\nscale 1 1e-300 1\npop\n",
            4,
            "'scale 1 1e-300 1' makes the transform's matrix singular",
        ),
        (
            "scale 1e200\nscale 1e200\n",
            2,
            "'scale 1e200' makes the transform's matrix not finite",
        ),
        (
            "translate 1e308 0 0\ntranslate 1e308 0 0\n",
            2,
            "'translate 1e308 0 0' makes the transform's matrix not finite",
        ),
    ] {
        let (l, message) = error(text);
        assert_eq!(l, line, "{message}");
        assert!(message.contains(needle), "{message}");
    }
    // Tiny and huge scales that stay within f64 are fine.
    let d = parse32("scale 1e-150\nscale 1e150 1e150 1e150\ntri 0 0 1 1 0 1 0 1 1\n").unwrap();
    assert_eq!(
        tri(&d, 0),
        [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]
    );
}

#[test]
fn a_column_scaled_to_zero_past_a_subnormal_one_is_singular() {
    // A subnormal largest entry was scaled by 2^1030 as 1 / 2^-1030 = 1 / 0: the column became
    // infinite, the determinant NaN, and a matrix with a zero column passed as regular.
    for (text, line, needle) in [
        (
            "scale 1e-310 1e-310 1\nscale 1e-20 1 1\ntri 0 0 1 1 0 1 0 1 1\n",
            2,
            "'scale 1e-20 1 1' makes the transform's matrix singular in f64",
        ),
        (
            "scale 1e-200 1e-200 1\nscale 1e-200 1 1\n",
            2,
            "'scale 1e-200 1 1' makes the transform's matrix singular in f64",
        ),
        (
            "rotate z 30\nscale 1e-310 1e-310 1\nscale 1 1e-20 1\n",
            3,
            "'scale 1 1e-20 1' makes the transform's matrix singular in f64",
        ),
    ] {
        let (l, message) = error(text);
        assert_eq!(l, line, "{message}");
        assert!(message.contains(needle), "{message}");
    }
    // Subnormal columns that are not zero, scales that cancel, mixed huge and tiny ones and a
    // long chain of rotations are regular.
    for text in [
        "scale 1e-310 1e-310 1\n".to_string(),
        "rotate x 30\nscale 1e-310 1e-320 1e-315\n".to_string(),
        "scale 1e-150\nscale 1e150\ntri 0 0 1 1 0 1 0 1 1\n".to_string(),
        "scale 1e100 1e-100 1\nrotate y 45\nscale 1e-100 1e100 1e100\nrotate x 10\n".to_string(),
        "scale 1e-300 1 1e300\nscale 1e300 1 1e-300\ntri 0 0 1 1 0 1 0 1 1\n".to_string(),
        (0..5000)
            .map(|k| format!("rotate {} {}.{}\n", ["x", "y", "z"][k % 3], k % 360, k % 7))
            .collect(),
    ] {
        let first = text.lines().next().unwrap_or_default().to_string();
        assert!(
            parse32(&text).is_ok(),
            "{first}: {:?}",
            parse32(&text).err()
        );
    }
    let d = parse32("scale 1e-300 1 1e300\nscale 1e300 1 1e-300\ntri 0 0 1 1 0 1 0 1 1\n");
    assert_eq!(
        tri(&d.unwrap(), 0),
        [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]
    );
}

#[test]
fn a_byte_order_mark_past_the_first_line_is_named() {
    // Files joined together: the second one's mark starts line 2.
    let (line, message) = error("tri 0 0 1 1 0 1 0 1 1\n\u{feff}tri 0 0 1 1 0 1 0 1 1\n");
    assert_eq!(line, 2);
    assert!(
        message.contains("starts with a byte-order mark (U+FEFF)"),
        "{message}"
    );
    let (line, message) = error("color 1 0\u{feff} 0\n");
    assert_eq!(line, 1);
    assert!(
        message.contains("'0' holds a byte-order mark (U+FEFF)"),
        "{message}"
    );
    // The first line's is skipped.
    assert_eq!(
        parse32("\u{feff}tri 0 0 1 1 0 1 0 1 1\n")
            .unwrap()
            .shapes
            .len(),
        1
    );
}

#[test]
fn line_breaks_of_a_lone_cr_are_line_breaks() {
    // A file written with CR alone between lines (classic Mac OS, some exporters) read as one
    // line: `:1: tri needs 9 numbers, found 20`. Scene, OBJ and rays files read it as the
    // same file with LF, and name the same lines.
    let dir = tempfile::tempdir().unwrap();
    let lf = "camera 0 0 -3\ntri 0 0 0 1 0 0 0 1 0\nsphere 0 0 2 0.5\n";
    let obj_lf = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    for (name, text) in [
        ("lf", lf.to_string()),
        ("cr", lf.replace('\n', "\r")),
        ("crlf", lf.replace('\n', "\r\n")),
    ] {
        let path = dir.path().join(format!("{name}.scene"));
        std::fs::write(&path, &text).unwrap();
        let scene = Scene::load(&path, ObjFrame::Lab).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(scene.len(), 2, "{name}");
        let obj = dir.path().join(format!("{name}.obj"));
        std::fs::write(
            &obj,
            obj_lf.replace('\n', if name == "cr" { "\r" } else { "\n" }),
        )
        .unwrap();
        assert_eq!(Scene::load(&obj, ObjFrame::Lab).unwrap().len(), 1, "{name}");
    }
    // An error names the line as counted with CR as the break.
    let bad = dir.path().join("bad.scene");
    std::fs::write(&bad, "tri 0 0 0 1 0 0 0 1 0\rtri 0 0\r").unwrap();
    let e = Scene::load(&bad, ObjFrame::Lab).unwrap_err();
    assert!(e.contains("bad.scene:2:"), "{e}");
}

/// A scene whose light lies within 2⁻⁶⁰ of it (the lit steps' ‖r‖² underflows f32: D reads
/// inf or 0) loads with a warning that says so; at 1, or with its light far off, none.
#[test]
fn a_scene_too_small_to_light_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let warned = |size: f32, light: &str| {
        let path = dir.path().join("corner.scene");
        let text = format!("{light}tri 0 0 0 {size:e} 0 0 0 {size:e} 0\n");
        std::fs::write(&path, text).unwrap();
        let scene = Scene::load(&path, ObjFrame::Lab).unwrap();
        scene.warnings.iter().any(|w| w.contains("below 2⁻⁶⁰"))
    };
    assert!(warned(1e-21, ""), "the light placed for it lies as close");
    assert!(warned(1e-35, ""));
    assert!(!warned(1.0, ""));
    assert!(!warned(1e-15, ""));
    assert!(
        !warned(1e-21, "light 0 0 -1\n"),
        "a light far off lights it"
    );
}
