//! The ray inspector: one pixel's camera ray as the lecture writes it, and what the renderer
//! decided for it. The window's panel shows it for a clicked pixel; `raylab inspect` prints
//! it, so it can be checked from outside.
//!
//! The ray is the centre ray of the pixel (with supersampling the pixel is the mean of its
//! samples; the inspector follows the one through the centre), or, by [`inspect_at`], the ray
//! through any position of the image (the window's inspector follows a crack's marked sample
//! so). Everything below is computed by
//! the renderer's own functions (the same accelerator query, the same shading), so the colour
//! it shows is the colour the renderer gives that ray.

use super::settings::{LabStep, RenderSettings, SettingsError};
use super::shade::{shading_point, step_colour, Lit, Rgb};
use super::Stage;
use crate::camera::Camera;
use crate::geometry::adaptive;
pub use crate::geometry::terms::ShapeTerms;
use crate::geometry::{Method, Ray, Shape};
use std::fmt;

/// One pixel's camera ray and what the renderer made of it.
#[derive(Clone, Debug, PartialEq)]
pub struct Inspection {
    /// The pixel (column, row from the top left).
    pub pixel: [u32; 2],
    /// The image position the ray passes through: the pixel's centre (i + 0.5, j + 0.5), or
    /// the position given to [`inspect_at`] (a sample of the pixel).
    pub at: [f64; 2],
    /// The lecture's (u, v, f): u = x − W/2, v = y − H/2 (the traced position from the image
    /// centre, y down: for the centre ray u = i + 0.5 − W/2), f = the focal length in pixels.
    pub uvf: [f64; 3],
    /// d = normalize(u, v, f), in camera space.
    pub d_camera: [f64; 3],
    /// The ray as traced, in the world: origin at the eye, the unit direction
    /// world_from_camera · d (f32, as the renderer has it).
    pub ray: Ray<f32>,
    /// The intersection method.
    pub method: Method,
    /// The lab step whose colour is given.
    pub step: LabStep,
    /// The nearest hit, if any.
    pub hit: Option<HitInspection>,
}

/// The nearest hit of an inspected ray.
#[derive(Clone, Debug, PartialEq)]
pub struct HitInspection {
    /// The primitive's index in the scene.
    pub prim: u32,
    /// The ray parameter (distance along the unit direction) the method found: what the
    /// renderer and the `t` AOV use (for the exact method, its f32 estimate, within 16 ulps on
    /// grazing hits).
    pub t: f32,
    /// The exact t at which the ray meets this primitive's surface, correctly rounded to f32:
    /// the number `raylab trace` prints.
    pub t_exact: f32,
    /// The primitive's own terms: the triangle's linear system or the sphere's quadratic.
    pub terms: ShapeTerms,
    /// Which level of the adaptive method decided that the ray meets this primitive (for the
    /// other methods: the method itself).
    pub decided_by: &'static str,
    /// The surface point used for shading ([`shading_point`]), its per-axis bounds on the
    /// distance to the surface and to the exact hit point, and the unit normal turned to face
    /// the camera.
    pub point: [f32; 3],
    pub point_error: [f32; 3],
    pub point_hit_error: [f32; 3],
    pub normal: [f32; 3],
    /// ρ, the primitive's diffuse colour.
    pub rho: Rgb,
    /// D as the step's colour takes it: 0 where the step casts shadows and one blocks the
    /// shadow ray (README, lab step 4).
    pub direct: Rgb,
    /// D before the shadow test, the direct light P·max(n·r̂, 0)/(4πr²) (step 3's).
    pub direct_unshadowed: Rgb,
    /// N, the lab's constant indirect term.
    pub indirect: Rgb,
    /// The shadow ray (from the light to the offset surface point, or the other way for a far
    /// light, t in (0, 1)); `None` where D = 0 (nothing to shadow).
    pub shadow: Option<Ray<f32>>,
    /// The primitive nearest the shadow ray's origin that blocks it, if any.
    pub blocked_by: Option<u32>,
    /// The step's colour, linear RGB: what the renderer gives this ray.
    pub colour: Rgb,
}

