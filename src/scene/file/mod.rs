//! The `.scene` format: scenes built with the lecture's transform stack.
//!
//! One statement per line; `#` starts a comment that runs to the end of the line; blank lines
//! and surrounding whitespace are ignored.
//! ```text
//! tri x0 y0 z0 x1 y1 z1 x2 y2 z2   a triangle, vertices in the current frame
//! sphere cx cy cz r                a sphere, centre and radius in the current frame
//! mesh PATH.obj [yup|lab]          an OBJ's triangles (PATH relative to the scene file; in
//!                                   double quotes if it holds spaces or #: "my mesh.obj")
//! cornell                          the built-in lab Cornell box (its 30 triangles)
//! color r g b                      linear-RGB diffuse colour of the primitives that follow
//! push | pop                       save / restore the current transform and colour
//! translate x y z                  M <- M*T
//! rotate x|y|z DEG                 M <- M*R
//! scale s | scale sx sy sz         M <- M*S
//! light x y z [p]                  the point light, in the current frame; power p per channel
//! ambient r g b                    the lab's indirect term N
//! camera x y z [yaw DEG] [pitch DEG] [fov DEG]   the starting camera, in world coordinates
//! ```
//! Writing translate, rotate, scale gives the lecture's M = T·R·S: a vertex is scaled first,
//! then rotated, then translated. Transforms in another order within one push level get a
//! warning naming the line (the lecture: pick an order and stick with it).
//!
//! A primitive's index is its position among all primitives in file order (a mesh adds its
//! triangles in its file order, `cornell` its 30). World coordinates are the current matrix
//! applied to the file's numbers in f64 (every number, product and sum rounded to f64), then
//! rounded to the chosen precision: for f32 two roundings, not one (tests/library/scene_file.rs
//! pins the rule on a coordinate next to an f32 midpoint); where the
//! matrix is the identity the numbers are read straight in that precision, so the files of
//! `raylab trace` (only `tri` and `sphere`) mean exactly what they meant before. Rotations
//! by multiples of 90° are exact ([`sin_cos_degrees`]), and so are translations and scales by
//! values exact in f64.
//!
//! A mesh the file uses at least [`Instancing::min_uses`] times (`cornell` counts as one
//! mesh; a file is one mesh however its path is spelled: `c.obj`, `./c.obj`, a link) is
//! loaded once when the scene is loaded for rendering ([`load_scene_file`]). One
//! with at least [`Instancing::min_triangles`] triangles, or whose copies would pass the room
//! for flattened copies ([`crate::limits::flattened_copies_room`], in proportion to the
//! file's size), is placed
//! as instances ([`super::instance`]): the primitives and every answer are the same as
//! flattened, the memory is one copy. (A placement whose matrix is too ill-conditioned to
//! carry rays back safely, see [`super::instance::MAX_CONDITION`], is flattened; such copies
//! are refused only past [`crate::limits::MAX_FLATTENED_COPIES`] triangles, whatever the
//! file's size.) [`parse`] flattens everything.
//!
//! Errors name the file and line: an unknown statement, a missing or extra number, NaN or
//! infinity, a `pop` without `push`, a sphere under a non-uniform scale (an ellipsoid), a mesh
//! that fails to load (with the mesh's own error).
//!
//! [`sin_cos_degrees`]: crate::math::transform::sin_cos_degrees

use super::instance::{Instance, Mesh};
use super::obj::{self, ObjFrame};
use super::{cornell, PointLight, Scene};
use crate::geometry::Shape;
use crate::math::MAX_VIEW_COORDINATE;
use crate::math::{Real, TransformStack};
use glam::DVec3;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

mod matrix;
mod mesh_files;
mod numbers;
mod parser;

pub use parser::{parse, parse_with};

/// When a mesh is stored once and placed as instances instead of flattened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Instancing {
    /// Uses (`mesh` statements naming the same file, however spelled, and frame) from which
    /// it is.
    pub min_uses: usize,
    /// Triangles the mesh must have at least (a small mesh is faster flattened).
    pub min_triangles: usize,
}

