//! A suite's failed families sorted by what rounding explains (`check --suite`'s last words,
//! `grade`'s status and feedback): those every measured correct program of the precision
//! passes, to mend first, and those where rounding fails some correct programs too
//! ([`raylab::check::rounding::Needs`]; the exported README's last column).

use raylab::check::rounding::Needs;

/// Failed families (directory names, `03-icosphere-from-inside`) sorted for a program
/// graded in double (`double`) or float.
pub(super) struct Failed {
    /// The numbers of those correct programs pass: a bug's.
    pub to_mend: Vec<String>,
    /// The numbers of those rounding fails some correct programs on too.
    pub rounding: Vec<String>,
    /// The names of those not of this raylab's suite (or whose scene is another's): unsorted.
    pub unknown: Vec<String>,
}

/// Whether rounding fails some correct programs graded in double (`double`) or in float on
/// the family of directory `dir`; `None` where it is not a family of this raylab's suite (an
/// export of another version) or its scene is another's (its first line names its family:
/// two directories swapped sorted a bug's family as rounding's).
pub(super) fn rounding_fails(dir: &std::path::Path, double: bool) -> Option<bool> {
    use std::io::{BufRead, Read};
    let name = super::suite_dir::family_name(dir);
    let (_, slug) = name.split_once('-')?;
    let known = raylab::check::suite::slugs().iter().any(|s| s == slug);
    let mut first = String::new();
    let scene = std::fs::File::open(dir.join("scene.txt")).ok()?;
    std::io::BufReader::new(scene)
        .take(4096)
        .read_line(&mut first)
        .ok()?;
    let named = first.strip_prefix("# ")?.split(": ").next()?;
    let its_own = raylab::check::suite::slug(named) == slug;
    (known && its_own).then(|| Needs::of(slug).rounding_fails(double))
}

impl Failed {
    /// The failed families, each a directory name and whether rounding fails correct code on
    /// it ([`rounding_fails`]; `None`: not this raylab's suite's, left unsorted).
    pub(super) fn sort<'a>(names: impl IntoIterator<Item = (&'a str, Option<bool>)>) -> Failed {
        let mut failed = Failed {
            to_mend: Vec::new(),
            rounding: Vec::new(),
            unknown: Vec::new(),
        };
        for (name, rounding) in names {
            let number = family_number(name);
            match rounding {
                Some(true) => failed.rounding.push(number),
                Some(false) => failed.to_mend.push(number),
                None => failed.unknown.push(raylab_app::one_line(name)),
            }
        }
        failed
    }

    /// What `check` says under a suite's total, where families failed: which to mend first,
    /// and which fail correct code too. (A correct double program failed five families and
    /// the student could not tell it from a bug.)
    /// (`ungraded`: how many families' runs did not end well, said first: a program that
    /// dropped its `miss` lines in 23 families was told that none failed but rounding's.)
    pub(super) fn sentence(&self, precision: &str, ungraded: usize) -> Option<String> {
        let sorted = self.sorted(precision);
        match (ungraded, sorted) {
            (0, sorted) => sorted,
            (n, None) => Some(format!("{}: mend {} first", not_graded(n), them(n))),
            (n, Some(sorted)) => Some(format!(
                "{}: mend {} first; of the others, {sorted}",
                not_graded(n),
                them(n)
            )),
        }
    }

    /// The sentence on the families graded.
    fn sorted(&self, precision: &str) -> Option<String> {
        let list = |numbers: &[String]| numbers.join(", ");
        let every = format!("every correct {precision} program measured passes");
        let rounding = format!(
            "where rounding fails some correct {precision} programs too (the suite's README.md, \
             \"correct code passes it in\")"
        );
        let mut parts = Vec::new();
        if !self.to_mend.is_empty() {
            parts.push(format!(
                "to mend first: {}, failed where {every}",
                list(&self.to_mend)
            ));
        }
        // (Only where every failed family is sorted: an unsorted one may be a bug's.)
        let all_sorted = self.to_mend.is_empty() && self.unknown.is_empty();
        match (self.rounding.is_empty(), all_sorted) {
            (true, _) => {}
            (false, true) => parts.push(format!(
                "no family failed that {every}; those failed ({}) are ones {rounding}: their \
                 hints say which mistakes lie within rounding",
                list(&self.rounding)
            )),
            (false, false) => parts.push(format!(
                "{}: {}, {rounding}",
                if self.to_mend.is_empty() {
                    "failed"
                } else {
                    "failed besides"
                },
                list(&self.rounding)
            )),
        }
        if !self.unknown.is_empty() {
            parts.push(format!(
                "not sorted: {} (not a family of this raylab's suite, or its scene.txt is \
                 another's: `raylab suite export` writes the suite)",
                self.unknown.join(", ")
            ));
        }
        (!parts.is_empty()).then(|| parts.join("; "))
    }
}

