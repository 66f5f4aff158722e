//! A bounding-volume hierarchy for large meshes: binned SAH build (16 bins along the widest
//! axis of the items' box centres, or along all three for a mesh placed by instances,
//! `Bvh::build_placed`; leaves of at most 4 triangles, 8 in a mesh of 2¹⁷ or
//! more (`leaf_max`); subtrees of at least
//! max(4096, n/32) triangles split across threads with rayon) into a binary tree, then
//! collapsed into nodes of 8 children (module `wide`), which every walk uses: one ray tests a
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

use super::instances::PacketSink;
use super::packet::{
    quad_indices, BlockIds, OriginBlock, OriginTriangle, OriginTriangles, PacketHits,
    PacketNearest, PacketSeed, PreciseTriangle, ShadowHits, ShadowPacket,
};
use super::prepared::{LeafCache, Prepared, Reached, BLOCK};
use super::IndexedTriangle;
use crate::geometry::adaptive::{box_extent, classify_f32, round_down, Estimate, Search};
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::math::lanes::{f32x8, LaneOps, Lanes};
use crate::math::simd::{avx2_or_baseline, each3};
use crate::math::Real;
use ::wide::f32x4;
use rayon::prelude::*;

mod leaf_vertices;
mod wide;
use leaf_vertices::{LeafCorners, LeafVertices};
pub(crate) use wide::WideStack;
pub use wide::MAX_ITEMS;

/// Levels of binned-SAH splits at most; deeper, sets are split by count (see `split`).
const SAH_DEPTH: usize = 36;

/// Items per leaf at most (a hierarchy's own limit is [`leaf_max`]'s).
pub(crate) const MAX_LEAF: usize = 8;
/// Items per leaf at most in a hierarchy over fewer than [`DENSE_MESH`] triangles, and over
/// boxes.
const SMALL_LEAF: usize = 4;
/// A leaf of at most this many triangles is prepared as met in lanes 0–3, repeated in lanes
/// 4–7 ([`Bvh::prepare_leaf`]): the layout [`PacketNearest::offer_leaf_to_lanes`] takes.
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

const BINS: usize = 16;
/// Subtrees this large (or n/32, whichever is larger) build their halves on two threads.
const PARALLEL_MIN: usize = 4096;

/// How a binary tree is built: subtrees of at least `parallel_min` items build their halves
/// on two threads; sets of at most `leaf_max` items are leaves; splits are sought along every
/// axis if `all_axes`, else along the centres' widest.
#[derive(Clone, Copy)]
struct Plan {
    parallel_min: usize,
    leaf_max: usize,
    all_axes: bool,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Aabb {
    pub(crate) lo: [f32; 3],
    pub(crate) hi: [f32; 3],
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The high corner if `hi`, else the low one.
    #[inline(always)]
    fn side(&self, hi: bool) -> &[f32; 3] {
        match hi {
            true => &self.hi,
            false => &self.lo,
        }
    }

    const EMPTY: Aabb = Aabb {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    /// Grows to hold `o` (a NaN coordinate of `o` is ignored, as `f32::min` would; the
    /// comparisons compile to plain `minss`/`maxss`; `f32::min`'s NaN rule cost a branch).
    #[inline(always)]
    pub(crate) fn grow(&mut self, o: &Aabb) {
        for k in 0..3 {
            let (lo, hi) = (self.lo[k], self.hi[k]);
            self.lo[k] = if o.lo[k] < lo { o.lo[k] } else { lo };
            self.hi[k] = if o.hi[k] > hi { o.hi[k] } else { hi };
        }
    }

    fn grow_point(&mut self, p: [f32; 3]) {
        self.grow(&Aabb { lo: p, hi: p });
    }

    /// In f64: products of f32 extents neither underflow nor overflow there (a box of
    /// subnormal size has area 0 in f32, and every split would look free).
    fn half_area(&self) -> f64 {
        let d = [0, 1, 2].map(|k| (f64::from(self.hi[k]) - f64::from(self.lo[k])).max(0.0));
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }
}

/// A node of the binary tree the build makes (and [`widen`](wide::widen) collapses), in
/// depth-first order: a node, its first child's subtree, its second's.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    bounds: Aabb,
    /// Leaf: index of its first triangle; interior: the offset from this node to its second
    /// child (the first follows it).
    offset: u32,
    /// Leaf: triangle count (1 to the build's `leaf_max`); interior: 0.
    count: u16,
    /// Levels below (a leaf 0): what a walk through the subtree may push.
    height: u16,
}

impl Node {
    /// An interior node's children.
    #[inline(always)]
    fn children(nodes: &[Node], i: usize) -> [usize; 2] {
        [i + 1, i + nodes[i].offset as usize]
    }
}

/// A node of [`Bvh::top_levels`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct TopNode {
    pub(crate) bounds: Aabb,
    /// Above the depth asked and where the node is not a leaf: its children's positions in
    /// the list, as the first and how many.
    pub(crate) children: Option<(u32, u32)>,
}

/// Items (or, in the collapse, binary nodes: about as many) a subtree must hold for its
/// halves to be built (and collapsed) on two threads: at least [`PARALLEL_MIN`], and n/32 of
/// `n` in all (enough subtrees for the threads, each large enough to pay for a task).
fn parallel_min(n: usize) -> usize {
    PARALLEL_MIN.max(n / 32)
}

/// The hierarchy and its triangles, reordered so that each leaf's are contiguous.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// The nodes, root first (empty: no triangles).
    wide: Vec<wide::WideNode>,
    /// The box around everything.
    bounds: Aabb,
    tris: Vec<[[f32; 3]; 3]>,
    prims: Vec<u32>,
    /// Whether every box coordinate is [`box_safe`].
    tame: bool,
    /// A dense mesh's leaves' distinct vertices, where leaves prepared as met read their
    /// triangles.
    leaf_vertices: Option<LeafVertices>,
}

/// Origin and direction components the f32 slab test keeps within its relative slack: 0, or
/// 2⁻⁴⁰…2⁴⁰; box coordinates: 0, or 2⁻⁸⁶…2⁴⁰ ([`box_safe`]). Then a nonzero difference of a
/// box coordinate and an origin coordinate is at least 2⁻⁸⁶ (the origin 0) or 2⁻⁶³ (an ulp of
/// either), and times 1/d at least 2⁻¹²⁶ and at most 2⁸¹: normal and finite, rounded by a
/// relative u. Beyond (subnormal or huge geometry, origins or directions), a per-ray test runs
/// in f64 and a packet offers every triangle: before, a direction below 2⁻¹²⁸ made 1/d
/// infinite and the BVH skipped the boxes it meets.
#[inline(always)]
fn slab_safe(x: f32) -> bool {
    in_range(x, SAFE_EXP)
}

/// 2^±`SAFE_EXP`: the range of [`slab_safe`] (and the top of [`box_safe`]'s).
const SAFE_EXP: u32 = 40;

/// [`slab_safe`] for a box coordinate: 0, or 2⁻⁸⁶…2⁴⁰ (scanned meshes hold coordinates of
/// 1e-14 and less near their axes).
#[inline(always)]
fn box_safe(x: f32) -> bool {
    in_range(x, 86)
}

/// Whether x is 0 or 2⁻ᵉ ≤ |x| ≤ 2⁴⁰, on the bits of |x| (ordered as the values).
#[inline(always)]
fn in_range(x: f32, e: u32) -> bool {
    const HI: u32 = (127 + SAFE_EXP) << 23;
    let lo = (127 - e) << 23;
    let bits = x.to_bits() & 0x7fff_ffff;
    bits == 0 || bits.wrapping_sub(lo) <= HI - lo
}

/// Whether every node box of `wide` has [`box_safe`] coordinates (an empty box's infinite
/// ones aside: such a box is never entered).
fn boxes_tame(wide: &[wide::WideNode]) -> bool {
    wide.par_iter()
        .all(|n| n.coordinates().all(|x| !x.is_finite() || box_safe(x)))
}

/// The binary tree over `refs` (depth first), and the items in its leaves' order.
fn binary_over(mut refs: Vec<Ref>, plan: Plan) -> (Vec<Node>, Vec<u32>) {
    let bounds = Bounds::of_par(&refs);
    let nodes = build_node(&mut refs, &bounds, 0, plan, 0);
    (nodes, refs.par_iter().map(Ref::index).collect())
}

/// The binary tree over triangles with leaves of at most `leaf_max`, and their indices in
/// its leaves' order.
fn binary(tris: &[IndexedTriangle], leaf_max: usize, all_axes: bool) -> (Vec<Node>, Vec<u32>) {
    let refs: Vec<Ref> = tris
        .par_iter()
        .enumerate()
        .map(|(i, (t, _))| {
            let mut b = Aabb::EMPTY;
            t.iter().for_each(|p| b.grow_point(*p));
            Ref::new(&b, i as u32)
        })
        .collect();
    let plan = Plan {
        parallel_min: parallel_min(tris.len()),
        leaf_max,
        all_axes,
    };
    binary_over(refs, plan)
}

/// An item during the build: its box, in 4 lanes so that binning takes a few 4-lane
/// operations (the low corner's fourth lane holds the index's bits; the high corner's is 0).
/// 32 bytes: the build partitions these themselves (not indices into side tables), so its
/// passes read memory in order. Items are binned by their box's centre.
#[derive(Clone, Copy)]
struct Ref {
    lo: f32x4,
    hi: f32x4,
}

impl Ref {
    fn new(b: &Aabb, i: u32) -> Self {
        Self {
            lo: f32x4::new([b.lo[0], b.lo[1], b.lo[2], f32::from_bits(i)]),
            hi: f32x4::new([b.hi[0], b.hi[1], b.hi[2], 0.0]),
        }
    }

    fn index(&self) -> u32 {
        self.lo.as_array()[3].to_bits()
    }

    /// The box's centre (halves first: no overflow).
    #[inline(always)]
    fn centre(&self) -> f32x4 {
        self.lo * 0.5 + self.hi * 0.5
    }

