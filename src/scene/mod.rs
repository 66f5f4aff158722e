//! Scenes: primitives with one colour each, a point light and the lab's constant indirect term.

pub(crate) mod bounds;
pub mod cornell;
pub mod file;
/// Meshes placed by instances live below both the scene and the accelerator.
pub use crate::geometry::instance;
pub mod obj;

use crate::geometry::Shape;
use crate::math::real::V3;
use crate::math::{check_range, MAX_SCENE_COORDINATE, MAX_VIEW_COORDINATE};
use std::sync::OnceLock;

pub use file::{load_scene_file, SceneCamera};
pub use instance::{Instance, Mesh, Stored};
pub use obj::{load_obj_file, load_obj_str, ObjError, ObjFrame};

/// The name of the built-in lab Cornell box wherever a scene is named ([`Scene::open`]).
pub const CORNELL: &str = "cornell";

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// Position in the world.
    pub position: V3<f32>,
    /// Power P per colour channel (the lab's 14·(1, 1, 1)).
    pub power: V3<f32>,
}

/// A scene: parallel arrays of primitives and their linear-RGB diffuse colours, meshes placed
/// as instances (stored once however often they are placed). The structure that answers rays
/// over them is built by whoever renders (`render::Stage`), not by the scene.
///
/// A primitive's index counts the instances' triangles too: without instances primitive `i`
/// is `shapes[i]`; with them, ask [`Scene::shape`] and [`Scene::color`].
#[derive(Clone, Debug)]
pub struct Scene {
    /// A short name for messages ("cornell" or the file name).
    pub name: String,
    /// The primitives stored one by one (all of them where there are no instances).
    pub shapes: Vec<Shape<f32>>,
    /// Diffuse colour (the lab's ρ, linear RGB) of each of `shapes` ([`Scene::colors`];
    /// written through [`Scene::colors_mut`], which forgets `color_runs`).
    colors: Vec<V3<f32>>,
    /// Where `colors` change along the primitives, found on first use (see
    /// [`Scene::color_run`]).
    color_runs: OnceLock<ColorRuns>,
    /// [`Scene::bounds`], found on first use by [`Scene::shadows_from_light`].
    bounds_once: OnceLock<Option<Bounds>>,
    /// Meshes placed by a matrix, in primitive order (see [`Scene::with_instances`]).
    instances: Vec<Instance>,
    /// Where each instance starts ([`instance::locate`]).
    instance_index: Vec<instance::InstanceStart>,
    /// The one light.
    pub light: PointLight,
    /// The lab's constant indirect-light approximation N.
    pub ambient: V3<f32>,
    /// What loading it had to skip or guess (shown to the user, never fatal).
    pub warnings: Vec<String>,
    /// The starting camera a `.scene` file names, if any.
    pub camera: Option<SceneCamera>,
    /// A `.scene` file's push levels (the transform-stack inspector); empty otherwise.
    pub levels: Vec<file::Level>,
    /// The mesh files a `.scene` file names (as joined to its directory), each once: what a
    /// viewer watches beside it. Empty otherwise.
    pub mesh_files: Vec<std::path::PathBuf>,
}

impl PartialEq for Scene {
    fn eq(&self, o: &Self) -> bool {
        (
            &self.name,
            &self.shapes,
            &self.colors,
            &self.light,
            &self.ambient,
            &self.warnings,
            (&self.camera, &self.levels, &self.instances),
        ) == (
            &o.name,
            &o.shapes,
            &o.colors,
            &o.light,
            &o.ambient,
            &o.warnings,
            (&o.camera, &o.levels, &o.instances),
        )
    }
}

/// Axis-aligned bounds (min, max) of a scene.
pub type Bounds = (V3<f32>, V3<f32>);

impl Scene {
    /// A scene of `shapes` with one colour each, a light and the indirect term.
    pub fn new(
        name: impl Into<String>,
        shapes: Vec<Shape<f32>>,
        colors: Vec<V3<f32>>,
        light: PointLight,
        ambient: V3<f32>,
    ) -> Self {
        assert_eq!(shapes.len(), colors.len(), "one colour per primitive");
        Self {
            name: name.into(),
            shapes,
            colors,
            color_runs: OnceLock::new(),
            bounds_once: OnceLock::new(),
            light,
            ambient,
            warnings: Vec::new(),
            camera: None,
            levels: Vec::new(),
            mesh_files: Vec::new(),
            instances: Vec::new(),
            instance_index: Vec::new(),
        }
    }

