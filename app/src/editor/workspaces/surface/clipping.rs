//! The clipping plane (Display ▸ clipping plane), as Rhino's ClippingPlane or Blender's
//! clipping region: the surface, its ghosts and the lines drawn on it (wireframe, curves,
//! sections) are cut away on one side of a plane normal to x, y or z, so a designer sees the
//! surface's profile and inside. The cage, the gizmos and the measurements stay whole: they are
//! what the designer edits and reads. The plane is drawn as an outline around the surface's box
//! with a handle; dragging the handle (`tools::clip_plane_drag`) moves the plane along its
//! normal, Esc puts it back.

use crate::editor::interaction::{self, ViewportRect};
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{ActiveTool, Pointer};
use egui::{Color32, Pos2, Stroke};
use glam::{DVec3, Vec2, Vec4};
use taut_render::overlay::{LineSegment, OverlayData};

/// The plane's outline and handle colour.
const PLANE_COLOUR: [f32; 4] = [0.95, 0.55, 0.15, 0.9];
/// How near the handle's tip a press must land, in points.
pub const HANDLE_REACH: f32 = 10.0;

/// Where the plane is and which side it cuts away.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipSettings {
    /// 0, 1 or 2: the plane is normal to x, y or z.
    pub axis: usize,
    /// Where it crosses the axis, in model units.
    pub offset: f64,
    /// Off: what lies beyond the plane (larger coordinates) is cut away; on: what lies before.
    pub flip: bool,
}

impl ClipSettings {
    /// The plane through the middle of `lo..hi` on `axis`.
    pub fn through_middle(axis: usize, lo: DVec3, hi: DVec3) -> Self {
        let axis = axis.min(2);
        ClipSettings { axis, offset: 0.5 * (lo[axis] + hi[axis]), flip: false }
    }

    /// The unit normal pointing at the side cut away, in model (and display) directions.
    pub fn cut_normal(&self) -> DVec3 {
        let mut n = DVec3::ZERO;
        n[self.axis.min(2)] = if self.flip { -1.0 } else { 1.0 };
        n
    }

    /// Whether a model point is cut away.
    pub fn cuts(&self, p: DVec3) -> bool {
        let n = self.cut_normal();
        n.dot(p) > n[self.axis.min(2)] * self.offset
    }

    /// The plane `(n, d)` in display coordinates for the renderer: cut where `n·p > d`.
    pub fn display_plane(&self, frame: &taut_render::DisplayFrame) -> Vec4 {
        let n = self.cut_normal();
        let mut on_plane = frame.origin;
        on_plane[self.axis.min(2)] = self.offset;
        let d = n.dot(frame.to_display_f64(on_plane));
        n.as_vec3().extend(d as f32)
    }
}

impl EditorState {
    /// The clipping plane for the renderer, when it is on (display coordinates).
    pub fn clip_plane(&self) -> Option<Vec4> {
        self.view.display.clip.map(|c| c.display_plane(&self.view.display_frame))
    }

    /// The point of the surface under `mouse` (model coordinates) that is seen: the first hit the
    /// clipping plane does not cut away.
    pub(crate) fn surface_under(&self, view: &ViewportRect, mouse: Vec2) -> Option<DVec3> {
        let mesh = self.surface_mesh()?;
        let frame = self.view.display_frame;
        let mut shown = mesh.clone();
        shown.positions_mut().iter_mut().for_each(|p| *p = frame.to_display_f64(*p));
        let (origin, direction) = interaction::unproject_ray(&self.view.camera, view, mouse);
        let clip = self.view.display.clip;
        let seen = |t: f64| clip.is_none_or(|c| !c.cuts(frame.to_model(origin + t * direction)));
        let t = crate::editor::pivot::ray_cast_where(&shown, origin, direction, seen)?;
        Some(frame.to_model(origin + t * direction))
    }

    /// The surface's box, in model coordinates (the cage's while there is no surface yet).
    fn clip_box(&self) -> Option<(DVec3, DVec3)> {
        self.surface_mesh().and_then(|m| m.bounding_box()).or_else(|| self.document.doc().cage.bounding_box())
    }

    /// The plane's outline around the surface's box, and the handle's base and tip, in display
    /// coordinates.
    fn clip_geometry(&self) -> Option<([DVec3; 4], DVec3, DVec3)> {
        let clip = self.view.display.clip?;
        let (lo, hi) = self.clip_box()?;
        let frame = &self.view.display_frame;
        let k = clip.axis.min(2);
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let pad = 0.1 * (hi - lo).max_element().max(1e-9);
        let corner = |a: f64, b: f64| {
            let mut q = DVec3::ZERO;
            (q[k], q[i], q[j]) = (clip.offset, a, b);
            frame.to_display_f64(q)
        };
        let (i0, i1, j0, j1) = (lo[i] - pad, hi[i] + pad, lo[j] - pad, hi[j] + pad);
        let corners = [corner(i0, j0), corner(i1, j0), corner(i1, j1), corner(i0, j1)];
        let base = corner(0.5 * (i0 + i1), 0.5 * (j0 + j1));
        // The handle points at the side cut away, a quarter of the plane's size long.
        let length = 0.25 * (corners[2] - corners[0]).length();
        Some((corners, base, base + clip.cut_normal() * length))
    }

