//! The renderer's one face on the accelerator: the queries of one frame.
//!
//! A renderer describes the frame once ([`FrameSetup`]: the eye every camera ray leaves, the
//! light every shadow segment starts at, the screen projection, the method, the number of
//! camera rays) and gets a [`FrameQueries`] from [`Accel::for_frame`]. Per screen tile it asks
//! [`FrameQueries::tile`] for a [`TileQueries`], whose answers are always fully resolved and
//! equal to the per-ray queries [`Accel::closest_hit`] and [`Accel::any_hit_except`] with the
//! frame's method:
//! - [`TileQueries::closest_x8`]: the nearest primitive along 8 camera rays,
//! - [`TileQueries::closest`]: the nearest hit of one camera ray,
//! - [`TileQueries::blocked_x8`]: which shadow segments of the tile are blocked, 8 at a time,
//! - [`TileQueries::blocked`]: whether one shadow segment is blocked.
//!
//! Inside, one plan per frame:
//! - **a small scene** ([`Accel::flat_triangles`]) with tile culling: a tile tests only the
//!   triangles whose screen projection meets it (`cull::ScreenTriangle`; every triangle where
//!   the frame has no projection, as for `raylab trace`'s rays); with the
//!   adaptive method its camera rays go 8 at a time against those triangles prepared for the
//!   eye ([`packet::closest`]), its shadow segments 8 at a time against the triangles prepared
//!   for the light whose box meets the tile's segments ([`packet::shadow_from_origin`]);
//! - **a BVH**, adaptive method: packets through the BVH from the eye and from the light; the
//!   triangles are prepared at most once per frame, as packets first reach them, where there
//!   are at least 8 camera rays per triangle ([`CAMERA_RAYS_PER_TRIANGLE`], up to
//!   [`MAX_PREPARED_ONCE`]), else as each packet meets them. The boxes of
//!   the BVH's top [`SCREEN_DEPTH`] levels are projected on the screen (`cull::ScreenTree`;
//!   with instances, one box around all of them): a tile that none meets has no triangle
//!   hits, and its packets skip the walk (with no other shape there,
//!   [`TileQueries::shows_nothing`]);
//! - otherwise **per ray** through the scene's structure.
//!
//! Shapes other than triangles (spheres) join the packets lane by lane, four lanes at a time
//! through the shape's f64 interval level (`sphere::interval_x4`, the per-ray search's own
//! level for a sphere): in a tile their projected box may show in, a camera packet starts
//! from the nearest shape of each lane ([`packet::PacketSeed`]), and its triangles are then
//! offered against it as against each other (a lane keeps a candidate only while its t
//! interval lies wholly below the others'; overlapping ones, and lanes the interval cannot
//! decide, are ambiguous and traced per ray); shadow segments whose box meets a shape's test
//! it first, and the triangle packets take the lanes it leaves clear.
//!
//! A lane the packet kernels leave ambiguous goes to the exact resolvers
//! ([`packet::nearest_exact_lane`], [`packet::blocked_exact_lane`]) and then to the per-ray
//! adaptive search, so packets and per-ray queries name the same primitives.

use super::cull::{Box3, Occluder, ScreenTree, ScreenTriangle, ShapeCull};
use super::flat::FlatLoop;
use super::packet::{self, OriginTriangles, PacketHits, PacketNearest, PacketSeed};
use super::prepared::{LeafCache, Prepared};
use super::{Accel, AccelKind, IndexedTriangle};
use crate::camera::Projection;
use crate::geometry::adaptive::levels::{self, Event};
use crate::geometry::adaptive::{round_down, round_up, widen, Search};
use crate::geometry::sphere;
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::math::lanes::LaneOps;
use crate::math::simd::{avx2_or_baseline, each3};
use wide::{f32x8, f64x4};

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
    /// Whether shadow segments will be asked.
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
    /// Camera rays and shadow segments 8 at a time through the BVH (adaptive); the triangles
    /// prepared once per frame as first reached, or at every visit (`None`).
    BvhPackets {
        from_eye: Option<LeafCache>,
        from_light: Option<LeafCache>,
        /// Where the triangles can show on screen (the BVH's top [`SCREEN_DEPTH`] levels of
        /// boxes): a tile this does not meet has no triangle hits, and its packets skip the
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
    /// Where the shapes other than triangles (spheres) can show and what they can block,
    /// with each shape seen from the eye and the light: the packets test them lane by lane.
    others: Vec<(ShapeCull, LaneShape)>,
}

