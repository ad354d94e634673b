//! What is drawn over the surface, on the CPU: cage edges and vertices, the refined wireframe,
//! curves with curvature combs, and the curvature legend (`docs/rendering.md`,
//! "Overlays"). The passes in [`crate::passes`] draw an [`OverlayData`] as it is; the builders
//! here decide how a designer's document looks.
//!
//! Colours are linear RGBA (the targets are sRGB, so the GPU encodes them); widths and radii are
//! in physical pixels, so overlays keep their size when the camera zooms.
//!
//! Cage style, chosen to read on the clay grey, the zebra stripes and the colour maps alike:
//! - fixed (interpolated) vertices are dark filled discs with a light halo, moving
//!   (approximated) vertices light rings with a dark halo;
//! - tension saturates at τ = [`TENSION_SATURATION`]: with `s = clamp(τ / 4, 0, 1)` an edge is
//!   `1.5 + 3·s` px wide and its colour goes linearly from [`EDGE_NEUTRAL`] to
//!   [`TENSION_WARM`]; a vertex mark grows by `3·s` px and gains a ring of [`TENSION_WARM`]
//!   around it whose opacity grows with `s`;
//! - selected edges and vertices take the [`SELECTED`] orange, hovered ones are lightened
//!   towards white and enlarged; both are drawn after the others so they are never covered.

use crate::colormap::ColorMap;
use crate::display::DisplayFrame;
use glam::Vec3;
use taut_core::{DVec3, EdgeId, FaceId, PolyMesh, VertexId};

/// One straight piece of line, drawn `width_px` wide with round ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSegment {
    pub a: Vec3,
    pub b: Vec3,
    /// Linear RGBA.
    pub color: [f32; 4],
    pub width_px: f32,
}

/// How a [`PointMark`] is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointStyle {
    /// A disc.
    Filled,
    /// A circle outline, `max(1.5, 0.3·radius)` px thick; the centre stays see-through.
    Ring,
}

/// A mark at a point, always on top of the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMark {
    pub position: Vec3,
    /// Linear RGBA.
    pub color: [f32; 4],
    pub radius_px: f32,
    pub style: PointStyle,
}

/// The colour-map legend of the curvature view.
#[derive(Clone, Debug, PartialEq)]
pub struct Legend {
    pub map: ColorMap,
    /// The values at the bottom and the top of the bar.
    pub min: f64,
    pub max: f64,
    /// The quantity's name, shown above the bar.
    pub title: String,
}

/// Everything drawn over the surface in one frame. Layers draw in the order of the fields.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OverlayData {
    /// Lines tested against the surface's depth, pulled slightly towards the camera so a line
    /// lying on the surface wins: the refined wireframe, curves, curvature combs.
    pub surface_lines: Vec<LineSegment>,
    /// Lines always visible, drawn after the surface: the cage edges.
    pub on_top_lines: Vec<LineSegment>,
    /// Marks always visible: the cage vertices.
    pub points: Vec<PointMark>,
    pub legend: Option<Legend>,
}

/// Which cage elements the designer has selected or is pointing at.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CageSelection {
    pub selected_vertices: Vec<VertexId>,
    pub selected_edges: Vec<EdgeId>,
    pub hovered_vertex: Option<VertexId>,
    pub hovered_edge: Option<EdgeId>,
    /// Selected faces: their edges are drawn selected and a dot marks each centre.
    pub selected_faces: Vec<FaceId>,
    pub hovered_face: Option<FaceId>,
    /// Face select mode: a small dot at the centre of every face, the handle a click picks.
    pub face_dots: bool,
    /// The parts of the cage that the cage itself hides from the eye, drawn at
    /// [`HIDDEN_ALPHA`] under the rest (`None`: X-ray, all drawn alike).
    pub hidden: Option<Hidden>,
}

/// Flags of the cage's hidden vertices, edges and faces (true: hidden); missing entries are seen.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Hidden {
    pub vertices: Vec<bool>,
    pub edges: Vec<bool>,
    pub faces: Vec<bool>,
}

/// Opacity factor of the cage's hidden parts: faint enough to read as behind, present enough to
/// show the cage's shape.
pub const HIDDEN_ALPHA: f32 = 0.25;

