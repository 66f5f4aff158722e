//! The hierarchy's nodes, 8 wide: every walk (per ray, packets of 8 rays, instances) tests a
//! node's up to 8 children's boxes at once.
//!
//! A wide node holds its children's boxes by axis (`lo[k][child]`), so one ray tests all 8
//! with a few 8-lane operations ([`RaySlabs`]), and a packet tests them lane by lane from
//! shared differences. A coherent packet (every lane's direction has the same sign per axis:
//! a camera block, a light's shadow block away from the view axis) first tests the 8 as an
//! interval ([`WideSlabs`]): per axis, fl((b − o)·1/dₖ) is monotone in 1/dₖ, so its least
//! (and, on the far side, greatest) value over the lanes is the one at the lanes' least or
//! greatest 1/dₖ. The interval test computes, per axis, exactly the extreme of the per-lane
//! test's own values, and passes whenever some lane's per-lane test passes. Every triangle a
//! lane can hit before its limit is then still offered to it, and each lane's answer stays
//! the one of the whole list (module docs of `bvh`). The children the interval test lets
//! through are then tested per lane (from the same differences): the interval alone let 4.3
//! times as many leaves through on the 1M-triangle mesh at 640×360.
//!
//! The wide nodes are made by collapsing the binned-SAH binary tree: each wide node takes the
//! largest interior child's two children in its place until it has 8 ([`widen`]). A subtree
//! of at most 4 triangles becomes one leaf (its triangles are contiguous), or of at most 8 in
//! a dense mesh (`bvh::leaf_max`). On the 1M-triangle mesh: 70 MB and 17.9 Mrays/s (640×360
//! flat, 2 threads), against 92 MB and 15.2 Mrays/s merging subtrees of at most 3
//! (interleaved runs) and 102 MB merging none; 4% more instructions than merging none, but
//! fewer cache misses. Leaves of up to 8 took it to 55 MB and its frame 20% faster at
//! 640×360, 11% at 1280×720 (2 threads, 7 interleaved rounds), Igea's (269k triangles) 19%
//! and 6%, where the bunny's (69k) 640×360 frame was 14% slower with them, the bunny
//! field's 13% (6% with its meshes' leaves prepared 8 at a time).
//! A walk's stack holds at most [`STACK`] entries: a node stops taking grandchildren where
//! the deepest path below could need more.
//!
//! Children are kept in order of entry distance on the walk's stack, nearest on top; a popped
//! child is skipped when its distance is beyond every live lane's limit (for one ray: the
//! culling margin of `bvh`'s module docs). For one ray this is the binary walk's test again:
//! the entry distance does not change, only the limit shrinks.

use super::TopNode;
use super::{
    box_safe, enter_f64, far_slack, slab_safe, Aabb, Bvh, Leaves, Node, PacketSlabs, MAX_LEAF,
};
use crate::accel::instances::PacketSink;
use crate::geometry::Ray;
use crate::math::lanes::{f32x8, LaneOps, Lanes};
use crate::math::Real;
use rayon::prelude::*;

/// Children per wide node.
const WIDTH: usize = 8;
/// A child reference with this bit is a leaf: triangle count − 1 in bits 28–30, the first
/// triangle's position in bits 0–27.
const LEAF: u32 = 1 << 31;
const FIRST_BITS: u32 = 28;
/// Most triangles (or instance boxes) a hierarchy holds: a leaf's first one must fit its
/// reference. The loaders and the scene format keep within it.
pub const MAX_ITEMS: usize = (1 << FIRST_BITS) - 1;
/// An unused child slot (its box is empty: no ray enters it). Unused slots come last.
const NONE: u32 = u32::MAX;
/// Stack entries a walk holds at most ([`widen`] keeps every tree within it).
pub(super) const STACK: usize = 128;

/// Up to 8 children: their boxes by axis and child, and what each is (a wide node's index,
/// a leaf, or [`NONE`]). 256 bytes, four cache lines.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct WideNode {
    lo: [[f32; WIDTH]; 3],
    hi: [[f32; WIDTH]; 3],
    child: [u32; WIDTH],
}

impl WideNode {
    const EMPTY: WideNode = WideNode {
        lo: [[f32::INFINITY; WIDTH]; 3],
        hi: [[f32::NEG_INFINITY; WIDTH]; 3],
        child: [NONE; WIDTH],
    };

    /// Child `c`'s box.
    #[inline(always)]
    fn bounds(&self, c: usize) -> Aabb {
        Aabb {
            lo: [self.lo[0][c], self.lo[1][c], self.lo[2][c]],
            hi: [self.hi[0][c], self.hi[1][c], self.hi[2][c]],
        }
    }

    /// The leaf children, as (first triangle, count).
    pub(super) fn leaves(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (self.child.iter())
            .filter(|&&r| r != NONE && r & LEAF != 0)
            .map(|&r| leaf_range(r))
    }

    /// Every coordinate of the children's boxes.
    /// (An unused child's are infinite.)
    pub(super) fn coordinates(&self) -> impl Iterator<Item = f32> + '_ {
        self.lo.iter().chain(&self.hi).flatten().copied()
    }
}

/// A leaf reference's first triangle and count.
#[inline(always)]
fn leaf_range(r: u32) -> (usize, usize) {
    let first = r & ((1 << FIRST_BITS) - 1);
    let count = ((r >> FIRST_BITS) & 7) + 1;
    (first as usize, count as usize)
}

/// A leaf's child reference.
fn leaf_ref(first: u32, count: u32) -> u32 {
    debug_assert!((1..=MAX_LEAF as u32).contains(&count) && (first as usize) <= MAX_ITEMS);
    LEAF | (count - 1) << FIRST_BITS | first
}

/// The wide nodes over the binary tree `nodes` (depth first, as the build makes it), root
/// first, children after their parents, such that no walk needs more than `stack` entries
/// (`stack` must exceed the binary tree's height, which the build keeps below 70). Subtrees
/// of at least `parallel_min` binary nodes collapse their children's subtrees on several
/// threads.
pub(super) fn widen(nodes: &[Node], stack: usize, parallel_min: usize) -> Vec<WideNode> {
    if nodes.is_empty() {
        return Vec::new();
    }
    assert!(
        usize::from(nodes[0].height) < stack,
        "a BVH of height {}",
        nodes[0].height
    );
    let collapse = Collapse {
        nodes,
        stack,
        parallel_min,
    };
    let root = Subtree {
        root: 0,
        end: nodes.len(),
    };
    collapse.subtree(root, 0)
}

