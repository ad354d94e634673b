//! The Reference images panel and the pictures behind it: add a PNG or JPEG, place it on the
//! front, side or top plane or facing the camera, move, size, turn and fade it, put it behind or
//! over the model, hide or remove it. Every change is one [`Edit`] (a slider's drag one undo
//! step); the pictures themselves are read by [`ReferencePictures`], never by the document.
//!
//! A document's pictures live beside it: the document stores a path relative to its folder
//! ([`taut_core::document::reference_images`]). A picture chosen inside that folder is stored so;
//! one chosen elsewhere is offered to be copied next to the document (Taut never reads a picture
//! outside the document's folder, so a document sent to someone cannot make it read their files);
//! an unsaved document has no folder yet, so Add asks to save first.

use crate::editor::state::EditorState;
use crate::editor::ui::{PathPurpose, UiState};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use taut_core::DVec3;
use taut_core::document::reference_images::relative_to_folder;
use taut_core::document::{Edit, ReferenceImage, ReferencePlane};
use taut_render::reference_images::{Picture, PictureKey, ReferenceQuad, load_picture, picture_key};

/// The extensions the picture browser lists.
pub const PICTURE_EXTENSIONS: &[&str] = &["png", "jpg", "jpeg"];

/// What became of one image's file: its picture, or why there is none.
#[derive(Clone, Debug)]
enum Entry {
    Shown(Picture),
    /// Why there is no picture, and the file it was read from when it was found (a broken
    /// picture is not decoded again each frame, only when its file changes).
    Refused(String, Option<PictureKey>),
}

/// The decoded pictures of the document's reference images, by the image's path as stored:
/// read again only when the file (or where the document is) changes, and the reason in one line
/// when it cannot be read.
#[derive(Debug, Default)]
pub struct ReferencePictures {
    entries: HashMap<String, Entry>,
    /// The folder the entries were read from.
    folder: Option<PathBuf>,
}

impl ReferencePictures {
    /// Brings the pictures in step with `images` in `folder`; returns the messages that are new
    /// (a refusal or a missing file is told once, not every frame).
    pub fn refresh(&mut self, images: &[ReferenceImage], folder: Option<&Path>) -> Vec<String> {
        if self.folder.as_deref() != folder {
            self.entries.clear();
            self.folder = folder.map(Path::to_path_buf);
        }
        self.entries.retain(|path, _| images.iter().any(|i| i.path == *path));
        let mut told = Vec::new();
        for image in images {
            let entry = match folder {
                None => Entry::Refused(
                    format!(
                        "reference image {} is not shown: save the document, as its path is relative to the document's folder",
                        image.path
                    ),
                    None,
                ),
                Some(folder) => match picture_key(image, folder) {
                    Err(message) => Entry::Refused(message, None),
                    Ok(key) => match self.entries.get(&image.path) {
                        Some(Entry::Shown(picture)) if picture.key == key => continue,
                        Some(Entry::Refused(_, Some(tried))) if *tried == key => continue,
                        _ => match load_picture(key.clone(), &image.path) {
                            Ok(picture) => Entry::Shown(picture),
                            Err(message) => Entry::Refused(message, Some(key)),
                        },
                    },
                },
            };
            if let Entry::Refused(message, _) = &entry
                && !matches!(self.entries.get(&image.path), Some(Entry::Refused(m, _)) if m == message)
                && folder.is_some()
            {
                told.push(message.clone());
            }
            self.entries.insert(image.path.clone(), entry);
        }
        told
    }

    /// The picture of an image's path, when it was read.
    pub fn picture(&self, path: &str) -> Option<&Picture> {
        match self.entries.get(path) {
            Some(Entry::Shown(picture)) => Some(picture),
            _ => None,
        }
    }

    /// Why an image's picture is not shown, if it is not.
    pub fn problem(&self, path: &str) -> Option<&str> {
        match self.entries.get(path) {
            Some(Entry::Refused(message, _)) => Some(message),
            _ => None,
        }
    }

    /// The visible images that have a picture, as the renderer draws them.
    pub fn quads<'a>(&'a self, images: &[ReferenceImage], frame: &taut_render::DisplayFrame) -> Vec<ReferenceQuad<'a>> {
        images
            .iter()
            .filter(|i| i.visible && i.opacity > 0.0)
            .filter_map(|i| self.picture(&i.path).map(|p| ReferenceQuad::new(i, p, frame)))
            .collect()
    }
}

