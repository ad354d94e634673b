//! The surface for CAD: a boundary representation of bicubic B-spline faces, written as STEP.
//!
//! Every scheme's surface is read as a network of four-sided patches sampled on grids
//! ([`network`]), the network is fitted with B-spline faces that share their edges and keep the
//! surface's tangent continuity within a tolerance ([`fit`]), and the faces, edges, vertices and
//! shells ([`brep`]) are written as an AP214 file ([`step`]). What each scheme gives and where we
//! chose: `docs/cad-export.md`.
//! - Catmull–Clark: the exact limit surface (limit points of a fine level); a regular face comes
//!   out as its exact bicubic patch, and grids of them are merged into larger faces ([`merge`]);
//!   the faces at extraordinary vertices as fitted patches with interior knots; sharp creases are
//!   edges without tangent continuity.
//! - NUSD: the solved finest level, fitted per cage face (per quad of the first split of every
//!   face at its centre when the cage has other polygons; triangles are read by interpolation,
//!   `nusd_patches.rs`).
//! - Curve mesh: the Gregory patches, each fitted by a B-spline face whose boundary is its four
//!   Bézier curves (a B-spline of one span each, exactly).
//!
//! Loop surfaces are refused (they are made of triangles; convert the cage or use Catmull–Clark).

mod assemble;
pub mod brep;
pub mod bspline;
pub mod fit;
pub mod merge;
pub mod network;
mod nusd_patches;
pub mod step;

use crate::document::Document;
use crate::subdiv::{RefinedPositions, Refinement, Scheme};
use crate::surface::SchemeKind;
use crate::{Error, Result};
pub use brep::{BrepModel, LengthUnit};
pub use fit::FitReport;
use network::PatchNetwork;
use nusd_patches::nusd_network;

/// The default tolerance, a fraction of the surface's bounding-box diagonal.
pub const DEFAULT_RELATIVE_TOLERANCE: f64 = 1e-4;

/// Samples per patch side are raised up to this (Catmull–Clark levels, curve-mesh samples)
/// while a face cannot reach the tolerance.
const MAX_SAMPLES: usize = 128;

/// A document's surface fitted for CAD.
#[derive(Clone, Debug)]
pub struct CadSurface {
    pub model: BrepModel,
    pub report: FitReport,
    /// The distance the faces were fitted within.
    pub tolerance: f64,
    /// Samples per patch side the fit read.
    pub samples: usize,
    /// What was done, a line each (the command line prints them).
    pub notes: Vec<String>,
    /// Per patch of the network (as [`surface_samples`] numbers them): the face of `model` it
    /// lies on and where (regular regions are merged into larger faces).
    pub placements: Vec<merge::Placement>,
}

