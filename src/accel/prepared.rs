//! Where a BVH walk gets a leaf's triangles prepared for its rays' shared origin
//! ([`OriginTriangle`](super::packet::OriginTriangle)): prepared beforehand, prepared at
//! every visit, or prepared once per frame by the first thread that reaches them
//! ([`LeafCache`]).
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
use std::cell::UnsafeCell;
use std::fmt;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Mutex;

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
/// [`OriginTriangle::new8`](super::packet::OriginTriangle::new8); a BVH leaf of up to 4
/// triangles lies in one block or two).
pub(crate) const BLOCK: usize = 8;

/// One frame's triangles prepared for one origin, a block of [`BLOCK`] positions of the
/// hierarchy's order at a time, as the frame's threads first reach them (the first thread
/// to reach a block prepares it in place; another that reaches it meanwhile waits for it).
/// Kept from frame to frame ([`CachePool`]) so its memory (about a full list's) is
/// allocated once.
pub(crate) struct LeafCache {
    origin: [f32; 3],
    /// How many triangles the hierarchy has.
    len: usize,
    /// The blocks, in order.
    blocks: Box<[BlockCell]>,
}

/// A [`BlockCell`] no thread has claimed this frame.
const EMPTY: u8 = 0;
/// Claimed: the claiming thread is writing the block.
const WRITING: u8 = 1;
/// Written: every thread may read it until the cache is reset.
const READY: u8 = 2;

/// One block of a [`LeafCache`], written in place by the one thread that claims it. (A
/// `OnceLock` took the block by value: two 704-byte copies per block outside the AVX2
/// kernel, 6% of Igea's 640×360 frame, callgrind.)
struct BlockCell {
    state: AtomicU8,
    block: UnsafeCell<OriginBlock>,
}

// SAFETY: `block` is written only through a `Claim`, which exists for one thread at a time
// (the one whose compare-exchange moved `state` from EMPTY to WRITING), and read only after
// `state` is READY (stored with Release after the writes, loaded with Acquire before the
// reads); it becomes EMPTY again only through `&mut` (`LeafCache::reset`) or a claim given
// up unwritten. So no read overlaps a write.
#[allow(unsafe_code)]
unsafe impl Sync for BlockCell {}

impl BlockCell {
    fn new() -> Self {
        Self {
            state: AtomicU8::new(EMPTY),
            block: UnsafeCell::new(OriginBlock::default()),
        }
    }

    #[inline(always)]
    fn ready(&self) -> Option<&OriginBlock> {
        match self.state.load(Ordering::Acquire) {
            // SAFETY: READY: written, and no claim can exist until `reset` (see `Sync`).
            #[allow(unsafe_code)]
            READY => Some(unsafe { &*self.block.get() }),
            _ => None,
        }
    }
}

/// The right to write one block of a [`LeafCache`]: [`Claim::block`] to write it,
/// [`Claim::ready`] to publish it. Dropped unpublished (a panic while writing), the block
/// is free to claim again.
pub(crate) struct Claim<'c> {
    cell: &'c BlockCell,
}

impl<'c> Claim<'c> {
    /// The block to write (what an earlier frame left there, or zeros).
    #[inline(always)]
    pub(crate) fn block(&mut self) -> &mut OriginBlock {
        // SAFETY: this claim is the only one, and no reader reads before READY (see `Sync`);
        // the `&mut self` borrow ends before `ready` publishes.
        #[allow(unsafe_code)]
        unsafe {
            &mut *self.cell.block.get()
        }
    }

    /// Publishes the block written: every thread reads it from now on.
    #[inline(always)]
    pub(crate) fn ready(self) -> &'c OriginBlock {
        let cell = self.cell;
        std::mem::forget(self);
        cell.state.store(READY, Ordering::Release);
        // SAFETY: READY (see `Sync`).
        #[allow(unsafe_code)]
        unsafe {
            &*cell.block.get()
        }
    }
}

impl Drop for Claim<'_> {
    fn drop(&mut self) {
        self.cell.state.store(EMPTY, Ordering::Release);
    }
}

