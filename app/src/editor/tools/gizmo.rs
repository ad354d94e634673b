//! The on-screen transform gizmo, as Blender's and Rhino's: at the pivot of the selection, axis
//! arrows (move along X, Y or Z), small plane squares (move in the plane, or scale in it when
//! only the scale handles are shown), rotation rings about X, Y and Z and a ring about the view
//! axis, and scale cubes beyond the arrow tips; the centre moves the selection in the view plane
//! in every mode. X is red, Y green, Z blue; the handle
//! under the mouse is drawn yellow; the gizmo keeps its size on screen ([`GIZMO_RADIUS_PX`]).
//!
//! A drag on a handle starts the very transform G, R or S start ([`crate::editor::transform`]) with the
//! handle's lock, so typed values, plane locks and snapping work the same, the whole drag is one
//! undo step, and letting go of the button confirms it. The gizmo is picked before the cage: a
//! press on a handle never selects or drags a cage point behind it, except at the centre, where
//! a cage vertex (in vertex mode) wins, as in Blender, so a selected point under the pivot can
//! still be dragged.
//!
//! Drawn with egui's painter over the viewport, projected with the view's camera; rings are
//! polylines whose far half is drawn faint and cannot be picked. Weak where Blender does more:
//! a ring drag turns by the angle the cursor sweeps about the pivot on screen (no trackball),
//! and handles seen end on (an arrow pointing at the eye) are hard to grab, as in Blender.

use crate::editor::interaction::{self, Axis, ViewportRect};
use crate::editor::pivot::Pivot;
use crate::editor::select_modes::SelectMode;
use crate::editor::snapping::SnapSettings;
use crate::editor::state::EditorState;
use crate::editor::tools::tool::ActiveTool;
use crate::editor::transform::{Transform, TransformKind};
use egui::{Color32, Pos2, Stroke};
use glam::Vec2;
use taut_core::{DVec3, PolyMesh};

/// The length of an arrow on screen, in points.
pub const GIZMO_RADIUS_PX: f32 = 80.0;
/// How close the mouse must come to a line or ring handle, in points.
const PICK_PX: f32 = 7.0;
/// The centre's radius, in points.
const CENTRE_PX: f32 = 9.0;
/// Half the side of a scale cube, in points.
const CUBE_PX: f32 = 6.0;
/// Where the parts sit, in arrow lengths from the pivot.
const SHAFT_FROM: f64 = 0.22;
const ARROW_TIP: f64 = 1.15;
const CUBE_AT: f64 = 1.45;
const RING_RADIUS: f64 = 0.85;
const PLANE_FROM: f64 = 0.3;
const PLANE_TO: f64 = 0.5;
/// The view ring's radius in arrow lengths on screen.
const VIEW_RING: f32 = 1.3;
const RING_SEGMENTS: usize = 64;

/// Which handles the gizmo shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum GizmoMode {
    Move,
    Rotate,
    Scale,
    #[default]
    All,
}

impl GizmoMode {
    pub const ALL: [GizmoMode; 4] = [GizmoMode::Move, GizmoMode::Rotate, GizmoMode::Scale, GizmoMode::All];

    pub fn name(self) -> &'static str {
        match self {
            GizmoMode::Move => "Move",
            GizmoMode::Rotate => "Rotate",
            GizmoMode::Scale => "Scale",
            GizmoMode::All => "All",
        }
    }

    fn moves(self) -> bool {
        matches!(self, GizmoMode::Move | GizmoMode::All)
    }

    fn rotates(self) -> bool {
        matches!(self, GizmoMode::Rotate | GizmoMode::All)
    }

    fn scales(self) -> bool {
        matches!(self, GizmoMode::Scale | GizmoMode::All)
    }
}

/// One handle of the gizmo.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Handle {
    /// Move along the axis.
    Arrow(Axis),
    /// Move (or scale) in the plane normal to the axis.
    Plane(Axis),
    /// Rotate about the axis.
    Ring(Axis),
    /// Rotate about the view axis.
    ViewRing,
    /// Scale along the axis.
    Cube(Axis),
    /// Move in the view plane.
    Centre,
}

