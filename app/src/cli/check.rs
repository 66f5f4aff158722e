//! `raylab suite export` and `raylab check`: the hard-case suite as files, and the grading of
//! answers from code that is not raylab's, an answer file or a program run on each scene.

use super::budget::Budget;
use super::line_up;
use super::reproducers::{first_shown, reproducers, Written};
use super::rounding::{family_number, rounding_fails, Digits, Failed};
use super::run_words::{crashed, stalled, stderr_hint};
use super::suite_dir::{family_name, suite_families};
use super::{program, template};
use super::{read_text, Precision, ViewArgs};
use anyhow::{bail, Result};
use raylab::check::grade::{self, Answer, Exact, Judged, Tally};
use raylab::check::{export, suite};
use raylab::math::Real;
use raylab::tracefile;
use std::path::{Path, PathBuf};
use std::sync::Arc;
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
    /// formats), DIR/README.md (what each family probes, the answer format) and, last,
    /// DIR/families.txt (each family and its number of rays: `check` and `grade` fail a
    /// family it lists that is missing or cut short). DIR must be new, empty or an earlier
    /// export.
    Export {
        /// The directory to write.
        dir: PathBuf,
    },
}

/// `raylab check`. The view's flags but --scene set the view of --image and are refused
/// without it, as is every flag its mode would not use.
#[derive(clap::Args, Debug)]
#[command(mut_args(only_with_image))]
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
    /// Ask --program for the camera rays of a view (the view's flags below: the lab's Cornell
    /// box by default, 160×120) and paint the flat step from its answers into this PNG, leaks magenta,
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
    /// computes in double; --image grades in f32, the renderer's).
    #[arg(long, value_enum, default_value = "f32")]
    pub precision: Precision,
    /// Seconds the program may take on one scene before it is stopped.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = DEFAULT_TIMEOUT,
        conflicts_with = "answers",
        allow_negative_numbers = true
    )]
    pub timeout: f64,
    /// With --suite: seconds the program may take on all families together; the families
    /// after it runs out are skipped, and failed (default: 5 × --timeout).
    #[arg(
        long,
        value_name = "SECONDS",
        requires = "suite",
        conflicts_with_all = ["rays", "image"],
        allow_negative_numbers = true
    )]
    pub budget: Option<f64>,
    /// How far a right hit's point o + t·d may lie from the exact one, relative to the size
    /// of the coordinates (|t − exact t|·|d| / (|o| + |exact t|·|d| + the primitive's largest
    /// coordinate)); a t beyond it is a failure. Within an ulp of the precision is always
    /// right.
    #[arg(long, value_name = "X", default_value_t = grade::DEFAULT_T_TOLERANCE, allow_hyphen_values = true)]
    pub t_tolerance: f64,
    /// With --suite: check only this family (its directory name, or its number).
    // (A conflict too: clap waives a requirement that conflicts with a flag given.)
    #[arg(
        long,
        value_name = "NAME",
        requires = "suite",
        conflicts_with_all = ["rays", "image"]
    )]
    pub family: Option<String>,
    /// How many of the first wrong answers and of the first t failures to print, each ray a
    /// line to reproduce it by (default 3 under each failing family of a suite, 5 otherwise).
    #[arg(
        long,
        value_name = "N",
        allow_negative_numbers = true,
        value_parser = super::count_in::<usize>(0..=u32::MAX as i64)
    )]
    pub show: Option<usize>,
    /// The scene and, with --image, the view.
    #[command(
        flatten,
        next_help_heading = "The scene (--rays, --image) and the view (--image)"
    )]
    pub view: ViewArgs,
}

