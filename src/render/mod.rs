//! The parallel render driver: a plain loop over tiles. Bands of [`BAND`] rows run in parallel
//! (rayon); each band walks its tiles of [`TILE`] pixels, asks the accelerator's face
//! ([`FrameQueries`]) for the tile's queries, and shades the hits with the lab step
//! ([`shade`]). n×n stratified samples per pixel; linear colour averaged and sRGB-encoded once
//! into RGBA8 ([`image`]).
//!
//! Camera rays go 8 at a time, over blocks of 4×2 pixels (16 at a time over 4×4 in the
//! AVX-512 build's flat one-sample frame), where the face says so for the tile
//! ([`TileQueries::packets`]), else one at a time; either way the face answers exactly, and
//! shading depends only on the ray and the primitive hit, so all give the same bits.

pub mod aov;
pub mod image;
pub mod inspect;
pub mod settings;
pub mod shade;
pub mod stage;

use crate::accel::frame::{OriginTriangle, NO_HIT};
use crate::accel::{Accel, FrameQueries, FrameSetup, TileQueries, TileScratch};
use crate::camera::{Camera, RayGenerator};
use crate::geometry::{Method, Ray};
use crate::math::lanes::LaneOps;
use crate::scene::Scene;
use image::SrgbTables;
use rayon::prelude::*;
use std::time::{Duration, Instant};
use wide::f32x8;

pub use image::{linear_to_srgb8, linear_to_srgb8_reference, write_png};
pub use settings::{
    Control, LabStep, RenderSettings, SettingsError, CONTROLS, MAX_PIXELS, MAX_SIDE, MAX_SPP,
};
pub use shade::Rgb;
use shade::{ShadePacket, ShadeTri};
pub use stage::Stage;

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

/// The colour of a crack in the cracks view (linear magenta).
pub const CRACK: Rgb = [1.0, 0.0, 1.0];

/// Whether the ray slips through with `method` where the (exact) adaptive method hits, or
/// hits where it misses: a crack. (Picking the other of two triangles that meet at the hit
/// point is not one; it is the same surface.)
pub fn is_crack(accel: &Accel, ray: &Ray, method: Method) -> bool {
    let hits = |m| accel.closest_hit(ray, m, 0.0, f32::INFINITY).is_some();
    method != Method::Adaptive && hits(method) != hits(Method::Adaptive)
}

/// Width of the tiles camera rays are traced in (four packets' blocks of pixels, `Block`).
/// 16 rather than 8: each tile culls the scene's triangles once, and the Cornell box's flat
/// frame took 5-6% less time at 1280×720 and 640×360 (2 threads, `benches/before_after.sh`); 32 gained no
/// more, and the meshes' frames were the same within noise.
pub const TILE: u32 = 16;

/// Height of the tiles, the rows a parallel band holds.
pub const BAND: u32 = 16;

/// Renders the stage's scene through `camera` into `rgba` (RGBA8, rows top to bottom, alpha
/// 255).
pub fn render_into(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
    rgba: &mut [u8],
) -> Result<RenderStats, SettingsError> {
    render_into_cancellable(stage, camera, settings, rgba, &|| false)
        .map(|stats| stats.expect("never cancelled"))
}

