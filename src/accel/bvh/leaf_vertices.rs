//! Each leaf's distinct vertices, kept beside a dense mesh's triangles for preparing its
//! leaves as met. Eight neighbouring triangles of a fine mesh share about 8 vertices, not 24
//! (the 1M-triangle mesh: 7.8 distinct vertices in a leaf of 6.1 triangles on average), so a
//! leaf's corners and vertices take 22 bytes a triangle (4 for the corners, 18 for the
//! places) instead of 36: a walk that waits on memory for each leaf it meets waits on fewer
//! cache lines, and a frame's leaves fit the caches better (the 1M mesh: 23.6 MB instead of
//! 38.7 MB, beside a 32 MB L3). They are kept beside the triangles, which every other
//! reader (per-ray queries, a frame's cache, the exact fallbacks) goes on using.
//!
//! Leaf `first..end` owns the vertex places `place(first)..place(end)`, 3 for every 2
//! triangles: where a leaf's vertices are follows from its position, with no lookup in
//! between. A leaf with more distinct vertices than places (1.5% of the 1M mesh's
//! triangles, in leaves of scattered or lone triangles) is marked spilled and prepared from
//! the triangles themselves. Vertices are told apart by their bits, so a corner read from
//! here is the very number the triangle holds.

use super::MAX_LEAF;
use crate::accel::packet::TriangleLanes;
use rayon::prelude::*;

/// The first vertex place of the leaf that starts at `position` (3 per 2 triangles).
#[inline(always)]
pub(super) const fn place(position: usize) -> usize {
    position * 3 / 2
}

/// Bytes of a place: a vertex's 3 coordinates.
const PLACE: usize = 12;

/// Bytes from a leaf's first place that a corner's byte offset (a `u8`) and its three
/// coordinates can reach: any leaf's are one bounds-checked array, and its reads need no
/// checks.
const REACH: usize = 256 + PLACE;
const _: () = assert!(PLACE * place(MAX_LEAF) <= 256);

/// A corner word's fourth byte where its leaf's vertices did not fit its places (otherwise
/// the byte is the triangle's place in its leaf, from 0).
const SPILLED: u8 = 0x80;

/// The leaves' distinct vertices, and each triangle's corners among its leaf's.
#[derive(Clone, Debug, Default)]
pub(super) struct LeafVertices {
    /// Per triangle position: its corners' byte offsets from its leaf's first place, and its
    /// place in the leaf (or [`SPILLED`]). [`MAX_LEAF`] more at the end, so that any leaf's
    /// words are a whole `[[u8; 4]; MAX_LEAF]`.
    corners: Vec<[u8; 4]>,
    /// The places, `PLACE` bytes each (native-endian f32s); [`REACH`] more at the end (see
    /// `corners`).
    bytes: Vec<u8>,
}

/// One leaf's corners and places, with the leaf's triangle (from 0) in each of 8 lanes.
#[derive(Clone, Copy)]
pub(super) struct LeafCorners<'a> {
    corners: &'a [[u8; 4]; MAX_LEAF],
    places: &'a [u8; REACH],
    lanes: [usize; 8],
}

impl LeafCorners<'_> {
    /// The same leaf with triangle `lanes[l]` in lane l.
    #[inline(always)]
    pub(super) fn in_lanes(self, lanes: [usize; 8]) -> Self {
        Self { lanes, ..self }
    }
}

impl TriangleLanes for LeafCorners<'_> {
    #[inline(always)]
    fn coordinate(&self, l: usize, j: usize, k: usize) -> f32 {
        let at = self.corners[self.lanes[l] % MAX_LEAF][j] as usize + 4 * k;
        f32::from_ne_bytes([
            self.places[at],
            self.places[at + 1],
            self.places[at + 2],
            self.places[at + 3],
        ])
    }
}

