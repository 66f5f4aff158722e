//! Closest-hit and any-hit queries over a scene's primitives, with the structure chosen per
//! scene: the 30-triangle Cornell box is fastest as the flat SIMD loop ([`flat::FlatLoop`]), a
//! 70k-triangle scan as a BVH ([`bvh::Bvh`]). Every path returns exactly the nearest hit of the
//! scalar reference loop ([`mod@reference`]) with the same intersection method
//! (tests/library/accel.rs holds them to it).
//!
//! The renderer sees one face: [`FrameQueries`] (made by [`Accel::for_frame`]) hands out
//! per-tile queries that are always fully resolved: camera rays 8 at a time or per ray,
//! shadow segments 8 at a time or per ray. Which structure, which rays go in packets, what is
//! prepared once per frame, tile culling and the exact resolvers of ambiguous lanes all stay
//! inside this module.
//!
//! Names inside the module. Two queries, one stem each at every level: the nearest hit is
//! `closest`, whether anything is hit (a shadow's question) is `any`. What the rays are: `_hit` one
//! ray; `_packet` 8 rays sharing an origin, through one structure; `_x8` 8 lanes: a tile's 8 rays
//! through the whole scene, or one ray against 8 triangles in the flat loop's lanes; `_lane` one
//! lane of a packet, decided alone. How: `_exact` the adaptive search's exact level; `_from_origin`
//! / `_from` / `_prepared` / `_of_triangles` with the triangles prepared once for the rays' origin;
//! `_seeded` starting from a hit already known; `_in` inside a kernel already built for one SIMD
//! level (no run-time choice: it takes the build's token or lanes; a few functions below the frame
//! take the token without the suffix: `closest_packet_of_triangles`, `any_packet_from`, …);
//! `_untrusted` where the f32 box test cannot be trusted (every triangle); `_body` the lane-generic
//! body that the dispatch macro builds per SIMD level; `walk_*` a BVH traversal.
//!
//! Crossover: below [`BVH_MIN_TRIANGLES`] triangles the flat SIMD loop wins; measured with
//! `raylab bench --accel flat|bvh` on subsets of the bunny mesh (docs/performance.md). Above
//! it, `auto` keeps the flat loop where the BVH would not cull ([`SOUP_SHARE`]).

