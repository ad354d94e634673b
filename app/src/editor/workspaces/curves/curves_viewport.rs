//! The Curves workspace's viewport: drawing a curve with the mouse or a pen on the chosen plane,
//! selecting a curve by clicking near it (Shift+click picks it for a Coons patch) or a Coons patch
//! by clicking on it, dragging a segment's control points, orbiting,
//! panning and zooming as in the surface workspace; and what it draws over the Coons patches:
//! the curves, the selected one's curvature comb, the segments' control polygons.
//!
//! A stroke is the mouse ray's intersection with the plane through the origin, sampled whenever
//! the pointer has moved 3 points on screen. A control point moves in the plane of its segment
//! (so the segment stays planar), or in the plane facing the camera when that plane is seen
//! edge-on. The whole drag is one undo step.

use crate::editor::curves::CurveTool;
use crate::editor::interaction::{self, ViewportRect};
use crate::editor::select_modes;
use crate::editor::state::EditorState;
use crate::editor::ui::UiState;
use egui::{PointerButton, Sense};
use taut_core::DVec3;
use taut_core::curve::DocCurve;
use taut_render::overlay::{LineSegment, OverlayData, PointMark, PointStyle, polyline_with_comb};

/// Screen distance between samples of a stroke, in points.
const STROKE_STEP: f32 = 3.0;
/// How near the pointer must come to a curve or control point to pick it, in points.
const PICK_RADIUS: f32 = 8.0;

const CURVE_COLOR: [f32; 4] = [0.62, 0.64, 0.68, 1.0];
const SELECTED_COLOR: [f32; 4] = [0.95, 0.95, 0.97, 1.0];
const PICKED_COLOR: [f32; 4] = [1.0, 0.62, 0.15, 1.0];
const CONTROL_COLOR: [f32; 4] = [0.35, 0.85, 0.45, 1.0];
const MISSING_COLOR: [f32; 4] = [1.0, 0.3, 0.3, 1.0];

/// Where the ray meets the plane `n · x = c`; `None` when they are (nearly) parallel or the
/// plane is behind the eye.
fn ray_plane(origin: DVec3, dir: DVec3, n: DVec3, c: f64) -> Option<DVec3> {
    let denom = dir.dot(n);
    if denom.abs() < 1e-6 {
        return None;
    }
    let t = (c - origin.dot(n)) / denom;
    (t > 0.0 && t.is_finite()).then(|| origin + t * dir)
}

impl EditorState {
    /// The model point under `mouse` on the plane through `point` with normal `n`.
    fn mouse_on_plane(&self, view: &ViewportRect, mouse: glam::Vec2, n: DVec3, point: DVec3) -> Option<DVec3> {
        let (o, d) = interaction::unproject_ray(&self.camera, view, mouse);
        let frame = self.display_frame;
        let (o, d) = (frame.to_model(o), (frame.to_model(o + d) - frame.to_model(o)).normalize());
        ray_plane(o, d, n, n.dot(point))
    }

    /// Where model point `p` is on screen.
    fn on_screen(&self, view: &ViewportRect, p: DVec3) -> Option<glam::Vec2> {
        interaction::project(&self.camera, view, self.display_frame.to_display_f64(p)).map(|(pixel, _)| pixel)
    }

    /// The segment control point under the mouse: curve, control index.
    fn pick_control(&self, view: &ViewportRect, mouse: glam::Vec2) -> Option<(usize, usize)> {
        let mut best = None;
        for (i, c) in self.curve_set().curves.iter().enumerate() {
            let Some(s) = c.segment else { continue };
            for (k, p) in s.points().into_iter().enumerate() {
                if let Some(px) = self.on_screen(view, p) {
                    let d = px.distance(mouse);
                    if d <= PICK_RADIUS && best.is_none_or(|(_, _, b)| d < b) {
                        best = Some((i, k, d));
                    }
                }
            }
        }
        best.map(|(i, k, _)| (i, k))
    }

