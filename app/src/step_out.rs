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
    /// STEP output: the length unit the file declares for the cage's coordinates: mm, cm, m or in
    /// [default: the document's own (a `.taut` says; millimetres otherwise)].
    #[arg(long, value_parser = parse_unit)]
    pub units: Option<LengthUnit>,
}

fn parse_unit(s: &str) -> Result<LengthUnit, String> {
    s.parse()
}

/// True for the extensions written as STEP.
pub fn is_step(extension: &str) -> bool {
    matches!(extension, "step" | "stp")
}

/// What a STEP export wrote: the command line prints it, the editor shows it as its message.
#[derive(Clone, Debug)]
pub struct StepSummary {
    pub faces: usize,
    pub edges: usize,
    /// Closed shells (solids when every shell is closed) and open ones.
    pub closed_shells: usize,
    pub open_shells: usize,
    /// The largest distance from a face to the surface, and the tolerance it was fitted within,
    /// in the cage's units.
    pub max_distance: f64,
    pub tolerance: f64,
    /// The largest angle (degrees) between neighbouring faces' normals along smooth edges.
    pub max_angle_degrees: f64,
    pub units: LengthUnit,
    pub fit_seconds: f64,
    pub bytes: usize,
    /// What the fit did, a line each.
    pub notes: Vec<String>,
}

impl StepSummary {
    /// One line for the editor: faces, solids or shells, largest distance and how well the
    /// normals agree across the faces' edges.
    pub fn describe(&self) -> String {
        let shells = if self.open_shells == 0 {
            plural(self.closed_shells, "solid")
        } else {
            format!(
                "{} ({} open: reads as surfaces)",
                plural(self.closed_shells + self.open_shells, "shell"),
                self.open_shells
            )
        };
        format!(
            "{} faces, {shells}, within {:.2e} {unit} of the surface (tolerance {:.2e} {unit}), normals across smooth \
             edges within {:.4}°, fitted in {:.2} s",
            self.faces,
            self.max_distance,
            self.tolerance,
            self.max_angle_degrees,
            self.fit_seconds,
            unit = unit_name(self.units),
        )
    }
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 { format!("1 {what}") } else { format!("{n} {what}s") }
}

/// The unit as the command line's `--units` takes it.
pub fn unit_name(unit: LengthUnit) -> &'static str {
    unit.symbol()
}

/// Fits the document's surface within `tolerance` (`None`: 1e-4 of the cage's bounding-box
/// diagonal) and writes it to `output` as STEP declaring `units`, atomically: on an error
/// nothing is written. An output that cannot be written is refused before the fit.
pub fn export_step(
    doc: &Document,
    output: &Path,
    tolerance: Option<f64>,
    units: LengthUnit,
) -> Result<StepSummary, String> {
    taut_core::io::file::check_writable(output).map_err(|e| e.to_string())?;
    let started = std::time::Instant::now();
    let surface = cad::fit_document(doc, tolerance).map_err(|e| e.to_string())?;
    let fitted = started.elapsed();
    let name = output.file_stem().and_then(|s| s.to_str()).unwrap_or("taut");
    let timestamp = utc_timestamp();
    let header = cad::step::StepHeader { name, timestamp: &timestamp, author: "" };
    let text = cad::step::step_text(&surface.model, units, surface.tolerance, &header).map_err(|e| e.to_string())?;
    taut_core::io::write_atomic(output, text.as_bytes()).map_err(|e| e.to_string())?;
    let closed_shells = surface.model.shells.iter().filter(|s| s.closed).count();
    Ok(StepSummary {
        faces: surface.model.faces.len(),
        edges: surface.model.edges.len(),
        closed_shells,
        open_shells: surface.model.shells.len() - closed_shells,
        max_distance: surface.report.max_distance,
        tolerance: surface.tolerance,
        max_angle_degrees: surface.report.max_angle_degrees,
        units,
        fit_seconds: fitted.as_secs_f64(),
        bytes: text.len(),
        notes: surface.notes,
    })
}

/// Fits the document's surface and writes it to `output` as STEP (atomically; nothing is
/// written on an error), printing what was done.
pub fn write_step(doc: &Document, output: &Path, flags: &StepFlags) -> Result<(), String> {
    let summary = export_step(doc, output, flags.tolerance, flags.units.unwrap_or(doc.units))?;
    for line in &summary.notes {
        println!("{line}");
    }
    println!(
        "wrote {} (STEP AP214, {} faces, {} edges, {} closed and {} open shells, {:.1} ms to fit, {} bytes)",
        output.display(),
        summary.faces,
        summary.edges,
        summary.closed_shells,
        summary.open_shells,
        summary.fit_seconds * 1e3,
        summary.bytes
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
