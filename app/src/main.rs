//! Parses the command line and dispatches; nothing else.
#![forbid(unsafe_code)]

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    raylab_app::init_logging();
    let args = cli::Cli::parse();
    if args.command.is_none() {
        // The window: before any thread starts (it may set an environment variable).
        raylab_app::window::quiet_wayland_probe();
    }
    if let Err(e) = raylab::input::check_limit_vars() {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    // Started here, so a system that cannot give the worker threads is an error, not a
    // panic at the first parallel loop.
    if let Err(e) = rayon::ThreadPoolBuilder::new().build_global() {
        eprintln!("error: cannot start the worker threads: {e}");
        return ExitCode::from(2);
    }
    let result = match &args.command {
        Some(cli::Command::Render(a)) => cli::render(a),
        Some(cli::Command::Trace(a)) => cli::trace(a),
        Some(cli::Command::Bench(a)) => cli::bench(a),
        Some(cli::Command::Inspect(a)) => cli::inspect(a),
        Some(cli::Command::Suite(a)) => cli::suite(a),
        Some(cli::Command::Grade(a)) => cli::grade(a),
        Some(cli::Command::Check(a)) => match cli::check(a) {
            // Wrong answers: the report is printed, the status says so.
            Ok(false) => return ExitCode::from(1),
            other => other.map(|_| ()),
        },
        None => viewer(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // The reader of stdout went away (`raylab bench | head -1`): stop quietly, with the
        // status a shell gives a program ended by SIGPIPE.
        Err(e) if cli::is_broken_pipe(&e) => ExitCode::from(141),
        Err(e) if e.is::<cli::Interrupted>() => {
            eprintln!("{e}");
            ExitCode::from(130)
        }
        Err(e) => {
            eprintln!("error: {}", raylab_app::error_text(&e));
            ExitCode::from(2)
        }
    }
}

fn viewer(args: &cli::Cli) -> anyhow::Result<()> {
    if let Some(model) = &args.window.model {
        cli::not_a_command(model)?;
    }
    raylab_app::window::run(args.window.options(None))
}
