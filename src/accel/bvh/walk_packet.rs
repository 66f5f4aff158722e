//! The walks of 8 (or 16) rays from one origin: the nearest-hit and shadow queries of a packet
//! ([`Bvh::closest_packet`], [`Bvh::any_packet`], [`Bvh::walk_into`]), the walk they
//! share ([`Bvh::walk_packet`]) and its loop over the wide nodes ([`Bvh::walk_wide`]).

use super::child_test::{push_lane, ChildTest, IntervalTest, LaneSlabs, LaneTest};
use super::leaves::{Leaves, OwnLeaves, PositionLeaves};
use super::node::{leaf_range, WideNode, WideStack, LEAF, NONE};
use super::slabs::{box_safe, PacketSlabs};
use super::{Bvh, MAX_LEAF};
use crate::accel::packet::{
    OriginTriangle, OriginTriangles, PacketHits, PacketLimits, PacketNearest, PacketSeed,
    PacketSink, ShadowHits, ShadowPacket,
};
use crate::accel::prepared::Prepared;
use crate::math::lanes::{f32x8, LaneOps, Lanes};
use crate::math::simd::{avx512_avx2_or_baseline, each3, with_cpu_isa, Isa};

impl Bvh {
    /// Walks the hierarchy with 8 rays from one origin (`slabs`), every box widened by `pad`
    /// (see [`Bvh::traverse`]): a node is entered while its box meets one of `sink`'s live
    /// lanes before that lane's limit; `leaves` visits a leaf's items, nearer children first.
    /// Untrusted slabs visit every item.
    #[inline(always)]
    pub(crate) fn walk_packet<V: LaneOps, S: PacketLimits<V>, L: Leaves<V, S>>(
        &self,
        slabs: &PacketSlabs<V>,
        pad: f32,
        sink: &mut S,
        leaves: &mut L,
    ) {
        let stack = &mut WideStack::new();
        self.walk_packet_on::<_, _, _, false>(slabs, pad, sink, leaves, stack, !0)
    }

    /// [`Bvh::walk_packet`] for the lanes of `only`, where a node only one lane entered has
    /// its subtree walked for that lane alone (8 boxes per test; the root too, if `only` has
    /// one live lane), on `stack` (its entries are not kept): instances'
    /// meshes, where 56% of the node visits at 320×180 are one lane's (the bunny field),
    /// walked many times per packet. On the meshes' own hierarchies the lone walk cost more
    /// than it saved (bunny 1280×720 +2.2%, Igea 640×360 +0.7%; −2.8% on Igea at 320×180).
    #[inline(always)]
    pub(crate) fn walk_packet_lone<V: LaneOps, S: PacketLimits<V>, L: Leaves<V, S>>(
        &self,
        slabs: &PacketSlabs<V>,
        pad: f32,
        sink: &mut S,
        leaves: &mut L,
        stack: &mut WideStack,
        only: u32,
    ) {
        self.walk_packet_on::<_, _, _, true>(slabs, pad, sink, leaves, stack, only)
    }

    #[inline(always)]
    fn walk_packet_on<V: LaneOps, S: PacketLimits<V>, L: Leaves<V, S>, const LONE: bool>(
        &self,
        slabs: &PacketSlabs<V>,
        pad: f32,
        sink: &mut S,
        leaves: &mut L,
        stack: &mut WideStack,
        only: u32,
    ) {
        if self.wide.is_empty() {
            return;
        }
        if !(slabs.trusted && box_safe(pad)) {
            // Every item, in leaf-sized runs (a leaf visit prepares at most `MAX_LEAF`
            // triangles: one visit of all of them served only the first and last blocks of
            // a frame's cache, and the rest went untested).
            for first in (0..self.prims.len()).step_by(MAX_LEAF) {
                let count = MAX_LEAF.min(self.prims.len() - first);
                leaves.visit(sink, first, count, sink.live() & only);
            }
            return;
        }
        // (A lone walk is a placed mesh's, whose pad is never 0: the padded test serves a 0
        // as well, and one variant fewer is compiled.)
        match (slabs.coherent, pad == 0.0 && !LONE) {
            (Some(near_hi), true) => {
                let test = IntervalTest::<V, false>::new(slabs, near_hi, 0.0);
                self.walk_wide::<_, _, _, _, LONE>(&test, sink, leaves, stack, only)
            }
            (Some(near_hi), false) => {
                let test = IntervalTest::<V, true>::new(slabs, near_hi, pad);
                self.walk_wide::<_, _, _, _, LONE>(&test, sink, leaves, stack, only)
            }
            (None, _) => {
                let test = LaneTest { rays: slabs, pad };
                self.walk_wide::<_, _, _, _, LONE>(&test, sink, leaves, stack, only)
            }
        }
    }