/// [`render_into`] that gives up when `cancelled()` turns true (checked before each band of
/// rows), returning `Ok(None)` and leaving the buffer partly drawn: an interactive viewer
/// drops a frame that a camera move has made stale instead of waiting for it.
pub fn render_into_cancellable(
    stage: &Stage,
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
    let (scene, accel) = (stage.scene(), stage.accel());
    let start = Instant::now();
    let gen = camera.ray_generator(w, h);
    let camera_rays = w as usize * h as usize * (settings.spp * settings.spp) as usize;
    let queries = accel.for_frame(&FrameSetup {
        eye: gen.origin(),
        light: scene.light.position,
        projection: settings.tile_culling.then(|| camera.projection(w, h)),
        method: settings.method,
        camera_rays,
        shadows: settings.step.casts_shadows(),
        per_ray: settings.cracks,
    });
    let frame = Frame::new(stage, settings, &queries, gen, camera_rays);
    let (hits, shadow_rays) = rgba
        .par_chunks_mut(frame.row_bytes * BAND as usize)
        .enumerate()
        .map(|(band, rows)| {
            let mut counts = Counts::default();
            if cancelled() {
                return counts;
            }
            let y0 = band as u32 * BAND;
            let band_h = (rows.len() / frame.row_bytes) as u32;
            let mut scratch = TileScratch::default();
            let mut shading = Shading::default();
            for x0 in (0..w).step_by(TILE as usize) {
                let tile = Tile {
                    x0,
                    y0,
                    w: TILE.min(w - x0),
                    h: band_h,
                };
                let pixels = [x0, y0, x0 + tile.w, y0 + tile.h];
                let mut tile_queries = queries.tile(pixels, &mut scratch);
                if tile_queries.shows_nothing() {
                    frame.fill_background(&tile, rows);
                    continue;
                }
                match tile_queries.packets() {
                    true => frame.trace_tile_packets(
                        &tile,
                        &mut tile_queries,
                        &mut shading,
                        rows,
                        &mut counts,
                    ),
                    false => frame.trace_tile(&tile, &mut tile_queries, rows, &mut counts),
                }
            }
            counts
        })
        .reduce(Counts::default, |a, b| (a.0 + b.0, a.1 + b.1));
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

/// (camera rays that hit, shadow rays cast).
type Counts = (u64, u64);

/// [`Frame::trace_packets`] compiled for the CPU's SIMD level as the kernels are
/// ([`crate::math::simd::avx512_avx2_or_baseline`]): the tile loop's own work (ray directions,
/// shading, colours, pixel writes) in AVX2 or AVX-512 where the CPU has them: the Cornell
/// box with shadows at 1280×720, 2 threads, 5–8% faster (Zen 5, AVX-512, interleaved). The
/// flat step's one-sample path has its own copy ([`trace_flat_for_cpu`]).
fn trace_packets_for_cpu(
    frame: &Frame,
    tile: &Tile,
    queries: &mut TileQueries,
    shading: &mut Shading,
    rows: &mut [u8],
    counts: &mut Counts,
) {
    crate::math::simd::avx512_avx2_or_baseline!(Frame::trace_packets => (
        frame: &Frame,
        tile: &Tile,
        queries: &mut TileQueries,
        shading: &mut Shading,
        rows: &mut [u8],
        counts: &mut Counts
    ) -> ())
}

/// The flat step's one-sample tile loop ([`Frame::trace_flat_tile`]) through the copy
/// built for the CPU, ray directions and a small scene's packet kernel inline in it: the
/// Cornell flat frame at 1280×720 on 2 threads took 1.4× as long in the default build as
/// with the whole program built for AVX2 while they were called per packet.
fn trace_flat_for_cpu(
    frame: &Frame,
    tile: &Tile,
    queries: &mut TileQueries,
    rgba: &FlatPixels,
    rows: &mut [u8],
    counts: &mut Counts,
) {
    crate::math::simd::avx512_avx2_or_baseline!(widest Frame::trace_flat_tile => (
        frame: &Frame,
        tile: &Tile,
        queries: &mut TileQueries,
        rgba: &FlatPixels,
        rows: &mut [u8],
        counts: &mut Counts
    ) -> ())
}

/// One tile of the image: pixels x0..x0 + w, y0..y0 + h.
struct Tile {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
}

impl Tile {
    /// The tile's blocks of [`PACKET_W`]×[`PACKET_H`] pixels (narrower or shorter at its right
    /// and bottom edges), row of blocks by row of blocks.
    fn blocks(&self) -> impl Iterator<Item = Block> + '_ {
        self.blocks_of(PACKET_H)
    }

    /// The tile's blocks of [`PACKET_W`]×`rows` pixels, as [`Tile::blocks`].
    fn blocks_of(&self, rows: u32) -> impl Iterator<Item = Block> + '_ {
        (0..self.h).step_by(rows as usize).flat_map(move |row0| {
            (0..self.w).step_by(PACKET_W as usize).map(move |x| Block {
                x0: self.x0 + x,
                w: PACKET_W.min(self.w - x),
                h: rows.min(self.h - row0),
                row0,
            })
        })
    }
}

/// Width of a camera packet's footprint: lane l traces pixel column l % 4 of its block.
const PACKET_W: u32 = 4;

