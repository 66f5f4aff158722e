//! The renderer's one face on the accelerator: the queries of one frame.
//!
//! A renderer describes the frame once ([`FrameSetup`]: the eye every camera ray leaves, the
//! light every shadow segment starts at, the screen projection, the method, the number of
//! camera rays) and gets a [`FrameQueries`] from [`Accel::for_frame`]. Per screen tile it asks
//! [`FrameQueries::tile`] for a [`TileQueries`], whose answers are always fully resolved and
//! equal to the per-ray queries [`Accel::closest_hit`] and [`Accel::any_hit`] with the
//! frame's method:
//! - [`TileQueries::closest_x8`]: the nearest primitive along 8 camera rays,
//! - [`TileQueries::closest`]: the nearest hit of one camera ray,
//! - [`TileQueries::any_x8`]: which shadow segments of the tile are blocked, 8 at a time,
//! - [`TileQueries::any`]: whether one shadow segment is blocked.
//!
//! Inside, one plan per frame:
//! - **a small scene** ([`Accel::flat_triangles`]) with tile culling: a tile tests only the
//!   triangles whose screen projection meets it (`cull::ScreenTriangle`; every triangle where
//!   the frame has no projection, as for `raylab trace`'s rays); with the
//!   adaptive method its camera rays go 8 at a time against those triangles prepared for the
//!   eye ([`packet::closest`]), its shadow segments 8 at a time against the triangles prepared
//!   for the light whose box meets the tile's segments ([`packet::any`]);
//! - **any other scene**, adaptive method: packets from the eye and from the light through
//!   the triangle layout's packet walk (`Layout::packet_into`: the BVH's down its boxes, the
//!   flat loop's over every block) and the instances'; the
//!   triangles are prepared at most once per frame, as packets first reach them, where there
//!   are at least 8 camera rays per triangle ([`CAMERA_RAYS_PER_TRIANGLE`], up to
//!   [`MAX_PREPARED_ONCE`]), else as each packet meets them. The layout's top boxes (the
//!   BVH's top [`SCREEN_DEPTH`] levels, the flat loop's one box) are projected on the screen
//!   (`cull::ScreenTree`; with instances, one box around all of them): a tile that none
//!   meets has no triangle hits, and its packets skip the walk (with no other shape there,
//!   [`TileQueries::shows_nothing`]); an eye so far from a mesh of small triangles that the
//!   packets' f32 bounds would decide few lanes sends the camera rays one at a time
//!   (`far.rs`) where the frame has no shadows;
//! - otherwise (the inexact methods, the cracks view) **per ray** through the scene's
//!   structure.
//!
//! Shapes other than triangles (spheres) join the packets through their own hierarchy
//! (`accel::spheres`), tested four lanes (or four (sphere, lane) pairs) at a time through the
//! shape's f64 interval level (`sphere::interval_x4_of`, the scalar `sphere::interval`'s
//! steps in lanes), each sphere seen from the eye and the light once per frame: in a tile the
//! hierarchy's top boxes may show in, a camera packet walks it first and starts from the
//! nearest sphere of each lane ([`packet::PacketSeed`]), and its triangles are then offered
//! against that as against each other (a lane keeps a candidate only while its t interval lies
//! wholly below the others'; overlapping ones, and lanes the interval cannot decide, are
//! ambiguous and traced per ray);
//! shadow segments walk it first too, and the triangle packets take the lanes it leaves clear.
//!
//! A lane the packet kernels leave ambiguous goes to the exact resolvers
//! ([`packet::closest_exact_lane`], [`packet::any_exact_lane`]) and then to the per-ray
//! adaptive search, so packets and per-ray queries name the same primitives.
//!
//! The files: `far.rs` says when an eye is too far for camera packets; `tile.rs` answers a
//! tile's queries ([`TileQueries`]: camera rays one at a time
//! and in packets, shadow segments 8 at a time, the exact resolvers of the lanes a packet
//! leaves ambiguous). This file keeps the face: the frame's setup and plan,
//! [`FrameQueries`], the tile's buffers and its shadow segments.
//!
//! [`packet::closest`]: super::packet::closest
//! [`packet::any`]: super::packet::any
//! [`packet::PacketSeed`]: super::packet::PacketSeed
//! [`packet::closest_exact_lane`]: super::packet::closest_exact_lane
//! [`packet::any_exact_lane`]: super::packet::any_exact_lane

