//! `raylab suite export`: the hard-case suite as files in the `trace` formats, so that code
//! in any language can be run on it and graded by `raylab check`.

use super::rounding::Needs;
use super::suite::{slug, Family};
use crate::input::{self, InputError};
use std::path::{Path, PathBuf};

/// The first line of an exported suite's README.md: how an earlier export is known (only
/// such a directory is written over).
pub const README_TITLE: &str = "# raylab's hard-case suite";

/// The manifest of an exported suite, `DIR/families.txt`, written last: one line per family,
/// its directory's name and its number of rays. A directory without it is not an export, or
/// one cut short; one whose families differ from it has lost or changed some.
pub const MANIFEST: &str = "families.txt";

/// The manifest's text ([`MANIFEST`]).
pub fn manifest_text(families: &[Family]) -> String {
    let mut text = String::from(
        "# The families of this suite and their numbers of rays, written last by `raylab suite\n\
         # export`: a directory without this file is not an export, or one cut short.\n",
    );
    for (i, family) in families.iter().enumerate() {
        text += &format!("{} {}\n", dir_name(i, &family.name), family.rays.len());
    }
    text
}

/// The families a manifest ([`MANIFEST`]) lists, with their numbers of rays; `#` comment and
/// blank lines skipped. An error names the first line that is not `NAME COUNT`, as `LINE:
/// why` (its caller puts the file's path first, `PATH:LINE: why`, as every file's error).
pub fn read_manifest(text: &str) -> Result<Vec<(String, usize)>, String> {
    let mut listed = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words[..] {
            [] => {}
            [first, ..] if first.starts_with('#') => {}
            [name, count] => match count.parse() {
                Ok(count) => listed.push((name.to_string(), count)),
                Err(_) => return Err(format!("{}: '{count}' is not a number of rays", i + 1)),
            },
            _ => return Err(format!("{}: not a family's name and number of rays", i + 1)),
        }
    }
    Ok(listed)
}

/// A family's directory: its place in the suite (two digits, so a listing keeps the suite's
/// order) and its [`slug`] (`01-cube-from-inside`).
pub fn dir_name(index: usize, name: &str) -> String {
    format!("{:02}-{}", index + 1, slug(name))
}

/// A family's scene file: a comment naming it, then one primitive per line (its index is its
/// position among them).
pub fn scene_text(family: &Family) -> String {
    let mut text = format!("# {}: {}\n", family.name, family.probes);
    for shape in &family.shapes {
        text += &shape.scene_line();
        text.push('\n');
    }
    text
}

/// A family's ray file: a comment naming the columns, then one ray per line with its
/// interval (tmin = 0 and tmax = inf but in the families that probe intervals).
pub fn rays_text(family: &Family) -> String {
    let mut text = String::from("# ox oy oz dx dy dz tmin tmax\n");
    for ray in family.trace_rays() {
        text += &ray.line();
        text.push('\n');
    }
    text
}

/// Why a suite could not be exported.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error(
        "{}: holds files and is not an exported suite (its README.md does not start with \
         \"{README_TITLE}\"): choose a new or empty directory",
        .0.display()
    )]
    NotASuite(PathBuf),
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Write(#[from] InputError),
}

/// Writes every family to `dir` (`DIR/<family>/scene.txt` and `rays.txt`, see [`dir_name`])
/// and a `DIR/README.md` on the families and the formats, then the manifest ([`MANIFEST`]),
/// last. `dir` is created if missing; one that holds anything must be an earlier export, whose
/// manifest is removed first and whose files are replaced one by one, each whole or not at
/// all. Returns the family directories written.
pub fn export(dir: &Path, families: &[Family]) -> Result<Vec<PathBuf>, ExportError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| ExportError::Io { path, source }
    };
    if dir.exists() {
        // An export's own temporary files do not count: another export into the same new
        // directory, still writing its README, leaves only those.
        // The listing before the README: an export renames its whole README into place
        // before it writes anything else, so a listing that holds files was read after a
        // whole README was there (read the other way round, a README not yet there and files
        // written meanwhile looked like a foreign directory).
        let entries = std::fs::read_dir(dir).map_err(io(dir))?;
        let holds = (entries.flatten()).any(|e| input::temp_owner(&e.file_name()).is_none());
        let readme = dir.join("README.md");
        let is_suite = std::fs::read_to_string(&readme)
            .is_ok_and(|text| text.lines().next() == Some(README_TITLE));
        if holds && !is_suite {
            return Err(ExportError::NotASuite(dir.to_path_buf()));
        }
    }
    // The directory itself only, as any output's: a missing parent is a mistyped path.
    match std::fs::create_dir(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && dir.is_dir() => {}
        made => made.map_err(io(dir))?,
    }
    // Until every family is written again, the directory is not a whole export.
    let manifest = dir.join(MANIFEST);
    match std::fs::remove_file(&manifest) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(io(&manifest)(e)),
        _ => {}
    }
    // The README first: an export cut short (a full disk) is still known as one, and redone.
    input::write_file(&dir.join("README.md"), readme(families).as_bytes())?;
    let mut written = Vec::new();
    for (i, family) in families.iter().enumerate() {
        let family_dir = dir.join(dir_name(i, &family.name));
        // A link inside the suite is replaced, never followed out of it.
        for path in [
            &family_dir,
            &family_dir.join("scene.txt"),
            &family_dir.join("rays.txt"),
        ] {
            if path
                .symlink_metadata()
                .is_ok_and(|m| m.file_type().is_symlink())
            {
                std::fs::remove_file(path).map_err(io(path))?;
            }
        }
        std::fs::create_dir_all(&family_dir).map_err(io(&family_dir))?;
        input::write_file(&family_dir.join("scene.txt"), scene_text(family).as_bytes())?;
        input::write_file(&family_dir.join("rays.txt"), rays_text(family).as_bytes())?;
        written.push(family_dir);
    }
    input::write_file(&manifest, manifest_text(families).as_bytes())?;
    Ok(written)
}

