//! X-ray (Alt+Z, View ▸ X-ray), as in Blender's edit mode: off, the cage's vertices, edges and
//! face dots that other faces of the cage hide are drawn dimmer and are never picked, so a
//! click, a box or a crease lands only on what the designer sees; on, the whole cage is drawn
//! alike and everything under the cursor can be picked.
//!
//! What is hidden comes from [`taut_core::mesh::visibility`]: rays from the eye against the cage's
//! own faces (the cage hides its back, as a designer reads it; the smooth surface inside the
//! cage does not hide the cage). The answer is kept until the cage or the eye moves.

use crate::editor::interaction::{self, ViewportRect};
use crate::editor::select_modes;
use crate::editor::state::EditorState;
use glam::Vec2;
use std::sync::Arc;
use taut_core::mesh::visibility::{Occluder, Visibility};
use taut_core::{DVec3, EdgeId, FaceId, PolyMesh, VertexId};

/// The last visibility worked out, and what it was worked out for: the cage's faces indexed
/// for its shape (kept while only the eye moves) and the answer for one eye.
#[derive(Debug, Default)]
pub struct VisibilityCache {
    shape: Option<(u64, Vec<DVec3>, Arc<Occluder>)>,
    eye: Option<DVec3>,
    seen: Option<Arc<Visibility>>,
}

/// How far from a face's centre dot, in pixels, a click picks the face with X-ray on.
pub const FACE_DOT_PICK_PX: f32 = 8.0;

impl EditorState {
    /// What the eye sees of the cage, or `None` with X-ray on (everything counts as seen).
    pub fn cage_seen(&self) -> Option<Arc<Visibility>> {
        if self.view.display.xray {
            return None;
        }
        let cage = &self.document.doc().cage;
        let eye = self.view.display_frame.to_model(self.view.camera.eye().as_dvec3());
        let mut cache = self.visibility.borrow_mut();
        let same_shape = cache.shape.as_ref().is_some_and(|(topology, positions, _)| {
            *topology == cage.topology_generation() && positions.as_slice() == cage.positions()
        });
        if !same_shape {
            let occluder = Arc::new(Occluder::new(cage));
            cache.shape = Some((cage.topology_generation(), cage.positions().to_vec(), occluder));
            cache.seen = None;
        }
        if cache.eye != Some(eye) || cache.seen.is_none() {
            let occluder = cache.shape.as_ref().map(|(_, _, o)| o.clone()).expect("indexed above");
            cache.seen = Some(Arc::new(occluder.visibility(cage, eye)));
            cache.eye = Some(eye);
        }
        cache.seen.clone()
    }

    /// Alt+Z: X-ray on or off, said in the message strip.
    pub fn toggle_xray(&mut self) {
        self.view.display.xray = !self.view.display.xray;
        let text = if self.view.display.xray {
            "X-ray on: the whole cage is drawn and can be picked, back included (Alt+Z)"
        } else {
            "X-ray off: the back of the cage is dimmed and cannot be picked (Alt+Z)"
        };
        self.notify(text.to_string(), false);
    }

    /// The vertex under `mouse` among those seen (all with X-ray on). `cage` is in display
    /// coordinates, with the document cage's numbering.
    pub(crate) fn pick_cage_vertex(
        &self,
        view: &ViewportRect,
        cage: &PolyMesh,
        mouse: Vec2,
        radius_px: f32,
    ) -> Option<VertexId> {
        let seen = self.cage_seen();
        let pickable = |v: VertexId| seen.as_ref().is_none_or(|s| s.vertex(v));
        interaction::pick_vertex_where(&self.view.camera, view, cage.positions(), mouse, radius_px, pickable)
    }

    /// The edge under `mouse` among those seen (all with X-ray on).
    pub(crate) fn pick_cage_edge(
        &self,
        view: &ViewportRect,
        cage: &PolyMesh,
        mouse: Vec2,
        radius_px: f32,
    ) -> Option<EdgeId> {
        let seen = self.cage_seen();
        let pickable = |e: EdgeId| seen.as_ref().is_none_or(|s| s.edge(e));
        interaction::pick_edge_where(&self.view.camera, view, cage, mouse, radius_px, pickable)
    }

    /// The face under `mouse`: the first one the mouse ray meets (the one in front, which is
    /// always seen); with X-ray on, the face whose centre dot is nearest the mouse within
    /// [`FACE_DOT_PICK_PX`] first, so a face behind can be picked by its dot.
    pub(crate) fn pick_cage_face(&self, view: &ViewportRect, cage: &PolyMesh, mouse: Vec2) -> Option<FaceId> {
        if self.view.display.xray {
            let centres: Vec<DVec3> = cage
                .faces()
                .map(|f| {
                    let ring: Vec<DVec3> = cage.face_vertices(f).map(|v| cage.position(v)).collect();
                    ring.iter().copied().sum::<DVec3>() / ring.len().max(1) as f64
                })
                .collect();
            if let Some(dot) = interaction::pick_vertex(&self.view.camera, view, &centres, mouse, FACE_DOT_PICK_PX) {
                return Some(FaceId(dot.0));
            }
        }
        select_modes::pick_face(&self.view.camera, view, cage, mouse)
    }

    /// The vertices of a rubber band from `from` to `to` among those seen (all with X-ray on).
    pub(crate) fn box_cage(&self, view: &ViewportRect, cage: &PolyMesh, from: Vec2, to: Vec2) -> Vec<VertexId> {
        let seen = self.cage_seen();
        let pickable = |v: VertexId| seen.as_ref().is_none_or(|s| s.vertex(v));
        interaction::box_select_where(&self.view.camera, view, cage.positions(), from, to, pickable)
    }
}
