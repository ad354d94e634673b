//! The per-face second fundamental form and its per-vertex average (Rusinkiewicz 2004, sec. 3).
//!
//! A face's shape operator `S` (a symmetric 2×2 tensor in the face's tangent frame) is the one
//! that best maps the vertex positions' differences to the vertex normals' differences,
//! `S·Δp ≈ Δn` (eq. 3), in the least-squares sense. Triangles use their three edges, exactly as
//! in the paper; a polygon uses every pair of its vertices (its edges and diagonals, so the fit
//! does not depend on which vertex the face starts from) or, past [`ALL_PAIRS_MAX_VALENCE`]
//! corners, its edges only. Each vertex then rotates the tensors of its faces into its own
//! tangent plane (sec. 3.2) and averages them weighted by its share of each face's area.

use crate::DVec3;

/// Faces with up to this many corners are fitted on all vertex pairs; larger ones on their edges.
pub const ALL_PAIRS_MAX_VALENCE: usize = 16;

/// A face whose area is below this fraction of its squared perimeter counts as degenerate.
const DEGENERATE_AREA: f64 = 1e-12;

/// A least-squares system whose determinant is below this fraction of the cube of its mean
/// diagonal counts as singular (edges all parallel).
const SINGULAR_SYSTEM: f64 = 1e-12;

/// Faces turned more than this far from a vertex's normal (cosine) do not count at that vertex:
/// the rotation onto the vertex's tangent plane is undefined for a folded-over face.
const MIN_NORMAL_COSINE: f64 = -0.999_999;

/// A symmetric 2×2 tensor `[[a, b], [b, c]]` in some tangent frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Tensor2 {
    pub a: f64,
    pub b: f64,
    pub c: f64,
}

/// A right-handed orthonormal frame: tangents `u`, `v` and normal `n = u × v`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    pub u: DVec3,
    pub v: DVec3,
    pub n: DVec3,
}

impl Frame {
    /// A frame around the unit normal `n` whose `u` is `hint` projected onto the tangent plane
    /// (any tangent if `hint` is parallel to `n`).
    pub fn new(n: DVec3, hint: DVec3) -> Self {
        let u = hint.reject_from_normalized(n).try_normalize().unwrap_or_else(|| n.any_orthonormal_vector());
        Self { u, v: n.cross(u), n }
    }
}

/// The fitted shape operator of one face.
#[derive(Clone, Copy, Debug)]
pub(super) struct FaceFit {
    pub frame: Frame,
    pub tensor: Tensor2,
    /// Mean of the corners, for the corner areas of polygons.
    pub centroid: DVec3,
    pub valence: usize,
}

/// Fits the shape operator of a face with corners `points` and unit vertex normals `normals`.
/// `None` for a face that cannot carry one: zero area, a corner without a normal, edges that
/// leave the system singular, or non-finite input.
pub(super) fn fit_face(points: &[DVec3], normals: &[DVec3]) -> Option<FaceFit> {
    let count = points.len();
    if count < 3 || normals.contains(&DVec3::ZERO) {
        return None;
    }
    let centroid = points.iter().copied().sum::<DVec3>() / count as f64;
    let mut area = DVec3::ZERO;
    let mut perimeter = 0.0;
    for i in 0..count {
        let (p, q) = (points[i] - centroid, points[(i + 1) % count] - centroid);
        area += 0.5 * p.cross(q);
        perimeter += (q - p).length();
    }
    let area_length = area.length();
    let sound = area_length > DEGENERATE_AREA * perimeter * perimeter; // false for NaN
    if !sound {
        return None;
    }
    let frame = Frame::new(area / area_length, points[1] - points[0]);

    // Normal equations of the two rows [eu ev 0]·x = dnu, [0 eu ev]·x = dnv per pair, for the
    // unknowns x = (S_uu, S_uv, S_vv).
    let (mut uu, mut uv, mut vv) = (0.0, 0.0, 0.0);
    let mut rhs = [0.0; 3];
    let mut add_pair = |i: usize, j: usize| {
        let e = points[j] - points[i];
        let dn = normals[j] - normals[i];
        let (eu, ev) = (e.dot(frame.u), e.dot(frame.v));
        let (dnu, dnv) = (dn.dot(frame.u), dn.dot(frame.v));
        uu += eu * eu;
        uv += eu * ev;
        vv += ev * ev;
        rhs[0] += eu * dnu;
        rhs[1] += ev * dnu + eu * dnv;
        rhs[2] += ev * dnv;
    };
    if count <= ALL_PAIRS_MAX_VALENCE {
        for i in 0..count {
            for j in i + 1..count {
                add_pair(i, j);
            }
        }
    } else {
        for i in 0..count {
            add_pair(i, (i + 1) % count);
        }
    }
    let m = [[uu, uv, 0.0], [uv, uu + vv, uv], [0.0, uv, vv]];
    let [a, b, c] = solve_symmetric3(m, rhs)?;
    let tensor = Tensor2 { a, b, c };
    (a.is_finite() && b.is_finite() && c.is_finite()).then_some(FaceFit { frame, tensor, centroid, valence: count })
}