    /// Whether the scene is within the range the f32 core renders without overflow: every
    /// primitive within ±[`MAX_SCENE_COORDINATE`], the light within ±[`MAX_VIEW_COORDINATE`].
    /// The error names the primitive and the value.
    pub fn check_ranges(&self) -> Result<(), String> {
        self.check_ranges_at(&|_| None)
    }

    /// [`Scene::check_ranges`], the error also naming the line `line_of` gives for the
    /// primitive's index (a scene file's statement).
    pub fn check_ranges_at(&self, line_of: &dyn Fn(u32) -> Option<usize>) -> Result<(), String> {
        let at = |index: usize| match line_of(index as u32) {
            Some(line) => format!("{}:{line}:", self.name),
            None => format!("{}:", self.name),
        };
        for (i, shape) in self.shapes.iter().enumerate() {
            let (lo, hi) = shape.bounds();
            for corner in [lo, hi] {
                let kind = match shape.is_triangle() {
                    true => "triangle",
                    false => shape.keyword(),
                };
                let what = format!("{} {kind} {i} (bounds corner)", at(i));
                check_range(&what, corner, MAX_SCENE_COORDINATE)?;
            }
        }
        for inst in &self.instances {
            let (lo, hi) = instance::world_bounds(inst);
            for corner in [lo, hi] {
                let what = format!(
                    "{} {} placed at primitive {} (bounds corner)",
                    at(inst.first_prim as usize),
                    inst.mesh.name,
                    inst.first_prim
                );
                check_range(&what, corner, MAX_SCENE_COORDINATE)?;
            }
        }
        let light = self.light.position;
        check_range(&format!("{}: light", self.name), light, MAX_VIEW_COORDINATE)
    }

    /// Opens what a user names as a scene, the same names everywhere (the command line, the
    /// window's argument, the panel's field, a dropped file, the File menu, a view's `scene`
    /// line): `cornell` for the built-in lab box, else a `.scene` or OBJ file ([`Scene::load`]).
    pub fn open(spec: &str, obj_frame: ObjFrame) -> Result<Scene, String> {
        match spec {
            CORNELL => Ok(Scene::cornell()),
            path => Scene::load(std::path::Path::new(path), obj_frame),
        }
    }

    /// Loads a `.scene` file or an OBJ file (`obj_frame`: how its coordinates are read), by the
    /// file's extension.
    /// The scene is checked to be within range ([`Scene::check_ranges`]).
    pub fn load(path: &std::path::Path, obj_frame: ObjFrame) -> Result<Scene, String> {
        let mut scene = Scene::load_unwarned(path, obj_frame)?;
        scene.warnings.extend(scene.too_small_to_light());
        Ok(scene)
    }

    /// [`Scene::load`] without the scene-wide warnings.
    fn load_unwarned(path: &std::path::Path, obj_frame: ObjFrame) -> Result<Scene, String> {
        match Scene::reads_as_obj(path) {
            // (Checked in range as it is built, naming the lines.)
            false => load_scene_file(path),
            // (Checked in range as it loads, naming the faces' lines.)
            true => load_obj_file(path, obj_frame).map_err(|e| match e {
                // (That one says so itself; and a file not read, missing or a directory, was
                // read as nothing.)
                ObjError::NoTriangles { .. } | ObjError::Input(_) => e.to_string(),
                e => format!("{e}{}", obj::read_as_obj_hint(&path.display().to_string())),
            }),
        }
    }

    /// A warning where the scene and its light lie within 2⁻⁶⁰ (≈ 8.7e-19) of each other: the
    /// lit steps divide by ‖r‖², the light's squared distance, which underflows f32 there
    /// (D reads inf, or 0 where the light's power, which goes with the size squared, does
    /// too). Geometry this small renders, unlit, as at any scale; raylab does not rescale it.
    fn too_small_to_light(&self) -> Option<String> {
        let (lo, hi) = self.bounds()?;
        let far = [0, 1, 2]
            .map(|k| {
                let l = self.light.position[k] as f64;
                (l - lo[k] as f64).abs().max((hi[k] as f64 - l).abs())
            })
            .into_iter()
            .fold(0.0, f64::max);
        let reach = self.size().max(far);
        let least = 2f64.powi(-60);
        // (Below 1e-30 across, the camera that frames a scene stands no nearer than 1e-30.)
        let framed = match self.size() < 1e-30 && self.camera.is_none() {
            true => "; a camera framing it stands back 1e-30, where it looks too small to see",
            false => "",
        };
        (reach > 0.0 && reach < least).then(|| {
            format!(
                "{}: the scene and its light lie within {reach:.2e}, below 2⁻⁶⁰ (≈ 8.7e-19): \
                 light falls off with squared distances that underflow f32 there, so the lit \
                 steps read D = inf or 0{framed}; scale the scene up",
                self.name
            )
        })
    }

