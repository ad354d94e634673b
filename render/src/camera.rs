//! The orbit camera shared by the editor's viewport and off-screen pictures.
//!
//! Z is up. The camera looks at `target` from `distance` away; `azimuth` turns it around Z
//! (0° looks from −Y towards +Y, the front view; 90° from +X, the right view) and `elevation`
//! lifts it (90° is the top view).
//!
//! The projection is perspective or orthographic ([`Camera::orthographic`], numpad 5 in the
//! editor). Orthographic keeps the scale perspective has at the target (half the view's height is
//! `distance · tan(fov_y / 2)` in both), so toggling does not jump; its eye is moved back along
//! the view direction ([`Camera::eye`]) so nothing of the model is behind it, which keeps every
//! depth test, near-plane cut and "in front of the eye" check of perspective valid unchanged.

use glam::{Mat4, Vec3};

/// How much of the viewport's tighter side [`Camera::frame_points`] fills.
pub const FRAME_FILL: f32 = 0.9;

/// How far past the target, in display units, an orthographic eye stands at least: the editor
/// and the pictures draw the model within the unit box around the origin
/// ([`crate::DisplayFrame`]), so this leaves it all in front whatever the zoom.
const ORTHO_CLEARANCE: f32 = 20.0;

/// An orbiting camera, perspective or orthographic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub target: Vec3,
    pub distance: f32,
    /// Degrees around Z.
    pub azimuth: f32,
    /// Degrees above the XY plane, in [−90, 90].
    pub elevation: f32,
    /// Vertical field of view, degrees; in orthographic projection it still sets the scale
    /// (what a perspective view would show at the target's depth).
    pub fov_y: f32,
    /// Parallel projection: lines parallel in the model stay parallel on screen.
    pub orthographic: bool,
}

/// The views a designer reaches with one key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StandardView {
    Front,
    Back,
    Left,
    Right,
    Top,
    Bottom,
    Perspective,
}

impl Default for Camera {
    fn default() -> Self {
        Camera { target: Vec3::ZERO, distance: 5.0, azimuth: 30.0, elevation: 25.0, fov_y: 35.0, orthographic: false }
    }
}

impl Camera {
    /// Unit vector from the target towards the eye.
    pub fn backward(&self) -> Vec3 {
        let (az, el) = (self.azimuth.to_radians(), self.elevation.to_radians());
        Vec3::new(az.sin() * el.cos(), -az.cos() * el.cos(), el.sin())
    }

    /// Eye position. Orthographic: far enough back that the whole display box is in front of
    /// it (only the direction matters to a parallel projection).
    pub fn eye(&self) -> Vec3 {
        self.target + self.eye_distance() * self.backward()
    }

    /// How far the eye is from the target.
    fn eye_distance(&self) -> f32 {
        if self.orthographic { self.distance + self.target.length() + ORTHO_CLEARANCE } else { self.distance }
    }

    /// Half the view's height at the target, in world units: the scale both projections share.
    pub fn half_height(&self) -> f32 {
        self.distance * (self.fov_y.to_radians() * 0.5).tan()
    }

    /// The world size of one pixel of a viewport `height` pixels high, at `depth` in front of the
    /// eye (orthographic: the same at every depth).
    pub fn pixel_size(&self, depth: f32, height: f32) -> f32 {
        let at_depth = if self.orthographic { self.distance } else { depth };
        2.0 * at_depth * (self.fov_y.to_radians() * 0.5).tan() / height.max(1.0)
    }

    /// Screen right, in world space.
    pub fn right(&self) -> Vec3 {
        let az = self.azimuth.to_radians();
        Vec3::new(az.cos(), az.sin(), 0.0)
    }

    /// Screen up, in world space.
    pub fn up(&self) -> Vec3 {
        self.backward().cross(self.right()).normalize()
    }