impl Instancing {
    /// Never: every mesh flattened.
    pub const NEVER: Instancing = Instancing {
        min_uses: usize::MAX,
        min_triangles: usize::MAX,
    };
    /// What loading a scene for rendering does.
    pub const DEFAULT: Instancing = Instancing {
        min_uses: 2,
        min_triangles: 64,
    };
}

/// The colour of primitives before any `color` statement.
pub const DEFAULT_COLOR: [f32; 3] = obj::DEFAULT_COLOR;

/// The colour a mesh to be instanced is loaded with for faces without a material: no colour
/// statement can give it (channels are ≥ 0), so `mesh_from_scene` knows them.
pub const UNSET_COLOR: [f32; 3] = [-1.0; 3];

/// The lab light's power per channel, the default of `light`.
pub const DEFAULT_POWER: f32 = 14.0;

/// A parse error with its place.
#[derive(Clone, Debug, thiserror::Error, PartialEq, Eq)]
#[error("{file}:{line}: {message}")]
pub struct FileError {
    /// The file name as given.
    pub file: String,
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// The starting camera of a `camera` statement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneCamera {
    /// Position in world coordinates.
    pub position: [f64; 3],
    /// Degrees; positive turns right.
    pub yaw: f64,
    /// Degrees; positive looks up.
    pub pitch: f64,
    /// Horizontal field of view in degrees, if given (else the lab's f = W).
    pub fov: Option<f64>,
}

impl SceneCamera {
    /// The lab's camera: (0, 0, −3.001) looking along +z, f = W.
    pub const LAB: SceneCamera = SceneCamera {
        position: [0.0, 0.0, -3.001],
        yaw: 0.0,
        pitch: 0.0,
        fov: None,
    };

    /// Focal length over image width: 1 (the lab's f = W) without a field of view.
    pub fn focal_ratio(&self) -> f64 {
        self.fov.map_or(1.0, |fov| {
            crate::camera::focal_of_fov(fov.to_radians(), 1.0)
        })
    }
}

/// One push level of the file: the transform-stack inspector's node.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// The `push` line (0 for the file's top level).
    pub line: usize,
    /// Nesting depth (0 at the top).
    pub depth: usize,
    /// The statements written directly in this level, with their lines.
    pub statements: Vec<(usize, String)>,
    /// The matrix at the level's end (row-major rows of `world_from_object`).
    pub world_from_object: [[f64; 4]; 4],
    /// The primitives added directly in this level: indices `first..end`, possibly several
    /// runs (nested levels interleave).
    pub primitives: Vec<std::ops::Range<u32>>,
}

/// What a `.scene` file describes, in precision `T`.
#[derive(Clone, Debug)]
pub struct Description<T: Real> {
    /// The primitives stored one by one (all of them without instancing).
    pub shapes: Vec<Shape<T>>,
    pub colors: Vec<[f32; 3]>,
    /// The meshes placed as instances, in primitive order (see [`Instancing`]).
    pub instances: Vec<Instance>,
    /// The `light` statement, if any: position (world, f32) and power.
    pub light: Option<PointLight>,
    pub ambient: Option<[f32; 3]>,
    pub camera: Option<SceneCamera>,
    /// The first `light` or `camera` beyond ±[`MAX_VIEW_COORDINATE`], the range the f32 core
    /// renders: refused where the scene is rendered ([`Scene::from_description`]), not by
    /// `trace`, which uses neither.
    pub beyond_view: Option<FileError>,
    /// Whether `cornell` was used (the lab's light and camera are then the defaults).
    pub has_cornell: bool,
    pub warnings: Vec<String>,
    /// The push levels in the order their `push` (or the file) starts.
    pub levels: Vec<Level>,
    /// The mesh files the file names (joined to its directory), each once, in first use's
    /// order.
    pub mesh_files: Vec<std::path::PathBuf>,
    /// Where each run of primitives was written: (its first index, its statement's line), in
    /// index order ([`line_of`]).
    pub lines: Vec<(u32, usize)>,
}

