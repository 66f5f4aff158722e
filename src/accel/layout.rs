//! The layout contract: what every structure over primitives answers, and the fold of one
//! query over the layouts of a scene.
//!
//! A layout ([`Layout`]) answers four per-ray queries over the primitives it holds, each with
//! tmin < t < tmax: the nearest hit with one of the inexact methods, merged into a best hit so
//! far; the exact nearest hit ([`Method::Adaptive`]), offering its candidates to one shared
//! [`Search`]; and an any-hit query (not primitive `skip`) for each. An [`Accel`] is a few
//! layouts answering together: the triangles' structure (`Triangles`: the flat loop or the
//! BVH, triangles.rs), the placed meshes (`Instances`) and the other shapes in a hierarchy of
//! their own (`Spheres`, spheres.rs; [`InOrder`], the loop in primitive order, is the
//! reference); [`closest`] and [`any`] fold one query over them. Ties go to the
//! lower primitive index in every layout, so the fold's answer does not depend on their order.
//!
//! Packets (8 or 16 rays from one origin, adaptive method) are the fifth query,
//! [`Layout::packet_into`]: the layout offers a packet's state (a [`PacketSink`]: the nearest
//! hits or the shadow segments) every triangle the live lanes may reach. Its provided default
//! leaves every lane to the per-ray queries, so a layout without a packet walk is still
//! answered exactly. The triangle layouts both walk packets: the BVH down its boxes, the flat
//! loop over every block. `Triangles` builds the packet queries on `packet_into`, with the
//! BVH's own faster walks where they apply (positions instead of primitives, no instances).
//!
//! A layout over a scene's stored triangles also answers [`TriangleLayout`]: its size, its
//! triangles prepared for one origin (the order its packet walk reads), its boxes for the
//! screen, and its own faster walks where it has them.
//!
//! Adding a layout (a BVH4, a grid) is its file and two lines: the file, with `impl Layout`
//! (whose `packet_into` may be left to its default) and `impl TriangleLayout` (its name, its
//! build, its size and preparations; its own faster walks are optional), and in accel/mod.rs
//! its `mod` line and its line in the `layouts!` list, which makes its [`AccelChoice`]
//! variant and its place in `AccelChoice::ALL`, and its variant and arms of `Triangles`. The tests take
//! every layout from that list (`accel::testing::layout_choices`): tests/library/accel.rs runs
//! each against the reference loop on random and hard-case scenes, per ray and in packets,
//! alone and beside instances.
//!
//! [`Accel`]: super::Accel
//! [`AccelChoice`]: super::AccelChoice
//! [`InOrder`]: super::reference::InOrder

use super::cull::{Box3, TreeNode};
use super::packet::{
    OriginTriangles, PacketHits, PacketNearest, PacketSeed, PacketSink, ShadowHits,
};
use super::prepared::Prepared;
use super::IndexedTriangle;
use crate::geometry::adaptive::Search;
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray};
use crate::math::lanes::{f32x8, LaneOps};
use crate::math::simd::Isa;

/// What every structure over primitives answers (see the module docs).
pub trait Layout: Send + Sync {
    /// The nearest hit with `method` (not [`Method::Adaptive`]), tmin < t < tmax, merged into
    /// `best`: a hit replaces it when nearer, or as near with a lower primitive index.
    fn closest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, best: &mut Option<Hit>);

    /// The exact nearest hit: offers to `search` every primitive that may be the nearest
    /// within its interval.
    fn closest_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &mut Search);

    /// Whether a primitive other than `skip` is hit with `method`, tmin < t < tmax.
    fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool;

    /// Whether a primitive other than `skip` is certainly hit within `search`'s interval.
    fn any_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &Search, skip: u32) -> bool;

    /// A packet of rays from `o` with directions `d` (the adaptive method): offers `sink`
    /// every triangle its live lanes may reach before their limits, taken from `prepared`
    /// where that was made for `o` and this layout, else prepared as met. Provided: every
    /// live lane left to the per-ray queries ([`PacketSink::per_ray`]).
    #[inline(always)]
    fn packet_into<V: LaneOps, S: PacketSink<V>>(
        &self,
        sink: &mut S,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
    ) where
        Self: Sized,
    {
        let _ = (o, prepared, d);
        sink.per_ray();
    }
}

