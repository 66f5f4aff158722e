//! OBJ models to scenes, through tobj, with every line checked first.
//!
//! A counting pass refuses a file whose faces (and polylines and points, which count although
//! they are skipped) make more triangles than [`max_triangles`], or that defines more than
//! [`MAX_VERTICES`] vertices, before anything is allocated. Then tobj reads the text through
//! `ObjStream`, which checks each line and hands tobj only what it cannot misread: `v x y z`
//! (a weight w divided out with the overflow checked, vertex colours dropped), `f` with
//! absolute vertex indices (negative ones resolved without overflow, every index checked,
//! texture and normal references checked and dropped), `mtllib`/`usemtl` with their names,
//! and nothing else. So every error names the file and line: a coordinate that is not a
//! finite f32 (NaN, inf, 1e39), a face with fewer than 3 vertices, an index of 0 or beyond what
//! is defined so far, a bare `usemtl`. Polylines (`l`), points (`p`) and free-form curves and
//! surfaces are skipped with one warning that counts them. TABs are whitespace everywhere,
//! `#` starts a comment anywhere on a line, and a UTF-8 byte-order mark is skipped. Polygons
//! are fan-triangulated. A triangle of zero area (vertices on one line) is kept, so that every
//! index stays its file position, but no ray hits it; a warning names its line. A file of
//! only such triangles is refused loaded on its own (nothing to show), and loads as a
//! `.scene` file's mesh (as `tri` lines of zero area do). A missing or broken material
//! library is a warning naming the library's line: its faces turn grey, as do those of a
//! `usemtl` no library defines (also a warning).
//!
//! OBJ models are conventionally y-up and face +z (towards a viewer at +z looking down −z),
//! while the lab's world is y-down and its camera looks along +z; [`ObjFrame::YUp`] turns
//! them the lab's way, negating y and z (a 180° turn about x), so they stand upright and face
//! the camera, as in any viewer. [`ObjFrame::Lab`] takes the coordinates as they are (for
//! files already in the lab's frame, such as `cornell_lab.obj`).

mod stream;

use super::{PointLight, Scene};
use crate::geometry::Shape;
use std::cell::RefCell;
use std::collections::HashMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use stream::ObjStream;

/// How an OBJ file's coordinates map to the world.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ObjFrame {
    /// The usual y-up model facing +z: y and z are negated (upright in the y-down lab world,
    /// facing its camera).
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

/// The triangle limit in force ([`MAX_TRIANGLES`] unless `RAYLAB_MAX_TRIANGLES` says; at
/// most what a BVH holds, [`crate::limits::MAX_HIERARCHY_ITEMS`]).
pub fn max_triangles() -> u64 {
    let limit = crate::input::limit_from_env("RAYLAB_MAX_TRIANGLES", MAX_TRIANGLES);
    limit.min(crate::limits::MAX_HIERARCHY_ITEMS as u64)
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
    #[error(
        "{file}:{line}: not a text OBJ file (binary data, or invalid UTF-8 outside a comment \
         or name)"
    )]
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
    /// No faces: nothing to render.
    #[error("{file}: no triangles{hint}")]
    NoTriangles {
        /// File name.
        file: String,
        /// Why, where the name may say: a file not named `.obj` was read as one.
        hint: &'static str,
    },
    /// A model loaded on its own with a triangle beyond the range raylab renders: the
    /// message names the face's line and the coordinate.
    #[error("{0}")]
    OutOfRange(String),
    /// A model loaded on its own whose every face has zero area: nothing a ray could hit, so
    /// nothing to show. (As a `.scene` file's mesh it loads, as such `tri` lines do.)
    #[error("{file}: has no triangle of nonzero area ({count} of zero area)")]
    OnlyZeroArea {
        /// File name.
        file: String,
        /// Its triangles, all of zero area.
        count: usize,
    },
}

/// What an error on file `name` adds where its name does not end in `.obj`: any name but
/// `.scene` is read as an OBJ (README.md opened by mistake failed on its line 122 with
/// "vertex takes 3 numbers", not saying why its words were vertices).
pub(super) fn read_as_obj_hint(name: &str) -> &'static str {
    let name = name.to_ascii_lowercase();
    match (name.ends_with(".obj"), name.ends_with(".view")) {
        (true, _) => "",
        // (A view names a scene; a `mesh` line or a view's `scene` naming one read it as
        // a model.)
        (false, true) => {
            " (read as an OBJ file: a .view is opened on its own, by `raylab FILE.view` or \
             `render --view`, and names a .scene or .obj itself)"
        }
        // (A `.scene` named where a model goes, by a `mesh` line, was told that a scene
        // file's name ends in .scene.)
        (false, false) if name.ends_with(".scene") => {
            " (read as an OBJ file: a `mesh` line places a model, an OBJ file; a .scene file is \
             opened on its own)"
        }
        (false, false) => " (read as an OBJ file: a scene file's name ends in .scene)",
    }
}

