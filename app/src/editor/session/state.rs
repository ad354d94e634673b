//! The editor's state apart from any window: the document, the live surface, the camera, the
//! selection and the display settings. The UI sends [`Edit`]s to the document; once a frame the
//! surface scheme catches up with the document's revision and advances within a time budget
//! ([`crate::editor::live`]), so the surface follows every drag and keeps settling after the mouse stops.

use crate::editor::document::{Edit, EditorDocument};
use crate::editor::files::{Autosave, RecentFiles};
use crate::editor::live::{CompareMode, Comparison, SurfaceView};
use crate::editor::select_modes::SelectMode;
use crate::editor::selection_history::SelectionHistory;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use taut_core::curvature::CurvatureQuantity;
use taut_core::io::UpAxis;
use taut_core::surface::{ColourBy, Progress};
use taut_core::{EdgeId, FaceId, VertexId};
use taut_render::colormap::ColorMap;
use taut_render::overlay::{self, CageControls, CageSelection, CombStyle, Legend, OverlayData};
use taut_render::passes::surface::SurfaceMode;
use taut_render::{Camera, DisplayFrame};

/// Solver time per frame: enough to converge a small cage in a few frames while keeping the
/// window responsive (about 30 frames a second with drawing on a software rasteriser).
pub const SOLVER_BUDGET: Duration = Duration::from_millis(12);

/// What the surface shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DisplayMode {
    Shaded,
    Zebra,
    Curvature,
    Draft,
    Highlight,
}

/// Display settings of the viewport.
#[derive(Clone, Debug, PartialEq)]
pub struct Display {
    pub mode: DisplayMode,
    pub stripes: f32,
    pub stripe_angle: f32,
    pub stripe_width: f32,
    /// What the curvature view colours by.
    pub colour_by: ColourBy,
    /// The other scheme's surface beside this one.
    pub compare: CompareMode,
    /// `None`: automatic (robust percentiles).
    pub fixed_range: Option<(f64, f64)>,
    pub show_cage: bool,
    /// X-ray (Alt+Z): the back of the cage drawn like the front and picked too
    /// ([`crate::editor::xray`]). Off by default: hidden parts are dimmed and not picked.
    pub xray: bool,
    pub show_wire: bool,
    pub show_curves: bool,
    /// Curvature combs: the longest tooth as a fraction of the model's size.
    pub comb_length: f64,
    /// Curvature combs: a tooth at every n-th point of a curve.
    pub comb_density: usize,
    /// Section curves with their combs, when on.
    pub sections: Option<crate::editor::workspaces::surface::sections::SectionSettings>,
    /// The clipping plane, when on.
    pub clip: Option<crate::editor::workspaces::surface::clipping::ClipSettings>,
    /// The draft and highlight views' settings.
    pub analysis: crate::editor::workspaces::surface::analysis_views::AnalysisSettings,
}

impl Default for Display {
    fn default() -> Self {
        Display {
            mode: DisplayMode::Zebra,
            stripes: 12.0,
            stripe_angle: 0.0,
            stripe_width: 0.5,
            colour_by: ColourBy::Curvature(CurvatureQuantity::Mean),
            compare: CompareMode::Off,
            fixed_range: None,
            show_cage: true,
            xray: false,
            show_wire: false,
            show_curves: false,
            comb_length: 0.12,
            comb_density: 1,
            sections: None,
            clip: None,
            analysis: Default::default(),
        }
    }
}

/// Selected and hovered cage elements.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Selection {
    pub vertices: Vec<VertexId>,
    pub edges: Vec<EdgeId>,
    pub hovered_vertex: Option<VertexId>,
    pub hovered_edge: Option<EdgeId>,
    /// Selected faces (face select mode).
    pub faces: Vec<FaceId>,
    pub hovered_face: Option<FaceId>,
    /// What a click picks (Tab cycles).
    pub mode: SelectMode,
}