/// Radius of a face's centre dot, in pixels.
pub const FACE_DOT: f32 = 3.0;
/// Tension at which edge width, vertex size and the warm colour stop growing.
pub const TENSION_SATURATION: f64 = 4.0;
/// Cage edge colour at τ = 0: a neutral grey-blue (sRGB ≈ 149, 170, 203).
pub const EDGE_NEUTRAL: [f32; 4] = [0.30, 0.40, 0.60, 1.0];
/// Colour of full tension: a warm crimson (sRGB ≈ 231, 56, 124), apart from the selection orange.
pub const TENSION_WARM: [f32; 4] = [0.80, 0.04, 0.20, 1.0];
/// Accent of selected edges and vertices: orange (sRGB ≈ 255, 156, 0).
pub const SELECTED: [f32; 4] = [1.0, 0.33, 0.0, 1.0];
/// Fill of fixed vertices: near black.
pub const FIXED_VERTEX: [f32; 4] = [0.012, 0.012, 0.016, 1.0];
/// Ring of moving vertices: a light blue-white.
pub const MOVING_VERTEX: [f32; 4] = [0.72, 0.80, 0.95, 1.0];

const EDGE_WIDTH: f32 = 1.5;
const EDGE_WIDTH_PER_TENSION: f32 = 3.0;
const VERTEX_RADIUS: f32 = 4.5;
const VERTEX_RADIUS_PER_TENSION: f32 = 3.0;
const HALO_LIGHT: [f32; 4] = [0.85, 0.87, 0.90, 0.9];
const HALO_DARK: [f32; 4] = [0.0, 0.0, 0.0, 0.6];

/// The per-element controls the cage overlay shows: NUSD's fixed flags and tensions, or the
/// subdivision schemes' crease sharpness (their cage vertices are all approximated: rings).
#[derive(Clone, Copy, Debug)]
pub enum CageControls<'a> {
    Nusd {
        fixed: &'a [bool],
        vertex_tension: &'a [f64],
        edge_tension: &'a [f64],
    },
    /// `corners`: the vertices' sharpness (OpenSubdiv's corners), one per vertex or none.
    Creases {
        sharpness: &'a [f64],
        corners: &'a [f64],
    },
}

impl<'a> CageControls<'a> {
    /// The controls of a document's scheme: creases and corners under Catmull–Clark and Loop,
    /// fixed flags and tensions otherwise.
    pub fn of(doc: &'a taut_core::Document) -> Self {
        if doc.scheme.is_subdivision() {
            CageControls::Creases { sharpness: &doc.crease, corners: &doc.corner }
        } else {
            CageControls::Nusd {
                fixed: &doc.fixed,
                vertex_tension: &doc.vertex_tension,
                edge_tension: &doc.edge_tension,
            }
        }
    }
}

/// Crease sharpness at which a crease edge stops growing wider (an infinitely sharp edge is drawn
/// as this).
pub const CREASE_SATURATION: f64 = 4.0;
/// Colour of a crease edge: a cyan apart from the tension crimson and the selection orange
/// (sRGB ≈ 0, 200, 230).
pub const CREASE: [f32; 4] = [0.0, 0.58, 0.79, 1.0];

/// Crease sharpness mapped to `[0, 1]`: 0 smooth, 1 at [`CREASE_SATURATION`] or sharp.
pub fn crease_level(s: f64) -> f32 {
    if s == f64::INFINITY {
        1.0
    } else if s.is_finite() && s > 0.0 {
        (s / CREASE_SATURATION).min(1.0) as f32
    } else {
        0.0
    }
}

/// Tension mapped to `[0, 1]`, saturating at [`TENSION_SATURATION`]; non-finite or negative
/// values read as 0.
pub fn tension_level(tau: f64) -> f32 {
    if tau.is_finite() { (tau / TENSION_SATURATION).clamp(0.0, 1.0) as f32 } else { 0.0 }
}

fn mix(a: [f32; 4], b: [f32; 4], t: f32) -> [f32; 4] {
    std::array::from_fn(|i| a[i] * (1.0 - t) + b[i] * t)
}

/// Lightened towards white, for the element under the cursor.
fn hover(c: [f32; 4]) -> [f32; 4] {
    let light = mix(c, [1.0; 4], 0.45);
    [light[0], light[1], light[2], c[3]]
}

/// Drawing priority: hidden first (under everything), plain, then selected, then hovered last
/// (on top).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Emphasis {
    Hidden,
    Plain,
    Selected,
    Hovered,
}

