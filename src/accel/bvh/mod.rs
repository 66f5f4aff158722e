//! A bounding-volume hierarchy for large meshes: binned SAH build (16 bins along the widest
//! axis of the items' box centres, or along all three for a mesh placed by instances,
//! `Bvh::build_placed`; leaves of at most 4 triangles, 8 in a mesh of 2¹⁷ or
//! more (`leaf_max`); subtrees of at least
//! max(4096, n/32) triangles split across threads with rayon) into a binary tree, then
//! collapsed into nodes of 8 children (`node.rs`), which every walk uses: one ray tests a
//! node's 8 boxes at once, a packet of 8 rays tests them lane by lane or, when coherent, as
//! an interval first; children are visited nearest first. A dense mesh's leaves also keep
//! their distinct vertices (module `leaf_vertices`), which leaves prepared as met read.
//!
//! The ray/box test is made conservative the pbrt-v4 way (the far slab distance is enlarged by
//! 2γ(3)), so a box that the exact ray touches is never culled by rounding. Boxes are culled
//! against the nearest hit so far only beyond `t·(1 + 2⁻¹⁶)`: a triangle's computed t and its
//! box's computed entry distance both carry rounding error, and a triangle lying on its box's
//! near face (a shared vertex, say) can hit at a computed t a few ulps before its box's
//! computed entry. With that margin the nearest hit is exactly the brute-force loop's (tested on
//! random scenes and on rays aimed at shared edges and vertices); equal-t hits resolve to the
//! lowest primitive index, as in the brute-force loop.
//!
//! The files: `build.rs` builds the binary tree (binned SAH) and `widen.rs` collapses it into
//! the wide nodes of `node.rs` (their boxes and child references, and the walks' stack);
//! `slabs.rs` tests one ray against a node's boxes and a packet against one box
//! (`approach.rs` moves a ray from far away up to the box first, for the exact queries),
//! `child_test.rs` a packet against a node's children (lane by lane, or as an interval first);
//! `walk_ray.rs` holds the walk of one ray and its queries, `walk_packet.rs` the walks of a
//! packet and theirs; `leaves.rs` what a packet walk does at a leaf, `leaf_triangles.rs` a
//! leaf's triangles prepared for the rays' origin (from a list, from a frame's cache, or as
//! met), `leaf_vertices.rs` a dense mesh's leaves' distinct vertices. This file keeps the
//! hierarchy itself and the leaf sizes.

mod approach;
pub(crate) mod build;
mod child_test;
mod leaf_triangles;
mod leaf_vertices;
mod leaves;
mod node;
mod slabs;
#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests;
mod walk_packet;
mod walk_ray;
mod widen;

pub(crate) use approach::{approach, Approached};
pub(crate) use leaves::Leaves;
pub(crate) use node::{Aabb, WideStack};
pub(crate) use slabs::PacketSlabs;

use crate::accel::cull::{Box3, TreeNode};
use crate::accel::packet::{OriginTriangles, PacketHits, PacketSeed, ShadowHits};
use crate::accel::prepared::Prepared;
use crate::geometry::adaptive::Search;
use crate::geometry::Ray;
use crate::math::lanes::{f32x8, LaneOps};
use crate::math::simd::Isa;
#[cfg(feature = "unit-tests")]
use build::binary;
use leaf_vertices::LeafVertices;
use node::WideNode;

/// Items per leaf at most (a hierarchy's own limit is [`leaf_max`]'s).
pub(crate) const MAX_LEAF: usize = 8;
/// Items per leaf at most in a hierarchy over fewer than [`DENSE_MESH`] triangles, and over
/// boxes.
const SMALL_LEAF: usize = 4;
/// A leaf of at most this many triangles is prepared as met in lanes 0–3, repeated in lanes
/// 4–7 ([`Bvh::prepare_leaf`]): the layout [`PacketNearest::offer_leaf_to_lanes`] takes.
///
/// [`PacketNearest::offer_leaf_to_lanes`]: crate::accel::packet::PacketNearest::offer_leaf_to_lanes
const QUAD_LEAF: usize = 4;
/// Meshes with at least this many triangles have leaves of up to [`MAX_LEAF`] triangles, and
/// keep their leaves' distinct vertices (module `leaf_vertices`: 22 bytes a triangle more,
/// read instead of the triangles' 36 where a leaf is prepared as met).
const DENSE_MESH: usize = 1 << 17;

/// Items per leaf at most in a hierarchy over `n` triangles. A mesh that dense has
/// triangles of a pixel or less on a screen the app shows, so a leaf is mostly reached by
/// one ray of a packet, and its 8 triangles cost that ray one 8-lane pass as 4 did, with
/// fewer leaves and nodes to visit. Where several rays reach a leaf (the bunny, the bunny
/// field), each of its triangles is a pass more, and 4 stay faster.
fn leaf_max(n: usize) -> usize {
    match n >= DENSE_MESH {
        true => MAX_LEAF,
        false => SMALL_LEAF,
    }
}

