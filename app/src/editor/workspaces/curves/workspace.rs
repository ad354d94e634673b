//! The Curves workspace: the document's curves ([`taut_core::curve::CurveSet`]) imported from
//! point files or drawn on a plane, faired toward log-aesthetic curves live (the discrete
//! log-aesthetic filter of Miura, Yoshida and Saito, seed `003_0c1161d9995b9b01`, read in
//! `docs/log-aesthetic.md`), shown with curvature combs and curvature/LCG plots, log-aesthetic
//! segments placed by their three control points (Yoshida–Saito), and Coons patches built from
//! four curves and shown with zebra stripes, which follow those curves
//! ([`crate::editor::curves_history`]). Delete deletes the selected curve or patch
//! ([`crate::editor::curves_keys`]).
//!
//! Every change of the curves is one [`Edit::SetCurves`], so undo covers import, drawing,
//! deleting, segment edits and patches. A filter run works on a copy of the selected curve (the
//! viewport and the plots show the copy as it moves) and becomes one undo step when it stops or
//! converges; Continue goes on with the same filter while the document's curve is what the run
//! left. An undo (or any other change of that curve) under a run drops the run.
//!
//! Where it is weak: the filter runs on the UI thread within [`FILTER_BUDGET`] a frame, so a
//! curve of 100,000 points moves about a pass a frame (7 ms); drawn strokes keep the mouse's samples
//! (3 points apart on screen), which the filter then smooths; four drawn curves rarely meet, so a
//! Coons patch snaps their ends together when they are within [`SNAP_FRACTION`] of the patch's
//! size (each side bent linearly along its length), and refuses them when they are farther.

use crate::editor::document::Edit;
use crate::editor::state::EditorState;
use std::time::{Duration, Instant};
use taut_core::DVec3;
use taut_core::aesthetic::{
    Alpha, CurvatureGraph, CurveFilter, EstimateSettings, FilterSettings, FilterStatus, curvature_graph, estimate_alpha,
};
use taut_core::curve::{CurveSet, DocCurve, Plane, PointSequence, SegmentControls, Workspace};

/// Filter time per frame.
pub const FILTER_BUDGET: Duration = Duration::from_millis(8);
/// Ends of the four curves of a Coons patch closer than this fraction of its size are snapped.
pub const SNAP_FRACTION: f64 = 0.1;

/// The plane a curve is drawn on (through the model's origin).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawPlane {
    Xy,
    Yz,
    Zx,
    /// The plane facing the camera.
    View,
}

impl DrawPlane {
    pub const ALL: [DrawPlane; 4] = [DrawPlane::Xy, DrawPlane::Yz, DrawPlane::Zx, DrawPlane::View];

    pub fn label(self) -> &'static str {
        match self {
            DrawPlane::Xy => "XY (z = 0)",
            DrawPlane::Yz => "YZ (x = 0)",
            DrawPlane::Zx => "ZX (y = 0)",
            DrawPlane::View => "view plane through the origin",
        }
    }

    /// The plane's unit normal; `view_backward` is the camera's backward direction.
    pub fn normal(self, view_backward: DVec3) -> DVec3 {
        match self {
            DrawPlane::Xy => DVec3::Z,
            DrawPlane::Yz => DVec3::X,
            DrawPlane::Zx => DVec3::Y,
            DrawPlane::View => view_backward.normalize_or(DVec3::Z),
        }
    }

    /// Two unit axes in the plane.
    pub fn axes(self, view_backward: DVec3) -> (DVec3, DVec3) {
        let n = self.normal(view_backward);
        let u = match self {
            DrawPlane::Xy => DVec3::X,
            DrawPlane::Yz => DVec3::Y,
            DrawPlane::Zx => DVec3::Z,
            DrawPlane::View => n.any_orthonormal_vector(),
        };
        (u, n.cross(u))
    }
}

/// What the primary mouse button does in the viewport.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveTool {
    /// Click a curve to select it; drag a segment's control point.
    Select,
    /// Drag to draw a curve on the plane.
    Draw,
}

/// The filter's controls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterControls {
    /// Estimate α per piece from the curve (else use `alpha`).
    pub estimate: bool,
    pub alpha: f64,
    /// Half-width m of the window of 2m + 1 points.
    pub window: usize,
    /// The space-curve filter (with torsion) instead of the planar one.
    pub space: bool,
    /// β of the torsion law, for the space-curve filter.
    pub torsion_beta: f64,
    /// Keep the curve where its points were (the shape-keeping fairing: a pre-fit and a data
    /// term, as `taut fair` does for plane curves); off, the paper's filter alone, which moves a
    /// noisy curve. The space-curve filter is always the paper's.
    pub keep_shape: bool,
}

