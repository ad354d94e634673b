//! `taut cage`: a light Loop control cage from a dense mesh (a scan or a heavy export).
//!
//! Reads any mesh Taut imports (without requiring it to be manifold: the fitter repairs scans),
//! simplifies it with QEM, fits the cage so its Loop limit surface lies on the original, prints
//! the evaluation (QEM only against fitted) as a small table and writes the cage (`.obj`,
//! `.glb` or a `.taut` document) and optionally the report as JSON. Each step shows a progress
//! bar on a terminal. Ctrl+C cancels between steps and chunks of work; files are written only
//! at the end, each atomically, so an interrupted run never leaves a half-written file.

use crate::cli::{FileFlags, note};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use taut_core::cage_fit::{CageFitParams, CageSize, DenseMesh, Evaluation, fit_cage};
use taut_core::surface::SchemeKind;
use taut_core::{Document, PolyMesh, io};

#[derive(Debug, Args)]
pub struct CageArgs {
    /// The dense mesh: .obj, .gltf, .glb, .stl or .ply.
    pub input: PathBuf,
    /// Where to write the cage: .obj, .glb or .taut.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Cage size as a fraction in (0, 1] of the input's triangles [default: 0.25].
    #[arg(long, conflicts_with = "faces")]
    pub ratio: Option<f64>,
    /// Cage size as a number of triangles.
    #[arg(long)]
    pub faces: Option<usize>,
    /// Fitting rounds: 1 is the paper's solve alone; each further round fits the limit surface to
    /// the original both ways, farthest points weighted most, keeping the volume.
    #[arg(long, default_value_t = taut_core::cage_fit::DEFAULT_ROUNDS)]
    pub rounds: u32,
    /// Also write the evaluation and step times as JSON.
    #[arg(long)]
    pub report: Option<PathBuf>,
    #[command(flatten)]
    pub files: FileFlags,
}