/// Height of a camera packet's footprint: lane l traces pixel row l / 4 of its block. A
/// squarer footprint meets fewer BVH boxes than a row of 8: 10-12% fewer instructions for the
/// bunny's frames at 640×360 and 1280×720, 3-4% more for the Cornell box's flat frames
/// (`benches/instructions.sh`).
const PACKET_H: u32 = 2;

/// The pixels one packet of camera rays traces: columns x0..x0 + w (at most 4) of the
/// tile's rows row0..row0 + h (at most 2, or 4 for the 16-lane packets of
/// [`Frame::trace_flat_tile`]).
struct Block {
    x0: u32,
    w: u32,
    h: u32,
    row0: u32,
}

impl Block {
    /// The lanes on pixels of the block; the others (past the image's edges) are dead.
    fn live_lanes(&self) -> u32 {
        let row = (1u32 << self.w) - 1;
        // The row's bits repeated every PACKET_W (= 4) bits, once per row (no carries).
        row * (0x1111 >> (PACKET_W * (4 - self.h)))
    }

    /// Per lane, the pixel's column and row in the image, where the tile starts at row `y0`
    /// (dead lanes repeat the block's last pixel, so that the packet stays as coherent as a
    /// full one). Sums of small integers, so exact.
    #[inline(always)]
    fn pixel_lanes<V: LaneOps>(&self, y0: u32) -> (V, V) {
        const COLUMN: [f32; 16] = [
            0.0, 1.0, 2.0, 3.0, 0.0, 1.0, 2.0, 3.0, 0.0, 1.0, 2.0, 3.0, 0.0, 1.0, 2.0, 3.0,
        ];
        const ROW: [f32; 16] = [
            0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0, 3.0,
        ];
        let column = V::load(&COLUMN).fast_min(V::splat((self.w - 1) as f32));
        let row = V::load(&ROW).fast_min(V::splat((self.h - 1) as f32));
        (
            V::splat(self.x0 as f32) + column,
            V::splat((y0 + self.row0) as f32) + row,
        )
    }

    /// The byte offset of the block's first pixel in the band's rows.
    fn offset(&self, row_bytes: usize) -> usize {
        self.row0 as usize * row_bytes + self.x0 as usize * 4
    }
}

/// Buffers a band reuses from tile to tile: per packet of camera rays (rows, then samples),
/// its hits readied for shading and its blocked shadow lanes.
#[derive(Default)]
struct Shading {
    packets: Vec<ShadePacket>,
    blocked: Vec<u32>,
}

/// What every tile of one frame shares.
struct Frame<'a> {
    scene: &'a Scene,
    /// The structure over it (the cracks view asks it per ray).
    accel: &'a Accel,
    settings: &'a RenderSettings,
    /// The triangles readied for shading hits from the eye, by primitive, where the face
    /// prepared them all for the eye (steps past the flat one; else each packet readies its
    /// own). The entries of other shapes are stand-ins never read: their lanes are shaded
    /// apart ([`Frame::shade_other_lanes`]).
    camera_tris: Vec<ShadeTri>,
    /// Whether the scene holds shapes other than triangles (a packet's lanes may hit them).
    other_shapes: bool,
    gen: RayGenerator,
    /// The flat step's pixels per primitive, for one sample per pixel (written as found).
    flat_rgba: Option<FlatPixels<'a>>,
    inv_n: f32,
    /// 1/n² for n×n samples.
    weight: f32,
    srgb: &'static SrgbTables,
    row_bytes: usize,
}

