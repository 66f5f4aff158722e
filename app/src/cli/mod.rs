//! The command line: `raylab` (the window), `raylab render`, `trace`, `bench`, `inspect`,
//! `suite` and `check` (check.rs, and program.rs for the programs it runs).

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use glam::DVec3;
use raylab::accel::AccelChoice;
use raylab::camera::Camera;
use raylab::controller::CameraController;
use raylab::math::radians_of_degrees;
use raylab::render::settings::{Control, Kind};
use raylab::render::{RenderSettings, CONTROLS};
use raylab::scene::{ObjFrame, Scene};
use std::path::{Path, PathBuf};

/// `println!` for the CLI's reports, where a closed stdout (`raylab bench | head -1`) is an
/// error that ends the command quietly (see `main`) instead of a panic.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout(), $($arg)*)?;
    }};
}

mod access;
mod account;
mod budget;
mod cases;
mod check;
mod check_image;
mod class_dir;
mod evidence;
mod grade;
mod hint_geometry;
mod images;
mod line_up;
mod program;
mod program_paths;
mod reports;
mod reproducers;
mod rounding;
mod rubric;
mod run_words;
mod suite_dir;
mod t_failures;
mod template;
mod trace;

pub use check::{suite, CheckArgs, SuiteArgs};
pub use grade::{grade, GradeArgs};
pub use images::{bench, inspect, render, Interrupted};
pub use trace::{trace, TraceArgs};

/// raylab: an interactive, teaching-grade CPU raycaster (the raytracing lab's Cornell box).
#[derive(Parser, Debug)]
#[command(name = "raylab", version, about, long_about = None, args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// What to do; without a command, raylab opens the interactive window.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// The window's flags (without a command).
    #[command(flatten)]
    pub window: raylab_app::window::WindowArgs,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene to a PNG file, headless, and print the time and Mrays/s.
    Render(RenderArgs),
    /// Intersect rays from a text file with primitives from a text file and print
    /// `hit <t> <index>` or `miss` per ray (how the intersection code is tested from outside).
    Trace(TraceArgs),
    /// Time K frames (after a warm-up) and print the accelerator build time, the median frame
    /// time, the hit count, and as the last line `mrays_per_s=<median>`.
    Bench(BenchArgs),
    /// Print one camera ray (a pixel's centre, or through an image position: a sample) as the
    /// lecture writes it (u, v, f, d, the triangle's
    /// A·x = b or the sphere's quadratic, t, the deciding level of the method, the surface
    /// point and normal, the shadow ray and what blocks it, ρ, D, N and the colour): the
    /// window's ray inspector, headless.
    Inspect(InspectArgs),
    /// The hard-case suite as files: `raylab suite export DIR` writes every family's scene
    /// and rays in the `trace` formats, for code that is not raylab's.
    Suite(SuiteArgs),
    /// Grade answers from code that is not raylab's against the exact ones: an answer file
    /// (--answers) or a program run on a scene (--program) or on every family of an exported
    /// suite (--suite). Prints rights, ties, leaks, false hits, wrong primitives and t errors,
    /// the first wrong rays, and as the last line `check: rays N right R leaks L false_hits F
    /// wrong W ties T t_failures U`. Exit 0 when every answer stands (no leak, false hit,
    /// wrong primitive or t beyond --t-tolerance); 1 when one does not (or a program gave no
    /// answers); 2 on bad input.
    Check(CheckArgs),
    /// Grade a class: run --program in a private copy of every submission directory of
    /// CLASS_DIR on every family of an exported suite (several submissions at once, each
    /// under limits of time, output, memory and processes) and print a row per submission;
    /// --csv and --json write a record per submission and family, --rubric adds points.
    /// Exit 0 when the grading ran, whatever the grades; 2 on bad input.
    Grade(GradeArgs),
}

