//! The colour maps of the curvature view, as 256-entry sRGB tables. The same table is sampled by
//! the surface shader and drawn as the legend's bar, so the two can never disagree.
//!
//! - diverging (signed quantities, centred at 0): ColorBrewer RdBu, blue for negative, white at
//!   0, red for positive;
//! - sequential (magnitudes): viridis, perceptually uniform.

/// Which map a quantity uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorMap {
    Diverging,
    Sequential,
}

/// Number of entries of a table.
pub const SIZE: usize = 256;

const DIVERGING: [[u8; 3]; 11] = [
    [5, 48, 97],
    [33, 102, 172],
    [67, 147, 195],
    [146, 197, 222],
    [209, 229, 240],
    [247, 247, 247],
    [253, 219, 199],
    [244, 165, 130],
    [214, 96, 77],
    [178, 24, 43],
    [103, 0, 31],
];

const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

impl ColorMap {
    /// Colour at `t ∈ [0, 1]` (clamped), interpolated between the control colours.
    pub fn color(self, t: f32) -> [u8; 3] {
        let stops: &[[u8; 3]] = match self {
            ColorMap::Diverging => &DIVERGING,
            ColorMap::Sequential => &VIRIDIS,
        };
        let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.5 };
        let x = t * (stops.len() - 1) as f32;
        let i = (x.floor() as usize).min(stops.len() - 2);
        let f = x - i as f32;
        let mix = |a: u8, b: u8| (a as f32 + (b as f32 - a as f32) * f).round() as u8;
        [mix(stops[i][0], stops[i + 1][0]), mix(stops[i][1], stops[i + 1][1]), mix(stops[i][2], stops[i + 1][2])]
    }

    /// The table uploaded as a 256 × 1 RGBA8 sRGB texture.
    pub fn table(self) -> Vec<[u8; 4]> {
        (0..SIZE)
            .map(|k| {
                let [r, g, b] = self.color(k as f32 / (SIZE - 1) as f32);
                [r, g, b, 255]
            })
            .collect()
    }
}

/// Values mapped to the colour range `[min, max]` as `[0, 1]` (clamped), in f64 before the
/// conversion to f32, so curvatures of any magnitude (1e300 on a tiny cage) colour correctly;
/// draw them with the range `0..1`. Non-finite values map to 0.5.
pub fn normalize(values: &[f64], min: f64, max: f64) -> Vec<f32> {
    let span = max - min;
    values
        .iter()
        .map(|&v| {
            let t = if span > 0.0 && span.is_finite() { (v - min) / span } else { 0.5 };
            if t.is_finite() { t.clamp(0.0, 1.0) as f32 } else { 0.5 }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_is_white_at_zero_and_blue_red_at_the_ends() {
        let map = ColorMap::Diverging;
        assert_eq!(map.color(0.5), [247, 247, 247]);
        let (lo, hi) = (map.color(0.0), map.color(1.0));
        assert!(lo[2] > lo[0] && hi[0] > hi[2]);
        // Symmetric lightness around the centre (RdBu is designed so).
        let luma = |c: [u8; 3]| 0.2126 * c[0] as f32 + 0.7152 * c[1] as f32 + 0.0722 * c[2] as f32;
        assert!((luma(map.color(0.3)) - luma(map.color(0.7))).abs() < 25.0);
    }

    #[test]
    fn viridis_lightness_increases_monotonically() {
        let table = ColorMap::Sequential.table();
        let luma = |c: [u8; 4]| 0.2126 * c[0] as f32 + 0.7152 * c[1] as f32 + 0.0722 * c[2] as f32;
        assert!(table.windows(2).all(|w| luma(w[1]) >= luma(w[0]) - 0.5));
        assert_eq!(table.len(), SIZE);
    }
}
