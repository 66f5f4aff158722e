//! The window's command-line flags (`raylab [MODEL] [--obj-frame …] [--accel …]` and the
//! scripted run's), shared by the `raylab` binary and programs that open the window with
//! their own code (the lab crate: [`main_with_code`]).

use super::ViewerOptions;
use raylab::accel::AccelChoice;
use raylab::check::LabCode;
use raylab::scene::ObjFrame;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

/// The window's flags.
#[derive(clap::Args, Debug, Clone)]
pub struct WindowArgs {
    /// An OBJ model, a `.scene` file or a saved `.view` to open in the window instead of the
    /// built-in Cornell box (`cornell`, as everywhere a scene is named).
    pub model: Option<PathBuf>,
    /// How the model's (and dropped files') coordinates are read: `yup` or `lab` (see
    /// `raylab render --help`).
    #[arg(long, default_value = "yup")]
    pub obj_frame: ObjFrame,
    /// The acceleration structure of every scene the window opens: `auto`, `flat` or `bvh`
    /// (as `raylab render --accel`).
    #[arg(long, default_value = "auto")]
    pub accel: AccelChoice,
    /// Scripted run: show N frames (then finish the script and refine the image), save what
    /// the window showed to --screenshot and exit 0. For tests; needs a display.
    #[arg(long, value_name = "N", requires = "screenshot", hide = true)]
    pub frames: Option<u64>,
    /// With --frames: the PNG file to save the window to.
    #[arg(long, value_name = "FILE.png", requires = "frames", hide = true)]
    pub screenshot: Option<PathBuf>,
    /// With --frames: timed key and mouse events to replay, one per line:
    /// `<ms> key <W|A|S|D|Q|E|Left|Right|Up|Down|Shift|R> down|up`, `<ms> mouse <dx> <dy>`,
    /// `<ms> wheel <lines>`, `<ms> step <flat|direct|shadows|indirect>`.
    #[arg(long, value_name = "FILE", requires = "frames", hide = true)]
    pub script: Option<PathBuf>,
}

impl WindowArgs {
    /// How to start the window, with linked `code` (or none).
    pub fn options(&self, code: Option<Arc<dyn LabCode>>) -> ViewerOptions {
        ViewerOptions {
            scene: self.model.clone(),
            obj_frame: self.obj_frame,
            accel: self.accel,
            frames: self.frames,
            screenshot: self.screenshot.clone(),
            script: self.script.clone(),
            code,
        }
    }
}

/// The window with linked code, from a program of its own: the window's flags, then
/// [`super::run`] with `code` offered (and chosen) in the method selector. Errors are printed
/// as `raylab` prints them, exit 2.
pub fn main_with_code(code: Arc<dyn LabCode>) -> ExitCode {
    #[derive(clap::Parser)]
    #[command(about = "raylab's window with your lab code in the method selector")]
    struct Cli {
        #[command(flatten)]
        window: WindowArgs,
    }
    crate::init_logging();
    let cli = <Cli as clap::Parser>::parse();
    // (Before any thread starts: it may set an environment variable.)
    super::quiet_wayland_probe();
    match super::run(cli.window.options(Some(code))) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", crate::error_text(&e));
            ExitCode::from(2)
        }
    }
}
