//! Framing: the camera fitted to the whole model (Home), to the selection (numpad .), and a
//! new or opened document kept framed while its surface settles. The display frame (model to
//! display coordinates) is fitted here too, so any finite model is drawn and picked well.

use crate::editor::state::EditorState;
use taut_render::DisplayFrame;

impl EditorState {
    /// Frames a new or opened document again, once the viewport is laid out and while its
    /// surface settles, so the whole surface shows with a margin; stops when the surface has
    /// settled or the designer has moved the view or edited the document (a drag must not move
    /// the camera under the mouse).
    pub(crate) fn keep_new_document_framed(&mut self) {
        let Some((camera, revision)) = self.auto_frame else { return };
        if self.view.camera != camera || self.document.revision() != revision {
            self.auto_frame = None;
            return;
        }
        self.frame_all();
        let settled = self.surface_error.is_some() || (self.surface.is_some() && !self.busy());
        self.auto_frame = (!settled).then_some((self.view.camera, revision));
    }

    /// Frames the whole cage and surface (in the Curves workspace, its curves and patches when
    /// there are any): a display frame fitted to them, and the camera filling the viewport (left
    /// of the legend, when one is shown).
    pub fn frame_all(&mut self) {
        if self.curves.workspace == taut_core::curve::Workspace::Curves {
            let points = self.curve_points();
            if !points.is_empty() {
                self.frame_model_points(&points);
                return;
            }
        }
        let cage = &self.document.doc().cage;
        let mut points: Vec<taut_core::DVec3> = cage.positions().to_vec();
        points.extend(self.mirror_frame_points());
        points.extend(self.curve_points());
        if let Some(mesh) = self.surface_mesh() {
            let step = (mesh.vertex_count() / 20_000).max(1);
            points.extend(mesh.positions().iter().step_by(step));
        }
        self.frame_model_points(&points);
    }

    /// A display frame fitted to model points, and the camera framing them; nothing without
    /// points.
    pub(crate) fn frame_model_points(&mut self, points: &[taut_core::DVec3]) {
        if points.is_empty() {
            return;
        }
        self.view.display_frame = DisplayFrame::for_points(points);
        self.frame_display_points(points);
    }

    /// Frames model points in the current display frame.
    fn frame_display_points(&mut self, points: &[taut_core::DVec3]) {
        let display: Vec<glam::Vec3> = points.iter().map(|&p| self.view.display_frame.point(p)).collect();
        let (aspect, margin_fraction) = self.viewport_shape;
        let legend = self.colours_shown() || self.curve_mesh_legend().is_some();
        let margin_fraction = if legend { margin_fraction } else { 0.0 };
        self.view.camera.frame_points(&display, aspect * (1.0 - margin_fraction));
        // Centre the model in what the legend leaves free: half the margin to the left, in
        // pixels of a viewport one unit high.
        self.view.camera.pan(-0.5 * margin_fraction * aspect, 0.0, 1.0);
    }

    /// Frames the selected vertices (or everything when nothing is selected).
    pub fn frame_selection(&mut self) {
        let cage = &self.document.doc().cage;
        let mut points: Vec<taut_core::DVec3> =
            self.view.selection.vertices.iter().map(|&v| cage.position(v)).collect();
        for &e in &self.view.selection.edges {
            let (a, b) = cage.edge_vertices(e);
            points.extend([cage.position(a), cage.position(b)]);
        }
        for &f in &self.view.selection.faces {
            points.extend(cage.face_vertices(f).map(|v| cage.position(v)));
        }
        match taut_core::mesh::bounding_box(&points) {
            Some((lo, hi)) => {
                // A lone vertex is framed with some of the model around it.
                let pad = taut_core::DVec3::splat(0.15 * cage.bounding_diagonal());
                let (lo, hi) = (lo - pad, hi + pad);
                let corners: Vec<taut_core::DVec3> = (0..8)
                    .map(|k| {
                        taut_core::DVec3::new(
                            if k & 1 == 0 { lo.x } else { hi.x },
                            if k & 2 == 0 { lo.y } else { hi.y },
                            if k & 4 == 0 { lo.z } else { hi.z },
                        )
                    })
                    .collect();
                self.frame_display_points(&corners);
            }
            None => self.frame_all(),
        }
    }
}
