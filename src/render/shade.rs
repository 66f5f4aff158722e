//! Shading for the lab steps: flat colour, or a hit readied once ([`Lit`]: surface point,
//! irradiance, shadow ray) and coloured per step. Colours are linear RGB.

use crate::accel::{OriginTriangle, ShadowSegments};
use crate::geometry::triangle::shading_points;
use crate::geometry::{offset_ray_origin, Hit, Ray, SurfacePoint};
use crate::math::lanes::{f32x8, Lanes};
use crate::math::real::{dot, sub};
use crate::math::simd::{avx512_avx2_or_baseline, each3};
use crate::render::LabStep;
use crate::scene::Scene;
use std::f32::consts::PI;
use std::ops::{Add, Mul};

/// A linear RGB colour.
pub type Rgb = [f32; 3];

/// The colour of `step` at camera ray `ray`'s nearest hit `hit`: the surface colour ρ for
/// the flat step, else the lit colour ([`Lit`]) with the shadow ray tested by
/// `blocked(ray, skip)`. Adds the shadow rays cast to `shadow_rays`.
pub fn shade(
    scene: &Scene,
    ray: &Ray,
    hit: &Hit,
    step: LabStep,
    blocked: impl Fn(&Ray, u32) -> bool,
    shadow_rays: &mut u64,
) -> Rgb {
    match step {
        LabStep::Flat => step_colour(scene, hit.prim, [0.0; 3], false, step),
        _ => Lit::new(scene, ray, hit).colour(scene, step, blocked, shadow_rays),
    }
}

/// The lab's D = P·max(n·r̂, 0)/(4πr²) at `sp` as the factor k of D = P·k (`None`: no
/// light), with the normal turned to face the viewer (surfaces are two-sided), and the
/// unit-free r = light − p.
fn irradiance_factor(scene: &Scene, sp: &SurfacePoint, ray: &Ray) -> Option<f32> {
    let r = sub(scene.light.position, sp.p);
    let r2 = dot(r, r);
    let facing = if dot(sp.n, ray.d) > 0.0 { -1.0 } else { 1.0 };
    let cos = facing * dot(sp.n, r) / r2.sqrt();
    // r2 = 0 (light on the surface) makes cos NaN: no light either way.
    if r2 <= 0.0 || cos.is_nan() || cos <= 0.0 {
        return None;
    }
    Some(cos / (FOUR_PI * r2))
}

const FOUR_PI: f32 = 4.0 * PI;
/// The shadow ray's widening of the point's error bound: relative, and of |L − p|.
const WIDEN: f32 = 1.0 + 1.0 / (1u32 << 21) as f32;
const END: f32 = 1.0 / (1u32 << 22) as f32;

/// The shadow ray of surface point `p` (error bound `p_error`, unit normal `n`): from the
/// light L to the point offset towards the light, t in (0, 1). Starting at the light lets
/// every shadow ray of a frame share one origin (the packet kernel of
/// `crate::accel::packet`). Its far end L + fl(p_o − L) misses the offset point p_o by at
/// most u·|p_o − L| per axis, so the offset also covers 2⁻²²·|L − p| (with p_o within a
/// tiny offset of p): the end stays on the light's side of the surface.
pub fn shadow_from_light(p: [f32; 3], p_error: [f32; 3], n: [f32; 3], light: [f32; 3]) -> Ray {
    let w = sub(light, p);
    let err = [0, 1, 2].map(|k| p_error[k] * WIDEN + END * w[k].abs());
    let po = offset_ray_origin(p, err, n, w);
    Ray::new(light, sub(po, light))
}