/// The triangles' layouts, one line each: `Variant(module::Type)`, its doc the
/// [`AccelChoice`] variant's. The list makes each layout's variant of [`AccelChoice`] (named
/// by its [`TriangleLayout::NAME`](layout::TriangleLayout::NAME)) and its place in
/// `AccelChoice::ALL`, its variant of `Triangles` (the structure over a scene's stored
/// triangles), its arm of `each_layout!` (the one match over them) and of `Triangles::build`
/// (by [`TriangleLayout::build`](layout::TriangleLayout::build)) and `Triangles::kind`. A new
/// layout is its file, its `mod` line and its line in the list (layout.rs says what the file
/// holds); the module is declared beside the list, not by it: rustfmt does not reach a module
/// a macro declares.
macro_rules! layouts {
    ($d:tt $($(#[$doc:meta])* $variant:ident($module:ident::$ty:ident)),+ $(,)?) => {

        /// Which structure to build.
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        pub enum AccelChoice {
            /// By primitive count (see [`BVH_MIN_TRIANGLES`]).
            #[default]
            Auto,
            $($(#[$doc])* $variant,)+
        }

        impl AccelChoice {
            /// Every choice: `auto`, then each layout of the triangles (what [`Accel::kind`]
            /// names).
            pub const ALL: [AccelChoice; 1 + [$(layouts!(@one $variant)),+].len()] =
                [AccelChoice::Auto, $(AccelChoice::$variant),+];

            /// CLI name.
            pub fn name(self) -> &'static str {
                match self {
                    AccelChoice::Auto => "auto",
                    $(AccelChoice::$variant => <$module::$ty as layout::TriangleLayout>::NAME,)+
                }
            }
        }

        /// The structure over a scene's stored triangles: the one dispatch on the layout
        /// (its queries: triangles.rs).
        #[derive(Clone, Debug)]
        pub(crate) enum Triangles {
            $($variant($module::$ty),)+
        }

        /// `$body` with `$t` bound to the layout in `$tris` (a [`Triangles`]): the one match
        /// over every variant.
        macro_rules! each_layout {
            ($d tris:expr, $d t:ident => $d body:expr) => {
                match $d tris {
                    $(Triangles::$variant($d t) => $d body,)+
                }
            };
        }

        impl Triangles {
            /// Builds the layout `choice` names over `tris` (copies already left out). `Auto`
            /// is the caller's to resolve by count; given here, it builds the BVH, as a large
            /// scene resolves it.
            pub(crate) fn build(tris: &[IndexedTriangle], choice: AccelChoice) -> Self {
                use layout::TriangleLayout;
                match choice {
                    $(AccelChoice::$variant => Triangles::$variant(<$module::$ty>::build(tris)),)+
                    AccelChoice::Auto => Self::build(tris, AccelChoice::Bvh),
                }
            }

            /// Which layout this is.
            pub(crate) fn kind(&self) -> AccelChoice {
                match self {
                    $(Triangles::$variant(_) => AccelChoice::$variant,)+
                }
            }
        }
    };
    (@one $variant:ident) => {
        ()
    };
}

pub(crate) mod bvh;
pub(crate) mod flat;

layouts! { $
    /// The flat SIMD loop over all triangles.
    Flat(flat::FlatLoop),
    /// A BVH.
    Bvh(bvh::Bvh),
}

mod cull;
pub(crate) mod frame;
pub(crate) mod instances;
pub(crate) mod layout;
pub(crate) mod packet;
pub(crate) mod prepared;
pub mod reference;
pub(crate) mod spheres;
#[doc(hidden)]
pub mod testing;
mod triangles;

use crate::geometry::adaptive::Search;
use crate::geometry::instance::Instance;
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::math::simd::{with_cpu_isa, Isa};
use crate::scene::Scene;
use crate::words::count;
use layout::Layout;
use rayon::prelude::*;
use spheres::Spheres;
use std::fmt;
use std::str::FromStr;

pub use frame::{
    FrameQueries, FrameSetup, OriginTriangle, ShadowSegments, TileQueries, TileScratch, NO_HIT,
};
pub use reference::{any_hit, closest_hit};

/// A triangle's vertices with its primitive index in the scene.
pub type IndexedTriangle = ([[f32; 3]; 3], u32);

/// Up to this many triangles the renderer culls camera rays per screen tile (whatever the
/// structure): measured faster than the BVH for framed meshes of 20 to 1280 triangles.
pub const TILE_CULL_MAX_TRIANGLES: usize = 2048;

/// From this many primitives on (triangles, spheres), `auto` builds a BVH.
pub const BVH_MIN_TRIANGLES: usize = 64;

/// The share of the triangles beyond which a BVH's estimate of the tests a ray makes
/// (`Bvh::expected_tests`) has `auto` choose the flat loop instead: where the triangles'
/// boxes overlap throughout (a soup of long triangles on an integer grid, 0.43–0.51 of them),
/// the walk visits most leaves, each test dearer than the flat loop's. 20,000 such triangles,
/// 160×90, 2 threads: the BVH 446 ms a frame, the flat loop 167 ms; 340,000: 10.6 s and 2.0 s;
/// 2,000: the same (so only above [`TILE_CULL_MAX_TRIANGLES`]). A mesh's estimate is a few
/// dozen (the bunny 8.3, Igea 16.7).
pub const SOUP_SHARE: f64 = 1.0 / 3.0;

impl fmt::Display for AccelChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for AccelChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        // "brute", the flat loop's name before it was called what it is, still works.
        let s = if s == "brute" { "flat" } else { s };
        AccelChoice::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = AccelChoice::ALL.iter().map(|c| c.name()).collect();
                let (last, rest) = names.split_last().expect("auto and a layout");
                format!(
                    "unknown accelerator '{s}' (expected {} or {last})",
                    rest.join(", ")
                )
            })
    }
}

