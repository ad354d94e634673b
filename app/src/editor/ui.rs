//! The editor's frame of egui: the layout of menus, panels and viewport, the keyboard, and the
//! actions that need the designer's answer (unsaved changes, paths). Everything the designer
//! does becomes an [`Edit`] of the document or a change of the camera, selection or display;
//! nothing here touches the GPU, so the panels are tested with egui_kittest. The panels are in
//! [`super::panels`], the viewport's mouse handling in [`super::viewport`], the keys in
//! [`super::shortcuts`].

use super::document::EditorDocument;
use super::files::Recovery;
use super::select_modes;
use super::shortcuts::{self, Action};
use super::state::EditorState;
use std::path::PathBuf;
use taut_render::StandardView;

/// What a file path is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathPurpose {
    Open,
    SaveAs,
    ExportObj,
    ExportGlb,
    /// File ▸ Export surface as STEP…, after its options.
    ExportStep,
    Screenshot,
    /// A point sequence for the Curves workspace.
    ImportCurve,
    /// The mesh of File ▸ Make cage from mesh…
    MakeCage,
    /// File ▸ Save edit script…: the session's edits for `taut edit --script`.
    EditScript,
    /// A picture for the Reference images panel.
    ReferenceImage,
}

impl PathPurpose {
    pub fn title(self) -> &'static str {
        match self {
            PathPurpose::Open => "Open a cage (.taut, .obj, .gltf, .glb)",
            PathPurpose::SaveAs => "Save the cage as (.taut)",
            PathPurpose::ExportObj => "Export the surface as OBJ",
            PathPurpose::ExportGlb => "Export the surface as GLB",
            PathPurpose::ExportStep => "Export the surface as STEP (.step, .stp)",
            PathPurpose::Screenshot => "Save a screenshot of the viewport (.png)",
            PathPurpose::ImportCurve => {
                "Import a curve: points as .json ({\"points\": [[x, y], ...]}) or .csv (x,y(,z) rows)"
            }
            PathPurpose::MakeCage => "Make a cage from a mesh (.obj, .stl, .ply, .gltf, .glb)",
            PathPurpose::EditScript => "Save this session's edits as a script for taut edit (.json)",
            PathPurpose::ReferenceImage => "Add a reference image (.png, .jpg, .jpeg)",
        }
    }

    /// The extensions (lower case) of the files the in-app browser lists for this purpose.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            PathPurpose::Open => &["taut", "obj", "gltf", "glb"],
            PathPurpose::ImportCurve => &["json", "csv"],
            PathPurpose::MakeCage => &["obj", "stl", "ply", "gltf", "glb"],
            PathPurpose::ExportStep => &["step", "stp"],
            PathPurpose::SaveAs => &["taut"],
            PathPurpose::ExportObj => &["obj"],
            PathPurpose::ExportGlb => &["glb"],
            PathPurpose::Screenshot => &["png"],
            PathPurpose::EditScript => &["json"],
            PathPurpose::ReferenceImage => super::workspaces::surface::reference_images::PICTURE_EXTENSIONS,
        }
    }

    fn extension(self) -> &'static str {
        match self {
            PathPurpose::Open => "taut",
            PathPurpose::SaveAs => "taut",
            PathPurpose::ExportObj => "obj",
            PathPurpose::ExportGlb => "glb",
            PathPurpose::ExportStep => "step",
            PathPurpose::Screenshot => "png",
            PathPurpose::ImportCurve => "json",
            PathPurpose::MakeCage => "obj",
            PathPurpose::EditScript => "json",
            PathPurpose::ReferenceImage => "png",
        }
    }
}

/// Makes a new document (the File ▸ New entries).
pub type MakeDocument = fn() -> taut_core::Document;

/// Something that would drop unsaved work, waiting for the designer's answer.
#[derive(Clone, Debug)]
pub enum Pending {
    New(MakeDocument),
    /// A new document made already (File ▸ New with counts).
    NewDocument(Box<taut_core::Document>),
    Open(Option<PathBuf>),
    Recover,
    Quit,
}

