//! The two analysis views beside zebra and curvature colour, as the CPU computes them: the draft
//! angle against a pull direction (moulded parts) and highlight lines from a set of parallel
//! light tubes (the car designer's check). `shaders/surface.wgsl` computes the same per pixel
//! from the exact normals (modes 4 and 5); these functions are its reference, for the tests and
//! for readers.
//!
//! **Draft angle.** The angle between the surface and the pull direction `p`: 90° less the angle
//! between the normal `n` and `p`, so `asin(n·p)` for unit vectors. A wall parallel to the pull
//! has draft 0 and cannot leave the mould; a face turned towards the pull has positive draft, one
//! turned away negative draft (an undercut for a mould half pulled along `p`). Faces within the
//! user's threshold of 0 form the band "needs draft". The sign follows the surface's own normals
//! (outward on a closed part), not the side the camera sees.
//!
//! **Highlight lines** (Beier and Chen, "Highlight-line algorithm for realtime surface-quality
//! assessment", CAD 26(4), 1994). Parallel light tubes along `E` lie in a plane with unit normal
//! `H` at `height` above the display origin (the model's centre), `spacing` apart across the
//! direction `D = E × H`. A point `P` with normal `N` lies on the highlight line of a tube when
//! its normal line `P + μN` meets that tube; equivalently, where the normal line pierces the
//! tubes' plane, `Q = P + μN` with `(Q − height·H)·H = 0`, the coordinate `(Q·D) / spacing` is the
//! tube's index (eq. 3 of the paper written with the plane). Unlike zebra, the lines do not move
//! with the camera, and they do not depend on which way the normal points. Weak where the normal
//! lies in the tubes' plane direction (`N·H → 0`): the normal line meets the plane far away and
//! the lines crowd; the shader greys such regions rather than drawing noise.

use glam::DVec3;

/// Colours of the draft view (sRGB): positive draft green, the band below the threshold yellow,
/// negative draft (undercut) red, as in the draft analyses of SolidWorks and NX. Their
/// lightness differs too (light yellow, mid green, dark red), so they stay apart for the
/// colour-blind and in grey.
pub const DRAFT_POSITIVE: [u8; 3] = [60, 170, 80];
pub const DRAFT_BELOW: [u8; 3] = [250, 215, 50];
pub const DRAFT_NEGATIVE: [u8; 3] = [180, 35, 40];

/// The default draft threshold, degrees (a common minimum for injection-moulded plastic).
pub const DEFAULT_DRAFT_DEGREES: f64 = 3.0;

/// The largest draft threshold a user may set, degrees.
pub const MAX_DRAFT_DEGREES: f64 = 89.0;

/// The draft angle in degrees, in [−90, 90], of a surface with normal `normal` against the pull
/// direction `pull` (neither needs to be unit length; `None` when either is zero or not finite).
pub fn draft_degrees(normal: DVec3, pull: DVec3) -> Option<f64> {
    let (n, p) = (normal.try_normalize()?, pull.try_normalize()?);
    Some(n.dot(p).clamp(-1.0, 1.0).asin().to_degrees())
}

/// Where a draft angle falls against the threshold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DraftClass {
    /// At least the threshold, turned towards the pull: leaves the mould.
    Positive,
    /// Within the threshold of 0: a wall that needs more draft.
    BelowThreshold,
    /// At least the threshold, turned away from the pull: an undercut for this mould half.
    Negative,
}

impl DraftClass {
    /// The class of `draft` degrees against `threshold` degrees (the band is open: a draft of
    /// exactly the threshold passes, as the shader draws it).
    pub fn of(draft: f64, threshold: f64) -> DraftClass {
        if draft >= threshold {
            DraftClass::Positive
        } else if draft <= -threshold {
            DraftClass::Negative
        } else {
            DraftClass::BelowThreshold
        }
    }

    /// The class's colour (sRGB).
    pub fn color(self) -> [u8; 3] {
        match self {
            DraftClass::Positive => DRAFT_POSITIVE,
            DraftClass::BelowThreshold => DRAFT_BELOW,
            DraftClass::Negative => DRAFT_NEGATIVE,
        }
    }

