//! Snapping to geometry while moving, as Blender's snap targets: with snapping on (the toolbar's
//! toggle, or Ctrl held) and a target other than the grid chosen in the toolbar's steps menu, a
//! move puts the selection's centre exactly on the target under the cursor: a cage vertex, the
//! midpoint of a cage edge, the centre of a cage face (the mean of its corners), or the point of
//! the surface under the cursor. What moves is never a target. The target is ringed while the
//! move runs. A locked axis or plane keeps its lock: the centre goes to the target's coordinate
//! along the axis, or in the plane. Typed values are never snapped.

use crate::editor::interaction::{self, ViewportRect};
use crate::editor::state::EditorState;
use glam::Vec2;
use taut_core::{DVec3, VertexId};

/// How near the cursor a target must be drawn to be taken, in points.
pub const SNAP_RADIUS_PX: f32 = 15.0;

/// What a snapped move lands on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SnapTarget {
    /// Whole steps of the grid (`crate::editor::snapping`).
    #[default]
    Grid,
    Vertex,
    EdgeMidpoint,
    FaceCentre,
    Surface,
}

impl SnapTarget {
    pub const ALL: [SnapTarget; 5] =
        [SnapTarget::Grid, SnapTarget::Vertex, SnapTarget::EdgeMidpoint, SnapTarget::FaceCentre, SnapTarget::Surface];

    pub fn name(self) -> &'static str {
        match self {
            SnapTarget::Grid => "grid steps",
            SnapTarget::Vertex => "vertex",
            SnapTarget::EdgeMidpoint => "edge midpoint",
            SnapTarget::FaceCentre => "face centre",
            SnapTarget::Surface => "surface",
        }
    }
}

impl EditorState {
    /// The target of `kind` drawn nearest the cursor at `mouse` (within [`SNAP_RADIUS_PX`]; the
    /// surface: where the cursor's ray meets it), in model coordinates; the `moving` vertices and
    /// what they belong to are never targets.
    pub(crate) fn snap_target(
        &self,
        kind: SnapTarget,
        view: &ViewportRect,
        mouse: Vec2,
        moving: &[VertexId],
    ) -> Option<DVec3> {
        let cage = &self.document.doc().cage;
        let frame = self.view.display_frame;
        let mut moves = vec![false; cage.vertex_count()];
        for v in moving.iter().filter(|v| v.index() < cage.vertex_count()) {
            moves[v.index()] = true;
        }
        let candidates: Vec<DVec3> = match kind {
            SnapTarget::Grid => return None,
            SnapTarget::Vertex => cage.vertices().filter(|v| !moves[v.index()]).map(|v| cage.position(v)).collect(),
            SnapTarget::EdgeMidpoint => cage
                .edges()
                .map(|e| cage.edge_vertices(e))
                .filter(|(a, b)| !moves[a.index()] && !moves[b.index()])
                .map(|(a, b)| (cage.position(a) + cage.position(b)) * 0.5)
                .collect(),
            SnapTarget::FaceCentre => cage
                .faces()
                .filter(|&f| cage.face_vertices(f).all(|v| !moves[v.index()]))
                .map(|f| {
                    let (sum, n) =
                        cage.face_vertices(f).fold((DVec3::ZERO, 0.0), |(s, n), v| (s + cage.position(v), n + 1.0));
                    sum / n
                })
                .collect(),
            SnapTarget::Surface => return self.surface_under(view, mouse),
        };
        candidates
            .into_iter()
            .filter_map(|p| {
                let (pixel, _) = interaction::project(&self.view.camera, view, frame.to_display_f64(p))?;
                let d = pixel.distance(mouse);
                (d <= SNAP_RADIUS_PX).then_some((d, p))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, p)| p)
    }
}

/// The offset that puts `centre` on `target`, keeping a lock: along an axis or direction only
/// that component, in a plane the normal component stays zero.
pub fn offset_to(centre: DVec3, target: DVec3, axis: Option<DVec3>, plane_normal: Option<DVec3>) -> DVec3 {
    let offset = target - centre;
    match (axis, plane_normal) {
        (Some(d), _) => d * d.dot(offset),
        (None, Some(n)) => offset - n * n.dot(offset),
        (None, None) => offset,
    }
}
