//! The curve-mesh scheme in the editor (issue 9): the designer finishes the shape by moving
//! curve-mesh vertices, tilting their tangent planes and pulling the curves' inner control points,
//! and only the Gregory patches around what moved change (`docs/curve-mesh-gregory.md`).
//!
//! In this scheme the viewport draws the curves over the patches, every curve-mesh vertex as a
//! dot, and for the one selected vertex its Bézier control legs (vertex to inner control point,
//! one per curve), its tangent plane as a square and its normal as a handle. Left drag on a vertex
//! moves the selection in the view plane, X, Y or Z while dragging locks an axis and Esc cancels,
//! through the same [`interaction::drag_positions`] as cage points; dragging a leg's end moves
//! that inner control point (the core keeps it in the vertex's tangent plane); dragging the
//! normal's tip turns the tangent plane so that the normal points at the cursor (from the plane
//! the drag began with, so dragging back puts it back exactly). The panel types coordinates and
//! the normal's tilt and azimuth, switches the continuity overlay (each shared curve coloured by
//! its measured G2 jump, a curve whose G1 angle exceeds [`G1_TOLERANCE`] drawn thick red; legend
//! beside it; measured again after every change, so it follows a drag) and the highlight of the
//! patches the last edit rebuilt, and rebuilds from the cage after asking.
//!
//! The cage in this scheme: drawn as a faint wire for reference and not editable in the viewport
//! (its points would sit among the curve-mesh vertices and steal their picks). A designer who
//! wants to change the cage switches to another scheme, edits it there, and comes back: the
//! curve-mesh edits follow the cage edit by [`taut_core::gregory::carry`]'s rule.
//!
//! Vertices on the far side of the surface (tangent plane turned away from the eye) are neither
//! drawn nor picked. Weak spots: picking is a linear scan over every curve-mesh vertex (fine for
//! a few thousand); the facing test is per vertex, so a vertex on a silhouette may flicker;
//! there is no box selection of curve-mesh vertices (Shift+click adds); the tilt and azimuth
//! fields turn the tangent plane by the smallest rotation from the current normal, so the inner
//! points' twist about the normal depends on the path the typed values took.

use crate::editor::interaction::{self, ViewportRect};

use crate::editor::state::EditorState;
use crate::editor::tools::curve_mesh_drag;
use crate::editor::tools::tool::{ActiveTool, Pointer};
use egui::PointerButton;
use taut_core::gregory::continuity::{ContinuityReport, DEFAULT_BOUNDARY_SAMPLES};
use taut_core::surface::SchemeKind;
use taut_core::surface::curve_mesh::CurveMeshSurface;
use taut_core::{DVec3, EdgeId, VertexId};
use taut_render::colormap::ColorMap;
use taut_render::overlay::{Legend, LineSegment, OverlayData, PointMark, PointStyle};

/// A shared curve whose measured normal angle exceeds this (radians) is not G1: drawn thick red.
pub const G1_TOLERANCE: f64 = 1e-6;
/// Length of the normal handle and half the side of the tangent-plane square, as a fraction of
/// the cage's bounding diagonal.
pub const HANDLE_FRACTION: f64 = 0.06;
/// Segments each curve is drawn with.
pub const CURVE_SEGMENTS: usize = 16;
const PICK_RADIUS_PX: f32 = 8.0;

const CURVE: [f32; 4] = [0.02, 0.02, 0.03, 0.85];
const NOT_G1: [f32; 4] = [0.9, 0.0, 0.0, 1.0];
const TOUCHED: [f32; 4] = [1.0, 0.45, 0.0, 1.0];
const VERTEX: [f32; 4] = [0.05, 0.08, 0.15, 1.0];
const SELECTED: [f32; 4] = [1.0, 0.33, 0.0, 1.0];
const HOVERED: [f32; 4] = [0.72, 0.80, 0.95, 1.0];
const LEG: [f32; 4] = [0.95, 0.85, 0.1, 1.0];
const PLANE: [f32; 4] = [0.0, 0.75, 0.85, 0.8];
const FAINT_CAGE: [f32; 4] = [0.30, 0.40, 0.60, 0.35];

/// What a pick or a drag in the curve-mesh scheme takes hold of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Handle {
    /// A curve-mesh vertex.
    Vertex(VertexId),
    /// The inner control point of `curve` next to its end vertex `end` (the selected vertex).
    Inner { curve: EdgeId, end: VertexId },
    /// The tip of the selected vertex's normal: turns its tangent plane.
    Normal(VertexId),
}