/// Dialog and gesture state of the UI.
#[derive(Debug, Default)]
pub struct UiState {
    /// The in-app path field (used when there is no system file dialog).
    pub path_dialog: Option<(PathPurpose, String)>,
    /// An action waiting for "save changes?".
    pub pending: Option<Pending>,
    /// A Save As onto a file that exists, waiting for "replace it?".
    pub replace: Option<PathBuf>,
    /// An action waiting for the Save As that "save changes?" asked for on an untitled
    /// document: it runs once the document is saved, and goes when the Save As is cancelled.
    pub after_save: Option<Pending>,
    /// A crash recovery offered at start.
    pub recovery: Option<Recovery>,
    /// Set when the editor should close.
    pub quit: bool,
    /// A screenshot the window should write.
    pub screenshot: Option<PathBuf>,
    /// The viewport's rectangle in physical pixels, for the renderer.
    pub viewport_px: Option<[u32; 4]>,
    /// The modal tool running, if any (it has the keyboard and the viewport's primary button).
    pub tool: super::tools::tool::ActiveTool,
    /// Tension slider values while a slider is held (one undo step a movement).
    pub(super) slider_active: bool,
    /// Use the in-app path field even when a system dialog might exist (tests, Xvfb).
    pub no_native_dialogs: bool,
    /// Help ▸ Keyboard shortcuts is open.
    pub show_shortcuts: bool,
    /// The message history is open.
    pub show_messages: bool,
    /// The path field was just opened: it takes the keyboard focus once.
    pub(super) focus_path_field: bool,
    /// The actions run by shortcuts and menus, newest last (the last 64; for tests and support).
    pub action_log: Vec<Action>,
    /// The pointer's last position over the viewport, in points.
    pub(super) pointer: Option<glam::Vec2>,
    /// Drags and questions of the curve-mesh scheme.
    pub curve_mesh: super::curve_mesh_edit::CurveMeshUi,
    /// File ▸ New with counts: the open dialog.
    pub(super) new_primitive: Option<super::new_primitive::NewPrimitive>,
    /// File ▸ Export surface as STEP…: its options and "Replace it?".
    pub step_export: super::step_export::StepExportUi,
    /// A reference picture chosen outside the document's folder, waiting for "copy it there?".
    pub reference_copy: Option<PathBuf>,
}

impl EditorState {
    /// One frame of the UI: lays it out, taking the input (panels, menus and keys emit
    /// commands; a running tool moves), then applies the frame's commands
    /// ([`super::session::commands`]).
    pub fn ui(&mut self, ui_root: &mut egui::Ui, ui_state: &mut UiState) {
        self.lay_out(ui_root, ui_state);
        if self.apply_commands(ui_state) {
            // What the commands changed is shown by the next frame, at once.
            ui_root.ctx().request_repaint();
        }
    }

