//! File ▸ Export surface as STEP… in the editor: a small dialog with the fit's tolerance and the
//! file's length unit, then the path (the system dialog where there is one, else the path
//! field), "Replace it?" when the file exists, and the export of [`crate::step_out::export_step`]
//! (the same fit, text and atomic write as the command line's `.step` outputs).
//!
//! The fit takes a fraction of a second on the bundled cube and seconds on a cage of a few hundred
//! faces, so the export runs on its own thread, as Make cage from mesh does: a small window says
//! what is being written and for how long, the editor stays usable (the surface exported is the
//! one shown when Export was pressed), and the entry is off until it ends. There is no Cancel: the
//! fit has no point to stop at. A failed export writes nothing and says why in one line; a
//! successful one reports faces, solids, the largest distance and how well the normals agree.
//!
//! What is exported is the surface shown: under the mirror option with a one-half cage, the
//! mirrored whole. Loop surfaces are made of triangles, which four-sided B-spline faces do not
//! take: the menu entry is off for them and says so.

use crate::editor::state::EditorState;
use crate::editor::ui::{PathPurpose, UiState};
use crate::step_out::StepSummary;
use egui::Key;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::{Duration, Instant};
use taut_core::Document;
use taut_core::cad::{DEFAULT_RELATIVE_TOLERANCE, LengthUnit};
use taut_core::surface::SchemeKind;

/// The menu entry.
pub const MENU_ENTRY: &str = "Export surface as STEP…";

/// Why the entry is off for a Loop surface.
pub const LOOP_REFUSAL: &str = "STEP takes four-sided B-spline faces; Loop surfaces are triangles: use Catmull–Clark, \
                                NUSD or the curve mesh";

/// How often the progress window looks at a running export.
const PROGRESS_REPAINT: Duration = Duration::from_millis(300);

/// The units offered, as the command line's `--units` names them.
const UNITS: [(LengthUnit, &str, &str); 4] = [
    (LengthUnit::Millimetre, "mm", "millimetres"),
    (LengthUnit::Centimetre, "cm", "centimetres"),
    (LengthUnit::Metre, "m", "metres"),
    (LengthUnit::Inch, "in", "inches"),
];

/// The export's options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOptions {
    /// The largest distance between the B-spline faces and the surface, in the cage's units.
    pub tolerance: f64,
    /// The length unit the file declares for the cage's coordinates.
    pub units: LengthUnit,
}

/// The STEP export's dialogs.
#[derive(Debug, Default)]
pub struct StepExportUi {
    /// The options dialog is open with these; the tolerance's default is the second.
    pub dialog: Option<(StepOptions, f64)>,
    /// The options of the last Export: the path chosen next is exported with them.
    pub options: Option<StepOptions>,
    /// An export onto a file that exists, waiting for "Replace it?".
    pub replace: Option<PathBuf>,
    /// The export running on its own thread.
    pub job: Option<StepJob>,
}

/// An export running on its own thread.
#[derive(Debug)]
pub struct StepJob {
    pub path: PathBuf,
    pub started: Instant,
    result: Receiver<Result<StepSummary, String>>,
}

impl StepJob {
    /// Fits `doc` and writes `path` on a new thread.
    fn start(doc: Document, path: PathBuf, options: StepOptions) -> Self {
        let (sender, result) = mpsc::channel();
        let target = path.clone();
        let started = std::thread::Builder::new().name("taut STEP export".into()).spawn(move || {
            let summary = crate::step_out::export_step(&doc, &target, Some(options.tolerance), options.units);
            let _ = sender.send(summary);
        });
        let mut job = StepJob { path, started: Instant::now(), result };
        if started.is_err() {
            let (sender, result) = mpsc::channel();
            let _ = sender.send(Err("could not start a thread for the export".into()));
            job.result = result;
        }
        job
    }

    /// The export's end, once it has ended.
    fn poll(&self) -> Option<Result<StepSummary, String>> {
        match self.result.try_recv() {
            Ok(result) => Some(result),
            Err(TryRecvError::Empty) => None,
            // The thread ended without a word: it panicked.
            Err(TryRecvError::Disconnected) => Some(Err("the export stopped unexpectedly".into())),
        }
    }
}

