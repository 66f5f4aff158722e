//! The built-in Cornell box against the lab's own numbers, and the core's independence from
//! the window stack.

use raylab::geometry::Shape;
use raylab::Scene;

/// The lab's `LoadTestModel`, in f32 and in its order: room, short block, tall block.
fn lab_triangles() -> Vec<([[f32; 3]; 3], [f32; 3])> {
    let l = 555.0f32;
    let (red, yellow, green) = ([0.75, 0.15, 0.15], [0.75, 0.75, 0.15], [0.15, 0.75, 0.15]);
    let (cyan, blue, purple) = ([0.15, 0.75, 0.75], [0.15, 0.15, 0.75], [0.75, 0.15, 0.75]);
    let white = [0.75f32, 0.75, 0.75];
    let mut tris = Vec::new();
    let (a, b, c, d) = ([l, 0.0, 0.0], [0.0, 0.0, 0.0], [l, 0.0, l], [0.0, 0.0, l]);
    let (e, f, g, h) = ([l, l, 0.0], [0.0, l, 0.0], [l, l, l], [0.0, l, l]);
    for (t, col) in [
        ([c, b, a], green),
        ([c, d, b], green),
        ([a, e, c], purple),
        ([c, e, g], purple),
        ([f, b, d], yellow),
        ([h, f, d], yellow),
        ([e, f, g], cyan),
        ([f, h, g], cyan),
        ([g, d, c], white),
        ([g, h, d], white),
    ] {
        tris.push((t, col));
    }
    let block = |corners: [[f32; 2]; 4], height: f32, col: [f32; 3], tris: &mut Vec<_>| {
        let [a, b, c, d] = corners.map(|p| [p[0], 0.0, p[1]]);
        let [e, f, g, h] = corners.map(|p| [p[0], height, p[1]]);
        for t in [
            [e, b, a],
            [e, f, b],
            [f, d, b],
            [f, h, d],
            [h, c, d],
            [h, g, c],
            [g, e, c],
            [e, a, c],
            [g, f, e],
            [g, h, f],
        ] {
            tris.push((t, col));
        }
    };
    block(
        [[290.0, 114.0], [130.0, 65.0], [240.0, 272.0], [82.0, 225.0]],
        165.0,
        red,
        &mut tris,
    );
    block(
        [
            [423.0, 247.0],
            [265.0, 296.0],
            [472.0, 406.0],
            [314.0, 456.0],
        ],
        330.0,
        blue,
        &mut tris,
    );
    // v *= 2/L; v -= (1,1,1); v.x *= -1; v.y *= -1 — in f32, in this order.
    for (t, _) in &mut tris {
        for v in t.iter_mut() {
            for c in v.iter_mut() {
                *c *= 2.0 / l;
                *c -= 1.0;
            }
            v[0] *= -1.0;
            v[1] *= -1.0;
        }
    }
    tris
}

#[test]
fn cornell_box_is_the_labs_30_triangles_bit_for_bit() {
    let scene = Scene::cornell();
    let lab = lab_triangles();
    assert_eq!(scene.len(), 30);
    assert_eq!(lab.len(), 30);
    for (k, ((tri, col), (shape, scene_col))) in lab
        .iter()
        .zip(scene.shapes.iter().zip(&scene.colors))
        .enumerate()
    {
        assert_eq!(*shape, Shape::Triangle(*tri), "triangle {k}");
        assert_eq!(scene_col, col, "colour of triangle {k}");
    }
    assert_eq!(scene.light.position, [0.0, -0.5, -0.7]);
    assert_eq!(scene.light.power, [14.0; 3]);
    assert_eq!(scene.ambient, [0.5; 3]);
    assert!(scene.warnings.is_empty());
    let (lo, hi) = scene.bounds().unwrap();
    assert_eq!((lo, hi), ([-1.0; 3], [1.0; 3]));
}

#[test]
fn shipped_asset_matches_the_shared_scene_when_present() {
    let shared =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/cornell_lab.obj");
    let Ok(text) = std::fs::read_to_string(&shared) else {
        eprintln!("SKIPPED: {} not present", shared.display());
        return;
    };
    assert_eq!(text, raylab::scene::cornell::OBJ);
}

#[test]
fn obj_polygons_are_triangulated_and_colours_read() {
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\nusemtl a\nf 1 2 3 5 4\nusemtl b\nf -5 -4 -3\n";
    let mtl = "newmtl a\nKd 0.2 0.4 0.6\nnewmtl b\nKd 2 -1 0.5\n";
    let scene = raylab::scene::load_obj_str("t.obj", obj, raylab::scene::ObjFrame::Lab, |name| {
        assert_eq!(name, "m.mtl");
        Ok(mtl.to_string())
    })
    .unwrap();
    assert_eq!(scene.len(), 4, "a pentagon fans into 3 triangles, plus one");
    assert_eq!(scene.colors[0], [0.2, 0.4, 0.6]);
    assert_eq!(scene.colors[3], [1.0, 0.0, 0.5], "Kd is clamped to [0, 1]");
    assert_eq!(
        scene.shapes[3],
        Shape::Triangle([[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
    );
}

#[test]
fn the_core_never_imports_the_window_stack() {
    // Everything under src/ but the window shell (src/app) must build without winit, egui
    // and pixels: `cargo test --no-default-features` proves it by building; this keeps it so.
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut stack = vec![src.clone()];
    let mut checked = 0;
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                if path != src.join("app") {
                    stack.push(path);
                }
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            for krate in ["winit", "egui", "pixels", "wgpu"] {
                for pattern in [format!("use {krate}"), format!("{krate}::")] {
                    let found = text.lines().any(|l| {
                        let l = l.trim_start();
                        !l.starts_with("//") && l.contains(&pattern)
                    });
                    assert!(!found, "{} uses {krate}", path.display());
                }
            }
            checked += 1;
        }
    }
    assert!(checked >= 10, "checked {checked} files");
}

#[test]
fn y_up_models_are_turned_into_the_lab_frame() {
    let obj = "v 1 2 3\nv 4 5 6\nv 7 8 10\nf 1 2 3\n";
    let no_mtl = |_: &str| Err("none".to_string());
    let lab =
        raylab::scene::load_obj_str("t.obj", obj, raylab::scene::ObjFrame::Lab, no_mtl).unwrap();
    let yup =
        raylab::scene::load_obj_str("t.obj", obj, raylab::scene::ObjFrame::YUp, no_mtl).unwrap();
    assert_eq!(
        lab.shapes[0],
        Shape::Triangle([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 10.0]])
    );
    assert_eq!(
        yup.shapes[0],
        Shape::Triangle([[-1.0, -2.0, 3.0], [-4.0, -5.0, 6.0], [-7.0, -8.0, 10.0]])
    );
}
