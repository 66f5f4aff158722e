//! Arbitrary output values: what the renderer decided per pixel, for students and for
//! checking from outside. For the centre ray of each pixel: the primitive hit, its t and the
//! unit geometric normal turned to face the camera, found by the same per-ray query as
//! every image (the scene's accelerator with the chosen method). Written as NumPy `.npy`
//! arrays (format 1.0, little-endian, C order), readable by `numpy.load`: `STEM.prim.npy`
//! (uint32, H×W), `STEM.t.npy` (float32, H×W) and `STEM.normal.npy` (float32, H×W×3).

use super::driver::{drive_rows, Counts, Tile, TileTracer};
use super::settings::RenderSettings;
use super::Stage;
use crate::camera::{Camera, RayGenerator};
use crate::geometry::{Method, Ray};
use crate::input::{InputError, OutputFile};
use crate::scene::Scene;
use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The primitive index of a pixel whose centre ray hits nothing.
pub const NO_PRIMITIVE: u32 = u32::MAX;

/// The pixels whose values [`write_aovs`] holds at a time (whole rows, at least one).
pub const BAND_PIXELS: u32 = 1 << 20;

/// The paths of `STEM.prim.npy`, `STEM.t.npy` and `STEM.normal.npy` beside `png` (its path
/// without the extension).
pub fn paths_beside(png: &Path) -> [PathBuf; 3] {
    let stem = png.with_extension("");
    ["prim", "t", "normal"].map(|what| {
        let mut p = stem.clone().into_os_string();
        p.push(format!(".{what}.npy"));
        PathBuf::from(p)
    })
}

/// Opens the three outputs beside `png` ([`paths_beside`]), writing nothing yet. Where `png`
/// is a device (/dev/null), the arrays go to it too: beside it they were files made in /dev.
pub fn create_beside(png: &Path) -> Result<[OutputFile; 3], InputError> {
    let device = std::fs::metadata(png).is_ok_and(|m| crate::input::is_device(&m));
    let [prim, t, normal] = match device {
        true => [png; 3].map(Path::to_path_buf),
        false => paths_beside(png),
    };
    Ok([
        OutputFile::create(&prim)?,
        OutputFile::create(&t)?,
        OutputFile::create(&normal)?,
    ])
}

