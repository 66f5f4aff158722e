//! The real window under Xvfb, in one test binary of its own: its tests run two windows at a
//! time, each on an X server of its own, one alone where its checks rest on timing
//! (`common::window::WINDOWS_AT_ONCE`), and nothing else of the test run beside them. A file is
//! a module (`cargo test -p raylab-app --test window panel::`).

#[path = "../../../tests/common/mod.rs"]
mod common;

mod files;
mod idle;
mod input;
mod inspector;
mod inspector_clicks;
mod layout;
mod panel;
mod sizes;
