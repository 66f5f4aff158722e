//! Where a BVH walk gets a leaf's triangles prepared for its rays' shared origin
//! ([`OriginTriangle`]): prepared beforehand, prepared at every visit, or prepared once per
//! frame by the first thread that reaches them ([`LeafCache`]).
//!
//! A frame reaches only part of a mesh: at the framing camera of `raylab bench`, the bunny's
//! flat frame at 640×360 reaches 28k of its 69k triangles (59k times), at 1280×720 31k
//! (147k times); Igea at 1280×720 118k of 269k (220k times). Preparing all of them beforehand
//! does work for triangles no ray meets; preparing at every visit repeats it. The cache
//! prepares each reached block of 8 positions once.
//!
//! Why blocks of 8 in one flat array (callgrind, bunny flat 640×360 against preparing all
//! beforehand): per leaf, a quad of 4 lanes for leaves of 1 to 4 triangles wasted lanes
//! (+1.2% instructions); blocks in lazily allocated chunks cost a second lookup per leaf
//! visit and a copy for leaves across two blocks (−6.5%); one flat array, with a leaf across
//! two blocks handed on as two slices, gave −11.9%.

use super::packet::{OriginBlock, OriginTriangles};
use std::fmt;
use std::sync::{Mutex, OnceLock};

/// How a BVH walk gets a leaf's triangles prepared for the rays' origin.
#[derive(Clone, Copy)]
pub(crate) enum Prepared<'a> {
    /// Prepared again at every visit.
    AsMet,
    /// All of them, prepared beforehand in the hierarchy's order.
    All(&'a OriginTriangles),
    /// Once per frame each, by the first thread to reach the leaf.
    Once(&'a LeafCache),
}

impl<'a> Prepared<'a> {
    /// A full list if there is one, else as met.
    pub(crate) fn from_list(list: Option<&'a OriginTriangles>) -> Self {
        match list {
            Some(p) => Prepared::All(p),
            None => Prepared::AsMet,
        }
    }

    /// A frame's cache if it has one, else as met.
    pub(crate) fn of(cache: Option<&'a LeafCache>) -> Self {
        match cache {
            Some(c) => Prepared::Once(c),
            None => Prepared::AsMet,
        }
    }

    /// Whether this can serve a walk from `origin` over `len` triangles: a list or cache made
    /// for another origin or hierarchy cannot.
    pub(crate) fn fits(&self, origin: [f32; 3], len: usize) -> bool {
        match self {
            Prepared::AsMet => true,
            Prepared::All(list) => list.origin == origin && list.tris.len() == len,
            Prepared::Once(cache) => cache.origin == origin && cache.len == len,
        }
    }
}

/// Triangle positions per block: the unit a cache prepares (the lanes of
/// [`OriginTriangle::new8`]; a BVH leaf of up to 4 triangles lies in one block or two).
pub(crate) const BLOCK: usize = 8;

/// One frame's triangles prepared for one origin, a block of [`BLOCK`] positions of the
/// hierarchy's order at a time, as the frame's threads first reach them (two threads that
/// reach an unprepared block together both prepare it, and the first stored is kept). Kept
/// from frame to frame ([`CachePool`]) so its memory (about a full list's) is allocated
/// once.
pub(crate) struct LeafCache {
    origin: [f32; 3],
    /// How many triangles the hierarchy has.
    len: usize,
    /// The blocks, in order.
    blocks: Box<[OnceLock<OriginBlock>]>,
}

impl fmt::Debug for LeafCache {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LeafCache")
            .field("origin", &self.origin)
            .field("len", &self.len)
            .finish()
    }
}

impl LeafCache {
    /// A cache for a hierarchy of `len` triangles (no chunk allocated yet).
    fn new(len: usize) -> Self {
        Self {
            origin: [f32::NAN; 3],
            len,
            blocks: (0..len.div_ceil(BLOCK)).map(|_| OnceLock::new()).collect(),
        }
    }

    /// Empties the cache for a frame from `origin`.
    fn reset(&mut self, origin: [f32; 3]) {
        for block in self.blocks.iter_mut() {
            block.take();
        }
        self.origin = origin;
    }

    /// Bytes the cache holds (about as much as a full list of the prepared triangles).
    pub(crate) fn memory_bytes(&self) -> usize {
        self.blocks.len() * size_of::<OnceLock<OriginBlock>>()
    }

    /// Block `block` if it is prepared this frame.
    #[inline(always)]
    pub(crate) fn block(&self, block: usize) -> Option<&OriginBlock> {
        self.blocks[block].get()
    }

    /// Keeps `prepared` as block `block` for the frame, unless another thread kept it first:
    /// the block kept.
    #[inline(never)]
    pub(crate) fn keep(&self, block: usize, prepared: &OriginBlock) -> &OriginBlock {
        self.blocks[block].get_or_init(|| *prepared)
    }
}

/// The caches an accelerator keeps between frames (one per origin a frame prepares for).
/// Cloning gives an empty pool.
#[derive(Default)]
pub(crate) struct CachePool(Mutex<Vec<LeafCache>>);

impl Clone for CachePool {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl fmt::Debug for CachePool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("CachePool")
    }
}

impl CachePool {
    /// An empty cache for `len` triangles and `origin`, reused when one is kept.
    pub(crate) fn take(&self, len: usize, origin: [f32; 3]) -> LeafCache {
        let kept = {
            let mut kept = self.lock();
            let i = kept.iter().position(|c| c.len == len);
            i.map(|i| kept.swap_remove(i))
        };
        let mut cache = kept.unwrap_or_else(|| LeafCache::new(len));
        cache.reset(origin);
        cache
    }

    /// Keeps `cache` for a later frame (at most two: the eye's and the light's).
    pub(crate) fn give(&self, cache: LeafCache) {
        let mut kept = self.lock();
        if kept.len() < 2 {
            kept.push(cache);
        }
    }

    /// Bytes the kept caches hold in use ([`LeafCache::memory_bytes`]).
    pub(crate) fn memory_bytes(&self) -> usize {
        self.lock().iter().map(LeafCache::memory_bytes).sum()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<LeafCache>> {
        // A panic elsewhere while holding the lock leaves the caches whole.
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}