/// A binary node and the end of its subtree in the depth-first list.
#[derive(Clone, Copy)]
struct Subtree {
    root: usize,
    end: usize,
}

impl Subtree {
    /// Its two children's subtrees (it must be interior).
    fn halves(self, nodes: &[Node]) -> [Subtree; 2] {
        let [a, b] = Node::children(nodes, self.root);
        [
            Subtree { root: a, end: b },
            Subtree {
                root: b,
                end: self.end,
            },
        ]
    }
}

/// The binary tree with what [`widen`] needs.
struct Collapse<'a> {
    nodes: &'a [Node],
    stack: usize,
    parallel_min: usize,
}

impl Collapse<'_> {
    /// Whether binary node `k` is interior (it holds more than the build's `leaf_max` items).
    fn interior(&self, k: usize) -> bool {
        self.nodes[k].count == 0
    }

    /// The children of the wide node made from binary subtree `root`, walked with `above`
    /// entries below it: its children, then the largest interior one's in its place, up to
    /// 8 (in an array: one allocation per wide node cost the build as many small ones).
    fn children(&self, root: Subtree, above: usize) -> ([Subtree; WIDTH], usize) {
        let mut kids = [root; WIDTH];
        let mut len = 1;
        if self.interior(root.root) {
            [kids[0], kids[1]] = root.halves(self.nodes);
            len = 2;
        }
        let h = |k: Subtree| usize::from(self.nodes[k.root].height);
        let mut area = [0.0f64; WIDTH];
        for slot in 0..len {
            area[slot] = self.nodes[kids[slot].root].bounds.half_area();
        }
        while len < WIDTH {
            let largest = (0..len)
                .filter(|&slot| self.interior(kids[slot].root))
                .max_by(|&a, &b| area[a].total_cmp(&area[b]));
            let Some(slot) = largest else { break };
            // Walking this node pushes `len` children; below each, a walk through nodes of
            // two children pushes at most one entry a level. Expand only while that fits.
            let others = (0..len).filter(|&s| s != slot).map(|s| h(kids[s])).max();
            let deepest = others.unwrap_or(0).max(h(kids[slot]) - 1);
            if above + len + 1 + deepest > self.stack {
                break;
            }
            [kids[slot], kids[len]] = kids[slot].halves(self.nodes);
            area[slot] = self.nodes[kids[slot].root].bounds.half_area();
            area[len] = self.nodes[kids[len].root].bounds.half_area();
            len += 1;
        }
        debug_assert!(above + len <= self.stack);
        (kids, len)
    }

    /// The wide node over `kids`, with their boxes and leaves (interior children: [`NONE`],
    /// to be set).
    fn wide_node(&self, kids: &[Subtree]) -> WideNode {
        let mut w = WideNode::EMPTY;
        for (c, k) in kids.iter().enumerate() {
            let n = &self.nodes[k.root];
            for a in 0..3 {
                w.lo[a][c] = n.bounds.lo[a];
                w.hi[a][c] = n.bounds.hi[a];
            }
            if n.count > 0 {
                w.child[c] = leaf_ref(n.offset, u32::from(n.count));
            }
        }
        w
    }

    /// The wide nodes of `root`'s subtree (walked with `above` entries below it), its root
    /// first, child references counted from there.
    fn subtree(&self, root: Subtree, above: usize) -> Vec<WideNode> {
        if root.end - root.root < self.parallel_min {
            return self.subtree_serial(root, above);
        }
        let (kids, len) = self.children(root, above);
        let kids = &kids[..len];
        let mut w = self.wide_node(kids);
        let inner: Vec<(usize, Subtree)> = (kids.iter().enumerate())
            .filter(|&(_, k)| self.interior(k.root))
            .map(|(c, &k)| (c, k))
            .collect();
        let parts: Vec<Vec<WideNode>> = inner
            .par_iter()
            .map(|&(_, k)| self.subtree(k, above + len - 1))
            .collect();
        let mut out = Vec::with_capacity(1 + parts.iter().map(Vec::len).sum::<usize>());
        out.push(w);
        for (&(c, _), part) in inner.iter().zip(parts) {
            let base = out.len() as u32;
            w.child[c] = base;
            out.extend(part.into_iter().map(|mut n| {
                for r in &mut n.child {
                    if *r & LEAF == 0 {
                        *r += base;
                    }
                }
                n
            }));
        }
        out[0] = w;
        out
    }

    /// [`Collapse::subtree`] on one thread, depth first from the root.
    fn subtree_serial(&self, root: Subtree, above: usize) -> Vec<WideNode> {
        // A guess with room: the 1M mesh has one wide node per 6.2 binary ones.
        let mut wide = Vec::with_capacity((root.end - root.root) / 3 + 1);
        wide.push(WideNode::EMPTY);
        // (binary subtree, wide slot to fill, stack entries left below it while it is walked)
        let mut todo = vec![(root, 0usize, above)];
        while let Some((root, at, above)) = todo.pop() {
            let (kids, len) = self.children(root, above);
            wide[at] = self.wide_node(&kids[..len]);
            for (c, k) in kids[..len].iter().enumerate() {
                if self.interior(k.root) {
                    wide[at].child[c] = wide.len() as u32;
                    todo.push((*k, wide.len(), above + len - 1));
                    wide.push(WideNode::EMPTY);
                }
            }
        }
        wide
    }
}

/// A walk's stack: child references with their entry distances, nearest on top. (1.1 KB:
/// made once per packet and handed to its walks, as a new one per walk is zeroed each time.)
/// Its height is the walk's own (`top`, a local): kept here, it went through memory, a store
/// and a reload chained from each push and pop to the next.
pub(crate) struct WideStack {
    refs: [u32; STACK],
    dists: [f32; STACK],
    /// A packet walk's lanes that enter each entry's box (bit l for lane l).
    lanes: [u16; STACK],
}

impl WideStack {
    #[inline(always)]
    pub(crate) fn new() -> Self {
        Self {
            refs: [0; STACK],
            dists: [0.0; STACK],
            lanes: [0; STACK],
        }
    }

