//! Unit tests of the wide nodes (the collapse keeps the binary leaves and the stack bound) and
//! of the packet walks over them (lane by lane, as an interval, lone lanes, padded boxes).

use super::super::child_test::{ChildTest, IntervalTest, LaneTest};
use super::super::leaves::PositionLeaves;
use super::super::node::{leaf_range, Node, WideNode, WideStack, LEAF, NONE, STACK, WIDTH};
use super::super::widen::widen;
use super::super::{Aabb, Bvh, PacketSlabs, MAX_LEAF, SMALL_LEAF};
use crate::accel::layout::Layout;
use crate::accel::packet::{OriginTriangles, PacketHits, PacketNearest};
use crate::accel::prepared::Prepared;
use crate::accel::IndexedTriangle;
use crate::math::lanes::f32x8;

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
        let mut next = move || (crate::math::xorshift(&mut x) >> 40) as f32 / (1u64 << 24) as f32;
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
                let shadow = bvh.any_packet(o, prepared, &d, dm, &none, 0xff);
                for (l, dir) in dirs.iter().enumerate() {
                    let ray = crate::geometry::Ray::new(o, *dir);
                    let want = bvh.any(&ray, crate::geometry::Method::Adaptive, 0.0, 1.0, u32::MAX);
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
                bvh.walk_wide::<_, _, _, _, false>(&lanes, &mut nearest, &mut leaves, stack, !0);
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

fn a_single_leaf_tree_is_one_wide_node() {
    let tris = super::super::tests::scattered(2, 7, 0.5);
    let bvh = Bvh::build(&tris);
    assert_eq!(bvh.wide.len(), 1);
    assert_eq!(wide_leaves(&bvh.wide).len(), 1);
    assert_eq!(wide_leaves(&bvh.wide)[0].1, 2);
}

/// This module's tests, for tests/unit.rs to run.
pub(crate) const TESTS: &[(&str, fn())] = &[
    (
        "wide_nodes_hold_the_binary_trees_leaves",
        wide_nodes_hold_the_binary_trees_leaves,
    ),
    (
        "widening_keeps_walks_within_their_stack",
        widening_keeps_walks_within_their_stack,
    ),
    (
        "the_wide_walks_decide_lanes_as_each_other_and_the_whole_list",
        the_wide_walks_decide_lanes_as_each_other_and_the_whole_list,
    ),
    (
        "a_single_leaf_tree_is_one_wide_node",
        a_single_leaf_tree_is_one_wide_node,
    ),
];