impl Default for FilterControls {
    fn default() -> Self {
        FilterControls { estimate: true, alpha: 1.0, window: 3, space: false, torsion_beta: 1.0, keep_shape: true }
    }
}

/// A filter running on one curve.
#[derive(Debug)]
pub struct FilterRun {
    /// The curve it works on.
    pub curve: usize,
    filter: CurveFilter,
    /// False while stopped.
    pub running: bool,
    /// The document's points of the curve the run goes on from (its start or last commit).
    base: Vec<DVec3>,
    /// LCG residual of the curve when the run began.
    pub residual_before: Option<f64>,
}

impl FilterRun {
    pub fn status(&self) -> FilterStatus {
        self.filter.status()
    }

    pub fn points(&self) -> &[DVec3] {
        self.filter.points()
    }
}

/// The plots' data for one curve's points, kept while the points stay the same.
#[derive(Clone, Debug)]
pub struct CurvePlots {
    points: Vec<DVec3>,
    pub graph: CurvatureGraph,
    /// Per piece of monotone curvature: its first and last point and the LCG line fitted to it.
    pub pieces: Vec<(usize, usize, taut_core::aesthetic::LineFit)>,
    /// Why α could not be estimated per piece, if it could not.
    pub estimate_error: Option<String>,
}

/// The Curves workspace's state beside the document.
#[derive(Debug)]
pub struct CurvesWorkspace {
    pub workspace: Workspace,
    pub selected: Option<usize>,
    pub tool: CurveTool,
    pub plane: DrawPlane,
    pub filter: FilterControls,
    pub run: Option<FilterRun>,
    pub show_combs: bool,
    /// Longest comb tooth as a fraction of the curves' size.
    pub comb_length: f64,
    /// A tooth at every n-th point.
    pub comb_density: usize,
    /// Curves picked for a Coons patch, in the order picked.
    pub picked: Vec<usize>,
    /// The selected Coons patch (a curve and a patch are never selected together).
    pub selected_patch: Option<usize>,
    pub patch_samples: usize,
    /// Time the live filter may take a frame ([`FILTER_BUDGET`]; at least one pass a frame
    /// whatever it is).
    pub filter_budget: Duration,
    /// α of a new segment.
    pub segment_alpha: f64,
    plots: Option<CurvePlots>,
}

impl Default for CurvesWorkspace {
    fn default() -> Self {
        CurvesWorkspace {
            workspace: Workspace::Surface,
            selected: None,
            tool: CurveTool::Select,
            plane: DrawPlane::Xy,
            filter: FilterControls::default(),
            run: None,
            show_combs: true,
            comb_length: 0.15,
            comb_density: 1,
            picked: Vec::new(),
            selected_patch: None,
            patch_samples: 24,
            filter_budget: FILTER_BUDGET,
            segment_alpha: 1.0,
            plots: None,
        }
    }
}

impl EditorState {
    /// The document's curves.
    pub fn curve_set(&self) -> &CurveSet {
        &self.document.doc().curves
    }

    /// Shows the surface or the curves workspace; the choice is saved with the file.
    pub fn set_workspace(&mut self, workspace: Workspace) {
        self.curves.workspace = workspace;
        self.sync_curves_view();
    }

    /// Writes the workspace and selection into the document's view (saved, not undone).
    pub(crate) fn sync_curves_view(&mut self) {
        let view = taut_core::curve::CurvesView { workspace: self.curves.workspace, selected: self.curves.selected };
        self.document.set_curves_view(view);
    }

    /// Takes the workspace and selection from a newly opened document.
    pub(crate) fn load_curves_view(&mut self) {
        let view = self.curve_set().view;
        self.curves.workspace = view.workspace;
        self.curves.selected = view.selected;
        self.curves.run = None;
        self.curves.picked.clear();
        self.curves.selected_patch = None;
        self.curves.plots = None;
    }

    /// After undo or redo: the selection and the picks kept within the curves there are.
    pub(crate) fn curves_after_undo(&mut self) {
        let n = self.curve_set().curves.len();
        self.curves.selected = self.curves.selected.filter(|&s| s < n);
        self.curves.picked.retain(|&p| p < n);
        let patches = self.curve_set().patches.len();
        self.curves.selected_patch = self.curves.selected_patch.filter(|&p| p < patches);
        self.sync_curves_view();
    }

    /// Selects a curve (or none); a selected patch is deselected.
    pub fn select_curve(&mut self, curve: Option<usize>) {
        self.curves.selected = curve.filter(|&c| c < self.curve_set().curves.len());
        if self.curves.selected.is_some() {
            self.curves.selected_patch = None;
        }
        self.sync_curves_view();
    }