/// The shadow ray of surface point `p` for a light far from the scene
/// ([`Scene::shadows_from_light`] false): from the point offset towards the light by its own
/// error bound to the light L, t in (0, 1). It starts exactly there, so nothing near the
/// surface is missed; its end p_o + fl(L − p_o) misses L by at most u·|L − p_o|, far from
/// every surface.
pub fn shadow_to_light(p: [f32; 3], p_error: [f32; 3], n: [f32; 3], light: [f32; 3]) -> Ray {
    let w = sub(light, p);
    let po = offset_ray_origin(p, p_error.map(|e| e * WIDEN), n, w);
    Ray::new(po, sub(light, po))
}

/// The shadow ray of surface point `sp` in `scene`: from the light, or to it where the light
/// is far ([`Scene::shadows_from_light`]).
pub fn shadow_ray(scene: &Scene, sp: &SurfacePoint) -> Ray {
    let light = scene.light.position;
    match scene.shadows_from_light() {
        true => shadow_from_light(sp.p, sp.p_error, sp.n, light),
        false => shadow_to_light(sp.p, sp.p_error, sp.n, light),
    }
}

/// A camera ray's hit readied for shading: its primitive, the irradiance D = P·k there without
/// shadows, and the shadow ray ([`shadow_ray`]; `None` where D = 0:
/// nothing to shadow). Made once per hit, so a renderer can gather the shadow rays of a tile
/// first.
///
/// The surface point is the shape's own ([`shading_point`]): it depends on the camera ray
/// and the primitive only, never on how the nearest hit was found (packet or per-ray search,
/// f32 or exact level), and the steps from it to D and the shadow ray are the ones
/// [`shade_packet`] takes lanes at a time, so every path shades a pixel to the same bits.
#[derive(Clone, Copy, Debug)]
pub struct Lit {
    pub prim: u32,
    /// D = P·`k` where D ≠ 0 (where there is a shadow ray: [`Lit::d`]); 0 elsewhere.
    pub k: f32,
    pub shadow: Option<Ray>,
    /// The primitive the shadow test may skip: `prim` itself where the shadow ray certainly
    /// stays clear of its shape ([`Shape::shadow_clear_of_itself`]: planar, or a sphere with
    /// the shadow ray's end on the light's side of it), else `u32::MAX` (none): a sphere seen
    /// from the other side than the light (from inside with the light outside), which the ray
    /// to the light must cross, and which then blocks it.
    ///
    /// [`Shape::shadow_clear_of_itself`]: crate::geometry::Shape::shadow_clear_of_itself
    pub skip: u32,
}

impl Lit {
    /// Readies camera ray `ray`'s hit `hit` (only its primitive is used).
    pub fn new(scene: &Scene, ray: &Ray, hit: &Hit) -> Self {
        Self::on(scene, ray, hit.prim)
    }

    /// Readies camera ray `ray`'s hit on primitive `prim`.
    pub fn on(scene: &Scene, ray: &Ray, prim: u32) -> Self {
        Self::at(scene, ray, prim, scene.shape(prim).surface_point(ray))
    }

    /// [`Lit::on`] at `sp`, the shading point of `ray` on `prim` (as its shape gives it,
    /// [`Shape::surface_point`](crate::geometry::Shape::surface_point)).
    pub fn at(scene: &Scene, ray: &Ray, prim: u32, sp: SurfacePoint) -> Self {
        let shape = scene.shape(prim);
        let k = irradiance_factor(scene, &sp, ray);
        let d = k.map_or([0.0; 3], |k| scene.light.power.map(|p| p * k));
        let light = scene.light.position;
        let shadow = (d != [0.0; 3]).then(|| shadow_ray(scene, &sp));
        // The shadow ray's end is offset outwards where (L − p)·n ≥ 0 (as
        // `offset_ray_origin` does), inwards otherwise.
        let end_outside = dot(sub(light, sp.p), sp.n) >= 0.0;
        let skip = match shape.shadow_clear_of_itself(light, end_outside) {
            true => prim,
            false => u32::MAX,
        };
        Self {
            prim,
            k: k.unwrap_or(0.0),
            shadow,
            skip,
        }
    }