    /// Camera rays 8 at a time from the origin `o` (directions `d`, `d_max` ≥ every |dₖ|):
    /// the nearest triangle per lane as [`super::packet::closest`] over all triangles would
    /// decide it, as its position in the hierarchy's order ([`Bvh::triangles`]; `prim` of
    /// the result; u32::MAX for none), or ambiguous (to be traced per ray). The triangles
    /// come from `prepared` (made for `o`) or, without it, are prepared as the leaves are
    /// reached.
    ///
    /// Packet traversal: a node is entered while its box meets some lane that is not yet
    /// ambiguous, nearer than that lane's [`PacketNearest::reach`] (with the margin of the
    /// module docs); the child whose box the packet's first live lane enters first is visited
    /// first, and a popped node is tested again against the nearer hits found meanwhile.
    /// Every triangle a lane can hit nearer than its best so far is offered to it, so its
    /// answer is the one of the whole list.
    ///
    /// [`super::packet::closest`]: crate::accel::packet::closest
    pub fn closest_packet(
        &self,
        o: [f32; 3],
        prepared: Option<&OriginTriangles>,
        d: &[f32x8; 3],
        d_max: f32,
    ) -> PacketHits {
        self.closest_packet_seeded(o, prepared, d, d_max, None)
    }

    /// [`Bvh::closest_packet`] starting from `seed` ([`PacketNearest::seeded`]; its ids must
    /// not be slots of this BVH).
    pub fn closest_packet_seeded(
        &self,
        o: [f32; 3],
        prepared: Option<&OriginTriangles>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        let prepared = Prepared::from_list(prepared);
        with_cpu_isa!(|isa| self.closest_packet_from(isa, o, prepared, d, d_max, seed))
    }