    /// Draws the whole UI for one frame and handles its input.
    fn lay_out(&mut self, ui_root: &mut egui::Ui, ui_state: &mut UiState) {
        let ctx = ui_root.ctx().clone();
        self.refresh_reference_images();
        // The selection this state began with, for undo and redo to put back.
        self.note_selection();
        self.shortcuts(&ctx, ui_state);
        egui::Panel::top("menu").show(ui_root, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                self.menu(ui, ui_state);
                self.workspace_switch(ui);
                if self.curves.workspace == taut_core::curve::Workspace::Surface {
                    self.transform_toolbar(ui);
                }
            });
        });
        if self.curves.workspace == taut_core::curve::Workspace::Curves {
            self.curves_workspace_ui(ui_root, ui_state);
            self.cage_window(&ctx, ui_state);
            self.dialogs(&ctx, ui_state);
            return;
        }
        egui::Panel::bottom("status").show(ui_root, |ui| self.status_bar(ui, ui_state));
        egui::Panel::left("cage").resizable(false).exact_size(260.0).show(ui_root, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| self.cage_panel(ui, ui_state));
        });
        egui::Panel::right("settings").resizable(false).exact_size(270.0).show(ui_root, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                self.solver_panel(ui, ui_state);
                ui.separator();
                self.display_panel(ui);
                ui.separator();
                self.reference_images_panel(ui, ui_state);
                self.cage_fit_panel(ui);
            });
        });
        let viewport = egui::CentralPanel::no_frame().show(ui_root, |ui| self.viewport(ui, ui_state)).response.rect;
        self.notice_overlay(&ctx, viewport, ui_state);
        self.cage_window(&ctx, ui_state);
        self.dialogs(&ctx, ui_state);
    }

    fn shortcuts(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        // Typing into a text field owns the keyboard, and so does an open dialog (Esc cancels it);
        // a focused slider or button does not.
        if ctx.text_edit_focused()
            || ui_state.path_dialog.is_some()
            || ui_state.pending.is_some()
            || ui_state.replace.is_some()
            || ui_state.recovery.is_some()
            || ui_state.new_primitive.is_some()
            || ui_state.step_export.is_open()
            || ui_state.reference_copy.is_some()
        {
            return;
        }
        if ui_state.tool.keys(self, ctx) {
            return;
        }
        if self.curves.workspace == taut_core::curve::Workspace::Curves {
            for action in ctx.input_mut(super::curves_keys::pressed) {
                self.run_curve_key(action);
            }
        }
        for action in ctx.input_mut(shortcuts::pressed) {
            self.emit_action(action);
        }
    }

    /// Runs what a shortcut or a menu entry asks for.
    pub(crate) fn run_action(&mut self, action: Action, ui_state: &mut UiState) {
        if ui_state.action_log.len() == 64 {
            ui_state.action_log.remove(0);
        }
        ui_state.action_log.push(action);
        if action.acts_on_the_cage() && self.curves.workspace == taut_core::curve::Workspace::Curves {
            return;
        }
        // Every listed tool starts the same way; its entry says how.
        if super::tools::listed(action).is_some() {
            self.start_listed_tool(action, ui_state);
            return;
        }
        match action {
            Action::Undo => self.undo(),
            Action::Redo => self.redo(),
            // Save without a path asks for one, as Save As does.
            Action::Save => {
                if !self.save() {
                    self.ask_path(PathPurpose::SaveAs, ui_state);
                }
            }
            Action::SaveAs => self.ask_path(PathPurpose::SaveAs, ui_state),
            // The file first, then "save changes?": the path typed or picked is kept through
            // the question and opened after Save or Discard.
            Action::Open => self.ask_path(PathPurpose::Open, ui_state),
            Action::Quit => self.request(Pending::Quit, ui_state),
            Action::SelectAll => {
                self.view.selection.clear();
                self.view.selection.vertices = self.document.doc().cage.vertices().collect();
                let mode = self.view.selection.mode;
                select_modes::set_mode(&self.document.doc().cage, &mut self.view.selection, mode);
            }
            Action::SelectNone => self.view.selection.clear(),
            Action::FrameAll => self.frame_all(),
            Action::FrameSelection if self.curves.workspace == taut_core::curve::Workspace::Curves => {
                self.frame_curves_selection()
            }
            Action::FrameSelection => self.frame_selection(),
            Action::ViewFront => self.view.camera.set_view(StandardView::Front),
            Action::ViewRight => self.view.camera.set_view(StandardView::Right),
            Action::ViewTop => self.view.camera.set_view(StandardView::Top),
            Action::ViewThreeQuarter => self.view.camera.set_view(StandardView::Perspective),
            Action::ToggleOrthographic => {
                let camera = &mut self.view.camera;
                camera.orthographic = !camera.orthographic;
                let name = if camera.orthographic { "Orthographic" } else { "Perspective" };
                self.notify(format!("{name} projection"), false);
            }
            Action::ShowShortcuts => ui_state.show_shortcuts = true,
            Action::CycleSelectMode => {
                let mode = self.view.selection.mode.next();
                select_modes::set_mode(&self.document.doc().cage, &mut self.view.selection, mode);
                self.notify(format!("{} select mode", mode.name()), false);
            }
            Action::SelectLinked => select_modes::select_linked(&self.document.doc().cage, &mut self.view.selection),
            Action::SelectMore => select_modes::select_more(&self.document.doc().cage, &mut self.view.selection),
            Action::SelectLess => select_modes::select_less(&self.document.doc().cage, &mut self.view.selection),
            Action::Mesh(op) => self.mesh_op(op),
            // Listed above.
            Action::Crease | Action::Corner | Action::Transform(_) | Action::Tool(_) => {}
            Action::ToggleGizmo => self.toggle_gizmo(),
            Action::CyclePivot => self.cycle_pivot(),
            Action::ToggleMirror => self.toggle_mirror(),
            Action::ToggleXray => self.toggle_xray(),
        }
    }

    /// Starts the tool [`super::tools::TOOLS`] lists for `action`.
    fn start_listed_tool(&mut self, action: Action, ui_state: &mut UiState) {
        let Some(entry) = super::tools::listed(action) else { return };
        // A tool running (its menu entry chosen while it runs) ends first, its gesture closed.
        ui_state.tool.end(self, super::tools::tool::End::Keep);
        self.apply_commands(ui_state);
        if let Some(tool) = (entry.start)(self, ui_state.pointer) {
            ui_state.tool.start(self, tool);
        }
    }

    /// Undoes the last step; the notice of what was undone goes (it no longer holds).
    pub fn undo(&mut self) {
        self.note_selection();
        if self.document.undo() {
            self.restore_selection();
            self.curves_after_undo();
            self.notice = None;
        }
    }

    /// Redoes the last undone step; the notice of the state before goes.
    pub fn redo(&mut self) {
        self.note_selection();
        if self.document.redo() {
            self.restore_selection();
            self.curves_after_undo();
            self.notice = None;
        }
    }

    /// Runs an action now, or asks first when it would drop unsaved changes.
    pub fn request(&mut self, action: Pending, ui_state: &mut UiState) {
        if self.document.is_dirty() {
            ui_state.pending = Some(action);
        } else {
            self.run_pending(action, ui_state);
        }
    }

    pub(super) fn run_pending(&mut self, action: Pending, ui_state: &mut UiState) {
        match action {
            Pending::New(make) => self.replace_document(EditorDocument::new(make(), None)),
            Pending::NewDocument(doc) => self.replace_document(EditorDocument::new(*doc, None)),
            Pending::Open(Some(path)) => self.open(&path),
            Pending::Open(None) => self.ask_path(PathPurpose::Open, ui_state),
            Pending::Recover => {
                match self.autosave.as_ref().ok_or_else(|| "autosave is off".to_string()).and_then(|a| a.recover()) {
                    Ok(document) => {
                        self.replace_document(document);
                        self.notify("recovered the autosaved work; save it to keep it", false);
                    }
                    Err(e) => self.notify(format!("could not recover: {e}"), true),
                }
            }
            Pending::Quit => ui_state.quit = true,
        }
    }

    /// Asks for a path: the system dialog when there is one, else the in-app path field.
    pub fn ask_path(&mut self, purpose: PathPurpose, ui_state: &mut UiState) {
        if !ui_state.no_native_dialogs && native_dialogs_available() {
            let dialog = rfd::FileDialog::new().set_title(purpose.title());
            let dialog = match purpose {
                PathPurpose::Open => dialog.add_filter("Cages and meshes", &["taut", "obj", "gltf", "glb"]),
                PathPurpose::ImportCurve => dialog.add_filter("Point files", &["json", "csv"]),
                PathPurpose::MakeCage => dialog.add_filter("Meshes", &["obj", "stl", "ply", "gltf", "glb"]),
                PathPurpose::ReferenceImage => dialog.add_filter("Pictures", purpose.extensions()),
                PathPurpose::ExportStep => {
                    let suggested = PathBuf::from(self.suggested_path(purpose));
                    let name = suggested.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                    dialog.add_filter("STEP", &["step", "stp"]).set_file_name(name)
                }
                other => dialog.add_filter(other.extension(), &[other.extension()]),
            };
            let picking = matches!(
                purpose,
                PathPurpose::Open | PathPurpose::MakeCage | PathPurpose::ImportCurve | PathPurpose::ReferenceImage
            );
            let picked = if picking { dialog.pick_file() } else { dialog.save_file() };
            if let Some(path) = picked {
                self.path_chosen(purpose, path, ui_state);
            }
            return;
        }
        ui_state.path_dialog = Some((purpose, self.suggested_path(purpose)));
        ui_state.focus_path_field = true;
    }

    /// What the path field offers: the document's own name (the `.taut` file, or the mesh it was
    /// imported from) with the purpose's extension; an export never suggests the mesh the cage
    /// came from, so it is not replaced by accident.
    pub(super) fn suggested_path(&self, purpose: PathPurpose) -> String {
        if purpose == PathPurpose::MakeCage {
            return self.cage.dialog.as_ref().map(|d| d.path.clone()).unwrap_or_default();
        }
        if purpose == PathPurpose::ReferenceImage {
            // The browser opens in the document's folder, where the pictures belong.
            let folder = self.document_folder().and_then(|f| f.canonicalize().ok());
            return folder.map(|f| format!("{}{}", f.display(), std::path::MAIN_SEPARATOR)).unwrap_or_default();
        }
        let named = self.document.path().or(self.document.source());
        let (Some(path), true) = (named, !matches!(purpose, PathPurpose::Open | PathPurpose::ImportCurve)) else {
            return if matches!(purpose, PathPurpose::Open | PathPurpose::ImportCurve) {
                String::new()
            } else {
                format!("untitled.{}", purpose.extension())
            };
        };
        let stem = path.file_stem().map_or_else(|| "untitled".into(), |s| s.to_string_lossy().into_owned());
        let name = match purpose {
            PathPurpose::ExportObj | PathPurpose::ExportGlb => format!("{stem}-surface.{}", purpose.extension()),
            PathPurpose::EditScript => format!("{stem}-edits.json"),
            _ => format!("{stem}.{}", purpose.extension()),
        };
        path.with_file_name(name).display().to_string()
    }

    pub(super) fn path_chosen(&mut self, purpose: PathPurpose, path: PathBuf, ui_state: &mut UiState) {
        match purpose {
            PathPurpose::Open => self.request(Pending::Open(Some(path)), ui_state),
            PathPurpose::SaveAs => self.save_as_asking(&path, ui_state),
            PathPurpose::ExportObj => self.export(&super::state::with_extension_if_missing(&path, "obj")),
            PathPurpose::ExportGlb => self.export(&super::state::with_extension_if_missing(&path, "glb")),
            PathPurpose::ExportStep => self.step_path_chosen(&path, ui_state),
            PathPurpose::Screenshot => {
                ui_state.screenshot = Some(super::state::with_extension_if_missing(&path, "png"))
            }
            PathPurpose::ImportCurve => self.import_curve(&path),
            PathPurpose::EditScript => self.save_edit_script(&super::state::with_extension_if_missing(&path, "json")),
            PathPurpose::ReferenceImage => self.reference_picked(path, ui_state),
            PathPurpose::MakeCage => {
                self.open_cage_dialog();
                if let Some(dialog) = &mut self.cage.dialog {
                    dialog.path = path.display().to_string();
                }
            }
        }
    }
}

