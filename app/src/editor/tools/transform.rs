//! G, R and S as in Blender: grab (move), rotate and scale the selected cage vertices about
//! the pivot ([`crate::editor::pivot`]: median centre, bounding-box centre, 3D cursor or active vertex).
//! The mouse drives it (grab: in the view plane, along a locked axis as a drag does, or in a
//! locked plane; rotate: the angle the cursor turns about the pivot on screen; scale: the ratio
//! of the cursor's distances from the pivot on screen); X, Y or Z locks an axis, Shift+X, Y or Z
//! the plane normal to it (move or scale in the other two; again: unlocks); Ctrl held (or the
//! toolbar's snap toggle) snaps ([`crate::editor::snapping`]); typed numbers (digits, '.', '-',
//! Backspace) give the exact distance, angle in degrees or factor, never snapped; Enter or a
//! click confirms, Esc or a right click cancels. The whole transform is one undo step (one
//! gesture). The on-screen gizmo ([`crate::editor::gizmo`]) starts the same transform with its lock set.
//!
//! Typed values without an axis: grab moves along X (with a plane lock, along the first free
//! axis), rotate turns about Z (with a lock, about the locked axis), scale scales evenly (with a
//! plane lock, in the plane). The mouse without a lock rotates about the view axis, as Blender.
//! A lock keeps the coordinates it locks bit for bit (a move adds exactly zero to them, a scale
//! or a rotation about a world axis copies them). Weak where Blender does more: no snapping to
//! other vertices, no Tab between the axes of a typed plane move.

use crate::editor::document::Edit;
use crate::editor::interaction::{self, Axis, ViewportRect};
use crate::editor::shortcuts;
use crate::editor::snapping;
use crate::editor::state::EditorState;
use crate::editor::tools::snap_targets::{self, SnapTarget};
use crate::editor::tools::tool::{CageStamp, End, Flow, Pointer, Tool, end_vertex_move};
use egui::Key;
use glam::DMat3;
use glam::Vec2;
use taut_core::{DVec3, VertexId};

/// The end of the message of a transform value that is not previewed.
const PREVIEW_WAITS: &str = "the preview waits for a value that keeps it open";

/// Which transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TransformKind {
    Grab,
    Rotate,
    Scale,
}

/// A transform under way.
#[derive(Clone, Debug)]
pub struct Transform {
    pub kind: TransformKind,
    /// The vertices and where they were, in model coordinates.
    pub start: Vec<(VertexId, DVec3)>,
    /// The pivot.
    pub centre: DVec3,
    /// The pointer when the transform began (the first position seen).
    pub mouse_start: Option<Vec2>,
    pub mouse_now: Option<Vec2>,
    pub axis: Option<Axis>,
    /// Shift+X/Y/Z: the plane normal to this axis (grab, scale); rotate turns about it.
    pub plane: Option<Axis>,
    /// A lock along any unit direction in model coordinates (extrude's normal, the gizmo's view
    /// ring); X, Y, Z or a plane lock replaces it.
    pub direction: Option<DVec3>,
    /// What has been typed.
    pub typed: String,
    /// Snap to increments this frame (Ctrl held, or the toolbar's toggle).
    pub snap: bool,
    /// The grid step of a snapped move, in model units (fixed when the transform began).
    pub grid_step: f64,
    /// A gizmo drag: letting go of the button confirms.
    pub release_confirms: bool,
    /// The cage's topology when it began: another one (a file opened meanwhile) ends it.
    pub topology: CageStamp,
    /// The value the cage shows now, for the header's readout.
    pub applied: Applied,
    /// The geometry a snapped move landed on (ringed on screen), model coordinates.
    pub snapped_to: Option<DVec3>,
}

/// A transform's value as applied: what the header reads out while it runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Applied {
    /// A move by this offset, in model units.
    Offset(DVec3),
    /// A turn by this many degrees.
    Degrees(f64),
    /// A scale by this factor.
    Factor(f64),
}