    /// [`Bvh::closest_packet_seeded`] with the triangles from `prepared`, in the build `isa`
    /// names.
    #[inline(always)]
    pub(crate) fn closest_packet_from<I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        let bvh = self;
        avx512_avx2_or_baseline!(token isa, lanes Bvh::closest_packet_body => (
            bvh: &Bvh,
            o: [f32; 3],
            prepared: Prepared<'_>,
            d: &[f32x8; 3],
            d_max: f32,
            seed: Option<&PacketSeed>
        ) -> PacketHits)
    }

    #[inline(always)]
    fn closest_packet_body<V: Lanes>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        let mut nearest = PacketNearest::<V>::seeded(d, d_max, seed);
        self.walk_closest(o, prepared, each3(|k| V::from_wide(d[k])), &mut nearest);
        nearest.finish()
    }

    /// [`Bvh::closest_packet_from`] (no seed) inside a kernel already in lanes `V` of any
    /// width (the AVX-512 tile loop's 16 camera rays): positions in the hierarchy's order
    /// into `prim[..V::WIDTH]`, the ambiguous lanes returned.
    #[inline(always)]
    pub(crate) fn closest_positions_in<V: LaneOps>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
        d_max: f32,
        prim: &mut [u32],
    ) -> u32 {
        let mut nearest = PacketNearest::<V>::new_in(d, d_max);
        self.walk_closest(o, prepared, d, &mut nearest);
        nearest.finish_into(prim)
    }

    /// Offers `nearest` (rays from `o`, directions `d`) every triangle its lanes may reach.
    #[inline(always)]
    fn walk_closest<V: LaneOps>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
        nearest: &mut PacketNearest<V>,
    ) {
        if self.wide.is_empty() {
            return;
        }
        if !prepared.fits(o, self.tris.len()) {
            return nearest.all_ambiguous();
        }
        let rays = PacketSlabs::<V>::new_in(o, d, self.tame);
        if !rays.trusted {
            return self.closest_packet_untrusted(nearest, o, prepared);
        }
        let mut leaves = PositionLeaves {
            bvh: self,
            o,
            prepared,
            scratch: None,
        };
        self.walk_packet(&rays, 0.0, nearest, &mut leaves);
    }

    /// [`Bvh::closest_packet`] where the f32 slab test cannot be trusted: every triangle.
    #[cold]
    #[inline(never)]
    fn closest_packet_untrusted<V: LaneOps>(
        &self,
        nearest: &mut PacketNearest<V>,
        o: [f32; 3],
        prepared: Prepared<'_>,
    ) {
        for i in 0..self.tris.len() {
            match prepared {
                Prepared::All(p) => nearest.offer(&p.tris[i], i as u32),
                _ => nearest.offer(
                    &OriginTriangle::new(&self.tris[i], o, self.prims[i]),
                    i as u32,
                ),
            }
        }
    }

    /// [`Bvh::any_packet`] where the f32 slab test cannot be trusted: every triangle.
    #[cold]
    #[inline(never)]
    fn any_packet_untrusted<V: Lanes>(
        &self,
        mut packet: ShadowPacket<V>,
        o: [f32; 3],
        prepared: Prepared<'_>,
    ) -> ShadowHits {
        for i in 0..self.tris.len() {
            match prepared {
                Prepared::All(p) => packet.offer(&p.tris[i]),
                _ => packet.offer(&OriginTriangle::new(&self.tris[i], o, self.prims[i])),
            }
        }
        packet.finish()
    }

    /// Offers to `sink` (a nearest-hit or shadow state, maybe shared with other structures,
    /// the instances) every triangle the rays from `o` may reach before their limits, from
    /// `prepared` (made for `o`) or prepared as met: [`Bvh::closest_packet`] and
    /// [`Bvh::any_packet`] with lanes recording primitive indices, not positions (this
    /// layout's [`Layout::packet_into`](crate::accel::layout::Layout::packet_into)).
    #[inline(always)]
    pub(super) fn walk_into<V: LaneOps, S: PacketSink<V>>(
        &self,
        sink: &mut S,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
    ) {
        let prepared = match prepared.fits(o, self.tris.len()) {
            true => prepared,
            false => Prepared::AsMet,
        };
        let slabs = PacketSlabs::<V>::new_in(o, d, self.tame);
        let mut leaves = OwnLeaves {
            bvh: self,
            o,
            prepared,
            scratch: None,
        };
        self.walk_packet(&slabs, 0.0, sink, &mut leaves);
    }

    /// Eight shadow segments from one origin `o` (the light) through the BVH, directions `d`
    /// (`d_max` ≥ every |dₖ|): per lane of `valid`, blocked for 0 < t < 1 by a triangle other
    /// than its `skip` primitive, or unsure (to be traced per ray); see
    /// [`crate::accel::packet::any`]. `prepared`: the triangles prepared for
    /// `o` (in the BVH's order), or `None` to prepare them as the packet meets them. Boxes are
    /// entered up to t = 1 + 2⁻¹⁶ (the culling margin of the module docs).
    pub fn any_packet(
        &self,
        o: [f32; 3],
        prepared: Option<&OriginTriangles>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> ShadowHits {
        let prepared = Prepared::from_list(prepared);
        with_cpu_isa!(|isa| self.any_packet_from(isa, o, prepared, d, d_max, skip, valid))
    }

    /// [`Bvh::any_packet`] with the triangles from `prepared`, in the build `isa` names.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn any_packet_from<I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> ShadowHits {
        let bvh = self;
        avx512_avx2_or_baseline!(token isa, lanes Bvh::any_packet_body => (
            bvh: &Bvh,
            o: [f32; 3],
            prepared: Prepared<'_>,
            d: &[f32x8; 3],
            d_max: f32,
            skip: &[u32; 8],
            valid: u32
        ) -> ShadowHits)
    }

    #[inline(always)]
    fn any_packet_body<V: Lanes>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> ShadowHits {
        let mut packet = ShadowPacket::<V>::new(d, d_max, skip, valid);
        if self.wide.is_empty() {
            return packet.finish();
        }
        if !prepared.fits(o, self.tris.len()) {
            return ShadowHits {
                blocked: 0,
                unsure: valid,
            };
        }
        let rays = PacketSlabs::<V>::new(o, d, self.tame);
        if !rays.trusted {
            return self.any_packet_untrusted(packet, o, prepared);
        }
        let mut leaves = OwnLeaves {
            bvh: self,
            o,
            prepared,
            scratch: None,
        };
        self.walk_packet(&rays, 0.0, &mut packet, &mut leaves);
        packet.finish()
    }
}

/// The greatest of `limits` over the lanes of `live` (−∞ for none).
#[inline(always)]
fn widest<V: LaneOps>(limits: V, live: u32) -> f32 {
    // Branch-free: the dead lanes set to −∞, then the lanes' greatest (the filtered fold it
    // replaces was 6% of a field frame's instructions). No limit is NaN: limits are ∞ or a
    // finite hit's bound.
    V::from_bitmask(live)
        .bitselect(limits, V::splat(f32::NEG_INFINITY))
        .reduce_max()
}

