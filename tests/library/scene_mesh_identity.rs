//! A mesh is its file, however its path is spelled: `c.obj`, `./c.obj`, `d/../c.obj` and a
//! link to it are one mesh, loaded once and placed as instances of one copy.

use raylab::geometry::Shape;
use raylab::scene::file::{load_obj_mesh, load_scene_file, parse};
use std::sync::Arc;

/// A strip of `n` triangles as OBJ text.
fn strip(n: usize) -> String {
    let mut text = String::new();
    for i in 0..n + 2 {
        text += &format!("v {} {} 0\n", i / 2, i % 2);
    }
    for i in 1..=n {
        text += &format!("f {} {} {}\n", i, i + 1, i + 2);
    }
    text
}

#[test]
fn every_spelling_of_a_mesh_path_is_one_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("grid.obj"), strip(128)).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    std::os::unix::fs::symlink(d.join("grid.obj"), d.join("link.obj")).unwrap();
    // Five uses in the usual frame under four spellings (one with the frame written out), one
    // in the lab's frame.
    let text = "\
mesh grid.obj
translate 0 0 1
mesh ./grid.obj
translate 0 0 1
mesh sub/../grid.obj
translate 0 0 1
mesh link.obj
translate 0 0 1
mesh ./grid.obj yup
mesh grid.obj lab
";
    let path = d.join("s.scene");
    std::fs::write(&path, text).unwrap();
    let scene = load_scene_file(&path).unwrap();
    // Placed five times, one copy of the mesh behind them all; used once, the lab frame's
    // triangles are stored one by one.
    let instances = scene.instances();
    assert_eq!(instances.len(), 5);
    assert!(instances
        .iter()
        .all(|i| Arc::ptr_eq(&i.mesh, &instances[0].mesh)));
    assert_eq!(instances[0].mesh.triangles.len(), 128);
    assert_eq!(scene.shapes.len(), 128);
    // The same primitives, in the same order, as the file flattened.
    let flat = parse::<f32>("s.scene", text, d, &load_obj_mesh).unwrap();
    assert_eq!(scene.len(), 6 * 128);
    assert_eq!(flat.shapes.len(), 6 * 128);
    for (p, shape) in flat.shapes.iter().enumerate() {
        assert_eq!(scene.shape(p as u32), *shape, "primitive {p}");
    }
    assert!(matches!(flat.shapes[4 * 128], Shape::Triangle(_)));
}