/// Inspects pixel (`i`, `j`) of the stage's scene through `camera` with the settings' size,
/// method and step.
pub fn inspect(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
    i: u32,
    j: u32,
) -> Result<Inspection, SettingsError> {
    let (w, h) = (settings.width, settings.height);
    if i >= w || j >= h {
        return Err(SettingsError::Pixel(i, j, w, h));
    }
    inspect_at(stage, camera, settings, i as f64 + 0.5, j as f64 + 0.5)
}

/// Inspects the ray through image position (`x`, `y`) (pixel (i, j) spans [i, i + 1) ×
/// [j, j + 1)): a sample of a supersampled pixel, as the renderer traces it (the position
/// rounded to f32, as the renderer's sample positions are).
pub fn inspect_at(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
    x: f64,
    y: f64,
) -> Result<Inspection, SettingsError> {
    settings.validate()?;
    let (w, h) = (settings.width, settings.height);
    // (The position as traced, and the pixel holding it; off the image, the first pixel
    // past its edge.)
    let (xf, yf) = (x as f32, y as f32);
    let pixel = |c: f32, n: u32| match (0.0..n as f32).contains(&c) {
        true => (c.floor() as u32).min(n - 1),
        false => n,
    };
    let (i, j) = (pixel(xf, w), pixel(yf, h));
    if i >= w || j >= h {
        return Err(SettingsError::Pixel(i, j, w, h));
    }
    let uvf = [
        xf as f64 - w as f64 / 2.0,
        yf as f64 - h as f64 / 2.0,
        camera.focal,
    ];
    let len = (uvf[0] * uvf[0] + uvf[1] * uvf[1] + uvf[2] * uvf[2]).sqrt();
    let ray = camera.ray_generator(w, h).ray_through(xf, yf);
    let method = settings.method;
    let (scene, accel) = (stage.scene(), stage.accel());
    let hit = accel
        .closest_hit(&ray, method, 0.0, f32::INFINITY)
        .map(|hit| {
            let shape = scene.shape(hit.prim);
            let sp = shading_point(scene, &ray, hit.prim);
            let facing = if dot64(sp.n, ray.d) > 0.0 { -1.0 } else { 1.0 };
            let lit = Lit::new(scene, &ray, &hit);
            let blocked_by = lit
                .shadow
                .and_then(|s| nearest_blocker(stage, &s, lit.skip, method));
            // The renderer's own test decides the colour (the blocker above is for showing).
            let blocked = lit
                .shadow
                .is_some_and(|s| accel.any_hit(&s, method, 0.0, 1.0, lit.skip));
            let shows_shadows = settings.step.casts_shadows();
            let d = lit.d(scene);
            HitInspection {
                prim: hit.prim,
                t: hit.t,
                t_exact: adaptive::rounded_t(&shape, &ray, 0.0, f32::INFINITY).unwrap_or(f32::NAN),
                terms: shape.terms(&ray),
                decided_by: decided_by(&shape, &ray, method),
                point: sp.p,
                point_error: sp.p_error,
                point_hit_error: sp.hit_error,
                normal: sp.n.map(|c| facing * c + 0.0),
                rho: scene.color(hit.prim),
                direct: match blocked && shows_shadows {
                    true => [0.0; 3],
                    false => d,
                },
                direct_unshadowed: d,
                indirect: scene.ambient,
                shadow: lit.shadow,
                blocked_by,
                colour: step_colour(scene, hit.prim, d, blocked && shows_shadows, settings.step),
            }
        });
    Ok(Inspection {
        pixel: [i, j],
        at: [xf as f64, yf as f64],
        uvf,
        d_camera: uvf.map(|c| c / len),
        ray,
        method,
        step: settings.step,
        hit,
    })
}

fn dot64(a: [f32; 3], b: [f32; 3]) -> f64 {
    (0..3).map(|k| a[k] as f64 * b[k] as f64).sum()
}

