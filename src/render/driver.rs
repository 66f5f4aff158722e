//! The one render driver: every image raylab draws (its own frames through the accelerator,
//! and linked lab code's, [`crate::check::code`]) goes through [`drive`], and the AOV arrays'
//! centre rays ([`super::aov`]) through [`drive_rows`], which it is made of. Bands of rows
//! ([`BAND`] for images, one for the arrays' single rays) run in parallel (rayon); each band
//! walks its tiles of [`TILE`] pixels and hands each to the frame's [`TileTracer`]; a render
//! is cancelled before a tile starts. Every image's tracer samples and encodes pixels through
//! [`Samples`]: n×n stratified samples a pixel, linear colour summed, averaged and
//! sRGB-encoded once into RGBA8. What differs between tracers is only how a sample's colour
//! (or a pixel's values) is found.

use super::image::SrgbTables;
use super::settings::{RenderSettings, SettingsError};
use super::shade::Rgb;
use super::{RenderStats, BAND, TILE};
use rayon::prelude::*;
use std::time::Instant;

/// (camera samples that got a colour, shadow rays cast).
pub(crate) type Counts = (u64, u64);

/// What a sample shows: a colour, averaged with the pixel's other samples, or a mark (the
/// cracks view's, a wrong answer's), which the whole pixel takes, so that one marked sample
/// of 2×2 shows as plainly as at one sample a pixel.
pub(crate) enum Sample {
    Colour(Rgb),
    Mark(Rgb),
}

/// One tile of the image: pixels x0..x0 + w, y0..y0 + h.
pub(crate) struct Tile {
    pub(crate) x0: u32,
    pub(crate) y0: u32,
    pub(crate) w: u32,
    pub(crate) h: u32,
}

/// What fills the tiles of one frame.
pub(crate) trait TileTracer: Sync {
    /// Buffers a band reuses from tile to tile.
    type Scratch: Default;

    /// Bytes a pixel takes: an image's RGBA8, or the values the tracer writes per pixel.
    const PIXEL_BYTES: usize = 4;

    /// Rows a band holds, the unit of work the threads share: [`BAND`] for the images'
    /// packets of rays (which span that many rows); a tracer of one ray at a time may take a
    /// row, so that even a few rows of a wide image keep every thread busy.
    const BAND_ROWS: u32 = BAND;

    /// Writes the pixels of `tile` into `rows` (the band of rows it lies in, starting at row
    /// `tile.y0`, width × [`TileTracer::PIXEL_BYTES`] apart) and adds what it traced to
    /// `counts`.
    fn trace(&self, tile: &Tile, scratch: &mut Self::Scratch, rows: &mut [u8], counts: &mut Counts);
}

/// The sample positions and pixel encoding every tracer shares.
pub(crate) struct Samples {
    /// n, for n×n samples a pixel.
    pub(crate) n: u32,
    inv_n: f32,
    /// 1/n².
    weight: f32,
    srgb: &'static SrgbTables,
    /// Bytes in one row of the image.
    pub(crate) row_bytes: usize,
}

impl Samples {
    pub(crate) fn new(settings: &RenderSettings) -> Self {
        Self {
            n: settings.spp,
            inv_n: 1.0 / settings.spp as f32,
            weight: 1.0 / (settings.spp * settings.spp) as f32,
            srgb: SrgbTables::get(),
            row_bytes: settings.width as usize * 4,
        }
    }

    /// Where sample `s` (0..n) lies across its pixel: (s + ½)/n.
    #[inline(always)]
    pub(crate) fn offset(&self, s: u32) -> f32 {
        (s as f32 + 0.5) * self.inv_n
    }

    /// Image position of sample (sx, sy) of pixel (i, j).
    #[inline(always)]
    pub(crate) fn position(&self, i: u32, j: u32, sx: u32, sy: u32) -> (f32, f32) {
        (i as f32 + self.offset(sx), j as f32 + self.offset(sy))
    }

    /// Writes RGBA8 pixel `px` from its samples' summed linear colour.
    #[inline(always)]
    pub(crate) fn put_pixel(&self, px: &mut [u8], sum: Rgb) {
        self.put_colour(px, sum.map(|c| c * self.weight));
    }

    /// Writes RGBA8 pixel `px` in linear colour `c` (a mark, or a pixel's average).
    #[inline(always)]
    fn put_colour(&self, px: &mut [u8], c: Rgb) {
        for k in 0..3 {
            px[k] = self.srgb.encode(c[k]);
        }
        px[3] = 255;
    }

