//! Viewport interaction as pure geometry: from window pixels to the cage and back.
//!
//! Everything here takes the orbit [`Camera`] and the viewport's [`ViewportRect`] and answers one
//! question: where does a point land on screen ([`project`]), which ray leaves a pixel
//! ([`unproject_ray`]), which vertex or edge is under the cursor ([`pick_vertex`],
//! [`pick_edge`]), which vertices lie in a rubber band ([`box_select`]), where a drag moves the
//! selection ([`drag_positions`]), and how mouse motion turns the camera ([`orbit_from_drag`],
//! [`zoom_factor`]). There is no window and no egui here, so all of it is tested without either.
//!
//! The camera's own matrices (`view_from_world`, `clip_from_view`) are the single source of the
//! projection, promoted to f64 so that picking and dragging agree with what the renderer draws
//! while keeping the cage's f64 precision. Drags are relative (they move the selection by the
//! motion of the cursor since the drag started), so grabbing a vertex away from the selection's
//! centroid never makes the selection jump.
//!
//! Weak spots: picking is a linear scan (fine for cages of a few thousand vertices, not for
//! refined meshes), and an axis drag whose axis points nearly at the eye has no good answer;
//! it then follows the screen-space projection of the axis at a bounded speed and is clamped to
//! [`MAX_DRAG_IN_DISTANCES`] camera distances.

use glam::{DMat4, DVec2, DVec3, DVec4, Vec2};
use taut_core::{EdgeId, PolyMesh, VertexId};
use taut_render::Camera;

/// Orbit speed: degrees of azimuth or elevation per pixel dragged (Blender's default orbit
/// sensitivity, 0.4°/px: a drag across a 900-pixel-wide viewport turns a full circle).
pub const ORBIT_DEGREES_PER_PIXEL: f32 = 0.4;

/// Distance factor of one wheel notch towards the scene (below 1: zooms in).
pub const ZOOM_PER_NOTCH: f32 = 0.9;

/// Two candidates for a pick whose screen distances differ by less than this many pixels look
/// like one dot to the designer; the one in front wins, as it is the one they see.
pub const PICK_TIE_PX: f32 = 0.5;

/// An axis drag never moves the selection further than this many camera distances.
pub const MAX_DRAG_IN_DISTANCES: f64 = 10.0;

/// An axis within this many degrees of the view ray through the selection counts as pointing at
/// the eye: the closest point between the mouse ray and the axis is then ill-conditioned, and
/// the drag follows the screen-space projection of the axis instead.
pub const AXIS_PARALLEL_DEGREES: f64 = 5.0;

/// The viewport's rectangle in window pixels (origin at the top left, y down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewportRect {
    pub min: Vec2,
    pub size: Vec2,
}

impl ViewportRect {
    /// Width over height, as the camera's projection wants it.
    pub fn aspect(&self) -> f32 {
        self.size.x / self.size.y.max(1e-6)
    }
}

/// A world axis for constrained drags.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// The unit vector along the axis.
    pub fn direction(self) -> DVec3 {
        match self {
            Axis::X => DVec3::X,
            Axis::Y => DVec3::Y,
            Axis::Z => DVec3::Z,
        }
    }
}

/// Where `p` lands in the viewport: its pixel and its depth in [0, 1] (0 on the near plane).
/// `None` when `p` is behind the camera or outside the depth range. A point beside the viewport
/// still gets a pixel (outside the rectangle).
// The references the picking and drag tests check against.
#[cfg_attr(not(test), allow(dead_code))]
pub fn project(camera: &Camera, rect: &ViewportRect, p: DVec3) -> Option<(Vec2, f32)> {
    View::new(camera, rect).project(p).map(|(pixel, depth)| (pixel.as_vec2(), depth as f32))
}

/// The ray under a pixel: it starts at the eye and its direction has unit length. Every point
/// that [`project`] sends to `pixel` lies on it, in front of the origin.
// The references the picking and drag tests check against.
#[cfg_attr(not(test), allow(dead_code))]
pub fn unproject_ray(camera: &Camera, rect: &ViewportRect, pixel: Vec2) -> (DVec3, DVec3) {
    View::new(camera, rect).ray(pixel.as_dvec2())
}

/// The vertex whose projection is within `radius_px` of the mouse, nearest on screen; among
/// those within [`PICK_TIE_PX`] of the nearest, the one in front. Vertices behind the camera are
/// never picked.
pub fn pick_vertex(
    camera: &Camera,
    rect: &ViewportRect,
    positions: &[DVec3],
    mouse: Vec2,
    radius_px: f32,
) -> Option<VertexId> {
    let view = View::new(camera, rect);
    let mouse = mouse.as_dvec2();
    let candidates = positions.iter().enumerate().filter_map(|(i, &p)| {
        let (pixel, depth) = view.project(p)?;
        Some(Candidate { index: i, distance: pixel.distance(mouse), depth })
    });
    nearest(candidates, radius_px).map(|i| VertexId(i as u32))
}

