//! `raylab suite export` and `raylab check`: the hard-case suite as files, and the grading of
//! answers from code that is not raylab's, an answer file or a program run on each scene.

use super::program;
use super::{read_text, Precision, ViewArgs};
use anyhow::{anyhow, bail, Result};
use raylab::check::grade::{self, Answer, Graded, Tally, Verdict};
use raylab::check::{export, suite};
use raylab::geometry::Shape;
use raylab::math::Real;
use raylab::tracefile::{self, TraceRay};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// `raylab suite`.
#[derive(clap::Args, Debug)]
pub struct SuiteArgs {
    #[command(subcommand)]
    pub action: SuiteAction,
}

/// What `raylab suite` does.
#[derive(clap::Subcommand, Debug)]
pub enum SuiteAction {
    /// Write every hard-case family as DIR/<family>/scene.txt and rays.txt (the `trace`
    /// formats) and DIR/README.md (what each family probes, the answer format). DIR must be
    /// new, empty or an earlier export.
    Export {
        /// The directory to write.
        dir: PathBuf,
    },
}

/// `raylab check`.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// Ray file (the `trace` format), with --scene FILE (a `.scene` file, the `trace` format)
    /// and --answers or --program.
    #[arg(long)]
    pub rays: Option<PathBuf>,
    /// The answers to grade, one line per ray: `hit <t> <index>` or `miss`, as `raylab
    /// trace` prints them.
    #[arg(long, requires = "rays", conflicts_with_all = ["program", "suite", "image"])]
    pub answers: Option<PathBuf>,
    /// An exported suite (`raylab suite export DIR`): run --program on every family.
    #[arg(long, value_name = "DIR", requires = "program", conflicts_with_all = ["rays", "image"])]
    pub suite: Option<PathBuf>,
    /// Ask --program for the camera rays of a view (the render options: the lab's Cornell box
    /// by default) and paint the flat step from its answers into this PNG, leaks magenta,
    /// wrong primitives cyan, false hits yellow (f32).
    #[arg(
        long,
        value_name = "OUT.png",
        requires = "program",
        conflicts_with = "rays"
    )]
    pub image: Option<PathBuf>,
    /// The program to grade: a shell command where `{scene}` and `{rays}` stand for the two
    /// files' paths; it prints its answers on standard output.
    #[arg(long, value_name = "CMD")]
    pub program: Option<String>,
    /// The precision the files are read in and the exact t is rounded to (`f64` for code that
    /// computes in double).
    #[arg(long, value_enum, default_value = "f32")]
    pub precision: Precision,
    /// Seconds the program may take on one scene before it is stopped.
    #[arg(long, value_name = "SECONDS", default_value_t = 60.0)]
    pub timeout: f64,
    /// The scene and, with --image, the view (the render options).
    #[command(flatten)]
    pub view: ViewArgs,
}

/// Runs `raylab suite`.
pub fn suite(args: &SuiteArgs) -> Result<()> {
    match &args.action {
        SuiteAction::Export { dir } => {
            let families = suite::all();
            let written = export::export(dir, &families)?;
            let rays: usize = families.iter().map(|f| f.rays.len()).sum();
            say!(
                "wrote {} families ({rays} rays) to {} (what each probes: {})",
                written.len(),
                dir.display(),
                dir.join("README.md").display()
            );
            Ok(())
        }
    }
}

/// Runs `raylab check`: `Ok(true)` when no answer is a leak, a false hit or a wrong primitive
/// (and every program run gave its answers).
pub fn check(args: &CheckArgs) -> Result<bool> {
    if args.answers.is_none() && args.program.is_none() {
        bail!("give the answers to grade: --answers FILE, or --program CMD to run");
    }
    if !(args.timeout > 0.0 && args.timeout <= 1e6) {
        bail!(
            "--timeout {} must be > 0 and at most 1e6 seconds",
            args.timeout
        );
    }
    if let Some(cmd) = &args.program {
        if !(cmd.contains("{scene}") && cmd.contains("{rays}")) {
            bail!("--program '{cmd}' must name {{scene}} and {{rays}}, where the files' paths go");
        }
    }
    if let (Some(image), Some(template)) = (&args.image, &args.program) {
        if args.precision != Precision::F32 {
            bail!("--image grades the camera rays in f32 (the renderer's); leave out --precision");
        }
        return super::check_image::check_image(args, image, template);
    }
    match args.precision {
        Precision::F32 => check_in::<f32>(args, exact_f32),
        Precision::F64 => check_in::<f64>(args, exact_generic::<f64>),
    }
}

