//! `taut`: the command line of the Taut surface editor.
//!
//! `main` only parses the arguments and hands them to one subcommand module; each returns a
//! one-line error message, printed on stderr with a non-zero exit status.

mod curve_cmd;
mod render_cmd;
mod smooth_cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Taut: smooth surfaces from coarse polygon cages (NUSD smoothing with tension).
#[derive(Debug, Parser)]
#[command(name = "taut", version)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Refine and smooth a cage (OBJ, glTF, GLB or .taut) and write the surface.
    Smooth(smooth_cmd::SmoothArgs),
    /// Smooth a polyline given as JSON, inserting points between the input points.
    SmoothCurve(curve_cmd::SmoothCurveArgs),
    /// Draw a surface shaded, as zebra stripes or in curvature colour into a PNG.
    Render(render_cmd::RenderArgs),
}

fn main() -> ExitCode {
    // A bug must still end in one readable line, not a backtrace.
    std::panic::set_hook(Box::new(|info| {
        let what = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_default();
        eprintln!("error: internal error in taut ({what}); please report it with the input file");
    }));
    let cli = Cli::parse();
    let result = match &cli.command {
        Some(Command::Smooth(args)) => smooth_cmd::run(args),
        Some(Command::SmoothCurve(args)) => curve_cmd::run(args),
        Some(Command::Render(args)) => render_cmd::run(args),
        None => {
            // The editor window is not built yet: show what the command line can do.
            use clap::CommandFactory;
            println!("{}", Cli::command().render_help());
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