/// The AOVs of the stage's scene through `camera` at the settings' size and method, written
/// into `outs` (from [`create_beside`]: `.prim`, `.t`, `.normal`) band by band without
/// committing them: about 32 bytes per pixel of a band of [`BAND_PIXELS`] are held, whatever
/// the image's size. The render driver traces each band, a row to a thread at a time;
/// `cancelled` is asked before each tile of a row and after each band: `Ok(false)` once it
/// says yes (the outputs are then incomplete: drop them), `Ok(true)` when every band is
/// written.
pub fn write_aovs(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
    outs: &mut [OutputFile; 3],
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<bool, InputError> {
    let paths = outs.each_ref().map(|o| o.path().to_path_buf());
    let [prim, t, normal] = outs;
    let writers: [&mut dyn Write; 3] = [prim, t, normal];
    write_bands(stage, camera, settings, writers, BAND_PIXELS, cancelled).map_err(|(k, source)| {
        InputError::Io {
            path: paths[k].clone(),
            source,
        }
    })
}

/// [`write_aovs`] into any three writers, `band_pixels` pixels (whole rows, at least one) at
/// a time; an error comes with the number of the writer it is of.
fn write_bands(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
    outs: [&mut dyn Write; 3],
    band_pixels: u32,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<bool, (usize, std::io::Error)> {
    let [prim, t, normal] = outs;
    settings
        .validate()
        .map_err(|e| (0, std::io::Error::new(std::io::ErrorKind::InvalidInput, e)))?;
    let (w, h) = (settings.width, settings.height);
    let shape = [h as usize, w as usize];
    prim.write_all(&npy_header("<u4", &shape))
        .map_err(|e| (0, e))?;
    t.write_all(&npy_header("<f4", &shape))
        .map_err(|e| (1, e))?;
    (normal.write_all(&npy_header("<f4", &[shape[0], shape[1], 3]))).map_err(|e| (2, e))?;
    let tracer = CentreRays {
        gen: camera.ray_generator(w, h),
        stage,
        method: settings.method,
        width: w,
    };
    let rows = (band_pixels / w).max(1);
    let mut band = Vec::new();
    let mut bytes = Vec::new();
    for y0 in (0..h).step_by(rows as usize) {
        let y1 = (y0 + rows).min(h);
        band.resize((y1 - y0) as usize * w as usize * PIXEL_BYTES, 0);
        if drive_rows(w, y0, &mut band, cancelled, &tracer).is_none() {
            return Ok(false);
        }
        let files = [
            (&mut *prim, PRIM_BYTES),
            (&mut *t, T_BYTES),
            (&mut *normal, NORMAL_BYTES),
        ];
        for (k, (out, bytes_at)) in files.into_iter().enumerate() {
            bytes.clear();
            for pixel in band.chunks_exact(PIXEL_BYTES) {
                bytes.extend_from_slice(&pixel[bytes_at.clone()]);
            }
            out.write_all(&bytes).map_err(|e| (k, e))?;
        }
    }
    Ok(true)
}

/// Where [`CentreRays`] writes a pixel's values in its bytes, little-endian: the primitive
/// (u32), t (f32) and the normal (3 × f32).
const PRIM_BYTES: Range<usize> = 0..4;
const T_BYTES: Range<usize> = 4..8;
const NORMAL_BYTES: Range<usize> = 8..20;
/// Bytes of one pixel's values.
const PIXEL_BYTES: usize = NORMAL_BYTES.end;

/// The render driver's tracer of the AOVs: each pixel's centre ray, by the per-ray query.
struct CentreRays<'a> {
    gen: RayGenerator,
    stage: &'a Stage,
    method: Method,
    width: u32,
}

impl TileTracer for CentreRays<'_> {
    type Scratch = ();
    const PIXEL_BYTES: usize = PIXEL_BYTES;
    /// A row at a time: a pass's band of [`BAND_PIXELS`] is only 64 rows of a 16384-pixel
    /// image, which bands of 16 rows would give to 4 threads only.
    const BAND_ROWS: u32 = 1;

    fn trace(&self, tile: &Tile, _: &mut (), rows: &mut [u8], counts: &mut Counts) {
        let (scene, accel) = (self.stage.scene(), self.stage.accel());
        let row_bytes = self.width as usize * PIXEL_BYTES;
        for j in tile.y0..tile.y0 + tile.h {
            let row = &mut rows[(j - tile.y0) as usize * row_bytes..][..row_bytes];
            for i in tile.x0..tile.x0 + tile.w {
                let ray = self.gen.ray_through(i as f32 + 0.5, j as f32 + 0.5);
                let (prim, t, normal) =
                    match accel.closest_hit(&ray, self.method, 0.0, f32::INFINITY) {
                        Some(hit) => {
                            counts.0 += 1;
                            (hit.prim, hit.t, facing_normal(scene, &ray, hit.prim, hit.t))
                        }
                        None => (NO_PRIMITIVE, f32::NAN, [0.0; 3]),
                    };
                let px = &mut row[i as usize * PIXEL_BYTES..][..PIXEL_BYTES];
                px[PRIM_BYTES].copy_from_slice(&prim.to_le_bytes());
                px[T_BYTES].copy_from_slice(&t.to_le_bytes());
                for (c, out) in normal.iter().zip(px[NORMAL_BYTES].chunks_exact_mut(4)) {
                    out.copy_from_slice(&c.to_le_bytes());
                }
            }
        }
    }
}

/// The unit geometric normal of primitive `prim` where `ray` meets it at `t`, turned against
/// the ray (surfaces are two-sided).
fn facing_normal(scene: &Scene, ray: &Ray, prim: u32, t: f32) -> [f32; 3] {
    let n = scene.shape(prim).normal_at(ray, t);
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let facing = n[0] * ray.d[0] as f64 + n[1] * ray.d[1] as f64 + n[2] * ray.d[2] as f64;
    let s = if facing > 0.0 { -1.0 / len } else { 1.0 / len };
    n.map(|c| (c * s) as f32)
}

