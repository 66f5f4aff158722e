//! Rays, primitives and their intersection, generic over f32/f64 ([`Real`]).
//!
//! A shape is a variant of [`Shape`] and a module of its own (`triangle`, `sphere`) holding
//! its tests: the plain f32/f64 ones and the adaptive method's levels. It plugs in through
//! the match arms of [`Shape::intersect`], [`Shape::bounds`], the adaptive search's interval
//! and exact levels ([`adaptive`]) and the surface point ([`offset::SurfacePoint`]); nothing
//! above `geometry` names a shape: the accelerators test every non-triangle through these,
//! and the renderer shades "triangle" or "any other shape".

pub mod adaptive;
pub mod exact;
pub mod instance;
pub mod offset;
pub mod sphere;
pub mod terms;
pub mod triangle;

use crate::math::real::V3;
use crate::math::Real;
use std::fmt;
use std::str::FromStr;

pub use offset::{offset_ray_origin, SurfacePoint};

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

/// A primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape<T: Real = f32> {
    /// A triangle v0, v1, v2 (closed, two-sided).
    Triangle([V3<T>; 3]),
    /// A sphere.
    Sphere {
        /// Centre.
        centre: V3<T>,
        /// Radius (> 0).
        radius: T,
    },
}

impl Shape<f64> {
    /// A sphere seen from ray origin `o`, prepared once for every ray from there
    /// ([`sphere::FromOrigin`]); `None` for a triangle (the packets prepare those).
    pub fn sphere_from_origin(&self, o: [f64; 3]) -> Option<sphere::FromOrigin> {
        match *self {
            Shape::Sphere { centre, radius } => Some(sphere::FromOrigin::new(o, centre, radius)),
            Shape::Triangle(_) => None,
        }
    }
}

impl Shape<f32> {
    /// Whether `p` is outside the closed shape: `None` for a triangle (no inside), and within
    /// 10⁻⁹ relative of a sphere's surface.
    pub fn outside(&self, p: [f32; 3]) -> Option<bool> {
        let Shape::Sphere { centre, radius } = *self else {
            return None;
        };
        let rel = [0, 1, 2].map(|k| f64::from(p[k]) - f64::from(centre[k]));
        let d2 = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2];
        let r2 = f64::from(radius) * f64::from(radius);
        match d2 {
            _ if d2 > r2 * (1.0 + 1e-9) => Some(true),
            _ if d2 < r2 * (1.0 - 1e-9) => Some(false),
            _ => None,
        }
    }

    /// The shape's kind and numbers as bits (−0 as +0): equal keys are the same shape to the
    /// bit (finding copies at build).
    #[inline]
    pub fn key(&self) -> (u8, [u32; 9]) {
        let bits = |x: f32| (x + 0.0).to_bits();
        let mut k = [0; 9];
        match self {
            Shape::Triangle(v) => {
                for (i, c) in v.iter().flatten().enumerate() {
                    k[i] = bits(*c);
                }
                (0, k)
            }
            Shape::Sphere { centre, radius } => {
                k[..3].copy_from_slice(&centre.map(bits));
                k[3] = bits(*radius);
                (1, k)
            }
        }
    }

    /// The geometric normal (not of unit length, in f64) where `ray` meets this shape at `t`:
    /// a triangle's e₁ × e₂, a sphere's p − c.
    pub fn normal_at(&self, ray: &Ray<f32>, t: f32) -> [f64; 3] {
        match self {
            Shape::Triangle(v) => {
                let e1 = [0, 1, 2].map(|k| v[1][k] as f64 - v[0][k] as f64);
                let e2 = [0, 1, 2].map(|k| v[2][k] as f64 - v[0][k] as f64);
                [
                    e1[1] * e2[2] - e1[2] * e2[1],
                    e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0],
                ]
            }
            Shape::Sphere { centre, .. } => {
                [0, 1, 2].map(|k| ray.o[k] as f64 + t as f64 * ray.d[k] as f64 - centre[k] as f64)
            }
        }
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

impl<T: Real> From<[V3<T>; 3]> for Shape<T> {
    /// The triangle of these vertices.
    fn from(v: [V3<T>; 3]) -> Self {
        Shape::Triangle(v)
    }
}

