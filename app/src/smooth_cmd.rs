//! `taut smooth`: make a cage's surface and write it — NUSD smoothing unless the document or
//! `--scheme` says otherwise.
//!
//! A `.taut` input brings its own scheme, fixed flags, tensions, creases and settings; the flags
//! given here override them. The output format follows the extension: `.obj` and `.glb` get the
//! surface of the finest level (cage vertex `i` is vertex `i` of the output), `.taut` gets the
//! cage document with the flags applied, ready for the editor.

use crate::cli::FileFlags;
use crate::surface_cmd::{SurfaceFlags, load_document, solve_reporting, write_output};
use clap::Args;
use std::path::PathBuf;
use taut_core::surface::SchemeKind;

#[derive(Debug, Args)]
pub struct SmoothArgs {
    /// Cage to smooth: .obj, .gltf, .glb, .stl, .ply or .taut.
    pub input: PathBuf,
    /// Where to write: .obj or .glb (the surface), .step or .stp (the surface as B-spline faces
    /// for CAD), or .taut (the cage document).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The surface scheme: nusd, catmull-clark, loop or curve-mesh [default: nusd, or the .taut file's].
    #[arg(long)]
    pub scheme: Option<SchemeKind>,
    #[command(flatten)]
    pub smoothing: SurfaceFlags,
    #[command(flatten)]
    pub step: crate::step_out::StepFlags,
    #[command(flatten)]
    pub files: FileFlags,
}

pub fn run(args: &SmoothArgs) -> Result<(), String> {
    args.files.check_output(&[&args.input], &args.output)?;
    let mut doc = load_document(&args.input, &args.files)?;
    args.smoothing.apply(&mut doc, args.scheme)?;
    doc.validate().map_err(|e| e.to_string())?;
    write_output(&doc, &args.output, &args.files, &args.step, || solve_reporting(&doc, true))
}
