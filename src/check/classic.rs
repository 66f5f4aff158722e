//! The families that each catch one classic lab bug: far and tiny spheres met near their rim
//! (the textbook quadratic in f64), directions that are not of unit length (t in units of a
//! normalised direction), intervals whose ends lie exactly at surfaces (`<=` for `<`, the near
//! root only), hits behind the origin (tmin ignored), exact ties (either answer stands), and
//! hits a hair past tmin (a fixed epsilon).
//! Where an interval's end must lie exactly at a surface, the t there is exact in f32: planes
//! z = k met by d = (dx, dy, s) with s a power of two, a sphere met at Pythagorean points.

use super::meshes::Rng;
use super::suite::Family;
use crate::geometry::{Ray, Shape};
use crate::tracefile::TraceRay;

/// The classic bugs' families.
pub fn classic_bugs() -> Vec<Family> {
    vec![
        rim_of_far_tiny_spheres(),
        directions_not_of_unit_length(),
        interval_ends_at_surfaces(),
        hits_behind_the_origin(),
        exact_ties(),
        hits_just_past_tmin(),
    ]
}

/// A ray over (tmin, tmax).
fn span(ray: Ray<f32>, tmin: f32, tmax: f32) -> TraceRay<f32> {
    TraceRay { ray, tmin, tmax }
}

/// A power of two from 2^lo to 2^hi.
fn power_of_two(rng: &mut Rng, lo: i32, hi: i32) -> f32 {
    2f32.powi(lo + rng.below((hi - lo + 1) as usize) as i32)
}

/// Spheres 2^14 to 2^23 away with radius 2^-28 of that: r² is a sixteenth of an ulp of the
/// distance squared in f64, so the textbook c = |o − c|² − r² loses r² and the ray's miss
/// distance entirely, and b² − 4ac is 0 for every ray: near the rim it hits what it should
/// miss or misses what it should hit. The perpendicular form (h = oc − (oc·d/d·d)·d) keeps
/// them.
fn rim_of_far_tiny_spheres() -> Family {
    let mut rng = Rng(201);
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for (k, (e, axis)) in [(20, 0usize), (17, 1), (23, 2), (14, 0)]
        .into_iter()
        .enumerate()
    {
        let far = 2f32.powi(e);
        let r = far * 2f32.powi(-28);
        // Each sphere off the others' axes by one unit.
        let mut base = [0.0f32; 3];
        base[(axis + 1) % 3] = k as f32;
        let mut centre = base;
        centre[axis] = far;
        shapes.push(Shape::sphere(centre, r));
        for j in 0..90 {
            // The miss distance: across the rim, a few within 1e-3 of it (none exactly tangent:
            // the origin's offsets round to f32).
            let f = match j % 10 {
                0 => 1.0,
                1 => 0.999,
                2 => 1.001,
                _ => rng.range(0.0, 1.3),
            };
            let a = rng.range(0.0, std::f64::consts::TAU);
            let mut o = base;
            o[(axis + 1) % 3] += (f * a.cos()) as f32 * r;
            o[(axis + 2) % 3] += (f * a.sin()) as f32 * r;
            let s = power_of_two(&mut rng, -2, 2);
            let mut d = [0.0f32; 3];
            if j % 3 == 2 {
                // From beyond the sphere, looking back.
                o[axis] = 2.0 * far;
                d[axis] = -s;
            } else {
                d[axis] = s;
            }
            rays.push(Ray::new(o, d));
        }
    }
    Family::new("far tiny spheres at the rim", shapes, rays)
        .probing("Spheres 2^14 to 2^23 away with a radius 2^-28 of that, rays along an axis across the rim: r² is below the rounding of |o − c|² in f64.")
        .catching("the textbook quadratic (-b ± sqrt(b² - 4ac)) / 2a in f64: c = |o - c|² - r² loses r², so rays near the rim leak or hit falsely")
}

