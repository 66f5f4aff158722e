//! What a level of the adaptive method tells about one primitive: [`Estimate`], a miss, a
//! hit with its t interval ([`Approx`]), or unsure. Every shape's levels answer in these.

/// An approximate hit: t with an interval certain to hold the exact t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approx {
    /// Estimate of t.
    pub t: f64,
    /// Lower end of the interval holding the exact t.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
    /// Barycentric weight of vertex 1 (0 for spheres).
    pub b1: f64,
    /// Barycentric weight of vertex 2.
    pub b2: f64,
    /// 0: the SIMD loop's f32 filter with its loose per-ray t bound, 1: f32 with pbrt's t
    /// bound, 2: f64 intervals.
    pub level: u8,
}

/// What a level could tell about one primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Estimate {
    /// Certainly missed.
    Miss,
    /// Cannot tell: ask the next level.
    Unsure,
    /// Certainly hit (the line meets it; for spheres also within the query's range).
    Hit(Approx),
}