/// A copy of `picture` in `folder` for a document there: the file itself when an identical one
/// is already there under its name, else a new name (`name-2.png`, …); never replaces a file.
pub fn copy_next_to_document(picture: &Path, folder: &Path) -> Result<PathBuf, String> {
    let bytes = taut_core::io::file::read_regular_file(picture).map_err(|e| e.to_string())?;
    let name = picture.file_name().ok_or_else(|| format!("{} names no file", picture.display()))?;
    let stem = picture.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = picture.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
    for n in 1..1000 {
        let target = if n == 1 { folder.join(name) } else { folder.join(format!("{stem}-{n}.{ext}")) };
        match std::fs::read(&target) {
            Ok(existing) if existing == bytes => return Ok(target),
            Ok(_) => continue,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                taut_core::io::write_atomic(&target, &bytes).map_err(|e| e.to_string())?;
                return Ok(target);
            }
            Err(e) => return Err(format!("{}: {e}", target.display())),
        }
    }
    Err(format!("no free name for a copy of {} in {}", picture.display(), folder.display()))
}

impl EditorState {
    /// The folder the document's reference images are relative to (none while it is unsaved).
    pub fn document_folder(&self) -> Option<PathBuf> {
        let path = self.document.path()?;
        let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        Some(folder.to_path_buf())
    }

    /// Reads the pictures the document names that are new or changed, and tells what cannot be read.
    pub fn refresh_reference_images(&mut self) {
        let folder = self.document_folder();
        let told = self.references.refresh(&self.document.doc().reference_images, folder.as_deref());
        for message in told {
            self.notify(message, true);
        }
    }

    /// A picture chosen with Add…: kept by its path relative to the document when it is in the
    /// document's folder; else the designer is asked whether to copy it there.
    pub(crate) fn reference_picked(&mut self, picture: PathBuf, ui_state: &mut UiState) {
        let Some(folder) = self.document_folder() else {
            self.notify("save the document first: a reference image is kept beside it", true);
            return;
        };
        if !picture.is_file() {
            self.notify(format!("{} is not a file", picture.display()), true);
            return;
        }
        match relative_to_folder(&picture, &folder) {
            Some(relative) => self.add_reference_image(relative),
            None => ui_state.reference_copy = Some(picture),
        }
    }

    /// Adds an image at `relative` (in the document's folder), placed where a designer expects:
    /// centred on the model, a little larger than it, on the plane the camera looks most along.
    pub(crate) fn add_reference_image(&mut self, relative: String) {
        let cage = &self.document.doc().cage;
        let (centre, size) = match taut_core::mesh::bounding_box(cage.positions()) {
            Some((lo, hi)) => (lo * 0.5 + hi * 0.5, (hi - lo).max_element()),
            None => (DVec3::ZERO, 1.0),
        };
        let back = self.view.camera.backward().abs();
        let plane = if back.z >= back.x.max(back.y) {
            ReferencePlane::Top
        } else if back.x >= back.y {
            ReferencePlane::Side
        } else {
            ReferencePlane::Front
        };
        let width = if size.is_finite() && size > 0.0 { size * 1.5 } else { 1.0 };
        let image = ReferenceImage { centre, ..ReferenceImage::new(relative, plane, width) };
        self.emit(Edit::AddReferenceImage(image));
    }

    /// The Reference images panel.
    pub(crate) fn reference_images_panel(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.heading("Reference images");
        let saved = self.document.path().is_some();
        let add = ui
            .add_enabled(saved, egui::Button::new("Add reference image…"))
            .on_hover_text("A PNG or JPEG to model over, kept next to the document")
            .on_disabled_hover_text("Save the document first: a reference image is kept beside it");
        if add.clicked() {
            self.ask_path(PathPurpose::ReferenceImage, ui_state);
        }
        let images = self.document.doc().reference_images.clone();
        for (index, image) in images.iter().enumerate() {
            egui::CollapsingHeader::new(&image.path).id_salt(("reference image", index)).default_open(true).show(
                ui,
                |ui| {
                    if let Some(problem) = self.references.problem(&image.path) {
                        ui.colored_label(egui::Color32::LIGHT_RED, problem);
                    }
                    self.reference_image_controls(ui, ui_state, index, image);
                },
            );
        }
    }

