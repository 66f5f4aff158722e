//! `cargo run -p lab --release`: raylab's window with your code in the method selector.

use std::process::ExitCode;
use std::sync::Arc;

fn main() -> ExitCode {
    raylab_app::window::main_with_code(Arc::new(lab::YourCode))
}