    /// The irradiance D without shadows: P·k where D ≠ 0 (as `sum_colours` takes it for a
    /// packet).
    pub fn d(&self, scene: &Scene) -> Rgb {
        match self.shadow {
            Some(_) => scene.light.power.map(|p| p * self.k),
            None => [0.0; 3],
        }
    }

    /// The colour of lab step 3, 4 or 5 ([`step_colour`]), the shadow ray (if any) tested by
    /// `blocked(ray, skip)` with [`Lit::skip`]. Adds the shadow rays cast to `shadow_rays`.
    pub fn colour(
        &self,
        scene: &Scene,
        step: LabStep,
        blocked: impl Fn(&Ray, u32) -> bool,
        shadow_rays: &mut u64,
    ) -> Rgb {
        let blocked = match (&self.shadow, step.casts_shadows()) {
            (Some(shadow), true) => {
                *shadow_rays += 1;
                blocked(shadow, self.skip)
            }
            _ => false,
        };
        step_colour(scene, self.prim, self.d(scene), blocked, step)
    }
}

/// Up to 8 camera hits readied for shading, lanes side by side (what [`Lit`] holds per hit):
/// lane l hit primitive `shadow.prim[l]` where bit l of `hit` is set; there D = P·`k[l]`
/// and, where bit l of `shadow.live` is set (D ≠ 0), the shadow segment runs from the light
/// along `shadow.d` (zero in the other lanes), skipping that primitive unless bit l of
/// `shadow.own_blocks` is set ([`Lit::skip`]).
#[derive(Clone, Copy, Debug)]
pub struct ShadePacket {
    pub hit: u32,
    pub k: [f32; 8],
    pub shadow: ShadowSegments,
}

impl ShadePacket {
    /// Lane l's primitive (`u32::MAX` where it hit nothing).
    #[inline]
    pub fn prim(&self, l: usize) -> u32 {
        self.shadow.prim[l]
    }

    /// Sets lane l to hit `lit` (made by [`Lit::new`] for that lane's ray): for the lanes
    /// [`shade_packet`] does not make, those on shapes other than triangles.
    pub fn set_lane(&mut self, l: usize, lit: &Lit) {
        let bit = 1 << l;
        self.hit |= bit;
        self.k[l] = lit.k;
        self.shadow.prim[l] = lit.prim;
        match lit.skip == lit.prim {
            true => self.shadow.own_blocks &= !bit,
            false => self.shadow.own_blocks |= bit,
        }
        let d = lit.shadow.map_or([0.0; 3], |ray| ray.d);
        for (k, c) in self.shadow.d.iter_mut().enumerate() {
            let mut lanes = c.to_array();
            lanes[l] = d[k];
            *c = f32x8::from(lanes);
        }
        match lit.shadow {
            Some(_) => self.shadow.live |= bit,
            None => self.shadow.live &= !bit,
        }
    }
}

impl AsRef<ShadowSegments> for ShadePacket {
    fn as_ref(&self) -> &ShadowSegments {
        &self.shadow
    }
}

