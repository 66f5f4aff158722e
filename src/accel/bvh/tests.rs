//! Unit tests of the build (depth, splits, top levels, dense leaves' shared vertices), of a
//! frame's cache and the leaves prepared as met, and of the packet walks (untrusted slabs, 16
//! lanes); the wide nodes' and their walks' in `tests/wide_nodes.rs`. The helpers here build
//! the scenes both use.

use super::build::binary;
use super::leaf_vertices::place;
use super::node::Node;
use super::*;
use crate::accel::layout::Layout;
use crate::accel::packet::{
    OriginBlock, OriginTriangle, OriginTriangles, PacketNearest, TriangleLanes,
};
use crate::accel::prepared::{Prepared, BLOCK};
use crate::accel::IndexedTriangle;
use crate::geometry::{Method, Ray, Shape};
use crate::math::lanes::f32x8;
use crate::math::simd::each3;

/// The per-ray walk's nearest hit, each triangle tested by its own exact test.
fn closest(bvh: &Bvh, ray: &Ray) -> Option<crate::geometry::Hit> {
    let mut best = None;
    bvh.closest(ray, Method::Adaptive, 0.0, f32::INFINITY, &mut best);
    best
}

pub(crate) mod wide_nodes;

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
    let mut next = || (crate::math::xorshift(&mut x) >> 40) as f32 / (1u64 << 24) as f32 * 10.0;
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
                    assert!((0..3)
                        .all(|k| n.bounds.lo[k] <= c.bounds.lo[k]
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
    let shapes: Vec<Shape> = row.iter().map(|(v, _)| Shape::from(*v)).collect();
    for x in [1e9f32, 5.0, 1e30] {
        let ray = Ray::new([x, 0.1, 0.0], [-1.0, 0.0, 0.0]);
        let want = crate::accel::closest_hit(&shapes, &ray, Method::Adaptive, 0.0, f32::INFINITY);
        let hit = closest(&bvh, &ray);
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
    let shapes: Vec<Shape> = tris.iter().map(|(v, _)| Shape::from(*v)).collect();
    for i in 0..200 {
        let (x, y) = (0.37 * i as f32 + 0.1, 10.0 * (i % 2) as f32 + 0.1);
        let ray = Ray::new([x, y, -5.0], [0.01, 0.002, 1.0]);
        let want = crate::accel::closest_hit(&shapes, &ray, Method::Adaptive, 0.0, f32::INFINITY);
        let hit = closest(&placed, &ray);
        assert_eq!(hit.map(|h| h.prim), want.map(|h| h.prim), "ray {i}");
    }
}

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
            bvh.packet_into(&mut nearest, o, prepared, d);
            let found = nearest.finish();
            for l in 0..8 {
                if (found.ambiguous | whole.ambiguous) & (1 << l) == 0 {
                    assert_eq!(found.prim[l], whole.prim[l], "lane {l}");
                }
            }
        }
    }
}

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
fn sixteen_lane_packets_decide_as_the_whole_list() {
    use crate::math::lanes::{Avx16, LaneOps};
    use crate::math::simd::{detected, SimdLevel};
    if detected() < SimdLevel::Avx512 {
        return; // no 16-lane build on this CPU
    }
    crate::math::simd::avx512_features! {
        fn walk16(
            bvh: &Bvh,
            o: [f32; 3],
            prepared: Prepared<'_>,
            d: &[[f32; 16]; 3],
            prim: &mut [u32; 16],
        ) -> u32 {
            let d = each3(|k| Avx16::load(&d[k]));
            let dm = crate::accel::packet::max_component_in(&d);
            bvh.closest_positions_in(o, prepared, d, dm, prim)
        }
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

fn leaves_give_their_triangles_bits_from_shared_vertices_or_spill() {
    // A wavy sheet of 1800 triangles (neighbours share vertices) and 300 scattered ones
    // (none shared), in leaves of up to 4 and of up to 8: a leaf whose distinct vertices
    // fit its places gives every triangle's corners with the triangle's own bits, in
    // whatever lanes; a leaf whose do not is spilled. Most of the sheet's leaves fit;
    // every scattered leaf of 2 or more spills.
    let mut tris = sheet(30);
    tris.extend(scattered(300, 0x853c49e6748fea9b, 0.05));
    for (i, t) in tris.iter_mut().enumerate() {
        t.1 = i as u32;
    }
    for leaf_max in [SMALL_LEAF, MAX_LEAF] {
        let bvh = Bvh::build_with(&tris, leaf_max, true);
        let shared = bvh.leaf_vertices.as_ref().unwrap();
        let (fit, spilled) = (&mut 0, &mut 0);
        for (first, count) in bvh.wide.iter().flat_map(|n| n.leaves()) {
            let leaf = &bvh.tris[first..first + count];
            let mut distinct: Vec<[u32; 3]> =
                leaf.iter().flatten().map(|v| v.map(f32::to_bits)).collect();
            distinct.sort_unstable();
            distinct.dedup();
            let room = place(first + count) - place(first);
            // A run across two leaves, or part of one after its first, is refused.
            if count < MAX_LEAF {
                assert!(shared.leaf(first, first + count + 1).is_none());
            }
            if count > 1 {
                assert!(shared.leaf(first + 1, first + count).is_none());
            }
            let Some(corners) = shared.leaf(first, first + count) else {
                assert!(distinct.len() > room, "leaf at {first} spilled");
                *spilled += 1;
                continue;
            };
            assert!(distinct.len() <= room, "leaf at {first}");
            *fit += 1;
            // Lane l holds triangle (l + 3) mod count.
            let lanes = std::array::from_fn(|l| (l + 3) % count);
            let corners = corners.in_lanes(lanes);
            for (l, &t) in lanes.iter().enumerate() {
                for (j, v) in leaf[t].iter().enumerate() {
                    for (k, x) in v.iter().enumerate() {
                        let got = corners.coordinate(l, j, k).to_bits();
                        assert_eq!(got, x.to_bits(), "leaf at {first}");
                    }
                }
            }
        }
        let sheet_leaves = 1800 / leaf_max;
        assert!(
            *fit > sheet_leaves * 3 / 4,
            "{fit} leaves fit, of {leaf_max}"
        );
        assert!(*spilled >= 300 / leaf_max, "{spilled} leaves spilled");
        // About 22 bytes a triangle, against 36.
        assert!(
            shared.bytes() < 23 * tris.len() + 300,
            "{} bytes",
            shared.bytes()
        );
    }
}

/// This module's tests, for tests/unit.rs to run.
pub(crate) const TESTS: &[(&str, fn())] = &[
    (
        "leaves_give_their_triangles_bits_from_shared_vertices_or_spill",
        leaves_give_their_triangles_bits_from_shared_vertices_or_spill,
    ),
    (
        "top_levels_cover_every_triangle_with_their_childless_boxes",
        top_levels_cover_every_triangle_with_their_childless_boxes,
    ),
    (
        "the_tree_stays_within_the_traversal_stacks",
        the_tree_stays_within_the_traversal_stacks,
    ),
    (
        "placed_meshes_split_on_the_axis_that_costs_least",
        placed_meshes_split_on_the_axis_that_costs_least,
    ),
    (
        "untrusted_packets_offer_every_triangle_from_every_kind_of_preparation",
        untrusted_packets_offer_every_triangle_from_every_kind_of_preparation,
    ),
    (
        "a_frames_cache_serves_every_leaf_its_own_triangles",
        a_frames_cache_serves_every_leaf_its_own_triangles,
    ),
    (
        "sixteen_lane_packets_decide_as_the_whole_list",
        sixteen_lane_packets_decide_as_the_whole_list,
    ),
];
