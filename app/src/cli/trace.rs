//! `raylab trace`: rays from a text file against primitives from a text file, the answers
//! printed one line per ray (how intersection code is tested from outside).

use super::{possible_values, read_text, Precision};
use anyhow::{bail, Result};
use clap::ValueEnum;
use raylab::accel::AccelChoice;
use raylab::geometry::Method;
use raylab::render::{self, Stage};
use raylab::tracefile;
use std::path::PathBuf;

/// `--method` of `raylab trace`: the render control's values.
fn method_parser() -> impl clap::builder::TypedValueParser<Value = Method> {
    use clap::builder::TypedValueParser;
    let method = render::settings::control("method").expect("a control");
    possible_values(method).map(|name| name.parse().expect("a listed method"))
}

/// `raylab trace`.
#[derive(clap::Args, Debug)]
pub struct TraceArgs {
    /// Scene file (the `.scene` format): at its simplest `tri x0 y0 z0 x1 y1 z1 x2 y2 z2` or
    /// `sphere cx cy cz r` per line; the index of a primitive is its 0-based position among
    /// the primitives; `#` starts a comment.
    #[arg(long)]
    pub scene: PathBuf,
    /// Ray file: `ox oy oz dx dy dz tmin tmax` per line (tmax may be `inf`). d is not
    /// normalised; a hit counts for tmin < t < tmax and the nearest wins.
    #[arg(long)]
    pub rays: PathBuf,
    /// Ray/triangle intersection method.
    #[arg(long, default_value = "adaptive", value_parser = method_parser())]
    pub method: Method,
    /// Arithmetic precision: inputs are parsed and intersected in this precision.
    #[arg(long, value_enum, default_value = "f32")]
    pub precision: Precision,
    /// Which path answers: `reference` (the scalar loop over every primitive), the
    /// renderer's per-ray structures, `flat` (the SIMD loop), `bvh`, or `auto` (as the
    /// renderer picks), or `packets` (the renderer's frame queries: rays with one origin, tmin
    /// 0 and tmax inf, 8 at a time as camera rays, or with `--query any` tmin 0 and tmax 1 as
    /// shadow segments; adaptive method only); the structures run in f32 only.
    #[arg(long, default_value = "reference")]
    pub accel: TraceAccel,
    /// What each ray asks: `nearest` (`hit <t> <index>` or `miss`) or `any` (`hit` or
    /// `miss`: whether anything is hit with tmin < t < tmax, a shadow ray's question; with
    /// `--accel packets`, rays with one origin, tmin 0 and tmax 1 go 8 at a time through the
    /// renderer's shadow packets).
    #[arg(long, value_enum, default_value = "nearest")]
    pub query: QueryArg,
}

/// `--query` of `raylab trace`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum QueryArg {
    Nearest,
    Any,
}

impl From<QueryArg> for tracefile::Query {
    fn from(q: QueryArg) -> Self {
        match q {
            QueryArg::Nearest => Self::Nearest,
            QueryArg::Any => Self::Any,
        }
    }
}

/// The paths `raylab trace` can take.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TraceAccel {
    Reference,
    Auto,
    Flat,
    Bvh,
    /// Rays sharing an origin 8 at a time through the renderer's camera or shadow packets.
    Packets,
}

/// Runs `raylab trace`; the whole output is built before anything is printed.
pub fn trace(args: &TraceArgs) -> Result<()> {
    // (`render --scene` takes an OBJ; trace does not, and its first error, `unknown
    // statement 'mtllib'` say, did not say why.)
    let obj = (args.scene.extension()).is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    trace_files(args).map_err(|e| match obj {
        true => e.context(format!(
            "{}: raylab trace reads the .scene format (`tri` and `sphere` lines and the \
             .scene statements), not OBJ: a .scene file's `mesh FILE.obj` line takes one",
            args.scene.display()
        )),
        false => e,
    })
}

fn trace_files(args: &TraceArgs) -> Result<()> {
    let scene_text = super::scene_text(&args.scene)?;
    let rays_text = read_text(&args.rays)?;
    let (sf, rf) = (
        args.scene.display().to_string(),
        args.rays.display().to_string(),
    );
    let method = args.method;
    let query = args.query.into();
    if args.accel == TraceAccel::Packets {
        if args.precision != Precision::F32 || method != Method::Adaptive {
            bail!("--accel packets runs the renderer's packets: f32 and the adaptive method only");
        }
        let scene = tracefile::parse_scene_instanced(&sf, &scene_text)?;
        let rays = tracefile::parse_rays::<f32>(&rf, &rays_text)?;
        let stage = Stage::new(scene, AccelChoice::Auto);
        print_warnings(&stage.scene().warnings);
        let (scene, structure) = (stage.scene(), stage.accel());
        return write_out(&tracefile::trace_all_packets(
            scene, structure, &rays, query,
        ));
    }
    let choice = match args.accel {
        TraceAccel::Packets => unreachable!("handled above"),
        TraceAccel::Reference => None,
        TraceAccel::Auto => Some(AccelChoice::Auto),
        TraceAccel::Flat => Some(AccelChoice::Flat),
        TraceAccel::Bvh => Some(AccelChoice::Bvh),
    };
    let (out, warnings) = match (args.precision, choice) {
        (Precision::F32, None) => tracefile::run::<f32>(&sf, &scene_text, &rf, &rays_text, method, query)?,
        (Precision::F64, None) => tracefile::run::<f64>(&sf, &scene_text, &rf, &rays_text, method, query)?,
        (Precision::F32, Some(choice)) => {
            let scene = tracefile::parse_scene_instanced(&sf, &scene_text)?;
            let rays = tracefile::parse_rays::<f32>(&rf, &rays_text)?;
            // (The stage adds what the build left out as copies to the warnings.)
            let stage = Stage::new(scene, choice);
            let (scene, structure) = (stage.scene(), stage.accel());
            let out = tracefile::trace_all_through(scene, structure, &rays, method, query);
            (out, scene.warnings.clone())
        }
        (Precision::F64, Some(_)) => bail!(
            "--accel {} runs in f32 only (the renderer's structures); use --precision f32 or --accel reference",
            args.accel.to_possible_value().map_or(String::new(), |v| v.get_name().to_string())
        ),
    };
    print_warnings(&warnings);
    write_out(&out)
}

/// A scene's warnings on stderr, one `warning:` line each (as `raylab render` prints them).
pub(super) fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Writes `raylab trace`'s whole output to stdout.
fn write_out(out: &str) -> Result<()> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(out.as_bytes())?;
    stdout.flush()?;
    Ok(())
}
