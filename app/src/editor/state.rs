//! The editor's state apart from any window: the document, the live solver, the camera, the
//! selection and the display settings. The UI sends [`Edit`]s to the document; once a frame the
//! solver catches up with the document's revision (warm start) and advances within a time
//! budget, so the surface follows every drag and keeps settling after the mouse stops.

use super::document::{Edit, EditorDocument};
use super::files::{Autosave, RecentFiles};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use taut_core::curvature::{CurvatureQuantity, robust_range, vertex_curvature};
use taut_core::io::UpAxis;
use taut_core::nusd::surface::{Budget, Phase, Status, SurfaceSolver};
use taut_core::{EdgeId, PolyMesh, VertexId};
use taut_render::colormap::ColorMap;
use taut_render::overlay::{self, CageSelection, CombStyle, Legend, OverlayData};
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
}

/// Display settings of the viewport.
#[derive(Clone, Debug, PartialEq)]
pub struct Display {
    pub mode: DisplayMode,
    pub stripes: f32,
    pub stripe_angle: f32,
    pub stripe_width: f32,
    pub quantity: CurvatureQuantity,
    /// `None`: automatic (robust percentiles).
    pub fixed_range: Option<(f64, f64)>,
    pub show_cage: bool,
    pub show_wire: bool,
    pub show_curves: bool,
    /// Curvature combs: the longest tooth as a fraction of the model's size.
    pub comb_length: f64,
    /// Curvature combs: a tooth at every n-th point of a curve.
    pub comb_density: usize,
}

