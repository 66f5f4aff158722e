//! SIMD helpers shared by the kernels (accel's packets, the renderer's shading packets): the
//! run-time choice of a kernel's build (AVX-512, AVX2+FMA or the baseline), and `each3`.
//!
//! Every kernel is compiled three times on x86-64 and the CPU picks one at run time
//! ([`level`]): for the baseline (SSE2, `wide`'s f32x8 as two 4-lane halves), with AVX2 and
//! FMA, and with AVX-512 (F, VL, BW, DQ, CD: x86-64-v4). The AVX2 and AVX-512 builds compute
//! in the same 8-lane type (`Avx8`, one 256-bit register): AVX-512VL lets the compiler use
//! its EVEX forms on it (32 vector registers instead of 16, mask registers for compares,
//! three-input logic for selects). All three give the same bits: the same IEEE operations,
//! none contracted to FMA (tests/library/packet.rs compares the builds bit for bit). The flat
//! frame's camera packets are 16 rays (`Avx16`, one 512-bit register) in the AVX-512 build
//! (`widest` below): their lanes are decided exactly as 8-ray packets decide them, so the
//! image's bytes are the same (tests/library/render.rs).
//!
//! Where the choice is made: once where a frame or a trace run starts ([`Chosen::now`], which
//! the frame's queries keep); each tile loop of the frame enters its build's copy by that
//! choice ([`avx512_avx2_or_baseline!`]'s `chosen` form, whose `isa` arms hand the loop its
//! build's token, an [`Isa`]), and below it the token's type says which build (the same
//! macro's `token` form), with no run-time check. A query called on its own, outside a frame,
//! chooses for itself ([`with_cpu_isa!`]) and reaches the same compiled copies.

/// `$item` (a function) compiled with the AVX-512 build's features: F, VL, BW, DQ and CD,
/// with AVX2 and FMA. The one place that list is written (the dispatch's wrappers and
/// [`Isa::outline`] use it).
macro_rules! avx512_features {
    ($item:item) => {
        #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma")]
        $item
    };
}
pub(crate) use avx512_features;

/// `$item` compiled with the AVX2 build's features (AVX2 and FMA), as [`avx512_features!`].
macro_rules! avx2_features {
    ($item:item) => {
        #[target_feature(enable = "avx2,fma")]
        $item
    };
}
pub(crate) use avx2_features;

/// The kernels' builds, from the slowest: `level() >= Avx2` where the AVX types may exist.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum SimdLevel {
    /// Baseline x86-64 (SSE2), or the portable build on other architectures.
    Baseline,
    /// AVX2 and FMA.
    Avx2,
    /// AVX-512 F, VL, BW, DQ and CD.
    Avx512,
}

impl SimdLevel {
    /// The name benchmarks print and `--simd` takes.
    pub fn name(self) -> &'static str {
        match self {
            SimdLevel::Baseline => "baseline",
            SimdLevel::Avx2 => "avx2",
            SimdLevel::Avx512 => "avx512",
        }
    }

    /// All levels, from the slowest.
    pub const ALL: [SimdLevel; 3] = [SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512];
}

impl std::fmt::Display for SimdLevel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for SimdLevel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        SimdLevel::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("unknown SIMD level {s:?} (baseline, avx2 or avx512)"))
    }
}