impl Transform {
    /// A transform of `start` about `centre` with no lock.
    pub fn new(kind: TransformKind, start: Vec<(VertexId, DVec3)>, centre: DVec3, mouse: Option<Vec2>) -> Self {
        Transform {
            kind,
            start,
            centre,
            mouse_start: mouse,
            mouse_now: mouse,
            axis: None,
            plane: None,
            direction: None,
            typed: String::new(),
            snap: false,
            grid_step: 1.0,
            release_confirms: false,
            topology: CageStamp::default(),
            snapped_to: None,
            applied: match kind {
                TransformKind::Grab => Applied::Offset(DVec3::ZERO),
                TransformKind::Rotate => Applied::Degrees(0.0),
                TransformKind::Scale => Applied::Factor(1.0),
            },
        }
    }

    /// The header's readout, as Blender shows it: ΔX ΔY ΔZ and the distance of a move (the
    /// offset along the normal of an extrusion), the angle of a turn, the factor of a scale.
    /// Lengths carry the document's `unit`.
    pub fn numbers(&self, unit: taut_core::document::LengthUnit) -> String {
        let n = |x: f64| unit.length(x);
        match self.applied {
            Applied::Offset(d) if self.direction.is_some() => {
                let along = self.direction.map_or(0.0, |u| d.dot(u));
                format!("offset {} along the normal (Δ {} {} {})", n(along), n(d.x), n(d.y), n(d.z))
            }
            Applied::Offset(d) => {
                format!("ΔX {}  ΔY {}  ΔZ {}  distance {}", n(d.x), n(d.y), n(d.z), n(d.length()))
            }
            Applied::Degrees(a) => format!("angle {:.2}°", if a == 0.0 { 0.0 } else { a }),
            Applied::Factor(f) => format!("factor {f:.4}"),
        }
    }

    /// The world axis a rotation turns about, or the locked direction; `None`: the view axis.
    fn rotation_axis(&self) -> Option<DVec3> {
        self.direction.or(self.axis.or(self.plane).map(Axis::direction))
    }

    /// What the status line says of the lock.
    pub fn lock_text(&self) -> String {
        match (self.direction, self.axis, self.plane) {
            (Some(_), ..) => match self.kind {
                TransformKind::Rotate => "about the view axis".to_string(),
                _ => "along the normal".to_string(),
            },
            (None, Some(a), _) if self.kind == TransformKind::Rotate => format!("about {a:?}"),
            (None, Some(a), _) => format!("along {a:?}"),
            (None, None, Some(a)) if self.kind == TransformKind::Rotate => format!("about {a:?}"),
            (None, None, Some(a)) => format!("in the plane normal to {a:?} ({a:?} locked)"),
            (None, None, None) => "free".to_string(),
        }
    }
}

/// The other two axes of a plane lock, in x, y, z order.
fn free_axes(plane: Axis) -> [Axis; 2] {
    match plane {
        Axis::X => [Axis::Y, Axis::Z],
        Axis::Y => [Axis::X, Axis::Z],
        Axis::Z => [Axis::X, Axis::Y],
    }
}

fn component(axis: Axis) -> usize {
    match axis {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    }
}

/// Where the vertices go for a typed `value`, and the value as applied.
fn typed(t: &Transform, value: f64) -> (Vec<(VertexId, DVec3)>, Applied) {
    match t.kind {
        TransformKind::Grab => {
            let direction = match (t.direction, t.axis, t.plane) {
                (Some(d), ..) => d,
                (None, Some(a), _) => a.direction(),
                (None, None, Some(p)) => free_axes(p)[0].direction(),
                (None, None, None) => DVec3::X,
            };
            (moved(t, direction * value), Applied::Offset(direction * value))
        }
        TransformKind::Rotate => (rotated(t, t.rotation_axis().unwrap_or(DVec3::Z), value), Applied::Degrees(value)),
        TransformKind::Scale => (scaled(t, value), Applied::Factor(value)),
    }
}