/// A family directory's number as shown (`03` of `03-icosphere-from-inside`; escaped: a
/// directory's name may hold a terminal's escapes).
pub(super) fn family_number(name: &str) -> String {
    raylab_app::one_line(name.split('-').next().unwrap_or(name))
}

/// "1 family's run did not end well" or "N families' runs …" (it crashed or failed, even after
/// its every answer, ran out of time, or printed what is not one answer a ray).
fn not_graded(n: usize) -> String {
    match n {
        1 => "1 family's run did not end well".into(),
        n => format!("{n} families' runs did not end well"),
    }
}

/// "it" or "them".
fn them(n: usize) -> &'static str {
    if n == 1 {
        "it"
    } else {
        "them"
    }
}

/// The t's a program printed, by their significant digits: what a float program prints (9 or
/// fewer, `%.9g`) and what a double one does (15 or more, `%.17g`), among those with 7 or
/// more (a t of 1 or 0.5 tells nothing). A float program graded `--precision f64` was told of
/// 15 families "to mend first", every one of them rounding's in f32.
#[derive(Default)]
pub(super) struct Digits {
    floats: usize,
    doubles: usize,
    told: usize,
}

impl Digits {
    /// Counts the t's of `output`'s `hit T INDEX` lines.
    pub(super) fn count(&mut self, output: &str) {
        use super::evidence::{hit_ts, significant_digits};
        for n in hit_ts(output).map(significant_digits) {
            match n {
                0..7 => {}
                7..=9 => (self.floats, self.told) = (self.floats + 1, self.told + 1),
                15.. => (self.doubles, self.told) = (self.doubles + 1, self.told + 1),
                _ => self.told += 1,
            }
        }
    }

    /// Where the t's say the program computes in another precision than the one graded
    /// (`double`): nine in ten of 20 or more, a word on grading it in that one.
    pub(super) fn advice(&self, double: bool) -> Option<String> {
        let most = |n: usize| self.told >= 20 && 10 * n >= 9 * self.told;
        match (double, most(self.floats), most(self.doubles)) {
            (true, true, _) => Some(
                "its t's have 9 significant digits or fewer, as a float program prints them: if \
                 it computes in float, check it with --precision f32 (the default), where \
                 rounding explains more"
                    .into(),
            ),
            (false, _, true) => Some(
                "its t's have 15 significant digits or more, as a double program prints them: \
                 if it computes in double, check it with --precision f64, where rounding \
                 explains less"
                    .into(),
            ),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Digits, Failed};

    /// A family not of the suite is left unsorted, named, and the others sorted all the same;
    /// "no family failed that every correct program passes" is said only where all are sorted.
    #[test]
    fn an_unknown_family_is_left_unsorted_and_the_others_sorted() {
        let rounding = "03-icosphere-from-inside";
        let sorted = Failed::sort([(rounding, Some(true)), ("39-mine", None)]);
        let said = sorted.sentence("f64", 0).unwrap();
        assert!(
            said.starts_with("failed: 03, where rounding fails"),
            "{said}"
        );
        assert!(
            said.contains("; not sorted: 39-mine (not a family of"),
            "{said}"
        );
        let alone = Failed::sort([(rounding, Some(true))])
            .sentence("f64", 0)
            .unwrap();
        assert!(alone.starts_with("no family failed that every correct f64 program"));
        let mend = Failed::sort([("01-cube-from-inside", Some(false))]).sentence("f32", 2);
        let said = "2 families' runs did not end well: mend them first; of the others, to mend \
                    first: 01";
        assert!(mend.unwrap().starts_with(said));
    }

    /// Float-printed t's graded in double are told of --precision f32, double-printed ones
    /// graded in float of f64; t's of few digits tell nothing.
    #[test]
    fn the_digits_of_the_ts_name_the_precision() {
        let floats: String = (0..30)
            .map(|k| format!("hit 1.{k:02}34567 {k}\nmiss\n"))
            .collect();
        let doubles: String = (0..30)
            .map(|k| format!("hit 1.{k}234567890123456 0\n"))
            .collect();
        let (mut f, mut d, mut round) = (Digits::default(), Digits::default(), Digits::default());
        f.count(&floats);
        d.count(&doubles);
        round.count(&"hit 1 0\nhit 0.5 1\n".repeat(30));
        assert!(f.advice(true).unwrap().contains("--precision f32"));
        assert_eq!(f.advice(false), None);
        assert!(d.advice(false).unwrap().contains("--precision f64"));
        assert_eq!(d.advice(true), None);
        assert_eq!((round.advice(true), round.advice(false)), (None, None));
    }
}
