//! The editor's menu bar and its modal dialogs (path field, unsaved changes, crash recovery).

use super::primitives;
use super::shortcuts::{self, Action};
use super::state::EditorState;
use super::ui::{MakeDocument, PathPurpose, Pending, UiState};
use egui::Key;
use std::path::PathBuf;
use taut_core::io::UpAxis;

/// What the mouse and the keys during a drag do, for Help ▸ Keyboard shortcuts.
const MOUSE_AND_DRAG_KEYS: &[(&str, &str)] = &[
    ("Left click", "Select a cage vertex or edge, or in face mode a face (Shift adds or removes)"),
    ("Alt + left click on an edge", "Select its edge loop (Shift+Alt adds; face mode: the loop of faces)"),
    ("Ctrl + Alt + left click on an edge", "Select its edge ring"),
    ("Left drag on a vertex", "Move the selection in the view plane"),
    ("X, Y or Z while dragging", "Lock the move to that axis (again: unlock)"),
    ("Esc while dragging", "Cancel the move"),
    ("Left drag on empty space", "Box select (Shift adds)"),
    ("Right or middle drag", "Orbit"),
    ("Shift + right or middle drag", "Pan"),
    ("Wheel", "Zoom"),
    ("Left drag on a gizmo handle", "Move along an arrow or in a plane, turn on a ring, scale on a cube or the centre"),
    ("Shift+X, Y or Z while transforming", "Lock to the plane normal to that axis (again: unlock)"),
    ("Ctrl held while transforming", "Snap to the grid step, 5° or 0.1 (the toolbar sets the steps)"),
    ("Shift + right click", "Place the 3D cursor on the surface under the mouse"),
    ("Click an axis of the triad (bottom left)", "Look along that axis; a drag on the triad orbits"),
];

/// What Help says an action does: a tool of the listing (`Action::Tool`) its own description
/// there, every other action the shortcut table's.
pub(crate) fn help_text(action: Action) -> &'static str {
    match (action, super::tools::listed(action)) {
        (Action::Tool(_), Some(tool)) => tool.description,
        _ => shortcuts::describe(action),
    }
}

/// A menu entry's text: its name and its first shortcut.
fn item(action: Action) -> String {
    format!("{}  {}", shortcuts::describe(action), shortcuts::label(action))
}

