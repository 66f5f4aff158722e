//! raylab's own tracer behind the render driver ([`super::driver`]): each tile asks the
//! accelerator's face ([`FrameQueries`]) for its queries and shades the hits with the lab step
//! ([`shade`]).
//!
//! Camera rays go 8 at a time, over blocks of 4×2 pixels (16 at a time over 4×4 in the
//! AVX-512 build's flat one-sample frame), where the face says so for the tile
//! ([`TileQueries::packets`]), else one at a time; either way the face answers exactly, and
//! shading depends only on the ray and the primitive hit, so all give the same bits.

use super::driver::{add, Counts, Sample, Samples, Tile, TileTracer};
use super::flat_pixels::{FlatPixels, LastWord, BLACK_RGBA};
use super::shade::{self, Rgb, ShadePacket, ShadeTri};
use super::{is_crack, LabStep, RenderSettings, Stage, CRACK};
use crate::accel::{Accel, FrameQueries, OriginTriangle, TileQueries, TileScratch, NO_HIT};
use crate::camera::RayGenerator;
use crate::geometry::triangle::surface_point_prepared;
use crate::geometry::Ray;
use crate::math::lanes::{LaneOps, Lanes};
use crate::math::simd::Isa;
use crate::scene::Scene;
use wide::f32x8;

impl TileTracer for Frame<'_> {
    type Scratch = (TileScratch, Shading);

    fn trace(
        &self,
        tile: &Tile,
        (scratch, shading): &mut Self::Scratch,
        rows: &mut [u8],
        counts: &mut Counts,
    ) {
        let pixels = [tile.x0, tile.y0, tile.x0 + tile.w, tile.y0 + tile.h];
        let mut queries = self.queries.tile(pixels, scratch);
        if queries.shows_nothing() {
            self.fill_background(tile, rows);
            return;
        }
        match queries.packets() {
            true => self.trace_tile_packets(tile, &mut queries, shading, rows, counts),
            false => self.trace_tile(tile, &mut queries, rows, counts),
        }
    }
}

/// [`Frame::trace_packets`] compiled for each SIMD build as the kernels are
/// ([`crate::math::simd::avx512_avx2_or_baseline`]), entered in the frame's one choice
/// ([`FrameQueries::build`]): the tile loop's own work (ray directions,
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
    crate::math::simd::avx512_avx2_or_baseline!(chosen frame.queries.build(), isa lanes trace_packets_in => (
        frame: &Frame,
        tile: &Tile,
        queries: &mut TileQueries,
        shading: &mut Shading,
        rows: &mut [u8],
        counts: &mut Counts
    ) -> ())
}

/// The flat step's one-sample tile loop ([`Frame::trace_flat_tile`]) through the copy
/// of the frame's build, ray directions and a small scene's packet kernel inline in it: the
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
    crate::math::simd::avx512_avx2_or_baseline!(chosen frame.queries.build(), isa widest trace_flat_in => (
        frame: &Frame,
        tile: &Tile,
        queries: &mut TileQueries,
        rgba: &FlatPixels,
        rows: &mut [u8],
        counts: &mut Counts
    ) -> ())
}

/// [`Frame::trace_packets`] with the build's token first, as the dispatch hands it.
#[inline(always)]
fn trace_packets_in<V: Lanes, I: Isa>(
    isa: I,
    frame: &Frame,
    tile: &Tile,
    queries: &mut TileQueries,
    shading: &mut Shading,
    rows: &mut [u8],
    counts: &mut Counts,
) {
    frame.trace_packets::<V, I>(isa, tile, queries, shading, rows, counts)
}

/// [`Frame::trace_flat_tile`] with the build's token first, as the dispatch hands it.
#[inline(always)]
fn trace_flat_in<V: LaneOps, I: Isa>(
    isa: I,
    frame: &Frame,
    tile: &Tile,
    queries: &mut TileQueries,
    rgba: &FlatPixels,
    rows: &mut [u8],
    counts: &mut Counts,
) {
    frame.trace_flat_tile::<V, I>(isa, tile, queries, rgba, rows, counts)
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
pub(super) struct Shading {
    packets: Vec<ShadePacket>,
    blocked: Vec<u32>,
}

/// What every tile of one frame shares.
pub(super) struct Frame<'a> {
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
    /// Whether a packet's hits are shaded one by one ([`shade::Lit`]), their shadow rays
    /// asked per ray: for a far light ([`Scene::shadows_from_light`] false) they start at
    /// the points and share no origin.
    lit_one_by_one: bool,
    gen: RayGenerator,
    /// The flat step's pixels per primitive, for one sample per pixel (written as found).
    flat_rgba: Option<FlatPixels<'a>>,
    /// The frame's queries, asked per tile.
    queries: &'a FrameQueries<'a>,
    samples: Samples,
}