impl Selection {
    pub fn clear(&mut self) {
        self.vertices.clear();
        self.edges.clear();
        self.faces.clear();
    }

    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty() && self.edges.is_empty() && self.faces.is_empty()
    }

    /// Selects a face; with `add`, toggles it.
    pub fn click_face(&mut self, f: FaceId, add: bool) {
        if !add {
            self.clear();
            self.faces.push(f);
        } else if let Some(k) = self.faces.iter().position(|&x| x == f) {
            self.faces.remove(k);
        } else {
            self.faces.push(f);
        }
    }

    /// Selects a vertex; with `add`, toggles it in the current selection instead.
    pub fn click_vertex(&mut self, v: VertexId, add: bool) {
        if !add {
            self.clear();
            self.vertices.push(v);
        } else if let Some(k) = self.vertices.iter().position(|&x| x == v) {
            self.vertices.remove(k);
        } else {
            self.vertices.push(v);
        }
    }

    /// Selects an edge; with `add`, toggles it.
    pub fn click_edge(&mut self, e: EdgeId, add: bool) {
        if !add {
            self.clear();
            self.edges.push(e);
        } else if let Some(k) = self.edges.iter().position(|&x| x == e) {
            self.edges.remove(k);
        } else {
            self.edges.push(e);
        }
    }
}

/// A message for the designer, shown until dismissed or replaced, and kept in the history.
#[derive(Clone, Debug, PartialEq)]
pub struct Notice {
    pub text: String,
    pub is_error: bool,
}

/// Most messages the history keeps (oldest dropped first).
pub const MAX_MESSAGES: usize = 200;

/// How the document is seen: what a view owns, apart from the session (the document, its undo
/// and the live surface, in [`EditorState`]).
#[derive(Clone, Debug)]
pub struct View {
    pub camera: Camera,
    /// What is drawn and how (shaded, zebra, curvature, the cage, X-ray, …).
    pub display: Display,
    pub selection: Selection,
    /// Model to display coordinates: the camera and every GPU position live in display space.
    pub display_frame: DisplayFrame,
}

impl Default for View {
    fn default() -> Self {
        View {
            camera: Camera::default(),
            display: Display::default(),
            selection: Selection::default(),
            display_frame: DisplayFrame::IDENTITY,
        }
    }
}

/// Everything the editor holds: the session (document, undo, live surface, messages) and the
/// view of it.
#[derive(Debug)]
pub struct EditorState {
    pub document: EditorDocument,
    /// The document revision the surface has seen.
    pub(crate) solved_revision: Option<u64>,
    /// The surface of the document's scheme.
    pub surface: Option<SurfaceView>,
    /// The other scheme's surface, while the compare view is on.
    pub comparison: Option<Comparison>,
    /// How the document is seen: camera, display settings, selection, display frame.
    pub view: View,
    /// The selection of each state of the undo history.
    pub(crate) selection_history: SelectionHistory,
    /// The kind of the last refused edit and its message, while shown.
    refused_edit: Option<(std::mem::Discriminant<Edit>, String)>,
    pub notice: Option<Notice>,
    /// Every message of the session, oldest first (at most [`MAX_MESSAGES`]).
    pub messages: Vec<Notice>,
    /// Where the surface's work stands.
    pub progress: Option<Progress>,
    pub frame_time: Duration,
    pub recent: RecentFiles,
    pub autosave: Option<Autosave>,
    pub last_autosave: Instant,
    /// The surface could not be made (a degenerate cage, Loop on quads): the message.
    pub surface_error: Option<String>,
    /// The up axis of OBJ files opened and exported.
    pub obj_up: UpAxis,
    /// The viewport's width over height and the legend's margin at its right, in points, as last
    /// laid out (framing fits the model into what the legend leaves free).
    pub viewport_shape: (f32, f32),
    /// A new or opened document is framed again each frame until its surface has settled (the
    /// surface can reach beyond the cage, and the viewport's shape is known only once laid
    /// out): the camera as last framed and the revision it framed, so a designer's own move of
    /// the view or edit of the document ends it.
    pub(crate) auto_frame: Option<(Camera, u64)>,
    /// The Curves workspace.
    pub curves: crate::editor::curves::CurvesWorkspace,
    /// File ▸ Make cage from mesh…: its dialog, the running fit, the original of the cage.
    pub cage: crate::editor::cage_from_mesh::CageFromMesh,
    /// The curve-mesh selection and overlays ([`crate::editor::curve_mesh_edit`]).
    pub curve_mesh: crate::editor::curve_mesh_edit::CurveMeshEditing,
    /// The transform gizmo, pivot, snapping and 3D cursor ([`crate::editor::gizmo`]).
    pub gizmo: crate::editor::gizmo::GizmoSettings,
    /// The mirror option's editing state ([`crate::editor::mirror`]).
    pub mirror: crate::editor::mirror::MirrorEditing,
    /// What the eye saw of the cage when last asked ([`crate::editor::xray`]).
    pub(crate) visibility: std::cell::RefCell<crate::editor::xray::VisibilityCache>,
    /// The section curves last cut ([`crate::editor::workspaces::surface::sections`]).
    pub(crate) sections: std::cell::RefCell<crate::editor::workspaces::surface::sections::SectionCache>,
    /// What the panels, menus and keys asked for this frame ([`crate::editor::session::commands`]).
    pub(crate) commands: Vec<crate::editor::session::commands::Command>,
    /// The decoded pictures of the document's reference images
    /// ([`crate::editor::workspaces::surface::reference_images`]).
    pub references: crate::editor::workspaces::surface::reference_images::ReferencePictures,
}

