//! The machine a benchmark ran on, for its report: every speed table names the CPU and the
//! SIMD level the kernels used.

/// The CPU's model name (the architecture where it is not known).
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// The SIMD level the packet kernels run at here ("AVX2+FMA" or the baseline build's), and
/// whether the CPU has AVX-512 (which no kernel uses yet).
pub fn simd_level() -> String {
    #[cfg(target_arch = "x86_64")]
    {
        let kernels = match crate::math::simd::has_avx2() {
            true => "AVX2+FMA",
            false => "SSE2 (baseline)",
        };
        let avx512 = match std::arch::is_x86_feature_detected!("avx512f") {
            true => "present, unused",
            false => "absent",
        };
        format!("kernels {kernels}; AVX-512 {avx512}")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        format!("kernels portable ({})", std::env::consts::ARCH)
    }
}
