//! A scene's bounds, which place the default camera and light: the same bits for an
//! instanced scene as for its flattened twin (`None` for both where nothing has a vertex:
//! no shapes, and only placements of empty meshes).
//!
//! A placement whose matrix only permutes, scales and moves the axes (each world coordinate
//! the f64 image of one object coordinate) has the box of its world vertices exactly where the
//! mesh's box corners go: rounding is monotone, so the vertices at the mesh's extremes stay at
//! the extremes. Any other placement (a turn by another angle, a shear) is bounded by its
//! mesh's box carried into the world ([`outer_bounds`]) and known to reach the images of the
//! mesh's extreme vertices along its axes. A first parallel pass over the placements takes
//! what each is known to reach; a second walks, vertex by vertex (each walk on one thread),
//! every turned placement whose box passes that. Placements inside the scene are not walked,
//! but in the worst case — turned placements that overlap at the scene's edges, each box
//! passing what the others reach — every turned placement is walked, as many vertex
//! transforms as flattening them takes. (Walking every placement's vertices, each in a
//! parallel fold of its own, took 12 to 51 s for 2¹⁸ placements of a small mesh.)

use super::instance::Instance;
use super::{Bounds, Scene};
use crate::geometry::Shape;
use glam::DMat4;
use rayon::prelude::*;

/// The box of two boxes.
fn merge((lo, hi): Bounds, (a, b): Bounds) -> Bounds {
    (
        [0, 1, 2].map(|k| lo[k].min(a[k])),
        [0, 1, 2].map(|k| hi[k].max(b[k])),
    )
}

/// Nothing yet: the identity of [`merge`].
const EMPTY: Bounds = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);

/// Whether each world coordinate of `m` depends on exactly one object coordinate.
fn permutes_axes(m: &DMat4) -> bool {
    let cols = [m.x_axis, m.y_axis, m.z_axis];
    (0..3).all(|k| cols.iter().filter(|c| c[k] != 0.0).count() == 1)
}

/// The box of the world vertices of `inst` where it is found without walking them: the mesh's
/// box for an empty mesh (as flattening it adds nothing), the corners' images where the
/// matrix permutes the axes.
fn exact_by_corners(inst: &Instance) -> Option<Bounds> {
    let (lo, hi) = inst.mesh.bounds();
    if inst.is_empty() {
        return Some((lo, hi));
    }
    let m = &inst.world_from_object;
    if !permutes_axes(m) {
        return None;
    }
    let corners = (0..8).map(|c| {
        let p = [0, 1, 2].map(|k| if c & (1 << k) != 0 { hi[k] } else { lo[k] });
        let w = Instance::world_vertex(m, p);
        (w, w)
    });
    Some(corners.fold(EMPTY, merge))
}

/// The vertices of a mesh at its extremes along each object axis: where a placement carries
/// them is reached, and near its extremes for any turn.
fn extreme_vertices(triangles: &[[[f32; 3]; 3]]) -> [[f32; 3]; 6] {
    let mut out = [triangles[0][0]; 6];
    for v in triangles.iter().flatten() {
        for k in 0..3 {
            if v[k] < out[2 * k][k] {
                out[2 * k] = *v;
            }
            if v[k] > out[2 * k + 1][k] {
                out[2 * k + 1] = *v;
            }
        }
    }
    out
}

