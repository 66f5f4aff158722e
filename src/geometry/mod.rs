//! Rays, primitives and their intersection, generic over f32/f64 ([`Real`]).
//!
//! A shape is a file of its own under [`shapes`] (`triangle`, `sphere`, re-exported here as
//! [`triangle`] and [`sphere`]) implementing [`Primitive`]: its tests (the plain f32/f64 ones
//! and the adaptive method's levels), bounds, normal, surface point, terms and scene line.
//! [`Shape`], the enum a scene holds, is made from the list in `shapes/mod.rs` (which also
//! says how to add a shape: its file and its line there) and hands every question to them
//! in one place; nothing else in the library names a kind of shape.

pub mod adaptive;
pub mod exact;
pub mod instance;
pub mod offset;
pub mod shapes;

/// What the ray inspector shows of a shape's own math for one ray
/// ([`ShapeTerms`](crate::geometry::shapes::ShapeTerms): the lecture's linear system for a
/// triangle, the quadratic for a sphere), which each shape computes and words in its own file.
pub mod terms {
    pub use super::shapes::ShapeTerms;
}

pub use offset::{offset_ray_origin, SurfacePoint};
pub use shapes::{sphere, triangle, Location, Primitive, Shape, Sphere, Triangle};

use crate::math::real::V3;
use crate::math::Real;
use std::fmt;
use std::str::FromStr;

/// A ray o + t·d; d need not be normalised (t is in units of |d|).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<T: Real = f32> {
    /// Origin.
    pub o: V3<T>,
    /// Direction.
    pub d: V3<T>,
}

impl<T: Real> Ray<T> {
    /// A ray from origin and direction.
    pub fn new(o: V3<T>, d: V3<T>) -> Self {
        Self { o, d }
    }

    /// The point o + t·d.
    pub fn at(&self, t: T) -> V3<T> {
        [
            self.o[0] + t * self.d[0],
            self.o[1] + t * self.d[1],
            self.o[2] + t * self.d[2],
        ]
    }
}

/// Which ray/primitive test to run. Spheres use the cancellation-free test, except under
/// `Adaptive`, which decides them exactly too.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Method {
    /// The default: watertight in f32 where that is certain, else f64 intervals, else exact
    /// rationals; always the exact nearest primitive ([`adaptive`]).
    #[default]
    Adaptive,
    /// Woop–Benthin–Wald watertight test, plain f32 (with the f64 re-decision of t vs tmin).
    Watertight,
    /// Möller–Trumbore.
    Moller,
    /// The lecture's x = A⁻¹b.
    Cramer,
}

impl Method {
    /// All methods, default first.
    pub const ALL: [Method; 4] = [
        Method::Adaptive,
        Method::Watertight,
        Method::Moller,
        Method::Cramer,
    ];

    /// The CLI / UI name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Adaptive => "adaptive",
            Method::Watertight => "watertight",
            Method::Moller => "moller",
            Method::Cramer => "cramer",
        }
    }

    /// One line for the UI and `--help`.
    pub fn explanation(self) -> &'static str {
        match self {
            Method::Adaptive => {
                "the default: watertight in f32 where certain, else f64 intervals, else exact \
                 rationals; always the exact nearest primitive"
            }
            Method::Watertight => {
                "Woop–Benthin–Wald watertight test in plain f32: no ray slips between shared edges"
            }
            Method::Moller => "Möller–Trumbore",
            Method::Cramer => "the lecture's x = A⁻¹b through an explicit inverse (the baseline)",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!("unknown method '{s}' (expected adaptive, watertight, moller or cramer)")
            })
    }
}

/// The nearest hit of a ray: parameter, primitive index, and for triangles the barycentrics
/// (b1, b2) of vertices 1 and 2 (zero for spheres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit<T: Real = f32> {
    /// Ray parameter.
    pub t: T,
    /// Index of the primitive in its scene.
    pub prim: u32,
    /// Barycentric weight of vertex 1.
    pub b1: T,
    /// Barycentric weight of vertex 2.
    pub b2: T,
}
