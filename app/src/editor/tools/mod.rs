//! The modal tools and what they share: G, R and S (`transform`) with the on-screen gizmo
//! (`gizmo`), snapping (`snapping`) and the pivot (`pivot`); E (`extrude_move`), I
//! (`inset_drag`), Ctrl+R (`loop_slide`); the transform toolbar (`toolbar`). Each starts from its
//! key in the shortcut table (`crate::editor::shortcuts`); the crease and corner drags (Shift+E,
//! Shift+V) are in the viewport (`crate::editor::viewport`).

pub mod extrude_move;
pub mod gizmo;
pub mod inset_drag;
pub mod loop_slide;
pub mod pivot;
pub mod snapping;
pub mod toolbar;
pub mod transform;