/// Loads an OBJ file (and the material libraries it names, relative to it) as a scene, with
/// a light placed for its size. A file whose every triangle has zero area is refused: there
/// is nothing to show.
pub fn load_obj_file(path: &Path, frame: ObjFrame) -> Result<Scene, ObjError> {
    on_its_own(read_obj_file(path, frame, DEFAULT_COLOR)?)
}

/// A model loaded on its own, refused where every triangle has zero area (a mesh in a
/// `.scene` file is not: the file may hold more, and its `tri` lines may be such triangles),
/// or where a triangle lies beyond the range raylab renders ([`Scene::check_ranges`]; the
/// error names the face's line: a `.scene` file may scale such a mesh into range).
fn on_its_own((scene, face_lines): (Scene, Vec<u32>)) -> Result<Scene, ObjError> {
    // (The first triangle with area ends the look.)
    if scene.shapes.iter().all(Shape::is_degenerate) {
        return Err(ObjError::OnlyZeroArea {
            file: scene.name.clone(),
            count: scene.shapes.len(),
        });
    }
    let line_of = |index: u32| face_lines.get(index as usize).map(|&line| line as usize);
    scene
        .check_ranges_at(&line_of)
        .map_err(ObjError::OutOfRange)?;
    Ok(scene)
}

/// [`load_obj_file`] with `default` as the colour of faces that name no material with a
/// diffuse colour (a `.scene` file's current `color`), as a `.scene` file's `mesh` loads it:
/// triangles of zero area only are a mesh (with their warning), no faces at all an error.
pub fn load_obj_file_coloured(
    path: &Path,
    frame: ObjFrame,
    default: [f32; 3],
) -> Result<Scene, ObjError> {
    Ok(read_obj_file(path, frame, default)?.0)
}

/// [`load_obj_file_coloured`], with the source line of each triangle.
fn read_obj_file(
    path: &Path,
    frame: ObjFrame,
    default: [f32; 3],
) -> Result<(Scene, Vec<u32>), ObjError> {
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
    // (A comment, or an object's or group's name, may be in another encoding, as exporters
    // write Latin-1 names: only shown, their bytes that are not UTF-8 become U+FFFD.)
    let names = |line: &[u8]| {
        let first = line
            .split(u8::is_ascii_whitespace)
            .next()
            .unwrap_or_default();
        first.starts_with(b"#") || first == b"o" || first == b"g"
    };
    let text = crate::input::lossy_where(bytes, names).map_err(|line| ObjError::NotText {
        file: name.to_string(),
        line,
    })?;
    Ok(crate::input::lone_cr_as_lf(text))
}

/// Loads OBJ text as a model on its own ([`load_obj_file`]); `load_mtl(name)` returns the
/// text of the material library `name`.
pub fn load_obj_str(
    name: &str,
    text: &str,
    frame: ObjFrame,
    load_mtl: impl Fn(&str) -> Result<String, String>,
) -> Result<Scene, ObjError> {
    on_its_own(load_obj_str_coloured(
        name,
        text,
        frame,
        DEFAULT_COLOR,
        load_mtl,
    )?)
}

/// The line of the first `mtllib` statement of `text` that names `library` (as tobj passes
/// it: the rest of the line).
fn mtllib_line(text: &str, library: &str) -> Option<usize> {
    let names = |line: &str| {
        let rest = line.trim_start().strip_prefix("mtllib")?;
        let rest = rest.split('#').next().unwrap_or_default();
        (rest.starts_with(char::is_whitespace) && rest.trim() == library).then_some(())
    };
    text.lines().position(|l| names(l).is_some()).map(|i| i + 1)
}

