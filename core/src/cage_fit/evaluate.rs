//! How good a cage is: the paper's Table 1 measure and sampled distances of its limit surface.
//!
//! - **Volume change** (the paper §3, Table 1): the volume of the cage after one Loop step, as
//!   `|V₁ − V| / V` with `V` the original's volume. Only for a closed original.
//! - **Distances**: the limit surface is sampled as the exact limit points of the cage refined
//!   `levels` times, joined by the refined triangles (a piecewise-linear surface through points
//!   of the limit surface); the original is sampled at up to [`ORIGINAL_SAMPLES`] of its
//!   vertices, taken at an even stride. The symmetric Hausdorff distance is the larger of the two
//!   one-sided maxima, the mean distance the average of the two one-sided means; both relative to
//!   the original's bounding-box diagonal.
//!
//! Weak spots: sampled, so the Hausdorff distance can miss a narrow spike between samples, and
//! the joining triangles cut slightly inside convex parts of the limit surface (by about the
//! square of the sample spacing times the curvature).

use super::Monitor;
use super::loop_step::{loop_step, refine};
use super::surface_index::SurfaceIndex;
use crate::DVec3;
use crate::mesh::PolyMesh;
use crate::subdiv::loop_limit_matrix;
use crate::{Error, Result};
use serde::Serialize;

/// Most original vertices measured against the limit surface.
pub const ORIGINAL_SAMPLES: usize = 1 << 17;
/// The limit surface is refined until it has about this many triangles (or the original's
/// count, if smaller), with at least one level and at most [`MAX_LEVELS`].
pub const SURFACE_TRIANGLES: usize = 100_000;
/// Most refinement levels for sampling the limit surface.
pub const MAX_LEVELS: u32 = 4;

/// The measures of one cage against the original (distances relative to the bounding-box
/// diagonal of the original).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Evaluation {
    /// `|ΔV| / V` after one Loop step; `None` for an open original.
    pub volume_change: Option<f64>,
    /// Sampled symmetric Hausdorff distance of the limit surface to the original.
    pub hausdorff: f64,
    /// Mean of the two one-sided mean distances.
    pub mean: f64,
    /// Largest distance of a cage vertex's limit point to the original.
    pub limit_points_max: f64,
}

/// A sampled limit surface with the distance of each of its vertices to the original.
#[derive(Clone, Debug)]
pub struct LimitSurface {
    /// Limit points of the refined cage (cage vertices first, in cage order), refined triangles.
    pub mesh: PolyMesh,
    /// Per vertex of `mesh`: distance to the original, in the original's units.
    pub distance: Vec<f64>,
}

/// Levels of refinement for sampling a cage of `faces` triangles against `original` ones.
pub fn sample_levels(faces: usize, original: usize) -> u32 {
    let want = original.clamp(1, SURFACE_TRIANGLES);
    let mut levels = 1;
    while levels < MAX_LEVELS && faces.saturating_mul(4usize.pow(levels)) < want {
        levels += 1;
    }
    levels
}

/// The sampled limit surface of a cage.
pub fn limit_mesh(cage: &PolyMesh, levels: u32) -> Result<PolyMesh> {
    let mut mesh = refine(cage, levels)?;
    let limit = loop_limit_matrix(&mesh)?.apply(mesh.positions());
    mesh.positions_mut().copy_from_slice(&limit);
    Ok(mesh)
}

/// Volume change after one Loop step, relative to `original_volume`.
pub fn volume_change(cage: &PolyMesh, original_volume: f64) -> Result<f64> {
    let once = loop_step(cage)?.mesh;
    let volume = super::input::signed_volume(once.positions(), &once.triangles());
    Ok((volume - original_volume).abs() / original_volume.abs())
}

/// Everything needed to measure cages against one original.
#[derive(Debug)]
pub struct Original<'a> {
    pub index: &'a SurfaceIndex,
    pub samples: Vec<DVec3>,
    pub volume: Option<f64>,
    pub diagonal: f64,
    pub triangles: usize,
}

impl<'a> Original<'a> {
    /// Samples the original's vertices at an even stride.
    pub fn new(index: &'a SurfaceIndex, positions: &[DVec3], triangles: usize, volume: Option<f64>) -> Self {
        let stride = positions.len().div_ceil(ORIGINAL_SAMPLES).max(1);
        let samples = positions.iter().step_by(stride).copied().collect();
        let diagonal = crate::mesh::bounding_box(positions).map_or(0.0, |(lo, hi)| (hi - lo).length());
        Original { index, samples, volume, diagonal, triangles }
    }
}

/// A cage's sampled limit surface, indexed, and its volume change: the part of a measure that
/// runs on one thread (refinement, one Loop step, the hierarchy's build), so that several cages
/// can be prepared side by side before [`measure`] runs their queries.
#[derive(Debug)]
pub struct Prepared {
    mesh: PolyMesh,
    index: SurfaceIndex,
    volume_change: Option<f64>,
    cage_vertices: usize,
}