/// The start positions moved by `offset` (a zero component leaves that coordinate's bits).
fn moved(t: &Transform, offset: DVec3) -> Vec<(VertexId, DVec3)> {
    t.start.iter().map(|&(v, p)| (v, p + offset)).collect()
}

/// Turned by `degrees` about the unit `axis` through the pivot; about a world axis, the
/// coordinate along it is copied.
fn rotated(t: &Transform, axis: DVec3, degrees: f64) -> Vec<(VertexId, DVec3)> {
    let c = t.centre;
    let turn = DMat3::from_axis_angle(axis, degrees.to_radians());
    let world = [Axis::X, Axis::Y, Axis::Z].into_iter().find(|a| a.direction() == axis);
    t.start
        .iter()
        .map(|&(v, p)| {
            let mut q = c + turn * (p - c);
            if let Some(a) = world {
                q[component(a)] = p[component(a)];
            }
            (v, q)
        })
        .collect()
}

fn scaled(t: &Transform, factor: f64) -> Vec<(VertexId, DVec3)> {
    let c = t.centre;
    if let Some(d) = t.direction {
        // Along a direction: p + (f − 1)·((p − c)·d)·d.
        return t.start.iter().map(|&(v, p)| (v, p + (factor - 1.0) * (p - c).dot(d) * d)).collect();
    }
    let k = match (t.axis, t.plane) {
        (Some(a), _) => {
            let mut k = [1.0; 3];
            k[component(a)] = factor;
            k
        }
        (None, Some(p)) => {
            let mut k = [factor; 3];
            k[component(p)] = 1.0;
            k
        }
        (None, None) => [factor; 3],
    };
    t.start
        .iter()
        .map(|&(v, p)| {
            let mut q = p;
            for i in 0..3 {
                // A factor of one copies the coordinate, so a lock keeps its bits.
                if k[i] != 1.0 {
                    q[i] = c[i] + k[i] * (p[i] - c[i]);
                }
            }
            (v, q)
        })
        .collect()
}

/// Presses of `key` with Shift only (the plane locks), consumed.
fn take_shifted(input: &mut egui::InputState, key: Key) -> bool {
    let mut found = false;
    input.events.retain(|event| match event {
        egui::Event::Key { key: k, pressed: true, modifiers, .. }
            if *k == key && modifiers.shift && !modifiers.command && !modifiers.alt =>
        {
            found = true;
            false
        }
        _ => true,
    });
    found
}

/// Starts G, R or S on the selection (one gesture); a message when nothing is selected.
pub(crate) fn start(editor: &mut EditorState, kind: TransformKind, mouse: Option<Vec2>) -> Option<Box<dyn Tool>> {
    let t = editor.new_transform(kind, mouse)?;
    editor.document.begin_gesture();
    Some(Box::new(t))
}

impl Tool for Transform {
    /// Axis and plane locks, typed numbers, Enter and Esc.
    fn keys(&mut self, editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        let t = self;
        let mut flow = Flow::Continue;
        ctx.input_mut(|i| {
            for (key, axis) in [(Key::X, Axis::X), (Key::Y, Axis::Y), (Key::Z, Axis::Z)] {
                if shortcuts::take_plain(i, key) {
                    t.axis = if t.axis == Some(axis) && t.direction.is_none() { None } else { Some(axis) };
                    (t.plane, t.direction) = (None, None);
                }
                if take_shifted(i, key) {
                    t.plane = if t.plane == Some(axis) && t.direction.is_none() { None } else { Some(axis) };
                    (t.axis, t.direction) = (None, None);
                }
            }
            shortcuts::take_typed_number(i, &mut t.typed, true);
            if shortcuts::take_plain(i, Key::Enter) {
                flow = Flow::Keep;
            } else if shortcuts::take_plain(i, Key::Escape) {
                flow = Flow::Cancel;
            }
            // Typed characters arrive as text too: drop them so no widget sees them.
            i.events.retain(|e| !matches!(e, egui::Event::Text(_)));
        });
        editor.update_transform(t, None);
        flow
    }