/// Makes the view's flags but --scene require --image, and --scene refuse --suite (whose
/// families hold their scenes): `check` refuses a flag it would ignore.
fn only_with_image(arg: clap::Arg) -> clap::Arg {
    let id = arg.get_id().as_str();
    if super::VIEW_FLAGS.contains(&id) {
        // (A conflict too: clap waives a requirement that conflicts with a flag given.)
        arg.requires("image").conflicts_with_all(["rays", "suite"])
    } else if id == "scene" {
        arg.conflicts_with("suite")
    } else {
        arg
    }
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

/// The options of `raylab check` checked before any work: something to grade, and a
/// usable timeout, tolerance and command template.
pub(super) fn check_args(args: &CheckArgs) -> Result<()> {
    if args.answers.is_none() && args.program.is_none() {
        bail!("give the answers to grade: --answers FILE, or --program CMD to run");
    }
    check_timeout(args.timeout)?;
    check_tolerance(args.t_tolerance)?;
    if let Some(cmd) = &args.program {
        template::check_template(cmd)?;
    }
    // (clap's own conflict said only that the two could not be used together.)
    if args.image.is_some() && args.precision == Precision::F64 {
        bail!(
            "--precision f64: --image grades in f32, the precision of the renderer's camera \
             rays it sends; leave --precision out, or check in f64 with --suite or --rays"
        );
    }
    Ok(())
}

/// `raylab check` of rays (not `--image`): `Ok(true)` when every answer stands: no leak,
/// false hit, wrong primitive or t beyond the tolerance (and every program run gave its
/// answers).
pub(super) fn check_answers(args: &CheckArgs) -> Result<bool> {
    match args.precision {
        Precision::F32 => check_in::<f32>(args, exact_f32),
        Precision::F64 => check_in::<f64>(args, exact_generic::<f64>),
    }
}

/// A run's --timeout where none is given, seconds.
pub(super) const DEFAULT_TIMEOUT: f64 = 60.0;

/// A --timeout a run can use: more than 0 and at most 1e6 seconds.
pub(super) fn check_timeout(timeout: f64) -> Result<()> {
    if !(timeout > 0.0 && timeout <= 1e6) {
        bail!("--timeout {timeout:?} must be > 0 and at most 1e6 seconds");
    }
    Ok(())
}

/// A --t-tolerance a grade can use: a number from 0 to 1.
pub(super) fn check_tolerance(tolerance: f64) -> Result<()> {
    if !(0.0..=1.0).contains(&tolerance) {
        bail!("--t-tolerance {tolerance:?} must be a number from 0 to 1 (relative)");
    }
    Ok(())
}

/// Answers with the line each was read from.
pub(super) type Answers<T> = Vec<(usize, Answer<T>)>;

type ExactFn<T> = fn(&Path, &Path) -> Result<Exact<T>>;

/// The files read in f32 and answered through the renderer's structures (disputed answers
/// confirmed by the reference loop).
pub(super) fn exact_f32(scene: &Path, rays: &Path) -> Result<Exact<f32>> {
    let (scene_text, rays_text) = (read_text(scene)?, read_text(rays)?);
    let scene = tracefile::parse_scene_instanced(&scene.display().to_string(), &scene_text)?;
    super::trace::print_warnings(&scene.warnings);
    let rays = tracefile::parse_rays_at_lines::<f32>(&rays.display().to_string(), &rays_text)?;
    Ok(Exact::of_scene(Arc::new(scene), rays))
}

/// The files read in `T` and answered by the reference loop.
pub(super) fn exact_generic<T: Real>(scene: &Path, rays: &Path) -> Result<Exact<T>> {
    let (scene_text, rays_text) = (read_text(scene)?, read_text(rays)?);
    let (shapes, warnings) =
        tracefile::parse_scene::<T>(&scene.display().to_string(), &scene_text)?;
    super::trace::print_warnings(&warnings);
    let rays = tracefile::parse_rays_at_lines::<T>(&rays.display().to_string(), &rays_text)?;
    Ok(Exact::of_shapes(shapes, rays))
}

pub(super) fn precision_name(p: Precision) -> &'static str {
    match p {
        Precision::F32 => "f32",
        Precision::F64 => "f64",
    }
}

