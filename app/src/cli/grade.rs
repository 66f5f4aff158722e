//! `raylab grade`: a class's programs run on an exported suite, one submission (a directory)
//! after another, several at once, each in a private copy of its directory with a fresh copy
//! of each family's files, under limits of time, output, memory and processes; graded against
//! the exact answers computed once. A submission that crashes, hangs, floods, forks or deletes
//! its input fails its families and harms no other: the grading goes on, and exits 0.

use super::account::{accounts, Account};
use super::budget::Budget;
use super::cases::{suite_cases, Case};
use super::class_dir::{
    copy_tree, holds_a_file, is_a_suite, list_order, only_archives, submissions,
};
use super::program::{self, Limits, RunDir, RunError};
use super::reports::{self, Record, Status, Submission};
use super::rubric::{name_of, Rubric};
use super::Precision;
use anyhow::{anyhow, bail, Context, Result};
use raylab::input::OutputFile;
use raylab_app::one_line;
use std::ffi::OsString;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// `raylab grade`.
#[derive(clap::Args, Debug)]
pub struct GradeArgs {
    /// The class: every directory in it is one submission, graded in name order.
    #[arg(value_name = "CLASS_DIR")]
    pub class: PathBuf,
    /// An exported suite (`raylab suite export DIR`).
    #[arg(long, value_name = "DIR")]
    pub suite: PathBuf,
    /// The command that runs a submission, in a private copy of its directory: `{scene}` and
    /// `{rays}` stand for the paths of the family's files (`python3 intersect.py {scene}
    /// {rays}`, `./a.out {scene} {rays}`, `make -s run SCENE={scene} RAYS={rays}`).
    #[arg(long, value_name = "CMD")]
    pub program: String,
    /// Submissions graded at once (1..=1024; default: the number of cores).
    #[arg(
        short = 'j',
        long = "jobs",
        value_name = "N",
        allow_negative_numbers = true,
        value_parser = super::count_in::<usize>(1..=1024)
    )]
    pub jobs: Option<usize>,
    /// Grade only the submission of this directory name (repeatable): a student's again, or
    /// the late ones; the outputs then hold those alone.
    #[arg(long, value_name = "NAME")]
    pub only: Vec<String>,
    /// Also write one row per submission and family to this CSV file.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Also write the same records to this JSON file (an array of objects).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Also write one row per submission to this CSV file, for a gradebook: families
    /// passed, the counts, seconds, status and, with --rubric, points and the most there are.
    #[arg(long, value_name = "FILE")]
    pub totals: Option<PathBuf>,
    /// Also write each submission's feedback to DIR/NAME.txt: every family's status and counts,
    /// and why it did not pass (its first mistake as `raylab check` shows it), for its student.
    #[arg(long, value_name = "DIR")]
    pub feedback: Option<PathBuf>,
    /// Points per passed family: lines `<family name or number> <points>`, `* <points>` for
    /// every family not named, `#` comments.
    #[arg(long, value_name = "FILE")]
    pub rubric: Option<PathBuf>,
    /// Seconds a program may take on one family before it is stopped.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = super::check::DEFAULT_TIMEOUT,
        allow_negative_numbers = true
    )]
    pub timeout: f64,
    /// Seconds a submission may take on all families together; the families after it runs
    /// out are skipped (default: 5 × --timeout).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub budget: Option<f64>,
    /// The precision the files are read in and the exact t is rounded to.
    #[arg(long, value_enum, default_value = "f32")]
    pub precision: Precision,
    /// How far a right hit's point may lie from the exact one, relative (as `raylab check`).
    #[arg(long, value_name = "X", default_value_t = raylab::check::grade::DEFAULT_T_TOLERANCE)]
    pub t_tolerance: f64,
    /// Grade only this family (its directory name, or its number).
    #[arg(long, value_name = "NAME")]
    pub family: Option<String>,
    /// Data memory (heap, written pages) of each of a program's processes, in MiB (16 or more).
    #[arg(
        long,
        value_name = "MIB",
        default_value_t = 2048,
        allow_negative_numbers = true,
        value_parser = super::count_in::<u64>(16..=u32::MAX as i64)
    )]
    pub max_memory: u64,
    /// Processes and threads a program may have at once (a fork bomb stops there; a program
    /// with a thread per core needs more than the cores).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 256,
        allow_negative_numbers = true,
        value_parser = super::count_in::<u64>(1..=u32::MAX as i64)
    )]
    pub max_processes: u64,
    /// As root, run the programs as root where no unprivileged uid can run them (refused
    /// otherwise: as root a program can read and change anything).
    #[arg(long)]
    pub as_root: bool,
    /// A variable of raylab's environment to pass to the programs (repeatable): they get
    /// only PATH, LANG, LC_ALL, LC_CTYPE, TZ and these (HOME and TMPDIR are their directory).
    #[arg(long = "env", value_name = "NAME")]
    pub env: Vec<String>,
}