    /// The box's centre on one axis.
    #[inline(always)]
    fn centre_on(&self, axis: usize) -> f32 {
        self.lo.as_array()[axis] * 0.5 + self.hi.as_array()[axis] * 0.5
    }
}

impl Bvh {
    /// Builds over triangles with their primitive indices (at most
    /// [`MAX_ITEMS`]; the loaders keep within it).
    pub fn build(tris: &[IndexedTriangle]) -> Self {
        let dense = tris.len() >= DENSE_MESH;
        Self::build_with(tris, leaf_max(tris.len()), dense)
    }

    /// [`Bvh::build`] for a mesh placed by instances (`accel::instances`): its splits sought
    /// along all three axes, not only the widest. Built once however often the mesh is
    /// placed, the better tree pays where a build per frame or per scene would not (see
    /// `sah_split`).
    pub(crate) fn build_placed(tris: &[IndexedTriangle]) -> Self {
        let dense = tris.len() >= DENSE_MESH;
        Self::build_planned(tris, leaf_max(tris.len()), dense, true)
    }

    /// [`Bvh::build`] with leaves of at most `leaf_max` (≤ [`MAX_LEAF`]) triangles, and
    /// their distinct vertices kept if `leaf_vertices`.
    fn build_with(tris: &[IndexedTriangle], leaf_max: usize, leaf_vertices: bool) -> Self {
        Self::build_planned(tris, leaf_max, leaf_vertices, false)
    }

    /// [`Bvh::build_with`], splits sought along every axis if `all_axes`.
    fn build_planned(
        tris: &[IndexedTriangle],
        leaf_max: usize,
        leaf_vertices: bool,
        all_axes: bool,
    ) -> Self {
        if tris.is_empty() {
            return Self::default();
        }
        assert!(tris.len() <= wide::MAX_ITEMS, "{} triangles", tris.len());
        assert!((1..=MAX_LEAF).contains(&leaf_max));
        let (nodes, order) = binary(tris, leaf_max, all_axes);
        let mut bvh = Self::over_binary(
            &nodes,
            order.par_iter().map(|&i| tris[i as usize].0).collect(),
            order.par_iter().map(|&i| tris[i as usize].1).collect(),
        );
        if leaf_vertices {
            let mut leaves: Vec<(usize, usize)> =
                bvh.wide.par_iter().flat_map_iter(|n| n.leaves()).collect();
            leaves.par_sort_unstable();
            bvh.leaf_vertices = Some(LeafVertices::new(&bvh.tris, &leaves));
        }
        bvh
    }

    /// The hierarchy from the binary tree `nodes`, with its items in the leaves' order.
    fn over_binary(nodes: &[Node], tris: Vec<[[f32; 3]; 3]>, prims: Vec<u32>) -> Self {
        let wide = wide::widen(nodes, wide::STACK, parallel_min(prims.len()));
        Self {
            tame: boxes_tame(&wide),
            bounds: nodes[0].bounds,
            wide,
            tris,
            prims,
            leaf_vertices: None,
        }
    }

    /// Bytes held by nodes and triangles.
    pub fn memory_bytes(&self) -> usize {
        self.wide.len() * std::mem::size_of::<wide::WideNode>()
            + self.tris.len() * std::mem::size_of::<[[f32; 3]; 3]>()
            + self.prims.len() * 4
            + self.leaf_vertices.as_ref().map_or(0, LeafVertices::bytes)
    }

    /// Nearest hit with tmin < t < tmax (ties to the lowest primitive index).
    pub fn closest_hit(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.traverse(ray, tmin, tmax, 0.0, |first, count, t_far| {
            for i in first..first + count {
                let shape = Shape::Triangle(self.tris[i]);
                if let Some((t, b1, b2)) = shape.intersect(ray, method, tmin, t_far) {
                    let prim = self.prims[i];
                    let better = best.is_none_or(|h| t < h.t || (t == h.t && prim < h.prim));
                    if better {
                        best = Some(Hit { t, prim, b1, b2 });
                    }
                }
            }
            // Hits at t equal to the best stay possible (for the index tie-break).
            (best.map_or(tmax, |h| h.t.next_up()), false)
        });
        best
    }

    /// Whether anything is hit with tmin < t < tmax; stops at the first hit.
    pub fn any_hit(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        let mut hit = false;
        self.traverse(ray, tmin, tmax, 0.0, |first, count, t_far| {
            hit = (first..first + count).any(|i| {
                self.prims[i] != skip
                    && Shape::Triangle(self.tris[i])
                        .intersect(ray, method, tmin, t_far)
                        .is_some()
            });
            (t_far, hit)
        });
        hit
    }

    /// The adaptive filter's M for this ray, from the root box (once per ray: per leaf it
    /// cost more than its tighter bound saved).
    fn extent(&self, ray: &Ray) -> f32 {
        match self.wide.is_empty() {
            true => f32::INFINITY,
            false => box_extent(ray.o, self.bounds.lo, self.bounds.hi),
        }
    }

    /// The adaptive closest-hit search (see `geometry::adaptive`).
    pub fn closest_hit_adaptive(&self, ray: &Ray, r: &WatertightRay<f32>, search: &mut Search) {
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let e = self.extent(ray);
        self.traverse(ray, tmin, tmax, 0.0, |first, count, _| {
            for i in first..first + count {
                let est = classify_f32(r, &self.tris[i], e);
                if est != Estimate::Miss {
                    search.offer_triangle(self.prims[i], &self.tris[i], est);
                }
            }
            (search.t_far32(), false)
        });
    }

    /// How many triangles.
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// A hierarchy over boxes (the instances' world boxes) instead of triangles: it holds no
    /// triangles, and its leaves' items are the boxes' indices ([`Bvh::triangles`]'s second
    /// part).
    pub(crate) fn build_over_boxes(boxes: &[([f32; 3], [f32; 3])]) -> Self {
        if boxes.is_empty() {
            return Self::default();
        }
        assert!(boxes.len() <= wide::MAX_ITEMS, "{} boxes", boxes.len());
        let refs: Vec<Ref> = (boxes.iter().enumerate())
            .map(|(i, &(lo, hi))| Ref::new(&Aabb { lo, hi }, i as u32))
            .collect();
        let plan = Plan {
            parallel_min: PARALLEL_MIN,
            leaf_max: SMALL_LEAF,
            all_axes: false,
        };
        let (nodes, order) = binary_over(refs, plan);
        Self::over_binary(&nodes, Vec::new(), order)
    }

    /// Whether every box coordinate is [`box_safe`] (the f32 slab test then holds).
    pub(crate) fn boxes_tame(&self) -> bool {
        self.tame
    }

    /// The root's box (`None` when empty).
    pub(crate) fn root_bounds(&self) -> Option<Aabb> {
        (!self.wide.is_empty()).then_some(self.bounds)
    }

    /// Walks the hierarchy with 8 rays from one origin (`slabs`), every box widened by `pad`
    /// (see [`Bvh::traverse`]): a node is entered while its box meets one of `sink`'s live
    /// lanes before that lane's limit; `leaves` visits a leaf's items, nearer children first.
    /// Untrusted slabs visit every item.
    #[inline(always)]
    pub(crate) fn walk_packet<V: LaneOps, S: PacketSink<V>, L: Leaves<V, S>>(
        &self,
        slabs: &PacketSlabs<V>,
        pad: f32,
        sink: &mut S,
        leaves: &mut L,
    ) {
        let stack = &mut WideStack::new();
        self.walk_packet_on::<_, _, _, false>(slabs, pad, sink, leaves, stack, !0)
    }

    /// [`Bvh::walk_packet`] for the lanes of `only`, where a node only one lane entered has
    /// its subtree walked for that lane alone (8 boxes per test; the root too, if `only` has
    /// one live lane), on `stack` (its entries are not kept): instances'
    /// meshes, where 56% of the node visits at 320×180 are one lane's (the bunny field),
    /// walked many times per packet. On the meshes' own hierarchies the lone walk cost more
    /// than it saved (bunny 1280×720 +2.2%, Igea 640×360 +0.7%; −2.8% on Igea at 320×180).
    #[inline(always)]
    pub(crate) fn walk_packet_lone<V: LaneOps, S: PacketSink<V>, L: Leaves<V, S>>(
        &self,
        slabs: &PacketSlabs<V>,
        pad: f32,
        sink: &mut S,
        leaves: &mut L,
        stack: &mut WideStack,
        only: u32,
    ) {
        self.walk_packet_on::<_, _, _, true>(slabs, pad, sink, leaves, stack, only)
    }

    #[inline(always)]
    fn walk_packet_on<V: LaneOps, S: PacketSink<V>, L: Leaves<V, S>, const LONE: bool>(
        &self,
        slabs: &PacketSlabs<V>,
        pad: f32,
        sink: &mut S,
        leaves: &mut L,
        stack: &mut WideStack,
        only: u32,
    ) {
        if self.wide.is_empty() {
            return;
        }
        if !(slabs.trusted && box_safe(pad)) {
            // Every item, in leaf-sized runs (a leaf visit prepares at most `MAX_LEAF`
            // triangles: one visit of all of them served only the first and last blocks of
            // a frame's cache, and the rest went untested).
            for first in (0..self.prims.len()).step_by(MAX_LEAF) {
                let count = MAX_LEAF.min(self.prims.len() - first);
                leaves.visit(sink, first, count, sink.live() & only);
            }
            return;
        }
        match (slabs.coherent, pad == 0.0) {
            (Some(near_hi), true) => {
                let test = wide::IntervalTest::<V, false>::new(slabs, near_hi, 0.0);
                self.walk_wide::<_, _, _, _, LONE>(&test, sink, leaves, stack, only)
            }
            (Some(near_hi), false) => {
                let test = wide::IntervalTest::<V, true>::new(slabs, near_hi, pad);
                self.walk_wide::<_, _, _, _, LONE>(&test, sink, leaves, stack, only)
            }
            (None, _) => {
                let test = wide::LaneTest { rays: slabs, pad };
                self.walk_wide::<_, _, _, _, LONE>(&test, sink, leaves, stack, only)
            }
        }
    }