/// Solves the symmetric 3×3 system `m·x = r` by Cramer's rule; `None` when it is singular.
fn solve_symmetric3(m: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let cofactor0 = [
        m[1][1] * m[2][2] - m[1][2] * m[2][1],
        m[1][2] * m[2][0] - m[1][0] * m[2][2],
        m[1][0] * m[2][1] - m[1][1] * m[2][0],
    ];
    let det = m[0][0] * cofactor0[0] + m[0][1] * cofactor0[1] + m[0][2] * cofactor0[2];
    let scale = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
    // The normal matrix is positive semi-definite: det ≥ 0 up to rounding.
    let regular = det > SINGULAR_SYSTEM * scale * scale * scale; // false for NaN
    if !regular {
        return None;
    }
    let column = |k: usize| {
        let mut mk = m;
        for row in 0..3 {
            mk[row][k] = r[row];
        }
        mk[0][0] * (mk[1][1] * mk[2][2] - mk[1][2] * mk[2][1]) - mk[0][1] * (mk[1][0] * mk[2][2] - mk[1][2] * mk[2][0])
            + mk[0][2] * (mk[1][0] * mk[2][1] - mk[1][1] * mk[2][0])
    };
    Some([column(0) / det, column(1) / det, column(2) / det])
}

/// The face's tensor expressed in `target`'s frame after rotating the face's frame about
/// `n_face × n_target` until the normals agree (Rusinkiewicz, sec. 3.2). `None` for a face turned
/// (almost) opposite to the target normal, where that rotation is undefined.
pub(super) fn tensor_in_frame(fit: &FaceFit, target: &Frame) -> Option<Tensor2> {
    let (from, to) = (fit.frame.n, target.n);
    let cos = from.dot(to);
    let turnable = cos > MIN_NORMAL_COSINE; // false for NaN
    if !turnable {
        return None;
    }
    // Rodrigues' rotation with the unnormalised axis w = from × to (|w| = sin θ).
    let w = from.cross(to);
    let rotate = |x: DVec3| cos * x + w.cross(x) + w * (w.dot(x) / (1.0 + cos));
    let (u, v) = (rotate(fit.frame.u), rotate(fit.frame.v));
    // Coordinates of the target's tangents in the rotated face frame.
    let (x1, y1) = (target.u.dot(u), target.u.dot(v));
    let (x2, y2) = (target.v.dot(u), target.v.dot(v));
    let Tensor2 { a, b, c } = fit.tensor;
    Some(Tensor2 {
        a: a * x1 * x1 + 2.0 * b * x1 * y1 + c * y1 * y1,
        b: a * x1 * x2 + b * (x1 * y2 + x2 * y1) + c * y1 * y2,
        c: a * x2 * x2 + 2.0 * b * x2 * y2 + c * y2 * y2,
    })
}