/// A triangle and a sphere met by directions of length 2^-20 to 2^20, 10^-6 to 10^6 and
/// 2^-100 to 2^-60: t is in the ray's own parameter, the distance divided by |d|, up to 10^31
/// (beyond any large number a program may read `inf` as).
fn directions_not_of_unit_length() -> Family {
    let mut rng = Rng(202);
    let shapes = vec![
        Shape::from([[-2.0, -2.0, 5.0], [2.0, -2.0, 5.0], [0.0, 2.0, 5.0]]),
        Shape::sphere([0.5, 0.0, -6.0], 1.5),
    ];
    let mut rays = Vec::new();
    for j in 0..240 {
        let o = [rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), 0.0];
        let target = match j % 2 {
            0 => [rng.range(-1.0, 1.0), rng.range(-1.0, 0.8), 5.0],
            _ => [0.5 + rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), -6.0],
        };
        let v = [0, 1, 2].map(|k| target[k] - o[k]);
        let len = v.iter().map(|c| c * c).sum::<f64>().sqrt();
        let length = match j % 4 {
            0 => f64::from(power_of_two(&mut rng, -20, 20)),
            1 => f64::from(power_of_two(&mut rng, -100, -60)),
            2 => 10f64.powf(rng.range(-6.0, 6.0)),
            _ => rng.range(0.5, 3.0),
        };
        rays.push(Ray::new(
            o.map(|c| c as f32),
            v.map(|c| (c / len * length) as f32),
        ));
    }
    Family::new("directions not of unit length", shapes, rays)
        .probing("A triangle and a sphere met by directions 2^-20 to 2^20, 1e-6 to 1e6 and 2^-100 to 2^-60 long: t is in units of the ray's own d, up to 1e31.")
        .catching("t in units of a normalised direction (off by the factor |d|); tmax `inf` read as a large number (1e8, 1e30)")
}

/// Triangles in the planes z = 1, 2, 3, 4 and a sphere of radius 5 at z = 20, met by rays
/// whose tmin and tmax lie exactly at a surface, one ulp inside or outside it, or between
/// surfaces: both ends are open.
fn interval_ends_at_surfaces() -> Family {
    let mut rng = Rng(203);
    let mut shapes: Vec<Shape<f32>> = (1..=4)
        .map(|z| {
            let z = z as f32;
            Shape::from([[-3.0, -3.0, z], [3.0, -3.0, z], [0.0, 3.0, z]])
        })
        .collect();
    shapes.push(Shape::sphere([0.0, 0.0, 20.0], 5.0));
    let mut rays = Vec::new();
    let up = f32::next_up;
    let down = f32::next_down;
    for j in 0..240 {
        let s = power_of_two(&mut rng, -2, 1);
        let o = [
            rng.range(-0.8, 0.8) as f32,
            rng.range(-0.8, 0.8) as f32,
            0.0,
        ];
        let d = [
            (rng.range(-0.05, 0.05) as f32) * s,
            (rng.range(-0.05, 0.05) as f32) * s,
            s,
        ];
        let t = |z: f32| z / s;
        let (tmin, tmax) = match j % 14 {
            0 => (0.0, f32::INFINITY),
            1 => (t(1.0), f32::INFINITY),
            2 => (down(t(1.0)), f32::INFINITY),
            3 => (up(t(1.0)), f32::INFINITY),
            4 => (0.0, t(1.0)),
            5 => (0.0, up(t(1.0))),
            6 => (0.0, down(t(1.0))),
            7 => (t(2.0), t(3.0)),
            8 => (down(t(2.0)), t(3.0)),
            9 => (t(1.0), up(t(3.0))),
            10 => (t(1.5), f32::INFINITY),
            11 => (-1.0, t(0.5)),
            12 => (t(4.0), f32::INFINITY),
            _ => (t(2.5), 1e30),
        };
        rays.push(span(Ray::new(o, d), tmin, tmax));
    }
    // The sphere: from (±h, 0, 0) along z it is met at z = 20 ∓ sqrt(25 − h²): 15 and 25, 16
    // and 24, 17 and 23, and 20 (tangent), all exact (from the axis, h = 0, the triangles
    // come first).
    for j in 0..120 {
        let (h, near, far) = [
            (0.0f32, 15.0f32, 25.0f32),
            (3.0, 16.0, 24.0),
            (4.0, 17.0, 23.0),
            (5.0, 20.0, 20.0),
        ][j % 4];
        let o = [if j % 8 < 4 { h } else { -h }, 0.0, 0.0];
        let s = power_of_two(&mut rng, -1, 1);
        let t = |z: f32| z / s;
        let (tmin, tmax) = match (j / 8) % 6 {
            0 => (0.0, f32::INFINITY),
            1 => (t(near), f32::INFINITY),
            2 => (up(t(near)), t(far).max(up(t(near)))),
            3 => (t((near + far) / 2.0), f32::INFINITY),
            4 => (0.0, t(near)),
            _ => (down(t(near)), up(t(near))),
        };
        rays.push(span(Ray::new(o, [0.0, 0.0, s]), tmin, tmax));
    }
    Family::with_spans("interval ends at surfaces", shapes, rays)
        .probing("Rays whose tmin and tmax lie exactly at a triangle or a sphere, one ulp inside or outside, or between surfaces (tmin < t < tmax, both open), tmin from -1 to 25.")
        .catching("t <= tmax or t >= tmin for < and >; the sphere's near root only (a ray starting inside or past it)")
}

