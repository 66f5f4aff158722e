//! OBJ models to scenes, through tobj, with the validation tobj does not do.
//!
//! A first pass over the text checks every `v` and `f` line and names the file and line of the
//! first problem: a coordinate that is not a finite f32 (NaN, inf, 1e39), a face with fewer
//! than 3 vertices, an index of 0 or beyond the vertices defined so far, more triangles or
//! vertices than [`MAX_TRIANGLES`] and [`MAX_VERTICES`] (before any allocation). tobj then parses the
//! text (polygons are fan-triangulated), and triangles of zero area are dropped and counted in
//! a warning. A missing or broken material library is a warning: its faces turn grey.
//!
//! OBJ models are conventionally y-up, while the lab's world is y-down; [`ObjFrame::YUp`]
//! turns them the lab's way, negating x and y (a 180° turn about z, as the lab does to its
//! Cornell box), so they stand upright in the viewer. [`ObjFrame::Lab`] takes the coordinates
//! as they are (for files already in the lab's frame, such as `cornell_lab.obj`).

use super::{PointLight, Scene};
use crate::geometry::Shape;
use std::cell::RefCell;
use std::collections::HashMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// How an OBJ file's coordinates map to the world.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ObjFrame {
    /// The usual y-up model: x and y are negated (upright in the y-down lab world).
    #[default]
    YUp,
    /// Already in the lab's y-down frame: used as is.
    Lab,
}

impl std::str::FromStr for ObjFrame {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "yup" => Ok(ObjFrame::YUp),
            "lab" => Ok(ObjFrame::Lab),
            _ => Err(format!("unknown OBJ frame '{s}' (expected yup or lab)")),
        }
    }
}

/// Largest OBJ file accepted (bytes): a guard against exhausting memory on a wrong file.
pub const MAX_OBJ_BYTES: u64 = crate::input::MAX_INPUT_BYTES;

/// Most triangles (after fan triangulation) and vertices an OBJ may define, checked by the
/// first pass before anything is allocated: about 130 bytes per triangle end to end (tobj's
/// copy, the scene, the BVH), so 16M triangles is about 2 GB. A 1 GB file of long polygons
/// could otherwise ask for 500M triangles. `RAYLAB_MAX_TRIANGLES` overrides the triangle limit.
pub const MAX_TRIANGLES: u64 = 16 << 20;

/// See [`MAX_TRIANGLES`].
pub const MAX_VERTICES: u64 = 16 << 20;

/// The triangle limit in force ([`MAX_TRIANGLES`] unless `RAYLAB_MAX_TRIANGLES` says).
pub fn max_triangles() -> u64 {
    crate::input::limit_from_env("RAYLAB_MAX_TRIANGLES", MAX_TRIANGLES)
}

/// Colour of faces without a material (linear RGB).
pub const DEFAULT_COLOR: [f32; 3] = [0.75, 0.75, 0.75];

/// Why an OBJ could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file could not be read: not a regular file, too large, or an I/O error.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// Not UTF-8 text, or holding NUL bytes.
    #[error("{file}:{line}: not a text OBJ file (binary data or invalid UTF-8)")]
    NotText {
        /// File name.
        file: String,
        /// 1-based line of the first bad byte.
        line: usize,
    },
    /// A problem on one line.
    #[error("{file}:{line}: {message}")]
    Line {
        /// File name.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// tobj refused the file.
    #[error("{file}: {message}")]
    Parse {
        /// File name.
        file: String,
        /// tobj's message.
        message: String,
    },
    /// Nothing to render.
    #[error("{file}: no triangles (after dropping {dropped} degenerate ones)")]
    NoTriangles {
        /// File name.
        file: String,
        /// Zero-area triangles dropped.
        dropped: usize,
    },
}

/// Loads an OBJ file (and the material libraries it names, relative to it) as a scene, with
/// a light placed for its size.
pub fn load_obj_file(path: &Path, frame: ObjFrame) -> Result<Scene, ObjError> {
    load_obj_file_coloured(path, frame, DEFAULT_COLOR)
}

/// [`load_obj_file`] with `default` as the colour of faces that name no material with a
/// diffuse colour (a `.scene` file's current `color`).
pub fn load_obj_file_coloured(
    path: &Path,
    frame: ObjFrame,
    default: [f32; 3],
) -> Result<Scene, ObjError> {
    let bytes = crate::input::read_bytes(path, crate::input::max_input_bytes())?;
    let name = path.display().to_string();
    let text = to_text(&name, bytes)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    load_obj_str_coloured(&name, &text, frame, default, |mtl: &str| {
        let p = dir.join(mtl);
        crate::input::read_text(&p, crate::input::max_input_bytes()).map_err(|e| e.to_string())
    })
}