/// A scene's primitives and its rays' exact answers, in one precision.
pub(super) struct Exact<T: Real> {
    pub primitives: usize,
    pub shape_of: Box<dyn Fn(u32) -> Shape<T> + Sync>,
    pub rays: Vec<(usize, TraceRay<T>)>,
    pub answers: Vec<Answer<T>>,
    pub elapsed: Duration,
}

/// Answers with the line each was read from.
pub(super) type Answers<T> = Vec<(usize, Answer<T>)>;

type ExactFn<T> = fn(&Path, &Path) -> Result<Exact<T>>;

/// The files read in f32 and answered through the renderer's structures.
fn exact_f32(scene: &Path, rays: &Path) -> Result<Exact<f32>> {
    let (scene_text, rays_text) = (read_text(scene)?, read_text(rays)?);
    let start = Instant::now();
    let scene = tracefile::parse_scene_instanced(&scene.display().to_string(), &scene_text)?;
    let rays = tracefile::parse_rays_at_lines::<f32>(&rays.display().to_string(), &rays_text)?;
    let plain: Vec<TraceRay<f32>> = rays.iter().map(|(_, r)| *r).collect();
    let answers = grade::exact_answers_f32(&scene, &plain);
    Ok(Exact {
        primitives: scene.len(),
        shape_of: Box::new(move |p| scene.shape(p)),
        rays,
        answers,
        elapsed: start.elapsed(),
    })
}

/// The files read in `T` and answered by the reference loop.
fn exact_generic<T: Real>(scene: &Path, rays: &Path) -> Result<Exact<T>> {
    let (scene_text, rays_text) = (read_text(scene)?, read_text(rays)?);
    let start = Instant::now();
    let shapes = tracefile::parse_scene::<T>(&scene.display().to_string(), &scene_text)?;
    let rays = tracefile::parse_rays_at_lines::<T>(&rays.display().to_string(), &rays_text)?;
    let plain: Vec<TraceRay<T>> = rays.iter().map(|(_, r)| *r).collect();
    let answers = grade::exact_answers(&shapes, &plain);
    Ok(Exact {
        primitives: shapes.len(),
        shape_of: Box::new(move |p| shapes[p as usize]),
        rays,
        answers,
        elapsed: start.elapsed(),
    })
}

fn check_in<T: Real>(args: &CheckArgs, exact_of: ExactFn<T>) -> Result<bool> {
    let name = match args.precision {
        Precision::F32 => "f32",
        Precision::F64 => "f64",
    };
    match (&args.suite, &args.rays) {
        (Some(dir), _) => {
            let program = args
                .program
                .as_deref()
                .expect("clap: --suite requires --program");
            check_suite(dir, program, args.timeout, name, exact_of)
        }
        (None, Some(rays)) => {
            let scene = &PathBuf::from(&args.view.scene);
            if !scene.is_file() {
                bail!(
                    "--rays goes with --scene FILE, the scene file (the `trace` format) the rays are shot at; '{}' is not a file",
                    scene.display()
                );
            }
            let exact = exact_of(scene, rays)?;
            // Written only once everything is read: bad input prints its error alone.
            let mut out = format!(
                "scene {} ({} primitives), rays {} ({} rays), {name}; exact answers by raylab's adaptive method in {:.1} ms\n",
                scene.display(),
                exact.primitives,
                rays.display(),
                exact.rays.len(),
                exact.elapsed.as_secs_f64() * 1e3
            );
            let answers = match (&args.answers, &args.program) {
                (Some(file), _) => {
                    let file_name = file.display().to_string();
                    (
                        file_name.clone(),
                        answers_for(&file_name, &read_text(file)?, &exact, rays)?,
                    )
                }
                (None, Some(template)) => {
                    let command = program::command_for(template, scene, rays);
                    match program_answers(&command, args.timeout, &exact, rays) {
                        Ok((elapsed, answers)) => {
                            let ms = elapsed.as_secs_f64() * 1e3;
                            out += &format!("program: {command} ({ms:.1} ms)\n");
                            ("its output".to_string(), answers)
                        }
                        Err(why) => {
                            say_failed(&out, &command, &why)?;
                            return Ok(false);
                        }
                    }
                }
                (None, None) => unreachable!("checked in `check`"),
            };
            let (answers_file, answers) = answers;
            let graded = grade_all(&exact, &answers);
            let place = |i: usize| format!("{}:{}", rays.display(), exact.rays[i].0);
            let tally = report(&mut out, &graded, &exact, &answers, &place, &answers_file);
            say!("{out}{}", tally.line());
            Ok(tally.passed())
        }
        _ => bail!(
            "give --scene S --rays R (with --answers or --program), --suite DIR --program CMD, or --image OUT.png --program CMD"
        ),
    }
}

