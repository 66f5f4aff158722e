//! The primitives, one file per shape: [`triangle`] and [`sphere`]. Each implements
//! [`Primitive`], everything the rest of the crate asks of a shape, from its tests to its
//! scene-file line; [`Shape`], the enum a scene holds them in, [`ShapeTerms`], the
//! inspector's terms, and [`Location`], where a ray meets it exactly, are made from one list
//! (`shapes!`, below), which also writes the one `match` that hands each question to the shape
//! (`dispatch!`). Neither the rest of
//! `geometry` nor the renderer nor the parser matches on the kind of a shape.
//!
//! # A new shape
//!
//! 1. **Its file**, `shapes/<name>.rs`: a struct of its numbers, its own ray tests (plain
//!    f32/f64, the adaptive method's levels), `impl Primitive<T>` (the compiler lists every
//!    answer still missing: none has a default; its scene line is [`Primitive::KEYWORD`] and
//!    [`Primitive::read`]), `pub struct Terms`, its inspector terms, with
//!    `impl WordedTerms`, and `pub enum Location` with `impl Display`.
//! 2. **Its two lines** below: `pub mod name;` and its line in the list, `Name(name::Name)`:
//!    its variant of [`Shape`], [`ShapeTerms`] and [`Location`], its arm of every dispatch and
//!    its keyword in the parser.
//!
//! The accelerators keep triangles in their SIMD structures and every other shape in a
//! hierarchy of its own, where a packet tests the shapes that answer
//! [`Primitive::seen_from`] (spheres) in lanes and the rest per ray. Outside the library
//! one exhaustive match names the kinds and the compiler points at it: the lab's reference
//! loop, which calls a student's function per shape (`lab/src/yours.rs`).
//!
//! Dispatch is static: each arm calls the shape's method on its struct, which inlines as a
//! hand-written `match` would.

use super::adaptive::{self, Decided, Estimate};
use super::exact::ExactT;
use super::{Method, Ray, SurfacePoint};
use crate::math::real::V3;
use crate::math::Real;

/// What a shape answers: everything the accelerators, the adaptive method, the renderer, the
/// inspector and the scene files ask of it. Generic over the precision of its numbers; the
/// renderer's questions ([`Primitive::surface_point`]) are asked of f32 shapes.
pub trait Primitive<T: Real>: Copy {
    /// The scene-file keyword (`tri`, `sphere`), which [`Shape::scene_line`] writes before
    /// the shape's [`numbers`](Primitive::numbers) and the parser reads.
    const KEYWORD: &'static str;
    /// The kind in [`Shape::key`] (distinct per shape).
    const KIND: u8;

    /// The shape of a scene line's numbers `words` (after the keyword), written in the
    /// current frame of the file's transform stack ([`SceneFrame`]): the parser's error for
    /// a line it cannot be.
    fn read(words: &[&str], frame: &impl SceneFrame<T>) -> Result<Self, String>;

    /// Its numbers in the order its scene line writes them (at most 9: [`Shape::key`]
    /// holds 9).
    fn numbers(&self) -> impl Iterator<Item = T>;

    /// The largest magnitude of its coordinates (for a sphere |c|∞ + r): the scale at which
    /// a computation with them rounds (the grader's t tolerance).
    fn extent(&self) -> f64;

    /// Axis-aligned bounds (min, max).
    fn bounds(&self) -> (V3<T>, V3<T>);

    /// Its box rounded outwards to f32, which the exact queries may cull by (the hierarchy of
    /// the shapes that are not triangles).
    fn box_f32(&self) -> ([f32; 3], [f32; 3]);

    /// Its vertices, where it is a triangle: the one kind the accelerators keep in their SIMD
    /// structures (every other shape goes to the hierarchy of the rest).
    fn triangle(&self) -> Option<&[V3<T>; 3]>;

    /// The shape seen from ray origin `o`, prepared once for every ray from there for the
    /// packets' f64 interval test in lanes ([`sphere::FromOrigin`]); `None` where it has no
    /// such test (a triangle: the packets prepare those; a shape the packets leave to the
    /// per-ray search).
    fn seen_from(&self, o: [f64; 3]) -> Option<sphere::FromOrigin>;

