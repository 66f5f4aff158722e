//! The binned-SAH build of the binary tree (16 bins along the widest axis of the items'
//! centres, or along all three; subtrees split across threads), and the hierarchy made from
//! it: apart from the walks, which never see the binary tree.

use super::leaf_vertices::LeafVertices;
use super::node::{Aabb, Node, MAX_ITEMS, STACK};
use super::slabs::boxes_tame;
use super::widen::widen;
use super::{leaf_max, Bvh, DENSE_MESH, MAX_LEAF, SMALL_LEAF};
use crate::accel::IndexedTriangle;
use ::wide::f32x4;
use rayon::prelude::*;

/// Levels of binned-SAH splits at most; deeper, sets are split by count (see `split`).
const SAH_DEPTH: usize = 36;

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

/// Items (or, in the collapse, binary nodes: about as many) a subtree must hold for its
/// halves to be built (and collapsed) on two threads: at least [`PARALLEL_MIN`], and n/32 of
/// `n` in all (enough subtrees for the threads, each large enough to pay for a task).
fn parallel_min(n: usize) -> usize {
    PARALLEL_MIN.max(n / 32)
}

/// The binary tree over `refs` (depth first), and the items in its leaves' order.
fn binary_over(mut refs: Vec<Ref>, plan: Plan) -> (Vec<Node>, Vec<u32>) {
    let bounds = Bounds::of_par(&refs);
    let nodes = build_node(&mut refs, &bounds, 0, plan, 0);
    (nodes, refs.par_iter().map(Ref::index).collect())
}

/// The binary tree over triangles with leaves of at most `leaf_max`, and their indices in
/// its leaves' order.
pub(super) fn binary(
    tris: &[IndexedTriangle],
    leaf_max: usize,
    all_axes: bool,
) -> (Vec<Node>, Vec<u32>) {
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

/// `v` with its fourth lane 0, by a mask: the low corner's fourth lane is an index's bits, a
/// subnormal f32 below 2²³, and Intel cores take a microcode assist (~100 cycles) for each
/// multiply or add that reads one. Binning the index lane with the coordinates made the 1M
/// mesh's build 4.8× slower on an Intel Xeon than on an AMD EPYC (docs/performance.md).
#[inline(always)]
fn xyz(v: f32x4) -> f32x4 {
    let all = f32::from_bits(u32::MAX);
    v & f32x4::new([all, all, all, 0.0])
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

    /// The box's centre (halves first: no overflow), its fourth lane 0.
    #[inline(always)]
    fn centre(&self) -> f32x4 {
        xyz(self.lo) * 0.5 + self.hi * 0.5
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
    pub(super) fn build_with(
        tris: &[IndexedTriangle],
        leaf_max: usize,
        leaf_vertices: bool,
    ) -> Self {
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
        assert!(tris.len() <= MAX_ITEMS, "{} triangles", tris.len());
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
        let wide = widen(nodes, STACK, parallel_min(prims.len()));
        Self {
            tame: boxes_tame(&wide),
            bounds: nodes[0].bounds,
            wide,
            tris,
            prims,
            leaf_vertices: None,
        }
    }

    /// A hierarchy over boxes (the instances' world boxes) instead of triangles: it holds no
    /// triangles, and its leaves' items are the boxes' indices ([`Bvh::triangles`]'s second
    /// part).
    pub(crate) fn build_over_boxes(boxes: &[([f32; 3], [f32; 3])]) -> Self {
        if boxes.is_empty() {
            return Self::default();
        }
        assert!(boxes.len() <= MAX_ITEMS, "{} boxes", boxes.len());
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
    let extent = (bounds.hi - xyz(bounds.lo)).to_array();
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
        let d = ((b.hi - xyz(b.lo)) * unit).to_array();
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

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    /// The arithmetic of binning never reads the index lane: an index's bits are a subnormal
    /// f32, which costs Intel cores a microcode assist per operation.
    fn binning_arithmetic_never_reads_the_index_lane() {
        let b = Aabb {
            lo: [-1.0, 2.0, 3.0],
            hi: [1.0, 4.0, 7.0],
        };
        for i in [1, 12_345, (1 << 23) - 1, MAX_ITEMS as u32] {
            let r = Ref::new(&b, i);
            assert_eq!(r.index(), i);
            assert!(r.lo.as_array()[3].is_subnormal() == (i < 1 << 23));
            assert_eq!(r.centre().to_array(), [0.0, 3.0, 5.0, 0.0]);
            let bounds = Bounds::of(&[r, r]);
            assert_eq!(xyz(bounds.boxes.lo).to_array(), [-1.0, 2.0, 3.0, 0.0]);
            assert_eq!(bounds.centres.lo.to_array(), [0.0, 3.0, 5.0, 0.0]);
        }
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[(
        "binning_arithmetic_never_reads_the_index_lane",
        binning_arithmetic_never_reads_the_index_lane,
    )];
}
