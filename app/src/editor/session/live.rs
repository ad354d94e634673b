//! The live surface: the document's scheme kept in step with the document, advanced within a
//! budget each frame, its colour values, and the compare view (the other scheme's surface as a
//! ghost, or the distance to it as colour).
//!
//! Whatever the scheme, the editor only talks to it through [`SurfaceScheme`]: on a new document
//! revision the scheme takes the document ([`SurfaceScheme::update`]: NUSD warm-starts, a
//! subdivision scheme re-evaluates its stencils), then it advances within the frame's budget, and
//! the viewport draws its mesh with its normals.

use crate::editor::state::{DisplayMode, EditorState, MAX_MESSAGES, Notice};
use std::time::{Duration, Instant};
use taut_core::curvature::robust_range;
use taut_core::surface::{self, Budget, ColourBy, Phase, SchemeKind, SurfaceScheme};
use taut_core::{DVec3, PolyMesh};

/// Source of [`SurfaceView::values_id`]: unique across views, so a new surface's values never
/// take an old one's identity.
static NEXT_VALUES_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// The surface the viewport draws, kept in step with the document.
#[derive(Debug)]
pub struct SurfaceView {
    /// The scheme making the surface.
    pub scheme: Box<dyn SurfaceScheme>,
    /// Per-vertex values of the colour view (already mapped to the range, see
    /// `taut_render::colormap::normalize`), with their range.
    pub values: Option<(Vec<f32>, f64, f64)>,
    /// Names the values shown (a fresh number each time they are set; 0 for none), for the GPU
    /// cache's key.
    pub values_id: u64,
    values_stale: bool,
    values_at: Option<Instant>,
}

impl SurfaceView {
    fn new(scheme: Box<dyn SurfaceScheme>) -> Self {
        SurfaceView { scheme, values: None, values_id: 0, values_stale: true, values_at: None }
    }

    /// The surface mesh (cage vertices first).
    pub fn mesh(&self) -> &PolyMesh {
        self.scheme.mesh()
    }
}

/// How the other scheme's surface is shown beside the document's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompareMode {
    Off,
    /// Drawn as a translucent ghost over the surface.
    Ghost,
    /// The surface coloured by its distance to the other one, with a legend.
    Distance,
}

/// The other scheme's surface, for the compare view.
#[derive(Debug)]
pub struct Comparison {
    pub scheme: Box<dyn SurfaceScheme>,
    /// Per vertex of the document's surface: its distance to the other surface.
    pub distances: Option<Vec<f64>>,
    /// The work of both surfaces the distances were measured at.
    measured_at: Option<(usize, usize)>,
}

impl EditorState {
    /// The surface's mesh, if there is one yet.
    pub fn surface_mesh(&self) -> Option<&PolyMesh> {
        self.surface.as_ref().map(SurfaceView::mesh)
    }

    /// The scheme the compare view shows against the document's: NUSD against Catmull–Clark,
    /// either subdivision scheme against NUSD.
    pub fn other_scheme(&self) -> SchemeKind {
        match self.document.doc().scheme {
            SchemeKind::Nusd => SchemeKind::CatmullClark,
            SchemeKind::CatmullClark | SchemeKind::Loop => SchemeKind::Nusd,
            // The limit surface the curve mesh was fitted to.
            SchemeKind::CurveMesh => SchemeKind::CatmullClark,
        }
    }

