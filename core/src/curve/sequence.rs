//! An ordered sequence of points, open or closed: the common ground of every curve method in
//! Taut (NUSD's control polylines, the log-aesthetic filters, curvature combs).
//!
//! It knows its segments, their chord lengths, the cumulative arc length of the polyline through
//! the points and its bounding box, and checks that the points make a curve at all (enough of
//! them, finite, no two consecutive ones at the same place). The arc length is the polyline's,
//! so it underestimates the length of the smooth curve the points sample by O(κ² h²) relative.

use crate::{DVec3, Error, Result};

/// Points in order along a curve; a closed sequence joins its last point back to the first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointSequence {
    /// Positions, in order along the curve.
    pub points: Vec<DVec3>,
    /// True when the last point joins back to the first.
    pub closed: bool,
}

/// Number of segments of `n` points: one per consecutive pair, plus the closing one.
pub fn segment_count(n: usize, closed: bool) -> usize {
    match n {
        0 => 0,
        n if closed => n,
        n => n - 1,
    }
}

/// Chord length of every segment (the closing one last, for a closed sequence).
pub fn chord_lengths(points: &[DVec3], closed: bool) -> Vec<f64> {
    let n = points.len();
    (0..segment_count(n, closed)).map(|e| points[e].distance(points[(e + 1) % n])).collect()
}

/// Cumulative chord length at every point, starting at 0 (the closing segment is not included).
pub fn arc_lengths(points: &[DVec3]) -> Vec<f64> {
    let mut s = 0.0;
    let mut out = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            s += p.distance(points[i - 1]);
        }
        out.push(s);
    }
    out
}

impl PointSequence {
    /// A sequence of the given points.
    pub fn new(points: Vec<DVec3>, closed: bool) -> Self {
        PointSequence { points, closed }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True without points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Number of segments: one per consecutive pair, plus the closing one of a closed curve.
    pub fn segment_count(&self) -> usize {
        segment_count(self.points.len(), self.closed)
    }

    /// Chord length of every segment; segment `e` joins point `e` to point `e + 1` (mod n).
    pub fn chord_lengths(&self) -> Vec<f64> {
        chord_lengths(&self.points, self.closed)
    }

    /// Cumulative chord length at every point, starting at 0.
    pub fn arc_lengths(&self) -> Vec<f64> {
        arc_lengths(&self.points)
    }

    /// Length of the polyline, the closing segment included for a closed one.
    pub fn total_length(&self) -> f64 {
        self.chord_lengths().iter().sum()
    }

    /// Corners of the axis-aligned bounding box, `None` without points.
    pub fn bounding_box(&self) -> Option<(DVec3, DVec3)> {
        crate::mesh::bounding_box(&self.points)
    }

    /// Diagonal of the bounding box (0 without points).
    pub fn diagonal(&self) -> f64 {
        self.bounding_box().map_or(0.0, |(lo, hi)| (hi - lo).length())
    }

    /// The point before `i` and the one after it, if it has both (always, on a closed curve of
    /// three points or more).
    pub fn neighbours(&self, i: usize) -> Option<(usize, usize)> {
        let n = self.points.len();
        if self.closed && n >= 3 {
            Some(((i + n - 1) % n, (i + 1) % n))
        } else if i > 0 && i + 1 < n {
            Some((i - 1, i + 1))
        } else {
            None
        }
    }

    /// Checks that the points make a curve: at least `least` of them, all finite, no two
    /// consecutive ones (the last and first of a closed curve included) closer than `1e-12` of
    /// the curve's size, and a size of at most `1e100`. Messages name the offending point.
    pub fn validate(&self, least: usize) -> Result<()> {
        let bad = |m: String| Err(Error::Input(m));
        let n = self.points.len();
        if n < least {
            let kind = if self.closed { "a closed" } else { "an open" };
            return bad(format!("{kind} curve needs at least {least} points here, got {n}"));
        }
        if let Some(i) = self.points.iter().position(|p| !p.is_finite()) {
            let p = self.points[i];
            return bad(format!("point {i} has a non-finite coordinate ({}, {}, {})", p.x, p.y, p.z));
        }
        let size = self.diagonal();
        if !(size > 0.0 && size <= 1e100) {
            return bad(if size == 0.0 {
                "all points of the curve coincide: there is no curve".into()
            } else {
                format!("the curve's size {size:e} is too large (at most 1e100); rescale it")
            });
        }
        for (e, length) in self.chord_lengths().iter().enumerate() {
            if *length <= 1e-12 * size {
                let next = (e + 1) % n;
                return bad(format!(
                    "points {e} and {next} are at the same place ({:?}); remove the repeated point",
                    self.points[e].to_array()
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_of_a_square() {
        let square = PointSequence::new(vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y], true);
        assert_eq!(square.segment_count(), 4);
        assert_eq!(square.chord_lengths(), vec![1.0; 4]);
        assert_eq!(square.arc_lengths(), vec![0.0, 1.0, 2.0, 3.0]);
        assert_eq!(square.total_length(), 4.0);
        assert_eq!(square.neighbours(0), Some((3, 1)));
        let open = PointSequence { closed: false, ..square };
        assert_eq!(open.total_length(), 3.0);
        assert_eq!((open.neighbours(0), open.neighbours(3), open.neighbours(2)), (None, None, Some((1, 3))));
    }

    #[test]
    fn bad_points_are_named() {
        let err = |points: Vec<DVec3>, closed| PointSequence::new(points, closed).validate(3).unwrap_err().to_string();
        assert!(err(vec![DVec3::ZERO, DVec3::X], false).contains("at least 3 points"));
        assert!(err(vec![DVec3::ZERO, DVec3::X, DVec3::X, DVec3::Y], false).contains("points 1 and 2"));
        assert!(err(vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ZERO], true).contains("points 3 and 0"));
        assert!(err(vec![DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Y], false).contains("point 1"));
        assert!(err(vec![DVec3::ONE; 3], false).contains("coincide"));
        assert!(PointSequence::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ZERO], false).validate(3).is_ok());
    }
}