    /// The triangles in the hierarchy's order (leaves index into it), and their primitives.
    pub fn triangles(&self) -> (&[[[f32; 3]; 3]], &[u32]) {
        (&self.tris, &self.prims)
    }

    /// [`Bvh::closest_hit_adaptive`] for a ray leaving the origin `prepared` was made for
    /// (from [`Bvh::triangles`]): the f32 level is the shared-origin test of
    /// [`super::packet`], three dot products per triangle instead of the sheared test.
    pub(crate) fn closest_hit_from_origin(
        &self,
        ray: &Ray,
        prepared: Prepared<'_>,
        search: &mut Search,
    ) {
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let d_max = ray.d.iter().fold(0.0f32, |m, c| m.max(c.abs()));
        let d_max = if ray.d.iter().any(|c| c.is_nan()) {
            f32::NAN
        } else {
            d_max
        };
        let mut scratch = None;
        self.traverse(ray, tmin, tmax, 0.0, |first, count, _| {
            let leaf = first..first + count;
            // (Per ray for the lanes packets leave ambiguous: the baseline lanes, the same bits.)
            let tris =
                self.leaf_triangles::<f32x8>(prepared, first, first + count, ray.o, &mut scratch);
            for (j, (tri, prim)) in (self.tris[leaf.clone()].iter())
                .zip(&self.prims[leaf])
                .enumerate()
            {
                let est = match tris {
                    LeafTriangles::Listed(list) => list[j].estimate(ray.d, d_max),
                    LeafTriangles::Leaf { .. } | LeafTriangles::Blocks { .. } => {
                        match tris.get(j).estimate(ray.d, d_max) {
                            Estimate::Unsure => self
                                .precise(first + j, ray.o)
                                .rounded
                                .estimate(ray.d, d_max),
                            est => est,
                        }
                    }
                };
                if est != Estimate::Miss {
                    search.offer_triangle(*prim, tri, est);
                }
            }
            (search.t_far32(), false)
        });
    }

    /// Camera rays 8 at a time from the origin `o` (directions `d`, `d_max` ≥ every |dₖ|):
    /// the nearest triangle per lane as [`super::packet::closest`] over all triangles would
    /// decide it, as its position in the hierarchy's order ([`Bvh::triangles`]; `prim` of
    /// the result; u32::MAX for none), or ambiguous (to be traced per ray). The triangles
    /// come from `prepared` (made for `o`) or, without it, are prepared as the leaves are
    /// reached.
    ///
    /// Packet traversal: a node is entered while its box meets some lane that is not yet
    /// ambiguous, nearer than that lane's [`PacketNearest::reach`] (with the margin of the
    /// module docs); the child whose box the packet's first live lane enters first is visited
    /// first, and a popped node is tested again against the nearer hits found meanwhile.
    /// Every triangle a lane can hit nearer than its best so far is offered to it, so its
    /// answer is the one of the whole list.
    pub fn closest_packet(
        &self,
        o: [f32; 3],
        prepared: Option<&OriginTriangles>,
        d: &[f32x8; 3],
        d_max: f32,
    ) -> PacketHits {
        self.closest_packet_seeded(o, prepared, d, d_max, None)
    }

    /// [`Bvh::closest_packet`] starting from `seed` ([`PacketNearest::seeded`]; its ids must
    /// not be slots of this BVH).
    pub fn closest_packet_seeded(
        &self,
        o: [f32; 3],
        prepared: Option<&OriginTriangles>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        let prepared = Prepared::from_list(prepared);
        self.closest_packet_from(o, prepared, d, d_max, seed)
    }

    /// [`Bvh::closest_packet_seeded`] with the triangles from `prepared`.
    pub(crate) fn closest_packet_from(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        let bvh = self;
        avx2_or_baseline!(lanes Bvh::closest_packet_body => (
            bvh: &Bvh,
            o: [f32; 3],
            prepared: Prepared<'_>,
            d: &[f32x8; 3],
            d_max: f32,
            seed: Option<&PacketSeed>
        ) -> PacketHits)
    }