/// The values of a choice control for clap, each with its one-line explanation (the values
/// are described once, in the library's table).
pub(crate) fn possible_values(control: &Control) -> clap::builder::PossibleValuesParser {
    use clap::builder::PossibleValue;
    let Kind::Choice { options, .. } = control.kind else {
        unreachable!("{} is not a choice", control.name)
    };
    let values = options()
        .into_iter()
        .map(|o| PossibleValue::new(o.name).help(o.help));
    clap::builder::PossibleValuesParser::new(values)
}

/// The image's controls as flags, one per row of [`CONTROLS`] (`--step`, `--spp`, `--method`,
/// `--cracks`, …): what they set, over the defaults. `ALL = false` keeps only those that
/// decide one ray's answer, `--step` and `--method` (`raylab inspect`, which follows the
/// pixel's centre ray and shows no cracks).
#[derive(Clone, Copy, Debug, Default)]
pub struct ControlFlags<const ALL: bool = true>(pub RenderSettings);

impl<const ALL: bool> ControlFlags<ALL> {
    /// The controls these flags set.
    fn controls() -> impl Iterator<Item = &'static Control> {
        CONTROLS
            .iter()
            .filter(|c| ALL || matches!(c.name, "step" | "method"))
    }
}

impl<const ALL: bool> clap::FromArgMatches for ControlFlags<ALL> {
    fn from_arg_matches(matches: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut flags = Self::default();
        flags.update_from_arg_matches(matches)?;
        Ok(flags)
    }

    fn update_from_arg_matches(&mut self, matches: &clap::ArgMatches) -> Result<(), clap::Error> {
        for control in Self::controls() {
            match control.kind {
                Kind::Toggle { set, .. } => {
                    if matches.get_flag(control.name) {
                        set(&mut self.0, true)
                    }
                }
                Kind::Count { set, .. } => {
                    if let Some(n) = matches.get_one::<u32>(control.name) {
                        set(&mut self.0, *n)
                    }
                }
                Kind::Choice { .. } => {
                    if let Some(name) = matches.get_one::<String>(control.name) {
                        let set = control.set_text(&mut self.0, name);
                        set.map_err(|e| clap::Error::raw(clap::error::ErrorKind::InvalidValue, e))?;
                    }
                }
            }
        }
        Ok(())
    }
}

impl<const ALL: bool> clap::Args for ControlFlags<ALL> {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        let defaults = RenderSettings::default();
        cmd.args(Self::controls().map(|control| {
            let arg = clap::Arg::new(control.name)
                .long(control.name)
                .help(control.help)
                .conflicts_with("view");
            match control.kind {
                Kind::Toggle { .. } => arg.action(clap::ArgAction::SetTrue),
                Kind::Count { min, max, .. } => arg
                    .value_name("N")
                    .allow_negative_numbers(true)
                    .value_parser(clap::value_parser!(u32).range(min as i64..=max as i64))
                    .default_value(control.text(&defaults)),
                Kind::Choice { .. } => arg
                    .value_name(control.name.to_uppercase())
                    .value_parser(possible_values(control))
                    .default_value(control.text(&defaults)),
            }
        }))
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

/// `--accel`: the structure the renderer's rays go through.
#[derive(clap::Args, Debug)]
pub struct AccelArg {
    /// Acceleration structure: `auto` picks the flat SIMD loop below 64 primitives and a BVH
    /// from there on; `flat` and `bvh` force one.
    #[arg(long, default_value = "auto")]
    pub accel: AccelChoice,
}

/// How an image is made: shared by `render` and `bench`.
#[derive(clap::Args, Debug)]
pub struct ImageArgs {
    /// The image's controls (step, supersampling, method, cracks).
    #[command(flatten)]
    pub controls: ControlFlags,
    #[command(flatten)]
    pub accel: AccelArg,
    /// Test every camera ray against every triangle of a small scene instead of only those
    /// whose screen bounds meet its 16x16 tile (the same image, slower: to measure the gain).
    #[arg(long)]
    pub no_tile_culling: bool,
}

impl ImageArgs {
    /// The settings the flags give (the size is the view's).
    fn settings(&self) -> RenderSettings {
        RenderSettings {
            tile_culling: !self.no_tile_culling,
            ..self.controls.0
        }
    }
}

/// Arithmetic precision of `trace`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Precision {
    /// Single precision, as the renderer uses.
    F32,
    /// Double precision.
    F64,
}