    /// The mouse drives it; a click confirms (a gizmo drag: the release), a right click cancels.
    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        let snap = editor.gizmo.snap.active(pointer.modifiers().command);
        if let Some(m) = pointer.mouse {
            self.mouse_start.get_or_insert(m);
            if self.mouse_now != Some(m) || self.snap != snap {
                self.mouse_now = Some(m);
                self.snap = snap;
                editor.update_transform(self, Some(&pointer.view));
            }
        }
        let released = self.release_confirms && pointer.ui.ctx().input(|i| i.pointer.primary_released());
        if released || pointer.clicked() {
            Flow::Keep
        } else if pointer.right_clicked() {
            Flow::Cancel
        } else {
            Flow::Continue
        }
    }

    fn readout(&self, editor: &EditorState) -> Option<String> {
        Some(self.numbers(editor.document.doc().units))
    }

    /// The geometry a snapped move landed on, ringed.
    fn overlay(&self, editor: &EditorState, painter: &egui::Painter, view: &ViewportRect) {
        let Some(target) = self.snapped_to else { return };
        let at = editor.view.display_frame.to_display_f64(target);
        if let Some((p, _)) = interaction::project(&editor.view.camera, view, at) {
            let colour = egui::Color32::from_rgb(255, 160, 40);
            painter.circle_stroke(egui::pos2(p.x, p.y), 9.0, egui::Stroke::new(2.0, colour));
            painter.circle_filled(egui::pos2(p.x, p.y), 2.5, colour);
        }
    }

    fn status(&self, editor: &EditorState) -> String {
        let what = match self.kind {
            TransformKind::Grab => "move",
            TransformKind::Rotate => "rotate (degrees)",
            TransformKind::Scale => "scale",
        };
        let lock = self.lock_text();
        let typed = if self.typed.is_empty() { String::new() } else { format!(" {}", self.typed) };
        let snapping = match (self.snap, self.kind) {
            (false, _) => String::new(),
            (true, TransformKind::Grab) => format!(", snap {}", self.grid_step),
            (true, TransformKind::Rotate) => format!(", snap {}°", editor.gizmo.snap.degrees),
            (true, TransformKind::Scale) => format!(", snap {}", editor.gizmo.snap.scale),
        };
        format!(
            "{what} {lock}{typed}{snapping}: X, Y, Z lock an axis, Shift+X, Y, Z a plane, Ctrl snaps, \
             type a value, Enter or click sets, Esc cancels"
        )
    }

    /// Keeps the transform (one undo step) or puts every vertex back.
    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        end_vertex_move(editor, self.start, end);
    }

    fn is_stale(&self, editor: &EditorState) -> bool {
        self.topology.is_stale(editor)
    }

    fn shows_gizmo(&self) -> bool {
        true
    }
}

impl EditorState {
    /// A transform of the selection about the pivot, or a message when nothing is selected.
    pub(crate) fn new_transform(&mut self, kind: TransformKind, mouse: Option<Vec2>) -> Option<Transform> {
        let cage = &self.document.doc().cage;
        let vertices = self.selected_vertices_with_edge_ends();
        let start: Vec<(VertexId, DVec3)> = vertices.iter().map(|&v| (v, cage.position(v))).collect();
        if start.is_empty() {
            self.notify("select the cage vertices, edges or faces to transform first", true);
            return None;
        }
        let centre = self.pivot_of(&vertices);
        let mut t = Transform::new(kind, start, centre, mouse);
        t.grid_step = self.gizmo.snap.grid_step(&self.view.camera, &self.view.display_frame);
        t.topology = CageStamp::now(self);
        Some(t)
    }

