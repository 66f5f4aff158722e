//! An instanced scene is framed and lit as its flattened twin: its bounds are the same bits
//! (or none for both).

use raylab::controller::CameraController;
use raylab::scene::file::{load_obj_mesh, load_scene_file, parse};
use raylab::Scene;

/// A bumpy strip of `n` triangles as OBJ text (coordinates that rotations round).
fn strip(n: usize) -> String {
    let mut text = String::new();
    for i in 0..n + 2 {
        let z = ((i * 7919) % 13) as f32 * 0.0371;
        text += &format!("v {} {} {z}\n", i as f32 * 0.173, (i % 2) as f32 * 1.31);
    }
    for i in 1..=n {
        text += &format!("f {} {} {}\n", i, i + 1, i + 2);
    }
    text
}

#[test]
fn an_instanced_scene_is_framed_and_lit_as_its_flattened_twin() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("strip.obj"), strip(100)).unwrap();
    // Placements that only move, scale, mirror and turn by quarter turns (bounded by the
    // mesh's box), and turns by other angles: some at the scene's edges (walked vertex by
    // vertex), some inside (bounded by their boxes alone), none lit by a `light` line.
    let mut text = String::from("tri -1 -1 2 1 -1 2 0 1 2\n");
    for (k, placement) in [
        "translate 3 0 0",
        "scale -2 1 0.5",
        "rotate z 90\nscale 1 3 1",
        "translate 0.1 0.2 0.3\nrotate y 33",
        "translate -40 7 3\nrotate x 17\nrotate z 61",
        "rotate x 45\nscale 0.25",
        "translate 2 1 1\nrotate y 180\nscale 1.1 0.9 1.7",
        "translate 0 0 55\nrotate z 5",
    ]
    .iter()
    .enumerate()
    {
        text += &format!("push\n{placement}\ncolor 0.{k} 0.5 0.5\nmesh strip.obj\npop\n");
    }
    let path = dir.path().join("s.scene");
    std::fs::write(&path, &text).unwrap();
    let instanced = load_scene_file(&path).unwrap();
    assert_eq!(instanced.instances().len(), 8);
    let name = path.display().to_string();
    let flat = parse::<f32>(&name, &text, dir.path(), &load_obj_mesh).unwrap();
    let flat = Scene::from_description(&name, flat).unwrap();
    assert!(flat.instances().is_empty());
    let bits = |b: ([f32; 3], [f32; 3])| (b.0.map(f32::to_bits), b.1.map(f32::to_bits));
    let (a, b) = (instanced.bounds().unwrap(), flat.bounds().unwrap());
    assert_eq!(bits(a), bits(b), "{a:?} {b:?}");
    // The light placed for the bounds, and the camera framing them, are the same.
    assert_eq!(instanced.light, flat.light);
    let (ca, cb) = (
        CameraController::framing(a, 320, 200),
        CameraController::framing(b, 320, 200),
    );
    assert_eq!(ca.position, cb.position);
    assert_eq!(instanced.size(), flat.size());
}

#[test]
fn placements_of_an_empty_mesh_alone_have_no_bounds_as_flattened() {
    use raylab::scene::{Instance, Mesh};
    use std::sync::Arc;
    let empty = Arc::new(Mesh::new("empty".into(), Vec::new(), Vec::new()));
    let placed = |m: glam::DMat4| Instance {
        mesh: empty.clone(),
        world_from_object: m,
        first_prim: 0,
        color: [1.0; 3],
        tint: None,
    };
    let turned = glam::DMat4::from_rotation_z(0.3);
    let instances = vec![placed(glam::DMat4::IDENTITY), placed(turned)];
    let scene = |shapes: Vec<raylab::geometry::Shape>| {
        let colors = vec![[1.0; 3]; shapes.len()];
        let (light, ambient) = (Scene::cornell().light, [0.1; 3]);
        Scene::new("e", shapes, colors, light, ambient)
    };
    let instanced = scene(Vec::new()).with_instances(instances.clone()).unwrap();
    let flat = scene(instanced.all_shapes().collect());
    assert_eq!(flat.bounds(), None);
    assert_eq!(instanced.bounds(), None);
    // With a shape, the shape's box for both.
    let tri = raylab::geometry::Shape::from([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]);
    let instanced = scene(vec![tri]).with_instances(instances).unwrap();
    assert_eq!(instanced.bounds(), Some(([0.0, 0.0, 1.0], [1.0, 1.0, 1.0])));
}
