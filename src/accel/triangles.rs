//! The structure over a scene's stored triangles, chosen per scene: the one dispatch on the
//! layout (see [`super::layout`] for the contract each one answers).

use super::bvh::Bvh;
use super::flat::FlatLoop;
use super::layout::Layout;
use super::{AccelKind, IndexedTriangle};

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