/// Triangles in z = -3 and -1 behind origins near z = 0 and in z = 2 and 5 in front, a sphere
/// around the origins, and 64 small triangles far off (so that a hierarchy is built): rays
/// with tmin = 0 must not take what lies behind, rays with tmin < 0 (`-inf` too) must.
fn hits_behind_the_origin() -> Family {
    let mut rng = Rng(204);
    let mut shapes: Vec<Shape<f32>> = [-3.0f32, -1.0, 2.0, 5.0]
        .into_iter()
        .map(|z| Shape::from([[-4.0, -4.0, z], [4.0, -4.0, z], [0.0, 4.0, z]]))
        .collect();
    shapes.push(Shape::sphere([0.0, 0.0, 0.5], 2.0));
    for k in 0..64 {
        let x = 100.0 + k as f32;
        shapes.push(Shape::from([
            [x, 0.0, 50.0],
            [x + 0.5, 0.0, 50.0],
            [x, 0.5, 50.5],
        ]));
    }
    let mut rays = Vec::new();
    for j in 0..240 {
        let s = power_of_two(&mut rng, -1, 1);
        let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
        let o = [
            rng.range(-0.5, 0.5) as f32,
            rng.range(-0.5, 0.5) as f32,
            0.0,
        ];
        let d = [
            (rng.range(-0.05, 0.05) as f32) * s,
            (rng.range(-0.05, 0.05) as f32) * s,
            sign * s,
        ];
        let (tmin, tmax) = match (j / 2) % 5 {
            0 | 1 => (0.0, f32::INFINITY),
            2 if (j / 10) % 2 == 0 => (f32::NEG_INFINITY, f32::INFINITY),
            2 => (-10.0, f32::INFINITY),
            3 => (-2.0 / s, f32::INFINITY),
            _ => (-1.0 / s, 1.0 / s),
        };
        rays.push(span(Ray::new(o, d), tmin, tmax));
    }
    Family::with_spans("hits behind the origin", shapes, rays)
        .probing("Surfaces behind and in front of the origin, a sphere around it: with tmin = 0 only what lies in front counts, with tmin < 0 (or -inf) the nearest above tmin (behind the origin).")
        .catching("hits behind the origin (t <= tmin accepted, or |t| compared); a tmin of `-inf` not read")
}

