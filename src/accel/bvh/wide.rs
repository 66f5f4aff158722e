//! An 8-wide copy of the hierarchy's nodes for coherent packets (every lane's direction has
//! the same sign per axis: a camera block or a light's shadow block away from the view axis).
//!
//! A wide node holds up to 8 children's boxes by axis (`lo[k][child]`), so one packet tests
//! all 8 with a few 8-lane operations: the test is the binary walk's per-lane slab test taken
//! over the packet as an interval. Per axis, fl((b − o)·1/dₖ) is monotone in 1/dₖ, so its
//! least (and, on the far side, greatest) value over the lanes is the one at the lanes' least
//! or greatest 1/dₖ: the interval test computes, per axis, exactly the extreme of the
//! per-lane test's own values, and passes whenever some lane's per-lane test passes. Every
//! triangle a lane can hit before its limit is then still offered to it, and each lane's
//! answer stays the one of the whole list (module docs of `bvh`). The children the interval
//! test lets through are then tested per lane, as the binary walk tests its boxes (from the
//! same differences): the interval alone let 4.3 times as many leaves through on the
//! 1M-triangle mesh at 640×360 (callgrind, this test 9.6% fewer instructions there; +1.8% on
//! the bunny, where triangles are larger than a packet's footprint).
//!
//! Memory: wide nodes take about 40 bytes a triangle beside the binary nodes' 35 (which the
//! per-ray, incoherent-packet and instance walks still use), so only meshes of up to
//! [`MAX_TRIANGLES`] get them: the 1M-triangle mesh stays within 100 MB (81 MB; with wide
//! nodes 121 MB).
//!
//! The wide nodes are made by collapsing the binary tree (each wide node takes the largest
//! interior child's two children in its place until it has 8), so leaves are the binary
//! ones: the same triangle ranges, the frame's cache of prepared triangles serves both.

use super::{far_slack, Bvh, Leaves, NodePair, PacketSlabs};
use crate::accel::instances::PacketSink;
use crate::math::lanes::Lanes;
use crate::math::simd::each3;

/// Meshes of more triangles keep only the binary nodes (see the module docs).
pub(super) const MAX_TRIANGLES: usize = 1 << 19;

/// Children per wide node.
const WIDTH: usize = 8;
/// A child reference with this bit is a leaf: triangle count − 1 in bits 29–30, the first
/// triangle's position in bits 0–28.
const LEAF: u32 = 1 << 31;
const FIRST_BITS: u32 = 29;
const _: () = assert!(MAX_TRIANGLES < 1 << FIRST_BITS);
/// An unused child slot (its box is empty: no ray enters it).
const NONE: u32 = u32::MAX;
/// Stack entries a walk holds at most; a tree that could need more is not widened (the
/// bunny could need 41, Igea 49).
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

/// A leaf's child reference.
fn leaf_ref(first: u32, count: u32) -> u32 {
    debug_assert!((1..=4).contains(&count) && first < 1 << FIRST_BITS);
    LEAF | (count - 1) << FIRST_BITS | first
}

/// A leaf reference's first triangle and count.
#[inline(always)]
fn leaf_range(r: u32) -> (usize, usize) {
    let first = r & ((1 << FIRST_BITS) - 1);
    let count = ((r >> FIRST_BITS) & 3) + 1;
    (first as usize, count as usize)
}

