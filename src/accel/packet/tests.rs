//! Unit tests of the preparations (their bounds against exact arithmetic, the same bits four
//! and eight at a time), the f64 crossings, and the block and leaf passes against offers one
//! by one. In one file: they share their triangle suites and ray generators.

use super::exact_lane::{Crossing, ExactLane};
use super::*;
use crate::accel::IndexedTriangle;
use crate::geometry::exact;
use crate::math::lanes::{f32x8, f64x4, LaneOps};
use crate::math::simd::each3;
use std::cmp::Ordering;

/// Values in [−0.5, 0.5) from the crate's test generator seeded with `seed`.
fn unit_steps(mut seed: u64) -> impl FnMut() -> f32 {
    move || (crate::math::xorshift(&mut seed) >> 40) as f32 / (1u64 << 24) as f32 - 0.5
}

/// Every field's bits.
fn bits(t: &OriginTriangle) -> Vec<u32> {
    let mut b: Vec<u32> = t.n.iter().flatten().map(|x| x.to_bits()).collect();
    b.extend(t.k.map(f32::to_bits));
    b.extend(t.normal.map(f32::to_bits));
    b.extend([t.k_sum, t.n_max, t.num, t.c_t, t.k_det].map(f32::to_bits));
    b.extend([t.det_from_normal as u32, t.prim, t.usable as u32]);
    b
}