pub fn run(args: &CageArgs) -> Result<(), String> {
    let mut outputs = vec![args.output.as_path()];
    outputs.extend(args.report.as_deref());
    for output in outputs {
        args.files.check_output(&[&args.input], output)?;
    }
    let kind = crate::surface_cmd::extension(&args.output);
    if !matches!(kind.as_str(), "obj" | "glb" | "taut") {
        return Err(format!("{}: unsupported cage file; use .obj, .glb or .taut", args.output.display()));
    }
    if let Some(report) = &args.report
        && crate::surface_cmd::extension(report) != "json"
    {
        return Err(format!("{}: the report is JSON; give it a .json name", report.display()));
    }
    let size = match (args.ratio, args.faces) {
        (_, Some(n)) => CageSize::Faces(n),
        (Some(r), None) => CageSize::Ratio(r),
        (None, None) => CageSize::Ratio(0.25),
    };
    let params = CageFitParams::new(size, args.rounds);

    let interrupted = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupted.clone();
        // A second handler cannot be installed in one process; the command runs once.
        let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
    }
    let cancelled = || format!("cancelled (Ctrl+C); nothing was written to {}", args.output.display());

    let spinner = |message: &str| {
        let bar = ProgressBar::new_spinner().with_message(message.to_string());
        bar.enable_steady_tick(std::time::Duration::from_millis(100));
        bar
    };
    let started = Instant::now();
    let bar = spinner("import");
    let (positions, triangles, import_report) =
        io::import_triangles(&args.input, &args.files.import_options()).map_err(|e| e.to_string())?;
    let import_seconds = started.elapsed().as_secs_f64();
    bar.finish_and_clear();
    if !import_report.is_clean() {
        note(format!("{}: {import_report}", args.input.display()));
    }
    if interrupted.load(Ordering::SeqCst) {
        return Err(cancelled());
    }
    let started = Instant::now();
    let bar = spinner("prepare");
    let dense =
        DenseMesh::from_triangles(positions, &triangles).map_err(|e| format!("{}: {e}", args.input.display()))?;
    drop(triangles);
    let prepare_seconds = started.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let notes = dense.report().notes();
    if !notes.is_empty() {
        note(format!("{}: {}", args.input.display(), notes.join(", ")));
    }

    let style = ProgressStyle::with_template("{msg:>22} [{bar:40}] {percent:>3}%")
        .map(|s| s.progress_chars("=> "))
        .unwrap_or_else(|_| ProgressStyle::default_bar());
    let mut current: Option<(String, ProgressBar)> = None;
    let mut progress = |step: &str, fraction: f64| {
        if current.as_ref().is_none_or(|(name, _)| name != step) {
            if let Some((_, bar)) = current.take() {
                bar.finish_and_clear();
            }
            let bar = ProgressBar::new(1000).with_style(style.clone()).with_message(step.to_string());
            current = Some((step.to_string(), bar));
        }
        if let Some((_, bar)) = &current {
            bar.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
        }
        !interrupted.load(Ordering::SeqCst)
    };
    let fit = fit_cage(&dense, &params, &mut progress).map_err(|e| format!("{}: {e}", args.input.display()))?;
    if let Some((_, bar)) = current.take() {
        bar.finish_and_clear();
    }
    let Some(fit) = fit else {
        return Err(cancelled());
    };
    if interrupted.load(Ordering::SeqCst) {
        return Err(cancelled());
    }

    let report = &fit.report;
    print_table(report.qem.clone(), report.fitted().cloned());
    println!("{}", report.verdict);
    if report.cage_faces > report.target_faces {
        println!(
            "the cage has {} faces, not the {} asked for: the topology (closed pieces, locked borders) allows no fewer",
            report.cage_faces, report.target_faces
        );
    } else if report.cage_faces < report.target_faces {
        println!(
            "the cage has {} faces, not the {} asked for: the simplifier's last collapses (or a nearby target tried \
             for a manifold cage) landed there",
            report.cage_faces, report.target_faces
        );
    }
    let mut times = vec![format!("import {import_seconds:.2} s"), format!("prepare {prepare_seconds:.2} s")];
    times.extend(report.steps.iter().map(|s| format!("{} {:.2} s", s.step, s.seconds)));
    println!("time: {}", times.join(", "));

    let report_json = serde_json::json!({
        "input": args.input.display().to_string(),
        "output": args.output.display().to_string(),
        "import": { "seconds": import_seconds, "summary": import_report.to_string() },
        "prepare_seconds": prepare_seconds,
        "fit": report,
    });
    let mut outputs = vec![args.output.as_path()];
    outputs.extend(args.report.as_deref());
    crate::cli::all_or_none(&outputs, || write_outputs(args, &kind, &fit.cage, &report_json))
}

/// The cage and, when asked, the report.
fn write_outputs(args: &CageArgs, kind: &str, cage: &PolyMesh, report_json: &serde_json::Value) -> Result<(), String> {
    match kind {
        // The cage is made for Loop subdivision: its document opens in that scheme.
        "taut" => {
            Document::new(cage.clone()).with_scheme(SchemeKind::Loop).save(&args.output).map_err(|e| e.to_string())?
        }
        _ => io::export_mesh_with(cage, &args.output, &args.files.export_options(None)).map_err(|e| e.to_string())?,
    }
    println!(
        "wrote the cage {} ({} vertices, {} faces)",
        args.output.display(),
        cage.vertex_count(),
        cage.face_count()
    );
    if let Some(path) = &args.report {
        let text = serde_json::to_string_pretty(report_json).map_err(|e| e.to_string())?;
        io::write_atomic(path, text.as_bytes()).map_err(|e| e.to_string())?;
        println!("wrote the report {}", path.display());
    }
    Ok(())
}

/// The evaluation as a small table, QEM only against fitted.
fn print_table(qem: Evaluation, fitted: Option<Evaluation>) {
    let cell = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3e}"));
    type Row = (&'static str, fn(&Evaluation) -> Option<f64>);
    let rows: [Row; 4] = [
        ("volume change, 1 Loop step", |e| e.volume_change),
        ("Hausdorff / diagonal", |e| Some(e.hausdorff)),
        ("mean distance / diagonal", |e| Some(e.mean)),
        ("limit points, max / diagonal", |e| Some(e.limit_points_max)),
    ];
    println!("{:<30} {:>11} {:>11}", "", "QEM only", "fitted");
    for (name, get) in rows {
        println!("{name:<30} {:>11} {:>11}", cell(get(&qem)), cell(fitted.as_ref().and_then(get)));
    }
}