/// The wide nodes over the binary `pairs` (root first) of a mesh of `triangles`, or none:
/// for more than [`MAX_TRIANGLES`], or where a path could need more than [`STACK`] entries.
pub(super) fn widen(pairs: &[NodePair], triangles: usize) -> Vec<WideNode> {
    let node = |i: usize| &pairs[i / 2].0[i % 2];
    if pairs.is_empty() || triangles > MAX_TRIANGLES {
        return Vec::new();
    }
    let mut wide: Vec<WideNode> = Vec::with_capacity(pairs.len() / 3 + 1);
    let empty = WideNode {
        lo: [[f32::INFINITY; WIDTH]; 3],
        hi: [[f32::NEG_INFINITY; WIDTH]; 3],
        child: [NONE; WIDTH],
    };
    // (binary node, wide slot to fill, stack entries needed above it)
    let mut todo = vec![(0usize, 0usize, 0usize)];
    wide.push(empty);
    let mut deepest = 0;
    while let Some((root, at, above)) = todo.pop() {
        // The node's children, then the largest interior one's in its place, up to 8 (in
        // an array: one allocation per wide node cost the build as many small ones).
        let mut kids = [0usize; WIDTH];
        let mut len = match node(root).count {
            0 => {
                kids[..2].copy_from_slice(&[0, 1].map(|j| node(root).offset as usize + j));
                2
            }
            _ => {
                kids[0] = root;
                1
            }
        };
        while len < WIDTH {
            let area = |k: usize| node(k).bounds.half_area();
            let largest = (0..len)
                .filter(|&slot| node(kids[slot]).count == 0)
                .max_by(|&a, &b| area(kids[a]).total_cmp(&area(kids[b])));
            let Some(slot) = largest else { break };
            let first = node(kids[slot]).offset as usize;
            kids[slot] = first;
            kids[len] = first + 1;
            len += 1;
        }
        let kids = &kids[..len];
        let below = above + kids.len() - 1;
        deepest = deepest.max(below);
        for (c, &k) in kids.iter().enumerate() {
            let n = node(k);
            for a in 0..3 {
                wide[at].lo[a][c] = n.bounds.lo[a];
                wide[at].hi[a][c] = n.bounds.hi[a];
            }
            wide[at].child[c] = match n.count {
                0 => {
                    let child = wide.len();
                    wide.push(empty);
                    todo.push((k, child, below));
                    child as u32
                }
                count => leaf_ref(n.offset, count),
            };
        }
    }
    match deepest < STACK {
        true => wide,
        false => Vec::new(),
    }
}

/// A packet set up for [`WideNode`]s: per axis, the near and far sides (shared by every
/// lane) and the lanes' least and greatest 1/dₖ (for the far side, enlarged as
/// [`PacketSlabs`] enlarges it).
struct WideSlabs {
    o: [f32; 3],
    near_hi: [bool; 3],
    inv: [[f32; 2]; 3],
    inv_far: [[f32; 2]; 3],
}