fn check_in<T: Real>(args: &CheckArgs, exact_of: ExactFn<T>) -> Result<bool> {
    let name = precision_name(args.precision);
    let tolerance = args.t_tolerance;
    match (&args.suite, &args.rays) {
        (Some(dir), _) => {
            let program = args
                .program
                .as_deref()
                .expect("clap: --suite requires --program");
            let run = SuiteRun {
                template: program,
                timeout_s: args.timeout,
                budget: Budget::new(args.budget, args.timeout)?,
                precision: name,
                tolerance,
                show: args.show.unwrap_or(SUITE_REPRODUCERS),
            };
            check_suite(dir, args.family.as_deref(), &run, exact_of)
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
                "scene {} ({}), rays {} ({}), {name}; exact answers by raylab's adaptive method in {:.1} ms; t tolerance {tolerance:e}\n",
                scene.display(),
                raylab::words::count(exact.primitives, "primitive", "primitives"),
                rays.display(),
                raylab::words::count(exact.rays.len(), "ray", "rays"),
                exact.elapsed.as_secs_f64() * 1e3
            );
            let answers = match (&args.answers, &args.program) {
                (Some(file), _) => {
                    let (file_name, text) = (file.display().to_string(), read_text(file)?);
                    let answers = answers_for(&file_name, &text, &exact, rays)?;
                    (file_name, text, answers)
                }
                (None, Some(template)) => {
                    let command = template::command_for(template, scene, rays);
                    let limits = (args.timeout, tolerance);
                    match program_answers(template, scene, limits, &exact, rays) {
                        Ok((elapsed, answers, printed)) => {
                            let ms = elapsed.as_secs_f64() * 1e3;
                            out += &format!("program: {command} ({ms:.1} ms)\n");
                            ("its output".to_string(), printed, answers)
                        }
                        Err(why) => {
                            say_failed(&out, &command, &why)?;
                            return Ok(false);
                        }
                    }
                }
                (None, None) => unreachable!("checked in `check`"),
            };
            let (name, text, answers) = answers;
            let judged = judge_all(&exact, &answers, tolerance);
            let place = |i: usize| ray_place(rays, &exact, i);
            let show = args.show.unwrap_or(REPRODUCERS);
            let written = Written { name: &name, text: &text };
            let tally = report(&mut out, &judged, &exact, &answers, &place, written, show);
            say!("{out}{}", tally.line());
            Ok(tally.passed())
        }
        _ => bail!(
            "give --scene S --rays R (with --answers or --program), --suite DIR --program CMD, or --image OUT.png --program CMD"
        ),
    }
}

/// Where ray `i` is: its file and line, and its number among the rays (the line of its answer
/// in an answer file without comments).
pub(super) fn ray_place<T: Real>(rays: &Path, exact: &Exact<T>, i: usize) -> String {
    format!("{}:{} (ray {})", rays.display(), exact.rays[i].0, i + 1)
}

/// The most a program may print for `rays` rays: far more than any answers need.
pub(super) fn max_output(rays: usize) -> usize {
    rays.saturating_mul(160).saturating_add(1 << 20)
}

/// The answers in `text`, one per ray (a count that differs is an error).
pub(super) fn answers_for<T: Real>(
    file: &str,
    text: &str,
    exact: &Exact<T>,
    rays_file: &Path,
) -> Result<Vec<(usize, Answer<T>)>> {
    let answers = grade::parse_answers::<T>(file, text, exact.primitives)?;
    if answers.len() != exact.rays.len() {
        // (Where they stop lining up: "187 answers for the 196 rays" named no ray to look at.)
        let given: Vec<Answer<T>> = answers.iter().map(|(_, a)| *a).collect();
        let place = |k: usize| ray_place(rays_file, exact, k);
        let where_ = match line_up::where_they_part(&given, &exact.answers, place) {
            said if said.is_empty() => said,
            said => format!(": {said}"),
        };
        bail!(
            "{file}: {} for the {} of {}{where_}",
            raylab::words::count(answers.len(), "answer", "answers"),
            raylab::words::count(exact.rays.len(), "ray", "rays"),
            rays_file.display()
        );
    }
    Ok(answers)
}

