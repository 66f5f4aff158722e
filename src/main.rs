//! Parses the command line and dispatches; nothing else.
#![forbid(unsafe_code)]

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let args = cli::Cli::parse();
    let result = match &args.command {
        Some(cli::Command::Render(a)) => cli::render(a),
        Some(cli::Command::Trace(a)) => cli::trace(a),
        None => {
            eprintln!(
                "raylab: the interactive window is not built yet; use `raylab render --out FILE.png` \
                 (see `raylab --help`)"
            );
            return ExitCode::from(1);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
