//! The Curves workspace's two drags. Draw: a left drag draws a stroke on the chosen plane (the
//! mouse ray's intersection with the plane through the origin, sampled whenever the pointer has
//! moved 3 points on screen); letting go makes it a curve, Esc drops it. Select: a left drag on
//! a segment's control point moves it in the plane of its segment (so the segment stays planar),
//! or in the plane facing the camera when that plane is seen edge-on; the whole drag is one undo
//! step, and Esc puts the segment back. The Curves viewport starts them
//! ([`crate::editor::workspaces::curves::curves_viewport`]).

use crate::editor::interaction::{self, ViewportRect};
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{End, Flow, Pointer, Tool, escape};
use taut_core::DVec3;
use taut_core::curve::{DocCurve, SegmentControls};

/// Screen distance between samples of a stroke, in points.
const STROKE_STEP: f32 = 3.0;
/// The colour of a stroke, and of the curves picked for a patch (linear RGBA).
pub(crate) const PICKED_COLOR: [f32; 4] = [1.0, 0.62, 0.15, 1.0];

/// A stroke being drawn, in model coordinates, and the last mouse position sampled.
#[derive(Clone, Debug)]
pub struct CurveStroke {
    pub points: Vec<DVec3>,
    last: glam::Vec2,
}

/// Starts a stroke at `origin`; `None`, with a message, when the plane is seen edge-on.
pub(crate) fn start_stroke(editor: &mut EditorState, view: &ViewportRect, origin: glam::Vec2) -> Option<Box<dyn Tool>> {
    let n = editor.curves.plane.normal(editor.view_backward());
    match editor.mouse_on_plane(view, origin, n, DVec3::ZERO) {
        Some(p) => Some(Box::new(CurveStroke { points: vec![p], last: origin })),
        None => {
            editor.notify("the drawing plane is seen edge-on: turn the view or choose another plane", true);
            None
        }
    }
}

impl Tool for CurveStroke {
    fn keys(&mut self, _editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        escape(ctx)
    }

    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        if pointer.dragged()
            && let Some(m) = pointer.mouse
            && m.distance(self.last) >= STROKE_STEP
        {
            let n = editor.curves.plane.normal(editor.view_backward());
            if let Some(p) = editor.mouse_on_plane(&pointer.view, m, n, DVec3::ZERO) {
                if self.points.last().is_none_or(|q| q.distance(p) > 0.0) {
                    self.points.push(p);
                }
                self.last = m;
            }
        }
        pointer.release()
    }

    /// The stroke so far.
    fn overlay(&self, editor: &EditorState, painter: &egui::Painter, view: &ViewportRect) {
        let [r, g, b, a] = PICKED_COLOR;
        let colour: egui::Color32 = egui::Rgba::from_rgba_premultiplied(r, g, b, a).into();
        let frame = editor.view.display_frame;
        let screen: Vec<egui::Pos2> = self
            .points
            .iter()
            .filter_map(|&p| interaction::project(&editor.view.camera, view, frame.to_display_f64(p)))
            .map(|(q, _)| egui::pos2(q.x, q.y))
            .collect();
        painter.add(egui::Shape::line(screen, egui::Stroke::new(2.0, colour)));
    }

    fn status(&self, _editor: &EditorState) -> String {
        "drawing: let go to finish the curve, Esc drops it".into()
    }

    /// Let go: the stroke becomes a curve when it is long enough.
    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        if end != End::Keep {
            return;
        }
        if self.points.len() >= 3 {
            let n = editor.curve_set().curves.len();
            let curve = DocCurve::new(format!("sketch {}", n + 1), self.points, false);
            editor.emit_run(move |e| e.add_curve(curve));
        } else {
            editor.notify("the stroke was too short for a curve: drag farther", true);
        }
    }

    fn navigates(&self) -> bool {
        true
    }
}

/// A segment's control point being dragged.
#[derive(Clone, Debug)]
pub struct ControlDrag {
    curve: usize,
    control: usize,
    /// The segment when the drag began (Esc puts it back).
    before: SegmentControls,
}

/// Starts dragging control point `control` of curve `curve`'s segment (one gesture).
pub(crate) fn start_control_drag(editor: &mut EditorState, curve: usize, control: usize) -> Option<Box<dyn Tool>> {
    let before = editor.curve_set().curves.get(curve)?.segment?;
    editor.select_curve(Some(curve));
    editor.document.begin_gesture();
    Some(Box::new(ControlDrag { curve, control, before }))
}

impl Tool for ControlDrag {
    fn keys(&mut self, _editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        escape(ctx)
    }

    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        if pointer.dragged()
            && let Some(m) = pointer.mouse
            && let Some(controls) = editor.curve_set().curves.get(self.curve).and_then(|c| c.segment)
        {
            let pts = controls.points();
            let normal = (pts[1] - pts[0]).cross(pts[2] - pts[1]).normalize_or_zero();
            let backward = editor.view_backward();
            let n = if normal.dot(backward).abs() > 0.2 { normal } else { backward };
            if let Some(p) = editor.mouse_on_plane(&pointer.view, m, n, pts[self.control]) {
                let mut moved = controls;
                moved.controls[self.control] = p.to_array();
                let curve = self.curve;
                editor.emit_run(move |e| e.set_segment(curve, moved));
            }
        }
        pointer.release()
    }

    fn status(&self, _editor: &EditorState) -> String {
        "moving a control point in its segment's plane: let go to set, Esc puts it back".into()
    }

    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        if end == End::Cancel {
            let (curve, before) = (self.curve, self.before);
            editor.emit_run(move |e| e.set_segment(curve, before));
        }
        editor.emit_end_gesture();
    }

    /// The curve went (undo, a file opened) under the drag.
    fn is_stale(&self, editor: &EditorState) -> bool {
        editor.curve_set().curves.get(self.curve).is_none_or(|c| c.segment.is_none())
    }

    fn navigates(&self) -> bool {
        true
    }
}