impl<'a> Frame<'a> {
    fn new(
        stage: &'a Stage,
        settings: &'a RenderSettings,
        queries: &FrameQueries,
        gen: RayGenerator,
        camera_rays: usize,
    ) -> Self {
        // By primitive, where every primitive not prepared is another shape (not where the
        // accelerator left out copies).
        let (scene, accel) = (stage.scene(), stage.accel());
        let prepared = queries.prepared_for_eye();
        let others = accel.other_shape_count();
        let camera_tris = match (settings.step, prepared.first()) {
            (LabStep::Flat, _) | (_, None) => Vec::new(),
            _ if prepared.len() + others != scene.len() => Vec::new(),
            (_, Some(first)) => {
                let ready = |tri: &OriginTriangle| ShadeTri {
                    tri: *tri,
                    normal: shade::unit_normal(&triangle(scene, tri.prim)),
                };
                let mut by_prim = vec![ready(first); scene.len()];
                for tri in prepared {
                    by_prim[tri.prim as usize] = ready(tri);
                }
                by_prim
            }
        };
        let one_colour_per_pixel = settings.step == LabStep::Flat && settings.spp == 1;
        let flat_rgba = (queries.packets() && one_colour_per_pixel)
            .then(|| FlatPixels::new(scene, camera_rays));
        Self {
            scene,
            accel,
            settings,
            camera_tris,
            other_shapes: accel.has_other_shapes(),
            gen,
            flat_rgba,
            inv_n: 1.0 / settings.spp as f32,
            weight: 1.0 / (settings.spp * settings.spp) as f32,
            srgb: SrgbTables::get(),
            row_bytes: settings.width as usize * 4,
        }
    }

    /// Image position of sample (sx, sy) of pixel (i, j).
    #[inline]
    fn sample(&self, i: u32, j: u32, sx: u32, sy: u32) -> (f32, f32) {
        let x = i as f32 + (sx as f32 + 0.5) * self.inv_n;
        let y = j as f32 + (sy as f32 + 0.5) * self.inv_n;
        (x, y)
    }

    /// Writes pixel (i, row) from its samples' summed linear colour.
    #[inline]
    fn put(&self, row: &mut [u8], i: u32, sum: Rgb) {
        self.put_pixel(&mut row[i as usize * 4..][..4], sum);
    }

    /// Writes RGBA8 pixel `px` from its samples' summed linear colour.
    #[inline(always)]
    fn put_pixel(&self, px: &mut [u8], sum: Rgb) {
        let (weight, srgb) = (self.weight, self.srgb);
        px[0] = srgb.encode(sum[0] * weight);
        px[1] = srgb.encode(sum[1] * weight);
        px[2] = srgb.encode(sum[2] * weight);
        px[3] = 255;
    }

    /// Writes the background (black: no sample hits) over a tile of `rows`, as the tracing
    /// paths would where no ray hits.
    fn fill_background(&self, tile: &Tile, rows: &mut [u8]) {
        for j in 0..tile.h as usize {
            let at = j * self.row_bytes + tile.x0 as usize * 4;
            for px in rows[at..][..tile.w as usize * 4].chunks_exact_mut(4) {
                px.copy_from_slice(&BLACK_RGBA.to_ne_bytes());
            }
        }
    }

    /// Traces a tile ray by ray into `rows` (the band of rows the tile lies in).
    fn trace_tile(
        &self,
        tile: &Tile,
        queries: &mut TileQueries,
        rows: &mut [u8],
        counts: &mut Counts,
    ) {
        let (scene, settings) = (self.scene, self.settings);
        let n = settings.spp;
        for j in tile.y0..tile.y0 + tile.h {
            let row = &mut rows[(j - tile.y0) as usize * self.row_bytes..][..self.row_bytes];
            for i in tile.x0..tile.x0 + tile.w {
                let mut sum = [0.0f32; 3];
                for sy in 0..n {
                    for sx in 0..n {
                        let (x, y) = self.sample(i, j, sx, sy);
                        let ray = self.gen.ray_through(x, y);
                        let colour =
                            if settings.cracks && is_crack(self.accel, &ray, settings.method) {
                                Some(CRACK)
                            } else {
                                queries.closest(&ray).map(|hit| {
                                    let blocked = |ray: &Ray, skip| queries.blocked(ray, skip);
                                    shade::shade(
                                        scene,
                                        &ray,
                                        &hit,
                                        settings.step,
                                        blocked,
                                        &mut counts.1,
                                    )
                                })
                            };
                        if let Some(c) = colour {
                            counts.0 += 1;
                            add(&mut sum, c);
                        }
                    }
                }
                self.put(row, i, sum);
            }
        }
    }

