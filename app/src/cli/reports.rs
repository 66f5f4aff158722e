//! What `raylab grade` found, a record per submission and family, and what it writes of
//! them: the table on stdout, the CSV, the JSON and each submission's feedback.

use super::cases::Case;
use super::rounding::Failed;
use super::rubric::points_text;
use raylab::check::Tally;
use raylab_app::one_line;
use std::ffi::OsString;

/// How one family went for one submission (the CSV's `status`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(super) enum Status {
    /// Graded, and passed.
    Ok,
    /// Graded, with mistakes.
    Failed,
    /// A status other than success, or a signal.
    Crashed,
    /// Still running at --timeout.
    Timeout,
    /// Still running when the submission's --budget ran out: stopped by the budget before
    /// its --timeout (as a slow program's last family is).
    Budget,
    /// More output than any answers need.
    Flooded,
    /// Output that is not one answer per ray, or not UTF-8.
    Garbage,
    /// Not run: the submission's --budget ran out on earlier families.
    Skipped,
    /// Not run: the submission's directory holds no file (nothing was handed in).
    Empty,
}

impl Status {
    pub(super) fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed => "failed",
            Status::Crashed => "crashed",
            Status::Timeout => "timeout",
            Status::Budget => "budget",
            Status::Flooded => "flooded",
            Status::Garbage => "garbage",
            Status::Skipped => "skipped",
            Status::Empty => "empty",
        }
    }
}

/// One submission on one family.
pub(super) struct Record {
    pub(super) tally: Option<Tally>,
    pub(super) ms: f64,
    pub(super) status: Status,
    /// Why it was not graded (empty when it was), or its first mistake.
    pub(super) detail: String,
    /// The line of that mistake's ray in the family's rays file.
    pub(super) first_line: Option<usize>,
}

/// One submission: its name and a record per family (in the cases' order).
pub(super) struct Submission {
    pub(super) name: String,
    /// Its directory's own name (`name` writes bytes that are not UTF-8 as `\xNN`, as a
    /// name can be written).
    pub(super) dir_name: OsString,
    pub(super) records: Vec<Record>,
}

impl Submission {
    /// How many families it passed.
    pub(super) fn passed(&self) -> usize {
        self.records
            .iter()
            .filter(|r| r.status == Status::Ok)
            .count()
    }

    /// Its counts summed over the families graded (`None` where none was: no counts, which
    /// differs from counts of 0), and its programs' seconds in all.
    fn totals(&self) -> (Option<Tally>, f64) {
        let mut graded = (self.records.iter().filter_map(|r| r.tally.as_ref())).peekable();
        let total = graded.peek().is_some().then(|| {
            let mut total = Tally::default();
            graded.for_each(|t| total.merge(t));
            total
        });
        let secs = self.records.iter().map(|r| r.ms).sum::<f64>() / 1e3;
        (total, secs)
    }

    /// The points of the families it passed (with `points` per family).
    fn points_earned(&self, points: Option<&[f64]>) -> f64 {
        (self.records.iter().enumerate())
            .filter_map(|(k, r)| earned(points, k, r))
            .sum()
    }
}