impl EditorState {
    /// An editor on a document; the solver starts on the first frame.
    pub fn new(document: EditorDocument, recent: RecentFiles, autosave: Option<Autosave>) -> Self {
        let mut state = EditorState {
            document,
            solved_revision: None,
            surface: None,
            comparison: None,
            view: View::default(),
            notice: None,
            messages: Vec::new(),
            progress: None,
            frame_time: Duration::ZERO,
            recent,
            autosave,
            last_autosave: Instant::now(),
            surface_error: None,
            obj_up: UpAxis::default(),
            viewport_shape: (1.6, 0.0),
            auto_frame: None,
            curves: Default::default(),
            cage: Default::default(),
            curve_mesh: Default::default(),
            gizmo: Default::default(),
            mirror: Default::default(),
            selection_history: Default::default(),
            refused_edit: None,
            visibility: Default::default(),
            sections: Default::default(),
            commands: Vec::new(),
            references: Default::default(),
        };
        state.load_curves_view();
        state.frame_all();
        state.auto_frame = Some((state.view.camera, state.document.revision()));
        state
    }

    /// Applies an edit, reporting a refused one as a notice.
    /// A refused edit's message goes when an edit of the same kind then succeeds (Loop refused
    /// on quads, chosen again after Triangulate).
    pub fn edit(&mut self, edit: Edit) {
        self.mirror_check_move(&edit);
        let kind = std::mem::discriminant(&edit);
        match self.document.apply(edit) {
            Err(message) => {
                self.refused_edit = Some((kind, message.clone()));
                self.notify(message, true);
            }
            Ok(()) => {
                if let Some((_, message)) = self.refused_edit.take_if(|(refused, _)| *refused == kind) {
                    self.retract(&message);
                }
            }
        }
    }

    /// Shows a message in the status bar and keeps it in the history.
    pub fn notify(&mut self, text: impl Into<String>, is_error: bool) {
        let notice = Notice { text: text.into(), is_error };
        if self.messages.len() == MAX_MESSAGES {
            self.messages.remove(0);
        }
        self.messages.push(notice.clone());
        self.notice = Some(notice);
    }

    /// Replaces the document (open, new, recover); the old one is kept if `document` fails.
    pub fn replace_document(&mut self, document: EditorDocument) {
        self.document = document;
        self.solved_revision = None;
        self.surface = None;
        self.comparison = None;
        self.progress = None;
        // A new document starts in vertex mode, whatever the last one was left in.
        self.view.selection = Selection::default();
        self.selection_history.clear();
        self.surface_error = None;
        self.load_curves_view();
        self.cage.original = None;
        if let Some(path) = self.document.path().map(Path::to_path_buf) {
            let _ = self.recent.add(&path);
        }
        // A new or opened document is seen from the front, right and above (Blender's and
        // Rhino's three-quarter view), framed, whatever view the last one was left in.
        self.view.camera.set_view(taut_render::StandardView::Perspective);
        self.frame_all();
        self.auto_frame = Some((self.view.camera, self.document.revision()));
    }