    /// The legend's words for the class at `threshold` degrees.
    pub fn label(self, threshold: f64) -> String {
        // Tenths of a degree, without a trailing ".0".
        let threshold = (threshold * 10.0).round() / 10.0;
        match self {
            DraftClass::Positive => format!("draft ≥ {threshold}°"),
            DraftClass::BelowThreshold => format!("below {threshold}°: needs draft"),
            DraftClass::Negative => format!("draft ≤ −{threshold}°: undercut"),
        }
    }

    pub const ALL: [DraftClass; 3] = [DraftClass::Positive, DraftClass::BelowThreshold, DraftClass::Negative];
}

/// The pull direction of the draft view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pull {
    /// A fixed direction in model coordinates (any length but zero).
    Direction(DVec3),
    /// Towards the camera: what faces the viewer leaves a mould pulled towards the viewer.
    View,
}

/// The default tubes' direction (along the model's X, the length of a car).
pub const DEFAULT_TUBE_DIRECTION: DVec3 = DVec3::X;
/// The default number of tubes.
pub const DEFAULT_TUBE_COUNT: u32 = 15;
/// The default spacing as a fraction of the model's largest half-extent (the display unit).
pub const DEFAULT_TUBE_SPACING: f64 = 0.25;
/// The tubes' plane above the model's centre, in the model's largest half-extent.
pub const TUBE_HEIGHT: f64 = 1.5;

/// Parallel light tubes, in display coordinates (the model's centre at the origin and its
/// largest half-extent as the unit, see [`crate::DisplayFrame`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightTubes {
    /// Along the tubes (any length but zero).
    pub direction: DVec3,
    /// Between neighbouring tubes.
    pub spacing: f64,
    pub count: u32,
    /// The tubes' plane's distance from the origin along [`plane_normal`](Self::plane_normal).
    pub height: f64,
}

impl Default for LightTubes {
    fn default() -> Self {
        LightTubes {
            direction: DEFAULT_TUBE_DIRECTION,
            spacing: DEFAULT_TUBE_SPACING,
            count: DEFAULT_TUBE_COUNT,
            height: TUBE_HEIGHT,
        }
    }
}

impl LightTubes {
    /// The unit direction along the tubes (X when `direction` is zero).
    pub fn axis(&self) -> DVec3 {
        self.direction.try_normalize().unwrap_or(DVec3::X)
    }

    /// The normal `H` of the tubes' plane: overhead (+Z, Taut's up) made perpendicular to the
    /// tubes, as the ceiling lights of a studio; for tubes within 25° of vertical, the front
    /// (−Y, where the default camera stands) instead.
    pub fn plane_normal(&self) -> DVec3 {
        let e = self.axis();
        let toward = if e.z.abs() < 0.9 { DVec3::Z } else { -DVec3::Y };
        (toward - toward.dot(e) * e).normalize()
    }

    /// The unit direction `D = E × H` across the tubes, along which they are spaced.
    pub fn across(&self) -> DVec3 {
        self.axis().cross(self.plane_normal())
    }

    /// The tube coordinate of point `p` with normal `n`: where the normal line meets the tubes'
    /// plane, across the tubes in units of the spacing, 0 at the first tube and `count − 1` at
    /// the last. A highlight line is where it is an integer in that range. `None` where the
    /// normal line is parallel to the plane.
    pub fn coordinate(&self, p: DVec3, n: DVec3) -> Option<f64> {
        let h = self.plane_normal();
        let nh = n.dot(h);
        if nh.abs() < 1e-12 {
            return None;
        }
        let mu = (self.height - p.dot(h)) / nh;
        let q = p + mu * n;
        Some(q.dot(self.across()) / self.spacing + 0.5 * (self.count as f64 - 1.0))
    }

