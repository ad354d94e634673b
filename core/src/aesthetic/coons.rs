//! Bilinearly blended Coons patches from four boundary curves (paper sec. 5.2, fig. 4; Farin,
//! "Curves and Surfaces for CAGD", ch. 22).
//!
//! With the boundary `b(u)` (v = 0), `r(v)` (u = 1), `t(u)` (v = 1), `l(v)` (u = 0) and corners
//! `P00, P10, P01, P11`, the patch is the sum of the two ruled surfaces between opposite sides
//! minus the bilinear surface of the corners:
//! `S(u, v) = (1−v) b(u) + v t(u) + (1−u) l(v) + u r(v) − [(1−u)(1−v) P00 + u(1−v) P10 + (1−u) v P01 + u v P11]`.
//! It interpolates all four curves. Four straight sides give the bilinear patch; two straight
//! sides give the ruled surface between the other two (a cylinder, K = 0, when those two are
//! translates of each other, as in the paper's figure).
//!
//! Each side is parametrised by its normalised arc length: an aesthetic segment exactly, a
//! polyline piecewise linearly between its points, so a polyline side gives a patch with creases
//! along its points' parameter lines (sample it densely). The curves are given as a loop, each
//! one starting where the previous ends; either direction is accepted and they are turned round
//! to fit. Where they do not meet the patch is refused.

use super::segment::AestheticSegment;
use super::surface::Grid;
use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};

/// One side of a Coons patch.
#[derive(Clone, Debug, PartialEq)]
pub enum BoundaryCurve {
    /// A polyline through the points, parametrised by arc length.
    Polyline(Vec<DVec3>),
    /// A log-aesthetic segment, parametrised by arc length.
    Aesthetic(AestheticSegment),
}

impl BoundaryCurve {
    fn validate(&self, which: usize) -> Result<()> {
        if let BoundaryCurve::Polyline(points) = self {
            crate::curve::PointSequence::new(points.clone(), false)
                .validate(2)
                .map_err(|e| Error::Input(format!("boundary curve {which}: {e}")))?;
        }
        Ok(())
    }

    fn ends(&self) -> (DVec3, DVec3) {
        match self {
            BoundaryCurve::Polyline(p) => (p[0], p[p.len() - 1]),
            BoundaryCurve::Aesthetic(s) => {
                let ends = s.points_at_fractions(&[0.0, 1.0]);
                (ends[0], ends[1])
            }
        }
    }

    /// Points at the given fractions of the arc length, from the start or (`reversed`) the end.
    fn points_at(&self, fractions: &[f64], reversed: bool) -> Vec<DVec3> {
        let f: Vec<f64> = fractions.iter().map(|f| if reversed { 1.0 - f } else { *f }).collect();
        match self {
            BoundaryCurve::Aesthetic(s) => s.points_at_fractions(&f),
            BoundaryCurve::Polyline(points) => {
                let arc = crate::curve::sequence::arc_lengths(points);
                let total = arc[arc.len() - 1];
                f.iter()
                    .map(|f| {
                        let s = f.clamp(0.0, 1.0) * total;
                        let k = arc.partition_point(|a| *a <= s).clamp(1, points.len() - 1);
                        let (a, b) = (arc[k - 1], arc[k]);
                        let t = if b > a { (s - a) / (b - a) } else { 0.0 };
                        points[k - 1].lerp(points[k], t.clamp(0.0, 1.0))
                    })
                    .collect()
            }
        }
    }
}

/// Most quads a side of a Coons patch: 1024 × 1024 quads (a million faces, about a gigabyte of
/// mesh while it is built) still run on a laptop; 4096 asked for 16 million faces and 6 GB.
pub const MAX_COONS_SAMPLES: usize = 1024;