    #[inline(always)]
    fn closest_packet_body<V: Lanes>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        let mut nearest = PacketNearest::<V>::seeded(d, d_max, seed);
        self.walk_nearest(o, prepared, each3(|k| V::from_wide(d[k])), &mut nearest);
        nearest.finish()
    }

    /// [`Bvh::closest_packet_from`] (no seed) inside a kernel already in lanes `V` of any
    /// width (the AVX-512 tile loop's 16 camera rays): the ids into `prim[..V::WIDTH]`, the
    /// ambiguous lanes returned.
    #[inline(always)]
    pub(crate) fn closest_packet_in<V: LaneOps>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
        d_max: f32,
        prim: &mut [u32],
    ) -> u32 {
        let mut nearest = PacketNearest::<V>::new_in(d, d_max);
        self.walk_nearest(o, prepared, d, &mut nearest);
        nearest.finish_into(prim)
    }

    /// Offers `nearest` (rays from `o`, directions `d`) every triangle its lanes may reach.
    #[inline(always)]
    fn walk_nearest<V: LaneOps>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
        nearest: &mut PacketNearest<V>,
    ) {
        if self.wide.is_empty() {
            return;
        }
        if !prepared.fits(o, self.tris.len()) {
            return nearest.all_ambiguous();
        }
        let rays = PacketSlabs::<V>::new_in(o, d, self.tame);
        if !rays.trusted {
            return self.closest_packet_untrusted(nearest, o, prepared);
        }
        let mut leaves = PositionLeaves {
            bvh: self,
            o,
            prepared,
            scratch: None,
        };
        self.walk_packet(&rays, 0.0, nearest, &mut leaves);
    }

    /// The triangles `start..end` (at most 8; positions in the hierarchy's order) prepared
    /// for `o` in `V`'s lanes ([`OriginTriangle::new8`]); a short block repeats its last
    /// triangle. (Plain indexing into the lanes, no closures or iterators over them: in the
    /// AVX2 kernels those stayed calls, and their lane operations with them.)
    #[inline(always)]
    fn prepare_block<V: Lanes>(
        &self,
        start: usize,
        end: usize,
        o: [f32; 3],
        out: &mut OriginBlock,
    ) {
        let last = end - 1;
        let i: [usize; BLOCK] = std::array::from_fn(|j| (start + j).min(last));
        let t = &self.tris;
        let p = &self.prims;
        OriginTriangle::new8::<V>(
            [
                &t[i[0]], &t[i[1]], &t[i[2]], &t[i[3]], &t[i[4]], &t[i[5]], &t[i[6]], &t[i[7]],
            ],
            o,
            [
                p[i[0]], p[i[1]], p[i[2]], p[i[3]], p[i[4]], p[i[5]], p[i[6]], p[i[7]],
            ],
            out,
        );
    }

    /// The leaf `first..end` (at most 4 triangles) prepared for `o` as lanes 0–3 of a block
    /// (lanes 4–7 repeat them: their coordinates are gathered once, 4 lanes at a time).
    #[inline(always)]
    fn prepare_leaf<V: Lanes>(&self, first: usize, end: usize, o: [f32; 3], out: &mut OriginBlock) {
        let [i0, i1, i2, i3] = quad_indices(first, end);
        let t = &self.tris;
        let p = &self.prims;
        let (t, p) = (
            [&t[i0], &t[i1], &t[i2], &t[i3]],
            [p[i0], p[i1], p[i2], p[i3]],
        );
        OriginTriangle::new8::<V>(
            [t[0], t[1], t[2], t[3], t[0], t[1], t[2], t[3]],
            o,
            [p[0], p[1], p[2], p[3], p[0], p[1], p[2], p[3]],
            out,
        );
    }

    /// The leaf `first..end` prepared for `o` from its distinct vertices `corners`, in the
    /// lanes [`Bvh::prepare_leaf`] (at most 4 triangles) or [`Bvh::prepare_block`] would
    /// put it, with the same bits.
    #[inline(always)]
    fn prepare_corners<V: Lanes>(
        &self,
        corners: LeafCorners<'_>,
        first: usize,
        end: usize,
        o: [f32; 3],
        out: &mut OriginBlock,
    ) {
        let len = end - first;
        let j: [usize; BLOCK] = match len <= QUAD_LEAF {
            true => {
                let quad = quad_indices(0, len);
                std::array::from_fn(|l| quad[l % 4])
            }
            false => std::array::from_fn(|l| l.min(len - 1)),
        };
        let p = &self.prims[first..end];
        OriginTriangle::new8_from::<V>(
            &corners.in_lanes(j),
            o,
            [
                p[j[0]], p[j[1]], p[j[2]], p[j[3]], p[j[4]], p[j[5]], p[j[6]], p[j[7]],
            ],
            out,
        );
    }

    /// Offers a leaf's triangles `js` (of those from lane `start` of `blocks` on, positions
    /// from `first` on, prepared for `o`) one at a time to every lane, each again as
    /// [`Bvh::precise`] prepares it where it would leave a lane undecided.
    #[inline(always)]
    fn offer_each<V: LaneOps>(
        &self,
        nearest: &mut PacketNearest<V>,
        o: [f32; 3],
        blocks: &[&OriginBlock; 2],
        start: usize,
        first: usize,
        js: std::ops::Range<usize>,
    ) {
        for j in js {
            let id = (first + j) as u32;
            if !nearest.offer_decided(&block_lane(blocks, start, j), id) {
                nearest.offer_precise(&self.precise(first + j, o), id);
            }
        }
    }

    /// [`Bvh::offer_each`] for any sink: the leaf's `len` triangles (from lane `start` of
    /// `blocks` on, positions from `first` on) taken one at a time.
    #[inline(always)]
    fn take_each<V: LaneOps, S: PacketSink<V>>(
        &self,
        sink: &mut S,
        o: [f32; 3],
        blocks: &[&OriginBlock; 2],
        start: usize,
        first: usize,
        len: usize,
    ) {
        for j in 0..len {
            if !sink.take_decided(&block_lane(blocks, start, j)) {
                sink.take_precise(&self.precise(first + j, o));
            }
        }
    }

    /// The triangle at `position` prepared for `o` in f64 ([`PreciseTriangle`]), for the
    /// rays the f32 preparation of [`Bvh::prepare_block`] leaves undecided (rare: out of the
    /// way of the kernels).
    #[cold]
    #[inline(never)]
    fn precise(&self, position: usize, o: [f32; 3]) -> PreciseTriangle {
        PreciseTriangle::new(&self.tris[position], o, self.prims[position])
    }

    /// The leaf `first..end`'s triangles prepared for `o`: from `prepared`, or prepared into
    /// `scratch` (a leaf holds at most [`MAX_LEAF`] = 8: a block).
    #[inline(always)]
    fn leaf_triangles<'q, V: Lanes>(
        &self,
        prepared: Prepared<'q>,
        first: usize,
        end: usize,
        o: [f32; 3],
        scratch: &'q mut Option<OriginBlock>,
    ) -> LeafTriangles<'q> {
        debug_assert!(end - first <= MAX_LEAF);
        let len = end - first;
        match prepared {
            Prepared::All(list) => LeafTriangles::Listed(&list.tris[first..end]),
            Prepared::AsMet => {
                let block = scratch.get_or_insert_with(OriginBlock::default);
                let shared = self.leaf_vertices.as_ref().and_then(|v| v.leaf(first, end));
                match shared {
                    Some(corners) => self.prepare_corners::<V>(corners, first, end, o, block),
                    None if len <= QUAD_LEAF => self.prepare_leaf::<V>(first, end, o, block),
                    None => self.prepare_block::<V>(first, end, o, block),
                }
                LeafTriangles::Leaf { block, len }
            }
            Prepared::Once(cache) => {
                let (b0, b1) = (first / BLOCK, (end - 1) / BLOCK);
                let lo = self.cached_block::<V>(cache, b0, o);
                let hi = match b0 == b1 {
                    true => lo,
                    false => self.cached_block::<V>(cache, b1, o),
                };
                LeafTriangles::Blocks {
                    blocks: [lo, hi],
                    start: first - b0 * BLOCK,
                    len,
                }
            }
        }
    }

    /// Block `block` of the triangles (positions `BLOCK·block..`) prepared for `o`: from
    /// `cache`, or prepared now and kept there.
    #[inline(always)]
    fn cached_block<'c, V: Lanes>(
        &self,
        cache: &'c LeafCache,
        block: usize,
        o: [f32; 3],
    ) -> &'c OriginBlock {
        if let Some(ready) = cache.block(block) {
            return ready;
        }
        match cache.reach(block) {
            Reached::Ready(ready) => ready,
            Reached::Claimed(mut claim) => {
                let start = block * BLOCK;
                let end = self.tris.len().min(start + BLOCK);
                self.prepare_block::<V>(start, end, o, claim.block());
                claim.ready()
            }
        }
    }

    /// [`Bvh::closest_packet`] where the f32 slab test cannot be trusted: every triangle.
    #[cold]
    #[inline(never)]
    fn closest_packet_untrusted<V: LaneOps>(
        &self,
        nearest: &mut PacketNearest<V>,
        o: [f32; 3],
        prepared: Prepared<'_>,
    ) {
        for i in 0..self.tris.len() {
            match prepared {
                Prepared::All(p) => nearest.offer(&p.tris[i], i as u32),
                _ => nearest.offer(
                    &OriginTriangle::new(&self.tris[i], o, self.prims[i]),
                    i as u32,
                ),
            }
        }
    }

    /// [`Bvh::blocked_packet`] where the f32 slab test cannot be trusted: every triangle.
    #[cold]
    #[inline(never)]
    fn blocked_packet_untrusted<V: Lanes>(
        &self,
        mut packet: ShadowPacket<V>,
        o: [f32; 3],
        prepared: Prepared<'_>,
    ) -> ShadowHits {
        for i in 0..self.tris.len() {
            match prepared {
                Prepared::All(p) => packet.offer(&p.tris[i]),
                _ => packet.offer(&OriginTriangle::new(&self.tris[i], o, self.prims[i])),
            }
        }
        packet.finish()
    }

    /// Offers to `sink` (a nearest-hit or shadow state shared with other structures, the
    /// instances) every triangle the 8 rays from `o` may reach before their limits, from
    /// `prepared` (made for `o`) or prepared as met: [`Bvh::closest_packet`] and
    /// [`Bvh::blocked_packet`] with lanes recording primitive indices, not positions.
    #[inline(always)]
    pub(crate) fn packet_into<V: Lanes, S: PacketSink<V>>(
        &self,
        sink: &mut S,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
    ) {
        let prepared = match prepared.fits(o, self.tris.len()) {
            true => prepared,
            false => Prepared::AsMet,
        };
        let slabs = PacketSlabs::<V>::new(o, d, self.tame);
        let mut leaves = OwnLeaves {
            bvh: self,
            o,
            prepared,
            scratch: None,
        };
        self.walk_packet(&slabs, 0.0, sink, &mut leaves);
    }

    /// Eight shadow segments from one origin `o` (the light) through the BVH, directions `d`
    /// (`d_max` ≥ every |dₖ|): per lane of `valid`, blocked for 0 < t < 1 by a triangle other
    /// than its `skip` primitive, or unsure (to be traced per ray); see
    /// [`crate::accel::packet::shadow_from_origin`]. `prepared`: the triangles prepared for
    /// `o` (in the BVH's order), or `None` to prepare them as the packet meets them. Boxes are
    /// entered up to t = 1 + 2⁻¹⁶ (the culling margin of the module docs).
    pub fn blocked_packet(
        &self,
        o: [f32; 3],
        prepared: Option<&OriginTriangles>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> ShadowHits {
        let prepared = Prepared::from_list(prepared);
        self.blocked_packet_from(o, prepared, d, d_max, skip, valid)
    }

    /// [`Bvh::blocked_packet`] with the triangles from `prepared`.
    pub(crate) fn blocked_packet_from(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> ShadowHits {
        let bvh = self;
        avx2_or_baseline!(lanes Bvh::blocked_packet_body => (
            bvh: &Bvh,
            o: [f32; 3],
            prepared: Prepared<'_>,
            d: &[f32x8; 3],
            d_max: f32,
            skip: &[u32; 8],
            valid: u32
        ) -> ShadowHits)
    }

    #[inline(always)]
    fn blocked_packet_body<V: Lanes>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> ShadowHits {
        let mut packet = ShadowPacket::<V>::new(d, d_max, skip, valid);
        if self.wide.is_empty() {
            return packet.finish();
        }
        if !prepared.fits(o, self.tris.len()) {
            return ShadowHits {
                blocked: 0,
                unsure: valid,
            };
        }
        let rays = PacketSlabs::<V>::new(o, d, self.tame);
        if !rays.trusted {
            return self.blocked_packet_untrusted(packet, o, prepared);
        }
        let mut leaves = OwnLeaves {
            bvh: self,
            o,
            prepared,
            scratch: None,
        };
        self.walk_packet(&rays, 0.0, &mut packet, &mut leaves);
        packet.finish()
    }

    /// The adaptive any-hit query.
    pub fn any_hit_adaptive(
        &self,
        ray: &Ray,
        r: &WatertightRay<f32>,
        search: &Search,
        skip: u32,
    ) -> bool {
        let mut hit = false;
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let e = self.extent(ray);
        self.traverse(ray, tmin, tmax, 0.0, |first, count, t_far| {
            hit = (first..first + count).any(|i| {
                self.prims[i] != skip
                    && search.confirms_triangle(&self.tris[i], classify_f32(r, &self.tris[i], e))
            });
            (t_far, hit)
        });
        hit
    }
}

/// The slab test of [`Bvh::traverse`] in f64, for rays or boxes beyond [`slab_safe`]: every
/// f32 input and its inverse direction are f64 values far from f64's limits, so the
/// distances are within a few f64 roundings of exact. Both are widened by 2⁻²⁰ relative, so
/// the test stays at least as generous as the f32 one (whose roundings the inexact methods'
/// own f32 hits may share); the entry distance is handed back rounded down to f32.
#[inline(never)]
fn enter_f64(b: &Aabb, pad: f32, ray: &Ray, inv: &[f64; 3], tmin: f32, t_far: f32) -> Option<f32> {
    const WIDEN: f64 = 1.0 / (1u64 << 20) as f64;
    let (mut t0, mut t1) = (f64::from(tmin), f64::from(t_far));
    for (k, &inv) in inv.iter().enumerate() {
        let pad = f64::from(pad);
        let (lo, hi) = (f64::from(b.lo[k]) - pad, f64::from(b.hi[k]) + pad);
        let (near, far) = if inv < 0.0 { (hi, lo) } else { (lo, hi) };
        let o = f64::from(ray.o[k]);
        let (tn, tf) = ((near - o) * inv, (far - o) * inv);
        // f64::min/max ignore a NaN (0·∞ for a ray in a slab's plane): conservative.
        t0 = t0.max(tn - tn.abs() * WIDEN);
        t1 = t1.min(tf + tf.abs() * WIDEN);
    }
    (t0 <= t1).then(|| {
        let t = t0 as f32;
        if f64::from(t) > t0 {
            t.next_down()
        } else {
            t
        }
    })
}

/// What a packet walk does at a leaf: offers the leaf's items to the packet's state.
pub(crate) trait Leaves<V, S> {
    /// Items `first..first + count` of the hierarchy walked, which the lanes `lanes` may
    /// reach (bit l for lane l; the others cannot reach them before their limits).
    fn visit(&mut self, sink: &mut S, first: usize, count: usize, lanes: u32);
}

/// A leaf's triangles prepared for a walk's origin: a run of a full list, a leaf prepared as
/// met (lanes 0 to `len` − 1 of `block`; a leaf of at most 4 again from lane 4 on:
/// [`Bvh::prepare_leaf`]), or
/// `len` lanes of one block or two from lane `start` on (a leaf across two of a cache's
/// blocks).
#[derive(Clone, Copy)]
enum LeafTriangles<'q> {
    Listed(&'q [OriginTriangle]),
    Leaf {
        block: &'q OriginBlock,
        len: usize,
    },
    Blocks {
        blocks: [&'q OriginBlock; 2],
        start: usize,
        len: usize,
    },
}

impl LeafTriangles<'_> {
    #[cfg(test)]
    fn len(&self) -> usize {
        match self {
            LeafTriangles::Listed(list) => list.len(),
            LeafTriangles::Leaf { len, .. } | LeafTriangles::Blocks { len, .. } => *len,
        }
    }

    /// The leaf's `j`th triangle. (The packet visits match on the kind outside their loops
    /// instead: one loop over both kinds kept a pointer per field, 9% more instructions.)
    #[inline(always)]
    fn get(&self, j: usize) -> OriginTriangle {
        match self {
            LeafTriangles::Listed(list) => list[j],
            LeafTriangles::Leaf { block, .. } => block.get(j),
            LeafTriangles::Blocks { blocks, start, .. } => block_lane(blocks, *start, j),
        }
    }
}

/// The `j`th lane from `start` on of the blocks `[lo, hi]` (`hi` past lane 7).
#[inline(always)]
fn block_lane(blocks: &[&OriginBlock; 2], start: usize, j: usize) -> OriginTriangle {
    // (One `get` at a computed block and lane: a `get` per block merged each field's
    // address from two, a register each.)
    let l = start + j;
    blocks[(l / BLOCK) & 1].get(l % BLOCK)
}

/// A hierarchy's own triangles, prepared for `o` (or as met).
struct OwnLeaves<'a> {
    bvh: &'a Bvh,
    o: [f32; 3],
    prepared: Prepared<'a>,
    /// Where a leaf prepared as met is written (made at the walk's first such leaf).
    scratch: Option<OriginBlock>,
}

