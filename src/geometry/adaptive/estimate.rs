//! What a level of the adaptive method tells about one primitive: [`Estimate`], a miss, a
//! hit with its t interval ([`Approx`]), or unsure; and the exact level's hit ([`Decided`],
//! where on the shape it lies: [`Feature`]). Every shape's levels answer in these.

use crate::geometry::exact::ExactT;
use crate::math::interval::Interval;

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

/// Where an exactly decided hit lies: two hits at the same edge line or vertex (the same f32
/// coordinates) are at the same t, which settles an exact tie without computing t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Feature {
    /// Inside a face (no other primitive's hit is known to share the point).
    Interior,
    /// On this edge of a triangle (its ends in order).
    Edge([[f64; 3]; 2]),
    /// At this vertex of a triangle.
    Vertex([f64; 3]),
    /// A root of a curved surface (its t is exact: [`Decided::exact`]).
    Root,
}

/// A hit decided exactly (level 3): t as an interval where one is known, the exact t once
/// needed.
#[derive(Clone, Debug)]
pub struct Decided {
    /// An interval holding the exact t, where known.
    pub t: Option<Interval>,
    /// Where on the shape the line meets it.
    pub point: Feature,
    /// The exact t, once computed.
    pub exact: Option<ExactT>,
    /// Barycentric weight of vertex 1 (0 for spheres).
    pub b1: f64,
    /// Barycentric weight of vertex 2.
    pub b2: f64,
}