    /// Whether [`Scene::load`] reads `path` as an OBJ file (what is not a `.scene` file), so
    /// that how OBJ coordinates are read ([`ObjFrame`]) matters to it.
    pub fn reads_as_obj(path: &std::path::Path) -> bool {
        let ext = path.extension().and_then(|e| e.to_str());
        !ext.is_some_and(|e| e.eq_ignore_ascii_case("scene"))
    }

    /// The bounding box's diagonal (1 for an empty scene): the scene's size for camera moves.
    pub fn size(&self) -> f64 {
        self.bounds().map_or(1.0, |(lo, hi)| {
            let d = [0, 1, 2].map(|k| hi[k] as f64 - lo[k] as f64);
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
    }

    /// The built-in lab Cornell box (30 triangles), embedded in the binary.
    pub fn cornell() -> Self {
        cornell::scene()
    }

    /// How many primitives (instanced triangles included).
    pub fn len(&self) -> usize {
        self.shapes.len() + self.instances.iter().map(Instance::len).sum::<usize>()
    }

    /// Whether the scene has no primitives.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The scene with `instances` placed among its shapes: in primitive order, each holding
    /// `first_prim..first_prim + len`, the shapes filling the gaps in order. The error says
    /// what does not fit.
    pub fn with_instances(mut self, instances: Vec<Instance>) -> Result<Self, String> {
        let total = self.shapes.len() + instances.iter().map(Instance::len).sum::<usize>();
        if total > u32::MAX as usize - 1 {
            return Err(format!(
                "{}: {total} primitives, more than {} can be numbered",
                self.name,
                u32::MAX - 1
            ));
        }
        let mut next = 0usize;
        let mut explicit = 0usize;
        for inst in &instances {
            let gap = (inst.first_prim as usize)
                .checked_sub(next)
                .ok_or_else(|| {
                    format!(
                        "{}: instances overlap at primitive {}",
                        self.name, inst.first_prim
                    )
                })?;
            explicit += gap;
            next = inst.first_prim as usize + inst.len();
        }
        if explicit > self.shapes.len() {
            return Err(format!(
                "{}: instances leave gaps no shape fills",
                self.name
            ));
        }
        if let Some(bad) = instances
            .iter()
            .find(|i| !Instance::placeable(&i.world_from_object))
        {
            return Err(format!(
                "{}: {} cannot be placed by {:?}",
                self.name, bad.mesh.name, bad.world_from_object
            ));
        }
        self.instance_index = instance::index(&instances);
        self.instances = instances;
        self.bounds_once = OnceLock::new();
        Ok(self)
    }

    /// The placed meshes, in primitive order.
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// Where primitive `prim` is stored.
    #[inline]
    pub fn stored(&self, prim: u32) -> Stored {
        match self.instances.is_empty() {
            true => Stored::Explicit(prim as usize),
            false => instance::locate(&self.instances, &self.instance_index, prim),
        }
    }

    /// Primitive `prim` in the world (an instanced triangle computed from its mesh).
    #[inline(always)]
    pub fn shape(&self, prim: u32) -> Shape<f32> {
        match self.instances.is_empty() {
            true => self.shapes[prim as usize],
            false => self.stored_shape(prim),
        }
    }

    #[inline(never)]
    fn stored_shape(&self, prim: u32) -> Shape<f32> {
        match self.stored(prim) {
            Stored::Explicit(i) => self.shapes[i],
            Stored::Instanced { instance, local } => {
                Shape::from(self.instances[instance].world_triangle(local))
            }
        }
    }

    /// The colours of the primitives stored one by one, by their order in `shapes`.
    pub fn colors(&self) -> &[V3<f32>] {
        &self.colors
    }

    /// The colours to change (one per shape, kept in step with `shapes`).
    pub fn colors_mut(&mut self) -> &mut Vec<V3<f32>> {
        self.color_runs = OnceLock::new();
        &mut self.colors
    }

    /// The colour of primitive `prim` and primitives around it known to share it: an
    /// instance showing one colour gives all of its own (a flat frame of 1,000 instanced
    /// bunnies then finds the instance once per run of pixels, not per pixel); without
    /// instances, a run of equal colours in `colors` where there are few such runs (a mesh
    /// of one material is one run: a flat frame's pixels then read no colour per primitive,
    /// 8-9% of the bunny's and the 1M-triangle mesh's flat frames at 640×360).
    #[inline]
    pub fn color_run(&self, prim: u32) -> (std::ops::Range<u32>, V3<f32>) {
        let one = prim..prim.saturating_add(1);
        if self.instances.is_empty() {
            let runs = self.color_runs.get_or_init(|| ColorRuns::of(&self.colors));
            if let Some(run) = runs.around(prim) {
                let first = run.start as usize;
                return (run, self.colors[first]);
            }
        }
        match self.stored(prim) {
            Stored::Explicit(i) => (one, self.colors[i]),
            Stored::Instanced { instance, local } => {
                let instance = &self.instances[instance];
                let run = match instance.one_color() {
                    true => instance.prims(),
                    false => one,
                };
                (run, instance.color(local))
            }
        }
    }

    /// The colour of primitive `prim`.
    #[inline(always)]
    pub fn color(&self, prim: u32) -> V3<f32> {
        match self.instances.is_empty() {
            true => self.colors[prim as usize],
            false => self.stored_color(prim),
        }
    }

    #[inline(never)]
    fn stored_color(&self, prim: u32) -> V3<f32> {
        match self.stored(prim) {
            Stored::Explicit(i) => self.colors[i],
            Stored::Instanced { instance, local } => self.instances[instance].color(local),
        }
    }

    /// Every primitive in the world, in primitive order.
    pub fn all_shapes(&self) -> impl Iterator<Item = Shape<f32>> + '_ {
        (0..self.len() as u32).map(|p| self.shape(p))
    }

    /// Colours primitives `prims` with `color` (the viewer's highlight): shapes one by one,
    /// instances that lie inside the range as a whole.
    pub fn tint(&mut self, prims: std::ops::Range<u32>, color: V3<f32>) {
        let mut p = prims.start;
        while p < prims.end {
            match self.stored(p) {
                Stored::Explicit(i) => {
                    self.colors_mut()[i] = color;
                    p += 1;
                }
                // (One step over the instance, not one per triangle.)
                Stored::Instanced { instance, .. } => {
                    let inst = &mut self.instances[instance];
                    if prims.start <= inst.first_prim && inst.prims().end <= prims.end {
                        inst.tint = Some(color);
                    }
                    p = inst.prims().end;
                }
            }
        }
    }

    /// The same scene with every instance's triangles stored one by one (what a `.scene`
    /// file without instancing gives): the reference instanced scenes are tested against.
    pub fn flattened(&self) -> Scene {
        let mut flat = self.clone();
        flat.shapes = self.all_shapes().collect();
        *flat.colors_mut() = (0..self.len() as u32).map(|p| self.color(p)).collect();
        flat.instances.clear();
        flat.instance_index.clear();
        flat
    }

    /// The explicit shapes (those outside any instance) with their primitive indices.
    pub fn explicit_with_prims(&self) -> Vec<(Shape<f32>, u32)> {
        let mut out = Vec::with_capacity(self.shapes.len());
        let mut shapes = self.shapes.iter();
        let mut prim = 0u32;
        for inst in &self.instances {
            while prim < inst.first_prim {
                out.push((*shapes.next().expect("checked by with_instances"), prim));
                prim += 1;
            }
            prim = inst.prims().end;
        }
        out.extend(shapes.map(|s| {
            prim += 1;
            (*s, prim - 1)
        }));
        out
    }

    /// A light and indirect term for a loaded model, placed as the lab places them relative to
    /// the Cornell box: above the centre and towards the default camera (at −z), with the power
    /// scaled by the model's size squared so the irradiance matches the lab's.
    pub fn light_for_bounds(bounds: Bounds) -> PointLight {
        let (lo, hi) = bounds;
        let centre = [
            (lo[0] + hi[0]) / 2.0,
            (lo[1] + hi[1]) / 2.0,
            (lo[2] + hi[2]) / 2.0,
        ];
        let half =
            ((hi[0] - lo[0]).max(hi[1] - lo[1]).max(hi[2] - lo[2]) / 2.0).max(f32::MIN_POSITIVE);
        let p = 14.0 * half * half;
        PointLight {
            position: [centre[0], centre[1] - 1.5 * half, centre[2] - 2.0 * half],
            power: [p, p, p],
        }
    }
}

/// The runs of equal colours along a scene's stored primitives, where there are at most
/// [`ColorRuns::MAX`] of them (else none are kept, and each primitive's colour is read).
#[derive(Clone, Debug, Default)]
struct ColorRuns {
    /// Each run's first primitive, increasing from 0; the last run ends at `end`.
    starts: Vec<u32>,
    end: u32,
}

impl ColorRuns {
    /// Enough for a mesh's few materials in contiguous groups; a search among them stays
    /// shorter than a read of a colour far away in memory.
    const MAX: usize = 256;

