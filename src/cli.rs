//! The command line: `raylab` (the window), `raylab render` and `raylab trace`.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use glam::DVec3;
use raylab::camera::Camera;
use raylab::controller::CameraController;
use raylab::geometry::Method;
use raylab::render::{self, LabStep, RenderSettings};
use raylab::scene::{self, Scene};
use raylab::tracefile;
use std::path::{Path, PathBuf};

/// raylab: an interactive, teaching-grade CPU raycaster (the raytracing lab's Cornell box).
#[derive(Parser, Debug)]
#[command(version, about, long_about = None, args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// What to do; without a command, raylab opens the interactive window.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// An OBJ model to open in the window instead of the built-in Cornell box.
    pub model: Option<PathBuf>,
    /// Scripted run: show N frames (then finish the script and refine the image), save what
    /// the window showed to --screenshot and exit 0. For tests; needs a display.
    #[arg(long, value_name = "N", requires = "screenshot")]
    pub frames: Option<u64>,
    /// With --frames: the PNG file to save the window to.
    #[arg(long, value_name = "FILE.png", requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// With --frames: timed key and mouse events to replay, one per line:
    /// `<ms> key <W|A|S|D|Q|E|Left|Right|Up|Down|Shift|R> down|up`, `<ms> mouse <dx> <dy>`,
    /// `<ms> wheel <lines>`, `<ms> step <flat|direct|shadows|indirect>`.
    #[arg(long, value_name = "FILE", requires = "frames")]
    pub script: Option<PathBuf>,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene to a PNG file, headless, and print the time and Mrays/s.
    Render(RenderArgs),
    /// Intersect rays from a text file with primitives from a text file and print
    /// `hit <t> <index>` or `miss` per ray (how the intersection code is tested from outside).
    Trace(TraceArgs),
}

/// Ray/triangle method names for clap.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MethodArg {
    /// Woop–Benthin–Wald watertight test (default): no ray slips between shared edges.
    Watertight,
    /// Möller–Trumbore.
    Moller,
    /// The lecture's x = A⁻¹b through an explicit inverse (the baseline).
    Cramer,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Method {
        match m {
            MethodArg::Watertight => Method::Watertight,
            MethodArg::Moller => Method::Moller,
            MethodArg::Cramer => Method::Cramer,
        }
    }
}

/// Lab step names for clap.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum StepArg {
    /// Step 1: colour of the closest surface, no light.
    Flat,
    /// Step 3: direct light from the point light, P·max(n·r̂,0)/(4πr²) times the colour.
    Direct,
    /// Step 4: direct light with shadow rays.
    Shadows,
    /// Step 5: shadows plus the lab's constant indirect light (colour·(D + N)).
    Indirect,
}

impl From<StepArg> for LabStep {
    fn from(s: StepArg) -> LabStep {
        match s {
            StepArg::Flat => LabStep::Flat,
            StepArg::Direct => LabStep::Direct,
            StepArg::Shadows => LabStep::Shadows,
            StepArg::Indirect => LabStep::Indirect,
        }
    }
}

/// Arithmetic precision of `trace`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Precision {
    /// Single precision, as the renderer uses.
    F32,
    /// Double precision.
    F64,
}

/// `raylab render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// `cornell` for the built-in lab Cornell box, or the path of an OBJ file (triangulated;
    /// Kd colours from its .mtl; the camera is placed to frame the model).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Image width in pixels (1..=16384).
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// Image height in pixels (1..=16384).
    #[arg(long, default_value_t = 480)]
    pub height: u32,
    /// Focal length in pixels (default: the image width, about 53° of horizontal view).
    #[arg(long, allow_hyphen_values = true)]
    pub focal: Option<f64>,
    /// Camera position `x,y,z` in scene units (default: the lab camera (0,0,-3.001) for the
    /// Cornell box, or a position framing the OBJ model). Note y points down.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub camera: Option<DVec3>,
    /// Camera yaw in degrees, about the y axis; positive turns right.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub yaw: f64,
    /// Camera pitch in degrees, about the camera's x axis; positive looks up.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub pitch: f64,
    /// Lab step (shading).
    #[arg(long, value_enum, default_value = "flat")]
    pub step: StepArg,
    /// Supersampling: N×N stratified rays per pixel (1..=16).
    #[arg(long, default_value_t = 1)]
    pub spp: u32,
    /// Ray/triangle intersection method.
    #[arg(long, value_enum, default_value = "watertight")]
    pub method: MethodArg,
    /// Output PNG file.
    #[arg(long)]
    pub out: PathBuf,
}