/// "ok", or how many families ended each other way ("failed 2, timeout 1"), with how many of
/// the failed ones rounding fails some correct programs on too ("failed 6 (rounding 5)").
pub(super) fn summary(records: &[Record], cases: &[Case]) -> String {
    let mut counts: Vec<(Status, usize)> = Vec::new();
    for r in records.iter().filter(|r| r.status != Status::Ok) {
        match counts.iter_mut().find(|(s, _)| *s == r.status) {
            Some((_, n)) => *n += 1,
            None => counts.push((r.status, 1)),
        }
    }
    counts.sort();
    let rounding = (records.iter().zip(cases))
        .filter(|(r, case)| r.status == Status::Failed && case.rounding == Some(true))
        .count();
    let name = |s: Status, n: usize| match (s, rounding) {
        (Status::Failed, 1..) => format!("failed {n} (rounding {rounding})"),
        _ => format!("{} {n}", s.name()),
    };
    match counts.is_empty() {
        true => "ok".into(),
        false => counts
            .iter()
            .map(|&(s, n)| name(s, n))
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// The feedback's words on the failed families: those to mend first, and those rounding
/// fails correct code on too (as `check --suite` says them).
fn failed_families(s: &Submission, cases: &[Case], precision: &str) -> Option<String> {
    let failed = (s.records.iter().zip(cases))
        .filter(|(r, _)| r.status == Status::Failed)
        .map(|(_, case)| (case.name.as_str(), case.rounding));
    let ungraded = (s.records.iter())
        .filter(|r| !matches!(r.status, Status::Ok | Status::Failed | Status::Empty))
        .count();
    Failed::sort(failed).sentence(precision, ungraded)
}

/// A family's points for a record: the family's when it passed.
fn earned(points: Option<&[f64]>, family: usize, r: &Record) -> Option<f64> {
    points.map(|p| {
        if r.status == Status::Ok {
            p[family]
        } else {
            0.0
        }
    })
}

/// The most terminal columns the table gives a submission's name (the files give it whole).
const NAME_COLUMNS: usize = 48;

/// `name` as the table shows it (escaped: [`one_line`]), cut to `columns` terminal columns
/// where it is wider: its first two thirds and its end, "…" between (names alike in their
/// first columns, cut at the end, read the same). The cut falls between characters of the
/// name, so an escape such as `\u{202e}` is kept whole or left out.
fn cut_to(name: &str, columns: usize) -> String {
    let shown: Vec<String> = name.chars().map(|c| one_line(&c.to_string())).collect();
    let whole = shown.concat();
    if columns_of(&whole) <= columns {
        return whole;
    }
    let room = columns - 1;
    let take = |units: &mut dyn Iterator<Item = &String>, most: usize| {
        let mut used = 0;
        units
            .take_while(|unit| {
                used += columns_of(unit);
                used <= most
            })
            .cloned()
            .collect::<Vec<String>>()
    };
    let head = take(&mut shown.iter(), room * 2 / 3).concat();
    let mut tail = take(&mut shown.iter().rev(), room - columns_of(&head));
    tail.reverse();
    head + "…" + &tail.concat()
}

/// The terminal columns of `text`, a character's at a time (as [`cut_to`] counts them).
fn columns_of(text: &str) -> usize {
    text.chars().map(char_columns).sum()
}

/// The terminal columns of one character (none for a control character or combining mark).
fn char_columns(c: char) -> usize {
    unicode_width::UnicodeWidthChar::width(c).unwrap_or(0)
}

/// The table: one row per submission.
pub(super) fn table(graded: &[Submission], cases: &[Case], points: Option<&[f64]>) -> String {
    let width = graded
        .iter()
        .map(|s| columns_of(&one_line(&s.name)))
        .max()
        .unwrap_or(0)
        .clamp(10, NAME_COLUMNS);
    // Padded by the columns a terminal gives each character (two for 李, none for a
    // combining accent), not by characters; a longer name cut to fit, so the columns stay in
    // line (a learning platform's folder names, "Björn Åkesson_1242_assignsubmission_file_",
    // pushed their rows out).
    let padded = |name: &str| {
        let name = cut_to(name, width);
        format!(
            "{name}{}",
            " ".repeat(width.saturating_sub(columns_of(&name)))
        )
    };
    // The points column, where there is a rubric.
    let points_column = |text: &str| match points {
        Some(_) => format!(" {text:>13}"),
        None => String::new(),
    };
    let mut out = format!(
        "{:<width$} {:>7} {:>6} {:>6} {:>6} {:>7} {:>9}{}  status\n",
        "submission",
        "passed",
        "leaks",
        "false",
        "wrong",
        "t fail",
        "time s",
        points_column("points")
    );
    let most: f64 = points.map_or(0.0, |p| p.iter().sum());
    for s in graded {
        let passed = s.passed();
        // (No family graded: no counts, not counts of 0, as the CSV's empty fields.)
        let (total, secs) = s.totals();
        let count =
            |n: fn(&Tally) -> usize| total.as_ref().map_or("-".to_string(), |t| n(t).to_string());
        let earned = s.points_earned(points);
        out += &format!(
            "{} {:>7} {:>6} {:>6} {:>6} {:>7} {:>9.2}{}  {}\n",
            padded(&s.name),
            format!("{passed}/{}", cases.len()),
            count(|t| t.leaks),
            count(|t| t.false_hits),
            count(|t| t.wrong),
            count(|t| t.t_beyond),
            secs,
            points_column(&format!("{}/{}", points_text(earned), points_text(most))),
            summary(&s.records, cases)
        );
    }
    out
}

/// The totals CSV: one row per submission, what a gradebook takes (the table's columns; with
/// a rubric, the points earned and the most there are).
pub(super) fn totals_csv(graded: &[Submission], cases: &[Case], points: Option<&[f64]>) -> String {
    let mut out =
        String::from("submission,families,passed,leaks,false_hits,wrong,t_failures,seconds,status");
    out += if points.is_some() {
        ",points,max_points\n"
    } else {
        "\n"
    };
    let most: f64 = points.map_or(0.0, |p| p.iter().sum());
    for s in graded {
        // (No family graded: empty counts, as the per-family CSV's, not counts of 0.)
        let (total, secs) = s.totals();
        let counts = match total {
            None => ",,,".into(),
            Some(t) => [t.leaks, t.false_hits, t.wrong, t.t_beyond]
                .map(|n| n.to_string())
                .join(","),
        };
        out += &format!(
            "{},{},{},{counts},{secs:.2},{}",
            csv_field(&as_text(&s.name)),
            cases.len(),
            s.passed(),
            csv_field(&summary(&s.records, cases)),
        );
        if points.is_some() {
            let earned = s.points_earned(points);
            out += &format!(",{},{}", points_text(earned), points_text(most));
        }
        out.push('\n');
    }
    out
}

/// The CSV: one row per submission and family.
pub(super) fn csv(graded: &[Submission], cases: &[Case], points: Option<&[f64]>) -> String {
    let mut out = String::from(
        "submission,family,rays,right,ties,leaks,false_hits,wrong,t_failures,ms,status",
    );
    out += if points.is_some() { ",points\n" } else { "\n" };
    for s in graded {
        for (k, (r, case)) in s.records.iter().zip(cases).enumerate() {
            let counts = match &r.tally {
                Some(t) => [t.right, t.ties, t.leaks, t.false_hits, t.wrong, t.t_beyond]
                    .map(|n| n.to_string())
                    .join(","),
                None => ",,,,,".into(),
            };
            out += &format!(
                "{},{},{},{counts},{:.1},{}",
                csv_field(&as_text(&s.name)),
                csv_field(&case.name),
                case.ray_count,
                r.ms,
                r.status.name()
            );
            if let Some(p) = earned(points, k, r) {
                out += &format!(",{p}");
            }
            out.push('\n');
        }
    }
    out
}

/// A submission's name as a spreadsheet shows it as text: after a `'` where it starts as a
/// formula would (`=`, `+`, `-`, `@`, a tab or a carriage return), which a spreadsheet opening
/// the CSV would otherwise run.
fn as_text(name: &str) -> String {
    match name.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        true => format!("'{name}"),
        false => name.to_string(),
    }
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
fn csv_field(s: &str) -> String {
    match s.contains([',', '"', '\n', '\r']) {
        true => format!("\"{}\"", s.replace('"', "\"\"")),
        false => s.to_string(),
    }
}

/// The JSON: an array of the CSV's records, the counts `null` where nothing was graded, with
/// `detail`, why not.
pub(super) fn json(graded: &[Submission], cases: &[Case], points: Option<&[f64]>) -> String {
    let mut rows = Vec::new();
    for s in graded {
        for (k, (r, case)) in s.records.iter().zip(cases).enumerate() {
            let count = |n: fn(&Tally) -> usize| {
                r.tally.as_ref().map_or("null".into(), |t| n(t).to_string())
            };
            let mut row = format!(
                "{{\"submission\": {}, \"family\": {}, \"rays\": {}, \"right\": {}, \"ties\": {}, \"leaks\": {}, \"false_hits\": {}, \"wrong\": {}, \"t_failures\": {}, \"ms\": {:.1}, \"status\": \"{}\", \"detail\": {}",
                json_string(&s.name),
                json_string(&case.name),
                case.ray_count,
                count(|t| t.right),
                count(|t| t.ties),
                count(|t| t.leaks),
                count(|t| t.false_hits),
                count(|t| t.wrong),
                count(|t| t.t_beyond),
                r.ms,
                r.status.name(),
                json_string(&r.detail)
            );
            if let Some(p) = earned(points, k, r) {
                row += &format!(", \"points\": {p}");
            }
            rows.push(row + "}");
        }
    }
    format!("[\n  {}\n]\n", rows.join(",\n  "))
}

/// `s` as a JSON string: quotes, backslashes and control characters escaped.
fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out += "\\\"",
            '\\' => out += "\\\\",
            '\n' => out += "\\n",
            '\r' => out += "\\r",
            '\t' => out += "\\t",
            c if (c as u32) < 0x20 => out += &format!("\\u{:04x}", c as u32),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// How a feedback file starts (then the submission's name): how a later grading knows the
/// files of an earlier one.
pub(super) const FEEDBACK_HEAD: &str = "raylab grade: ";

/// One submission's feedback, the file its student reads: every family's status and counts,
/// and where it did not pass why (its first mistake as `raylab check` shows it: the ray's file
/// and line in the suite, the ray, the exact answer and the given one; or why it was not
/// graded), with `again`, the command that runs one family as the grading did, and under a
/// first mistake the command that checks its ray alone (`alone` of the family and the ray's
/// line), and what rounding explains of the failed families in `precision`.
pub(super) fn feedback(
    s: &Submission,
    cases: &[Case],
    points: Option<&[f64]>,
    (again, precision): (&str, &str),
    alone: &dyn Fn(&str, usize) -> String,
) -> String {
    let mut out = format!(
        "{FEEDBACK_HEAD}{}\n{} of {} families passed",
        one_line(&s.name),
        s.passed(),
        cases.len()
    );
    if let Some(p) = points {
        let (earned, most) = (s.points_earned(points), p.iter().sum());
        out += &format!(", {} of {} points", points_text(earned), points_text(most));
    }
    if let Some(sentence) = failed_families(s, cases, precision) {
        out += &format!("\n{sentence}");
    }
    out += &format!(
        "\nA family again, as graded (SUITE: `raylab suite export SUITE` writes it; NAME: the \
         family's name or number):\n  {again}\n\n"
    );
    let mut above = "";
    for (r, case) in s.records.iter().zip(cases) {
        let counts = match &r.tally {
            Some(t) => format!(
                "{} rays: right {}, ties {}, leaks {}, false hits {}, wrong {}, t failures {}",
                case.ray_count, t.right, t.ties, t.leaks, t.false_hits, t.wrong, t.t_beyond
            ),
            None => format!("{} rays", case.ray_count),
        };
        let secs = r.ms / 1e3;
        out += &format!(
            "{}: {} ({counts}) {secs:.2} s\n",
            one_line(&case.name),
            r.status.name()
        );
        // (A ray's file named from SUITE, as the command above names the suite: the student
        // exported it somewhere else than the teacher's path.)
        let teachers = case.rays.display().to_string();
        let file = case.rays.file_name().unwrap_or_default().to_string_lossy();
        let students = format!("SUITE/{}/{file}", case.name);
        // (A detail the family above gave word for word, once: a program that never starts
        // repeated its error under each of the 38 families.)
        if !r.detail.trim().is_empty() && r.detail == above {
            out += "    (the same as the family above)\n";
            continue;
        }
        above = &r.detail;
        for line in r.detail.lines().filter(|l| !l.trim().is_empty()) {
            out += &format!("    {}\n", one_line(&line.replace(&teachers, &students)));
        }
        // (The family's command prints it; here the student need not run the family first.)
        if let (Status::Failed, Some(line)) = (r.status, r.first_line) {
            out += &format!("    this ray alone: {}\n", alone(&case.name, line));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{columns_of, cut_to};

    #[test]
    fn a_cut_name_keeps_each_escape_whole_or_leaves_it_out() {
        // A right-to-left override at each place a cut can fall: the table's name is never
        // wider than its columns, and shows the override escaped whole or not at all.
        for at in 0..60 {
            let name = format!("{}\u{202e}{}", "a".repeat(at), "b".repeat(60 - at));
            let cut = cut_to(&name, 48);
            assert!(columns_of(&cut) <= 48, "{cut}");
            assert!(cut.contains('…') && !cut.contains('\u{202e}'), "{cut}");
            let kept = cut.replace("\\u{202e}", "");
            assert!(!kept.contains(['\\', '{', '}']), "{at}: {cut}");
        }
        // Wide characters (two columns each) are kept whole: two thirds of the room before
        // the "…", the rest after it.
        assert_eq!(cut_to(&"李".repeat(30), 11), "李李李…李李");
        // A name that fits is shown whole, escaped.
        assert_eq!(cut_to("eve\nada", 48), "eve\\nada");
    }
}
