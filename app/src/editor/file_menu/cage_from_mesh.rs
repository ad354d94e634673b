//! File ▸ Make cage from mesh… in the editor: a designer picks a dense mesh (a scan, a heavy
//! export) and a target size, the fit runs in the background ([`crate::editor::cage_job`]) with a
//! progress bar and a Cancel button, and the fitted Loop cage becomes the document.
//!
//! The cage is adopted as one undo step ([`EditorDocument::adopt`]): Ctrl+Z goes back to the
//! document that was open, unsaved changes included, so nothing needs asking; the cage has no
//! `.taut` file yet (Save asks for one) and names the mesh as its source. The original stays
//! beside it for comparison, shown as a translucent ghost under the cage's limit surface and as
//! a "distance to original" colour view with a legend, both of which can be turned off and
//! follow every later edit of the cage (the distances are measured again after each change,
//! throttled to at most a third of the time when the measuring is slow). A panel shows the
//! fit's numbers: QEM only against fitted, which cage was kept and the time of each step.
//!
//! The original is not saved in the `.taut` file: a scan is far larger than the cage and is
//! kept where it came from; the panel says so. Opening or starting another document forgets it.
//!
//! [`EditorDocument::adopt`]: crate::editor::document::EditorDocument::adopt

use crate::editor::cage_job::{CageJob, CageRequest, CageResult, Gate, JobEnd, display_name};
use crate::editor::state::EditorState;
use crate::editor::ui::{PathPurpose, UiState};
use std::path::PathBuf;
use std::time::{Duration, Instant};
use taut_core::cage_fit::surface_index::SurfaceIndex;
use taut_core::cage_fit::{CageFitParams, CageSize, Evaluation, FitReport};
use taut_core::surface::SchemeKind;
use taut_core::{Document, PolyMesh};

/// The original's ghost colour (linear RGBA): a translucent blue, apart from the compare
/// view's amber ghost.
pub const ORIGINAL_GHOST: [f32; 4] = [0.10, 0.45, 0.95, 0.30];

/// Source of [`Original`] ids.
static NEXT_ORIGINAL: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// How often the window looks at a running fit's progress.
const PROGRESS_REPAINT: Duration = Duration::from_millis(300);

/// The fastest the distance view re-measures while the cage is being edited.
const MIN_REMEASURE: Duration = Duration::from_millis(150);

/// Why Browse… is off: there is no system file dialog to show.
pub const NO_FILE_DIALOG: &str =
    "No system file dialog is available here (no desktop portal on the session bus): type the mesh's path in the field";

/// The settings of the Make cage dialog.
#[derive(Clone, Debug, PartialEq)]
pub struct CageDialog {
    /// The mesh file, as typed or picked.
    pub path: String,
    /// Size by face count (what a designer asks for) or by a ratio of the triangles (the paper).
    pub by_faces: bool,
    pub faces: usize,
    pub ratio: f64,
    pub rounds: u32,
}

impl Default for CageDialog {
    fn default() -> Self {
        // A ratio fits every mesh (a face count above the mesh's triangles is refused); the
        // face count a designer switches to starts at a size that suits most parts.
        CageDialog {
            path: String::new(),
            by_faces: false,
            faces: 1000,
            ratio: 0.25,
            rounds: taut_core::cage_fit::DEFAULT_ROUNDS,
        }
    }
}

impl CageDialog {
    /// The fit's settings.
    pub fn params(&self) -> CageFitParams {
        let size = if self.by_faces { CageSize::Faces(self.faces) } else { CageSize::Ratio(self.ratio) };
        CageFitParams::new(size, self.rounds)
    }
}

/// The mesh a cage was fitted to, kept beside the document for comparison.
#[derive(Debug)]
pub struct Original {
    pub source: PathBuf,
    /// The prepared original (what the fit saw), drawn as the ghost.
    pub mesh: PolyMesh,
    pub index: SurfaceIndex,
    pub report: FitReport,
    /// Reading, preparing, and the ghost with its index, in seconds.
    pub import_seconds: f64,
    pub prepare_seconds: f64,
    pub ghost_seconds: f64,
    pub show_ghost: bool,
    pub show_distance: bool,
    /// When the distances were last measured and how long that took.
    measured: Option<(Instant, Duration)>,
    /// Unique per original, so the ghost knows a new one from the last.
    id: u64,
}

impl Original {
    /// True when the distance view may measure again: some time after the last measurement, at
    /// least twice as long as it took, so measuring takes at most a third of the time.
    pub fn measure_due(&self) -> bool {
        self.measured.is_none_or(|(at, cost)| at.elapsed() >= MIN_REMEASURE.max(2 * cost))
    }
}

