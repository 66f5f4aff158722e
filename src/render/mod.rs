//! The parallel render driver: rows of the image in parallel (rayon), n×n stratified samples
//! per pixel, linear colour averaged and sRGB-encoded once into RGBA8.

pub mod settings;
pub mod shade;

use crate::camera::Camera;
use crate::scene::Scene;
use rayon::prelude::*;
use std::path::Path;
use std::time::{Duration, Instant};

pub use settings::{LabStep, RenderSettings, SettingsError, MAX_PIXELS, MAX_SIDE, MAX_SPP};
pub use shade::Rgb;

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
    ray: &crate::geometry::Ray,
    settings: &RenderSettings,
    shadow_rays: &mut u64,
) -> Option<Rgb> {
    let hit = scene
        .accel()
        .closest_hit(ray, settings.method, 0.0, f32::INFINITY)?;
    let m = settings.method;
    Some(match settings.step {
        LabStep::Flat => shade::flat(scene, &hit),
        LabStep::Direct => shade::direct(scene, ray, &hit),
        LabStep::Shadows => shade::shadows(scene, ray, &hit, m, shadow_rays),
        LabStep::Indirect => shade::indirect(scene, ray, &hit, m, shadow_rays),
    })
}

/// Renders `scene` through `camera` into `rgba` (RGBA8, rows top to bottom, alpha 255).
pub fn render_into(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    rgba: &mut [u8],
) -> Result<RenderStats, SettingsError> {
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
    scene.accel();
    let start = Instant::now();
    let gen = camera.ray_generator(w, h);
    let n = settings.spp;
    let inv_n = 1.0 / n as f32;
    let weight = 1.0 / (n * n) as f32;
    let (hits, shadow_rays) = rgba
        .par_chunks_mut(w as usize * 4)
        .enumerate()
        .map(|(j, row)| {
            let mut hits = 0u64;
            let mut shadow_rays = 0u64;
            for (i, px) in row.chunks_exact_mut(4).enumerate() {
                let mut sum = [0.0f32; 3];
                for sy in 0..n {
                    for sx in 0..n {
                        let x = i as f32 + (sx as f32 + 0.5) * inv_n;
                        let y = j as f32 + (sy as f32 + 0.5) * inv_n;
                        let ray = gen.ray_through(x, y);
                        if let Some(c) = trace_pixel_ray(scene, &ray, settings, &mut shadow_rays) {
                            hits += 1;
                            for k in 0..3 {
                                sum[k] += c[k];
                            }
                        }
                    }
                }
                px[0] = linear_to_srgb8(sum[0] * weight);
                px[1] = linear_to_srgb8(sum[1] * weight);
                px[2] = linear_to_srgb8(sum[2] * weight);
                px[3] = 255;
            }
            (hits, shadow_rays)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    Ok(RenderStats {
        primary_rays: w as u64 * h as u64 * (n * n) as u64,
        shadow_rays,
        hits,
        elapsed: start.elapsed(),
    })
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
    let x = if x > 0.0 { x.min(1.0) } else { 0.0 };
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