/// A shape other than a triangle for the lane-by-lane tests of the packets: seen from the
/// eye and from the light ([`sphere::FromOrigin`]; `None`: a kind of shape the packets do
/// not know, whose lanes go per ray).
#[derive(Clone, Copy, Debug)]
struct LaneShape {
    prim: u32,
    bounds: Box3,
    from_eye: Option<sphere::FromOrigin>,
    from_light: Option<sphere::FromOrigin>,
}

impl LaneShape {
    fn new(shape: &Shape<f32>, prim: u32, bounds: Box3, eye: [f32; 3], light: [f32; 3]) -> Self {
        // (Triangles are prepared in the packets themselves.)
        let from = |o: [f32; 3]| widen(shape).sphere_from_origin(o.map(f64::from));
        Self {
            prim,
            bounds,
            from_eye: from(eye),
            from_light: from(light),
        }
    }
}

/// Buffers a thread reuses from tile to tile.
#[derive(Default)]
pub struct TileScratch {
    /// The tile's triangles, as given and prepared for the eye.
    subset: Vec<IndexedTriangle>,
    prepared: Vec<OriginTriangle>,
    /// The triangles (prepared for the light) that may block the tile's shadow segments.
    near: Vec<OriginTriangle>,
    /// The shapes other than triangles that may show in the tile.
    shapes: Vec<LaneShape>,
    /// Those that may block one of a tile's shadow segments.
    near_shapes: Vec<LaneShape>,
}

/// The answer of a packet started from `seed` where no triangle can show: the seed's.
#[cold]
#[inline(never)]
fn seed_only(d: &[f32x8; 3], d_max: f32, seed: Option<&PacketSeed>) -> PacketHits {
    PacketNearest::<f32x8>::seeded(d, d_max, seed).finish()
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
    /// The shapes other than triangles that may show in the tile.
    shapes: &'a [LaneShape],
    near_shapes: &'a mut Vec<LaneShape>,
    /// The tile's triangles as a flat loop, made when a ray first needs it.
    subset_loop: Option<FlatLoop>,
    /// Whether any triangle may show in the tile (culled plans: the tile has some; a BVH:
    /// its box meets the tile on screen; per ray: true).
    triangles_may_show: bool,
}

impl Accel {
    /// The queries of one frame (see [`FrameQueries`]).
    pub fn for_frame(&self, setup: &FrameSetup) -> FrameQueries<'_> {
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
        let triangles = self.stored_triangle_count();
        let prepare_once = triangles.saturating_mul(CAMERA_RAYS_PER_TRIANGLE) <= setup.camera_rays
            && triangles <= MAX_PREPARED_ONCE;
        let plan = match culling {
            Some(culling) if packets => {
                let tris = culling.tris;
                let (from_light, occluders) = match setup.shadows {
                    true => (
                        OriginTriangles::new(tris, setup.light).tris,
                        tris.iter()
                            .enumerate()
                            .map(|(slot, t)| Occluder::new(slot, t))
                            .collect(),
                    ),
                    false => (Vec::new(), Vec::new()),
                };
                Plan::CulledPackets {
                    from_eye: OriginTriangles::new(tris, setup.eye),
                    culling,
                    from_light,
                    occluders,
                }
            }
            Some(culling) => Plan::Culled(culling),
            None if packets && self.kind() == AccelKind::Bvh => Plan::BvhPackets {
                from_eye: prepare_once.then(|| self.leaf_cache(setup.eye)).flatten(),
                from_light: (prepare_once && setup.shadows)
                    .then(|| self.leaf_cache(setup.light))
                    .flatten(),
                triangles_seen: ScreenTree::new(
                    self.triangle_boxes(SCREEN_DEPTH),
                    setup.projection.as_ref(),
                ),
            },
            None => Plan::PerRay,
        };
        let others = match plan {
            Plan::PerRay => Vec::new(),
            _ => (self.other_shapes().iter())
                .map(|&(shape, prim)| {
                    let cull = ShapeCull::new(shape.bounds(), setup.projection.as_ref());
                    let lane = LaneShape::new(&shape, prim, cull.bounds, setup.eye, setup.light);
                    (cull, lane)
                })
                .collect(),
        };
        FrameQueries {
            accel: self,
            method,
            eye: setup.eye,
            light: setup.light,
            plan,
            others,
        }
    }
}

