//! How often the adaptive method's slower levels (and the exact zero-area test's) run,
//! counted only while switched on
//! ([`count_levels`]; `examples/speed_vs_error` reports them): off,
//! counting costs a load and a branch on the slow paths only.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

/// What is counted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// A candidate the f32 filter left unsure, tested in f32 with pbrt's bound.
    PreciseF32,
    /// A candidate tested in f64 interval arithmetic.
    F64Intervals,
    /// A candidate decided exactly (expansions or rationals).
    Exact,
    /// Two hits' t compared by exact rational t's.
    ExactT,
    /// A camera lane the packet kernels left ambiguous.
    CameraLaneAmbiguous,
    /// A shadow lane the packet kernels left unsure.
    ShadowLaneUnsure,
    /// A t rounded by [`super::rounded_t`] from plain f64 or an f64 interval.
    RoundedFromF64,
    /// A t rounded by [`super::rounded_t`] exactly.
    RoundedExactly,
    /// A triangle's zero-area question ([`crate::geometry::exact::zero_area`]) that the f64
    /// filter left to exact arithmetic (zero area, or nearly).
    ZeroAreaExact,
    /// … of those, one answered in rationals (coordinates past the expansions' range).
    ZeroAreaRational,
}

const EVENTS: usize = Event::ZeroAreaRational as usize + 1;
static ON: AtomicBool = AtomicBool::new(false);
static COUNTS: [AtomicU64; EVENTS] = [const { AtomicU64::new(0) }; EVENTS];

/// Switches counting on or off (the counts stay).
pub fn count_levels(on: bool) {
    ON.store(on, Relaxed);
}

/// Counts `event` where counting is on.
#[inline]
pub fn note(event: Event) {
    if ON.load(Relaxed) {
        COUNTS[event as usize].fetch_add(1, Relaxed);
    }
}

/// Counts `n` of `event` where counting is on.
#[inline]
pub fn note_many(event: Event, n: u32) {
    if ON.load(Relaxed) {
        COUNTS[event as usize].fetch_add(n.into(), Relaxed);
    }
}

/// The count of `event` so far.
pub fn count(event: Event) -> u64 {
    COUNTS[event as usize].load(Relaxed)
}

/// Sets every count to zero.
pub fn reset() {
    for c in &COUNTS {
        c.store(0, Relaxed);
    }
}