    pub fn view_from_world(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, self.up())
    }

    /// The projection, with a near and far plane that follow the distance; depth in [0, 1].
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        if self.orthographic {
            let (h, eye) = (self.half_height().max(1e-9), self.eye_distance());
            let w = h * aspect.max(1e-6);
            // The whole display box lies between these: the eye stands the clearance behind it.
            let near = ORTHO_CLEARANCE * 0.5;
            let far = eye + self.distance * 100.0 + ORTHO_CLEARANCE;
            return glam::camera::rh::proj::directx::orthographic(-w, w, -h, h, near, far);
        }
        let near = (self.distance * 0.01).max(1e-6);
        // wgpu's clip space: depth in [0, 1], y up (glam's `directx` convention).
        glam::camera::rh::proj::directx::perspective(
            self.fov_y.to_radians(),
            aspect.max(1e-6),
            near,
            self.distance * 100.0,
        )
    }

    /// Turns the camera around the target.
    pub fn orbit(&mut self, d_azimuth: f32, d_elevation: f32) {
        self.azimuth = (self.azimuth + d_azimuth).rem_euclid(360.0);
        self.elevation = (self.elevation + d_elevation).clamp(-90.0, 90.0);
    }

    /// Moves target and eye in the view plane by a number of pixels of a viewport `height`
    /// pixels high, so the point under the cursor follows the cursor.
    pub fn pan(&mut self, dx_pixels: f32, dy_pixels: f32, height: f32) {
        let per_pixel = self.pixel_size(self.distance, height);
        self.target += (-dx_pixels * self.right() + dy_pixels * self.up()) * per_pixel;
    }

    /// Multiplies the distance (below 1 zooms in).
    pub fn zoom(&mut self, factor: f32) {
        self.distance = (self.distance * factor).clamp(1e-6, 1e9);
    }

    /// Frames a bounding box so all of it is in view with a small margin, whatever the direction
    /// the camera looks from (the box's bounding sphere fits the narrower side of a square view).
    pub fn frame(&mut self, min: Vec3, max: Vec3) {
        let radius = ((max - min).length() * 0.5).max(1e-6);
        self.target = (min + max) * 0.5;
        let half_angle = self.fov_y.to_radians() * 0.5;
        // Perspective: the sphere's tangent cone; orthographic: its silhouette, a circle.
        let fit = if self.orthographic { half_angle.tan() } else { half_angle.sin() };
        self.distance = 1.1 * radius / fit;
    }

    /// Frames `points` seen from the current direction so they fill [`FRAME_FILL`] of a viewport
    /// of aspect `aspect` (width over height) along its tighter side, centred on screen. This is
    /// what "frame all" does: the model fills the view instead of its bounding sphere.
    pub fn frame_points(&mut self, points: &[Vec3], aspect: f32) {
        let Some(first) = points.first() else { return };
        let (lo, hi) = points.iter().fold((*first, *first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let (right, up, back) = (self.right(), self.up(), self.backward());
        // Centre the projected extent: the middle of the points along right and up, and the
        // middle of the box in depth.
        let centre = (lo + hi) * 0.5;
        let span = |axis: Vec3| {
            points.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &p| {
                let x = (p - centre).dot(axis);
                (a.min(x), b.max(x))
            })
        };
        let ((r0, r1), (u0, u1)) = (span(right), span(up));
        self.target = centre + right * (r0 + r1) * 0.5 + up * (u0 + u1) * 0.5;
        let tan_v = (self.fov_y.to_radians() * 0.5).tan() * FRAME_FILL;
        let tan_h = tan_v * aspect.max(1e-3);
        if self.orthographic {
            // No depth: the centred extent alone sets the scale.
            let (half_x, half_y) = ((r1 - r0) * 0.5, (u1 - u0) * 0.5);
            self.distance = (half_x / tan_h).max(half_y / tan_v).max(1e-6);
            return;
        }
        // Perspective makes the near side look larger: fit the distance, then move the target so
        // the projected extent is centred, and fit again.
        let fit = |target: Vec3| {
            points.iter().fold(1e-6f32, |d, &p| {
                let q = p - target;
                let (x, y, z) = (q.dot(right).abs(), q.dot(up).abs(), q.dot(back));
                d.max(z + x / tan_h).max(z + y / tan_v)
            })
        };
        for _ in 0..6 {
            let distance = fit(self.target);
            let (mut x0, mut x1, mut y0, mut y1) = (f32::INFINITY, f32::NEG_INFINITY, f32::INFINITY, f32::NEG_INFINITY);
            for &p in points {
                let q = p - self.target;
                let depth = (distance - q.dot(back)).max(1e-9);
                let (x, y) = (q.dot(right) / depth, q.dot(up) / depth);
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
            // Shift by the offset of the centre, measured at the target's depth.
            self.target += right * (x0 + x1) * 0.5 * distance + up * (y0 + y1) * 0.5 * distance;
        }
        let distance = fit(self.target);
        let size = (hi - lo).length().max(1e-6);
        // Never inside the model: the eye stays at least its depth in front.
        self.distance = distance.max(0.5 * size + 0.02 * size);
    }

    /// Jumps to a standard view, keeping target and distance.
    pub fn set_view(&mut self, view: StandardView) {
        let (az, el) = match view {
            StandardView::Front => (0.0, 0.0),
            StandardView::Back => (180.0, 0.0),
            StandardView::Right => (90.0, 0.0),
            StandardView::Left => (270.0, 0.0),
            StandardView::Top => (0.0, 90.0),
            StandardView::Bottom => (0.0, -90.0),
            StandardView::Perspective => (30.0, 25.0),
        };
        self.azimuth = az;
        self.elevation = el;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_look_where_their_names_say() {
        let mut c = Camera { distance: 10.0, ..Default::default() };
        c.set_view(StandardView::Front);
        assert!((c.eye() - Vec3::new(0.0, -10.0, 0.0)).length() < 1e-5);
        c.set_view(StandardView::Right);
        assert!((c.eye() - Vec3::new(10.0, 0.0, 0.0)).length() < 1e-4);
        c.set_view(StandardView::Top);
        assert!((c.eye() - Vec3::new(0.0, 0.0, 10.0)).length() < 1e-4);
        // The top view still has a well-defined up (screen up is +Y).
        assert!((c.up() - Vec3::Y).length() < 1e-5);
    }

    #[test]
    fn target_projects_to_the_centre_and_frame_fits_the_box() {
        for orthographic in [false, true] {
            let mut c = Camera { orthographic, ..Camera::default() };
            let (lo, hi) = (Vec3::new(-1.0, 2.0, 0.0), Vec3::new(3.0, 4.0, 5.0));
            c.frame(lo, hi);
            let clip = c.clip_from_view(1.6) * c.view_from_world();
            let centre = clip.project_point3((lo + hi) * 0.5);
            assert!(centre.truncate().length() < 1e-5);
            for corner in 0..8 {
                let p = Vec3::new(
                    if corner & 1 == 0 { lo.x } else { hi.x },
                    if corner & 2 == 0 { lo.y } else { hi.y },
                    if corner & 4 == 0 { lo.z } else { hi.z },
                );
                let q = clip.project_point3(p);
                assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0 && (0.0..=1.0).contains(&q.z), "{corner}: {q}");
            }
        }
    }

    #[test]
    fn framing_points_fills_the_view_along_its_tighter_side() {
        // A flat wide plate seen from the front at aspect 1.6: it should span 90 % of the width
        // or of the height, whichever binds first, and stay inside both.
        let points: Vec<Vec3> = (0..=20)
            .flat_map(|i| (0..=4).map(move |k| Vec3::new(-3.0 + 0.3 * i as f32, 0.0, -0.5 + 0.25 * k as f32)))
            .collect();
        for (azimuth, aspect) in [(0.0, 1.6), (35.0, 1.6), (0.0, 0.5)] {
            for orthographic in [false, true] {
                let mut c = Camera { azimuth, elevation: 10.0, orthographic, ..Default::default() };
                c.frame_points(&points, aspect);
                let clip = c.clip_from_view(aspect) * c.view_from_world();
                let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
                for &p in &points {
                    let q = clip.project_point3(p);
                    lo = lo.min(q);
                    hi = hi.max(q);
                }
                assert!(lo.x >= -0.901 && hi.x <= 0.901 && lo.y >= -0.901 && hi.y <= 0.901, "{lo} {hi}");
                let fill = (hi.x - lo.x).max(hi.y - lo.y) / 2.0;
                assert!(fill > 0.88, "fills {fill} at azimuth {azimuth}, aspect {aspect}");
                assert!(((hi.x + lo.x) / 2.0).abs() < 0.05 && ((hi.y + lo.y) / 2.0).abs() < 0.05, "centred");
            }
        }
    }

    #[test]
    fn pan_moves_the_target_by_the_pixels_dragged() {
        let mut c = Camera::default();
        let before = c.clip_from_view(1.0) * c.view_from_world();
        let start = c.target;
        c.pan(100.0, 0.0, 800.0);
        // The old target now sits 100 px to the right of the centre (NDC 2·100/800).
        let ndc = (c.clip_from_view(1.0) * c.view_from_world()).project_point3(start);
        assert!((ndc.x - 0.25).abs() < 1e-4 && ndc.y.abs() < 1e-4, "{ndc}");
        let _ = before;
    }
}