/// Calls `body(args)` (an `#[inline(always)]` kernel) through its copy compiled for one
/// build: AVX-512, AVX2+FMA, or the baseline. Each copy is one function
/// (`#[inline(never)]`). With [`crate::math::lanes`] (whose AVX types may exist only behind
/// this choice), where most of the crate's unsafe code is.
///
/// Which build: the CPU's [`level`], checked at run time (the macro's plain form, a query's
/// per-call entry point); after `chosen c,`, the build the [`Chosen`] `c` names (a tile
/// loop's start, with its frame's choice); or, after `token isa,`, the build of the
/// token `isa` (an [`Isa`]), with no run-time check: the token's type says which build, so the
/// choice is a constant (a query's `_in` form, called from code already built for one level).
/// Both reach the same three copies of a kernel when written as a function's whole body.
///
/// With `lanes` before the kernel's path, the kernel is generic over its
/// [`Lanes`](crate::math::lanes::Lanes) type: its AVX2 and AVX-512 builds compute in
/// `Avx8` (crate-private), its baseline build in `wide`'s f32x8. With `widest`, over its
/// [`LaneOps`](crate::math::lanes::LaneOps) type: the AVX-512 build computes in 16 lanes
/// (`Avx16`), the others as with `lanes`. With `isa lanes`, as with `lanes`, and the kernel is
/// also generic over its build's [`Isa`] token, which it takes as its first argument; with
/// `isa widest`, as with `widest` and the token.
macro_rules! avx512_avx2_or_baseline {
    (@kernel [$level:expr] lanes $($body:ident)::+ => ($($arg:ident: $ty:ty),*) -> $ret:ty) => {
        $crate::math::simd::avx512_avx2_or_baseline!(@builds [$level]
            ($($body)::+::<$crate::math::lanes::Avx8>)
            ($($body)::+::<$crate::math::lanes::Avx8>)
            ($($body)::+::<$crate::math::lanes::f32x8>)
            [] [] []
            ($($arg: $ty),*) -> $ret)
    };
    (@kernel [$level:expr] widest $($body:ident)::+ => ($($arg:ident: $ty:ty),*) -> $ret:ty) => {
        $crate::math::simd::avx512_avx2_or_baseline!(@builds [$level]
            ($($body)::+::<$crate::math::lanes::Avx16>)
            ($($body)::+::<$crate::math::lanes::Avx8>)
            ($($body)::+::<$crate::math::lanes::f32x8>)
            [] [] []
            ($($arg: $ty),*) -> $ret)
    };
    (@kernel [$level:expr] isa lanes $($body:ident)::+ => ($($arg:ident: $ty:ty),*) -> $ret:ty) => {
        $crate::math::simd::avx512_avx2_or_baseline!(@builds [$level]
            ($($body)::+::<$crate::math::lanes::Avx8, $crate::math::simd::Avx512>)
            ($($body)::+::<$crate::math::lanes::Avx8, $crate::math::simd::Avx2>)
            ($($body)::+::<$crate::math::lanes::f32x8, $crate::math::simd::Baseline>)
            [$crate::math::simd::Avx512::checked()]
            [$crate::math::simd::Avx2::checked()]
            [$crate::math::simd::Baseline]
            ($($arg: $ty),*) -> $ret)
    };
    (@kernel [$level:expr] isa widest $($body:ident)::+ => ($($arg:ident: $ty:ty),*) -> $ret:ty) => {
        $crate::math::simd::avx512_avx2_or_baseline!(@builds [$level]
            ($($body)::+::<$crate::math::lanes::Avx16, $crate::math::simd::Avx512>)
            ($($body)::+::<$crate::math::lanes::Avx8, $crate::math::simd::Avx2>)
            ($($body)::+::<$crate::math::lanes::f32x8, $crate::math::simd::Baseline>)
            [$crate::math::simd::Avx512::checked()]
            [$crate::math::simd::Avx2::checked()]
            [$crate::math::simd::Baseline]
            ($($arg: $ty),*) -> $ret)
    };
    (@kernel [$level:expr] $body:path => ($($arg:ident: $ty:ty),*) -> $ret:ty) => {
        $crate::math::simd::avx512_avx2_or_baseline!(@builds [$level] ($body) ($body) ($body)
            [] [] [] ($($arg: $ty),*) -> $ret)
    };
    (@builds [$level:expr] ($avx512:expr) ($avx:expr) ($base:expr)
        [$($isa512:expr)?] [$($isa2:expr)?] [$($isa_base:expr)?]
        ($($arg:ident: $ty:ty),*) -> $ret:ty) => {{
        #[cfg(target_arch = "x86_64")]
        match $level {
            $crate::math::simd::SimdLevel::Avx512 => {
                $crate::math::simd::avx512_features! {
                    #[inline(never)]
                    fn avx512($($arg: $ty),*) -> $ret {
                        $avx512($($isa512,)? $($arg),*)
                    }
                }
                // SAFETY: the CPU has these features: `level` checked them (directly or
                // through a `Chosen`), or a token of this build exists (made only after that
                // check).
                #[allow(unsafe_code)]
                return unsafe { avx512($($arg),*) };
            }
            $crate::math::simd::SimdLevel::Avx2 => {
                $crate::math::simd::avx2_features! {
                    #[inline(never)]
                    fn avx2($($arg: $ty),*) -> $ret {
                        $avx($($isa2,)? $($arg),*)
                    }
                }
                // SAFETY: as above, for AVX2 and FMA.
                #[allow(unsafe_code)]
                return unsafe { avx2($($arg),*) };
            }
            $crate::math::simd::SimdLevel::Baseline => {}
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = $level;
        #[inline(never)]
        fn baseline($($arg: $ty),*) -> $ret {
            $base($($isa_base,)? $($arg),*)
        }
        baseline($($arg),*)
    }};
    (@ $($malformed:tt)*) => {
        compile_error!("avx512_avx2_or_baseline!: expected `[token isa,] [isa] lanes|widest path => (args) -> ret` or `path => (args) -> ret`")
    };
    (chosen $chosen:expr, $($kernel:tt)+) => {
        $crate::math::simd::avx512_avx2_or_baseline!(@kernel
            [$crate::math::simd::Chosen::level($chosen)] $($kernel)+)
    };
    (token $isa:ident, $($kernel:tt)+) => {
        $crate::math::simd::avx512_avx2_or_baseline!(@kernel
            [$crate::math::simd::Isa::level($isa)] $($kernel)+)
    };
    ($($kernel:tt)+) => {
        $crate::math::simd::avx512_avx2_or_baseline!(@kernel [$crate::math::simd::level()] $($kernel)+)
    };
}
pub(crate) use avx512_avx2_or_baseline;

/// `$body` with `$isa` bound to the token of the CPU's build ([`level`]): the run-time
/// choice of a query's per-call entry point, which then calls the query's `_in` form with
/// the token (whose kernels are [`avx512_avx2_or_baseline!`]'s `token` form).
macro_rules! with_cpu_isa {
    (|$isa:ident| $body:expr) => {
        $crate::math::simd::with_isa!($crate::math::simd::Chosen::now(), |$isa| $body)
    };
}
pub(crate) use with_cpu_isa;

/// `$body` with `$isa` bound to the token of the build `$chosen` (a [`Chosen`]) names: a
/// frame's queries, entered with the frame's one choice.
macro_rules! with_isa {
    ($chosen:expr, |$isa:ident| $body:expr) => {
        match $crate::math::simd::Chosen::level($chosen) {
            #[cfg(target_arch = "x86_64")]
            $crate::math::simd::SimdLevel::Avx512 => {
                let $isa = $crate::math::simd::Avx512::checked();
                $body
            }
            #[cfg(target_arch = "x86_64")]
            $crate::math::simd::SimdLevel::Avx2 => {
                let $isa = $crate::math::simd::Avx2::checked();
                $body
            }
            _ => {
                let $isa = $crate::math::simd::Baseline;
                $body
            }
        }
    };
}
pub(crate) use with_isa;

/// A kernel build as a value, made only where the CPU runs it: the `isa lanes` arm of
/// [`avx512_avx2_or_baseline!`] hands one to its kernel (its first argument), after the run-time
/// check or from the caller's own token (the `token` form). [`Isa::outline`] runs a part of the
/// kernel compiled for that build as one function the kernel calls: a part reached from several
/// places of a kernel (the instances' mesh walk, under each variant of the walk over the
/// placements) is then compiled once per build, not once per place it would be inlined into.
pub(crate) trait Isa: Copy + Send + Sync {
    /// Which build this is.
    const LEVEL: SimdLevel;

    /// [`Isa::LEVEL`] of a token (the dispatch's `token` form asks it; a constant once compiled).
    #[inline(always)]
    fn level(self) -> SimdLevel {
        Self::LEVEL
    }

    /// `part.run()`, compiled for this build and called, not inlined.
    fn outline<P: Outlined>(self, part: P) -> P::Output;
}

/// A part of a kernel that [`Isa::outline`] compiles once per build: `run` inlines
/// (`#[inline(always)]`) into the one function made for the build.
pub(crate) trait Outlined {
    type Output;
    fn run(self) -> Self::Output;
}

/// The baseline build (SSE2 on x86-64; the portable build elsewhere).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Baseline;

impl Isa for Baseline {
    const LEVEL: SimdLevel = SimdLevel::Baseline;

    #[inline(always)]
    fn outline<P: Outlined>(self, part: P) -> P::Output {
        #[inline(never)]
        fn baseline<P: Outlined>(part: P) -> P::Output {
            part.run()
        }
        baseline(part)
    }
}

/// An AVX build's token ([`Isa`]): the type, `checked` (the dispatch's only way to make one,
/// after [`level`] said `$level` or more) and `outline` through a function made by the
/// `$features` macro.
macro_rules! avx_build {
    ($(#[$doc:meta])* $name:ident, $level:ident, $features:ident) => {
        $(#[$doc])*
        #[cfg(target_arch = "x86_64")]
        #[derive(Clone, Copy, Debug)]
        pub(crate) struct $name(());

        #[cfg(target_arch = "x86_64")]
        impl $name {
            /// The token, after [`level`] said this build or more (only the dispatch calls this).
            #[inline(always)]
            pub(crate) fn checked() -> Self {
                debug_assert!(detected() >= SimdLevel::$level);
                $name(())
            }
        }

        #[cfg(target_arch = "x86_64")]
        impl Isa for $name {
            const LEVEL: SimdLevel = SimdLevel::$level;

            #[inline(always)]
            fn outline<P: Outlined>(self, part: P) -> P::Output {
                $features! {
                    #[inline(never)]
                    fn build<P: Outlined>(part: P) -> P::Output {
                        part.run()
                    }
                }
                // SAFETY: a token exists only where the CPU has these features (`checked`).
                #[allow(unsafe_code)]
                unsafe {
                    build(part)
                }
            }
        }
    };
}

avx_build!(
    /// The AVX2+FMA build: exists only where the CPU has both.
    Avx2,
    Avx2,
    avx2_features
);
avx_build!(
    /// The AVX-512 build: exists only where the CPU has AVX-512 F, VL, BW, DQ and CD.
    Avx512,
    Avx512,
    avx512_features
);

/// `[f(0), f(1), f(2)]`: array `map` inside the kernels left calls (with AVX state
/// transitions) in the AVX2 builds; this always inlines.
#[inline(always)]
pub(crate) fn each3<T>(mut f: impl FnMut(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// The kernels' build, chosen once where a frame or a trace run starts: [`level`] then, kept
/// so that each of the frame's tiles and queries runs that build without asking again (and
/// all of them the same one, even if [`limit`] changes meanwhile). Made only by
/// [`Chosen::now`], so that it never names a build the CPU lacks: the dispatch relies on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Chosen(SimdLevel);

impl Chosen {
    /// The build the kernels run now ([`level`]).
    #[inline]
    pub fn now() -> Self {
        Chosen(level())
    }

    /// Which build.
    #[inline(always)]
    pub fn level(self) -> SimdLevel {
        self.0
    }
}

/// The best build this CPU runs ([`SimdLevel`]), detected once.
pub fn detected() -> SimdLevel {
    static DETECTED: std::sync::OnceLock<SimdLevel> = std::sync::OnceLock::new();
    *DETECTED.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            if has!("avx512f")
                && has!("avx512vl")
                && has!("avx512bw")
                && has!("avx512dq")
                && has!("avx512cd")
            {
                return SimdLevel::Avx512;
            }
            if has!("avx2") && has!("fma") {
                return SimdLevel::Avx2;
            }
        }
        SimdLevel::Baseline
    })
}

/// The build the kernels run: the [`detected`] one, or lower where [`limit`] says so.
#[inline]
pub fn level() -> SimdLevel {
    match LIMIT.load(std::sync::atomic::Ordering::Relaxed) {
        0 => SimdLevel::Baseline,
        1 => SimdLevel::Avx2.min(detected()),
        _ => detected(),
    }
}

/// Whether the CPU has AVX2 and FMA: the tests' guard before they call an AVX build
/// themselves (whatever [`limit`] says).
#[cfg(feature = "unit-tests")]
pub(crate) fn has_avx2() -> bool {
    detected() >= SimdLevel::Avx2
}

static LIMIT: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(2);

/// Runs the kernels' builds no higher than `at_most`, even where the CPU has more (for tests
/// and comparisons in one run: every build of a kernel must give the same bits). Process-wide;
/// `SimdLevel::Avx512` lifts the limit.
pub fn limit(at_most: SimdLevel) {
    LIMIT.store(at_most as u8, std::sync::atomic::Ordering::Relaxed);
}

/// `f()` with the kernels' builds no higher than `at_most` ([`limit`]), the limit lifted
/// afterwards: one frame or query of a lower build beside the best one.
pub fn limited<T>(at_most: SimdLevel, f: impl FnOnce() -> T) -> T {
    limit(at_most);
    let out = f();
    limit(SimdLevel::Avx512);
    out
}