/// [`load_obj_str`] with `default` as the colour of faces without a diffuse material colour;
/// with the source line of each triangle.
fn load_obj_str_coloured(
    name: &str,
    text: &str,
    frame: ObjFrame,
    default: [f32; 3],
    load_mtl: impl Fn(&str) -> Result<String, String>,
) -> Result<(Scene, Vec<u32>), ObjError> {
    // A UTF-8 byte-order mark is no part of the first statement.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if let Some(pos) = text.find('\0') {
        return Err(ObjError::NotText {
            file: name.to_string(),
            line: 1 + text[..pos].matches('\n').count(),
        });
    }
    let counts = count_elements(name, text)?;

    // Each library is read once however often `mtllib` names it, and parsed once however it
    // is spelled or linked (by its text): its materials come once, a repeat gives none (200
    // names of one 4.5 MB library on a line were parsed 200 times: 44 s, and as links each
    // text was kept). Problems become warnings.
    let warnings = RefCell::new(Vec::<String>::new());
    let skipped = std::cell::Cell::new(false);
    let read = RefCell::new(HashMap::<PathBuf, Result<(), String>>::new());
    let parsed = RefCell::new(std::collections::HashSet::<(usize, u64)>::new());
    let library = |p: &Path| -> Result<Materials, String> {
        if let Some(seen) = read.borrow().get(p) {
            return seen.clone().map(|()| Materials::default());
        }
        let text = load_mtl(&p.to_string_lossy());
        read.borrow_mut().insert(
            p.to_path_buf(),
            text.as_ref().map(|_| ()).map_err(Clone::clone),
        );
        let text = text?;
        let identity = (text.len(), {
            use std::hash::{Hash, Hasher};
            let mut hasher = std::collections::hash_map::DefaultHasher::new();
            text.hash(&mut hasher);
            hasher.finish()
        });
        if !parsed.borrow_mut().insert(identity) {
            return Ok(Materials::default());
        }
        let (materials, notes) =
            load_mtl_text(&text).map_err(|(line, m)| format!("{}:{line}: {m}", p.display()))?;
        for (line, note) in notes {
            let note = format!("{name}: {}:{line}: {note}", p.display());
            warnings.borrow_mut().push(note);
        }
        Ok(materials)
    };
    // (At the `mtllib` line that names it: the warning named the OBJ file alone.)
    let skip = |line: Option<usize>, problem: String| {
        skipped.set(true);
        let at = line.map_or(String::new(), |l| format!(":{l}"));
        warnings
            .borrow_mut()
            .push(format!("{name}{at}: material library skipped: {problem}"));
    };
    let loader = |p: &Path| -> tobj::MTLLoadResult {
        let problem = match library(p) {
            Ok(materials) => return Ok(materials),
            Err(problem) => problem,
        };
        // `mtllib a.mtl b.mtl` names two libraries (the format allows several); tobj reads
        // the rest of the line as one name, which a name with a space is. Where that one
        // does not load, each word is a library.
        let whole = p.to_string_lossy();
        let line = mtllib_line(text, &whole);
        let words: Vec<&str> = whole.split_whitespace().collect();
        let loaded: Vec<Result<Materials, String>> = match words.len() > 1 {
            true => words.iter().map(|w| library(Path::new(w))).collect(),
            false => Vec::new(),
        };
        if !loaded.iter().any(Result::is_ok) {
            skip(line, problem);
            return Err(tobj::LoadError::MaterialParseError);
        }
        let mut all = Materials::default();
        for each in loaded {
            match each {
                Ok((materials, names)) => {
                    let offset = all.0.len();
                    all.1
                        .extend(names.into_iter().map(|(n, i)| (n, i + offset)));
                    all.0.extend(materials);
                }
                Err(problem) => skip(line, problem),
            }
        }
        Ok(all)
    };
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut stream = ObjStream::new(name, text);
    let loaded = tobj::load_obj_buf(&mut stream, &options, loader);
    if let Some(error) = stream.error.take() {
        return Err(error);
    }
    // What reaches tobj is checked line by line, so tobj has nothing left to refuse; should
    // it, the last line it was given is named.
    let (models, materials) = loaded.map_err(|e| ObjError::Line {
        file: name.to_string(),
        line: stream.line_number,
        message: format!("tobj: {e}"),
    })?;
    let mut warnings = warnings.into_inner();
    let materials = materials.unwrap_or_else(|e| {
        if !skipped.get() {
            skipped.set(true);
            warnings.push(format!("{name}: material library: {e}"));
        }
        Vec::new()
    });
    // (A library skipped is already a warning, which explains its materials' absence.)
    let library_skipped = skipped.get();
    warnings.extend(skipped_warning(name, &counts));
    let defined: std::collections::HashSet<&str> =
        materials.iter().map(|m| m.name.as_str()).collect();
    let unknown: Vec<&str> = (stream.used_materials.iter())
        .map(String::as_str)
        .filter(|used| !defined.contains(used))
        .collect();
    if !unknown.is_empty() && !library_skipped {
        let listed = unknown
            .iter()
            .take(5)
            .copied()
            .collect::<Vec<_>>()
            .join(", ");
        let more = if unknown.len() > 5 { ", …" } else { "" };
        warnings.push(format!(
            "{name}: usemtl names {} material(s) no library defines ({listed}{more}): their \
             faces take the default colour",
            unknown.len()
        ));
    }
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
    let mut degenerate = ZeroArea::default();
    for model in &models {
        let mesh = &model.mesh;
        let color = mesh
            .material_id
            .and_then(|id| colors.get(id).copied())
            .unwrap_or(default);
        let vertex = |i: u32| -> Option<[f32; 3]> {
            let k = 3 * i as usize;
            mesh.positions.get(k..k + 3).map(|p| match frame {
                ObjFrame::YUp => [p[0], -p[1], -p[2]],
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
            let index = scene.shapes.len();
            if zero_area(&[a, b, c]) {
                degenerate.add(index, stream.face_lines.get(index).copied());
            }
            scene.shapes.push(Shape::from([a, b, c]));
            scene.colors_mut().push(color);
        }
    }
    warnings.extend(degenerate.warning(name));
    // (Whoever loads the scene shows its warnings: the CLI prints them, the window's panel.)
    scene.warnings = warnings;
    let Some(bounds) = scene.bounds() else {
        // (A file of `tri` lines named `.txt` came here, read as OBJ.)
        return Err(ObjError::NoTriangles {
            file: name.to_string(),
            hint: read_as_obj_hint(name),
        });
    };
    scene.light = Scene::light_for_bounds(bounds);
    Ok((scene, stream.face_lines))
}

/// The triangles of zero area met while loading: how many, and the first few with their
/// primitive index and source line (for one warning of bounded size).
#[derive(Debug, Default)]
pub(crate) struct ZeroArea {
    pub(crate) count: usize,
    first: Vec<(usize, Option<u32>)>,
}

impl ZeroArea {
    /// How many are named one by one in the warning.
    const LISTED: usize = 5;

    /// Counts primitive `index` (from source line `line`, where known).
    pub(crate) fn add(&mut self, index: usize, line: Option<u32>) {
        self.count += 1;
        if self.first.len() < Self::LISTED {
            self.first.push((index, line));
        }
    }

    /// The warning, if any was met: `file:line:` of the first, the count, and the others'
    /// lines (or primitive indices where lines are not known).
    pub(crate) fn warning(&self, file: &str) -> Option<String> {
        let &(index, line) = self.first.first()?;
        let place = line.map_or(format!("{file}:"), |l| format!("{file}:{l}:"));
        let what = match self.count {
            1 => format!("triangle {index} has zero area (its vertices on one line)"),
            n => {
                let others: Vec<String> = (self.first[1..].iter())
                    .map(|&(i, l)| l.map_or(format!("triangle {i}"), |l| format!("line {l}")))
                    .collect();
                let more = if n > self.first.len() { ", …" } else { "" };
                format!(
                    "{n} triangles have zero area (their vertices on one line): triangle {index} \
                     here, then {}{more}",
                    others.join(", ")
                )
            }
        };
        let them = if self.count == 1 { "it" } else { "them" };
        Some(format!(
            "{place} {what}: kept, so that later triangles keep their file positions as \
             indices, but no ray hits {them}"
        ))
    }
}

/// Whether the triangle has zero area, exactly ([`crate::geometry::triangle::zero_area`]).
fn zero_area(v: &[[f32; 3]; 3]) -> bool {
    crate::geometry::triangle::zero_area(v)
}

/// What tobj makes of a material library: the materials and their indices by name.
type Materials = <tobj::MTLLoadResult as Loaded>::Value;

/// Names the success type of a `Result` (tobj's name map is a type of its hashing crate).
trait Loaded {
    type Value;
}

impl<T, E> Loaded for Result<T, E> {
    type Value = T;
}

/// What is said of one line of a file: its number and the words.
type LineNote = (usize, String);

/// Parses a material library with tobj, naming the line of any problem: what tobj 4 panics on
/// (a colour with fewer than three numbers: it unwraps a failed conversion) is checked first,
/// and tobj's own refusals are placed by how far it had read. With the materials, what is
/// said of a `Kd` the faces cannot show as written, by line: not finite (they take the default
/// colour) or outside 0…1 (clamped).
fn load_mtl_text(text: &str) -> Result<(Materials, Vec<LineNote>), LineNote> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut notes = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            let all: Vec<&str> = words.collect();
            let words: Vec<&str> = all.iter().take(3).copied().collect();
            // (A word that is no number is named: `Kd 0x1 0 0` said "found 2" of 3 words.)
            if let Some(bad) = words.iter().find(|w| w.parse::<f32>().is_err()) {
                return Err((i + 1, format!("{key}: '{bad}' is not a number")));
            }
            let values: Vec<f32> = words.iter().filter_map(|w| w.parse().ok()).collect();
            if values.len() < 3 {
                let found = values.len();
                return Err((i + 1, format!("{key} needs 3 numbers, found {found}")));
            }
            if key == "Kd" && all.len() > 3 {
                let extra = all[3..].join(" ");
                notes.push((
                    i + 1,
                    format!("Kd takes 3 numbers: '{extra}' after them ignored"),
                ));
            }
            let finite = values.iter().all(|v| v.is_finite());
            if key == "Kd" && !(finite && values.iter().all(|v| (0.0..=1.0).contains(v))) {
                let what = match finite {
                    true => "is outside 0…1: clamped",
                    false => "is not finite: the material's faces take the default colour",
                };
                notes.push((i + 1, format!("Kd {} {what}", words.join(" "))));
            }
        }
    }
    let mut reader = Cursor::new(text.as_bytes());
    tobj::load_mtl_buf(&mut reader)
        .map_err(|e| {
            // tobj stops right after reading the line it refuses (through its newline).
            let read = &text.as_bytes()[..(reader.position() as usize).saturating_sub(1)];
            let line = 1 + read.iter().filter(|&&b| b == b'\n').count();
            let message = match e {
                tobj::LoadError::InvalidObjectName => "newmtl needs a name".to_string(),
                e => format!("tobj: {e}"),
            };
            (line, message)
        })
        .map(|materials| (materials, notes))
}