    /// Opens a file; an unreadable one is reported and the current document stays.
    pub fn open(&mut self, path: &Path) {
        match EditorDocument::open_with(path, self.obj_up) {
            Ok(document) => {
                let _ = self.recent.add(path);
                let repaired = document.import_report().filter(|r| !r.is_clean()).map(|r| r.to_string());
                self.replace_document(document);
                match repaired {
                    Some(report) => self.notify(format!("opened {}: {report}", path.display()), false),
                    None => self.notify(format!("opened {}", path.display()), false),
                }
            }
            Err(message) => {
                // A file that cannot be read leaves the recent list.
                let _ = self.recent.remove(path);
                self.notify(format!("could not open {}: {message}", path.display()), true)
            }
        }
    }

    /// Saves to the document's path, or returns false when it has none (ask for one).
    pub fn save(&mut self) -> bool {
        if self.document.path().is_none() {
            return false;
        }
        match self.document.save() {
            Ok(()) => {
                if let Some(a) = &self.autosave {
                    let _ = a.clear();
                }
                let path = self.document.path().map(|p| p.display().to_string()).unwrap_or_default();
                self.notify(format!("saved {path}"), false);
            }
            Err(message) => self.notify(format!("could not save: {message}"), true),
        }
        true
    }

    pub fn save_as(&mut self, path: &Path) {
        let path = with_extension_if_missing(path, "taut");
        match self.document.save_as(&path) {
            Ok(()) => {
                let _ = self.recent.add(&path);
                if let Some(a) = &self.autosave {
                    let _ = a.clear();
                }
                self.notify(format!("saved {}", path.display()), false);
            }
            Err(message) => self.notify(format!("could not save {}: {message}", path.display()), true),
        }
    }

    /// Writes the smoothed surface (OBJ or GLB by extension).
    pub fn export(&mut self, path: &Path) {
        let Some(surface) = &self.surface else {
            self.notify("there is no surface to export yet", true);
            return;
        };
        match self.document.export_surface(surface.mesh(), surface.scheme.normals(), path, self.obj_up) {
            Ok(()) => self.notify(format!("exported {}", path.display()), false),
            Err(message) => self.notify(format!("could not export {}: {message}", path.display()), true),
        }
    }

    /// The surface mode for the renderer.
    pub fn surface_mode(&self) -> SurfaceMode {
        let d = &self.view.display;
        if self.colours_shown() {
            // The values are uploaded already mapped to the range (see `refresh_values`).
            return SurfaceMode::Curvature { map: self.color_map(), min: 0.0, max: 1.0 };
        }
        match d.mode {
            DisplayMode::Shaded => SurfaceMode::Shaded,
            DisplayMode::Zebra => {
                SurfaceMode::Zebra { stripes: d.stripes, angle_degrees: d.stripe_angle, width_ratio: d.stripe_width }
            }
            DisplayMode::Curvature => SurfaceMode::Curvature { map: self.color_map(), min: 0.0, max: 1.0 },
            DisplayMode::Draft => self.draft_mode(),
            DisplayMode::Highlight => self.highlight_mode(),
        }
    }

    fn color_map(&self) -> ColorMap {
        if self.colour_by().is_signed() { ColorMap::Diverging } else { ColorMap::Sequential }
    }

    /// Cage, wireframe, curves and the legend, from the current document and selection, in
    /// display coordinates.
    pub fn overlays(&self) -> OverlayData {
        let mut data = OverlayData::default();
        let doc = self.document.doc();
        let frame = &self.view.display_frame;
        if self.view.display.show_wire
            && let Some(mesh) = self.surface_mesh()
        {
            data.surface_lines.extend(overlay::wireframe(mesh, [0.05, 0.05, 0.06, 0.7], 1.0, frame));
        }
        if self.view.display.show_curves
            && let Some(mesh) = self.surface_mesh()
        {
            let curves = self.surface_curves();
            let style = comb_style(
                &curves,
                mesh.bounding_diagonal(),
                self.view.display.comb_length,
                self.view.display.comb_density,
            );
            for c in &curves {
                data.surface_lines.extend(overlay::polyline_with_comb(c, false, &style, frame));
            }
        }
        self.section_overlays(&mut data);
        if self.curve_mesh_overlays(&mut data) {
            // The curve-mesh scheme draws its own vertices and a faint cage.
        } else if self.view.display.show_cage {
            let selection = CageSelection {
                selected_vertices: self.view.selection.vertices.clone(),
                selected_edges: self.view.selection.edges.clone(),
                hovered_vertex: self.view.selection.hovered_vertex,
                hovered_edge: self.view.selection.hovered_edge,
                selected_faces: self.view.selection.faces.clone(),
                hovered_face: self.view.selection.hovered_face,
                face_dots: self.view.selection.mode == SelectMode::Face,
                hidden: self.cage_seen().map(|seen| overlay::Hidden {
                    vertices: seen.vertices.iter().map(|&s| !s).collect(),
                    edges: seen.edges.iter().map(|&s| !s).collect(),
                    faces: seen.faces.iter().map(|&s| !s).collect(),
                }),
            };
            let controls = CageControls::of(doc);
            let (lines, points) = overlay::cage_overlay(&doc.cage, controls, &selection, frame);
            data.on_top_lines.extend(lines);
            data.points.extend(points);
            self.mirror_overlay(&mut data);
        }
        self.clip_overlays(&mut data);
        data.legend = self.curve_mesh_legend().or_else(|| self.legend());
        data
    }

