//! Property-based fuzzing of every text parser (cargo-fuzz needs a nightly toolchain, which this
//! project's machines do not have): OBJ-to-scene, the `trace` formats. Inputs are built from
//! the formats' own tokens, mixed with hostile ones (NaN, inf, 1e39, 0 and negative and huge
//! indices, junk, control bytes), so most cases get past the first line. Every input must give
//! `Ok` or an `Err` naming a line, never a panic; an `Ok` scene must be safe to render.
//!
//! More cases: `PROPTEST_CASES=100000 cargo test --release --test library fuzz::`.

use proptest::prelude::*;
use raylab::geometry::{Shape, Sphere, Triangle};
use raylab::scene::{load_obj_str, ObjFrame};
use raylab::tracefile::{parse_rays, parse_scene};

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-1e3f32..1e3).prop_map(|x| x.to_string()),
        (-5i64..5).prop_map(|x| x.to_string()),
        Just("nan".to_string()),
        Just("-inf".to_string()),
        Just("inf".to_string()),
        Just("1e39".to_string()),
        Just("-1e-45".to_string()),
        Just("0x10".to_string()),
        Just("1e30".to_string()),
        Just("1e-30".to_string()),
        Just("3e11".to_string()),
        Just("".to_string()),
        "[a-z#/.]{1,3}",
    ]
}

fn index() -> impl Strategy<Value = String> {
    prop_oneof![
        (1i64..12).prop_map(|x| x.to_string()),
        (-12i64..0).prop_map(|x| x.to_string()),
        Just("0".to_string()),
        Just("99999999999".to_string()),
        Just("-9223372036854775808".to_string()),
        Just("18446744073709551617".to_string()),
        ((1i64..12), (1i64..4)).prop_map(|(v, t)| format!("{v}/{t}")),
        ((1i64..12), (1i64..4)).prop_map(|(v, n)| format!("{v}//{n}")),
        Just("1/2/3/4".to_string()),
        Just("x".to_string()),
    ]
}

/// Spaces or TABs between words.
fn gap() -> impl Strategy<Value = &'static str> {
    prop_oneof![4 => Just(" "), 1 => Just("\t"), 1 => Just(" \t ")]
}

fn obj_line() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (prop::collection::vec(number(), 0..8), gap())
            .prop_map(|(n, g)| format!("v{g}{}", n.join(g))),
        4 => (prop::collection::vec(index(), 0..7), gap())
            .prop_map(|(i, g)| format!("f{g}{}", i.join(g))),
        1 => prop::collection::vec(index(), 0..5).prop_map(|i| format!("l {}", i.join(" "))),
        1 => prop::collection::vec(index(), 0..3).prop_map(|i| format!("p {}", i.join(" "))),
        1 => prop::collection::vec(number(), 0..4).prop_map(|n| format!("curv {}", n.join(" "))),
        1 => (prop::collection::vec(number(), 3..4), "[ -~]{0,8}")
            .prop_map(|(n, c)| format!("v {} # {c}", n.join(" "))),
        1 => prop::collection::vec(number(), 0..3).prop_map(|n| format!("vt {}", n.join(" "))),
        1 => prop::collection::vec(number(), 0..4).prop_map(|n| format!("vn {}", n.join(" "))),
        1 => ("[a-z]{0,6}", gap()).prop_map(|(m, g)| format!("usemtl{g}{m}")),
        1 => "[a-z./]{0,8}".prop_map(|m| format!("mtllib {m}")),
        1 => "[a-z]{0,6}".prop_map(|m| format!("o {m}")),
        1 => "[ -~]{0,20}",
        1 => prop::collection::vec(any::<char>(), 0..8).prop_map(|c| c.into_iter().collect::<String>()),
    ]
}

fn mtl_text() -> impl Strategy<Value = String> {
    prop::collection::vec(
        prop_oneof![
            "[a-z]{0,6}".prop_map(|m| format!("newmtl {m}")),
            prop::collection::vec(number(), 0..4).prop_map(|n| format!("Kd {}", n.join(" "))),
            (
                prop_oneof![
                    Just("Ns"),
                    Just("d"),
                    Just("illum"),
                    Just("map_Kd"),
                    Just("Ni")
                ],
                number()
            )
                .prop_map(|(k, n)| format!("{k} {n}")),
            "[ -~]{0,16}",
        ],
        0..8,
    )
    .prop_map(|l| l.join("\n"))
}

fn assert_safe_scene(scene: &raylab::Scene) {
    assert_eq!(scene.shapes.len(), scene.colors().len());
    assert!(!scene.shapes.is_empty());
    for (s, c) in scene.shapes.iter().zip(scene.colors()) {
        let Shape::Triangle(Triangle(v)) = s else {
            panic!("OBJ gives triangles only")
        };
        assert!(v.iter().flatten().all(|x| x.is_finite()), "{v:?}");
        assert!(c.iter().all(|x| (0.0..=1.0).contains(x)), "{c:?}");
    }
    assert!(scene.light.position.iter().all(|x| x.is_finite()));
}