/// Runs the program on the scene and ray files and reads its answers, one per ray: its time
/// and answers, or why it gave none (it crashed, ran out of time, printed too much or
/// something that is not one answer per ray), which makes the run a failure, not bad input.
/// (`timeout_s`, and the t tolerance a crash's complete answers are graded with all the same.)
pub(super) fn program_answers<T: Real>(
    template: &str,
    scene_file: &Path,
    (timeout_s, tolerance): (f64, f64),
    exact: &Exact<T>,
    rays_file: &Path,
) -> Result<(Duration, Answers<T>, String), String> {
    let timeout = Duration::from_secs_f64(timeout_s);
    // The program reads copies, made for this run: one that writes to its input (`open(path,
    // "w")` for "r") would otherwise change the files, and the next check, whose exact answers
    // are read from them, would grade the damage (an emptied scene: every `miss` right).
    let input = program::RunDir::new("check").map_err(|e| format!("cannot copy the input: {e}"))?;
    let copy = |file: &Path, folder: &str| -> std::io::Result<PathBuf> {
        let to = input.path().join(folder);
        std::fs::create_dir(&to)?;
        let to = to.join(file.file_name().unwrap_or(folder.as_ref()));
        std::fs::copy(file, &to)?;
        Ok(to)
    };
    let copies = copy(scene_file, "scene").and_then(|s| Ok((s, copy(rays_file, "rays")?)));
    let (scene_copy, rays_copy) = copies.map_err(|e| format!("cannot copy the input: {e}"))?;
    // The paths go in as bytes (a path that is not UTF-8 reaches the program intact).
    let command = template::command_line(template, &scene_copy, &rays_copy);
    let limits = program::Limits::new(timeout, max_output(exact.rays.len()));
    let place = |i: usize| ray_place(rays_file, exact, i);
    let ran = program::run_with(&command, &limits).map_err(|e| match &e {
        program::RunError::Timeout { printed, .. } => {
            stalled(e.to_string(), printed, exact.rays.len(), place)
        }
        program::RunError::Failed { printed, .. } => {
            let graded = || {
                let text = String::from_utf8_lossy(printed);
                let answers = answers_for("its output", &text, exact, rays_file);
                (answers.map(|a| tally_of(&judge_all(exact, &a, tolerance))))
                    .map_err(|e| format!("{e:#}"))
            };
            crashed(e.to_string(), printed, exact.rays.len(), place, graded)
        }
        _ => e.to_string(),
    })?;
    let answers = answers_for("its output", &ran.stdout, exact, rays_file)
        .map_err(|e| stderr_hint(format!("{e:#}"), &ran))?;
    Ok((ran.elapsed, answers, ran.stdout))
}

/// Prints what was written so far, the program's failure and the failed run's last line.
pub(super) fn say_failed(out: &str, command: &str, why: &str) -> Result<()> {
    let why = raylab_app::escape_controls(why.to_string());
    say!("{out}program: {command}\nFAILED: {why}");
    say!("{}", failed_line(&Tally::default(), 1));
    Ok(())
}

/// Every answer graded against the exact ones (the reference's where disputed).
pub(super) fn judge_all<T: Real>(
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    tolerance: f64,
) -> Vec<Judged<T>> {
    let plain: Vec<Answer<T>> = answers.iter().map(|(_, a)| *a).collect();
    exact.judge(&plain, tolerance)
}

/// The tally of graded rays.
pub(super) fn tally_of<T: Real>(judged: &[Judged<T>]) -> Tally {
    let mut tally = Tally::default();
    judged.iter().for_each(|j| tally.add(&j.graded));
    tally
}

/// Writes the counts and the first wrong answers as one-line reproducers; returns the tally.
pub(super) fn report<T: Real>(
    out: &mut String,
    judged: &[Judged<T>],
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    place: &dyn Fn(usize) -> String,
    written: Written,
    show: usize,
) -> Tally {
    use std::fmt::Write;
    // Writing to a String cannot fail.
    macro_rules! w {
        ($($arg:tt)*) => { writeln!(out, $($arg)*).expect("a String takes any text") };
    }
    let tally = tally_of(judged);
    let hits = tally.t_within_ulp + tally.t_within_tolerance + tally.t_beyond;
    w!(
        "  right       {:>8}   the exact primitive, or a miss where nothing is met",
        tally.right
    );
    w!(
        "  ties        {:>8}   another primitive at the same t, or one rounding alike (accepted)",
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
        "  wrong       {:>8}   another primitive, not met at the same t (or an index past the last)",
        tally.wrong
    );
    w!(
        "  t failures  {:>8}   a right or tied hit whose t is beyond the tolerance",
        tally.t_beyond
    );
    w!(
        "  t of the {hits} right or tied hits against the exact t rounded: {} within 1 ulp, {} within the tolerance, {} beyond",
        tally.t_within_ulp,
        tally.t_within_tolerance,
        tally.t_beyond
    );
    for line in reproducers(judged, exact, answers, place, written, show) {
        w!("{line}");
    }
    if let Some(off) = line_up::off_by_a_line(judged, answers) {
        w!("{off}");
    }
    tally
}

/// The last line of a run where some programs' runs did not end well.
fn failed_line(tally: &Tally, failed: usize) -> String {
    format!("{} failed_runs {failed}", tally.line())
}