    /// Pushes the children of `n` in `hits` (distances `t0`, entered by `lanes`) onto the
    /// `*top` entries, farthest first.
    #[inline(always)]
    fn push(
        &mut self,
        top: &mut usize,
        n: &WideNode,
        mut hits: u32,
        t0: &[f32; WIDTH],
        lanes: u32,
    ) {
        let base = *top;
        while hits != 0 {
            let c = hits.trailing_zeros() as usize;
            hits &= hits - 1;
            self.insert(base, top, n.child[c], t0[c], lanes);
        }
    }

    /// Inserts `r` at distance `t` (entered by `lanes`) among the entries `base..*top`, kept
    /// farthest first.
    #[inline(always)]
    fn insert(&mut self, base: usize, top: &mut usize, r: u32, t: f32, lanes: u32) {
        let mut at = *top;
        while at > base && self.dists[at - 1] < t {
            self.refs[at] = self.refs[at - 1];
            self.dists[at] = self.dists[at - 1];
            self.lanes[at] = self.lanes[at - 1];
            at -= 1;
        }
        self.refs[at] = r;
        self.dists[at] = t;
        self.lanes[at] = lanes as u16;
        *top += 1;
    }

    /// The lanes of entry `at` (the one [`WideStack::pop_above`] returned last, at the
    /// height it left).
    #[inline(always)]
    fn lanes_at(&self, at: usize) -> u32 {
        self.lanes[at] as u32
    }

    /// The nearest entry of `base..*top` whose distance is within `limit` ([`NONE`]: none),
    /// the entries above it taken off with it.
    #[inline(always)]
    fn pop_above(&self, base: usize, top: &mut usize, limit: f32) -> u32 {
        while *top > base {
            *top -= 1;
            if self.dists[*top] <= limit {
                return self.refs[*top];
            }
        }
        NONE
    }

    /// The entry [`WideStack::pop_above`] would look at next, if any.
    #[inline(always)]
    fn top_above(&self, base: usize, top: usize) -> Option<u32> {
        (top > base).then(|| self.refs[top - 1])
    }
}

/// One ray set up for the f32 slab test against a wide node's 8 boxes (the test of
/// `Bvh::traverse`, 8 boxes at once), every box widened by `pad`.
struct RaySlabs {
    o: [f32; 3],
    inv: [f32; 3],
    near_hi: [bool; 3],
    tmin: f32,
    pad: f32,
}

impl RaySlabs {
    /// The children of `n` the ray enters before `limit`, and its entry distances.
    #[inline(always)]
    fn enter(&self, n: &WideNode, limit: f32) -> (u32, [f32; WIDTH]) {
        let slack = f32x8::splat(1.0 + 2.0 * f32::error_gamma(3));
        let pad = f32x8::splat(self.pad);
        let mut t0 = f32x8::splat(self.tmin);
        let mut t1 = f32x8::splat(limit);
        for k in 0..3 {
            let lo = f32x8::from(n.lo[k]) - pad;
            let hi = f32x8::from(n.hi[k]) + pad;
            let (near, far) = match self.near_hi[k] {
                true => (hi, lo),
                false => (lo, hi),
            };
            let (o, inv) = (f32x8::splat(self.o[k]), f32x8::splat(self.inv[k]));
            // `max`/`min` ignore a NaN (0·∞ for a ray in a slab's plane): conservative.
            t0 = LaneOps::max(t0, (near - o) * inv);
            t1 = LaneOps::min(t1, (far - o) * inv * slack);
        }
        (t0.simd_le(t1).to_bitmask(), t0.to_array())
    }
}

/// How a packet walk tests a wide node's children.
pub(super) trait ChildTest<V> {
    /// Pushes onto `stack` (`top` entries high) the children of `n` some lane of `live` may
    /// enter before its `reach` (`limit`: the greatest over `live`), each at a distance no
    /// greater than those lanes' entries.
    fn push(
        &self,
        n: &WideNode,
        reach: V,
        live: u32,
        limit: f32,
        stack: &mut WideStack,
        top: &mut usize,
    );

    /// The packet's slabs, and the pad its boxes are widened by (`None`: not widened), for
    /// walks of one lane ([`Bvh::walk_lane`]).
    fn slabs(&self) -> (&PacketSlabs<V>, Option<f32>);
}

/// One lane of a [`PacketSlabs`]: its 1/dₖ, its far factors, and its bit.
pub(super) struct LaneSlabs {
    inv: [f32; 3],
    inv_far: [f32; 3],
    bit: u32,
}

impl LaneSlabs {
    #[inline(always)]
    fn of<V: LaneOps>(rays: &PacketSlabs<V>, lane: usize) -> Self {
        let (inv, far) = (&rays.inv, &rays.inv_far);
        Self {
            inv: [inv[0].lane(lane), inv[1].lane(lane), inv[2].lane(lane)],
            inv_far: [far[0].lane(lane), far[1].lane(lane), far[2].lane(lane)],
            bit: 1 << lane,
        }
    }
}

/// Pushes onto `stack` the children of `n` that lane `lane` of `rays` enters before
/// `reach`, every box widened by `pad` if any, at that lane's entry distances: the 8 children
/// at once, with the operations [`PacketSlabs::enter`] (and [`Sides::lanes`]) apply to that
/// lane, one child at a time, so the same children pass.
#[inline(always)]
fn push_lane<V: LaneOps>(
    (rays, pad): (&PacketSlabs<V>, Option<f32>),
    n: &WideNode,
    lane: &LaneSlabs,
    reach: f32,
    stack: &mut WideStack,
    top: &mut usize,
) {
    // The node's 8 children in the build's 8 lanes, whatever the packet's width.
    type C<V> = <V as LaneOps>::Eight;
    let mut t0 = C::<V>::zero();
    let mut t1 = C::<V>::splat(reach);
    #[allow(clippy::needless_range_loop)]
    for k in 0..3 {
        let (mut lo, mut hi) = (C::<V>::from_array(n.lo[k]), C::<V>::from_array(n.hi[k]));
        if let Some(pad) = pad {
            lo = lo - C::<V>::splat(pad);
            hi = hi + C::<V>::splat(pad);
        }
        let o = C::<V>::splat(rays.o[k]);
        let (lo, hi) = (lo - o, hi - o);
        let inv = lane.inv[k];
        // The lane's sign as `PacketSlabs::neg` has it (1/dₖ < 0).
        let (near, far) = match inv < 0.0 {
            true => (hi, lo),
            false => (lo, hi),
        };
        let tn = near * C::<V>::splat(inv);
        let tf = far * C::<V>::splat(lane.inv_far[k]);
        if rays.tame {
            t0 = t0.fast_max(tn);
            t1 = t1.fast_min(tf);
        } else {
            // As `PacketSlabs::enter`: a NaN (0·∞) constrains nothing.
            t0 = t0.max(tn);
            t1 = t1.min(tf);
        }
    }
    stack.push(
        top,
        n,
        t0.simd_le(t1).to_bitmask(),
        &t0.to_array(),
        lane.bit,
    );
}