/// What to look at and from where: shared by `render`, `bench`, `inspect` and `check --image`.
#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    /// A view saved by the window (F5): its scene, camera, light, size, step, samples and
    /// method, instead of the flags that set them.
    #[arg(long, value_name = "FILE.view", conflicts_with_all = [
        "scene", "width", "height", "focal", "camera", "yaw", "pitch", "light", "obj_frame",
    ])]
    pub view: Option<PathBuf>,
    /// `cornell` for the built-in lab Cornell box, a `.scene` file (the transform-stack scene
    /// format: see the README), or the path of an OBJ file (triangulated; Kd colours from its
    /// .mtl; the camera is placed to frame the model).
    #[arg(long, default_value = "cornell", value_parser = utf8_name())]
    pub scene: String,
    /// Image width in pixels (1..=16384; default 640, `check --image` 160).
    #[arg(
        long,
        allow_negative_numbers = true,
        value_parser = count_in::<u32>(1..=raylab::render::MAX_SIDE as i64)
    )]
    pub width: Option<u32>,
    /// Image height in pixels (1..=16384; default 480, `check --image` 120).
    #[arg(
        long,
        allow_negative_numbers = true,
        value_parser = count_in::<u32>(1..=raylab::render::MAX_SIDE as i64)
    )]
    pub height: Option<u32>,
    /// Focal length in pixels (default: the image width, about 53° of horizontal view).
    #[arg(long, allow_hyphen_values = true)]
    pub focal: Option<f64>,
    /// Camera position `x,y,z` in scene units (default: the lab camera (0,0,-3.001) for the
    /// Cornell box, or a position framing the OBJ model as the window frames it). Note y
    /// points down.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub camera: Option<DVec3>,
    /// Camera yaw in degrees, about the y axis; positive turns right (default 0, or the
    /// `.scene` file's camera).
    #[arg(long, allow_hyphen_values = true)]
    pub yaw: Option<f64>,
    /// Camera pitch in degrees, about the camera's x axis; positive looks up (default 0, or
    /// the `.scene` file's camera).
    #[arg(long, allow_hyphen_values = true)]
    pub pitch: Option<f64>,
    /// The point light's position `x,y,z` (default: the scene's: the lab's (0,-0.5,-0.7) for
    /// the Cornell box, a `.scene` file's `light`, or one placed for an OBJ model's size), as
    /// the window's panel sets it.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub light: Option<DVec3>,
    /// How an OBJ file's coordinates are read: `yup` (the usual convention, y up and the front
    /// towards +z; y and z are negated so the model stands upright in the lab's y-down world,
    /// facing the camera) or `lab` (already y-down, like cornell_lab.obj).
    #[arg(long, default_value = "yup")]
    pub obj_frame: ObjFrame,
}

/// The ids of [`ViewArgs`]' flags but `--scene` (which `check --rays` reads too).
pub(crate) const VIEW_FLAGS: [&str; 9] = [
    "view",
    "width",
    "height",
    "focal",
    "camera",
    "yaw",
    "pitch",
    "light",
    "obj_frame",
];

/// `raylab render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Output PNG file.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Also write, beside the PNG, each pixel's centre-ray primitive (OUT.prim.npy, uint32,
    /// 4294967295 for none), t (OUT.t.npy, float32, NaN for none) and unit normal facing the
    /// camera (OUT.normal.npy, float32 H×W×3), as NumPy arrays.
    #[arg(long)]
    pub aov: bool,
}

