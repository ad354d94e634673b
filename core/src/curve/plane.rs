//! The plane a planar curve lies in: the least-squares plane of its points.
//!
//! The normal is the eigenvector of the smallest eigenvalue of the points' covariance (principal
//! component analysis), found with cyclic Jacobi rotations on the 3 × 3 matrix; the in-plane axes
//! are the other two eigenvectors, the first along the curve's longest extent. Points that lie in
//! a plane z = const, as 2D input does, get exactly the normal ±z back. Weak where the curve is
//! (nearly) straight: every plane through a line fits it, and the normal is then arbitrary
//! (`None` is returned when the two smaller eigenvalues are both at roundoff level).

use crate::DVec3;

/// A plane with an orthonormal frame: `origin + x·axis_u + y·axis_v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane (the centroid of the points it was fitted to).
    pub origin: DVec3,
    /// First in-plane axis (unit).
    pub axis_u: DVec3,
    /// Second in-plane axis (unit), `normal × axis_u`.
    pub axis_v: DVec3,
    /// Unit normal.
    pub normal: DVec3,
}

impl Plane {
    /// The plane z = `z` with its usual axes.
    pub fn xy(z: f64) -> Plane {
        Plane { origin: DVec3::new(0.0, 0.0, z), axis_u: DVec3::X, axis_v: DVec3::Y, normal: DVec3::Z }
    }

    /// Signed distance of `p` from the plane (positive on the normal's side).
    pub fn distance(&self, p: DVec3) -> f64 {
        (p - self.origin).dot(self.normal)
    }

    /// The foot of `p` on the plane.
    pub fn project(&self, p: DVec3) -> DVec3 {
        p - self.distance(p) * self.normal
    }

    /// Least-squares plane of `points`; `None` for fewer than three points, non-finite ones, or
    /// points on a line. Points with a common z get the plane z = const with normal +z, so
    /// counter-clockwise curves seen from +z turn positively.
    pub fn fit(points: &[DVec3]) -> Option<Plane> {
        if points.len() < 3 || !points.iter().all(|p| p.is_finite()) {
            return None;
        }
        let centroid = points.iter().copied().sum::<DVec3>() / points.len() as f64;
        let mut c = [[0.0f64; 3]; 3];
        for p in points {
            let d = (*p - centroid).to_array();
            for r in 0..3 {
                for k in 0..3 {
                    c[r][k] += d[r] * d[k];
                }
            }
        }
        let (values, vectors) = symmetric_eigen(c);
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
        let (big, mid) = (values[order[0]], values[order[1]]);
        if big.is_nan() || big <= 0.0 || mid <= 1e-14 * big {
            return None; // all points on a line (or one point)
        }
        let axis_u = vectors[order[0]];
        let mut normal = vectors[order[2]];
        // A plane z = const keeps +z, so 2D input keeps its orientation.
        if normal.z < 0.0 || (normal.z == 0.0 && (normal.y < 0.0 || (normal.y == 0.0 && normal.x < 0.0))) {
            normal = -normal;
        }
        let flat_z = points.iter().all(|p| p.z == points[0].z);
        if flat_z {
            normal = DVec3::Z;
        }
        let axis_u = (axis_u - axis_u.dot(normal) * normal).normalize();
        Some(Plane { origin: centroid, axis_u, axis_v: normal.cross(axis_u), normal })
    }
}

/// Eigenvalues and unit eigenvectors of a symmetric 3 × 3 matrix by cyclic Jacobi rotations.
fn symmetric_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [DVec3; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-32 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // The rotation that zeroes a[p][q] (Golub and Van Loan, sec. 8.5).
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let column = |j: usize| DVec3::new(v[0][j], v[1][j], v[2][j]).normalize();
    ([a[0][0], a[1][1], a[2][2]], [column(0), column(1), column(2)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_circle_gives_its_plane() {
        let normal = DVec3::new(1.0, -2.0, 0.5).normalize();
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        let centre = DVec3::new(3.0, 1.0, -2.0);
        let points: Vec<DVec3> =
            (0..30).map(|i| i as f64 * 0.2).map(|t| centre + 2.0 * t.cos() * u + 0.5 * t.sin() * v).collect();
        let plane = Plane::fit(&points).unwrap();
        assert!(plane.normal.dot(normal).abs() > 1.0 - 1e-12, "{plane:?}");
        assert!(points.iter().all(|p| plane.distance(*p).abs() < 1e-12));
        assert!((plane.axis_u.cross(plane.axis_v) - plane.normal).length() < 1e-12);
    }

    #[test]
    fn flat_points_keep_plus_z_and_lines_have_no_plane() {
        let points = [DVec3::new(0.0, 0.0, 2.0), DVec3::new(1.0, 0.1, 2.0), DVec3::new(2.0, -0.3, 2.0)];
        assert_eq!(Plane::fit(&points).unwrap().normal, DVec3::Z);
        let line: Vec<DVec3> = (0..5).map(|i| DVec3::new(1.0, 2.0, 3.0) * i as f64).collect();
        assert!(Plane::fit(&line).is_none());
        assert!(Plane::fit(&points[..2]).is_none());
    }
}
