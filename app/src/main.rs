//! `taut`: the Taut surface editor and its command line.
//!
//! `taut [FILE]` opens the editor (on the bundled default scene when no file is given);
//! `taut SUBCOMMAND …` runs one command-line tool. `main` only parses the arguments and hands
//! them on; every failure is one line on stderr with a non-zero exit status.

mod cage_cmd;
mod cli;
mod curve_cmd;
mod editor;
mod render_cmd;
mod smooth_cmd;
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
    /// Draw a surface shaded, as zebra stripes or in curvature colour into a PNG.
    Render(render_cmd::RenderArgs),
    /// Make a light Loop control cage from a dense mesh (a scan or a heavy export).
    Cage(cage_cmd::CageArgs),
}

mod runtime {
    //! A private `XDG_RUNTIME_DIR` for sessions that have none (CI shells, `env -i`, cron): Mesa's
    //! Vulkan window-system code prints "XDG_RUNTIME_DIR is invalid or not set" twice otherwise,
    //! on stderr, which must hold only the one line of an error.

    use std::path::PathBuf;

    /// Removes the folder when the command ends.
    #[derive(Debug)]
    pub struct RuntimeDir(PathBuf);

    impl Drop for RuntimeDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// Makes and announces a private runtime folder unless the session has a usable one.
    #[allow(unsafe_code)]
    pub fn ensure_runtime_dir() -> Option<RuntimeDir> {
        if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir()) {
            return None;
        }
        let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
        let dir = std::env::temp_dir().join(format!("taut-runtime-{}-{nanos}", std::process::id()));
        let mut builder = std::fs::DirBuilder::new();
        #[cfg(unix)]
        std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
        builder.create(&dir).ok()?;
        // SAFETY: `set_var` is unsound only while another thread reads or writes the
        // environment. This runs in `main` right after the arguments are parsed, before the
        // command starts: no thread other than the main one exists yet (rayon's pool, wgpu and
        // winit are all started later by the command itself).
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
        Some(RuntimeDir(dir))
    }
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