    /// Traces `tile` pixel by pixel, sample by sample: `sample(x, y, counts)` is what the
    /// sample at image position (x, y) shows (a linear colour, or a mark: the pixel then shows
    /// its first sample's mark), `None` where it shows the background.
    #[inline(always)]
    pub(crate) fn each_pixel(
        &self,
        tile: &Tile,
        rows: &mut [u8],
        counts: &mut Counts,
        mut sample: impl FnMut(f32, f32, &mut Counts) -> Option<Sample>,
    ) {
        for j in tile.y0..tile.y0 + tile.h {
            let row = &mut rows[(j - tile.y0) as usize * self.row_bytes..][..self.row_bytes];
            for i in tile.x0..tile.x0 + tile.w {
                let (mut sum, mut mark) = ([0.0f32; 3], None);
                for sy in 0..self.n {
                    for sx in 0..self.n {
                        let (x, y) = self.position(i, j, sx, sy);
                        match sample(x, y, counts) {
                            Some(Sample::Colour(c)) => add(&mut sum, c),
                            Some(Sample::Mark(c)) => _ = mark.get_or_insert(c),
                            None => continue,
                        }
                        counts.0 += 1;
                    }
                }
                let px = &mut row[i as usize * 4..][..4];
                match mark {
                    Some(c) => self.put_colour(px, c),
                    None => self.put_pixel(px, sum),
                }
            }
        }
    }
}

/// Adds colour `c` to `sum`.
#[inline(always)]
pub(crate) fn add(sum: &mut Rgb, c: Rgb) {
    for k in 0..3 {
        sum[k] += c[k];
    }
}

/// Checks `settings` and that `rgba` is their RGBA8 buffer, and starts the render's clock.
pub(crate) fn start(settings: &RenderSettings, rgba: &[u8]) -> Result<Instant, SettingsError> {
    settings.validate()?;
    if rgba.len() != settings.buffer_len() {
        return Err(SettingsError::Buffer(
            rgba.len(),
            settings.width,
            settings.height,
            settings.buffer_len(),
        ));
    }
    Ok(Instant::now())
}

/// Renders one frame into `rgba` (RGBA8, rows top to bottom; checked by [`start`], which
/// gave `started`) with `tracer` over every tile, giving up with `None` (the buffer partly
/// drawn) when `cancelled()` turns true: asked before each tile ([`super::tiles`] of them)
/// and once at the end.
pub(crate) fn drive<T: TileTracer>(
    settings: &RenderSettings,
    rgba: &mut [u8],
    cancelled: &(dyn Fn() -> bool + Sync),
    started: Instant,
    tracer: &T,
) -> Option<RenderStats> {
    let (w, h, n) = (settings.width, settings.height, settings.spp);
    let (hits, shadow_rays) = drive_rows(w, 0, rgba, cancelled, tracer)?;
    Some(RenderStats {
        primary_rays: w as u64 * h as u64 * (n * n) as u64,
        shadow_rays,
        hits,
        elapsed: started.elapsed(),
    })
}

/// Traces the image rows from `first_row` on that `rows` holds (whole rows of `width`
/// pixels, [`TileTracer::PIXEL_BYTES`] each) with `tracer`, bands of
/// [`TileTracer::BAND_ROWS`] rows in parallel, and returns what it counted; `None` (the rows
/// partly written) when `cancelled()` turns true: asked before each tile and once at the end
/// (a tile, not a band: a band of 16x16 samples with cracks counted took seconds, which a
/// window's change waited for).
pub(crate) fn drive_rows<T: TileTracer>(
    width: u32,
    first_row: u32,
    rows: &mut [u8],
    cancelled: &(dyn Fn() -> bool + Sync),
    tracer: &T,
) -> Option<Counts> {
    let row_bytes = width as usize * T::PIXEL_BYTES;
    let counts = rows
        .par_chunks_mut(row_bytes * T::BAND_ROWS as usize)
        .enumerate()
        .map(|(band, rows)| {
            let mut counts = Counts::default();
            let mut scratch = T::Scratch::default();
            for x0 in (0..width).step_by(TILE as usize) {
                if cancelled() {
                    return counts;
                }
                let tile = Tile {
                    x0,
                    y0: first_row + band as u32 * T::BAND_ROWS,
                    w: TILE.min(width - x0),
                    h: (rows.len() / row_bytes) as u32,
                };
                tracer.trace(&tile, &mut scratch, rows, &mut counts);
            }
            counts
        })
        .reduce(Counts::default, |a, b| (a.0 + b.0, a.1 + b.1));
    (!cancelled()).then_some(counts)
}