impl Drop for FrameQueries<'_> {
    /// Hands the frame's caches back to the accelerator for the next frame.
    fn drop(&mut self) {
        if let Plan::BvhPackets {
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
    /// Whether camera rays may go 8 at a time ([`TileQueries::packets`]).
    pub fn packets(&self) -> bool {
        matches!(
            self.plan,
            Plan::CulledPackets { .. } | Plan::BvhPackets { .. }
        )
    }

    /// Whether the frame's BVH packets prepare each triangle at most once for the eye, as they
    /// first reach it ([`CAMERA_RAYS_PER_TRIANGLE`]).
    pub fn prepares_once(&self) -> bool {
        matches!(
            self.plan,
            Plan::BvhPackets {
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
    fn blocked(&self, ray: &Ray, skip: u32) -> bool {
        self.accel.any_hit_except(ray, self.method, 0.0, 1.0, skip)
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
        scratch.shapes.clear();
        scratch.shapes.extend(
            (self.others.iter())
                .filter(|(cull, _)| cull.meets_tile(x0, y0, x1, y1))
                .map(|(_, shape)| *shape),
        );
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
            Plan::BvhPackets { triangles_seen, .. } => triangles_seen.may_show([x0, y0, x1, y1]),
            Plan::Culled(_) | Plan::CulledPackets { .. } => !scratch.subset.is_empty(),
            Plan::PerRay => true,
        };
        TileQueries {
            frame: self,
            triangles_may_show,
            subset: &scratch.subset,
            prepared: &scratch.prepared,
            near: &mut scratch.near,
            shapes: &scratch.shapes,
            near_shapes: &mut scratch.near_shapes,
            subset_loop: None,
        }
    }
}

impl TileQueries<'_> {
    /// Whether no camera ray of the tile can hit anything: every pixel is background.
    pub fn shows_nothing(&self) -> bool {
        !self.triangles_may_show && self.shapes.is_empty()
    }

    /// Whether the tile's camera rays go 8 at a time ([`TileQueries::closest_x8`]); else per
    /// ray ([`TileQueries::closest`]).
    pub fn packets(&self) -> bool {
        self.frame.packets()
    }

    /// The nearest hit of camera ray `ray` (from the eye) with 0 < t < ∞.
    pub fn closest(&mut self, ray: &Ray) -> Option<Hit> {
        let frame = self.frame;
        let method = frame.method;
        match &frame.plan {
            Plan::Culled(_) | Plan::CulledPackets { .. } if self.shapes.is_empty() => {
                let subset = self.subset;
                let tris = self
                    .subset_loop
                    .get_or_insert_with(|| FlatLoop::new(subset));
                WatertightRay::new(ray.o, ray.d).and_then(|r| {
                    if method == Method::Adaptive {
                        let mut search = Search::new(ray, 0.0, f32::INFINITY);
                        tris.closest_hit_adaptive(&r, &mut search);
                        search.hit()
                    } else {
                        tris.closest_hit(&r, 0.0, f32::INFINITY)
                    }
                })
            }
            Plan::BvhPackets {
                from_eye: Some(cache),
                ..
            } => (frame.accel).closest_hit_prepared(ray, Prepared::Once(cache), 0.0, f32::INFINITY),
            _ => frame.accel.closest_hit(ray, method, 0.0, f32::INFINITY),
        }
    }

    /// The nearest primitive along each of 8 camera rays from the eye with directions `d`,
    /// for lanes `live` (bit l for lane l; the others are [`NO_HIT`]).
    #[inline(always)]
    pub fn closest_x8(&mut self, d: &[f32x8; 3], live: u32) -> [u32; 8] {
        let d_max = packet::max_component(d);
        let found = match self.shapes.is_empty() {
            true => self.closest_triangles_x8(d, d_max, None),
            false => self.closest_with_shapes_x8(d, d_max, live),
        };
        // (The lanes are handed on as the kernel stored them: a vector load of its scalar
        // stores would stall store forwarding; measured 5-10% of a Cornell flat frame.)
        let unused = !live & 0xff;
        let mut out = found.prim;
        if (found.ambiguous | unused) != 0 {
            let d = each3(|k| d[k].to_array());
            self.resolve_lanes(&d, found.ambiguous, unused, &mut out);
        }
        out
    }

    /// [`TileQueries::closest_x8`] inside a tile loop already compiled for the CPU, in lanes
    /// `V` of any width, into `out[..V::WIDTH]`: a small scene's culled triangles are tested
    /// inline (no call, no dispatch and no conversion per packet: the Cornell flat frame at
    /// 1280×720 took 1.4× as long in the default build as with AVX2 for the whole program);
    /// other plans go 8 lanes at a time through `closest_x8`.
    /// `d_max` bounds every |dₖ| of the packet (the generator's bound for its directions:
    /// no reduction per packet in the culled lists' kernel, 3-4% of the Cornell flat frame).
    #[inline(always)]
    pub(crate) fn closest_in<V: LaneOps>(
        &mut self,
        d: [V; 3],
        d_max: f32,
        live: u32,
        out: &mut [u32],
    ) {
        let frame = self.frame;
        let ambiguous = match (&frame.plan, self.shapes.is_empty()) {
            (Plan::CulledPackets { .. }, true) => {
                Some(packet::closest_in(self.prepared, d, d_max, out))
            }
            (Plan::BvhPackets { from_eye, .. }, true) if self.triangles_may_show => {
                let prepared = Prepared::of(from_eye.as_ref());
                // (The packet's own max|dₖ|: with the generator's bound passed in, the
                // AVX-512 build's walk took 12% longer on the bunny at 1280×720, the same
                // lanes ambiguous: code generation.)
                let d_max = packet::max_component_in(&d);
                (frame.accel).closest_packet_in(frame.eye, prepared, d, d_max, out)
            }
            _ => None,
        };
        let Some(ambiguous) = ambiguous else {
            let lanes = lanes_of(&d);
            for h in 0..V::WIDTH / 8 {
                let half = each3(|k| f32x8::from(std::array::from_fn(|l| lanes[k][8 * h + l])));
                let prims = self.closest_x8(&half, (live >> (8 * h)) & 0xff);
                out[8 * h..][..8].copy_from_slice(&prims);
            }
            return;
        };
        let unused = !live & V::full();
        if (ambiguous | unused) != 0 {
            self.resolve_lanes(&lanes_of(&d), ambiguous, unused, out);
        }
    }

    /// The packet kernels' answer over the tile's triangles, starting from `seed`.
    #[inline(always)]
    fn closest_triangles_x8(
        &self,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        let frame = self.frame;
        match &frame.plan {
            Plan::CulledPackets { .. } => packet::closest_seeded(self.prepared, d, d_max, seed),
            Plan::BvhPackets { .. } if !self.triangles_may_show => seed_only(d, d_max, seed),
            Plan::BvhPackets { from_eye, .. } => frame
                .accel
                .closest_packet_of_triangles(
                    frame.eye,
                    Prepared::of(from_eye.as_ref()),
                    d,
                    d_max,
                    seed,
                )
                .unwrap_or_else(PacketHits::undecided),
            _ => PacketHits::undecided(),
        }
    }

    /// [`TileQueries::closest_triangles_x8`] where shapes other than triangles may show: they
    /// are tested first, and the triangles offered against them.
    #[inline(never)]
    fn closest_with_shapes_x8(&self, d: &[f32x8; 3], d_max: f32, live: u32) -> PacketHits {
        let shapes = shapes_seed(self.shapes, d, live);
        let mut found = self.closest_triangles_x8(d, d_max, Some(&shapes.seed));
        for (prim, shape) in found.prim.iter_mut().zip(shapes.prims) {
            if *prim == SEEDED {
                *prim = shape;
            }
        }
        found
    }

    /// Lanes `ambiguous` of `out` decided exactly; lanes `unused` set to [`NO_HIT`].
    /// (`d`: the packet's directions by component, lane by lane; as wide as `out`.)
    #[inline(never)]
    fn resolve_lanes<const N: usize>(
        &mut self,
        d: &[[f32; N]; 3],
        ambiguous: u32,
        unused: u32,
        out: &mut [u32],
    ) {
        for (l, out) in out.iter_mut().enumerate().take(N) {
            if unused & (1 << l) != 0 {
                *out = NO_HIT;
            } else if ambiguous & (1 << l) != 0 {
                levels::note(Event::CameraLaneAmbiguous);
                *out = self
                    .resolve_lane([d[0][l], d[1][l], d[2][l]])
                    .unwrap_or(NO_HIT);
            }
        }
    }

    /// An ambiguous camera lane's primitive: exact edge signs over the tile's triangles where
    /// that decides, else the per-ray search.
    fn resolve_lane(&mut self, d: [f32; 3]) -> Option<u32> {
        let frame = self.frame;
        // (The exact resolver knows triangles only.)
        if let (Plan::CulledPackets { culling, .. }, true) = (&frame.plan, self.shapes.is_empty()) {
            let vertices = |p| culling.vertices(p);
            if let Some(prim) = packet::nearest_exact_lane(self.prepared, vertices, frame.eye, d) {
                return prim;
            }
        }
        self.closest(&Ray::new(frame.eye, d)).map(|h| h.prim)
    }

    /// Whether shadow segment `ray` (0 < t < 1) is blocked by anything but primitive `skip`.
    pub fn blocked(&self, ray: &Ray, skip: u32) -> bool {
        self.frame.blocked(ray, skip)
    }

    /// Which live lanes of each of the tile's shadow segments are blocked: `blocked[i]` gets
    /// packet i's mask.
    pub fn blocked_x8<S: AsRef<ShadowSegments>>(&mut self, packets: &[S], blocked: &mut Vec<u32>) {
        blocked.clear();
        blocked.resize(packets.len(), 0);
        let frame = self.frame;
        let light = frame.light;
        let per_ray = |s: &ShadowSegments, mut lanes: u32, out: &mut u32| {
            while lanes != 0 {
                let l = lanes.trailing_zeros() as usize;
                lanes &= lanes - 1;
                let ray = Ray::new(light, s.d.map(|c| c.to_array()[l]));
                if frame.blocked(&ray, s.skip(l)) {
                    *out |= 1 << l;
                }
            }
        };
        // The shapes other than triangles that the segments may meet: tested first, lane by
        // lane; the triangles' packets then take the lanes those leave clear.
        let near_shapes = &mut *self.near_shapes;
        near_shapes.clear();
        if !frame.others.is_empty() {
            let segments = segments_box(packets, light);
            near_shapes.extend(
                (frame.others.iter())
                    .filter(|(cull, _)| cull.bounds.meets(segments.lo, segments.hi))
                    .map(|(_, shape)| *shape),
            );
        }
        let near_shapes = &*near_shapes;
        match &frame.plan {
            Plan::BvhPackets { from_light, .. } => {
                let accel = frame.accel;
                for (s, out) in packets.iter().map(AsRef::as_ref).zip(blocked.iter_mut()) {
                    if s.live == 0 {
                        continue;
                    }
                    let by_shapes = shapes_block(near_shapes, light, s);
                    *out = by_shapes.blocked;
                    let valid = s.live & !(by_shapes.blocked | by_shapes.unsure);
                    if valid != 0 {
                        let d_max = packet::max_component(&s.d);
                        let prepared = Prepared::of(from_light.as_ref());
                        let found = accel
                            .blocked_packet_of_triangles(
                                light, prepared, &s.d, d_max, &s.prim, valid,
                            )
                            .expect("a BVH plan has a BVH");
                        *out |= found.blocked;
                        note_unsure(found.unsure);
                        per_ray(s, found.unsure, out);
                    }
                    per_ray(s, by_shapes.unsure, out);
                }
            }
            Plan::CulledPackets {
                culling,
                from_light,
                occluders,
                ..
            } => {
                let near = &mut *self.near;
                near_occluders(packets, light, occluders, from_light, near);
                let mut near_loop = None;
                for (s, out) in packets.iter().map(AsRef::as_ref).zip(blocked.iter_mut()) {
                    if s.live == 0 {
                        continue;
                    }
                    let by_shapes = shapes_block(near_shapes, light, s);
                    *out = by_shapes.blocked;
                    per_ray(s, by_shapes.unsure, out);
                    let valid = s.live & !(by_shapes.blocked | by_shapes.unsure);
                    if valid == 0 {
                        continue;
                    }
                    let d_max = packet::max_component(&s.d);
                    let found = packet::shadow_from_origin(near, &s.d, d_max, &s.prim, valid);
                    *out |= found.blocked;
                    note_unsure(found.unsure);
                    // Unsure lanes: exact edge signs and sides where that decides.
                    let mut left = 0;
                    for l in (0..8).filter(|l| found.unsure & (1 << l) != 0) {
                        let d = s.d.map(|c| c.to_array()[l]);
                        let vertices = |p| culling.vertices(p);
                        match packet::blocked_exact_lane(near, vertices, light, d, s.prim[l]) {
                            Some(true) => *out |= 1 << l,
                            Some(false) => {}
                            None => left |= 1 << l,
                        }
                    }
                    // Then per ray against the same triangles.
                    for l in (0..8).filter(|l| left & (1 << l) != 0) {
                        let tris = near_loop.get_or_insert_with(|| {
                            let tris: Vec<IndexedTriangle> = near
                                .iter()
                                .map(|t| (culling.vertices(t.prim), t.prim))
                                .collect();
                            FlatLoop::new(&tris)
                        });
                        let ray = Ray::new(light, s.d.map(|c| c.to_array()[l]));
                        let search = Search::new(&ray, 0.0, 1.0);
                        let hit = WatertightRay::new(ray.o, ray.d)
                            .is_some_and(|r| tris.any_hit_adaptive(&r, &search, s.prim[l]));
                        if hit {
                            *out |= 1 << l;
                        }
                    }
                }
            }
            // Per ray: the plan has no shadow packets.
            _ => {
                for (s, out) in packets.iter().map(AsRef::as_ref).zip(blocked.iter_mut()) {
                    per_ray(s, s.live, out);
                }
            }
        }
    }
}

/// The id a packet's lanes give a shape other than a triangle ([`ShapeSeed`]): beyond every
/// primitive and BVH slot, so that no kernel maps it.
const SEEDED: u32 = u32::MAX - 1;

/// The shapes other than triangles along a camera packet, found before its triangles.
struct ShapeSeed {
    /// The packet's starting state: the nearest shape's t interval per lane (id [`SEEDED`]),
    /// and the lanes the shapes leave ambiguous.
    seed: PacketSeed,
    /// The nearest shape's primitive per lane.
    prims: [u32; 8],
}

/// The shapes other than triangles tested on lanes `live` of a camera packet (rays from the
/// eye along `d`), four lanes at a time: see the module doc.
#[inline(never)]
fn shapes_seed(shapes: &[LaneShape], d: &[f32x8; 3], live: u32) -> ShapeSeed {
    avx2_or_baseline!(shapes_seed_body => (
        shapes: &[LaneShape],
        d: &[f32x8; 3],
        live: u32
    ) -> ShapeSeed)
}

#[inline(always)]
fn shapes_seed_body(shapes: &[LaneShape], d: &[f32x8; 3], live: u32) -> ShapeSeed {
    let mut out = ShapeSeed {
        seed: PacketSeed::default(),
        prims: [NO_HIT; 8],
    };
    let used = live & 0xff;
    let d = d.map(|c| c.to_array());
    for half in 0..2 {
        let bits = (used >> (4 * half)) & 0xf;
        if bits == 0 {
            continue;
        }
        let lane = |l: usize| 4 * half + l;
        let d = half_in_f64(&d, half);
        let mut lo = f64x4::splat(f64::INFINITY);
        let mut hi = lo;
        let mut undecided = 0u32;
        for shape in shapes {
            let Some(from_eye) = &shape.from_eye else {
                undecided = 0xf;
                break;
            };
            let r = sphere::interval_x4(from_eye, &d, 0.0, f64::INFINITY);
            let nearer = r.hit & r.hi.simd_lt(lo);
            let farther = r.hit & r.lo.simd_gt(hi);
            // Too close to order, or the interval cannot tell: per ray.
            undecided |= (!(r.miss | nearer | farther)).to_bitmask();
            lo = nearer.bitselect(r.lo, lo);
            hi = nearer.bitselect(r.hi, hi);
            let taken = nearer.to_bitmask();
            for l in (0..4).filter(|l| taken & (1 << l) != 0) {
                out.prims[lane(l)] = shape.prim;
                out.seed.prim[lane(l)] = SEEDED;
            }
        }
        out.seed.ambiguous |= (undecided & bits) << (4 * half);
        // The interval rounded outwards to f32.
        let (lo, hi) = (lo.to_array(), hi.to_array());
        for l in 0..4 {
            out.seed.lo[lane(l)] = round_down(lo[l]);
            out.seed.hi[lane(l)] = round_up(hi[l]);
        }
    }
    out
}

/// Lanes 4·`half` to 4·`half` + 3 of the directions `d` (per axis), in f64.
#[inline(always)]
fn half_in_f64(d: &[[f32; 8]; 3], half: usize) -> [f64x4; 3] {
    each3(|k| f64x4::new(std::array::from_fn(|l| f64::from(d[k][4 * half + l]))))
}

/// Shadow lanes decided by the shapes other than triangles.
struct ShapeLanes {
    /// Certainly blocked by one of them.
    blocked: u32,
    /// Not blocked for certain, and one of them the interval cannot decide: per ray.
    unsure: u32,
}

/// Which live lanes of shadow segments `s` (from the light) the shapes `near` block, each
/// lane skipping its own primitive, four lanes at a time (see the module doc).
#[inline(always)]
fn shapes_block(near: &[LaneShape], light: [f32; 3], s: &ShadowSegments) -> ShapeLanes {
    if near.is_empty() {
        return ShapeLanes {
            blocked: 0,
            unsure: 0,
        };
    }
    avx2_or_baseline!(shapes_block_body => (
        near: &[LaneShape],
        light: [f32; 3],
        s: &ShadowSegments
    ) -> ShapeLanes)
}

#[inline(always)]
fn shapes_block_body(near: &[LaneShape], light: [f32; 3], s: &ShadowSegments) -> ShapeLanes {
    let mut lanes = ShapeLanes {
        blocked: 0,
        unsure: 0,
    };
    let segments = segments_box(std::slice::from_ref(s), light);
    let d = s.d.map(|c| c.to_array());
    for half in 0..2 {
        let live = (s.live >> (4 * half)) & 0xf;
        if live == 0 {
            continue;
        }
        let lane = |l: usize| 4 * half + l;
        let d = half_in_f64(&d, half);
        let (mut blocked, mut unsure) = (0u32, 0u32);
        for shape in near {
            if !shape.bounds.meets(segments.lo, segments.hi) {
                continue;
            }
            let own = (0..4).fold(0, |m, l| m | ((s.skip(lane(l)) == shape.prim) as u32) << l);
            let Some(from_light) = &shape.from_light else {
                unsure |= !own;
                continue;
            };
            let r = sphere::interval_x4(from_light, &d, 0.0, 1.0);
            blocked |= r.hit.to_bitmask() & !own;
            // Another shape may still block such a lane for certain.
            unsure |= (!(r.hit | r.miss)).to_bitmask() & !own;
        }
        lanes.blocked |= (blocked & live) << (4 * half);
        lanes.unsure |= (unsure & live) << (4 * half);
    }
    lanes.unsure &= !lanes.blocked;
    lanes
}

/// Counts the shadow lanes a packet left unsure ([`levels`]).
#[inline]
fn note_unsure(unsure: u32) {
    levels::note_many(Event::ShadowLaneUnsure, unsure.count_ones());
}

/// Fills `near` with the triangles (prepared for the light) that may block one of the shadow
/// segments of `packets`: those whose bounding box meets the box around every segment (light
/// to light + direction, widened for the rounding of that end). A triangle meeting a segment
/// has a point in that box.
fn near_occluders<S: AsRef<ShadowSegments>>(
    packets: &[S],
    light: [f32; 3],
    occluders: &[Occluder],
    from_light: &[OriginTriangle],
    near: &mut Vec<OriginTriangle>,
) {
    let Box3 { lo, hi } = segments_box(packets, light);
    near.clear();
    near.extend(
        occluders
            .iter()
            .filter(|occ| occ.bounds.meets(lo, hi))
            .map(|occ| from_light[occ.slot as usize]),
    );
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

/// Lanes `d` by component as arrays (16 wide, the widest lanes; the first `V::WIDTH` used).
#[inline(always)]
fn lanes_of<V: LaneOps>(d: &[V; 3]) -> [[f32; 16]; 3] {
    let mut lanes = [[0.0f32; 16]; 3];
    for (lane, d) in lanes.iter_mut().zip(d) {
        d.store(lane);
    }
    lanes
}
