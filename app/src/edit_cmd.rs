//! `taut edit`: replays a script of edits (`docs/edit-scripts.md`) on a cage and writes the
//! result, so what a designer did in the editor (File ▸ Save Edit Script…) can be redone in a
//! batch, or on another cage of the same topology.
//!
//! Every step is checked as the editor checks it; the first refused step stops the replay with
//! its number and reason, and nothing is written.

use crate::cli::FileFlags;
use clap::Args;
use std::path::PathBuf;
use taut_core::document::modelling::Script;
use taut_core::io;

#[derive(Debug, Args)]
pub struct EditArgs {
    /// The cage to edit: .obj, .gltf, .glb, .stl, .ply or .taut.
    pub input: PathBuf,
    /// The edit script (JSON).
    #[arg(long)]
    pub script: PathBuf,
    /// Where to write the edited cage: .taut (the document) or .obj / .glb (the cage's polygons).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub files: FileFlags,
}

pub fn run(args: &EditArgs) -> Result<(), String> {
    args.files.check_output(&[&args.input, &args.script], &args.output)?;
    let kind = crate::surface_cmd::extension(&args.output);
    if !matches!(kind.as_str(), "taut" | "obj" | "glb") {
        return Err(format!("{}: unsupported output; use .taut, .obj or .glb", args.output.display()));
    }
    let text = std::fs::read_to_string(&args.script)
        .map_err(|e| format!("cannot read the edit script {}: {e}", args.script.display()))?;
    let script = Script::from_json(&text).map_err(|e| format!("{}: {e}", args.script.display()))?;
    let mut doc = crate::surface_cmd::load_document(&args.input, &args.files)?;
    script.replay(&mut doc).map_err(|e| format!("{}: {e}", args.script.display()))?;
    if kind == "taut" {
        doc.save(&args.output).map_err(|e| e.to_string())?;
    } else {
        io::export_mesh_with(&doc.cage, &args.output, &args.files.export_options(None)).map_err(|e| e.to_string())?;
    }
    println!(
        "replayed {} edits: {} vertices, {} faces; wrote {}",
        script.edits.len(),
        doc.cage.vertex_count(),
        doc.cage.face_count(),
        args.output.display()
    );
    Ok(())
}
