//! The `.scene` parser: one statement at a time through the transform stack (the format is
//! described in the module above).

use super::matrix::check_matrix;
use super::mesh_files::{FileKey, MeshFiles};
use super::numbers::{exact, f32_channels, number, numbers};
use super::*;
use crate::geometry::shapes::SceneFrame;

/// What `push` saves.
#[derive(Clone)]
struct Saved {
    color: [f32; 3],
    /// The rank of the last transform statement of the level (translate 0, rotate 1, scale 2).
    last_rank: Option<(u8, usize)>,
    /// The level's entry in the scene tree (`None` past the tree's limit).
    level: Option<usize>,
    /// The level's `push` line (0 at the top).
    push_line: usize,
}

struct Parser<'a, T: Real> {
    file: &'a str,
    /// The line being read.
    line: usize,
    stack: TransformStack,
    saved: Vec<Saved>,
    current: Saved,
    out: Description<T>,
    /// The line of each statement a scene has at most one of (light, camera, ambient).
    given_once: HashMap<&'static str, usize>,
    meshes: HashMap<(FileKey, ObjFrame, [u32; 3]), Scene>,
    /// The meshes used often enough to be instanced, loaded once whatever the colour.
    shared: HashMap<Repeated, Shared>,
    /// How often each (file, frame) is used, however its path is spelled.
    uses: HashMap<(FileKey, Result<ObjFrame, String>), usize>,
    /// Each mesh path as written, with the file it names.
    files: MeshFiles,
    /// How often `cornell` is used.
    cornell_uses: usize,
    /// The room for copies of repeated meshes flattened by choice, in proportion to the
    /// file ([`crate::limits::flattened_copies_room`]).
    flatten_room: u64,
    /// Triangles flattened as copies so far: by choice, and where only flattening can hold a
    /// copy (refused past [`crate::limits::MAX_FLATTENED_COPIES`]).
    flattened: u64,
    instancing: Instancing,
    /// With every mesh flattened ([`Instancing::NEVER`], the reference loop's scenes): the
    /// (file, frame) of each mesh loaded so far, the triangles they hold, and the triangles
    /// flattened as copies of them, which may not pass `flatten_room` plus those
    /// (`count_copy`).
    loaded: std::collections::HashSet<Repeated>,
    loaded_triangles: u64,
    copied: u64,
    /// Primitives placed as instances so far.
    instanced: usize,
    /// Most primitives stored one by one ([`obj::max_triangles`]).
    max_stored: u64,
    /// Most meshes placed as instances ([`crate::limits::max_placements`]).
    max_placements: u64,
    /// Entries (levels and statements) the scene tree may still record.
    tree_room: u64,
    /// The first line the scene tree did not record.
    tree_full_at: Option<usize>,
    /// `tri` statements of zero area (kept: no ray hits them).
    zero_area: obj::ZeroArea,
}

/// A mesh named repeatedly: a file in a frame, or the built-in Cornell box.
#[derive(Clone, PartialEq, Eq, Hash)]
enum Repeated {
    File(FileKey, ObjFrame),
    Cornell,
}

/// A repeated mesh, loaded once, and whether its uses are flattened (a small mesh, while the
/// room for flattened copies lasts) or placed as instances.
struct Shared {
    mesh: Arc<Mesh>,
    flatten: bool,
}

/// Parses `.scene` text, every mesh flattened. `dir` is where mesh paths are relative to;
/// `load_mesh` loads them.
pub fn parse<T: Real>(
    file: &str,
    text: &str,
    dir: &Path,
    load_mesh: &MeshLoader,
) -> Result<Description<T>, FileError> {
    parse_with(file, text, dir, load_mesh, Instancing::NEVER)
}