    /// Moves the vertices where the typed value or the mouse says, and notes the value applied.
    pub(crate) fn update_transform(&mut self, t: &mut Transform, view: Option<&ViewportRect>) {
        let (moved, applied) = if let Ok(value) = t.typed.parse::<f64>() {
            if !value.is_finite() {
                return;
            }
            t.snapped_to = None;
            typed(t, value)
        } else {
            let (Some(view), Some(from), Some(to)) = (view, t.mouse_start, t.mouse_now) else { return };
            t.snapped_to = self.geometry_snap(t, view, to).map(|(_, target)| target);
            self.mouse_positions(t, view, from, to)
        };
        if let Some(face) = self.newly_collapsed_face(&moved) {
            // A passing value of the gesture (a scale through 0) is not previewed: it would
            // collapse a face, and under the mirror its corners would stay on the plane for the
            // rest of the gesture. The cage waits at the gesture's start.
            let what = if t.typed.is_empty() { "this position".to_string() } else { format!("the value {}", t.typed) };
            let text = format!("{what} would collapse face {}; {PREVIEW_WAITS}", face.0);
            let start = t.start.clone();
            if self.notice.as_ref().is_none_or(|n| n.text != text) {
                self.notify(text, true);
            }
            self.emit(Edit::MoveVertices(start));
            t.applied = Transform::new(t.kind, Vec::new(), t.centre, None).applied;
            return;
        }
        // A value that keeps every face open: the refusal of an earlier one no longer holds.
        if self.notice.as_ref().is_some_and(|n| n.text.ends_with(PREVIEW_WAITS)) {
            self.notice = None;
        }
        self.emit(Edit::MoveVertices(moved));
        t.applied = applied;
    }

    /// A face that `moved` would collapse and that is open now, if any.
    fn newly_collapsed_face(&self, moved: &[(VertexId, DVec3)]) -> Option<taut_core::FaceId> {
        let doc = self.document.doc();
        let mut trial = doc.clone();
        if trial.apply(Edit::MoveVertices(moved.to_vec())).is_err() {
            return None;
        }
        let before = crate::editor::live::collapsed_faces(&doc.cage);
        crate::editor::live::collapsed_faces(&trial.cage).into_iter().find(|f| !before.contains(f))
    }

    fn mouse_positions(
        &self,
        t: &Transform,
        view: &ViewportRect,
        from: Vec2,
        to: Vec2,
    ) -> (Vec<(VertexId, DVec3)>, Applied) {
        let frame = self.view.display_frame;
        let snap = &self.gizmo.snap;
        let unmoved = (t.start.clone(), Transform::new(t.kind, Vec::new(), t.centre, None).applied);
        match t.kind {
            TransformKind::Grab => {
                let offset = match self.geometry_snap(t, view, to) {
                    // Unlocked, the centre lands on the target exactly (a lone vertex is the
                    // target, bit for bit).
                    Some((offset, target)) if t.direction.is_none() && t.axis.is_none() && t.plane.is_none() => {
                        let centre = t.start.iter().map(|&(_, p)| p).sum::<DVec3>() / t.start.len() as f64;
                        let moves = t.start.iter().map(|&(v, p)| (v, target + (p - centre))).collect();
                        return (moves, Applied::Offset(offset));
                    }
                    Some((offset, _)) => offset,
                    None => self.grab_offset(t, view, from, to),
                };
                if !offset.is_finite() {
                    return unmoved;
                }
                (moved(t, offset), Applied::Offset(offset))
            }
            TransformKind::Rotate | TransformKind::Scale => {
                let centre = frame.to_display_f64(t.centre);
                let Some((c, _)) = interaction::project(&self.view.camera, view, centre) else {
                    return unmoved;
                };
                let (a, b) = (from - c, to - c);
                if a.length() < 1.0 || b.length() < 1.0 {
                    return unmoved;
                }
                if t.kind == TransformKind::Scale {
                    let factor = f64::from(b.length() / a.length());
                    let factor = if t.snap { snapping::to_multiple(factor, snap.scale) } else { factor };
                    (scaled(t, factor), Applied::Factor(factor))
                } else {
                    // Screen y runs down: a counter-clockwise turn on screen is a negative perp,
                    // and counter-clockwise about an axis that points at the viewer.
                    let screen = f64::from(-a.perp_dot(b).atan2(a.dot(b))).to_degrees();
                    let towards_viewer = (self.view.camera.eye().as_dvec3() - centre).normalize();
                    let axis = t.rotation_axis().unwrap_or(towards_viewer);
                    let degrees = if axis.dot(towards_viewer) < 0.0 { -screen } else { screen };
                    let degrees = if t.snap { snapping::to_multiple(degrees, snap.degrees) } else { degrees };
                    (rotated(t, axis, degrees), Applied::Degrees(degrees))
                }
            }
        }
    }