impl<V: LaneOps, S: PacketSink<V>> Leaves<V, S> for OwnLeaves<'_> {
    #[inline(always)]
    fn visit(&mut self, sink: &mut S, first: usize, count: usize, _: u32) {
        let end = first + count;
        let tris = (self.bvh).leaf_triangles::<V::Eight>(
            self.prepared,
            first,
            end,
            self.o,
            &mut self.scratch,
        );
        match tris {
            LeafTriangles::Listed(list) => {
                // (A loop, not `for_each` with a closure: see `PacketSlabs::new_in`.)
                for t in list {
                    sink.take(t);
                }
            }
            // (A leaf prepared as met is the one block it is written in.)
            LeafTriangles::Leaf { block, len } => {
                (self.bvh).take_each(sink, self.o, &[block, block], 0, first, len)
            }
            LeafTriangles::Blocks { blocks, start, len } => {
                (self.bvh).take_each(sink, self.o, &blocks, start, first, len)
            }
        }
    }
}

/// The packet slab test's far-distance factor: 2γ(3) (pbrt) and one rounding more, for the
/// rounding of 1/dₖ·slack itself.
#[inline(always)]
fn far_slack() -> f32 {
    1.0 + 2.0 * f32::error_gamma(4)
}

/// A hierarchy's own triangles for [`Bvh::closest_packet`]: lanes record positions in the
/// hierarchy's order, not primitive indices.
struct PositionLeaves<'a> {
    bvh: &'a Bvh,
    o: [f32; 3],
    prepared: Prepared<'a>,
    /// Where a leaf prepared as met is written (made at the walk's first such leaf).
    scratch: Option<OriginBlock>,
}

impl<V: LaneOps> Leaves<V, PacketNearest<V>> for PositionLeaves<'_> {
    #[inline(always)]
    fn visit(&mut self, nearest: &mut PacketNearest<V>, first: usize, count: usize, lanes: u32) {
        let end = first + count;
        let tris = (self.bvh).leaf_triangles::<V::Eight>(
            self.prepared,
            first,
            end,
            self.o,
            &mut self.scratch,
        );
        match tris {
            LeafTriangles::Listed(list) => {
                for (j, tri) in list.iter().enumerate() {
                    nearest.offer(tri, (first + j) as u32);
                }
            }
            LeafTriangles::Leaf { block, len } => {
                let decided = match lanes.count_ones() {
                    1 => {
                        let (tris, base) = ((1 << len) - 1, BlockIds::From(first as u32));
                        nearest.offer_block_to_lane(
                            block,
                            tris,
                            base,
                            lanes.trailing_zeros() as usize,
                        )
                    }
                    // A few lanes: the leaf to them alone, 4 triangles by 2 or 4 rays a pass.
                    // (Two passes of 16 lanes for 5 to 8 lanes were slower than offers one by
                    // one: bunny 640×360, 1 thread, 2.21 against 2.17 ms.)
                    2..=4 if len <= QUAD_LEAF => {
                        nearest.offer_leaf_to_lanes(block, len, first as u32, lanes)
                    }
                    _ => false,
                };
                if !decided {
                    (self.bvh).offer_each(nearest, self.o, &[block, block], 0, first, 0..len);
                }
            }
            LeafTriangles::Blocks { blocks, start, len } => {
                if lanes.count_ones() != 1 {
                    return (self.bvh).offer_each(nearest, self.o, &blocks, start, first, 0..len);
                }
                // One lane: the leaf's part of each block at once.
                let l = lanes.trailing_zeros() as usize;
                let in_first = len.min(BLOCK - start);
                let base = (first - start) as u32;
                let mask = ((1u32 << in_first) - 1) << start;
                if !nearest.offer_block_to_lane(blocks[0], mask, BlockIds::From(base), l) {
                    (self.bvh).offer_each(nearest, self.o, &blocks, start, first, 0..in_first);
                }
                if in_first < len {
                    let mask = (1u32 << (len - in_first)) - 1;
                    let base = base + BLOCK as u32;
                    if !nearest.offer_block_to_lane(blocks[1], mask, BlockIds::From(base), l) {
                        (self.bvh).offer_each(
                            nearest,
                            self.o,
                            &blocks,
                            start,
                            first,
                            in_first..len,
                        );
                    }
                }
            }
        }
    }
}

/// Eight rays from one origin set up for the slab test against boxes.
pub(crate) struct PacketSlabs<V = f32x8> {
    o: [f32; 3],
    inv: [V; 3],
    /// 1/dₖ enlarged for the far distances (see `new`).
    inv_far: [V; 3],
    neg: [V; 3],
    /// Per axis, the sign every lane's direction shares (`None` if mixed): near and far slab
    /// are then the same for the whole packet.
    sign: [Option<bool>; 3],
    /// Whether every 1/dₖ is finite (then no 0·∞ can arise).
    tame: bool,
    /// Tame, and every axis's sign shared: per axis, whether the near slab is the box's high
    /// side (`enter` then takes one branch-free path).
    coherent: Option<[bool; 3]>,
    /// Whether the f32 test can be trusted: the origin and every direction are
    /// [`slab_safe`], the boxes [`box_safe`]; else the walks offer every triangle, testing no
    /// box.
    pub(crate) trusted: bool,
}

impl<V: Lanes> PacketSlabs<V> {
    #[inline(always)]
    pub(crate) fn new(o: [f32; 3], d: &[f32x8; 3], boxes_tame: bool) -> Self {
        Self::new_in(o, each3(|k| V::from_wide(d[k])), boxes_tame)
    }
}

impl<V: LaneOps> PacketSlabs<V> {
    /// [`PacketSlabs::new`] for directions already in lanes `V` (of any width).
    #[inline(always)]
    pub(crate) fn new_in(o: [f32; 3], d: [V; 3], boxes_tame: bool) -> Self {
        let inv = each3(|k| V::one() / d[k]);
        let neg = each3(|k| inv[k].simd_lt(V::zero()));
        let sign = each3(|k| match neg[k].to_bitmask() {
            0 => Some(false),
            m if m == V::full() => Some(true),
            _ => None,
        });
        // Tame: every |dₖ| within 2⁻⁴⁰…2⁴⁰ ([`slab_safe`]), so no 1/dₖ is infinite (no 0·∞)
        // and the f32 test holds. Else zeros are fine too, anything else is not trusted.
        let (lo, hi) = (
            f32::from_bits((127 - SAFE_EXP) << 23),
            f32::from_bits((127 + SAFE_EXP) << 23),
        );
        let (lo_v, hi_v) = (V::splat(lo), V::splat(hi));
        // (Masks and plain loops, no closures over lanes: in the instances' kernels, which
        // set up a packet per instance it meets, those stayed calls compiled without the
        // kernels' target features, each lane operation in them a call of its own.)
        let (mut in_range, mut safe) = (V::full(), V::full());
        for dk in &d {
            let a = dk.abs();
            let within = (a.simd_ge(lo_v) & a.simd_le(hi_v)).to_bitmask();
            in_range &= within;
            safe &= within | a.simd_eq(V::zero()).to_bitmask();
        }
        let tame = in_range == V::full();
        let mut origin_safe = true;
        for x in o {
            let a = x.abs();
            origin_safe &= a == 0.0 || (a >= lo && a <= hi);
        }
        let trusted = boxes_tame && origin_safe && safe == V::full();
        let inv_far = each3(|k| inv[k] * V::splat(far_slack()));
        let coherent = match sign {
            [Some(x), Some(y), Some(z)] if tame => Some([x, y, z]),
            _ => None,
        };
        Self {
            o,
            inv,
            inv_far,
            neg,
            sign,
            tame,
            coherent,
            trusted,
        }
    }