/// Exact ties: two triangles sharing a diagonal met exactly on it, an exact copy, and a sphere
/// touching a triangle's plane at the point a ray meets: either primitive is right. Rays
/// beside the ties keep the family honest.
fn exact_ties() -> Family {
    let mut rng = Rng(205);
    let shapes = vec![
        Shape::from([[-1.0, -1.0, 2.0], [1.0, -1.0, 2.0], [1.0, 1.0, 2.0]]),
        Shape::from([[-1.0, -1.0, 2.0], [1.0, 1.0, 2.0], [-1.0, 1.0, 2.0]]),
        Shape::from([[-1.0, -1.0, 2.0], [1.0, 1.0, 2.0], [-1.0, 1.0, 2.0]]),
        Shape::from([[2.0, -1.0, 2.0], [4.0, -1.0, 2.0], [3.0, 1.0, 2.0]]),
        Shape::sphere([3.0, 0.0, 3.0], 1.0),
    ];
    let mut rays = Vec::new();
    // Origins and targets on a grid of 1/64, so that d = target − o is exact and the ray
    // passes exactly through its target.
    let grid = |rng: &mut Rng| (rng.below(129) as f32 - 64.0) / 64.0;
    for j in 0..200 {
        let o = [grid(&mut rng), grid(&mut rng), 0.0];
        let target = match j % 4 {
            // On the shared diagonal, at a point exact in f32.
            0 | 1 => {
                let x = (rng.below(15) as f32 - 7.0) / 8.0;
                [x, x, 2.0]
            }
            // Where the sphere touches the plane z = 2.
            2 => [3.0, 0.0, 2.0],
            _ => [grid(&mut rng) * 0.875, grid(&mut rng) * 0.875, 2.0],
        };
        rays.push(Ray::new(o, [0, 1, 2].map(|k| target[k] - o[k])));
    }
    Family::new("exact ties", shapes, rays)
        .probing("Rays exactly through an edge two triangles share, at an exact copy, and at the point where a sphere touches a triangle: exact ties, where either primitive is right.")
        .catching("none: it holds that no correct program is failed for a tie")
}

/// A triangle in z = 0 and a sphere resting on that plane, met from origins 2^-8 to 2^-67 in
/// front of the triangle and 2^-8 to 2^-16 in front of the sphere (tmin = 0), from origins
/// 1 + 2^-k behind the plane with tmin = 1, and with tmin exactly at the hit: every hit lies
/// a power of two past tmin, exactly, so a program that asks t > tmin + ε for some fixed
/// ε ≥ 2^-67 loses some of them, while the lecture's formulas in f32 and f64 keep them.
fn hits_just_past_tmin() -> Family {
    let mut rng = Rng(206);
    let shapes = vec![
        Shape::from([[-4.0, -4.0, 0.0], [4.0, -4.0, 0.0], [0.0, 4.0, 0.0]]),
        Shape::sphere([10.0, 0.0, 1.0], 1.0),
    ];
    let mut rays = Vec::new();
    for j in 0..240 {
        let s = power_of_two(&mut rng, -1, 1);
        let gap = 2f32.powi(-8 - (j / 4) % 60);
        // The origin's z (d = (…, s)) and tmin.
        let (z, tmin) = match j % 4 {
            // Met at t = gap/s, past tmin = 0 by that.
            0 | 1 => (-gap, 0.0),
            // Met at t = 1 + g/s, past tmin = 1 by g/s (s + g is exact in f32 for s ≤ 2).
            2 => {
                let g = 2f32.powi(-8 - (j / 4) % 14);
                (-(s + g), 1.0)
            }
            // tmin exactly at the plane: missed (tmin < t is open), and the sphere met only
            // at its top.
            _ => (-gap, gap / s),
        };
        // The sphere only from 2^-16 away and past tmin = 0: nearer, even f64 rounds o − c
        // onto the sphere (the family "inside and one ulp outside" holds that).
        let to_sphere = j % 3 == 2 && j % 4 != 2 && gap >= 2f32.powi(-16);
        let (o, d) = match to_sphere {
            // Straight up to the sphere's lowest point, (10, 0, 0).
            true => ([10.0, 0.0, z], [0.0, 0.0, s]),
            false => (
                [rng.range(-0.5, 0.5) as f32, rng.range(-0.5, 0.5) as f32, z],
                [
                    (rng.range(-0.25, 0.25) as f32) * s,
                    (rng.range(-0.25, 0.25) as f32) * s,
                    s,
                ],
            ),
        };
        rays.push(span(Ray::new(o, d), tmin, f32::INFINITY));
    }
    Family::with_spans("hits just past tmin", shapes, rays)
        .probing("A triangle and a sphere met 2^-8 to 2^-67 past tmin = 0, 2^-8 to 2^-22 past tmin = 1, and with tmin exactly at the hit: tmin < t, open, with no epsilon.")
        .catching("a fixed epsilon for tmin (t > tmin + ε): hits nearer than ε are lost, for any ε down to 2^-67")
}