/// Everything of Make cage from mesh: the dialog, the running fit, and the original.
#[derive(Debug, Default)]
pub struct CageFromMesh {
    /// The dialog is open with these settings.
    pub dialog: Option<CageDialog>,
    /// The settings the dialog opens with next (the last ones used).
    pub last: CageDialog,
    pub job: Option<CageJob>,
    pub original: Option<Original>,
    /// Tests hold the job at its first report with this.
    pub(crate) gate: Option<Gate>,
}

impl CageFromMesh {
    /// True while the original's distances colour the surface.
    pub fn distance_shown(&self) -> bool {
        self.original.as_ref().is_some_and(|o| o.show_distance)
    }
}

impl EditorState {
    /// Opens the Make cage dialog (File ▸ Make cage from mesh…).
    pub fn open_cage_dialog(&mut self) {
        if self.cage.dialog.is_none() {
            self.cage.dialog = Some(self.cage.last.clone());
        }
    }

    /// Starts fitting with the dialog's settings; refused with a message when one is running or
    /// the settings cannot work.
    pub fn start_cage_fit(&mut self) {
        let Some(dialog) = self.cage.dialog.clone() else { return };
        if self.cage.job.is_some() {
            self.notify("a cage is being made already: wait for it or cancel it", true);
            return;
        }
        let path = PathBuf::from(dialog.path.trim());
        if path.as_os_str().is_empty() {
            self.notify("choose the mesh to make a cage from first", true);
            return;
        }
        let params = dialog.params();
        // The same checks the fit makes first, before a thread is started (the input's size is
        // not known yet: only what holds for any input).
        if let Err(e) = params.target_faces(usize::MAX) {
            self.notify(format!("cannot make a cage: {e}"), true);
            return;
        }
        self.cage.last = dialog;
        let request = CageRequest { path, params, obj_up: self.obj_up };
        self.cage.job = Some(CageJob::start(request, self.cage.gate.clone()));
    }

    /// Cancels the running fit; the document stays as it is.
    pub fn cancel_cage_fit(&mut self) {
        if let Some(job) = &self.cage.job {
            job.cancel();
        }
    }

    /// Takes what the running fit reported; adopts the cage when it has finished.
    pub fn poll_cage_fit(&mut self) {
        let Some(job) = &mut self.cage.job else { return };
        let Some(end) = job.poll() else { return };
        let name = display_name(&job.request.path);
        self.cage.job = None;
        match end {
            JobEnd::Finished(result) => self.adopt_cage(*result),
            JobEnd::Cancelled => self.notify(format!("cancelled making a cage from {name}; nothing changed"), false),
            JobEnd::Failed(e) => self.notify(format!("could not make a cage: {e}"), true),
        }
    }

    /// Makes the fitted cage the document (one undo step) and keeps the original beside it.
    fn adopt_cage(&mut self, result: CageResult) {
        let CageResult {
            request,
            cage,
            original,
            index,
            report,
            import_seconds,
            prepare_seconds,
            ghost_seconds,
            notes,
        } = result;
        let (faces, vertices) = (cage.face_count(), cage.vertex_count());
        let doc = Document::new(cage).with_scheme(SchemeKind::Loop);
        if let Err(e) = self.document.adopt(doc, Some(request.path.clone())) {
            self.notify(format!("could not use the fitted cage: {e}"), true);
            return;
        }
        self.surface = None;
        self.comparison = None;
        self.surface_error = None;
        self.view.selection.clear();
        self.cage.dialog = None;
        let kept = if report.kept_round > 0 { "the fitted cage" } else { "the QEM cage" };
        let mut text = format!(
            "made a Loop cage of {faces} faces and {vertices} vertices from {}; kept {kept}; Ctrl+Z goes back",
            display_name(&request.path)
        );
        if !notes.is_empty() {
            text.push_str(&format!(" (the mesh: {})", notes.join(", ")));
        }
        self.cage.original = Some(Original {
            source: request.path,
            mesh: original,
            index,
            report,
            import_seconds,
            prepare_seconds,
            ghost_seconds,
            show_ghost: true,
            show_distance: false,
            measured: None,
            id: NEXT_ORIGINAL.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        });
        self.frame_all();
        self.notify(text, false);
    }

    /// Turns the distance-to-original view on or off (it replaces the compare view's distance).
    pub fn set_original_distance(&mut self, on: bool) {
        let Some(original) = &mut self.cage.original else { return };
        original.show_distance = on;
        if on && self.view.display.compare == crate::editor::live::CompareMode::Distance {
            self.set_compare(crate::editor::live::CompareMode::Off);
        }
        self.invalidate_values();
    }

