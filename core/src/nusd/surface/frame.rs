//! The solver's internal frame: the cage scaled by a power of two when its size is extreme.
//!
//! `K` grows with the square of the spacing and `R` with its inverse square, so a cage 1e-200 or
//! 1e300 across underflows or overflows in the iteration although every input coordinate is an
//! ordinary finite number. Multiplying by a power of two is exact in binary floating point (no
//! rounding, barring overflow and subnormals), and every operation of the method commutes with
//! it, so solving the scaled cage and scaling back gives bit for bit the scaled result. Cages
//! within [`SAFE_RANGE`] are not scaled at all (their results are untouched); others are scaled
//! by an even power of two (so the centripetal `sqrt` spacing stays exact) to a size near 1.
//!
//! `R` scales as `length / K`: with chord spacing as 1/length, uniform spacing as a length, and
//! centripetal spacing not at all.

use crate::DVec3;
use crate::nusd::Spacing;

/// Bounding-box diagonals in `[2^-SAFE_RANGE, 2^SAFE_RANGE]` (about 1e-90 to 1e90) are solved
/// as they are.
pub const SAFE_RANGE: i32 = 300;

/// Internal coordinates are the designer's multiplied by `2^-exponent`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Frame {
    exponent: i32,
}

impl Frame {
    /// The frame for a cage whose bounding box is `lo`..`hi` (finite corners).
    pub fn for_box(lo: DVec3, hi: DVec3) -> Frame {
        let size = half_extent(lo, hi);
        if !(size > 0.0 && size.is_finite()) {
            return Frame::default();
        }
        // log2 of the diagonal, up to a factor below 2 (the half-extent's largest component).
        let log2 = size.log2().floor() as i32 + 1;
        if (-SAFE_RANGE..=SAFE_RANGE).contains(&log2) {
            return Frame::default();
        }
        Frame { exponent: log2 & !1 }
    }

    /// True when internal and designer coordinates are the same.
    pub fn is_identity(&self) -> bool {
        self.exponent == 0
    }

    /// Designer length → internal length.
    pub fn to_internal(&self, x: DVec3) -> DVec3 {
        x * pow2(-self.exponent / 2) * pow2(-self.exponent / 2)
    }

    /// Internal length → designer length.
    pub fn length_out(&self, x: f64) -> f64 {
        x * pow2(self.exponent / 2) * pow2(self.exponent / 2)
    }

    /// Internal position → designer position.
    pub fn position_out(&self, x: DVec3) -> DVec3 {
        x * pow2(self.exponent / 2) * pow2(self.exponent / 2)
    }

    /// Internal second derivative → designer second derivative, for the spacing in use.
    pub fn second_derivative_out(&self, r: DVec3, spacing: Spacing) -> DVec3 {
        let e = match spacing {
            Spacing::Chord => -self.exponent,
            Spacing::Uniform => self.exponent,
            Spacing::Centripetal => 0,
        };
        r * pow2(e / 2) * pow2(e / 2)
    }
}

/// The largest component of half the box's extent: a size that never overflows.
pub fn half_extent(lo: DVec3, hi: DVec3) -> f64 {
    (0.5 * hi - 0.5 * lo).abs().max_element()
}

/// `2^e` for `|e| ≤ 1023`, exactly.
fn pow2(e: i32) -> f64 {
    f64::from_bits(((e + 1023) as u64) << 52)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinary_sizes_are_left_alone_and_extreme_ones_scaled_exactly() {
        assert!(Frame::for_box(DVec3::ZERO, DVec3::splat(80.0)).is_identity());
        assert!(Frame::for_box(DVec3::ZERO, DVec3::splat(1e-80)).is_identity());
        for size in [1e-200, 1e-300, 1e100, 1e300, f64::MAX / 2.0] {
            let frame = Frame::for_box(DVec3::splat(-size), DVec3::splat(size));
            assert!(!frame.is_identity());
            assert_eq!(frame.exponent % 2, 0);
            let p = DVec3::new(size, -0.3 * size, 0.7 * size);
            let inside = frame.to_internal(p);
            assert!((0.25..4.0).contains(&inside.x), "{size:e} → {inside}");
            assert_eq!(frame.position_out(inside), p, "scaling by a power of two is exact");
        }
    }

    #[test]
    fn second_derivatives_scale_with_the_units_of_their_spacing() {
        let frame = Frame::for_box(DVec3::ZERO, DVec3::splat(1e200));
        let f = frame.length_out(1.0);
        let r = DVec3::ONE;
        assert_eq!(frame.second_derivative_out(r, Spacing::Chord), r / f);
        assert_eq!(frame.second_derivative_out(r, Spacing::Uniform), r * f);
        assert_eq!(frame.second_derivative_out(r, Spacing::Centripetal), r);
    }
}
