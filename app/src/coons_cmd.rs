//! `taut coons`: a bilinearly blended Coons patch from four boundary curves (see
//! `taut_core::aesthetic::coons`), written as a mesh of quads or as a `.taut` cage.
//!
//! `CURVES.json` is `{"curves": [C0, C1, C2, C3]}`, the four sides as a loop (C0 from corner P00
//! to P10, then P10 → P11, P11 → P01, P01 → P00; each may run either way). A side is either a
//! polyline, `{"points": [[x, y, z], ...]}`, or a log-aesthetic segment,
//! `{"p0": [x, y, z], "p1": [...], "p2": [...], "alpha": A}`; 2D points get z = 0.

use clap::Args;
use serde::Deserialize;
use std::path::PathBuf;
use taut_core::aesthetic::{AestheticSegment, BoundaryCurve, coons_patch, grid_mesh};
use taut_core::{DVec3, Document, io};

#[derive(Debug, Args)]
pub struct CoonsArgs {
    /// The four boundary curves (JSON).
    pub curves: PathBuf,
    /// Where to write: .obj or .glb (the patch as quads), or .taut (the patch as a cage of quads).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Quads along each side (1 to 1024).
    #[arg(long, default_value_t = 32)]
    pub samples: usize,
    /// Write the output even when it is the input file.
    #[arg(long)]
    pub force: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CurvesFile {
    curves: Vec<CurveSpec>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PolylineSpec {
    points: Vec<Vec<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SegmentSpec {
    p0: Vec<f64>,
    p1: Vec<f64>,
    p2: Vec<f64>,
    alpha: f64,
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum CurveSpec {
    Points(PolylineSpec),
    Aesthetic(SegmentSpec),
}

fn point(v: &[f64], what: &str) -> Result<DVec3, String> {
    match v.len() {
        2 | 3 => Ok(DVec3::new(v[0], v[1], v.get(2).copied().unwrap_or(0.0))),
        n => Err(format!("{what} has {n} coordinates; use 2 or 3")),
    }
}

fn boundary(spec: &CurveSpec, k: usize) -> Result<BoundaryCurve, String> {
    match spec {
        CurveSpec::Points(PolylineSpec { points }) => {
            let p: Result<Vec<DVec3>, String> =
                points.iter().enumerate().map(|(i, v)| point(v, &format!("curve {k}, point {i}"))).collect();
            Ok(BoundaryCurve::Polyline(p?))
        }
        CurveSpec::Aesthetic(SegmentSpec { p0, p1, p2, alpha }) => {
            let (a, b, c) = (point(p0, "p0")?, point(p1, "p1")?, point(p2, "p2")?);
            match AestheticSegment::from_control_points(a, b, c, *alpha) {
                Ok(Some(segment)) => Ok(BoundaryCurve::Aesthetic(segment)),
                Ok(None) => Err(format!(
                    "curve {k}: no log-aesthetic segment with α = {alpha} has these control points; move p1 or \
                     choose α between 0 and 1"
                )),
                Err(e) => Err(format!("curve {k}: {e}")),
            }
        }
    }
}

pub fn run(args: &CoonsArgs) -> Result<(), String> {
    crate::cli::check_output(args.force, &[&args.curves], &args.output)?;
    let input = args.curves.display();
    let kind = crate::surface_cmd::extension(&args.output);
    if !matches!(kind.as_str(), "obj" | "glb" | "taut") {
        return Err(format!("{}: unsupported output; use .obj, .glb or .taut", args.output.display()));
    }
    let text = taut_core::io::file::read_regular_text(&args.curves).map_err(|e| e.to_string())?;
    let file: CurvesFile = serde_json::from_str(&text).map_err(|e| {
        format!(
            "{input}: not a valid curves file ({{\"curves\": [four curves, each {{\"points\": [...]}} or \
             {{\"p0\", \"p1\", \"p2\", \"alpha\"}}]}}): {e}"
        )
    })?;
    if file.curves.len() != 4 {
        return Err(format!(
            "{input}: a Coons patch needs exactly 4 boundary curves, the file has {}",
            file.curves.len()
        ));
    }
    let curves: Vec<BoundaryCurve> = file
        .curves
        .iter()
        .enumerate()
        .map(|(k, c)| boundary(c, k))
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{input}: {e}"))?;
    let curves: [BoundaryCurve; 4] = curves.try_into().expect("four curves");
    let grid = coons_patch(&curves, args.samples).map_err(|e| format!("{input}: {e}"))?;
    let mesh = grid_mesh(&grid).map_err(|e| format!("{input}: {e}"))?;
    if kind == "taut" {
        Document::new(mesh.clone()).save(&args.output).map_err(|e| e.to_string())?;
    } else {
        io::export_mesh(&mesh, &args.output).map_err(|e| e.to_string())?;
    }
    println!(
        "Coons patch: {} × {} quads ({} vertices); wrote {}",
        args.samples,
        args.samples,
        mesh.vertex_count(),
        args.output.display()
    );
    Ok(())
}
