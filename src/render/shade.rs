//! Shading for the lab steps: flat colour, or a hit readied once ([`Lit`]: surface point,
//! irradiance, shadow ray) and coloured per step. Colours are linear RGB.

use crate::accel::soa::TriangleBlocks;
use crate::geometry::adaptive::Search;
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, SurfacePoint};
use crate::math::real::{dot, sub};
use crate::render::LabStep;
use crate::scene::Scene;
use std::f32::consts::PI;

/// A linear RGB colour.
pub type Rgb = [f32; 3];

/// Step 1: the surface colour ρ.
pub fn flat(scene: &Scene, hit: &Hit) -> Rgb {
    scene.colors[hit.prim as usize]
}

/// The lab's D = P·max(n·r̂, 0)/(4πr²) at `sp`, with the normal turned to face the viewer
/// (surfaces are two-sided), and the unit-free r = light − p.
fn irradiance(scene: &Scene, sp: &SurfacePoint, ray: &Ray) -> Rgb {
    let r = sub(scene.light.position, sp.p);
    let r2 = dot(r, r);
    let facing = if dot(sp.n, ray.d) > 0.0 { -1.0 } else { 1.0 };
    let cos = facing * dot(sp.n, r) / r2.sqrt();
    // r2 = 0 (light on the surface) makes cos NaN: no light either way.
    if r2 <= 0.0 || cos.is_nan() || cos <= 0.0 {
        return [0.0; 3];
    }
    let k = cos / (4.0 * PI * r2);
    scene.light.power.map(|p| p * k)
}

/// A camera ray's hit readied for shading: its surface point, the irradiance D there
/// without shadows, and the shadow ray towards the light (`None` where D = 0: nothing to
/// shadow). Made once per hit, so a renderer can gather the shadow rays of a tile first.
#[derive(Clone, Copy, Debug)]
pub struct Lit {
    pub hit: Hit,
    pub d: Rgb,
    pub shadow: Option<Ray>,
    /// Whether the shadow ray is blocked, where already known (tested in packets).
    pub blocked: Option<bool>,
}

impl Lit {
    pub fn new(scene: &Scene, ray: &Ray, hit: &Hit) -> Self {
        let sp = SurfacePoint::new(&scene.shapes[hit.prim as usize], ray, hit);
        let d = irradiance(scene, &sp, ray);
        let shadow = (d != [0.0; 3]).then(|| sp.ray_towards(scene.light.position));
        Self {
            hit: *hit,
            d,
            shadow,
            blocked: None,
        }
    }

    /// D, zero where the shadow ray is blocked before the light. Adds the shadow rays cast to
    /// `shadow_rays`.
    fn shadowed(&self, scene: &Scene, test: (Method, Occluders), shadow_rays: &mut u64) -> Rgb {
        let Some(shadow) = &self.shadow else {
            return self.d;
        };
        *shadow_rays += 1;
        // The primitive itself cannot block (planar or convex, light on its lit side).
        let blocked = self
            .blocked
            .unwrap_or_else(|| test.1.blocked(scene, shadow, test.0, self.hit.prim));
        if blocked {
            [0.0; 3]
        } else {
            self.d
        }
    }

    /// The colour of lab step 3, 4 or 5 (ρ·D, with shadows, plus the ambient term N).
    pub fn colour(
        &self,
        scene: &Scene,
        step: LabStep,
        test: (Method, Occluders),
        shadow_rays: &mut u64,
    ) -> Rgb {
        let rho = flat(scene, &self.hit);
        match step {
            LabStep::Flat => rho,
            LabStep::Direct => mul(rho, self.d),
            LabStep::Shadows => mul(rho, self.shadowed(scene, test, shadow_rays)),
            LabStep::Indirect => {
                let d = self.shadowed(scene, test, shadow_rays);
                let n = scene.ambient;
                mul(rho, [d[0] + n[0], d[1] + n[1], d[2] + n[2]])
            }
        }
    }
}

/// What shadow rays are tested against.
#[derive(Clone, Copy, Debug)]
pub enum Occluders<'a> {
    /// The scene's own structure.
    Scene,
    /// A subset of a triangle-only scene's triangles that holds every triangle the shadow
    /// rays at hand can meet (the renderer culls them per tile); adaptive method only.
    Culled(&'a TriangleBlocks),
}

impl Occluders<'_> {
    /// Whether `ray` is blocked for 0 < t < 1 by anything but primitive `skip`.
    fn blocked(&self, scene: &Scene, ray: &Ray, method: Method, skip: u32) -> bool {
        match self {
            Occluders::Scene => scene.accel().any_hit_except(ray, method, 0.0, 1.0, skip),
            Occluders::Culled(blocks) => {
                debug_assert_eq!(method, Method::Adaptive);
                WatertightRay::new(ray.o, ray.d)
                    .is_some_and(|r| blocks.any_hit_adaptive(&r, &Search::new(ray, 0.0, 1.0), skip))
            }
        }
    }
}

/// The colour of `step` at a camera ray's nearest hit, shadow rays against the scene.
pub fn shade(
    scene: &Scene,
    ray: &Ray,
    hit: &Hit,
    step: LabStep,
    method: Method,
    shadow_rays: &mut u64,
) -> Rgb {
    if step == LabStep::Flat {
        return flat(scene, hit);
    }
    Lit::new(scene, ray, hit).colour(scene, step, (method, Occluders::Scene), shadow_rays)
}

fn mul(a: Rgb, b: Rgb) -> Rgb {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}