    /// The lanes of `live` whose rays meet box `b` before `limit`, and their entry distances.
    #[inline(always)]
    pub(crate) fn enter(&self, b: &Aabb, limit: V, live: u32) -> (u32, V) {
        let mut t0 = V::zero();
        let mut t1 = limit;
        if let Some(near_hi) = self.coherent {
            // The loop below for this case, the same operations without its per-axis
            // branches (bunny flat: 1.5% fewer instructions, callgrind). Indexed: the
            // iterator form took 5% more.
            #[allow(clippy::needless_range_loop)]
            for k in 0..3 {
                let near = b.side(near_hi[k])[k] - self.o[k];
                let far = b.side(!near_hi[k])[k] - self.o[k];
                t0 = t0.fast_max(V::splat(near) * self.inv[k]);
                t1 = t1.fast_min(V::splat(far) * self.inv_far[k]);
            }
            return (t0.simd_le(t1).to_bitmask() & live, t0);
        }
        for k in 0..3 {
            let (lo, hi) = (b.lo[k] - self.o[k], b.hi[k] - self.o[k]);
            let (near, far) = match self.sign[k] {
                Some(false) => (V::splat(lo), V::splat(hi)),
                Some(true) => (V::splat(hi), V::splat(lo)),
                None => {
                    let (lo, hi) = (V::splat(lo), V::splat(hi));
                    (self.neg[k].bitselect(hi, lo), self.neg[k].bitselect(lo, hi))
                }
            };
            let (tn, tf) = (near * self.inv[k], far * self.inv_far[k]);
            if self.tame {
                t0 = t0.fast_max(tn);
                t1 = t1.fast_min(tf);
            } else {
                // `max`/`min` keep the left side where the right is NaN (0·∞ for a ray in a
                // slab's plane): no constraint, as in the scalar test.
                t0 = t0.max(tn);
                t1 = t1.min(tf);
            }
        }
        (t0.simd_le(t1).to_bitmask() & live, t0)
    }
}

/// A box in 4 lanes (the fourth is not a coordinate).
#[derive(Clone, Copy)]
struct Box4 {
    lo: f32x4,
    hi: f32x4,
}

impl Box4 {
    const EMPTY: Box4 = Box4 {
        lo: f32x4::splat(f32::INFINITY),
        hi: f32x4::splat(f32::NEG_INFINITY),
    };

    /// Grows to hold the box `lo`–`hi` (`minps`/`maxps`, which answer their second operand
    /// where either is NaN: a NaN coordinate of the new box is ignored, as [`Aabb::grow`]
    /// ignores it).
    #[inline(always)]
    fn grow(&mut self, lo: f32x4, hi: f32x4) {
        self.lo = lo.fast_min(self.lo);
        self.hi = hi.fast_max(self.hi);
    }

    #[inline(always)]
    fn union(mut self, o: &Box4) -> Self {
        self.grow(o.lo, o.hi);
        self
    }

    fn aabb(&self) -> Aabb {
        let (lo, hi) = (self.lo.as_array(), self.hi.as_array());
        Aabb {
            lo: [lo[0], lo[1], lo[2]],
            hi: [hi[0], hi[1], hi[2]],
        }
    }
}

/// What a split needs to know of a set of items: their boxes' box and their centres' box.
#[derive(Clone, Copy)]
struct Bounds {
    boxes: Box4,
    centres: Box4,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        boxes: Box4::EMPTY,
        centres: Box4::EMPTY,
    };

    #[inline(always)]
    fn add(&mut self, r: &Ref) {
        self.boxes.grow(r.lo, r.hi);
        let c = r.centre();
        self.centres.grow(c, c);
    }

    #[inline(always)]
    fn union(mut self, o: &Bounds) -> Self {
        self.boxes = self.boxes.union(&o.boxes);
        self.centres = self.centres.union(&o.centres);
        self
    }

    fn of(refs: &[Ref]) -> Self {
        let mut b = Self::EMPTY;
        refs.iter().for_each(|r| b.add(r));
        b
    }

    /// [`Bounds::of`] on every thread (the root's set: no split runs beside it).
    fn of_par(refs: &[Ref]) -> Self {
        (refs.par_chunks(PARALLEL_MIN).map(Self::of)).reduce(|| Self::EMPTY, |a, b| a.union(&b))
    }
}

/// Where `order` (partitioned by the call) divides into two children, with their bounds, or
/// `None` for a leaf: exactly the sets of at most `leaf_max` items, which the wide nodes
/// hold as one leaf whatever the binary tree below (splitting them was a third of the build).
fn split(
    order: &mut [Ref],
    bounds: &Bounds,
    depth: usize,
    plan: Plan,
) -> Option<(usize, [Bounds; 2])> {
    let n = order.len();
    if n <= plan.leaf_max {
        return None;
    }
    let cb = bounds.centres.aabb();
    let extent = [0, 1, 2].map(|k| cb.hi[k] - cb.lo[k]);
    let widest = (0..3)
        .max_by(|&a, &b| extent[a].total_cmp(&extent[b]))
        .unwrap_or(0);
    // Past `SAH_DEPTH` levels, split by count: the tree stays within the traversals'
    // stacks whatever the geometry (at most 2²⁸ items: 28 more levels).
    if depth < SAH_DEPTH {
        let axes: &[usize] = match plan.all_axes {
            true => &[0, 1, 2],
            false => &[widest],
        };
        if let Some(s) = sah_split(order, &cb, &bounds.boxes, axes) {
            return Some(s);
        }
    }
    // Too deep, all centres in one bin (or equal), or an extent too small to bin: split by
    // count so leaves stay small.
    let axis = widest;
    order.select_nth_unstable_by(n / 2, |a, b| {
        a.centre_on(axis).total_cmp(&b.centre_on(axis))
    });
    let (left, right) = order.split_at(n / 2);
    Some((n / 2, [Bounds::of(left), Bounds::of(right)]))
}

/// Centres' bins along one axis: `BINS` between the least and greatest centre.
struct Binning {
    axis: usize,
    lo: f32x4,
    scale: f32x4,
}

impl Binning {
    /// Along `axis` of the centres' box `cb`; `None` where the extent is too small for an f32
    /// scale (below 16/f32::MAX: the set is then split by count).
    fn new(cb: &Aabb, axis: usize) -> Option<Self> {
        let scale = BINS as f64 / (f64::from(cb.hi[axis]) - f64::from(cb.lo[axis]));
        if scale > f64::from(f32::MAX) {
            return None;
        }
        let lane = |v: f32| std::array::from_fn(|k| if k == axis { v } else { 0.0 });
        Some(Self {
            axis,
            lo: f32x4::new(lane(cb.lo[axis])),
            scale: f32x4::new(lane(scale as f32)),
        })
    }

    /// Item `r`'s bin.
    #[inline(always)]
    fn of(&self, r: &Ref) -> u32 {
        // (centre − lo)·scale ≥ 0 (lo is the least centre), clamped, in 4 lanes: `as u32` on
        // one f32 checks for overflow and NaN at every item, `cvttps2dq` does not.
        let last = f32x4::splat((BINS - 1) as f32);
        let b = ((r.centre() - self.lo) * self.scale)
            .fast_min(last)
            .fast_trunc_int();
        b.to_array()[self.axis] as u32
    }
}

/// The best binned-SAH split along any of `axes` (`cb`: the centres' box, `bounds`: the
/// set's box): partitions `order` and returns the split point with both sides' bounds, or
/// `None` when no plane separates anything. (Binning all three axes and taking the best cut
/// the 1M mesh's rendering instructions by 5% but cost the build 73% more: the widest axis
/// alone, but for the instanced meshes, built once however often they are placed.)
fn sah_split(
    order: &mut [Ref],
    cb: &Aabb,
    bounds: &Box4,
    axes: &[usize],
) -> Option<(usize, [Bounds; 2])> {
    // Areas relative to the set's box's largest extent: in f32, and within 0…3.
    let extent = (bounds.hi - bounds.lo).to_array();
    let largest = f64::from(extent[0].max(extent[1]).max(extent[2]));
    let unit = (1.0 / largest).min(f64::from(f32::MAX)) as f32;
    let mut best: Option<(f32, u32, Binning)> = None;
    for &axis in axes {
        let Some(binning) = Binning::new(cb, axis) else {
            continue;
        };
        let mut counts = [0u32; BINS];
        let mut bins = [Box4::EMPTY; BINS];
        for r in order.iter() {
            let b = binning.of(r) as usize;
            counts[b] += 1;
            bins[b].grow(r.lo, r.hi);
        }
        let Some((cost, split_bin)) = cheapest_plane(&counts, &bins, unit) else {
            continue;
        };
        if best.as_ref().is_none_or(|b| cost < b.0) {
            best = Some((cost, split_bin as u32, binning));
        }
    }
    let (_, split_bin, binning) = best?;
    let mut sides = [Bounds::EMPTY; 2];
    let mut i = 0;
    let mut j = order.len();
    while i < j {
        let r = &order[i];
        if binning.of(r) <= split_bin {
            sides[0].add(r);
            i += 1;
        } else {
            sides[1].add(r);
            j -= 1;
            order.swap(i, j);
        }
    }
    Some((i, sides))
}

/// The cheapest plane between `BINS` bins: its SAH cost and the last bin on its left, or
/// `None` when every item is in one bin. Areas are in f32 on extents times `unit`.
fn cheapest_plane(counts: &[u32; BINS], bins: &[Box4; BINS], unit: f32) -> Option<(f32, usize)> {
    let half_area = |b: &Box4| {
        let d = ((b.hi - b.lo) * unit).to_array();
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    };
    // Sweep from the right, then from the left, for the cost of each of the BINS-1 planes.
    let mut right_area = [0.0f32; BINS];
    let mut acc = Box4::EMPTY;
    for b in (1..BINS).rev() {
        acc = acc.union(&bins[b]);
        right_area[b] = half_area(&acc);
    }
    let n: u32 = counts.iter().sum();
    let mut best = (f32::INFINITY, 0usize);
    let mut left = Box4::EMPTY;
    let mut left_n = 0u32;
    for b in 0..BINS - 1 {
        left = left.union(&bins[b]);
        left_n += counts[b];
        let right_n = n - left_n;
        if left_n == 0 || right_n == 0 {
            continue;
        }
        let cost = half_area(&left) * left_n as f32 + right_area[b + 1] * right_n as f32;
        if cost < best.0 {
            best = (cost, b);
        }
    }
    best.0.is_finite().then_some(best)
}