/// The Coons patch of four curves given as a loop (`curves[0]` from corner P00 to P10, then
/// P10 → P11, P11 → P01, P01 → P00; each may run either way), sampled on a grid of
/// `(samples + 1)²` points: row i is `u = i / samples`, column j is `v = j / samples`. The curves
/// must meet within `1e-6` of the patch's size.
pub fn coons_patch(curves: &[BoundaryCurve; 4], samples: usize) -> Result<Grid> {
    if !(1..=MAX_COONS_SAMPLES).contains(&samples) {
        return Err(Error::Input(format!(
            "a Coons patch needs between 1 and {MAX_COONS_SAMPLES} samples a side, not {samples}"
        )));
    }
    for (k, c) in curves.iter().enumerate() {
        c.validate(k)?;
    }
    let ends: Vec<(DVec3, DVec3)> = curves.iter().map(|c| c.ends()).collect();
    let size = ends.iter().map(|(a, b)| a.distance(*b)).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let close = |a: DVec3, b: DVec3| a.distance(b) <= 1e-6 * size;
    // Orient each curve so it starts where the previous one ends, trying both ways for the
    // first; the message names where the chain breaks.
    let mut broken = String::new();
    let mut orientation = None;
    for first_reversed in [false, true] {
        let mut reversed = [first_reversed, false, false, false];
        let (start, mut at) = if first_reversed { (ends[0].1, ends[0].0) } else { ends[0] };
        let mut chained = true;
        for k in 1..4 {
            let (a, b) = ends[k];
            if close(a, at) {
                at = b;
            } else if close(b, at) {
                reversed[k] = true;
                at = a;
            } else {
                if broken.is_empty() {
                    broken = format!(
                        "boundary curve {k} does not start or end where curve {} ends ({:?})",
                        k - 1,
                        at.to_array()
                    );
                }
                chained = false;
                break;
            }
        }
        if chained && close(at, start) {
            orientation = Some(reversed);
            break;
        }
        if chained && !first_reversed {
            broken = format!(
                "boundary curve 3 ends at {:?}, not where curve 0 starts: the loop does not close",
                at.to_array()
            );
        }
    }
    let Some(reversed) = orientation else {
        return Err(Error::Input(format!(
            "{broken}; the four curves must form a closed loop, each starting where the previous one ends"
        )));
    };
    let fractions: Vec<f64> = (0..=samples).map(|k| k as f64 / samples as f64).collect();
    let bottom = curves[0].points_at(&fractions, reversed[0]);
    let right = curves[1].points_at(&fractions, reversed[1]);
    // The top and left sides run backwards around the loop.
    let top = curves[2].points_at(&fractions, !reversed[2]);
    let left = curves[3].points_at(&fractions, !reversed[3]);
    // Corners: the mean of the two curve ends that meet there.
    let (p00, p10) = (0.5 * (bottom[0] + left[0]), 0.5 * (bottom[samples] + right[0]));
    let (p01, p11) = (0.5 * (top[0] + left[samples]), 0.5 * (top[samples] + right[samples]));
    let mut points = Vec::with_capacity((samples + 1) * (samples + 1));
    for (i, &u) in fractions.iter().enumerate() {
        for (j, &v) in fractions.iter().enumerate() {
            let ruled_v = (1.0 - v) * bottom[i] + v * top[i];
            let ruled_u = (1.0 - u) * left[j] + u * right[j];
            let corners = (1.0 - u) * (1.0 - v) * p00 + u * (1.0 - v) * p10 + (1.0 - u) * v * p01 + u * v * p11;
            points.push(ruled_v + ruled_u - corners);
        }
    }
    Ok(Grid { rows: samples + 1, cols: samples + 1, points })
}

/// The grid as a mesh of quads, vertex (i, j) at index `i · cols + j`, faces oriented along
/// `S_u × S_v`.
pub fn grid_mesh(grid: &Grid) -> Result<PolyMesh> {
    let cols = grid.cols as u32;
    let mut faces = Vec::with_capacity((grid.rows - 1) * (grid.cols - 1));
    for i in 0..grid.rows as u32 - 1 {
        for j in 0..cols - 1 {
            let v = i * cols + j;
            faces.push([v, v + cols, v + cols + 1, v + 1]);
        }
    }
    PolyMesh::from_polygons(grid.points.clone(), &faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_sides_given_in_any_direction_give_the_bilinear_patch() {
        let (p00, p10, p11, p01) =
            (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.5), DVec3::new(2.5, 1.5, 0.0), DVec3::new(0.0, 1.0, 1.0));
        let line = |a: DVec3, b: DVec3| BoundaryCurve::Polyline(vec![a, a.lerp(b, 0.3), b]);
        // Curve 0 backwards and curve 2 forwards round the loop.
        let curves = [line(p10, p00), line(p10, p11), line(p01, p11), line(p01, p00)];
        let grid = coons_patch(&curves, 4).unwrap();
        for i in 0..=4 {
            for j in 0..=4 {
                let (u, v) = (i as f64 / 4.0, j as f64 / 4.0);
                let bilinear = (1.0 - u) * (1.0 - v) * p00 + u * (1.0 - v) * p10 + (1.0 - u) * v * p01 + u * v * p11;
                assert!(grid.at(i, j).distance(bilinear) < 1e-12, "({i}, {j})");
            }
        }
        let mesh = grid_mesh(&grid).unwrap();
        assert_eq!((mesh.vertex_count(), mesh.face_count()), (25, 16));
    }

    #[test]
    fn an_open_loop_is_refused() {
        let line = |a: DVec3, b: DVec3| BoundaryCurve::Polyline(vec![a, b]);
        let curves = [
            line(DVec3::ZERO, DVec3::X),
            line(DVec3::X, DVec3::ONE),
            line(DVec3::ONE, DVec3::Y),
            line(DVec3::Y, DVec3::Z),
        ];
        let err = coons_patch(&curves, 4).unwrap_err().to_string();
        assert!(err.contains("loop does not close"), "{err}");
        let curves = [
            line(DVec3::ZERO, DVec3::X),
            line(DVec3::Y, DVec3::ONE),
            line(DVec3::ONE, DVec3::Y),
            line(DVec3::Y, DVec3::ZERO),
        ];
        assert!(coons_patch(&curves, 4).unwrap_err().to_string().contains("curve 1"));
    }
}
