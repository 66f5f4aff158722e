//! Checking intersection code that is not raylab's (a student's lab, in any language) against
//! exact answers: the hard-case suite ([`suite`]), its export in the `trace` formats
//! ([`export`]), and the grading of answer files ([`grade`]: leaks, false hits, wrong
//! primitives, exact ties, t errors); code linked in rather than run as a program answers
//! through [`code::LabCode`]. `raylab suite export` and `raylab check` are the command line
//! over these.
//!
//! The files: `suite.rs` the families and `round_two.rs` the second round of them;
//! `classic.rs` those that each catch one classic lab bug (rays with their own intervals);
//! `meshes.rs` the seeded generator, the closed test meshes and the aimed rays they are made
//! of; `export.rs` the files; `rounding.rs` the families rounding fails correct code on;
//! `grade.rs` the answers and their verdicts; `code.rs` the seam for
//! linked code, its answers and its frames.

mod classic;
pub mod code;
pub mod export;
pub mod grade;
pub mod meshes;
mod round_two;
pub mod rounding;
pub mod suite;

pub use code::LabCode;
pub use grade::{Answer, Graded, TError, Tally, Verdict};
pub use suite::Family;