    /// The colour legend, when the surface is coloured.
    pub fn legend(&self) -> Option<Legend> {
        self.colours_shown().then(|| {
            let (min, max) = self.value_range();
            let title = if self.cage.distance_shown() {
                "distance to original".to_string()
            } else {
                overlay::legend_title(self.colour_by()).to_string()
            };
            Legend { map: self.color_map(), min, max, title }
        })
    }

    /// When the next autosave is due (far away while there is nothing to save).
    pub fn next_autosave(&self) -> Instant {
        if self.autosave.is_some() && self.document.is_dirty() {
            self.last_autosave + crate::editor::files::AUTOSAVE_INTERVAL
        } else {
            Instant::now() + Duration::from_secs(3600)
        }
    }

    /// Writes the autosave file when due.
    pub fn autosave_if_due(&mut self) {
        let Some(autosave) = &self.autosave else { return };
        if crate::editor::files::should_autosave(self.last_autosave, Instant::now(), self.document.is_dirty()) {
            self.last_autosave = Instant::now();
            if let Err(e) = autosave.write(&self.document) {
                self.notify(format!("autosave failed: {e}"), true);
            }
        }
    }

    /// The cage vertices an edit of the selection applies to: selected vertices, the ends of
    /// selected edges and the corners of selected faces.
    pub fn selected_vertices_with_edge_ends(&self) -> Vec<VertexId> {
        crate::editor::select_modes::selected_vertex_set(&self.document.doc().cage, &self.view.selection)
    }

    /// Drops selected elements that no longer exist (after undo of a document replacement).
    pub fn prune_selection(&mut self) {
        let cage = &self.document.doc().cage;
        let (nv, ne, nf) = (cage.vertex_count(), cage.edge_count(), cage.face_count());
        self.view.selection.vertices.retain(|v| v.index() < nv);
        self.view.selection.edges.retain(|e| e.index() < ne);
        self.view.selection.faces.retain(|f| f.index() < nf);
        if self.view.selection.hovered_face.is_some_and(|f| f.index() >= nf) {
            self.view.selection.hovered_face = None;
        }
        if self.view.selection.hovered_vertex.is_some_and(|v| v.index() >= nv) {
            self.view.selection.hovered_vertex = None;
        }
        if self.view.selection.hovered_edge.is_some_and(|e| e.index() >= ne) {
            self.view.selection.hovered_edge = None;
        }
    }
}

/// The comb style for `curves` on a model of size `diagonal`: the longest tooth `length` of the
/// size, a tooth every `density` points.
pub fn comb_style(curves: &[Vec<taut_core::DVec3>], diagonal: f64, length: f64, density: usize) -> CombStyle {
    let peak = curves
        .iter()
        .flat_map(|c| taut_core::curvature::polyline_curvature(c, false).magnitude())
        .fold(0.0f64, f64::max);
    let scale = if peak > 0.0 && peak.is_finite() { length * diagonal / peak } else { 0.0 };
    CombStyle { scale, density: density.max(1), tooth_width_px: 1.5, envelope_width_px: 2.0, ..Default::default() }
}

/// `path` with `.ext` appended when it has no extension.
pub fn with_extension_if_missing(path: &Path, ext: &str) -> PathBuf {
    if path.extension().is_some() { path.to_path_buf() } else { path.with_extension(ext) }
}