/// The gizmo, pivot, snapping and 3D cursor settings of the editor (not saved in the document).
#[derive(Clone, Debug, PartialEq)]
pub struct GizmoSettings {
    /// Shown while something is selected (W, the toolbar).
    pub shown: bool,
    pub mode: GizmoMode,
    pub pivot: Pivot,
    pub snap: SnapSettings,
    /// The 3D cursor, in model coordinates.
    pub cursor: DVec3,
    /// The handle under the mouse.
    pub hovered: Option<Handle>,
    /// The handle being dragged.
    pub active: Option<Handle>,
}

impl Default for GizmoSettings {
    fn default() -> Self {
        GizmoSettings {
            shown: true,
            mode: GizmoMode::All,
            pivot: Pivot::Median,
            snap: SnapSettings::default(),
            cursor: DVec3::ZERO,
            hovered: None,
            active: None,
        }
    }
}

const AXES: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

fn colour(axis: Axis) -> Color32 {
    match axis {
        Axis::X => Color32::from_rgb(225, 60, 60),
        Axis::Y => Color32::from_rgb(100, 195, 70),
        Axis::Z => Color32::from_rgb(70, 125, 235),
    }
}

const HIGHLIGHT: Color32 = Color32::from_rgb(255, 220, 50);

/// The other two axes, in x, y, z order.
fn plane_axes(normal: Axis) -> (DVec3, DVec3) {
    match normal {
        Axis::X => (DVec3::Y, DVec3::Z),
        Axis::Y => (DVec3::X, DVec3::Z),
        Axis::Z => (DVec3::X, DVec3::Y),
    }
}

/// The gizmo placed in one view: where its pivot is and how long an arrow is.
#[derive(Clone, Copy, Debug)]
pub struct GizmoLayout {
    /// The pivot in display coordinates.
    pub pivot: DVec3,
    /// The pivot on screen.
    pub centre: Vec2,
    /// One arrow length in display units (it projects to [`GIZMO_RADIUS_PX`] at the pivot).
    pub length: f64,
    /// Unit vector from the pivot towards the eye.
    pub towards_eye: DVec3,
}

impl GizmoLayout {
    /// The gizmo at `pivot` (display coordinates); `None` when it is behind the camera.
    pub fn new(camera: &taut_render::Camera, view: &ViewportRect, pivot: DVec3) -> Option<GizmoLayout> {
        let (centre, _) = interaction::project(camera, view, pivot)?;
        let eye = camera.eye().as_dvec3();
        let forward = (camera.target.as_dvec3() - eye).normalize();
        let depth = (pivot - eye).dot(forward);
        // Orthographic: a pixel is the same size at every depth, the size it has at the target.
        let depth = if camera.orthographic { f64::from(camera.distance) } else { depth };
        let per_px = 2.0 * depth * (f64::from(camera.fov_y).to_radians() * 0.5).tan() / f64::from(view.size.y.max(1.0));
        let length = f64::from(GIZMO_RADIUS_PX) * per_px;
        let towards_eye = (eye - pivot).normalize();
        (length.is_finite() && length > 0.0 && towards_eye.is_finite()).then_some(GizmoLayout {
            pivot,
            centre,
            length,
            towards_eye,
        })
    }

    fn point(&self, offset: DVec3) -> DVec3 {
        self.pivot + self.length * offset
    }

    /// A ring about `axis` as points with whether each lies on the near half.
    fn ring(&self, axis: Axis) -> Vec<(DVec3, bool)> {
        let (u, v) = plane_axes(axis);
        (0..=RING_SEGMENTS)
            .map(|k| {
                let a = k as f64 / RING_SEGMENTS as f64 * std::f64::consts::TAU;
                let offset = RING_RADIUS * (a.cos() * u + a.sin() * v);
                // Nearly edge on counts as near (a ring seen straight on has f32 noise in its tilt).
                (self.point(offset), offset.dot(self.towards_eye) >= -0.05 * RING_RADIUS)
            })
            .collect()
    }