impl EditorState {
    /// Writes the session's edits as a script (atomically); an existing file is not replaced.
    pub fn save_edit_script(&mut self, path: &std::path::Path) {
        let written = self.document.script().and_then(|script| {
            if std::fs::symlink_metadata(path).is_ok() {
                return Err(format!("{} exists already: choose another name", path.display()));
            }
            taut_core::io::write_atomic(path, script.to_json().as_bytes()).map_err(|e| e.to_string())?;
            Ok(script.edits.len())
        });
        match written {
            Ok(n) => self.notify(format!("saved {n} edits to {}", path.display()), false),
            Err(message) => self.notify(format!("could not save the edit script: {message}"), true),
        }
    }

    /// Save As to `path`, asking first when a file is there already (whichever way the path was
    /// chosen: the system dialog or the path field): nothing is written until the designer says
    /// Replace.
    pub fn save_as_asking(&mut self, path: &std::path::Path, ui_state: &mut UiState) {
        let path = super::state::with_extension_if_missing(path, "taut");
        if std::fs::symlink_metadata(&path).is_ok() {
            ui_state.replace = Some(path);
        } else {
            self.save_as(&path);
        }
    }
}

/// True when a system file dialog can be shown (an XDG desktop portal on the session bus).
pub fn native_dialogs_available() -> bool {
    std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some() && std::env::var_os("TAUT_NO_NATIVE_DIALOGS").is_none()
}
