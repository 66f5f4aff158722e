//! The text formats of `raylab trace`, the intersection code's outside interface.
//!
//! Scene file: the `.scene` format ([`crate::scene::file`]); its simplest form is one
//! primitive per line, `tri x0 y0 z0 x1 y1 z1 x2 y2 z2` or `sphere cx cy cz r`; a primitive's
//! index is its 0-based position among primitives; `#` starts a comment. Ray file: one ray per line,
//! `ox oy oz dx dy dz tmin tmax` (`tmax` may be `inf`); d is used exactly as given (not
//! normalised). Numbers are parsed directly in the chosen precision (correctly rounded, so an
//! f32 run never rounds twice). Output of the nearest-hit query: per ray `hit <t> <index>` or
//! `miss`, t printed with Rust's shortest round-trip formatting. With the adaptive method t is
//! the exact t correctly rounded to the chosen precision, whichever path found the primitive
//! ([`adaptive::rounded_t`]); the other methods print the t they computed. Output of the
//! any-hit query ([`Query::Any`], a shadow ray's question): per ray `hit` or `miss`.
//!
//! Rejected, with file and line: a wrong count of numbers, junk, NaN, infinite coordinates,
//! a zero direction, tmin > tmax, a radius that is not finite and > 0. A triangle of zero
//! area is accepted and keeps its index, but no method on any path hits it (a warning names
//! its line).

use crate::accel;
use crate::geometry::{adaptive, Method, Ray, Shape};
use crate::math::Real;
use rayon::prelude::*;
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

/// The most words of a ray line kept: one past a ray's 8, enough to say there are too many
/// without holding every word of an arbitrarily long line (they are counted, not kept).
const RAY_WORDS_KEPT: usize = 9;

/// Lines that carry data: (1-based line number, its first [`RAY_WORDS_KEPT`] words, its
/// number of words), skipping blanks and `#` comments.
fn data_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>, usize)> {
    text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.trim();
        let words: Vec<&str> = l.split_whitespace().take(RAY_WORDS_KEPT).collect();
        let count = match words.len() < RAY_WORDS_KEPT {
            true => words.len(),
            false => l.split_whitespace().count(),
        };
        (!l.is_empty() && !l.starts_with('#')).then_some((i + 1, words, count))
    })
}

/// The `expect` numbers of a line of `count` words (`words`: its first ones).
fn numbers<T: Real>(
    (words, count): (&[&str], usize),
    expect: usize,
    what: &str,
) -> Result<Vec<T>, String> {
    if count != expect {
        // (A comment after the numbers counted as numbers: "found 10" for 8 and "# note".)
        let comment = match words.iter().any(|w| w.starts_with('#')) {
            true => " (a `#` comment takes a line of its own)",
            false => "",
        };
        return Err(format!(
            "{what} needs {expect} numbers, found {count} words{comment}"
        ));
    }
    words
        .iter()
        .map(|w| {
            let shown = crate::words::shown(w);
            match w.parse::<T>() {
                Ok(x) if x.is_nan() => Err(format!("'{shown}' is NaN")),
                Ok(x) => Ok(x),
                Err(_) => Err(format!("'{shown}' is not a number")),
            }
        })
        .collect()
}

/// Whether the coordinates `xs`, read from `words`, are finite; else the first that is not,
/// as written (1e39 overflows f32: the message said `inf`).
fn all_finite<T: Real>(xs: &[T], words: &[&str], what: &str) -> Result<(), String> {
    match xs.iter().zip(words).find(|(x, _)| !x.is_finite()) {
        Some((_, w)) if !w.to_ascii_lowercase().contains("inf") => Err(format!(
            "{what} coordinate {} is not finite in this precision",
            crate::words::shown(w)
        )),
        Some((x, _)) => Err(format!("{what} coordinate {x} is not finite")),
        None => Ok(()),
    }
}

/// Parses a scene file: the `.scene` format ([`crate::scene::file`]); meshes it names are
/// read relative to `file`'s directory. Returns the primitives and the warnings (a triangle
/// of zero area, kept but never hit, with its line), which the caller shows (the command line
/// prints them as it prints a rendered scene's).
pub fn parse_scene<T: Real>(
    file: &str,
    text: &str,
) -> Result<(Vec<Shape<T>>, Vec<String>), TraceError> {
    let dir = Path::new(file).parent().unwrap_or(Path::new(""));
    let load_mesh = crate::scene::file::load_obj_mesh;
    let d = crate::scene::file::parse::<T>(file, text, dir, &load_mesh)?;
    Ok((d.shapes, d.warnings))
}