    /// A snapped grab onto geometry: the offset that puts the selection's centre on the target
    /// under the cursor, and the target.
    fn geometry_snap(&self, t: &Transform, view: &ViewportRect, mouse: Vec2) -> Option<(DVec3, DVec3)> {
        if !t.snap || self.gizmo.snap.target == SnapTarget::Grid {
            return None;
        }
        let moving: Vec<VertexId> = t.start.iter().map(|&(v, _)| v).collect();
        let target = self.snap_target(self.gizmo.snap.target, view, mouse, &moving)?;
        let centre = t.start.iter().map(|&(_, p)| p).sum::<DVec3>() / t.start.len() as f64;
        let axis = t.direction.or(t.axis.map(Axis::direction));
        let normal = t.plane.map(Axis::direction);
        Some((snap_targets::offset_to(centre, target, axis, normal), target))
    }

    /// A grab's offset in model coordinates for the mouse going from `from` to `to`, locked and
    /// snapped as the transform says.
    fn grab_offset(&self, t: &Transform, view: &ViewportRect, from: Vec2, to: Vec2) -> DVec3 {
        let frame = self.view.display_frame;
        let centroid = t.start.iter().map(|&(_, p)| frame.to_display_f64(p)).sum::<DVec3>() / t.start.len() as f64;
        let anchor = [(VertexId(0), centroid)];
        let view_plane = |axis: Option<Axis>| {
            interaction::drag_positions(&self.view.camera, view, &anchor, from, to, axis)[0].1 - centroid
        };
        let limit = 100.0 * f64::from(self.view.camera.distance);
        let ray = |m: Vec2| interaction::unproject_ray(&self.view.camera, view, m);
        let display = match (t.direction, t.axis, t.plane) {
            (Some(d), ..) => {
                let param = |m: Vec2| {
                    let (o, r) = ray(m);
                    let w = centroid - o;
                    let b = d.dot(r);
                    let den = 1.0 - b * b;
                    (den > 1e-9).then(|| (b * r.dot(w) - d.dot(w)) / den)
                };
                let s = match (param(from), param(to)) {
                    (Some(a), Some(b)) => (b - a).clamp(-limit, limit),
                    _ => 0.0,
                };
                let s = frame.scale * s;
                let s = if t.snap { snapping::to_multiple(s, t.grid_step) } else { s };
                return d * s;
            }
            (None, Some(a), _) => view_plane(Some(a)),
            (None, None, Some(p)) => {
                let n = p.direction();
                let hit = |m: Vec2| {
                    let (o, r) = ray(m);
                    let along = r.dot(n);
                    let t = (centroid - o).dot(n) / along;
                    (along.abs() > 0.02 && t > 0.0).then(|| o + t * r)
                };
                let mut offset = match (hit(from), hit(to)) {
                    (Some(a), Some(b)) if (b - a).length() <= limit => b - a,
                    // The plane is seen edge on: follow the view plane within it.
                    _ => view_plane(None),
                };
                offset[component(p)] = 0.0;
                offset
            }
            (None, None, None) => view_plane(None),
        };
        let offset = display * frame.scale;
        if !t.snap {
            offset
        } else if self.gizmo.snap.absolute {
            let centre = t.start.iter().map(|&(_, p)| p).sum::<DVec3>() / t.start.len() as f64;
            snapping::snap_to_grid(centre, offset, t.grid_step)
        } else {
            snapping::snap_offset(offset, t.grid_step)
        }
    }
}

#[cfg(test)]
#[path = "transform_tests.rs"]
mod tests;