impl Default for Display {
    fn default() -> Self {
        Display {
            mode: DisplayMode::Zebra,
            stripes: 12.0,
            stripe_angle: 0.0,
            stripe_width: 0.5,
            quantity: CurvatureQuantity::Mean,
            fixed_range: None,
            show_cage: true,
            show_wire: false,
            show_curves: false,
            comb_length: 0.12,
            comb_density: 1,
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
}

impl Selection {
    pub fn clear(&mut self) {
        self.vertices.clear();
        self.edges.clear();
    }

    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty() && self.edges.is_empty()
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

/// The smoothed surface the viewport draws, kept in step with the solver.
#[derive(Debug)]
pub struct SurfaceView {
    /// The finest level built so far, positions from the solver.
    pub mesh: PolyMesh,
    /// Per-vertex values of the curvature view, with their colour range.
    pub values: Option<(Vec<f32>, f64, f64)>,
    values_stale: bool,
    values_at: Option<Instant>,
}

/// Everything the editor holds.
#[derive(Debug)]
pub struct EditorState {
    pub document: EditorDocument,
    pub solver: Option<SurfaceSolver>,
    /// The document revision the solver has seen.
    solved_revision: Option<u64>,
    pub surface: Option<SurfaceView>,
    pub camera: Camera,
    pub selection: Selection,
    pub display: Display,
    pub notice: Option<Notice>,
    /// Every message of the session, oldest first (at most [`MAX_MESSAGES`]).
    pub messages: Vec<Notice>,
    pub status: Option<Status>,
    pub frame_time: Duration,
    pub recent: RecentFiles,
    pub autosave: Option<Autosave>,
    pub last_autosave: Instant,
    /// The solver could not even start (a degenerate cage): the message.
    pub solver_error: Option<String>,
    /// The up axis of OBJ files opened and exported.
    pub obj_up: UpAxis,
    /// Model to display coordinates: the camera and every GPU position live in display space.
    pub display_frame: DisplayFrame,
    /// The viewport's width over height and the legend's margin at its right, in points, as last
    /// laid out (framing fits the model into what the legend leaves free).
    pub viewport_shape: (f32, f32),
}

impl EditorState {
    /// An editor on a document; the solver starts on the first frame.
    pub fn new(document: EditorDocument, recent: RecentFiles, autosave: Option<Autosave>) -> Self {
        let mut state = EditorState {
            document,
            solver: None,
            solved_revision: None,
            surface: None,
            camera: Camera::default(),
            selection: Selection::default(),
            display: Display::default(),
            notice: None,
            messages: Vec::new(),
            status: None,
            frame_time: Duration::ZERO,
            recent,
            autosave,
            last_autosave: Instant::now(),
            solver_error: None,
            obj_up: UpAxis::default(),
            display_frame: DisplayFrame::IDENTITY,
            viewport_shape: (1.6, 0.0),
        };
        state.frame_all();
        state
    }

    /// Applies an edit, reporting a refused one as a notice.
    pub fn edit(&mut self, edit: Edit) {
        if let Err(message) = self.document.apply(edit) {
            self.notify(message, true);
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
        self.solver = None;
        self.solved_revision = None;
        self.surface = None;
        self.selection.clear();
        self.solver_error = None;
        if let Some(path) = self.document.path().map(Path::to_path_buf) {
            let _ = self.recent.add(&path);
        }
        self.frame_all();
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
        match self.document.export_surface(&surface.mesh, path, self.obj_up) {
            Ok(()) => self.notify(format!("exported {}", path.display()), false),
            Err(message) => self.notify(format!("could not export {}: {message}", path.display()), true),
        }
    }

    /// One frame of solving: catch up with the document, then advance within `budget`.
    pub fn step_solver(&mut self, budget: Duration) {
        let revision = self.document.revision();
        if self.solved_revision != Some(revision) {
            self.solved_revision = Some(revision);
            let doc = self.document.doc();
            let result = match &mut self.solver {
                Some(solver) => solver.update(doc),
                None => SurfaceSolver::new(doc).map(|s| self.solver = Some(s)),
            };
            match result {
                Ok(()) => self.solver_error = None,
                Err(e) => {
                    self.solver = None;
                    self.surface = None;
                    self.solver_error = Some(e.to_string());
                }
            }
        }
        let Some(solver) = &mut self.solver else { return };
        let before = solver.status();
        let status = if before.phase == Phase::Iterating {
            solver.advance(Budget { iterations: usize::MAX, time: Some(budget) })
        } else {
            before
        };
        for event in solver.take_events() {
            let text = format!("solver: {event}");
            if self.messages.len() == MAX_MESSAGES {
                self.messages.remove(0);
            }
            self.messages.push(Notice { text: text.clone(), is_error: true });
            self.notice = Some(Notice { text, is_error: true });
        }
        if status.phase == Phase::Diverged && before.phase != Phase::Diverged {
            self.notify(
                "the solve diverged even with the smallest λ and was rolled back to the last good surface; lower the tensions",
                true,
            );
        }
        self.status = Some(status);
        let changed = before.total_iterations != status.total_iterations
            || before.phase != status.phase
            || self.surface.is_none();
        if changed {
            self.sync_surface();
        }
    }

    /// Copies the solver's finest positions into the viewport's mesh.
    fn sync_surface(&mut self) {
        let Some(solver) = &self.solver else { return };
        let topology = solver.surface_topology();
        let reuse =
            self.surface.as_ref().is_some_and(|s| s.mesh.topology_generation() == topology.topology_generation());
        if !reuse {
            self.surface =
                Some(SurfaceView { mesh: topology.clone(), values: None, values_stale: true, values_at: None });
        }
        let surface = self.surface.as_mut().expect("set above");
        surface.mesh.positions_mut().copy_from_slice(solver.surface_positions());
        surface.values_stale = true;
    }

    /// True while the solver still has work: the window keeps redrawing.
    pub fn busy(&self) -> bool {
        self.solved_revision != Some(self.document.revision())
            || self.solver.as_ref().is_some_and(|s| s.status().phase == Phase::Iterating)
    }

    /// Recomputes the curvature values when shown and stale (at most every 150 ms while the
    /// solver runs, at once when it has finished).
    pub fn refresh_values(&mut self) {
        if self.display.mode != DisplayMode::Curvature {
            return;
        }
        let done = !self.busy();
        let (Some(surface), Some(solver)) = (&mut self.surface, &self.solver) else { return };
        let due = surface.values_at.is_none_or(|t| t.elapsed() > Duration::from_millis(150));
        if !(surface.values_stale && (done || due)) {
            return;
        }
        let q = self.display.quantity;
        let r = (q == CurvatureQuantity::NusdR).then(|| solver.surface_second_derivatives());
        let result = vertex_curvature(&surface.mesh).values(q, r);
        surface.values_stale = false;
        surface.values_at = Some(Instant::now());
        match result {
            Ok(values) => {
                let (min, max) = self.display.fixed_range.unwrap_or_else(|| robust_range(&values, q.is_signed()));
                // Mapped to the colour range in f64: a tiny model's curvatures overflow f32.
                surface.values = Some((taut_render::colormap::normalize(&values, min, max), min, max));
            }
            Err(e) => self.notify(e.to_string(), true),
        }
    }

    /// Marks the curvature values for recomputation (quantity or range changed).
    pub fn invalidate_values(&mut self) {
        if let Some(s) = &mut self.surface {
            s.values_stale = true;
            s.values_at = None;
        }
    }

    /// The surface mode for the renderer.
    pub fn surface_mode(&self) -> SurfaceMode {
        let d = &self.display;
        match d.mode {
            DisplayMode::Shaded => SurfaceMode::Shaded,
            DisplayMode::Zebra => {
                SurfaceMode::Zebra { stripes: d.stripes, angle_degrees: d.stripe_angle, width_ratio: d.stripe_width }
            }
            // The values are uploaded already mapped to the range (see `refresh_values`).
            DisplayMode::Curvature => SurfaceMode::Curvature { map: self.color_map(), min: 0.0, max: 1.0 },
        }
    }

    fn color_map(&self) -> ColorMap {
        if self.display.quantity.is_signed() { ColorMap::Diverging } else { ColorMap::Sequential }
    }

    /// The colour range in force.
    pub fn value_range(&self) -> (f64, f64) {
        self.surface.as_ref().and_then(|s| s.values.as_ref()).map_or((-1.0, 1.0), |(_, a, b)| (*a, *b))
    }

    /// Cage, wireframe, curves and the legend, from the current document and selection, in
    /// display coordinates.
    pub fn overlays(&self) -> OverlayData {
        let mut data = OverlayData::default();
        let doc = self.document.doc();
        let frame = &self.display_frame;
        if self.display.show_wire
            && let Some(s) = &self.surface
        {
            data.surface_lines.extend(overlay::wireframe(&s.mesh, [0.05, 0.05, 0.06, 0.7], 1.0, frame));
        }
        if self.display.show_curves
            && let (Some(s), Some(solver)) = (&self.surface, &self.solver)
        {
            let curves: Vec<Vec<taut_core::DVec3>> = solver
                .cage_edge_curves()
                .into_iter()
                .map(|(_, chain)| {
                    chain.iter().filter(|v| v.index() < s.mesh.vertex_count()).map(|&v| s.mesh.position(v)).collect()
                })
                .collect();
            let style =
                comb_style(&curves, s.mesh.bounding_diagonal(), self.display.comb_length, self.display.comb_density);
            for c in &curves {
                data.surface_lines.extend(overlay::polyline_with_comb(c, false, &style, frame));
            }
        }
        if self.display.show_cage {
            let selection = CageSelection {
                selected_vertices: self.selection.vertices.clone(),
                selected_edges: self.selection.edges.clone(),
                hovered_vertex: self.selection.hovered_vertex,
                hovered_edge: self.selection.hovered_edge,
            };
            let (lines, points) =
                overlay::cage_overlay(&doc.cage, &doc.fixed, &doc.vertex_tension, &doc.edge_tension, &selection, frame);
            data.on_top_lines = lines;
            data.points = points;
        }
        data.legend = self.legend();
        data
    }

    /// The colour legend, when the curvature view is on.
    pub fn legend(&self) -> Option<Legend> {
        (self.display.mode == DisplayMode::Curvature).then(|| {
            let (min, max) = self.value_range();
            let title = overlay::legend_title(self.display.quantity).to_string();
            Legend { map: self.color_map(), min, max, title }
        })
    }

    /// Frames the whole cage and surface: a display frame fitted to them, and the camera filling
    /// the viewport (left of the legend, when one is shown).
    pub fn frame_all(&mut self) {
        let cage = &self.document.doc().cage;
        let mut points: Vec<taut_core::DVec3> = cage.positions().to_vec();
        if let Some(s) = &self.surface {
            let step = (s.mesh.vertex_count() / 20_000).max(1);
            points.extend(s.mesh.positions().iter().step_by(step));
        }
        if points.is_empty() {
            return;
        }
        self.display_frame = DisplayFrame::for_points(&points);
        self.frame_display_points(&points);
    }

    /// Frames model points in the current display frame.
    fn frame_display_points(&mut self, points: &[taut_core::DVec3]) {
        let display: Vec<glam::Vec3> = points.iter().map(|&p| self.display_frame.point(p)).collect();
        let (aspect, margin_fraction) = self.viewport_shape;
        let margin_fraction = if self.display.mode == DisplayMode::Curvature { margin_fraction } else { 0.0 };
        self.camera.frame_points(&display, aspect * (1.0 - margin_fraction));
        // Centre the model in what the legend leaves free: half the margin to the left, in
        // pixels of a viewport one unit high.
        self.camera.pan(-0.5 * margin_fraction * aspect, 0.0, 1.0);
    }

    /// Frames the selected vertices (or everything when nothing is selected).
    pub fn frame_selection(&mut self) {
        let cage = &self.document.doc().cage;
        let mut points: Vec<taut_core::DVec3> = self.selection.vertices.iter().map(|&v| cage.position(v)).collect();
        for &e in &self.selection.edges {
            let (a, b) = cage.edge_vertices(e);
            points.extend([cage.position(a), cage.position(b)]);
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

    /// When the next autosave is due (far away while there is nothing to save).
    pub fn next_autosave(&self) -> Instant {
        if self.autosave.is_some() && self.document.is_dirty() {
            self.last_autosave + super::files::AUTOSAVE_INTERVAL
        } else {
            Instant::now() + Duration::from_secs(3600)
        }
    }

    /// Writes the autosave file when due.
    pub fn autosave_if_due(&mut self) {
        let Some(autosave) = &self.autosave else { return };
        if super::files::should_autosave(self.last_autosave, Instant::now(), self.document.is_dirty()) {
            self.last_autosave = Instant::now();
            if let Err(e) = autosave.write(&self.document) {
                self.notify(format!("autosave failed: {e}"), true);
            }
        }
    }

    /// The cage vertices an edit of the selection applies to: selected vertices, and the ends
    /// of selected edges.
    pub fn selected_vertices_with_edge_ends(&self) -> Vec<VertexId> {
        let cage = &self.document.doc().cage;
        let mut out = self.selection.vertices.clone();
        for &e in &self.selection.edges {
            let (a, b) = cage.edge_vertices(e);
            for v in [a, b] {
                if !out.contains(&v) {
                    out.push(v);
                }
            }
        }
        out
    }

    /// Drops selected elements that no longer exist (after undo of a document replacement).
    pub fn prune_selection(&mut self) {
        let cage = &self.document.doc().cage;
        let (nv, ne) = (cage.vertex_count(), cage.edge_count());
        self.selection.vertices.retain(|v| v.index() < nv);
        self.selection.edges.retain(|e| e.index() < ne);
        if self.selection.hovered_vertex.is_some_and(|v| v.index() >= nv) {
            self.selection.hovered_vertex = None;
        }
        if self.selection.hovered_edge.is_some_and(|e| e.index() >= ne) {
            self.selection.hovered_edge = None;
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