/// The structure over one scene's primitives.
#[derive(Clone, Debug)]
pub struct Accel {
    triangles: Triangles,
    /// The triangles in primitive order (for the scalar methods and tile culling).
    list: Vec<IndexedTriangle>,
    /// The primitives the triangle structures do not hold (spheres), with their indices, in
    /// a hierarchy of their own.
    spheres: Spheres,
    /// Triangles left out as copies of an earlier one (see [`without_copies`]).
    copies: usize,
    /// Other shapes left out as copies of an earlier one ([`others_without_copies`]).
    other_copies: usize,
    /// Triangles of zero area left out: no ray hits them ([`without_zero_area`]).
    degenerate: usize,
    /// The meshes placed as instances, if any ([`instances::Instances`]).
    instances: Option<Box<instances::Instances>>,
    /// The stored triangles' typical side, for the frames' plan ([`frame::typical_side`]).
    typical_side: f32,
    /// The frames' caches of triangles prepared for the eye and the light, kept between
    /// frames ([`prepared::LeafCache`]).
    caches: prepared::CachePool,
}

impl Accel {
    /// Builds over a scene's primitives, its placed meshes included (primitive indices as
    /// [`Scene::shape`] numbers them).
    pub fn for_scene(scene: &Scene, choice: AccelChoice) -> Self {
        match scene.instances().is_empty() {
            true => Self::build(&scene.shapes, choice),
            false => {
                Self::build_with_instances(scene.explicit_with_prims(), scene.instances(), choice)
            }
        }
    }

    /// What the build left out of `scene`'s primitives as copies, as a warning naming the
    /// scene: triangles that repeat an earlier triangle's vertices, spheres an earlier sphere;
    /// `None` when nothing was.
    pub fn copies_warning(&self, scene: &Scene) -> Option<String> {
        let (copies, others) = (self.copies, self.other_copies);
        let mut what = Vec::new();
        if copies > 0 {
            let repeat = count(copies, "triangle repeats", "triangles repeat");
            what.push(format!("{repeat} an earlier triangle's vertices exactly"));
        }
        if others > 0 {
            let repeat = count(others, "sphere repeats", "spheres repeat");
            what.push(format!("{repeat} an earlier sphere exactly"));
        }
        (!what.is_empty()).then(|| {
            format!(
                "{}: {}: each is kept once (the earlier one answers every ray either would)",
                scene.name,
                what.join(", and ")
            )
        })
    }

    /// Builds over `shapes` (primitive index = position in the slice).
    pub fn build(shapes: &[Shape<f32>], choice: AccelChoice) -> Self {
        // Straight from the slice, in parallel: copying every shape with its index first, then
        // sorting triangles from the rest one push at a time, was a sixth of a 1M-triangle
        // mesh's build.
        let triangle = |(i, s): (usize, &Shape<f32>)| s.triangle().map(|v| (*v, i as u32));
        let tris: Vec<IndexedTriangle> = match shapes.iter().all(Shape::is_triangle) {
            // Indexed: written in place (a filtered collect gathers pieces and copies them).
            true => (shapes.par_iter().enumerate())
                .map(|x| triangle(x).unwrap())
                .collect(),
            false => (shapes.par_iter().enumerate())
                .filter_map(triangle)
                .collect(),
        };
        let others = (shapes.iter().enumerate())
            .filter(|(_, s)| !s.is_triangle())
            .map(|(i, s)| (*s, i as u32))
            .collect();
        Self::over(tris, others, &[], choice)
    }

    /// Builds over `shapes` (each with its primitive index) and the meshes placed as
    /// `instances` (a two-level structure: [`instances::Instances`]). With instances, the
    /// explicit triangles go into a BVH unless `choice` is [`AccelChoice::Flat`], so that
    /// camera and shadow packets serve both.
    pub fn build_with_instances(
        shapes: Vec<(Shape<f32>, u32)>,
        instances: &[Instance],
        choice: AccelChoice,
    ) -> Self {
        let mut tris = Vec::new();
        let mut others = Vec::new();
        for (s, i) in shapes {
            match s.triangle() {
                Some(v) => tris.push((*v, i)),
                None => others.push((s, i)),
            }
        }
        Self::over(tris, others, instances, choice)
    }