impl StepExportUi {
    /// True while one of its dialogs is open (it owns the keyboard then).
    pub fn is_open(&self) -> bool {
        self.dialog.is_some() || self.replace.is_some()
    }
}

/// The unit's short name (mm, cm, m, in).
pub fn unit_label(unit: LengthUnit) -> &'static str {
    crate::step_out::unit_name(unit)
}

impl EditorState {
    /// The document whose surface is exported: the one shown (the mirrored whole of a one-half
    /// cage under the mirror option).
    fn step_document(&mut self) -> Document {
        self.mirrored_surface_document().unwrap_or_else(|| self.document.doc().clone())
    }

    /// The default options for the surface shown: 1e-4 of its cage's bounding-box diagonal, in
    /// the units last chosen for an export, or at first the document's.
    fn default_step_options(&mut self, ui_state: &UiState) -> StepOptions {
        let tolerance = DEFAULT_RELATIVE_TOLERANCE * self.step_document().cage.bounding_diagonal();
        let units = ui_state.step_export.options.map_or(self.document.doc().units, |o| o.units);
        StepOptions { tolerance, units }
    }

    /// The File menu's entry: off, saying why, for a Loop surface.
    pub(crate) fn step_export_item(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let scheme = self.document.doc().scheme;
        let running = ui_state.step_export.job.is_some();
        let why_off = if running { "A STEP export is running: wait for it to end" } else { LOOP_REFUSAL };
        let clicked = ui
            .add_enabled(scheme != SchemeKind::Loop && !running, egui::Button::new(MENU_ENTRY))
            .on_hover_text("The surface as B-spline faces for CAD (STEP AP214): a solid when the cage is closed")
            .on_disabled_hover_text(why_off)
            .clicked();
        if clicked {
            let options = self.default_step_options(ui_state);
            ui_state.step_export.dialog = Some((options, options.tolerance));
        }
    }

    /// The options dialog and the "Replace it?" question, while open, and the running export.
    pub(crate) fn step_export_dialogs(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        self.step_export_progress(ctx, ui_state);
        if let Some((mut options, default)) = ui_state.step_export.dialog.take() {
            let mut answer = None;
            egui::Modal::new(egui::Id::unique("step options")).show(ctx, |ui| {
                ui.heading("Export the surface as STEP");
                ui.label(format!("B-spline faces fitted to the {} surface", self.document.doc().scheme.display_name()));
                egui::Grid::new("step options grid").num_columns(2).show(ui, |ui| {
                    let name = ui.label("tolerance");
                    ui.horizontal(|ui| {
                        let floor = (default * 1e-6).max(f64::MIN_POSITIVE);
                        ui.add(
                            egui::DragValue::new(&mut options.tolerance)
                                .range(floor..=(default * 1e4).max(floor))
                                .speed(default * 0.02)
                                .custom_formatter(|v, _| format!("{v:.3e}"))
                                .custom_parser(|s| s.trim().parse::<f64>().ok()),
                        )
                        .labelled_by(name.id)
                        .on_hover_text(format!(
                            "The largest distance allowed between the B-spline faces and the surface, in the cage's \
                             units; the default is 1e-4 of the cage's bounding-box diagonal ({default:.3e})"
                        ));
                        ui.label(unit_label(options.units));
                        if ui
                            .add_enabled(options.tolerance != default, egui::Button::new("default"))
                            .on_hover_text(format!("Back to 1e-4 of the cage's bounding-box diagonal ({default:.3e})"))
                            .clicked()
                        {
                            options.tolerance = default;
                        }
                    });
                    ui.end_row();
                    ui.label("units");
                    ui.horizontal(|ui| {
                        for (unit, short, long) in UNITS {
                            ui.radio_value(&mut options.units, unit, short)
                                .on_hover_text(format!("The file says the cage's coordinates are in {long}"));
                        }
                    });
                    ui.end_row();
                });
                ui.horizontal(|ui| {
                    if ui.button("Export…").on_hover_text("Choose the file and write it").clicked() {
                        answer = Some(true);
                    }
                    if ui.button("Cancel").clicked() || ui.input(|i| i.key_pressed(Key::Escape)) {
                        answer = Some(false);
                    }
                });
            });
            match answer {
                Some(true) => {
                    ui_state.step_export.options = Some(options);
                    self.ask_path(PathPurpose::ExportStep, ui_state);
                }
                Some(false) => {}
                None => ui_state.step_export.dialog = Some((options, default)),
            }
        }
        if let Some(path) = ui_state.step_export.replace.take() {
            let answer = crate::editor::menus::replace_question(
                ctx,
                "step replace",
                &path,
                "Replacing it writes the STEP file over it",
            );
            match answer {
                Some(true) => {
                    let options = ui_state.step_export.options.unwrap_or_else(|| self.default_step_options(ui_state));
                    self.export_step(&path, options, ui_state);
                }
                Some(false) => {}
                None => ui_state.step_export.replace = Some(path),
            }
        }
    }