/// What the counting pass found: enough to refuse a file before anything is allocated.
#[derive(Debug, Default)]
struct Counts {
    /// `l` statements (polylines), skipped.
    lines: usize,
    /// `p` statements (points), skipped.
    points: usize,
    /// Free-form geometry statements (curves, surfaces and their parameters), skipped.
    free_form: usize,
}

/// The keywords of OBJ's free-form geometry (curves and surfaces), which raylab does not draw.
const FREE_FORM: &[&str] = &[
    "vp", "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv",
    "sp", "end", "con",
];

/// The first pass: counts vertices and the elements faces, lines and points make, and refuses
/// a file over the limits before tobj or the scene allocate anything. Polylines and points
/// count towards the limit although they are skipped: their references are read all the same.
fn count_elements(name: &str, text: &str) -> Result<Counts, ObjError> {
    let mut counts = Counts::default();
    let (mut vertices, mut elements) = (0u64, 0u64);
    let max_elements = max_triangles();
    for (i, line) in text.lines().enumerate() {
        let err = |message: String| ObjError::Line {
            file: name.to_string(),
            line: i + 1,
            message,
        };
        let mut words = line.split_whitespace();
        let (added, over) = match words.next() {
            Some("v") => {
                vertices += 1;
                if vertices > MAX_VERTICES {
                    return Err(err(format!(
                        "more than {MAX_VERTICES} vertices: too large a model to load"
                    )));
                }
                continue;
            }
            Some("f") => (words.count().saturating_sub(2) as u64, "triangles"),
            Some("l") => {
                counts.lines += 1;
                (words.count() as u64, "elements (l and p references count)")
            }
            Some("p") => {
                counts.points += 1;
                (words.count() as u64, "elements (l and p references count)")
            }
            Some(w) if FREE_FORM.contains(&w) => {
                counts.free_form += 1;
                continue;
            }
            _ => continue,
        };
        elements += added;
        if elements > max_elements {
            return Err(err(format!(
                "the faces so far make more than {max_elements} {over}: too large a model to \
                 load (RAYLAB_MAX_TRIANGLES raises the limit)"
            )));
        }
    }
    Ok(counts)
}

/// The warning for statements raylab read but does not draw, or `None`.
fn skipped_warning(name: &str, counts: &Counts) -> Option<String> {
    let parts: Vec<String> = [
        (counts.lines, "polyline (l)"),
        (counts.points, "point (p)"),
        (counts.free_form, "curve/surface"),
    ]
    .iter()
    .filter(|(n, _)| *n > 0)
    .map(|(n, what)| format!("{n} {what}"))
    .collect();
    (!parts.is_empty()).then(|| {
        format!(
            "{name}: skipped {} statements: raylab draws only faces (f)",
            parts.join(", ")
        )
    })
}