/// The colours of lab step `step` (past the flat one) of `packets`, one tile row's camera
/// packets with its samples in order, summed per lane (pixel) over lanes `lanes`: the sums the
/// per-ray path makes per pixel ([`step_colour`] added sample by sample), with the same
/// operations in the same order, 8 lanes at a time. `blocked[i]` is packet i's blocked
/// shadow lanes; `colors` the scene's colours by primitive where no instances are present.
/// (One lane at a time this was about 80 instructions a pixel of the Cornell box.)
#[inline(always)]
pub(crate) fn sum_colours<V: Lanes>(
    scene: &Scene,
    colors: Option<&[Rgb]>,
    packets: &[ShadePacket],
    blocked: &[u32],
    step: LabStep,
    lanes: u32,
) -> [Rgb; 8] {
    let (power, ambient) = (scene.light.power, scene.ambient);
    let mut sums = [V::zero(); 3];
    for (packet, &blocked) in packets.iter().zip(blocked) {
        let hit = packet.hit & lanes;
        if hit == 0 {
            continue;
        }
        let colour = |prim: u32| match colors {
            Some(colors) => colors[prim as usize],
            None => scene.color(prim),
        };
        // ρ by lane (missed lanes are dropped below): one look-up where every lane hit the
        // same primitive (most packets of a box-like scene), else one per lane.
        let prims = &packet.shadow.prim;
        let mut rho = [[0.0f32; 8]; 3];
        if hit == 0xff && prims.iter().all(|&p| p == prims[0]) {
            let c = colour(prims[0]);
            rho = [[c[0]; 8], [c[1]; 8], [c[2]; 8]];
        } else {
            for l in 0..8 {
                if hit & (1 << l) != 0 {
                    let c = colour(prims[l]);
                    rho[0][l] = c[0];
                    rho[1][l] = c[1];
                    rho[2][l] = c[2];
                }
            }
        }
        let lit = V::from_bitmask(packet.shadow.live & !blocked);
        let hit = V::from_bitmask(hit);
        let k = V::from_array(packet.k);
        for c in 0..3 {
            // As `Lit::d` then `step_colour`: D = power·k where the light is seen.
            let d = lit.bitselect(V::splat(power[c]) * k, V::zero());
            let colour = step_channel(step, V::from_array(rho[c]), d, V::splat(ambient[c]));
            sums[c] = sums[c] + hit.bitselect(colour, V::zero());
        }
    }
    let channels = [sums[0].to_array(), sums[1].to_array(), sums[2].to_array()];
    let mut pixels = [[0.0; 3]; 8];
    for l in 0..8 {
        for c in 0..3 {
            pixels[l][c] = channels[c][l];
        }
    }
    pixels
}

/// The colour of lab step `step` for primitive `prim` with irradiance `d` (ρ·D, with
/// shadows, plus the ambient term N; ρ alone for the flat step): what every path computes per
/// sample ([`step_channel`] per channel).
#[inline]
pub fn step_colour(scene: &Scene, prim: u32, d: Rgb, blocked: bool, step: LabStep) -> Rgb {
    let rho = scene.color(prim);
    let d = if blocked { [0.0; 3] } else { d };
    let n = scene.ambient;
    [0, 1, 2].map(|c| step_channel(step, rho[c], d[c], n[c]))
}

/// The lab step's formula, written once: one colour channel from the surface colour ρ, the
/// irradiance D (zero where the light is not seen) and the ambient term N. Generic so that
/// the per-sample path (f32) and the packet path (8 lanes) compute it with the same
/// operations in the same order, to the same bits.
#[inline(always)]
pub fn step_channel<T: Copy + Add<Output = T> + Mul<Output = T>>(
    step: LabStep,
    rho: T,
    d: T,
    ambient: T,
) -> T {
    match step {
        LabStep::Flat => rho,
        LabStep::Direct | LabStep::Shadows => rho * d,
        LabStep::Indirect => rho * (d + ambient),
    }
}

/// The point where camera ray `ray`'s hit on primitive `prim` is shaded, with its bounds
/// ([`SurfacePoint`]: `p_error` from the surface, `hit_error` from the exact hit point), the
/// bits every path of the renderer shades with: the shape's own
/// ([`Primitive::surface_point`](crate::geometry::Primitive::surface_point); a triangle's
/// from the barycentrics of [`shade_packet`], a sphere's re-projected onto it).
pub fn shading_point(scene: &Scene, ray: &Ray, prim: u32) -> SurfacePoint {
    scene.shape(prim).surface_point(ray)
}

/// A triangle readied for shading the hits of rays from one origin: prepared for that origin
/// (the barycentrics of [`Lit`]) and its unit geometric normal.
#[derive(Clone, Copy, Debug)]
pub struct ShadeTri {
    pub tri: OriginTriangle,
    pub normal: [f32; 3],
}