/// `raylab trace`.
#[derive(clap::Args, Debug)]
pub struct TraceArgs {
    /// Scene file: `tri x0 y0 z0 x1 y1 z1 x2 y2 z2` or `sphere cx cy cz r` per line; the index
    /// of a primitive is its 0-based position among these lines; `#` and blank lines skipped.
    #[arg(long)]
    pub scene: PathBuf,
    /// Ray file: `ox oy oz dx dy dz tmin tmax` per line (tmax may be `inf`). d is not
    /// normalised; a hit counts for tmin < t < tmax and the nearest wins.
    #[arg(long)]
    pub rays: PathBuf,
    /// Ray/triangle intersection method.
    #[arg(long, value_enum, default_value = "watertight")]
    pub method: MethodArg,
    /// Arithmetic precision: inputs are parsed and intersected in this precision.
    #[arg(long, value_enum, default_value = "f32")]
    pub precision: Precision,
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

/// Loads `cornell` or an OBJ file.
pub fn load_scene(spec: &str) -> Result<Scene> {
    if spec == "cornell" {
        return Ok(Scene::cornell());
    }
    Ok(scene::load_obj_file(Path::new(spec))?)
}

/// Runs `raylab render`.
pub fn render(args: &RenderArgs) -> Result<()> {
    let settings = RenderSettings {
        width: args.width,
        height: args.height,
        step: args.step.into(),
        spp: args.spp,
        method: args.method.into(),
    };
    settings.validate()?;
    let focal = args.focal.unwrap_or(args.width as f64);
    let scene =
        load_scene(&args.scene).with_context(|| format!("loading scene '{}'", args.scene))?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let (yaw, pitch) = (args.yaw.to_radians(), args.pitch.to_radians());
    let camera = match (args.camera, args.scene.as_str()) {
        (Some(pos), _) => Camera::from_yaw_pitch(pos, yaw, pitch, focal)?,
        (None, "cornell") => {
            Camera::from_yaw_pitch(Camera::cornell(args.width).position(), yaw, pitch, focal)?
        }
        (None, _) => {
            let bounds = scene.bounds().context("empty scene")?;
            let framed = CameraController::framing(bounds, args.width, args.height);
            Camera::from_yaw_pitch(framed.position, yaw, pitch, focal)?
        }
    };
    // Fail on an unwritable path before spending the render time.
    std::fs::File::create(&args.out)
        .with_context(|| format!("cannot write '{}'", args.out.display()))?;
    let (rgba, stats) = render::render_image(&scene, &camera, &settings)?;
    render::write_png(&args.out, settings.width, settings.height, &rgba)
        .with_context(|| format!("writing '{}'", args.out.display()))?;
    println!(
        "rendered {} ({} primitives) {}x{} step={} spp={}x{} method={} on {} threads in {:.2} ms: \
         {} primary + {} shadow rays, {:.2} Mrays/s -> {}",
        scene.name,
        scene.len(),
        settings.width,
        settings.height,
        settings.step,
        settings.spp,
        settings.spp,
        settings.method,
        rayon::current_num_threads(),
        stats.elapsed.as_secs_f64() * 1e3,
        stats.primary_rays,
        stats.shadow_rays,
        stats.mrays_per_s(),
        args.out.display()
    );
    Ok(())
}

fn read_text(path: &Path) -> Result<String> {
    if path.is_dir() {
        bail!("{}: is a directory", path.display());
    }
    let bytes = std::fs::read(path).with_context(|| format!("cannot read '{}'", path.display()))?;
    String::from_utf8(bytes).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        anyhow::anyhow!("{}:{line}: not UTF-8 text", path.display())
    })
}

/// Runs `raylab trace`; the whole output is built before anything is printed.
pub fn trace(args: &TraceArgs) -> Result<()> {
    let scene_text = read_text(&args.scene)?;
    let rays_text = read_text(&args.rays)?;
    let (sf, rf) = (
        args.scene.display().to_string(),
        args.rays.display().to_string(),
    );
    let method = args.method.into();
    let out = match args.precision {
        Precision::F32 => tracefile::run::<f32>(&sf, &scene_text, &rf, &rays_text, method)?,
        Precision::F64 => tracefile::run::<f64>(&sf, &scene_text, &rf, &rays_text, method)?,
    };
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(out.as_bytes())?;
    stdout.flush()?;
    Ok(())
}