/// The curve-mesh selection and overlay switches (part of the editor state).
#[derive(Clone, Debug, Default)]
pub struct CurveMeshEditing {
    /// Selected curve-mesh vertices.
    pub selected: Vec<VertexId>,
    /// What the cursor is over.
    pub hovered: Option<Handle>,
    /// The continuity overlay is on.
    pub show_continuity: bool,
    /// The patches the last edit rebuilt are outlined.
    pub highlight_last_edit: bool,
    continuity: Option<MeasuredContinuity>,
}

/// The continuity of the surface's curve mesh as last measured.
#[derive(Clone, Debug)]
pub struct MeasuredContinuity {
    /// The surface's id and update count it was measured at.
    at: (u64, u64),
    /// The curve of every shared boundary, in the report's order.
    pub curves: Vec<EdgeId>,
    /// Per shared boundary its G1 angle and G2 jump.
    pub report: ContinuityReport,
}

/// The curve-mesh part of the UI state.
#[derive(Debug, Default)]
pub struct CurveMeshUi {
    /// "Rebuild from cage" is asking whether to discard the edits.
    pub confirm_rebuild: bool,
}

/// Linear RGBA of a colour-map entry (the map's colours are sRGB).
fn linear(c: [u8; 3]) -> [f32; 4] {
    let f = |x: u8| (x as f32 / 255.0).powf(2.2);
    [f(c[0]), f(c[1]), f(c[2]), 1.0]
}

/// Two unit vectors spanning the plane normal to `n`.
fn tangent_frame(n: DVec3) -> (DVec3, DVec3) {
    let a = n.any_orthonormal_vector();
    (a, n.cross(a))
}

impl EditorState {
    /// The curve-mesh surface, when the document is in that scheme and it is built.
    pub fn curve_mesh_surface(&self) -> Option<&CurveMeshSurface> {
        self.surface.as_ref().and_then(|s| s.scheme.as_curve_mesh())
    }

    /// The length of the normal handle in model units.
    pub(crate) fn handle_length(&self) -> f64 {
        HANDLE_FRACTION * self.document.doc().cage.bounding_diagonal()
    }

    /// Every handle the designer can take hold of, with its model position: the selected
    /// vertex's normal tip and inner points first, then every curve-mesh vertex on a curve.
    pub fn curve_mesh_handles(&self) -> Vec<(Handle, DVec3)> {
        let Some(s) = self.curve_mesh_surface() else { return Vec::new() };
        let cm = s.curve_mesh();
        let t = cm.topology();
        let mut out = Vec::new();
        if let [v] = self.curve_mesh.selected[..]
            && v.index() < cm.vertex_count()
            && !t.is_isolated(v)
        {
            let p = cm.vertex_position(v);
            out.push((Handle::Normal(v), p + cm.vertex_normal(v) * self.handle_length()));
            for h in t.outgoing(v) {
                if let Some(q) = cm.inner_point(h.edge(), v) {
                    out.push((Handle::Inner { curve: h.edge(), end: v }, q));
                }
            }
        }
        out.extend(
            t.vertices()
                .filter(|&v| self.curve_mesh_vertex_faces_eye(v))
                .map(|v| (Handle::Vertex(v), cm.vertex_position(v))),
        );
        out
    }

    /// True for a curve-mesh vertex on a curve whose tangent plane faces the camera: the others
    /// are on the far side of the surface, neither drawn nor picked (a dot seen through the
    /// surface would take the pick from the one in front of it). Selected vertices always are.
    pub fn curve_mesh_vertex_faces_eye(&self, v: VertexId) -> bool {
        let Some(s) = self.curve_mesh_surface() else { return false };
        let cm = s.curve_mesh();
        if v.index() >= cm.vertex_count() || cm.topology().is_isolated(v) {
            return false;
        }
        let eye = self.view.display_frame.to_model(self.view.camera.eye().as_dvec3());
        self.curve_mesh.selected.contains(&v) || (eye - cm.vertex_position(v)).dot(cm.vertex_normal(v)) > 0.0
    }

    /// The handle under `mouse` (points), nearest on screen, the front one among ties.
    pub fn pick_curve_mesh_handle(&self, view: &ViewportRect, mouse: glam::Vec2) -> Option<Handle> {
        let handles = self.curve_mesh_handles();
        let positions: Vec<DVec3> = handles.iter().map(|&(_, p)| self.view.display_frame.to_display_f64(p)).collect();
        interaction::pick_vertex(&self.view.camera, view, &positions, mouse, PICK_RADIUS_PX)
            .map(|i| handles[i.index()].0)
    }

