//! Homogeneous transforms and the small amount of floating-point machinery the geometry needs.

pub mod interval;
pub mod lanes;
pub mod real;
pub mod simd;
pub mod transform;

pub use real::Real;
pub use transform::{
    degrees_within_half_turn, radians_of_degrees, rotation_x, rotation_xyz, rotation_y, rotation_z,
    TransformStack,
};

/// The unit tests' xorshift generator: steps `x` and returns it.
#[cfg(feature = "unit-tests")]
pub(crate) fn xorshift(x: &mut u64) -> u64 {
    *x ^= *x << 13;
    *x ^= *x >> 7;
    *x ^= *x << 17;
    *x
}

/// The largest |coordinate| of a rendered scene's geometry: 2³⁸ ≈ 2.7e11. The f32 tests of
/// the packet kernels multiply up to three coordinate differences (edge normals prepared for
/// an origin, dotted with an unnormalised shadow segment), and beyond about 5e11 those
/// products overflow: every answer stays exact (the exact fallback takes over) but a frame
/// slows 2–5× (measured on a cube scaled by 5e11 and 1e12: shadows at half speed, then both
/// steps; up to 2.7e11, as fast as the unit cube). Faces' normals overflowed from about 4e9
/// before `normalize` rescaled them.
pub const MAX_SCENE_COORDINATE: f64 = (1u64 << 38) as f64;

/// The largest |coordinate| of the camera and the light: 2⁴⁰ ≈ 1.1e12, 4× the scene's range
/// (a cube at the scene's limit seen and lit from there renders at the unit cube's speed).
pub const MAX_VIEW_COORDINATE: f64 = (1u64 << 40) as f64;

/// `Ok` if every coordinate of `p` is finite and within ±`max`; else a message naming `what`
/// and the value (as written in `T`'s shortest form: an f32 shows as the f32 it is).
pub fn check_range<T: Copy + Into<f64> + std::fmt::Debug>(
    what: &str,
    p: [T; 3],
    max: f64,
) -> Result<(), String> {
    let within = |c: f64| c.is_finite() && c.abs() <= max;
    match p.iter().find(|c| !within((**c).into())) {
        None => Ok(()),
        Some(c) => Err(format!(
            "{what} {p:?} has coordinate {c:?}, beyond ±{max:e}: the range raylab's f32 core \
             renders without overflow"
        )),
    }
}