    /// Adds the clipping plane's outline.
    pub(crate) fn clip_overlays(&self, data: &mut OverlayData) {
        let Some((corners, _, _)) = self.clip_geometry() else { return };
        for k in 0..4 {
            data.on_top_lines.push(LineSegment {
                a: corners[k].as_vec3(),
                b: corners[(k + 1) % 4].as_vec3(),
                color: PLANE_COLOUR,
                width_px: 1.5,
            });
        }
    }

    /// The handle's base and tip on screen, when the plane is on and in front of the camera.
    pub(crate) fn clip_handle(&self, view: &ViewportRect) -> Option<(Vec2, Vec2, DVec3)> {
        let (_, base, tip) = self.clip_geometry()?;
        let camera = &self.view.camera;
        let (b, _) = interaction::project(camera, view, base)?;
        let (t, _) = interaction::project(camera, view, tip)?;
        Some((b, t, base))
    }

    /// Whether a press at `mouse` lands on the handle (its tip, or along it).
    pub(crate) fn over_clip_handle(&self, view: &ViewportRect, mouse: Vec2) -> bool {
        let Some((base, tip, _)) = self.clip_handle(view) else { return false };
        let along = tip - base;
        let t = if along.length_squared() > 0.0 {
            ((mouse - base).dot(along) / along.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        mouse.distance(tip) <= HANDLE_REACH || (t > 0.2 && mouse.distance(base + along * t) <= HANDLE_REACH * 0.6)
    }

    /// A press on the handle starts moving the plane (before the transform gizmo: the handle is
    /// the smaller target); true when it did.
    pub(crate) fn clip_handle_viewport(&mut self, pointer: &Pointer, tool: &mut ActiveTool) -> bool {
        if !pointer.response.drag_started_by(egui::PointerButton::Primary) {
            return false;
        }
        let origin = pointer.ui.ctx().input(|i| i.pointer.press_origin()).map(|p| Vec2::new(p.x, p.y));
        let Some(o) = origin.filter(|&o| self.over_clip_handle(&pointer.view, o)) else { return false };
        let Some(started) = crate::editor::tools::clip_plane_drag::start(self, &pointer.view, o) else { return false };
        tool.start(self, started);
        tool.pointer(self, pointer);
        true
    }

    /// Draws the handle over the viewport (brighter while hovered or dragged).
    pub(crate) fn draw_clip_handle(&self, painter: &egui::Painter, view: &ViewportRect, hot: bool) {
        let Some((base, tip, _)) = self.clip_handle(view) else { return };
        let [r, g, b, _] = PLANE_COLOUR.map(|c| (c * 255.0) as u8);
        let colour = if hot { Color32::from_rgb(255, 200, 120) } else { Color32::from_rgb(r, g, b) };
        let pos = |p: Vec2| Pos2::new(p.x, p.y);
        painter.line_segment([pos(base), pos(tip)], Stroke::new(2.5, colour));
        painter.circle_filled(pos(tip), 6.0, colour);
        painter.circle_stroke(pos(base), 4.0, Stroke::new(1.5, colour));
    }

    /// The Display panel's clipping-plane controls.
    pub(crate) fn clip_controls(&mut self, ui: &mut egui::Ui) {
        let mut on = self.view.display.clip.is_some();
        ui.checkbox(&mut on, "clipping plane")
            .on_hover_text("Cut the surface away on one side of a plane to see its profile; drag the orange handle");
        let bounds = self.clip_box().unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)));
        match (on, self.view.display.clip.as_mut()) {
            (false, _) => self.view.display.clip = None,
            (true, None) => self.view.display.clip = Some(ClipSettings::through_middle(2, bounds.0, bounds.1)),
            (true, Some(clip)) => {
                ui.horizontal(|ui| {
                    for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                        if ui.radio(clip.axis == axis, name).on_hover_text("The axis the plane is normal to").clicked()
                        {
                            *clip = ClipSettings {
                                flip: clip.flip,
                                ..ClipSettings::through_middle(axis, bounds.0, bounds.1)
                            };
                        }
                    }
                    ui.checkbox(&mut clip.flip, "flip").on_hover_text("Cut away the other side");
                });
                let span = (bounds.1 - bounds.0).max_element().max(1e-9);
                ui.horizontal(|ui| {
                    ui.add(egui::DragValue::new(&mut clip.offset).speed(span / 200.0).max_decimals(6).prefix("at "))
                        .on_hover_text("Where the plane crosses its axis, in model units");
                    if ui.button("middle").on_hover_text("Through the middle of the surface").clicked() {
                        *clip = ClipSettings {
                            flip: clip.flip,
                            ..ClipSettings::through_middle(clip.axis, bounds.0, bounds.1)
                        };
                    }
                });
                if !clip.offset.is_finite() {
                    clip.offset = 0.5 * (bounds.0[clip.axis] + bounds.1[clip.axis]);
                }
            }
        }
    }
}

#[cfg(test)]
#[path = "clipping_tests.rs"]
mod tests;