    fn reference_image_controls(
        &mut self,
        ui: &mut egui::Ui,
        ui_state: &mut UiState,
        index: usize,
        image: &ReferenceImage,
    ) {
        let mut edited = image.clone();
        ui.horizontal(|ui| {
            ui.checkbox(&mut edited.visible, "visible").on_hover_text("Show the picture (it stays in the document)");
            ui.checkbox(&mut edited.in_front, "in front").on_hover_text(
                "Over the model, translucent at its opacity; off, the picture is behind the model everywhere",
            );
        });
        egui::ComboBox::from_id_salt(("reference plane", index))
            .selected_text(edited.plane.display_name())
            .show_ui(ui, |ui| {
                for plane in ReferencePlane::ALL {
                    ui.selectable_value(&mut edited.plane, plane, plane.display_name());
                }
            })
            .response
            .on_hover_text("The plane the picture lies in, or facing the camera from wherever it looks");
        let mut responses = Vec::new();
        ui.horizontal(|ui| {
            ui.label("centre");
            for (value, axis) in
                [(&mut edited.centre.x, "x "), (&mut edited.centre.y, "y "), (&mut edited.centre.z, "z ")]
            {
                responses.push(
                    ui.add(egui::DragValue::new(value).speed(0.01).prefix(axis))
                        .on_hover_text("Where the picture's centre is, in model units"),
                );
            }
        });
        responses.push(
            ui.add(egui::DragValue::new(&mut edited.width).range(1e-9..=f64::MAX).speed(0.01).prefix("width "))
                .on_hover_text("The picture's width in model units; its height follows from its shape"),
        );
        responses.push(
            ui.add(egui::Slider::new(&mut edited.rotation, -180.0..=180.0).text("rotation °"))
                .on_hover_text("Turns the picture in its plane, counter-clockwise"),
        );
        responses.push(
            ui.add(egui::Slider::new(&mut edited.opacity, 0.0..=1.0).text("opacity"))
                .on_hover_text("0 invisible, 1 opaque"),
        );
        for response in &responses {
            self.gesture_start(response, ui_state);
        }
        if edited != *image {
            self.emit(Edit::SetReferenceImage(index, edited));
        }
        for response in &responses {
            self.gesture_end(response, ui_state);
        }
        if ui.button("Remove").on_hover_text("Takes the picture out of the document (the file stays)").clicked() {
            self.emit(Edit::RemoveReferenceImage(index));
        }
    }

    /// "Copy it next to the document?" for a picture chosen outside the document's folder.
    pub(crate) fn reference_copy_dialog(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        let Some(picture) = ui_state.reference_copy.take() else { return };
        let Some(folder) = self.document_folder() else { return };
        let mut answer = None;
        egui::Modal::new(egui::Id::unique("reference copy")).show(ctx, |ui| {
            ui.label(format!(
                "{} is outside the document's folder. Taut reads reference images only from beside the \
                 document, so the document can be moved or sent with its pictures. Copy it into {}?",
                picture.display(),
                folder.display()
            ));
            ui.horizontal(|ui| {
                if ui.button("Copy next to the document").clicked() {
                    answer = Some(true);
                }
                if ui.button("Cancel").clicked() || ui.input(|i| i.key_pressed(egui::Key::Escape)) {
                    answer = Some(false);
                }
            });
        });
        match answer {
            None => ui_state.reference_copy = Some(picture),
            Some(false) => {}
            Some(true) => match copy_next_to_document(&picture, &folder) {
                Ok(copy) => match relative_to_folder(&copy, &folder) {
                    Some(relative) => self.add_reference_image(relative),
                    None => self.notify(format!("the copy {} is not in the document's folder", copy.display()), true),
                },
                Err(message) => self.notify(format!("could not copy the reference image: {message}"), true),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set_modified(path: &Path, seconds: u64) {
        let file = std::fs::OpenOptions::new().write(true).open(path).unwrap();
        file.set_modified(std::time::UNIX_EPOCH + std::time::Duration::from_secs(seconds)).unwrap();
    }

    /// A picture is read once per file version: a broken one is told once and not decoded again
    /// each frame, and read again when its file changes.
    #[test]
    fn pictures_are_read_again_only_when_their_file_changes() {
        let folder = crate::editor::document::tests::temp_dir("refimg-store");
        let path = folder.join("p.png");
        std::fs::write(&path, b"\x89PNG\r\n\x1a\n broken").unwrap();
        set_modified(&path, 1_000_000);
        let images = [ReferenceImage::new("p.png", ReferencePlane::Front, 1.0)];
        let mut store = ReferencePictures::default();
        let told = store.refresh(&images, Some(&folder));
        assert!(told.len() == 1 && told[0].contains("cannot decode it"), "{told:?}");
        // A good picture in place of the broken one, with the same time: not read again.
        image::RgbaImage::from_pixel(2, 2, image::Rgba([1, 2, 3, 255])).save(&path).unwrap();
        set_modified(&path, 1_000_000);
        assert!(store.refresh(&images, Some(&folder)).is_empty(), "told once");
        assert!(store.picture("p.png").is_none(), "the same file version was decoded again");
        set_modified(&path, 2_000_000);
        assert!(store.refresh(&images, Some(&folder)).is_empty());
        assert_eq!(store.picture("p.png").map(|p| p.pixels.dimensions()), Some((2, 2)), "a changed file is read");
        assert!(store.problem("p.png").is_none());
        // Unsaved (no folder): nothing is read, and the panel says why.
        assert!(store.refresh(&images, None).is_empty());
        assert!(store.picture("p.png").is_none() && store.problem("p.png").unwrap().contains("save the document"));
    }
}