impl EditorState {
    pub(super) fn menu(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.menu_button("File", |ui| {
            ui.menu_button("New", |ui| {
                let items: [(&str, MakeDocument); 4] = [
                    ("Cube", primitives::cube),
                    ("Pentagonal prism", || primitives::prism(5)),
                    ("Grid patch", || primitives::grid_patch(4, 3)),
                    ("Cylinder", || primitives::cylinder(8, 3)),
                ];
                for (label, make) in items {
                    if ui.button(label).clicked() {
                        self.request(Pending::New(make), ui_state);
                    }
                }
                ui.separator();
                self.new_primitive_items(ui, ui_state);
            });
            if ui.button(item(Action::Open)).clicked() {
                self.emit_action(Action::Open);
            }
            ui.menu_button("Open recent", |ui| {
                let recent: Vec<PathBuf> = self.recent.paths().to_vec();
                if recent.is_empty() {
                    ui.label("(none yet)");
                }
                for path in recent {
                    if ui.button(path.display().to_string()).clicked() {
                        self.request(Pending::Open(Some(path)), ui_state);
                    }
                }
                if !self.recent.paths().is_empty() && ui.button("Clear the list").clicked() {
                    let _ = self.recent.clear();
                }
            });
            if ui.button("Type a path to open…").clicked() {
                ui_state.path_dialog = Some((PathPurpose::Open, String::new()));
                ui_state.focus_path_field = true;
            }
            if ui.button("Make cage from mesh…").clicked() {
                self.open_cage_dialog();
            }
            ui.separator();
            if ui.button(item(Action::Save)).clicked() {
                self.emit_action(Action::Save);
            }
            if ui.button(item(Action::SaveAs)).clicked() {
                self.emit_action(Action::SaveAs);
            }
            ui.menu_button(format!("Units ({})", self.document.doc().units.symbol()), |ui| {
                ui.label("What one model unit is: lengths are shown with it and STEP files declare it");
                for unit in taut_core::document::LengthUnit::ALL {
                    let now = self.document.doc().units == unit;
                    if ui.radio(now, format!("{} ({})", unit.name(), unit.symbol())).clicked() && !now {
                        self.emit(taut_core::document::edit::Edit::SetUnits(unit));
                    }
                }
            });
            ui.separator();
            if ui.button("Export surface as OBJ…").clicked() {
                self.ask_path(PathPurpose::ExportObj, ui_state);
            }
            if ui.button("Export surface as GLB…").clicked() {
                self.ask_path(PathPurpose::ExportGlb, ui_state);
            }
            self.step_export_item(ui, ui_state);
            if ui
                .button("Save edit script…")
                .on_hover_text(
                    "This session's modelling steps as JSON, which `taut edit --script` replays on the file opened",
                )
                .clicked()
            {
                self.ask_path(PathPurpose::EditScript, ui_state);
            }
            if ui.button("Save screenshot…").clicked() {
                self.ask_path(PathPurpose::Screenshot, ui_state);
            }
            ui.separator();
            ui.menu_button("OBJ files are", |ui| {
                ui.radio_value(&mut self.obj_up, UpAxis::Y, "Y up (Blender, most tools)")
                    .on_hover_text("Read and write OBJ files with +Y up, as Blender exports them by default");
                ui.radio_value(&mut self.obj_up, UpAxis::Z, "Z up (Taut's own axes)")
                    .on_hover_text("Read and write OBJ coordinates as they are");
            });
            ui.separator();
            if ui.button(item(Action::Quit)).clicked() {
                self.emit_action(Action::Quit);
            }
        });
        let surface = self.curves.workspace == taut_core::curve::Workspace::Surface;
        ui.menu_button("Edit", |ui| {
            let named = |action: Action, name: Option<&str>| match name {
                Some(name) => format!("{} {name}  {}", shortcuts::describe(action), shortcuts::label(action)),
                None => item(action),
            };
            let undo = named(Action::Undo, self.document.undo_name());
            if ui.add_enabled(self.document.can_undo(), egui::Button::new(undo)).clicked() {
                self.emit_action(Action::Undo);
            }
            let redo = named(Action::Redo, self.document.redo_name());
            if ui.add_enabled(self.document.can_redo(), egui::Button::new(redo)).clicked() {
                self.emit_action(Action::Redo);
            }
            if surface {
                ui.separator();
                if ui.button(item(Action::SelectAll)).clicked() {
                    self.emit_action(Action::SelectAll);
                }
                if ui.button(format!("Select none  {}", shortcuts::label(Action::SelectNone))).clicked() {
                    self.emit_action(Action::SelectNone);
                }
            }
        });
        // The cage is edited in the Surface workspace only.
        if surface {
            self.mesh_menu(ui);
            ui.menu_button("Tools", |ui| {
                // The listing of the tools (`tools::TOOLS`): a new tool appears here by itself.
                for tool in super::tools::TOOLS {
                    let text = format!("{}  {}", tool.name, shortcuts::label(tool.action));
                    if ui.button(text).on_hover_text(tool.description).clicked() {
                        self.emit_action(tool.action);
                    }
                }
            });
        }
        ui.menu_button("View", |ui| {
            for action in [Action::ViewFront, Action::ViewRight, Action::ViewTop, Action::ViewThreeQuarter] {
                if ui.button(item(action)).clicked() {
                    self.emit_action(action);
                }
            }
            let ortho = format!("Orthographic  {}", shortcuts::label(Action::ToggleOrthographic));
            if ui
                .checkbox(&mut self.view.camera.orthographic.clone(), ortho)
                .on_hover_text("On: parallel projection, as a drawing. Off: perspective, as the eye sees")
                .clicked()
            {
                self.emit_action(Action::ToggleOrthographic);
            }
            ui.separator();
            if ui.button(item(Action::FrameAll)).clicked() {
                self.emit_action(Action::FrameAll);
            }
            if ui.button(item(Action::FrameSelection)).clicked() {
                self.emit_action(Action::FrameSelection);
            }
            ui.separator();
            let xray = format!("X-ray  {}", shortcuts::label(Action::ToggleXray));
            if ui
                .checkbox(&mut self.view.display.xray.clone(), xray)
                .on_hover_text("Off: the back of the cage is drawn dimmer and cannot be picked. On: all of it is")
                .clicked()
            {
                self.emit_action(Action::ToggleXray);
            }
            ui.separator();
            if ui.button(format!("Messages ({})", self.messages.len())).clicked() {
                ui_state.show_messages = true;
            }
        });
        ui.menu_button("Help", |ui| {
            if ui.button(item(Action::ShowShortcuts)).clicked() {
                self.emit_action(Action::ShowShortcuts);
            }
        });
    }

