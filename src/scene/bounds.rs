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
//! what each is known to reach; a second walks every turned placement whose box passes that
//! (each walk on one thread), through a tree of its mesh's vertex boxes ([`VertexTree`]): a
//! node's box carried into the world the same way either passes what is reached so far or
//! holds no vertex that could. Only the leaves near a placement's extremes are walked vertex
//! by vertex, so even the worst case — turned placements that overlap at the scene's edges,
//! each passing what the others reach — costs a few leaves per placement, not its whole mesh
//! (which took 55 s for 20,000 turned placements of a 100,000-triangle mesh).

use super::instance::Instance;
use super::{Bounds, Scene};
use crate::geometry::Shape;
use glam::DMat4;
use rayon::prelude::*;
use std::collections::HashMap;

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

/// A box around the world vertices of `m` applied to any vertex in `(lo, hi)`, from the
/// box's corners in f64 widened by a bound on the f64 rounding of any vertex and of the
/// corners, then rounded to f32 as [`Instance::world_vertex`] rounds (to nearest, monotone): a
/// vertex reaches its side only where the extreme is shared, so placements tied at the
/// scene's edge are not walked.
fn outer_bounds(m: &DMat4, (lo, hi): Bounds) -> Bounds {
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

/// Whether some point of `b` lies outside `reached`.
fn passes((lo, hi): Bounds, reached: Bounds) -> bool {
    (0..3).any(|k| lo[k] < reached.0[k] || hi[k] > reached.1[k])
}

/// Vertices per leaf of a [`VertexTree`].
const LEAF: usize = 8;

/// A mesh's distinct vertices in a tree of boxes (each node's box around its vertices, split
/// at the median of its longest side), so that a turned placement is walked only where its
/// vertices may pass what is reached: a few leaves near its extremes, not the whole mesh.
struct VertexTree {
    vertices: Vec<[f32; 3]>,
    /// Depth first: a node's first child follows it.
    nodes: Vec<VertexNode>,
}

struct VertexNode {
    bounds: Bounds,
    vertices: std::ops::Range<usize>,
    /// The second child's index; 0 for a leaf.
    second: usize,
}

impl VertexTree {
    fn new(triangles: &[[[f32; 3]; 3]]) -> Self {
        let mut vertices: Vec<[f32; 3]> = triangles.iter().flatten().copied().collect();
        vertices.sort_unstable_by_key(|v| v.map(f32::to_bits));
        vertices.dedup_by_key(|v| v.map(f32::to_bits));
        let mut nodes = Vec::with_capacity(2 * vertices.len() / LEAF + 1);
        Self::split(&mut vertices, 0, &mut nodes);
        Self { vertices, nodes }
    }

    fn split(vertices: &mut [[f32; 3]], first: usize, nodes: &mut Vec<VertexNode>) {
        let bounds = (vertices.iter()).map(|v| (*v, *v)).fold(EMPTY, merge);
        let at = nodes.len();
        let range = first..first + vertices.len();
        nodes.push(VertexNode {
            bounds,
            vertices: range,
            second: 0,
        });
        if vertices.len() <= LEAF {
            return;
        }
        let side = |k: usize| bounds.1[k] - bounds.0[k];
        let axis = (0..3).fold(0, |a, k| if side(k) > side(a) { k } else { a });
        let mid = vertices.len() / 2;
        vertices.select_nth_unstable_by(mid, |a, b| a[axis].total_cmp(&b[axis]));
        let (low, high) = vertices.split_at_mut(mid);
        Self::split(low, first, nodes);
        nodes[at].second = nodes.len();
        Self::split(high, first + mid, nodes);
    }

    /// `reached` and the box of the world vertices of `m` applied to the mesh, with how
    /// many vertices were transformed: only those in leaves whose [`outer_bounds`] pass what
    /// is reached so far.
    fn walk(&self, m: &DMat4, reached: Bounds) -> (Bounds, usize) {
        let (mut found, mut walked) = (reached, 0);
        let mut stack = vec![0];
        while let Some(i) = stack.pop() {
            let node = &self.nodes[i];
            if !passes(outer_bounds(m, node.bounds), found) {
                continue;
            }
            if node.second == 0 {
                for v in &self.vertices[node.vertices.clone()] {
                    let w = Instance::world_vertex(m, *v);
                    found = merge(found, (w, w));
                }
                walked += node.vertices.len();
            } else {
                stack.extend([node.second, i + 1]);
            }
        }
        (found, walked)
    }
}

impl Scene {
    /// Bounds of all primitives, or `None` where there are none (no shapes, and no placement
    /// of a mesh with triangles): the same as for the flattened twin (see the module's notes).
    pub fn bounds(&self) -> Option<Bounds> {
        self.bounds_walking().0
    }

    /// [`Scene::bounds`], and how many vertices of turned placements it transformed.
    fn bounds_walking(&self) -> (Option<Bounds>, usize) {
        let explicit = self.shapes.iter().map(Shape::bounds).reduce(merge);
        if self.instances.iter().all(Instance::is_empty) {
            // (Flattened, an empty mesh adds nothing.)
            return (explicit, 0);
        }
        // Each mesh's extreme vertices, once however often it is placed.
        let key = |inst: &Instance| std::sync::Arc::as_ptr(&inst.mesh) as usize;
        let mut extremes = HashMap::new();
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
        // The other placements that may pass it, walked through their meshes' vertex trees.
        let turned: Vec<&Instance> = (self.instances.par_iter())
            .filter(|inst| !inst.is_empty() && !permutes_axes(&inst.world_from_object))
            .filter(|inst| {
                let m = &inst.world_from_object;
                passes(outer_bounds(m, inst.mesh.bounds()), reached)
            })
            .collect();
        let meshes: HashMap<usize, &Instance> = turned.iter().map(|i| (key(i), *i)).collect();
        let trees: HashMap<usize, VertexTree> = (meshes.into_par_iter())
            .map(|(k, inst)| (k, VertexTree::new(&inst.mesh.triangles)))
            .collect();
        let (found, walked) = (turned.par_iter())
            .map(|inst| trees[&key(inst)].walk(&inst.world_from_object, reached))
            .reduce(|| (EMPTY, 0), |(a, n), (b, m)| (merge(a, b), n + m));
        (Some(merge(reached, found)), walked)
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

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;
    use crate::scene::{cornell, Mesh};
    use glam::{DQuat, DVec3};
    use std::sync::Arc;

    pub const TESTS: crate::unit_tests::Tests = &[(
        "turned_placements_at_the_edges_walk_a_few_leaves_and_match_every_vertex",
        turned_placements_at_the_edges_walk_a_few_leaves_and_match_every_vertex,
    )];

    /// A bumpy ball of `2·n·n` triangles (no two vertices at one extreme).
    fn ball(n: usize) -> Vec<[[f32; 3]; 3]> {
        let point = |i: usize, j: usize| {
            let (theta, phi) = (
                std::f64::consts::PI * i as f64 / n as f64,
                std::f64::consts::TAU * j as f64 / n as f64,
            );
            let r = 1.0 + 0.013 * ((i * 31 + j * 17) % 23) as f64 / 23.0;
            let p = [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ];
            p.map(|x| (r * x) as f32)
        };
        let mut triangles = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (a, b) = (point(i, j), point(i + 1, j));
                let (c, d) = (point(i, j + 1), point(i + 1, j + 1));
                triangles.extend([[a, b, c], [b, d, c]]);
            }
        }
        triangles
    }

    /// Placements that overlap at the scene's edges, each turned another way: every one
    /// passes what the others reach, so all are walked (the worst case). Their tree walks
    /// give the box of every world vertex to the bit, transforming a small part of them.
    fn turned_placements_at_the_edges_walk_a_few_leaves_and_match_every_vertex() {
        let triangles = ball(48);
        let mesh = Arc::new(Mesh::new(
            "ball".into(),
            triangles.clone(),
            vec![None; 4608],
        ));
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let instances: Vec<Instance> = (0..300)
            .map(|k| {
                let axis = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
                let turn = DQuat::from_axis_angle(axis, 6.0 * next());
                let shift = DVec3::new(next(), next(), next()) * 1e-3;
                Instance {
                    mesh: mesh.clone(),
                    world_from_object: DMat4::from_rotation_translation(turn, shift),
                    first_prim: 1 + k * 4608,
                    color: [1.0; 3],
                    tint: None,
                }
            })
            .collect();
        let every_vertex = (instances.iter())
            .flat_map(|inst| {
                let m = inst.world_from_object;
                (triangles.iter().flatten()).map(move |v| Instance::world_vertex(&m, *v))
            })
            .map(|w| (w, w))
            .fold(EMPTY, merge);
        let tri = Shape::from([[0.0, 0.0, 0.5], [0.5, 0.0, 0.5], [0.0, 0.5, 0.5]]);
        let scene = Scene::new("balls", vec![tri], vec![[1.0; 3]], cornell::LIGHT, [0.1; 3])
            .with_instances(instances)
            .unwrap();
        let (bounds, walked) = scene.bounds_walking();
        let bits = |b: Bounds| (b.0.map(f32::to_bits), b.1.map(f32::to_bits));
        assert_eq!(bits(bounds.unwrap()), bits(every_vertex));
        let all = 300 * 3 * triangles.len();
        assert!(walked > 0, "no placement was walked");
        assert!(walked * 20 < all, "{walked} of {all} vertices transformed");
    }
}
