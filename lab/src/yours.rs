//! Your code: the lab's pieces, filled in with the lecture's plain formulas so that everything
//! runs. Change them; `cargo test -p lab` grades them against exact answers and
//! `cargo run -p lab --release` shows them in raylab's window ("your code" in the method
//! selector; the ray inspector shows your (t, u, v) beside the exact ones).
//!
//! Conventions (raylab's, the lecture's): camera space is x right, y down, z forward; pixel
//! (i, j) has its centre at image position (i + ½, j + ½); a hit counts for tmin < t < tmax,
//! the nearest wins, and on a tie the lower index.

use glam::{Mat4, Vec3};
use raylab::geometry::{Shape, Sphere, Triangle};

/// A ray o + t·d.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

/// The nearest hit: t, the shape's index, and on a triangle the weights (u, v) of its
/// vertices 1 and 2.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    pub index: usize,
    pub u: f32,
    pub v: f32,
}

/// Lab step 2, the camera: the ray through image position (x, y) of a `width`×`height`
/// image, for a pinhole camera with focal length `focal` (pixels) placed by the transform
/// stack's `world_from_camera`.
pub fn camera_ray(
    world_from_camera: Mat4,
    focal: f32,
    (width, height): (u32, u32),
    x: f32,
    y: f32,
) -> Ray {
    // (u, v, f): the position from the image centre, and the focal length.
    let u = x - width as f32 / 2.0;
    let v = y - height as f32 / 2.0;
    let d = Vec3::new(u, v, focal).normalize();
    // Homogeneous coordinates: the eye is the point (0, 0, 0, 1), the direction (d, 0), so
    // the camera's translation moves the origin and not the direction.
    Ray {
        origin: world_from_camera.transform_point3(Vec3::ZERO),
        dir: world_from_camera.transform_vector3(d),
    }
}

/// Ray/triangle, the lecture's A·x = b: o + t·d = v0 + u·(v1 − v0) + v·(v2 − v0), that is
/// [−d, e1, e2]·(t, u, v) = o − v0, solved by Cramer's rule. A hit needs u ≥ 0, v ≥ 0,
/// u + v ≤ 1; returns (t, u, v).
pub fn ray_triangle(ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<(f32, f32, f32)> {
    let (e1, e2, b) = (v1 - v0, v2 - v0, ray.origin - v0);
    let a = -ray.dir;
    // det[p q r] = p · (q × r).
    let det = a.dot(e1.cross(e2));
    if det == 0.0 {
        return None;
    }
    let t = b.dot(e1.cross(e2)) / det;
    let u = a.dot(b.cross(e2)) / det;
    let v = a.dot(e1.cross(b)) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0).then_some((t, u, v))
}

/// Ray/sphere, the lecture's quadratic: |o + t·d − c|² = r², a·t² + b·t + c = 0 with
/// a = d·d, b = 2·d·(o − c), c = |o − c|² − r². Returns the smallest root above `tmin`.
pub fn ray_sphere(ray: &Ray, centre: Vec3, radius: f32, tmin: f32) -> Option<f32> {
    let oc = ray.origin - centre;
    let a = ray.dir.dot(ray.dir);
    let b = 2.0 * ray.dir.dot(oc);
    let c = oc.dot(oc) - radius * radius;
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    [(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)]
        .into_iter()
        .find(|&t| t > tmin)
}

/// The closest-hit search: every shape tried, the nearest hit with tmin < t < tmax kept
/// (a later shape replaces it only when strictly nearer: ties go to the lower index).
pub fn closest_hit(shapes: &[Shape], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
    let mut nearest: Option<Hit> = None;
    for (index, shape) in shapes.iter().enumerate() {
        let found = match *shape {
            Shape::Triangle(Triangle([v0, v1, v2])) => {
                ray_triangle(ray, v0.into(), v1.into(), v2.into())
            }
            Shape::Sphere(Sphere { centre, radius }) => {
                ray_sphere(ray, centre.into(), radius, tmin).map(|t| (t, 0.0, 0.0))
            }
        };
        if let Some((t, u, v)) = found {
            if t > tmin && t < nearest.map_or(tmax, |h| h.t) {
                nearest = Some(Hit { t, index, u, v });
            }
        }
    }
    nearest
}
