//! `taut subdivide`: Catmull–Clark or Loop subdivision of a cage, with creases.
//!
//! Without `--limit` the output is the refined mesh of the last level (the vertices Blender's
//! subdivision modifier gives); with it, every vertex moves to its exact limit position and the
//! file carries the exact limit normals. Cage vertex `i` is vertex `i` of the output. A `.taut`
//! input brings its scheme, levels and creases; the flags override them. Loop needs a cage of
//! triangles: `--triangulate` splits every other face first (by its shortest diagonals).

use crate::cli::{FileFlags, note};
use crate::surface_cmd::{SurfaceFlags, load_document, solve_reporting, write_output};
use clap::Args;
use std::path::PathBuf;
use taut_core::surface::SchemeKind;

#[derive(Debug, Args)]
pub struct SubdivideArgs {
    /// Cage to subdivide: .obj, .gltf, .glb, .stl, .ply or .taut.
    pub input: PathBuf,
    /// Where to write: .obj or .glb (the surface), .step or .stp (the surface as B-spline faces
    /// for CAD), or .taut (the cage document).
    #[arg(short, long)]
    pub output: PathBuf,
    /// catmull-clark or loop [default: the .taut file's, else catmull-clark].
    #[arg(long)]
    pub scheme: Option<SchemeKind>,
    /// Move the vertices to their limit positions and write the limit normals.
    #[arg(long)]
    pub limit: bool,
    /// Split every face that is not a triangle first (Loop needs triangles).
    #[arg(long)]
    pub triangulate: bool,
    #[command(flatten)]
    pub surface: SurfaceFlags,
    #[command(flatten)]
    pub step: crate::step_out::StepFlags,
    #[command(flatten)]
    pub files: FileFlags,
}

pub fn run(args: &SubdivideArgs) -> Result<(), String> {
    args.files.check_output(&[&args.input], &args.output)?;
    let mut doc = load_document(&args.input, &args.files)?;
    let scheme = match args.scheme {
        Some(SchemeKind::Nusd) => {
            return Err(
                "--scheme nusd: subdivide makes catmull-clark or loop surfaces; use taut smooth for NUSD".into()
            );
        }
        Some(SchemeKind::CurveMesh) => {
            return Err(
                "--scheme curve-mesh: subdivide makes catmull-clark or loop surfaces; use taut curve-mesh or taut smooth for the curve mesh".into()
            );
        }
        Some(s) => s,
        None if doc.scheme.is_subdivision() => doc.scheme,
        None => SchemeKind::CatmullClark,
    };
    if args.triangulate {
        let edited =
            taut_core::mesh::edit::triangulate(&doc.cage, None, taut_core::mesh::edit::Triangulation::ShortestDiagonal)
                .map_err(|e| format!("--triangulate: {e}"))?;
        let before = doc.cage.face_count();
        doc = doc.with_edited_cage(edited).map_err(|e| format!("--triangulate: {e}"))?;
        note(format!("triangulated {before} faces into {}", doc.cage.face_count()));
    }
    args.surface.apply(&mut doc, Some(scheme))?;
    doc.validate().map_err(|e| e.to_string())?;
    write_output(&doc, &args.output, &args.files, &args.step, || solve_reporting(&doc, args.limit))
}
