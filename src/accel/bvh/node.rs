//! The hierarchy's nodes, 8 wide: every walk (per ray, packets of 8 rays, instances) tests a
//! node's up to 8 children's boxes at once.
//!
//! This file holds the nodes (children's boxes by axis, child references), the binary
//! tree's nodes the build makes, the boxes, and the walks' stack of child references.
//!
//! Children are kept in order of entry distance on the walk's stack, nearest on top; a popped
//! child is skipped when its distance is beyond every live lane's limit (for one ray: the
//! culling margin of `bvh`'s module docs). For one ray this is the binary walk's test again:
//! the entry distance does not change, only the limit shrinks.

use super::{Bvh, MAX_LEAF};

/// Children per wide node.
pub(super) const WIDTH: usize = 8;
/// A child reference with this bit is a leaf: triangle count − 1 in bits 28–30, the first
/// triangle's position in bits 0–27.
pub(super) const LEAF: u32 = 1 << 31;
const FIRST_BITS: u32 = 28;
/// Most triangles (or instance boxes) a hierarchy holds: a leaf's first one must fit its
/// reference. The loaders and the scene format keep within it.
pub use crate::limits::MAX_HIERARCHY_ITEMS as MAX_ITEMS;
const _: () = assert!(MAX_ITEMS == (1 << FIRST_BITS) - 1);
/// An unused child slot (its box is empty: no ray enters it). Unused slots come last.
pub(super) const NONE: u32 = u32::MAX;
/// Stack entries a walk holds at most ([`widen`] keeps every tree within it).
///
/// [`widen`]: super::widen::widen
pub(super) const STACK: usize = 128;

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
    pub(super) fn side(&self, hi: bool) -> &[f32; 3] {
        match hi {
            true => &self.hi,
            false => &self.lo,
        }
    }

    pub(super) const EMPTY: Aabb = Aabb {
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

    pub(super) fn grow_point(&mut self, p: [f32; 3]) {
        self.grow(&Aabb { lo: p, hi: p });
    }

    /// In f64: products of f32 extents neither underflow nor overflow there (a box of
    /// subnormal size has area 0 in f32, and every split would look free).
    pub(super) fn half_area(&self) -> f64 {
        let d = [0, 1, 2].map(|k| (f64::from(self.hi[k]) - f64::from(self.lo[k])).max(0.0));
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }
}

/// A node of the binary tree the build makes (and [`widen`](super::widen::widen) collapses), in
/// depth-first order: a node, its first child's subtree, its second's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Node {
    pub(super) bounds: Aabb,
    /// Leaf: index of its first triangle; interior: the offset from this node to its second
    /// child (the first follows it).
    pub(super) offset: u32,
    /// Leaf: triangle count (1 to the build's `leaf_max`); interior: 0.
    pub(super) count: u16,
    /// Levels below (a leaf 0): what a walk through the subtree may push.
    pub(super) height: u16,
}

impl Node {
    /// An interior node's children.
    #[inline(always)]
    pub(super) fn children(nodes: &[Node], i: usize) -> [usize; 2] {
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

/// Up to 8 children: their boxes by axis and child, and what each is (a wide node's index,
/// a leaf, or [`NONE`]). 256 bytes, four cache lines.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct WideNode {
    pub(super) lo: [[f32; WIDTH]; 3],
    pub(super) hi: [[f32; WIDTH]; 3],
    pub(super) child: [u32; WIDTH],
}

impl WideNode {
    pub(super) const EMPTY: WideNode = WideNode {
        lo: [[f32::INFINITY; WIDTH]; 3],
        hi: [[f32::NEG_INFINITY; WIDTH]; 3],
        child: [NONE; WIDTH],
    };

    /// Child `c`'s box.
    #[inline(always)]
    pub(super) fn bounds(&self, c: usize) -> Aabb {
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
pub(super) fn leaf_range(r: u32) -> (usize, usize) {
    let first = r & ((1 << FIRST_BITS) - 1);
    let count = ((r >> FIRST_BITS) & 7) + 1;
    (first as usize, count as usize)
}

/// A leaf's child reference.
pub(super) fn leaf_ref(first: u32, count: u32) -> u32 {
    debug_assert!((1..=MAX_LEAF as u32).contains(&count) && (first as usize) <= MAX_ITEMS);
    LEAF | (count - 1) << FIRST_BITS | first
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
    pub(super) fn push(
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
    pub(super) fn insert(&mut self, base: usize, top: &mut usize, r: u32, t: f32, lanes: u32) {
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
    pub(super) fn lanes_at(&self, at: usize) -> u32 {
        self.lanes[at] as u32
    }

    /// The nearest entry of `base..*top` whose distance is within `limit` ([`NONE`]: none),
    /// the entries above it taken off with it.
    #[inline(always)]
    pub(super) fn pop_above(&self, base: usize, top: &mut usize, limit: f32) -> u32 {
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
    pub(super) fn top_above(&self, base: usize, top: usize) -> Option<u32> {
        (top > base).then(|| self.refs[top - 1])
    }
}

impl Bvh {
    /// Per wide node, the largest |coordinate| of its children's boxes: what a pad that
    /// grows with the coordinates needs there ([`Bvh::traverse_padded`]).
    pub(crate) fn node_extents(&self) -> Vec<f32> {
        let extent = |b: Aabb| (b.lo.iter().chain(&b.hi)).fold(0.0f32, |m, c| m.max(c.abs()));
        (self.wide.iter())
            .map(|n| {
                (0..WIDTH)
                    .take_while(|&c| n.child[c] != NONE)
                    .map(|c| extent(n.bounds(c)))
                    .fold(0.0f32, f32::max)
            })
            .collect()
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
