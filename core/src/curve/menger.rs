//! Discrete curvature of a polyline, for curvature combs on curves.
//!
//! The curvature at a point is the Menger curvature of the point and its two neighbours: the
//! inverse radius of the circle through the three, `κ = 4·area / (|a|·|b|·|c|)` for the triangle
//! with sides `a`, `b`, `c`. It is exact for points on a circle however they are spaced, and
//! second-order accurate for evenly sampled smooth curves; on unevenly spaced samples of a curve
//! whose curvature varies it is only first-order accurate. Endpoints of an open polyline have a
//! single neighbour and copy the curvature of the point next to them.

use crate::DVec3;

/// Curvature along a polyline, one entry per point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolylineCurvature {
    /// Distance along the polyline from the first point (cumulative chord length).
    pub arc_length: Vec<f64>,
    /// The curvature vector `κ·N`: length `1/R` of the circle through the point and its
    /// neighbours, pointing towards that circle's centre (the direction a curvature comb is drawn
    /// in, or the opposite). Zero where the three points are collinear or two coincide.
    pub curvature: Vec<DVec3>,
    /// Unit binormal `T × N`: the axis the curve turns counter-clockwise about at the point
    /// (normal to the plane of the three points); zero where the curvature is zero.
    pub binormal: Vec<DVec3>,
    /// Length of the whole polyline, the closing segment included for a closed one.
    pub total_length: f64,
}

impl PolylineCurvature {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.curvature.len()
    }

    /// True for a polyline without points.
    pub fn is_empty(&self) -> bool {
        self.curvature.is_empty()
    }

    /// Unsigned curvature `|κ|` per point.
    pub fn magnitude(&self) -> Vec<f64> {
        self.curvature.iter().map(|k| k.length()).collect()
    }

    /// Signed curvature of a curve lying in the plane with normal `plane_normal` (any length):
    /// positive where the curve turns left, i.e. counter-clockwise seen from the side
    /// `plane_normal` points to, so a counter-clockwise circle has `+1/R`. The magnitude is the
    /// full 3D `|κ|`; for a curve out of the plane only the sign comes from the projection.
    pub fn signed(&self, plane_normal: DVec3) -> Vec<f64> {
        self.curvature
            .iter()
            .zip(&self.binormal)
            .map(|(k, b)| {
                let side = b.dot(plane_normal);
                if side > 0.0 {
                    k.length()
                } else if side < 0.0 {
                    -k.length()
                } else {
                    0.0
                }
            })
            .collect()
    }
}

/// Curvature and arc length at every point of a polyline (see the module documentation). Open
/// ends copy their neighbour's curvature; polylines with fewer than three points have zero
/// curvature everywhere.
pub fn polyline_curvature(points: &[DVec3], closed: bool) -> PolylineCurvature {
    let n = points.len();
    let arc_length = super::sequence::arc_lengths(points);
    let mut length = arc_length.last().copied().unwrap_or(0.0);
    if closed && n > 1 {
        length += (points[0] - points[n - 1]).length();
    }
    let (mut curvature, mut binormal): (Vec<DVec3>, Vec<DVec3>) = (0..n)
        .map(|i| neighbours(points, i, closed).map_or((DVec3::ZERO, DVec3::ZERO), |(a, b, c)| menger(a, b, c)))
        .unzip();
    if !closed && n >= 3 {
        curvature[0] = curvature[1];
        curvature[n - 1] = curvature[n - 2];
        binormal[0] = binormal[1];
        binormal[n - 1] = binormal[n - 2];
    }
    PolylineCurvature { arc_length, curvature, binormal, total_length: length }
}

/// Point `i` with the points before and after it, if it has both.
fn neighbours(points: &[DVec3], i: usize, closed: bool) -> Option<(DVec3, DVec3, DVec3)> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    if closed {
        Some((points[(i + n - 1) % n], points[i], points[(i + 1) % n]))
    } else if i > 0 && i + 1 < n {
        Some((points[i - 1], points[i], points[i + 1]))
    } else {
        None
    }
}

/// The Menger curvature vector at `b` of the circle through `a`, `b`, `c` (`1/R` towards the
/// centre) and the unit binormal of the turn `a → b → c`; both zero for collinear or coincident
/// points.
fn menger(a: DVec3, b: DVec3, c: DVec3) -> (DVec3, DVec3) {
    let (to_a, to_c) = (a - b, c - b);
    let w = to_a.cross(to_c);
    let (la, lc, lac) = (to_a.length(), to_c.length(), (c - a).length());
    let denominator = la * lc * lac;
    let turns = w.length() > 1e-14 * denominator / lac.max(la).max(lc); // false for NaN
    if !turns {
        return (DVec3::ZERO, DVec3::ZERO); // collinear, coincident or not finite
    }
    let kappa = 2.0 * w.length() / denominator;
    // Circumcentre relative to b: ((|a|²c − |c|²a) × w) / (2|w|²); only its direction is used.
    let to_centre = (to_a.length_squared() * to_c - to_c.length_squared() * to_a).cross(w);
    // (b − a) × (c − b) = −w is the turn's axis.
    (kappa * to_centre.normalize(), -w.normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circumcircle_of_a_right_angle() {
        // Circle through (1,0), (0,0), (0,1): centre (0.5, 0.5), radius √2/2.
        let (k, binormal) = menger(DVec3::X, DVec3::ZERO, DVec3::Y);
        let expected = DVec3::new(0.5, 0.5, 0.0) / 0.5;
        assert!((k - expected).length() < 1e-15, "{k}");
        // From +x through the origin to +y is a right turn seen from +z.
        assert_eq!(binormal, -DVec3::Z);
        assert_eq!(menger(DVec3::ZERO, DVec3::X, 2.0 * DVec3::X), (DVec3::ZERO, DVec3::ZERO));
        assert_eq!(menger(DVec3::X, DVec3::X, DVec3::Y), (DVec3::ZERO, DVec3::ZERO));
    }

    #[test]
    fn short_polylines_have_no_curvature() {
        let c = polyline_curvature(&[DVec3::ZERO, DVec3::X], false);
        assert_eq!(c.curvature, vec![DVec3::ZERO; 2]);
        assert_eq!(c.arc_length, vec![0.0, 1.0]);
        assert_eq!(polyline_curvature(&[], true).len(), 0);
    }
}