/// Any packet: each used child tested lane by lane ([`PacketSlabs::enter`]), its box widened
/// by `pad`.
pub(super) struct LaneTest<'a, V> {
    pub(super) rays: &'a PacketSlabs<V>,
    pub(super) pad: f32,
}

impl<V: LaneOps> ChildTest<V> for LaneTest<'_, V> {
    #[inline(always)]
    fn push(
        &self,
        n: &WideNode,
        reach: V,
        live: u32,
        _: f32,
        stack: &mut WideStack,
        top: &mut usize,
    ) {
        let base = *top;
        for c in 0..WIDTH {
            if n.child[c] == NONE {
                break;
            }
            let b = n.bounds(c);
            let b = match self.pad == 0.0 {
                true => b,
                false => Aabb {
                    lo: b.lo.map(|x| x - self.pad),
                    hi: b.hi.map(|x| x + self.pad),
                },
            };
            let (m, t0) = self.rays.enter(&b, reach, live);
            if m != 0 {
                let entries = V::from_bitmask(m).bitselect(t0, V::splat(f32::INFINITY));
                // (No entry is NaN: `enter`'s t0 starts at 0 and grows by `max`.)
                let t = entries.reduce_min();
                stack.insert(base, top, n.child[c], t, m);
            }
        }
    }

    #[inline(always)]
    fn slabs(&self) -> (&PacketSlabs<V>, Option<f32>) {
        (self.rays, (self.pad != 0.0).then_some(self.pad))
    }
}

/// A coherent packet ([`PacketSlabs::coherent`]), boxes widened by a pad if `PADDED`: the
/// interval test over the lanes, then the lanes of each child that passes.
pub(super) struct IntervalTest<'a, V, const PADDED: bool> {
    rays: &'a PacketSlabs<V>,
    slabs: WideSlabs<PADDED>,
}

impl<'a, V: LaneOps, const PADDED: bool> IntervalTest<'a, V, PADDED> {
    /// Boxes widened by `pad` on every side (0 unless `PADDED`).
    #[inline(always)]
    pub(super) fn new(rays: &'a PacketSlabs<V>, near_hi: [bool; 3], pad: f32) -> Self {
        debug_assert!(PADDED || pad == 0.0);
        Self {
            rays,
            slabs: WideSlabs::new(rays, near_hi, pad),
        }
    }
}

impl<V: LaneOps, const PADDED: bool> ChildTest<V> for IntervalTest<'_, V, PADDED> {
    #[inline(always)]
    fn push(
        &self,
        n: &WideNode,
        reach: V,
        live: u32,
        limit: f32,
        stack: &mut WideStack,
        top: &mut usize,
    ) {
        let mut sides = Sides {
            near: [[0.0; WIDTH]; 3],
            far: [[0.0; WIDTH]; 3],
        };
        let (mut hits, t0) = self.slabs.enter::<V::Eight>(n, limit, &mut sides);
        let t0 = t0.to_array();
        let base = *top;
        while hits != 0 {
            let c = hits.trailing_zeros() as usize;
            hits &= hits - 1;
            let lanes = sides.lanes(self.rays, c, reach, live);
            if lanes != 0 {
                stack.insert(base, top, n.child[c], t0[c], lanes);
            }
        }
    }

    #[inline(always)]
    fn slabs(&self) -> (&PacketSlabs<V>, Option<f32>) {
        (self.rays, PADDED.then_some(self.slabs.pad))
    }
}

/// A packet set up for [`WideNode`]s: per axis, the near and far sides (shared by every
/// lane) and the lanes' least and greatest 1/dₖ (for the far side, enlarged as
/// [`PacketSlabs`] enlarges it).
struct WideSlabs<const PADDED: bool> {
    o: [f32; 3],
    near_hi: [bool; 3],
    /// Added to the boxes' high sides and taken from their low ones (if `PADDED`).
    pad: f32,
    inv: [[f32; 2]; 3],
    inv_far: [[f32; 2]; 3],
}

impl<const PADDED: bool> WideSlabs<PADDED> {
    #[inline(always)]
    fn new<V: LaneOps>(rays: &PacketSlabs<V>, near_hi: [bool; 3], pad: f32) -> Self {
        // (Coherent packets are tame: no 1/dₖ is NaN. Written out: as a closure it stayed a
        // call outside the AVX2 kernel, 4% of a field frame.)
        let i = &rays.inv;
        let inv = [
            [i[0].reduce_min(), i[0].reduce_max()],
            [i[1].reduce_min(), i[1].reduce_max()],
            [i[2].reduce_min(), i[2].reduce_max()],
        ];
        // fl(x·slack) is monotone in x: the far factors' extremes are the extremes' far
        // factors, rounded as `PacketSlabs` rounds them lane by lane.
        let slack = far_slack();
        let far = |k: usize| [inv[k][0] * slack, inv[k][1] * slack];
        Self {
            o: rays.o,
            near_hi,
            pad,
            inv,
            inv_far: [far(0), far(1), far(2)],
        }
    }

    /// The children of `n` some lane may enter before `limit`, their least entry distances
    /// over the lanes, and their near and far sides less the origin (`sides`).
    #[inline(always)]
    fn enter<V: Lanes>(&self, n: &WideNode, limit: f32, sides: &mut Sides) -> (u32, V) {
        let mut t0 = V::zero();
        let mut t1 = V::splat(limit);
        #[allow(clippy::needless_range_loop)]
        for k in 0..3 {
            let (near, far) = match self.near_hi[k] {
                true => (&n.hi[k], &n.lo[k]),
                false => (&n.lo[k], &n.hi[k]),
            };
            let (mut near, mut far) = (V::from_array(*near), V::from_array(*far));
            if PADDED {
                // As `LaneTest` widens a box: lo − pad, hi + pad.
                let pad = V::splat(self.pad);
                (near, far) = match self.near_hi[k] {
                    true => (near + pad, far - pad),
                    false => (near - pad, far + pad),
                };
            }
            let o = V::splat(self.o[k]);
            let a = near - o;
            let c = far - o;
            sides.near[k] = a.to_array();
            sides.far[k] = c.to_array();
            let [lo, hi] = self.inv[k];
            let [far_lo, far_hi] = self.inv_far[k];
            let tn = (a * V::splat(lo)).fast_min(a * V::splat(hi));
            let tf = (c * V::splat(far_lo)).fast_max(c * V::splat(far_hi));
            t0 = t0.fast_max(tn);
            t1 = t1.fast_min(tf);
        }
        (t0.simd_le(t1).to_bitmask(), t0)
    }
}