/// Parses a scene file for the renderer's structures (f32): meshes used repeatedly are placed
/// as instances ([`crate::scene::file::Instancing::DEFAULT`]), so a field of a thousand
/// meshes takes the memory of one; primitive indices are the file's, as with [`parse_scene`].
/// The warnings are the scene's `warnings`, for the caller to show.
pub fn parse_scene_instanced(file: &str, text: &str) -> Result<crate::scene::Scene, TraceError> {
    use crate::scene::{cornell, file as scene_file, Scene};
    let dir = Path::new(file).parent().unwrap_or(Path::new(""));
    let instancing = scene_file::Instancing::DEFAULT;
    let load_mesh = scene_file::load_obj_mesh;
    let d = scene_file::parse_with::<f32>(file, text, dir, &load_mesh, instancing)?;
    let mut scene = Scene::new(file, d.shapes, d.colors, cornell::LIGHT, cornell::AMBIENT);
    scene.warnings = d.warnings;
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
    Ok(parse_rays_at_lines(file, text)?
        .into_iter()
        .map(|(_, ray)| ray)
        .collect())
}

/// Parses a ray file: each ray with its 1-based line number.
pub fn parse_rays_at_lines<T: Real>(
    file: &str,
    text: &str,
) -> Result<Vec<(usize, TraceRay<T>)>, TraceError> {
    data_lines(text)
        .map(|(line, words, count)| {
            let parsed = numbers::<T>((&words, count), 8, "ray").and_then(|x| {
                all_finite(&x[..6], &words[..6], "ray")?;
                let d = [x[3], x[4], x[5]];
                if d.iter().all(|c| *c == T::zero()) {
                    return Err("direction is zero".to_string());
                }
                let (tmin, tmax) = (x[6], x[7]);
                if tmin > tmax {
                    return Err(format!("tmin {tmin} > tmax {tmax}"));
                }
                Ok((
                    line,
                    TraceRay {
                        ray: Ray::new([x[0], x[1], x[2]], d),
                        tmin,
                        tmax,
                    },
                ))
            });
            parsed.map_err(|message| TraceError {
                file: file.to_string(),
                line,
                message,
            })
        })
        .collect()
}

impl<T: Real> TraceRay<T> {
    /// `ray` over its whole length: tmin = 0 and tmax = ∞ (a camera ray, every suite ray).
    pub fn whole(ray: Ray<T>) -> Self {
        Self {
            ray,
            tmin: T::zero(),
            tmax: T::infinity(),
        }
    }

    /// The ray as a line of a ray file (`ox oy oz dx dy dz tmin tmax`), each number written exactly
    /// ([`crate::math::real::exact_decimal`]: the same value read in f32, f64 or exact
    /// arithmetic).
    pub fn line(&self) -> String {
        let o = self.ray.o.iter();
        let numbers: Vec<String> = (o.chain(&self.ray.d).chain([&self.tmin, &self.tmax]))
            .map(|x| crate::math::real::exact_decimal(x.f64()))
            .collect();
        numbers.join(" ")
    }
}

/// What `raylab trace` asks of each ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Query {
    /// The nearest hit with tmin < t < tmax (ties to the lower index): `hit <t> <index>` or
    /// `miss`.
    Nearest,
    /// Whether anything is hit with tmin < t < tmax (a shadow ray's question): `hit` or
    /// `miss`.
    Any,
}

/// Traces every ray and returns the output text.
pub fn trace_all<T: Real>(
    shapes: &[Shape<T>],
    rays: &[TraceRay<T>],
    method: Method,
    query: Query,
) -> String {
    match query {
        Query::Nearest => answers(
            rays,
            method,
            |p| shapes[p as usize],
            |_, r| accel::closest_hit(shapes, &r.ray, method, r.tmin, r.tmax),
        ),
        Query::Any => any_answers(rays, |_, r| {
            accel::any_hit(shapes, &r.ray, method, r.tmin, r.tmax, u32::MAX)
        }),
    }
}

