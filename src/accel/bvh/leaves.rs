//! What a packet walk does at a leaf ([`Leaves`]): offers the leaf's triangles to the
//! packet's state, one block to one lane, a leaf to a few lanes, or one at a time
//! ([`OwnLeaves`], [`PositionLeaves`]).

use super::leaf_triangles::{block_lane, LeafTriangles};
use super::{Bvh, QUAD_LEAF};
use crate::accel::packet::{BlockIds, OriginBlock, PacketNearest, PacketSink};
use crate::accel::prepared::{Prepared, BLOCK};
use crate::math::lanes::LaneOps;

/// What a packet walk does at a leaf: offers the leaf's items to the packet's state.
pub(crate) trait Leaves<V, S> {
    /// Items `first..first + count` of the hierarchy walked, which the lanes `lanes` may
    /// reach (bit l for lane l; the others cannot reach them before their limits).
    fn visit(&mut self, sink: &mut S, first: usize, count: usize, lanes: u32);
}

/// A hierarchy's own triangles, prepared for `o` (or as met).
pub(super) struct OwnLeaves<'a> {
    pub(super) bvh: &'a Bvh,
    pub(super) o: [f32; 3],
    pub(super) prepared: Prepared<'a>,
    /// Where a leaf prepared as met is written (made at the walk's first such leaf).
    pub(super) scratch: Option<OriginBlock>,
}

impl<V: LaneOps, S: PacketSink<V>> Leaves<V, S> for OwnLeaves<'_> {
    #[inline(always)]
    fn visit(&mut self, sink: &mut S, first: usize, count: usize, _: u32) {
        let end = first + count;
        let tris = (self.bvh).leaf_triangles::<V::Eight>(
            self.prepared,
            first,
            end,
            self.o,
            &mut self.scratch,
        );
        match tris {
            LeafTriangles::Listed(list) => {
                // (A loop, not `for_each` with a closure: see `PacketSlabs::new_in`.)
                for t in list {
                    sink.take(t);
                }
            }
            // (A leaf prepared as met is the one block it is written in.)
            LeafTriangles::Leaf { block, len } => {
                (self.bvh).take_each(sink, self.o, &[block, block], 0, first, len)
            }
            LeafTriangles::Blocks { blocks, start, len } => {
                (self.bvh).take_each(sink, self.o, &blocks, start, first, len)
            }
        }
    }
}

/// A hierarchy's own triangles for [`Bvh::closest_packet`]: lanes record positions in the
/// hierarchy's order, not primitive indices.
pub(super) struct PositionLeaves<'a> {
    pub(super) bvh: &'a Bvh,
    pub(super) o: [f32; 3],
    pub(super) prepared: Prepared<'a>,
    /// Where a leaf prepared as met is written (made at the walk's first such leaf).
    pub(super) scratch: Option<OriginBlock>,
}

impl<V: LaneOps> Leaves<V, PacketNearest<V>> for PositionLeaves<'_> {
    #[inline(always)]
    fn visit(&mut self, nearest: &mut PacketNearest<V>, first: usize, count: usize, lanes: u32) {
        let end = first + count;
        let tris = (self.bvh).leaf_triangles::<V::Eight>(
            self.prepared,
            first,
            end,
            self.o,
            &mut self.scratch,
        );
        match tris {
            LeafTriangles::Listed(list) => {
                for (j, tri) in list.iter().enumerate() {
                    nearest.offer(tri, (first + j) as u32);
                }
            }
            LeafTriangles::Leaf { block, len } => {
                let decided = match lanes.count_ones() {
                    1 => {
                        let (tris, base) = ((1 << len) - 1, BlockIds::From(first as u32));
                        nearest.offer_block_to_lane(
                            block,
                            tris,
                            base,
                            lanes.trailing_zeros() as usize,
                        )
                    }
                    // A few lanes: the leaf to them alone, 4 triangles by 2 or 4 rays a pass.
                    // (Two passes of 16 lanes for 5 to 8 lanes were slower than offers one by
                    // one: bunny 640×360, 1 thread, 2.21 against 2.17 ms.)
                    2..=4 if len <= QUAD_LEAF => {
                        nearest.offer_leaf_to_lanes(block, len, first as u32, lanes)
                    }
                    _ => false,
                };
                if !decided {
                    (self.bvh).offer_each(nearest, self.o, &[block, block], 0, first, 0..len);
                }
            }
            LeafTriangles::Blocks { blocks, start, len } => {
                if lanes.count_ones() != 1 {
                    return (self.bvh).offer_each(nearest, self.o, &blocks, start, first, 0..len);
                }
                // One lane: the leaf's part of each block at once.
                let l = lanes.trailing_zeros() as usize;
                let in_first = len.min(BLOCK - start);
                let base = (first - start) as u32;
                let mask = ((1u32 << in_first) - 1) << start;
                if !nearest.offer_block_to_lane(blocks[0], mask, BlockIds::From(base), l) {
                    (self.bvh).offer_each(nearest, self.o, &blocks, start, first, 0..in_first);
                }
                if in_first < len {
                    let mask = (1u32 << (len - in_first)) - 1;
                    let base = base + BLOCK as u32;
                    if !nearest.offer_block_to_lane(blocks[1], mask, BlockIds::From(base), l) {
                        (self.bvh).offer_each(
                            nearest,
                            self.o,
                            &blocks,
                            start,
                            first,
                            in_first..len,
                        );
                    }
                }
            }
        }
    }
}

impl Bvh {
    /// Offers a leaf's triangles `js` (of those from lane `start` of `blocks` on, positions
    /// from `first` on, prepared for `o`) one at a time to every lane, each again as
    /// [`Bvh::precise`] prepares it where it would leave a lane undecided.
    #[inline(always)]
    fn offer_each<V: LaneOps>(
        &self,
        nearest: &mut PacketNearest<V>,
        o: [f32; 3],
        blocks: &[&OriginBlock; 2],
        start: usize,
        first: usize,
        js: std::ops::Range<usize>,
    ) {
        for j in js {
            let id = (first + j) as u32;
            if !nearest.offer_decided(&block_lane(blocks, start, j), id) {
                nearest.offer_precise(&self.precise(first + j, o), id);
            }
        }
    }

    /// [`Bvh::offer_each`] for any sink: the leaf's `len` triangles (from lane `start` of
    /// `blocks` on, positions from `first` on) taken one at a time.
    #[inline(always)]
    fn take_each<V: LaneOps, S: PacketSink<V>>(
        &self,
        sink: &mut S,
        o: [f32; 3],
        blocks: &[&OriginBlock; 2],
        start: usize,
        first: usize,
        len: usize,
    ) {
        for j in 0..len {
            if !sink.take_decided(&block_lane(blocks, start, j)) {
                sink.take_precise(&self.precise(first + j, o));
            }
        }
    }
}