/// The variables of raylab's environment every program gets (`--env` adds others).
const PASSED_ENV: [&str; 5] = ["PATH", "LANG", "LC_ALL", "LC_CTYPE", "TZ"];

/// Runs `raylab grade`: `Ok` when the grading ran, whatever the grades.
pub fn grade(args: &GradeArgs) -> Result<()> {
    super::check::check_timeout(args.timeout)?;
    let budget = Budget::new(args.budget, args.timeout)?;
    super::template::check_template(&args.program)?;
    if let Some(bad) = (args.env.iter()).find(|n| n.is_empty() || n.contains(['=', '\0'])) {
        bail!("--env '{bad}' is not a variable's name (a name, without '=')");
    }
    // (Its families were graded as 38 submissions.)
    if same_file(&args.class, &args.suite) {
        bail!(
            "CLASS_DIR and --suite name the same directory, {}",
            args.class.display()
        );
    }
    if is_a_suite(&args.class) {
        bail!(
            "CLASS_DIR {}: an exported suite, not a class (a directory per submission); the \
             suite goes to --suite",
            args.class.display()
        );
    }
    let submissions = only(submissions(&args.class)?, &args.only, &args.class)?;
    for (submission, archives) in (submissions.iter()).filter_map(|s| Some((s, only_archives(s)?)))
    {
        eprintln!(
            "warning: {}: holds archives alone ({}): unpack them where the program should run",
            one_line(&submission.display().to_string()),
            one_line(&archives.join(", "))
        );
    }
    let jobs = (args.jobs.unwrap_or_else(super::cores)).min(submissions.len().max(1));
    if !args.suite.is_dir() {
        bail!(
            "--suite {}: not a directory (write one with `raylab suite export DIR`)",
            args.suite.display()
        );
    }
    let rubric = match &args.rubric {
        Some(file) => Some(Rubric::read(file, &args.suite)?),
        None => None,
    };
    // The outputs are opened now, so a bad path fails before the grading, not after it.
    let inputs: Vec<PathBuf> = submissions.iter().chain([&args.suite]).cloned().collect();
    // (Each with the report written to it.)
    let mut outputs: Vec<(OutputFile, Report)> = Vec::new();
    let files: [(&str, &Option<PathBuf>, Report); 3] = [
        ("--csv", &args.csv, reports::csv),
        ("--json", &args.json, reports::json),
        ("--totals", &args.totals, reports::totals_csv),
    ];
    for (flag, path, report) in files {
        if let Some(path) = path {
            refuse_inside(flag, path, &inputs)?;
            let output = OutputFile::create(path).context(flag)?;
            // (Ctrl+C leaves no temporary file beside the output.)
            if let Some(temp) = output.temp_path() {
                program::remove_at_signal(temp);
            }
            outputs.push((output, report));
        }
    }
    if let (Some(dir), Some(family)) = (&args.feedback, &args.family) {
        // (A family graded again replaced a student's whole feedback, unsaid.)
        eprintln!(
            "warning: --feedback {} with --family {}: each student's file there is written \
             anew, of that family alone",
            dir.display(),
            one_line(family)
        );
    }
    if let Some(dir) = &args.feedback {
        // (Within the class's directory it would be graded as a submission next time.)
        refuse_inside("--feedback", dir, &[args.class.clone(), args.suite.clone()])?;
        writable_dir(dir).with_context(|| format!("--feedback {}", dir.display()))?;
    }
    for (k, (flag, path, _)) in files.iter().enumerate() {
        for (other, later, _) in &files[k + 1..] {
            if let (Some(a), Some(b)) = (path, later) {
                if same_file(a, b) {
                    bail!("{flag} and {other} name the same file, {}", a.display());
                }
            }
        }
    }
    // The exact answers, once (the suite's files are read here).
    let cases = suite_cases(
        &args.suite,
        args.family.as_deref(),
        args.precision,
        args.t_tolerance,
    )?;
    let points: Option<Vec<f64>> =
        rubric.map(|r| cases.iter().map(|c| r.points(&c.name)).collect());
    let limits = Limits {
        timeout: Duration::from_secs_f64(args.timeout),
        max_output_bytes: 0,
        max_memory_bytes: Some(args.max_memory.saturating_mul(1 << 20)),
        max_processes: Some(args.max_processes),
        dir: None,
        run_as: None,
        env: Some(
            PASSED_ENV
                .iter()
                .map(|n| n.to_string())
                .chain(args.env.clone())
                .collect(),
        ),
    };
    let accounts = accounts(jobs, &limits, args.as_root)?;
    // (The programs run as accounts could read the submissions' originals there.)
    let class_open =
        std::fs::canonicalize(&args.class).is_ok_and(|c| super::access::open_to_others(&c));
    if accounts.first().is_some_and(Option::is_some) && class_open {
        eprintln!(
            "warning: {}: other users may enter it, so a program can read the other \
             submissions' originals there (`chmod 700` it; each program gets a private copy)",
            one_line(&args.class.display().to_string())
        );
    }
    // (A range a reader can finish: "as uids 61000.." looked cut short.)
    let uids = match (accounts.first(), accounts.last()) {
        (Some(Some(a)), Some(Some(b))) if a.uid() != b.uid() => {
            Some(format!("uids {} to {}", a.uid(), b.uid()))
        }
        (Some(Some(a)), _) => Some(format!("uid {}", a.uid())),
        _ => None,
    };
    super::program_paths::check_program_paths(&args.program, &submissions, uids.as_deref())?;
    eprintln!(
        "grading {} on {}, {jobs} at a time{}",
        raylab::words::count(submissions.len(), "submission", "submissions"),
        raylab::words::count(cases.len(), "family", "families"),
        uids.as_ref().map_or(String::new(), |u| format!(", as {u}"))
    );
    let graded = run_all(
        &submissions,
        &cases,
        &args.program,
        &limits,
        budget,
        accounts,
    );
    // The files before the table: a reader of the table that is gone (a closed pipe) ends
    // the run after them. A file that cannot be written is said, and the others and the table
    // are still written (a full disk lost the whole grading's table), the run failing after.
    let mut unwritten = 0;
    for (mut out, report) in outputs {
        let text = report(&graded, &cases, points.as_deref());
        let written = match out.write_all(text.as_bytes()) {
            Ok(()) => out.commit().map_err(|e| e.to_string()),
            Err(e) => Err(format!("writing {}: {e}", out.path().display())),
        };
        if let Err(e) = written {
            eprintln!("error: {}", one_line(&e));
            unwritten += 1;
        }
    }
    if let Some(dir) = &args.feedback {
        let again = rerun_command(args);
        let precision = super::check::precision_name(args.precision);
        let graded_as = (precision, args.t_tolerance, args.timeout);
        let alone = |family: &str, line: usize| {
            let (scene, rays) = (
                format!("SUITE/{family}/scene.txt"),
                format!("SUITE/{family}/rays.txt"),
            );
            let files = (&*scene, &*rays);
            super::check::ray_alone_command("raylab", files, line, &args.program, graded_as)
        };
        for submission in &graded {
            let graded_in = (&*again, precision);
            let text = reports::feedback(submission, &cases, points.as_deref(), graded_in, &alone);
            let mut file = submission.dir_name.clone();
            file.push(".txt");
            let path = dir.join(file);
            if let Err(e) = raylab::input::write_file(&path, text.as_bytes()) {
                eprintln!("warning: --feedback: {}", one_line(&e.to_string()));
            }
        }
        warn_of_earlier_feedback(dir, &graded);
    }
    say!(
        "{}",
        reports::table(&graded, &cases, points.as_deref()).trim_end()
    );
    if unwritten > 0 {
        bail!(
            "{} not written (above); the table is",
            raylab::words::count(unwritten, "output file", "output files")
        );
    }
    Ok(())
}