/// The cage's edges (on-top lines) and vertex marks, styled as the module documentation says.
/// `fixed`, `vertex_tension` and `edge_tension` are indexed by vertex and edge; missing entries
/// read as moving and τ = 0.
///
/// With [`CageControls::Creases`], an edge of sharpness `s > 0` is drawn in [`CREASE`], wider with
/// `c = crease_level(s)` (`2 + 3·c` px), and every vertex as a ring.
pub fn cage_overlay(
    cage: &PolyMesh,
    controls: CageControls<'_>,
    selection: &CageSelection,
    frame: &DisplayFrame,
) -> (Vec<LineSegment>, Vec<PointMark>) {
    let none: &[f64] = &[];
    let (fixed, vertex_tension, edge_tension, crease): (&[bool], &[f64], &[f64], &[f64]) = match controls {
        CageControls::Nusd { fixed, vertex_tension, edge_tension } => (fixed, vertex_tension, edge_tension, none),
        CageControls::Creases { sharpness, .. } => (&[], none, none, sharpness),
    };
    let corners = match controls {
        CageControls::Creases { corners, .. } => corners,
        CageControls::Nusd { .. } => none,
    };
    let mut selected_edge = vec![false; cage.edge_count()];
    for e in &selection.selected_edges {
        if let Some(flag) = selected_edge.get_mut(e.index()) {
            *flag = true;
        }
    }
    let mut selected_vertex = vec![false; cage.vertex_count()];
    for v in &selection.selected_vertices {
        if let Some(flag) = selected_vertex.get_mut(v.index()) {
            *flag = true;
        }
    }

    let hidden = selection.hidden.as_ref();
    let mut hovered_face_edge = vec![false; cage.edge_count()];
    for (faces, flags) in [
        (selection.selected_faces.as_slice(), &mut selected_edge),
        (selection.hovered_face.as_slice(), &mut hovered_face_edge),
    ] {
        for &f in faces.iter().filter(|f| f.index() < cage.face_count()) {
            for h in cage.face_halfedges(f) {
                flags[h.edge().index()] = true;
            }
        }
    }

    let mut lines: Vec<(Emphasis, LineSegment)> = cage
        .edges()
        .map(|e| {
            let (a, b) = cage.edge_vertices(e);
            let s = tension_level(edge_tension.get(e.index()).copied().unwrap_or(0.0));
            let c = crease_level(crease.get(e.index()).copied().unwrap_or(0.0));
            let mut line = LineSegment {
                a: frame.point(cage.position(a)),
                b: frame.point(cage.position(b)),
                color: mix(EDGE_NEUTRAL, TENSION_WARM, s),
                width_px: EDGE_WIDTH + EDGE_WIDTH_PER_TENSION * s,
            };
            if c > 0.0 {
                line.color = CREASE;
                line.width_px = 2.0 + 3.0 * c;
            }
            let mut emphasis = Emphasis::Plain;
            if selected_edge[e.index()] {
                emphasis = Emphasis::Selected;
                line.color = SELECTED;
                line.width_px += 1.0;
            }
            if selection.hovered_edge == Some(e) || hovered_face_edge[e.index()] {
                emphasis = Emphasis::Hovered;
                line.color = hover(line.color);
                line.width_px = line.width_px * 1.5 + 1.0;
            }
            if is_hidden(hidden.map(|h| h.edges.as_slice()), e.index()) {
                emphasis = Emphasis::Hidden;
                line.color[3] *= HIDDEN_ALPHA;
            }
            (emphasis, line)
        })
        .collect();

    let mut points: Vec<(Emphasis, PointMark)> = Vec::with_capacity(cage.vertex_count() * 3);
    for v in cage.vertices() {
        let position = frame.point(cage.position(v));
        let is_fixed = fixed.get(v.index()).copied().unwrap_or(false);
        let s = tension_level(vertex_tension.get(v.index()).copied().unwrap_or(0.0));
        let mut emphasis = Emphasis::Plain;
        let (mut color, mut style) =
            if is_fixed { (FIXED_VERTEX, PointStyle::Filled) } else { (MOVING_VERTEX, PointStyle::Ring) };
        let mut radius_px = VERTEX_RADIUS + VERTEX_RADIUS_PER_TENSION * s;
        // A sharp vertex (a corner): a filled dot in the crease colour, larger with its sharpness.
        let corner = crease_level(corners.get(v.index()).copied().unwrap_or(0.0));
        if corner > 0.0 {
            (color, style) = (CREASE, PointStyle::Filled);
            radius_px += 1.0 + 2.0 * corner;
        }
        if selected_vertex[v.index()] {
            emphasis = Emphasis::Selected;
            color = SELECTED;
        }
        if selection.hovered_vertex == Some(v) {
            emphasis = Emphasis::Hovered;
            color = hover(color);
            radius_px += 2.0;
        }
        let dim = is_hidden(hidden.map(|h| h.vertices.as_slice()), v.index());
        let emphasised = emphasis != Emphasis::Plain;
        if dim {
            emphasis = Emphasis::Hidden;
        }
        let mark = |color: [f32; 4], radius_px, style| {
            let alpha = if dim { color[3] * HIDDEN_ALPHA } else { color[3] };
            (emphasis, PointMark { position, color: [color[0], color[1], color[2], alpha], radius_px, style })
        };
        if s > 0.0 {
            let warm = [TENSION_WARM[0], TENSION_WARM[1], TENSION_WARM[2], 0.35 + 0.65 * s];
            points.push(mark(warm, radius_px + 3.0 + 2.0 * s, PointStyle::Ring));
        }
        // A halo of the opposite lightness keeps the mark readable on any background.
        let halo = if is_fixed || emphasised { HALO_LIGHT } else { HALO_DARK };
        points.push(mark(halo, radius_px + 1.5, style));
        points.push(mark(color, radius_px, style));
    }

    if selection.face_dots || !selection.selected_faces.is_empty() || selection.hovered_face.is_some() {
        let mut selected_face = vec![false; cage.face_count()];
        for f in selection.selected_faces.iter().filter(|f| f.index() < cage.face_count()) {
            selected_face[f.index()] = true;
        }
        for f in cage.faces() {
            let (selected, hovered) = (selected_face[f.index()], selection.hovered_face == Some(f));
            if !(selection.face_dots || selected || hovered) {
                continue;
            }
            let ring: Vec<_> = cage.face_vertices(f).map(|v| cage.position(v)).collect();
            let centre = ring.iter().copied().sum::<DVec3>() / ring.len().max(1) as f64;
            let (mut emphasis, color) = match (selected, hovered) {
                (_, true) => (Emphasis::Hovered, hover(if selected { SELECTED } else { EDGE_NEUTRAL })),
                (true, false) => (Emphasis::Selected, SELECTED),
                (false, false) => (Emphasis::Plain, EDGE_NEUTRAL),
            };
            let dim = is_hidden(hidden.map(|h| h.faces.as_slice()), f.index());
            if dim {
                emphasis = Emphasis::Hidden;
            }
            let alpha = |c: [f32; 4]| [c[0], c[1], c[2], if dim { c[3] * HIDDEN_ALPHA } else { c[3] }];
            let position = frame.point(centre);
            points.push((
                emphasis,
                PointMark { position, color: alpha(HALO_DARK), radius_px: FACE_DOT + 1.5, style: PointStyle::Filled },
            ));
            points.push((
                emphasis,
                PointMark { position, color: alpha(color), radius_px: FACE_DOT, style: PointStyle::Filled },
            ));
        }
    }

    // A stable sort keeps the order within each emphasis and puts highlighted ones last.
    lines.sort_by_key(|(e, _)| *e);
    points.sort_by_key(|(e, _)| *e);
    (lines.into_iter().map(|(_, l)| l).collect(), points.into_iter().map(|(_, p)| p).collect())
}