pub(crate) mod far;
mod tile;

pub(crate) use far::typical_side;

use super::cull::{Box3, Occluder, ScreenTree, ScreenTriangle};
use super::flat::FlatLoop;
use super::packet::OriginTriangles;
use super::prepared::LeafCache;
use super::spheres::SpheresSeen;
use super::{Accel, IndexedTriangle};
use crate::camera::Projection;
use crate::geometry::{Method, Ray};
use crate::math::simd::Chosen;
use wide::f32x8;

pub use super::packet::OriginTriangle;

/// A lane of [`TileQueries::closest_x8`] whose ray hits nothing.
pub const NO_HIT: u32 = u32::MAX;

/// Camera rays per triangle from which a BVH scene's triangles are prepared for the eye (and
/// the light) at most once per frame, a block of 8 as a packet first reaches it, and kept for
/// the frame's other packets (`prepared::LeafCache`); below, as each packet meets them.
/// Preparing one costs about 65 instructions, eight at a time in f32 (callgrind). At the
/// framing cameras of `raylab bench`, a frame reaches 28k of the bunny's 69k triangles at
/// 640×360 (59k times). Instruction counts (callgrind, AVX2 build) favoured the cache down to
/// 2 rays a triangle; in wall time (1 thread, interleaved) it paid only where the rays far
/// outnumber the triangles: without it the bunny's flat frame at 1280×720 (13
/// rays a triangle) took 2-6% longer, but Igea's took 16% less at 1280×720 (3.4 rays a
/// triangle) and 23% less at 640×360, the bunny's 8-10% less at 640×360 and 320×180, the
/// same in the AVX2 build (11-24% less for Igea) and with shadows (Igea 640×360: 19.1 →
/// 15.5-16.0 ms). The cache's reset, its atomic claims and the lookups cost more than
/// preparing a leaf again for the fewer packets that share it, more so with 16-ray packets.
pub const CAMERA_RAYS_PER_TRIANGLE: usize = 8;

/// The most triangles prepared once per frame ([`CAMERA_RAYS_PER_TRIANGLE`]): the cache holds
/// a full prepared list, about 89 bytes a triangle for the eye and as much for the light, so
/// at most 47 MB each. (The 1M-triangle mesh, at 1.2 triangles a ray at 1280×720, would add
/// 95 MB, as much again as its BVH.)
pub const MAX_PREPARED_ONCE: usize = 1 << 19;

/// Levels of a BVH's 8-wide nodes below its root whose boxes are projected each frame to
/// find the tiles no triangle can show in (585 boxes at most, 8 corners each). Against the
/// root's box alone (depth 0), the bunny's flat frame took 5% fewer instructions at 640×360
/// and 9.6% fewer at 1280×720 (binary nodes, 8 levels; `benches/instructions.sh`).
pub const SCREEN_DEPTH: usize = 3;

/// What the accelerator needs to know of a frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameSetup {
    /// The origin of every camera ray (f32, as the rays carry it).
    pub eye: [f32; 3],
    /// The light, where every shadow segment starts.
    pub light: [f32; 3],
    /// Where world points land on the image, for tile culling; `None`: no culling (every
    /// tile may show every primitive, as for rays that are not on a pixel grid).
    pub projection: Option<Projection>,
    /// The intersection method of every query.
    pub method: Method,
    /// Camera rays in the frame (pixels × samples).
    pub camera_rays: usize,
    /// Whether shadow segments from the light will be asked in packets.
    pub shadows: bool,
    /// Camera rays one at a time only (the cracks view compares methods ray by ray).
    pub per_ray: bool,
}

/// A small scene's triangles in primitive order, and where each can show on screen.
struct Culling<'a> {
    accel: &'a Accel,
    tris: &'a [IndexedTriangle],
    screen: Vec<Option<ScreenTriangle>>,
}

impl Culling<'_> {
    fn vertices(&self, prim: u32) -> [[f32; 3]; 3] {
        self.tris[self.accel.slot(prim)].0
    }
}