proptest! {
    #![proptest_config(crate::cases(2000))]

    #[test]
    fn obj_text_never_panics(lines in prop::collection::vec(obj_line(), 0..40), mtl in mtl_text()) {
        let text = lines.join("\n");
        for frame in [ObjFrame::YUp, ObjFrame::Lab] {
            match load_obj_str("fuzz.obj", &text, frame, |_| Ok(mtl.clone())) {
                Ok(scene) => assert_safe_scene(&scene),
                // Every error names the file, and the line unless the file as a whole is
                // wrong (nothing to draw).
                Err(e) => {
                    let e = e.to_string();
                    let line = e
                        .strip_prefix("fuzz.obj:")
                        .and_then(|rest| rest.split(':').next())
                        .is_some_and(|n| n.parse::<usize>().is_ok());
                    let nothing = ["fuzz.obj: no triangles", "fuzz.obj: has no triangle of"];
                    prop_assert!(line || nothing.iter().any(|n| e.starts_with(n)), "{e}");
                }
            }
        }
    }

    #[test]
    fn arbitrary_bytes_as_obj_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        if let Ok(scene) = load_obj_str("bytes.obj", &text, ObjFrame::YUp, |_| Err("none".into())) {
            assert_safe_scene(&scene);
        }
    }

    #[test]
    fn trace_scene_text_never_panics(lines in prop::collection::vec(
        (prop_oneof![Just("tri"), Just("sphere"), Just("#"), Just(""), Just("cube")],
         prop::collection::vec(number(), 0..11)),
        0..20,
    )) {
        let text: String = lines.iter().map(|(k, n)| format!("{k} {}\n", n.join(" "))).collect();
        match parse_scene::<f32>("s.txt", &text) {
            Ok((shapes, _)) => {
                for s in shapes {
                    match s {
                        Shape::Triangle(Triangle(v)) => prop_assert!(v.iter().flatten().all(|x| x.is_finite())),
                        Shape::Sphere(Sphere { centre, radius }) => {
                            prop_assert!(centre.iter().all(|x| x.is_finite()));
                            prop_assert!(radius > 0.0 && radius.is_finite());
                        }
                    }
                }
            }
            Err(e) => prop_assert!(e.line >= 1 && e.file == "s.txt"),
        }
        let _ = parse_scene::<f64>("s.txt", &text);
    }

    #[test]
    fn scene_files_never_panic(lines in prop::collection::vec(
        (prop_oneof![
            Just("tri"), Just("sphere"), Just("push"), Just("pop"), Just("translate"),
            Just("rotate x"), Just("rotate y"), Just("scale"), Just("color"), Just("light"),
            Just("ambient"), Just("camera"), Just("cornell"), Just("mesh"), Just("bogus"),
        ], prop::collection::vec(number(), 0..10)),
        0..16,
    )) {
        let text: String = lines.iter().map(|(k, n)| format!("{k} {}\n", n.join(" "))).collect();
        let no_meshes = |_: &std::path::Path, _, _| Err("no meshes here".to_string());
        let parsed = raylab::scene::file::parse::<f32>("f.scene", &text, std::path::Path::new(""), &no_meshes);
        match parsed {
            Ok(d) => match raylab::Scene::from_description("f.scene", d) {
                Ok(scene) => {
                    if scene.check_ranges().is_ok() {
                        let finite = scene.shapes.iter().all(|s| {
                            let (lo, hi) = s.bounds();
                            lo.iter().chain(&hi).all(|x| x.is_finite())
                        });
                        prop_assert!(finite);
                    }
                }
                Err(e) => prop_assert!(e.starts_with("f.scene"), "{e}"),
            },
            Err(e) => prop_assert!(e.line >= 1 && e.file == "f.scene", "{e}"),
        }
    }

    #[test]
    fn trace_ray_text_never_panics(lines in prop::collection::vec(prop::collection::vec(number(), 0..10), 0..20)) {
        let text: String = lines.iter().map(|n| format!("{}\n", n.join(" "))).collect();
        match parse_rays::<f32>("r.txt", &text) {
            Ok(rays) => {
                for r in rays {
                    prop_assert!(r.ray.o.iter().chain(&r.ray.d).all(|x| x.is_finite()));
                    prop_assert!(r.ray.d.iter().any(|x| *x != 0.0));
                    prop_assert!(r.tmin <= r.tmax);
                }
            }
            Err(e) => prop_assert!(e.line >= 1),
        }
        let _ = parse_rays::<f64>("r.txt", &text);
    }
}