    /// Picks curve `i` for a Coons patch, or unpicks it when it is picked.
    pub fn toggle_pick(&mut self, i: usize) {
        if self.curves.picked.contains(&i) {
            self.curves.picked.retain(|&p| p != i);
        } else if i < self.curve_set().curves.len() {
            self.curves.picked.push(i);
        }
    }

    /// Selects a Coons patch (or none); a selected curve is deselected.
    pub fn select_patch(&mut self, patch: Option<usize>) {
        self.curves.selected_patch = patch.filter(|&p| p < self.curve_set().patches.len());
        if self.curves.selected_patch.is_some() {
            self.curves.selected = None;
        }
        self.sync_curves_view();
    }

    /// The points shown for curve `i`: the running filter's, or the document's.
    pub fn shown_points(&self, i: usize) -> &[DVec3] {
        match &self.curves.run {
            Some(run) if run.curve == i => run.points(),
            _ => &self.curve_set().curves[i].points,
        }
    }

    /// Applies a new curve set as one edit, keeping the selection valid. Patches with history
    /// are rebuilt from their curves first ([`crate::editor::curves_history`]).
    pub(crate) fn set_curves(&mut self, mut set: CurveSet) {
        let kept = crate::editor::curves_history::follow_sources(&mut set, self.curve_set());
        self.edit(Edit::SetCurves(Box::new(set)));
        let n = self.curve_set().curves.len();
        self.curves.selected = self.curves.selected.filter(|&s| s < n);
        self.curves.picked.retain(|&p| p < n);
        let patches = self.curve_set().patches.len();
        self.curves.selected_patch = self.curves.selected_patch.filter(|&p| p < patches);
        self.sync_curves_view();
        // Once per change of what is wrong, not once per frame of a drag.
        if let Some(kept) = kept
            && self.notice.as_ref().is_none_or(|n| n.text != kept)
        {
            self.notify(kept, true);
        }
    }

    /// Adds a curve and selects it.
    pub fn add_curve(&mut self, curve: DocCurve) {
        let mut set = self.curve_set().clone();
        set.curves.push(curve);
        let n = set.curves.len();
        let before = self.curve_set().curves.len();
        self.set_curves(set);
        if self.curve_set().curves.len() == n && n > before {
            self.select_curve(Some(n - 1));
        }
    }

    /// Reads a point file (JSON or CSV) as a new curve.
    pub fn import_curve(&mut self, path: &std::path::Path) {
        let read = taut_core::io::points::read_points(path).and_then(|file| {
            let seq = PointSequence::new(file.points, file.closed);
            seq.validate(3)?;
            Ok(seq)
        });
        match read {
            Ok(seq) => {
                let name = path.file_stem().map_or_else(|| "curve".into(), |s| s.to_string_lossy().into_owned());
                let count = seq.len();
                self.add_curve(DocCurve::new(name, seq.points, seq.closed));
                self.notify(format!("imported {count} points from {}", path.display()), false);
            }
            Err(e) => self.notify(format!("could not import {}: {e}", path.display()), true),
        }
    }

    /// Deletes the selected curve.
    pub fn delete_selected_curve(&mut self) {
        let Some(s) = self.curves.selected else {
            self.notify("select a curve to delete first", true);
            return;
        };
        self.curves.run = None;
        let mut set = self.curve_set().clone();
        let name = set.curves[s].name.clone();
        let orphaned = set.remove_curve(s);
        self.curves.picked.clear();
        self.curves.selected = None;
        let before = self.document.revision();
        self.set_curves(set);
        if self.document.revision() != before {
            let list: Vec<String> = orphaned.iter().map(|k| (k + 1).to_string()).collect();
            match list.len() {
                0 => self.notify(format!("deleted the curve '{name}'"), false),
                1 => self.notify(format!("deleted '{name}': Coons patch {} keeps its shape without it", list[0]), true),
                _ => self.notify(
                    format!("deleted '{name}': Coons patches {} keep their shapes without it", list.join(", ")),
                    true,
                ),
            }
        }
    }

    /// Deletes the selected Coons patch.
    pub fn delete_selected_patch(&mut self) {
        let Some(k) = self.curves.selected_patch else {
            self.notify("select a Coons patch to delete first", true);
            return;
        };
        let mut set = self.curve_set().clone();
        set.patches.remove(k);
        self.curves.selected_patch = None;
        self.set_curves(set);
        self.notify(format!("deleted Coons patch {}", k + 1), false);
    }