/// The output text: per ray `hit <t> <index>` or `miss`, as `closest` answers it (given the
/// ray's position and the ray). For the
/// adaptive method t is the exact t correctly rounded ([`adaptive::rounded_t`]), whichever
/// path found the primitive; the other methods print their own t. Rays are answered on every
/// core, in chunks, and printed in their order.
fn answers<T: Real>(
    rays: &[TraceRay<T>],
    method: Method,
    shape_of: impl Fn(u32) -> Shape<T> + Sync,
    closest: impl Fn(usize, &TraceRay<T>) -> Option<crate::geometry::Hit<T>> + Sync,
) -> String {
    in_chunks(rays, 24, |i, r, out| {
        match closest(i, r) {
            Some(h) => {
                let t = match method {
                    Method::Adaptive => {
                        adaptive::rounded_t(&shape_of(h.prim), &r.ray, r.tmin, r.tmax)
                            .unwrap_or(h.t)
                    }
                    _ => h.t,
                };
                writeln!(out, "hit {} {}", t, h.prim)
            }
            None => writeln!(out, "miss"),
        }
        .expect("writing to a String cannot fail");
    })
}

/// The output text of [`Query::Any`]: per ray `hit` or `miss`, as `any` answers it (on every
/// core, as [`answers`]).
fn any_answers<T: Real>(
    rays: &[TraceRay<T>],
    any: impl Fn(usize, &TraceRay<T>) -> bool + Sync,
) -> String {
    in_chunks(rays, 5, |i, r, out| {
        out.push_str(if any(i, r) { "hit\n" } else { "miss\n" })
    })
}

/// `line(position, ray, out)` for every ray, chunks of rays on every core, the text in the rays' order
/// (`bytes`: a line's usual length).
fn in_chunks<T: Real>(
    rays: &[TraceRay<T>],
    bytes: usize,
    line: impl Fn(usize, &TraceRay<T>, &mut String) + Sync,
) -> String {
    const CHUNK: usize = 256;
    let parts: Vec<String> = (rays.par_chunks(CHUNK).enumerate())
        .map(|(k, chunk)| {
            let mut out = String::with_capacity(chunk.len() * bytes);
            for (i, r) in chunk.iter().enumerate() {
                line(k * CHUNK + i, r, &mut out);
            }
            out
        })
        .collect();
    parts.concat()
}

/// Traces every ray in f32 through `structure`, an acceleration structure built over the
/// scene (its instances included, [`accel::Accel::for_scene`]): the per-ray paths the renderer
/// uses (the flat SIMD loop, the BVH, the two-level structure of instances), in the same
/// output format as [`trace_all`].
pub fn trace_all_through(
    scene: &crate::scene::Scene,
    structure: &accel::Accel,
    rays: &[TraceRay<f32>],
    method: Method,
    query: Query,
) -> String {
    match query {
        Query::Nearest => answers(
            rays,
            method,
            |p| scene.shape(p),
            |_, r| structure.closest_hit(&r.ray, method, r.tmin, r.tmax),
        ),
        Query::Any => any_answers(rays, |_, r| {
            structure.any_hit(&r.ray, method, r.tmin, r.tmax, u32::MAX)
        }),
    }
}

/// The most spheres per ray of an origin for [`trace_all_packets`] to trace its rays as a
/// frame.
const SPHERES_PER_FRAME_RAY: usize = 64;