/// The submissions `names` name (all where none is), each name one of them: a teacher
/// grading one student again made a folder of links to it and merged the CSV by hand.
fn only(submissions: Vec<PathBuf>, names: &[String], class: &Path) -> Result<Vec<PathBuf>> {
    // (A name as typed: its last part (`Zed/`, `./Zed`, `class/Zed` by tab), its accents
    // composed or not (a Mac's zip writes é as e and a combining accent).)
    use unicode_normalization::UnicodeNormalization;
    let key = |name: &str| -> String {
        let last = Path::new(name)
            .file_name()
            .map_or(name.into(), |n| n.to_string_lossy());
        last.nfc().collect()
    };
    let named = |s: &PathBuf, n: &String| key(&name_of(s)) == key(n);
    if let Some(name) = names
        .iter()
        .find(|n| !submissions.iter().any(|s| named(s, n)))
    {
        bail!(
            "--only {}: no submission of that name in {} (a directory of it, as named there)",
            raylab::view::shell_quote(&one_line(name)),
            class.display()
        );
    }
    Ok((submissions.into_iter())
        .filter(|s| names.is_empty() || names.iter().any(|n| named(s, n)))
        .collect())
}

/// A report the grading writes to a file: the CSV, the JSON or the totals.
type Report = fn(&[Submission], &[Case], Option<&[f64]>) -> String;

