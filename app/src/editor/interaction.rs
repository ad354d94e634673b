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

/// The ray under a pixel: it starts at the eye (orthographic: on the near plane, along the view
/// direction) and its direction has unit length. Every point
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
    pick_vertex_where(camera, rect, positions, mouse, radius_px, |_| true)
}

/// [`pick_vertex`] among the vertices `pickable` accepts (those seen, when X-ray is off).
pub fn pick_vertex_where(
    camera: &Camera,
    rect: &ViewportRect,
    positions: &[DVec3],
    mouse: Vec2,
    radius_px: f32,
    pickable: impl Fn(VertexId) -> bool,
) -> Option<VertexId> {
    let view = View::new(camera, rect);
    let mouse = mouse.as_dvec2();
    let candidates = positions.iter().enumerate().filter_map(|(i, &p)| {
        if !pickable(VertexId(i as u32)) {
            return None;
        }
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
    pick_edge_where(camera, rect, mesh, mouse, radius_px, |_| true)
}

/// [`pick_edge`] among the edges `pickable` accepts (those seen, when X-ray is off).
pub fn pick_edge_where(
    camera: &Camera,
    rect: &ViewportRect,
    mesh: &PolyMesh,
    mouse: Vec2,
    radius_px: f32,
    pickable: impl Fn(EdgeId) -> bool,
) -> Option<EdgeId> {
    let view = View::new(camera, rect);
    let mouse = mouse.as_dvec2();
    let candidates = mesh.edges().filter(|&e| pickable(e)).filter_map(|e| {
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
// The reference the box tests check against; the editor boxes through `box_select_where`.
#[cfg_attr(not(test), allow(dead_code))]
pub fn box_select(
    camera: &Camera,
    rect: &ViewportRect,
    positions: &[DVec3],
    corner_a: Vec2,
    corner_b: Vec2,
) -> Vec<VertexId> {
    box_select_where(camera, rect, positions, corner_a, corner_b, |_| true)
}

/// [`box_select`] among the vertices `pickable` accepts (those seen, when X-ray is off).
pub fn box_select_where(
    camera: &Camera,
    rect: &ViewportRect,
    positions: &[DVec3],
    corner_a: Vec2,
    corner_b: Vec2,
    pickable: impl Fn(VertexId) -> bool,
) -> Vec<VertexId> {
    let view = View::new(camera, rect);
    let (lo, hi) = (corner_a.min(corner_b).as_dvec2(), corner_a.max(corner_b).as_dvec2());
    positions
        .iter()
        .enumerate()
        .filter(|&(i, &p)| {
            pickable(VertexId(i as u32))
                && view.project(p).is_some_and(|(q, _)| lo.x <= q.x && q.x <= hi.x && lo.y <= q.y && q.y <= hi.y)
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
    /// Parallel projection: rays start on the near plane, not at the eye.
    orthographic: bool,
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
            orthographic: camera.orthographic,
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
        // The point on the near plane, in view space (the eye at the origin).
        let on_near = self.view_from_clip.project_point3(ndc);
        if self.orthographic {
            // Parallel rays: each starts on the near plane and runs along the view direction.
            return (self.world_from_view.transform_point3(on_near), self.forward);
        }
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
        origin + direction * ((self.depth_of(anchor) - self.depth_of(origin)) / direction.dot(self.forward))
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
#[path = "interaction_tests.rs"]
mod tests;