/// Triangles of every kind the preparation meets: random ones at all scales, slivers,
/// degenerate and tiny ones, ones through the origin's plane, huge and non-finite
/// coordinates.
fn triangles() -> Vec<[[f32; 3]; 3]> {
    let mut next = unit_steps(0x9e37_79b9_7f4a_7c15);
    let mut tris = Vec::new();
    for scale in [1e-30f32, 1e-6, 1.0, 1e3, 1e12, 1e30] {
        for _ in 0..64 {
            tris.push([(); 3].map(|_| [(); 3].map(|_| next() * scale)));
        }
    }
    let v = [1.0f32, 2.0, 3.0];
    tris.extend([
        [v, v, v],
        [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], // the origin on its plane
        [
            [1.0, 1.0, 5.0],
            [1.0 + f32::EPSILON, 1.0, 5.0],
            [1.0, 1.0 + 1e-7, 5.0],
        ],
        [[3e38, 0.0, 1.0], [-3e38, 1.0, 1.0], [0.0, 3e38, 1.0]],
        [[f32::NAN, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
        [[f32::INFINITY, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
        [
            [1e-45, 0.0, 1e-45],
            [0.0, 1e-45, 1e-45],
            [1e-45, 1e-45, 2e-45],
        ],
    ]);
    tris
}

#[allow(unsafe_code)]
fn four_at_a_time_prepares_the_same_bits_as_one_by_one() {
    crate::math::simd::avx2_features! {
        fn avx(v: [&[[f32; 3]; 3]; 4], o: [f32; 3], prim: [u32; 4]) -> [OriginTriangle; 4] {
            let quad = OriginTriangle::new4::<crate::math::lanes::Avx4d>(v, o, prim);
            [0, 1, 2, 3].map(|l| quad.get(l))
        }
    }
    crate::math::simd::avx512_features! {
        fn avx512(v: [&[[f32; 3]; 3]; 4], o: [f32; 3], prim: [u32; 4]) -> [OriginTriangle; 4] {
            let quad = OriginTriangle::new4::<crate::math::lanes::Avx4d>(v, o, prim);
            [0, 1, 2, 3].map(|l| quad.get(l))
        }
    }
    let tris = triangles();
    for o in [[0.0f32, 0.0, 0.0], [0.3, -0.2, -3.0], [1e6, 2.0, -1e-3]] {
        for (q, quad) in tris.chunks_exact(4).enumerate() {
            let v = [&quad[0], &quad[1], &quad[2], &quad[3]];
            let prim = [0, 1, 2, 3].map(|j| (4 * q + j) as u32);
            let one = (0..4).map(|j| bits(&OriginTriangle::new(v[j], o, prim[j])));
            let quad = OriginTriangle::new4::<f64x4>(v, o, prim);
            let wide = [0, 1, 2, 3].map(|l| bits(&quad.get(l)));
            for (j, one) in one.enumerate() {
                assert_eq!(one, wide[j], "{:?} from {o:?}", v[j]);
                if crate::math::simd::has_avx2() {
                    // SAFETY: the CPU has AVX2 and FMA.
                    let avx = unsafe { avx(v, o, prim) }.map(|t| bits(&t));
                    assert_eq!(one, avx[j], "{:?} from {o:?}", v[j]);
                }
                if crate::math::simd::detected() == crate::math::simd::SimdLevel::Avx512 {
                    // SAFETY: the CPU has AVX-512 F, VL, BW, DQ and CD.
                    let avx = unsafe { avx512(v, o, prim) }.map(|t| bits(&t));
                    assert_eq!(one, avx[j], "{:?} from {o:?}", v[j]);
                }
            }
        }
    }
}

/// The bounds the kernels rely on, against exact rational arithmetic: for every usable
/// triangle and direction d, |ẽᵢ − eᵢ| ≤ Kᵢ·max|dₖ| + EDGE_ABS (ẽᵢ computed as the kernels
/// compute it), |d·Ñ − d·N| ≤ k_det·max|dₖ| + EDGE_ABS, Σ Kᵢ ≤ k_sum, and det[p₀, p₁, p₂]
/// within the relative error c_t allows of num (so its sign is num's). Returns how many
/// edge functions came within 4 bounds of zero (the test must reach the hard cases).
fn check_bounds(tri: &OriginTriangle, v: &[[f32; 3]; 3], o: [f32; 3], d: [f32; 3]) -> usize {
    use crate::geometry::exact::{dot, q, qv, sub, Q, QV};
    use num_traits::Signed;
    const U: f64 = 1.0 / (1u64 << 24) as f64;
    let cross = |a: &QV, b: &QV| -> QV {
        [
            &a[1] * &b[2] - &a[2] * &b[1],
            &a[2] * &b[0] - &a[0] * &b[2],
            &a[0] * &b[1] - &a[1] * &b[0],
        ]
    };
    let wide = |x: [f32; 3]| x.map(f64::from);
    let (oq, dq) = (qv(wide(o)), qv(wide(d)));
    let p: Vec<QV> = v.iter().map(|v| sub(&qv(wide(*v)), &oq)).collect();
    let dm = d.iter().fold(0f32, |m, c| m.max(c.abs())) * (1.0 + 1e-6);
    let within = |computed: f32, exact: &Q, bound: f32, what: &str| {
        let err = (q(f64::from(computed)) - exact).abs();
        assert!(
            err <= q(f64::from(bound)),
            "{what}: {computed} off by {err} > {bound} for {v:?} from {o:?} along {d:?}"
        );
    };
    let mut close = 0;
    for i in 0..3 {
        let exact = dot(&dq, &cross(&p[(i + 1) % 3], &p[(i + 2) % 3]));
        let n = &tri.n[i];
        let e = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
        let bound = tri.k[i] * dm + EDGE_ABS;
        within(e, &exact, bound, "edge function");
        close += (e.abs() <= 4.0 * bound) as usize;
    }
    assert!(tri.k.iter().map(|&k| f64::from(k)).sum::<f64>() <= f64::from(tri.k_sum));
    let normal = cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0]));
    let n = &tri.normal;
    let det = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    within(
        det,
        &dot(&dq, &normal),
        tri.k_det * dm + EDGE_ABS,
        "determinant",
    );
    let num = dot(&p[0], &normal);
    let r_num = (f64::from(tri.c_t) / (1.0 + 1e-6) - 6.0 * U) / 1.4 - 2.1 * U;
    within(
        tri.num,
        &num,
        (r_num * f64::from(tri.num).abs()) as f32,
        "numerator",
    );
    close
}

/// Directions at the triangle's edges and vertices (and a little off them) and random
/// ones, from `o`.
fn directions(v: &[[f32; 3]; 3], o: [f32; 3], next: &mut impl FnMut() -> f32) -> Vec<[f32; 3]> {
    let mut out = Vec::new();
    for j in 0..3 {
        let (a, b) = (v[j], v[(j + 1) % 3]);
        for s in [0.0f32, 0.5, next() + 0.5, 1.0] {
            let at = each3(|k| a[k] + s * (b[k] - a[k]));
            let d = each3(|k| at[k] - o[k]);
            out.push(d);
            out.push(each3(|k| d[k] * (1.0 + 1e-6 * next())));
        }
    }
    out.push([next(), next(), next()]);
    out
}

fn both_preparations_bound_their_errors_exactly() {
    let mut next = unit_steps(0x2545_f491_4f6c_dd1d);
    let tris = triangles();
    let (mut usable, mut close) = ([0usize; 2], 0);
    for o in [
        [0.0f32, 0.0, 0.0],
        [0.3, -0.2, -3.0],
        [1e6, 2.0, -1e-3],
        [0.01, 0.02, 40.0],
    ] {
        for block in tris.chunks(8) {
            let v: [&[[f32; 3]; 3]; 8] = std::array::from_fn(|j| &block[j.min(block.len() - 1)]);
            let prim = std::array::from_fn(|j| j as u32);
            let mut f32s = OriginBlock::default();
            OriginTriangle::new8::<f32x8>(v, o, prim, &mut f32s);
            for (j, v) in v.iter().enumerate().take(block.len()) {
                let kinds = [OriginTriangle::new(v, o, 0), f32s.get(j)];
                for (kind, tri) in kinds.iter().enumerate() {
                    if !tri.usable {
                        continue;
                    }
                    usable[kind] += 1;
                    for d in directions(v, o, &mut next) {
                        close += check_bounds(tri, v, o, d);
                    }
                }
            }
        }
    }
    // Most of the suite is usable in f32 too (not the 1e30 scale, not the non-finite).
    assert!(usable[1] * 10 >= usable[0] * 7, "usable: {usable:?}");
    assert!(close > 1000, "{close} edge functions near zero");
}

/// Triangles about 10⁻³ across, about 5 units from `o` in every direction: a far
/// bunny's, whose edge functions are small against their f32 rounding bounds.
fn far_small(o: [f32; 3], next: &mut impl FnMut() -> f32) -> Vec<[[f32; 3]; 3]> {
    (0..48)
        .map(|_| {
            let c = each3(|k| o[k] + 10.0 * next());
            [(); 3].map(|_| each3(|k| c[k] + 2e-3 * next()))
        })
        .collect()
}

/// How the line o + t·d meets triangle `v`, in exact arithmetic alone (`None`: the line
/// lies in its plane, or the input is not finite).
fn exact_crossing(v: &[[f32; 3]; 3], o: [f32; 3], d: [f32; 3]) -> Option<Crossing> {
    use num_traits::Zero;
    let wide = |x: [f32; 3]| x.map(f64::from);
    let mut sign = [Ordering::Equal; 3];
    for (i, s) in sign.iter_mut().enumerate() {
        *s = exact::orient(wide(d), wide(o), wide(v[(i + 1) % 3]), wide(v[(i + 2) % 3]))?;
    }
    if sign.contains(&Ordering::Greater) && sign.contains(&Ordering::Less) {
        return Some(Crossing::Away);
    }
    if sign.iter().all(|s| *s == Ordering::Equal) {
        return None;
    }
    let t = exact_t(v, o, d)?;
    Some(match t > Zero::zero() {
        true => Crossing::Front,
        false => Crossing::Away,
    })
}

/// [`PreciseTriangle::crossing`] against exact arithmetic: a certain miss is one, a
/// certain crossing is one in front with the exact t in its interval; and it decides
/// most of the rays the f32 rounding leaves within its bounds of an edge.
fn f64_crossings_hold_the_exact_answer_and_decide_what_f32_cannot() {
    use crate::geometry::exact::q;
    let mut next = unit_steps(0x5851_f42d_4c95_7f2d);
    let (mut f32_unsure, mut rescued, mut f64_unsure, mut fronts) = (0, 0, 0, 0);
    for o in [
        [0.0f32, 0.0, 0.0],
        [0.3, -0.2, -3.0],
        [1e6, 2.0, -1e-3],
        [4.0, 1.0, 5.0],
    ] {
        let mut tris = triangles();
        tris.extend(far_small(o, &mut next));
        for v in &tris {
            let tri = PreciseTriangle::new(v, o, 7);
            if !tri.usable {
                continue;
            }
            for d in directions(v, o, &mut next) {
                let (Some(lane), Some(exact)) = (ExactLane::new(o, d), exact_crossing(v, o, d))
                else {
                    continue;
                };
                let exact = Some(exact);
                let got = tri.crossing(d);
                let f32_sure = tri.rounded.usable
                    && (0..3).all(|i| {
                        let n = &tri.rounded.n[i];
                        let e = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
                        e.abs() > tri.rounded.k[i] * lane.dm + EDGE_ABS
                    });
                f32_unsure += !f32_sure as usize;
                rescued += (!f32_sure && got.is_some()) as usize;
                match got {
                    None => f64_unsure += 1,
                    Some(None) => {
                        assert_eq!(exact, Some(Crossing::Away), "{v:?} from {o:?} along {d:?}")
                    }
                    Some(Some((lo, hi))) => {
                        fronts += 1;
                        assert_eq!(exact, Some(Crossing::Front), "{v:?} from {o:?} along {d:?}");
                        let t = exact_t(v, o, d).expect("crossed, so not parallel");
                        assert!(
                            q(f64::from(lo)) <= t && t <= q(f64::from(hi)),
                            "t {t} outside [{lo}, {hi}] for {v:?} from {o:?} along {d:?}"
                        );
                    }
                }
            }
        }
    }
    assert!(fronts > 500, "{fronts} crossings");
    assert!(f32_unsure > 200, "{f32_unsure} rays near an edge for f32");
    // (Here about 90%: the rest pass exactly through a vertex or along an edge.)
    assert!(
        rescued * 10 > f32_unsure * 8,
        "{rescued} of {f32_unsure} decided in f64"
    );
    assert!(
        f64_unsure * 4 < f32_unsure,
        "{f64_unsure} left undecided in f64"
    );
}

/// The exact t of the line o + t·d in the plane of `v` (None if parallel).
fn exact_t(v: &[[f32; 3]; 3], o: [f32; 3], d: [f32; 3]) -> Option<crate::geometry::exact::Q> {
    use crate::geometry::exact::{dot, qv, sub};
    use num_traits::Zero;
    let wide = |x: [f32; 3]| qv(x.map(f64::from));
    let p: Vec<_> = v.iter().map(|v| sub(&wide(*v), &wide(o))).collect();
    let (a, b) = (sub(&p[1], &p[0]), sub(&p[2], &p[0]));
    let normal = [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ];
    let det = dot(&wide(d), &normal);
    (!det.is_zero()).then(|| dot(&p[0], &normal) / det)
}

/// Triangles for the block passes' tests: three triangulated sheets one behind the other
/// (shared edges and vertices, two candidates along most rays; the third lies within the
/// t intervals' width of the first: their order is uncertain), interleaved so that each
/// run of 8 (or leaf of 4) holds triangles of every sheet; then some of the
/// preparation's hard suite.
fn layered_triangles() -> Vec<[[f32; 3]; 3]> {
    let sheet = |z: f32, shift: f32| {
        let mut tris = Vec::new();
        for i in 0..4 {
            for j in 0..4 {
                let (x, y) = (i as f32 * 0.1 - 0.2 + shift, j as f32 * 0.1 - 0.2);
                let c = [
                    [x, y, z],
                    [x + 0.1, y, z],
                    [x, y + 0.1, z],
                    [x + 0.1, y + 0.1, z],
                ];
                tris.push([c[0], c[1], c[2]]);
                tris.push([c[2], c[1], c[3]]);
            }
        }
        tris
    };
    let sheets = [
        sheet(2.0, 0.0),
        sheet(2.0 + 1e-4, 0.013),
        sheet(f32::from_bits(2.0f32.to_bits() + 1), 0.029),
    ];
    let mut tris: Vec<_> = (0..32)
        .flat_map(|i| sheets.each_ref().map(|s| s[i]))
        .collect();
    tris.extend(triangles().into_iter().step_by(5));
    tris
}

/// Directions from `o` at the edges and vertices of `tris` and between
/// ([`directions`]), and through their insides (where the sheets overlap).
fn rays_at(tris: &[[[f32; 3]; 3]], o: [f32; 3], next: &mut impl FnMut() -> f32) -> Vec<[f32; 3]> {
    let mut dirs = Vec::new();
    for t in tris {
        dirs.extend(directions(t, o, next));
        for _ in 0..4 {
            let (a, b) = (next() + 0.5, next() + 0.5);
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            dirs.push(each3(|k| {
                t[0][k] + a * (t[1][k] - t[0][k]) + b * (t[2][k] - t[0][k]) - o[k]
            }));
        }
    }
    dirs
}

/// The exact nearest front crossing of the ray from `o` along `d` among `ids` of
/// `block` (vertices `v`): its id and whether another front one was crossed, or None.
fn exact_nearest(
    block: &OriginBlock,
    v: &[&[[f32; 3]; 3]; 8],
    o: [f32; 3],
    d: [f32; 3],
    ids: &[usize],
) -> Option<(usize, bool)> {
    let exact = ExactLane::new(o, d).unwrap();
    let fronts: Vec<(usize, _)> = (ids.iter().copied())
        .filter(|&j| exact.crossing(&block.get(j), v[j]) == Some(Crossing::Front))
        .map(|j| (j, exact_t(v[j], o, d).unwrap()))
        .collect();
    let (j, t) = fronts.iter().min_by(|a, b| a.1.cmp(&b.1))?;
    assert!(
        fronts.iter().all(|(k, u)| k == j || u > t),
        "a tie at {d:?}"
    );
    Some((*j, fronts.len() > 1))
}

fn one_lane_offers_of_a_block_decide_as_offers_one_by_one() {
    // Blocks of 8 from two triangulated sheets one behind the other (shared edges and
    // vertices, two candidates along most rays) and from the preparation's hard suite;
    // rays at their edges and vertices and between; every leaf-sized run of lanes, from
    // an empty lane and from one holding a candidate. Where the one-lane pass decides,
    // its answer is the exact nearest (rational t, exact edge signs), and the one of
    // offers one by one wherever those decide; where it does not, nothing changed.
    let mut next = unit_steps(0x5851_f42d_4c95_7f2d);
    let tris = layered_triangles();
    let o = [0.01f32, -0.02, 0.0];
    let (mut decided, mut taken, mut declined, mut ordered) = (0, 0, 0, 0);
    for block_tris in tris.chunks(8).filter(|b| b.len() == 8) {
        let v: [&[[f32; 3]; 3]; 8] = std::array::from_fn(|j| &block_tris[j]);
        let mut block = OriginBlock::default();
        OriginTriangle::new8::<f32x8>(v, o, [0; 8], &mut block);
        let dirs = rays_at(block_tris, o, &mut next);
        for (k, d) in dirs.iter().enumerate() {
            let l = k % 8;
            let mut lanes = [[0f32; 8]; 3];
            for (c, lane) in lanes.iter_mut().enumerate() {
                for (m, x) in lane.iter_mut().enumerate() {
                    *x = match m == l {
                        true => d[c],
                        false => dirs[(k + m * 7) % dirs.len()][c],
                    };
                }
            }
            let dw = lanes.map(f32x8::from);
            let d_max = lanes.iter().flatten().fold(0f32, |m, x| m.max(x.abs()));
            for (start, len) in [(0, 4), (4, 4), (2, 3), (5, 3), (0, 8), (7, 1)] {
                let mask = ((1u32 << len) - 1) << start;
                for seeded in [None, Some((start + len) % 8)] {
                    let mut one = PacketNearest::<f32x8>::seeded(&dw, d_max, None);
                    if let Some(s) = seeded {
                        one.offer(&block.get(s), 100 + s as u32);
                    }
                    if one.ambiguous() & (1 << l) != 0 {
                        continue;
                    }
                    let mut each = PacketNearest::<f32x8>::seeded(&dw, d_max, None);
                    if let Some(s) = seeded {
                        each.offer(&block.get(s), 100 + s as u32);
                    }
                    let before = format!("{:?}", one.finish_ref());
                    let lo_before = one.best_lo.to_array()[l];
                    if !one.offer_block_to_lane(&block, mask, BlockIds::From(0), l) {
                        assert_eq!(format!("{:?}", one.finish_ref()), before);
                        assert_eq!(one.best_lo.to_array()[l].to_bits(), lo_before.to_bits());
                        declined += 1;
                        continue;
                    }
                    decided += 1;
                    assert_eq!(one.ambiguous() & (1 << l), 0);
                    for j in (start..start + len).filter(|j| *j < 8) {
                        each.offer(&block.get(j), j as u32);
                    }
                    let got = one.finish_ref().prim[l];
                    if each.ambiguous() & (1 << l) == 0 {
                        assert_eq!(got, each.finish_ref().prim[l], "block lane {l}, {d:?}");
                    }
                    // Exact: the nearest front crossing among the run and the seed.
                    let mut ids: Vec<usize> = (start..start + len).filter(|j| *j < 8).collect();
                    ids.extend(seeded);
                    match exact_nearest(&block, &v, o, *d, &ids) {
                        None => assert_eq!(got, u32::MAX, "{d:?}"),
                        Some((j, others)) => {
                            let from_seed = Some(j) == seeded && got == 100 + j as u32;
                            assert!(got == j as u32 || from_seed, "{got} for {j}, {d:?}");
                            taken += (got < 100) as usize;
                            ordered += others as usize;
                        }
                    }
                }
            }
        }
    }
    // (Most rays here are aimed at edges and vertices: many lanes stay undecided.)
    println!("decided {decided}, taken {taken}, ordered {ordered}, declined {declined}");
    assert!(decided > 10_000 && taken > 1_000 && ordered > 200 && declined > 1_000);
}

/// A leaf's offers to two to four lanes at once ([`PacketNearest::offer_leaf_to_lanes`]),
/// in 8 lanes (two passes for three or four rays) and, where the CPU has AVX-512, in 16
/// (one pass), on the triangles and rays of the one-lane test: where they decide, each
/// ray's answer is the exact nearest of the leaf and its seed, and that of offers one by
/// one wherever those decide, and no other lane changed; where they do not, nothing did.
fn leaf_offers_to_a_few_lanes_decide_as_offers_one_by_one() {
    let check = |[decided, taken, ordered, declined]: [usize; 4]| {
        println!("decided {decided}, taken {taken}, ordered {ordered}, declined {declined}");
        assert!(decided > 5_000 && taken > 1_000 && ordered > 200 && declined > 500);
    };
    check(leaf_offers::<f32x8>());
    use crate::math::lanes::Avx16;
    use crate::math::simd::{detected, SimdLevel};
    if detected() >= SimdLevel::Avx512 {
        crate::math::simd::avx512_features! {
            fn in_16_lanes() -> [usize; 4] {
                leaf_offers::<Avx16>()
            }
        }
        // SAFETY: the CPU has AVX-512 F, VL, BW, DQ and CD (checked above).
        #[allow(unsafe_code)]
        check(unsafe { in_16_lanes() });
    }
}

/// The body of `leaf_offers_to_a_few_lanes_decide_as_offers_one_by_one` in lanes `V`:
/// the counts of leaf offers decided, rays that took a leaf triangle, rays that crossed
/// more than one, and offers declined.
#[inline(always)]
fn leaf_offers<V: LaneOps>() -> [usize; 4] {
    /// The lanes' bits.
    #[inline(always)]
    fn bits<V: LaneOps>(x: V) -> [u32; 16] {
        let mut a = [0f32; 16];
        x.store(&mut a);
        a.map(f32::to_bits)
    }
    #[inline(always)]
    fn state<V: LaneOps>(p: &PacketNearest<V>) -> ([u32; 16], u32, [u32; 16], [u32; 16]) {
        let mut prims = [0u32; 16];
        let ambiguous = p.finish_into(&mut prims);
        (prims, ambiguous, bits(p.best_lo), bits(p.best_hi))
    }
    let mut next = unit_steps(0x2545_f491_4f6c_dd1d);
    let tris = layered_triangles();
    let o = [0.01f32, -0.02, 0.0];
    let width = V::WIDTH;
    let (mut decided, mut taken, mut declined, mut ordered) = (0, 0, 0, 0);
    for leaf_tris in tris.chunks(4).filter(|b| b.len() == 4) {
        // As `Bvh::prepare_leaf` prepares a leaf: lanes 4–7 repeat lanes 0–3.
        let v: [&[[f32; 3]; 3]; 8] = std::array::from_fn(|j| &leaf_tris[j % 4]);
        let mut block = OriginBlock::default();
        OriginTriangle::new8::<f32x8>(v, o, [0; 8], &mut block);
        let dirs = rays_at(leaf_tris, o, &mut next);
        for k in 0..dirs.len() {
            let mut lanes = [[0f32; 16]; 3];
            for (c, lane) in lanes.iter_mut().enumerate() {
                for (m, x) in lane.iter_mut().enumerate() {
                    *x = dirs[(k + m * 7) % dirs.len()][c];
                }
            }
            let d = [0, 1, 2].map(|c| V::load(&lanes[c]));
            let d_max = (lanes.iter())
                .flat_map(|lane| &lane[..width])
                .fold(0f32, |m, x| m.max(x.abs()));
            for rays in [0b11, 0x22, 0xc8, 0xb1, 0x8421, 0xe002] {
                let rays = rays & V::full();
                for len in 1..=4 {
                    // A seed outside the leaf, offered to every lane first.
                    for seeded in [None, (len < 4).then_some(len)] {
                        let mut one = PacketNearest::<V>::new_in(d, d_max);
                        if let Some(s) = seeded {
                            one.offer(&block.get(s), 100 + s as u32);
                        }
                        let live = rays & !one.ambiguous();
                        if live.count_ones() < 2 {
                            continue;
                        }
                        let before = state(&one);
                        if !one.offer_leaf_to_lanes(&block, len, 0, live) {
                            assert_eq!(state(&one), before);
                            declined += 1;
                            continue;
                        }
                        decided += 1;
                        let after = state(&one);
                        assert_eq!(after.1, before.1, "no lane left ambiguous");
                        for m in (0..width).filter(|m| live & (1 << m) == 0) {
                            let lane = |s: &([u32; 16], u32, [u32; 16], [u32; 16])| {
                                (s.0[m], s.2[m], s.3[m])
                            };
                            assert_eq!(lane(&after), lane(&before), "lane {m} untouched");
                        }
                        let mut each = PacketNearest::<V>::new_in(d, d_max);
                        if let Some(s) = seeded {
                            each.offer(&block.get(s), 100 + s as u32);
                        }
                        for j in 0..len {
                            each.offer(&block.get(j), j as u32);
                        }
                        let each = state(&each);
                        let mut ids: Vec<usize> = (0..len).collect();
                        ids.extend(seeded);
                        for l in (0..width).filter(|l| live & (1 << l) != 0) {
                            let got = after.0[l];
                            if each.1 & (1 << l) == 0 {
                                assert_eq!(got, each.0[l], "lane {l} of {rays:#x}");
                            }
                            let dl = [lanes[0][l], lanes[1][l], lanes[2][l]];
                            match exact_nearest(&block, &v, o, dl, &ids) {
                                None => assert_eq!(got, u32::MAX, "{dl:?}"),
                                Some((j, others)) => {
                                    let want = match Some(j) == seeded {
                                        true => 100 + j as u32,
                                        false => j as u32,
                                    };
                                    assert_eq!(got, want, "{dl:?}");
                                    taken += (got < 100) as usize;
                                    ordered += others as usize;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    [decided, taken, ordered, declined]
}

fn prepared_lists_keep_order_and_length() {
    let tris = triangles();
    for n in [0, 1, 3, 4, 5, 4099] {
        let list: Vec<IndexedTriangle> = (0..n)
            .map(|i| (tris[i % tris.len()], 7 * i as u32))
            .collect();
        let o = [0.1, 0.2, -2.0];
        let prepared = OriginTriangles::new(&list, o);
        assert_eq!(prepared.tris.len(), n);
        for (t, (v, prim)) in prepared.tris.iter().zip(&list) {
            assert_eq!(bits(t), bits(&OriginTriangle::new(v, o, *prim)));
        }
    }
}

/// This module's tests, for tests/unit.rs to run.
pub(crate) const TESTS: &[(&str, fn())] = &[
    (
        "four_at_a_time_prepares_the_same_bits_as_one_by_one",
        four_at_a_time_prepares_the_same_bits_as_one_by_one,
    ),
    (
        "both_preparations_bound_their_errors_exactly",
        both_preparations_bound_their_errors_exactly,
    ),
    (
        "f64_crossings_hold_the_exact_answer_and_decide_what_f32_cannot",
        f64_crossings_hold_the_exact_answer_and_decide_what_f32_cannot,
    ),
    (
        "one_lane_offers_of_a_block_decide_as_offers_one_by_one",
        one_lane_offers_of_a_block_decide_as_offers_one_by_one,
    ),
    (
        "leaf_offers_to_a_few_lanes_decide_as_offers_one_by_one",
        leaf_offers_to_a_few_lanes_decide_as_offers_one_by_one,
    ),
    (
        "prepared_lists_keep_order_and_length",
        prepared_lists_keep_order_and_length,
    ),
];