/// Prepares a cage's measure against `original`.
pub fn prepare(cage: &PolyMesh, original: &Original<'_>) -> Result<Prepared> {
    let levels = sample_levels(cage.face_count(), original.triangles);
    let mesh = limit_mesh(cage, levels)?;
    let volume_change = match original.volume {
        Some(v) if v != 0.0 => Some(volume_change(cage, v)?),
        _ => None,
    };
    let index = SurfaceIndex::new(mesh.positions(), &mesh.triangles())?;
    Ok(Prepared { mesh, index, volume_change, cage_vertices: cage.vertex_count() })
}

/// Measures a cage; `None` when cancelled.
pub fn evaluate(
    cage: &PolyMesh,
    original: &Original<'_>,
    monitor: &mut Monitor<'_>,
) -> Result<Option<(Evaluation, LimitSurface)>> {
    measure(prepare(cage, original)?, original, monitor)
}

/// Measures a prepared cage (distances both ways); `None` when cancelled.
pub fn measure(
    prepared: Prepared,
    original: &Original<'_>,
    monitor: &mut Monitor<'_>,
) -> Result<Option<(Evaluation, LimitSurface)>> {
    let Prepared { mesh, index, volume_change, cage_vertices } = prepared;
    let positions = mesh.positions();
    // Each query's search is bounded by a neighbour's answer (the same distances, found faster).
    let split = positions.len() as f64 / (positions.len() + original.samples.len()).max(1) as f64;
    let Some(forward) = monitor
        .map_near(0.0..split, positions, |p, near: Option<&DVec3>| original.index.closest_point_near(p, near.copied()))
    else {
        return Ok(None);
    };
    let Some(backward) = monitor
        .map_near(split..1.0, &original.samples, |p, near: Option<&DVec3>| index.closest_point_near(p, near.copied()))
    else {
        return Ok(None);
    };
    let to_original: Vec<f64> = positions
        .iter()
        .zip(&forward)
        .chain(original.samples.iter().zip(&backward))
        .map(|(p, q)| (*q - *p).length())
        .collect();
    let (forward, backward) = to_original.split_at(positions.len());
    if to_original.iter().any(|d| !d.is_finite()) || forward.is_empty() || backward.is_empty() {
        return Err(Error::Solver("the distance of the limit surface to the original is not finite".into()));
    }
    let scale = if original.diagonal > 0.0 { 1.0 / original.diagonal } else { 1.0 };
    let max = |d: &[f64]| d.iter().copied().fold(0.0, f64::max);
    let mean = |d: &[f64]| d.iter().sum::<f64>() / d.len() as f64;
    let evaluation = Evaluation {
        volume_change,
        hausdorff: max(forward).max(max(backward)) * scale,
        mean: 0.5 * (mean(forward) + mean(backward)) * scale,
        // The refined mesh numbers the cage's vertices first, at their limit points.
        limit_points_max: max(&forward[..cage_vertices]) * scale,
    };
    let distance = forward.to_vec();
    Ok(Some((evaluation, LimitSurface { mesh, distance })))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_grow_with_the_original_and_stay_bounded() {
        assert_eq!(sample_levels(1000, 100), 1);
        assert_eq!(sample_levels(2000, 1_000_000), 3);
        assert_eq!(sample_levels(1000, 1_000_000), 4);
        assert_eq!(sample_levels(10, 1_000_000), MAX_LEVELS);
        assert_eq!(sample_levels(100_000, 1_000_000), 1);
    }

    #[test]
    fn one_loop_step_of_a_regular_octahedron_by_hand() {
        let p = vec![DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z];
        let faces = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
        let cage = PolyMesh::from_polygons(p, &faces).unwrap();
        // Old vertices at r = 1 − 4β = 1 − 31/64 = 33/64 on the axes, edge points at
        // (3/8, 3/8, 0) and permutations. Each octant holds 4 small triangles; the volume is
        // 8 × (volume of the octant's fan from the centre).
        let r = 33.0 / 64.0;
        let e = 0.375;
        let (a, b, c) = (DVec3::new(r, 0.0, 0.0), DVec3::new(0.0, r, 0.0), DVec3::new(0.0, 0.0, r));
        let (ab, bc, ca) = (DVec3::new(e, e, 0.0), DVec3::new(0.0, e, e), DVec3::new(e, 0.0, e));
        let tet = |p: DVec3, q: DVec3, s: DVec3| p.dot(q.cross(s)) / 6.0;
        let octant = tet(a, ab, ca) + tet(ab, b, bc) + tet(ca, bc, c) + tet(ab, bc, ca);
        let expected = 8.0 * octant;
        let original = 4.0 / 3.0;
        let change = volume_change(&cage, original).unwrap();
        assert!((change - (original - expected).abs() / original).abs() < 1e-14, "{change}");
    }
}