impl<'a> Frame<'a> {
    pub(super) fn new(
        stage: &'a Stage,
        settings: &'a RenderSettings,
        queries: &'a FrameQueries<'a>,
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
            lit_one_by_one: settings.step.casts_shadows() && !scene.shadows_from_light(),
            gen,
            flat_rgba,
            queries,
            samples: Samples::new(settings),
        }
    }

    /// Writes the background (black: no sample hits) over a tile of `rows`, as the tracing
    /// paths would where no ray hits.
    fn fill_background(&self, tile: &Tile, rows: &mut [u8]) {
        for j in 0..tile.h as usize {
            let at = j * self.samples.row_bytes + tile.x0 as usize * 4;
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
        self.samples.each_pixel(tile, rows, counts, |x, y, counts| {
            let ray = self.gen.ray_through(x, y);
            if settings.cracks && is_crack(self.accel, &ray, settings.method) {
                return Some(Sample::Mark(CRACK));
            }
            let hit = queries.closest(&ray)?;
            let blocked = |ray: &Ray, skip| queries.any(ray, skip);
            let colour = shade::shade(scene, &ray, &hit, settings.step, blocked, &mut counts.1);
            Some(Sample::Colour(colour))
        });
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
    fn trace_packets<V: Lanes, I: Isa>(
        &self,
        isa: I,
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
        let n = self.samples.n;
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
                    let (off_x, off_y) = (self.samples.offset(sx), self.samples.offset(sy));
                    let dirs = (self.gen)
                        .directions_x8_in::<V>(xs + f32x8::splat(off_x), ys + f32x8::splat(off_y));
                    let prims = queries.closest_x8_in(isa, &dirs, live);
                    if self.lit_one_by_one {
                        self.shade_one_by_one(o, &dirs, &prims, queries, &mut sums, counts);
                        continue;
                    }
                    if !flat {
                        let mut others = 0;
                        shaded.push(self.ready_for_shading::<V>(o, &dirs, &prims, &mut others));
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
            if flat || self.lit_one_by_one {
                self.put_block(&block, &sums, rows);
            }
        }
        if flat || self.lit_one_by_one {
            return;
        }
        let casts_shadows = settings.step.casts_shadows();
        if casts_shadows {
            queries.any_x8_in(isa, shaded, blocked);
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
            let sums = shade::sum_colours::<V>(
                scene,
                stored_colors,
                packets,
                blocked,
                settings.step,
                live,
            );
            self.put_block(&block, &sums, rows);
        }
    }

    /// The flat step with one sample per pixel: each pixel the colour of the primitive its
    /// camera ray hits ([`FlatPixels`]), written as found. In lanes `V`, inside the copy of
    /// the tile loop built for the CPU ([`trace_flat_for_cpu`]): 16 lanes (blocks of 4×4
    /// pixels) in the AVX-512 build, else 8 (4×2).
    #[inline(always)]
    fn trace_flat_tile<V: LaneOps, I: Isa>(
        &self,
        isa: I,
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
            queries.closest_in(isa, dirs, d_max, block.live_lanes(), &mut prims);
            // (Dead lanes are NO_HIT.)
            let prims = &prims[..V::WIDTH];
            counts.0 += prims.iter().map(|&p| u64::from(p != NO_HIT)).sum::<u64>();
            let (w, at) = (block.w as usize, block.offset(self.samples.row_bytes));
            for (r, row) in prims
                .chunks_exact(PACKET_W as usize)
                .take(block.h as usize)
                .enumerate()
            {
                let at = at + r * self.samples.row_bytes;
                rgba.put(&mut rows[at..][..w * 4], &row[..w], &mut last);
            }
        }
    }

    /// Writes the pixels of `block` from their lanes' summed linear colours.
    fn put_block(&self, block: &Block, sums: &[Rgb; 8], rows: &mut [u8]) {
        let (w, at) = (block.w as usize, block.offset(self.samples.row_bytes));
        let put_row = |pixels: &mut [u8], sums: &[Rgb]| {
            for (px, sum) in pixels.chunks_exact_mut(4).zip(sums) {
                self.samples.put_pixel(px, *sum);
            }
        };
        put_row(&mut rows[at..][..w * 4], &sums[..w]);
        if block.h == 2 {
            let at = at + self.samples.row_bytes;
            put_row(&mut rows[at..][..w * 4], &sums[4..][..w]);
        }
    }

    /// 8 camera hits (directions `dirs` from the eye `o`, primitives `prims`) on triangles
    /// readied for shading: the triangles prepared for the eye where the face made them, else
    /// here. Lanes on other shapes are left empty and set in `others`
    /// ([`Frame::shade_other_lanes`]).
    #[inline(always)]
    fn ready_for_shading<V: Lanes>(
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
        shade::shade_packet_in::<V>(self.scene, dirs, &prepared)
    }

    /// 8 camera hits (directions `dirs` from the eye `o`, primitives `prims`; dead lanes
    /// miss) shaded one by one as the per-ray path shades them, each shadow ray asked alone,
    /// their colours added to `sums`.
    #[inline(never)]
    fn shade_one_by_one(
        &self,
        o: [f32; 3],
        dirs: &[f32x8; 3],
        prims: &[u32; 8],
        queries: &TileQueries,
        sums: &mut [Rgb; 8],
        counts: &mut Counts,
    ) {
        let (scene, step) = (self.scene, self.settings.step);
        for (l, (&prim, sum)) in prims.iter().zip(sums).enumerate() {
            if prim == NO_HIT {
                continue;
            }
            let ray = Ray::new(o, dirs.map(|c| c.to_array()[l]));
            let blocked = |ray: &Ray, skip| queries.any(ray, skip);
            // (A triangle the frame prepared for the eye is not prepared again per hit.)
            let prepared = (self.camera_tris.get(prim as usize))
                .filter(|_| !self.other_shapes || scene.shape(prim).is_triangle());
            let lit = match prepared {
                Some(t) => {
                    let v = triangle(scene, prim);
                    let sp = surface_point_prepared(&t.tri, &v, t.normal, ray.d);
                    shade::Lit::at(scene, &ray, prim, sp)
                }
                None => shade::Lit::on(scene, &ray, prim),
            };
            add(sum, lit.colour(scene, step, blocked, &mut counts.1));
            counts.0 += 1;
        }
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
