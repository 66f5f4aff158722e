//! Arbitrary output values: what the renderer decided per pixel, for students and for
//! checking from outside. For the centre ray of each pixel: the primitive hit, its t and the
//! unit geometric normal turned to face the camera, found by the same per-ray query as
//! every image (the scene's accelerator with the chosen method). Written as NumPy `.npy`
//! arrays (format 1.0, little-endian, C order), readable by `numpy.load`.

use super::settings::{RenderSettings, SettingsError};
use super::Stage;
use crate::camera::Camera;
use crate::geometry::Ray;
use crate::input::{InputError, OutputFile};
use crate::scene::Scene;
use rayon::prelude::*;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The primitive index of a pixel whose centre ray hits nothing.
pub const NO_PRIMITIVE: u32 = u32::MAX;

/// Per-pixel values, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Aovs {
    pub width: u32,
    pub height: u32,
    /// The primitive hit ([`NO_PRIMITIVE`] for none).
    pub prim: Vec<u32>,
    /// Its ray parameter along the unit-length camera ray (NaN for none).
    pub t: Vec<f32>,
    /// The unit geometric normal facing the camera (zero for none).
    pub normal: Vec<[f32; 3]>,
}

/// The AOVs of the stage's scene through `camera` at the settings' size and method.
pub fn render_aovs(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
) -> Result<Aovs, SettingsError> {
    settings.validate()?;
    let (w, h) = (settings.width, settings.height);
    let gen = camera.ray_generator(w, h);
    let (scene, accel) = (stage.scene(), stage.accel());
    let pixels: Vec<(u32, f32, [f32; 3])> = (0..w * h)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % w, k / w);
            let ray = gen.ray_through(i as f32 + 0.5, j as f32 + 0.5);
            match accel.closest_hit(&ray, settings.method, 0.0, f32::INFINITY) {
                Some(hit) => (hit.prim, hit.t, facing_normal(scene, &ray, hit.prim, hit.t)),
                None => (NO_PRIMITIVE, f32::NAN, [0.0; 3]),
            }
        })
        .collect();
    Ok(Aovs {
        width: w,
        height: h,
        prim: pixels.iter().map(|p| p.0).collect(),
        t: pixels.iter().map(|p| p.1).collect(),
        normal: pixels.iter().map(|p| p.2).collect(),
    })
}

/// The pixels whose values [`write_aovs`] holds at a time (whole rows, at least one).
const BAND_PIXELS: u32 = 1 << 20;

/// The AOVs of the stage's scene through `camera` at the settings' size and method, written
/// into `outs` (from [`Aovs::create_beside`]: `.prim`, `.t`, `.normal`) band by band without
/// committing them: about 40 bytes per pixel of a band of [`BAND_PIXELS`] are held, whatever
/// the image's size ([`render_aovs`] holds the whole image's).
pub fn write_aovs(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
    outs: &mut [OutputFile; 3],
) -> Result<(), InputError> {
    let [prim, t, normal] = outs;
    let io = |out: &OutputFile| {
        let path = out.path().to_path_buf();
        move |source| InputError::Io { path, source }
    };
    settings
        .validate()
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e))
        .map_err(io(prim))?;
    let (w, h) = (settings.width, settings.height);
    let shape = [h as usize, w as usize];
    prim.write_all(&npy_header("<u4", &shape))
        .map_err(io(prim))?;
    t.write_all(&npy_header("<f4", &shape)).map_err(io(t))?;
    (normal.write_all(&npy_header("<f4", &[shape[0], shape[1], 3]))).map_err(io(normal))?;
    let gen = camera.ray_generator(w, h);
    let (scene, accel) = (stage.scene(), stage.accel());
    let rows = (BAND_PIXELS / w).max(1);
    let mut band = Vec::new();
    let mut bytes = Vec::new();
    for y0 in (0..h).step_by(rows as usize) {
        let y1 = (y0 + rows).min(h);
        (0..(y1 - y0) * w)
            .into_par_iter()
            .map(|k| {
                let (i, j) = (k % w, y0 + k / w);
                let ray = gen.ray_through(i as f32 + 0.5, j as f32 + 0.5);
                match accel.closest_hit(&ray, settings.method, 0.0, f32::INFINITY) {
                    Some(hit) => (hit.prim, hit.t, facing_normal(scene, &ray, hit.prim, hit.t)),
                    None => (NO_PRIMITIVE, f32::NAN, [0.0; 3]),
                }
            })
            .collect_into_vec(&mut band);
        bytes.clear();
        bytes.extend(band.iter().flat_map(|p| p.0.to_le_bytes()));
        prim.write_all(&bytes).map_err(io(prim))?;
        bytes.clear();
        bytes.extend(band.iter().flat_map(|p| p.1.to_le_bytes()));
        t.write_all(&bytes).map_err(io(t))?;
        bytes.clear();
        bytes.extend(band.iter().flat_map(|p| p.2).flat_map(|c| c.to_le_bytes()));
        normal.write_all(&bytes).map_err(io(normal))?;
    }
    Ok(())
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