/// The primitive other than `own` (and its exact copies; `u32::MAX`: none skipped) that
/// `shadow` meets nearest its origin (the light, or the surface point where the light is far:
/// [`Scene::shadows_from_light`]), by the scalar loop (one ray: the accelerator answers only
/// whether).
///
/// [`Scene::shadows_from_light`]: crate::scene::Scene::shadows_from_light
fn nearest_blocker(stage: &Stage, shadow: &Ray<f32>, own: u32, method: Method) -> Option<u32> {
    let scene = stage.scene();
    if !scene.instances().is_empty() {
        // Millions of instanced triangles: the structure's nearest hit from the light (the
        // segment ends off its own surface, so that is the blocker).
        let hit = stage.accel().closest_hit(shadow, method, 0.0, 1.0)?;
        return (hit.prim != own).then_some(hit.prim);
    }
    let own_shape = scene.shapes.get(own as usize).copied();
    let mut best: Option<(f32, u32)> = None;
    for (k, s) in scene.shapes.iter().enumerate() {
        if k as u32 == own || (s.is_triangle() && Some(*s) == own_shape) {
            continue;
        }
        let far = best.map_or(1.0, |b| b.0);
        if let Some((t, _, _)) = s.intersect(shadow, method, 0.0, far) {
            if best.is_none_or(|b| t < b.0) {
                best = Some((t, k as u32));
            }
        }
    }
    best.map(|b| b.1)
}

/// Which level of the adaptive method decides whether `ray` meets `shape`: the f32 filter
/// (the watertight test with its error bound), f64 interval arithmetic, or exact arithmetic.
fn decided_by(shape: &Shape<f32>, ray: &Ray<f32>, method: Method) -> &'static str {
    if method != Method::Adaptive {
        return method.name();
    }
    adaptive::deciding_level(shape, ray)
}

impl fmt::Display for Inspection {
    /// One `name: value` line per field, the lecture's names.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v3 = |v: [f64; 3]| format!("{} {} {}", v[0], v[1], v[2]);
        let f3 = |v: [f32; 3]| format!("{} {} {}", v[0], v[1], v[2]);
        writeln!(f, "pixel: {} {}", self.pixel[0], self.pixel[1])?;
        writeln!(f, "uvf: {}", v3(self.uvf))?;
        writeln!(f, "d_camera: {}", v3(self.d_camera))?;
        writeln!(f, "origin: {}", f3(self.ray.o))?;
        writeln!(f, "d_world: {}", f3(self.ray.d))?;
        writeln!(f, "method: {}", self.method.name())?;
        let Some(h) = &self.hit else {
            return writeln!(f, "hit: none");
        };
        writeln!(f, "hit: {}", h.prim)?;
        writeln!(f, "t: {}", h.t)?;
        writeln!(f, "t_exact: {}", h.t_exact)?;
        writeln!(f, "decided_by: {}", h.decided_by)?;
        for line in h.terms.lines() {
            writeln!(f, "{line}")?;
        }
        writeln!(f, "point: {}", f3(h.point))?;
        writeln!(f, "point_error: {}", f3(h.point_error))?;
        writeln!(f, "point_hit_error: {}", f3(h.point_hit_error))?;
        writeln!(f, "normal: {}", f3(h.normal))?;
        match &h.shadow {
            Some(s) => {
                let end = [0, 1, 2].map(|k| s.o[k] + s.d[k]);
                writeln!(f, "shadow_ray: from {} to {}", f3(s.o), f3(end))?
            }
            None => writeln!(f, "shadow_ray: none (D = 0)")?,
        }
        match h.blocked_by {
            Some(p) => writeln!(f, "blocked_by: {p}")?,
            None => writeln!(f, "blocked_by: none")?,
        }
        writeln!(f, "rho: {}", f3(h.rho))?;
        writeln!(f, "D: {}", f3(h.direct))?;
        writeln!(f, "D_unshadowed: {}", f3(h.direct_unshadowed))?;
        writeln!(f, "N: {}", f3(h.indirect))?;
        writeln!(f, "step: {}", self.step)?;
        // (Which of the terms above the colour holds: N = 0.5 beside a shadows colour read as
        // part of it.)
        writeln!(f, "colour_terms: {}", self.step.colour_terms())?;
        writeln!(f, "colour: {}", f3(h.colour))
    }
}
