//! Homogeneous transforms and the small amount of floating-point machinery the geometry needs.

pub mod interval;
pub mod real;
pub mod simd;
pub mod transform;

pub use real::Real;
pub use transform::{rotation_x, rotation_xyz, rotation_y, rotation_z, TransformStack};