/// A leaf over `count` items from `first`.
fn leaf(bounds: &Bounds, first: usize, count: usize) -> Node {
    Node {
        bounds: bounds.boxes.aabb(),
        offset: first as u32,
        count: count as u16,
        height: 0,
    }
}

/// An interior node whose second child is `offset` nodes on, `height` levels above the
/// leaves.
fn interior(bounds: &Bounds, offset: usize, height: u16) -> Node {
    Node {
        bounds: bounds.boxes.aabb(),
        offset: offset as u32,
        count: 0,
        height,
    }
}

/// Builds the subtree over `order` (with its `bounds`; its first item goes to position
/// `start`) in depth-first order: the node, then its first child's subtree, then its
/// second's. Sets of at least `parallel_min` items build their two halves on two threads and
/// concatenate them; smaller ones push into one vector (concatenating at every level copied
/// each node once per level above it: 1.3 GB of copies for a million triangles).
fn build_node(
    order: &mut [Ref],
    bounds: &Bounds,
    start: usize,
    plan: Plan,
    depth: usize,
) -> Vec<Node> {
    if order.len() < plan.parallel_min {
        // At most 2n - 1 nodes (every leaf holds an item); reserving is not touching.
        let mut nodes = Vec::with_capacity(2 * order.len());
        build_into(order, bounds, start, &mut nodes, depth, plan);
        return nodes;
    }
    let Some((mid, [left_bounds, right_bounds])) = split(order, bounds, depth, plan) else {
        return vec![leaf(bounds, start, order.len())];
    };
    let (left, right) = order.split_at_mut(mid);
    let (l, r) = rayon::join(
        || build_node(left, &left_bounds, start, plan, depth + 1),
        || build_node(right, &right_bounds, start + mid, plan, depth + 1),
    );
    let mut nodes = Vec::with_capacity(1 + l.len() + r.len());
    let height = 1 + l[0].height.max(r[0].height);
    nodes.push(interior(bounds, 1 + l.len(), height));
    nodes.extend(l);
    nodes.extend(r);
    nodes
}