    /// Distances from the surface's vertices to the original, noting when and how long.
    pub(crate) fn measure_original_distances(&mut self) -> Result<Vec<f64>, String> {
        let (Some(view), Some(original)) = (&self.surface, &mut self.cage.original) else {
            return Err("there is no original to measure against".into());
        };
        let started = Instant::now();
        let distances = taut_core::surface::distance::distances_from(view.mesh().positions(), &original.index);
        original.measured = Some((Instant::now(), started.elapsed()));
        Ok(distances)
    }

    /// The Make cage window: settings, then progress and Cancel while the fit runs.
    pub(crate) fn cage_window(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        let was_running = self.cage.job.is_some();
        self.poll_cage_fit();
        if was_running && self.cage.job.is_none() {
            // The document changed after the panels were drawn this frame: draw them again.
            ctx.request_repaint();
        }
        if self.cage.job.is_some() {
            // Look again soon for progress, without spinning: the fit runs on its own thread, and
            // on a software renderer a frame takes a good part of a core
            // (a few frames a second keep the bar moving and leave the fit its CPU).
            ctx.request_repaint_after(PROGRESS_REPAINT);
        }
        let Some(mut dialog) = self.cage.dialog.take() else { return };
        let mut open = true;
        let mut start = false;
        let mut browse = false;
        let mut cancel = false;
        let running = self.cage.job.as_ref().map(|j| (j.progress.clone(), j.cancelling()));
        egui::Window::new("Make cage from mesh").open(&mut open).collapsible(false).resizable(false).show(ctx, |ui| {
            ui.add_enabled_ui(running.is_none(), |ui| {
                let name = ui.label("mesh file (.obj, .stl, .ply, .gltf, .glb)");
                ui.horizontal(|ui| {
                    ui.add(egui::TextEdit::singleline(&mut dialog.path).desired_width(300.0))
                        .labelled_by(name.id)
                        .on_hover_text("The dense mesh to fit a cage to: a scan or a heavy export");
                    // Without a system file dialog Browse would only open another path field.
                    let can_browse = !ui_state.no_native_dialogs && crate::editor::ui::native_dialogs_available();
                    browse = ui
                        .add_enabled(can_browse, egui::Button::new("Browse…"))
                        .on_hover_text("Pick the mesh in the system's file dialog")
                        .on_disabled_hover_text(NO_FILE_DIALOG)
                        .clicked();
                });
                ui.horizontal(|ui| {
                    ui.radio_value(&mut dialog.by_faces, true, "face count")
                        .on_hover_text("About this many triangles in the cage");
                    ui.radio_value(&mut dialog.by_faces, false, "ratio of the triangles")
                        .on_hover_text("A fraction of the mesh's triangles (the paper uses 0.25)");
                });
                if dialog.by_faces {
                    let name = ui.label("faces");
                    ui.add(egui::DragValue::new(&mut dialog.faces).range(4..=10_000_000).speed(10.0))
                        .labelled_by(name.id)
                        .on_hover_text("The cage's size in triangles: 500 to 5,000 suit most parts");
                } else {
                    let name = ui.label("ratio");
                    ui.add(egui::Slider::new(&mut dialog.ratio, 0.0001..=1.0).logarithmic(true))
                        .labelled_by(name.id)
                        .on_hover_text("The cage's triangles as a fraction of the mesh's");
                }
                let name = ui.label("rounds");
                ui.add(egui::DragValue::new(&mut dialog.rounds).range(1..=taut_core::cage_fit::MAX_ROUNDS))
                    .labelled_by(name.id)
                    .on_hover_text("1 is the paper's solve alone; each further round fits the surface to the mesh both ways, farthest points first, keeping the volume");
                start = ui.button("Make cage").clicked();
            });
            if let Some((progress, cancelling)) = &running {
                ui.separator();
                let seconds = progress.started.elapsed().as_secs_f64();
                ui.label(format!("{} ({seconds:.1} s)", progress.step));
                // Steps that report no fraction (reading, preparing) show their name alone.
                let text = if progress.fraction > 0.0 {
                    format!("{}: {:.0} %", progress.step, 100.0 * progress.fraction)
                } else {
                    format!("{}…", progress.step)
                };
                // Not animated: an animated bar repaints every frame and takes the fit's CPU.
                ui.add(egui::ProgressBar::new(progress.fraction.clamp(0.0, 1.0) as f32).text(text));
                if *cancelling {
                    ui.label("cancelling…");
                } else {
                    cancel = ui.button("Cancel").on_hover_text("Stop making the cage; nothing changes").clicked();
                }
            }
        });
        self.cage.dialog = Some(dialog);
        if browse {
            self.ask_path(PathPurpose::MakeCage, ui_state);
        }
        if start {
            self.start_cage_fit();
        }
        if cancel || (!open && self.cage.job.is_some()) {
            self.cancel_cage_fit();
        }
        if !open {
            self.cage.dialog = None;
        }
    }

