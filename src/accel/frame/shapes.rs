//! The shapes other than triangles (spheres) in the packets, lane by lane: each seen from
//! the eye and from the light ([`LaneShape`]), tested four lanes at a time through the
//! shape's f64 interval level, before a camera packet's triangles ([`shapes_seed`]) and
//! for shadow segments ([`shapes_block`]).

use super::{segments_box, ShadowSegments, NO_HIT};
use crate::accel::cull::Box3;
use crate::accel::packet::PacketSeed;
use crate::geometry::adaptive::{round_down, round_up, widen};
use crate::geometry::{sphere, Shape};
use crate::math::simd::{avx512_avx2_or_baseline, each3};
use wide::{f32x8, f64x4};

/// A shape other than a triangle for the lane-by-lane tests of the packets: seen from the
/// eye and from the light ([`sphere::FromOrigin`]; `None`: a kind of shape the packets do
/// not know, whose lanes go per ray).
#[derive(Clone, Copy, Debug)]
pub(super) struct LaneShape {
    prim: u32,
    bounds: Box3,
    from_eye: Option<sphere::FromOrigin>,
    from_light: Option<sphere::FromOrigin>,
}

impl LaneShape {
    pub(super) fn new(
        shape: &Shape<f32>,
        prim: u32,
        bounds: Box3,
        eye: [f32; 3],
        light: [f32; 3],
    ) -> Self {
        // (Triangles are prepared in the packets themselves.)
        let from = |o: [f32; 3]| widen(shape).sphere_from_origin(o.map(f64::from));
        Self {
            prim,
            bounds,
            from_eye: from(eye),
            from_light: from(light),
        }
    }
}
/// The id a packet's lanes give a shape other than a triangle ([`ShapeSeed`]): beyond every
/// primitive and BVH slot, so that no kernel maps it.
pub(super) const SEEDED: u32 = u32::MAX - 1;

/// The shapes other than triangles along a camera packet, found before its triangles.
pub(super) struct ShapeSeed {
    /// The packet's starting state: the nearest shape's t interval per lane (id [`SEEDED`]),
    /// and the lanes the shapes leave ambiguous.
    pub(super) seed: PacketSeed,
    /// The nearest shape's primitive per lane.
    pub(super) prims: [u32; 8],
}

/// The shapes other than triangles tested on lanes `live` of a camera packet (rays from the
/// eye along `d`), four lanes at a time: see the module doc.
#[inline(never)]
pub(super) fn shapes_seed(shapes: &[LaneShape], d: &[f32x8; 3], live: u32) -> ShapeSeed {
    avx512_avx2_or_baseline!(shapes_seed_body => (
        shapes: &[LaneShape],
        d: &[f32x8; 3],
        live: u32
    ) -> ShapeSeed)
}

#[inline(always)]
fn shapes_seed_body(shapes: &[LaneShape], d: &[f32x8; 3], live: u32) -> ShapeSeed {
    let mut out = ShapeSeed {
        seed: PacketSeed::default(),
        prims: [NO_HIT; 8],
    };
    let used = live & 0xff;
    let d = d.map(|c| c.to_array());
    for half in 0..2 {
        let bits = (used >> (4 * half)) & 0xf;
        if bits == 0 {
            continue;
        }
        let lane = |l: usize| 4 * half + l;
        let d = half_in_f64(&d, half);
        let mut lo = f64x4::splat(f64::INFINITY);
        let mut hi = lo;
        let mut undecided = 0u32;
        for shape in shapes {
            let Some(from_eye) = &shape.from_eye else {
                undecided = 0xf;
                break;
            };
            let r = sphere::interval_x4(from_eye, &d, 0.0, f64::INFINITY);
            let nearer = r.hit & r.hi.simd_lt(lo);
            let farther = r.hit & r.lo.simd_gt(hi);
            // Too close to order, or the interval cannot tell: per ray.
            undecided |= (!(r.miss | nearer | farther)).to_bitmask();
            lo = nearer.bitselect(r.lo, lo);
            hi = nearer.bitselect(r.hi, hi);
            let taken = nearer.to_bitmask();
            for l in (0..4).filter(|l| taken & (1 << l) != 0) {
                out.prims[lane(l)] = shape.prim;
                out.seed.prim[lane(l)] = SEEDED;
            }
        }
        out.seed.ambiguous |= (undecided & bits) << (4 * half);
        // The interval rounded outwards to f32.
        let (lo, hi) = (lo.to_array(), hi.to_array());
        for l in 0..4 {
            out.seed.lo[lane(l)] = round_down(lo[l]);
            out.seed.hi[lane(l)] = round_up(hi[l]);
        }
    }
    out
}

/// Lanes 4·`half` to 4·`half` + 3 of the directions `d` (per axis), in f64.
#[inline(always)]
fn half_in_f64(d: &[[f32; 8]; 3], half: usize) -> [f64x4; 3] {
    each3(|k| f64x4::new(std::array::from_fn(|l| f64::from(d[k][4 * half + l]))))
}

/// Shadow lanes decided by the shapes other than triangles.
pub(super) struct ShapeLanes {
    /// Certainly blocked by one of them.
    pub(super) blocked: u32,
    /// Not blocked for certain, and one of them the interval cannot decide: per ray.
    pub(super) unsure: u32,
}

/// Which live lanes of shadow segments `s` (from the light) the shapes `near` block, each
/// lane skipping its own primitive, four lanes at a time (see the module doc).
#[inline(always)]
pub(super) fn shapes_block(near: &[LaneShape], light: [f32; 3], s: &ShadowSegments) -> ShapeLanes {
    if near.is_empty() {
        return ShapeLanes {
            blocked: 0,
            unsure: 0,
        };
    }
    avx512_avx2_or_baseline!(shapes_block_body => (
        near: &[LaneShape],
        light: [f32; 3],
        s: &ShadowSegments
    ) -> ShapeLanes)
}

#[inline(always)]
fn shapes_block_body(near: &[LaneShape], light: [f32; 3], s: &ShadowSegments) -> ShapeLanes {
    let mut lanes = ShapeLanes {
        blocked: 0,
        unsure: 0,
    };
    let segments = segments_box(std::slice::from_ref(s), light);
    let d = s.d.map(|c| c.to_array());
    for half in 0..2 {
        let live = (s.live >> (4 * half)) & 0xf;
        if live == 0 {
            continue;
        }
        let lane = |l: usize| 4 * half + l;
        let d = half_in_f64(&d, half);
        let (mut blocked, mut unsure) = (0u32, 0u32);
        for shape in near {
            if !shape.bounds.meets(segments.lo, segments.hi) {
                continue;
            }
            let own = (0..4).fold(0, |m, l| m | ((s.skip(lane(l)) == shape.prim) as u32) << l);
            let Some(from_light) = &shape.from_light else {
                unsure |= !own;
                continue;
            };
            let r = sphere::interval_x4(from_light, &d, 0.0, 1.0);
            blocked |= r.hit.to_bitmask() & !own;
            // Another shape may still block such a lane for certain.
            unsure |= (!(r.hit | r.miss)).to_bitmask() & !own;
        }
        lanes.blocked |= (blocked & live) << (4 * half);
        lanes.unsure |= (unsure & live) << (4 * half);
    }
    lanes.unsure &= !lanes.blocked;
    lanes
}