/// The header of a NumPy `.npy` file (format 1.0): the magic, the header dict padded with
/// spaces to a multiple of 64 bytes.
fn npy_header(descr: &str, shape: &[usize]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    let shape = match dims.len() {
        1 => format!("({},)", dims[0]),
        _ => format!("({})", dims.join(", ")),
    };
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    // magic (6) + version (2) + length (2) + header + '\n', a multiple of 64.
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;
    use crate::accel::AccelChoice;

    /// The three files' bytes written `band_pixels` at a time.
    fn banded(
        stage: &Stage,
        camera: &Camera,
        settings: &RenderSettings,
        band_pixels: u32,
    ) -> [Vec<u8>; 3] {
        let [mut a, mut b, mut c] = [Vec::new(), Vec::new(), Vec::new()];
        let done = write_bands(
            stage,
            camera,
            settings,
            [&mut a, &mut b, &mut c],
            band_pixels,
            &|| false,
        )
        .unwrap();
        assert!(done);
        [a, b, c]
    }

    /// The three files' bytes from the whole image at once, pixel by pixel.
    fn whole(stage: &Stage, camera: &Camera, settings: &RenderSettings) -> [Vec<u8>; 3] {
        let (w, h) = (settings.width, settings.height);
        let gen = camera.ray_generator(w, h);
        let shape = [h as usize, w as usize];
        let mut files = [
            npy_header("<u4", &shape),
            npy_header("<f4", &shape),
            npy_header("<f4", &[shape[0], shape[1], 3]),
        ];
        for j in 0..h {
            for i in 0..w {
                let ray = gen.ray_through(i as f32 + 0.5, j as f32 + 0.5);
                let hit = stage
                    .accel()
                    .closest_hit(&ray, settings.method, 0.0, f32::INFINITY);
                let (prim, t, n) = match hit {
                    Some(hit) => (
                        hit.prim,
                        hit.t,
                        facing_normal(stage.scene(), &ray, hit.prim, hit.t),
                    ),
                    None => (NO_PRIMITIVE, f32::NAN, [0.0; 3]),
                };
                files[0].extend(prim.to_le_bytes());
                files[1].extend(t.to_le_bytes());
                files[2].extend(n.iter().flat_map(|c| c.to_le_bytes()));
            }
        }
        files
    }

    fn bands_of_any_height_write_the_whole_images_bytes() {
        let stage = Stage::new(Scene::cornell(), AccelChoice::Bvh);
        let settings = RenderSettings {
            width: 24,
            height: 17,
            ..RenderSettings::default()
        };
        let camera = Camera::cornell(settings.width);
        let reference = whole(&stage, &camera, &settings);
        assert!(reference[0].len() > 128 + 4 * 24 * 17 - 1);
        // 17 rows in bands of 5 (the last of 2), of 1, and all in one.
        for band_pixels in [5 * 24, 5 * 24 + 7, 1, 24 * 17, u32::MAX] {
            let files = banded(&stage, &camera, &settings, band_pixels);
            assert!(files == reference, "bands of {band_pixels} pixels");
        }
    }

    fn a_cancelled_pass_stops_at_the_next_row() {
        let stage = Stage::new(Scene::cornell(), AccelChoice::Bvh);
        let settings = RenderSettings {
            width: 8,
            height: 10,
            ..RenderSettings::default()
        };
        let camera = Camera::cornell(settings.width);
        let asked = std::sync::atomic::AtomicU32::new(0);
        // Yes from the fifth question on: the driver asks before each row of the first band
        // (of 3 rows, each a unit of work of its own) and after it, which is written; then
        // before each row of the second, which it skips, and once more after it.
        let cancel = || asked.fetch_add(1, std::sync::atomic::Ordering::Relaxed) >= 4;
        let [mut a, mut b, mut c] = [Vec::new(), Vec::new(), Vec::new()];
        let outs: [&mut dyn Write; 3] = [&mut a, &mut b, &mut c];
        let done = write_bands(&stage, &camera, &settings, outs, 3 * 8, &cancel).unwrap();
        assert!(!done);
        assert_eq!(asked.into_inner(), 8);
        let header = npy_header("<u4", &[10, 8]).len();
        assert_eq!(a.len(), header + 4 * 3 * 8);
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "bands_of_any_height_write_the_whole_images_bytes",
            bands_of_any_height_write_the_whole_images_bytes,
        ),
        (
            "a_cancelled_pass_stops_at_the_next_row",
            a_cancelled_pass_stops_at_the_next_row,
        ),
    ];
}