    /// The fit's numbers and the original's views, in the settings panel.
    pub(crate) fn cage_fit_panel(&mut self, ui: &mut egui::Ui) {
        let Some(original) = &self.cage.original else { return };
        ui.separator();
        ui.heading("Cage from mesh");
        let r = &original.report;
        ui.add(
            egui::Label::new(format!(
                "{}: {} triangles to {} faces, {} vertices",
                display_name(&original.source),
                r.input_triangles,
                r.cage_faces,
                r.cage_vertices
            ))
            .wrap(),
        );
        let fitted = r.fitted();
        let percent = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{:.3} %", 100.0 * v));
        let cell = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.2e}"));
        egui::Grid::new("cage fit numbers").num_columns(3).striped(true).show(ui, |ui| {
            ui.label("");
            ui.label("QEM only");
            ui.label("fitted");
            ui.end_row();
            type Row = (&'static str, &'static str, fn(&Evaluation) -> Option<f64>, bool);
            let rows: [Row; 4] = [
                ("volume change", "|V1 - V| / V after one Loop step (the paper's measure)", |e| e.volume_change, true),
                (
                    "Hausdorff",
                    "Sampled symmetric Hausdorff distance / bounding-box diagonal",
                    |e| Some(e.hausdorff),
                    false,
                ),
                ("mean distance", "Mean distance / bounding-box diagonal", |e| Some(e.mean), false),
                ("limit points max", "Farthest cage limit point / diagonal", |e| Some(e.limit_points_max), false),
            ];
            for (name, help, get, is_percent) in rows {
                ui.label(name).on_hover_text(help);
                let show = |v| if is_percent { percent(v) } else { cell(v) };
                ui.label(show(get(&r.qem)));
                ui.label(show(fitted.and_then(get)));
                ui.end_row();
            }
        });
        let kept = if r.kept_round > 0 { format!("kept: fitted (round {})", r.kept_round) } else { "kept: QEM".into() };
        ui.label(kept);
        ui.add(egui::Label::new(&r.verdict).wrap());
        let mut times = vec![
            format!("read {:.2} s", original.import_seconds),
            format!("prepare {:.2} s", original.prepare_seconds),
        ];
        times.extend(r.steps.iter().map(|s| format!("{} {:.2} s", s.step, s.seconds)));
        times.push(format!("ghost {:.2} s", original.ghost_seconds));
        ui.add(egui::Label::new(format!("times: {}", times.join(", "))).wrap());
        let (mut ghost, mut distance) = (original.show_ghost, original.show_distance);
        ui.checkbox(&mut ghost, "original as ghost").on_hover_text("The mesh the cage was made from, translucent blue");
        let distance_changed = ui
            .checkbox(&mut distance, "colour by distance to original")
            .on_hover_text("The surface coloured by its distance to the original, with a legend; follows every edit")
            .changed();
        ui.add(
            egui::Label::new(
                "The original is not saved in the .taut file, only the cage: make the cage again from the mesh \
                 to compare after reopening.",
            )
            .wrap(),
        );
        let forget = ui.button("Forget the original").on_hover_text("Drop the ghost and the distance view").clicked();
        if let Some(o) = &mut self.cage.original {
            o.show_ghost = ghost;
        }
        if distance_changed {
            self.set_original_distance(distance);
        }
        if forget {
            self.cage.original = None;
            self.invalidate_values();
        }
    }
}

/// The original drawn as a ghost: uploaded once per original and display frame.
#[derive(Debug, Default)]
pub struct OriginalGhost {
    cache: taut_render::SurfaceCache<(u64, u64, u64, taut_render::DisplayFrame)>,
}

impl OriginalGhost {
    /// Uploads the original when it changed; drops it when there is none or it is hidden.
    pub fn upload(&mut self, gpu: &taut_render::Gpu, editor: &EditorState) {
        let Some(original) = editor.cage.original.as_ref().filter(|o| o.show_ghost) else {
            self.cache.clear();
            return;
        };
        let mesh = &original.mesh;
        let key = (original.id, mesh.topology_generation(), mesh.generation(), editor.view.display_frame);
        self.cache.show(gpu, key, taut_render::ShownMesh::plain(mesh), &editor.view.display_frame);
    }

    /// The ghost to draw, if shown.
    pub fn shown(&self, editor: &EditorState) -> Option<(&taut_render::GpuSurface, [f32; 4])> {
        editor.cage.original.as_ref().filter(|o| o.show_ghost).and(self.cache.surface()).map(|g| (g, ORIGINAL_GHOST))
    }
}