/// How a suite's program is run and graded.
struct SuiteRun<'a> {
    template: &'a str,
    timeout_s: f64,
    /// The time for all the families' runs together.
    budget: Budget,
    precision: &'a str,
    tolerance: f64,
    /// The reproducers shown under each failing family (--show).
    show: usize,
}

/// The reproducers shown under each failing family of a suite where --show is not given.
const SUITE_REPRODUCERS: usize = 3;

impl SuiteRun<'_> {
    /// The command that checks family `name` of suite `dir` alone, as this run checks it:
    /// what a student runs again while mending it.
    fn alone(&self, dir: &Path, name: &str) -> String {
        let suite = dir.display().to_string();
        let graded = (self.precision, self.tolerance, self.timeout_s);
        family_command(&invoked_as(), &suite, name, self.template, graded)
    }

    /// The commands that check line `line` of `rays` (with `scene`) alone, as this run checks
    /// it: the ray cut out with `sed`, then `raylab check` of it (a failing ray of a family
    /// of thousands, for the student's own debugging).
    fn ray_alone(&self, scene: &Path, rays: &Path, line: usize) -> String {
        let graded = (self.precision, self.tolerance, self.timeout_s);
        let files = (&*scene.display().to_string(), &*rays.display().to_string());
        ray_alone_command(&invoked_as(), files, line, self.template, graded)
    }
}

/// The command that ran this raylab, for the commands `check` prints to paste: its path
/// where it was run by one (`./target/release/raylab`: a student without raylab on PATH
/// pasted `raylab check …` and got "command not found"), else `raylab`.
fn invoked_as() -> String {
    match std::env::args_os().next() {
        Some(path) if path.as_encoded_bytes().contains(&b'/') => {
            raylab::view::shell_quote(&path.to_string_lossy())
        }
        _ => "raylab".into(),
    }
}

/// `raylab check` of one family of a suite with `template`, in `precision` (`f32` or `f64`)
/// and with `tolerance`, words quoted for a shell: `check`'s line under a failing family
/// (`raylab` as it was run) and `grade`'s feedback (bare, with SUITE and NAME to fill in).
pub(super) fn family_command(
    raylab: &str,
    suite: &str,
    family: &str,
    template: &str,
    graded: (&str, f64, f64),
) -> String {
    let quote = raylab::view::shell_quote;
    let what = format!("--suite {} --family {}", quote(suite), quote(family));
    check_command(raylab, &what, template, graded)
}

/// Line `line` of the rays file written to one.txt and checked alone on the scene file (of
/// `files`, scene then rays), as [`family_command`] checks a family: `check`'s line under a
/// failing family's first ray and `grade`'s feedback.
pub(super) fn ray_alone_command(
    raylab: &str,
    (scene, rays): (&str, &str),
    line: usize,
    template: &str,
    graded: (&str, f64, f64),
) -> String {
    let quote = raylab::view::shell_quote;
    let what = format!("--scene {} --rays one.txt", quote(scene));
    let check = check_command(raylab, &what, template, graded);
    format!("sed -n {line}p {} > one.txt && {check}", quote(rays))
}

/// `raylab check {what}` (`raylab` the command that runs it) with `template`, in `precision`
/// and with `tolerance` and `timeout` where they are not the defaults.
fn check_command(
    raylab: &str,
    what: &str,
    template: &str,
    (precision, tolerance, timeout): (&str, f64, f64),
) -> String {
    let quote = raylab::view::shell_quote;
    let mut command = format!("{raylab} check {what} --program {}", quote(template));
    if precision == "f64" {
        command += " --precision f64";
    }
    if tolerance != raylab::check::grade::DEFAULT_T_TOLERANCE {
        command += &format!(" --t-tolerance {tolerance}");
    }
    if timeout != DEFAULT_TIMEOUT {
        command += &format!(" --timeout {timeout}");
    }
    command
}

/// The reproducers shown of one answer file, program run or image where --show is not given.
pub(super) const REPRODUCERS: usize = 5;

