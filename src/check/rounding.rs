//! Which families rounding fails correct code on: the arithmetic a program with no bug needs
//! to pass each one, as measured with the correct programs docs/grading.md names (the C++
//! starter, Möller–Trumbore in double and in float, Cramer's rule, signed areas, the plane
//! then edge tests, each sphere formula). `check` sorts a program's failed families by it:
//! those to mend first, and those rounding alone fails too.

/// The arithmetic in which every measured correct program passes a family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Needs {
    /// Correct float (f32) programs pass it.
    F32,
    /// Correct double programs pass it; rounding fails float ones.
    F64,
    /// Rounding fails some correct double programs: only exact decisions pass it always.
    Exact,
}

/// The families (by directory name without its number) that some correct double programs
/// fail by rounding: rays through shared edges and vertices, copies a ulp apart, far tiny
/// spheres, origins on a surface.
const EXACT: [&str; 12] = [
    "icosphere-from-inside",
    "icosphere-from-outside",
    "origin-on-the-sphere-r-5",
    "origin-on-the-sphere-r-13",
    "origin-on-the-sphere-r-0-625",
    "cornell-primary-edges-vertices",
    "fan-of-12-around-an-apex",
    "t-junctions",
    "coincident-copies-permuted-and-1-ulp-moved",
    "origins-at-a-vertex",
    "slivers-1e-3-1e-45-wide",
    "far-tiny-spheres-at-the-rim",
];

/// The families every measured correct float program passes.
const F32: [&str; 8] = [
    "grazing-1e-1-1e-6-rad",
    "parallel-1e-3-1e-7-apart",
    "60-overlapping-coplanar-faces",
    "minus-0-0-directions",
    "interval-ends-at-surfaces",
    "hits-behind-the-origin",
    "exact-ties",
    "hits-just-past-tmin",
];

impl Needs {
    /// What the family of directory name `slug` (without its number) needs: a family not
    /// listed, correct double programs pass (check a name against [`super::suite::slugs`]).
    pub fn of(slug: &str) -> Needs {
        match (EXACT.contains(&slug), F32.contains(&slug)) {
            (true, _) => Needs::Exact,
            (_, true) => Needs::F32,
            _ => Needs::F64,
        }
    }

    /// Whether rounding may fail correct code on it that computes in double (`true`) or in
    /// float.
    pub fn rounding_fails(self, double: bool) -> bool {
        match self {
            Needs::F32 => false,
            Needs::F64 => !double,
            Needs::Exact => true,
        }
    }

    /// The least precision a correct program passes it in, in words (the exported README's
    /// column).
    pub fn words(self) -> &'static str {
        match self {
            Needs::F32 => "f32",
            Needs::F64 => "f64",
            Needs::Exact => "exact only",
        }
    }
}