    /// Help ▸ Keyboard shortcuts: every key of the table, and the mouse.
    fn shortcuts_window(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        let mut open = ui_state.show_shortcuts;
        let window = egui::Window::new("Keyboard shortcuts").open(&mut open).collapsible(false).auto_sized();
        // Scrolled: the table is taller than a laptop's window.
        let height = 0.8 * ctx.content_rect().height();
        window.show(ctx, |ui| {
            egui::ScrollArea::vertical().max_height(height).show(ui, |ui| {
                egui::Grid::new("shortcut table").striped(true).num_columns(2).show(ui, |ui| {
                    let mut seen = Vec::new();
                    for s in shortcuts::SHORTCUTS {
                        if seen.contains(&s.action) {
                            continue;
                        }
                        seen.push(s.action);
                        ui.label(shortcuts::all_labels(s.action));
                        ui.label(help_text(s.action));
                        ui.end_row();
                    }
                    for (keys, what) in super::curves_keys::help_rows() {
                        ui.label(keys);
                        ui.label(what);
                        ui.end_row();
                    }
                    for (keys, what) in MOUSE_AND_DRAG_KEYS {
                        ui.label(*keys);
                        ui.label(*what);
                        ui.end_row();
                    }
                });
            })
        });
        ui_state.show_shortcuts = open;
    }

    /// Every message of this session, newest last, wrapped to the window.
    fn messages_window(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        let mut open = ui_state.show_messages;
        egui::Window::new("Messages").open(&mut open).default_width(520.0).show(ctx, |ui| {
            if self.messages.is_empty() {
                ui.label("No messages yet.");
            }
            egui::ScrollArea::vertical().max_height(360.0).stick_to_bottom(true).show(ui, |ui| {
                for m in &self.messages {
                    let color = if m.is_error { egui::Color32::LIGHT_RED } else { ui.visuals().text_color() };
                    ui.add(egui::Label::new(egui::RichText::new(&m.text).color(color)).wrap());
                    ui.separator();
                }
            });
            if !self.messages.is_empty() && ui.button("Clear").clicked() {
                self.messages.clear();
                self.notice = None;
            }
        });
        ui_state.show_messages = open;
    }