/// The document's surface as B-spline faces within `tolerance` (a distance; `None` for
/// [`DEFAULT_RELATIVE_TOLERANCE`] of the cage's bounding-box diagonal).
pub fn fit_document(doc: &Document, tolerance: Option<f64>) -> Result<CadSurface> {
    doc.validate()?;
    if doc.cage.face_count() == 0 {
        return Err(Error::Input("the cage has no faces: there is no surface to export".into()));
    }
    let tolerance = match tolerance {
        Some(t) if t.is_finite() && t > 0.0 => t,
        Some(t) => return Err(Error::Input(format!("--tolerance must be a positive distance, not {t}"))),
        None => DEFAULT_RELATIVE_TOLERANCE * doc.cage.bounding_diagonal(),
    };
    if tolerance.is_nan() || tolerance <= 0.0 {
        return Err(Error::Input("the cage has no extent: there is no surface to export".into()));
    }
    let all_quads = doc.cage.faces().all(|f| doc.cage.face_valence(f) == 4);
    let base = if all_quads { 0 } else { 1 };
    match doc.scheme {
        SchemeKind::Loop => Err(Error::Input(
            "STEP export of a Loop surface is not offered: its patches are triangles, which B-spline faces do not \
             take; use Catmull–Clark, NUSD or the curve mesh"
                .into(),
        )),
        SchemeKind::CatmullClark => {
            let corners: usize = doc.cage.faces().map(|f| doc.cage.face_valence(f)).sum();
            // Faces of the refinement that samples `m` per side.
            let refined = |m: usize| if all_quads { doc.cage.face_count() * m * m } else { corners * m * m };
            let mut samples: usize = 16;
            loop {
                let levels = base + samples.trailing_zeros();
                let net = catmull_clark_network(doc, base, levels)?;
                let (model, mut report) = fit::fit(&net, tolerance)?;
                // Checked again between the samples, on the next level's limit points.
                let finer = samples * 2;
                let affordable = finer <= MAX_SAMPLES && refined(finer) <= crate::subdiv::MAX_REFINED_FACES;
                if report.within && affordable {
                    let between = fit::distance_to(&model, &catmull_clark_network(doc, base, levels + 1)?);
                    report.max_distance = report.max_distance.max(between);
                    report.within = between <= tolerance;
                }
                if report.within || !affordable || finer * 2 > MAX_SAMPLES {
                    let notes = vec![format!(
                        "Catmull–Clark limit surface sampled at level {levels}, checked at level {}",
                        levels + 1
                    )];
                    return finish(&net, model, report, tolerance, samples, notes);
                }
                samples = finer;
            }
        }
        SchemeKind::Nusd => {
            // From the document's levels (at least four below the patches) one level finer at a
            // time while the fit is not within the tolerance and a finer level is affordable: a
            // surface with tight bends needs more samples and spans than a smooth one.
            let corners: usize = doc.cage.faces().map(|f| doc.cage.face_valence(f)).sum();
            let mut levels = doc.settings.levels.max(base + 4).min(crate::nusd::MAX_LEVELS);
            loop {
                let (mut net, solved) = nusd_network(doc, base, levels)?;
                let samples = net.m;
                // NUSD is not a polynomial at its boundary corners either: rings there too.
                let layout = &net.layout;
                let depth = solved - base;
                net.grade = extraordinary_grading(layout, depth)
                    .into_iter()
                    .zip(layout.vertices())
                    .map(|(g, v)| if layout.is_boundary_vertex(v) && layout.valence(v) == 2 { depth } else { g })
                    .collect();
                let (model, report) = fit::fit(&net, tolerance)?;
                let finer = 2 * samples;
                let affordable = levels < crate::nusd::MAX_LEVELS
                    && finer <= MAX_SAMPLES
                    && corners * finer * finer <= crate::subdiv::MAX_REFINED_FACES;
                if report.within || !affordable {
                    let notes = vec![format!(
                        "NUSD solved to level {solved}, fitted per cage face (per quad of its first split on a cage of \
                         other polygons)"
                    )];
                    return finish(&net, model, report, tolerance, samples, notes);
                }
                levels += 1;
            }
        }
        SchemeKind::CurveMesh => {
            let (curves, _) = doc.curve_mesh()?;
            let mut samples: usize = 16;
            loop {
                let net = PatchNetwork::from_curve_mesh(&curves, samples)?;
                let (model, report) = fit::fit(&net, tolerance)?;
                if report.within || samples * 2 > MAX_SAMPLES {
                    let notes = vec![format!("curve mesh sampled {samples} times per patch side")];
                    return finish(&net, model, report, tolerance, samples, notes);
                }
                samples *= 2;
            }
        }
    }
}

/// The Catmull–Clark limit surface sampled at `levels`, patches on level `base` (0 or 1).
fn catmull_clark_network(doc: &Document, base: u32, levels: u32) -> Result<PatchNetwork> {
    let refinement = Refinement::with_corners(&doc.cage, Scheme::CatmullClark, &doc.crease, &doc.corner, levels)?;
    let mut positions = RefinedPositions::default();
    refinement.evaluate(doc.cage.positions(), &mut positions)?;
    let fine = refinement.surface(&positions.limit);
    let layout_mesh = refinement.mesh(base);
    let mut layout = layout_mesh.clone();
    // The layout's corners on the limit surface.
    let count = layout.vertex_count();
    layout.positions_mut().copy_from_slice(&positions.limit[..count]);
    // An edge still sharp at the sampled level looks sharp to the fit: a crease, not a fillet.
    let remaining = f64::from(levels - base);
    let sharp = refinement.sharpness(base).iter().map(|&s| s >= remaining).collect();
    let corner = refinement.corners(base).iter().map(|&s| s >= remaining).collect();
    let m = 1usize << (levels - base);
    let mut net = PatchNetwork::from_refined(layout, &fine, Some(&positions.normals), m, sharp, corner)?;
    net.grade = extraordinary_grading(&net.layout, levels - base);
    Ok(net)
}

