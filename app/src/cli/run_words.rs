//! What `check` and `grade` say of a program's run that did not end well: stopped for its
//! time, crashed, or printing what is not its answers, each with how far its answers came (and
//! a crash's every answer graded all the same).

use super::program;

/// `why` a run was stopped for its time, with how far its answers had come (`printed`, its
/// output then; `place(i)`, where ray i is): the first ray without one, or, where none came,
/// that output a program holds in a buffer shows only when it ends.
pub(super) fn stalled(
    why: String,
    printed: &[u8],
    rays: usize,
    place: impl Fn(usize) -> String,
) -> String {
    match answered(printed) {
        0 => format!(
            "{why}; no answer had reached raylab: it printed none, or kept them in its buffer \
             (as Python and C do into a pipe, where output shows only when the program ends: \
             flush after each answer to see where it stalls)"
        ),
        n if n < rays => format!(
            "{why}; {} had reached raylab: the first ray without one is {} (or a later one, \
             where the program keeps output in a buffer)",
            raylab::words::count(n, "answer", "answers"),
            place(n)
        ),
        _ => format!("{why}; it had printed an answer for every ray, and did not end"),
    }
}

/// `why` a run failed (a crash, an exit status not 0), with how far its answers had come
/// (`printed`, its output; `place(i)`, where ray i is), and where it had printed an answer for
/// every ray, how those answers grade all the same (`graded()`: their tally, or why they are
/// not one answer a ray). (A crash half way said nothing of the 147 answers before it; one
/// that answered every ray right and then exited 1, a `sys.exit(1)` at the end, was told
/// only that it had printed every answer.)
pub(super) fn crashed(
    why: String,
    printed: &[u8],
    rays: usize,
    place: impl Fn(usize) -> String,
    graded: impl FnOnce() -> Result<raylab::check::Tally, String>,
) -> String {
    match answered(printed) {
        0 => why,
        n if n < rays => format!(
            "{why}; {} had reached raylab before it ended: the first ray without one is {}",
            raylab::words::count(n, "answer", "answers"),
            place(n)
        ),
        _ => format!(
            "{why}; it had printed an answer for every ray first: graded all the same, {}",
            graded_words(graded())
        ),
    }
}

/// The answers in `printed`: its complete lines that are not blank or comments, as answers
/// are read.
fn answered(printed: &[u8]) -> usize {
    let lines = printed.split(|&b| b == b'\n');
    let complete = lines.clone().count().saturating_sub(1);
    (lines.take(complete))
        .filter(|l| !l.trim_ascii().is_empty() && !l.trim_ascii().starts_with(b"#"))
        .count()
}

/// `why` a run's output is not its answers, with a hint where it printed nothing on standard
/// output but wrote to standard error: the answers went to the wrong one, or it failed in
/// words of its own there (a shell's `fork: Resource temporarily unavailable`), the last of
/// which are quoted.
pub(super) fn stderr_hint(why: String, ran: &program::Ran) -> String {
    if !ran.stdout.trim().is_empty() || ran.stderr_tail.is_empty() {
        return why;
    }
    let lines: Vec<&str> = ran.stderr_tail.lines().collect();
    let last = lines[lines.len().saturating_sub(3)..].join(" | ");
    let last: String = last.chars().take(300).collect();
    format!(
        "{why} (it printed nothing on standard output, where the answers go, and wrote to \
         standard error, which is not read; its last words: {last})"
    )
}

/// How a failed run's every answer grades (`graded`), in words after "graded all the same".
fn graded_words(graded: Result<raylab::check::Tally, String>) -> String {
    match graded {
        Ok(t) if t.passed() => {
            "every answer stands: its exit status alone fails it (end with status 0)".into()
        }
        Ok(t) => {
            let wrong = t.leaks + t.false_hits + t.wrong + t.t_beyond;
            let does = if wrong == 1 { "does" } else { "do" };
            let stand = t.right + t.ties - t.t_beyond;
            format!("{stand} stand and {wrong} {does} not")
        }
        Err(not_answers) => not_answers,
    }
}
