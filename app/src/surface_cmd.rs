//! What `smooth`, `subdivide` and `render` share: reading a cage document from any file, the
//! flags that change it (as core [`Edit`]s, through the one validator the editor uses too),
//! making its surface through the scheme-neutral seam and reporting how that went.

use crate::cli::{FileFlags, note};
use clap::Args;
use std::path::Path;
use taut_core::nusd::Spacing;
use taut_core::surface::{self, SchemeKind, SurfaceScheme};
use taut_core::{Document, EdgeId, Edit, VertexId, io};

/// The flags that set a document's scheme and its controls.
#[derive(Debug, Args, Default)]
pub struct SurfaceFlags {
    /// Refinement levels [default: 3, or the .taut file's].
    #[arg(long)]
    pub levels: Option<u32>,
    /// NUSD: diffusion constant λ in (0, 1) [default: 0.6, or the .taut file's].
    #[arg(long)]
    pub lambda: Option<f64>,
    /// NUSD: relative tolerance: stop when the estimated distance to convergence is below
    /// tol × bounding-box diagonal [default: 1e-3, or the .taut file's].
    #[arg(long)]
    pub tol: Option<f64>,
    /// NUSD: cap on iterations per level [default: 5000, or the .taut file's].
    #[arg(long = "max-iter")]
    pub max_iter: Option<usize>,
    /// NUSD: parametrisation of the edges: chord, uniform or centripetal [default: chord].
    #[arg(long)]
    pub spacing: Option<Spacing>,
    /// NUSD: tension τ ≥ 0 at a cage vertex, as V=TAU (0-based index); repeatable.
    #[arg(long = "tension-vertex", value_name = "V=TAU")]
    pub tension_vertex: Vec<String>,
    /// NUSD: tension τ ≥ 0 on the cage edge between two vertices, as V1-V2=TAU; repeatable.
    #[arg(long = "tension-edge", value_name = "V1-V2=TAU")]
    pub tension_edge: Vec<String>,
    /// NUSD: let a cage vertex move (the surface then approximates it); repeatable.
    #[arg(long = "unfix", value_name = "V")]
    pub unfix: Vec<u32>,
    /// Subdivision: crease sharpness S ≥ 0 (or inf) of the cage edge between two vertices, as
    /// V1-V2=S; repeatable.
    #[arg(long = "crease", value_name = "V1-V2=S")]
    pub crease: Vec<String>,
    /// Subdivision: corner sharpness S ≥ 0 (or inf) of a cage vertex, as V=S (OpenSubdiv's
    /// corner vertices, Blender's vertex crease); repeatable.
    #[arg(long = "corner", value_name = "V=S")]
    pub corner: Vec<String>,
}

impl SurfaceFlags {
    /// True when any flag was given.
    pub fn any(&self) -> bool {
        self.levels.is_some()
            || self.lambda.is_some()
            || self.tol.is_some()
            || self.max_iter.is_some()
            || self.spacing.is_some()
            || !self.tension_vertex.is_empty()
            || !self.tension_edge.is_empty()
            || !self.unfix.is_empty()
            || !self.crease.is_empty()
            || !self.corner.is_empty()
    }

    /// Applies the flags to `doc` as edits, each checked by the core's validator; the scheme is
    /// set first, so `--levels` reaches the right settings.
    pub fn apply(&self, doc: &mut Document, scheme: Option<SchemeKind>) -> Result<(), String> {
        let edit = |doc: &mut Document, edit: Edit, flag: &str| {
            doc.apply(edit).map(|_| ()).map_err(|e| format!("{flag}: {e}"))
        };
        if let Some(scheme) = scheme {
            edit(doc, Edit::SetScheme(scheme), &format!("--scheme {}", scheme.cli_name()))?;
        }
        if let Some(levels) = self.levels {
            if doc.scheme.is_subdivision() {
                let subdiv = taut_core::surface::SubdivSettings { levels };
                edit(doc, Edit::SetSubdivSettings(subdiv), &format!("--levels {levels}"))?;
            } else {
                edit(
                    doc,
                    Edit::SetSettings(taut_core::nusd::SolverSettings { levels, ..doc.settings }),
                    &format!("--levels {levels}"),
                )?;
            }
        }
        let mut settings = doc.settings;
        if let Some(lambda) = self.lambda {
            settings.lambda = lambda;
        }
        if let Some(tol) = self.tol {
            settings.tol = tol;
        }
        if let Some(max_iter) = self.max_iter {
            settings.max_iterations = max_iter;
        }
        if let Some(spacing) = self.spacing {
            settings.spacing = spacing;
        }
        edit(doc, Edit::SetSettings(settings), "smoothing settings")?;
        for spec in &self.tension_vertex {
            let (v, tau) = parse_assignment(spec, "--tension-vertex", "V=TAU")?;
            let v = parse_index(v, spec, "--tension-vertex")?;
            check_vertex(doc, v, spec, "--tension-vertex")?;
            edit(doc, Edit::SetVertexTension(vec![v], tau), &format!("--tension-vertex {spec}"))?;
        }
        for spec in &self.tension_edge {
            let (e, tau) = parse_edge(doc, spec, "--tension-edge", "V1-V2=TAU")?;
            edit(doc, Edit::SetEdgeTension(vec![e], tau), &format!("--tension-edge {spec}"))?;
        }
        for spec in &self.crease {
            let (e, s) = parse_edge(doc, spec, "--crease", "V1-V2=S")?;
            edit(doc, Edit::SetCrease(vec![e], s), &format!("--crease {spec}"))?;
        }
        let sharpness_given = !self.crease.is_empty() || !self.corner.is_empty();
        if sharpness_given && !doc.scheme.is_subdivision() {
            note(format!(
                "--crease and --corner shape the Catmull–Clark and Loop surfaces; {} keeps them in a .taut output but \
                 does not use them",
                doc.scheme.display_name()
            ));
        }
        for spec in &self.corner {
            let (v, s) = parse_assignment(spec, "--corner", "V=S")?;
            let v = parse_index(v, spec, "--corner")?;
            check_vertex(doc, v, spec, "--corner")?;
            edit(doc, Edit::SetCorner(vec![v], s), &format!("--corner {spec}"))?;
        }
        if !self.unfix.is_empty() {
            let vertices: Vec<VertexId> = self.unfix.iter().map(|&v| VertexId(v)).collect();
            for &v in &vertices {
                check_vertex(doc, v, &v.0.to_string(), "--unfix")?;
            }
            let list: Vec<String> = self.unfix.iter().map(|v| v.to_string()).collect();
            edit(doc, Edit::SetFixed(vertices, false), &format!("--unfix {}", list.join(", ")))?;
        }
        Ok(())
    }
}