/// The edge whose projection passes within `radius_px` of the mouse, nearest on screen (ties
/// within [`PICK_TIE_PX`] go to the one in front at the closest point). Edges are clipped to the
/// camera's depth range first, so an edge reaching behind the camera is picked by its visible
/// part only.
pub fn pick_edge(camera: &Camera, rect: &ViewportRect, mesh: &PolyMesh, mouse: Vec2, radius_px: f32) -> Option<EdgeId> {
    let view = View::new(camera, rect);
    let mouse = mouse.as_dvec2();
    let candidates = mesh.edges().filter_map(|e| {
        let (a, b) = mesh.edge_vertices(e);
        let (ca, cb) = clip_segment(view.clip(mesh.position(a)), view.clip(mesh.position(b)))?;
        let (pa, da) = view.clip_to_pixel(ca);
        let (pb, db) = view.clip_to_pixel(cb);
        // Depth over w is affine in screen space, so interpolating it by the screen parameter
        // gives the depth at the closest point exactly.
        let ab = pb - pa;
        let s =
            if ab.length_squared() > 0.0 { ((mouse - pa).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
        Some(Candidate { index: e.index(), distance: (pa + s * ab).distance(mouse), depth: da + s * (db - da) })
    });
    nearest(candidates, radius_px).map(|i| EdgeId(i as u32))
}

/// The vertices in front of the camera whose projections lie inside the rectangle spanned by
/// two corners (in any order, edges included), in vertex order.
pub fn box_select(
    camera: &Camera,
    rect: &ViewportRect,
    positions: &[DVec3],
    corner_a: Vec2,
    corner_b: Vec2,
) -> Vec<VertexId> {
    let view = View::new(camera, rect);
    let (lo, hi) = (corner_a.min(corner_b).as_dvec2(), corner_a.max(corner_b).as_dvec2());
    positions
        .iter()
        .enumerate()
        .filter(|&(_, &p)| {
            view.project(p).is_some_and(|(q, _)| lo.x <= q.x && q.x <= hi.x && lo.y <= q.y && q.y <= hi.y)
        })
        .map(|(i, _)| VertexId(i as u32))
        .collect()
}

/// Where a drag that started at `mouse_start` with the selection at `start` puts it now that
/// the mouse is at `mouse_now`. Every vertex moves by the same world offset:
///
/// - free (`axis` is `None`): in the view plane through the centroid, by the offset between the
///   two mouse rays' hits on that plane, so the centroid's projection follows the cursor
///   exactly (and stays under it when the drag started on it);
/// - along a world axis: by the change of the closest point between the mouse ray and the axis
///   line through the centroid. When the axis points within [`AXIS_PARALLEL_DEGREES`] of the eye
///   the drag follows the axis' screen-space direction instead, at a bounded speed. Axis drags
///   are clamped to [`MAX_DRAG_IN_DISTANCES`] camera distances and never carry the centroid
///   behind the near plane.
///
/// With `mouse_now == mouse_start` the start positions come back unchanged.
pub fn drag_positions(
    camera: &Camera,
    rect: &ViewportRect,
    start: &[(VertexId, DVec3)],
    mouse_start: Vec2,
    mouse_now: Vec2,
    axis: Option<Axis>,
) -> Vec<(VertexId, DVec3)> {
    if start.is_empty() || mouse_now == mouse_start {
        return start.to_vec();
    }
    let view = View::new(camera, rect);
    let centroid = start.iter().map(|&(_, p)| p).sum::<DVec3>() / start.len() as f64;
    // A selection at or behind the near plane (orbited past) is dragged as if it sat on the
    // near plane: the offsets stay finite and in the direction the cursor goes.
    let depth = view.depth_of(centroid);
    let anchor = centroid + view.forward * (view.near - depth).max(0.0);
    let (from, to) = (mouse_start.as_dvec2(), mouse_now.as_dvec2());
    let offset = match axis {
        None => view.hit_view_plane(anchor, to) - view.hit_view_plane(anchor, from),
        Some(axis) => axis.direction() * view.axis_offset(anchor, axis.direction(), from, to, camera.distance as f64),
    };
    if !offset.is_finite() {
        return start.to_vec();
    }
    start.iter().map(|&(v, p)| (v, p + offset)).collect()
}

/// Orbit angles for a mouse drag of `delta_px` pixels (x right, y down), at
/// [`ORBIT_DEGREES_PER_PIXEL`]: as in Blender's turntable, the scene turns as if grabbed, so
/// dragging right turns its near side to the right and dragging down shows it more from above.
/// Returns `(d_azimuth, d_elevation)` in degrees, for [`Camera::orbit`].
pub fn orbit_from_drag(delta_px: Vec2) -> (f32, f32) {
    (-delta_px.x * ORBIT_DEGREES_PER_PIXEL, delta_px.y * ORBIT_DEGREES_PER_PIXEL)
}

/// Distance factor for a scroll of `scroll_lines` wheel notches (positive: the wheel turned away
/// from the designer, which zooms in), [`ZOOM_PER_NOTCH`] per notch, for [`Camera::zoom`].
/// Fractional notches (trackpads) compose: two half notches zoom as far as one.
pub fn zoom_factor(scroll_lines: f32) -> f32 {
    if !scroll_lines.is_finite() {
        return 1.0;
    }
    ZOOM_PER_NOTCH.powf(scroll_lines.clamp(-100.0, 100.0))
}

/// A pick candidate: its index, screen distance to the mouse in pixels and depth in [0, 1].
struct Candidate {
    index: usize,
    distance: f64,
    depth: f64,
}

/// The candidate within `radius_px`, nearest on screen, the front one among near ties.
fn nearest(candidates: impl Iterator<Item = Candidate>, radius_px: f32) -> Option<usize> {
    let within: Vec<Candidate> = candidates.filter(|c| c.distance <= radius_px as f64).collect();
    let closest = within.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min);
    within
        .iter()
        .filter(|c| c.distance <= closest + PICK_TIE_PX as f64)
        .min_by(|a, b| a.depth.total_cmp(&b.depth).then(a.distance.total_cmp(&b.distance)))
        .map(|c| c.index)
}

/// Clips a segment in homogeneous clip coordinates to the visible depth range 0 ≤ z ≤ w (which
/// implies w > 0 for a perspective projection); `None` when nothing is left.
fn clip_segment(mut a: DVec4, mut b: DVec4) -> Option<(DVec4, DVec4)> {
    let planes: [fn(DVec4) -> f64; 2] = [|c| c.z, |c| c.w - c.z];
    for plane in planes {
        let (fa, fb) = (plane(a), plane(b));
        if fa.is_nan() || fb.is_nan() || (fa < 0.0 && fb < 0.0) {
            return None;
        }
        if fa < 0.0 {
            a += (b - a) * (fa / (fa - fb));
        } else if fb < 0.0 {
            b += (a - b) * (fb / (fb - fa));
        }
    }
    Some((a, b))
}

/// The camera's matrices for one viewport, in f64, with what picking and dragging need.
struct View {
    clip_from_world: DMat4,
    view_from_clip: DMat4,
    world_from_view: DMat4,
    eye: DVec3,
    /// Unit view direction (into the screen).
    forward: DVec3,
    /// Distance of the near plane from the eye.
    near: f64,
    min: DVec2,
    size: DVec2,
}

impl View {
    fn new(camera: &Camera, rect: &ViewportRect) -> View {
        let view_from_world = camera.view_from_world().as_dmat4();
        let clip_from_view = camera.clip_from_view(rect.aspect()).as_dmat4();
        let world_from_view = view_from_world.inverse();
        // In glam's directx perspective, clip z = A·z_view + B with B = near·far/(near − far) and
        // A = far/(near − far); the near plane (clip z = 0) is at view depth B / A.
        let near = clip_from_view.w_axis.z / clip_from_view.z_axis.z;
        View {
            clip_from_world: clip_from_view * view_from_world,
            view_from_clip: clip_from_view.inverse(),
            world_from_view,
            eye: world_from_view.w_axis.truncate(),
            forward: -world_from_view.z_axis.truncate().normalize(),
            near: near.abs(),
            min: rect.min.as_dvec2(),
            size: rect.size.as_dvec2().max(DVec2::splat(1e-6)),
        }
    }

    fn clip(&self, p: DVec3) -> DVec4 {
        self.clip_from_world * p.extend(1.0)
    }

    /// Pixel and depth of a clip-space point with w > 0.
    fn clip_to_pixel(&self, c: DVec4) -> (DVec2, f64) {
        let ndc = c.truncate() / c.w;
        (self.min + DVec2::new(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 * self.size, ndc.z)
    }

    fn project(&self, p: DVec3) -> Option<(DVec2, f64)> {
        let c = self.clip(p);
        if c.w.is_nan() || c.w <= 0.0 {
            return None;
        }
        let (pixel, depth) = self.clip_to_pixel(c);
        ((0.0..=1.0).contains(&depth) && pixel.is_finite()).then_some((pixel, depth))
    }

    fn ray(&self, pixel: DVec2) -> (DVec3, DVec3) {
        let t = (pixel - self.min) / self.size;
        let ndc = DVec3::new(2.0 * t.x - 1.0, 1.0 - 2.0 * t.y, 0.0);
        // The point on the near plane, seen from the eye at the view-space origin.
        let on_near = self.view_from_clip.project_point3(ndc);
        (self.eye, self.world_from_view.transform_vector3(on_near).normalize())
    }

    /// Distance of `p` in front of the eye along the view direction.
    fn depth_of(&self, p: DVec3) -> f64 {
        (p - self.eye).dot(self.forward)
    }

    /// Where the ray under `pixel` meets the plane facing the camera through `anchor` (which is
    /// at least the near distance in front of the eye, so the ray meets it ahead).
    fn hit_view_plane(&self, anchor: DVec3, pixel: DVec2) -> DVec3 {
        let (origin, direction) = self.ray(pixel);
        origin + direction * (self.depth_of(anchor) / direction.dot(self.forward))
    }

    /// Pixels moved on screen per world unit moved from `p` along `direction`.
    fn screen_velocity(&self, p: DVec3, direction: DVec3) -> DVec2 {
        let c = self.clip(p);
        let dc = self.clip_from_world * direction.extend(0.0);
        // Quotient rule on ndc = c.xy / c.w; pixel y runs down.
        let d_ndc = (dc.truncate().truncate() * c.w - c.truncate().truncate() * dc.w) / (c.w * c.w);
        DVec2::new(d_ndc.x, -d_ndc.y) * 0.5 * self.size
    }

    /// Signed distance to move along the unit `axis` from `anchor` for a drag from pixel `from`
    /// to pixel `to`, clamped as [`drag_positions`] promises.
    fn axis_offset(&self, anchor: DVec3, axis: DVec3, from: DVec2, to: DVec2, camera_distance: f64) -> f64 {
        let limit = MAX_DRAG_IN_DISTANCES * camera_distance.max(self.near);
        let along_view = axis.dot(self.forward);
        let sin_to_view = axis.cross((anchor - self.eye).normalize()).length();
        let offset = if sin_to_view >= AXIS_PARALLEL_DEGREES.to_radians().sin() {
            self.axis_parameter(anchor, axis, to, limit) - self.axis_parameter(anchor, axis, from, limit)
        } else {
            // The axis points nearly at the eye. Follow its screen direction at no more world
            // units per pixel than an axis at the threshold angle would need; an axis exactly
            // along the view has no screen direction, so dragging up pushes it into the scene.
            let velocity = self.screen_velocity(anchor, axis);
            let in_plane = self.screen_velocity(anchor, self.world_from_view.x_axis.truncate().normalize()).length();
            let speed = velocity.length().max(in_plane * AXIS_PARALLEL_DEGREES.to_radians().sin());
            let direction = if velocity.length() > 1e-3 * in_plane {
                velocity / velocity.length()
            } else {
                DVec2::new(0.0, -along_view.signum())
            };
            (to - from).dot(direction) / speed
        };
        let offset = if offset.is_finite() { offset.clamp(-limit, limit) } else { 0.0 };
        // Keep the centroid in front of the near plane (the anchor is, so 0 is always allowed).
        let room = self.depth_of(anchor) - self.near;
        if along_view < 0.0 {
            offset.min(room / -along_view)
        } else if along_view > 0.0 {
            offset.max(-room / along_view)
        } else {
            offset
        }
    }

    /// The parameter along the axis line `anchor + s·axis` of its closest point to the ray under
    /// `pixel`, within ±`limit`. A ray nearly parallel to the axis, or one whose closest point
    /// lies behind the eye (the cursor went past the axis' vanishing point), saturates towards
    /// the vanishing point, so the selection runs off to the horizon and never jumps back.
    fn axis_parameter(&self, anchor: DVec3, axis: DVec3, pixel: DVec2, limit: f64) -> f64 {
        let (origin, direction) = self.ray(pixel);
        let to_vanishing = limit * axis.dot(self.forward).signum();
        let w = anchor - origin;
        let b = axis.dot(direction);
        let denominator = 1.0 - b * b;
        if denominator < 1e-12 {
            return to_vanishing;
        }
        // Minimise |anchor + s·axis − origin − t·direction|² over s and t (both unit vectors).
        let s = (b * direction.dot(w) - axis.dot(w)) / denominator;
        if self.depth_of(anchor + s * axis) <= 0.0 {
            return to_vanishing;
        }
        s.clamp(-limit, limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn rect() -> ViewportRect {
        ViewportRect { min: Vec2::new(40.0, 25.0), size: Vec2::new(800.0, 600.0) }
    }

    fn camera() -> Camera {
        Camera { target: Vec3::new(0.5, -0.25, 0.3), distance: 6.0, azimuth: 30.0, elevation: 25.0, fov_y: 35.0 }
    }

    /// Independent pinhole model from the camera's frame and field of view (no matrices):
    /// pixel and depth of `p`, or `None` behind the eye.
    fn pinhole(c: &Camera, r: &ViewportRect, p: DVec3) -> Option<(DVec2, f64)> {
        let (eye, right, up, back) =
            (c.eye().as_dvec3(), c.right().as_dvec3(), c.up().as_dvec3(), c.backward().as_dvec3());
        let v = p - eye;
        let z = -v.dot(back);
        if z <= 0.0 {
            return None;
        }
        let tan = (0.5 * c.fov_y as f64).to_radians().tan();
        let aspect = r.size.x as f64 / r.size.y as f64;
        let ndc = DVec2::new(v.dot(right) / (z * tan * aspect), v.dot(up) / (z * tan));
        let (near, far) = (c.distance as f64 * 0.01, c.distance as f64 * 100.0);
        let depth = far * (z - near) / (z * (far - near));
        let pixel = r.min.as_dvec2() + DVec2::new(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 * r.size.as_dvec2();
        Some((pixel, depth))
    }

    /// Independent ray under a pixel, from the same pinhole model.
    fn pinhole_ray(c: &Camera, r: &ViewportRect, pixel: Vec2) -> (DVec3, DVec3) {
        let t = (pixel - r.min) / r.size;
        let tan = (0.5 * c.fov_y as f64).to_radians().tan();
        let aspect = r.size.x as f64 / r.size.y as f64;
        let (x, y) = ((2.0 * t.x as f64 - 1.0) * tan * aspect, (1.0 - 2.0 * t.y as f64) * tan);
        let d = -c.backward().as_dvec3() + x * c.right().as_dvec3() + y * c.up().as_dvec3();
        (c.eye().as_dvec3(), d.normalize())
    }

    fn distance_to_line(p: DVec3, (o, d): (DVec3, DVec3)) -> f64 {
        let v = p - o;
        (v - d * v.dot(d)).length()
    }

    fn pixel_of(c: &Camera, r: &ViewportRect, p: DVec3) -> Vec2 {
        project(c, r, p).expect("in front").0
    }

    #[test]
    fn the_target_lands_at_the_centre_and_projection_matches_a_pinhole() {
        let (c, r) = (camera(), rect());
        let (pixel, depth) = project(&c, &r, c.target.as_dvec3()).unwrap();
        let centre = r.min + 0.5 * r.size;
        assert!(pixel.distance(centre) < 1e-3, "{pixel} vs {centre}");
        assert!(depth > 0.0 && depth < 1.0);
        for p in [DVec3::new(1.0, 0.5, -0.2), DVec3::new(-1.5, 1.0, 1.2), DVec3::new(0.2, -2.0, 0.0)] {
            let (got, got_depth) = project(&c, &r, p).unwrap();
            let (want, want_depth) = pinhole(&c, &r, p).unwrap();
            assert!(got.as_dvec2().distance(want) < 2e-3, "{p}: {got} vs {want}");
            assert!((got_depth as f64 - want_depth).abs() < 1e-5, "{p}: {got_depth} vs {want_depth}");
        }
    }

    #[test]
    fn project_and_unproject_round_trip() {
        let (c, r) = (camera(), rect());
        for p in [DVec3::new(1.0, 0.5, -0.2), DVec3::new(-1.5, 1.0, 1.2), DVec3::new(3.0, 8.0, -1.0)] {
            let pixel = pixel_of(&c, &r, p);
            let (origin, direction) = unproject_ray(&c, &r, pixel);
            assert!((direction.length() - 1.0).abs() < 1e-12);
            assert!((p - origin).dot(direction) > 0.0, "the point is ahead on the ray");
            // f32 pixel rounding: well under a micrometre at these distances.
            assert!(distance_to_line(p, (origin, direction)) < 1e-4, "{p}");
        }
        for pixel in [Vec2::new(41.0, 26.0), Vec2::new(500.0, 300.0), Vec2::new(839.0, 624.0)] {
            let ray = unproject_ray(&c, &r, pixel);
            let reference = pinhole_ray(&c, &r, pixel);
            assert!(ray.0.distance(reference.0) < 1e-5 && ray.1.distance(reference.1) < 1e-6);
            let p = ray.0 + 4.0 * ray.1;
            assert!(pixel_of(&c, &r, p).distance(pixel) < 1e-3);
        }
    }

    #[test]
    fn behind_the_camera_is_never_projected_picked_or_selected() {
        let (c, r) = (camera(), rect());
        let eye = c.eye().as_dvec3();
        let front = DVec3::new(0.8, 0.1, 0.4);
        // Mirrored through the eye: a naive divide by w puts it on the same pixel as `front`.
        let behind = eye - 0.5 * (front - eye);
        assert!(project(&c, &r, behind).is_none());
        let mouse = pixel_of(&c, &r, front);
        assert_eq!(pick_vertex(&c, &r, &[behind], mouse, 10.0), None);
        assert_eq!(pick_vertex(&c, &r, &[behind, front], mouse, 10.0), Some(VertexId(1)));
        let band = box_select(&c, &r, &[behind], mouse - Vec2::splat(20.0), mouse + Vec2::splat(20.0));
        assert!(band.is_empty());
    }

    #[test]
    fn pick_prefers_the_nearer_of_two_overlapping_vertices_and_respects_the_radius() {
        let (c, r) = (camera(), rect());
        let (eye, p) = (c.eye().as_dvec3(), DVec3::new(0.3, 0.2, 0.1));
        let far = eye + 2.0 * (p - eye);
        let beside = DVec3::new(-1.0, 1.5, 0.8);
        let mouse = pixel_of(&c, &r, p) + Vec2::new(3.0, -2.0);
        for positions in [[far, p, beside], [p, far, beside]] {
            let want = positions.iter().position(|&q| q == p).unwrap();
            assert_eq!(pick_vertex(&c, &r, &positions, mouse, 6.0), Some(VertexId(want as u32)));
        }
        // 3.6 px away: outside a 3-pixel radius, inside a 4-pixel one.
        assert_eq!(pick_vertex(&c, &r, &[far, p], mouse, 3.0), None);
        assert!(pick_vertex(&c, &r, &[far, p], mouse, 4.0).is_some());
        // Strictly nearer on screen beats nearer in depth.
        let offside = pixel_of(&c, &r, far) + Vec2::new(10.0, 0.0);
        let slightly = unproject_ray(&c, &r, offside + Vec2::new(-3.0, 0.0));
        let back_but_closer = slightly.0 + 12.0 * slightly.1;
        assert_eq!(pick_vertex(&c, &r, &[p, back_but_closer], offside, 15.0), Some(VertexId(1)));
    }

    fn two_quads() -> PolyMesh {
        let positions = vec![
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
        ];
        PolyMesh::from_polygons(positions, &[[0u32, 1, 4, 3], [1, 2, 5, 4]]).unwrap()
    }

    #[test]
    fn edge_pick_at_the_middle_of_each_segment() {
        let (c, r, mesh) = (camera(), rect(), two_quads());
        for e in mesh.edges() {
            let (a, b) = mesh.edge_vertices(e);
            let middle = 0.5 * (mesh.position(a) + mesh.position(b));
            let mouse = pixel_of(&c, &r, middle);
            assert_eq!(pick_edge(&c, &r, &mesh, mouse, 5.0), Some(e), "{a:?}-{b:?}");
        }
        let nowhere = pixel_of(&c, &r, DVec3::new(0.0, 0.0, 3.0));
        assert_eq!(pick_edge(&c, &r, &mesh, nowhere, 5.0), None);
    }

    #[test]
    fn edge_pick_uses_the_visible_part_of_an_edge_crossing_the_near_plane() {
        let (c, r) = (camera(), rect());
        let eye = c.eye().as_dvec3();
        let inside = c.target.as_dvec3() + DVec3::new(0.2, 0.0, 0.1);
        // From in front of the camera to well behind it, passing beside the eye.
        let behind = eye + 1.5 * (eye - inside) + c.right().as_dvec3() * 0.5;
        let off = DVec3::new(0.0, 0.0, -3.0);
        let mesh = PolyMesh::from_polygons(vec![inside, behind, inside + off], &[[0u32, 1, 2]]).unwrap();
        let e = mesh
            .edges()
            .find(|&e| {
                mesh.edge_vertices(e) == (VertexId(0), VertexId(1))
                    || mesh.edge_vertices(e) == (VertexId(1), VertexId(0))
            })
            .unwrap();
        // A point on the edge a little way from `inside`, still well in front.
        let on_edge = inside + 0.1 * (behind - inside);
        let mouse = pixel_of(&c, &r, on_edge);
        assert_eq!(pick_edge(&c, &r, &mesh, mouse, 3.0), Some(e));
        // Projected without clipping, `behind` lands on the other side of `inside` (its mirror
        // through the eye); the middle of that naive segment is far from the visible part,
        // which starts at `inside` and runs the other way, so nothing may be picked there.
        let m = c.clip_from_view(r.aspect()) * c.view_from_world();
        let q = m * behind.as_vec3().extend(1.0);
        let naive = r.min + Vec2::new(q.x / q.w + 1.0, 1.0 - q.y / q.w) * 0.5 * r.size;
        let naive_middle = 0.5 * (naive + pixel_of(&c, &r, inside));
        let (start, run) = (pixel_of(&c, &r, inside), (mouse - pixel_of(&c, &r, inside)).normalize());
        let to_visible = naive_middle - (start + run * (naive_middle - start).dot(run).max(0.0));
        assert!(to_visible.length() > 10.0, "the naive middle is away from the visible edge");
        assert_ne!(pick_edge(&c, &r, &mesh, naive_middle, 3.0), Some(e));
    }

    #[test]
    fn box_select_in_any_corner_order() {
        let (c, r) = (camera(), rect());
        let positions = [DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.6, -0.2, 0.5), DVec3::new(-2.0, 3.0, 2.0)];
        let (p0, p1) = (pixel_of(&c, &r, positions[0]), pixel_of(&c, &r, positions[1]));
        let (lo, hi) = (p0.min(p1) - Vec2::splat(2.0), p0.max(p1) + Vec2::splat(2.0));
        assert!(!(lo.cmple(pixel_of(&c, &r, positions[2])).all() && pixel_of(&c, &r, positions[2]).cmple(hi).all()));
        let want = vec![VertexId(0), VertexId(1)];
        let (other_a, other_b) = (Vec2::new(lo.x, hi.y), Vec2::new(hi.x, lo.y));
        for (a, b) in [(lo, hi), (hi, lo), (other_a, other_b), (other_b, other_a)] {
            assert_eq!(box_select(&c, &r, &positions, a, b), want, "{a} {b}");
        }
        assert!(box_select(&c, &r, &positions, lo, lo).is_empty());
    }

    fn selection() -> Vec<(VertexId, DVec3)> {
        vec![
            (VertexId(3), DVec3::new(0.2, 0.1, 0.0)),
            (VertexId(7), DVec3::new(1.0, -0.4, 0.6)),
            (VertexId(9), DVec3::new(-0.3, 0.5, 0.9)),
        ]
    }

    fn centroid(points: &[(VertexId, DVec3)]) -> DVec3 {
        points.iter().map(|&(_, p)| p).sum::<DVec3>() / points.len() as f64
    }

    #[test]
    fn free_drag_keeps_the_centroid_under_the_cursor_in_the_view_plane() {
        let (c, r, start) = (camera(), rect(), selection());
        let grab = pixel_of(&c, &r, centroid(&start));
        for delta in [Vec2::new(37.0, -21.0), Vec2::new(-250.0, 180.0), Vec2::new(0.5, 0.0)] {
            let moved = drag_positions(&c, &r, &start, grab, grab + delta, None);
            let offset = moved[0].1 - start[0].1;
            for (&(v0, p0), &(v1, p1)) in start.iter().zip(&moved) {
                assert_eq!(v0, v1);
                assert!(((p1 - p0) - offset).length() < 1e-12, "one rigid offset");
            }
            // Checked against the pinhole reference, not against the code's own projection.
            let (now, _) = pinhole(&c, &r, centroid(&moved)).unwrap();
            assert!(now.distance((grab + delta).as_dvec2()) < 2e-3, "{delta}: {now}");
            assert!(offset.dot(c.backward().as_dvec3()).abs() < 1e-6 * offset.length().max(1.0), "{offset}");
        }
        // Grabbed beside the centroid, the centroid's projection follows the cursor's motion.
        let beside = grab + Vec2::new(12.0, 8.0);
        let moved = drag_positions(&c, &r, &start, beside, beside + Vec2::new(-40.0, 30.0), None);
        let (now, _) = pinhole(&c, &r, centroid(&moved)).unwrap();
        assert!(now.distance((grab + Vec2::new(-40.0, 30.0)).as_dvec2()) < 2e-3, "{now}");
    }

    #[test]
    fn a_drag_that_has_not_moved_returns_the_start_positions_exactly() {
        let (c, r, start) = (camera(), rect(), selection());
        let mouse = Vec2::new(321.5, 200.25);
        for axis in [None, Some(Axis::X), Some(Axis::Y), Some(Axis::Z)] {
            assert_eq!(drag_positions(&c, &r, &start, mouse, mouse, axis), start);
        }
        assert!(drag_positions(&c, &r, &[], mouse, mouse + Vec2::ONE, None).is_empty());
    }

    #[test]
    fn axis_drag_changes_only_that_coordinate_and_follows_the_cursor() {
        let (c, r, start) = (camera(), rect(), selection());
        let grab = pixel_of(&c, &r, centroid(&start));
        for (axis, index) in [(Axis::X, 0), (Axis::Y, 1), (Axis::Z, 2)] {
            let now = grab + Vec2::new(45.0, -30.0);
            let moved = drag_positions(&c, &r, &start, grab, now, Some(axis));
            for (&(_, p0), &(_, p1)) in start.iter().zip(&moved) {
                for k in 0..3 {
                    if k == index {
                        assert!((p1[k] - p0[k]).abs() > 1e-3, "{axis:?} moves");
                    } else {
                        assert_eq!(p1[k], p0[k], "{axis:?} keeps coordinate {k}");
                    }
                }
            }
            // The moved centroid is the axis point closest to the reference mouse ray: the
            // shortest segment between them is perpendicular to the axis.
            let moved_centroid = centroid(&moved);
            let (o, d) = pinhole_ray(&c, &r, now);
            let foot = o + d * (moved_centroid - o).dot(d);
            let gap = moved_centroid - foot;
            assert!(gap.dot(axis.direction()).abs() < 1e-5, "{axis:?}: {gap}");
        }
    }

    #[test]
    fn an_axis_along_the_view_gives_finite_bounded_positions() {
        let r = rect();
        let mut c = camera();
        c.target = Vec3::ZERO;
        // Front view: the eye looks along +Y, straight down the Y axis; then nearly along it.
        for (azimuth, elevation) in [(0.0, 0.0), (1.0, 0.5), (0.0, 4.0), (180.0, 0.0), (0.0, 6.0)] {
            c.azimuth = azimuth;
            c.elevation = elevation;
            let start = vec![(VertexId(0), DVec3::new(0.0, 0.0, 0.0)), (VertexId(1), DVec3::new(0.0, 0.2, 0.0))];
            let grab = pixel_of(&c, &r, centroid(&start));
            let limit = MAX_DRAG_IN_DISTANCES * c.distance as f64;
            for dx in [-1.0e5, -300.0, -1.0, 0.0, 2.0, 300.0, 1.0e5] {
                for dy in [-1.0e5, -250.0, -1.0, 0.0, 1.0, 250.0, 1.0e5] {
                    let moved = drag_positions(&c, &r, &start, grab, grab + Vec2::new(dx, dy), Some(Axis::Y));
                    for (&(_, p0), &(_, p1)) in start.iter().zip(&moved) {
                        assert!(p1.is_finite(), "{azimuth} {elevation} {dx} {dy}");
                        assert!((p1 - p0).length() <= limit * (1.0 + 1e-9), "{azimuth} {elevation} {dx} {dy}: {p1}");
                        assert_eq!((p1.x, p1.z), (p0.x, p0.z));
                    }
                    // The selection stays in front of the camera.
                    let depth = (centroid(&moved) - c.eye().as_dvec3()).dot(-c.backward().as_dvec3());
                    assert!(depth >= 0.0099 * c.distance as f64, "{azimuth} {elevation} {dx} {dy}: {depth}");
                }
            }
            // A few pixels move the selection a little, not across the scene.
            let nudge = drag_positions(&c, &r, &start, grab, grab + Vec2::new(0.0, -3.0), Some(Axis::Y));
            let step = (nudge[0].1 - start[0].1).length();
            assert!(step < 0.5 * c.distance as f64, "{azimuth} {elevation}: {step}");
        }
    }

    #[test]
    fn a_selection_behind_the_camera_drags_to_finite_positions() {
        let (c, r) = (camera(), rect());
        let eye = c.eye().as_dvec3();
        let start = vec![(VertexId(0), eye + 2.0 * c.backward().as_dvec3())];
        for axis in [None, Some(Axis::X), Some(Axis::Z)] {
            let moved = drag_positions(
                &c,
                &r,
                &start,
                r.min + 0.5 * r.size,
                r.min + 0.5 * r.size + Vec2::new(30.0, 10.0),
                axis,
            );
            assert!(moved[0].1.is_finite(), "{axis:?}");
        }
    }

    #[test]
    fn orbit_turns_the_scene_as_if_grabbed() {
        let r = rect();
        let c = camera();
        // A point on the near side of the target, between it and the eye.
        let near_side = (c.target + 0.5 * c.backward()).as_dvec3();
        let before = pixel_of(&c, &r, near_side);
        let (d_azimuth, d_elevation) = orbit_from_drag(Vec2::new(50.0, 0.0));
        assert_eq!(d_elevation, 0.0);
        assert!((d_azimuth.abs() - 50.0 * ORBIT_DEGREES_PER_PIXEL).abs() < 1e-6);
        let mut turned = c;
        turned.orbit(d_azimuth, d_elevation);
        assert!(pixel_of(&turned, &r, near_side).x > before.x + 1.0, "dragging right moves the near side right");
        let (d_azimuth, d_elevation) = orbit_from_drag(Vec2::new(0.0, 40.0));
        assert_eq!(d_azimuth, 0.0);
        let mut tilted = c;
        tilted.orbit(d_azimuth, d_elevation);
        assert!(tilted.elevation > c.elevation, "dragging down looks more from above");
        assert!(pixel_of(&tilted, &r, near_side).y > before.y + 1.0, "dragging down moves the near side down");
    }

    #[test]
    fn zoom_notches_compose() {
        assert_eq!(zoom_factor(0.0), 1.0);
        assert!((zoom_factor(1.0) - ZOOM_PER_NOTCH).abs() < 1e-7);
        assert!(zoom_factor(1.0) < 1.0, "scrolling away from the designer zooms in");
        assert!((zoom_factor(-1.0) * zoom_factor(1.0) - 1.0).abs() < 1e-6);
        assert!((zoom_factor(0.5) * zoom_factor(0.5) - zoom_factor(1.0)).abs() < 1e-6);
        assert_eq!(zoom_factor(f32::NAN), 1.0);
        assert!(zoom_factor(1e9).is_finite() && zoom_factor(1e9) > 0.0);
    }
}