    /// Builds over triangles and other shapes, each with its primitive index, and instances.
    fn over(
        tris: Vec<IndexedTriangle>,
        others: Vec<(Shape<f32>, u32)>,
        instances: &[Instance],
        choice: AccelChoice,
    ) -> Self {
        let (tris, degenerate) = without_zero_area(tris);
        let (mut tris, mut copies) = without_copies(tris);
        let (others, other_copies) = others_without_copies(others);
        let instances = (!instances.is_empty()).then(|| {
            let built = instances::Instances::build(instances);
            copies += built.copies_left_out();
            Box::new(built)
        });
        let auto = choice;
        let mut choice = match choice {
            // Every primitive counts: 3,000 spheres and no triangle took 0.66 s at 64×48 with
            // the flat loop, 0.04 s with the BVH's frame plan (the same image).
            AccelChoice::Auto
                if tris.len() + others.len() < BVH_MIN_TRIANGLES && instances.is_none() =>
            {
                AccelChoice::Flat
            }
            AccelChoice::Auto => AccelChoice::Bvh,
            chosen => chosen,
        };
        let mut triangles = Triangles::build(&tris, choice);
        if let (AccelChoice::Auto, Triangles::Bvh(b)) = (auto, &triangles) {
            let soup = b.expected_tests() > tris.len() as f64 * SOUP_SHARE;
            if soup && tris.len() > TILE_CULL_MAX_TRIANGLES {
                choice = AccelChoice::Flat;
                triangles = Triangles::build(&tris, choice);
            }
        }
        let typical_side = frame::typical_side(&tris);
        if choice == AccelChoice::Bvh && tris.len() > TILE_CULL_MAX_TRIANGLES {
            tris = Vec::new(); // the BVH holds its own copy
        }
        Self {
            triangles,
            list: tris,
            spheres: Spheres::build(others),
            copies,
            other_copies,
            degenerate,
            instances,
            typical_side,
            caches: prepared::CachePool::default(),
        }
    }

    /// The two-level structure over the scene's instances, if it has any.
    pub fn instances(&self) -> Option<&instances::Instances> {
        self.instances.as_deref()
    }

    /// How many triangles were left out as exact copies of an earlier one (the same three
    /// vertices in any order): whoever loads a scene says so.
    pub fn copies_left_out(&self) -> usize {
        self.copies
    }

    /// How many shapes other than triangles (spheres) were left out as exact copies of an
    /// earlier one.
    pub fn other_copies_left_out(&self) -> usize {
        self.other_copies
    }

    /// Which structure was built (never [`AccelChoice::Auto`]).
    pub fn kind(&self) -> AccelChoice {
        self.triangles.kind()
    }

    /// The triangles in primitive order, for the renderer's tile culling: `None` above
    /// [`TILE_CULL_MAX_TRIANGLES`]. (With other shapes among them, a triangle's position here
    /// is not its primitive index: see [`Accel::slot`].)
    pub fn flat_triangles(&self) -> Option<&[IndexedTriangle]> {
        let small = !self.list.is_empty()
            && self.list.len() <= TILE_CULL_MAX_TRIANGLES
            && self.instances.is_none();
        small.then_some(&self.list)
    }

    /// The position in [`Accel::flat_triangles`] of triangle primitive `prim`.
    pub fn slot(&self, prim: u32) -> usize {
        match self.spheres.is_empty() && self.copies == 0 && self.degenerate == 0 {
            true => prim as usize,
            false => self.list.partition_point(|t| t.1 < prim),
        }
    }

    /// Boxes around the triangles, instanced ones included, as a tree for tile culling
    /// ([`cull::ScreenTree`]): the triangle layout's top boxes (`Triangles::top_boxes`);
    /// with instances, one box around everything. Empty: no triangles.
    pub(crate) fn triangle_boxes(&self, depth: usize) -> Vec<cull::TreeNode> {
        let Some(inst) = self.instances() else {
            return self.triangles.top_boxes(depth);
        };
        let mut all = inst.world_bounds();
        if let Some(own) = self.triangles.bounding_box() {
            all.grow(&bvh::Aabb {
                lo: own.lo,
                hi: own.hi,
            });
        }
        vec![((all.lo, all.hi), None)]
    }