    /// Traces a tile's camera rays 8 at a time, a [`Block`] of 4×2 pixels per packet, into
    /// `rows`; then, past the flat step, readies the hits for shading 8 at a time
    /// ([`shade::shade_packet`]), asks for the tile's shadow segments at once, and colours each
    /// pixel from its samples in the per-ray path's order.
    #[inline(never)]
    fn trace_tile_packets(
        &self,
        tile: &Tile,
        queries: &mut TileQueries,
        shading: &mut Shading,
        rows: &mut [u8],
        counts: &mut Counts,
    ) {
        match &self.flat_rgba {
            Some(rgba) => trace_flat_for_cpu(self, tile, queries, rgba, rows, counts),
            None => trace_packets_for_cpu(self, tile, queries, shading, rows, counts),
        }
    }

    /// [`Frame::trace_tile_packets`] past the flat step's one-sample path.
    #[inline(always)]
    fn trace_packets(
        &self,
        tile: &Tile,
        queries: &mut TileQueries,
        shading: &mut Shading,
        rows: &mut [u8],
        counts: &mut Counts,
    ) {
        let (scene, settings) = (self.scene, self.settings);
        let Shading {
            packets: shaded,
            blocked,
        } = shading;
        // Looked up once: loads through `scene` cannot be hoisted out of the loops (it holds
        // a OnceLock), and without instances primitive i's colour is colors[i].
        let stored_colors = scene.instances().is_empty().then_some(scene.colors());
        let n = settings.spp;
        let o = self.gen.origin();
        let flat = settings.step == LabStep::Flat;
        shaded.clear();
        for block in tile.blocks() {
            let live = block.live_lanes();
            let (xs, ys) = block.pixel_lanes::<f32x8>(tile.y0);
            let mut sums = [[0.0f32; 3]; 8];
            for sy in 0..n {
                for sx in 0..n {
                    // The image positions of `sample`, with the same operations.
                    let off_x = (sx as f32 + 0.5) * self.inv_n;
                    let off_y = (sy as f32 + 0.5) * self.inv_n;
                    let dirs = self
                        .gen
                        .directions_x8(xs + f32x8::splat(off_x), ys + f32x8::splat(off_y));
                    let prims = queries.closest_x8(&dirs, live);
                    if !flat {
                        let mut others = 0;
                        shaded.push(self.ready_for_shading(o, &dirs, &prims, &mut others));
                        if others != 0 {
                            let packet = shaded.last_mut().expect("just pushed");
                            self.shade_other_lanes(o, &dirs, &prims, others, packet);
                        }
                        continue;
                    }
                    // (Dead lanes are NO_HIT.)
                    counts.0 += prims.iter().filter(|&&p| p != NO_HIT).count() as u64;
                    for (sum, &prim) in sums.iter_mut().zip(&prims) {
                        if prim != NO_HIT {
                            add(
                                sum,
                                shade::step_colour(scene, prim, [0.0; 3], false, LabStep::Flat),
                            );
                        }
                    }
                }
            }
            if flat {
                self.put_block(&block, &sums, rows);
            }
        }
        if flat {
            return;
        }
        let casts_shadows = settings.step.casts_shadows();
        if casts_shadows {
            queries.blocked_x8(shaded, blocked);
        } else {
            blocked.clear();
            blocked.resize(shaded.len(), 0);
        }
        // Colour: the samples of each pixel summed in the per-ray path's order.
        let per_block = (n * n) as usize;
        for (block, (packets, blocked)) in tile
            .blocks()
            .zip(shaded.chunks(per_block).zip(blocked.chunks(per_block)))
        {
            let live = block.live_lanes();
            for pk in packets {
                let hit = pk.hit & live;
                counts.0 += hit.count_ones() as u64;
                if casts_shadows {
                    counts.1 += (hit & pk.shadow.live).count_ones() as u64;
                }
            }
            let sums =
                shade::sum_colours(scene, stored_colors, packets, blocked, settings.step, live);
            self.put_block(&block, &sums, rows);
        }
    }

