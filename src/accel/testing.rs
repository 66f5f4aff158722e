//! What the integration tests and the benchmarks reach inside the accelerator for: the packet
//! kernels on their own, the flat loop's lanes, and every layout built alone. Not part of the
//! library's face: the renderer uses [`Accel`](super::Accel) and
//! [`FrameQueries`](super::FrameQueries) only.

use super::layout::{self, Layout};
use super::reference::InOrder;
use super::spheres::Spheres;
use super::Triangles;
use super::{without_copies, AccelChoice, IndexedTriangle};
use crate::geometry::instance::{Instance, Mesh};
use crate::geometry::{Hit, Method, Ray, Shape};
use glam::DMat4;
use std::sync::Arc;

pub use super::bvh::Bvh;
pub use super::flat::FlatLoop;
pub use super::instances::Instances;
pub use super::packet::{
    any, any_exact_lane, closest, closest_exact_lane, max_component, OriginTriangles, PacketHits,
    ShadowHits,
};

/// The adaptive nearest hit of `accel` for a ray from the origin `prepared` was made for (the
/// camera rays' per-ray path: the triangles' shared-origin f32 level where the layout has that
/// walk); a ray from elsewhere is answered as [`Accel::closest_hit`](super::Accel::closest_hit)
/// answers it.
pub fn closest_from_origin(
    accel: &super::Accel,
    ray: &Ray,
    prepared: &OriginTriangles,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    if ray.o.map(f32::to_bits) != prepared.origin.map(f32::to_bits) {
        return accel.closest_hit(ray, Method::Adaptive, tmin, tmax);
    }
    accel.closest_hit_prepared(ray, super::prepared::Prepared::All(prepared), tmin, tmax)
}

/// Layouts answering one query together, as an [`Accel`](super::Accel)'s parts do.
pub struct Parts(Vec<Box<dyn Layout>>);

impl Parts {
    /// The nearest hit ([`layout::closest`]).
    pub fn closest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32) -> Option<Hit> {
        let parts: Vec<&dyn Layout> = self.0.iter().map(|p| p.as_ref()).collect();
        layout::closest(&parts, ray, method, tmin, tmax)
    }

    /// Whether anything but `skip` is hit ([`layout::any`]).
    pub fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        let parts: Vec<&dyn Layout> = self.0.iter().map(|p| p.as_ref()).collect();
        layout::any(&parts, ray, method, tmin, tmax, skip)
    }
}

/// Every layout over `shapes` (primitive index = position), by name, each holding the
/// triangles (exact copies left out, as [`Accel`](super::Accel) leaves them out) beside the
/// other shapes in their hierarchy (`accel::spheres`): each layout of the triangles
/// ([`layout_choices`]: `flat`, `bvh`), `instances` (each run
/// of consecutive triangles a mesh placed by the identity); and `in-order` (every primitive
/// one by one, the reference).
pub fn layouts(shapes: &[Shape<f32>]) -> Vec<(&'static str, Parts)> {
    let tris: Vec<IndexedTriangle> = (shapes.iter().enumerate())
        .filter_map(|(i, s)| s.triangle().map(|v| (*v, i as u32)))
        .collect();
    let (tris, _) = without_copies(tris);
    let others_list = || -> Vec<(Shape<f32>, u32)> {
        (shapes.iter().enumerate())
            .filter(|(_, s)| !s.is_triangle())
            .map(|(i, s)| (*s, i as u32))
            .collect()
    };
    let others = || Box::new(Spheres::build(others_list())) as Box<dyn Layout>;
    let mut runs: Vec<Instance> = Vec::new();
    for run in tris.chunk_by(|a, b| a.1 + 1 == b.1) {
        let triangles: Vec<[[f32; 3]; 3]> = run.iter().map(|t| t.0).collect();
        let colors = vec![None; triangles.len()];
        runs.push(Instance {
            mesh: Arc::new(Mesh::new(format!("run {}", run[0].1), triangles, colors)),
            world_from_object: DMat4::IDENTITY,
            first_prim: run[0].1,
            color: [1.0; 3],
            tint: None,
        });
    }
    let mut every: Vec<(Shape<f32>, u32)> = (tris.iter()).map(|&(v, i)| (v.into(), i)).collect();
    every.extend(others_list());
    every.sort_by_key(|s| s.1);
    let instances: Box<dyn Layout> = match runs.is_empty() {
        true => Box::new(InOrder(Vec::new())),
        false => Box::new(super::instances::Instances::build(&runs)),
    };
    let mut all: Vec<(&'static str, Parts)> = layout_choices()
        .map(|c| {
            let tris = Box::new(Triangles::build(&tris, c));
            (c.name(), Parts(vec![tris, others()]))
        })
        .collect();
    all.push(("instances", Parts(vec![instances, others()])));
    all.push(("in-order", Parts(vec![Box::new(InOrder(every))])));
    all
}

/// Every layout of the triangles by its choice (`flat`, `bvh`: every [`AccelChoice`] but
/// `auto`), so that a new layout joins the tests by its name alone.
pub fn layout_choices() -> impl Iterator<Item = AccelChoice> {
    (AccelChoice::ALL.into_iter()).filter(|c| *c != AccelChoice::Auto)
}
