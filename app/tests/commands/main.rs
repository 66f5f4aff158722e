//! The `raylab` binary from outside, every command but the window, in one test binary: one link
//! instead of one per file, and the harness's threads shared by every file's tests. A file is a
//! module (`cargo test -p raylab-app --test commands check::`).

#[path = "../../../tests/common/mod.rs"]
mod common;

mod bad_input;
mod check;
mod check_grading;
mod classic_bugs;
mod cli;
mod flags;
mod grade;
mod grade_isolation;
mod grade_outputs;
mod hints;
mod hints_bugs;
mod limits;
mod outputs;
mod programs;
mod rounding;
mod scene_memory;
mod trace;
mod views;