/// Runs the program on every family of an exported suite (or on `only`): one row per family,
/// the first reproducers under each failing one, and a total.
fn check_suite<T: Real>(
    dir: &Path,
    only: Option<&str>,
    run: &SuiteRun,
    exact_of: ExactFn<T>,
) -> Result<bool> {
    let families = suite_families(dir, only)?;
    let count = raylab::words::count(families.len(), "family", "families");
    say!(
        "suite {} ({count}), {}, t tolerance {:e}, program: {}",
        dir.display(),
        run.precision,
        run.tolerance,
        run.template
    );
    say!("{}", grade::table_header());
    let mut total = Tally::default();
    let mut failed = 0;
    // The families graded and not passed, and the numbers of those answered a line off.
    let (mut unpassed, mut off): (Vec<(String, Option<bool>)>, Vec<String>) = (vec![], vec![]);
    let double = run.precision == "f64";
    let mut digits = Digits::default();
    let (mut program_time, mut raylab_time) = (Duration::ZERO, Duration::ZERO);
    // The program's time, its failed runs' included.
    let mut budget = run.budget;
    for family in &families {
        let name = family_name(family);
        // (As shown: a directory's name may hold a terminal's escapes.)
        let shown = raylab_app::one_line(&name);
        let Some((timeout, cut)) = budget.next_run(Duration::from_secs_f64(run.timeout_s)) else {
            failed += 1;
            say!("{shown:<46} SKIPPED: not run: the {}", budget.ran_out());
            continue;
        };
        let (scene, rays) = (family.join("scene.txt"), family.join("rays.txt"));
        let exact = exact_of(&scene, &rays)?;
        let start = Instant::now();
        let limits = (timeout.as_secs_f64(), run.tolerance);
        let answers = program_answers(run.template, &scene, limits, &exact, &rays);
        budget.spend(start.elapsed());
        let answers = answers.map_err(|e| match cut && e.starts_with("ran out of time") {
            true => format!("ran out of time: the {}", budget.ran_out()),
            false => e,
        });
        match answers {
            Ok((elapsed, answers, printed)) => {
                let judged = judge_all(&exact, &answers, run.tolerance);
                digits.count(&printed);
                let tally = tally_of(&judged);
                let ms = (
                    elapsed.as_secs_f64() * 1e3,
                    exact.elapsed.as_secs_f64() * 1e3,
                );
                say!("{}", tally.row(&shown, ms));
                if !tally.passed() {
                    unpassed.push((name.clone(), rounding_fails(family, double)));
                    let place = |i: usize| ray_place(&rays, &exact, i);
                    let written = Written {
                        name: "its output",
                        text: &printed,
                    };
                    let lines = reproducers(&judged, &exact, &answers, &place, written, run.show);
                    for line in lines {
                        say!("    {line}");
                    }
                    if let Some(said) = line_up::off_by_a_line(&judged, &answers) {
                        say!("    {said}");
                        off.push(family_number(&name));
                    }
                    if only.is_none() {
                        say!("    this family alone: {}", run.alone(dir, &name));
                    }
                    if let Some(i) = first_shown(&judged).filter(|_| run.show > 0) {
                        let alone = run.ray_alone(&scene, &rays, exact.rays[i].0);
                        say!("    the first ray above, alone: {alone}");
                    }
                }
                total.merge(&tally);
                program_time += elapsed;
                raylab_time += exact.elapsed;
            }
            Err(e) => {
                failed += 1;
                let e = raylab_app::escape_controls(e.to_string());
                say!("{shown:<46} FAILED: {e}");
                if only.is_none() {
                    say!("    this family alone: {}", run.alone(dir, &name));
                }
            }
        }
    }
    let ms = (
        program_time.as_secs_f64() * 1e3,
        raylab_time.as_secs_f64() * 1e3,
    );
    say!("{}", total.row("total", ms));
    // (Said first: a student told of 26 families "to mend first" mended geometry that was
    // right, the order a line off.)
    if !off.is_empty() {
        say!(
            "answers a line off in {} {}: mend their order first (the line under each family \
             says from where)",
            if off.len() == 1 { "family" } else { "families" },
            off.join(", ")
        );
    }
    let sorted = Failed::sort(unpassed.iter().map(|(n, r)| (n.as_str(), *r)));
    if let Some(sentence) = sorted.sentence(run.precision, failed) {
        say!("{sentence}");
        if let Some(advice) = digits.advice(double) {
            say!("{advice}");
        }
    }
    if failed > 0 {
        say!(
            "{failed} of {} families' runs did not end well (FAILED or SKIPPED above): not a \
             pass",
            families.len()
        );
        say!("{}", failed_line(&total, failed));
        return Ok(false);
    }
    say!("{}", total.line());
    Ok(total.passed())
}