/// [`parse`], with the meshes `instancing` picks placed as instances.
pub fn parse_with<T: Real>(
    file: &str,
    text: &str,
    dir: &Path,
    load_mesh: &MeshLoader,
    instancing: Instancing,
) -> Result<Description<T>, FileError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut uses = HashMap::new();
    let mut files = MeshFiles::default();
    let mut cornell_uses = 0;
    let (mut mesh_files, mut named) = (Vec::new(), std::collections::HashSet::new());
    for line in text.lines() {
        // (A line whose words do not parse is reported below, at its number.)
        let words = crate::words::words(line).unwrap_or_default();
        let mut words = words.into_iter();
        match words.next().as_deref() {
            Some("mesh") => {
                let path = words.next().unwrap_or_default();
                let frame = words
                    .next()
                    .map_or(Ok(ObjFrame::YUp), |w| w.parse::<ObjFrame>().map_err(|_| w));
                let file = files.key(dir, &path);
                let joined = dir.join(&path);
                if named.insert(joined.clone()) {
                    mesh_files.push(joined);
                }
                *uses.entry((file, frame)).or_insert(0) += 1;
            }
            Some("cornell") => cornell_uses += 1,
            _ => {}
        }
    }
    let mut p = Parser::<T> {
        file,
        line: 0,
        stack: TransformStack::new(),
        saved: Vec::new(),
        current: Saved {
            color: DEFAULT_COLOR,
            last_rank: None,
            level: Some(0),
            push_line: 0,
        },
        out: Description {
            shapes: Vec::new(),
            colors: Vec::new(),
            instances: Vec::new(),
            light: None,
            ambient: None,
            camera: None,
            beyond_view: None,
            has_cornell: false,
            warnings: Vec::new(),
            lines: Vec::new(),
            mesh_files,
            levels: vec![Level {
                line: 0,
                depth: 0,
                statements: Vec::new(),
                world_from_object: glam::DMat4::IDENTITY.to_cols_array_2d(),
                primitives: Vec::new(),
            }],
        },
        given_once: HashMap::new(),
        meshes: HashMap::new(),
        shared: HashMap::new(),
        uses,
        files,
        cornell_uses,
        flatten_room: crate::limits::flattened_copies_room(text.len()),
        flattened: 0,
        instancing,
        loaded: std::collections::HashSet::new(),
        loaded_triangles: 0,
        copied: 0,
        instanced: 0,
        max_stored: obj::max_triangles(),
        max_placements: crate::limits::max_placements(),
        tree_room: crate::limits::max_tree_entries(),
        tree_full_at: None,
        zero_area: obj::ZeroArea::default(),
    };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let error = |message| FileError {
            file: file.to_string(),
            line,
            message,
        };
        let words = crate::words::words(raw).map_err(error)?;
        if words.is_empty() {
            continue;
        }
        let words: Vec<&str> = words.iter().map(String::as_str).collect();
        p.line = line;
        p.statement(line, &words, dir, load_mesh).map_err(error)?;
    }
    if !p.saved.is_empty() {
        p.warn(
            p.current.push_line,
            "push without a matching pop (the file ends inside this level)",
        );
    }
    if let Some(w) = p.zero_area.warning(file) {
        p.out.warnings.push(w);
    }
    if let Some(line) = p.tree_full_at {
        // (Not the top level, which every file has: the limit counts what the file adds.)
        let listed = p.out.levels.len() - 1
            + p.out
                .levels
                .iter()
                .map(|l| l.statements.len())
                .sum::<usize>();
        let message = format!(
            "the scene tree lists the first {listed} push levels and statements, up to here \
             (RAYLAB_MAX_TREE_ENTRIES=N sets another limit); the whole file renders"
        );
        p.warn(line, &message);
    }
    Ok(p.out)
}

