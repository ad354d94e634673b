//! STEP output of the command line: `taut subdivide`, `taut smooth` and `taut curve-mesh` write
//! the document's surface as a B-rep of B-spline faces when the output ends in `.step` or `.stp`
//! (`taut_core::cad`).

use clap::Args;
use std::path::Path;
use taut_core::Document;
use taut_core::cad::{self, LengthUnit};

/// The flags of a STEP output.
#[derive(Debug, Args, Clone, Default)]
pub struct StepFlags {
    /// STEP output: the largest distance allowed between the B-spline faces and the surface, in
    /// the cage's units [default: 1e-4 of the cage's bounding-box diagonal].
    #[arg(long, value_name = "DISTANCE")]
    pub tolerance: Option<f64>,
    /// STEP output: the length unit the file declares for the cage's coordinates: mm, cm, m or in.
    #[arg(long, default_value = "mm", value_parser = parse_unit)]
    pub units: LengthUnit,
}

fn parse_unit(s: &str) -> Result<LengthUnit, String> {
    s.parse()
}

/// True for the extensions written as STEP.
pub fn is_step(extension: &str) -> bool {
    matches!(extension, "step" | "stp")
}

/// Fits the document's surface and writes it to `output` as STEP (atomically; nothing is
/// written on an error).
pub fn write_step(doc: &Document, output: &Path, flags: &StepFlags) -> Result<(), String> {
    let started = std::time::Instant::now();
    let surface = cad::fit_document(doc, flags.tolerance).map_err(|e| e.to_string())?;
    let fitted = started.elapsed();
    let name = output.file_stem().and_then(|s| s.to_str()).unwrap_or("taut");
    let timestamp = utc_timestamp();
    let header = cad::step::StepHeader { name, timestamp: &timestamp, author: "" };
    let text =
        cad::step::step_text(&surface.model, flags.units, surface.tolerance, &header).map_err(|e| e.to_string())?;
    taut_core::io::write_atomic(output, text.as_bytes()).map_err(|e| e.to_string())?;
    for line in &surface.notes {
        println!("{line}");
    }
    let solids = surface.model.shells.iter().filter(|s| s.closed).count();
    let open = surface.model.shells.len() - solids;
    println!(
        "wrote {} (STEP AP214, {} faces, {} edges, {solids} closed and {open} open shells, {:.1} ms to fit, {} bytes)",
        output.display(),
        surface.model.faces.len(),
        surface.model.edges.len(),
        fitted.as_secs_f64() * 1e3,
        text.len()
    );
    Ok(())
}

/// Now in UTC as ISO 8601 (`2026-12-03T10:00:00`), without a time-zone library.
fn utc_timestamp() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (days, rest) = ((secs / 86_400) as i64, secs % 86_400);
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}", rest / 3600, rest % 3600 / 60, rest % 60)
}