impl ShadeTri {
    pub fn new(v: &[[f32; 3]; 3], origin: [f32; 3], prim: u32) -> Self {
        Self {
            tri: OriginTriangle::new(v, origin, prim),
            normal: unit_normal(v),
        }
    }
}

pub use crate::geometry::triangle::unit_normal;

/// [`Lit`] for up to 8 camera rays from one origin (directions `d`, lanes) that hit triangles:
/// `lanes[l]` is lane l's triangle readied for the origin (its `prim` names it), `None` for
/// no hit. Lane by lane the same bits as [`Lit::new`]: the same shading point
/// (`shading_points`, which a triangle's own point runs on one lane) and the same steps
/// from it, lanes at a time.
pub fn shade_packet(scene: &Scene, d: &[f32x8; 3], lanes: &[Option<&ShadeTri>; 8]) -> ShadePacket {
    avx512_avx2_or_baseline!(lanes shade_packet_in => (
        scene: &Scene,
        d: &[f32x8; 3],
        lanes: &[Option<&ShadeTri>; 8]
    ) -> ShadePacket)
}

/// [`shade_packet`] inside a kernel already built for lanes `V` (the frame's tile loop).
#[inline(always)]
pub(crate) fn shade_packet_in<V: Lanes>(
    scene: &Scene,
    d: &[f32x8; 3],
    lanes: &[Option<&ShadeTri>; 8],
) -> ShadePacket {
    let d = &each3(|k| V::from_wide(d[k]));
    let triangle = |tri: &OriginTriangle| {
        *(scene.shape(tri.prim).triangle()).expect("shade_packet takes triangles")
    };
    let mut prim = [u32::MAX; 8];
    let mut hit = 0u32;
    for (l, lane) in lanes.iter().enumerate() {
        if let Some(t) = lane {
            prim[l] = t.tri.prim;
            hit |= 1 << l;
        }
    }
    let (edge, v, n) = match lanes[0] {
        // One triangle in every lane (most packets of a small scene): broadcast it.
        Some(first) if hit == 0xff && prim.iter().all(|p| *p == first.tri.prim) => (
            splat33(first.tri.edge_normals()),
            splat33(&triangle(&first.tri)),
            splat3(first.normal),
        ),
        _ => {
            let (mut edge, mut vert) = ([[[0.0f32; 8]; 3]; 3], [[[0.0f32; 8]; 3]; 3]);
            let mut normal = [[0.0f32; 8]; 3];
            for (l, lane) in lanes.iter().enumerate() {
                let Some(t) = lane else { continue };
                let (e, v) = (t.tri.edge_normals(), triangle(&t.tri));
                for i in 0..3 {
                    for k in 0..3 {
                        edge[i][k][l] = e[i][k];
                        vert[i][k][l] = v[i][k];
                    }
                    normal[i][l] = t.normal[i];
                }
            }
            (
                each3(|i| each3(|k| V::from_array(edge[i][k]))),
                each3(|i| each3(|k| V::from_array(vert[i][k]))),
                each3(|k| V::from_array(normal[k])),
            )
        }
    };
    let (p, p_error) = shading_points::<V>(d, &edge, &v);
    // The irradiance D (see `irradiance`), lanes at a time.
    let light = scene.light.position;
    let r = each3(|k| V::splat(light[k]) - p[k]);
    let r2 = dot8(&r, &r);
    let facing = dot8(&n, d)
        .simd_gt(V::zero())
        .bitselect(V::splat(-1.0), V::one());
    let cos = facing * dot8(&n, &r) / r2.sqrt();
    let k = cos / (V::splat(FOUR_PI) * r2);
    // D ≠ 0 (some channel of P·k), as `Lit` asks before casting a shadow ray.
    let power = scene.light.power;
    let (zero, [p0, p1, p2]) = (V::zero(), power);
    let nonzero = (V::splat(p0) * k).simd_ne(zero)
        | (V::splat(p1) * k).simd_ne(zero)
        | (V::splat(p2) * k).simd_ne(zero);
    let lit = r2.simd_gt(zero) & cos.simd_gt(zero) & nonzero;
    // (Lanes without a hit have n = 0, so cos = 0 there: unlit.)
    let shadowed = lit.to_bitmask() & hit;
    // The shadow ray from the light, as `shadow_from_light` makes it, lanes at a time.
    let widen = V::splat(WIDEN);
    let end = V::splat(END);
    let err = each3(|k| p_error[k] * widen + end * r[k].abs());
    let dist = n[0].abs() * err[0] + n[1].abs() * err[1] + n[2].abs() * err[2];
    let away = dot8(&r, &n).simd_lt(V::zero());
    let mut shadow_d = [V::zero(); 3];
    for k in 0..3 {
        let offset = n[k] * dist;
        let offset = away.bitselect(offset * V::splat(-1.0), offset);
        let po = nudge(p[k] + offset, offset);
        shadow_d[k] = lit.bitselect(po - V::splat(light[k]), V::zero());
    }
    ShadePacket {
        hit,
        k: k.to_array(),
        shadow: ShadowSegments {
            d: each3(|k| shadow_d[k].to_wide()),
            prim,
            live: shadowed,
            own_blocks: 0,
        },
    }
}

