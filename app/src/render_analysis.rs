//! The options of `taut render`'s two analysis views, `--view draft` (the draft angle against a
//! pull direction) and `--view highlight` (highlight lines of parallel light tubes), checked
//! before any work and turned into the renderer's [`SurfaceMode`]. The views themselves are in
//! `taut_render::analysis`. A flag of one view given with another view is an error, so a typo in
//! `--view` never silently draws something else.

use clap::Args;
use taut_core::{DVec3, PolyMesh};
use taut_render::DisplayFrame;
use taut_render::analysis::{self, DraftClass, LightTubes, Pull};
use taut_render::passes::surface::SurfaceMode;

/// The most tubes a picture may have.
const MAX_TUBES: u32 = 500;

#[derive(Debug, Args)]
pub struct AnalysisFlags {
    /// Draft: the pull direction, X,Y,Z in the model's coordinates (Z is up), or `view` for
    /// towards the camera [default: 0,0,1].
    #[arg(long, value_name = "X,Y,Z|view", allow_hyphen_values = true)]
    pub pull: Option<String>,
    /// Draft: the least draft a face needs, degrees (0 to 89); faces with less, on either side,
    /// are drawn yellow, positive draft green and undercuts red [default: 3].
    #[arg(long = "draft-angle", value_name = "DEG", allow_hyphen_values = true)]
    pub draft_angle: Option<f64>,
    /// Highlight: the direction of the light tubes, X,Y,Z in the model's coordinates; the tubes
    /// lie in a plane above the model (in front of it for tubes within 25° of vertical), 0.75 of
    /// its largest extent from its centre [default: 1,0,0].
    #[arg(long = "tube-direction", value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub tube_direction: Option<String>,
    /// Highlight: the distance between neighbouring tubes, in model units [default: an eighth
    /// of the model's largest extent].
    #[arg(long = "tube-spacing", value_name = "DISTANCE", allow_hyphen_values = true)]
    pub tube_spacing: Option<f64>,
    /// Highlight: the number of tubes, 1 to 500, centred over the model [default: 15].
    #[arg(long = "tube-count", value_name = "N", allow_hyphen_values = true)]
    pub tube_count: Option<i64>,
}

/// A checked analysis view, still in model units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Analysis {
    Draft { pull: Pull, angle_degrees: f64 },
    Highlight { direction: DVec3, spacing: Option<f64>, count: u32 },
}

impl AnalysisFlags {
    /// Checks the flags against the view (`draft`, `highlight` or another) and returns the
    /// analysis to draw, if the view is one; every message names the flag and says what fits.
    pub fn check(&self, view: &str) -> Result<Option<Analysis>, String> {
        let draft_flags = [("--pull", self.pull.is_some()), ("--draft-angle", self.draft_angle.is_some())];
        let highlight_flags = [
            ("--tube-direction", self.tube_direction.is_some()),
            ("--tube-spacing", self.tube_spacing.is_some()),
            ("--tube-count", self.tube_count.is_some()),
        ];
        let stray = |flags: &[(&str, bool)], wanted: &str| match flags.iter().find(|(_, given)| *given) {
            Some((flag, _)) => Err(format!("{flag} goes with --view {wanted}")),
            None => Ok(()),
        };
        if view != "draft" {
            stray(&draft_flags, "draft")?;
        }
        if view != "highlight" {
            stray(&highlight_flags, "highlight")?;
        }
        match view {
            "draft" => {
                let pull = match self.pull.as_deref().map(str::trim) {
                    None => Pull::Direction(DVec3::Z),
                    Some("view") => Pull::View,
                    Some(text) => Pull::Direction(parse_direction(text, "--pull")?),
                };
                let angle_degrees = self.draft_angle.unwrap_or(analysis::DEFAULT_DRAFT_DEGREES);
                if !(0.0..=analysis::MAX_DRAFT_DEGREES).contains(&angle_degrees) {
                    return Err(format!("--draft-angle {angle_degrees}: must be 0 to 89 degrees"));
                }
                Ok(Some(Analysis::Draft { pull, angle_degrees }))
            }
            "highlight" => {
                let direction = match &self.tube_direction {
                    Some(text) => parse_direction(text, "--tube-direction")?,
                    None => analysis::DEFAULT_TUBE_DIRECTION,
                };
                if let Some(s) = self.tube_spacing
                    && !(s > 0.0 && s.is_finite())
                {
                    return Err(format!("--tube-spacing {s}: must be a positive distance"));
                }
                let count = self.tube_count.unwrap_or(analysis::DEFAULT_TUBE_COUNT as i64);
                if !(1..=MAX_TUBES as i64).contains(&count) {
                    return Err(format!("--tube-count {count}: must be 1 to {MAX_TUBES}"));
                }
                Ok(Some(Analysis::Highlight { direction, spacing: self.tube_spacing, count: count as u32 }))
            }
            _ => Ok(None),
        }
    }
}

impl Analysis {
    /// The renderer's mode, with lengths converted to the picture's display coordinates.
    pub fn mode(&self, frame: &DisplayFrame) -> SurfaceMode {
        match *self {
            Analysis::Draft { pull, angle_degrees } => SurfaceMode::Draft { pull, angle_degrees: angle_degrees as f32 },
            Analysis::Highlight { direction, spacing, count } => SurfaceMode::Highlight(LightTubes {
                direction,
                spacing: spacing.map_or(analysis::DEFAULT_TUBE_SPACING, |s| frame.length(s)),
                count,
                height: analysis::TUBE_HEIGHT,
            }),
        }
    }
}

/// `X,Y,Z`: a direction of any length but zero.
fn parse_direction(text: &str, flag: &str) -> Result<DVec3, String> {
    let numbers: Vec<f64> = text
        .split(',')
        .map(|t| t.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{flag} {text}: expected three numbers X,Y,Z"))?;
    match numbers.as_slice() {
        [x, y, z] => {
            let d = DVec3::new(*x, *y, *z);
            d.try_normalize().ok_or_else(|| format!("{flag} {text}: the direction must not be zero"))?;
            Ok(d)
        }
        _ => Err(format!("{flag} {text}: expected three numbers X,Y,Z")),
    }
}

/// The shares of the surface's area in each draft class, in the order of [`DraftClass::ALL`]:
/// each triangle classed by the mean of its corners' normals (`normals`, or the mesh's
/// area-weighted ones), against the unit pull `pull`.
pub fn draft_shares(mesh: &PolyMesh, normals: Option<&[DVec3]>, pull: DVec3, threshold: f64) -> [f64; 3] {
    let computed;
    let normals = match normals {
        Some(n) => n,
        None => {
            computed = mesh.vertex_normals();
            &computed
        }
    };
    let mut areas = [0.0; 3];
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|v| v as usize);
        let (pa, pb, pc) = (mesh.positions()[a], mesh.positions()[b], mesh.positions()[c]);
        let area = 0.5 * (pb - pa).cross(pc - pa).length();
        let Some(draft) = analysis::draft_degrees(normals[a] + normals[b] + normals[c], pull) else { continue };
        let k = DraftClass::ALL.iter().position(|&c| c == DraftClass::of(draft, threshold)).unwrap_or(1);
        areas[k] += area;
    }
    let total: f64 = areas.iter().sum();
    if total > 0.0 { areas.map(|a| a / total) } else { [0.0; 3] }
}