/// Names the feedback files in `dir` of an earlier grading (their first line raylab's) of no
/// submission graded now: handed out with the folder, a student dropped from the class was
/// sent an old grade. Not removed: a grading of a few late submissions into the class's
/// folder leaves everyone else's.
fn warn_of_earlier_feedback(dir: &Path, graded: &[Submission]) {
    use std::io::Read;
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let now: std::collections::HashSet<String> = (graded.iter())
        .map(|s| format!("{}.txt", s.dir_name.to_string_lossy()))
        .collect();
    let mut earlier: Vec<String> = (entries.filter_map(|e| e.ok()))
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".txt") && !now.contains(name))
        .filter(|name| {
            let mut head = [0u8; reports::FEEDBACK_HEAD.len()];
            (std::fs::File::open(dir.join(name)))
                .and_then(|mut f| f.read_exact(&mut head))
                .is_ok_and(|()| head == reports::FEEDBACK_HEAD.as_bytes())
        })
        .collect();
    if earlier.is_empty() {
        return;
    }
    // (In the table's order.)
    earlier.sort_by_cached_key(|name| (list_order(name), name.clone()));
    let count = raylab::words::count(earlier.len(), "file", "files");
    let shown: Vec<String> = earlier.iter().take(5).map(|n| one_line(n)).collect();
    let more = if earlier.len() > 5 { ", …" } else { "" };
    let them = if earlier.len() == 1 { "it" } else { "them" };
    eprintln!(
        "warning: --feedback {}: {count} of an earlier grading, of no submission graded now: \
         {}{more} (kept: a grading of late submissions leaves the others' \
         feedback; of a student no longer in the class, remove {them} before handing the \
         folder out)",
        dir.display(),
        shown.join(", ")
    );
}

