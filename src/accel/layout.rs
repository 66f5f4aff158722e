//! The layout contract: what every structure over primitives answers, and the one place that
//! dispatches on which structure holds a scene's triangles.
//!
//! A layout ([`Layout`]) answers four per-ray queries over the primitives it holds, each with
//! tmin < t < tmax: the nearest hit with one of the inexact methods, merged into a best hit so
//! far; the exact nearest hit ([`Method::Adaptive`]), offering its candidates to one shared
//! [`Search`]; and an any-hit query (not primitive `skip`) for each. An [`Accel`] is a few
//! layouts answering together: the triangles' structure ([`Triangles`]: the flat loop or the
//! BVH), the placed meshes ([`Instances`]) and the other shapes, one by one
//! ([`InOrder`]); [`nearest`] and [`any`] fold one query over them. Ties go to the
//! lower primitive index in every layout, so the fold's answer does not depend on their order.
//!
//! Packets (8 or 16 rays from one origin) are the BVH's own: a layout without a packet walk
//! is traced per ray ([`Triangles::bvh`] says which layout has one).
//!
//! Adding a layout (a BVH4, a grid): its files, `impl Layout` for it, a variant of
//! [`Triangles`] with its arms below (build, `layout`, `kind`), and its name in
//! [`AccelChoice`]. tests/layouts.rs runs every layout ([`crate::accel::testing::layouts`])
//! against the reference loop on random and hard-case scenes.
//!
//! [`Accel`]: super::Accel
//! [`Instances`]: super::instances::Instances
//! [`AccelChoice`]: super::AccelChoice
//! [`InOrder`]: super::reference::InOrder

use super::bvh::Bvh;
use super::flat::FlatLoop;
use super::{AccelKind, IndexedTriangle};
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

/// The structure over a scene's stored triangles: the one dispatch on the layout.
#[derive(Clone, Debug)]
pub(crate) enum Triangles {
    Flat(FlatLoop),
    Bvh(Bvh),
}

impl Triangles {
    /// Builds the structure `use_bvh` names over `tris` (copies already left out).
    pub(crate) fn build(tris: &[IndexedTriangle], use_bvh: bool) -> Self {
        match use_bvh {
            true => Triangles::Bvh(Bvh::build(tris)),
            false => Triangles::Flat(FlatLoop::new(tris)),
        }
    }

    /// The per-ray queries.
    pub(crate) fn layout(&self) -> &dyn Layout {
        match self {
            Triangles::Flat(f) => f,
            Triangles::Bvh(b) => b,
        }
    }

    /// Which structure this is.
    pub(crate) fn kind(&self) -> AccelKind {
        match self {
            Triangles::Flat(_) => AccelKind::Flat,
            Triangles::Bvh(_) => AccelKind::Bvh,
        }
    }

    /// The BVH, the layout with packet walks (`None`: traced per ray).
    pub(crate) fn bvh(&self) -> Option<&Bvh> {
        match self {
            Triangles::Bvh(b) => Some(b),
            Triangles::Flat(_) => None,
        }
    }

    /// How many triangles are stored.
    pub(crate) fn len(&self) -> usize {
        match self {
            Triangles::Flat(f) => f.len(),
            Triangles::Bvh(b) => b.len(),
        }
    }

    /// Bytes of the structure.
    pub(crate) fn memory_bytes(&self) -> usize {
        match self {
            Triangles::Flat(f) => f.memory_bytes(),
            Triangles::Bvh(b) => b.memory_bytes(),
        }
    }
}