    /// One frame of surface work: catch up with the document, then advance within `budget`.
    pub fn step_solver(&mut self, budget: Duration) {
        let revision = self.document.revision();
        if self.solved_revision != Some(revision) {
            self.solved_revision = Some(revision);
            let whole = self.mirrored_surface_document();
            let doc = whole.as_ref().unwrap_or(self.document.doc());
            if doc.scheme == SchemeKind::Nusd
                && let Some(face) = collapsed_face(&self.document.doc().cage).or_else(|| collapsed_face(&doc.cage))
            {
                // A passing state of a gesture (a scale through 0): the solver never sees it, so
                // it cannot poison the solve; the last surface stays until the face opens again.
                let text = format!(
                    "face {} has collapsed (its corners meet at a point or on a line): the surface is not \
                     solved until it opens again",
                    face.0
                );
                if self.surface_error.as_deref() != Some(&text) {
                    self.notify(text.clone(), true);
                }
                self.surface_error = Some(text);
                return;
            }
            let result = match &mut self.surface {
                Some(view) if view.scheme.kind() == doc.scheme => view.scheme.update(doc),
                _ => surface::build(doc).map(|s| self.surface = Some(SurfaceView::new(s))),
            };
            // A subdivision surface moves in `update`, not in `advance`: its colours are stale now.
            if let Some(view) = &mut self.surface {
                view.values_stale = true;
            }
            match result {
                Ok(()) => {
                    // The message of the surface that could not be made no longer holds.
                    if let Some(old) = self.surface_error.take() {
                        self.retract(&old);
                        self.retract(&format!("cannot make the surface: {old}"));
                    }
                }
                Err(e) => {
                    self.surface = None;
                    if self.surface_error.as_deref() != Some(&e.to_string()) {
                        self.notify(format!("cannot make the surface: {e}"), true);
                    }
                    self.surface_error = Some(e.to_string());
                }
            }
            self.update_comparison();
        }
        let Some(view) = &mut self.surface else { return };
        let before = view.scheme.progress();
        let progress = view.scheme.advance(Budget { iterations: usize::MAX, time: Some(budget) });
        let events = view.scheme.take_events();
        if progress.work != before.work || progress.phase != before.phase {
            view.values_stale = true;
        }
        for event in events {
            self.remember(Notice { text: format!("solver: {event}"), is_error: true });
        }
        if progress.phase == Phase::Diverged && before.phase != Phase::Diverged {
            let doc = self.document.doc();
            let tensioned = doc.vertex_tension.iter().chain(&doc.edge_tension).any(|&t| t > 0.0);
            let advice = if tensioned {
                "lower the tensions"
            } else {
                "the cage has no tension, so its shape defeats the iteration: look for nearly coincident vertices \
                 or folded faces"
            };
            self.notify(
                format!(
                    "the solve diverged even with the smallest λ and was rolled back to the last good surface; {advice}"
                ),
                true,
            );
        }
        self.progress = Some(progress);
        if let Some(other) = &mut self.comparison {
            other.scheme.advance(Budget { iterations: usize::MAX, time: Some(budget / 2) });
        }
    }

    /// Keeps the compare view's surface in step with the document (in the other scheme).
    fn update_comparison(&mut self) {
        if self.view.display.compare == CompareMode::Off {
            self.comparison = None;
            return;
        }
        let whole = self.mirrored_surface_document();
        let other = whole.unwrap_or_else(|| self.document.doc().clone()).with_scheme(self.other_scheme());
        let result = match &mut self.comparison {
            Some(c) if c.scheme.kind() == other.scheme => c.scheme.update(&other),
            _ => surface::build(&other)
                .map(|scheme| self.comparison = Some(Comparison { scheme, distances: None, measured_at: None })),
        };
        if let Err(e) = result {
            self.comparison = None;
            self.view.display.compare = CompareMode::Off;
            self.notify(format!("cannot compare with {}: {e}", other.scheme.display_name()), true);
        }
    }

    /// Turns the compare view on or off (or switches between ghost and distance).
    pub fn set_compare(&mut self, mode: CompareMode) {
        self.view.display.compare = mode;
        if mode == CompareMode::Distance
            && let Some(original) = &mut self.cage.original
        {
            // One distance view at a time: the other scheme's replaces the original's.
            original.show_distance = false;
        }
        self.update_comparison();
        self.invalidate_values();
    }

    /// Keeps a message in the history and shows it, without the borrow of [`notify`].
    fn remember(&mut self, notice: Notice) {
        if self.messages.len() == MAX_MESSAGES {
            self.messages.remove(0);
        }
        self.messages.push(notice.clone());
        self.notice = Some(notice);
    }

    /// Takes a message off the status bar when it is the one shown: what it said no longer holds
    /// (it stays in the history).
    pub(crate) fn retract(&mut self, text: &str) {
        if self.notice.as_ref().is_some_and(|n| n.text == text) {
            self.notice = None;
        }
    }

    /// True while the surface still has work: the window keeps redrawing.
    pub fn busy(&self) -> bool {
        let working = |s: &dyn SurfaceScheme| s.progress().phase == Phase::Iterating;
        self.solved_revision != Some(self.document.revision())
            || self.surface.as_ref().is_some_and(|v| working(v.scheme.as_ref()))
            || self.comparison.as_ref().is_some_and(|c| working(c.scheme.as_ref()))
            // The distance to a fitted cage's original, waiting for its throttled re-measure.
            || (self.cage.distance_shown() && self.surface.as_ref().is_some_and(|v| v.values_stale))
    }

    /// What the colour view shows now.
    pub fn colour_by(&self) -> ColourBy {
        if self.view.display.compare == CompareMode::Distance || self.cage.distance_shown() {
            ColourBy::Distance
        } else {
            self.view.display.colour_by
        }
    }

