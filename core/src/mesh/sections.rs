//! Section curves: where a set of parallel planes cut a surface mesh, as polylines, the way
//! Rhino's Contour and Alias's cross sections show a surface's shape plane by plane.
//!
//! Every face is split into triangles (as the surface is drawn); a triangle whose corners lie on
//! both sides of a plane contributes one segment between the points where the plane crosses two
//! of its edges. A crossing point is named by its edge (the two vertex numbers), so the segments
//! of neighbouring triangles meet in the same point, bit for bit, and chain into polylines: a
//! closed loop where the section goes round, an open run where it leaves an open surface. A
//! vertex exactly on a plane counts as above it, so a plane through vertices still cuts every
//! triangle around them once.

use super::PolyMesh;
use crate::DVec3;
use std::collections::HashMap;

/// The step at which a section of `mesh` is resampled for its comb ([`SectionCurve::evenly`]):
/// three times the mesh's mean edge length, so that each step spans a few facets and the comb
/// reads the surface's bending, not the turns at the facets' edges.
pub fn comb_step(mesh: &PolyMesh) -> f64 {
    let count = mesh.edge_count().max(1) as f64;
    3.0 * mesh.edges().map(|e| mesh.edge_length(e)).sum::<f64>() / count
}

/// One polyline of a section.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionCurve {
    pub points: Vec<DVec3>,
    /// True for a loop (the last point joins the first; not repeated).
    pub closed: bool,
}

impl SectionCurve {
    /// The curve's points again at even arc-length steps of about `step` (at least 8 steps; the
    /// ends of an open run kept). A section crosses the triangles at uneven spacing and turns a
    /// little at every edge it crosses; a curvature comb read from three neighbouring crossings
    /// shows those turns as spikes, so combs are drawn on points a steady distance apart, a step
    /// spanning several triangles.
    pub fn evenly(&self, step: f64) -> Vec<DVec3> {
        let (points, closed) = (&self.points, self.closed);
        let mut path = points.to_vec();
        if closed && let Some(&first) = points.first() {
            path.push(first);
        }
        let lengths: Vec<f64> = path.windows(2).map(|w| w[0].distance(w[1])).collect();
        let total: f64 = lengths.iter().sum();
        if path.len() < 3 || total.is_nan() || total <= 0.0 {
            return points.to_vec();
        }
        let count = if step > 0.0 { ((total / step).round() as usize).clamp(8, 100_000) } else { 8 };
        let step = total / count as f64;
        let mut out = Vec::with_capacity(count + 1);
        let (mut segment, mut walked) = (0, 0.0);
        for k in 0..count + usize::from(!closed) {
            let at = (k as f64 * step).min(total);
            while segment + 1 < lengths.len() && walked + lengths[segment] < at {
                walked += lengths[segment];
                segment += 1;
            }
            let t = if lengths[segment] > 0.0 { ((at - walked) / lengths[segment]).clamp(0.0, 1.0) } else { 0.0 };
            out.push(path[segment].lerp(path[segment + 1], t));
        }
        out
    }
}

/// The sections of `mesh` by the planes `normal · p = offset` for each offset (in order), each
/// a list of polylines. `normal` need not be unit length; a zero or non-finite normal, or a
/// non-finite offset, gives no curves for it.
pub fn sections(mesh: &PolyMesh, normal: DVec3, offsets: &[f64]) -> Vec<Vec<SectionCurve>> {
    let triangles = mesh.triangles();
    let usable = normal.is_finite() && normal != DVec3::ZERO;
    offsets
        .iter()
        .map(|&c| if usable && c.is_finite() { section(mesh, &triangles, normal, c) } else { Vec::new() })
        .collect()
}

fn section(mesh: &PolyMesh, triangles: &[[u32; 3]], normal: DVec3, offset: f64) -> Vec<SectionCurve> {
    let positions = mesh.positions();
    let side = |v: u32| normal.dot(positions[v as usize]) - offset;
    // The crossing point on edge (a, b), a < b: the same arithmetic from either triangle.
    let crossing = |a: u32, b: u32| {
        let (a, b) = if a < b { (a, b) } else { (b, a) };
        let (da, db) = (side(a), side(b));
        let t = da / (da - db);
        positions[a as usize].lerp(positions[b as usize], t)
    };
    let mut points: Vec<DVec3> = Vec::new();
    let mut index: HashMap<(u32, u32), usize> = HashMap::new();
    let mut point_of = |a: u32, b: u32, points: &mut Vec<DVec3>| {
        let key = if a < b { (a, b) } else { (b, a) };
        *index.entry(key).or_insert_with(|| {
            points.push(crossing(a, b));
            points.len() - 1
        })
    };
    // Segments as pairs of point numbers; each point has at most two (a manifold mesh).
    let mut links: Vec<Vec<usize>> = Vec::new();
    for &[a, b, c] in triangles {
        let above = [a, b, c].map(|v| side(v) >= 0.0);
        if above[0] == above[1] && above[1] == above[2] {
            continue;
        }
        let crossed: Vec<usize> = [(a, b, 0, 1), (b, c, 1, 2), (c, a, 2, 0)]
            .into_iter()
            .filter(|&(_, _, i, j)| above[i] != above[j])
            .map(|(u, v, _, _)| point_of(u, v, &mut points))
            .collect();
        if let [p, q] = crossed[..] {
            links.resize(points.len(), Vec::new());
            links[p].push(q);
            links[q].push(p);
        }
    }
    links.resize(points.len(), Vec::new());
    chain(&points, &links)
}

