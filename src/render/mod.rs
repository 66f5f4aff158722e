//! The parallel render driver: rows of the image in parallel (rayon), n×n stratified samples
//! per pixel, linear colour averaged and sRGB-encoded once into RGBA8.

pub mod settings;
pub mod shade;

use crate::accel::packet::{self, Occluder, OriginTriangle, OriginTriangles};
use crate::accel::soa::TriangleBlocks;
use crate::accel::IndexedTriangle;
use crate::camera::{Camera, RayGenerator};
use crate::geometry::adaptive::Search;
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::scene::Scene;
use glam::DVec3;
use rayon::prelude::*;
use std::path::Path;
use std::time::{Duration, Instant};
use wide::f32x8;

pub use settings::{LabStep, RenderSettings, SettingsError, MAX_PIXELS, MAX_SIDE, MAX_SPP};
pub use shade::Rgb;
use shade::{Occluders, ShadePacket, ShadeTri};

/// The CPU's model name, for benchmark reports (the architecture where it is not known).
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// What a render did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Camera rays traced.
    pub primary_rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
    /// Camera rays that hit something.
    pub hits: u64,
    /// Wall time of the render.
    pub elapsed: Duration,
}

impl RenderStats {
    /// All rays traced.
    pub fn rays(&self) -> u64 {
        self.primary_rays + self.shadow_rays
    }

    /// Millions of rays (primary plus shadow) per second of wall time.
    pub fn mrays_per_s(&self) -> f64 {
        self.rays() as f64 / self.elapsed.as_secs_f64().max(1e-9) / 1e6
    }
}

/// The colour seen along one camera ray (black where it escapes). Counts shadow rays.
pub fn trace_pixel_ray(
    scene: &Scene,
    ray: &Ray,
    settings: &RenderSettings,
    shadow_rays: &mut u64,
) -> Option<Rgb> {
    let hit = scene
        .accel()
        .closest_hit(ray, settings.method, 0.0, f32::INFINITY)?;
    Some(shade_hit(scene, ray, &hit, settings, shadow_rays))
}

/// The lab step's colour at a camera ray's nearest hit.
fn shade_hit(
    scene: &Scene,
    ray: &Ray,
    hit: &Hit,
    settings: &RenderSettings,
    shadow_rays: &mut u64,
) -> Rgb {
    shade::shade(scene, ray, hit, settings.step, settings.method, shadow_rays)
}

/// The colour of a crack in the cracks view (linear magenta).
pub const CRACK: Rgb = [1.0, 0.0, 1.0];

/// Whether the ray slips through with `method` where the (exact) adaptive method hits, or
/// hits where it misses: a crack. (Picking the other of two triangles that meet at the hit
/// point is not one; it is the same surface.)
pub fn is_crack(scene: &Scene, ray: &Ray, method: Method) -> bool {
    let accel = scene.accel();
    let hits = |m| accel.closest_hit(ray, m, 0.0, f32::INFINITY).is_some();
    method != Method::Adaptive && hits(method) != hits(Method::Adaptive)
}

/// Camera rays per triangle from which a BVH scene's triangles are prepared for the camera
/// origin once per frame rather than per packet (see `render_into_cancellable`).
pub const PREPARE_RAYS_PER_TRIANGLE: usize = 1;

/// Width of the tiles camera rays are traced in (a packet's 8 lanes).
pub const TILE: u32 = 8;

/// Height of the tiles, the rows a parallel band holds.
pub const BAND: u32 = 16;

/// Where a triangle of a flat (small) scene can appear on screen, for tile culling: its
/// projection's bounding rectangle and edge lines, widened by a pixel for rounding. A camera
/// ray through image position (x, y) can only hit a triangle in front of the pinhole whose
/// projection (a triangle) holds (x, y).
#[derive(Clone, Copy, Debug)]
struct ScreenTriangle {
    /// x0, y0, x1, y1.
    bounds: [f32; 4],
    /// a·x + b·y + c ≥ −1 (a, b unit) on the triangle's side of each edge, for each edge.
    edges: [[f64; 3]; 3],
}