/// How a frame's queries run.
enum Plan<'a> {
    /// Per ray through the scene's structure.
    PerRay,
    /// Per ray against the tile's triangles (watertight or adaptive).
    Culled(Culling<'a>),
    /// The tile's triangles prepared for the eye, camera rays 8 at a time; shadow segments 8
    /// at a time against the triangles prepared for the light (adaptive).
    CulledPackets {
        culling: Culling<'a>,
        /// All triangles prepared for the eye, in the order of [`Accel::flat_triangles`].
        from_eye: OriginTriangles,
        /// All triangles prepared for the light, in that order (with shadows).
        from_light: Vec<OriginTriangle>,
        /// All triangles with their boxes (with shadows).
        occluders: Vec<Occluder>,
    },
    /// Camera rays and shadow segments 8 at a time through the triangle layout's packet walk
    /// (`Layout::packet_into`: the BVH's, or the flat loop's over every block; adaptive); the
    /// triangles prepared once per frame as first reached, or at every visit (`None`).
    Packets {
        from_eye: Option<LeafCache>,
        from_light: Option<LeafCache>,
        /// Camera rays one at a time in a frame without shadows: an eye so far from a mesh of
        /// small triangles that the packets' f32 bounds would decide few lanes ([`far`]).
        camera_per_ray: bool,
        /// Where the triangles can show on screen (the layout's top boxes: the BVH's top
        /// [`SCREEN_DEPTH`] levels): a tile this does not meet has no triangle hits, and its packets skip the
        /// walk (most of a frame that frames a mesh).
        triangles_seen: ScreenTree,
    },
}

/// The queries of one frame ([`Accel::for_frame`]).
pub struct FrameQueries<'a> {
    accel: &'a Accel,
    method: Method,
    eye: [f32; 3],
    light: [f32; 3],
    plan: Plan<'a>,
    /// The spheres as the packets test them (packet plans with spheres only).
    spheres: Option<FrameSpheres>,
    /// The kernels' build every tile and query of the frame runs, chosen as it starts.
    build: Chosen,
}

/// A frame's spheres as its packets test them.
struct FrameSpheres {
    /// Each seen from the eye, and from the light (with shadows).
    from_eye: SpheresSeen,
    from_light: Option<SpheresSeen>,
    /// Where they can show on screen (their hierarchy's top [`SCREEN_DEPTH`] levels of
    /// boxes), and whether some are outside it (then they may show anywhere).
    seen: ScreenTree,
    loose: bool,
}

/// Buffers a thread reuses from tile to tile.
#[derive(Default)]
pub struct TileScratch {
    /// The tile's triangles, as given and prepared for the eye.
    subset: Vec<IndexedTriangle>,
    prepared: Vec<OriginTriangle>,
    /// The triangles (prepared for the light) that may block the tile's shadow segments.
    near: Vec<OriginTriangle>,
}

/// Shadow segments from the frame's light L to L + d (t in (0, 1)), 8 lanes, for the lanes in
/// `live`; lane l's segment ends on primitive `prim[l]`, which cannot block it (planar or
/// convex, the light on its lit side) and is skipped, except in the lanes of `own_blocks`
/// (a sphere seen from the other side than the light, which blocks its own shadow segment:
/// [`Lit::skip`](crate::render::shade::Lit::skip)).
#[derive(Clone, Copy, Debug)]
pub struct ShadowSegments {
    pub d: [f32x8; 3],
    pub prim: [u32; 8],
    pub live: u32,
    pub own_blocks: u32,
}

impl ShadowSegments {
    /// The primitive lane l skips (`u32::MAX`: none).
    #[inline]
    pub fn skip(&self, l: usize) -> u32 {
        match self.own_blocks & (1 << l) {
            0 => self.prim[l],
            _ => u32::MAX,
        }
    }
}

impl AsRef<ShadowSegments> for ShadowSegments {
    fn as_ref(&self) -> &ShadowSegments {
        self
    }
}

/// The queries of one tile of a frame ([`FrameQueries::tile`]).
pub struct TileQueries<'a> {
    frame: &'a FrameQueries<'a>,
    /// The tile's triangles (culled plans), as given and prepared for the eye (packets);
    /// held as slices so that a packet's loads come straight from here.
    subset: &'a [IndexedTriangle],
    prepared: &'a [OriginTriangle],
    near: &'a mut Vec<OriginTriangle>,
    /// Whether a sphere may show in the tile (packet plans; per ray: false, the per-ray
    /// queries answer for them).
    spheres_may_show: bool,
    /// The tile's triangles as a flat loop, made when a ray first needs it.
    subset_loop: Option<FlatLoop>,
    /// Whether any triangle may show in the tile (culled plans: the tile has some; packets:
    /// the layout's top boxes meet the tile on screen; per ray: true).
    triangles_may_show: bool,
}