    /// The path for the STEP export was chosen (by the system dialog or the path field): asks
    /// first when a file is there, else exports with the options of the dialog.
    pub(crate) fn step_path_chosen(&mut self, path: &Path, ui_state: &mut UiState) {
        let path = crate::editor::state::with_extension_if_missing(path, "step");
        if std::fs::metadata(&path).is_ok_and(|m| m.is_file()) {
            ui_state.step_export.replace = Some(path);
            return;
        }
        let options = ui_state.step_export.options.unwrap_or_else(|| self.default_step_options(ui_state));
        self.export_step(&path, options, ui_state);
    }

    /// Starts fitting the surface shown and writing it to `path` as STEP on its own thread; a
    /// name that is not `.step` or `.stp` is refused at once. Nothing is written on an error.
    pub fn export_step(&mut self, path: &Path, options: StepOptions, ui_state: &mut UiState) {
        let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !extension.as_deref().is_some_and(crate::step_out::is_step) {
            self.step_export_ended(path, Err("a STEP file's name ends in .step or .stp".into()));
            return;
        }
        if ui_state.step_export.job.is_some() {
            self.notify("a STEP export is running: wait for it to end", true);
            return;
        }
        let doc = self.step_document();
        ui_state.step_export.job = Some(StepJob::start(doc, path.to_path_buf(), options));
    }

    /// The running export's window (what is written, for how long); its end becomes the message.
    fn step_export_progress(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        let Some(job) = &ui_state.step_export.job else { return };
        if let Some(result) = job.poll() {
            let path = job.path.clone();
            ui_state.step_export.job = None;
            self.step_export_ended(&path, result);
            // The message came after this frame's panels were drawn: draw them again.
            ctx.request_repaint();
            return;
        }
        ctx.request_repaint_after(PROGRESS_REPAINT);
        let seconds = job.started.elapsed().as_secs_f64();
        let window = egui::Window::new("Exporting STEP").collapsible(false).resizable(false);
        // Above the message strip, where the export's summary will show.
        window.anchor(egui::Align2::CENTER_BOTTOM, [0.0, -80.0]).show(ctx, |ui| {
            ui.label(format!("Fitting B-spline faces for {} ({seconds:.1} s)", job.path.display()));
            ui.label("The file is written when the fit ends; you can go on working meanwhile.");
        });
    }

    /// The summary or the one-line reason as the message.
    fn step_export_ended(&mut self, path: &Path, result: Result<StepSummary, String>) {
        match result {
            Ok(summary) => self.notify(
                format!("exported {} (STEP, {}): {}", path.display(), unit_label(summary.units), summary.describe()),
                false,
            ),
            Err(message) => {
                // The core speaks of the command line's flag.
                let message = message.replace("--tolerance", "the tolerance").replace('\n', " ");
                self.notify(format!("could not export {}: {message}", path.display()), true);
            }
        }
    }
}
