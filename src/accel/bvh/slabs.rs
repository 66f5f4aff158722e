//! The slab tests of boxes: the coordinates within which the f32 test holds
//! ([`slab_safe`], [`box_safe`]), one ray against a wide node's 8 boxes ([`RaySlabs`]; in f64
//! beyond that range, [`enter_f64`]), and a packet of 8 rays against one box
//! ([`PacketSlabs`]). Apart from the walks: the conservative arithmetic they all share.

use super::node::{Aabb, WideNode, WIDTH};
use crate::accel::cull::Box3;
use crate::geometry::Ray;
use crate::math::lanes::{f32x8, LaneOps, Lanes};
use crate::math::simd::each3;
use crate::math::Real;
use rayon::prelude::*;

/// Origin and direction components the f32 slab test keeps within its relative slack: 0, or
/// 2⁻⁴⁰…2⁴⁰; box coordinates: 0, or 2⁻⁸⁶…2⁴⁰ ([`box_safe`]). Then a nonzero difference of a
/// box coordinate and an origin coordinate is at least 2⁻⁸⁶ (the origin 0) or 2⁻⁶³ (an ulp of
/// either), and times 1/d at least 2⁻¹²⁶ and at most 2⁸¹: normal and finite, rounded by a
/// relative u. Beyond (subnormal or huge geometry, origins or directions), a per-ray test runs
/// in f64 and a packet offers every triangle: before, a direction below 2⁻¹²⁸ made 1/d
/// infinite and the BVH skipped the boxes it meets.
#[inline(always)]
pub(super) fn slab_safe(x: f32) -> bool {
    in_range(x, SAFE_EXP)
}

/// 2^±`SAFE_EXP`: the range of [`slab_safe`] (and the top of [`box_safe`]'s).
const SAFE_EXP: u32 = 40;

/// [`slab_safe`] for a box coordinate: 0, or 2⁻⁸⁶…2⁴⁰ (scanned meshes hold coordinates of
/// 1e-14 and less near their axes).
#[inline(always)]
pub(super) fn box_safe(x: f32) -> bool {
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
pub(super) fn boxes_tame(wide: &[WideNode]) -> bool {
    wide.par_iter()
        .all(|n| n.coordinates().all(|x| !x.is_finite() || box_safe(x)))
}

/// The slab test of [`Bvh::traverse`] in f64, for rays or boxes beyond [`slab_safe`]
/// ([`Box3::slab_interval_f64`]): widened by 2⁻²⁰ relative, it stays at least as generous as
/// the f32 one (whose roundings the inexact methods' own f32 hits may share); the entry
/// distance is handed back rounded down to f32.
///
/// [`Bvh::traverse`]: super::Bvh::traverse
#[inline(never)]
pub(super) fn enter_f64(
    b: &Aabb,
    pad: f32,
    ray: &Ray,
    inv: &[f64; 3],
    tmin: f32,
    t_far: f32,
) -> Option<f32> {
    let (lo, hi) = (b.lo, b.hi);
    let (t0, t1) = Box3 { lo, hi }.slab_interval_f64(pad, ray.o, inv, (tmin.into(), t_far.into()));
    (t0 <= t1).then(|| {
        let t = t0 as f32;
        if f64::from(t) > t0 {
            t.next_down()
        } else {
            t
        }
    })
}

/// One ray set up for the f32 slab test against a wide node's 8 boxes (the test of
/// `Bvh::traverse`, 8 boxes at once), every box widened by `pad`. For tmin ≥ 0 only: the far
/// distances are widened by a factor, which widens a positive distance and narrows a negative
/// one ([`enter_f64`] answers intervals that reach behind the origin).
pub(super) struct RaySlabs {
    pub(super) o: [f32; 3],
    pub(super) inv: [f32; 3],
    pub(super) near_hi: [bool; 3],
    pub(super) tmin: f32,
    pub(super) pad: f32,
}

impl RaySlabs {
    /// The children of `n` the ray enters before `limit`, and its entry distances.
    #[inline(always)]
    pub(super) fn enter(&self, n: &WideNode, limit: f32) -> (u32, [f32; WIDTH]) {
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

/// The packet slab test's far-distance factor: 2γ(3) (pbrt) and one rounding more, for the
/// rounding of 1/dₖ·slack itself.
#[inline(always)]
pub(super) fn far_slack() -> f32 {
    1.0 + 2.0 * f32::error_gamma(4)
}

/// Eight rays from one origin set up for the slab test against boxes.
pub(crate) struct PacketSlabs<V = f32x8> {
    pub(super) o: [f32; 3],
    pub(super) inv: [V; 3],
    /// 1/dₖ enlarged for the far distances (see `new`).
    pub(super) inv_far: [V; 3],
    neg: [V; 3],
    /// Per axis, the sign every lane's direction shares (`None` if mixed): near and far slab
    /// are then the same for the whole packet.
    sign: [Option<bool>; 3],
    /// Whether every 1/dₖ is finite (then no 0·∞ can arise).
    pub(super) tame: bool,
    /// Tame, and every axis's sign shared: per axis, whether the near slab is the box's high
    /// side (`enter` then takes one branch-free path).
    pub(super) coherent: Option<[bool; 3]>,
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