impl Accel {
    /// The queries of one frame (see [`FrameQueries`]).
    pub fn for_frame(&self, setup: &FrameSetup) -> FrameQueries<'_> {
        let build = Chosen::now();
        let method = setup.method;
        let culling = match self.flat_triangles() {
            Some(tris) if matches!(method, Method::Watertight | Method::Adaptive) => {
                let screen = match &setup.projection {
                    Some(projection) => tris
                        .iter()
                        .map(|(v, _)| ScreenTriangle::new(v, projection))
                        .collect(),
                    None => vec![None; tris.len()],
                };
                Some(Culling {
                    accel: self,
                    tris,
                    screen,
                })
            }
            _ => None,
        };
        let packets = method == Method::Adaptive && !setup.per_ray;
        // (Not with shadows: their segments would go per ray too, and from 2,000 units the
        // bunny's shadow frames took 20% longer so; from 10⁴, 10% less.)
        let eye_far = !setup.shadows
            && self.instances.is_none()
            && self.triangles.kind() == super::AccelChoice::Bvh
            && (self.triangles.bounding_box())
                .is_some_and(|b| far::too_far_for_packets(setup.eye, &b, self.typical_side));
        let triangles = self.stored_triangle_count();
        let prepare_once = triangles.saturating_mul(CAMERA_RAYS_PER_TRIANGLE) <= setup.camera_rays
            && triangles <= MAX_PREPARED_ONCE;
        let plan = match culling {
            Some(culling) if packets => {
                let tris = culling.tris;
                let (from_light, occluders) = match setup.shadows {
                    true => (
                        OriginTriangles::new_in(build, tris, setup.light).tris,
                        tris.iter()
                            .enumerate()
                            .map(|(slot, t)| Occluder::new(slot, t))
                            .collect(),
                    ),
                    false => (Vec::new(), Vec::new()),
                };
                Plan::CulledPackets {
                    from_eye: OriginTriangles::new_in(build, tris, setup.eye),
                    culling,
                    from_light,
                    occluders,
                }
            }
            Some(culling) => Plan::Culled(culling),
            None if packets => Plan::Packets {
                camera_per_ray: eye_far,
                from_eye: (prepare_once && !eye_far).then(|| self.leaf_cache(setup.eye)),
                from_light: (prepare_once && setup.shadows).then(|| self.leaf_cache(setup.light)),
                triangles_seen: ScreenTree::new(
                    self.triangle_boxes(SCREEN_DEPTH),
                    setup.projection.as_ref(),
                ),
            },
            None => Plan::PerRay,
        };
        let spheres = self.spheres();
        let spheres = match plan {
            Plan::PerRay => None,
            _ if spheres.is_empty() => None,
            _ => Some(FrameSpheres {
                from_eye: spheres.seen_from(setup.eye),
                from_light: setup.shadows.then(|| spheres.seen_from(setup.light)),
                seen: ScreenTree::new(spheres.top_boxes(SCREEN_DEPTH), setup.projection.as_ref()),
                loose: !spheres.loose().is_empty(),
            }),
        };
        FrameQueries {
            accel: self,
            method,
            eye: setup.eye,
            light: setup.light,
            plan,
            spheres,
            build,
        }
    }
}

impl Drop for FrameQueries<'_> {
    /// Hands the frame's caches back to the accelerator for the next frame.
    fn drop(&mut self) {
        if let Plan::Packets {
            from_eye,
            from_light,
            ..
        } = &mut self.plan
        {
            for cache in [from_eye.take(), from_light.take()].into_iter().flatten() {
                self.accel.keep_leaf_cache(cache);
            }
        }
    }
}

impl<'a> FrameQueries<'a> {
    /// The kernels' build the frame runs, chosen once as it started: each tile loop enters
    /// its copy of that build by it.
    pub fn build(&self) -> Chosen {
        self.build
    }

    /// Whether camera rays may go 8 at a time ([`TileQueries::packets`]): not with an eye too
    /// far for them (`far.rs`).
    pub fn packets(&self) -> bool {
        matches!(
            self.plan,
            Plan::CulledPackets { .. }
                | Plan::Packets {
                    camera_per_ray: false,
                    ..
                }
        )
    }