    fn of(colors: &[V3<f32>]) -> Self {
        let mut starts = Vec::new();
        for (i, c) in colors.iter().enumerate() {
            // (Bits, not `==`: a NaN colour, unequal to itself, still makes one run.)
            if i == 0 || c.map(f32::to_bits) != colors[i - 1].map(f32::to_bits) {
                if starts.len() == Self::MAX {
                    return Self::default();
                }
                starts.push(i as u32);
            }
        }
        Self {
            starts,
            end: colors.len() as u32,
        }
    }

    /// The run holding primitive `prim`, if runs are kept and it is stored.
    #[inline]
    fn around(&self, prim: u32) -> Option<std::ops::Range<u32>> {
        if prim >= self.end {
            return None;
        }
        let r = self.starts.partition_point(|&s| s <= prim).checked_sub(1)?;
        let end = self.starts.get(r + 1).copied().unwrap_or(self.end);
        Some(self.starts[r]..end)
    }
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    fn scene_of(colors: Vec<V3<f32>>) -> Scene {
        let shapes = (0..colors.len())
            .map(|i| {
                let x = i as f32;
                Shape::from([[x, 0.0, 1.0], [x + 1.0, 0.0, 1.0], [x, 1.0, 1.0]])
            })
            .collect();
        Scene::new("runs", shapes, colors, cornell::LIGHT, cornell::AMBIENT)
    }

