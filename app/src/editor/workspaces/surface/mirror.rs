//! Mirror modelling in the editor: Mesh ▸ Mirror (plane X, Y or Z through the origin or through
//! the selection's centre, Apply, Off), the Cage panel's toggle and Shift+M, the surface of a
//! one-half cage made on the mirrored whole, and the virtual half drawn as a ghost.
//!
//! The option is the document's (`taut_core::symmetry`): turning it on or off, and Apply mirror
//! (the virtual half made real), are each one undo step through [`EditorState::edit`]; the moves,
//! fixed flags, tensions and creases of either half reach the other in the core's
//! `Document::apply`, so every drag, G/R/S, panel field and gizmo move is mirrored. Only the real
//! half is picked and edited: the virtual half is not in the document, only in the surface and in
//! the ghosted lines. As in Blender, Shift+M with the option off turns on the plane last used (X
//! through the origin at first).

use crate::editor::document::Edit;
use crate::editor::select_modes::selected_vertex_set;
use crate::editor::state::EditorState;
use taut_core::Document;
use taut_core::document::symmetry::{MirrorHalves, MirroredWhole};
use taut_core::mesh::edit::{Axis, MirrorPlane};
use taut_render::overlay::{LineSegment, OverlayData};

/// The ghost lines of the virtual half: linear RGBA and width in pixels.
pub(crate) const GHOST_COLOUR: [f32; 4] = [0.55, 0.7, 0.95, 0.4];
const GHOST_WIDTH_PX: f32 = 1.0;

/// Where a new mirror plane goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MirrorThrough {
    /// The plane through the origin.
    Origin,
    /// The plane through the centre of the selected vertices.
    SelectionCentre,
}

/// The editor's side of the mirror option.
#[derive(Debug, Default)]
pub struct MirrorEditing {
    /// The mirrored whole of a one-half cage, kept per connectivity.
    pub whole: MirroredWhole,
    /// The plane Shift+M turns on.
    last_plane: Option<MirrorPlane>,
    /// The cage topology whose unpaired vertices were already reported (said once).
    warned_topology: Option<u64>,
    /// The last reason the half could not be mirrored (said once).
    refused: Option<String>,
}

/// The name of an axis in the menus.
pub fn axis_name(axis: Axis) -> &'static str {
    match axis {
        Axis::X => "X",
        Axis::Y => "Y",
        Axis::Z => "Z",
    }
}

fn axis_index(axis: Axis) -> usize {
    match axis {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    }
}

impl EditorState {
    /// Turns the mirror on across `axis` (one undo step), or says why it cannot.
    pub fn set_mirror(&mut self, axis: Axis, through: MirrorThrough) {
        let offset = match through {
            MirrorThrough::Origin => 0.0,
            MirrorThrough::SelectionCentre => {
                let cage = &self.document.doc().cage;
                let vertices = selected_vertex_set(cage, &self.view.selection);
                if vertices.is_empty() {
                    self.notify("select the vertices whose centre the mirror plane goes through", true);
                    return;
                }
                let sum: f64 = vertices.iter().map(|&v| cage.position(v)[axis_index(axis)]).sum();
                sum / vertices.len() as f64
            }
        };
        let plane = MirrorPlane::new(axis, offset);
        self.mirror.last_plane = Some(plane);
        self.mirror.refused = None;
        self.edit(Edit::SetMirror(Some(plane)));
        self.notify(format!("mirror on: {}", self.mirror_summary()), false);
    }

    /// Turns the mirror off (one undo step); the cage stays as it is.
    pub fn mirror_off(&mut self) {
        if let Some(plane) = self.document.doc().mirror {
            self.mirror.last_plane = Some(plane);
            self.edit(Edit::SetMirror(None));
            self.notify("mirror off", false);
        }
    }

