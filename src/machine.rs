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

/// The build the packet kernels run here ([`crate::math::simd::level`]) and the best the
/// CPU has, for every speed table's header.
pub fn simd_level() -> String {
    use crate::math::simd::{detected, level, SimdLevel};
    let name = |l: SimdLevel| match l {
        SimdLevel::Avx512 => "AVX-512 (x86-64-v4; the flat frame's camera packets 16 lanes)",
        SimdLevel::Avx2 => "AVX2+FMA",
        SimdLevel::Baseline if cfg!(target_arch = "x86_64") => "SSE2 (baseline)",
        SimdLevel::Baseline => "portable",
    };
    match level() == detected() {
        true => format!("kernels {}", name(level())),
        false => format!(
            "kernels {} (limited; the CPU has {})",
            name(level()),
            name(detected())
        ),
    }
}