/// An output inside a submission or the suite would be read as their input (or be copied
/// with the submission): refused.
fn refuse_inside(flag: &str, path: &Path, inputs: &[PathBuf]) -> Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| anyhow!("{flag} {}: not a file name", path.display()))?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // (Through a link, where the path names one: a link to a submission led inside it.)
    let at = std::fs::canonicalize(path)
        .or_else(|_| std::fs::canonicalize(parent).map(|p| p.join(name)));
    let Ok(at) = at else {
        return Ok(()); // (OutputFile::create names the missing directory)
    };
    for input in inputs {
        if std::fs::canonicalize(input).is_ok_and(|i| at.starts_with(i)) {
            bail!(
                "{flag} {}: inside the input {}; write it elsewhere",
                path.display(),
                input.display()
            );
        }
    }
    Ok(())
}

/// Makes directory `dir` where missing, private to the teacher (700: each student's feedback
/// is for that student), and writes (and removes) a file in it: one that cannot take the
/// feedback is refused before the grading, as a CSV that cannot be written is.
fn writable_dir(dir: &Path) -> Result<()> {
    use std::os::unix::fs::DirBuilderExt;
    if dir.exists() && !dir.is_dir() {
        bail!("not a directory");
    }
    // Through dangling links, the directory they name (making the link's own path said
    // "File exists"); a loop of links is left to fail as one.
    let mut made = dir.to_path_buf();
    for _ in 0..40 {
        match std::fs::read_link(&made) {
            Ok(target) if !made.exists() => {
                made = made.parent().unwrap_or(Path::new("")).join(target);
            }
            _ => break,
        }
    }
    std::fs::DirBuilder::new()
        .recursive(true)
        .mode(0o700)
        .create(&made)
        .with_context(|| format!("making {}", made.display()))?;
    let probe = dir.join(format!(".raylab-probe-{}", std::process::id()));
    std::fs::write(&probe, b"")?;
    std::fs::remove_file(&probe)?;
    Ok(())
}

/// The command that runs one family again as this grading ran it (its program, precision,
/// tolerance and timeout), for a student's feedback: SUITE and NAME to fill in. (A budget is
/// of all the families: one family alone has its --timeout.)
fn rerun_command(args: &GradeArgs) -> String {
    let precision = super::check::precision_name(args.precision);
    let graded = (precision, args.t_tolerance, args.timeout);
    super::check::family_command("raylab", "SUITE", "NAME", &args.program, graded)
}

fn same_file(a: &Path, b: &Path) -> bool {
    let full = |p: &Path| std::path::absolute(p).ok();
    a == b || full(a).is_some_and(|x| Some(x) == full(b))
}

/// Grades every submission, `accounts.len()` at a time; a line on stderr as each ends.
fn run_all(
    submissions: &[PathBuf],
    cases: &[Case],
    template: &str,
    limits: &Limits,
    budget: Budget,
    accounts: Vec<Option<Account>>,
) -> Vec<Submission> {
    let next = AtomicUsize::new(0);
    let (done, finished) = std::sync::mpsc::channel();
    let mut graded: Vec<Option<Submission>> = (0..submissions.len()).map(|_| None).collect();
    std::thread::scope(|scope| {
        for account in accounts {
            let (next, done) = (&next, done.clone());
            scope.spawn(move || loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(dir) = submissions.get(k) else { break };
                let start = Instant::now();
                let records = grade_one(dir, cases, template, limits, budget, account.as_ref());
                let _ = done.send((
                    k,
                    Submission {
                        name: name_of(dir),
                        dir_name: dir.file_name().unwrap_or_default().to_os_string(),
                        records,
                    },
                    start.elapsed(),
                ));
            });
        }
        drop(done);
        for (n, (k, submission, took)) in finished.iter().enumerate() {
            let passed = submission.passed();
            eprintln!(
                // (Wall time, its copy and grading too: the table's is the program's.)
                "[{}/{}] {}: {passed}/{} families passed{} ({:.1} s in all)",
                n + 1,
                submissions.len(),
                one_line(&submission.name),
                cases.len(),
                match reports::summary(&submission.records, cases).as_str() {
                    "ok" => String::new(),
                    s => format!(", {s}"),
                },
                took.as_secs_f64()
            );
            graded[k] = Some(submission);
        }
    });
    graded
        .into_iter()
        .map(|s| s.expect("every submission graded"))
        .collect()
}

