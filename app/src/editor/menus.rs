//! The editor's menu bar and its modal dialogs (path field, unsaved changes, crash recovery).

use super::primitives;
use super::state::EditorState;
use super::ui::{MakeDocument, PathPurpose, Pending, UiState};
use egui::Key;
use std::path::PathBuf;
use taut_render::StandardView;

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
            });
            if ui.button("Open…  Ctrl+O").clicked() {
                self.request(Pending::Open(None), ui_state);
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
            }
            ui.separator();
            if ui.button("Save  Ctrl+S").clicked() && !self.save() {
                self.ask_path(PathPurpose::SaveAs, ui_state);
            }
            if ui.button("Save as…  Ctrl+Shift+S").clicked() {
                self.ask_path(PathPurpose::SaveAs, ui_state);
            }
            if ui.button("Export surface as OBJ…").clicked() {
                self.ask_path(PathPurpose::ExportObj, ui_state);
            }
            if ui.button("Export surface as GLB…").clicked() {
                self.ask_path(PathPurpose::ExportGlb, ui_state);
            }
            if ui.button("Save screenshot…").clicked() {
                self.ask_path(PathPurpose::Screenshot, ui_state);
            }
            ui.separator();
            if ui.button("Quit  Ctrl+Q").clicked() {
                self.request(Pending::Quit, ui_state);
            }
        });
        ui.menu_button("Edit", |ui| {
            if ui.add_enabled(self.document.can_undo(), egui::Button::new("Undo  Ctrl+Z")).clicked() {
                self.undo();
            }
            if ui.add_enabled(self.document.can_redo(), egui::Button::new("Redo  Ctrl+Shift+Z")).clicked() {
                self.redo();
            }
            ui.separator();
            if ui.button("Select all  Ctrl+A").clicked() {
                self.selection.clear();
                self.selection.vertices = self.document.doc().cage.vertices().collect();
            }
            if ui.button("Select none  Esc").clicked() {
                self.selection.clear();
            }
        });
        ui.menu_button("View", |ui| {
            for (label, view) in [
                ("Front  1", StandardView::Front),
                ("Right  3", StandardView::Right),
                ("Top  7", StandardView::Top),
                ("Perspective  5", StandardView::Perspective),
            ] {
                if ui.button(label).clicked() {
                    self.camera.set_view(view);
                }
            }
            ui.separator();
            if ui.button("Frame all  Home").clicked() {
                self.frame_all();
            }
            if ui.button("Frame selection  F").clicked() {
                self.frame_selection();
            }
        });
    }

    pub(super) fn dialogs(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        if let Some((purpose, mut text)) = ui_state.path_dialog.take() {
            let mut keep = true;
            let mut chosen = None;
            egui::Modal::new(egui::Id::unique("path dialog")).show(ctx, |ui| {
                ui.label(purpose.title());
                let field = ui
                    .add(egui::TextEdit::singleline(&mut text).desired_width(420.0).id(egui::Id::unique("path field")));
                field.request_focus();
                let enter = field.lost_focus() && ui.input(|i| i.key_pressed(Key::Enter));
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
                        self.ask_path(PathPurpose::SaveAs, ui_state);
                    }
                }
                Some(1) => self.run_pending(action, ui_state),
                Some(_) => {}
                None => ui_state.pending = Some(action),
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