/// What a thread reaching a block of a [`LeafCache`] finds.
pub(crate) enum Reached<'c> {
    /// Prepared this frame.
    Ready(&'c OriginBlock),
    /// Unprepared, and now this thread's to prepare.
    Claimed(Claim<'c>),
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
            blocks: (0..len.div_ceil(BLOCK)).map(|_| BlockCell::new()).collect(),
        }
    }

    /// Empties the cache for a frame from `origin`.
    fn reset(&mut self, origin: [f32; 3]) {
        for cell in self.blocks.iter_mut() {
            *cell.state.get_mut() = EMPTY;
        }
        self.origin = origin;
    }

    /// Bytes the cache holds (about as much as a full list of the prepared triangles).
    pub(crate) fn memory_bytes(&self) -> usize {
        self.blocks.len() * size_of::<BlockCell>()
    }

    /// Block `block` if it is prepared this frame.
    #[inline(always)]
    pub(crate) fn block(&self, block: usize) -> Option<&OriginBlock> {
        self.blocks[block].ready()
    }

    /// Block `block` prepared, or the claim to prepare it; while another thread prepares
    /// it, this one waits (a block takes about 100 instructions).
    #[cold]
    pub(crate) fn reach(&self, block: usize) -> Reached<'_> {
        let cell = &self.blocks[block];
        let mut spins = 0u32;
        loop {
            if let Some(ready) = cell.ready() {
                return Reached::Ready(ready);
            }
            let claimed =
                (cell.state).compare_exchange(EMPTY, WRITING, Ordering::Acquire, Ordering::Relaxed);
            if claimed.is_ok() {
                return Reached::Claimed(Claim { cell });
            }
            spins += 1;
            match spins < 64 {
                true => std::hint::spin_loop(),
                // The writer may be descheduled (more threads than cores).
                false => std::thread::yield_now(),
            }
        }
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

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    /// Writes block `b` through `claim` as a value naming it (its `prim` lanes).
    fn write(mut claim: Claim<'_>, b: usize) -> &OriginBlock {
        let mut block = OriginBlock::default();
        block.set_prims([b as u32; BLOCK]);
        *claim.block() = block;
        claim.ready()
    }

    fn each_block_is_prepared_once_and_read_whole_by_every_thread() {
        // Four threads reach all 64 blocks in different orders, many times: each block is
        // claimed exactly once per frame, and every thread reads the value its claimer wrote.
        let mut cache = LeafCache::new(64 * BLOCK);
        for frame in 0..3 {
            cache.reset([frame as f32; 3]);
            let claims = AtomicUsize::new(0);
            let walk = |stride: usize| {
                for k in 0..64 * 5 {
                    let b = (k * stride) % 64;
                    let block = match cache.block(b) {
                        Some(ready) => ready,
                        None => match cache.reach(b) {
                            Reached::Ready(ready) => ready,
                            Reached::Claimed(claim) => {
                                claims.fetch_add(1, Ordering::Relaxed);
                                write(claim, b)
                            }
                        },
                    };
                    assert_eq!(block.prims(), [b as u32; BLOCK], "block {b}");
                }
            };
            std::thread::scope(|s| {
                for stride in [1, 3, 5, 7] {
                    s.spawn(move || walk(stride));
                }
            });
            assert_eq!(claims.into_inner(), 64, "frame {frame}");
        }
    }

    fn a_claim_given_up_unwritten_leaves_the_block_free() {
        // (As when the writing thread panics.)
        let cache = LeafCache::new(2 * BLOCK);
        let Reached::Claimed(claim) = cache.reach(1) else {
            panic!("an empty cache's block is claimed");
        };
        drop(claim);
        assert!(cache.block(1).is_none());
        let Reached::Claimed(claim) = cache.reach(1) else {
            panic!("a block given up is claimed again");
        };
        assert_eq!(write(claim, 1).prims(), [1; BLOCK]);
        assert!(matches!(cache.reach(1), Reached::Ready(_)));
        assert_eq!(cache.block(1).map(OriginBlock::prims), Some([1; BLOCK]));
        assert!(cache.block(0).is_none());
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "each_block_is_prepared_once_and_read_whole_by_every_thread",
            each_block_is_prepared_once_and_read_whole_by_every_thread,
        ),
        (
            "a_claim_given_up_unwritten_leaves_the_block_free",
            a_claim_given_up_unwritten_leaves_the_block_free,
        ),
    ];
}