    /// Deletes what is selected in the Curves workspace: the curve or the patch (the Delete key).
    pub fn delete_selected_curve_item(&mut self) {
        if self.curves.selected_patch.is_some() {
            self.delete_selected_patch();
        } else {
            self.delete_selected_curve();
        }
    }

    /// A new log-aesthetic segment on the drawing plane, sized to the model.
    pub fn add_segment(&mut self) {
        let (u, v) = self.curves.plane.axes(self.view_backward());
        let r = 0.4 * self.curves_size();
        let controls = SegmentControls {
            controls: [(-r * u).to_array(), (0.2 * r * u + 0.9 * r * v).to_array(), (r * u).to_array()],
            alpha: self.curves.segment_alpha,
        };
        let n = self.curve_set().curves.len();
        match DocCurve::segment(format!("segment {}", n + 1), controls) {
            Ok(curve) => self.add_curve(curve),
            Err(e) => self.notify(format!("cannot make the segment: {e}"), true),
        }
    }

    /// Sets the controls of segment `curve` (within a gesture for drags and sliders).
    pub fn set_segment(&mut self, curve: usize, controls: SegmentControls) {
        let Some(old) = self.curve_set().curves.get(curve) else { return };
        let name = old.name.clone();
        match DocCurve::segment(name, controls) {
            Ok(c) => {
                let mut set = self.curve_set().clone();
                set.curves[curve] = c;
                self.set_curves(set);
            }
            Err(e) => self.notify(format!("cannot move the segment: {e}"), true),
        }
    }

    /// The camera's backward direction in model coordinates.
    pub(crate) fn view_backward(&self) -> DVec3 {
        self.view.camera.backward().as_dvec3()
    }

    /// The size of what the workspace shows: the curves and patches, or the cage.
    pub fn curves_size(&self) -> f64 {
        let points = self.curve_points();
        let d = taut_core::mesh::bounding_box(&points).map_or(0.0, |(lo, hi)| lo.distance(hi));
        if d > 0.0 { d } else { self.document.doc().cage.bounding_diagonal().max(1e-9) }
    }

    /// Frames the selected curve or Coons patch, else the picked curves, else everything the
    /// workspace shows.
    pub fn frame_curves_selection(&mut self) {
        let points: Vec<DVec3> = match (self.curves.selected, self.curves.selected_patch) {
            (Some(i), _) => self.shown_points(i).to_vec(),
            (None, Some(k)) => self.shown_patch(k).boundaries.iter().flatten().copied().collect(),
            (None, None) => self.curves.picked.iter().flat_map(|&i| self.shown_points(i).iter().copied()).collect(),
        };
        if points.is_empty() {
            self.frame_all();
        } else {
            self.frame_model_points(&points);
        }
    }

    /// Every point of the curves and patch boundaries.
    pub(crate) fn curve_points(&self) -> Vec<DVec3> {
        let set = self.curve_set();
        let mut points: Vec<DVec3> = set.curves.iter().flat_map(|c| c.points.iter().copied()).collect();
        for c in set.curves.iter().filter_map(|c| c.segment) {
            points.extend(c.points());
        }
        for p in &set.patches {
            points.extend(p.boundaries.iter().flatten());
        }
        points
    }

    // The filter.

    /// Starts the filter on the selected curve.
    pub fn run_filter(&mut self) {
        let Some(i) = self.curves.selected else {
            self.notify("select a curve to fair first", true);
            return;
        };
        let curve = &self.curve_set().curves[i];
        if curve.segment.is_some() {
            self.notify("this is a log-aesthetic segment already: there is nothing to fair", true);
            return;
        }
        let seq = curve.sequence();
        let refused = format!("cannot fair '{}': ", curve.name);
        match self.make_filter(&seq) {
            Ok(filter) => {
                // An earlier refusal (no α to estimate) no longer holds.
                if self.notice.as_ref().is_some_and(|n| n.text.starts_with(&refused)) {
                    self.notice = None;
                }
                let before = curvature_graph(&seq, filter.plane().map(|p| p.normal)).fit.map(|f| f.residual);
                self.curves.run =
                    Some(FilterRun { curve: i, filter, running: true, base: seq.points, residual_before: before });
            }
            Err(e) => self.notify(format!("{refused}{e}"), true),
        }
    }