impl ScreenTriangle {
    /// `None` where a vertex is not in front of the camera (such a triangle is kept for
    /// every tile).
    fn new(
        v: &[[f32; 3]; 3],
        from_world: &glam::DMat4,
        (cx, cy, f): (f64, f64, f64),
    ) -> Option<Self> {
        let mut q = [[0.0f64; 2]; 3];
        for (p, s) in v.iter().zip(&mut q) {
            let c = from_world.transform_point3(DVec3::from_array(p.map(f64::from)));
            if c.z <= 1e-9 * c.length() {
                return None;
            }
            *s = [f * c.x / c.z + cx, f * c.y / c.z + cy];
        }
        let lo = [0, 1].map(|k| q[0][k].min(q[1][k]).min(q[2][k]) as f32 - 1.0);
        let hi = [0, 1].map(|k| q[0][k].max(q[1][k]).max(q[2][k]) as f32 + 1.0);
        let area =
            (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
        let side = if area < 0.0 { -1.0 } else { 1.0 };
        let edges = [0, 1, 2].map(|i| {
            let (p, r) = (q[i], q[(i + 1) % 3]);
            let (a, b) = (-(r[1] - p[1]) * side, (r[0] - p[0]) * side);
            let len = a.hypot(b);
            if len.is_nan() || len <= 1e-9 || !area.is_finite() || area == 0.0 {
                // Seen edge-on or degenerate on screen: the rectangle alone decides.
                return [0.0, 0.0, 1.0];
            }
            let (a, b) = (a / len, b / len);
            [a, b, -(a * p[0] + b * p[1])]
        });
        Some(Self {
            bounds: [lo[0], lo[1], hi[0], hi[1]],
            edges,
        })
    }

    /// Whether the triangle may show in the rectangle [x0, x1] × [y0, y1].
    #[inline]
    fn meets(&self, x0: f32, y0: f32, x1: f32, y1: f32) -> bool {
        let b = &self.bounds;
        if b[2] < x0 || b[0] > x1 || b[3] < y0 || b[1] > y1 {
            return false;
        }
        self.edges.iter().all(|[a, bb, c]| {
            // The rectangle's corner farthest along the edge's inward normal.
            let x = if *a > 0.0 { x1 } else { x0 } as f64;
            let y = if *bb > 0.0 { y1 } else { y0 } as f64;
            a * x + bb * y + c >= -1.0
        })
    }
}

/// [`ScreenTriangle`]s of a flat scene's triangles.
fn screen_triangles(
    tris: &[IndexedTriangle],
    camera: &Camera,
    w: u32,
    h: u32,
) -> Vec<Option<ScreenTriangle>> {
    let from_world = camera.camera_from_world();
    let frame = (w as f64 / 2.0, h as f64 / 2.0, camera.focal);
    tris.iter()
        .map(|(v, _)| ScreenTriangle::new(v, &from_world, frame))
        .collect()
}

/// Renders `scene` through `camera` into `rgba` (RGBA8, rows top to bottom, alpha 255).
///
/// Camera rays run in bands of [`BAND`] rows in parallel, tile by tile. For a small scene
/// traced with the watertight method, each tile tests only the triangles whose screen bounds
/// meet it (tile culling), which gives exactly the same nearest hits as testing them all.
pub fn render_into(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    rgba: &mut [u8],
) -> Result<RenderStats, SettingsError> {
    render_into_cancellable(scene, camera, settings, rgba, &|| false)
        .map(|stats| stats.expect("never cancelled"))
}

/// [`render_into`] that gives up when `cancelled()` turns true (checked before each band of
/// rows), returning `Ok(None)` and leaving the buffer partly drawn: an interactive viewer
/// drops a frame that a camera move has made stale instead of waiting for it.
pub fn render_into_cancellable(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    rgba: &mut [u8],
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<Option<RenderStats>, SettingsError> {
    settings.validate()?;
    let (w, h) = (settings.width, settings.height);
    if rgba.len() != settings.buffer_len() {
        return Err(SettingsError::Buffer(
            rgba.len(),
            w,
            h,
            settings.buffer_len(),
        ));
    }
    // Build the acceleration structure before the clock starts (once per scene).
    let accel = scene.accel();
    let start = Instant::now();
    let culled = match accel.flat_triangles() {
        Some(tris)
            if settings.tile_culling
                && matches!(settings.method, Method::Watertight | Method::Adaptive) =>
        {
            Some((tris, screen_triangles(tris, camera, w, h)))
        }
        _ => None,
    };
    let gen = camera.ray_generator(w, h);
    // Camera rays in packets where the adaptive method runs over a culled small scene.
    let packets = match &culled {
        Some((tris, _)) if settings.method == Method::Adaptive && !settings.cracks => {
            Some(OriginTriangles::new(tris, gen.origin()))
        }
        _ => None,
    };
    // A BVH scene's camera rays go 8 at a time through the BVH (adaptive method, triangles
    // only: spheres go per ray). Its triangles are prepared for the camera position once per
    // frame when there are at least as many camera rays as triangles; below that, each
    // packet prepares the triangles it meets (about 400 instructions each, callgrind; 1280x720,
    // 2 threads: the bunny's 69k triangles met about 5 times each per frame, the 1M-triangle
    // mesh's fewer than once).
    let bvh_packets = culled.is_none()
        && settings.method == Method::Adaptive
        && !settings.cracks
        && accel.kind() == "bvh"
        && !accel.has_spheres();
    let camera_rays = w as usize * h as usize * (settings.spp * settings.spp) as usize;
    let from_camera = match bvh_packets {
        true if scene.len().saturating_mul(PREPARE_RAYS_PER_TRIANGLE) <= camera_rays => {
            accel.prepare_origin(gen.origin())
        }
        _ => None,
    };
    let casts_shadows = matches!(settings.step, LabStep::Shadows | LabStep::Indirect);
    let occluders = match &packets {
        Some(_) if casts_shadows => accel
            .flat_triangles()
            .unwrap_or(&[])
            .iter()
            .map(Occluder::new)
            .collect(),
        _ => Vec::new(),
    };
    let camera_tris = match &packets {
        Some(p) if settings.step != LabStep::Flat => {
            let flat = accel.flat_triangles().unwrap_or(&[]);
            debug_assert!(flat.iter().enumerate().all(|(i, t)| t.1 == i as u32));
            (p.tris.iter().zip(flat))
                .map(|(tri, (v, _))| ShadeTri {
                    tri: *tri,
                    normal: shade::unit_normal(v),
                })
                .collect()
        }
        _ => Vec::new(),
    };
    let light_tris = match (&packets, accel.flat_triangles()) {
        (Some(_), Some(tris)) if casts_shadows => {
            OriginTriangles::new(tris, scene.light.position).tris
        }
        _ => Vec::new(),
    };
    let light_bvh = match bvh_packets && casts_shadows {
        true if scene.len().saturating_mul(PREPARE_RAYS_PER_TRIANGLE) <= camera_rays => {
            accel.prepare_origin(scene.light.position)
        }
        _ => None,
    };
    let uses_packets = packets.is_some() || bvh_packets;
    let flat_rgba =
        (uses_packets && settings.step == LabStep::Flat && settings.spp == 1 && !settings.cracks)
            .then(|| FlatPixels::new(scene, camera_rays));
    let frame = Frame {
        scene,
        settings,
        flat_rgba,
        from_camera,
        camera_tris,
        light_tris,
        light_bvh,
        occluders,
        gen,
        inv_n: 1.0 / settings.spp as f32,
        weight: 1.0 / (settings.spp * settings.spp) as f32,
        srgb: SrgbTables::get(),
        row_bytes: w as usize * 4,
    };
    let (hits, shadow_rays) = rgba
        .par_chunks_mut(frame.row_bytes * BAND as usize)
        .enumerate()
        .map(|(band, rows)| {
            let mut counts = (0u64, 0u64);
            if cancelled() {
                return counts;
            }
            let y0 = band as u32 * BAND;
            let band_h = (rows.len() / frame.row_bytes) as u32;
            let mut scratch = TileScratch::default();
            for x0 in (0..w).step_by(TILE as usize) {
                let tile = Tile {
                    x0,
                    y0,
                    w: TILE.min(w - x0),
                    h: band_h,
                };
                let Some((tris, bounds)) = &culled else {
                    if bvh_packets {
                        frame.trace_tile_packets(&tile, &mut scratch, rows, &mut counts, true);
                    } else {
                        frame.trace_tile(&tile, None, rows, &mut counts);
                    }
                    continue;
                };
                let (tx0, ty0) = (tile.x0 as f32, tile.y0 as f32);
                let (tx1, ty1) = ((tile.x0 + tile.w) as f32, (tile.y0 + tile.h) as f32);
                let meets = |b: &Option<ScreenTriangle>| match b {
                    Some(b) => b.meets(tx0, ty0, tx1, ty1),
                    None => true,
                };
                let subset = &mut scratch.subset;
                subset.clear();
                subset.extend(
                    tris.iter()
                        .zip(bounds)
                        .filter(|(_, b)| meets(b))
                        .map(|(t, _)| *t),
                );
                match &packets {
                    Some(p) => {
                        scratch.tris.clear();
                        scratch.tris.extend(
                            p.tris
                                .iter()
                                .zip(bounds)
                                .filter(|(_, b)| meets(b))
                                .map(|(t, _)| *t),
                        );
                        frame.trace_tile_packets(&tile, &mut scratch, rows, &mut counts, false);
                    }
                    None => {
                        let blocks = TriangleBlocks::new(subset);
                        frame.trace_tile(&tile, Some(&blocks), rows, &mut counts);
                    }
                }
            }
            counts
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    let n = settings.spp;
    if cancelled() {
        return Ok(None);
    }
    Ok(Some(RenderStats {
        primary_rays: w as u64 * h as u64 * (n * n) as u64,
        shadow_rays,
        hits,
        elapsed: start.elapsed(),
    }))
}

/// What a packet found for one of its rays.
#[derive(Clone, Copy)]
enum Lane {
    Miss,
    /// The nearest primitive (its t is computed only when shading needs it).
    Prim(u32),
    /// Undecided: traced per ray.
    PerRay,
}

/// One tile of the image: pixels x0..x0 + w, y0..y0 + h.
struct Tile {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
}

/// Buffers a band of tiles reuses: the tile's triangles (prepared for the camera origin, and
/// as given), and its camera-ray hits readied for shading.
#[derive(Default)]
struct TileScratch {
    tris: Vec<OriginTriangle>,
    subset: Vec<IndexedTriangle>,
    /// Per packet (rows, then samples), its hits readied for shading and its blocked lanes.
    shaded: Vec<ShadePacket>,
    blocked: Vec<u32>,
    /// The triangles (prepared for the light) that may block the tile's shadow rays.
    near: Vec<OriginTriangle>,
}

/// What every tile of one frame shares.
struct Frame<'a> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    /// The scene's BVH triangles prepared for the camera position (adaptive method).
    from_camera: Option<OriginTriangles>,
    /// A flat scene's triangles prepared for the camera position, indexed by primitive, for
    /// shading (steps past the flat one; empty otherwise: shading prepares its own).
    camera_tris: Vec<ShadeTri>,
    /// A flat scene's triangles prepared for the light's position, indexed by primitive
    /// (steps with shadows; shadow rays start at the light).
    light_tris: Vec<OriginTriangle>,
    /// A BVH scene's triangles prepared for the light's position, in the BVH's order, where
    /// they are prepared once per frame (as for the camera).
    light_bvh: Option<OriginTriangles>,
    /// A flat scene's triangles with their boxes, for culling shadow rays per tile (only
    /// for the steps with shadows).
    occluders: Vec<Occluder>,
    gen: RayGenerator,
    /// The flat step's pixels per primitive, for one sample per pixel (written as found).
    flat_rgba: Option<FlatPixels<'a>>,
    inv_n: f32,
    /// 1/n² for n×n samples.
    weight: f32,
    srgb: &'static SrgbTables,
    row_bytes: usize,
}

impl Frame<'_> {
    /// Image position of sample (sx, sy) of pixel (i, j).
    #[inline]
    fn sample(&self, i: u32, j: u32, sx: u32, sy: u32) -> (f32, f32) {
        let x = i as f32 + (sx as f32 + 0.5) * self.inv_n;
        let y = j as f32 + (sy as f32 + 0.5) * self.inv_n;
        (x, y)
    }

    /// The colour along one camera ray, per ray: tile-culled `blocks` (watertight or
    /// adaptive), or the whole scene's structure.
    fn trace_ray(
        &self,
        ray: &Ray,
        blocks: Option<&TriangleBlocks>,
        shadow_rays: &mut u64,
    ) -> Option<Rgb> {
        let (scene, settings) = (self.scene, self.settings);
        if settings.cracks && is_crack(scene, ray, settings.method) {
            return Some(CRACK);
        }
        let hit = self.find_hit(ray, blocks)?;
        Some(shade_hit(scene, ray, &hit, settings, shadow_rays))
    }

    /// The nearest hit of a camera ray, per ray (see [`Frame::trace_ray`]).
    fn find_hit(&self, ray: &Ray, blocks: Option<&TriangleBlocks>) -> Option<Hit> {
        let accel = self.scene.accel();
        let method = self.settings.method;
        let Some(b) = blocks else {
            return match &self.from_camera {
                Some(prepared) => accel.closest_hit_from_origin(ray, prepared, 0.0, f32::INFINITY),
                None => accel.closest_hit(ray, method, 0.0, f32::INFINITY),
            };
        };
        WatertightRay::new(ray.o, ray.d).and_then(|r| {
            if method == Method::Adaptive {
                let mut s = Search::new(ray, 0.0, f32::INFINITY);
                b.closest_hit_adaptive(&r, &mut s);
                s.hit()
            } else {
                b.closest_hit(&r, 0.0, f32::INFINITY)
            }
        })
    }

    /// Writes pixel (i, row) from its samples' summed linear colour.
    #[inline]
    fn put(&self, row: &mut [u8], i: u32, sum: Rgb) {
        let (weight, srgb) = (self.weight, self.srgb);
        let px = &mut row[i as usize * 4..][..4];
        px[0] = srgb.encode(sum[0] * weight);
        px[1] = srgb.encode(sum[1] * weight);
        px[2] = srgb.encode(sum[2] * weight);
        px[3] = 255;
    }

    /// Traces a tile ray by ray into `rows` (the band of rows the tile lies in). Adds
    /// (hits, shadow rays) to `counts`.
    fn trace_tile(
        &self,
        tile: &Tile,
        blocks: Option<&TriangleBlocks>,
        rows: &mut [u8],
        counts: &mut (u64, u64),
    ) {
        let n = self.settings.spp;
        for j in tile.y0..tile.y0 + tile.h {
            let row = &mut rows[(j - tile.y0) as usize * self.row_bytes..][..self.row_bytes];
            for i in tile.x0..tile.x0 + tile.w {
                let mut sum = [0.0f32; 3];
                for sy in 0..n {
                    for sx in 0..n {
                        let (x, y) = self.sample(i, j, sx, sy);
                        let ray = self.gen.ray_through(x, y);
                        if let Some(c) = self.trace_ray(&ray, blocks, &mut counts.1) {
                            counts.0 += 1;
                            add(&mut sum, c);
                        }
                    }
                }
                self.put(row, i, sum);
            }
        }
    }

    /// Traces a tile's camera rays 8 at a time against `tris` (the tile's triangles prepared
    /// for the camera position, see [`crate::accel::packet`]) or through the BVH; a rare
    /// ambiguous ray goes to the exact-edge resolver, then the per-ray adaptive search over
    /// `subset` (the same triangles). The nearest primitive is the same either way, and
    /// shading depends on the primitive only ([`shade::Lit`]). Shadow rays, from the light,
    /// are tested 8 at a time against the triangles that can meet one of the tile's (the
    /// others cannot answer "blocked").
    fn trace_tile_packets(
        &self,
        tile: &Tile,
        scratch: &mut TileScratch,
        rows: &mut [u8],
        counts: &mut (u64, u64),
        bvh: bool,
    ) {
        let (scene, settings) = (self.scene, self.settings);
        let accel = scene.accel();
        let TileScratch {
            tris,
            subset,
            shaded,
            blocked,
            near,
        } = scratch;
        let vertices = |p: u32| match &scene.shapes[p as usize] {
            Shape::Triangle(v) => *v,
            Shape::Sphere { .. } => unreachable!("packets run over triangles only"),
        };
        let n = settings.spp;
        let o = self.gen.origin();
        let mut blocks: Option<TriangleBlocks> = None;
        let flat = settings.step == LabStep::Flat;
        let mut sums = [[0.0f32; 3]; TILE as usize];
        shaded.clear();
        for j in tile.y0..tile.y0 + tile.h {
            let row_off = (j - tile.y0) as usize * self.row_bytes;
            sums.fill([0.0; 3]);
            for sy in 0..n {
                for sx in 0..n {
                    // The image positions of `sample`, with the same operations.
                    let off_x = (sx as f32 + 0.5) * self.inv_n;
                    let y = j as f32 + (sy as f32 + 0.5) * self.inv_n;
                    // Lanes past the tile's right edge repeat its last pixel.
                    let xs = std::array::from_fn(|l| {
                        (tile.x0 + (l as u32).min(tile.w - 1)) as f32 + off_x
                    });
                    let dirs = self.gen.directions_x8(f32x8::from(xs), y);
                    let d_max = packet::max_component(&dirs);
                    let found = match bvh {
                        true => accel
                            .closest_packet(o, self.from_camera.as_ref(), &dirs, d_max)
                            .unwrap_or(packet::PacketHits {
                                prim: [u32::MAX; 8],
                                ambiguous: 0xff,
                            }),
                        false => packet::closest(tris, &dirs, d_max),
                    };
                    let lanes: [Lane; 8] = std::array::from_fn(|l| match found.prim[l] {
                        _ if found.ambiguous & (1 << l) != 0 => Lane::PerRay,
                        u32::MAX => Lane::Miss,
                        prim => Lane::Prim(prim),
                    });
                    let [dx, dy, dz] = dirs.map(|d| d.to_array());
                    let ray_of = |l: usize| Ray::new(o, [dx[l], dy[l], dz[l]]);
                    // An ambiguous lane's primitive: exact edge signs over the tile's
                    // triangles where that decides, else the per-ray search.
                    let mut per_ray = |l: usize| {
                        let ray = ray_of(l);
                        if bvh {
                            return self.find_hit(&ray, None).map(|h| h.prim);
                        }
                        if let Some(prim) = packet::nearest_exact_lane(tris, vertices, o, ray.d) {
                            return prim;
                        }
                        let b = blocks.get_or_insert_with(|| TriangleBlocks::new(subset));
                        self.find_hit(&ray, Some(b)).map(|h| h.prim)
                    };
                    let w = tile.w as usize;
                    if !flat {
                        // Each lane's primitive, then the lanes readied for shading at once.
                        let mut own = [None; 8];
                        let mut prepared: [Option<&ShadeTri>; 8] = [None; 8];
                        for l in 0..w {
                            let prim = match lanes[l] {
                                Lane::Miss => None,
                                Lane::Prim(prim) => Some(prim),
                                Lane::PerRay => per_ray(l),
                            };
                            let Some(prim) = prim else { continue };
                            match self.camera_tris.get(prim as usize) {
                                Some(tri) => prepared[l] = Some(tri),
                                None => {
                                    let Shape::Triangle(v) = &scene.shapes[prim as usize] else {
                                        unreachable!("packets run over triangles only")
                                    };
                                    own[l] = Some(ShadeTri::new(v, o, prim));
                                }
                            }
                        }
                        for (l, tri) in own.iter().enumerate() {
                            if let Some(tri) = tri {
                                prepared[l] = Some(tri);
                            }
                        }
                        shaded.push(shade::shade_packet(scene, &dirs, &prepared));
                        continue;
                    }
                    for (l, sum) in sums.iter_mut().take(w).enumerate() {
                        let i = tile.x0 + l as u32;
                        let prim = match lanes[l] {
                            Lane::Miss => None,
                            Lane::Prim(prim) => Some(prim),
                            Lane::PerRay => per_ray(l),
                        };
                        counts.0 += prim.is_some() as u64;
                        match (&self.flat_rgba, prim) {
                            (Some(rgba), _) => rgba.put(rows, row_off, i, prim),
                            (None, Some(prim)) => add(sum, scene.colors[prim as usize]),
                            (None, None) => {}
                        }
                    }
                }
            }
            if flat && self.flat_rgba.is_none() {
                let row = &mut rows[(j - tile.y0) as usize * self.row_bytes..][..self.row_bytes];
                for (l, sum) in sums.iter().take(tile.w as usize).enumerate() {
                    self.put(row, tile.x0 + l as u32, *sum);
                }
            }
        }
        if flat {
            return;
        }
        // Shadow rays, 8 at a time from the light: a flat scene's against the triangles that
        // can block one of the tile's, a BVH scene's through its BVH; the unsure ones per ray.
        let casts_shadows = matches!(settings.step, LabStep::Shadows | LabStep::Indirect);
        blocked.clear();
        blocked.resize(shaded.len(), 0);
        if casts_shadows {
            let light = scene.light.position;
            let per_ray = |occluders: Occluders, pk: &ShadePacket, lanes: u32, out: &mut u32| {
                for l in (0..8).filter(|l| lanes & (1 << l) != 0) {
                    let ray = Ray::new(light, pk.shadow_d.map(|c| c.to_array()[l]));
                    if occluders.blocked(scene, &ray, settings.method, pk.prim[l]) {
                        *out |= 1 << l;
                    }
                }
            };
            if bvh {
                // 8 at a time from the light through the BVH; the unsure lanes per ray.
                for (pk, out) in shaded.iter().zip(blocked.iter_mut()) {
                    if pk.shadowed == 0 {
                        continue;
                    }
                    let d_max = packet::max_component(&pk.shadow_d);
                    let prepared = self.light_bvh.as_ref();
                    let skip = &pk.prim;
                    match accel.blocked_packet(
                        light,
                        prepared,
                        &pk.shadow_d,
                        d_max,
                        skip,
                        pk.shadowed,
                    ) {
                        Some(found) => {
                            *out = found.blocked;
                            per_ray(Occluders::Scene, pk, found.unsure, out);
                        }
                        None => per_ray(Occluders::Scene, pk, pk.shadowed, out),
                    }
                }
            } else {
                self.occluders_for(shaded, near);
                let mut culled_blocks = None;
                for (pk, out) in shaded.iter().zip(blocked.iter_mut()) {
                    if pk.shadowed == 0 {
                        continue;
                    }
                    let d_max = packet::max_component(&pk.shadow_d);
                    let found = packet::shadow_from_origin(
                        near,
                        &pk.shadow_d,
                        d_max,
                        &pk.prim,
                        pk.shadowed,
                    );
                    *out = found.blocked;
                    // Unsure lanes: exact edge signs and sides where that decides.
                    let mut left = 0;
                    for l in (0..8).filter(|l| found.unsure & (1 << l) != 0) {
                        let d = pk.shadow_d.map(|c| c.to_array()[l]);
                        match packet::blocked_exact_lane(near, vertices, light, d, pk.prim[l]) {
                            Some(true) => *out |= 1 << l,
                            Some(false) => {}
                            None => left |= 1 << l,
                        }
                    }
                    if left != 0 {
                        let blocks = culled_blocks.get_or_insert_with(|| {
                            let tris: Vec<IndexedTriangle> = near
                                .iter()
                                .map(|t| (self.occluders[t.prim as usize].v, t.prim))
                                .collect();
                            TriangleBlocks::new(&tris)
                        });
                        per_ray(Occluders::Culled(blocks), pk, left, out);
                    }
                }
            }
        }
        // Colour: the samples of each pixel summed in the per-ray path's order.
        let per_row = (n * n) as usize;
        for (jj, row_packets) in shaded.chunks(per_row).enumerate() {
            let mut sums = [[0.0f32; 3]; TILE as usize];
            for (pk, blocked) in row_packets.iter().zip(&blocked[jj * per_row..]) {
                for (l, sum) in sums.iter_mut().enumerate().take(tile.w as usize) {
                    if pk.hit & (1 << l) == 0 {
                        continue;
                    }
                    counts.0 += 1;
                    let shadowed = pk.shadowed & (1 << l) != 0;
                    counts.1 += (casts_shadows && shadowed) as u64;
                    let d = pk.d(scene, l);
                    let c = shade::step_colour(
                        scene,
                        pk.prim[l],
                        d,
                        blocked & (1 << l) != 0,
                        settings.step,
                    );
                    add(sum, c);
                }
            }
            let row = &mut rows[jj * self.row_bytes..][..self.row_bytes];
            for (l, sum) in sums.iter().take(tile.w as usize).enumerate() {
                self.put(row, tile.x0 + l as u32, *sum);
            }
        }
    }

    /// Fills `near` with the scene's triangles (prepared for the light) that may block one
    /// of the shadow rays of `shaded`: those whose bounding box meets the box around every
    /// shadow segment (light to light + direction, widened for the rounding of that end). A
    /// triangle meeting a segment has a point in that box.
    fn occluders_for(&self, shaded: &[ShadePacket], near: &mut Vec<OriginTriangle>) {
        // Each segment's end L + d rounded as `Occluder::meets` allows for; the other lanes'
        // d are zero, so their ends are L, the segments' start. No end is NaN (a lane is lit
        // only where r² > 0 and cos > 0, so L, the point and the normal are finite there, and
        // d is finite or ±∞), so the NaN-blind `fast_min`/`fast_max` serve (2% of a shadows
        // frame's instructions less than `min`/`max`).
        let light = self.scene.light.position.map(f32x8::splat);
        let (mut lo, mut hi) = (light, light);
        for pk in shaded {
            for k in 0..3 {
                let end = light[k] + pk.shadow_d[k];
                lo[k] = lo[k].fast_min(end);
                hi[k] = hi[k].fast_max(end);
            }
        }
        let reduce = |x: [f32x8; 3], pick: fn(f32, f32) -> f32| {
            x.map(|c| c.to_array().into_iter().reduce(pick).expect("8 lanes"))
        };
        let (lo, hi) = (reduce(lo, f32::min), reduce(hi, f32::max));
        near.clear();
        near.extend(
            self.occluders
                .iter()
                .filter(|occ| occ.meets(lo, hi))
                .map(|occ| self.light_tris[occ.prim as usize]),
        );
    }
}

/// The flat step's RGBA8 pixels: with one sample per pixel, a pixel is its primitive's
/// colour encoded once (what `Frame::put` makes of it), or black. Encoded per primitive up
/// front where each is likely to be reused (at most one primitive per 8 camera rays: the
/// Cornell box, the bunny), else per pixel (the 1M-triangle mesh: a table would cost more
/// per frame than the pixels it serves).
struct FlatPixels<'a> {
    colors: &'a [Rgb],
    /// Per primitive; empty when encoding per pixel.
    table: Vec<[u8; 4]>,
    srgb: &'static SrgbTables,
}

impl<'a> FlatPixels<'a> {
    fn new(scene: &'a Scene, camera_rays: usize) -> Self {
        let srgb = SrgbTables::get();
        let encode = |c: &Rgb| [srgb.encode(c[0]), srgb.encode(c[1]), srgb.encode(c[2]), 255];
        let table = match scene.colors.len().saturating_mul(8) <= camera_rays {
            true => scene.colors.iter().map(encode).collect(),
            false => Vec::new(),
        };
        Self {
            colors: &scene.colors,
            table,
            srgb,
        }
    }

