//! The scenes of the run: which exist and were asked for, loaded, with what each peer is given.

use crate::embree::Placement;
use crate::spheres;
use anyhow::{anyhow, Context as _};
use raylab::camera::Camera;
use raylab::controller::CameraController;
use raylab::geometry::{Shape, Triangle};
use raylab::scene::Mesh;
use raylab::Scene;
use std::path::Path;
use std::sync::Arc;

/// One scene of the run: its name, the raylab scene and its triangles for the peers (empty
/// for the instanced field, which only raylab and Embree render, as `instanced`, and for the
/// balls, which Embree renders as spheres).
pub struct Bench {
    pub name: String,
    pub scene: Scene,
    pub triangles: Vec<[[f32; 3]; 3]>,
    pub instanced: Option<Instanced>,
    /// The same balls as instanced icospheres (a `spheresN` scene), for raylab's second frame.
    pub icospheres: Option<Scene>,
    /// What the scene is, for the notes under the table (a generated scene).
    pub description: Option<String>,
}

/// A scene's instances as Embree places them: the distinct meshes, the placements, and the
/// triangles outside any instance with their primitive numbers.
pub struct Instanced {
    pub meshes: Vec<Arc<Mesh>>,
    pub placements: Vec<Placement>,
    pub loose: Vec<([[f32; 3]; 3], u32)>,
}

impl Instanced {
    /// `scene`'s instances, or `None` if it has none. Spheres outside instances are left out
    /// (the field has none).
    pub fn of(scene: &Scene) -> Option<Self> {
        if scene.instances().is_empty() {
            return None;
        }
        let mut meshes: Vec<Arc<Mesh>> = Vec::new();
        let placements = (scene.instances().iter())
            .map(|inst| {
                let mesh = match meshes.iter().position(|m| Arc::ptr_eq(m, &inst.mesh)) {
                    Some(k) => k,
                    None => {
                        meshes.push(inst.mesh.clone());
                        meshes.len() - 1
                    }
                };
                let m = inst.world_from_object;
                let cols = [m.x_axis, m.y_axis, m.z_axis, m.w_axis];
                Placement {
                    mesh,
                    world_from_object: std::array::from_fn(|i| cols[i / 3][i % 3] as f32),
                    first_prim: inst.first_prim,
                }
            })
            .collect();
        let loose = (scene.explicit_with_prims().into_iter())
            .filter_map(|(shape, prim)| match shape {
                Shape::Triangle(Triangle(v)) => Some((v, prim)),
                Shape::Sphere(_) => None,
            })
            .collect();
        Some(Instanced {
            meshes,
            placements,
            loose,
        })
    }
}

pub fn load_benches(only: &[String], write: Option<&Path>) -> anyhow::Result<Vec<Bench>> {
    let wanted = |name: &str| only.is_empty() || only.iter().any(|o| o == name);
    let mut benches = Vec::new();
    const NAMES: [&str; 5] = ["cornell", "bunny", "igea", "igea_1m", "field"];
    if let Some(o) =
        (only.iter()).find(|o| !NAMES.contains(&o.as_str()) && spheres::count(o).is_none())
    {
        anyhow::bail!(
            "unknown scene '{o}' (known: {}, spheresN)",
            NAMES.join(", ")
        );
    }
    let sources = [
        ("cornell", None),
        ("bunny", Some("../shared/scenes/bunny.obj")),
        ("igea", Some("../shared/scenes/igea.obj")),
        ("igea_1m", Some("target/igea_1m.obj")),
        ("field", Some("benches/scenes/bunny_field.scene")),
    ];
    for (name, path) in sources {
        if !wanted(name) {
            continue;
        }
        let scene = match path {
            None => Scene::cornell(),
            Some(p)
                if Path::new(p).exists() && Path::new("../shared/scenes/bunny.obj").exists() =>
            {
                Scene::load(Path::new(p), Default::default())
                    .map_err(|e| anyhow!(e))
                    .with_context(|| format!("loading {p}"))?
            }
            Some(p) => {
                println!("({name}: {p} or ../shared/scenes not found, skipped)");
                continue;
            }
        };
        let triangles = match name {
            "field" => Vec::new(),
            _ => scene
                .shapes
                .iter()
                .filter_map(|s| match s {
                    Shape::Triangle(Triangle(v)) => Some(*v),
                    Shape::Sphere(_) => None,
                })
                .collect(),
        };
        let instanced = Instanced::of(&scene);
        benches.push(Bench {
            name: name.into(),
            scene,
            triangles,
            instanced,
            icospheres: None,
            description: None,
        });
    }
    for name in only.iter().filter(|o| spheres::count(o).is_some()) {
        let balls = spheres::load(name, write)?;
        benches.push(Bench {
            name: name.clone(),
            scene: balls.exact,
            triangles: Vec::new(),
            instanced: None,
            icospheres: Some(balls.icospheres),
            description: Some(balls.description),
        });
    }
    Ok(benches)
}

/// The camera every method shares: the scene file's, the lab's, or one framing the mesh.
pub fn camera_for(bench: &Bench, w: u32, h: u32) -> anyhow::Result<Camera> {
    if bench.name == "cornell" {
        return Ok(Camera::cornell(w));
    }
    if let Some(c) = &bench.scene.camera {
        return Ok(CameraController::from_scene_camera(c, bench.scene.size()).camera(w));
    }
    let bounds = bench.scene.bounds().context("empty scene")?;
    Ok(CameraController::framing(bounds, w, h).camera(w))
}