/// Runs one submission on every family, in a private copy of its directory (`work`) with a
/// fresh copy of the family's files (`input`) each time, for at most `budget` in all: a
/// family's run is stopped where the budget runs out, and the families after it are skipped.
fn grade_one(
    dir: &Path,
    cases: &[Case],
    template: &str,
    limits: &Limits,
    mut budget: Budget,
    account: Option<&Account>,
) -> Vec<Record> {
    let not_run = |status: Status, why: String| -> Vec<Record> {
        let record = |_| Record {
            tally: None,
            ms: 0.0,
            status,
            detail: why.clone(),
            first_line: None,
        };
        cases.iter().map(record).collect()
    };
    // (An empty directory, a student who handed nothing in, was graded as 38 crashes of a
    // program not found.)
    if !holds_a_file(dir) {
        let why = "not run: the submission's directory holds no file (nothing handed in; a \
                   system's .DS_Store or __MACOSX/ is not the student's)";
        return not_run(Status::Empty, why.to_string());
    }
    let setup = || -> std::io::Result<(RunDir, PathBuf)> {
        let run = RunDir::new("grade")?;
        let work = run.path().join("work");
        copy_tree(dir, &work, &mut 0)?;
        if let Some(account) = account {
            account.give(run.path())?;
        }
        Ok((run, work))
    };
    let (run, work) = match setup() {
        Ok(ok) => ok,
        Err(e) => {
            let why = format!("cannot copy {}: {e}", dir.display());
            return not_run(Status::Crashed, why);
        }
    };
    let input = run.path().join("input");
    let mut records = Vec::with_capacity(cases.len());
    for case in cases {
        // (The programs' time counts; copying the files is raylab's.)
        let Some((timeout, cut_by_budget)) = budget.next_run(limits.timeout) else {
            records.push(Record {
                tally: None,
                ms: 0.0,
                status: Status::Skipped,
                detail: format!("not run: the submission's {}", budget.ran_out()),
                first_line: None,
            });
            continue;
        };
        let (scene, rays) = (input.join("scene.txt"), input.join("rays.txt"));
        let fresh = || -> std::io::Result<()> {
            if input.symlink_metadata().is_ok() {
                std::fs::remove_dir_all(&input)?;
            }
            std::fs::create_dir(&input)?;
            std::fs::copy(&case.scene, &scene)?;
            std::fs::copy(&case.rays, &rays)?;
            account.map_or(Ok(()), |a| a.give(&input))
        };
        if let Err(e) = fresh() {
            records.push(Record {
                tally: None,
                ms: 0.0,
                status: Status::Crashed,
                detail: format!("cannot copy the family's files: {e}"),
                first_line: None,
            });
            continue;
        }
        let command: OsString = super::template::command_line(template, &scene, &rays);
        let limits = Limits {
            max_output_bytes: case.max_output,
            dir: Some(work.clone()),
            run_as: account.map(Account::uid),
            timeout,
            ..limits.clone()
        };
        let start = Instant::now();
        let ran = program::run_with(&command, &limits);
        budget.spend(start.elapsed());
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let record = |status, detail: String| Record {
            tally: None,
            ms,
            status,
            detail,
            first_line: None,
        };
        records.push(match ran {
            Ok(ran) => match case.grade(&ran.stdout) {
                Ok(graded) => Record {
                    tally: Some(graded.tally),
                    ms: ran.elapsed.as_secs_f64() * 1e3,
                    status: if graded.tally.passed() {
                        Status::Ok
                    } else {
                        Status::Failed
                    },
                    detail: graded.first_mistake,
                    first_line: graded.first_line,
                },
                Err(why) => record(Status::Garbage, super::run_words::stderr_hint(why, &ran)),
            },
            Err(RunError::Timeout { .. }) if cut_by_budget => record(
                Status::Budget,
                format!("ran out of time: the submission's {}", budget.ran_out()),
            ),
            Err(ref e @ RunError::Timeout { ref printed, .. }) => {
                record(Status::Timeout, case.stalled(e.to_string(), printed))
            }
            Err(e @ RunError::TooMuch(_)) => record(Status::Flooded, e.to_string()),
            Err(e @ RunError::NotText(_)) => record(Status::Garbage, e.to_string()),
            Err(ref e @ RunError::Failed { ref printed, .. }) => record(
                Status::Crashed,
                case.crashed(limit_hint(e, &limits), printed),
            ),
            Err(e @ (RunError::Start(_) | RunError::NoDir(_))) => {
                record(Status::Crashed, limit_hint(&e, &limits))
            }
        });
    }
    drop(run);
    if let Some(account) = account {
        account.sweep();
    }
    records
}