impl<T: Real> Shape<T> {
    /// A sphere (the loaders' constructor: nothing outside this module names a kind of shape).
    pub fn sphere(centre: V3<T>, radius: T) -> Self {
        Shape::Sphere { centre, radius }
    }

    /// The vertices, where this is a triangle. Triangles are the one kind the accelerators keep
    /// in their SIMD structures; every other shape they test through [`Shape::intersect`].
    #[inline]
    pub fn triangle(&self) -> Option<&[V3<T>; 3]> {
        match self {
            Shape::Triangle(v) => Some(v),
            _ => None,
        }
    }

    /// The largest magnitude of its coordinates (for a sphere |c|∞ + r): the scale at which a
    /// computation with them rounds (the grader's t tolerance).
    pub fn extent(&self) -> f64 {
        let max = |xs: &mut dyn Iterator<Item = T>| xs.fold(0.0f64, |m, x| m.max(x.f64().abs()));
        match self {
            Shape::Triangle(v) => max(&mut v.iter().flatten().copied()),
            Shape::Sphere { centre, radius } => {
                max(&mut centre.iter().copied()) + radius.f64().abs()
            }
        }
    }

    /// The shape as a `.scene` statement: `tri` and its 9 coordinates or `sphere` and its
    /// centre and radius, each number written exactly ([`crate::math::real::exact_decimal`]:
    /// the same value read in f32, f64 or exact arithmetic).
    pub fn scene_line(&self) -> String {
        let numbers = |xs: &[T]| -> Vec<String> {
            xs.iter()
                .map(|x| crate::math::real::exact_decimal(x.f64()))
                .collect()
        };
        match self {
            Shape::Triangle(v) => format!("tri {}", numbers(v.as_flattened()).join(" ")),
            Shape::Sphere { centre, radius } => {
                format!(
                    "sphere {} {}",
                    numbers(centre).join(" "),
                    numbers(&[*radius])[0]
                )
            }
        }
    }

    /// Whether this is a triangle of zero area ([`triangle::zero_area`]): a primitive that
    /// keeps its index but that no ray hits.
    pub fn is_degenerate(&self) -> bool {
        self.triangle().is_some_and(triangle::zero_area)
    }

    /// Whether this is a triangle ([`Shape::triangle`]).
    #[inline]
    pub fn is_triangle(&self) -> bool {
        self.triangle().is_some()
    }

    /// Intersects with `method`; a hit needs tmin < t < tmax. A triangle of zero area is never
    /// hit.
    #[inline]
    pub fn intersect(&self, ray: &Ray<T>, method: Method, tmin: T, tmax: T) -> Option<(T, T, T)> {
        if method == Method::Adaptive {
            let h = adaptive::closest_hit_reference(std::slice::from_ref(self), ray, tmin, tmax)?;
            return Some((T::of(h.t), T::of(h.b1), T::of(h.b2)));
        }
        match self {
            Shape::Triangle(v) => {
                let hit = match method {
                    Method::Adaptive => unreachable!(),
                    Method::Watertight => triangle::watertight(ray.o, ray.d, v, tmin, tmax),
                    Method::Moller => triangle::moller(ray.o, ray.d, v, tmin, tmax),
                    Method::Cramer => triangle::cramer(ray.o, ray.d, v, tmin, tmax),
                };
                // A triangle of zero area is never hit (decided only for a hit: rare).
                hit.filter(|_| !triangle::zero_area(v))
            }
            Shape::Sphere { centre, radius } => {
                sphere::intersect(ray.o, ray.d, *centre, *radius, tmin, tmax)
                    .map(|t| (t, T::zero(), T::zero()))
            }
        }
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (V3<T>, V3<T>) {
        match self {
            Shape::Triangle(v) => {
                let mut lo = v[0];
                let mut hi = v[0];
                for p in &v[1..] {
                    for k in 0..3 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
                (lo, hi)
            }
            Shape::Sphere { centre, radius } => {
                let r = *radius;
                (
                    [centre[0] - r, centre[1] - r, centre[2] - r],
                    [centre[0] + r, centre[1] + r, centre[2] + r],
                )
            }
        }
    }
}