    fn plane_square(&self, normal: Axis) -> [DVec3; 4] {
        let (u, v) = plane_axes(normal);
        [(PLANE_FROM, PLANE_FROM), (PLANE_TO, PLANE_FROM), (PLANE_TO, PLANE_TO), (PLANE_FROM, PLANE_TO)]
            .map(|(a, b)| self.point(a * u + b * v))
    }
}

/// Distance from `m` to the segment `a`–`b` on screen.
fn segment_distance(m: Vec2, a: Vec2, b: Vec2) -> f32 {
    let ab = b - a;
    let s = if ab.length_squared() > 0.0 { ((m - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (a + s * ab).distance(m)
}

/// Whether `m` is inside the convex screen polygon `q` (either winding).
fn inside(m: Vec2, q: &[Vec2]) -> bool {
    let signs: Vec<f32> = (0..q.len()).map(|i| (q[(i + 1) % q.len()] - q[i]).perp_dot(m - q[i])).collect();
    signs.iter().all(|&s| s >= 0.0) || signs.iter().all(|&s| s <= 0.0)
}

/// The handle of a gizmo in `mode` under the mouse at `m`, in the order the handles win:
/// centre, scale cubes, arrows, plane squares, rings, the view ring.
pub fn pick_handle(
    camera: &taut_render::Camera,
    view: &ViewportRect,
    layout: &GizmoLayout,
    mode: GizmoMode,
    m: Vec2,
) -> Option<Handle> {
    let px = |p: DVec3| interaction::project(camera, view, p).map(|(q, _)| q);
    if m.distance(layout.centre) <= CENTRE_PX && (mode.moves() || mode.scales()) {
        return Some(Handle::Centre);
    }
    let nearest = |candidates: Vec<(Handle, f32)>| {
        candidates.into_iter().filter(|&(_, d)| d <= PICK_PX).min_by(|a, b| a.1.total_cmp(&b.1)).map(|(h, _)| h)
    };
    if mode.scales() {
        let cubes = AXES.iter().filter_map(|&a| Some((Handle::Cube(a), px(layout.point(CUBE_AT * a.direction()))?)));
        let hit = cubes.map(|(h, c)| (h, (m - c).abs().max_element() - CUBE_PX + PICK_PX * 0.5)).collect();
        if let Some(h) = nearest(hit) {
            return Some(h);
        }
    }
    if mode.moves() {
        let arrows = AXES.iter().filter_map(|&a| {
            let (from, to) =
                (px(layout.point(SHAFT_FROM * a.direction()))?, px(layout.point(ARROW_TIP * a.direction()))?);
            Some((Handle::Arrow(a), segment_distance(m, from, to)))
        });
        if let Some(h) = nearest(arrows.collect()) {
            return Some(h);
        }
    }
    if mode.moves() || mode.scales() {
        for a in AXES {
            let square: Option<Vec<Vec2>> = layout.plane_square(a).iter().map(|&p| px(p)).collect();
            if square.is_some_and(|q| inside(m, &q)) {
                return Some(Handle::Plane(a));
            }
        }
    }
    if mode.rotates() {
        let rings = AXES.iter().map(|&a| {
            let ring = layout.ring(a);
            let d = ring
                .windows(2)
                .filter(|w| w[0].1 && w[1].1)
                .filter_map(|w| Some(segment_distance(m, px(w[0].0)?, px(w[1].0)?)))
                .fold(f32::INFINITY, f32::min);
            (Handle::Ring(a), d)
        });
        if let Some(h) = nearest(rings.collect()) {
            return Some(h);
        }
        if (m.distance(layout.centre) - VIEW_RING * GIZMO_RADIUS_PX).abs() <= PICK_PX {
            return Some(Handle::ViewRing);
        }
    }
    None
}

impl EditorState {
    /// The gizmo's layout in this view, when it is shown (something selected, W on).
    pub fn gizmo_layout(&self, view: &ViewportRect) -> Option<GizmoLayout> {
        if !self.gizmo.shown {
            return None;
        }
        let vertices = self.selected_vertices_with_edge_ends();
        if vertices.is_empty() {
            return None;
        }
        let pivot = self.view.display_frame.to_display_f64(self.pivot_of(&vertices));
        GizmoLayout::new(&self.view.camera, view, pivot)
    }

    /// The gizmo's and the 3D cursor's share of the viewport's mouse, before the cage's: the
    /// hovered handle, a drag on a handle (a transform), a click on one (swallowed), and
    /// Shift+right-click (the 3D cursor). True when the mouse was the gizmo's this frame.
    pub(crate) fn gizmo_viewport(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        view: &ViewportRect,
        cage: &PolyMesh,
        mouse: Option<Vec2>,
        tool: &mut ActiveTool,
    ) -> bool {
        let shift = ui.ctx().input(|i| i.modifiers.shift);
        if shift && response.clicked_by(egui::PointerButton::Secondary) {
            if let Some(m) = mouse {
                self.place_cursor(view, m);
            }
            return true;
        }
        let layout = self.gizmo_layout(view);
        // A cage vertex under the centre handle wins over it, as in Blender: the press drags the
        // vertex (the centre handle would move the same selection in the view plane anyway, but
        // a press there must also be able to pick a vertex that is not selected yet).
        // Only a vertex in view (or any, with X-ray) counts.
        let (seen, camera, mode, gizmo_mode) =
            (self.cage_seen(), self.view.camera, self.view.selection.mode, self.gizmo.mode);
        let vertex_under = |m: Vec2| {
            let pickable = |v| seen.as_ref().is_none_or(|s| s.vertex(v));
            mode == SelectMode::Vertex
                && interaction::pick_vertex_where(&camera, view, cage.positions(), m, 8.0, pickable).is_some()
        };
        let over = |m: Vec2| {
            layout
                .and_then(|l| pick_handle(&camera, view, &l, gizmo_mode, m))
                .filter(|&h| h != Handle::Centre || !vertex_under(m))
        };
        self.gizmo.hovered = response.hovered().then_some(mouse).flatten().and_then(over);
        if response.drag_started_by(egui::PointerButton::Primary) {
            let origin = ui.ctx().input(|i| i.pointer.press_origin()).map(|p| Vec2::new(p.x, p.y)).or(mouse);
            if let Some(handle) = origin.and_then(over) {
                if let Some(t) = self.start_gizmo_drag(handle, origin, mouse, view) {
                    tool.start(self, Box::new(t));
                }
                return true;
            }
        }
        if self.gizmo.hovered.is_some() {
            // The gizmo is in front: nothing of the cage is hovered or clicked through it.
            self.view.selection.hovered_vertex = None;
            self.view.selection.hovered_edge = None;
            self.view.selection.hovered_face = None;
            return response.clicked_by(egui::PointerButton::Primary);
        }
        false
    }

    /// Starts the transform a handle drags: one gesture, confirmed when the button is let go.
    fn start_gizmo_drag(
        &mut self,
        handle: Handle,
        origin: Option<Vec2>,
        mouse: Option<Vec2>,
        view: &ViewportRect,
    ) -> Option<Transform> {
        let mode = self.gizmo.mode;
        let kind = match handle {
            Handle::Arrow(_) => TransformKind::Grab,
            Handle::Plane(_) if mode == GizmoMode::Scale => TransformKind::Scale,
            Handle::Plane(_) => TransformKind::Grab,
            Handle::Ring(_) | Handle::ViewRing => TransformKind::Rotate,
            Handle::Cube(_) => TransformKind::Scale,
            // The centre moves in the view plane in every mode; the cubes and (in scale mode) the
            // plane squares scale.
            Handle::Centre => TransformKind::Grab,
        };
        let mut t = self.new_transform(kind, origin)?;
        match handle {
            Handle::Arrow(a) | Handle::Ring(a) | Handle::Cube(a) => t.axis = Some(a),
            Handle::Plane(a) => t.plane = Some(a),
            Handle::ViewRing => {
                let pivot = self.view.display_frame.to_display_f64(t.centre);
                t.direction = Some((self.view.camera.eye().as_dvec3() - pivot).normalize());
            }
            Handle::Centre => {}
        }
        t.release_confirms = true;
        t.mouse_now = mouse;
        t.snap = self.gizmo.snap.active(false);
        self.gizmo.active = Some(handle);
        self.document.begin_gesture();
        self.update_transform(&mut t, Some(view));
        Some(t)
    }

    /// Draws the gizmo (and the 3D cursor) over the viewport.
    /// `transforming`: a transform runs (the handle it started from stays lit).
    pub(crate) fn draw_gizmo(&mut self, painter: &egui::Painter, view: &ViewportRect, transforming: bool) {
        self.draw_cursor(painter, view);
        if !transforming {
            self.gizmo.active = None;
        }
        let Some(layout) = self.gizmo_layout(view) else { return };
        let camera = self.view.camera;
        let px = |p: DVec3| interaction::project(&camera, view, p).map(|(q, _)| Pos2::new(q.x, q.y));
        let mode = self.gizmo.mode;
        let lit = |h: Handle, c: Color32| {
            if self.gizmo.hovered == Some(h) || self.gizmo.active == Some(h) { HIGHLIGHT } else { c }
        };
        let centre = Pos2::new(layout.centre.x, layout.centre.y);
        if mode.rotates() {
            for a in AXES {
                let c = lit(Handle::Ring(a), colour(a));
                let ring = layout.ring(a);
                for w in ring.windows(2) {
                    if let (Some(p), Some(q)) = (px(w[0].0), px(w[1].0)) {
                        let near = w[0].1 && w[1].1;
                        let stroke = if near { Stroke::new(2.5, c) } else { Stroke::new(1.0, c.gamma_multiply(0.35)) };
                        painter.line_segment([p, q], stroke);
                    }
                }
            }
            let c = lit(Handle::ViewRing, Color32::from_gray(220));
            painter.circle_stroke(centre, VIEW_RING * GIZMO_RADIUS_PX, Stroke::new(1.5, c));
        }
        if mode.moves() || mode.scales() {
            for a in AXES {
                let square: Option<Vec<Pos2>> = layout.plane_square(a).iter().map(|&p| px(p)).collect();
                if let Some(q) = square {
                    let c = lit(Handle::Plane(a), colour(a));
                    painter.add(egui::Shape::convex_polygon(q, c.gamma_multiply(0.55), Stroke::new(1.0, c)));
                }
            }
        }
        for a in AXES {
            let d = a.direction();
            let base = if mode.moves() { SHAFT_FROM } else { 0.0 };
            let tip = if mode.moves() {
                ARROW_TIP
            } else if mode.scales() {
                CUBE_AT
            } else {
                continue;
            };
            let (Some(p), Some(q)) = (px(layout.point(base * d)), px(layout.point(tip * d))) else { continue };
            let c = lit(Handle::Arrow(a), colour(a));
            painter.line_segment([p, q], Stroke::new(3.0, c));
            if mode.moves() {
                // The arrow head: a triangle along the shaft's screen direction.
                let dir = (q - p).normalized();
                let side = egui::vec2(-dir.y, dir.x);
                let head = vec![q + dir * 12.0, q + side * 5.0, q - side * 5.0];
                painter.add(egui::Shape::convex_polygon(head, c, Stroke::NONE));
            }
            if mode.scales()
                && let Some(cube) = px(layout.point(CUBE_AT * d))
            {
                if mode == GizmoMode::All {
                    let from = q + (cube - q).normalized() * 2.0;
                    painter.line_segment([from, cube], Stroke::new(1.5, colour(a)));
                }
                let c = lit(Handle::Cube(a), colour(a));
                let r = egui::Rect::from_center_size(cube, egui::vec2(2.0 * CUBE_PX, 2.0 * CUBE_PX));
                painter.rect_filled(r, 1.0, c);
            }
        }
        if mode.moves() || mode.scales() {
            let c = lit(Handle::Centre, Color32::from_gray(235));
            painter.circle_stroke(centre, CENTRE_PX * 0.7, Stroke::new(2.0, c));
        }
    }
}