    /// How many shapes the triangle structures do not hold (spheres; copies left out).
    pub fn other_shape_count(&self) -> usize {
        self.spheres.len()
    }

    /// The shapes the triangle structures do not hold (spheres), with their primitives, in
    /// no particular order.
    pub fn other_shapes(&self) -> impl Iterator<Item = &(Shape<f32>, u32)> {
        self.spheres.shapes()
    }

    /// The spheres' hierarchy (for the frames' packets).
    pub(crate) fn spheres(&self) -> &Spheres {
        &self.spheres
    }

    /// How many triangles the structure answers for (copies left out), instanced ones
    /// included.
    pub fn triangle_count(&self) -> usize {
        self.stored_triangle_count() + self.instances().map_or(0, |i| i.triangle_count())
    }

    /// How many triangles are stored one by one (not through instances).
    pub fn stored_triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Whether the scene holds shapes other than triangles (the frame's packets test them
    /// lane by lane, the per-ray queries one by one).
    pub fn has_other_shapes(&self) -> bool {
        !self.spheres.is_empty()
    }

    /// Bytes of the structure (triangles included).
    pub fn memory_bytes(&self) -> usize {
        let list = self.list.len() * std::mem::size_of::<IndexedTriangle>();
        let instanced = self.instances().map_or(0, |i| i.memory_bytes());
        list + instanced
            + self.caches.memory_bytes()
            + self.triangles.memory_bytes()
            + self.spheres.memory_bytes()
    }

    /// Calls `f` with the layouts answering together: the triangles' structure, the
    /// instances if any, the other shapes if any.
    #[inline]
    fn with_parts<R>(&self, f: impl FnOnce(&[&dyn Layout]) -> R) -> R {
        let tris: &dyn Layout = &self.triangles;
        match (self.instances(), self.spheres.is_empty()) {
            (None, true) => f(&[tris]),
            (None, false) => f(&[tris, &self.spheres]),
            (Some(inst), true) => f(&[tris, inst]),
            (Some(inst), false) => f(&[tris, inst, &self.spheres]),
        }
    }

    /// Nearest hit with tmin < t < tmax; an exact tie goes to the lowest primitive index.
    pub fn closest_hit(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32) -> Option<Hit> {
        self.with_parts(|parts| layout::closest(parts, ray, method, tmin, tmax))
    }

    /// The triangles prepared for rays from `origin` ([`packet::OriginTriangles`]) in the
    /// order the packets read them.
    pub fn prepare_origin(&self, origin: [f32; 3]) -> packet::OriginTriangles {
        self.triangles.prepared_for(origin)
    }

    /// An empty cache of the triangles prepared for `origin`, for one frame;
    /// [`Accel::keep_leaf_cache`] takes it back.
    pub(crate) fn leaf_cache(&self, origin: [f32; 3]) -> prepared::LeafCache {
        self.caches.take(self.triangles.len(), origin)
    }

    /// Keeps a frame's cache for the next frame.
    pub(crate) fn keep_leaf_cache(&self, cache: prepared::LeafCache) {
        self.caches.give(cache);
    }

    /// The adaptive nearest hit for a ray from the origin `prepared` was made for: the same
    /// primitive as [`Accel::closest_hit`] with [`Method::Adaptive`], found with the cheaper
    /// shared-origin f32 level where the layout has that walk (the BVH's).
    pub(crate) fn closest_hit_prepared(
        &self,
        ray: &Ray,
        prepared: prepared::Prepared<'_>,
        tmin: f32,
        tmax: f32,
    ) -> Option<Hit> {
        let mut search = Search::new(ray, tmin, tmax);
        if !(self.triangles).closest_prepared(ray, prepared, &mut search) {
            return self.closest_hit(ray, Method::Adaptive, tmin, tmax);
        }
        if let Some(r) = WatertightRay::new(ray.o, ray.d) {
            // The other parts as in every exact query.
            self.with_parts(|parts| {
                for part in &parts[1..] {
                    part.closest_exact(ray, &r, &mut search);
                }
            });
        }
        search.hit()
    }

    /// Camera rays 8 at a time from one origin `o` through the triangles' packet walk
    /// (`prepared`: the triangles prepared for `o` by [`Accel::prepare_origin`], or `None` to
    /// prepare them as the packet meets them): per lane the primitive [`Accel::closest_hit`]
    /// with [`Method::Adaptive`] names (u32::MAX for none), and the lanes left ambiguous, to
    /// be traced per ray. `None` where there are other shapes.
    pub fn closest_packet(
        &self,
        o: [f32; 3],
        prepared: Option<&packet::OriginTriangles>,
        d: &[wide::f32x8; 3],
        d_max: f32,
    ) -> Option<packet::PacketHits> {
        if self.has_other_shapes() {
            return None;
        }
        let prepared = prepared::Prepared::from_list(prepared);
        let found = with_cpu_isa!(|isa| {
            self.closest_packet_of_triangles(isa, o, prepared, d, d_max, None)
        });
        Some(found)
    }

    /// [`Accel::closest_packet`] over the triangles alone, whatever other shapes there are,
    /// starting from `seed` (its ids must be beyond every primitive and slot, and are handed
    /// back as they are), in the build `isa` names.
    #[inline(always)]
    pub(crate) fn closest_packet_of_triangles<I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        prepared: prepared::Prepared<'_>,
        d: &[wide::f32x8; 3],
        d_max: f32,
        seed: Option<&packet::PacketSeed>,
    ) -> packet::PacketHits {
        (self.triangles).closest_packet(isa, self.instances(), o, prepared, d, d_max, seed)
    }

