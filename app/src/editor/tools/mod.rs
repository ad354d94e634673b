//! The modal tools and what they share. Every tool is a [`tool::Tool`] run by the one
//! [`tool::ActiveTool`]: G, R and S (`transform`) with the on-screen gizmo (`gizmo`), snapping
//! (`snapping`) and the pivot (`pivot`); E (`extrude_move`), I (`inset_drag`), Ctrl+R
//! (`loop_slide`); the crease and corner drags, Shift+E and Shift+V (`crease_drag`); the drags a
//! press starts in the viewport (`vertex_drag`, `box_select`, `curve_mesh_drag`, and the Curves workspace's
//! `curve_stroke`), the navigation triad's orbit (`triad`), the clipping plane's handle
//! (`clip_plane_drag`); the transform toolbar
//! (`toolbar`).
//!
//! A new tool is one file plus one line in [`TOOLS`] (its action `Action::Tool("name")`, menu
//! name, description and start); its key is a line of the shortcut table, the one source of
//! Help. Its menu entry (Tools), its Help text and how a key or the menu starts it all come from
//! these two listings.

pub mod box_select;
pub mod clip_plane_drag;
pub mod crease_drag;
pub mod curve_mesh_drag;
pub mod curve_stroke;
pub mod extrude_move;
pub mod gizmo;
pub mod inset_drag;
pub mod loop_slide;
pub mod measure;
pub mod pivot;
pub mod snap_targets;
pub mod snapping;
pub mod tool;
pub mod toolbar;
pub mod transform;
pub mod triad;
pub mod vertex_drag;

use crate::editor::mesh_ops::MeshOp;
use crate::editor::shortcuts::Action;
use crate::editor::state::EditorState;
use glam::Vec2;
use tool::Tool;
use transform::TransformKind;

/// Starts a tool from the pointer's last position over the viewport (`None`: the mouse is
/// elsewhere, a menu); `None` back, with a message shown, when it cannot start.
pub type StartTool = fn(&mut EditorState, Option<Vec2>) -> Option<Box<dyn Tool>>;

/// A tool the designer starts from its key or the Tools menu.
pub struct ToolEntry {
    /// The action its key runs (the key itself is in the shortcut table).
    pub action: Action,
    /// Its name in the Tools menu.
    pub name: &'static str,
    /// What it does, for Help and the menu's tooltip.
    pub description: &'static str,
    /// Starts it.
    pub start: StartTool,
}

/// The tools started from a key or a menu.
pub const TOOLS: &[ToolEntry] = &[
    ToolEntry {
        action: Action::Transform(TransformKind::Grab),
        name: "Move",
        description: "Move the selection (X, Y, Z lock an axis; type a distance)",
        start: |e, m| transform::start(e, TransformKind::Grab, m),
    },
    ToolEntry {
        action: Action::Transform(TransformKind::Rotate),
        name: "Rotate",
        description: "Rotate the selection about the pivot (type degrees)",
        start: |e, m| transform::start(e, TransformKind::Rotate, m),
    },
    ToolEntry {
        action: Action::Transform(TransformKind::Scale),
        name: "Scale",
        description: "Scale the selection about the pivot (type a factor)",
        start: |e, m| transform::start(e, TransformKind::Scale, m),
    },
    ToolEntry {
        action: Action::Mesh(MeshOp::Extrude),
        name: "Extrude and move",
        description: "Extrude the selection, then move it along its normal",
        start: extrude_move::start,
    },
    ToolEntry {
        action: Action::Mesh(MeshOp::Inset),
        name: "Inset and set thickness",
        description: "Inset the selected faces, then set the thickness with the mouse",
        start: inset_drag::start,
    },
    ToolEntry {
        action: Action::Mesh(MeshOp::LoopCut),
        name: "Loop cut and slide",
        description: "Cut a loop across the ring under the mouse, then slide it",
        start: loop_slide::start,
    },
    ToolEntry {
        action: Action::Crease,
        name: "Crease edges",
        description: "Set the crease sharpness of the selected edges with the mouse",
        start: crease_drag::start_crease,
    },
    ToolEntry {
        action: Action::Corner,
        name: "Sharpen corners",
        description: "Set the corner sharpness of the selected vertices with the mouse",
        start: crease_drag::start_corner,
    },
    ToolEntry {
        action: Action::Tool("measure"),
        name: "Measure",
        description: "Measure: click two points for a distance, three for an angle, the surface for its radii",
        start: measure::start,
    },
];

/// The listed tool an action starts, if any.
pub fn listed(action: Action) -> Option<&'static ToolEntry> {
    TOOLS.iter().find(|t| t.action == action)
}