fn is_hidden(flags: Option<&[bool]>, index: usize) -> bool {
    flags.and_then(|f| f.get(index)).copied().unwrap_or(false)
}

/// Every edge of `mesh` once, as depth-tested lines (the refined wireframe).
pub fn wireframe(mesh: &PolyMesh, color: [f32; 4], width_px: f32, frame: &DisplayFrame) -> Vec<LineSegment> {
    mesh.edges()
        .map(|e| {
            let (a, b) = mesh.edge_vertices(e);
            LineSegment { a: frame.point(mesh.position(a)), b: frame.point(mesh.position(b)), color, width_px }
        })
        .collect()
}

/// How a curve and its curvature comb look.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CombStyle {
    /// Tooth length per unit curvature: a tooth is `scale · κ` long, so on a circle of radius
    /// `R` every tooth is `scale / R` (a length squared, in model units²).
    pub scale: f64,
    /// A tooth at every `density`-th point (1: every point; 0 reads as 1).
    pub density: usize,
    /// Teeth towards the centre of curvature instead of away from it. The default (`false`)
    /// draws them away from the centre, on the convex side, as Rhino's CurvatureGraph does, so
    /// the comb never crosses the inside of a bend.
    pub inward: bool,
    pub curve_color: [f32; 4],
    pub curve_width_px: f32,
    pub tooth_color: [f32; 4],
    pub tooth_width_px: f32,
    /// The envelope joining the tooth tips.
    pub envelope_color: [f32; 4],
    pub envelope_width_px: f32,
}

