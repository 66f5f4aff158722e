//! A leaf's triangles prepared for the rays' origin ([`Bvh::leaf_triangles`]): from a list
//! prepared beforehand, from a frame's cache of blocks of 8, or prepared as met (from the
//! triangles or from the leaf's distinct vertices), and in f64 for the lanes f32 leaves
//! undecided ([`Bvh::precise`]).

use super::leaf_vertices::LeafCorners;
use super::{Bvh, MAX_LEAF, QUAD_LEAF};
use crate::accel::packet::{quad_indices, OriginBlock, OriginTriangle, PreciseTriangle};
use crate::accel::prepared::{LeafCache, Prepared, Reached, BLOCK};
use crate::math::lanes::Lanes;

/// A leaf's triangles prepared for a walk's origin: a run of a full list, a leaf prepared as
/// met (lanes 0 to `len` − 1 of `block`; a leaf of at most 4 again from lane 4 on:
/// [`Bvh::prepare_leaf`]), or
/// `len` lanes of one block or two from lane `start` on (a leaf across two of a cache's
/// blocks).
#[derive(Clone, Copy)]
pub(super) enum LeafTriangles<'q> {
    Listed(&'q [OriginTriangle]),
    Leaf {
        block: &'q OriginBlock,
        len: usize,
    },
    Blocks {
        blocks: [&'q OriginBlock; 2],
        start: usize,
        len: usize,
    },
}

impl LeafTriangles<'_> {
    #[cfg(feature = "unit-tests")]
    pub(super) fn len(&self) -> usize {
        match self {
            LeafTriangles::Listed(list) => list.len(),
            LeafTriangles::Leaf { len, .. } | LeafTriangles::Blocks { len, .. } => *len,
        }
    }

    /// The leaf's `j`th triangle. (The packet visits match on the kind outside their loops
    /// instead: one loop over both kinds kept a pointer per field, 9% more instructions.)
    #[inline(always)]
    pub(super) fn get(&self, j: usize) -> OriginTriangle {
        match self {
            LeafTriangles::Listed(list) => list[j],
            LeafTriangles::Leaf { block, .. } => block.get(j),
            LeafTriangles::Blocks { blocks, start, .. } => block_lane(blocks, *start, j),
        }
    }
}

/// The `j`th lane from `start` on of the blocks `[lo, hi]` (`hi` past lane 7).
#[inline(always)]
pub(super) fn block_lane(blocks: &[&OriginBlock; 2], start: usize, j: usize) -> OriginTriangle {
    // (One `get` at a computed block and lane: a `get` per block merged each field's
    // address from two, a register each.)
    let l = start + j;
    blocks[(l / BLOCK) & 1].get(l % BLOCK)
}

impl Bvh {
    /// The triangles `start..end` (at most 8; positions in the hierarchy's order) prepared
    /// for `o` in `V`'s lanes ([`OriginTriangle::new8`]); a short block repeats its last
    /// triangle. (Plain indexing into the lanes, no closures or iterators over them: in the
    /// AVX2 kernels those stayed calls, and their lane operations with them.)
    #[inline(always)]
    pub(super) fn prepare_block<V: Lanes>(
        &self,
        start: usize,
        end: usize,
        o: [f32; 3],
        out: &mut OriginBlock,
    ) {
        let last = end - 1;
        let i: [usize; BLOCK] = std::array::from_fn(|j| (start + j).min(last));
        let t = &self.tris;
        let p = &self.prims;
        OriginTriangle::new8::<V>(
            [
                &t[i[0]], &t[i[1]], &t[i[2]], &t[i[3]], &t[i[4]], &t[i[5]], &t[i[6]], &t[i[7]],
            ],
            o,
            [
                p[i[0]], p[i[1]], p[i[2]], p[i[3]], p[i[4]], p[i[5]], p[i[6]], p[i[7]],
            ],
            out,
        );
    }

    /// The leaf `first..end` (at most 4 triangles) prepared for `o` as lanes 0–3 of a block
    /// (lanes 4–7 repeat them: their coordinates are gathered once, 4 lanes at a time).
    #[inline(always)]
    fn prepare_leaf<V: Lanes>(&self, first: usize, end: usize, o: [f32; 3], out: &mut OriginBlock) {
        let [i0, i1, i2, i3] = quad_indices(first, end);
        let t = &self.tris;
        let p = &self.prims;
        let (t, p) = (
            [&t[i0], &t[i1], &t[i2], &t[i3]],
            [p[i0], p[i1], p[i2], p[i3]],
        );
        OriginTriangle::new8::<V>(
            [t[0], t[1], t[2], t[3], t[0], t[1], t[2], t[3]],
            o,
            [p[0], p[1], p[2], p[3], p[0], p[1], p[2], p[3]],
            out,
        );
    }

