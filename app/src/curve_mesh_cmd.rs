//! `taut curve-mesh`: build a cage's curve mesh on its Catmull–Clark limit surface, fill it with
//! G1 Gregory patches and write the tessellated patches (`core::gregory`).
//!
//! The output format follows the extension: `.obj` (one `g` group per patch, `s 1`, analytic
//! normals), `.glb` (one merged mesh whose triangles run patch after patch) or `.taut` (the
//! document in the curve-mesh scheme, with the input's curve-mesh edits when it is a `.taut`
//! that has them) or `.step`/`.stp` (each patch a B-spline face whose boundary is its four Bézier
//! curves, `taut_core::cad`). A `.taut` input's curve-mesh edits are applied to what is written. `--curves` writes
//! every curve's four Bézier points and every patch's 20 Gregory points as JSON; `--report`
//! prints the figures of the fit, the continuity and the closeness to the limit surface.

use crate::cli::FileFlags;
use crate::surface_cmd::{extension, load_document};
use clap::Args;
use std::path::PathBuf;
use taut_core::Document;
use taut_core::gregory::build::FitReport;
use taut_core::gregory::tessellate::{DEFAULT_SAMPLES, MAX_SAMPLES};
use taut_core::gregory::{CurveMesh, Tessellation, export, fit_edge_curves};
use taut_core::surface::SchemeKind;

#[derive(Debug, Args)]
pub struct CurveMeshArgs {
    /// Cage: .obj, .gltf, .glb or .taut.
    pub input: PathBuf,
    /// Where to write the tessellated patches (.obj or .glb), the patches as B-spline faces for
    /// CAD (.step or .stp) or the document in the curve-mesh scheme (.taut).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Samples per patch side (each patch becomes samples × samples quads).
    #[arg(long, default_value_t = DEFAULT_SAMPLES)]
    pub samples: usize,
    /// Also write every curve's Bézier points and every patch's Gregory points as JSON.
    #[arg(long, value_name = "CURVES.json")]
    pub curves: Option<PathBuf>,
    /// Print the fit, continuity and closeness figures.
    #[arg(long)]
    pub report: bool,
    #[command(flatten)]
    pub step: crate::step_out::StepFlags,
    #[command(flatten)]
    pub files: FileFlags,
}

pub fn run(args: &CurveMeshArgs) -> Result<(), String> {
    let kind = extension(&args.output);
    if kind != "obj" && kind != "glb" && kind != "taut" && !crate::step_out::is_step(&kind) {
        return Err(format!("{}: unsupported output; use .obj, .glb, .step or .taut", args.output.display()));
    }
    if !(1..=MAX_SAMPLES).contains(&args.samples) {
        return Err(format!("--samples {}: use 1 to {MAX_SAMPLES}", args.samples));
    }
    if let Some(path) = args.curves.as_ref().filter(|p| extension(p) != "json") {
        return Err(format!("--curves {}: the curves are written as JSON; use a .json file name", path.display()));
    }
    args.files.check_output(&[&args.input], &args.output)?;
    if let Some(path) = &args.curves {
        args.files.check_output(&[&args.input], path)?;
    }
    let doc = load_document(&args.input, &args.files)?;
    let cage = &doc.cage;
    let started = std::time::Instant::now();
    // The document's curve mesh: built from the cage, with the edits a .taut input carries.
    let (curves, report) = doc.curve_mesh().map_err(|e| e.to_string())?;
    let built = started.elapsed();
    println!(
        "curve mesh: {} vertices, {} curves, {} Gregory patches{}, built in {:.1} ms",
        curves.vertex_count(),
        curves.curve_count(),
        curves.patch_count(),
        if report.subdivided_first { " (the cage has faces other than quads: subdivided once first)" } else { "" },
        built.as_secs_f64() * 1e3
    );
    let mut outputs = vec![args.output.as_path()];
    outputs.extend(args.curves.as_deref());
    crate::cli::all_or_none(&outputs, || write_outputs(args, &kind, &doc, &curves))?;
    if args.report {
        print_report(&curves, &report.fit, &report.closeness, cage.bounding_diagonal());
        if report.subdivided_first {
            // The paper's §3 figures are on the cage's own edges, before the Catmull–Clark step.
            let own = fit_edge_curves(cage).map_err(|e| e.to_string())?;
            println!(
                "on the cage's own edges (the paper's §3 setting): limit point to curve {:.4}, level-2 vertex to limit point {:.4}, longest cage edge {:.4}, α ≤ 0 guards {}",
                own.report.max_limit_to_curve,
                own.report.max_chain_to_limit,
                own.report.longest_edge,
                own.report.alpha_guards.len()
            );
        }
    }
    Ok(())
}