/// The most a program may print for `rays` rays: far more than any answers need.
fn max_output(rays: usize) -> usize {
    rays.saturating_mul(160).saturating_add(1 << 20)
}

/// The answers in `text`, one per ray (a count that differs is an error).
fn answers_for<T: Real>(
    file: &str,
    text: &str,
    exact: &Exact<T>,
    rays_file: &Path,
) -> Result<Vec<(usize, Answer<T>)>> {
    let answers = grade::parse_answers::<T>(file, text, exact.primitives)?;
    if answers.len() != exact.rays.len() {
        bail!(
            "{file}: {} answers for the {} rays of {}",
            answers.len(),
            exact.rays.len(),
            rays_file.display()
        );
    }
    Ok(answers)
}

/// Runs the program on the scene and ray files and reads its answers, one per ray: its time
/// and answers, or why it gave none (it crashed, ran out of time, printed too much or
/// something that is not one answer per ray), which makes the run a failure, not bad input.
pub(super) fn program_answers<T: Real>(
    command: &str,
    timeout_s: f64,
    exact: &Exact<T>,
    rays_file: &Path,
) -> Result<(Duration, Answers<T>), String> {
    let timeout = Duration::from_secs_f64(timeout_s);
    let ran =
        program::run(command, timeout, max_output(exact.rays.len())).map_err(|e| e.to_string())?;
    let answers =
        answers_for("its output", &ran.stdout, exact, rays_file).map_err(|e| format!("{e:#}"))?;
    Ok((ran.elapsed, answers))
}

/// Prints what was written so far, the program's failure and the failed run's last line.
pub(super) fn say_failed(out: &str, command: &str, why: &str) -> Result<()> {
    say!("{out}program: {command}\nFAILED: {why}");
    say!("{}", failed_line(&Tally::default(), 1));
    Ok(())
}

pub(super) fn grade_all<T: Real>(exact: &Exact<T>, answers: &[(usize, Answer<T>)]) -> Vec<Graded> {
    use rayon::prelude::*;
    (0..exact.rays.len())
        .into_par_iter()
        .map(|i| {
            grade::grade(
                &exact.shape_of,
                &exact.rays[i].1,
                exact.answers[i],
                answers[i].1,
            )
        })
        .collect()
}

/// Writes the counts and the first wrong answers as one-line reproducers; returns the tally.
pub(super) fn report<T: Real>(
    out: &mut String,
    graded: &[Graded],
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    place: &dyn Fn(usize) -> String,
    answers_file: &str,
) -> Tally {
    use std::fmt::Write;
    // Writing to a String cannot fail.
    macro_rules! w {
        ($($arg:tt)*) => { writeln!(out, $($arg)*).expect("a String takes any text") };
    }
    let mut tally = Tally::default();
    graded.iter().for_each(|g| tally.add(g));
    let hits = tally.t_within_ulp + tally.t_within_micro + tally.t_beyond;
    w!(
        "  right       {:>8}   the exact primitive, or a miss where nothing is met",
        tally.right
    );
    w!(
        "  ties        {:>8}   another primitive at exactly the same t (accepted)",
        tally.ties
    );
    w!(
        "  leaks       {:>8}   a miss where the exact ray meets a primitive",
        tally.leaks
    );
    w!(
        "  false hits  {:>8}   a hit where the exact ray meets nothing",
        tally.false_hits
    );
    w!(
        "  wrong       {:>8}   another primitive, not met at the same t",
        tally.wrong
    );
    w!(
        "  t of the {hits} right or tied hits against the exact t rounded: {} within 1 ulp, {} within 1e-6 relative, {} beyond",
        tally.t_within_ulp,
        tally.t_within_micro,
        tally.t_beyond
    );
    let shown = |wanted: fn(&Graded) -> bool| {
        (graded.iter().enumerate())
            .filter(move |(_, g)| wanted(g))
            .take(5)
    };
    let wrong = tally.leaks + tally.false_hits + tally.wrong;
    if wrong > 0 {
        w!("the first of the {wrong} wrong answers (ray, exact answer, the answer given):");
        for (i, g) in shown(|g| !matches!(g.verdict, Verdict::Right | Verdict::Tie)) {
            w!("{}", reproducer(i, g, exact, answers, place, answers_file));
        }
    }
    if tally.t_beyond > 0 {
        w!(
            "the first of the {} hits whose t is off by more than 1e-6:",
            tally.t_beyond
        );
        for (i, g) in shown(|g| g.t_error == Some(grade::TError::Beyond)) {
            w!("{}", reproducer(i, g, exact, answers, place, answers_file));
        }
    }
    tally
}