/// The exported suite's README.md: what each family probes, the formats and how to grade.
pub fn readme(families: &[Family]) -> String {
    let rays: usize = families.iter().map(|f| f.rays.len()).sum();
    let mut text = format!(
        "{README_TITLE}

{n} families of primitives and rays ({rays} rays) on which intersection code goes wrong,
written by `raylab suite export`. Each directory holds a scene and its rays:

- `scene.txt`: a `#` comment line naming the family, then one primitive per line,
  `tri x0 y0 z0 x1 y1 z1 x2 y2 z2` (a triangle: two-sided and closed, its edges and
  vertices included; a ray in its plane misses) or `sphere cx cy cz r` (a tangent touch
  hits). A primitive's index is its 0-based position among the primitives.
- `rays.txt`: a `#` comment line naming the columns, then one ray per line,
  `ox oy oz dx dy dz tmin tmax`: the points o + t·d with tmin < t < tmax (both ends open).
  tmin is 0 and tmax `inf` except in the families that probe intervals, where tmin may be
  negative and tmax finite; d is not normalised (t is in units of d).
- In both files a line whose first word starts with `#` is a comment and a blank line is
  skipped; numbers are separated by spaces. A reader that skips comment and blank lines
  reads every file of the suite. Ray K (counting rays, not lines) is line K + 1 of rays.txt.

Every number is an f32 value written out exactly (its whole decimal expansion, no exponent;
`inf` for infinity): read as a float, a double or an exact rational, it is the same number.
The longest is {longest} characters (a tiny one's digits): a reader into a fixed buffer
(C's `%63s`) cuts it and reads another number.

`families.txt`, written last, lists each family's directory and its number of rays: `raylab
check --suite` and `raylab grade --suite` fail a family it lists that is missing or has
another number of rays (a copy cut short), and say so where it is missing.

**The answer**, one line per ray, in the rays' order (line K answers ray K): `hit <t> <index>`
(the nearest primitive the ray meets with tmin < t < tmax, and its t) or `miss`. Blank lines
and `#` comments are skipped. `raylab trace --scene S --rays R` prints the exact answers in
this format.

**Grading** (`raylab check`): an answer is right when it names the exact nearest primitive
(or misses where nothing is met); another primitive met at exactly the same t, or at a t that
rounds to the same value, is a tie and stands; a miss where something is met is a leak, a hit
where nothing is met a false hit, another primitive a wrong primitive. A right or tied hit's
t must be within an ulp of the exact t rounded, or within the tolerance (`--t-tolerance`,
1e-6 by default): the answer's point o + t·d within that much of the exact one, relative to
|o| + |t·d| + the primitive's largest coordinate. A t of `inf` is right only where the exact
t rounds to infinity. A family passes when every answer stands.

`raylab check --scene S --rays R --answers A` grades an answer file; `raylab check --suite
DIR --program 'CMD {{scene}} {{rays}}'` runs a program on every family (it reads the two
files named on its command line and prints its answers) and prints a row per family and the
first wrong rays under each failing one (`--family NAME` checks one). Add `--precision f64`
for code that computes in double precision.

**Rounding.** Some families ask for more than the lecture's formulas in floating point give:
rays exactly through shared edges and vertices, copies of a triangle an ulp apart, far tiny
spheres, origins on a surface. The column \"correct code passes it in\" says where every correct
program measured (Möller–Trumbore, Cramer's rule, signed areas, the plane then edge tests; each
sphere formula) passes: `f32` in float, `f64` in double (rounding in float fails some correct
programs), `exact only` where rounding fails some correct double programs too. `raylab check
--suite` names the failed families rounding does not explain (mend those first) apart from the
others.

| directory | rays | primitives | what it probes | the classic bug it catches | correct code passes it in |
|---|---:|---:|---|---|---|
",
        n = families.len(),
        longest = longest_number(families)
    );
    for (i, family) in families.iter().enumerate() {
        text += &format!(
            "| `{}` | {} | {} | {} | {} | {} |\n",
            dir_name(i, &family.name),
            family.rays.len(),
            family.shapes.len(),
            cell(&family.probes),
            match family.catches.is_empty() {
                true => "—".to_string(),
                false => cell(&family.catches),
            },
            Needs::of(&slug(&family.name)).words()
        );
    }
    text
}

/// The most characters a number of the families' files takes.
fn longest_number(families: &[Family]) -> usize {
    let files = families.iter().flat_map(|f| [scene_text(f), rays_text(f)]);
    let words = |text: String| -> usize {
        let lines = text.lines().filter(|l| !l.starts_with('#'));
        lines
            .flat_map(str::split_whitespace)
            .map(str::len)
            .max()
            .unwrap_or(0)
    };
    files.map(words).max().unwrap_or(0)
}

/// Text as a Markdown table cell: a `|` (|d|, |o − c|²) written `\|`.
pub fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}