impl Bvh {
    /// Walks the hierarchy with 8 rays from one origin: offers `sink` (through `leaves`)
    /// every leaf some live lane of `only` may reach before its limit, as `test` decides,
    /// nearer children first; the other lanes take no part. (No closures: everything here
    /// must inline into the caller's AVX2 build.)
    #[inline(always)]
    pub(super) fn walk_wide<
        V: LaneOps,
        S: PacketLimits<V>,
        L: Leaves<V, S>,
        T: ChildTest<V>,
        const LONE: bool,
    >(
        &self,
        test: &T,
        sink: &mut S,
        leaves: &mut L,
        stack: &mut WideStack,
        only: u32,
    ) {
        let mut live = sink.live() & only;
        if self.wide.is_empty() || live == 0 {
            return;
        }
        let mut reach = sink.limit();
        let mut limit = widest(reach, live);
        let mut top = 0;
        // The root, then what the stack gives: one place each for a node, a lone lane's
        // subtree and a leaf (each inlines its whole walk or visit).
        let mut next = Some((0, live));
        loop {
            let (r, lanes) = match next.take() {
                Some(entry) => entry,
                None => {
                    if live == 0 {
                        return;
                    }
                    let r = stack.pop_above(0, &mut top, limit);
                    if r == NONE {
                        return;
                    }
                    if let Some(next) = stack.top_above(0, top) {
                        self.prefetch(next);
                    }
                    (r, stack.lanes_at(top) & live)
                }
            };
            if r & LEAF == 0 {
                if !(LONE && lanes.is_power_of_two()) {
                    test.push(&self.wide[r as usize], reach, live, limit, stack, &mut top);
                    continue;
                }
                self.walk_lane(test, sink, leaves, (r as usize, lanes), (stack, top));
            } else {
                let (first, count) = leaf_range(r);
                leaves.visit(sink, first, count, lanes);
            }
            live = sink.live() & only;
            reach = sink.limit();
            limit = widest(reach, live);
        }
    }

    /// Asks the CPU to bring in stack entry `r`'s data (a node's boxes, or a leaf's
    /// triangles) while the entry popped before it is worked on: a mesh whose hierarchy and
    /// triangles outgrow the caches waits on each node and leaf as the walk reaches it.
    #[inline(always)]
    fn prefetch(&self, r: u32) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            let spans: [(*const i8, usize); 2] = match r & LEAF == 0 {
                true => [
                    (
                        self.wide.as_ptr().wrapping_add(r as usize).cast(),
                        std::mem::size_of::<WideNode>(),
                    ),
                    (std::ptr::null(), 0),
                ],
                false => {
                    let (first, count) = leaf_range(r);
                    match &self.leaf_vertices {
                        Some(v) => v.spans(first, count),
                        None => [
                            (
                                self.tris.as_ptr().wrapping_add(first).cast(),
                                count * std::mem::size_of::<[[f32; 3]; 3]>(),
                            ),
                            (std::ptr::null(), 0),
                        ],
                    }
                }
            };
            for (p, bytes) in spans {
                // Every cache line the bytes touch: from the line of the first byte (a leaf's
                // triangles, 36 bytes each, seldom start on a line) to that of the last.
                let mut at = 0;
                let end = (p as usize % 64) + bytes;
                while at < end {
                    // SAFETY: a prefetch only hints the cache; it never reads or faults,
                    // whatever the address (and SSE is part of x86-64).
                    #[allow(unsafe_code)]
                    unsafe {
                        _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(at))
                    };
                    at += 64;
                }
            }
        }
    }

    /// [`Bvh::walk_wide`] below node `root`, which only lane `lane` (a one-bit mask) of the
    /// packet entered: its subtree for that lane alone, 8 boxes per test
    /// ([`push_lane`]), its leaves offered to that lane, until the lane is decided
    /// or the subtree is done. Uses `stack` above its first `base` entries and leaves those
    /// as they were.
    #[inline(always)]
    fn walk_lane<V: LaneOps, S: PacketLimits<V>, L: Leaves<V, S>, T: ChildTest<V>>(
        &self,
        test: &T,
        sink: &mut S,
        leaves: &mut L,
        (root, lane): (usize, u32),
        (stack, base): (&mut WideStack, usize),
    ) {
        let at = lane.trailing_zeros() as usize;
        let packet = test.slabs();
        let slabs = LaneSlabs::of(packet.0, at);
        let mut top = base;
        let mut reach = sink.limit().lane(at);
        let mut node = root;
        loop {
            push_lane(packet, &self.wide[node], &slabs, reach, stack, &mut top);
            loop {
                let r = stack.pop_above(base, &mut top, reach);
                if r == NONE {
                    return;
                }
                if let Some(next) = stack.top_above(base, top) {
                    self.prefetch(next);
                }
                if r & LEAF == 0 {
                    node = r as usize;
                    break;
                }
                let (first, count) = leaf_range(r);
                leaves.visit(sink, first, count, lane);
                if sink.live() & lane == 0 {
                    return;
                }
                reach = sink.limit().lane(at);
            }
        }
    }
}