    /// Whether it keeps its index but no ray hits it (a triangle of zero area).
    fn is_degenerate(&self) -> bool;

    /// The nearest hit (t, b1, b2) with tmin < t < tmax by a plain `method` (b1, b2 the
    /// barycentrics of vertices 1 and 2 where it has vertices, else zero).
    /// [`Method::Adaptive`] does not come here: [`Shape::intersect`] answers it for every
    /// shape by the adaptive search over the levels below.
    fn intersect(&self, ray: &Ray<T>, method: Method, tmin: T, tmax: T) -> Option<(T, T, T)>;

    /// The geometric normal (not of unit length, in f64) where `ray` meets it at `t`.
    fn normal_at(&self, ray: &Ray<T>, t: T) -> [f64; 3];

    /// Whether `p` is outside it: `None` where it has no inside, or where `p` is too near its
    /// surface to tell.
    fn outside(&self, p: V3<T>) -> Option<bool>;

    /// Which side a light is on: whether the shadow segment from `light` to a point of this
    /// surface, offset to the light's side of it (outwards along the normal where
    /// `end_outside`, inwards otherwise: `offset_ray_origin`), certainly stays clear of this
    /// shape, so that the shadow test may skip it. Always, for a flat shape; for a closed one,
    /// where the light is certainly on the side the segment ends on.
    fn shadow_clear_of_itself(&self, light: V3<T>, end_outside: bool) -> bool;

    /// Where the renderer shades `ray`'s hit on it, with the point's error bounds and unit
    /// normal ([`SurfacePoint`]): the same bits on every path (packets or per ray, whichever
    /// level found the hit). For the renderer's f32 shapes (wider numbers are rounded to f32).
    fn surface_point(&self, ray: &Ray<f32>) -> SurfacePoint;

    /// Its own math for `ray`, as the ray inspector shows it ([`ShapeTerms`]).
    fn terms(&self, ray: &Ray<T>) -> ShapeTerms;

    /// Where the line of `ray` meets it, decided exactly ([`Location`]: on a triangle's
    /// edge or vertex, tangent to a sphere), as the ray inspector says where a hit lies.
    fn locate(&self, ray: &Ray<T>) -> Location;

    /// The same shape in f64 (exact for f32 numbers): what the adaptive levels run on.
    fn widen(&self) -> Shape<f64>;

    /// The adaptive method's level 1 for f32 inputs: the f32 test with its error bound;
    /// `None` where the shape has no f32 level (a sphere starts at level 2).
    fn f32_filter(&self, o: [f32; 3], d: [f32; 3]) -> Option<Estimate>;