    /// The flat step with one sample per pixel: each pixel the colour of the primitive its
    /// camera ray hits ([`FlatPixels`]), written as found. In lanes `V`, inside the copy of
    /// the tile loop built for the CPU ([`trace_flat_for_cpu`]): 16 lanes (blocks of 4×4
    /// pixels) in the AVX-512 build, else 8 (4×2).
    #[inline(always)]
    fn trace_flat_tile<V: LaneOps>(
        &self,
        tile: &Tile,
        queries: &mut TileQueries,
        rgba: &FlatPixels,
        rows: &mut [u8],
        counts: &mut Counts,
    ) {
        // (The pixel centres of `sample` for one sample: i + 0.5.)
        let centre = V::splat(0.5);
        let d_max = self.gen.component_bound();
        let mut prims = [NO_HIT; 16];
        let mut last = LastWord::default();
        for block in tile.blocks_of((V::WIDTH / PACKET_W as usize) as u32) {
            let (xs, ys) = block.pixel_lanes::<V>(tile.y0);
            let dirs = self.gen.directions_in(xs + centre, ys + centre);
            queries.closest_in(dirs, d_max, block.live_lanes(), &mut prims);
            // (Dead lanes are NO_HIT.)
            let prims = &prims[..V::WIDTH];
            counts.0 += prims.iter().map(|&p| u64::from(p != NO_HIT)).sum::<u64>();
            let (w, at) = (block.w as usize, block.offset(self.row_bytes));
            for (r, row) in prims
                .chunks_exact(PACKET_W as usize)
                .take(block.h as usize)
                .enumerate()
            {
                let at = at + r * self.row_bytes;
                rgba.put(&mut rows[at..][..w * 4], &row[..w], &mut last);
            }
        }
    }

    /// Writes the pixels of `block` from their lanes' summed linear colours.
    fn put_block(&self, block: &Block, sums: &[Rgb; 8], rows: &mut [u8]) {
        let (w, at) = (block.w as usize, block.offset(self.row_bytes));
        let put_row = |pixels: &mut [u8], sums: &[Rgb]| {
            for (px, sum) in pixels.chunks_exact_mut(4).zip(sums) {
                self.put_pixel(px, *sum);
            }
        };
        put_row(&mut rows[at..][..w * 4], &sums[..w]);
        if block.h == 2 {
            let at = at + self.row_bytes;
            put_row(&mut rows[at..][..w * 4], &sums[4..][..w]);
        }
    }

    /// 8 camera hits (directions `dirs` from the eye `o`, primitives `prims`) on triangles
    /// readied for shading: the triangles prepared for the eye where the face made them, else
    /// here. Lanes on other shapes are left empty and set in `others`
    /// ([`Frame::shade_other_lanes`]).
    fn ready_for_shading(
        &self,
        o: [f32; 3],
        dirs: &[f32x8; 3],
        prims: &[u32; 8],
        others: &mut u32,
    ) -> ShadePacket {
        let mut own = [None; 8];
        let mut prepared: [Option<&ShadeTri>; 8] = [None; 8];
        for (l, &prim) in prims.iter().enumerate() {
            if prim == NO_HIT {
                continue;
            }
            if self.other_shapes && !self.scene.shape(prim).is_triangle() {
                *others |= 1 << l;
                continue;
            }
            match self.camera_tris.get(prim as usize) {
                Some(tri) => prepared[l] = Some(tri),
                None => own[l] = Some(ShadeTri::new(&triangle(self.scene, prim), o, prim)),
            }
        }
        for (l, tri) in own.iter().enumerate() {
            if let Some(tri) = tri {
                prepared[l] = Some(tri);
            }
        }
        shade::shade_packet(self.scene, dirs, &prepared)
    }

    /// Lanes `others` of `packet` (hits on shapes other than triangles) readied for shading,
    /// one by one as the per-ray path readies them ([`shade::Lit`]).
    #[inline(never)]
    fn shade_other_lanes(
        &self,
        o: [f32; 3],
        dirs: &[f32x8; 3],
        prims: &[u32; 8],
        others: u32,
        packet: &mut ShadePacket,
    ) {
        for l in (0..8).filter(|l| others & (1 << l) != 0) {
            let ray = Ray::new(o, dirs.map(|c| c.to_array()[l]));
            packet.set_lane(l, &shade::Lit::on(self.scene, &ray, prims[l]));
        }
    }
}

/// The vertices of triangle `prim` (asked of triangles only: other shapes' lanes are shaded
/// apart).
fn triangle(scene: &Scene, prim: u32) -> [[f32; 3]; 3] {
    *(scene.shape(prim).triangle()).expect("other shapes are shaded in shade_other_lanes")
}

