//! The real window under Xvfb, in one test binary of its own: its tests run one window at a time
//! (timed real input), and nothing else of the test run beside them. A file is a module
//! (`cargo test -p raylab-app --test window panel::`).

#[path = "../../../tests/common/mod.rs"]
mod common;

mod files;
mod input;
mod inspector;
mod layout;
mod panel;
mod sizes;
