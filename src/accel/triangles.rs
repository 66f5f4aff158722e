//! The structure over a scene's stored triangles, chosen per scene: the queries of
//! [`Triangles`] (the enum and its one dispatch, `each_layout!`, are made by the list of
//! layouts in accel/mod.rs, over the contract of [`super::layout`]), and the packet queries
//! built on the layouts' packet walks, with the placed meshes (`Instances`) filling the same
//! packet state.
//!
//! Adding a triangle layout: see [`super::layout`].

use super::cull::{Box3, TreeNode};
use super::instances::Instances;
use super::layout::{Layout, TriangleLayout};
use super::packet::{
    OriginTriangles, PacketHits, PacketNearest, PacketSeed, PacketSink, ShadowHits, ShadowPacket,
};
use super::prepared::Prepared;
use super::Triangles;
use crate::geometry::adaptive::Search;
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray};
use crate::math::lanes::{LaneOps, Lanes};
use crate::math::simd::{avx512_avx2_or_baseline, each3, Isa};
use wide::f32x8;

impl Triangles {
    /// How many triangles are stored.
    pub(crate) fn len(&self) -> usize {
        each_layout!(self, t => TriangleLayout::len(t))
    }

    /// Bytes of the structure.
    pub(crate) fn memory_bytes(&self) -> usize {
        each_layout!(self, t => TriangleLayout::memory_bytes(t))
    }

    /// [`TriangleLayout::prepared_for`].
    pub(crate) fn prepared_for(&self, origin: [f32; 3]) -> OriginTriangles {
        each_layout!(self, t => TriangleLayout::prepared_for(t, origin))
    }

    /// [`TriangleLayout::bounding_box`].
    pub(crate) fn bounding_box(&self) -> Option<Box3> {
        each_layout!(self, t => TriangleLayout::bounding_box(t, ))
    }

    /// [`TriangleLayout::top_boxes`].
    pub(crate) fn top_boxes(&self, depth: usize) -> Vec<TreeNode> {
        each_layout!(self, t => TriangleLayout::top_boxes(t, depth))
    }

    /// [`TriangleLayout::closest_prepared`].
    pub(crate) fn closest_prepared(
        &self,
        ray: &Ray,
        prepared: Prepared<'_>,
        search: &mut Search,
    ) -> bool {
        each_layout!(self, t => TriangleLayout::closest_prepared(t, ray, prepared, search))
    }

    /// The nearest primitive along 8 rays from `o` (the adaptive method), over the triangles
    /// and the placed meshes `instances`, starting from `seed` (its ids must be beyond every
    /// primitive and slot, and are handed back as they are); lanes the bounds cannot decide
    /// are ambiguous. The layout's own walk where it has one and there are no instances,
    /// else its `packet_into` and the instances' walk into one state.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn closest_packet<I: Isa>(
        &self,
        isa: I,
        instances: Option<&Instances>,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        if instances.is_none() {
            let own = each_layout!(self, t => TriangleLayout::own_closest_packet(t, isa, o, prepared, d, d_max, seed));
            if let Some(found) = own {
                return found;
            }
        }
        closest_with(isa, self, instances, o, prepared, d, d_max, seed)
    }

    /// [`TriangleLayout::closest_packet_in`].
    #[inline(always)]
    pub(crate) fn closest_packet_in<V: LaneOps>(
        &self,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
        d_max: f32,
        prim: &mut [u32],
    ) -> u32 {
        each_layout!(self, t => TriangleLayout::closest_packet_in(t, o, prepared, d, d_max, prim))
    }

    /// Which of 8 shadow segments from `o` (0 < t < 1, lanes `valid`, each not blocked by its
    /// `skip` primitive) the triangles and the placed meshes `instances` block, and which
    /// the bounds leave unsure (as [`Triangles::closest_packet`] chooses the walk).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn any_packet<I: Isa>(
        &self,
        isa: I,
        instances: Option<&Instances>,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32,
    ) -> ShadowHits {
        if instances.is_none() {
            let own = each_layout!(self, t => TriangleLayout::own_any_packet(t, isa, o, prepared, d, d_max, skip, valid));
            if let Some(found) = own {
                return found;
            }
        }
        any_with(isa, self, instances, o, prepared, d, d_max, skip, valid)
    }
}

impl Layout for Triangles {
    fn closest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, best: &mut Option<Hit>) {
        each_layout!(self, t => Layout::closest(t, ray, method, tmin, tmax, best))
    }

    fn closest_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &mut Search) {
        each_layout!(self, t => Layout::closest_exact(t, ray, r, search))
    }

    fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        each_layout!(self, t => Layout::any(t, ray, method, tmin, tmax, skip))
    }

    fn any_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &Search, skip: u32) -> bool {
        each_layout!(self, t => Layout::any_exact(t, ray, r, search, skip))
    }

    #[inline(always)]
    fn packet_into<V: LaneOps, S: PacketSink<V>>(
        &self,
        sink: &mut S,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
    ) {
        each_layout!(self, t => Layout::packet_into(t, sink, o, prepared, d))
    }
}

/// Camera rays 8 at a time through the triangles' packet walk and the instances', into one
/// nearest-hit state (see [`Triangles::closest_packet`]), in the build `isa` names.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn closest_with<I: Isa>(
    isa: I,
    tris: &Triangles,
    instances: Option<&Instances>,
    o: [f32; 3],
    prepared: Prepared<'_>,
    d: &[f32x8; 3],
    d_max: f32,
    seed: Option<&PacketSeed>,
) -> PacketHits {
    avx512_avx2_or_baseline!(token isa, isa lanes closest_with_body => (
        tris: &Triangles,
        instances: Option<&Instances>,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>
    ) -> PacketHits)
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn closest_with_body<V: Lanes, I: Isa>(
    isa: I,
    tris: &Triangles,
    instances: Option<&Instances>,
    o: [f32; 3],
    prepared: Prepared<'_>,
    d: &[f32x8; 3],
    d_max: f32,
    seed: Option<&PacketSeed>,
) -> PacketHits {
    let mut nearest = PacketNearest::<V>::seeded(d, d_max, seed);
    tris.packet_into(&mut nearest, o, prepared, each3(|k| V::from_wide(d[k])));
    if let Some(instances) = instances {
        instances.packet(isa, o, d, &mut nearest);
    }
    nearest.finish()
}

/// Shadow segments 8 at a time through the triangles' packet walk and the instances' (see
/// [`Triangles::any_packet`]), in the build `isa` names.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn any_with<I: Isa>(
    isa: I,
    tris: &Triangles,
    instances: Option<&Instances>,
    o: [f32; 3],
    prepared: Prepared<'_>,
    d: &[f32x8; 3],
    d_max: f32,
    skip: &[u32; 8],
    valid: u32,
) -> ShadowHits {
    avx512_avx2_or_baseline!(token isa, isa lanes any_with_body => (
        tris: &Triangles,
        instances: Option<&Instances>,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32
    ) -> ShadowHits)
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn any_with_body<V: Lanes, I: Isa>(
    isa: I,
    tris: &Triangles,
    instances: Option<&Instances>,
    o: [f32; 3],
    prepared: Prepared<'_>,
    d: &[f32x8; 3],
    d_max: f32,
    skip: &[u32; 8],
    valid: u32,
) -> ShadowHits {
    let mut shadow = ShadowPacket::<V>::new(d, d_max, skip, valid);
    tris.packet_into(&mut shadow, o, prepared, each3(|k| V::from_wide(d[k])));
    if let Some(instances) = instances {
        instances.packet(isa, o, d, &mut shadow);
    }
    shadow.finish()
}