    fn make_filter(&self, seq: &PointSequence) -> taut_core::Result<CurveFilter> {
        let c = self.curves.filter;
        let torsion_beta = c.space.then_some(c.torsion_beta);
        let alpha = if c.estimate {
            seq.validate(2 * c.window + 1)?;
            let normal = if c.space { None } else { Plane::fit(&seq.points).map(|p| p.normal) };
            let estimate = estimate_alpha(seq, normal, &EstimateSettings::default())
                .map_err(|e| taut_core::Error::Input(format!("cannot estimate α: {e}")))?;
            Alpha::PerPoint(estimate.per_point())
        } else {
            Alpha::Uniform(c.alpha)
        };
        let base = if c.keep_shape && !c.space { FilterSettings::keeping_shape() } else { FilterSettings::default() };
        CurveFilter::new(seq, FilterSettings { window: c.window, alpha, torsion_beta, ..base })
    }

    /// Stops the filter, keeping what it did as one undo step.
    pub fn stop_filter(&mut self) {
        if let Some(run) = &mut self.curves.run {
            run.running = false;
        }
        self.commit_filter();
    }

    /// Goes on with the stopped filter (a new one when the curve changed since).
    pub fn continue_filter(&mut self) {
        match &mut self.curves.run {
            Some(run) if !run.status().converged => run.running = true,
            _ => self.run_filter(),
        }
    }

    /// Writes the run's points into the document (one undo step).
    fn commit_filter(&mut self) {
        let Some(run) = &self.curves.run else { return };
        let (i, points) = (run.curve, run.points().to_vec());
        let mut set = self.curve_set().clone();
        if set.curves[i].points == points {
            return;
        }
        set.curves[i].points = points.clone();
        self.set_curves(set);
        if let Some(run) = &mut self.curves.run {
            run.base = points;
        }
    }

    /// One frame of filter work within `budget`; commits when the run converges.
    /// Runs the live filter for about `budget` (one pass at least) and commits it when it ends.
    pub fn step_curves(&mut self, budget: Duration) {
        let Some(run) = &self.curves.run else { return };
        // A run whose curve changed under it (undo, delete) is dropped.
        let current = self.curve_set().curves.get(run.curve).map(|c| &c.points);
        if current != Some(&run.base) {
            self.curves.run = None;
            return;
        }
        if !run.running {
            return;
        }
        let started = Instant::now();
        let run = self.curves.run.as_mut().expect("checked above");
        let mut failure = None;
        let mut passes = 1;
        loop {
            let t = Instant::now();
            match run.filter.run(passes) {
                Ok(status) if status.converged => break,
                Ok(_) => {}
                Err(e) => {
                    failure = Some(e.to_string());
                    break;
                }
            }
            if started.elapsed() >= budget {
                break;
            }
            // Double the passes while they are fast, to keep the clock checks cheap.
            if t.elapsed() < budget / 16 {
                passes = (passes * 2).min(64);
            }
        }
        let status = run.status();
        let done = status.converged || status.passes >= run.filter.settings().max_passes || failure.is_some();
        if done {
            run.running = false;
            self.commit_filter();
            match failure {
                Some(e) => self.notify(format!("the filter stopped: {e}; the last good pass is kept"), true),
                None => self.notify(format!("the filter converged after {} passes", status.passes), false),
            }
        }
    }

    /// True while the filter is running (the window keeps redrawing).
    pub fn curves_busy(&self) -> bool {
        self.curves.run.as_ref().is_some_and(|r| r.running)
    }

    /// The plots' data of the selected curve as shown now.
    pub fn selected_plots(&mut self) -> Option<&CurvePlots> {
        let i = self.curves.selected?;
        let points = self.shown_points(i).to_vec();
        if points.len() < 3 {
            return None;
        }
        let fresh = self.curves.plots.as_ref().is_some_and(|p| p.points == points);
        if !fresh {
            let closed = self.curve_set().curves[i].closed;
            let normal = if self.curves.filter.space { None } else { Plane::fit(&points).map(|p| p.normal) };
            let seq = PointSequence::new(points, closed);
            let graph = curvature_graph(&seq, normal);
            let (pieces, estimate_error) = match estimate_alpha(&seq, normal, &EstimateSettings::default()) {
                Ok(est) => {
                    let pieces = est
                        .pieces
                        .iter()
                        .filter_map(|p| {
                            let inside: Vec<usize> =
                                (0..seq.len()).filter(|&k| (p.start..=p.end).contains(&est.parameters[k])).collect();
                            let (first, last) = (*inside.first()?, *inside.last()?);
                            Some((first, last, graph.fit_range(first, last)?))
                        })
                        .collect();
                    (pieces, None)
                }
                Err(e) => (Vec::new(), Some(e.to_string())),
            };
            self.curves.plots = Some(CurvePlots { points: seq.points, graph, pieces, estimate_error });
        }
        self.curves.plots.as_ref()
    }
}

#[cfg(test)]
#[path = "curves_tests.rs"]
mod tests;
