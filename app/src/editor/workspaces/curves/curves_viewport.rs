//! The Curves workspace's viewport: drawing a curve with the mouse or a pen on the chosen plane,
//! selecting a curve by clicking near it (Shift+click picks it for a Coons patch) or a Coons patch
//! by clicking on it, dragging a segment's control points, orbiting,
//! panning and zooming as in the surface workspace; and what it draws over the Coons patches:
//! the curves, the selected one's curvature comb, the segments' control polygons.
//!
//! The stroke and the control point's drag are tools ([`crate::editor::tools::curve_stroke`]).

use crate::editor::curves::CurveTool;
use crate::editor::interaction::{self, ViewportRect};
use crate::editor::select_modes;
use crate::editor::state::EditorState;
use crate::editor::tools::curve_stroke::{self, PICKED_COLOR};
use crate::editor::tools::tool::Pointer;
use crate::editor::ui::UiState;
use egui::PointerButton;
use taut_core::DVec3;
use taut_render::overlay::{LineSegment, OverlayData, PointMark, PointStyle, polyline_with_comb};

/// How near the pointer must come to a curve or control point to pick it, in points.
const PICK_RADIUS: f32 = 8.0;

const CURVE_COLOR: [f32; 4] = [0.62, 0.64, 0.68, 1.0];
const SELECTED_COLOR: [f32; 4] = [0.95, 0.95, 0.97, 1.0];
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
    pub(crate) fn mouse_on_plane(
        &self,
        view: &ViewportRect,
        mouse: glam::Vec2,
        n: DVec3,
        point: DVec3,
    ) -> Option<DVec3> {
        let (o, d) = interaction::unproject_ray(&self.view.camera, view, mouse);
        let frame = self.view.display_frame;
        let (o, d) = (frame.to_model(o), (frame.to_model(o + d) - frame.to_model(o)).normalize());
        ray_plane(o, d, n, n.dot(point))
    }

    /// Where model point `p` is on screen.
    fn on_screen(&self, view: &ViewportRect, p: DVec3) -> Option<glam::Vec2> {
        interaction::project(&self.view.camera, view, self.view.display_frame.to_display_f64(p)).map(|(pixel, _)| pixel)
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
        let (o, d) = interaction::unproject_ray(&self.view.camera, view, mouse);
        let frame = self.view.display_frame;
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
        let (response, view, mouse) = crate::editor::viewport::allocate(ui, ui_state);
        let rect = response.rect;
        self.viewport_shape = (rect.width() / rect.height().max(1.0), 0.0);
        let shift = ui.ctx().input(|i| i.modifiers.shift);

        // Navigation, as in the surface workspace.
        crate::editor::navigation::navigate(&mut self.view.camera, ui, &response, rect.height());

        let pointer = Pointer { ui, response: &response, view, mouse };
        let running = ui_state.tool.pointer(self, &pointer);
        let origin = ui.ctx().input(|i| i.pointer.press_origin()).map(|p| glam::Vec2::new(p.x, p.y)).or(mouse);
        if !running
            && response.drag_started_by(PointerButton::Primary)
            && let Some(origin) = origin
        {
            let tool = match self.curves.tool {
                CurveTool::Draw => curve_stroke::start_stroke(self, &view, origin),
                CurveTool::Select => {
                    self.pick_control(&view, origin).and_then(|(i, k)| curve_stroke::start_control_drag(self, i, k))
                }
            };
            if let Some(tool) = tool {
                ui_state.tool.start(self, tool);
                ui_state.tool.pointer(self, &pointer);
            }
        }
        if !running
            && response.clicked_by(PointerButton::Primary)
            && self.curves.tool == CurveTool::Select
            && let Some(m) = mouse
        {
            self.click_curves(&view, m, shift);
        }

        let painter = ui.painter_at(rect);
        let hint = match self.curves.tool {
            CurveTool::Draw => format!("Draw: drag on the {} to draw a curve", self.curves.plane.label()),
            CurveTool::Select => {
                "Select: click a curve or patch; Shift+click picks curves for a patch; drag a segment's green control points"
                    .to_string()
            }
        };
        if !ui_state.tool.is_running() {
            pointer.say(&hint);
        }
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
        let frame = &self.view.display_frame;
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
        data
    }
}