/// A wide node's children's near and far sides less the packet's origin, by axis and child
/// (as [`PacketSlabs::enter`] computes them for one box).
struct Sides {
    near: [[f32; WIDTH]; 3],
    far: [[f32; WIDTH]; 3],
}

impl Sides {
    /// [`PacketSlabs::enter`]'s lanes for child `c` (the same operations on the same values).
    #[inline(always)]
    fn lanes<V: LaneOps>(&self, rays: &PacketSlabs<V>, c: usize, reach: V, live: u32) -> u32 {
        let mut t0 = V::zero();
        let mut t1 = reach;
        #[allow(clippy::needless_range_loop)]
        for k in 0..3 {
            t0 = t0.fast_max(V::splat(self.near[k][c]) * rays.inv[k]);
            t1 = t1.fast_min(V::splat(self.far[k][c]) * rays.inv_far[k]);
        }
        t0.simd_le(t1).to_bitmask() & live
    }
}

/// The greatest of `limits` over the lanes of `live` (−∞ for none).
#[inline(always)]
fn widest<V: LaneOps>(limits: V, live: u32) -> f32 {
    // Branch-free: the dead lanes set to −∞, then the lanes' greatest (the filtered fold it
    // replaces was 6% of a field frame's instructions). No limit is NaN: limits are ∞ or a
    // finite hit's bound.
    V::from_bitmask(live)
        .bitselect(limits, V::splat(f32::NEG_INFINITY))
        .reduce_max()
}

impl Bvh {
    /// Walks the hierarchy with 8 rays from one origin: offers `sink` (through `leaves`)
    /// every leaf some live lane of `only` may reach before its limit, as `test` decides,
    /// nearer children first; the other lanes take no part. (No closures: everything here
    /// must inline into the caller's AVX2 build.)
    #[inline(always)]
    pub(super) fn walk_wide<
        V: LaneOps,
        S: PacketSink<V>,
        L: Leaves<V, S>,
        T: ChildTest<V>,
        const LONE: bool,
    >(
        &self,
        test: &T,
        sink: &mut S,
        leaves: &mut L,
        stack: &mut WideStack,
        only: u32,
    ) {
        let mut live = sink.live() & only;
        if self.wide.is_empty() || live == 0 {
            return;
        }
        if LONE && live.is_power_of_two() {
            return self.walk_lane(test, sink, leaves, (0, live), (stack, 0));
        }
        let mut reach = sink.limit();
        let mut limit = widest(reach, live);
        let mut top = 0;
        let mut node = 0usize;
        loop {
            let n = &self.wide[node];
            test.push(n, reach, live, limit, stack, &mut top);
            loop {
                if live == 0 {
                    return;
                }
                let r = stack.pop_above(0, &mut top, limit);
                if r == NONE {
                    return;
                }
                if let Some(next) = stack.top_above(0, top) {
                    self.prefetch(next);
                }
                let lanes = stack.lanes_at(top) & live;
                if r & LEAF == 0 {
                    if !(LONE && lanes.is_power_of_two()) {
                        node = r as usize;
                        break;
                    }
                    self.walk_lane(test, sink, leaves, (r as usize, lanes), (stack, top));
                } else {
                    let (first, count) = leaf_range(r);
                    leaves.visit(sink, first, count, lanes);
                }
                live = sink.live() & only;
                reach = sink.limit();
                limit = widest(reach, live);
            }
        }
    }