    /// Selects a curve-mesh vertex; with `add`, toggles it in the selection.
    pub fn click_curve_mesh_vertex(&mut self, v: VertexId, add: bool) {
        let selected = &mut self.curve_mesh.selected;
        if !add {
            selected.clear();
            selected.push(v);
        } else if let Some(k) = selected.iter().position(|&x| x == v) {
            selected.remove(k);
        } else {
            selected.push(v);
        }
    }

    /// Drops selected curve-mesh vertices that no longer exist (after undo of a cage change).
    fn prune_curve_mesh_selection(&mut self) {
        let n = self.curve_mesh_surface().map_or(0, |s| s.curve_mesh().vertex_count());
        self.curve_mesh.selected.retain(|v| v.index() < n);
    }

    /// Measures the continuity again when the overlay is on and the surface changed.
    pub fn refresh_curve_mesh_continuity(&mut self) {
        if !self.curve_mesh.show_continuity {
            return;
        }
        let Some(s) = self.curve_mesh_surface() else { return };
        let at = (s.id(), s.updates());
        if self.curve_mesh.continuity.as_ref().is_some_and(|m| m.at == at) {
            return;
        }
        let (curves, report) = s.curve_mesh().continuity(DEFAULT_BOUNDARY_SAMPLES);
        self.curve_mesh.continuity = Some(MeasuredContinuity { at, curves, report });
    }

    /// The continuity measured on the surface shown now (`None` while the overlay is off).
    pub fn measured_continuity(&self) -> Option<&MeasuredContinuity> {
        let s = self.curve_mesh_surface()?;
        let m = self.curve_mesh.continuity.as_ref()?;
        (self.curve_mesh.show_continuity && m.at == (s.id(), s.updates())).then_some(m)
    }

    /// The continuity overlay's legend.
    pub fn curve_mesh_legend(&self) -> Option<Legend> {
        let m = self.measured_continuity()?;
        Some(Legend {
            map: ColorMap::Sequential,
            min: 0.0,
            max: m.report.max_curvature_jump.max(1e-12),
            title: format!("G2 jump (max G1 {:.0e} rad)", m.report.max_normal_angle),
        })
    }

    /// What the curve-mesh scheme keeps up to date every frame, with or without a drag: the
    /// cage's hover is off (the curve mesh is picked instead), the selection holds only vertices
    /// that exist, the continuity overlay is measured on the surface shown. False in other schemes.
    pub(crate) fn curve_mesh_upkeep(&mut self) -> bool {
        if self.document.doc().scheme != SchemeKind::CurveMesh {
            return false;
        }
        self.view.selection.hovered_vertex = None;
        self.view.selection.hovered_edge = None;
        self.prune_curve_mesh_selection();
        self.refresh_curve_mesh_continuity();
        true
    }

    /// The viewport's mouse in the curve-mesh scheme with no drag running: hover, click to
    /// select (Shift adds), a press on a vertex, an inner point or the normal's tip starts its
    /// drag ([`crate::editor::tools::curve_mesh_drag`]). Returns false (doing nothing) in other
    /// schemes.
    pub(crate) fn curve_mesh_viewport(&mut self, pointer: &Pointer, tool: &mut ActiveTool) -> bool {
        if !self.curve_mesh_upkeep() {
            return false;
        }
        let (ui, response, view, mouse) = (pointer.ui, pointer.response, &pointer.view, pointer.mouse);
        let shift = ui.ctx().input(|i| i.modifiers.shift);
        self.curve_mesh.hovered =
            response.hovered().then_some(mouse).flatten().and_then(|m| self.pick_curve_mesh_handle(view, m));
        if response.drag_started_by(PointerButton::Primary) {
            let origin = ui.ctx().input(|i| i.pointer.press_origin()).map(|p| glam::Vec2::new(p.x, p.y)).or(mouse);
            if let Some(origin) = origin
                && let Some(handle) = self.pick_curve_mesh_handle(view, origin)
                && let Some(drag) = curve_mesh_drag::start(self, handle, origin, shift)
            {
                tool.start(self, drag);
                tool.pointer(self, pointer);
                return true;
            }
        }
        if response.clicked_by(PointerButton::Primary) {
            match self.curve_mesh.hovered {
                Some(Handle::Vertex(v)) => self.click_curve_mesh_vertex(v, shift),
                Some(_) => {}
                None if !shift => self.curve_mesh.selected.clear(),
                None => {}
            }
        }
        pointer.say("Drag a curve-mesh vertex, its legs' ends or its normal's tip");
        true
    }