/// Traces every ray in f32 through the renderer's own face on `structure` (built over the
/// scene as the renderer builds it, [`accel::AccelChoice::Auto`]), the queries of a frame
/// ([`accel::FrameQueries`], adaptive method), as the renderer traces a frame: rays sharing
/// an origin go 8 at a time, [`Query::Nearest`] rays with tmin = 0 and tmax = ∞ as
/// camera rays from that origin (the eye), [`Query::Any`] rays with tmin = 0 and tmax = 1 as
/// shadow segments from it (the light; none skips a primitive). Each origin is one frame
/// without tile culling (the rays are not on a pixel grid), so the frame picks its plan as
/// for the renderer: a small scene's triangles prepared for the origin, the packets through
/// the BVH and the instances (the triangles prepared once where there are at least as many
/// rays as stored triangles, else as met), spheres lane by lane, the ambiguous lanes through
/// the exact resolvers and per ray. Other rays go per ray through the scene's structure, as
/// do those of an origin with fewer than 1/64 as many rays as the scene has spheres.
/// Same output format as [`trace_all`]; a nearest hit's t is the adaptive t of its primitive.
pub fn trace_all_packets(
    scene: &crate::scene::Scene,
    structure: &accel::Accel,
    rays: &[TraceRay<f32>],
    query: Query,
) -> String {
    use crate::accel::{FrameSetup, ShadowSegments, TileScratch, NO_HIT};
    use wide::f32x8;
    let tmax_of_group = match query {
        Query::Nearest => f32::INFINITY,
        Query::Any => 1.0,
    };
    // Rays that fit the frame's queries, grouped by their origin's bits in order of first
    // appearance.
    let mut groups: Vec<([f32; 3], Vec<usize>)> = Vec::new();
    let mut group_of = std::collections::HashMap::new();
    for (i, r) in rays.iter().enumerate() {
        if r.tmin != 0.0 || r.tmax != tmax_of_group {
            continue;
        }
        let key = r.ray.o.map(f32::to_bits);
        let g = *group_of.entry(key).or_insert_with(|| {
            groups.push((r.ray.o, Vec::new()));
            groups.len() - 1
        });
        groups[g].1.push(i);
    }
    // Per ray: Some(prim or NO_HIT) for a nearest query, Some(1 or 0) for an any-hit query.
    let mut found: Vec<Option<u32>> = vec![None; rays.len()];
    let mut scratch = TileScratch::default();
    // A frame sees every sphere from its origin first: an origin with few rays beside many
    // spheres goes per ray, so that many origins never cost origins × spheres.
    let spheres = structure.spheres().len();
    for (o, members) in &groups {
        if spheres > SPHERES_PER_FRAME_RAY * members.len() {
            continue;
        }
        let frame = structure.for_frame(&FrameSetup {
            eye: *o,
            light: *o,
            projection: None,
            method: Method::Adaptive,
            camera_rays: members.len(),
            shadows: query == Query::Any,
            per_ray: false,
        });
        let mut tile = frame.tile([0, 0, 1, 1], &mut scratch);
        let lanes_of = |chunk: &[usize]| {
            let dirs: [[f32; 3]; 8] =
                std::array::from_fn(|l| chunk.get(l).map_or([0.0; 3], |&i| rays[i].ray.d));
            [0, 1, 2].map(|k| f32x8::from(dirs.map(|v| v[k])))
        };
        match query {
            Query::Nearest => {
                for chunk in members.chunks(8) {
                    let prims = match tile.packets() {
                        true => tile.closest_x8(&lanes_of(chunk), (1 << chunk.len()) - 1),
                        false => std::array::from_fn(|l| match chunk.get(l) {
                            Some(&i) => tile.closest(&rays[i].ray).map_or(NO_HIT, |h| h.prim),
                            None => NO_HIT,
                        }),
                    };
                    for (&i, prim) in chunk.iter().zip(prims) {
                        found[i] = Some(prim);
                    }
                }
            }
            Query::Any => {
                let segments: Vec<ShadowSegments> = (members.chunks(8))
                    .map(|chunk| ShadowSegments {
                        d: lanes_of(chunk),
                        prim: [u32::MAX; 8],
                        live: (1u32 << chunk.len()) - 1,
                        own_blocks: 0,
                    })
                    .collect();
                let mut blocked = Vec::new();
                tile.any_x8(&segments, &mut blocked);
                for (chunk, mask) in members.chunks(8).zip(blocked) {
                    for (l, &i) in chunk.iter().enumerate() {
                        found[i] = Some(mask >> l & 1);
                    }
                }
            }
        }
    }
    match query {
        Query::Nearest => answers(
            rays,
            Method::Adaptive,
            |p| scene.shape(p),
            |i, r| match found[i] {
                Some(NO_HIT) => None,
                // t: `answers` prints the primitive's adaptive t (NaN would show a primitive
                // the ray does not hit).
                Some(prim) => Some(crate::geometry::Hit {
                    t: f32::NAN,
                    prim,
                    b1: 0.0,
                    b2: 0.0,
                }),
                None => structure.closest_hit(&r.ray, Method::Adaptive, r.tmin, r.tmax),
            },
        ),
        Query::Any => any_answers(rays, |i, r| match found[i] {
            Some(blocked) => blocked == 1,
            None => structure.any_hit(&r.ray, Method::Adaptive, r.tmin, r.tmax, u32::MAX),
        }),
    }
}

/// Parses both texts and traces: the whole `raylab trace` in one call. Returns the output
/// text and the scene's warnings ([`parse_scene`]), for the caller to show.
pub fn run<T: Real>(
    scene_file: &str,
    scene_text: &str,
    rays_file: &str,
    rays_text: &str,
    method: Method,
    query: Query,
) -> Result<(String, Vec<String>), TraceError> {
    let (shapes, warnings) = parse_scene::<T>(scene_file, scene_text)?;
    let rays = parse_rays::<T>(rays_file, rays_text)?;
    Ok((trace_all(&shapes, &rays, method, query), warnings))
}