impl<T: Real> Parser<'_, T> {
    fn warn(&mut self, line: usize, message: &str) {
        // (Whoever loads the scene shows its warnings.)
        self.out
            .warnings
            .push(format!("{}:{line}: {message}", self.file));
    }

    fn identity(&self) -> bool {
        self.stack.matrix() == glam::DMat4::IDENTITY
    }

    fn transformed(&self, p: [f64; 3]) -> Result<[T; 3], String> {
        let placed = self.stack.transform_point(DVec3::from_array(p)).to_array();
        let w = placed.map(T::of);
        if w.iter().all(|c| c.is_finite()) {
            return Ok(w);
        }
        // (Past f32 but finite, it was "not finite"; with no transform, "after the transform".)
        let by = format!(", placed at {placed:?} by the transform,");
        let moved = if self.identity() { "" } else { &by };
        let past = match (placed.iter().all(|c| c.is_finite()), T::PRECISION <= 24) {
            (true, true) => "beyond f32's range",
            (true, false) => "beyond f64's range",
            (false, _) => "not finite",
        };
        Err(format!("the point {p:?}{moved} is {past} ({w:?})"))
    }

    /// The uniform scale of the current matrix's linear part, or `None` where it is not
    /// uniform (to a relative 1e-12).
    fn uniform_scale(&self) -> Option<f64> {
        let m = self.stack.matrix();
        // Measured on the columns divided by a power of two near their largest entry (exact),
        // so no square overflows or underflows at any scale f64 holds; the result is
        // multiplied back, to the same bits as the columns' own lengths where those are exact.
        let cols = [m.x_axis, m.y_axis, m.z_axis].map(|c| c.truncate());
        let max = cols
            .iter()
            .map(|c| c.abs().max_element())
            .fold(0.0, f64::max);
        if !(max.is_finite() && max > 0.0) {
            return None;
        }
        let unit = match max >= f64::MIN_POSITIVE {
            true => f64::from_bits(max.to_bits() & 0x7ff0_0000_0000_0000),
            false => f64::MIN_POSITIVE,
        };
        let cols = cols.map(|c| c / unit);
        let len = cols.map(|c| c.length());
        let tol = 1e-12 * len[0];
        let equal = (len[1] - len[0]).abs() <= tol && (len[2] - len[0]).abs() <= tol;
        let dots = [
            cols[0].dot(cols[1]),
            cols[1].dot(cols[2]),
            cols[0].dot(cols[2]),
        ];
        let orthogonal = dots.iter().all(|d| d.abs() <= 1e-12 * len[0] * len[0]);
        (equal && orthogonal).then_some(len[0] * unit)
    }

    fn add(&mut self, shape: Shape<T>, color: [f32; 3]) -> Result<(), String> {
        if self.out.shapes.len() as u64 >= self.max_stored {
            return Err(format!(
                "more than {} primitives stored one by one (RAYLAB_MAX_TRIANGLES raises the \
                 limit; `raylab trace --accel reference` flattens every mesh, the renderer \
                 places a mesh used repeatedly as instances)",
                self.max_stored
            ));
        }
        let index = (self.out.shapes.len() + self.instanced) as u32;
        self.out.shapes.push(shape);
        self.out.colors.push(color);
        self.record(index..index + 1);
        Ok(())
    }

    /// Primitives `added` belong to the current level and the current line.
    fn record(&mut self, added: std::ops::Range<u32>) {
        if self.out.lines.last().map(|&(_, line)| line) != Some(self.line) {
            self.out.lines.push((added.start, self.line));
        }
        let Some(level) = self.current.level else {
            return;
        };
        let runs = &mut self.out.levels[level].primitives;
        match runs.last_mut() {
            Some(r) if r.end == added.start => r.end = added.end,
            _ => runs.push(added),
        }
    }

    /// With every mesh flattened ([`Instancing::NEVER`]): a use of a mesh (or `cornell`)
    /// flattened before is a copy, and the copies may hold at most the file's room for
    /// flattened copies plus the triangles of the meshes themselves, so memory stays in
    /// proportion to the input (16,000 uses of a 1,000-triangle mesh, 157 KB, took 822 MB).
    fn count_copy(&mut self, mesh: Repeated, triangles: usize) -> Result<(), String> {
        if self.instancing != Instancing::NEVER {
            return Ok(());
        }
        let n = triangles as u64;
        if self.loaded.insert(mesh) {
            self.loaded_triangles += n;
            return Ok(());
        }
        self.copied += n;
        let room = self.flatten_room + self.loaded_triangles;
        if self.copied > room {
            return Err(format!(
                "the copies of meshes used again pass {room} triangles, the room this input \
                 gives a scene with every mesh flattened; `raylab trace --accel auto` places \
                 repeated meshes as instances"
            ));
        }
        Ok(())
    }

    /// A mesh's loading warnings, once, under the `mesh` statement's line.
    fn mesh_warnings(&mut self, line: usize, path: &str, warnings: &[String]) {
        for w in warnings {
            self.warn(line, &format!("mesh '{path}': {w}"));
        }
    }

    /// A repeated mesh, loaded by `load` at its first use, and whether its uses are flattened:
    /// a mesh under [`Instancing::min_triangles`] is, if all its `uses` fit in the room left
    /// for flattened copies (a small mesh walks faster flattened, but 10⁵ copies of the
    /// Cornell box flattened took gigabytes for a few hundred kilobytes of input).
    fn repeated(
        &mut self,
        line: usize,
        path: &str,
        key: Repeated,
        uses: usize,
        load: impl FnOnce() -> Result<(Mesh, Vec<String>), String>,
    ) -> Result<(Arc<Mesh>, bool), String> {
        if !self.shared.contains_key(&key) {
            let (mesh, warnings) = load()?;
            self.mesh_warnings(line, path, &warnings);
            let copies = (mesh.triangles.len() as u64).saturating_mul(uses as u64);
            let small = mesh.triangles.len() < self.instancing.min_triangles.max(1);
            let flatten = small && self.flattened.saturating_add(copies) <= self.flatten_room;
            if flatten {
                self.flattened += copies;
            }
            let mesh = Arc::new(mesh);
            self.shared.insert(key.clone(), Shared { mesh, flatten });
        }
        let shared = &self.shared[&key];
        Ok((shared.mesh.clone(), shared.flatten))
    }

    /// Places `mesh` as an instance in the current frame (faces without a material get
    /// `color`), or adds its triangles where `flatten` says so or the matrix cannot place it.
    /// Copies only flattening can hold count with the flattened ones (so later meshes are
    /// flattened by choice less), and are refused only past the absolute
    /// [`crate::limits::MAX_FLATTENED_COPIES`], not the file's room: their memory grows with
    /// the mesh file, which is input too.
    fn place_or_add(
        &mut self,
        mesh: Arc<Mesh>,
        color: [f32; 3],
        flatten: bool,
    ) -> Result<(), String> {
        let m = self.stack.matrix();
        let n = mesh.triangles.len();
        let placeable = Instance::placeable(&m);
        if !flatten && !placeable {
            let limit = crate::limits::MAX_FLATTENED_COPIES;
            if self.flattened.saturating_add(n as u64) > limit {
                return Err(format!(
                    "this matrix is too ill-conditioned to place mesh '{}' as an instance \
                     (condition number over {}), and flattening its copies passes the {} \
                     triangles they may take (a scale this uneven places no instance: scale \
                     less unevenly, or place fewer meshes under it)",
                    mesh.name,
                    crate::geometry::instance::MAX_CONDITION,
                    limit
                ));
            }
            self.flattened += n as u64;
        }
        if flatten || !placeable {
            let colors = mesh.colors.iter().map(|c| c.unwrap_or(color));
            return self.add_triangles(mesh.triangles.iter().zip(colors));
        }
        let first = self.out.shapes.len() + self.instanced;
        if first + n > u32::MAX as usize - 1 {
            return Err(format!("more than {} primitives", u32::MAX - 1));
        }
        if self.out.instances.len() as u64 >= self.max_placements {
            return Err(format!(
                "more than {} mesh placements (RAYLAB_MAX_PLACEMENTS=N sets another limit)",
                self.max_placements
            ));
        }
        self.out.instances.push(Instance {
            mesh,
            world_from_object: m,
            first_prim: first as u32,
            color,
            tint: None,
        });
        self.instanced += n;
        self.record(first as u32..(first + n) as u32);
        Ok(())
    }

    /// Refuses a second `light`, `camera` or `ambient`: the first would be silently lost.
    fn once(&mut self, keyword: &'static str) -> Result<(), String> {
        match self.given_once.insert(keyword, self.line) {
            Some(first) => Err(format!("a scene has one {keyword} (given on line {first})")),
            None => Ok(()),
        }
    }

    /// Keeps the first light or camera out of the rendered range, `in_view`'s error, with its
    /// line ([`Description::beyond_view`]).
    fn beyond_view(&mut self, in_view: Result<(), String>) {
        if let (Err(message), None) = (in_view, &self.out.beyond_view) {
            let (file, line) = (self.file.to_string(), self.line);
            self.out.beyond_view = Some(FileError {
                file,
                line,
                message,
            });
        }
    }

    fn transform(&mut self, line: usize, rank: u8, what: &str) {
        let names = ["translate", "rotate", "scale"];
        if let Some((last, last_line)) = self.current.last_rank {
            if rank < last {
                let message = format!(
                    "{what} after {} (line {last_line}) in one push level: the lecture's fixed \
                     order is translate, rotate, scale (M = T*R*S)",
                    names[last as usize]
                );
                self.warn(line, &message);
            }
        }
        self.current.last_rank = Some((rank, line));
        if let Some(level) = self.current.level {
            let rows = self.stack.matrix().transpose().to_cols_array_2d();
            self.out.levels[level].world_from_object = rows;
        }
    }

    /// Takes room for one more scene-tree entry, if there is any.
    fn tree_entry(&mut self, line: usize) -> bool {
        match self.tree_room {
            0 => {
                self.tree_full_at.get_or_insert(line);
                false
            }
            _ => {
                self.tree_room -= 1;
                true
            }
        }
    }

    fn statement(
        &mut self,
        line: usize,
        words: &[&str],
        dir: &Path,
        load_mesh: &MeshLoader,
    ) -> Result<(), String> {
        let (keyword, args) = (words[0], &words[1..]);
        if let Some(level) = self.current.level {
            if self.tree_entry(line) {
                let text = words.join(" ");
                self.out.levels[level].statements.push((line, text));
            }
        }
        if let Some(shape) = Shape::read(keyword, args, &*self) {
            let shape = shape?;
            if shape.is_degenerate() {
                let index = self.out.shapes.len() + self.instanced;
                self.zero_area.add(index, u32::try_from(line).ok());
            }
            return self.add(shape, self.current.color);
        }
        match keyword {
            "mesh" => {
                let (path, frame) = match args {
                    [path] => (path, ObjFrame::YUp),
                    [path, frame] => (path, frame.parse::<ObjFrame>()?),
                    _ => return Err("mesh needs a path and optionally yup or lab".into()),
                };
                if path.is_empty() {
                    return Err("mesh '': the path is empty".into());
                }
                let full = dir.join(path);
                let color = self.current.color;
                let file = self.files.key(dir, path);
                let uses = (self.uses.get(&(file.clone(), Ok(frame))))
                    .copied()
                    .unwrap_or(1);
                if uses >= self.instancing.min_uses {
                    // Used often: loaded once, whatever the colour; placed or flattened.
                    let key = Repeated::File(file, frame);
                    let load = || -> Result<_, String> {
                        let mesh = load_mesh(&full, frame, UNSET_COLOR)
                            .map_err(|e| format!("mesh '{path}': {e}"))?;
                        Ok((mesh_from_scene(&mesh), mesh.warnings))
                    };
                    let (mesh, flatten) = self.repeated(line, path, key, uses, load)?;
                    return self.place_or_add(mesh, color, flatten);
                }
                let repeated = Repeated::File(file.clone(), frame);
                let key = (file, frame, color.map(f32::to_bits));
                if !self.meshes.contains_key(&key) {
                    let mesh = load_mesh(&full, frame, color)
                        .map_err(|e| format!("mesh '{path}': {e}"))?;
                    self.mesh_warnings(line, path, &mesh.warnings);
                    self.meshes.insert(key.clone(), mesh);
                }
                // (Taken out and put back: no copy of the mesh per use.)
                let mesh = self.meshes.remove(&key).expect("loaded above");
                let added =
                    (self.count_copy(repeated, mesh.len())).and_then(|()| self.add_scene(&mesh));
                self.meshes.insert(key, mesh);
                added?;
            }
            "cornell" => {
                if !args.is_empty() {
                    return Err("cornell takes no numbers".into());
                }
                self.out.has_cornell = true;
                if self.cornell_uses >= self.instancing.min_uses {
                    // (Repeated, like a mesh: its copies flattened up to a room, else placed.)
                    let load = || Ok((mesh_from_scene(&cornell::scene()), Vec::new()));
                    let (mesh, flatten) =
                        self.repeated(line, "cornell", Repeated::Cornell, self.cornell_uses, load)?;
                    return self.place_or_add(mesh, self.current.color, flatten);
                }
                let cornell = cornell::scene();
                self.count_copy(Repeated::Cornell, cornell.len())?;
                self.add_scene(&cornell)?;
            }
            "color" => {
                let c = numbers(args, &[3], "color")?;
                if c.iter().any(|x| *x < 0.0) {
                    return Err(format!(
                        "color {} {} {} has a negative channel",
                        c[0], c[1], c[2]
                    ));
                }
                let color = f32_channels("color", [c[0], c[1], c[2]])?;
                // (A reflectance above 1 is clamped, as an MTL's Kd is, and said.)
                if color.iter().any(|x| *x > 1.0) {
                    let written = args.join(" ");
                    self.warn(line, &format!("color {written} is outside 0…1: clamped"));
                }
                self.current.color = color.map(|x| x.min(1.0));
            }
            "push" => {
                if !args.is_empty() {
                    return Err("push takes nothing".into());
                }
                if self.saved.len() >= crate::limits::MAX_PUSH_DEPTH {
                    return Err(format!(
                        "push nests deeper than {} levels",
                        crate::limits::MAX_PUSH_DEPTH
                    ));
                }
                self.stack.push();
                self.saved.push(self.current.clone());
                let depth = self.saved.len();
                // (A level inside one the tree did not record is not recorded either.)
                self.current.level = match self.current.level.is_some() && self.tree_entry(line) {
                    true => {
                        self.out.levels.push(Level {
                            line,
                            depth,
                            statements: Vec::new(),
                            world_from_object: self.stack.matrix().transpose().to_cols_array_2d(),
                            primitives: Vec::new(),
                        });
                        Some(self.out.levels.len() - 1)
                    }
                    false => None,
                };
                self.current.push_line = line;
                self.current.last_rank = None;
            }
            "pop" => {
                if !args.is_empty() {
                    return Err("pop takes nothing".into());
                }
                let saved = self.saved.pop().ok_or("pop without a matching push")?;
                self.stack.pop();
                self.current = saved;
            }
            "translate" => {
                let t = numbers(args, &[3], "translate")?;
                self.stack.translate(DVec3::new(t[0], t[1], t[2]));
                check_matrix(&self.stack.matrix(), words)?;
                self.transform(line, 0, "translate");
            }
            "rotate" => {
                let [axis, deg] = args else {
                    return Err("rotate needs an axis (x, y or z) and an angle in degrees".into());
                };
                let axis = match *axis {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    other => return Err(format!("rotate axis '{other}' is not x, y or z")),
                };
                self.stack.rotate_degrees(axis, number(deg)?);
                check_matrix(&self.stack.matrix(), words)?;
                self.transform(line, 1, "rotate");
            }
            "scale" => {
                let s = numbers(args, &[1, 3], "scale")?;
                let s = match s[..] {
                    [k] => DVec3::splat(k),
                    _ => DVec3::new(s[0], s[1], s[2]),
                };
                if s.to_array().contains(&0.0) {
                    return Err("a scale of 0 flattens everything after it".into());
                }
                self.stack.scale(s);
                check_matrix(&self.stack.matrix(), words)?;
                self.transform(line, 2, "scale");
            }
            "light" => {
                let x = numbers(args, &[3, 4], "light")?;
                self.once("light")?;
                let p = x.get(3).copied().unwrap_or(DEFAULT_POWER as f64);
                if p < 0.0 {
                    return Err(format!("light power {p} is negative"));
                }
                let [p] = f32_channels("light power", [p])?;
                let position = self.transformed([x[0], x[1], x[2]]);
                let position = position.map(|w| w.map(|c| c.f64() as f32))?;
                let in_view =
                    crate::math::check_range("light position", position, MAX_VIEW_COORDINATE);
                self.beyond_view(in_view);
                self.out.light = Some(PointLight {
                    position,
                    power: [p; 3],
                });
            }
            "ambient" => {
                let n = numbers(args, &[3], "ambient")?;
                self.once("ambient")?;
                if n.iter().any(|x| *x < 0.0) {
                    return Err("ambient has a negative channel".into());
                }
                self.out.ambient = Some(f32_channels("ambient", [n[0], n[1], n[2]])?);
            }
            "camera" => {
                if args.len() < 3 {
                    return Err(format!("camera needs x y z, found {} numbers", args.len()));
                }
                self.once("camera")?;
                let p = numbers(&args[..3], &[3], "camera")?;
                let position = [p[0], p[1], p[2]];
                let in_view =
                    crate::math::check_range("camera position", position, MAX_VIEW_COORDINATE);
                self.beyond_view(in_view);
                let mut camera = SceneCamera {
                    position,
                    yaw: 0.0,
                    pitch: 0.0,
                    fov: None,
                };
                let mut rest = args[3..].chunks(2);
                let mut seen = Vec::new();
                for pair in rest.by_ref() {
                    let [key, value] = pair else {
                        return Err(format!("camera option '{}' needs a value", pair[0]));
                    };
                    if seen.contains(key) {
                        return Err(format!("camera option '{key}' given twice"));
                    }
                    seen.push(*key);
                    let v = number(value)?;
                    match *key {
                        "yaw" => camera.yaw = v,
                        "pitch" => camera.pitch = v,
                        "fov" if v > 0.0 && v < 180.0 => {
                            camera.fov = Some(v);
                            // Every image size must get a focal length the camera takes.
                            let ratio = camera.focal_ratio();
                            let (lo, hi) = crate::camera::FOCAL_RANGE;
                            let max_side = crate::limits::MAX_IMAGE_SIDE as f64;
                            if !(ratio >= lo && ratio * max_side <= hi) {
                                return Err(format!(
                                    "camera fov {value} gives a focal length of {ratio:.4e} image \
                                     widths, beyond what the camera takes at every size \
                                     ({lo:e} px to {hi:e} px)"
                                ));
                            }
                        }
                        "fov" => {
                            return Err(format!("camera fov {value} is not in (0, 180) degrees"))
                        }
                        other => {
                            return Err(format!("camera option '{other}' is not yaw, pitch or fov"))
                        }
                    }
                }
                self.out.camera = Some(camera);
            }
            other => {
                return Err(format!(
                    "unknown statement '{}' (expected {}, mesh, cornell, color, push, pop, \
                     translate, rotate, scale, light, ambient or camera)",
                    crate::words::shown(other),
                    Shape::<T>::KEYWORDS.join(", ")
                ))
            }
        }
        Ok(())
    }

    /// Adds a loaded scene's primitives (a mesh, the Cornell box) in the current frame.
    fn add_scene(&mut self, scene: &Scene) -> Result<(), String> {
        let triangles = (scene.shapes.iter())
            .map(|s| (s.triangle()).expect("meshes and the Cornell box are triangles"));
        self.add_triangles(triangles.zip(scene.colors().iter().copied()))
    }

    /// Adds triangles written in the current frame, each with its colour.
    fn add_triangles<'t>(
        &mut self,
        triangles: impl Iterator<Item = (&'t [[f32; 3]; 3], [f32; 3])>,
    ) -> Result<(), String> {
        let identity = self.identity();
        for (v, color) in triangles {
            let world = |p: [f32; 3]| -> Result<[T; 3], String> {
                match identity {
                    true => Ok(p.map(|c| T::of(c as f64))),
                    false => self.transformed(p.map(f64::from)),
                }
            };
            let shape = Shape::from([world(v[0])?, world(v[1])?, world(v[2])?]);
            self.add(shape, color)?;
        }
        Ok(())
    }
}