/// Polylines through the links: open runs from their ends first, then the loops.
fn chain(points: &[DVec3], links: &[Vec<usize>]) -> Vec<SectionCurve> {
    let mut used = vec![false; points.len()];
    let mut curves = Vec::new();
    let starts = (0..points.len()).filter(|&p| links[p].len() == 1).chain(0..points.len());
    for start in starts {
        if used[start] || links[start].is_empty() {
            continue;
        }
        let mut run = vec![start];
        used[start] = true;
        let mut at = start;
        while let Some(&next) = links[at].iter().find(|&&n| !used[n]) {
            used[next] = true;
            run.push(next);
            at = next;
        }
        let closed = run.len() > 2 && links[at].contains(&start);
        curves.push(SectionCurve { points: run.into_iter().map(|p| points[p]).collect(), closed });
    }
    curves
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives::{torus, uv_sphere};

    #[test]
    fn sections_of_a_sphere_are_circles_of_the_right_radius() {
        let (r, segments) = (2.0, 96);
        let sphere = uv_sphere(segments, 48, r).unwrap();
        let heights = [-1.5, -0.7, 0.0, 0.3, 1.9];
        let cut = sections(&sphere, DVec3::Z, &heights);
        // The mesh lies inside the sphere by at most its chord error.
        let chord = r * (1.0 - (std::f64::consts::PI / segments as f64).cos()) * 2.0;
        for (z, curves) in heights.iter().zip(&cut) {
            assert_eq!(curves.len(), 1, "one loop at z = {z}");
            let loop_ = &curves[0];
            assert!(loop_.closed && loop_.points.len() > 20, "z = {z}: {} points", loop_.points.len());
            let expected = (r * r - z * z).sqrt();
            for p in &loop_.points {
                assert!((p.z - z).abs() < 1e-12, "on its plane");
                let radius = p.truncate().length();
                assert!((radius - expected).abs() <= chord, "z = {z}: radius {radius}, circle {expected}");
            }
        }
    }

    #[test]
    fn a_torus_cut_through_its_middle_gives_two_circles_and_a_plane_past_it_nothing() {
        let ring = torus(64, 32, 2.0, 0.5).unwrap();
        let cut = sections(&ring, DVec3::new(0.0, 0.0, 2.0), &[0.0, 3.0, f64::NAN]);
        assert_eq!(cut[0].len(), 2);
        let mut radii: Vec<f64> = cut[0].iter().map(|c| c.points[0].truncate().length()).collect();
        radii.sort_by(f64::total_cmp);
        assert!((radii[0] - 1.5).abs() < 0.01 && (radii[1] - 2.5).abs() < 0.01, "{radii:?}");
        assert!(cut[0].iter().all(|c| c.closed));
        assert!(cut[1].is_empty() && cut[2].is_empty());
    }

    #[test]
    fn a_section_resampled_evenly_stays_on_it_at_even_steps() {
        let sphere = uv_sphere(64, 32, 1.0).unwrap();
        let loop_ = sections(&sphere, DVec3::Z, &[0.2]).remove(0).remove(0);
        let length: f64 =
            (0..loop_.points.len()).map(|k| loop_.points[k].distance(loop_.points[(k + 1) % loop_.points.len()])).sum();
        let even = loop_.evenly(length / 40.0);
        assert_eq!(even.len(), 40);
        // On the section: every point within rounding of one of its segments.
        let n = loop_.points.len();
        for p in &even {
            let near = (0..n)
                .map(|k| {
                    let (a, b) = (loop_.points[k], loop_.points[(k + 1) % n]);
                    let t = ((*p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                    p.distance(a.lerp(b, t))
                })
                .fold(f64::INFINITY, f64::min);
            assert!(near < 1e-12, "{near}");
        }
        // Even steps: the chords between neighbours differ by far less than the raw pieces do.
        let chords: Vec<f64> = (0..even.len()).map(|k| even[k].distance(even[(k + 1) % even.len()])).collect();
        let (lo, hi) = chords.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &c| (a.min(c), b.max(c)));
        assert!(hi / lo < 1.01, "{lo} .. {hi}");
    }

    #[test]
    fn an_open_patch_gives_an_open_run() {
        let grid = crate::mesh::primitives::quad_grid(4, 4, 2.0, 2.0).unwrap();
        let cut = sections(&grid, DVec3::X, &[0.3]);
        assert_eq!(cut[0].len(), 1);
        let run = &cut[0][0];
        assert!(!run.closed);
        assert!(run.points.iter().all(|p| (p.x - 0.3).abs() < 1e-12));
        let span = run.points.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max)
            - run.points.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        assert!((span - 2.0).abs() < 1e-12, "it crosses the whole patch: {span}");
    }
}