impl Default for CombStyle {
    fn default() -> Self {
        CombStyle {
            scale: 1.0,
            density: 1,
            inward: false,
            curve_color: [0.90, 0.90, 0.92, 1.0],
            curve_width_px: 2.0,
            tooth_color: [0.10, 0.55, 1.0, 0.75],
            tooth_width_px: 1.0,
            envelope_color: [0.05, 0.40, 1.0, 1.0],
            envelope_width_px: 1.5,
        }
    }
}

/// The tips of the comb's teeth: `(point, tip)` for every `density`-th point. Curvature comes
/// from [`taut_core::curvature::polyline_curvature`] (Menger curvature through each point and its
/// neighbours; open ends copy their neighbour's).
fn comb_teeth(points: &[DVec3], closed: bool, comb: &CombStyle) -> Vec<(DVec3, DVec3)> {
    let curvature = taut_core::curvature::polyline_curvature(points, closed);
    let sign = if comb.inward { 1.0 } else { -1.0 };
    let step = comb.density.max(1);
    let mut samples: Vec<usize> = (0..points.len()).step_by(step).collect();
    // An open curve's comb reaches its last point, so the envelope spans the whole curve.
    if !closed && points.len() > 1 && samples.last() != Some(&(points.len() - 1)) {
        samples.push(points.len() - 1);
    }
    samples.into_iter().map(|i| (points[i], points[i] + sign * comb.scale * curvature.curvature[i])).collect()
}

/// A curve and its curvature comb (porcupine): the polyline itself, a tooth along the
/// curvature direction at every `density`-th point, `scale · κ` long, and the envelope joining
/// the tooth tips. All lines are depth-tested (put them in [`OverlayData::surface_lines`]).
pub fn polyline_with_comb(points: &[DVec3], closed: bool, comb: &CombStyle, frame: &DisplayFrame) -> Vec<LineSegment> {
    let line =
        |a: DVec3, b: DVec3, color, width_px| LineSegment { a: frame.point(a), b: frame.point(b), color, width_px };
    let n = points.len();
    let links = if closed && n > 2 { n } else { n.saturating_sub(1) };
    let mut out: Vec<LineSegment> =
        (0..links).map(|i| line(points[i], points[(i + 1) % n], comb.curve_color, comb.curve_width_px)).collect();
    if comb.scale == 0.0 || !comb.scale.is_finite() || n < 3 {
        return out;
    }
    let teeth = comb_teeth(points, closed, comb);
    out.extend(teeth.iter().map(|&(p, tip)| line(p, tip, comb.tooth_color, comb.tooth_width_px)));
    let tips: Vec<DVec3> = teeth.iter().map(|t| t.1).collect();
    let envelope_links = if closed { tips.len() } else { tips.len().saturating_sub(1) };
    out.extend(
        (0..envelope_links)
            .map(|i| line(tips[i], tips[(i + 1) % tips.len()], comb.envelope_color, comb.envelope_width_px)),
    );
    out
}

/// A legend number with `significant` digits, as short as reads well: plain decimals for
/// magnitudes from 0.001 to below 10 000 (`0.0123`, `12.3`, `1500`), otherwise scientific
/// (`-4.5e-5`, `1.23e5`); trailing zeros dropped; exactly `0` for zero.
pub fn format_number(x: f64, significant: usize) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "nan".into()
        } else if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    let digits = significant.max(1);
    // Rounding to the significant digits first tells the exponent after rounding (9.996 → 1.00e1).
    let scientific = format!("{:.*e}", digits - 1, x);
    let (mantissa, exponent) = scientific.split_once('e').unwrap_or((&scientific, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let trim = |s: &str| -> String {
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s.to_string() }
    };
    if (-3..4).contains(&exponent) {
        let rounded: f64 = scientific.parse().unwrap_or(x);
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        trim(&format!("{rounded:.decimals$}"))
    } else {
        format!("{}e{exponent}", trim(mantissa))
    }
}

/// The short title a legend shows for what the colours mean (the panel stays narrow).
pub fn legend_title(by: taut_core::surface::ColourBy) -> &'static str {
    use taut_core::curvature::CurvatureQuantity as Q;
    use taut_core::surface::ColourBy;
    match by {
        ColourBy::Curvature(Q::Mean) => "mean H",
        ColourBy::Curvature(Q::Gaussian) => "Gauss K",
        ColourBy::Curvature(Q::MinPrincipal) => "kmin",
        ColourBy::Curvature(Q::MaxPrincipal) => "kmax",
        ColourBy::Curvature(Q::MaxAbsolute) => "|k|max",
        ColourBy::Field(f) => f.title,
        ColourBy::Distance => "distance",
    }
}

#[cfg(test)]
#[path = "overlay_tests.rs"]
mod tests;
