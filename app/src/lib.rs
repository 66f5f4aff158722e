//! raylab's window: a winit event loop, an egui panel and a `pixels` framebuffer over the raylab
//! library ([`window::run`]). The `raylab` binary (src/main.rs, with the command line in
//! src/cli/) opens it when given no subcommand; a program of its own can open it too.
#![forbid(unsafe_code)]

pub mod window;