/// The hierarchy and its triangles, reordered so that each leaf's are contiguous.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// The nodes, root first (empty: no triangles).
    wide: Vec<WideNode>,
    /// The box around everything.
    bounds: Aabb,
    tris: Vec<[[f32; 3]; 3]>,
    prims: Vec<u32>,
    /// Whether every box coordinate is [`box_safe`].
    ///
    /// [`box_safe`]: slabs::box_safe
    tame: bool,
    /// A dense mesh's leaves' distinct vertices, where leaves prepared as met read their
    /// triangles.
    leaf_vertices: Option<LeafVertices>,
}

impl Bvh {
    /// Bytes held by nodes and triangles.
    pub fn memory_bytes(&self) -> usize {
        self.wide.len() * std::mem::size_of::<WideNode>()
            + self.tris.len() * std::mem::size_of::<[[f32; 3]; 3]>()
            + self.prims.len() * 4
            + self.leaf_vertices.as_ref().map_or(0, LeafVertices::bytes)
    }

    /// How many triangles.
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// Whether every box coordinate is [`box_safe`] (the f32 slab test then holds).
    ///
    /// [`box_safe`]: slabs::box_safe
    pub(crate) fn boxes_tame(&self) -> bool {
        self.tame
    }

    /// The root's box (`None` when empty).
    pub(crate) fn root_bounds(&self) -> Option<Aabb> {
        (!self.wide.is_empty()).then_some(self.bounds)
    }

    /// How many triangles a ray through the root's box tests, as the surface-area heuristic
    /// estimates it: each leaf's count weighted by the chance that such a ray crosses the
    /// leaf's box (its area over the root's), without stopping at a hit. About log n for a
    /// mesh; a good part of n where the triangles' boxes overlap throughout (a soup of long
    /// triangles), which a flat loop then tests faster.
    pub(crate) fn expected_tests(&self) -> f64 {
        let root = self.bounds.half_area();
        if self.wide.is_empty() || root <= 0.0 {
            return self.tris.len() as f64;
        }
        let leaves = (self.wide.iter()).flat_map(|n| {
            (0..node::WIDTH)
                .filter(|&c| n.child[c] != node::NONE && n.child[c] & node::LEAF != 0)
                .map(|c| n.bounds(c).half_area() * node::leaf_range(n.child[c]).1 as f64)
        });
        leaves.sum::<f64>() / root
    }

    /// The triangles in the hierarchy's order (leaves index into it), and their primitives.
    pub fn triangles(&self) -> (&[[[f32; 3]; 3]], &[u32]) {
        (&self.tris, &self.prims)
    }
}

/// The BVH's own walks: per ray from a prepared list, and packets recording positions (a
/// leaf's triangles are offered without looking up their primitives).
impl crate::accel::layout::TriangleLayout for Bvh {
    const NAME: &'static str = "bvh";

    fn build(tris: &[crate::accel::IndexedTriangle]) -> Self {
        Bvh::build(tris)
    }

    fn len(&self) -> usize {
        self.tris.len()
    }

    fn memory_bytes(&self) -> usize {
        Bvh::memory_bytes(self)
    }

    fn prepared_for(&self, origin: [f32; 3]) -> OriginTriangles {
        OriginTriangles::from_parts(&self.tris, &self.prims, origin)
    }

    fn bounding_box(&self) -> Option<Box3> {
        let b = self.root_bounds()?;
        Some(Box3 { lo: b.lo, hi: b.hi })
    }

    /// The wide nodes down to `depth` levels ([`Bvh::top_levels`]).
    fn top_boxes(&self, depth: usize) -> Vec<TreeNode> {
        (self.top_levels(depth).into_iter())
            .map(|n| ((n.bounds.lo, n.bounds.hi), n.children))
            .collect()
    }

    fn closest_prepared(&self, ray: &Ray, prepared: Prepared<'_>, search: &mut Search) -> bool {
        if !prepared.fits(ray.o, self.tris.len()) {
            return false;
        }
        self.closest_from_origin(ray, prepared, search);
        true
    }

    fn own_closest_packet<I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> Option<PacketHits> {
        let mut found = self.closest_packet_from(isa, o, prepared, d, d_max, seed);
        self.primitives_of(&mut found.prim);
        Some(found)
    }

    fn own_any_packet<I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> Option<ShadowHits> {
        Some(self.any_packet_from(isa, o, prepared, d, d_max, skip, valid))
    }

    #[inline(always)]
    fn closest_packet_in<V: LaneOps>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
        d_max: f32,
        prim: &mut [u32],
    ) -> u32 {
        let ambiguous = self.closest_positions_in(o, prepared, d, d_max, prim);
        self.primitives_of(&mut prim[..V::WIDTH]);
        ambiguous
    }
}

impl Bvh {
    /// Positions in the hierarchy's order replaced by their primitives (other ids, a seed's
    /// and none's, are left as they are).
    #[inline(always)]
    fn primitives_of(&self, ids: &mut [u32]) {
        for id in ids {
            if let Some(prim) = self.prims.get(*id as usize) {
                *id = *prim;
            }
        }
    }
}