/// `raylab inspect`: `--pixel` or `--at`, one of them.
#[derive(clap::Args, Debug)]
#[group(id = "ray", required = true, multiple = false)]
pub struct InspectArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    /// The step and the method (the pixel's centre ray: no supersampling, no cracks view).
    #[command(flatten)]
    pub controls: ControlFlags<false>,
    #[command(flatten)]
    pub accel: AccelArg,
    /// The pixel `x,y` (column, row from the top left, 0-based): its centre ray.
    #[arg(long, value_parser = parse_pixel, allow_hyphen_values = true, group = "ray")]
    pub pixel: Option<(u32, u32)>,
    /// The ray through image position `x,y` instead (pixel (i, j) spans [i, i + 1) ×
    /// [j, j + 1)): a supersampled pixel's sample, as the ray inspector's `traced` row names
    /// a crack's marked one.
    #[arg(long, value_parser = parse_position, allow_hyphen_values = true, group = "ray")]
    pub at: Option<Position>,
}

/// An image position as given (`--at`): its numbers, and its text for messages (`1e300`
/// rather than its 301 digits).
#[derive(Clone, Debug)]
pub struct Position {
    pub x: f64,
    pub y: f64,
    pub text: String,
}

/// `x,y` as two values of `T` (spaces around each allowed); the error says `s` is not `what`.
fn parse_pair<T: std::str::FromStr>(s: &str, what: &str) -> Result<(T, T), String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y] = parts[..] else {
        return Err(format!("expected x,y, got '{s}'"));
    };
    match (x.parse(), y.parse()) {
        (Ok(x), Ok(y)) => Ok((x, y)),
        _ => Err(format!("'{s}' is not {what}")),
    }
}

fn parse_position(s: &str) -> Result<Position, String> {
    let what = "an image position x,y (two finite numbers)";
    let (x, y): (f64, f64) = parse_pair(s, what)?;
    match x.is_finite() && y.is_finite() {
        true => Ok(Position {
            x,
            y,
            text: s.trim().to_string(),
        }),
        false => Err(format!("'{s}' is not {what}")),
    }
}

fn parse_pixel(s: &str) -> Result<(u32, u32), String> {
    parse_pair(s, "two pixel coordinates x,y (whole numbers ≥ 0)")
}

/// Runs `raylab check`: `Ok(true)` when every answer stands (rays: `check::check_answers`;
/// a program's image: `check_image::check_image`).
pub fn check(args: &CheckArgs) -> Result<bool> {
    check::check_args(args)?;
    match (&args.image, &args.program) {
        (Some(image), Some(template)) => check_image::check_image(args, image, template),
        _ => check::check_answers(args),
    }
}

/// `raylab bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub image: ImageArgs,
    /// Worker threads (1..=1024; default: all cores).
    #[arg(long, allow_negative_numbers = true, value_parser = count_in::<usize>(1..=1024))]
    pub threads: Option<usize>,
    /// Frames timed after one warm-up frame (1..=10000); the median is reported.
    #[arg(
        long,
        default_value_t = 5,
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(1..=10_000)
    )]
    pub frames: u32,
    /// Run the kernels' build for this SIMD level (`baseline`, `avx2` or `avx512`; at most
    /// what the CPU has), to compare the builds in one run. Default: the best the CPU has.
    #[arg(long)]
    pub simd: Option<raylab::math::simd::SimdLevel>,
}

/// Whether `e` is a write to a closed pipe (the reader went away: not worth a message).
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// The cores to run on where `--threads` or `-j` is not given: all of them, at most the
/// 1024 those flags take.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().min(1024))
}

/// A count flag's parser: a value outside `range`, a negative one too, is named with the
/// range (as a plain `usize` or `u64`, `-1` read "invalid digit"; as a plain `u32`, a
/// range of 0..=4294967295).
pub fn count_in<T: TryFrom<i64> + Clone + Send + Sync + 'static>(
    range: impl std::ops::RangeBounds<i64> + 'static,
) -> impl clap::builder::TypedValueParser<Value = T> {
    use clap::builder::TypedValueParser;
    // (In range, so never negative: the conversion cannot fail.)
    let convert = |n: i64| T::try_from(n).ok().expect("a count in its range");
    clap::value_parser!(i64).range(range).map(convert)
}