/// Why a run crashed, with a word on the limit that may have done it, each where that limit
/// is set: `--max-processes` where it says it could not start a process or thread;
/// `--max-memory` where it says memory ran out, or died of a signal (SIGSEGV, SIGBUS,
/// SIGABRT, SIGKILL; or its shell's 128 + that), as a program refused memory dies where at
/// home it ran ("exit status 139" said nothing of the limit), unless it names a memory bug
/// of its own.
fn limit_hint(e: &RunError, limits: &Limits) -> String {
    use std::os::unix::process::ExitStatusExt;
    let said = e.to_string();
    let RunError::Failed { status, stderr, .. } = e else {
        return said;
    };
    // What a run out of processes or memory says, by the words of common shells, Python, C,
    // C++, Java and Node (it ended with an error of its own, not a signal). (Java names a
    // thread it could not start an OutOfMemoryError: the processes' words come first.)
    let said_of = |words: &[&str]| words.iter().any(|w| stderr.contains(w));
    let no_process = said_of(&[
        "fork",
        "can't start new thread",
        "Resource temporarily unavailable",
        "unable to create native thread",
        "pthread_create",
        "EAGAIN",
    ]);
    if let Some(most) = limits.max_processes.filter(|_| no_process) {
        return format!(
            "{said} (it could not start a process or thread: a program may have {most} at \
             once, --max-processes)"
        );
    }
    let no_memory = said_of(&[
        "MemoryError",
        "Cannot allocate memory",
        "bad_alloc",
        "out of memory",
    ]);
    // (A crash that names its own memory bug, glibc's heap checks or a sanitizer's, is that
    // bug: "realloc(): invalid next size | Aborted" was told it may be the limit.)
    let own_bug = said_of(&[
        // (glibc's own words, whole: "corrupted" alone took "a scene line looks corrupted".)
        "double free or corruption",
        "free(): ",
        "malloc(): ",
        "realloc(): ",
        "munmap_chunk(): ",
        "malloc_consolidate(): ",
        "corrupted size vs. prev_size",
        "corrupted double-linked list",
        "corrupted top size",
        "stack smashing detected",
        "AddressSanitizer",
    ]);
    let signal = status
        .signal()
        .or(status.code().filter(|c| *c > 128).map(|c| c - 128));
    match (
        limits.max_memory_bytes,
        !own_bug && (no_memory || matches!(signal, Some(6 | 7 | 9 | 11))),
    ) {
        (Some(limit), true) => format!(
            "{said} (a crash like this may be the memory limit: each process may write {} MiB \
             of data, --max-memory)",
            limit >> 20
        ),
        _ => said,
    }
}
