//! `raylab render`, `bench` and `inspect`: the commands that trace a view headless, as the
//! window would show it (the image with its progress and Ctrl+C, the timed frames, one ray).

use super::{png_only, prepare, BenchArgs, InspectArgs, RenderArgs};
use anyhow::{bail, Result};
use raylab::accel::AccelChoice;
use raylab::camera::Camera;
use raylab::render::settings::controls_text;
use raylab::render::{self, RenderSettings, SettingsError, Stage};
use raylab::scene::Scene;
use raylab_app::window::values::clean;
use raylab_app::window::Detail;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Runs `raylab inspect`.
pub fn inspect(args: &InspectArgs) -> Result<()> {
    let (scene, camera, settings) = prepare(&args.view, args.controls.0)?;
    let stage = Stage::new(scene, args.accel.accel);
    let (w, h) = (settings.width, settings.height);
    // The position traced: a pixel's centre, or as given (rounded to f32, as the renderer's
    // sample positions are).
    let (x, y) = match (args.pixel, &args.at) {
        (Some((i, j)), _) if i >= w || j >= h => bail!("{}", SettingsError::Pixel(i, j, w, h)),
        (Some((i, j)), _) => (i as f64 + 0.5, j as f64 + 0.5),
        (None, Some(at)) => {
            let inside = |c: f64, n: u32| (0.0..n as f32).contains(&(c as f32));
            if !inside(at.x, w) || !inside(at.y, h) {
                bail!(
                    "position {} is outside the {w}x{h} image (x in [0, {w}), y in [0, {h}) \
                     once rounded to f32)",
                    at.text
                );
            }
            (at.x, at.y)
        }
        (None, None) => bail!("give the pixel (--pixel X,Y) or the image position (--at X,Y)"),
    };
    // With the cracks view on (a view file's `cracks on`), the rows the window's inspector
    // adds for it (the ray graded against the exact one, and where each hit lies), and for a
    // pixel its first marked sample's ray, as the window's inspector takes it.
    let job = (&stage, &camera, settings.method, None);
    let crack = settings.cracks.then(|| match args.pixel {
        Some(pixel) => Detail::of_pixel(job, &[], (w, h), pixel, settings.spp),
        None => Detail::of_ray(job, &[], (w, h), (x as f32, y as f32), None),
    });
    // (Every field is of the ray the crack rows name: for a pixel, maybe a sample's.)
    let (x, y) = crack
        .as_ref()
        .map_or((x, y), |d| (d.at.0.into(), d.at.1.into()));
    let inspection = raylab::render::inspect::inspect_at(&stage, &camera, &settings, x, y)?;
    say!("{}", inspection.to_string().trim_end());
    for (name, value) in crack.iter().flat_map(Detail::rows) {
        say!("{name}: {value}");
    }
    Ok(())
}

/// A render stopped by Ctrl+C (exit code 130, as a shell reports SIGINT).
#[derive(Debug, thiserror::Error)]
#[error("interrupted: nothing written")]
pub struct Interrupted;

/// Camera rays from which `raylab render` shows a progress bar (on a terminal only).
const PROGRESS_MIN_RAYS: u64 = 1 << 22;

/// Set by Ctrl+C during `raylab render` (from [`watch_interrupt`] on).
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// From now on Ctrl+C sets [`INTERRUPTED`] instead of ending the process, so that the render
/// stops at its next tile and nothing is written.
fn watch_interrupt() {
    use std::sync::atomic::Ordering;
    // (Fails only if a handler is set already: then Ctrl+C ends the process as usual.)
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::Relaxed));
}

/// Whether Ctrl+C was pressed since [`watch_interrupt`].
fn interrupted() -> bool {
    INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed)
}

/// Renders with a progress bar and ETA on a terminal for large renders, stopping cleanly at
/// Ctrl+C (`None`).
fn render_with_progress(
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
) -> Result<Option<(Vec<u8>, render::RenderStats)>> {
    watch_interrupt();
    let rays =
        settings.width as u64 * settings.height as u64 * (settings.spp * settings.spp) as u64;
    let tiles = render::tiles(settings.width, settings.height);
    let bar = match rays >= PROGRESS_MIN_RAYS {
        // Drawn only where stderr is a terminal.
        true => indicatif::ProgressBar::new(tiles),
        false => indicatif::ProgressBar::hidden(),
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} {elapsed_precise} [{bar:40}] {percent}% ETA {eta} (Ctrl+C stops)",
        )
        .expect("a valid template")
        .progress_chars("=> "),
    );
    let mut rgba = vec![0u8; settings.buffer_len()];
    // Asked before each tile (and once at the end).
    let cancelled = || {
        bar.inc(1);
        interrupted()
    };
    let stats = render::render_into_cancellable(stage, camera, settings, &mut rgba, &cancelled)?;
    bar.finish_and_clear();
    Ok(stats.map(|s| (rgba, s)))
}

/// Builds the structure `accel` names over `scene`, timed, and says what it left out as copies.
fn stage(scene: Scene, accel: AccelChoice) -> (Stage, Duration) {
    let start = Instant::now();
    let stage = Stage::new(scene, accel);
    let build = start.elapsed();
    if let Some(w) = stage.accel().copies_warning(stage.scene()) {
        eprintln!("warning: {w}");
    }
    (stage, build)
}

/// Opens every output of `raylab render` (the PNG, and the arrays with --aov) and drops them:
/// an unwritable or missing directory, a directory's name (`a.png/`), a FIFO or an input as
/// output fails now, before any work. Nothing at the paths changes until all is written.
fn check_render_outputs(args: &RenderArgs) -> Result<()> {
    raylab::input::OutputFile::create(&args.out)?;
    if args.aov {
        render::aov::create_beside(&args.out)?;
    }
    Ok(())
}