    /// Level 2: decided in f64 interval arithmetic on the exact inputs, or unsure.
    fn f64_intervals(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Estimate;

    /// Level 3: a hit with tmin < t < tmax decided exactly (`None`: a miss), where on the
    /// shape it lies, and its t as far as known.
    fn decide_exactly(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<Decided>;

    /// The exact t of a hit [`Primitive::decide_exactly`] decided without it.
    fn exact_t(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<ExactT>;

    /// Whether exactly decided hits on this shape and on `other` are certainly at the same t,
    /// without computing it (two triangles in one plane: the line crosses it once).
    fn same_t(&self, other: &Shape<T>) -> bool;

    /// The t at which the line meets it (a triangle: its plane; a sphere: the nearest root
    /// within tmin < t < tmax) within an f64 interval (lo, hi), where a cheap computation
    /// gives one ([`adaptive::rounded_t`]).
    fn t_in_f64(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<(f64, f64)>;

    /// That t exactly, correctly rounded to R (`None` where there is none).
    fn t_rounded<R: Real>(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<R>;
}

/// What a scene line's shape may ask of the parser: its numbers, and where the current frame
/// of the transform stack puts the points and lengths they write.
pub trait SceneFrame<T: Real> {
    /// The `count` numbers of `words` (each finite, as f64), or the error naming `what`.
    fn numbers(&self, words: &[&str], count: usize, what: &str) -> Result<Vec<f64>, String>;

    /// The point written as `words[0..3]` in world coordinates: those words read straight in
    /// `T` where the frame is the world's, else the frame's matrix applied in f64 and then
    /// rounded to `T`.
    fn point(&self, words: &[&str]) -> Result<V3<T>, String>;

    /// The length written as `word`, in the world: read straight in `T` where the frame is
    /// the world's, else times the frame's scale; `None` where that scale is not the same
    /// along every axis.
    fn length(&self, word: &str) -> Option<T>;
}

/// The list of shapes: `Name(module::Name)` per shape makes its variant of [`Shape`] (holding
/// its struct) and of [`ShapeTerms`] (holding its `module::Terms`) and [`Location`], its arm
/// of `dispatch!` and its keyword in [`Shape::read`]. (Its module is declared beside the list,
/// not by it: rustfmt does not reach a module a macro declares.)
macro_rules! shapes {
    ($d:tt $($(#[$doc:meta])* $variant:ident($module:ident::$name:ident)),+ $(,)?) => {
        $(pub use $module::$name;)+

        /// A primitive.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum Shape<T: Real = f32> {
            $($(#[$doc])* $variant($name<T>),)+
        }

        /// A primitive's own math for one ray, as the ray inspector shows it (`raylab
        /// inspect`, the window's panel), in f64 from the f32 inputs: each shape computes and
        /// words its own ([`Primitive::terms`], its `Terms` and their [`WordedTerms`]).
        #[derive(Clone, Debug, PartialEq)]
        pub enum ShapeTerms {
            $($(#[$doc])* $variant($module::Terms),)+
        }

        /// Where a ray's line meets a primitive, decided exactly (what the ray inspector says
        /// of a hit): each shape's own `module::Location` ([`Primitive::locate`]).
        #[derive(Clone, Debug, PartialEq)]
        pub enum Location {
            $($(#[$doc])* $variant($module::Location),)+
        }

        impl std::fmt::Display for Location {
            fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                match self {
                    $(Location::$variant(at) => at.fmt(f),)+
                }
            }
        }

        /// `dispatch!(shape, p => expr)`: `expr` with `p` the shape's own struct (a
        /// reference), for every kind of shape: the one place that turns a [`Shape`] into a
        /// [`Primitive`].
        macro_rules! dispatch {
            ($d shape:expr, $d p:ident => $d body:expr) => {
                match $d shape {
                    $(Shape::$variant($d p) => $d body,)+
                }
            };
        }

        /// The terms' `match`, as `dispatch!`'s.
        macro_rules! dispatch_terms {
            ($d terms:expr, $d p:ident => $d body:expr) => {
                match $d terms {
                    $(ShapeTerms::$variant($d p) => $d body,)+
                }
            };
        }

        impl<T: Real> Shape<T> {
            /// Every shape's scene-file keyword, in the list's order.
            pub const KEYWORDS: &'static [&'static str] =
                &[$(<$name<T> as Primitive<T>>::KEYWORD),+];

            /// The shape of a scene line with `keyword` and numbers `words` in `frame`
            /// ([`Primitive::read`]); `None` where the keyword names no shape.
            pub fn read(
                keyword: &str,
                words: &[&str],
                frame: &impl SceneFrame<T>,
            ) -> Option<Result<Self, String>> {
                $(if keyword == <$name<T> as Primitive<T>>::KEYWORD {
                    return Some($name::read(words, frame).map(Shape::$variant));
                })+
                None
            }
        }
    };
}

pub mod sphere;
pub mod triangle;

shapes! { $
    /// A triangle v0, v1, v2 (closed, two-sided): [`Triangle`].
    Triangle(triangle::Triangle),
    /// A sphere (closed): [`Sphere`].
    Sphere(sphere::Sphere),
}

/// How a shape's [`Terms`](triangle::Terms) are worded.
pub trait WordedTerms {
    /// The `name: value` lines of `raylab inspect` (every digit).
    fn lines(&self) -> Vec<String>;

    /// The window panel's (label, value) rows, vectors formatted by `v3`, other numbers to a
    /// few digits.
    fn rows(&self, v3: &dyn Fn([f64; 3]) -> String) -> Vec<(&'static str, String)>;
}

impl<T: Real> From<[V3<T>; 3]> for Shape<T> {
    /// The triangle of these vertices.
    fn from(v: [V3<T>; 3]) -> Self {
        Shape::Triangle(Triangle(v))
    }
}

impl<T: Real> Shape<T> {
    /// A sphere (the loaders' constructor).
    pub fn sphere(centre: V3<T>, radius: T) -> Self {
        Shape::Sphere(Sphere { centre, radius })
    }

    /// The vertices, where this is a triangle ([`Primitive::triangle`]). Triangles are the
    /// one kind the accelerators keep in their SIMD structures; every other shape they test
    /// through [`Shape::intersect`].
    #[inline]
    pub fn triangle(&self) -> Option<&[V3<T>; 3]> {
        dispatch!(self, p => p.triangle())
    }

    /// Where the line of `ray` meets this shape, decided exactly ([`Primitive::locate`]).
    pub fn locate(&self, ray: &Ray<T>) -> Location {
        dispatch!(self, p => p.locate(ray))
    }

    /// The shape's scene-file keyword ([`Primitive::KEYWORD`]).
    pub fn keyword(&self) -> &'static str {
        fn keyword<T: Real, P: Primitive<T>>(_: &P) -> &'static str {
            P::KEYWORD
        }
        dispatch!(self, p => keyword(p))
    }

    /// [`Primitive::box_f32`].
    pub fn box_f32(&self) -> ([f32; 3], [f32; 3]) {
        dispatch!(self, p => p.box_f32())
    }

    /// [`Primitive::seen_from`].
    pub fn seen_from(&self, o: [f64; 3]) -> Option<sphere::FromOrigin> {
        dispatch!(self, p => p.seen_from(o))
    }

    /// Whether this is a triangle ([`Shape::triangle`]).
    #[inline]
    pub fn is_triangle(&self) -> bool {
        self.triangle().is_some()
    }

    /// [`Primitive::extent`].
    pub fn extent(&self) -> f64 {
        dispatch!(self, p => p.extent())
    }

    /// The shape as a `.scene` statement: its keyword (`tri`, `sphere`) and its numbers
    /// ([`Primitive::numbers`]: a triangle's 9 coordinates, a sphere's centre and radius),
    /// each number written exactly ([`crate::math::real::exact_decimal`]: the same value read
    /// in f32, f64 or exact arithmetic).
    pub fn scene_line(&self) -> String {
        fn line<T: Real, P: Primitive<T>>(p: &P) -> String {
            let numbers: Vec<String> = (p.numbers())
                .map(|x| crate::math::real::exact_decimal(x.f64()))
                .collect();
            format!("{} {}", P::KEYWORD, numbers.join(" "))
        }
        dispatch!(self, p => line(p))
    }

    /// Whether no ray hits this primitive though it keeps its index
    /// ([`Primitive::is_degenerate`]: a triangle of zero area, [`triangle::zero_area`]).
    pub fn is_degenerate(&self) -> bool {
        dispatch!(self, p => p.is_degenerate())
    }

    /// Intersects with `method`; a hit needs tmin < t < tmax. A triangle of zero area is never
    /// hit.
    #[inline]
    pub fn intersect(&self, ray: &Ray<T>, method: Method, tmin: T, tmax: T) -> Option<(T, T, T)> {
        if method == Method::Adaptive {
            let h = adaptive::closest_hit_reference(std::slice::from_ref(self), ray, tmin, tmax)?;
            return Some((T::of(h.t), T::of(h.b1), T::of(h.b2)));
        }
        dispatch!(self, p => p.intersect(ray, method, tmin, tmax))
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (V3<T>, V3<T>) {
        dispatch!(self, p => p.bounds())
    }

    /// [`Primitive::widen`] ([`adaptive::widen`]).
    pub(crate) fn widen(&self) -> Shape<f64> {
        dispatch!(self, p => p.widen())
    }

    /// [`Primitive::f32_filter`].
    pub(crate) fn f32_filter(&self, o: [f32; 3], d: [f32; 3]) -> Option<Estimate> {
        dispatch!(self, p => p.f32_filter(o, d))
    }

    /// [`Primitive::f64_intervals`].
    pub(crate) fn f64_intervals(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Estimate {
        dispatch!(self, p => p.f64_intervals(o, d, tmin, tmax))
    }

    /// [`Primitive::decide_exactly`].
    pub(crate) fn decide_exactly(
        &self,
        o: [f64; 3],
        d: [f64; 3],
        tmin: f64,
        tmax: f64,
    ) -> Option<Decided> {
        dispatch!(self, p => p.decide_exactly(o, d, tmin, tmax))
    }

    /// [`Primitive::exact_t`].
    pub(crate) fn exact_t(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<ExactT> {
        dispatch!(self, p => p.exact_t(o, d, tmin, tmax))
    }

    /// [`Primitive::same_t`].
    pub(crate) fn same_t(&self, other: &Shape<T>) -> bool {
        dispatch!(self, p => p.same_t(other))
    }

    /// [`Primitive::t_in_f64`].
    pub(crate) fn t_in_f64(
        &self,
        o: [f64; 3],
        d: [f64; 3],
        tmin: f64,
        tmax: f64,
    ) -> Option<(f64, f64)> {
        dispatch!(self, p => p.t_in_f64(o, d, tmin, tmax))
    }

    /// [`Primitive::t_rounded`].
    pub(crate) fn t_rounded<R: Real>(
        &self,
        o: [f64; 3],
        d: [f64; 3],
        tmin: f64,
        tmax: f64,
    ) -> Option<R> {
        dispatch!(self, p => p.t_rounded::<R>(o, d, tmin, tmax))
    }
}

impl Shape<f32> {
    /// Whether `p` is outside the closed shape ([`Primitive::outside`]): `None` for a triangle
    /// (no inside), and within 10⁻⁹ relative of a sphere's surface.
    pub fn outside(&self, p: [f32; 3]) -> Option<bool> {
        dispatch!(self, s => s.outside(p))
    }

    /// [`Primitive::shadow_clear_of_itself`]: whether the shadow segment from `light` to this
    /// surface's offset point (offset outwards where `end_outside`) may skip this shape.
    pub fn shadow_clear_of_itself(&self, light: [f32; 3], end_outside: bool) -> bool {
        dispatch!(self, p => p.shadow_clear_of_itself(light, end_outside))
    }

    /// Where `ray`'s hit on this shape is shaded ([`Primitive::surface_point`]).
    pub fn surface_point(&self, ray: &Ray<f32>) -> SurfacePoint {
        dispatch!(self, p => p.surface_point(ray))
    }

    /// The shape's kind and numbers as bits (−0 as +0): equal keys are the same shape to the
    /// bit (finding copies at build).
    #[inline]
    pub fn key(&self) -> (u8, [u32; 9]) {
        #[inline]
        fn key<P: Primitive<f32>>(p: &P) -> (u8, [u32; 9]) {
            let mut k = [0; 9];
            for (slot, x) in k.iter_mut().zip(p.numbers()) {
                *slot = (x + 0.0).to_bits();
            }
            (P::KIND, k)
        }
        dispatch!(self, p => key(p))
    }

    /// The geometric normal (not of unit length, in f64) where `ray` meets this shape at `t`:
    /// a triangle's e₁ × e₂, a sphere's p − c.
    pub fn normal_at(&self, ray: &Ray<f32>, t: f32) -> [f64; 3] {
        dispatch!(self, p => p.normal_at(ray, t))
    }

    /// This shape's terms for `ray` ([`ShapeTerms`]).
    pub fn terms(&self, ray: &Ray<f32>) -> ShapeTerms {
        dispatch!(self, p => p.terms(ray))
    }
}

impl ShapeTerms {
    /// The `name: value` lines of `raylab inspect` (every digit).
    pub fn lines(&self) -> Vec<String> {
        dispatch_terms!(self, t => t.lines())
    }

    /// The window panel's (label, value) rows, the values formatted by `v3` (vectors) or to
    /// a few digits (other numbers).
    pub fn rows(&self, v3: impl Fn([f64; 3]) -> String) -> Vec<(&'static str, String)> {
        dispatch_terms!(self, t => t.rows(&v3))
    }
}