/// [`build_node`] on one thread, appending to `nodes`; returns the subtree's height.
fn build_into(
    order: &mut [Ref],
    bounds: &Bounds,
    start: usize,
    nodes: &mut Vec<Node>,
    depth: usize,
    plan: Plan,
) -> u16 {
    let Some((mid, [left_bounds, right_bounds])) = split(order, bounds, depth, plan) else {
        nodes.push(leaf(bounds, start, order.len()));
        return 0;
    };
    let at = nodes.len();
    nodes.push(interior(bounds, 0, 0));
    let (left, right) = order.split_at_mut(mid);
    let left_height = build_into(left, &left_bounds, start, nodes, depth + 1, plan);
    nodes[at].offset = (nodes.len() - at) as u32;
    let right_height = build_into(right, &right_bounds, start + mid, nodes, depth + 1, plan);
    nodes[at].height = 1 + left_height.max(right_height);
    nodes[at].height
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The binary tree's height below node `node` (a leaf 0), counted.
    pub(super) fn depth(nodes: &[Node], node: usize) -> usize {
        match nodes[node].count {
            0 => {
                let [a, b] = Node::children(nodes, node);
                1 + depth(nodes, a).max(depth(nodes, b))
            }
            _ => 0,
        }
    }

    /// `n` triangles with edges `size` long at xorshift-random places (from `seed`) in
    /// [0, 10)³.
    pub(super) fn scattered(n: u32, seed: u64, size: f32) -> Vec<IndexedTriangle> {
        let mut x = seed;
        let mut next = || (crate::xorshift(&mut x) >> 40) as f32 / (1u64 << 24) as f32 * 10.0;
        (0..n)
            .map(|i| {
                let p = [next(), next(), next()];
                let q = |d: [f32; 3]| [0, 1, 2].map(|k| p[k] + d[k] * size);
                ([p, q([1.0, 0.0, 0.0]), q([0.0, 1.0, 1.0])], i)
            })
            .collect()
    }

    /// The hierarchies the walk tests run on: leaves of up to 4 triangles, of up to 8 (a
    /// dense mesh's), and of up to 8 read from the leaves' shared vertices.
    pub(super) const LAYOUTS: [(usize, bool); 3] =
        [(SMALL_LEAF, false), (MAX_LEAF, false), (MAX_LEAF, true)];

    /// A sheet of 512 triangles (see [`sheet`]) and then `tris`, renumbered from 0: leaves
    /// of shared vertices and leaves of none.
    pub(super) fn with_sheet(tris: Vec<IndexedTriangle>) -> Vec<IndexedTriangle> {
        let mut all = sheet(16);
        all.extend(tris);
        for (i, t) in all.iter_mut().enumerate() {
            t.1 = i as u32;
        }
        all
    }

    /// A wavy sheet of 2n² triangles over a grid of (n + 1)² points, 6 units wide: neighbours
    /// share their vertices' bits, as a fine mesh's do (prims from 0).
    pub(super) fn sheet(n: u32) -> Vec<IndexedTriangle> {
        let p = |i: u32, j: u32| {
            let (x, y) = (
                2.0 + 6.0 * i as f32 / n as f32,
                2.0 + 6.0 * j as f32 / n as f32,
            );
            [x, y, 5.0 + 0.3 * (1.7 * x).sin() * (1.3 * y).cos()]
        };
        (0..n * n)
            .flat_map(|c| {
                let (i, j) = (c % n, c / n);
                [
                    [p(i, j), p(i + 1, j), p(i, j + 1)],
                    [p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)],
                ]
            })
            .enumerate()
            .map(|(k, t)| (t, k as u32))
            .collect()
    }

    #[test]
    fn top_levels_cover_every_triangle_with_their_childless_boxes() {
        // 4000 scattered triangles: at each depth, the nodes form a tree in breadth-first
        // order (children after their parent, each parent's contiguous, inside its box)
        // whose childless boxes hold every triangle; deep enough, they are the leaves.
        let tris = scattered(4000, 0x9e3779b97f4a7c15, 0.05);
        let bvh = Bvh::build(&tris);
        let leaves = bvh.wide.iter().flat_map(|n| n.leaves()).count();
        let mut sizes = Vec::new();
        for depth in [0, 1, 2, 3, 40] {
            let nodes = bvh.top_levels(depth);
            sizes.push(nodes.len());
            assert_eq!(nodes[0].bounds, bvh.root_bounds().unwrap());
            let childless: Vec<&Aabb> = (nodes.iter())
                .filter(|n| n.children.is_none())
                .map(|n| &n.bounds)
                .collect();
            let mut next = 1;
            for (i, n) in nodes.iter().enumerate() {
                if let Some((first, count)) = n.children {
                    assert!(first as usize > i && first as usize == next && count >= 2);
                    next += count as usize;
                    for c in &nodes[first as usize..next] {
                        assert!((0..3).all(|k| n.bounds.lo[k] <= c.bounds.lo[k]
                            && c.bounds.hi[k] <= n.bounds.hi[k]));
                    }
                }
            }
            assert_eq!(next, nodes.len());
            if depth == 40 {
                assert_eq!(childless.len(), leaves, "leaves at depth {depth}");
            }
            for (v, i) in &tris {
                let inside = |b: &&&Aabb| {
                    v.iter()
                        .all(|p| (0..3).all(|k| b.lo[k] <= p[k] && p[k] <= b.hi[k]))
                };
                assert!(childless.iter().any(|b| inside(&b)), "triangle {i}");
            }
        }
        assert!(sizes.windows(2).all(|w| w[0] < w[1]), "{sizes:?}");
    }

    #[test]
    fn the_tree_stays_within_the_traversal_stacks() {
        // Triangles at positions growing geometrically (binned SAH peels one off per level)
        // and a cube of side 2⁻¹³⁰ (subnormal: every area 0 in f32): the depth stays below
        // the 64-entry stacks, and a ray along the row still finds its nearest triangle.
        let row: Vec<IndexedTriangle> = (0..120)
            .map(|i| {
                let x = 2f32.powi(i);
                ([[x, -1.0, 1.0], [x, 1.0, 1.0], [x, 0.0, -1.0]], i as u32)
            })
            .collect();
        let (nodes, _) = binary(&row, SMALL_LEAF, false);
        assert!(depth(&nodes, 0) < 64, "depth {}", depth(&nodes, 0));
        let bvh = Bvh::build(&row);
        let shapes: Vec<Shape> = row.iter().map(|(v, _)| Shape::Triangle(*v)).collect();
        for x in [1e9f32, 5.0, 1e30] {
            let ray = Ray::new([x, 0.1, 0.0], [-1.0, 0.0, 0.0]);
            let want =
                crate::accel::closest_hit(&shapes, &ray, Method::Adaptive, 0.0, f32::INFINITY);
            let hit = bvh.closest_hit(&ray, Method::Adaptive, 0.0, f32::INFINITY);
            assert_eq!(hit.map(|h| h.prim), want.map(|h| h.prim));
            assert!(hit.is_some());
        }

        let s = 2f32.powi(-130);
        let tiny: Vec<IndexedTriangle> = (0..400)
            .map(|i| {
                let (x, y) = ((i % 20) as f32 * s, (i / 20) as f32 * s);
                ([[x, y, 0.0], [x + s, y, 0.0], [x, y + s, s]], i as u32)
            })
            .collect();
        let bvh = Bvh::build(&tiny);
        assert!(!bvh.boxes_tame());
        let (nodes, _) = binary(&tiny, SMALL_LEAF, false);
        assert!(depth(&nodes, 0) < 64, "depth {}", depth(&nodes, 0));
    }

    #[test]
    fn placed_meshes_split_on_the_axis_that_costs_least() {
        // Two rows of small triangles 100 units long (x, the centres' widest extent) and 10
        // apart in y. Split along x only, both halves of the root span both rows (a box 10
        // tall); sought along every axis, the root's split is the cheaper one between the
        // rows, and each half is a row (under 1 tall). Answers are the list's either way.
        let tris: Vec<IndexedTriangle> = (0..200u32)
            .map(|i| {
                let (x, y) = (f32::from((i % 100) as u16), 10.0 * (i / 100) as f32);
                ([[x, y, 0.0], [x + 0.5, y, 0.0], [x, y + 0.5, 0.5]], i)
            })
            .collect();
        let root_halves_height = |all_axes: bool| {
            let (nodes, _) = binary(&tris, SMALL_LEAF, all_axes);
            let [a, b] = Node::children(&nodes, 0);
            [a, b].map(|c| nodes[c].bounds.hi[1] - nodes[c].bounds.lo[1])
        };
        assert!(root_halves_height(false).iter().all(|&h| h > 10.0));
        assert!(root_halves_height(true).iter().all(|&h| h < 1.0));
        let placed = Bvh::build_placed(&tris);
        let shapes: Vec<Shape> = tris.iter().map(|(v, _)| Shape::Triangle(*v)).collect();
        for i in 0..200 {
            let (x, y) = (0.37 * i as f32 + 0.1, 10.0 * (i % 2) as f32 + 0.1);
            let ray = Ray::new([x, y, -5.0], [0.01, 0.002, 1.0]);
            let want =
                crate::accel::closest_hit(&shapes, &ray, Method::Adaptive, 0.0, f32::INFINITY);
            let hit = placed.closest_hit(&ray, Method::Adaptive, 0.0, f32::INFINITY);
            assert_eq!(hit.map(|h| h.prim), want.map(|h| h.prim), "ray {i}");
        }
    }

    #[test]
    fn untrusted_packets_offer_every_triangle_from_every_kind_of_preparation() {
        // A sheet and 1003 scattered triangles, packets from an origin at 1e-20 (beyond the
        // f32 slab test's range: no box is tested, every triangle offered, in runs of 8 that
        // are not leaves), the triangles prepared beforehand, once per frame in a cache, or
        // as met: each lane's nearest is the whole list's.
        let tris = with_sheet(scattered(1003, 0x2545f4914f6cdd1d, 0.3));
        for (leaf_max, shared) in LAYOUTS {
            let bvh = Bvh::build_with(&tris, leaf_max, shared);
            let o = [1e-20, 5.0, -4.0];
            let (vertices, prims) = bvh.triangles();
            let list = OriginTriangles::from_parts(vertices, prims, o);
            let pool = super::super::prepared::CachePool::default();
            let cache = pool.take(bvh.len(), o);
            // Lane l towards triangle 97·l's centroid.
            let d: [f32x8; 3] = [0, 1, 2].map(|k| {
                f32x8::from(std::array::from_fn(|l| {
                    let v = &tris[97 * l].0;
                    (v[0][k] + v[1][k] + v[2][k]) / 3.0 - o[k]
                }))
            });
            let dm = crate::accel::packet::max_component(&d);
            let whole = crate::accel::packet::closest(&list.tris, &d, dm);
            assert!(whole.prim.iter().filter(|&&p| p != u32::MAX).count() >= 6);
            let slabs = PacketSlabs::<f32x8>::new(o, &d, bvh.boxes_tame());
            assert!(!slabs.trusted);
            for prepared in [
                Prepared::All(&list),
                Prepared::Once(&cache),
                Prepared::AsMet,
            ] {
                let mut nearest = PacketNearest::<f32x8>::seeded(&d, dm, None);
                bvh.packet_into(&mut nearest, o, prepared, &d);
                let found = nearest.finish();
                for l in 0..8 {
                    if (found.ambiguous | whole.ambiguous) & (1 << l) == 0 {
                        assert_eq!(found.prim[l], whole.prim[l], "lane {l}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_frames_cache_serves_every_leaf_its_own_triangles() {
        // A sheet and 1003 scattered triangles (the last block of 8 is short; leaves with
        // shared vertices and without, see `LAYOUTS`). Two threads walk every
        // leaf three times each in scattered orders through one cache, so blocks are found
        // unprepared, prepared by the other thread, and ready; every leaf's triangles are the
        // bits of its positions prepared for the same origin one by one (lane l of a block
        // is lane l's own arithmetic), and so are a leaf's prepared as met. The cache is then
        // kept and taken again for another origin: no triangle of the first frame is served.
        let tris = with_sheet(scattered(1003, 0x2545f4914f6cdd1d, 0.1));
        for (leaf_max, shared) in LAYOUTS {
            let bvh = Bvh::build_with(&tris, leaf_max, shared);
            let leaves: Vec<(usize, usize)> = (bvh.wide.iter().flat_map(|n| n.leaves()))
                .map(|(first, count)| (first, first + count))
                .collect();
            assert_eq!(leaves.iter().map(|(a, b)| b - a).sum::<usize>(), tris.len());
            assert!(leaves.iter().any(|&(a, b)| a / BLOCK != (b - 1) / BLOCK));
            let bits = |t: &OriginTriangle| format!("{t:?}");
            let pool = super::super::prepared::CachePool::default();
            for origin in [[5.1, 4.2, 15.0], [-3.0, 5.5, 4.75]] {
                let cache = pool.take(bvh.len(), origin);
                let want: Vec<OriginTriangle> = (0..bvh.len())
                    .map(|i| {
                        let mut block = OriginBlock::default();
                        bvh.prepare_block::<f32x8>(i, i + 1, origin, &mut block);
                        block.get(0)
                    })
                    .collect();
                let check = |order: usize| {
                    for k in 0..3 * leaves.len() {
                        let (first, end) = leaves[(k * order) % leaves.len()];
                        let mut scratch = None;
                        let prepared = Prepared::Once(&cache);
                        let tris =
                            bvh.leaf_triangles::<f32x8>(prepared, first, end, origin, &mut scratch);
                        assert_eq!(tris.len(), end - first);
                        let mut scratch = None;
                        let met = bvh.leaf_triangles::<f32x8>(
                            Prepared::AsMet,
                            first,
                            end,
                            origin,
                            &mut scratch,
                        );
                        assert_eq!(met.len(), end - first);
                        for i in 0..tris.len() {
                            let want = bits(&want[first + i]);
                            assert_eq!(bits(&tris.get(i)), want, "leaf at {first}");
                            assert_eq!(bits(&met.get(i)), want, "leaf at {first}, as met");
                            assert_eq!(tris.get(i).prim, bvh.prims[first + i]);
                        }
                    }
                };
                // (Strides: primes above the leaf count, so each visits every leaf.)
                rayon::join(|| check(1009), || check(1013));
                pool.give(cache);
            }
        }
    }

    /// 16 rays at once (the AVX-512 tile loop's packets): every lane the 16-lane walk decides
    /// is the whole list's nearest, from every kind of preparation, for an origin the slab
    /// test trusts and one it does not (every triangle offered). The rays diverge, so most
    /// leaves are reached by one lane: lanes 8–15 go through the one-lane pass too.
    #[test]
    fn sixteen_lane_packets_decide_as_the_whole_list() {
        use crate::math::lanes::{Avx16, LaneOps};
        use crate::math::simd::{detected, SimdLevel};
        if detected() < SimdLevel::Avx512 {
            return; // no 16-lane build on this CPU
        }
        #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma")]
        fn walk16(
            bvh: &Bvh,
            o: [f32; 3],
            prepared: Prepared<'_>,
            d: &[[f32; 16]; 3],
            prim: &mut [u32; 16],
        ) -> u32 {
            let d = each3(|k| Avx16::load(&d[k]));
            let dm = crate::accel::packet::max_component_in(&d);
            bvh.closest_packet_in(o, prepared, d, dm, prim)
        }
        let tris = with_sheet(scattered(1003, 0x2545f4914f6cdd1d, 0.3));
        for (leaf_max, shared) in LAYOUTS {
            let bvh = Bvh::build_with(&tris, leaf_max, shared);
            let (vertices, prims) = bvh.triangles();
            let pool = super::super::prepared::CachePool::default();
            for o in [[5.1, 4.2, -15.0], [1e-20, 5.0, -4.0]] {
                let list = OriginTriangles::from_parts(vertices, prims, o);
                // Lane l towards triangle 61·l's centroid, odd lanes near its first vertex.
                let d: [[f32; 16]; 3] = [0, 1, 2].map(|k| {
                    std::array::from_fn(|l| {
                        let v = &tris[61 * l].0;
                        let aim = match l % 2 {
                            0 => (v[0][k] + v[1][k] + v[2][k]) / 3.0,
                            _ => 0.9 * v[0][k] + 0.05 * (v[1][k] + v[2][k]),
                        };
                        aim - o[k]
                    })
                });
                let cache = pool.take(bvh.len(), o);
                for prepared in [
                    Prepared::All(&list),
                    Prepared::Once(&cache),
                    Prepared::AsMet,
                ] {
                    let mut found = [0u32; 16];
                    // SAFETY: the CPU has AVX-512 F, VL, BW, DQ and CD (checked above).
                    #[allow(unsafe_code)]
                    let ambiguous = unsafe { walk16(&bvh, o, prepared, &d, &mut found) };
                    let mut decided = 0;
                    for half in 0..2 {
                        let d8: [f32x8; 3] =
                            each3(|k| f32x8::from(std::array::from_fn(|l| d[k][8 * half + l])));
                        let dm = crate::accel::packet::max_component(&d8);
                        let whole = crate::accel::packet::closest(&list.tris, &d8, dm);
                        for l in 0..8 {
                            let lane = 8 * half + l;
                            if (ambiguous >> lane | whole.ambiguous >> l) & 1 == 0 {
                                let got = prims.get(found[lane] as usize).copied();
                                let want = (whole.prim[l] != u32::MAX).then_some(whole.prim[l]);
                                assert_eq!(got, want, "origin {o:?}, lane {lane}");
                                decided += 1;
                            }
                        }
                    }
                    assert!(decided >= 12, "only {decided} lanes decided");
                }
                pool.give(cache);
            }
        }
    }
}