/// The area of a face that belongs to its corner `p` (neighbours `prev` and `next` along the
/// face). Triangles: the mixed Voronoi area of Meyer et al. 2002 (sec. 3.3), the Voronoi cell
/// clipped to the triangle, with a quarter/half of the area at obtuse triangles. Polygons: the
/// region bounded by the corner, the midpoints of its two edges and the face's centroid (the
/// Voronoi cell for a rectangle or a regular polygon). Either way a face's corner areas add up to
/// its area (for a planar convex polygon).
pub(super) fn corner_area(fit: &FaceFit, prev: DVec3, p: DVec3, next: DVec3) -> f64 {
    if fit.valence == 3 {
        let (to_next, to_prev) = (next - p, prev - p);
        let double_area = to_next.cross(to_prev).length();
        let dot_p = to_next.dot(to_prev);
        let dot_next = (p - next).dot(prev - next);
        let dot_prev = (p - prev).dot(next - prev);
        if dot_p < 0.0 {
            0.25 * double_area
        } else if dot_next < 0.0 || dot_prev < 0.0 {
            0.125 * double_area
        } else if double_area > 0.0 {
            // (|p − prev|² cot∠next + |p − next|² cot∠prev) / 8, with cot = dot / (2·area).
            (to_prev.length_squared() * dot_next + to_next.length_squared() * dot_prev) / (8.0 * double_area)
        } else {
            0.0
        }
    } else {
        let (to_next, to_prev, to_centre) = (0.5 * (next - p), 0.5 * (prev - p), fit.centroid - p);
        0.5 * (to_next.cross(to_centre).length() + to_centre.cross(to_prev).length())
    }
}

