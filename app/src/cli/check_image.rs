//! `raylab check --image`: a program's answers to a view's camera rays, painted as the flat
//! step in grey with its mistakes marked in colour: the cracks view for code that is not
//! raylab's. (In the flat step's own colours the marks were lost: the Cornell box's walls are
//! purple, cyan and yellow, and a leak on the purple wall was one pixel of another magenta.)

use super::check::{judge_all, program_answers, report, say_failed, CheckArgs, REPRODUCERS};
use super::program;
use super::reproducers::Written;
use anyhow::{Context, Result};
use raylab::check::grade::{Answer, Exact};
use raylab::render::image::linear_to_srgb8;
use raylab::render::shade::step_colour;
use raylab::tracefile::TraceRay;
use raylab::LabStep;
use std::io::Write;
use std::path::Path;
use std::sync::Arc;

/// The default image of `check --image`: 19,200 camera rays, which examples/check/exact.py (exact
/// rationals in Python) answers on the Cornell box within the default --timeout on 2 cores.
const IMAGE_SIZE: (u32, u32) = (160, 120);

/// The most camera rays `check --image` writes and grades (1024×1024): a rays file of about
/// 110 MB, streamed to disk, and about 120 bytes a ray held (the ray, its exact answer, the
/// program's answer and its grade: 141 MB measured at this cap); a larger image is refused
/// before any work.
const MAX_RAYS: u64 = 1 << 20;

/// The most primitives of the scene file it writes for the program (instances written out
/// one triangle a line, about 110 bytes each).
const MAX_PRIMITIVES: usize = 1 << 20;

/// Refuses an image that is one of the program's own files (`--image my_lab.sh --program 'sh
/// my_lab.sh …'` turned the script into a PNG): every word of the command that names an
/// existing file is compared with the image by identity.
fn refuse_program_file(image: &Path, template: &str) -> Result<()> {
    use std::os::unix::fs::MetadataExt;
    let Ok(out) = std::fs::metadata(image) else {
        return Ok(());
    };
    let words = template.split_whitespace();
    for word in words.map(|w| w.trim_matches(|c| c == '\'' || c == '"')) {
        if let Ok(meta) = std::fs::metadata(word) {
            if (meta.dev(), meta.ino()) == (out.dev(), out.ino()) {
                anyhow::bail!(
                    "{}: is '{word}', which --program runs: refusing to overwrite it",
                    image.display()
                );
            }
        }
    }
    Ok(())
}

/// The grey of linear colour `c`: its luminance (Rec. 709 weights, as sRGB's primaries).
fn grey(c: [f32; 3]) -> [f32; 3] {
    [0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; 3]
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
    refuse_program_file(image, template)?;
    // Before any work: a missing directory, a directory's name or a FIFO is said now.
    raylab::input::OutputFile::create(image)?;
    super::png_only(image)?;
    let defaults = raylab::render::RenderSettings::default();
    let (scene, camera, settings) = super::prepare_sized(&args.view, IMAGE_SIZE, defaults)?;
    let (w, h) = (settings.width, settings.height);
    if u64::from(w) * u64::from(h) > MAX_RAYS {
        anyhow::bail!(
            "--width {w} × --height {h} is {} camera rays; check --image writes and grades at most {MAX_RAYS} (a rays file of about 110 MB): ask for a smaller image",
            u64::from(w) * u64::from(h)
        );
    }
    if scene.len() > MAX_PRIMITIVES {
        anyhow::bail!(
            "{}: {} primitives once its instances are written out one a line; check --image writes at most {MAX_PRIMITIVES} for the program",
            args.view.scene,
            scene.len()
        );
    }
    // Opened again now that the scene's files are known (none is the image); committed
    // when whole.
    let mut png = raylab::input::OutputFile::create(image)?;
    let rays: Vec<(usize, TraceRay<f32>)> = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .enumerate()
        .map(|(k, (i, j))| (k + 2, TraceRay::whole(camera.ray_for_pixel(i, j, w, h))))
        .collect();
    // Removed when done, and on Ctrl+C or SIGTERM; never a name an earlier run used.
    let dir = program::RunDir::new("check").context("a temporary directory")?;
    let (scene_file, rays_file) = (dir.path().join("scene.txt"), dir.path().join("rays.txt"));
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

    let scene = Arc::new(scene);
    let exact = Exact::of_scene(scene.clone(), rays);
    let mut out = format!(
        "view: {} ({}), the {w}×{h} camera rays; exact answers by raylab's adaptive method in {:.1} ms\n",
        args.view.scene,
        raylab::words::primitives(exact.primitives),
        exact.elapsed.as_secs_f64() * 1e3
    );
    let command = super::template::command_for(template, &scene_file, &rays_file);
    eprintln!(
        "check --image: {w}×{h} camera rays written; running the program (at most {} s)",
        args.timeout
    );
    let (answers, printed) = match program_answers(
        template,
        &scene_file,
        (args.timeout, args.t_tolerance),
        &exact,
        &rays_file,
    ) {
        Ok((elapsed, answers, printed)) => {
            let ms = elapsed.as_secs_f64() * 1e3;
            out += &format!("program: {command} ({ms:.1} ms)\n");
            (answers, printed)
        }
        Err(why) => {
            let why = match why.contains("ran out of time") {
                true => format!(
                    "{why}; or ask for fewer camera rays with --width and --height (now {w}×{h})"
                ),
                false => why,
            };
            say_failed(&out, &command, &why)?;
            return Ok(false);
        }
    };
    eprintln!("check --image: grading the {} answers", w * h);
    let graded = judge_all(&exact, &answers, args.t_tolerance);
    let mut rgba = Vec::with_capacity(graded.len() * 4);
    for (j, (_, answer)) in graded.iter().zip(&answers) {
        let colour = match (j.graded.verdict.mark(), answer) {
            (Some(mark), _) => mark,
            (None, Answer::Hit { prim, .. }) => {
                grey(step_colour(&scene, *prim, [0.0; 3], false, LabStep::Flat))
            }
            (None, Answer::Miss) => [0.0; 3],
        };
        rgba.extend(colour.map(linear_to_srgb8));
        rgba.push(255);
    }
    raylab::render::image::encode_png(&mut png, w, h, &rgba)
        .with_context(|| format!("{}", image.display()))?;
    png.commit()?;
    let place = |k: usize| format!("pixel {},{}", k % w as usize, k / w as usize);
    let show = args.show.unwrap_or(REPRODUCERS);
    let tally = report(
        &mut out,
        &graded,
        &exact,
        &answers,
        &place,
        Written {
            name: "its output",
            text: &printed,
        },
        show,
    );
    say!(
        "{out}image: {}: the flat step in grey from the program's answers; leaks magenta, wrong primitives cyan, false hits yellow",
        image.display()
    );
    say!("{}", tally.line());
    Ok(tally.passed())
}
