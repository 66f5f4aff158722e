//! `cargo run -p lab --release --bin lab-trace -- SCENE RAYS`: your `closest_hit` as a
//! program, `raylab trace` with your code: it reads the trace formats (a scene, and rays
//! `ox oy oz dx dy dz tmin tmax`) and prints per ray `hit <t> <index>` or `miss`, t written
//! so that it reads back to the same f32. So `raylab check` grades your code as it grades a
//! program in any language:
//!
//! ```sh
//! cargo build -p lab --release --bin lab-trace
//! raylab check --suite lab-suite --program 'target/release/lab-trace {scene} {rays}'
//! ```

use raylab::check::code;
use raylab::tracefile;
use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene, rays] = args.as_slice() else {
        eprintln!("usage: lab-trace SCENE RAYS");
        return ExitCode::from(2);
    };
    let answers = match answers(scene, rays) {
        Ok(answers) => answers,
        Err(message) => {
            eprintln!("lab-trace: {message}");
            return ExitCode::from(2);
        }
    };
    match std::io::stdout().lock().write_all(answers.as_bytes()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("lab-trace: writing the answers: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Your code's answers to the rays of `rays_file` over the scene of `scene_file`, one line
/// per ray (f32's shortest round-trip t).
fn answers(scene_file: &str, rays_file: &str) -> Result<String, String> {
    let read = |file: &str| std::fs::read_to_string(file).map_err(|e| format!("{file}: {e}"));
    let (shapes, warnings) =
        tracefile::parse_scene::<f32>(scene_file, &read(scene_file)?).map_err(|e| e.to_string())?;
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    let rays =
        tracefile::parse_rays::<f32>(rays_file, &read(rays_file)?).map_err(|e| e.to_string())?;
    let answers = code::answers(&lab::YourCode, &shapes, &rays);
    Ok(answers.iter().map(|a| a.text() + "\n").collect())
}