    /// Shift+M: off when on, else on with the plane last used (X through the origin at first).
    pub fn toggle_mirror(&mut self) {
        if self.document.doc().mirror.is_some() {
            self.mirror_off();
        } else {
            let plane = self.mirror.last_plane.unwrap_or(MirrorPlane::new(Axis::X, 0.0));
            self.mirror.last_plane = Some(plane);
            self.edit(Edit::SetMirror(Some(plane)));
            self.notify(format!("mirror on: {}", self.mirror_summary()), false);
        }
    }

    /// Makes the virtual half real, one undo step; the option stays on, editing both halves.
    pub fn apply_mirror(&mut self) {
        match self.document.apply_mesh(taut_core::document::modelling::MeshEdit::ApplyMirror) {
            Ok(Some(_)) => {
                // The half's elements keep their numbers; the new half is not selected.
                self.prune_selection();
                self.notify("mirror applied: both halves are real and edited together", false);
            }
            Ok(None) => {}
            Err(message) => self.notify(message, true),
        }
    }

    /// "plane X = 0 (one half, the other drawn as a ghost)", or "off".
    pub fn mirror_summary(&self) -> String {
        let doc = self.document.doc();
        let Some(plane) = doc.mirror else { return "off".to_string() };
        let layout = match doc.mirror_halves() {
            Some(MirrorHalves::OneHalf) => "one half; the other is drawn as a ghost",
            Some(MirrorHalves::BothHalves) => "both halves, edited together",
            _ => "the cage lies in the plane",
        };
        format!("plane {} = {} ({layout})", axis_name(plane.axis), plane.offset)
    }

    /// The document whose surface is drawn: the mirrored whole of a one-half cage, else `None`
    /// (the document itself). A half that cannot be mirrored is said once and drawn alone.
    pub(crate) fn mirrored_surface_document(&mut self) -> Option<Document> {
        match self.mirror.whole.whole(self.document.doc()) {
            Ok(whole) => {
                self.mirror.refused = None;
                whole
            }
            Err(e) => {
                let text = format!("the mirrored half cannot be shown: {e}");
                if self.mirror.refused.as_deref() != Some(text.as_str()) {
                    self.notify(text.clone(), true);
                    self.mirror.refused = Some(text);
                }
                None
            }
        }
    }

    /// Before a move under the mirror option: says once per cage topology which moved vertices
    /// have no partner across the plane (they move alone).
    pub(crate) fn mirror_check_move(&mut self, edit: &Edit) {
        let Edit::MoveVertices(moves) = edit else { return };
        let doc = self.document.doc();
        if doc.mirror.is_none() || self.mirror.warned_topology == Some(doc.cage.topology_generation()) {
            return;
        }
        let moved: Vec<_> = moves.iter().map(|&(v, _)| v).collect();
        let Ok(unpaired) = doc.unpaired_vertices(&moved) else { return };
        if let Some(first) = unpaired.first() {
            self.mirror.warned_topology = Some(doc.cage.topology_generation());
            let more = if unpaired.len() > 1 { format!(" and {} more", unpaired.len() - 1) } else { String::new() };
            self.notify(
                format!(
                    "mirror: vertex {}{more} has no partner across the plane and moves alone; make the halves \
                     symmetric or delete one half and mirror the other",
                    first.0
                ),
                false,
            );
        }
    }

    /// The virtual half of a one-half cage as ghosted lines: the edges of the mirrored whole with
    /// an end off the real half.
    pub(crate) fn mirror_overlay(&self, data: &mut OverlayData) {
        let doc = self.document.doc();
        let Some(plane) = doc.mirror else { return };
        if !self.view.display.show_cage {
            return;
        }
        let cage = &doc.cage;
        let frame = &self.view.display_frame;
        data.on_top_lines.extend(plane_outline(plane, cage.positions()).map(|[a, b]| LineSegment {
            a: frame.point(a),
            b: frame.point(b),
            color: PLANE_COLOUR,
            width_px: 1.5,
        }));
        if doc.mirror_halves() != Some(MirrorHalves::OneHalf) {
            return;
        }
        for e in cage.edges() {
            let (a, b) = cage.edge_vertices(e);
            let (p, q) = (plane.reflect(cage.position(a)), plane.reflect(cage.position(b)));
            if plane.distance(p) == 0.0 && plane.distance(q) == 0.0 {
                continue; // an edge on the plane is the real one
            }
            // Over the surface like the real cage, but faint: it cannot be picked.
            data.on_top_lines.push(LineSegment {
                a: frame.point(p),
                b: frame.point(q),
                color: GHOST_COLOUR,
                width_px: GHOST_WIDTH_PX,
            });
        }
    }