/// Eigen-decomposition of a symmetric 2×2 tensor in closed form: `(κ_min, κ_max, θ)` with the
/// eigenvector of `κ_max` at angle `θ` from the frame's `u`.
pub(super) fn principal(t: Tensor2) -> (f64, f64, f64) {
    let mean = 0.5 * (t.a + t.c);
    let radius = (0.5 * (t.a - t.c)).hypot(t.b);
    (mean - radius, mean + radius, 0.5 * (2.0 * t.b).atan2(t.a - t.c))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit_on_sphere(points: &[DVec3]) -> FaceFit {
        let normals: Vec<DVec3> = points.iter().map(|p| p.normalize()).collect();
        fit_face(points, &normals).unwrap()
    }

    #[test]
    fn exact_normals_of_a_sphere_give_the_identity_over_r() {
        // With exact normals n = p/r the normal differences are Δp/r for every pair, so the fit is
        // exactly S = I/r on any face, triangle or not.
        let r = 2.5;
        let on_sphere = |x: f64, y: f64| DVec3::new(x, y, 1.0).normalize() * r;
        let tri = [on_sphere(0.0, 0.0), on_sphere(0.1, 0.02), on_sphere(0.03, 0.12)];
        let quad = [on_sphere(0.0, 0.0), on_sphere(0.1, 0.0), on_sphere(0.12, 0.09), on_sphere(-0.01, 0.1)];
        for face in [&tri[..], &quad[..]] {
            let fit = fit_on_sphere(face);
            let Tensor2 { a, b, c } = fit.tensor;
            assert!((a - 1.0 / r).abs() < 1e-12 && (c - 1.0 / r).abs() < 1e-12 && b.abs() < 1e-12, "{a} {b} {c}");
        }
    }

    #[test]
    fn a_cylinder_face_gives_its_principal_curvatures() {
        // Axis along z, radius 3: S has eigenvalues 0 (along z) and 1/3 (around).
        let r = 3.0;
        let at = |t: f64, z: f64| DVec3::new(r * t.cos(), r * t.sin(), z);
        let points = [at(0.0, 0.0), at(0.05, 0.0), at(0.05, 0.1), at(0.0, 0.1)];
        let normals: Vec<DVec3> = points.iter().map(|p| DVec3::new(p.x, p.y, 0.0).normalize()).collect();
        let fit = fit_face(&points, &normals).unwrap();
        let (k_min, k_max, theta) = principal(fit.tensor);
        assert!(k_min.abs() < 1e-12 && (k_max - 1.0 / r).abs() < 1e-12, "{k_min} {k_max}");
        let dir = theta.cos() * fit.frame.u + theta.sin() * fit.frame.v;
        assert!(dir.z.abs() < 1e-9, "the largest curvature runs around the cylinder: {dir}");
    }

    #[test]
    fn degenerate_faces_are_refused() {
        let n = [DVec3::Z; 3];
        assert!(fit_face(&[DVec3::ZERO, DVec3::X, 2.0 * DVec3::X], &n).is_none());
        assert!(fit_face(&[DVec3::ZERO, DVec3::ZERO, DVec3::ZERO], &n).is_none());
        assert!(fit_face(&[DVec3::ZERO, DVec3::X, DVec3::NAN], &n).is_none());
        assert!(fit_face(&[DVec3::ZERO, DVec3::X, DVec3::Y], &[DVec3::Z, DVec3::ZERO, DVec3::Z]).is_none());
        assert!(fit_face(&[DVec3::ZERO, DVec3::X, DVec3::Y], &n).is_some());
    }

    #[test]
    fn corner_areas_are_voronoi_and_add_up_to_the_face_area() {
        let n = [DVec3::Z; 4];
        // Acute triangle: the cotangent formula against the circumcentre's cells.
        let tri = [DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.8, 1.5, 0.0)];
        let fit = fit_face(&tri, &n[..3]).unwrap();
        let areas: Vec<f64> = (0..3).map(|i| corner_area(&fit, tri[(i + 2) % 3], tri[i], tri[(i + 1) % 3])).collect();
        assert!((areas.iter().sum::<f64>() - 1.5).abs() < 1e-12, "{areas:?}");
        // Corner 0's cell: the quadrilateral (p0, mid01, circumcentre, mid02).
        let (a, b) = (tri[1], tri[2]);
        let centre_y = (b.length_squared() - 2.0 * b.x) / (2.0 * b.y); // circumcentre (1, centre_y)
        let cc = DVec3::new(1.0, centre_y, 0.0);
        let cell = 0.5 * ((0.5 * a).cross(cc).length() + cc.cross(0.5 * b).length());
        assert!((areas[0] - cell).abs() < 1e-12, "{} vs {cell}", areas[0]);
        // Obtuse at corner 0: half there, a quarter at the others.
        let obtuse = [DVec3::ZERO, DVec3::new(2.0, 0.2, 0.0), DVec3::new(-1.0, 0.5, 0.0)];
        let fit = fit_face(&obtuse, &n[..3]).unwrap();
        let area = 0.5 * (obtuse[1].cross(obtuse[2])).length();
        assert!((corner_area(&fit, obtuse[2], obtuse[0], obtuse[1]) - 0.5 * area).abs() < 1e-12);
        assert!((corner_area(&fit, obtuse[0], obtuse[1], obtuse[2]) - 0.25 * area).abs() < 1e-12);
        // A rectangle: a quarter each.
        let rect = [DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::new(3.0, 1.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];
        let fit = fit_face(&rect, &n).unwrap();
        for i in 0..4 {
            assert!((corner_area(&fit, rect[(i + 3) % 4], rect[i], rect[(i + 1) % 4]) - 0.75).abs() < 1e-12);
        }
    }

    #[test]
    fn rotating_into_another_frame_keeps_the_invariants() {
        let fit = FaceFit {
            frame: Frame::new(DVec3::Z, DVec3::X),
            tensor: Tensor2 { a: 0.3, b: -0.2, c: 1.1 },
            centroid: DVec3::ZERO,
            valence: 3,
        };
        let target = Frame::new(DVec3::new(0.3, -0.2, 1.0).normalize(), DVec3::new(0.4, 1.0, 0.0));
        let t = tensor_in_frame(&fit, &target).unwrap();
        let (k0, k1, _) = principal(fit.tensor);
        let (r0, r1, _) = principal(t);
        assert!((k0 - r0).abs() < 1e-14 && (k1 - r1).abs() < 1e-14);
        let flipped = Frame::new(-DVec3::Z, DVec3::X);
        assert!(tensor_in_frame(&fit, &flipped).is_none());
    }

    #[test]
    fn principal_directions_diagonalise() {
        let t = Tensor2 { a: 0.7, b: 0.4, c: -0.5 };
        let (k_min, k_max, theta) = principal(t);
        let (x, y) = (theta.cos(), theta.sin());
        let image = (t.a * x + t.b * y, t.b * x + t.c * y);
        assert!((image.0 - k_max * x).abs() < 1e-14 && (image.1 - k_max * y).abs() < 1e-14);
        assert!((k_min * k_max - (t.a * t.c - t.b * t.b)).abs() < 1e-14);
    }
}