    /// The leaf `first..end` prepared for `o` from its distinct vertices `corners`, in the
    /// lanes [`Bvh::prepare_leaf`] (at most 4 triangles) or [`Bvh::prepare_block`] would
    /// put it, with the same bits.
    #[inline(always)]
    fn prepare_corners<V: Lanes>(
        &self,
        corners: LeafCorners<'_>,
        first: usize,
        end: usize,
        o: [f32; 3],
        out: &mut OriginBlock,
    ) {
        let len = end - first;
        let j: [usize; BLOCK] = match len <= QUAD_LEAF {
            true => {
                let quad = quad_indices(0, len);
                std::array::from_fn(|l| quad[l % 4])
            }
            false => std::array::from_fn(|l| l.min(len - 1)),
        };
        let p = &self.prims[first..end];
        OriginTriangle::new8_from::<V>(
            &corners.in_lanes(j),
            o,
            [
                p[j[0]], p[j[1]], p[j[2]], p[j[3]], p[j[4]], p[j[5]], p[j[6]], p[j[7]],
            ],
            out,
        );
    }

    /// The triangle at `position` prepared for `o` in f64 ([`PreciseTriangle`]), for the
    /// rays the f32 preparation of [`Bvh::prepare_block`] leaves undecided (rare: out of the
    /// way of the kernels).
    #[cold]
    #[inline(never)]
    pub(super) fn precise(&self, position: usize, o: [f32; 3]) -> PreciseTriangle {
        PreciseTriangle::new(&self.tris[position], o, self.prims[position])
    }

    /// The leaf `first..end`'s triangles prepared for `o`: from `prepared`, or prepared into
    /// `scratch` (a leaf holds at most [`MAX_LEAF`] = 8: a block).
    #[inline(always)]
    pub(super) fn leaf_triangles<'q, V: Lanes>(
        &self,
        prepared: Prepared<'q>,
        first: usize,
        end: usize,
        o: [f32; 3],
        scratch: &'q mut Option<OriginBlock>,
    ) -> LeafTriangles<'q> {
        debug_assert!(end - first <= MAX_LEAF);
        let len = end - first;
        match prepared {
            Prepared::All(list) => LeafTriangles::Listed(&list.tris[first..end]),
            Prepared::AsMet => {
                let block = scratch.get_or_insert_with(OriginBlock::default);
                let shared = self.leaf_vertices.as_ref().and_then(|v| v.leaf(first, end));
                match shared {
                    Some(corners) => self.prepare_corners::<V>(corners, first, end, o, block),
                    None if len <= QUAD_LEAF => self.prepare_leaf::<V>(first, end, o, block),
                    None => self.prepare_block::<V>(first, end, o, block),
                }
                LeafTriangles::Leaf { block, len }
            }
            Prepared::Once(cache) => {
                let (b0, b1) = (first / BLOCK, (end - 1) / BLOCK);
                let lo = self.cached_block::<V>(cache, b0, o);
                let hi = match b0 == b1 {
                    true => lo,
                    false => self.cached_block::<V>(cache, b1, o),
                };
                LeafTriangles::Blocks {
                    blocks: [lo, hi],
                    start: first - b0 * BLOCK,
                    len,
                }
            }
        }
    }

    /// Block `block` of the triangles (positions `BLOCK·block..`) prepared for `o`: from
    /// `cache`, or prepared now and kept there.
    #[inline(always)]
    fn cached_block<'c, V: Lanes>(
        &self,
        cache: &'c LeafCache,
        block: usize,
        o: [f32; 3],
    ) -> &'c OriginBlock {
        if let Some(ready) = cache.block(block) {
            return ready;
        }
        match cache.reach(block) {
            Reached::Ready(ready) => ready,
            Reached::Claimed(mut claim) => {
                let start = block * BLOCK;
                let end = self.tris.len().min(start + BLOCK);
                self.prepare_block::<V>(start, end, o, claim.block());
                claim.ready()
            }
        }
    }
}
