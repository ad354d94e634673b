//! The modal tools and what they share: G, R and S (`transform`) with the on-screen gizmo
//! (`gizmo`), snapping (`snapping`) and the pivot (`pivot`); E (`extrude_move`), I
//! (`inset_drag`), Ctrl+R (`loop_slide`); the transform toolbar (`toolbar`); the crease and
//! corner drags, Shift+E and Shift+V (`crease_drag`). Each starts from its key in the shortcut
//! table (`crate::editor::shortcuts`).

pub mod crease_drag;
pub mod extrude_move;
pub mod gizmo;
pub mod inset_drag;
pub mod loop_slide;
pub mod pivot;
pub mod snapping;
pub mod toolbar;
pub mod transform;