/// The line of the statement that added primitive `index` (a shape, a mesh, `cornell`), in a
/// [`Description::lines`].
pub fn line_of(lines: &[(u32, usize)], index: u32) -> Option<usize> {
    let run = lines.partition_point(|&(first, _)| first <= index);
    run.checked_sub(1).map(|r| lines[r].1)
}

/// Loads OBJ meshes for `mesh` statements: `(path, frame, current colour)`.
pub type MeshLoader<'a> = dyn Fn(&Path, ObjFrame, [f32; 3]) -> Result<Scene, String> + 'a;

/// A mesh as loaded into a scene of triangles whose faces without a material were given
/// [`UNSET_COLOR`].
fn mesh_from_scene(scene: &Scene) -> Mesh {
    let triangles = (scene.shapes.iter())
        .map(|s| *s.triangle().expect("meshes hold triangles"))
        .collect();
    let colors = (scene.colors().iter())
        .map(|c| (*c != UNSET_COLOR).then_some(*c))
        .collect();
    Mesh::new(scene.name.clone(), triangles, colors)
}

/// The [`MeshLoader`] of files on disk: an OBJ file, faces without a material in `color`.
pub fn load_obj_mesh(path: &Path, frame: ObjFrame, color: [f32; 3]) -> Result<Scene, String> {
    obj::load_obj_file_coloured(path, frame, color).map_err(|e| e.to_string())
}

/// Loads a `.scene` file as a renderable scene (f32), with its meshes relative to it.
pub fn load_scene_file(path: &Path) -> Result<Scene, String> {
    let name = path.display().to_string();
    let text = read_scene_text(path)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let d = parse_with::<f32>(&name, &text, &dir, &load_obj_mesh, Instancing::DEFAULT)
        .map_err(|e| e.to_string())?;
    Scene::from_description(&name, d)
}

/// A scene file's text: a regular file of at most [`crate::input::max_input_bytes`], UTF-8
/// (a byte-order mark dropped).
pub fn read_scene_text(path: &Path) -> Result<String, String> {
    crate::input::read_text(path, crate::input::max_input_bytes()).map_err(|e| e.to_string())
}

impl Scene {
    /// The scene a parsed `.scene` file describes: its light (else the lab's with `cornell`,
    /// else one placed for the scene's size), ambient term (else the lab's) and camera.
    /// Its primitives and light are checked to be within range, an error naming the line
    /// ([`Scene::check_ranges_at`]).
    pub fn from_description(name: &str, d: Description<f32>) -> Result<Scene, String> {
        if let Some(e) = d.beyond_view {
            return Err(e.to_string());
        }
        let mut scene = Scene::new(
            name,
            d.shapes,
            d.colors,
            cornell::LIGHT,
            d.ambient.unwrap_or(cornell::AMBIENT),
        )
        .with_instances(d.instances)?;
        if scene.is_empty() {
            return Err(format!(
                "{name}: no primitives ({}, mesh or cornell)",
                Shape::<f32>::KEYWORDS.join(", ")
            ));
        }
        scene.light = match (d.light, d.has_cornell) {
            (Some(light), _) => light,
            (None, true) => cornell::LIGHT,
            (None, false) => Scene::light_for_bounds(scene.bounds().expect("not empty")),
        };
        // With the Cornell box and no camera statement: the lab's camera.
        scene.camera = d.camera.or(d.has_cornell.then_some(SceneCamera::LAB));
        scene.levels = d.levels;
        scene.mesh_files = d.mesh_files;
        scene.warnings = d.warnings;
        scene.check_ranges_at(&|index| line_of(&d.lines, index))?;
        Ok(scene)
    }
}