fn to_text(name: &str, bytes: Vec<u8>) -> Result<String, ObjError> {
    let line_of =
        |bytes: &[u8], pos: usize| 1 + bytes[..pos].iter().filter(|&&b| b == b'\n').count();
    if let Some(pos) = bytes.iter().position(|&b| b == 0) {
        return Err(ObjError::NotText {
            file: name.to_string(),
            line: line_of(&bytes, pos),
        });
    }
    String::from_utf8(bytes).map_err(|e| {
        let pos = e.utf8_error().valid_up_to();
        ObjError::NotText {
            file: name.to_string(),
            line: line_of(e.as_bytes(), pos),
        }
    })
}

/// Loads OBJ text; `load_mtl(name)` returns the text of the material library `name`.
pub fn load_obj_str(
    name: &str,
    text: &str,
    frame: ObjFrame,
    load_mtl: impl Fn(&str) -> Result<String, String>,
) -> Result<Scene, ObjError> {
    load_obj_str_coloured(name, text, frame, DEFAULT_COLOR, load_mtl)
}

/// [`load_obj_str`] with `default` as the colour of faces without a diffuse material colour.
fn load_obj_str_coloured(
    name: &str,
    text: &str,
    frame: ObjFrame,
    default: [f32; 3],
    load_mtl: impl Fn(&str) -> Result<String, String>,
) -> Result<Scene, ObjError> {
    // A UTF-8 byte-order mark is no part of the first statement.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if let Some(pos) = text.find('\0') {
        return Err(ObjError::NotText {
            file: name.to_string(),
            line: 1 + text[..pos].matches('\n').count(),
        });
    }
    prescan(name, text)?;

    // Each library is read once however often `mtllib` names it; problems become warnings.
    let warnings = RefCell::new(Vec::<String>::new());
    let cache = RefCell::new(HashMap::<PathBuf, Result<String, String>>::new());
    let loader = |p: &Path| -> tobj::MTLLoadResult {
        let text = cache
            .borrow_mut()
            .entry(p.to_path_buf())
            .or_insert_with(|| load_mtl(&p.to_string_lossy()))
            .clone();
        let problem = match text {
            Ok(t) => match check_mtl(&t) {
                Ok(()) => return tobj::load_mtl_buf(&mut Cursor::new(t.as_bytes())),
                Err((line, m)) => format!("{}:{line}: {m}", p.display()),
            },
            Err(e) => e,
        };
        warnings
            .borrow_mut()
            .push(format!("{name}: material library skipped: {problem}"));
        Err(tobj::LoadError::MaterialParseError)
    };
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, materials) =
        tobj::load_obj_buf(&mut Cursor::new(text.as_bytes()), &options, loader).map_err(|e| {
            ObjError::Parse {
                file: name.to_string(),
                message: format!("tobj: {e}"),
            }
        })?;
    let mut warnings = warnings.into_inner();
    let materials = materials.unwrap_or_else(|e| {
        if warnings.is_empty() {
            warnings.push(format!("{name}: material library: {e}"));
        }
        Vec::new()
    });
    let colors: Vec<[f32; 3]> = materials
        .iter()
        .map(|m| match m.diffuse {
            Some(kd) if kd.iter().all(|c| c.is_finite()) => kd.map(|c| c.clamp(0.0, 1.0)),
            _ => default,
        })
        .collect();

    let dark = PointLight {
        position: [0.0; 3],
        power: [0.0; 3],
    };
    let mut scene = Scene::new(name, Vec::new(), Vec::new(), dark, [0.5; 3]);
    let mut dropped = 0usize;
    for model in &models {
        let mesh = &model.mesh;
        let color = mesh
            .material_id
            .and_then(|id| colors.get(id).copied())
            .unwrap_or(default);
        let vertex = |i: u32| -> Option<[f32; 3]> {
            let k = 3 * i as usize;
            mesh.positions.get(k..k + 3).map(|p| match frame {
                ObjFrame::YUp => [-p[0], -p[1], p[2]],
                ObjFrame::Lab => [p[0], p[1], p[2]],
            })
        };
        for tri in mesh.indices.chunks_exact(3) {
            let (Some(a), Some(b), Some(c)) = (vertex(tri[0]), vertex(tri[1]), vertex(tri[2]))
            else {
                return Err(ObjError::Parse {
                    file: name.to_string(),
                    message: format!("model '{}': face index out of range", model.name),
                });
            };
            if zero_area(a, b, c) {
                dropped += 1;
                continue;
            }
            scene.shapes.push(Shape::Triangle([a, b, c]));
            scene.colors.push(color);
        }
    }
    if dropped > 0 {
        warnings.push(format!(
            "{name}: dropped {dropped} degenerate (zero-area) triangles"
        ));
    }
    // (Whoever loads the scene shows its warnings: the CLI prints them, the window's panel.)
    scene.warnings = warnings;
    let Some(bounds) = scene.bounds() else {
        return Err(ObjError::NoTriangles {
            file: name.to_string(),
            dropped,
        });
    };
    scene.light = Scene::light_for_bounds(bounds);
    Ok(scene)
}