    /// The offset of tube `k` across the tubes from the plane's centre.
    pub fn offset(&self, k: u32) -> f64 {
        (k as f64 - 0.5 * (self.count as f64 - 1.0)) * self.spacing
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A cone of half-angle α (between the axis and the surface), axis along +Z, apex up: the
    /// outward normal at angle θ around the axis is (cos α cos θ, cos α sin θ, sin α), so the
    /// draft against +Z is α everywhere, and −α against −Z.
    #[test]
    fn the_draft_of_a_cone_is_its_half_angle() {
        for alpha_deg in [0.5_f64, 3.0, 10.0, 45.0, 80.0] {
            let alpha = alpha_deg.to_radians();
            for k in 0..24 {
                let theta = 2.0 * PI * k as f64 / 24.0;
                let n = DVec3::new(alpha.cos() * theta.cos(), alpha.cos() * theta.sin(), alpha.sin());
                let up = draft_degrees(n, DVec3::new(0.0, 0.0, 2.5)).unwrap();
                assert!((up - alpha_deg).abs() < 1e-9, "α {alpha_deg}: draft {up}");
                let down = draft_degrees(n, -DVec3::Z).unwrap();
                assert!((down + alpha_deg).abs() < 1e-9, "α {alpha_deg}: draft {down} pulled down");
                // A pull tilted by β in the XZ plane: the generator at θ = 0 then has draft α + β.
                if k == 0 {
                    let beta = 7.0_f64.to_radians();
                    let tilted = draft_degrees(n, DVec3::new(beta.sin(), 0.0, beta.cos())).unwrap();
                    assert!((tilted - (alpha_deg + 7.0)).abs() < 1e-9, "{tilted}");
                }
            }
            assert_eq!(DraftClass::of(alpha_deg, alpha_deg - 0.1), DraftClass::Positive);
            assert_eq!(DraftClass::of(alpha_deg, alpha_deg + 0.1), DraftClass::BelowThreshold);
            assert_eq!(DraftClass::of(-alpha_deg, alpha_deg - 0.1), DraftClass::Negative);
        }
        assert_eq!(draft_degrees(DVec3::ZERO, DVec3::Z), None);
        assert_eq!(draft_degrees(DVec3::X, DVec3::ZERO), None);
    }

    /// On a cylinder of radius R along the tubes, the normal line passes through the axis, so it
    /// meets the plane at height h (the axis at the origin) at `h tan θ` across the tubes: the
    /// highlight line of the tube at offset `c` lies at `θ = atan(c / h)`, a point `R sin θ`
    /// across and `R cos θ` up.
    #[test]
    fn highlight_lines_on_a_cylinder_lie_where_the_closed_form_puts_them() {
        let tubes = LightTubes { direction: DVec3::X, spacing: 0.3, count: 9, height: 1.7 };
        assert_eq!(tubes.plane_normal(), DVec3::Z);
        assert_eq!(tubes.across(), -DVec3::Y);
        let radius = 0.8;
        for k in 0..tubes.count {
            let theta = (tubes.offset(k) / tubes.height).atan();
            // The point on the cylinder whose normal turns by θ towards D = −Y.
            let n = DVec3::new(0.0, -theta.sin(), theta.cos());
            for x in [-0.9, 0.0, 0.4] {
                let p = DVec3::new(x, 0.0, 0.0) + radius * n;
                let u = tubes.coordinate(p, n).unwrap();
                assert!((u - k as f64).abs() < 1e-9, "tube {k}: coordinate {u}");
                // The coordinate does not care which way the normal points.
                assert!((tubes.coordinate(p, -n).unwrap() - u).abs() < 1e-9);
            }
        }
        // Half-way between two lines the coordinate is half-way between two tubes.
        let mid = ((tubes.offset(3) + tubes.offset(4)) / 2.0 / tubes.height).atan();
        let n = DVec3::new(0.0, -mid.sin(), mid.cos());
        assert!((tubes.coordinate(radius * n, n).unwrap() - 3.5).abs() < 1e-9);
        // A normal parallel to the plane never meets it.
        assert_eq!(tubes.coordinate(DVec3::ZERO, DVec3::Y), None);
    }

    #[test]
    fn vertical_tubes_hang_in_front() {
        let tubes = LightTubes { direction: DVec3::new(0.1, 0.0, -1.0), ..LightTubes::default() };
        let h = tubes.plane_normal();
        assert!(h.dot(tubes.axis()).abs() < 1e-12 && (h.length() - 1.0).abs() < 1e-12);
        assert!(h.y < -0.99, "{h}");
    }
}