#[inline(always)]
fn dot8<V: Lanes>(a: &[V; 3], b: &[V; 3]) -> V {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn splat3<V: Lanes>(x: [f32; 3]) -> [V; 3] {
    [V::splat(x[0]), V::splat(x[1]), V::splat(x[2])]
}

#[inline(always)]
fn splat33<V: Lanes>(x: &[[f32; 3]; 3]) -> [[V; 3]; 3] {
    [splat3(x[0]), splat3(x[1]), splat3(x[2])]
}

/// `x` one ulp up where `offset` > 0 and down where it is < 0 (`next_up`/`next_down`).
#[inline(always)]
fn nudge<V: Lanes>(x: V, offset: V) -> V {
    let zero = V::zero();
    let (up, down) = (offset.simd_gt(zero), offset.simd_lt(zero));
    let (pos, neg) = (x.simd_gt(zero), x.simd_lt(zero));
    let at_zero = x.simd_eq(zero);
    // Away from zero one step: bits + 1; towards it: bits − 1 (a true mask is −1); from ±0:
    // the least subnormal.
    let grow = (up & pos) | (down & neg);
    let shrink = (up & neg) | (down & pos);
    let stepped = x.step_bits(grow, shrink);
    let tiny = up.bitselect(V::splat(f32::from_bits(1)), V::splat(-f32::from_bits(1)));
    let stepped = (at_zero & (up | down)).bitselect(tiny, stepped);
    // NaN stays; so do +∞ going up and −∞ going down.
    let inf = V::splat(f32::INFINITY);
    let fixed = x.simd_ne(x) | (up & x.simd_eq(inf)) | (down & x.simd_eq(-inf));
    fixed.bitselect(x, stepped)
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    fn nudge_steps_as_next_up_and_next_down() {
        let tiny = f32::from_bits(1);
        let xs = [
            0.0,
            -0.0,
            tiny,
            -tiny,
            f32::MIN_POSITIVE,
            1.0,
            -1.0,
            1e-30,
            -3.5e20,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for x in xs {
            for (offset, want) in [(1.0, x.next_up()), (-1.0, x.next_down()), (0.0, x)] {
                let got = nudge(f32x8::splat(x), f32x8::splat(offset)).to_array()[0];
                assert_eq!(got.to_bits(), want.to_bits(), "x {x:e} offset {offset}");
            }
        }
        let nan = nudge(f32x8::splat(f32::NAN), f32x8::ONE).to_array()[0];
        assert!(nan.is_nan());
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[(
        "nudge_steps_as_next_up_and_next_down",
        nudge_steps_as_next_up_and_next_down,
    )];
}
