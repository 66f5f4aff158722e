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
//! reference); [`nearest`] and [`any`] fold one query over them. Ties go to the
//! lower primitive index in every layout, so the fold's answer does not depend on their order.
//!
//! Packets (8 or 16 rays from one origin) are the BVH's own walk and the spheres': a layout
//! without a packet walk is traced per ray (`Triangles::bvh` says which layout has one).
//!
//! Adding a layout (a BVH4, a grid): its files, `impl Layout` for it, a variant of
//! `Triangles` with its arms in triangles.rs (build, `layout`, `kind`), its name in
//! [`AccelChoice`], and a line in `accel::testing::layouts`. tests/accel.rs runs every layout
//! against the reference loop on random and hard-case scenes.
//!
//! [`Accel`]: super::Accel
//! [`AccelChoice`]: super::AccelChoice
//! [`InOrder`]: super::reference::InOrder

use crate::geometry::adaptive::Search;
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray};

/// What every structure over primitives answers (see the module docs).
pub trait Layout: Send + Sync {
    /// The nearest hit with `method` (not [`Method::Adaptive`]), tmin < t < tmax, merged into
    /// `best`: a hit replaces it when nearer, or as near with a lower primitive index.
    fn nearest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, best: &mut Option<Hit>);

    /// The exact nearest hit: offers to `search` every primitive that may be the nearest
    /// within its interval.
    fn nearest_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &mut Search);

    /// Whether a primitive other than `skip` is hit with `method`, tmin < t < tmax.
    fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool;

    /// Whether a primitive other than `skip` is certainly hit within `search`'s interval.
    fn any_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &Search, skip: u32) -> bool;
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
pub fn nearest(
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
                part.nearest_exact(ray, &r, &mut search);
            }
        }
        return search.hit();
    }
    let mut best = None;
    for part in parts {
        part.nearest(ray, method, tmin, tmax, &mut best);
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
