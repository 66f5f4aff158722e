//! One shading function per lab step. Colours are linear RGB.

use crate::geometry::{Hit, Method, Ray, SurfacePoint};
use crate::math::real::{dot, sub};
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

/// Step 3: ρ·D.
pub fn direct(scene: &Scene, ray: &Ray, hit: &Hit) -> Rgb {
    let sp = SurfacePoint::new(&scene.shapes[hit.prim as usize], ray, hit);
    mul(flat(scene, hit), irradiance(scene, &sp, ray))
}

/// D, zero where the shadow ray (origin offset past the hit's error bound) is blocked before
/// the light. Adds the shadow rays cast to `shadow_rays`.
fn shadowed_irradiance(
    scene: &Scene,
    ray: &Ray,
    hit: &Hit,
    method: Method,
    shadow_rays: &mut u64,
) -> Rgb {
    let sp = SurfacePoint::new(&scene.shapes[hit.prim as usize], ray, hit);
    let d = irradiance(scene, &sp, ray);
    if d == [0.0; 3] {
        return d;
    }
    *shadow_rays += 1;
    let shadow = sp.ray_towards(scene.light.position);
    // The primitive itself cannot block (planar or convex, light on its lit side).
    if scene
        .accel()
        .any_hit_except(&shadow, method, 0.0, 1.0, hit.prim)
    {
        [0.0; 3]
    } else {
        d
    }
}

/// Step 4: ρ·D with shadows.
pub fn shadows(scene: &Scene, ray: &Ray, hit: &Hit, method: Method, shadow_rays: &mut u64) -> Rgb {
    mul(
        flat(scene, hit),
        shadowed_irradiance(scene, ray, hit, method, shadow_rays),
    )
}

/// Step 5: ρ·(D + N) with shadows.
pub fn indirect(scene: &Scene, ray: &Ray, hit: &Hit, method: Method, shadow_rays: &mut u64) -> Rgb {
    let d = shadowed_irradiance(scene, ray, hit, method, shadow_rays);
    let n = scene.ambient;
    mul(flat(scene, hit), [d[0] + n[0], d[1] + n[1], d[2] + n[2]])
}

fn mul(a: Rgb, b: Rgb) -> Rgb {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}