/// `values` in f32, the renderer's colour type; one that f32 cannot hold (it would become
/// infinity) is refused, naming it.
/// What a shape's scene line reads through the current frame ([`Primitive::read`]).
impl<T: Real> SceneFrame<T> for Parser<'_, T> {
    fn numbers(&self, words: &[&str], count: usize, what: &str) -> Result<Vec<f64>, String> {
        numbers(words, &[count], what)
    }

    /// The matrix applied in f64, then rounded to `T` (the numbers straight in `T` where the
    /// matrix is the identity).
    fn point(&self, words: &[&str]) -> Result<[T; 3], String> {
        if !self.identity() {
            let p = [0, 1, 2].map(|k| number(words[k]));
            let [x, y, z] = p;
            return self.transformed([x?, y?, z?]);
        }
        let v = [0, 1, 2].map(|k| exact::<T>(words[k]));
        match v.iter().position(|c| !c.is_finite()) {
            Some(k) => Err(format!(
                "coordinate {} is not finite in this precision",
                words[k]
            )),
            None => Ok(v),
        }
    }

    fn length(&self, word: &str) -> Option<T> {
        if self.identity() {
            return Some(exact::<T>(word));
        }
        let scale = self.uniform_scale()?;
        Some(T::of(number(word).ok()? * scale))
    }
}
