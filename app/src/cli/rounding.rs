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
}

/// Whether rounding fails some correct programs graded in double (`double`) or in float on
/// the family of directory `name`; `None` where it is not a family of this raylab's suite
/// (an export of another version: nothing is said of it).
pub(super) fn rounding_fails(name: &str, double: bool) -> Option<bool> {
    let (_, slug) = name.split_once('-')?;
    let known = raylab::check::suite::slugs().iter().any(|s| s == slug);
    known.then(|| Needs::of(slug).rounding_fails(double))
}

impl Failed {
    /// The failed families, each a directory name and whether rounding fails correct code on
    /// it ([`rounding_fails`]; `None` for one not the suite's: nothing is said).
    pub(super) fn sort<'a>(
        names: impl IntoIterator<Item = (&'a str, Option<bool>)>,
    ) -> Option<Failed> {
        let mut failed = Failed {
            to_mend: Vec::new(),
            rounding: Vec::new(),
        };
        for (name, rounding) in names {
            let number = name.split_once('-').map_or(name, |(n, _)| n).to_string();
            match rounding? {
                true => failed.rounding.push(number),
                false => failed.to_mend.push(number),
            }
        }
        Some(failed)
    }

    /// What `check` says under a suite's total, where families failed: which to mend first,
    /// and which fail correct code too. (A correct double program failed five families and
    /// the student could not tell it from a bug.)
    pub(super) fn sentence(&self, precision: &str) -> Option<String> {
        let list = |numbers: &[String]| numbers.join(", ");
        let rounding = format!(
            "where rounding fails some correct {precision} programs too (the suite's README.md, \
             \"correct code passes it in\")"
        );
        match (self.to_mend.is_empty(), self.rounding.is_empty()) {
            (true, true) => None,
            (true, false) => Some(format!(
                "no family failed that every correct {precision} program measured passes; those \
                 failed ({}) are ones {rounding}: their hints say which mistakes lie within \
                 rounding",
                list(&self.rounding)
            )),
            (false, true) => Some(format!(
                "to mend first: {}, failed where every correct {precision} program measured \
                 passes",
                list(&self.to_mend)
            )),
            (false, false) => Some(format!(
                "to mend first: {}, failed where every correct {precision} program measured \
                 passes; failed besides: {}, {rounding}",
                list(&self.to_mend),
                list(&self.rounding)
            )),
        }
    }
}
