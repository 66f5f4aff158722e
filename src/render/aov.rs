//! Arbitrary output values: what the renderer decided per pixel, for students and for
//! checking from outside. For the centre ray of each pixel: the primitive hit, its t and the
//! unit geometric normal turned to face the camera, found by the same per-ray query as
//! every image (the scene's accelerator with the chosen method). Written as NumPy `.npy`
//! arrays (format 1.0, little-endian, C order), readable by `numpy.load`.

use super::settings::{RenderSettings, SettingsError};
use crate::camera::Camera;
use crate::geometry::{Ray, Shape};
use crate::scene::Scene;
use rayon::prelude::*;
use std::io::Write;
use std::path::Path;

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

/// The AOVs of `scene` through `camera` at the settings' size and method.
pub fn render_aovs(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
) -> Result<Aovs, SettingsError> {
    settings.validate()?;
    let (w, h) = (settings.width, settings.height);
    let gen = camera.ray_generator(w, h);
    let accel = scene.accel();
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

/// The unit geometric normal of primitive `prim` where `ray` meets it at `t`, turned against
/// the ray (surfaces are two-sided).
fn facing_normal(scene: &Scene, ray: &Ray, prim: u32, t: f32) -> [f32; 3] {
    let n = match &scene.shape(prim) {
        Shape::Triangle(v) => {
            let e1 = [0, 1, 2].map(|k| v[1][k] as f64 - v[0][k] as f64);
            let e2 = [0, 1, 2].map(|k| v[2][k] as f64 - v[0][k] as f64);
            [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ]
        }
        Shape::Sphere { centre, .. } => {
            [0, 1, 2].map(|k| ray.o[k] as f64 + t as f64 * ray.d[k] as f64 - centre[k] as f64)
        }
    };
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let facing = n[0] * ray.d[0] as f64 + n[1] * ray.d[1] as f64 + n[2] * ray.d[2] as f64;
    let s = if facing > 0.0 { -1.0 / len } else { 1.0 / len };
    n.map(|c| (c * s) as f32)
}

impl Aovs {
    /// Writes `STEM.prim.npy` (uint32, H×W), `STEM.t.npy` (float32, H×W) and
    /// `STEM.normal.npy` (float32, H×W×3) beside `png` (its path without the extension).
    pub fn write_beside(&self, png: &Path) -> std::io::Result<Vec<std::path::PathBuf>> {
        let stem = png.with_extension("");
        let path = |what: &str| {
            let mut p = stem.clone().into_os_string();
            p.push(format!(".{what}.npy"));
            std::path::PathBuf::from(p)
        };
        let (h, w) = (self.height as usize, self.width as usize);
        let bytes = |xs: &mut dyn Iterator<Item = [u8; 4]>| xs.flatten().collect::<Vec<u8>>();
        let files = [
            (
                path("prim"),
                "<u4",
                vec![h, w],
                bytes(&mut self.prim.iter().map(|x| x.to_le_bytes())),
            ),
            (
                path("t"),
                "<f4",
                vec![h, w],
                bytes(&mut self.t.iter().map(|x| x.to_le_bytes())),
            ),
            (
                path("normal"),
                "<f4",
                vec![h, w, 3],
                bytes(&mut self.normal.iter().flatten().map(|x| x.to_le_bytes())),
            ),
        ];
        let mut written = Vec::new();
        for (p, descr, shape, data) in files {
            write_npy(&p, descr, &shape, &data)?;
            written.push(p);
        }
        Ok(written)
    }
}

/// Writes a NumPy `.npy` file (format 1.0): the magic, the header dict padded with spaces
/// to a multiple of 64 bytes, then `data` (already in `descr`'s byte order, C order).
pub fn write_npy(path: &Path, descr: &str, shape: &[usize], data: &[u8]) -> std::io::Result<()> {
    crate::input::check_output(path).map_err(std::io::Error::other)?;
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
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    out.write_all(b"\x93NUMPY\x01\x00")?;
    out.write_all(&(header.len() as u16).to_le_bytes())?;
    out.write_all(header.as_bytes())?;
    out.write_all(data)?;
    out.flush()
}
