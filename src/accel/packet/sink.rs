//! The face a packet walk fills ([`PacketLimits`], [`PacketSink`]): the hierarchies' walks
//! (`accel::bvh`, `accel::instances`, `accel::spheres`) ask it which lanes are open and how
//! far they reach, and hand it the triangles they meet.

use super::{BlockIds, OriginBlock, OriginTriangle, PacketNearest, PreciseTriangle, ShadowPacket};
use crate::math::lanes::{f32x8, LaneOps, Lanes};

/// What a packet walk asks of the state it fills: which lanes are still open, and how far
/// each may still reach. Every packet state is one: the triangles' ([`PacketSink`]) and the
/// spheres' (`accel::spheres`).
pub(crate) trait PacketLimits<V = f32x8> {
    /// Lanes still to be decided.
    fn live(&self) -> u32;
    /// Per lane, the distance beyond which nothing can change its answer.
    fn limit(&self) -> V;
}

/// Where packets and walks of the hierarchies send the triangles they reach: a packet's
/// nearest-hit or shadow state.
pub(crate) trait PacketSink<V = f32x8>: PacketLimits<V> {
    /// Tests one triangle (prepared for the packet's origin) on the live lanes.
    fn take(&mut self, tri: &OriginTriangle);
    /// [`PacketSink::take`] unless the triangle would leave a live lane undecided: then
    /// nothing changes and the answer is false.
    fn take_decided(&mut self, tri: &OriginTriangle) -> bool;
    /// Leaves every live lane to the per-ray queries (a layout without a packet walk): a
    /// nearest-hit lane turns ambiguous, a shadow lane unsure.
    fn per_ray(&mut self);
    /// Takes a triangle prepared in f64 for the lanes its f32 preparation left undecided: by
    /// default as rounded to f32 ([`PacketSink::take`]).
    #[inline(always)]
    fn take_precise(&mut self, tri: &PreciseTriangle) {
        self.take(&tri.rounded);
    }
    /// Takes lanes `tris` of `block` for ray lane `lane` alone, where that is done in one
    /// pass and decides the lane ([`PacketNearest::offer_block_to_lane`]); otherwise
    /// nothing changes and the answer is false.
    #[inline(always)]
    fn take_block_for_lane(&mut self, _block: &OriginBlock, _tris: u32, _lane: usize) -> bool {
        false
    }
}

impl<V: LaneOps> PacketLimits<V> for PacketNearest<V> {
    #[inline(always)]
    fn live(&self) -> u32 {
        !self.ambiguous() & V::full()
    }
    #[inline(always)]
    fn limit(&self) -> V {
        // The nearest hit's bound plus the culling margin of `bvh` (∞ while none).
        let reach = self.reach();
        let inf = V::splat(f32::INFINITY);
        let m = reach + reach.abs() * V::splat(1.0 / 65536.0);
        reach.simd_lt(inf).bitselect(m, inf)
    }
}

impl<V: LaneOps> PacketSink<V> for PacketNearest<V> {
    #[inline(always)]
    fn take(&mut self, tri: &OriginTriangle) {
        self.offer(tri, tri.prim);
    }
    #[inline(always)]
    fn take_decided(&mut self, tri: &OriginTriangle) -> bool {
        self.offer_decided(tri, tri.prim)
    }
    #[inline(always)]
    fn take_precise(&mut self, tri: &PreciseTriangle) {
        self.offer_precise(tri, tri.rounded.prim);
    }
    fn per_ray(&mut self) {
        self.all_ambiguous();
    }
    #[inline(always)]
    fn take_block_for_lane(&mut self, block: &OriginBlock, tris: u32, lane: usize) -> bool {
        self.offer_block_to_lane(block, tris, BlockIds::Prims, lane)
    }
}

impl<V: Lanes> PacketLimits<V> for ShadowPacket<V> {
    #[inline(always)]
    fn live(&self) -> u32 {
        ShadowPacket::live(self)
    }
    #[inline(always)]
    fn limit(&self) -> V {
        V::splat(1.0 + 1.0 / 65536.0)
    }
}

impl<V: Lanes> PacketSink<V> for ShadowPacket<V> {
    #[inline(always)]
    fn take(&mut self, tri: &OriginTriangle) {
        self.offer(tri);
    }
    #[inline(always)]
    fn take_decided(&mut self, tri: &OriginTriangle) -> bool {
        self.offer_decided(tri)
    }
    fn per_ray(&mut self) {
        self.all_unsure();
    }
}
