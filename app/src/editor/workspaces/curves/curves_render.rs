//! The Coons patches of the Curves workspace on the GPU: one mesh of every patch, uploaded when
//! the document changes and drawn as the viewport's surface with zebra stripes (reflection lines
//! show a patch's smoothness and its kinks at a glance), the cage's surface as a ghost behind it.

use crate::editor::state::EditorState;
use taut_core::curve::Workspace;
use taut_render::passes::surface::{GHOST, SurfaceMode};
use taut_render::{Gpu, GpuSurface, Scene, ShownMesh, SurfaceCache};

/// The stripes the patches are drawn with.
pub fn patch_zebra(editor: &EditorState) -> SurfaceMode {
    let d = &editor.view.display;
    SurfaceMode::Zebra { stripes: d.stripes, angle_degrees: d.stripe_angle, width_ratio: d.stripe_width }
}

/// The patches' GPU surface, kept in step with the document: keyed on the document revision,
/// the running filter's curve and passes (patches follow a running filter live) and the display
/// frame.
#[derive(Debug, Default)]
pub struct PatchSurface {
    cache: SurfaceCache<PatchKey>,
}

/// The document revision, the running filter's curve and passes, and the display frame.
type PatchKey = (u64, Option<(usize, usize)>, taut_render::DisplayFrame);

impl PatchSurface {
    /// Uploads the patches when the document, a running filter's points or the display frame
    /// changed (Curves workspace).
    pub fn upload(&mut self, gpu: &Gpu, editor: &EditorState) {
        if editor.curves.workspace != Workspace::Curves {
            return;
        }
        let run = editor.curves.run.as_ref().map(|r| (r.curve, r.status().passes));
        let key = (editor.document.revision(), run, editor.view.display_frame);
        let mesh = std::cell::OnceCell::new();
        self.cache.show_with(
            gpu,
            key,
            || Some(ShownMesh::plain(mesh.get_or_init(|| editor.patches_mesh()).as_ref()?)),
            &editor.view.display_frame,
        );
    }

    /// The Curves workspace's scene: the patches in zebra, the cage's surface ghosted behind
    /// them; `None` in the surface workspace.
    pub fn scene<'a>(
        &'a self,
        editor: &EditorState,
        cage_surface: Option<&'a GpuSurface>,
        overlays: &'a taut_render::overlay::OverlayData,
    ) -> Option<Scene<'a>> {
        (editor.curves.workspace == Workspace::Curves).then(|| Scene {
            overlays: Some(overlays),
            ghost: cage_surface.map(|g| (g, GHOST)),
            ..Scene::new(editor.view.camera, self.cache.surface(), patch_zebra(editor))
        })
    }
}
