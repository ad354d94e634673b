//! `taut`: the Taut surface editor and its command line.
//!
//! `taut [FILE]` opens the editor (on the bundled default scene when no file is given);
//! `taut SUBCOMMAND …` runs one command-line tool. `main` only parses the arguments and hands
//! them on; every failure is one line on stderr with a non-zero exit status.

mod aesthetic_curve_cmd;
mod cage_cmd;
mod cli;
mod coons_cmd;
mod curve_cmd;
mod curve_mesh_cmd;
mod edit_cmd;
mod editor;
mod fair_cmd;
mod fair_surface_cmd;
mod lcg_cmd;
mod render_analysis;
mod render_cmd;
mod runtime;
mod smooth_cmd;
mod step_out;
mod subdivide_cmd;
mod surface_cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Taut: smooth surfaces from coarse polygon cages (NUSD smoothing with tension).
#[derive(Debug, Parser)]
#[command(name = "taut", version, args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// A cage or mesh to open in the editor (.taut, .obj, .gltf, .glb, .stl, .ply).
    file: Option<std::path::PathBuf>,
    /// How the editor first shows the surface: shaded, zebra or curvature.
    #[arg(long, default_value = "zebra")]
    view: String,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Refine and smooth a cage (OBJ, glTF, GLB, STL, PLY or .taut) and write the surface.
    Smooth(smooth_cmd::SmoothArgs),
    /// Subdivide a cage by Catmull–Clark or Loop, with creases, and write the surface.
    Subdivide(subdivide_cmd::SubdivideArgs),
    /// Smooth a polyline given as JSON, inserting points between the input points.
    SmoothCurve(curve_cmd::SmoothCurveArgs),
    /// Build a cage's curve mesh on its Catmull–Clark limit surface, fill it with G1 Gregory
    /// patches and write them (.obj, .glb or .taut).
    CurveMesh(curve_mesh_cmd::CurveMeshArgs),
    /// Draw a surface shaded, as zebra stripes or in curvature colour into a PNG.
    Render(Box<render_cmd::RenderArgs>),
    /// Make a light Loop control cage from a dense mesh (a scan or a heavy export).
    Cage(cage_cmd::CageArgs),
    /// Replay a script of modelling edits (JSON) on a cage and write the result.
    Edit(edit_cmd::EditArgs),
    /// Fair a sketched or digitised curve towards a log-aesthetic curve.
    Fair(fair_cmd::FairArgs),
    /// A log-aesthetic curve segment from three control points and α.
    AestheticCurve(aesthetic_curve_cmd::AestheticCurveArgs),
    /// A Coons patch from four boundary curves (polylines or aesthetic segments).
    Coons(coons_cmd::CoonsArgs),
    /// Drive a grid surface towards constant Gaussian curvature.
    FairSurface(fair_surface_cmd::FairSurfaceArgs),
    /// Plot a curve's curvature and its logarithmic curvature graph into a PNG.
    Lcg(lcg_cmd::LcgArgs),
}

fn main() -> ExitCode {
    taut_core::memory::keep_freed_memory();
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
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            return ExitCode::FAILURE;
        }
        Err(e) => {
            eprintln!("error: {}", cli::one_line(&e));
            return ExitCode::FAILURE;
        }
    };
    // The GPU's loader wants a runtime folder; the editor and `render` draw.
    let _runtime = match &cli.command {
        None | Some(Command::Render(_)) => runtime::ensure_runtime_dir(),
        _ => None,
    };
    let result = match &cli.command {
        Some(Command::Smooth(args)) => smooth_cmd::run(args),
        Some(Command::Subdivide(args)) => subdivide_cmd::run(args),
        Some(Command::SmoothCurve(args)) => curve_cmd::run(args),
        Some(Command::Render(args)) => render_cmd::run(args),
        Some(Command::Cage(args)) => cage_cmd::run(args),
        Some(Command::Edit(args)) => edit_cmd::run(args),
        Some(Command::Fair(args)) => fair_cmd::run(args),
        Some(Command::AestheticCurve(args)) => aesthetic_curve_cmd::run(args),
        Some(Command::Coons(args)) => coons_cmd::run(args),
        Some(Command::FairSurface(args)) => fair_surface_cmd::run(args),
        Some(Command::Lcg(args)) => lcg_cmd::run(args),
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
            eprintln!("error: {}", cli::clip_quotes(&message));
            ExitCode::FAILURE
        }
    }
}