impl Aovs {
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

    /// Opens the three outputs beside `png` ([`Aovs::paths_beside`]), writing nothing yet.
    pub fn create_beside(png: &Path) -> Result<[OutputFile; 3], InputError> {
        let [prim, t, normal] = Self::paths_beside(png);
        Ok([
            OutputFile::create(&prim)?,
            OutputFile::create(&t)?,
            OutputFile::create(&normal)?,
        ])
    }

    /// Writes `STEM.prim.npy` (uint32, H×W), `STEM.t.npy` (float32, H×W) and
    /// `STEM.normal.npy` (float32, H×W×3) into `outs` (from [`Aovs::create_beside`]), one
    /// array at a time, without committing them.
    pub fn write_into(&self, outs: &mut [OutputFile; 3]) -> std::io::Result<()> {
        let (h, w) = (self.height as usize, self.width as usize);
        let [prim, t, normal] = outs;
        write_npy_into(
            prim,
            "<u4",
            &[h, w],
            self.prim.iter().map(|x| x.to_le_bytes()),
        )?;
        write_npy_into(t, "<f4", &[h, w], self.t.iter().map(|x| x.to_le_bytes()))?;
        let normals = self.normal.iter().flatten().map(|x| x.to_le_bytes());
        write_npy_into(normal, "<f4", &[h, w, 3], normals)
    }

    /// Writes the three arrays beside `png` ([`Aovs::paths_beside`]): all three, or none
    /// changes.
    pub fn write_beside(&self, png: &Path) -> std::io::Result<Vec<PathBuf>> {
        let mut outs = Self::create_beside(png).map_err(std::io::Error::other)?;
        self.write_into(&mut outs)?;
        let mut written = Vec::new();
        for out in outs {
            written.push(out.path().to_path_buf());
            out.commit().map_err(std::io::Error::other)?;
        }
        Ok(written)
    }
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

/// Writes a `.npy` array into `out` (buffered): the header, then `items` (already in
/// `descr`'s byte order, C order) streamed, so no copy of the array is made.
fn write_npy_into<const N: usize>(
    out: &mut impl Write,
    descr: &str,
    shape: &[usize],
    items: impl Iterator<Item = [u8; N]>,
) -> std::io::Result<()> {
    out.write_all(&npy_header(descr, shape))?;
    for item in items {
        out.write_all(&item)?;
    }
    Ok(())
}

/// Writes a NumPy `.npy` file (format 1.0) of `data` (already in `descr`'s byte order, C
/// order): the whole file, or nothing changes at `path`.
pub fn write_npy(path: &Path, descr: &str, shape: &[usize], data: &[u8]) -> std::io::Result<()> {
    let mut out = OutputFile::create(path).map_err(std::io::Error::other)?;
    out.write_all(&npy_header(descr, shape))?;
    out.write_all(data)?;
    out.commit().map_err(std::io::Error::other)
}
