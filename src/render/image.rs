//! Image output: linear colour to sRGB-encoded RGBA8 (once per pixel), and PNG files.

use std::io::Write as _;
use std::path::Path;

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
pub(crate) struct SrgbTables {
    levels: [f32; 256],
    start: [u8; SRGB_BINS],
}

/// The first bin: x = 2^-13 (exponent 114, mantissa 0) shifted right by 15.
const SRGB_FIRST_BIN: usize = 114 << 8;
/// Bins from 2^-13 up to 1: 13 binades of 256.
const SRGB_BINS: usize = 13 << 8;

impl SrgbTables {
    /// The tables, built on first use.
    pub(crate) fn get() -> &'static SrgbTables {
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
    pub(crate) fn encode(&self, x: f32) -> u8 {
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

/// Writes an RGBA8 image as PNG to `path`: the whole file, or nothing changes there (see
/// [`crate::input::OutputFile`]).
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> std::io::Result<()> {
    let mut out = crate::input::OutputFile::create(path).map_err(std::io::Error::other)?;
    encode_png(&mut out, width, height, rgba)?;
    out.commit().map_err(std::io::Error::other)
}

/// Encodes an RGBA8 image as PNG (sRGB) into `out`, holding no copy of it.
pub fn encode_png(
    out: impl std::io::Write,
    width: u32,
    height: u32,
    rgba: &[u8],
) -> std::io::Result<()> {
    let mut enc = png::Encoder::new(out, width, height);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = enc.write_header().map_err(std::io::Error::other)?;
    // Streamed, a chunk at a time: `write_image_data` holds the whole compressed image.
    let mut stream = writer
        .stream_writer_with_size(PNG_CHUNK_BYTES)
        .map_err(std::io::Error::other)?;
    stream.write_all(rgba)?;
    stream.finish().map_err(std::io::Error::other)?;
    writer.finish().map_err(std::io::Error::other)
}

/// The size of a PNG's compressed data chunks (the most held before one is written).
const PNG_CHUNK_BYTES: usize = 1 << 20;
