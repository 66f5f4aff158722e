//! Rendering: one driver ([`driver`]: bands of [`BAND`] rows in parallel, tiles of [`TILE`]
//! pixels, n×n stratified samples a pixel, linear colour averaged and sRGB-encoded once into
//! RGBA8 by [`image`], cancelling, statistics) with a tracer behind it: raylab's own
//! ([`frame`]: the accelerator's queries, packets or per ray, shaded by [`shade`]), linked
//! lab code's ([`crate::check::code`]) or the AOV arrays' centre rays ([`aov`]).

pub mod aov;
pub(crate) mod driver;
mod flat_pixels;
mod frame;
pub mod image;
pub mod inspect;
pub mod settings;
pub mod shade;
pub mod stage;

use crate::accel::{Accel, FrameSetup};
use crate::camera::Camera;
use crate::geometry::{Method, Ray};
use frame::Frame;
use std::time::Duration;

pub use image::{linear_to_srgb8, linear_to_srgb8_reference, write_png};
pub use settings::{
    Control, LabStep, RenderSettings, SettingsError, CONTROLS, MAX_PIXELS, MAX_SIDE, MAX_SPP,
};
pub use shade::Rgb;
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

/// How many tiles (of [`TILE`] by [`BAND`] pixels) a frame of `width` by `height` is traced
/// in: how many times a cancellable render asks whether to stop before its end.
pub fn tiles(width: u32, height: u32) -> u64 {
    width.div_ceil(TILE) as u64 * height.div_ceil(BAND) as u64
}

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

/// [`render_into`] that gives up when `cancelled()` turns true (asked before each of the
/// frame's [`tiles`] and once at the end, so its asks also tell how far it has come),
/// returning `Ok(None)` and leaving the buffer partly drawn: an interactive viewer drops a
/// frame that a camera move has made stale instead of waiting for it.
pub fn render_into_cancellable(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
    rgba: &mut [u8],
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<Option<RenderStats>, SettingsError> {
    let started = driver::start(settings, rgba)?;
    let (w, h) = (settings.width, settings.height);
    let (scene, accel) = (stage.scene(), stage.accel());
    let gen = camera.ray_generator(w, h);
    let camera_rays = w as usize * h as usize * (settings.spp * settings.spp) as usize;
    let queries = accel.for_frame(&FrameSetup {
        eye: gen.origin(),
        light: scene.light.position,
        projection: settings.tile_culling.then(|| camera.projection(w, h)),
        method: settings.method,
        camera_rays,
        // (Shadow rays that start at the surface points, for a far light, share no origin:
        // they are asked one by one, and the packets' from the light are not.)
        shadows: settings.step.casts_shadows() && scene.shadows_from_light(),
        per_ray: settings.cracks,
    });
    let frame = Frame::new(stage, settings, &queries, gen, camera_rays);
    Ok(driver::drive(settings, rgba, cancelled, started, &frame))
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
