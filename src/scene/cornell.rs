//! The lab's Cornell box, shipped as `assets/cornell_lab.obj` and compiled into the binary.
//!
//! 30 triangles: the room (L = 555) and a short red and a tall blue block, every lab vertex
//! mapped by v·2/L − 1 and then x and y negated (y points down). Light at (0, −0.5, −0.7) with
//! power 14·(1, 1, 1); the indirect approximation is 0.5·(1, 1, 1).

use super::{obj, PointLight, Scene};

/// The OBJ text of the lab scene.
pub const OBJ: &str = include_str!("../../assets/cornell_lab.obj");
/// Its material library.
pub const MTL: &str = include_str!("../../assets/cornell_lab.mtl");

/// The lab light.
pub const LIGHT: PointLight = PointLight {
    position: [0.0, -0.5, -0.7],
    power: [14.0, 14.0, 14.0],
};

/// The lab's indirect-light approximation.
pub const AMBIENT: [f32; 3] = [0.5, 0.5, 0.5];

/// Builds the scene from the embedded OBJ.
pub fn scene() -> Scene {
    let mut scene = obj::load_obj_str("cornell", OBJ, obj::ObjFrame::Lab, |_| Ok(MTL.to_string()))
        .expect("the embedded Cornell box is valid");
    scene.light = LIGHT;
    scene.ambient = AMBIENT;
    scene
}