/// A scene's name, which is kept as text (a view file and the window's field show it): a
/// path that is not UTF-8 is refused naming its flag, where clap's own check names none.
fn utf8_name() -> impl clap::builder::TypedValueParser<Value = String> {
    use clap::builder::TypedValueParser;
    clap::builder::OsStringValueParser::new().try_map(|name| {
        name.into_string().map_err(|name| {
            let shown = name.to_string_lossy().into_owned();
            format!(
                "{shown} is not UTF-8, and raylab keeps a scene's name as text: rename the file"
            )
        })
    })
}

fn parse_vec3(s: &str) -> Result<DVec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected x,y,z (three comma-separated numbers), got '{s}'"
        ));
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        let x: f64 = p.parse().map_err(|_| format!("'{p}' is not a number"))?;
        if !x.is_finite() {
            return Err(format!("'{p}' is not finite"));
        }
        v[k] = x;
    }
    Ok(DVec3::from_array(v))
}

/// Loads `cornell`, a `.scene` file or an OBJ file.
pub fn load_scene(spec: &str, frame: ObjFrame) -> Result<Scene> {
    Scene::open(spec, frame).map_err(anyhow::Error::msg)
}

/// [`load_scene`] with its warnings printed.
fn load_scene_warning(spec: &str, frame: ObjFrame) -> Result<Scene> {
    let scene = load_scene(spec, frame)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(scene)
}

/// Moves the scene's light to `position`, if that is within the range the core renders.
fn set_light(scene: &mut Scene, position: [f64; 3]) -> Result<()> {
    raylab::math::check_range(
        "light position",
        position,
        raylab::math::MAX_VIEW_COORDINATE,
    )
    .map_err(anyhow::Error::msg)?;
    scene.light.position = position.map(|c| c as f32);
    Ok(())
}

/// The scene, camera and settings of a view file (F5 in the window). A relative scene path
/// that does not exist from here is looked up beside the view file.
fn prepare_view(path: &Path, base: RenderSettings) -> Result<(Scene, Camera, RenderSettings)> {
    let text = read_text(path)?;
    let view = raylab::view::View::parse(&path.display().to_string(), &text)?;
    let spec = view.scene_path(path);
    let mut scene = load_scene_warning(&spec, view.obj_frame)
        .with_context(|| format!("loading scene '{spec}' of view '{}'", path.display()))?;
    if let Some(light) = view.light {
        set_light(&mut scene, light.map(f64::from))?;
    }
    let mut s = view.settings;
    // (A view holds no tile culling: --no-tile-culling applies to it too.)
    s.tile_culling = base.tile_culling;
    // (Without a `camera` line, the scene's own start, as `--scene` takes it; a `focal` line
    // sets the lens either way.)
    let flags = match view.camera {
        Some(c) => CameraFlags {
            position: Some(DVec3::from_array(c.position)),
            yaw: Some(c.yaw),
            pitch: Some(c.pitch),
            focal: Some(view.focal.unwrap_or(c.focal_ratio() * s.width as f64)),
        },
        None => CameraFlags {
            focal: view.focal,
            ..CameraFlags::default()
        },
    };
    let camera = starting_camera(&scene, &spec, flags, (s.width, s.height))?;
    Ok((scene, camera, s))
}

/// The camera flags of a render (degrees), each `None` where not given.
#[derive(Clone, Copy, Default)]
struct CameraFlags {
    position: Option<DVec3>,
    yaw: Option<f64>,
    pitch: Option<f64>,
    focal: Option<f64>,
}

/// The camera of a render of `scene` (named `name`) at `size`: the flags win; then a `.scene`
/// file's camera; then the lab's or one framing the model.
fn starting_camera(
    scene: &Scene,
    name: &str,
    flags: CameraFlags,
    (width, height): (u32, u32),
) -> Result<Camera> {
    let start = scene.camera;
    let yaw = radians_of_degrees(flags.yaw.or(start.map(|c| c.yaw)).unwrap_or(0.0));
    let pitch = radians_of_degrees(flags.pitch.or(start.map(|c| c.pitch)).unwrap_or(0.0));
    let focal = (flags.focal).unwrap_or(start.map_or(1.0, |c| c.focal_ratio()) * width as f64);
    let position = match (flags.position, start, name) {
        (Some(pos), _, _) => pos,
        (None, Some(c), _) => DVec3::from_array(c.position),
        (None, None, raylab::scene::CORNELL) => Camera::cornell(width).position(),
        (None, None, _) => {
            let bounds = scene.bounds().context("empty scene")?;
            CameraController::framing(bounds, width, height).position
        }
    };
    Ok(Camera::from_yaw_pitch(position, yaw, pitch, focal)?)
}

