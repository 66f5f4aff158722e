//! Closest-hit and any-hit queries over a scene's primitives.
//!
//! For now only the brute-force loop: the Cornell box has 30 triangles. Faster paths (a SIMD
//! loop, a BVH for large meshes) must give the same nearest hit as [`brute`].

pub mod brute;

pub use brute::{any_hit, closest_hit};
