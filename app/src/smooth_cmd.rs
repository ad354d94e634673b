//! `taut smooth`: refine and smooth a cage with NUSD and write the surface.
//!
//! A `.taut` input brings its own fixed flags, tensions and settings; the flags given here
//! override them. The output format follows the extension: `.obj` and `.glb` get the smoothed
//! surface of the finest level (cage vertex `i` is vertex `i` of the output), `.taut` gets the
//! cage document with the settings and tensions of this command applied, ready for the editor.

use crate::cli::{FileFlags, note};
use clap::Args;
use std::path::{Path, PathBuf};
use taut_core::nusd::Spacing;
use taut_core::nusd::surface::SurfaceSolver;
use taut_core::{Document, VertexId, io};

#[derive(Debug, Args)]
pub struct SmoothArgs {
    /// Cage to smooth: .obj, .gltf, .glb or .taut.
    pub input: PathBuf,
    /// Where to write: .obj or .glb (the surface), or .taut (the cage document).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub smoothing: SmoothingFlags,
    #[command(flatten)]
    pub files: FileFlags,
}

/// The smoothing flags shared by `smooth` and `render`.
#[derive(Debug, Args)]
pub struct SmoothingFlags {
    /// Refinement levels [default: 3, or the .taut file's].
    #[arg(long)]
    pub levels: Option<u32>,
    /// Diffusion constant λ in (0, 1) [default: 0.6, or the .taut file's].
    #[arg(long)]
    pub lambda: Option<f64>,
    /// Relative tolerance: stop when the estimated distance to convergence is below
    /// tol × bounding-box diagonal [default: 1e-3, or the .taut file's].
    #[arg(long)]
    pub tol: Option<f64>,
    /// Cap on iterations per level [default: 5000, or the .taut file's].
    #[arg(long = "max-iter")]
    pub max_iter: Option<usize>,
    /// Parametrisation of the edges: chord, uniform or centripetal [default: chord].
    #[arg(long)]
    pub spacing: Option<Spacing>,
    /// Tension τ ≥ 0 at a cage vertex, as V=TAU (0-based index); repeatable.
    #[arg(long = "tension-vertex", value_name = "V=TAU")]
    pub tension_vertex: Vec<String>,
    /// Tension τ ≥ 0 on the cage edge between two vertices, as V1-V2=TAU; repeatable.
    #[arg(long = "tension-edge", value_name = "V1-V2=TAU")]
    pub tension_edge: Vec<String>,
    /// Let a cage vertex move (the surface then approximates it); repeatable.
    #[arg(long = "unfix", value_name = "V")]
    pub unfix: Vec<u32>,
}

impl SmoothingFlags {
    /// True when any smoothing flag was given.
    pub fn any(&self) -> bool {
        self.levels.is_some()
            || self.lambda.is_some()
            || self.tol.is_some()
            || self.max_iter.is_some()
            || self.spacing.is_some()
            || !self.tension_vertex.is_empty()
            || !self.tension_edge.is_empty()
            || !self.unfix.is_empty()
    }
}

pub fn run(args: &SmoothArgs) -> Result<(), String> {
    args.files.check_output(&[&args.input], &args.output)?;
    let mut doc = load_document(&args.input, &args.files)?;
    apply_flags(&mut doc, &args.smoothing)?;
    doc.validate().map_err(|e| e.to_string())?;
    let output_kind = extension(&args.output);
    if output_kind == "taut" {
        doc.save(&args.output).map_err(|e| e.to_string())?;
        println!("wrote the cage document {}", args.output.display());
        return Ok(());
    }
    if output_kind != "obj" && output_kind != "glb" {
        return Err(format!("{}: unsupported output; use .obj, .glb or .taut", args.output.display()));
    }
    let solver = solve_reporting(&doc)?;
    let surface = solver.surface();
    io::export_mesh_with(&surface, &args.output, &args.files.export_options(None)).map_err(|e| e.to_string())?;
    println!("wrote {} ({} vertices, {} faces)", args.output.display(), surface.vertex_count(), surface.face_count());
    Ok(())
}

