//! The flat step's one-sample pixels: a pixel is its primitive's colour, encoded once.

use super::image::SrgbTables;
use super::shade::Rgb;
use crate::accel::NO_HIT;
use crate::scene::Scene;

/// The flat step's RGBA8 pixels: with one sample per pixel, a pixel is its primitive's
/// colour encoded once (what `Samples::put_pixel` makes of it), or black. Encoded per primitive up
/// front where each is likely to be reused (at most one primitive per 8 camera rays: the
/// Cornell box, the bunny), else per pixel (the 1M-triangle mesh: a table would cost more
/// per frame than the pixels it serves).
pub(super) struct FlatPixels<'a> {
    scene: &'a Scene,
    /// Per primitive, RGBA8 as one word in memory order; empty when encoding per pixel.
    table: Vec<u32>,
    srgb: &'static SrgbTables,
}

impl<'a> FlatPixels<'a> {
    pub(super) fn new(scene: &'a Scene, camera_rays: usize) -> Self {
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
    pub(super) fn put(&self, out: &mut [u8], prims: &[u32], last: &mut LastWord) {
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
pub(super) struct LastWord {
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
    pub(super) fn of(&mut self, srgb: &SrgbTables, scene: &Scene, p: u32) -> u32 {
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
pub(super) const BLACK_RGBA: u32 = u32::from_ne_bytes([0, 0, 0, 255]);

/// Linear colour `c` encoded as an RGBA8 word in memory order, alpha 255.
fn rgba_word(srgb: &SrgbTables, c: Rgb) -> u32 {
    u32::from_ne_bytes([srgb.encode(c[0]), srgb.encode(c[1]), srgb.encode(c[2]), 255])
}
