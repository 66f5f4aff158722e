//! Placed meshes as a scene stores and loads them: one stored mesh for a thousand placements,
//! coincident placements left out, `.scene` files that place OBJ meshes, colour runs, and a
//! scene without a camera or light framed and lit; each still answers and renders as the same
//! scene flattened into world triangles (the queries themselves: tests/library/instances.rs).

use crate::common;
use crate::instances::{auto, mesh, placement, rays_at, scene_with, triangles};
use common::{icosphere, same_hit, Rng};
use glam::{DMat4, DVec3};
use raylab::geometry::{Method, Ray, Shape, Triangle};
use raylab::render::{render_image, LabStep, RenderSettings, Stage};
use raylab::scene::{cornell, Instance, Mesh, Scene};
use raylab::Camera;
use std::sync::Arc;

#[test]
fn a_thousand_placements_store_the_mesh_once() {
    let mut rng = Rng(9);
    let mesh = mesh("ball", &icosphere(4, 0.5, [0.0; 3]), &mut rng); // 5,120 triangles
    let n = mesh.triangles.len();
    let instances: Vec<Instance> = (0..1000)
        .map(|k| Instance {
            mesh: mesh.clone(),
            world_from_object: DMat4::from_translation(DVec3::new(
                (k % 40) as f64 * 1.5,
                0.0,
                (k / 40) as f64 * 1.5,
            )),
            first_prim: (k * n) as u32,
            color: [0.5; 3],
            tint: None,
        })
        .collect();
    let scene = Scene::new("field", vec![], vec![], cornell::LIGHT, cornell::AMBIENT)
        .with_instances(instances)
        .unwrap();
    assert_eq!(scene.len(), 1000 * n);
    let accel = auto(&scene);
    assert_eq!(accel.triangle_count(), 1000 * n);
    // One mesh hierarchy (~60 bytes a triangle) and ~250 bytes per placement; flattened,
    // 5.1M triangles would take ~300 MB.
    let bytes = accel.memory_bytes();
    assert!(bytes < 2_000_000, "{bytes} bytes");
    // A ray down the row of balls hits the first (primitive of placement 0), and one from
    // above the last placement hits it.
    let hit = accel
        .closest_hit(
            &Ray::new([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            Method::Adaptive,
            0.0,
            f32::INFINITY,
        )
        .unwrap();
    assert!((hit.prim as usize) < n, "{}", hit.prim);
    assert!((hit.t - 4.5).abs() < 0.01, "{}", hit.t);
    let last = [39.0 * 1.5, -5.0, 24.0 * 1.5];
    let hit = accel
        .closest_hit(
            &Ray::new(last, [0.0, 1.0, 0.0]),
            Method::Adaptive,
            0.0,
            f32::INFINITY,
        )
        .unwrap();
    assert_eq!(hit.prim as usize / n, 999);
}

#[test]
fn coincident_placements_are_left_out_and_answer_as_flattened() {
    // 100 placements of one mesh by the same matrix, among two others (one of them placed
    // twice too): the copies are left out at build (triangles and walks), and every query
    // answers as the flattened scene, whose structure keeps one of each copied triangle.
    let mut rng = Rng(77);
    let mesh = mesh("ball", &icosphere(2, 0.6, [0.0; 3]), &mut rng);
    let n = mesh.triangles.len();
    let (a, b, c) = (
        placement(&mut rng),
        placement(&mut rng),
        placement(&mut rng),
    );
    let mut placements = vec![a, b];
    placements.extend(std::iter::repeat_n(a, 99));
    placements.extend([c, b]);
    let scene = scene_with(&mesh, &placements, &mut rng);
    let accel = auto(&scene);
    let distinct = 3 * n;
    let explicit = accel.stored_triangle_count();
    assert_eq!(accel.triangle_count(), distinct + explicit);
    assert_eq!(accel.copies_left_out(), 100 * n);
    let flat = scene.flattened();
    let reference = auto(&flat);
    for ray in rays_at(&flat, &mut rng, 300) {
        for method in Method::ALL {
            let want = reference.closest_hit(&ray, method, 0.0, f32::INFINITY);
            let got = accel.closest_hit(&ray, method, 0.0, f32::INFINITY);
            same_hit(method, &ray, got, want, &format!("{method} {ray:?}"));
            for tmax in [0.5, 2.0] {
                let want = reference.any_hit(&ray, method, 0.0, tmax, u32::MAX);
                let got = accel.any_hit(&ray, method, 0.0, tmax, u32::MAX);
                assert_eq!(got, want, "{method} any hit to {tmax} {ray:?}");
            }
        }
    }
}

/// An OBJ file of `shapes` (triangles), one `v` per corner.
fn obj_text(shapes: &[Shape<f32>]) -> String {
    let mut text = String::from("# test mesh\n");
    for v in triangles(shapes) {
        for p in v {
            text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
        }
    }
    for i in 0..shapes.len() {
        text += &format!("f {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3);
    }
    text
}

#[test]
fn a_scene_file_places_repeated_meshes_as_instances() {
    let dir = tempfile::tempdir().unwrap();
    let ball = icosphere(2, 0.5, [0.1, 0.2, 0.3]); // 320 triangles
    let mut ball_obj = obj_text(&ball);
    // A zero-area face: kept (never hit) with a warning, which the scene shows under the
    // mesh's line.
    ball_obj += "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 961 962 963\n";
    std::fs::write(dir.path().join("ball.obj"), ball_obj).unwrap();
    std::fs::write(
        dir.path().join("tri.obj"),
        obj_text(&icosphere(0, 1.0, [0.0; 3])),
    )
    .unwrap();
    let text = "\
tri 0 0 0 1 0 0 0 1 0
push
  translate 1 0 0
  rotate y 33
  scale 0.5
  color 0.9 0.1 0.1
  mesh ball.obj
pop
sphere 0 0 3 0.5
push
  translate -1 0.5 0
  rotate x 90
  mesh ball.obj
  push
    scale 1e7 1e-7 1
    mesh ball.obj
  pop
pop
mesh tri.obj
push
  rotate z 180
  mesh ball.obj lab
  mesh ball.obj lab
pop
";
    let path = dir.path().join("t.scene");
    std::fs::write(&path, text).unwrap();
    let scene = raylab::scene::load_scene_file(&path).unwrap();
    // ball.obj (yup) 3 uses: 2 placed, the ill-conditioned one flattened; ball.obj lab 2
    // uses, both placed; tri.obj (20 faces, used once) flattened.
    assert_eq!(scene.instances().len(), 4);
    let load = |p: &std::path::Path, frame, color| {
        raylab::scene::obj::load_obj_file_coloured(p, frame, color).map_err(|e| e.to_string())
    };
    let name = path.display().to_string();
    let flat = raylab::scene::file::parse::<f32>(&name, text, dir.path(), &load).unwrap();
    assert_eq!(scene.len(), flat.shapes.len());
    assert_eq!(scene.len(), 1 + 321 * 5 + 1 + 20);
    for (p, (shape, color)) in flat.shapes.iter().zip(&flat.colors).enumerate() {
        assert_eq!(scene.shape(p as u32), *shape, "primitive {p}");
        assert_eq!(scene.color(p as u32), *color, "colour of {p}");
    }
    assert_eq!(scene.levels, flat.levels);
    let degenerate = scene
        .warnings
        .iter()
        .filter(|w| {
            w.contains("mesh 'ball.obj'") && w.contains("ball.obj:1285: triangle 320 has zero area")
        })
        .count();
    assert_eq!(degenerate, 2, "{:?}", scene.warnings); // once per frame it is loaded in
    assert!(scene.warnings[0].contains(":7:"), "{:?}", scene.warnings);
    // And the flattened description renders as the scene does.
    let flat_scene = Stage::from(Scene::from_description(&name, flat).unwrap());
    let stage = Stage::from(scene);
    let cam = Camera::from_yaw_pitch(DVec3::new(0.0, 0.0, -6.0), 0.0, 0.0, 50.0).unwrap();
    assert_same_images(
        &stage,
        &flat_scene,
        &cam,
        (96, 64),
        &[LabStep::Flat, LabStep::Shadows],
    );
}

#[test]
fn colour_runs_hold_their_primitives_colour_and_flat_images_use_them() {
    // `Scene::color_run`: the flat frame reuses an encoded colour over a run of primitives,
    // so every primitive of a run must show the run's colour; an instance of a mesh without
    // colours of its own (or tinted) is one run, other primitives runs of one.
    let mut rng = Rng(5);
    let ball = icosphere(1, 0.3, [0.0; 3]);
    let coloured = mesh("coloured", &ball, &mut rng);
    let plain = Arc::new(Mesh::new(
        "plain".into(),
        triangles(&ball),
        vec![None; ball.len()],
    ));
    for (m, whole) in [(&coloured, 1), (&plain, 4)] {
        let placements: Vec<DMat4> = (0..4).map(|_| placement(&mut rng)).collect();
        let scene = scene_with(m, &placements, &mut rng);
        let mut long_runs = std::collections::BTreeSet::new();
        for p in 0..scene.len() as u32 {
            let (run, c) = scene.color_run(p);
            assert!(run.contains(&p), "{p} outside {run:?}");
            assert_eq!(c, scene.color(p), "{p}");
            if run.len() > 1 {
                assert!(run.clone().all(|q| scene.color(q) == c), "{run:?}");
                long_runs.insert((run.start, run.end));
            }
        }
        assert_eq!(long_runs.len(), whole, "{}", m.name);
    }
    // Four plain balls in differing colours in the Cornell box, more triangles than an
    // eighth of the camera rays (no colour table): the flat image equals the flattened one.
    let mut shapes = cornell::scene().shapes;
    let colors = cornell::scene().colors().to_vec();
    let at = |x: f64, z: f64| DMat4::from_translation(DVec3::new(x, 0.65, z));
    let big = icosphere(2, 0.3, [0.0; 3]);
    let plain = Arc::new(Mesh::new(
        "plain".into(),
        triangles(&big),
        vec![None; big.len()],
    ));
    let instances: Vec<Instance> = [(-0.5, -0.5), (0.1, -0.7), (0.6, -0.5), (0.0, 0.2)]
        .iter()
        .enumerate()
        .map(|(k, &(x, z))| Instance {
            mesh: plain.clone(),
            world_from_object: at(x, z),
            first_prim: (shapes.len() + k * big.len()) as u32,
            color: [0.2 * k as f32, 0.5, 0.9 - 0.2 * k as f32],
            tint: None,
        })
        .collect();
    shapes.truncate(colors.len());
    let scene = Scene::new(
        "plain balls",
        shapes,
        colors,
        cornell::LIGHT,
        cornell::AMBIENT,
    )
    .with_instances(instances)
    .unwrap();
    let settings = RenderSettings {
        width: 64,
        height: 48,
        ..Default::default()
    };
    assert!(scene.len() * 8 > 64 * 48);
    let (a, _) = render_image(&scene.clone().into(), &Camera::cornell(64), &settings).unwrap();
    let (b, _) = render_image(&scene.flattened().into(), &Camera::cornell(64), &settings).unwrap();
    assert!(a == b, "flat images differ");
    let colours: std::collections::BTreeSet<&[u8]> = a.chunks(4).collect();
    assert!(colours.len() > 8, "{} colours", colours.len());
}

#[test]
fn an_instanced_scene_without_camera_or_light_is_framed_and_lit_as_flattened() {
    // Only placed meshes, turned so that their boxes carried into the world are larger than
    // their triangles' box: the default light and camera come from the triangles' real box,
    // so the instanced scene and the same file flattened give the same bounds, light and image.
    let dir = tempfile::tempdir().unwrap();
    let ball = icosphere(2, 0.5, [0.1, 0.2, 0.3]);
    std::fs::write(dir.path().join("ball.obj"), obj_text(&ball)).unwrap();
    let text = "\
push
  rotate y 37
  rotate x 21
  mesh ball.obj
pop
push
  translate 1.3 0.2 0.4
  rotate z 50
  scale 0.7 1.6 1
  mesh ball.obj
pop
";
    let path = dir.path().join("two.scene");
    std::fs::write(&path, text).unwrap();
    let scene = raylab::scene::load_scene_file(&path).unwrap();
    assert_eq!(scene.instances().len(), 2);
    let load = |p: &std::path::Path, frame, color| {
        raylab::scene::obj::load_obj_file_coloured(p, frame, color).map_err(|e| e.to_string())
    };
    let name = path.display().to_string();
    let flat = raylab::scene::file::parse::<f32>(&name, text, dir.path(), &load).unwrap();
    let flat = Scene::from_description(&name, flat).unwrap();
    assert!(flat.instances().is_empty());
    let bounds = scene.bounds().unwrap();
    assert_eq!(Some(bounds), flat.bounds());
    // The bounds are the triangles' own: some vertex lies on each face of the box.
    let on_face = |k: usize, x: f32| {
        (0..scene.len() as u32).any(|p| match scene.shape(p) {
            Shape::Triangle(Triangle(v)) => v.iter().any(|q| q[k] == x),
            _ => false,
        })
    };
    for k in 0..3 {
        assert!(
            on_face(k, bounds.0[k]) && on_face(k, bounds.1[k]),
            "axis {k}"
        );
    }
    assert_eq!(scene.light, flat.light);
    let (w, h) = (96, 72);
    let cam = raylab::controller::CameraController::framing(bounds, w, h).camera(w);
    let (scene, flat) = (Stage::from(scene), Stage::from(flat));
    let steps = [LabStep::Flat, LabStep::Shadows, LabStep::Indirect];
    assert_same_images(&scene, &flat, &cam, (w, h), &steps);
}

/// Asserts that stages `a` and `b` render the same image through `cam` at each of `steps`.
fn assert_same_images(a: &Stage, b: &Stage, cam: &Camera, (w, h): (u32, u32), steps: &[LabStep]) {
    for &step in steps {
        let settings = RenderSettings {
            width: w,
            height: h,
            step,
            ..Default::default()
        };
        let x = render_image(a, cam, &settings).unwrap().0;
        let y = render_image(b, cam, &settings).unwrap().0;
        assert!(x == y, "{step}: images differ");
    }
}