/// Whether the triangle has zero area, decided in f64 (where the edge vectors of f32
/// vertices are exact for any sane model).
fn zero_area(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> bool {
    let e1 = [0, 1, 2].map(|k| b[k] as f64 - a[k] as f64);
    let e2 = [0, 1, 2].map(|k| c[k] as f64 - a[k] as f64);
    let n = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    n == [0.0; 3]
}

/// Checks a material library for what tobj 4 panics on (a colour with fewer than three
/// numbers: it unwraps a failed conversion) and names the line.
fn check_mtl(text: &str) -> Result<(), (usize, String)> {
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            let numbers = words.take(3).filter(|w| w.parse::<f32>().is_ok()).count();
            if numbers < 3 {
                return Err((i + 1, format!("{key} needs 3 numbers, found {numbers}")));
            }
        }
    }
    Ok(())
}

/// Checks what tobj silently accepts or reports without a line number.
fn prescan(name: &str, text: &str) -> Result<(), ObjError> {
    let (mut nv, mut nvt, mut nvn) = (0i64, 0i64, 0i64);
    let mut triangles = 0u64;
    let max_tris = max_triangles();
    for (i, line) in text.lines().enumerate() {
        let err = |message: String| ObjError::Line {
            file: name.to_string(),
            line: i + 1,
            message,
        };
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let coords: Vec<&str> = words.collect();
                if coords.len() < 3 {
                    return Err(err(format!(
                        "vertex needs 3 coordinates, found {}",
                        coords.len()
                    )));
                }
                for w in coords {
                    match w.parse::<f32>() {
                        Ok(x) if x.is_finite() => {}
                        Ok(_) => {
                            return Err(err(format!("coordinate '{w}' is not a finite f32")));
                        }
                        Err(_) => return Err(err(format!("coordinate '{w}' is not a number"))),
                    }
                }
                nv += 1;
                if nv as u64 > MAX_VERTICES {
                    return Err(err(format!(
                        "more than {MAX_VERTICES} vertices: too large a model to load"
                    )));
                }
            }
            Some("vt") => nvt += 1,
            Some("vn") => nvn += 1,
            Some("f") => {
                let refs: Vec<&str> = words.collect();
                if refs.len() < 3 {
                    return Err(err(format!(
                        "face needs at least 3 vertices, found {}",
                        refs.len()
                    )));
                }
                triangles += refs.len() as u64 - 2;
                if triangles > max_tris {
                    return Err(err(format!(
                        "the faces so far make more than {max_tris} triangles: too large a \
                         model to load (RAYLAB_MAX_TRIANGLES raises the limit)"
                    )));
                }
                for r in refs {
                    let mut parts = r.split('/');
                    for (k, count, what) in
                        [(0, nv, "vertex"), (1, nvt, "texture"), (2, nvn, "normal")]
                    {
                        let Some(part) = parts.next() else { break };
                        if part.is_empty() && k > 0 {
                            continue;
                        }
                        check_index(part, count, what)
                            .map_err(|m| err(format!("face '{r}': {m}")))?;
                    }
                    if parts.next().is_some() {
                        return Err(err(format!(
                            "face '{r}': more than 3 '/'-separated indices"
                        )));
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

fn check_index(word: &str, count: i64, what: &str) -> Result<(), String> {
    let idx: i64 = word
        .parse()
        .map_err(|_| format!("{what} index '{word}' is not an integer"))?;
    let ok = (idx > 0 && idx <= count) || (idx < 0 && -idx <= count);
    if ok {
        Ok(())
    } else {
        Err(format!(
            "{what} index {idx} is out of range ({count} {what}s defined so far; OBJ indices start at 1)"
        ))
    }
}