/// A box around the world vertices of `inst`, from its mesh's box corners in f64 widened by a
/// bound on the f64 rounding of any vertex and of the corners, then rounded to f32 as
/// [`Instance::world_vertex`] rounds (to nearest, monotone): a vertex reaches its side only
/// where the extreme is shared, so placements tied at the scene's edge are not walked.
fn outer_bounds(inst: &Instance) -> Bounds {
    let (lo, hi) = inst.mesh.bounds();
    let m = &inst.world_from_object;
    let (mut wlo, mut whi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for c in 0..8 {
        let p = [0, 1, 2].map(|k| if c & (1 << k) != 0 { hi[k] } else { lo[k] } as f64);
        let w = m.transform_point3(glam::DVec3::from_array(p));
        for k in 0..3 {
            // Three products and three sums, for a vertex near this corner and the corner
            // itself: 2·γ₆ < 2⁻⁴⁸ of the terms' magnitudes (value plus error is convex, so
            // the corners bound it over the box).
            let terms = (m.x_axis[k] * p[0]).abs() + (m.y_axis[k] * p[1]).abs();
            let size = terms + (m.z_axis[k] * p[2]).abs() + m.w_axis[k].abs();
            let err = size * f64::EPSILON * 32.0 + f64::MIN_POSITIVE;
            wlo[k] = wlo[k].min(w[k] - err);
            whi[k] = whi[k].max(w[k] + err);
        }
    }
    (wlo.map(|x| x as f32), whi.map(|x| x as f32))
}

/// The box of the world vertices of `inst`, vertex by vertex (on this thread).
fn exact_by_vertices(inst: &Instance) -> Bounds {
    let m = &inst.world_from_object;
    (inst.mesh.triangles.iter().flatten())
        .map(|v| {
            let w = Instance::world_vertex(m, *v);
            (w, w)
        })
        .fold(EMPTY, merge)
}

impl Scene {
    /// Bounds of all primitives, or `None` where there are none (no shapes, and no placement
    /// of a mesh with triangles): the same as for the flattened twin (see the module's notes).
    pub fn bounds(&self) -> Option<Bounds> {
        let explicit = self.shapes.iter().map(Shape::bounds).reduce(merge);
        if self.instances.iter().all(Instance::is_empty) {
            // (Flattened, an empty mesh adds nothing.)
            return explicit;
        }
        // Each mesh's extreme vertices, once however often it is placed.
        let key = |inst: &Instance| std::sync::Arc::as_ptr(&inst.mesh) as usize;
        let mut extremes = std::collections::HashMap::new();
        for inst in self.instances.iter().filter(|i| !i.is_empty()) {
            (extremes.entry(key(inst))).or_insert_with(|| extreme_vertices(&inst.mesh.triangles));
        }
        // What is known to be reached: the explicit shapes, the exact boxes, and the extreme
        // vertices of every other placement.
        let reached = (self.instances.par_iter())
            .map(|inst| match exact_by_corners(inst) {
                Some(b) => b,
                None => (extremes[&key(inst)].iter())
                    .map(|v| {
                        let w = Instance::world_vertex(&inst.world_from_object, *v);
                        (w, w)
                    })
                    .fold(EMPTY, merge),
            })
            .reduce(|| EMPTY, merge);
        let reached = merge(reached, explicit.unwrap_or(EMPTY));
        // The other placements that may pass it, walked.
        let passes =
            |(lo, hi): Bounds| (0..3).any(|k| lo[k] < reached.0[k] || hi[k] > reached.1[k]);
        let walked = (self.instances.par_iter())
            .filter(|inst| !inst.is_empty() && !permutes_axes(&inst.world_from_object))
            .filter(|inst| passes(outer_bounds(inst)))
            .map(exact_by_vertices)
            .reduce(|| EMPTY, merge);
        Some(merge(reached, walked))
    }
}

/// How far the light may lie from the scene's box, in units of the box's longest side, for
/// shadow rays to start at the light ([`Scene::shadows_from_light`]).
pub const LIGHT_REACH: f64 = 1024.0;

impl Scene {
    /// Whether shadow rays start at the light (`render::shade::shadow_from_light`: every
    /// shadow ray of a frame then shares one origin, which the packet kernels need), else at
    /// the surface point (`render::shade::shadow_to_light`). A ray from the light ends within
    /// 2⁻²⁴·|L − p| of the point per axis and is shortened by that much to stay off the
    /// surface, so it misses what lies that close: under 2⁻¹²·(the box's longest side) with the
    /// light within [`LIGHT_REACH`] sides of the box, but a whole scene with a light 10⁸ away
    /// (a sun). Beyond that reach the ray starts at the point, offset by the point's own error
    /// bound, and its rounding moves to the light's end, far from everything.
    pub fn shadows_from_light(&self) -> bool {
        let Some((lo, hi)) = *self.bounds_once.get_or_init(|| self.bounds()) else {
            return true;
        };
        let light = self.light.position;
        let (mut side, mut gap) = (0.0f64, 0.0f64);
        for k in 0..3 {
            let (lo, hi, l) = (f64::from(lo[k]), f64::from(hi[k]), f64::from(light[k]));
            side = side.max(hi - lo);
            gap = gap.max(lo - l).max(l - hi);
        }
        gap <= LIGHT_REACH * side
    }
}