    /// The curve-mesh overlays: curves (coloured by continuity when it is on), the patches of the
    /// last edit, vertices, the selected vertex's legs, tangent plane and normal, and a faint
    /// cage. False (nothing drawn) when the document is not in the curve-mesh scheme or its
    /// surface is not built.
    pub(crate) fn curve_mesh_overlays(&self, data: &mut OverlayData) -> bool {
        if self.document.doc().scheme != SchemeKind::CurveMesh {
            return false;
        }
        let Some(s) = self.curve_mesh_surface() else { return false };
        let frame = &self.view.display_frame;
        let cm = s.curve_mesh();
        let t = cm.topology();
        if self.view.display.show_cage {
            let cage = &self.document.doc().cage;
            data.on_top_lines.extend(cage.edges().map(|e| {
                let (a, b) = cage.edge_vertices(e);
                LineSegment {
                    a: frame.point(cage.position(a)),
                    b: frame.point(cage.position(b)),
                    color: FAINT_CAGE,
                    width_px: 1.0,
                }
            }));
        }
        let mut style = vec![(CURVE, 1.5f32); t.edge_count()];
        if let Some(m) = self.measured_continuity() {
            let max = m.report.max_curvature_jump.max(1e-12);
            for (e, b) in m.curves.iter().zip(&m.report.boundaries) {
                style[e.index()] = if b.normal_angle > G1_TOLERANCE {
                    (NOT_G1, 4.0)
                } else {
                    (linear(ColorMap::Sequential.color((b.curvature_jump / max) as f32)), 3.0)
                };
            }
        }
        if self.curve_mesh.highlight_last_edit
            && let Some(changed) = s.last_changed()
        {
            for &f in changed.patches.iter().filter(|f| f.index() < t.face_count()) {
                for h in t.face_halfedges(f) {
                    style[h.edge().index()] = (TOUCHED, 3.0);
                }
            }
        }
        for e in t.edges() {
            let curve = cm.curve(e);
            let (color, width_px) = style[e.index()];
            data.surface_lines.extend((0..CURVE_SEGMENTS).map(|k| LineSegment {
                a: frame.point(curve.point(k as f64 / CURVE_SEGMENTS as f64)),
                b: frame.point(curve.point((k + 1) as f64 / CURVE_SEGMENTS as f64)),
                color,
                width_px,
            }));
        }
        for v in t.vertices().filter(|&v| self.curve_mesh_vertex_faces_eye(v)) {
            let selected = self.curve_mesh.selected.contains(&v);
            let hovered = self.curve_mesh.hovered == Some(Handle::Vertex(v));
            data.points.push(PointMark {
                position: frame.point(cm.vertex_position(v)),
                color: if hovered {
                    HOVERED
                } else if selected {
                    SELECTED
                } else {
                    VERTEX
                },
                radius_px: if selected || hovered { 5.0 } else { 3.5 },
                style: PointStyle::Filled,
            });
        }
        if let [v] = self.curve_mesh.selected[..]
            && v.index() < cm.vertex_count()
        {
            let (p, n) = (cm.vertex_position(v), cm.vertex_normal(v));
            let length = self.handle_length();
            let line = |a: DVec3, b: DVec3, color, width_px| LineSegment {
                a: frame.point(a),
                b: frame.point(b),
                color,
                width_px,
            };
            for h in t.outgoing(v) {
                let e = h.edge();
                if let Some(q) = cm.inner_point(e, v) {
                    data.on_top_lines.push(line(p, q, LEG, 2.0));
                    let hovered = self.curve_mesh.hovered == Some(Handle::Inner { curve: e, end: v });
                    data.points.push(PointMark {
                        position: frame.point(q),
                        color: if hovered { HOVERED } else { LEG },
                        radius_px: 5.0,
                        style: PointStyle::Ring,
                    });
                }
            }
            let (a, b) = tangent_frame(n);
            let corners = [a + b, b - a, -a - b, a - b].map(|d| p + d * length);
            for k in 0..4 {
                data.on_top_lines.push(line(corners[k], corners[(k + 1) % 4], PLANE, 1.5));
            }
            let tip = p + n * length;
            data.on_top_lines.push(line(p, tip, PLANE, 2.0));
            let hovered = self.curve_mesh.hovered == Some(Handle::Normal(v));
            data.points.push(PointMark {
                position: frame.point(tip),
                color: if hovered { HOVERED } else { PLANE },
                radius_px: 5.0,
                style: PointStyle::Filled,
            });
        }
        true
    }
}

#[cfg(test)]
#[path = "curve_mesh_tests.rs"]
mod tests;
