//! The text formats of `raylab trace`, the intersection code's outside interface.
//!
//! Scene file: the `.scene` format ([`crate::scene::file`]); its simplest form is one
//! primitive per line, `tri x0 y0 z0 x1 y1 z1 x2 y2 z2` or `sphere cx cy cz r`; a primitive's
//! index is its 0-based position among primitives; `#` starts a comment. Ray file: one ray per line,
//! `ox oy oz dx dy dz tmin tmax` (`tmax` may be `inf`); d is used exactly as given (not
//! normalised). Numbers are parsed directly in the chosen precision (correctly rounded, so an
//! f32 run never rounds twice). Output: per ray `hit <t> <index>` or `miss`, t printed with
//! Rust's shortest round-trip formatting.
//!
//! Rejected, with file and line: a wrong count of numbers, junk, NaN, infinite coordinates,
//! a zero direction, tmin > tmax, a radius that is not finite and > 0. Degenerate triangles
//! are accepted (they are never hit).

use crate::accel;
use crate::geometry::{Method, Ray, Shape};
use crate::math::Real;
use std::fmt::Write;
use std::path::Path;

/// A parse error with its place (the scene file's and the ray file's).
pub use crate::scene::file::FileError as TraceError;

/// A ray with its open interval (tmin, tmax).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceRay<T: Real> {
    /// The ray.
    pub ray: Ray<T>,
    /// Lower bound (exclusive).
    pub tmin: T,
    /// Upper bound (exclusive).
    pub tmax: T,
}

/// Lines that carry data: (1-based line number, words), skipping blanks and `#` comments.
fn data_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.trim();
        (!l.is_empty() && !l.starts_with('#')).then(|| (i + 1, l.split_whitespace().collect()))
    })
}

fn numbers<T: Real>(words: &[&str], expect: usize, what: &str) -> Result<Vec<T>, String> {
    if words.len() != expect {
        return Err(format!(
            "{what} needs {expect} numbers, found {}",
            words.len()
        ));
    }
    words
        .iter()
        .map(|w| match w.parse::<T>() {
            Ok(x) if x.is_nan() => Err(format!("'{w}' is NaN")),
            Ok(x) => Ok(x),
            Err(_) => Err(format!("'{w}' is not a number")),
        })
        .collect()
}

fn all_finite<T: Real>(xs: &[T], what: &str) -> Result<(), String> {
    match xs.iter().find(|x| !x.is_finite()) {
        Some(x) => Err(format!("{what} coordinate {x} is not finite")),
        None => Ok(()),
    }
}

/// Parses a scene file: the `.scene` format ([`crate::scene::file`]); meshes it names are
/// read relative to `file`'s directory.
pub fn parse_scene<T: Real>(file: &str, text: &str) -> Result<Vec<Shape<T>>, TraceError> {
    let dir = Path::new(file).parent().unwrap_or(Path::new(""));
    let load_mesh = |p: &Path, frame, color| {
        crate::scene::obj::load_obj_file_coloured(p, frame, color).map_err(|e| e.to_string())
    };
    Ok(crate::scene::file::parse::<T>(file, text, dir, &load_mesh)?.shapes)
}

/// Parses a scene file for the renderer's structures (f32): meshes used repeatedly are placed
/// as instances ([`crate::scene::file::Instancing::DEFAULT`]), so a field of a thousand
/// meshes takes the memory of one; primitive indices are the file's, as with [`parse_scene`].
pub fn parse_scene_instanced(file: &str, text: &str) -> Result<crate::scene::Scene, TraceError> {
    use crate::scene::{cornell, file as scene_file, Scene};
    let dir = Path::new(file).parent().unwrap_or(Path::new(""));
    let load_mesh = |p: &Path, frame, color| {
        crate::scene::obj::load_obj_file_coloured(p, frame, color).map_err(|e| e.to_string())
    };
    let instancing = scene_file::Instancing::DEFAULT;
    let d = scene_file::parse_with::<f32>(file, text, dir, &load_mesh, instancing)?;
    let scene = Scene::new(file, d.shapes, d.colors, cornell::LIGHT, cornell::AMBIENT);
    scene
        .with_instances(d.instances)
        .map_err(|message| TraceError {
            file: file.to_string(),
            line: 0,
            message,
        })
}

/// Parses a ray file.
pub fn parse_rays<T: Real>(file: &str, text: &str) -> Result<Vec<TraceRay<T>>, TraceError> {
    data_lines(text)
        .map(|(line, words)| {
            let parsed = numbers::<T>(&words, 8, "ray").and_then(|x| {
                all_finite(&x[..6], "ray")?;
                let d = [x[3], x[4], x[5]];
                if d.iter().all(|c| *c == T::zero()) {
                    return Err("direction is zero".to_string());
                }
                let (tmin, tmax) = (x[6], x[7]);
                if tmin > tmax {
                    return Err(format!("tmin {tmin} > tmax {tmax}"));
                }
                Ok(TraceRay {
                    ray: Ray::new([x[0], x[1], x[2]], d),
                    tmin,
                    tmax,
                })
            });
            parsed.map_err(|message| TraceError {
                file: file.to_string(),
                line,
                message,
            })
        })
        .collect()
}

/// Traces every ray (nearest hit, ties to the lower index) and returns the output text.
pub fn trace_all<T: Real>(shapes: &[Shape<T>], rays: &[TraceRay<T>], method: Method) -> String {
    answers(rays, |r| {
        accel::closest_hit(shapes, &r.ray, method, r.tmin, r.tmax)
    })
}

/// The output text: per ray `hit <t> <index>` or `miss`, as `closest` answers it.
fn answers<T: Real>(
    rays: &[TraceRay<T>],
    closest: impl Fn(&TraceRay<T>) -> Option<crate::geometry::Hit<T>>,
) -> String {
    let mut out = String::with_capacity(rays.len() * 24);
    for r in rays {
        match closest(r) {
            Some(h) => writeln!(out, "hit {} {}", h.t, h.prim),
            None => writeln!(out, "miss"),
        }
        .expect("writing to a String cannot fail");
    }
    out
}

/// Traces every ray in f32 through an acceleration structure built with `choice` over the
/// scene (its instances included): the per-ray paths the renderer uses (the flat SIMD loop,
/// the BVH, the two-level structure of instances), in the same output format as
/// [`trace_all`].
pub fn trace_all_through(
    scene: &mut crate::scene::Scene,
    rays: &[TraceRay<f32>],
    method: Method,
    choice: accel::AccelChoice,
) -> String {
    scene.set_accel(choice);
    let structure = scene.accel();
    answers(rays, |r| {
        structure.closest_hit(&r.ray, method, r.tmin, r.tmax)
    })
}

/// Parses both texts and traces: the whole `raylab trace` in one call.
pub fn run<T: Real>(
    scene_file: &str,
    scene_text: &str,
    rays_file: &str,
    rays_text: &str,
    method: Method,
) -> Result<String, TraceError> {
    let shapes = parse_scene::<T>(scene_file, scene_text)?;
    let rays = parse_rays::<T>(rays_file, rays_text)?;
    Ok(trace_all(&shapes, &rays, method))
}