    /// The virtual half's cage points, for framing (none unless the cage is one half).
    pub(crate) fn mirror_frame_points(&self) -> Vec<taut_core::DVec3> {
        let doc = self.document.doc();
        match doc.mirror {
            Some(plane) if doc.mirror_halves() == Some(MirrorHalves::OneHalf) => {
                doc.cage.positions().iter().map(|&p| plane.reflect(p)).collect()
            }
            _ => Vec::new(),
        }
    }

    /// Mesh ▸ Mirror.
    pub(crate) fn mirror_menu(&mut self, ui: &mut egui::Ui) {
        ui.menu_button("Mirror", |ui| {
            ui.label(format!("now: {}", self.mirror_summary()));
            for axis in [Axis::X, Axis::Y, Axis::Z] {
                let name = axis_name(axis);
                if ui.button(format!("Plane {name} through the origin")).clicked() {
                    self.set_mirror(axis, MirrorThrough::Origin);
                }
                if ui.button(format!("Plane {name} through the selection's centre")).clicked() {
                    self.set_mirror(axis, MirrorThrough::SelectionCentre);
                }
            }
            ui.separator();
            let on = self.document.doc().mirror.is_some();
            if ui.add_enabled(on, egui::Button::new("Apply mirror")).clicked() {
                self.apply_mirror();
            }
            if ui.add_enabled(on, egui::Button::new("Mirror off")).clicked() {
                self.mirror_off();
            }
        });
    }

    /// The Cage panel's toggle: on/off with the plane last used, and the plane's summary.
    pub(crate) fn mirror_panel(&mut self, ui: &mut egui::Ui) {
        let mut on = self.document.doc().mirror.is_some();
        let response = ui.checkbox(&mut on, "Mirror modelling").on_hover_text(
            "Model symmetrically about a plane (the Mirror entry of the Mesh menu chooses it; Shift+M toggles)",
        );
        if response.changed() {
            self.toggle_mirror();
        }
        if self.document.doc().mirror.is_some() {
            ui.label(self.mirror_summary());
        }
    }
}

#[cfg(test)]
#[path = "mirror_tests.rs"]
mod tests;

/// The mirror plane's colour: a magenta apart from the cage, creases and selection.
const PLANE_COLOUR: [f32; 4] = [0.85, 0.25, 0.75, 0.9];

/// The mirror plane drawn as a rectangle over the cage's extent in the plane (a tenth wider on
/// every side), with its two diagonals: four edges and a cross.
pub fn plane_outline(
    plane: taut_core::mesh::edit::MirrorPlane,
    points: &[taut_core::DVec3],
) -> [[taut_core::DVec3; 2]; 6] {
    use taut_core::mesh::edit::Axis;
    let k = match plane.axis {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    };
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points.iter().map(|p| p.to_array()) {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    if !lo[i].is_finite() {
        (lo, hi) = ([-1.0; 3], [1.0; 3]);
    }
    let pad = |c: usize| 0.1 * (hi[c] - lo[c]).max(1e-9);
    let corner = |a: f64, b: f64| {
        let mut q = [0.0; 3];
        (q[k], q[i], q[j]) = (plane.offset, a, b);
        taut_core::DVec3::from_array(q)
    };
    let (a0, a1, b0, b1) = (lo[i] - pad(i), hi[i] + pad(i), lo[j] - pad(j), hi[j] + pad(j));
    let c = [corner(a0, b0), corner(a1, b0), corner(a1, b1), corner(a0, b1)];
    [[c[0], c[1]], [c[1], c[2]], [c[2], c[3]], [c[3], c[0]], [c[0], c[2]], [c[1], c[3]]]
}
