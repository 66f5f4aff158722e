//! `raylab check --image`: a program's answers to a view's camera rays, painted as the flat
//! step with its mistakes marked: the cracks view for code that is not raylab's.

use super::check::{grade_all, program_answers, report, say_failed, CheckArgs, Exact};
use super::program;
use anyhow::{Context, Result};
use raylab::check::grade::{self, Answer};
use raylab::render::image::linear_to_srgb8;
use raylab::render::shade::step_colour;
use raylab::tracefile::TraceRay;
use raylab::LabStep;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// A directory of this run's own in the system's temporary directory, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> Result<Self> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("raylab-check-{}-{n}", std::process::id()));
        std::fs::create_dir(&dir).with_context(|| format!("{}", dir.display()))?;
        Ok(TempDir(dir))
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Writes `lines` after a comment to `path`.
fn write_lines(path: &Path, comment: &str, lines: impl Iterator<Item = String>) -> Result<()> {
    let io = || format!("{}", path.display());
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).with_context(io)?);
    writeln!(out, "# {comment}").with_context(io)?;
    for line in lines {
        writeln!(out, "{line}").with_context(io)?;
    }
    out.flush().with_context(io)
}

/// Runs `raylab check --image`: `Ok(true)` when no pixel's answer is a leak, a false hit or a
/// wrong primitive.
pub fn check_image(args: &CheckArgs, image: &Path, template: &str) -> Result<bool> {
    raylab::input::check_output(image)?;
    let (scene, camera, settings) = super::prepare(&args.view)?;
    let (w, h) = (settings.width, settings.height);
    let rays: Vec<(usize, TraceRay<f32>)> = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .enumerate()
        .map(|(k, (i, j))| (k + 2, TraceRay::whole(camera.ray_for_pixel(i, j, w, h))))
        .collect();
    let dir = TempDir::new()?;
    let (scene_file, rays_file) = (dir.0.join("scene.txt"), dir.0.join("rays.txt"));
    let comment = format!(
        "the scene of the view ({}), one primitive per line",
        args.view.scene
    );
    write_lines(
        &scene_file,
        &comment,
        scene.all_shapes().map(|s| s.scene_line()),
    )?;
    let comment = format!("the camera rays of a {w}×{h} image, row by row from the top left");
    write_lines(&rays_file, &comment, rays.iter().map(|(_, r)| r.line()))?;

    let start = Instant::now();
    let plain: Vec<TraceRay<f32>> = rays.iter().map(|(_, r)| *r).collect();
    let exact_answers = grade::exact_answers_f32(&scene, &plain);
    let scene = Arc::new(scene);
    let exact = Exact {
        primitives: scene.len(),
        shape_of: Box::new({
            let scene = scene.clone();
            move |p| scene.shape(p)
        }),
        rays,
        answers: exact_answers,
        elapsed: start.elapsed(),
    };
    let mut out = format!(
        "view: {} ({} primitives), the {w}×{h} camera rays; exact answers by raylab's adaptive method in {:.1} ms\n",
        args.view.scene,
        exact.primitives,
        exact.elapsed.as_secs_f64() * 1e3
    );
    let command = program::command_for(template, &scene_file, &rays_file);
    let answers = match program_answers(&command, args.timeout, &exact, &rays_file) {
        Ok((elapsed, answers)) => {
            let ms = elapsed.as_secs_f64() * 1e3;
            out += &format!("program: {command} ({ms:.1} ms)\n");
            answers
        }
        Err(why) => {
            say_failed(&out, &command, &why)?;
            return Ok(false);
        }
    };
    let graded = grade_all(&exact, &answers);
    let mut rgba = Vec::with_capacity(graded.len() * 4);
    for (g, (_, answer)) in graded.iter().zip(&answers) {
        let colour = match (g.verdict.mark(), answer) {
            (Some(mark), _) => mark,
            (None, Answer::Hit { prim, .. }) => {
                step_colour(&scene, *prim, [0.0; 3], false, LabStep::Flat)
            }
            (None, Answer::Miss) => [0.0; 3],
        };
        rgba.extend(colour.map(linear_to_srgb8));
        rgba.push(255);
    }
    let mut png = raylab::input::OutputFile::create(image)?;
    raylab::render::image::encode_png(&mut png, w, h, &rgba)
        .with_context(|| format!("{}", image.display()))?;
    png.commit()?;
    let place = |k: usize| format!("pixel {},{}", k % w as usize, k / w as usize);
    let tally = report(&mut out, &graded, &exact, &answers, &place, "its output");
    say!(
        "{out}image: {}: the flat step from the program's answers; leaks magenta, wrong primitives cyan, false hits yellow",
        image.display()
    );
    say!("{}", tally.line());
    Ok(tally.passed())
}