/// One graded ray as a line: where the ray is, the ray, the exact answer and the one given.
fn reproducer<T: Real>(
    i: usize,
    g: &Graded,
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    place: &dyn Fn(usize) -> String,
    answers_file: &str,
) -> String {
    let ray = exact.rays[i].1;
    let what = match g.verdict {
        Verdict::Right | Verdict::Tie => format!("t off by {:.1e} relative", g.relative),
        v => v.name().to_string(),
    };
    format!(
        "  {}: {}  exact: {}  given ({answers_file}:{}): {}  [{what}]",
        place(i),
        ray.line(),
        exact.answers[i].text(),
        answers[i].0,
        answers[i].1.text()
    )
}

/// The last line of a run where some programs gave no answers.
fn failed_line(tally: &Tally, failed: usize) -> String {
    format!("{} failed_runs {failed}", tally.line())
}

/// Runs the program on every family of an exported suite: one row per family and a total.
fn check_suite<T: Real>(
    dir: &Path,
    template: &str,
    timeout_s: f64,
    precision: &str,
    exact_of: ExactFn<T>,
) -> Result<bool> {
    let families = suite_families(dir)?;
    say!(
        "suite {} ({} families), {precision}, program: {template}",
        dir.display(),
        families.len()
    );
    say!("{}", grade::table_header());
    let mut total = Tally::default();
    let mut failed = 0;
    let (mut program_time, mut raylab_time) = (Duration::ZERO, Duration::ZERO);
    for family in &families {
        let name = family
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let (scene, rays) = (family.join("scene.txt"), family.join("rays.txt"));
        let exact = exact_of(&scene, &rays)?;
        let command = program::command_for(template, &scene, &rays);
        let outcome = program_answers(&command, timeout_s, &exact, &rays);
        match outcome {
            Ok((elapsed, answers)) => {
                let mut tally = Tally::default();
                grade_all(&exact, &answers)
                    .iter()
                    .for_each(|g| tally.add(g));
                let ms = (
                    elapsed.as_secs_f64() * 1e3,
                    exact.elapsed.as_secs_f64() * 1e3,
                );
                say!("{}", tally.row(&name, ms));
                total.merge(&tally);
                program_time += elapsed;
                raylab_time += exact.elapsed;
            }
            Err(e) => {
                failed += 1;
                say!("{name:<46} FAILED: {e}");
            }
        }
    }
    let ms = (
        program_time.as_secs_f64() * 1e3,
        raylab_time.as_secs_f64() * 1e3,
    );
    say!("{}", total.row("total", ms));
    if failed > 0 {
        say!(
            "{failed} of {} families gave no answers (FAILED above): not a pass",
            families.len()
        );
        say!("{}", failed_line(&total, failed));
        return Ok(false);
    }
    say!("{}", total.line());
    Ok(total.passed())
}

/// The family directories of an exported suite (each with scene.txt and rays.txt), in order.
fn suite_families(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).map_err(|e| anyhow!("{}: {e}", dir.display()))?;
    let mut families: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("scene.txt").is_file() && p.join("rays.txt").is_file())
        .collect();
    families.sort();
    if families.is_empty() {
        bail!(
            "{}: no family directories (DIR/<family>/scene.txt and rays.txt); write a suite with `raylab suite export {}`",
            dir.display(),
            dir.display()
        );
    }
    Ok(families)
}