impl WideSlabs {
    #[inline(always)]
    fn new<V: Lanes>(rays: &PacketSlabs<V>, near_hi: [bool; 3]) -> Self {
        let inv = each3(|k| {
            let a = rays.inv[k].to_array();
            let lo = a.iter().fold(f32::INFINITY, |m, &x| m.min(x));
            let hi = a.iter().fold(f32::NEG_INFINITY, |m, &x| m.max(x));
            [lo, hi]
        });
        // fl(x·slack) is monotone in x: the far factors' extremes are the extremes' far
        // factors, rounded as `PacketSlabs` rounds them lane by lane.
        let slack = far_slack();
        Self {
            o: rays.o,
            near_hi,
            inv,
            inv_far: each3(|k| inv[k].map(|x| x * slack)),
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
            let o = V::splat(self.o[k]);
            let a = V::from_array(*near) - o;
            let c = V::from_array(*far) - o;
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
    fn lanes<V: Lanes>(&self, rays: &PacketSlabs<V>, c: usize, reach: V, live: u32) -> u32 {
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
fn widest<V: Lanes>(limits: V, live: u32) -> f32 {
    let a = limits.to_array();
    (0..8)
        .filter(|l| live & (1 << l) != 0)
        .fold(f32::NEG_INFINITY, |m, l| m.max(a[l]))
}

impl Bvh {
    /// [`Bvh::walk_packet`] over the wide nodes for a packet whose lanes share every axis's
    /// direction sign (`near_hi`), boxes unpadded: offers `sink` every leaf some live lane
    /// may reach before its limit, nearer children first.
    #[inline(always)]
    pub(super) fn walk_wide<V: Lanes, S: PacketSink<V>, L: Leaves<V, S>>(
        &self,
        rays: &PacketSlabs<V>,
        near_hi: [bool; 3],
        sink: &mut S,
        leaves: &mut L,
    ) {
        let slabs = WideSlabs::new(rays, near_hi);
        let mut live = sink.live();
        let mut reach = sink.limit();
        let mut limit = widest(reach, live);
        let mut refs = [0u32; STACK];
        let mut dists = [0f32; STACK];
        let mut sp = 0usize;
        let mut node = 0usize;
        let mut sides = Sides {
            near: [[0.0; WIDTH]; 3],
            far: [[0.0; WIDTH]; 3],
        };
        loop {
            let n = &self.wide[node];
            let (mut hits, t0) = slabs.enter::<V>(n, limit, &mut sides);
            let t0 = t0.to_array();
            // Onto the stack farthest first, so the nearest comes off next.
            let base = sp;
            while hits != 0 {
                let c = hits.trailing_zeros() as usize;
                hits &= hits - 1;
                let (r, t) = (n.child[c], t0[c]);
                if sides.lanes(rays, c, reach, live) == 0 {
                    continue;
                }
                let mut at = sp;
                while at > base && dists[at - 1] < t {
                    refs[at] = refs[at - 1];
                    dists[at] = dists[at - 1];
                    at -= 1;
                }
                refs[at] = r;
                dists[at] = t;
                sp += 1;
            }
            loop {
                if sp == 0 || live == 0 {
                    return;
                }
                sp -= 1;
                let (r, t) = (refs[sp], dists[sp]);
                if t > limit {
                    continue;
                }
                if r & LEAF == 0 {
                    node = r as usize;
                    break;
                }
                let (first, count) = leaf_range(r);
                leaves.visit(sink, first, count);
                live = sink.live();
                reach = sink.limit();
                limit = widest(reach, live);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::Aabb;
    use super::*;
    use crate::accel::packet::{OriginTriangles, PacketHits};
    use crate::math::lanes::f32x8;

    /// Every leaf of the wide nodes, as (first, count, its box), walking from the root.
    fn wide_leaves(wide: &[WideNode]) -> Vec<(usize, usize, Aabb)> {
        let mut out = Vec::new();
        let mut todo = vec![0usize];
        while let Some(i) = todo.pop() {
            for c in 0..WIDTH {
                let r = wide[i].child[c];
                let b = Aabb {
                    lo: [0, 1, 2].map(|k| wide[i].lo[k][c]),
                    hi: [0, 1, 2].map(|k| wide[i].hi[k][c]),
                };
                match r {
                    NONE => assert_eq!(b, Aabb::EMPTY),
                    r if r & LEAF != 0 => {
                        let (first, count) = leaf_range(r);
                        out.push((first, count, b));
                    }
                    r => todo.push(r as usize),
                }
            }
        }
        out
    }

    #[test]
    fn wide_nodes_hold_the_binary_leaves_with_their_boxes() {
        // 3000 scattered triangles: the wide nodes' leaves are exactly the binary tree's
        // (same ranges, same boxes), together every triangle once, and a node with an
        // interior child is full.
        let tris = super::super::tests::scattered(3000, 0x853c49e6748fea9b, 0.05);
        let bvh = Bvh::build(&tris);
        assert!(!bvh.wide.is_empty());
        assert_eq!(widen(&bvh.pairs, 3000), bvh.wide);
        assert!(widen(&bvh.pairs, MAX_TRIANGLES + 1).is_empty());
        let mut binary: Vec<(usize, usize, Aabb)> = (0..2 * bvh.pairs.len())
            .map(|i| *bvh.node(i))
            .filter(|n| n.count > 0)
            .map(|n| (n.offset as usize, n.count as usize, n.bounds))
            .collect();
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
    }

    #[test]
    fn the_wide_walk_decides_lanes_as_the_binary_walk_and_the_whole_list() {
        // 5000 scattered triangles of mixed sizes; packets from random origins, fanned
        // around a triangle's vertex or edge point (rays on shared edges and vertices) or a
        // random point, spreads from 1e-6 to 0.3 radians. Where the wide walk, the binary
        // walk and the whole list decide a lane, they name the same triangle, and the wide
        // walk leaves about as few lanes undecided as the binary one. Shadow segments to the
        // fan's points: every lane the wide walk decides is the per-ray any-hit query's
        // answer, and it decides about as many as the binary walk.
        let mut tris = super::super::tests::scattered(4000, 0xda942042e4dd58b5, 0.05);
        tris.extend(super::super::tests::scattered(
            1000,
            0x2545f4914f6cdd1d,
            1.5,
        ));
        for (i, t) in tris.iter_mut().enumerate() {
            t.1 = i as u32;
        }
        let bvh = Bvh::build(&tris);
        let mut binary = bvh.clone();
        binary.wide.clear();
        let (vertices, prims) = bvh.triangles();
        let mut x = 0x9e3779b97f4a7c15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 40) as f32 / (1u64 << 24) as f32
        };
        let (mut wide_walks, mut decided, mut binary_decided) = (0, 0, 0);
        let (mut shadow_decided, mut shadow_binary_decided) = (0, 0);
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
            wide_walks += usize::from(rays.coherent.is_some());
            for prepared in [Some(&list), None] {
                // Shadow segments from o to the fan's points (t = 1 there).
                let none = [u32::MAX; 8];
                let wide = bvh.blocked_packet(o, prepared, &d, dm, &none, 0xff);
                let bin = binary.blocked_packet(o, prepared, &d, dm, &none, 0xff);
                assert_eq!(wide.blocked & !bin.unsure & !bin.blocked, 0);
                assert_eq!(bin.blocked & !wide.unsure & !wide.blocked, 0);
                for (l, dir) in dirs.iter().enumerate() {
                    let ray = crate::geometry::Ray::new(o, *dir);
                    let want =
                        bvh.any_hit(&ray, crate::geometry::Method::Adaptive, 0.0, 1.0, u32::MAX);
                    if wide.unsure & (1 << l) == 0 {
                        assert_eq!(wide.blocked & (1 << l) != 0, want, "shadow lane {l}");
                        shadow_decided += 1;
                    }
                    shadow_binary_decided += usize::from(bin.unsure & (1 << l) == 0);
                }
                let wide = bvh.closest_packet(o, prepared, &d, dm);
                let bin = binary.closest_packet(o, prepared, &d, dm);
                for l in 0..8 {
                    let undecided = |h: &PacketHits| h.ambiguous & (1 << l) != 0;
                    decided += usize::from(!undecided(&wide));
                    binary_decided += usize::from(!undecided(&bin));
                    if undecided(&wide) {
                        continue;
                    }
                    if !undecided(&bin) {
                        assert_eq!(wide.prim[l], bin.prim[l], "lane {l}");
                    }
                    if !undecided(&whole) {
                        let prim = prims.get(wide.prim[l] as usize).copied();
                        assert_eq!(prim.unwrap_or(u32::MAX), whole.prim[l], "lane {l}");
                    }
                }
            }
        }
        assert!(wide_walks > 200, "{wide_walks} packets walked wide");
        assert!(
            decided * 100 >= binary_decided * 98,
            "{decided} vs {binary_decided}"
        );
        assert!(decided > 300 * 2 * 8 * 3 / 4, "{decided} decided");
        assert!(
            shadow_decided * 100 >= shadow_binary_decided * 98,
            "{shadow_decided} vs {shadow_binary_decided}"
        );
        assert!(
            shadow_decided > 300 * 2 * 8 / 2,
            "{shadow_decided} shadow lanes decided"
        );
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