/// Solves a document, printing per level the iterations, final step and estimate.
pub fn solve_reporting(doc: &Document) -> Result<SurfaceSolver, String> {
    let mut solver = SurfaceSolver::new(doc).map_err(|e| e.to_string())?;
    let started = std::time::Instant::now();
    let result = solver.solve();
    for event in solver.take_events() {
        note(event);
    }
    let reports = result.map_err(|e| e.to_string())?;
    let elapsed = started.elapsed();
    for r in &reports {
        println!(
            "level {}: {} vertices, {} iterations, final step {:.3e}, estimated distance to convergence {:.3e}{}{}",
            r.level,
            r.vertices,
            r.iterations,
            r.last_step,
            r.remaining,
            if r.converged { "" } else { " (iteration cap reached, not converged)" },
            if r.lambda != doc.settings.lambda { format!(" (λ reduced to {})", r.lambda) } else { String::new() },
        );
    }
    let status = solver.status();
    println!(
        "threshold {:.3e} (tol {} × diagonal), solved in {:.1} ms",
        status.threshold,
        doc.settings.tol,
        elapsed.as_secs_f64() * 1e3
    );
    Ok(solver)
}

/// Reads a cage document from any supported file, reporting what the import repaired.
pub fn load_document(path: &Path, files: &FileFlags) -> Result<Document, String> {
    if extension(path) == "taut" {
        return Document::load(path).map_err(|e| e.to_string());
    }
    let (mesh, report) = io::import_mesh_with(path, &files.import_options()).map_err(|e| e.to_string())?;
    if !report.is_clean() {
        note(format!("{}: {report}", path.display()));
    }
    Ok(Document::new(mesh))
}

pub fn apply_flags(doc: &mut Document, args: &SmoothingFlags) -> Result<(), String> {
    let s = &mut doc.settings;
    if let Some(levels) = args.levels {
        s.levels = levels;
    }
    if let Some(lambda) = args.lambda {
        s.lambda = lambda;
    }
    if let Some(tol) = args.tol {
        s.tol = tol;
    }
    if let Some(max_iter) = args.max_iter {
        s.max_iterations = max_iter;
    }
    if let Some(spacing) = args.spacing {
        s.spacing = spacing;
    }
    for spec in &args.tension_vertex {
        let (v, tau) = parse_assignment(spec, "--tension-vertex", "V=TAU")?;
        let v = parse_index(v, spec, "--tension-vertex")?;
        doc.set_vertex_tension(v, tau).map_err(|e| format!("--tension-vertex {spec}: {e}"))?;
    }
    for spec in &args.tension_edge {
        let (edge, tau) = parse_assignment(spec, "--tension-edge", "V1-V2=TAU")?;
        let (a, b) = edge
            .split_once('-')
            .ok_or_else(|| format!("--tension-edge {spec}: expected V1-V2=TAU, for example 0-3=2.5"))?;
        let (a, b) = (parse_index(a, spec, "--tension-edge")?, parse_index(b, spec, "--tension-edge")?);
        doc.set_edge_tension(a, b, tau).map_err(|e| format!("--tension-edge {spec}: {e}"))?;
    }
    for &v in &args.unfix {
        doc.set_fixed(VertexId(v), false).map_err(|e| format!("--unfix {v}: {e}"))?;
    }
    Ok(())
}

fn parse_assignment<'a>(spec: &'a str, flag: &str, shape: &str) -> Result<(&'a str, f64), String> {
    let (target, tau) = spec.split_once('=').ok_or_else(|| format!("{flag} {spec}: expected {shape}"))?;
    let tau: f64 = tau.trim().parse().map_err(|_| format!("{flag} {spec}: '{tau}' is not a number"))?;
    Ok((target.trim(), tau))
}

fn parse_index(text: &str, spec: &str, flag: &str) -> Result<VertexId, String> {
    text.trim()
        .parse::<u32>()
        .map(VertexId)
        .map_err(|_| format!("{flag} {spec}: '{text}' is not a vertex index (0-based)"))
}

pub fn extension(path: &Path) -> String {
    path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase()
}