fn check_vertex(doc: &Document, v: VertexId, spec: &str, flag: &str) -> Result<(), String> {
    let n = doc.cage.vertex_count();
    if v.index() < n {
        Ok(())
    } else {
        Err(format!("{flag} {spec}: vertex {} does not exist (the cage has {n} vertices, numbered from 0)", v.0))
    }
}

fn parse_edge(doc: &Document, spec: &str, flag: &str, shape: &str) -> Result<(EdgeId, f64), String> {
    let (edge, value) = parse_assignment(spec, flag, shape)?;
    let (a, b) = edge.split_once('-').ok_or_else(|| format!("{flag} {spec}: expected {shape}, for example 0-3=2.5"))?;
    let (a, b) = (parse_index(a, spec, flag)?, parse_index(b, spec, flag)?);
    let e = doc.edge_between(a, b).map_err(|e| format!("{flag} {spec}: {e}"))?;
    Ok((e, value))
}

fn parse_assignment<'a>(spec: &'a str, flag: &str, shape: &str) -> Result<(&'a str, f64), String> {
    let (target, value) = spec.split_once('=').ok_or_else(|| format!("{flag} {spec}: expected {shape}"))?;
    let value = match value.trim() {
        "inf" | "infinity" | "sharp" => f64::INFINITY,
        v => v.parse().map_err(|_| format!("{flag} {spec}: '{value}' is not a number"))?,
    };
    Ok((target.trim(), value))
}

fn parse_index(text: &str, spec: &str, flag: &str) -> Result<VertexId, String> {
    text.trim()
        .parse::<u32>()
        .map(VertexId)
        .map_err(|_| format!("{flag} {spec}: '{text}' is not a vertex index (0-based)"))
}

/// Reads a cage document from any supported file (a mesh is a NUSD document with every vertex
/// fixed), reporting what the import repaired as a note.
pub fn load_document(path: &Path, files: &FileFlags) -> Result<Document, String> {
    let (doc, report) = Document::open(path, &files.import_options()).map_err(|e| e.to_string())?;
    if let Some(report) = report.filter(|r| !r.is_clean()) {
        note(format!("{}: {report}", path.display()));
    }
    Ok(doc)
}

/// Makes the document's surface to the end through the seam, printing what the work did (per
/// level for NUSD) and the time it took.
pub fn solve_reporting(doc: &Document, limit: bool) -> Result<Box<dyn SurfaceScheme>, String> {
    let started = std::time::Instant::now();
    let mut surface: Box<dyn SurfaceScheme> = if doc.scheme.is_subdivision() && !limit {
        Box::new(surface::subdivision::SubdivSurface::new(doc, false).map_err(|e| e.to_string())?)
    } else {
        surface::build(doc).map_err(|e| e.to_string())?
    };
    let progress = surface.advance(surface::Budget::UNLIMITED);
    for event in surface.take_events() {
        note(event);
    }
    if progress.phase == surface::Phase::Diverged {
        return Err(format!(
            "the solve diverged even with λ = {}: lower the tensions",
            taut_core::nusd::surface::MIN_LAMBDA
        ));
    }
    for line in surface.report() {
        println!("{line}");
    }
    println!("{} in {:.1} ms", doc.scheme.display_name(), started.elapsed().as_secs_f64() * 1e3);
    Ok(surface)
}

/// Writes what a surface command makes: `.obj` / `.glb` get the surface with its normals (cage
/// vertex `i` is vertex `i`), `.taut` the document.
pub fn write_output(
    doc: &Document,
    output: &Path,
    files: &FileFlags,
    step: &crate::step_out::StepFlags,
    surface: impl FnOnce() -> Result<Box<dyn SurfaceScheme>, String>,
) -> Result<(), String> {
    match extension(output).as_str() {
        "step" | "stp" => crate::step_out::write_step(doc, output, step)?,
        "taut" => {
            doc.save(output).map_err(|e| e.to_string())?;
            println!("wrote the cage document {} ({} scheme)", output.display(), doc.scheme.display_name());
        }
        "obj" | "glb" => {
            let surface = surface()?;
            let mesh = surface.mesh();
            io::export_mesh_with(mesh, output, &files.export_options(surface.normals())).map_err(|e| e.to_string())?;
            println!("wrote {} ({} vertices, {} faces)", output.display(), mesh.vertex_count(), mesh.face_count());
        }
        _ => return Err(format!("{}: unsupported output; use .obj, .glb, .step or .taut", output.display())),
    }
    Ok(())
}

/// A path's extension in lower case ("" without one).
pub fn extension(path: &Path) -> String {
    path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase()
}