/// Rings of knots towards every extraordinary vertex, down to the sample spacing `2^-depth`.
fn extraordinary_grading(layout: &crate::mesh::PolyMesh, depth: u32) -> Vec<u32> {
    layout
        .vertices()
        .map(|v| {
            let regular = if layout.is_boundary_vertex(v) { layout.valence(v) <= 3 } else { layout.valence(v) == 4 };
            if regular { 0 } else { depth }
        })
        .collect()
}

fn finish(
    net: &PatchNetwork,
    model: BrepModel,
    report: FitReport,
    tolerance: f64,
    samples: usize,
    mut notes: Vec<String>,
) -> Result<CadSurface> {
    let most = report.spans.iter().copied().max().unwrap_or(1);
    let exact = report.spans.iter().filter(|&&s| s == 1).count();
    notes.push(format!(
        "{} patches ({} of one span, up to {most}×{most} spans), within {:.3e} of the surface (tolerance {:.3e}), \
         normals across smooth edges within {:.4}° (the sampled surface's own: up to {:.4}°)",
        report.spans.len(),
        exact,
        report.max_distance,
        tolerance,
        report.max_angle_degrees,
        report.max_surface_gap_degrees,
    ));
    if report.max_star_angle_degrees > 0.0 {
        notes.push(format!(
            "within the last two rings of knots around extraordinary vertices the normals differ by up to {:.3}°",
            report.max_star_angle_degrees
        ));
    }
    if !report.within {
        return Err(Error::Input(format!(
            "the surface could not be fitted within the tolerance {tolerance:.3e}: the closest fit is {:.3e} away and \
             its normals differ by up to {:.3}° more than the surface's own (raise --tolerance)",
            report.max_distance, report.max_excess_degrees
        )));
    }
    let patches = model.faces.len();
    let (model, placements) = merge::merge_regular(model, &net.layout, &net.sharp);
    if model.faces.len() < patches {
        let mut per_face = vec![0usize; model.faces.len()];
        for p in &placements {
            per_face[p.face] += 1;
        }
        let merged: usize = per_face.iter().filter(|&&n| n > 1).sum();
        notes.push(format!(
            "{merged} patches of regular regions merged into {} larger faces: {} faces in all",
            model.faces.len() + merged - patches,
            model.faces.len()
        ));
    }
    Ok(CadSurface { model, report, tolerance, samples, notes, placements })
}

/// The document's surface sampled exactly on every patch of the layout the export fits,
/// `per_side` samples per side (a power of two for Catmull–Clark and NUSD, whose finest level
/// is then the one that has them): what a test compares an exported file with, patch `f` lying
/// on STEP face `placements[f].face` at `placements[f].map(u, v)` (see [`CadSurface::placements`]).
pub fn surface_samples(doc: &Document, per_side: usize) -> Result<PatchNetwork> {
    let all_quads = doc.cage.faces().all(|f| doc.cage.face_valence(f) == 4);
    let base = if all_quads { 0 } else { 1 };
    match doc.scheme {
        SchemeKind::CatmullClark if per_side.is_power_of_two() => {
            catmull_clark_network(doc, base, base + per_side.trailing_zeros())
        }
        SchemeKind::CurveMesh => PatchNetwork::from_curve_mesh(&doc.curve_mesh()?.0, per_side),
        SchemeKind::Nusd if per_side.is_power_of_two() => {
            Ok(nusd_network(doc, base, base + per_side.trailing_zeros())?.0)
        }
        _ => Err(Error::Input(format!("no STEP samples for {} with {per_side} per side", doc.scheme.display_name()))),
    }
}