    /// Writes pixel `i` of the row at `row_off` in `rows`.
    #[inline]
    fn put(&self, rows: &mut [u8], row_off: usize, i: u32, prim: Option<u32>) {
        let px = match prim {
            None => [0, 0, 0, 255],
            Some(p) if !self.table.is_empty() => self.table[p as usize],
            Some(p) => {
                let c = self.colors[p as usize];
                let e = |x| self.srgb.encode(x);
                [e(c[0]), e(c[1]), e(c[2]), 255]
            }
        };
        rows[row_off + i as usize * 4..][..4].copy_from_slice(&px);
    }
}

fn add(sum: &mut Rgb, c: Rgb) {
    for k in 0..3 {
        sum[k] += c[k];
    }
}

/// Allocates the RGBA8 buffer and renders into it.
pub fn render_image(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
) -> Result<(Vec<u8>, RenderStats), SettingsError> {
    settings.validate()?;
    let mut rgba = vec![0u8; settings.buffer_len()];
    let stats = render_into(scene, camera, settings, &mut rgba)?;
    Ok((rgba, stats))
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value, clamped to [0, 1] and
/// rounded to 8 bits. NaN maps to 0.
pub fn linear_to_srgb8(x: f32) -> u8 {
    SrgbTables::get().encode(x)
}

/// The tables behind [`linear_to_srgb8`].
///
/// No `powf`: the code is the number of the 255 decision levels (the linear values where the
/// rounded code steps up, computed once in f64) at or below `x`. The bin of x is read off its
/// bits (exponent and 8 mantissa bits: bins 2^-8 wide relative to x, from 2^-13 up, below
/// which the code is 0); a table gives the count at the start of the bin, and since the curve
/// rises by at most 0.44 codes across a bin (255·x·srgb'(x) ≤ 112 per unit of ln x), one
/// comparison finishes it, with no branch.
struct SrgbTables {
    levels: [f32; 256],
    start: [u8; SRGB_BINS],
}

/// The first bin: x = 2^-13 (exponent 114, mantissa 0) shifted right by 15.
const SRGB_FIRST_BIN: usize = 114 << 8;
/// Bins from 2^-13 up to 1: 13 binades of 256.
const SRGB_BINS: usize = 13 << 8;

impl SrgbTables {
    /// The tables, built on first use.
    fn get() -> &'static SrgbTables {
        static TABLES: std::sync::LazyLock<SrgbTables> = std::sync::LazyLock::new(|| {
            let mut levels = [f32::INFINITY; 256];
            for (k, level) in levels.iter_mut().take(255).enumerate() {
                // The code steps from k to k + 1 where the encoded value reaches (k + 0.5)/255.
                let s = (k as f64 + 0.5) / 255.0;
                let lin = if s <= 0.04045 {
                    s / 12.92
                } else {
                    ((s + 0.055) / 1.055).powf(2.4)
                };
                *level = lin as f32;
            }
            let start = std::array::from_fn(|b| {
                let x = f32::from_bits(((b + SRGB_FIRST_BIN) << 15) as u32);
                levels.partition_point(|&l| l <= x) as u8
            });
            SrgbTables { levels, start }
        });
        &TABLES
    }

    #[inline]
    fn encode(&self, x: f32) -> u8 {
        if x.is_nan() || x <= 0.0 {
            return 0;
        }
        if x >= 1.0 {
            return 255;
        }
        // 0 < x < 1: the bin is below SRGB_BINS, or "negative" (wrapped) below 2^-13.
        let bin = ((x.to_bits() >> 15) as usize).wrapping_sub(SRGB_FIRST_BIN);
        let Some(&c) = self.start.get(bin) else {
            return 0;
        };
        c + (self.levels[c as usize] <= x) as u8
    }
}

/// The exact curve with `powf`, kept to test the table against.
pub fn linear_to_srgb8_reference(x: f32) -> u8 {
    let x = if x > 0.0 { (x as f64).min(1.0) } else { 0.0 };
    let s = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// Writes an RGBA8 image as PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> std::io::Result<()> {
    let file = std::fs::File::create(path)?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = enc.write_header().map_err(std::io::Error::other)?;
    writer
        .write_image_data(rgba)
        .map_err(std::io::Error::other)?;
    writer.finish().map_err(std::io::Error::other)
}