    /// The curve passing nearest the mouse on screen, within the pick radius.
    fn pick_curve(&self, view: &ViewportRect, mouse: glam::Vec2) -> Option<usize> {
        let mut best: Option<(usize, f32)> = None;
        for i in 0..self.curve_set().curves.len() {
            let pixels: Vec<glam::Vec2> =
                self.shown_points(i).iter().filter_map(|&p| self.on_screen(view, p)).collect();
            for w in pixels.windows(2) {
                let (a, b) = (w[0], w[1]);
                let ab = b - a;
                let t = if ab.length_squared() > 0.0 {
                    ((mouse - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = (a + t * ab).distance(mouse);
                if d <= PICK_RADIUS && best.is_none_or(|(_, b)| d < b) {
                    best = Some((i, d));
                }
            }
        }
        best.map(|(i, _)| i)
    }

    /// The Coons patch under the mouse: the nearest one the mouse ray meets.
    fn pick_patch(&self, view: &ViewportRect, mouse: glam::Vec2) -> Option<usize> {
        let (o, d) = interaction::unproject_ray(&self.camera, view, mouse);
        let frame = self.display_frame;
        let (o, d) = (frame.to_model(o), (frame.to_model(o + d) - frame.to_model(o)).normalize());
        let mut best: Option<(f64, usize)> = None;
        for k in 0..self.curve_set().patches.len() {
            let Ok(mesh) = self.shown_patch(k).mesh() else { continue };
            if let Some((t, _)) = select_modes::ray_mesh(o, d, &mesh)
                && best.is_none_or(|(b, _)| t < b)
            {
                best = Some((t, k));
            }
        }
        best.map(|(_, k)| k)
    }

    /// A click of the Select tool at `mouse`: a curve is selected (with Shift, picked or unpicked
    /// for a Coons patch), else the patch under the mouse is selected, else nothing is (Shift
    /// keeps the selection).
    pub(crate) fn click_curves(&mut self, view: &ViewportRect, mouse: glam::Vec2, shift: bool) {
        match self.pick_curve(view, mouse) {
            Some(i) if shift => self.toggle_pick(i),
            Some(i) => self.select_curve(Some(i)),
            None => match self.pick_patch(view, mouse) {
                Some(k) => self.select_patch(Some(k)),
                None if !shift => {
                    self.select_curve(None);
                    self.select_patch(None);
                }
                None => {}
            },
        }
    }

    pub(crate) fn curves_viewport(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point();
        ui_state.viewport_px = Some([
            (rect.min.x * ppp).round().max(0.0) as u32,
            (rect.min.y * ppp).round().max(0.0) as u32,
            (rect.width() * ppp).round().max(1.0) as u32,
            (rect.height() * ppp).round().max(1.0) as u32,
        ]);
        self.viewport_shape = (rect.width() / rect.height().max(1.0), 0.0);
        let view = ViewportRect {
            min: glam::Vec2::new(rect.min.x, rect.min.y),
            size: glam::Vec2::new(rect.width(), rect.height()),
        };
        let (shift, pointer) = ui.ctx().input(|i| (i.modifiers.shift, i.pointer.hover_pos()));
        let mouse = pointer.map(|p| glam::Vec2::new(p.x, p.y));
        if mouse.is_some() {
            ui_state.pointer = mouse;
        }

        // Navigation, as in the surface workspace.
        crate::editor::navigation::navigate(&mut self.camera, ui, &response, rect.height());

        let origin = ui.ctx().input(|i| i.pointer.press_origin()).map(|p| glam::Vec2::new(p.x, p.y)).or(mouse);
        if response.drag_started_by(PointerButton::Primary)
            && let Some(origin) = origin
        {
            match self.curves.tool {
                CurveTool::Draw => {
                    let n = self.curves.plane.normal(self.view_backward());
                    match self.mouse_on_plane(&view, origin, n, DVec3::ZERO) {
                        Some(p) => self.curves.stroke = Some((vec![p], origin)),
                        None => self
                            .notify("the drawing plane is seen edge-on: turn the view or choose another plane", true),
                    }
                }
                CurveTool::Select => {
                    if let Some(hit) = self.pick_control(&view, origin) {
                        self.select_curve(Some(hit.0));
                        self.document.begin_gesture();
                        self.curves.control_drag = Some(hit);
                    }
                }
            }
        }
        if response.dragged_by(PointerButton::Primary)
            && let Some(m) = mouse
        {
            self.continue_curve_drag(&view, m);
        }
        if response.drag_stopped_by(PointerButton::Primary) {
            self.finish_curve_drag();
        }
        if response.clicked_by(PointerButton::Primary)
            && self.curves.tool == CurveTool::Select
            && let Some(m) = mouse
        {
            self.click_curves(&view, m, shift);
        }

        let painter = ui.painter_at(rect);
        let hint = match (self.curves.tool, &self.curves.stroke) {
            (CurveTool::Draw, Some(_)) => "drawing: let go to finish the curve".to_string(),
            (CurveTool::Draw, None) => format!("Draw: drag on the {} to draw a curve", self.curves.plane.label()),
            (CurveTool::Select, _) => {
                "Select: click a curve or patch; Shift+click picks curves for a patch; drag a segment's green control points"
                    .to_string()
            }
        };
        painter.text(
            rect.left_top() + egui::vec2(8.0, 8.0),
            egui::Align2::LEFT_TOP,
            hint,
            egui::FontId::proportional(14.0),
            egui::Color32::WHITE,
        );
        if let Some(i) = self.curves.selected
            && self.curve_set().curves.get(i).is_some_and(|c| c.segment.is_some() && c.points.is_empty())
        {
            painter.text(
                rect.left_top() + egui::vec2(8.0, 28.0),
                egui::Align2::LEFT_TOP,
                "no such segment for these control points and α",
                egui::FontId::proportional(16.0),
                egui::Color32::from_rgb(255, 90, 90),
            );
        }
    }

    /// The pointer moved to `m` with the primary button down.
    pub(crate) fn continue_curve_drag(&mut self, view: &ViewportRect, m: glam::Vec2) {
        if let Some((points, last)) = &self.curves.stroke {
            if m.distance(*last) >= STROKE_STEP {
                let n = self.curves.plane.normal(self.view_backward());
                if let Some(p) = self.mouse_on_plane(view, m, n, DVec3::ZERO) {
                    let mut points = points.clone();
                    if points.last().is_none_or(|q| q.distance(p) > 0.0) {
                        points.push(p);
                    }
                    self.curves.stroke = Some((points, m));
                }
            }
        } else if let Some((i, k)) = self.curves.control_drag
            && let Some(controls) = self.curve_set().curves.get(i).and_then(|c| c.segment)
        {
            let pts = controls.points();
            let normal = (pts[1] - pts[0]).cross(pts[2] - pts[1]).normalize_or_zero();
            let backward = self.view_backward();
            let n = if normal.dot(backward).abs() > 0.2 { normal } else { backward };
            if let Some(p) = self.mouse_on_plane(view, m, n, pts[k]) {
                let mut moved = controls;
                moved.controls[k] = p.to_array();
                self.set_segment(i, moved);
            }
        }
    }

    /// The primary button let go: a stroke becomes a curve, a control drag one undo step.
    pub(crate) fn finish_curve_drag(&mut self) {
        if let Some((points, _)) = self.curves.stroke.take() {
            if points.len() >= 3 {
                let n = self.curve_set().curves.len();
                self.add_curve(DocCurve::new(format!("sketch {}", n + 1), points, false));
            } else {
                self.notify("the stroke was too short for a curve: drag farther", true);
            }
        }
        if self.curves.control_drag.take().is_some() {
            self.document.end_gesture();
        }
    }

    /// What the viewport draws over the surface in the workspace shown.
    pub fn workspace_overlays(&self) -> OverlayData {
        match self.curves.workspace {
            taut_core::curve::Workspace::Curves => self.curves_overlays(),
            _ => self.overlays(),
        }
    }

    /// The curves, combs, control polygons and the stroke, in display coordinates.
    pub fn curves_overlays(&self) -> OverlayData {
        let mut data = OverlayData::default();
        let frame = &self.display_frame;
        let size = self.curves_size();
        let line =
            |a: DVec3, b: DVec3, color, width_px| LineSegment { a: frame.point(a), b: frame.point(b), color, width_px };
        for (i, c) in self.curve_set().curves.iter().enumerate() {
            let points = self.shown_points(i);
            let selected = self.curves.selected == Some(i);
            let color = if self.curves.picked.contains(&i) {
                PICKED_COLOR
            } else if selected {
                SELECTED_COLOR
            } else {
                CURVE_COLOR
            };
            let comb = if selected && self.curves.show_combs {
                crate::editor::state::comb_style(
                    &[points.to_vec()],
                    size,
                    self.curves.comb_length,
                    self.curves.comb_density,
                )
            } else {
                taut_render::overlay::CombStyle { scale: 0.0, ..Default::default() }
            };
            let comb = taut_render::overlay::CombStyle {
                curve_color: color,
                curve_width_px: if selected { 2.5 } else { 1.5 },
                ..comb
            };
            data.on_top_lines.extend(polyline_with_comb(points, c.closed, &comb, frame));
            if let Some(s) = c.segment {
                let p = s.points();
                let color = if c.points.is_empty() { MISSING_COLOR } else { CONTROL_COLOR };
                data.on_top_lines.push(line(p[0], p[1], color, 1.0));
                data.on_top_lines.push(line(p[1], p[2], color, 1.0));
                data.points.extend(p.iter().map(|&q| PointMark {
                    position: frame.point(q),
                    color,
                    radius_px: 5.0,
                    style: PointStyle::Filled,
                }));
            }
        }
        if let Some((points, _)) = &self.curves.stroke {
            data.on_top_lines.extend(points.windows(2).map(|w| line(w[0], w[1], PICKED_COLOR, 2.0)));
        }
        data
    }
}