/// The image size of `render`, `bench` and `inspect` where the flags give none.
const DEFAULT_SIZE: (u32, u32) = (640, 480);

/// The scene, camera and settings a `ViewArgs` asks for, over `base` (the controls' flags).
fn prepare(v: &ViewArgs, base: RenderSettings) -> Result<(Scene, Camera, RenderSettings)> {
    prepare_sized(v, DEFAULT_SIZE, base)
}

/// [`prepare`] with another default image size.
fn prepare_sized(
    v: &ViewArgs,
    size: (u32, u32),
    base: RenderSettings,
) -> Result<(Scene, Camera, RenderSettings)> {
    if let Some(path) = &v.view {
        return prepare_view(path, base);
    }
    let (width, height) = (v.width.unwrap_or(size.0), v.height.unwrap_or(size.1));
    let settings = RenderSettings {
        width,
        height,
        ..base
    };
    settings.validate()?;
    let mut scene = load_scene_warning(&v.scene, v.obj_frame)
        .with_context(|| format!("loading scene '{}'", v.scene))?;
    if let Some(light) = v.light {
        set_light(&mut scene, light.to_array())?;
    }
    let flags = CameraFlags {
        position: v.camera,
        yaw: v.yaw,
        pitch: v.pitch,
        focal: v.focal,
    };
    let camera = starting_camera(&scene, &v.scene, flags, (width, height))?;
    Ok((scene, camera, settings))
}

pub(crate) fn read_text(path: &Path) -> Result<String> {
    Ok(raylab::input::read_text(
        path,
        raylab::input::max_input_bytes(),
    )?)
}

/// A scene file's text for `trace`, where `cornell` (no such file) names the built-in lab box
/// as everywhere a scene is named: a scene of that one statement. (Not for `check`: the
/// program it runs is given the scene's path.)
pub(crate) fn scene_text(path: &Path) -> Result<String> {
    match path.as_os_str() == raylab::scene::CORNELL && !path.exists() {
        true => Ok(format!("{}\n", raylab::scene::CORNELL)),
        false => read_text(path),
    }
}

/// Says which command a mistyped one meant: `raylab rendr` opens the window on a file named
/// `rendr`, which does not exist, so a word without an extension that is no file and is within
/// two edits of a command is refused with that command suggested.
pub fn not_a_command(model: &Path) -> Result<()> {
    use clap::CommandFactory;
    let word = model.to_string_lossy();
    if model.exists() || model.extension().is_some() || word == raylab::scene::CORNELL {
        return Ok(());
    }
    let command = Cli::command();
    let nearest = (command.get_subcommands())
        .map(|c| c.get_name().to_string())
        .map(|name| (edits(&word, &name), name))
        .min();
    match nearest {
        Some((d, name)) if d <= 2 => bail!(
            "'{word}' is neither a file nor a command; did you mean `raylab {name}`? (`raylab --help` lists the commands)"
        ),
        _ => Ok(()),
    }
}

/// The edit distance of two words (insertions, deletions, substitutions).
fn edits(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for j in 0..b.len() {
            let next = (prev + usize::from(ca != b[j]))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            prev = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// Refuses an output whose extension names another format than the PNG raylab writes
/// (`-o x.jpg` wrote PNG bytes into a .jpg); no extension, or a device, is written as PNG.
pub(crate) fn png_only(out: &Path) -> Result<()> {
    match out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
    {
        Some(ext) if ext != "png" && !out.starts_with("/dev") => bail!(
            "{}: raylab writes PNG images only; name the file .png",
            out.display()
        ),
        _ => Ok(()),
    }
}