    /// Asks the CPU to bring in stack entry `r`'s data (a node's boxes, or a leaf's
    /// triangles) while the entry popped before it is worked on: a mesh whose hierarchy and
    /// triangles outgrow the caches waits on each node and leaf as the walk reaches it.
    #[inline(always)]
    fn prefetch(&self, r: u32) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            let spans: [(*const i8, usize); 2] = match r & LEAF == 0 {
                true => [
                    (
                        self.wide.as_ptr().wrapping_add(r as usize).cast(),
                        std::mem::size_of::<WideNode>(),
                    ),
                    (std::ptr::null(), 0),
                ],
                false => {
                    let (first, count) = leaf_range(r);
                    match &self.leaf_vertices {
                        Some(v) => v.spans(first, count),
                        None => [
                            (
                                self.tris.as_ptr().wrapping_add(first).cast(),
                                count * std::mem::size_of::<[[f32; 3]; 3]>(),
                            ),
                            (std::ptr::null(), 0),
                        ],
                    }
                }
            };
            for (p, bytes) in spans {
                // Every cache line the bytes touch: from the line of the first byte (a leaf's
                // triangles, 36 bytes each, seldom start on a line) to that of the last.
                let mut at = 0;
                let end = (p as usize % 64) + bytes;
                while at < end {
                    // SAFETY: a prefetch only hints the cache; it never reads or faults,
                    // whatever the address (and SSE is part of x86-64).
                    #[allow(unsafe_code)]
                    unsafe {
                        _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(at))
                    };
                    at += 64;
                }
            }
        }
    }

    /// [`Bvh::walk_wide`] below node `root`, which only lane `lane` (a one-bit mask) of the
    /// packet entered: its subtree for that lane alone, 8 boxes per test
    /// ([`push_lane`]), its leaves offered to that lane, until the lane is decided
    /// or the subtree is done. Uses `stack` above its first `base` entries and leaves those
    /// as they were.
    #[inline(always)]
    fn walk_lane<V: LaneOps, S: PacketSink<V>, L: Leaves<V, S>, T: ChildTest<V>>(
        &self,
        test: &T,
        sink: &mut S,
        leaves: &mut L,
        (root, lane): (usize, u32),
        (stack, base): (&mut WideStack, usize),
    ) {
        let at = lane.trailing_zeros() as usize;
        let packet = test.slabs();
        let slabs = LaneSlabs::of(packet.0, at);
        let mut top = base;
        let mut reach = sink.limit().lane(at);
        let mut node = root;
        loop {
            push_lane(packet, &self.wide[node], &slabs, reach, stack, &mut top);
            loop {
                let r = stack.pop_above(base, &mut top, reach);
                if r == NONE {
                    return;
                }
                if let Some(next) = stack.top_above(base, top) {
                    self.prefetch(next);
                }
                if r & LEAF == 0 {
                    node = r as usize;
                    break;
                }
                let (first, count) = leaf_range(r);
                leaves.visit(sink, first, count, lane);
                if sink.live() & lane == 0 {
                    return;
                }
                reach = sink.limit().lane(at);
            }
        }
    }

    /// Visits the leaves the ray may reach, nearer child first, every box widened by `pad`
    /// on each side (0 but for a mesh's hierarchy walked in its own frame by a ray carried
    /// there with rounding, see `accel::instances`). `leaf(first, count, t_far)` returns the
    /// new t_far and whether to stop.
    pub(crate) fn traverse(
        &self,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        pad: f32,
        mut leaf: impl FnMut(usize, usize, f32) -> (f32, bool),
    ) {
        if self.wide.is_empty() {
            return;
        }
        let in_f32 =
            self.tame && (ray.o.iter().chain(&ray.d)).all(|&x| slab_safe(x)) && box_safe(pad);
        let inv = ray.d.map(|c| 1.0 / c);
        let slabs = RaySlabs {
            o: ray.o,
            inv,
            near_hi: inv.map(|c| c < 0.0),
            tmin,
            pad,
        };
        // Only the f64 test needs these divisions.
        let inv64 = (!in_f32).then(|| ray.d.map(|c| 1.0 / f64::from(c)));
        let enter = |n: &WideNode, limit: f32| -> (u32, [f32; WIDTH]) {
            let Some(inv64) = &inv64 else {
                return slabs.enter(n, limit);
            };
            let mut hits = 0;
            let mut t = [f32::INFINITY; WIDTH];
            for c in (0..WIDTH).take_while(|&c| n.child[c] != NONE) {
                if let Some(t0) = enter_f64(&n.bounds(c), pad, ray, inv64, tmin, limit) {
                    hits |= 1 << c;
                    t[c] = t0;
                }
            }
            (hits, t)
        };
        let mut t_far = tmax;
        // Culling margin against the best hit so far (see the module docs of `bvh`).
        let cull = |t: f32| {
            if t < tmax {
                (t + t.abs() * (1.0 / 65536.0)).min(tmax)
            } else {
                tmax
            }
        };
        let mut stack = WideStack::new();
        let mut top = 0;
        let mut node = 0usize;
        loop {
            let n = &self.wide[node];
            let (hits, t0) = enter(n, cull(t_far));
            stack.push(&mut top, n, hits, &t0, 1);
            loop {
                let r = stack.pop_above(0, &mut top, cull(t_far));
                if r == NONE {
                    return;
                }
                if r & LEAF == 0 {
                    node = r as usize;
                    break;
                }
                let (first, count) = leaf_range(r);
                let stop;
                (t_far, stop) = leaf(first, count, t_far);
                if stop {
                    return;
                }
            }
        }
    }

    /// The hierarchy's nodes down to `depth` wide levels below the root, breadth first:
    /// the root (the box around everything), then children. Every triangle lies in the box
    /// of a node without children.
    pub(crate) fn top_levels(&self, depth: usize) -> Vec<TopNode> {
        let Some(bounds) = self.root_bounds() else {
            return Vec::new();
        };
        let mut out = vec![TopNode {
            bounds,
            children: None,
        }];
        // (position in `out`, its wide node)
        let mut level = vec![(0usize, 0usize)];
        for _ in 0..depth {
            let mut next = Vec::new();
            for (at, i) in level {
                let n = &self.wide[i];
                let first = out.len();
                for c in (0..WIDTH).take_while(|&c| n.child[c] != NONE) {
                    if n.child[c] & LEAF == 0 {
                        next.push((out.len(), n.child[c] as usize));
                    }
                    out.push(TopNode {
                        bounds: n.bounds(c),
                        children: None,
                    });
                }
                out[at].children = Some((first as u32, (out.len() - first) as u32));
            }
            level = next;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Aabb, PositionLeaves, SMALL_LEAF};
    use super::*;
    use crate::accel::packet::{OriginTriangles, PacketHits, PacketNearest};
    use crate::accel::prepared::Prepared;
    use crate::accel::IndexedTriangle;

    /// What a child reference names.
    enum Child {
        Node(usize),
        /// The first triangle's position and the count.
        Leaf(usize, usize),
        None,
    }

    fn child(r: u32) -> Child {
        match r {
            NONE => Child::None,
            r if r & LEAF == 0 => Child::Node(r as usize),
            r => {
                let (first, count) = leaf_range(r);
                Child::Leaf(first, count)
            }
        }
    }

    /// Every leaf of the wide nodes, as (first, count, its box), walking from the root.
    fn wide_leaves(wide: &[WideNode]) -> Vec<(usize, usize, Aabb)> {
        let mut out = Vec::new();
        let mut todo = vec![0usize];
        while let Some(i) = todo.pop() {
            for c in 0..WIDTH {
                let b = wide[i].bounds(c);
                match child(wide[i].child[c]) {
                    Child::None => assert_eq!(b, Aabb::EMPTY),
                    Child::Leaf(first, count) => out.push((first, count, b)),
                    Child::Node(j) => todo.push(j),
                }
            }
        }
        out
    }

    /// The most entries a walk of `wide` from node `i` holds, `above` held below it.
    fn stack_need(wide: &[WideNode], i: usize, above: usize) -> usize {
        let used = wide[i].child.iter().filter(|&&r| r != NONE).count();
        let below = (wide[i].child.iter()).filter_map(|&r| match child(r) {
            Child::Node(j) => Some(stack_need(wide, j, above + used - 1)),
            _ => None,
        });
        below.fold(above + used, usize::max)
    }

    #[test]
    fn wide_nodes_hold_the_binary_trees_leaves() {
        // 3000 scattered triangles, leaves of at most 4 (as a mesh of that size is built)
        // and of at most 8 (a dense mesh's): the binary tree's leaves are exactly its nodes
        // of at most that many triangles; the wide nodes' leaves are the binary leaves (same
        // ranges, same boxes), together every triangle once, and a node with an interior
        // child is full.
        let tris = super::super::tests::scattered(3000, 0x853c49e6748fea9b, 0.05);
        assert_eq!(
            Bvh::build(&tris).wide,
            Bvh::build_with(&tris, SMALL_LEAF, false).wide
        );
        for leaf_max in [SMALL_LEAF, MAX_LEAF] {
            leaves_of_at_most(&tris, leaf_max);
        }
    }

    fn leaves_of_at_most(tris: &[IndexedTriangle], leaf_max: usize) {
        let (nodes, _) = super::super::binary(tris, leaf_max, false);
        let bvh = Bvh::build_with(tris, leaf_max, false);
        assert_eq!(widen(&nodes, STACK, usize::MAX), bvh.wide);
        /// Node i's triangles as (first, count).
        fn range(nodes: &[Node], i: usize) -> (usize, usize) {
            match nodes[i].count {
                0 => {
                    let [a, b] = Node::children(nodes, i);
                    (range(nodes, a).0, range(nodes, a).1 + range(nodes, b).1)
                }
                count => (nodes[i].offset as usize, usize::from(count)),
            }
        }
        let mut binary = Vec::new();
        for (i, n) in nodes.iter().enumerate() {
            let (first, count) = range(&nodes, i);
            assert_eq!(
                n.count == 0,
                count > leaf_max,
                "node {i}: {count} triangles"
            );
            if n.count > 0 {
                binary.push((first, count, n.bounds));
            }
        }
        let sizes = binary.iter().map(|l| l.1);
        // Full leaves and short ones, many of each (4: 270 and 742; 8: 72 and 454).
        assert!(sizes.clone().filter(|&c| c == leaf_max).count() > 50);
        assert!(sizes.clone().filter(|&c| c < leaf_max).count() > 100);
        let mut wide = wide_leaves(&bvh.wide);
        let key = |l: &(usize, usize, Aabb)| l.0;
        binary.sort_by_key(key);
        wide.sort_by_key(key);
        assert_eq!(wide, binary);
        let mut next = 0;
        for &(first, count, _) in &wide {
            assert_eq!(first, next);
            next += count;
        }
        assert_eq!(next, 3000);
        // A node stops taking grandchildren only when all its children are leaves.
        for n in &bvh.wide {
            let interior = n.child.iter().any(|&r| r & LEAF == 0);
            let used = n.child.iter().filter(|&&r| r != NONE).count();
            assert!(used >= 2 && (!interior || used == WIDTH), "{:?}", n.child);
        }
        assert!(stack_need(&bvh.wide, 0, 0) <= STACK);
    }

    #[test]
    fn widening_keeps_walks_within_their_stack() {
        // A row of triangles at geometrically growing positions (the binary tree is a chain
        // about 60 deep) and 3000 scattered ones, widened for stacks of 128 down to just
        // above the binary height: every walk fits, every triangle is kept, and with room to
        // spare there is a node for every 6 triangles at most.
        let row: Vec<IndexedTriangle> = (0..120)
            .map(|i| {
                let x = 2f32.powi(i);
                ([[x, -1.0, 1.0], [x, 1.0, 1.0], [x, 0.0, -1.0]], i as u32)
            })
            .collect();
        let scattered = super::super::tests::scattered(3000, 0x853c49e6748fea9b, 0.05);
        for tris in [&row, &scattered] {
            let (nodes, _) = super::super::binary(tris, SMALL_LEAF, false);
            let height = super::super::tests::depth(&nodes, 0);
            assert_eq!(usize::from(nodes[0].height), height);
            for stack in [STACK, height + 8, height + 1] {
                let wide = widen(&nodes, stack, 64);
                let need = stack_need(&wide, 0, 0);
                assert!(need <= stack, "{need} entries for a stack of {stack}");
                let leaves = wide_leaves(&wide);
                assert_eq!(leaves.iter().map(|l| l.1).sum::<usize>(), tris.len());
                if stack == STACK {
                    // (256 bytes a node: about 40 bytes a triangle at most.)
                    let n = wide.len();
                    assert!(
                        n * 6 <= tris.len(),
                        "{n} nodes for {} triangles",
                        tris.len()
                    );
                }
            }
        }
    }

    /// The nearest hits of a walk with lone lanes walked alone (as an instance's mesh is),
    /// by the lanes of `only`.
    fn lone_walk<T: ChildTest<f32x8>>(
        bvh: &Bvh,
        test: &T,
        (d, dm): (&[f32x8; 3], f32),
        leaves: &mut PositionLeaves,
        stack: &mut WideStack,
        only: u32,
    ) -> PacketHits {
        let mut nearest = PacketNearest::<f32x8>::seeded(d, dm, None);
        bvh.walk_wide::<_, _, _, _, true>(test, &mut nearest, leaves, stack, only);
        nearest.finish()
    }

    #[test]
    fn the_wide_walks_decide_lanes_as_each_other_and_the_whole_list() {
        // 5000 scattered triangles of mixed sizes; packets from random origins, fanned
        // around a triangle's vertex or edge point (rays on shared edges and vertices) or a
        // random point, spreads from 1e-6 to 0.3 radians. Where the interval walk (coherent
        // packets), the lane-by-lane walk and the whole list decide a lane, they name the
        // same triangle, and the interval walk leaves about as few lanes undecided. Shadow
        // segments to the fan's points: every lane decided is the per-ray any-hit answer. With
        // boxes widened by a pad, both walks still give the whole list's answers.
        let mut tris = super::super::tests::scattered(4000, 0xda942042e4dd58b5, 0.05);
        tris.extend(super::super::tests::scattered(
            1000,
            0x2545f4914f6cdd1d,
            1.5,
        ));
        // And a sheet of shared vertices (see `LAYOUTS`).
        let tris = super::super::tests::with_sheet(tris);
        for (leaf_max, shared) in super::super::tests::LAYOUTS {
            let bvh = Bvh::build_with(&tris, leaf_max, shared);
            let (vertices, prims) = bvh.triangles();
            let mut x = 0x9e3779b97f4a7c15u64;
            let mut next = move || (crate::xorshift(&mut x) >> 40) as f32 / (1u64 << 24) as f32;
            let (mut coherent, mut decided, mut lane_decided) = (0, 0, 0);
            let (mut shadow_decided, mut only_decided) = (0, 0);
            for _ in 0..300 {
                let o = [0, 1, 2].map(|_| next() * 16.0 - 3.0);
                let v = vertices[(next() * vertices.len() as f32) as usize % vertices.len()];
                let centre = match (next() * 3.0) as u32 {
                    0 => v[0],
                    1 => [0, 1, 2].map(|k| (v[1][k] + v[2][k]) * 0.5),
                    _ => [0, 1, 2].map(|_| next() * 10.0),
                };
                let spread = 10f32.powf(-6.0 + 5.5 * next());
                let dirs: [[f32; 3]; 8] = std::array::from_fn(|l| {
                    let mut jitter = |s: f32| if l == 0 { 0.0 } else { s * (next() - 0.5) };
                    let d = [0, 1, 2].map(|k| centre[k] - o[k]);
                    let len = d.iter().map(|c| c * c).sum::<f32>().sqrt();
                    d.map(|c| c + jitter(spread * len))
                });
                let d: [f32x8; 3] = [0, 1, 2].map(|k| f32x8::from(dirs.map(|d| d[k])));
                let dm = crate::accel::packet::max_component(&d);
                let list = OriginTriangles::from_parts(vertices, prims, o);
                let whole = crate::accel::packet::closest(&list.tris, &d, dm);
                let rays = PacketSlabs::<f32x8>::new(o, &d, bvh.boxes_tame());
                coherent += usize::from(rays.coherent.is_some());
                for prepared in [Some(&list), None] {
                    // Shadow segments from o to the fan's points (t = 1 there).
                    let none = [u32::MAX; 8];
                    let shadow = bvh.blocked_packet(o, prepared, &d, dm, &none, 0xff);
                    for (l, dir) in dirs.iter().enumerate() {
                        let ray = crate::geometry::Ray::new(o, *dir);
                        let want = bvh.any_hit(
                            &ray,
                            crate::geometry::Method::Adaptive,
                            0.0,
                            1.0,
                            u32::MAX,
                        );
                        if shadow.unsure & (1 << l) == 0 {
                            assert_eq!(shadow.blocked & (1 << l) != 0, want, "shadow lane {l}");
                            shadow_decided += 1;
                        }
                    }
                    let found = bvh.closest_packet(o, prepared, &d, dm);
                    let mut nearest = PacketNearest::<f32x8>::seeded(&d, dm, None);
                    let mut leaves = PositionLeaves {
                        bvh: &bvh,
                        o,
                        prepared: Prepared::from_list(prepared),
                        scratch: None,
                    };
                    let lanes = LaneTest {
                        rays: &rays,
                        pad: 0.0,
                    };
                    let stack = &mut WideStack::new();
                    bvh.walk_wide::<_, _, _, _, false>(
                        &lanes,
                        &mut nearest,
                        &mut leaves,
                        stack,
                        !0,
                    );
                    let by_lane = nearest.finish();
                    // Boxes widened and lone lanes' subtrees walked for that lane alone (as an
                    // instance's mesh is walked): both tests again, and the interval test unpadded.
                    let pad = 1e-3;
                    let lanes = LaneTest { rays: &rays, pad };
                    let rays_d = (&d, dm);
                    let mut padded = vec![lone_walk(&bvh, &lanes, rays_d, &mut leaves, stack, !0)];
                    // Walks for some lanes only (one, or a few), the others left alone: an
                    // instance's mesh walked by the lanes that enter its world box.
                    let one = 1 << ((next() * 8.0) as u32 % 8);
                    let few = (next() * 256.0) as u32 & 0xff;
                    let only = [one, few].map(|part| {
                        let hits = lone_walk(&bvh, &lanes, rays_d, &mut leaves, stack, part);
                        (hits, part)
                    });
                    if let Some(near_hi) = rays.coherent {
                        let interval = IntervalTest::<_, true>::new(&rays, near_hi, pad);
                        padded.push(lone_walk(&bvh, &interval, rays_d, &mut leaves, stack, !0));
                        let interval = IntervalTest::<_, false>::new(&rays, near_hi, 0.0);
                        padded.push(lone_walk(&bvh, &interval, rays_d, &mut leaves, stack, !0));
                    }
                    for l in 0..8 {
                        let undecided = |h: &PacketHits| h.ambiguous & (1 << l) != 0;
                        decided += usize::from(!undecided(&found));
                        lane_decided += usize::from(!undecided(&by_lane));
                        if !undecided(&by_lane) && !undecided(&found) {
                            assert_eq!(found.prim[l], by_lane.prim[l], "lane {l}");
                        }
                        let walked = (only.iter())
                            .filter(|(_, part)| part & (1 << l) != 0)
                            .map(|(h, _)| h);
                        for h in [&found, &by_lane].into_iter().chain(&padded).chain(walked) {
                            if !undecided(h) && !undecided(&whole) {
                                let prim = prims.get(h.prim[l] as usize).copied();
                                assert_eq!(prim.unwrap_or(u32::MAX), whole.prim[l], "lane {l}");
                            }
                        }
                        for (h, part) in &only {
                            only_decided += usize::from(part & (1 << l) != 0 && !undecided(h));
                        }
                    }
                }
            }
            assert!(coherent > 200, "{coherent} coherent packets");
            assert!(
                decided * 100 >= lane_decided * 98,
                "{decided} vs {lane_decided}"
            );
            assert!(decided > 300 * 2 * 8 * 3 / 4, "{decided} decided");
            // One lane in each packet, and about half the lanes in another walk.
            assert!(
                only_decided > 300 * 2 * 5 * 3 / 4,
                "{only_decided} lanes decided walking some lanes only"
            );
            assert!(
                shadow_decided > 300 * 2 * 8 / 2,
                "{shadow_decided} shadow lanes decided"
            );
        }
    }

    #[test]
    fn a_single_leaf_tree_is_one_wide_node() {
        let tris = super::super::tests::scattered(2, 7, 0.5);
        let bvh = Bvh::build(&tris);
        assert_eq!(bvh.wide.len(), 1);
        assert_eq!(wide_leaves(&bvh.wide).len(), 1);
        assert_eq!(wide_leaves(&bvh.wide)[0].1, 2);
    }
}