impl LeafVertices {
    /// The leaves' vertices of `tris` (in the hierarchy's order), whose leaves
    /// `(first, count)` are `leaves`, sorted by `first` and covering every position.
    pub(super) fn new(tris: &[[[f32; 3]; 3]], leaves: &[(usize, usize)]) -> Self {
        let n = tris.len();
        let mut corners = vec![[0u8; 4]; n + MAX_LEAF];
        let mut bytes = vec![0u8; PLACE * place(n) + REACH];
        // Each leaf's own part of both arrays, filled in parallel.
        let mut parts = Vec::with_capacity(leaves.len());
        let (mut corners_left, mut bytes_left) =
            (&mut corners[..n], &mut bytes[..PLACE * place(n)]);
        let mut next = 0;
        for &(first, count) in leaves {
            assert_eq!(first, next, "leaves out of order");
            next = first + count;
            let (c, rest) = std::mem::take(&mut corners_left).split_at_mut(count);
            corners_left = rest;
            let places = PLACE * (place(next) - place(first));
            let (p, rest) = std::mem::take(&mut bytes_left).split_at_mut(places);
            bytes_left = rest;
            parts.push((&tris[first..next], c, p));
        }
        assert_eq!(next, n, "leaves miss positions");
        parts
            .into_par_iter()
            .for_each(|(tris, corners, places)| fill(tris, corners, places));
        Self { corners, bytes }
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        self.corners.len() * 4 + self.bytes.len()
    }

    /// The corners of positions `first..end`, one leaf's from its first triangle on (that
    /// triangle in every lane), unless the leaf spilled; `None` too for any other run (a
    /// walk that offers every triangle goes by runs of [`MAX_LEAF`]).
    #[inline(always)]
    pub(super) fn leaf(&self, first: usize, end: usize) -> Option<LeafCorners<'_>> {
        let corners: &[[u8; 4]; MAX_LEAF] =
            self.corners[first..first + MAX_LEAF].try_into().ok()?;
        let last = end - first - 1;
        if corners[0][3] != 0 || corners[last % MAX_LEAF][3] as usize != last {
            return None;
        }
        let at = PLACE * place(first);
        let places = self.bytes[at..at + REACH].try_into().ok()?;
        Some(LeafCorners {
            corners,
            places,
            lanes: [0; 8],
        })
    }

    /// Where the leaf `first..first + count`'s data lies: its corner words and its places,
    /// as (address, bytes) (for prefetches).
    #[inline(always)]
    pub(super) fn spans(&self, first: usize, count: usize) -> [(*const i8, usize); 2] {
        let (at, end) = (place(first), place(first + count));
        [
            (self.corners.as_ptr().wrapping_add(first).cast(), 4 * count),
            (
                self.bytes.as_ptr().wrapping_add(PLACE * at).cast(),
                PLACE * (end - at),
            ),
        ]
    }
}

/// One leaf's corner words and places (`PLACE` bytes each), from its triangles (all
/// [`SPILLED`] where its distinct vertices outnumber the places).
fn fill(tris: &[[[f32; 3]; 3]], corners: &mut [[u8; 4]], places: &mut [u8]) {
    let room = places.len() / PLACE;
    let mut kept = [[0u32; 3]; 256 / PLACE];
    let mut used = 0;
    for (t, tri) in tris.iter().enumerate() {
        for (j, v) in tri.iter().enumerate() {
            let bits = v.map(f32::to_bits);
            let at = match kept[..used].iter().position(|p| *p == bits) {
                Some(at) => at,
                None if used < room => {
                    for (k, x) in v.iter().enumerate() {
                        let b = PLACE * used + 4 * k;
                        places[b..b + 4].copy_from_slice(&x.to_ne_bytes());
                    }
                    kept[used] = bits;
                    used += 1;
                    used - 1
                }
                None => {
                    corners.fill([0, 0, 0, SPILLED]);
                    return;
                }
            };
            corners[t][j] = (PLACE * at) as u8;
        }
        corners[t][3] = t as u8;
    }
}
