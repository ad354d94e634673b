//! `taut`: the Taut surface editor and its command line.
//!
//! `taut [FILE]` opens the editor (on the bundled default scene when no file is given);
//! `taut SUBCOMMAND …` runs one command-line tool. `main` only parses the arguments and hands
//! them on; every failure is one line on stderr with a non-zero exit status.

mod curve_cmd;
mod curve_mesh_cmd;
mod editor;
mod render_cmd;
mod smooth_cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Taut: smooth surfaces from coarse polygon cages (NUSD smoothing with tension).
#[derive(Debug, Parser)]
#[command(name = "taut", version, args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// A cage or mesh to open in the editor (.taut, .obj, .gltf, .glb).
    file: Option<std::path::PathBuf>,
    /// How the editor first shows the surface: shaded, zebra or curvature.
    #[arg(long, default_value = "zebra")]
    view: String,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Refine and smooth a cage (OBJ, glTF, GLB or .taut) and write the surface.
    Smooth(smooth_cmd::SmoothArgs),
    /// Smooth a polyline given as JSON, inserting points between the input points.
    SmoothCurve(curve_cmd::SmoothCurveArgs),
    /// Build a cage's curve mesh on its Catmull–Clark limit surface, fill it with G1 Gregory
    /// patches and write them (.obj or .glb).
    CurveMesh(curve_mesh_cmd::CurveMeshArgs),
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
        Some(Command::CurveMesh(args)) => curve_mesh_cmd::run(args),
        None => match cli.view.as_str() {
            "shaded" | "zebra" | "curvature" => {
                editor::window::run(editor::window::Startup { file: cli.file.clone(), view: cli.view.clone() })
            }
            other => Err(format!("--view {other}: use shaded, zebra or curvature")),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
