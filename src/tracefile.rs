//! The text formats of `raylab trace`, the intersection code's outside interface.
//!
//! Scene file: one primitive per line, `tri x0 y0 z0 x1 y1 z1 x2 y2 z2` or
//! `sphere cx cy cz r`; a primitive's index is its 0-based position among primitive lines;
//! blank lines and lines starting with `#` are skipped. Ray file: one ray per line,
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

/// A parse error with its place.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error("{file}:{line}: {message}")]
pub struct TraceError {
    /// The file name as given.
    pub file: String,
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

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

/// Parses a scene file.
pub fn parse_scene<T: Real>(file: &str, text: &str) -> Result<Vec<Shape<T>>, TraceError> {
    data_lines(text)
        .map(|(line, words)| {
            let shape = match words[0] {
                "tri" => numbers::<T>(&words[1..], 9, "tri").and_then(|x| {
                    all_finite(&x, "tri")?;
                    Ok(Shape::Triangle([
                        [x[0], x[1], x[2]],
                        [x[3], x[4], x[5]],
                        [x[6], x[7], x[8]],
                    ]))
                }),
                "sphere" => numbers::<T>(&words[1..], 4, "sphere").and_then(|x| {
                    all_finite(&x, "sphere")?;
                    if x[3] <= T::zero() {
                        return Err(format!("sphere radius {} must be > 0", x[3]));
                    }
                    Ok(Shape::Sphere {
                        centre: [x[0], x[1], x[2]],
                        radius: x[3],
                    })
                }),
                other => Err(format!(
                    "unknown primitive '{other}' (expected 'tri' or 'sphere')"
                )),
            };
            shape.map_err(|message| TraceError {
                file: file.to_string(),
                line,
                message,
            })
        })
        .collect()
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
    let mut out = String::with_capacity(rays.len() * 24);
    for r in rays {
        match accel::closest_hit(shapes, &r.ray, method, r.tmin, r.tmax) {
            Some(h) => writeln!(out, "hit {} {}", h.t, h.prim),
            None => writeln!(out, "miss"),
        }
        .expect("writing to a String cannot fail");
    }
    out
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