/// What a layout over a scene's stored triangles answers beyond [`Layout`]: its size, its
/// triangles prepared for an origin, its boxes for the screen, and its own faster walks where
/// it has them (each provided from [`Layout::packet_into`] or left out where it has none).
pub(crate) trait TriangleLayout: Layout + Sized {
    /// Its name on the command line (`--accel NAME`) and in reports: its `AccelChoice`'s.
    const NAME: &'static str;

    /// The layout over `tris` (exact copies and triangles of zero area already left out).
    fn build(tris: &[IndexedTriangle]) -> Self;

    /// How many triangles are stored.
    fn len(&self) -> usize;

    /// Bytes of the structure.
    fn memory_bytes(&self) -> usize;

    /// Every triangle prepared for rays from `origin`, in the order its packet walk reads a
    /// `Prepared::All` list (and a frame's cache, in blocks of 8).
    fn prepared_for(&self, origin: [f32; 3]) -> OriginTriangles;

    /// The box around every triangle (`None`: there are none).
    fn bounding_box(&self) -> Option<Box3>;

    /// Boxes around the triangles as a tree for tile culling (`cull::ScreenTree`), down to
    /// `depth` levels below the root. Provided: the one box around them all.
    fn top_boxes(&self, depth: usize) -> Vec<TreeNode> {
        let _ = depth;
        (self.bounding_box().into_iter())
            .map(|b| ((b.lo, b.hi), None))
            .collect()
    }

    /// The adaptive nearest hit of `ray` among the triangles into `search`, from triangles
    /// `prepared` for its origin. Provided: false (nothing offered; also where `prepared`
    /// does not fit), and the caller asks the per-ray search instead.
    fn closest_prepared(&self, ray: &Ray, prepared: Prepared<'_>, search: &mut Search) -> bool {
        let _ = (ray, prepared, search);
        false
    }

    /// Its own walk of 8 camera rays, where faster than [`Layout::packet_into`] into a state
    /// the instances share (`Triangles::closest_packet`). Provided: none.
    fn own_closest_packet<I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> Option<PacketHits> {
        let _ = (isa, o, prepared, d, d_max, seed);
        None
    }

    /// Its own walk of 8 shadow segments (`Triangles::any_packet`). Provided: none.
    #[allow(clippy::too_many_arguments)]
    fn own_any_packet<I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> Option<ShadowHits> {
        let _ = (isa, o, prepared, d, d_max, skip, valid);
        None
    }

    /// `Triangles::closest_packet` (no seed, no instances) inside a kernel already in lanes
    /// `V` of any width: primitives into `prim[..V::WIDTH]`, the ambiguous lanes returned.
    /// Provided: through [`Layout::packet_into`].
    #[inline(always)]
    fn closest_packet_in<V: LaneOps>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
        d_max: f32,
        prim: &mut [u32],
    ) -> u32 {
        let mut nearest = PacketNearest::<V>::new_in(d, d_max);
        self.packet_into(&mut nearest, o, prepared, d);
        nearest.finish_into(prim)
    }
}

/// Keeps `hit` in `best` if it is nearer, or as near with a lower primitive index.
#[inline]
pub(crate) fn merge(best: &mut Option<Hit>, hit: Option<Hit>) {
    if let Some(h) = hit {
        if best.is_none_or(|b| h.t < b.t || (h.t == b.t && h.prim < b.prim)) {
            *best = Some(h);
        }
    }
}

/// The nearest hit over `parts` with tmin < t < tmax (ties to the lower primitive index).
pub fn closest(
    parts: &[&dyn Layout],
    ray: &Ray,
    method: Method,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    if method == Method::Adaptive {
        let mut search = Search::new(ray, tmin, tmax);
        if let Some(r) = WatertightRay::new(ray.o, ray.d) {
            for part in parts {
                part.closest_exact(ray, &r, &mut search);
            }
        }
        return search.hit();
    }
    let mut best = None;
    for part in parts {
        part.closest(ray, method, tmin, tmax, &mut best);
    }
    best
}

/// Whether anything in `parts` but primitive `skip` is hit with tmin < t < tmax.
pub fn any(
    parts: &[&dyn Layout],
    ray: &Ray,
    method: Method,
    tmin: f32,
    tmax: f32,
    skip: u32,
) -> bool {
    if method == Method::Adaptive {
        let Some(r) = WatertightRay::new(ray.o, ray.d) else {
            return false;
        };
        let search = Search::new(ray, tmin, tmax);
        return (parts.iter()).any(|part| part.any_exact(ray, &r, &search, skip));
    }
    (parts.iter()).any(|part| part.any(ray, method, tmin, tmax, skip))
}