    /// True when the surface is drawn in colour (the curvature view, or the compare distance).
    pub fn colours_shown(&self) -> bool {
        self.view.display.mode == DisplayMode::Curvature
            || self.view.display.compare == CompareMode::Distance
            || self.cage.distance_shown()
    }

    /// Recomputes the colour values when shown and stale (at most every 150 ms while the surface
    /// is still settling, at once when it has finished).
    pub fn refresh_values(&mut self) {
        if !self.colours_shown() {
            return;
        }
        let done = !self.busy();
        let by = self.colour_by();
        let Some(view) = &self.surface else { return };
        let due = view.values_at.is_none_or(|t| t.elapsed() > Duration::from_millis(150));
        let comparison_moved = by == ColourBy::Distance
            && self
                .comparison
                .as_ref()
                .is_some_and(|c| c.measured_at != Some((view.scheme.progress().work, c.scheme.progress().work)));
        if !((view.values_stale || comparison_moved) && (done || due)) {
            return;
        }
        let original = self.cage.distance_shown();
        if original && self.cage.original.as_ref().is_some_and(|o| !o.measure_due()) {
            return;
        }
        let result = match by {
            ColourBy::Distance if original => self.measure_original_distances(),
            ColourBy::Distance => self.measure_distances(),
            other => other.values(view.scheme.as_ref()).map_err(|e| e.to_string()),
        };
        let fixed_range = self.view.display.fixed_range;
        let Some(view) = &mut self.surface else { return };
        view.values_stale = false;
        view.values_at = Some(Instant::now());
        match result {
            Ok(values) => {
                let (min, max) = fixed_range.unwrap_or_else(|| robust_range(&values, by.is_signed()));
                // Mapped to the colour range in f64: a tiny model's curvatures overflow f32.
                view.values = Some((taut_render::colormap::normalize(&values, min, max), min, max));
                view.values_id = NEXT_VALUES_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            }
            Err(e) => self.notify(e, true),
        }
    }

    /// Distances from the surface's vertices to the other scheme's surface.
    fn measure_distances(&mut self) -> Result<Vec<f64>, String> {
        let (Some(view), Some(other)) = (&self.surface, &mut self.comparison) else {
            return Err("there is no surface to compare with yet".into());
        };
        let distances = taut_core::surface::distance::distances_to(view.mesh(), other.scheme.mesh());
        other.measured_at = Some((view.scheme.progress().work, other.scheme.progress().work));
        other.distances = Some(distances.clone());
        Ok(distances)
    }

    /// Marks the colour values for recomputation (quantity or range changed).
    pub fn invalidate_values(&mut self) {
        if let Some(s) = &mut self.surface {
            s.values_stale = true;
            s.values_at = None;
        }
    }

    /// The colour range in force.
    pub fn value_range(&self) -> (f64, f64) {
        self.surface.as_ref().and_then(|s| s.values.as_ref()).map_or((-1.0, 1.0), |(_, a, b)| (*a, *b))
    }

    /// The surface's curves along the cage edges, in model coordinates.
    pub fn surface_curves(&self) -> Vec<Vec<DVec3>> {
        self.surface.as_ref().map_or_else(Vec::new, |s| s.scheme.curves())
    }
}

/// The first face of `cage` that has collapsed: an edge shorter than a billionth of the cage's
/// size, or no area (its corners on one line). NUSD cannot solve over such a face: its step
/// grows at every λ.
pub(crate) fn collapsed_face(cage: &PolyMesh) -> Option<taut_core::FaceId> {
    collapsed_faces(cage).into_iter().next()
}

/// Every face of `cage` that has collapsed (see [`collapsed_face`]).
pub(crate) fn collapsed_faces(cage: &PolyMesh) -> Vec<taut_core::FaceId> {
    let Some((lo, hi)) = cage.bounding_box() else { return Vec::new() };
    let size = taut_core::mesh::diagonal_length(lo, hi);
    if !(size > 0.0 && size.is_finite()) {
        return Vec::new();
    }
    let (short, small) = (1e-9 * size, 1e-12 * size * size);
    cage.faces()
        .filter(|&f| {
            let edge_collapsed = cage
                .face_halfedges(f)
                .any(|h| (cage.position(cage.to_vertex(h)) - cage.position(cage.from_vertex(h))).length() <= short);
            edge_collapsed || cage.face_area_vector(f).length() <= small
        })
        .collect()
}
