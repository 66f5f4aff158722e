//! SIMD helpers shared by the kernels (accel's packets, the renderer's shading packets): the
//! run-time choice between a kernel's AVX2+FMA build and its baseline build, and `each3`.

/// Calls `body(args)` (an `#[inline(always)]` kernel) through a copy compiled with AVX2 and
/// FMA where the CPU has them ([`has_avx2`]), else as compiled for the baseline. With
/// [`crate::math::lanes`] (whose AVX types may exist only behind this check), the one place
/// the crate uses unsafe code.
///
/// With `lanes` before the kernel's path, the kernel is generic over its
/// [`Lanes`](crate::math::lanes::Lanes) type: its AVX2 build computes in
/// `Avx8` (crate-private), its baseline build in `wide`'s f32x8.
macro_rules! avx2_or_baseline {
    (lanes $($body:ident)::+ => ($($arg:ident: $ty:ty),*) -> $ret:ty) => {{
        #[cfg(target_arch = "x86_64")]
        if $crate::math::simd::has_avx2() {
            #[target_feature(enable = "avx2,fma")]
            fn avx2($($arg: $ty),*) -> $ret {
                $($body)::+::<$crate::math::lanes::Avx8>($($arg),*)
            }
            // SAFETY: the CPU has AVX2 and FMA (checked at run time).
            #[allow(unsafe_code)]
            return unsafe { avx2($($arg),*) };
        }
        $($body)::+::<$crate::math::lanes::f32x8>($($arg),*)
    }};
    ($body:path => ($($arg:ident: $ty:ty),*) -> $ret:ty) => {{
        #[cfg(target_arch = "x86_64")]
        if $crate::math::simd::has_avx2() {
            #[target_feature(enable = "avx2,fma")]
            fn avx2($($arg: $ty),*) -> $ret {
                $body($($arg),*)
            }
            // SAFETY: the CPU has AVX2 and FMA (checked at run time).
            #[allow(unsafe_code)]
            return unsafe { avx2($($arg),*) };
        }
        $body($($arg),*)
    }};
}
pub(crate) use avx2_or_baseline;

/// `[f(0), f(1), f(2)]`: array `map` inside the kernels left calls (with AVX state
/// transitions) in the AVX2 builds; this always inlines.
#[inline(always)]
pub(crate) fn each3<T>(mut f: impl FnMut(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// Whether the CPU has AVX2 and FMA, for the kernels compiled twice: for the baseline x86-64
/// (SSE2, f32x8 as two 4-lane halves) and with AVX2 and FMA enabled (VEX-encoded
/// three-operand instructions: 18% fewer instructions in `closest`, callgrind). The
/// answer is cached by the standard library.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn has_avx2() -> bool {
    !BASELINE_ONLY.load(std::sync::atomic::Ordering::Relaxed)
        && std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("fma")
}

static BASELINE_ONLY: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Runs the kernels' baseline build even where AVX2 is present (for tests and comparisons:
/// both builds of a kernel must give the same bits, as neither contracts to FMA).
pub fn use_baseline_simd(on: bool) {
    BASELINE_ONLY.store(on, std::sync::atomic::Ordering::Relaxed);
}
