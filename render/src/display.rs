//! [`DisplayFrame`]: the map from Taut's f64 model coordinates to the f32 coordinates the GPU
//! draws in.
//!
//! The GPU works in f32, which cannot hold a cage near 1e308 (it overflows to infinity) or one of
//! size 1e-300 (it underflows to zero), and loses the shape of a small part far from the origin.
//! Everything is therefore drawn relative to a frame chosen from the model's bounding box: its
//! centre becomes the origin and its half-extent the unit, computed in f64 without overflow, so
//! any finite cage draws as a shape of size about 1 around the origin. The camera lives in these
//! display coordinates; picking and dragging convert through the same frame.

use glam::{DVec3, Vec3};

/// Display coordinates are `(p − origin) / scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplayFrame {
    pub origin: DVec3,
    pub scale: f64,
}

impl Default for DisplayFrame {
    fn default() -> Self {
        DisplayFrame::IDENTITY
    }
}

impl DisplayFrame {
    /// Model coordinates drawn as they are.
    pub const IDENTITY: DisplayFrame = DisplayFrame { origin: DVec3::ZERO, scale: 1.0 };

    /// The frame for a bounding box: its centre at the origin, its largest half-extent as the unit
    /// (1 for an empty or single-point box). Never overflows for finite corners.
    pub fn for_bounds(lo: DVec3, hi: DVec3) -> Self {
        if !(lo.is_finite() && hi.is_finite()) {
            return DisplayFrame::IDENTITY;
        }
        // Halving first keeps the sum and the difference of two huge values finite.
        let origin = lo * 0.5 + hi * 0.5;
        let half = (hi * 0.5 - lo * 0.5).max_element();
        let scale = if half > 0.0 && half.is_finite() { half } else { 1.0 };
        DisplayFrame { origin, scale }
    }

    /// The frame for a set of points (see [`for_bounds`](Self::for_bounds)).
    pub fn for_points(points: &[DVec3]) -> Self {
        match taut_core::mesh::bounding_box(points) {
            Some((lo, hi)) => Self::for_bounds(lo, hi),
            None => DisplayFrame::IDENTITY,
        }
    }

    /// A model point in display coordinates, in f64.
    #[inline]
    pub fn to_display_f64(&self, p: DVec3) -> DVec3 {
        let d = p - self.origin;
        if d.is_finite() { d / self.scale } else { p / self.scale - self.origin / self.scale }
    }

    /// A model point in display coordinates.
    #[inline]
    pub fn point(&self, p: DVec3) -> Vec3 {
        self.to_display_f64(p).as_vec3()
    }

    /// A display point back in model coordinates.
    #[inline]
    pub fn to_model(&self, p: DVec3) -> DVec3 {
        p * self.scale + self.origin
    }

    /// A model length in display units.
    #[inline]
    pub fn length(&self, l: f64) -> f64 {
        l / self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extreme_boxes_map_to_unit_size() {
        for (lo, hi) in [
            (DVec3::splat(-1.7e308), DVec3::splat(1.7e308)),
            (DVec3::splat(1e308), DVec3::new(1.5e308, 1.2e308, 1.1e308)),
            (DVec3::ZERO, DVec3::splat(3e-300)),
            (DVec3::new(1e6, 1e6, 1e6), DVec3::new(1e6 + 1e-3, 1e6 + 2e-3, 1e6)),
        ] {
            let frame = DisplayFrame::for_bounds(lo, hi);
            for corner in [lo, hi] {
                let d = frame.point(corner);
                assert!(d.is_finite() && d.abs().max_element() <= 1.0 + 1e-6, "{corner} -> {d}");
                let back = frame.to_model(frame.to_display_f64(corner));
                assert!((back - corner).abs().max_element() <= 1e-12 * corner.abs().max_element().max(frame.scale));
            }
            assert!(frame.point(hi).max_element() > 0.9, "the box spans the unit");
        }
    }
}