/// The flat step's RGBA8 pixels: with one sample per pixel, a pixel is its primitive's
/// colour encoded once (what `Frame::put` makes of it), or black. Encoded per primitive up
/// front where each is likely to be reused (at most one primitive per 8 camera rays: the
/// Cornell box, the bunny), else per pixel (the 1M-triangle mesh: a table would cost more
/// per frame than the pixels it serves).
struct FlatPixels<'a> {
    scene: &'a Scene,
    /// Per primitive, RGBA8 as one word in memory order; empty when encoding per pixel.
    table: Vec<u32>,
    srgb: &'static SrgbTables,
}

impl<'a> FlatPixels<'a> {
    fn new(scene: &'a Scene, camera_rays: usize) -> Self {
        let srgb = SrgbTables::get();
        // (Encoded once per run of primitives known to share a colour: building the bunny's
        // table, 69k encodings, was 4.5% of its flat frame at 1280×720.)
        let mut last = LastWord::default();
        let mut table = Vec::new();
        if scene.len().saturating_mul(8) <= camera_rays {
            table.reserve_exact(scene.len());
            while table.len() < scene.len() {
                let p = table.len() as u32;
                let word = last.of(srgb, scene, p);
                let run_end = (last.run.end as usize).clamp(p as usize + 1, scene.len());
                table.resize(run_end, word);
            }
        }
        Self { scene, table, srgb }
    }

    /// Writes the pixels of primitives `prims` ([`NO_HIT`]: black) into `out`, 4 bytes each.
    /// (In words: written as bytes, the table's entries were taken apart and put together
    /// again, 24 instructions a pixel.) Without a table, a colour is encoded only where it
    /// differs from the `last` one encoded.
    #[inline(always)]
    fn put(&self, out: &mut [u8], prims: &[u32], last: &mut LastWord) {
        for (px, &p) in out.chunks_exact_mut(4).zip(prims) {
            // (NO_HIT is past the table's end.)
            let rgba = match self.table.get(p as usize) {
                Some(&rgba) => rgba,
                None if p == NO_HIT => BLACK_RGBA,
                None => last.of(self.srgb, self.scene, p),
            };
            px.copy_from_slice(&rgba.to_ne_bytes());
        }
    }
}

/// The last colour a tile encoded, its RGBA word, and the primitives known to show it: a
/// mesh's neighbouring pixels mostly show one material, and encoding each pixel's colour
/// anew (three sRGB conversions) was 5-6% of the bunny's flat frame at 640×360, where the
/// mesh has too many triangles for a table per primitive; finding each pixel's instance and
/// its colour was 13% of the field of 1,000 bunnies' flat frame at 1280×720.
struct LastWord {
    run: std::ops::Range<u32>,
    color: Rgb,
    word: u32,
}

impl Default for LastWord {
    fn default() -> Self {
        // (NaN equals nothing: the first colour is encoded.)
        Self {
            run: 0..0,
            color: [f32::NAN; 3],
            word: 0,
        }
    }
}

impl LastWord {
    /// Primitive `p`'s RGBA word.
    #[inline(always)]
    fn of(&mut self, srgb: &SrgbTables, scene: &Scene, p: u32) -> u32 {
        if !self.run.contains(&p) {
            let (run, c) = scene.color_run(p);
            self.run = run;
            if c != self.color {
                self.color = c;
                self.word = rgba_word(srgb, c);
            }
        }
        self.word
    }
}

/// Opaque black as an RGBA8 word in memory order.
const BLACK_RGBA: u32 = u32::from_ne_bytes([0, 0, 0, 255]);

/// Linear colour `c` encoded as an RGBA8 word in memory order, alpha 255.
fn rgba_word(srgb: &SrgbTables, c: Rgb) -> u32 {
    u32::from_ne_bytes([srgb.encode(c[0]), srgb.encode(c[1]), srgb.encode(c[2]), 255])
}

fn add(sum: &mut Rgb, c: Rgb) {
    for k in 0..3 {
        sum[k] += c[k];
    }
}

/// Allocates the RGBA8 buffer and renders into it.
pub fn render_image(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
) -> Result<(Vec<u8>, RenderStats), SettingsError> {
    settings.validate()?;
    let mut rgba = vec![0u8; settings.buffer_len()];
    let stats = render_into(stage, camera, settings, &mut rgba)?;
    Ok((rgba, stats))
}