    /// [`Accel::closest_packet_of_triangles`] (no seed, no instances) inside a kernel already
    /// in lanes `V` of any width: primitives into `prim[..V::WIDTH]`, the ambiguous lanes
    /// returned; `None` where there are instances.
    #[inline(always)]
    pub(crate) fn closest_packet_in<V: crate::math::lanes::LaneOps>(
        &self,
        o: [f32; 3],
        prepared: prepared::Prepared<'_>,
        d: [V; 3],
        d_max: f32,
        prim: &mut [u32],
    ) -> Option<u32> {
        if self.instances().is_some() {
            // (8 lanes at a time there: 16-lane packets through the field of 1,000 bunnies
            // took 10% longer, its packets part at the instances' boxes.)
            return None;
        }
        Some((self.triangles).closest_packet_in(o, prepared, d, d_max, prim))
    }

    /// Shadow segments 8 at a time from one origin `o` (the light) through the triangles'
    /// packet walk (`prepared`: the triangles prepared for `o` by [`Accel::prepare_origin`],
    /// or `None` to prepare them as met): per lane whether [`Accel::any_hit`] with
    /// [`Method::Adaptive`] answers "blocked" for 0 < t < 1, or unsure. `None` where there
    /// are other shapes.
    pub fn any_packet(
        &self,
        o: [f32; 3],
        prepared: Option<&packet::OriginTriangles>,
        d: &[wide::f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> Option<packet::ShadowHits> {
        if self.has_other_shapes() {
            return None;
        }
        let prepared = prepared::Prepared::from_list(prepared);
        let found = with_cpu_isa!(|isa| {
            self.any_packet_of_triangles(isa, o, prepared, d, d_max, skip, valid)
        });
        Some(found)
    }

    /// [`Accel::any_packet`] over the triangles alone, whatever other shapes there are, in
    /// the build `isa` names.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn any_packet_of_triangles<I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        prepared: prepared::Prepared<'_>,
        d: &[wide::f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> packet::ShadowHits {
        let instances = self.instances();
        (self.triangles).any_packet(isa, instances, o, prepared, d, d_max, skip, valid)
    }

    /// Whether a primitive other than `skip` (u32::MAX: none) is hit with tmin < t < tmax (a
    /// shadow query: stops at the first). A shadow segment between a point on a triangle or
    /// sphere (offset off it) and a light on its lit side cannot meet that primitive (planar
    /// or convex): skipping it spares every shadow ray the decision at the segment's end on it.
    pub fn any_hit(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        self.with_parts(|parts| layout::any(parts, ray, method, tmin, tmax, skip))
    }
}

/// `tris` without the triangles of zero area, and how many were left out: such a triangle is
/// no surface and no method hits it ([`crate::geometry::triangle::zero_area`]), while the
/// SIMD loops, which run the watertight test lane by lane, could (its shear leaves a sliver
/// of some). Their primitive indices stay theirs: the others keep their own.
fn without_zero_area(tris: Vec<IndexedTriangle>) -> (Vec<IndexedTriangle>, usize) {
    use crate::geometry::triangle::zero_area;
    if !tris.par_iter().any(|(v, _)| zero_area(v)) {
        return (tris, 0);
    }
    let before = tris.len();
    let kept: Vec<IndexedTriangle> = (tris.into_par_iter())
        .filter(|(v, _)| !zero_area(v))
        .collect();
    let left_out = before - kept.len();
    (kept, left_out)
}

/// `tris` without the triangles that repeat an earlier one's vertices exactly (equal values,
/// -0 = +0), in the same order, and how many were left out. Such a copy can never be the
/// answer: every method computes what it computes for the earlier one (up to the sign of a
/// zero), ties go to the lower index in every query, and a shadow query that skips the
/// earlier one skips its copies (see [`reference::any_hit`]). Kept, a file of 10⁶ copies of
/// one face costs each ray 10⁶ exact tie-breaks; left out, it costs what one triangle does.
/// (The same vertices in another order are kept: the inexact methods may answer differently
/// for them, which is what they are shown for. There are at most 6 orders, so the work stays
/// bounded.) Found by sorting randomly keyed hashes, so no input can force the quadratic case;
/// the order of the rest is unchanged.
pub(crate) fn without_copies(tris: Vec<IndexedTriangle>) -> (Vec<IndexedTriangle>, usize) {
    let key = |t: &IndexedTriangle| Shape::from(t.0).key();
    let hasher = ahash::RandomState::new();
    // Each triangle as one u64: its hash's high bits above its index (sorting these is half
    // the work of sorting (hash, index) pairs; 44 bits of hash are left for 10⁶ triangles).
    let index_bits = usize::BITS - tris.len().leading_zeros();
    let hash_of = |x: u64| x >> index_bits;
    let index_of = |x: u64| (x & ((1 << index_bits) - 1)) as usize;
    let mut keyed: Vec<u64> = (tris.par_iter().enumerate())
        .map(|(i, t)| hash_of(hasher.hash_one(key(t))) << index_bits | i as u64)
        .collect();
    keyed.par_sort_unstable();
    let mut copy = vec![false; tris.len()];
    let mut copies = 0;
    let runs = keyed.chunk_by(|&a, &b| hash_of(a) == hash_of(b));
    for run in runs.filter(|r| r.len() > 1) {
        // In index order: the first of each distinct key in the run is kept.
        let mut kept: Vec<(u8, [u32; 9])> = Vec::new();
        for &x in run {
            let i = index_of(x);
            let k = key(&tris[i]);
            if kept.contains(&k) {
                copy[i] = true;
                copies += 1;
            } else {
                kept.push(k);
            }
        }
    }
    if copies == 0 {
        return (tris, 0);
    }
    let kept = tris
        .into_iter()
        .zip(copy)
        .filter_map(|(t, c)| (!c).then_some(t))
        .collect();
    (kept, copies)
}

/// `others` without the shapes that repeat an earlier one exactly ([`Shape::key`]): a copy is
/// never the nearest (ties go to the lower index) and blocks no shadow its original leaves lit;
/// kept, two coincident spheres send every ray that meets them to exact arithmetic to break
/// their tie. The order of the rest is unchanged.
fn others_without_copies(others: Vec<(Shape<f32>, u32)>) -> (Vec<(Shape<f32>, u32)>, usize) {
    let mut seen = std::collections::HashSet::with_capacity(others.len());
    let before = others.len();
    let kept: Vec<_> = (others.into_iter())
        .filter(|(s, _)| seen.insert(s.key()))
        .collect();
    let copies = before - kept.len();
    (kept, copies)
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    fn copies_are_left_out_in_order_among_many_triangles() {
        // 70,000 random triangles (17 index bits below each hash), some with a coordinate 0,
        // then 20,000 more drawn from the first ones: exact copies, copies with -0 for 0, and
        // the same vertices turned (kept). Exactly the first of each vertex list is kept, in
        // order, and the rest are counted.
        let mut x = 0x9e3779b97f4a7c15u64;
        let mut next = move || crate::math::xorshift(&mut x);
        let mut tris: Vec<IndexedTriangle> = (0..70_000u32)
            .map(|i| {
                let mut v = [[0.0f32; 3]; 3];
                for c in v.iter_mut().flatten() {
                    *c = (next() >> 40) as f32 / 64.0;
                }
                if i % 5 == 0 {
                    v[1][2] = 0.0;
                }
                (v, i)
            })
            .collect();
        for i in 70_000..90_000u32 {
            let (v, _) = tris[(next() % 70_000) as usize];
            let v = match next() % 3 {
                0 => v,
                1 => v.map(|p| p.map(|c| if c == 0.0 { -0.0 } else { c })),
                _ => [v[1], v[2], v[0]],
            };
            tris.push((v, i));
        }
        let key = |v: &[[f32; 3]; 3]| v.map(|p| p.map(|c| if c == 0.0 { 0 } else { c.to_bits() }));
        let mut seen = std::collections::HashSet::new();
        let want: Vec<IndexedTriangle> = (tris.iter().copied())
            .filter(|(v, _)| seen.insert(key(v)))
            .collect();
        let (kept, copies) = without_copies(tris.clone());
        assert_eq!(copies, tris.len() - want.len());
        assert!(copies > 10_000, "{copies} copies");
        assert!(kept == want);
    }

    /// This module's tests, for tests/unit.rs to run.
    /// A frame runs the build chosen as it starts ([`FrameQueries::build`]), whatever the
    /// limit says afterwards, and a tile's packets answer in it as every build answers. (The
    /// unit tests' binary is the one that never limits the builds elsewhere.)
    fn a_frame_keeps_the_build_chosen_as_it_starts() {
        use crate::math::simd::{self, SimdLevel};
        let scene = crate::scene::Scene::cornell();
        let accel = Accel::for_scene(&scene, AccelChoice::Bvh);
        let camera = crate::camera::Camera::cornell(64);
        let generator = camera.ray_generator(64, 64);
        let setup = FrameSetup {
            eye: generator.origin(),
            light: scene.light.position,
            projection: None,
            method: Method::Adaptive,
            camera_rays: 64 * 64,
            shadows: false,
            per_ray: false,
        };
        let best = accel.for_frame(&setup);
        assert_eq!(best.build().level(), simd::detected());
        let xs = wide::f32x8::from([0, 1, 2, 3, 0, 1, 2, 3].map(|x| 30.0 + x as f32));
        let ys = wide::f32x8::from([0, 0, 0, 0, 1, 1, 1, 1].map(|y| 40.0 + y as f32));
        let d = generator.directions_x8(xs, ys);
        let mut scratch = TileScratch::default();
        let want = best.tile([0, 0, 64, 64], &mut scratch).closest_x8(&d, 0xff);
        assert!(want.iter().all(|&p| p != NO_HIT), "{want:?}");
        drop(best);
        for lower in SimdLevel::ALL.into_iter().filter(|l| *l < simd::detected()) {
            let frame = simd::limited(lower, || accel.for_frame(&setup));
            assert_eq!(simd::level(), simd::detected(), "the limit is lifted");
            assert_eq!(frame.build().level(), lower);
            let got = frame
                .tile([0, 0, 64, 64], &mut scratch)
                .closest_x8(&d, 0xff);
            assert_eq!(got, want, "{lower}");
        }
    }

    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "copies_are_left_out_in_order_among_many_triangles",
            copies_are_left_out_in_order_among_many_triangles,
        ),
        (
            "a_frame_keeps_the_build_chosen_as_it_starts",
            a_frame_keeps_the_build_chosen_as_it_starts,
        ),
    ];
}