/// The main output and, when asked, the curves file.
fn write_outputs(args: &CurveMeshArgs, kind: &str, doc: &Document, curves: &CurveMesh) -> Result<(), String> {
    if crate::step_out::is_step(kind) {
        crate::step_out::write_step(&doc.clone().with_scheme(SchemeKind::CurveMesh), &args.output, &args.step)?;
    } else if kind == "taut" {
        let out = doc.clone().with_scheme(SchemeKind::CurveMesh);
        out.save(&args.output).map_err(|e| e.to_string())?;
        println!(
            "wrote {} (the document in the curve-mesh scheme, {} edited vertices and {} edited curves)",
            args.output.display(),
            out.curve_mesh.vertices.len(),
            out.curve_mesh.curves.len()
        );
    } else {
        let tessellation = Tessellation::new(curves, args.samples).map_err(|e| e.to_string())?;
        export::export_tessellation(&tessellation, &args.output, args.files.up).map_err(|e| e.to_string())?;
        println!(
            "wrote {} ({} vertices, {} faces, {} × {} per patch)",
            args.output.display(),
            tessellation.mesh().vertex_count(),
            tessellation.mesh().face_count(),
            args.samples,
            args.samples
        );
    }
    if let Some(path) = &args.curves {
        export::export_curves_json(curves, path).map_err(|e| e.to_string())?;
        println!("wrote the curves and control points to {}", path.display());
    }
    Ok(())
}

fn print_report(
    curves: &CurveMesh,
    fit: &FitReport,
    closeness: &taut_core::gregory::closeness::LimitCloseness,
    diagonal: f64,
) {
    let share = |d: f64| {
        if diagonal > 0.0 { format!(" ({:.3} % of the diagonal)", 100.0 * d / diagonal) } else { String::new() }
    };
    let t = curves.topology();
    let curve_name = |e: Option<taut_core::EdgeId>| {
        e.map(|e| {
            let (a, b) = t.edge_vertices(e);
            format!(", curve {} between vertices {} and {}", e.0, a.0, b.0)
        })
        .unwrap_or_default()
    };
    println!(
        "largest limit-point-to-curve distance: {:.6}{}{} (at the fit's parameters: {:.6})",
        fit.max_limit_to_curve,
        share(fit.max_limit_to_curve),
        curve_name(fit.worst_curve),
        fit.max_residual
    );
    let (shared, continuity) = curves.continuity(taut_core::gregory::continuity::DEFAULT_BOUNDARY_SAMPLES);
    let worst = continuity.worst_angle_boundary.map(|i| shared[i]);
    println!(
        "largest normal angle across shared boundaries: {:.3e} rad over {} boundaries{} ({})",
        continuity.max_normal_angle,
        shared.len(),
        curve_name(worst),
        if continuity.max_normal_angle <= 1e-6 { "G1 within 1e-6 rad" } else { "EXCEEDS 1e-6 rad" }
    );
    println!(
        "largest normal-curvature jump across shared boundaries: {:.4e} per unit length (G2, which Gregory patches do not promise){}",
        continuity.max_curvature_jump,
        if continuity.degenerate_samples > 0 {
            format!("; {} samples at degenerate corners skipped", continuity.degenerate_samples)
        } else {
            String::new()
        }
    );
    println!(
        "largest distance from interior Catmull–Clark limit points (two levels down) to their patch: {:.6}{} over {} points{}",
        closeness.max_distance,
        share(closeness.max_distance),
        closeness.points,
        closeness.worst_patch.map(|f| format!(", patch {}", f.0)).unwrap_or_default()
    );
    print!("α ≤ 0 guards taken: {}", fit.alpha_guards.len());
    for g in fit.alpha_guards.iter().take(5) {
        print!("; curve {} at vertex {}: α = {:.3e}, used {:.3e}", g.curve.0, g.end.0, g.alpha, g.used);
    }
    println!();
    println!(
        "level-2 vertex to limit point: {:.6} on the edge chains ({:.6} over all), longest edge {:.4}, tangent-plane projection moved inner points by up to {:.6}{}",
        fit.max_chain_to_limit,
        fit.max_level2_to_limit,
        fit.longest_edge,
        fit.max_projection,
        if fit.fallback_normals.is_empty() {
            String::new()
        } else {
            format!("; {} vertices without a limit normal took the faces' normal", fit.fallback_normals.len())
        }
    );
}