    pub(super) fn dialogs(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        self.shortcuts_window(ctx, ui_state);
        self.messages_window(ctx, ui_state);
        self.new_primitive_dialog(ctx, ui_state);
        self.step_export_dialogs(ctx, ui_state);
        self.reference_copy_dialog(ctx, ui_state);
        if let Some((purpose, mut text)) = ui_state.path_dialog.take() {
            let mut keep = true;
            let mut chosen = None;
            egui::Modal::new(egui::Id::unique("path dialog")).show(ctx, |ui| {
                ui.label(purpose.title());
                let field = ui
                    .add(egui::TextEdit::singleline(&mut text).desired_width(420.0).id(egui::Id::unique("path field")));
                // Focus once when the dialog opens: taking it every frame would swallow the
                // Enter that confirms the path.
                if std::mem::take(&mut ui_state.focus_path_field) {
                    field.request_focus();
                }
                let enter = (field.lost_focus() || field.has_focus()) && ui.input(|i| i.key_pressed(Key::Enter));
                if let Some(path) =
                    super::file_menu::file_browser::browse(ui, &mut text, purpose.extensions(), self.recent.paths())
                {
                    chosen = Some(path);
                }
                ui.horizontal(|ui| {
                    if ui.button("OK").clicked() || enter {
                        chosen = Some(PathBuf::from(text.trim()));
                    }
                    if ui.button("Cancel").clicked() || ui.input(|i| i.key_pressed(Key::Escape)) {
                        keep = false;
                    }
                });
            });
            match chosen {
                Some(path) if !path.as_os_str().is_empty() => self.path_chosen(purpose, path, ui_state),
                _ if keep => ui_state.path_dialog = Some((purpose, text)),
                _ => {}
            }
        }
        if let Some(action) = ui_state.pending.take() {
            let mut answer = None;
            egui::Modal::new(egui::Id::unique("unsaved")).show(ctx, |ui| {
                ui.label(format!("Save the changes to {} first?", self.document.title().trim_end_matches('*')));
                ui.horizontal(|ui| {
                    if ui.button("Save").clicked() {
                        answer = Some(0);
                    }
                    if ui.button("Discard changes").clicked() {
                        answer = Some(1);
                    }
                    if ui.button("Cancel").clicked() {
                        answer = Some(2);
                    }
                });
            });
            match answer {
                Some(0) => {
                    if self.save() {
                        if !self.document.is_dirty() {
                            self.run_pending(action, ui_state);
                        }
                    } else {
                        // Untitled: the open, new or quit waits for the Save As.
                        ui_state.after_save = Some(action);
                        self.ask_path(PathPurpose::SaveAs, ui_state);
                    }
                }
                Some(1) => self.run_pending(action, ui_state),
                Some(_) => {}
                None => ui_state.pending = Some(action),
            }
        }
        if let Some(path) = ui_state.replace.take() {
            let answer = replace_question(ctx, "replace", &path, "Replacing it writes this cage over the file");
            match answer {
                Some(true) => self.save_as(&path),
                Some(false) => {}
                None => ui_state.replace = Some(path),
            }
        }
        // The Save As that "save changes?" asked for is over: saved, the waiting action runs;
        // cancelled (or failed), it goes and the work stays open.
        if ui_state.after_save.is_some() && ui_state.path_dialog.is_none() && ui_state.replace.is_none() {
            let action = ui_state.after_save.take();
            if let Some(action) = action.filter(|_| !self.document.is_dirty()) {
                self.run_pending(action, ui_state);
            }
        }
        if let Some(recovery) = ui_state.recovery.take() {
            let mut answer = None;
            egui::Modal::new(egui::Id::unique("recovery")).show(ctx, |ui| {
                let what =
                    recovery.original.as_ref().map_or("an untitled cage".to_string(), |p| p.display().to_string());
                ui.label(format!("Taut closed without saving {what}. Recover the autosaved work?"));
                ui.horizontal(|ui| {
                    if ui.button("Recover").clicked() {
                        answer = Some(true);
                    }
                    if ui.button("Discard it").clicked() {
                        answer = Some(false);
                    }
                });
            });
            match answer {
                Some(true) => self.run_pending(Pending::Recover, ui_state),
                Some(false) => {
                    if let Some(a) = &self.autosave {
                        let _ = a.clear();
                    }
                }
                None => ui_state.recovery = Some(recovery),
            }
        }
    }
}

/// "PATH exists already. Replace it?": Some(true) for Replace, Some(false) for Cancel or Esc,
/// `None` while the designer has not answered (ask again next frame). `consequence` says what
/// replacing writes.
pub(crate) fn replace_question(
    ctx: &egui::Context,
    id: &str,
    path: &std::path::Path,
    consequence: &str,
) -> Option<bool> {
    let mut answer = None;
    egui::Modal::new(egui::Id::unique(id)).show(ctx, |ui| {
        ui.label(format!("{} exists already. Replace it?", path.display()));
        ui.label(format!("{consequence}; it cannot be undone."));
        ui.horizontal(|ui| {
            if ui.button("Replace").clicked() {
                answer = Some(true);
            }
            if ui.button("Cancel").clicked() || ui.input(|i| i.key_pressed(Key::Escape)) {
                answer = Some(false);
            }
        });
    });
    answer
}
