//! Shadow rays from the light in packets of 8: [`ShadowPacket`] as triangles are offered,
//! and [`any`] over a list.

use super::predicates::{t_interval, EdgeTests};
use super::{OriginTriangle, MAX_PRODUCT};
use crate::math::lanes::{f32x8, Lanes};
use crate::math::simd::{avx512_avx2_or_baseline, each3, with_cpu_isa, Isa};

/// Eight shadow rays from the origin `tris` were prepared for (the light), directions `d`
/// (`d_max` ≥ every |dₖ|, [`max_component`]): whether each lane in `valid` is blocked for
/// 0 < t < 1 by one of `tris` other than its `skip` primitive, decided as `PacketNearest`
/// decides a candidate (certain edge signs, t in a certain interval), or left to the per-ray
/// adaptive search (`unsure`) where the bounds cannot tell. A lane is blocked when some
/// triangle certainly crosses it with its whole t interval below 1; it is clear of a
/// triangle that it certainly misses, that lies certainly behind the origin, or whose t
/// interval starts at 1 or beyond.
///
/// [`max_component`]: super::max_component
pub fn any(
    tris: &[OriginTriangle],
    d: &[f32x8; 3],
    d_max: f32,
    skip: &[u32; 8],
    valid: u32,
) -> ShadowHits {
    with_cpu_isa!(|isa| any_in(isa, tris, d, d_max, skip, valid))
}

/// [`any`] in the build `isa` names.
#[inline(always)]
pub(crate) fn any_in<I: Isa>(
    isa: I,
    tris: &[OriginTriangle],
    d: &[f32x8; 3],
    d_max: f32,
    skip: &[u32; 8],
    valid: u32,
) -> ShadowHits {
    avx512_avx2_or_baseline!(token isa, lanes any_body => (
        tris: &[OriginTriangle],
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32
    ) -> ShadowHits)
}

#[inline(always)]
fn any_body<V: Lanes>(
    tris: &[OriginTriangle],
    d: &[f32x8; 3],
    d_max: f32,
    skip: &[u32; 8],
    valid: u32,
) -> ShadowHits {
    let mut packet = ShadowPacket::<V>::new(d, d_max, skip, valid);
    for tri in tris {
        if packet.live() == 0 {
            break;
        }
        packet.offer(tri);
    }
    packet.finish()
}

/// Eight shadow segments from the origin triangles are prepared for, as triangles are offered
/// in any order (all of a small scene's, or a BVH's leaves as the segments reach them): per
/// lane, blocked for certain, or unsure. See [`packet::any`](any).
pub struct ShadowPacket<V = f32x8> {
    d: [V; 3],
    /// max|dₖ| rounded up.
    dm: f32,
    /// Each lane's own primitive (bit patterns; u32::MAX, a NaN, equals nothing).
    skip: V,
    valid: u32,
    blocked: u32,
    unsure: u32,
}

impl<V: Lanes> ShadowPacket<V> {
    #[inline(always)]
    pub fn new(d: &[f32x8; 3], d_max: f32, skip: &[u32; 8], valid: u32) -> Self {
        let dm = d_max * (1.0 + 1e-6);
        Self {
            d: each3(|k| V::from_wide(d[k])),
            dm,
            skip: V::from_bits(*skip),
            valid,
            blocked: 0,
            // Every lane, where max|d| is not finite.
            unsure: if dm.is_finite() { 0 } else { valid },
        }
    }

    /// The lanes still to be decided: valid, not yet blocked (an unsure lane may still be
    /// found blocked by another triangle).
    #[inline(always)]
    pub fn live(&self) -> u32 {
        match self.dm.is_finite() {
            true => self.valid & !self.blocked,
            false => 0,
        }
    }

    /// Tests one triangle on every live lane but those it belongs to.
    #[inline(always)]
    pub fn offer(&mut self, tri: &OriginTriangle) {
        self.offer_as::<false>(tri);
    }

    /// [`ShadowPacket::offer`] unless the triangle would leave a live lane unsure: then
    /// nothing changes and the answer is false (see [`PacketNearest::offer_decided`]).
    ///
    /// [`PacketNearest::offer_decided`]: super::PacketNearest::offer_decided
    #[inline(always)]
    pub fn offer_decided(&mut self, tri: &OriginTriangle) -> bool {
        self.offer_as::<true>(tri)
    }

    #[inline(always)]
    fn offer_as<const DECIDED: bool>(&mut self, tri: &OriginTriangle) -> bool {
        let (d, dm) = (&self.d, self.dm);
        let own = self
            .skip
            .simd_eq(V::splat(f32::from_bits(tri.prim)))
            .to_bitmask();
        let live = self.live() & !own;
        if live == 0 {
            return true;
        }
        if !tri.usable || tri.n_max * dm >= MAX_PRODUCT {
            // (Only an unusable triangle can hold the origin in its plane.)
            if tri.in_plane {
                return true;
            }
            if DECIDED {
                return false;
            }
            self.unsure |= live;
            return true;
        }
        let one = V::one();
        let EdgeTests {
            e,
            miss,
            front,
            behind,
        } = EdgeTests::new(tri, d, dm);
        let (front_bits, clear_bits) = (front.to_bitmask(), (miss | behind).to_bitmask());
        if front_bits & live == 0 {
            let unsure = live & !clear_bits;
            if DECIDED && unsure != 0 {
                return false;
            }
            self.unsure |= unsure;
            return true;
        }
        let (lo, hi, tight) = t_interval(tri, &e, d, dm);
        let before_end = (front & tight & hi.simd_lt(one)).to_bitmask();
        let past_end = (front & tight & lo.simd_ge(one)).to_bitmask();
        let unsure = live & !(clear_bits | before_end | past_end);
        if DECIDED && unsure != 0 {
            return false;
        }
        self.blocked |= live & before_end;
        self.unsure |= unsure;
        true
    }

    /// Every live lane unsure: left to the per-ray query (another triangle may still block
    /// it).
    pub(crate) fn all_unsure(&mut self) {
        self.unsure |= self.live();
    }

    pub fn finish(self) -> ShadowHits {
        ShadowHits {
            blocked: self.blocked,
            unsure: self.unsure & !self.blocked,
        }
    }
}

/// Shadow lanes: blocked for certain, and undecided (traced per ray).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShadowHits {
    pub blocked: u32,
    pub unsure: u32,
}