    /// Every primitive's run holds it, shares its colour throughout and is as long as the
    /// colours allow (where runs are kept), and the colour given is the primitive's own.
    fn check_runs(scene: &Scene, kept: bool) {
        let colors = scene.colors();
        for p in 0..colors.len() as u32 {
            let (run, c) = scene.color_run(p);
            assert!(run.contains(&p), "{p} in {run:?}");
            assert_eq!(c, colors[p as usize], "colour of {p}");
            assert!(colors[run.start as usize..run.end as usize]
                .iter()
                .all(|x| *x == c));
            if kept {
                let (s, e) = (run.start as usize, run.end as usize);
                assert!(s == 0 || colors[s - 1] != c, "run {run:?} stops early");
                assert!(
                    e == colors.len() || colors[e] != c,
                    "run {run:?} stops early"
                );
            } else {
                assert_eq!(run, p..p + 1);
            }
        }
    }

    fn colour_runs_follow_the_colours_and_every_change_to_them() {
        let (a, b) = ([0.1, 0.2, 0.3], [0.9, 0.8, 0.7]);
        let mut scene = scene_of(vec![a, a, b, b, b, a]);
        check_runs(&scene, true);
        assert_eq!(scene.color_run(3), (2..5, b));
        // Changed after the runs were found: through `colors_mut`, by `tint`, on a clone.
        scene.colors_mut()[1] = b;
        check_runs(&scene, true);
        assert_eq!(scene.color_run(3), (1..5, b));
        let before = scene.clone();
        scene.tint(4..6, b);
        check_runs(&scene, true);
        assert_eq!(scene.color_run(3), (1..6, b));
        let mut copy = before.clone();
        copy.colors_mut().push(a);
        copy.shapes.push(copy.shapes[0]);
        check_runs(&copy, true);
        assert_eq!(copy.color_run(5), (5..7, a));
        check_runs(&before, true);
        assert_eq!(before.color_run(5), (5..6, a));
    }

    fn too_many_colour_runs_give_each_primitive_its_own() {
        // Runs of two primitives: MAX of them are kept, one more and none is.
        let pairs = |runs: usize| {
            (0..2 * runs)
                .map(|i| [(i / 2 % 2) as f32, 0.5, 0.5])
                .collect()
        };
        let kept = scene_of(pairs(ColorRuns::MAX));
        check_runs(&kept, true);
        assert_eq!(kept.color_run(5), (4..6, [0.0, 0.5, 0.5]));
        check_runs(&scene_of(pairs(ColorRuns::MAX + 1)), false);
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "colour_runs_follow_the_colours_and_every_change_to_them",
            colour_runs_follow_the_colours_and_every_change_to_them,
        ),
        (
            "too_many_colour_runs_give_each_primitive_its_own",
            too_many_colour_runs_give_each_primitive_its_own,
        ),
    ];
}