    /// Whether the frame's packets prepare each triangle at most once for the eye, as they
    /// first reach it (`CAMERA_RAYS_PER_TRIANGLE`).
    pub fn prepares_once(&self) -> bool {
        matches!(
            self.plan,
            Plan::Packets {
                from_eye: Some(_),
                ..
            }
        )
    }

    /// The scene's triangles prepared for the eye, in primitive order, where this frame made
    /// them for all of them (a small scene in packets); else empty. Shading reuses them. (With
    /// shapes other than triangles in the scene, position is not the primitive index.)
    pub fn prepared_for_eye(&self) -> &[OriginTriangle] {
        match &self.plan {
            Plan::CulledPackets { from_eye, .. } => &from_eye.tris,
            _ => &[],
        }
    }

    /// Whether shadow segment `ray` (0 < t < 1) is blocked by anything but primitive `skip`.
    fn any(&self, ray: &Ray, skip: u32) -> bool {
        self.accel.any_hit(ray, self.method, 0.0, 1.0, skip)
    }

    /// The queries for the tile of pixels [x0, x1) × [y0, y1).
    pub fn tile<'t>(
        &'t self,
        [x0, y0, x1, y1]: [u32; 4],
        scratch: &'t mut TileScratch,
    ) -> TileQueries<'t>
    where
        'a: 't,
    {
        let (x0, y0, x1, y1) = (x0 as f32, y0 as f32, x1 as f32, y1 as f32);
        let spheres_may_show =
            (self.spheres.as_ref()).is_some_and(|s| s.loose || s.seen.may_show([x0, y0, x1, y1]));
        if let Plan::Culled(culling) | Plan::CulledPackets { culling, .. } = &self.plan {
            let meets = |s: &Option<ScreenTriangle>| match s {
                Some(s) => s.meets(x0, y0, x1, y1),
                None => true,
            };
            scratch.subset.clear();
            scratch.prepared.clear();
            match &self.plan {
                // One test per triangle for both lists.
                Plan::CulledPackets { from_eye, .. } => {
                    for ((t, p), s) in culling.tris.iter().zip(&from_eye.tris).zip(&culling.screen)
                    {
                        if meets(s) {
                            scratch.subset.push(*t);
                            scratch.prepared.push(*p);
                        }
                    }
                }
                _ => scratch.subset.extend(
                    (culling.tris.iter().zip(&culling.screen))
                        .filter(|(_, s)| meets(s))
                        .map(|(t, _)| *t),
                ),
            }
        }
        let triangles_may_show = match &self.plan {
            Plan::Packets { triangles_seen, .. } => triangles_seen.may_show([x0, y0, x1, y1]),
            Plan::Culled(_) | Plan::CulledPackets { .. } => !scratch.subset.is_empty(),
            Plan::PerRay => true,
        };
        TileQueries {
            frame: self,
            triangles_may_show,
            subset: &scratch.subset,
            prepared: &scratch.prepared,
            near: &mut scratch.near,
            spheres_may_show,
            subset_loop: None,
        }
    }
}

/// The box around the shadow segments of `packets` (light to light + direction, the ends as
/// computed in f32: [`Box3::meets`] widens it for their rounding).
fn segments_box<S: AsRef<ShadowSegments>>(packets: &[S], light: [f32; 3]) -> Box3 {
    // Each segment's end L + d rounded as `Box3::meets` allows for; the other lanes' d
    // are zero, so their ends are L, the segments' start. No end is NaN (a lane is live only
    // where its point, normal and light are finite, and d is finite or ±∞), so the NaN-blind
    // `fast_min`/`fast_max` serve (2% of a shadows frame's instructions less than
    // `min`/`max`).
    let light = light.map(f32x8::splat);
    let (mut lo, mut hi) = (light, light);
    for s in packets.iter().map(AsRef::as_ref) {
        for k in 0..3 {
            let end = light[k] + s.d[k];
            lo[k] = lo[k].fast_min(end);
            hi[k] = hi[k].fast_max(end);
        }
    }
    let reduce = |x: [f32x8; 3], pick: fn(f32, f32) -> f32| {
        x.map(|c| c.to_array().into_iter().reduce(pick).expect("8 lanes"))
    };
    Box3 {
        lo: reduce(lo, f32::min),
        hi: reduce(hi, f32::max),
    }
}