/// Runs `raylab render`.
pub fn render(args: &RenderArgs) -> Result<()> {
    check_render_outputs(args)?;
    // (A file there may be an input, which is the better message: said once it is known.)
    if !args.out.exists() {
        png_only(&args.out)?;
    }
    let (scene, camera, settings) = prepare(&args.view, args.image.settings())?;
    // Again, now that the scene's files are known: none of them is an output (said before
    // the format, which an input's name would fail too).
    check_render_outputs(args)?;
    png_only(&args.out)?;
    let (stage, build) = stage(scene, args.image.accel.accel);
    let scene = stage.scene();
    let Some((rgba, stats)) = render_with_progress(&stage, &camera, &settings)? else {
        return Err(Interrupted.into());
    };
    let mut png = raylab::input::OutputFile::create(&args.out)?;
    render::image::encode_png(&mut png, settings.width, settings.height, &rgba).map_err(|e| {
        raylab::input::InputError::Io {
            path: args.out.clone(),
            source: e,
        }
    })?;
    drop(rgba);
    // The arrays band by band, each into its temporary file: memory for one band, not the image.
    let mut arrays = Vec::new();
    if args.aov {
        let mut outs = render::aov::create_beside(&args.out)?;
        // Ctrl+C stops the pass at its next tile, and nothing is written.
        if !render::aov::write_aovs(&stage, &camera, &settings, &mut outs, &interrupted)? {
            return Err(Interrupted.into());
        }
        arrays.extend(outs);
    }
    if interrupted() {
        return Err(Interrupted.into());
    }
    // The whole set is committed before anything is reported: a reader of the report that is
    // gone (a closed pipe) ends the run after the files, never between them. The arrays are
    // renamed first (.prim, .t, .normal), the PNG last: a PNG from this run means its three
    // arrays were all renamed before it; a run that fails or is killed during the renames
    // leaves the previous PNG (some arrays may already be new).
    let written: Vec<PathBuf> = arrays.iter().map(|o| o.path().to_path_buf()).collect();
    for out in arrays {
        out.commit()?;
    }
    png.commit()?;
    say!(
        "rendered {} ({}, {} built in {:.1} ms) {}x{} {} on {} threads in {:.2} ms: \
         {} primary + {} shadow rays, {:.2} Mrays/s -> {}",
        scene.name,
        raylab::words::primitives(scene.len()),
        stage.accel().kind(),
        build.as_secs_f64() * 1e3,
        settings.width,
        settings.height,
        controls_text(&settings),
        rayon::current_num_threads(),
        stats.elapsed.as_secs_f64() * 1e3,
        stats.primary_rays,
        stats.shadow_rays,
        stats.mrays_per_s(),
        args.out.display()
    );
    // (Each file once: a device's arrays went to it, as the image did.)
    for path in written.iter().filter(|p| **p != args.out) {
        say!("wrote {}", path.display());
    }
    Ok(())
}

/// Runs `raylab bench`.
pub fn bench(args: &BenchArgs) -> Result<()> {
    let threads = args.threads.unwrap_or_else(super::cores);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    if let Some(level) = args.simd {
        let best = raylab::math::simd::detected();
        if level > best {
            bail!("--simd {level}: this CPU runs at most {best}");
        }
        raylab::math::simd::limit(level);
    }
    let (scene, camera, settings) = prepare(&args.view, args.image.settings())?;
    let cpu = raylab::machine::cpu_model();
    say!(
        "machine: {cpu}, {} cores available; threads: {threads}; simd: {}",
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        raylab::machine::simd_level()
    );
    let (stage, build) = pool.install(|| stage(scene, args.image.accel.accel));
    let (scene, accel) = (stage.scene(), stage.accel().kind());
    say!(
        "scene: {} ({}), accel: {accel}, build {:.1} ms, {:.1} MB",
        scene.name,
        raylab::words::primitives(scene.len()),
        build.as_secs_f64() * 1e3,
        stage.accel().memory_bytes() as f64 / 1e6
    );
    say!(
        "view: {}x{} {} camera={} yaw={} pitch={} focal={}",
        settings.width,
        settings.height,
        controls_text(&settings),
        camera.position(),
        clean(camera.forward().x.atan2(camera.forward().z).to_degrees()),
        clean((-camera.forward().y).asin().to_degrees()),
        camera.focal
    );
    let mut rgba = vec![0u8; settings.buffer_len()];
    let mut runs = Vec::new();
    for frame in 0..=args.frames {
        let stats = pool.install(|| render::render_into(&stage, &camera, &settings, &mut rgba))?;
        if frame > 0 {
            say!(
                "frame {frame}: {:.3} ms, {} primary + {} shadow rays, {} hits, {:.2} Mrays/s",
                stats.elapsed.as_secs_f64() * 1e3,
                stats.primary_rays,
                stats.shadow_rays,
                stats.hits,
                stats.mrays_per_s()
            );
            runs.push(stats);
        }
    }
    runs.sort_by_key(|r| r.elapsed);
    let median = runs[runs.len() / 2];
    let (lo, hi) = (runs[0], runs[runs.len() - 1]);
    say!(
        "median frame {:.3} ms (min {:.3}, max {:.3}), {:.1} frames/s, hits {}",
        median.elapsed.as_secs_f64() * 1e3,
        lo.elapsed.as_secs_f64() * 1e3,
        hi.elapsed.as_secs_f64() * 1e3,
        1.0 / median.elapsed.as_secs_f64(),
        median.hits
    );
    say!("mrays_per_s={:.3}", median.mrays_per_s());
    Ok(())
}
