//! The in-app file browser under the path field, for when the desktop offers no system dialog
//! (Xvfb, a bare window manager): the folder of the path typed so far, its sub-folders and the
//! files of the formats the purpose takes (others are not listed; hidden ones neither), a
//! parent button, and the folders of recent files. A click on a folder goes into it, a click on
//! a file puts its path in the field, a double click chooses it. The field stays the truth: what
//! is typed there is what is opened or written, so a name can still be typed for a new file.
//! Save As asks before replacing a file whatever chose the path (`ui::save_as_asking`).

use std::path::{Path, PathBuf};

/// Most entries listed from one folder (a huge folder is cut, and says so).
const MAX_ENTRIES: usize = 400;

/// What is listed of a folder: sub-folders and matching files, sorted by name, and whether the
/// listing was cut.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Listing {
    pub folders: Vec<String>,
    pub files: Vec<String>,
    pub cut: bool,
}

/// The folder a path typed so far points into: itself when it is a folder (or ends in a
/// separator), else its parent; the working folder for an empty field.
pub fn folder_of(text: &str) -> PathBuf {
    let path = Path::new(text.trim());
    if text.trim().is_empty() {
        return std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
    }
    if text.ends_with(std::path::MAIN_SEPARATOR) || path.is_dir() {
        return path.to_path_buf();
    }
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::env::current_dir().unwrap_or_else(|_| PathBuf::from(".")),
    }
}

/// The sub-folders and the files with one of `extensions` (lower case, without the dot) in
/// `folder`; hidden entries are left out. An unreadable folder lists nothing.
pub fn list(folder: &Path, extensions: &[&str]) -> Listing {
    let Ok(entries) = std::fs::read_dir(folder) else { return Listing::default() };
    let mut listing = Listing::default();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        if listing.folders.len() + listing.files.len() >= MAX_ENTRIES {
            listing.cut = true;
            break;
        }
        let path = entry.path();
        if path.is_dir() {
            listing.folders.push(name);
        } else {
            let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
            if extensions.contains(&ext.as_str()) {
                listing.files.push(name);
            }
        }
    }
    listing.folders.sort();
    listing.files.sort();
    listing
}

/// The path of `name` in `folder`, as the field shows it.
fn joined(folder: &Path, name: &str) -> String {
    folder.join(name).display().to_string()
}

/// Draws the browser for the field's `text`; a click changes `text`; a double-clicked file is
/// returned (chosen). `recent` are recent files: their folders are offered.
pub fn browse(ui: &mut egui::Ui, text: &mut String, extensions: &[&str], recent: &[PathBuf]) -> Option<PathBuf> {
    let folder = folder_of(text);
    let mut chosen = None;
    ui.horizontal(|ui| {
        let parent = folder.parent().map(Path::to_path_buf);
        if ui.add_enabled(parent.is_some(), egui::Button::new("Parent folder")).clicked()
            && let Some(parent) = parent
        {
            *text = format!("{}{}", parent.display(), std::path::MAIN_SEPARATOR);
        }
        ui.label(format!("in {}", folder.display()));
    });
    let mut folders: Vec<PathBuf> = Vec::new();
    for p in recent.iter().filter_map(|p| p.parent()) {
        if !folders.iter().any(|f| f == p) {
            folders.push(p.to_path_buf());
        }
    }
    if !folders.is_empty() {
        ui.horizontal_wrapped(|ui| {
            ui.label("recent folders:");
            for f in folders.iter().take(6) {
                let name = f.file_name().map_or_else(|| f.display().to_string(), |n| n.to_string_lossy().into_owned());
                if ui.button(name).on_hover_text(f.display().to_string()).clicked() {
                    *text = format!("{}{}", f.display(), std::path::MAIN_SEPARATOR);
                }
            }
        });
    }
    let listing = list(&folder, extensions);
    // A fixed height, so the dialog does not jump about as folders of other sizes are listed.
    egui::ScrollArea::vertical().min_scrolled_height(220.0).max_height(220.0).auto_shrink([false, false]).show(
        ui,
        |ui| {
            for name in &listing.folders {
                if ui.selectable_label(false, format!("{name}/")).clicked() {
                    *text = format!("{}{}", joined(&folder, name), std::path::MAIN_SEPARATOR);
                }
            }
            for name in &listing.files {
                let path = joined(&folder, name);
                let response = ui.selectable_label(*text == path, name.as_str());
                if response.double_clicked() {
                    chosen = Some(PathBuf::from(&path));
                } else if response.clicked() {
                    *text = path;
                }
            }
            if listing.folders.is_empty() && listing.files.is_empty() {
                ui.weak(format!("no folders and no .{} files here", extensions.join(", .")));
            }
            if listing.cut {
                ui.weak(format!("only the first {MAX_ENTRIES} entries are listed: type the name"));
            }
        },
    );
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_lists_its_folders_and_the_files_of_the_purpose_sorted_without_hidden_ones() {
        let dir = crate::editor::document::tests::temp_dir("browser-list");
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::create_dir_all(dir.join(".hidden")).unwrap();
        for name in ["b.obj", "a.TAUT", "notes.txt", ".secret.taut"] {
            std::fs::write(dir.join(name), "x").unwrap();
        }
        let listing = list(&dir, &["taut", "obj"]);
        assert_eq!(listing.folders, vec!["sub".to_string()]);
        assert_eq!(listing.files, vec!["a.TAUT".to_string(), "b.obj".to_string()]);
        assert!(!listing.cut);
        assert_eq!(folder_of(&format!("{}/a.TAUT", dir.display())), dir);
        assert_eq!(folder_of(&dir.join("sub").display().to_string()), dir.join("sub"), "a folder is itself");
        assert_eq!(folder_of(&format!("{}/new-name.taut", dir.display())), dir, "a new name: its folder");
        assert_eq!(list(&dir.join("missing"), &["taut"]), Listing::default(), "unreadable: nothing");
        let _ = std::fs::remove_dir_all(dir);
    }
}

#[cfg(test)]
mod editor_tests {
    use crate::editor::panel_tests::{cube_editor, frames};
    use crate::editor::ui::PathPurpose;
    use egui_kittest::kittest::Queryable;

    fn field(h: &egui_kittest::Harness<'static, crate::editor::panel_tests::App>) -> String {
        h.state().ui.path_dialog.as_ref().expect("the path dialog is open").1.clone()
    }

    #[test]
    fn the_browser_lists_navigates_opens_and_save_as_onto_a_listed_file_asks_first() {
        let dir = crate::editor::document::tests::temp_dir("browser-ui");
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let mut h = cube_editor();
        h.state_mut().editor.save_as(&dir.join("a.taut"));
        h.state_mut().editor.save_as(&dir.join("sub").join("b.taut"));
        // The document's own name (its title on screen) elsewhere, so only the listing shows these.
        let elsewhere = crate::editor::document::tests::temp_dir("browser-ui-doc");
        h.state_mut().editor.save_as(&elsewhere.join("current.taut"));
        std::fs::write(dir.join("notes.txt"), "x").unwrap();
        let sep = std::path::MAIN_SEPARATOR;
        h.state_mut().ui.path_dialog = Some((PathPurpose::Open, format!("{}{sep}", dir.display())));
        frames(&mut h);
        h.get_by_label("a.taut");
        assert!(h.query_by_label("notes.txt").is_none(), "only the formats Open reads are listed");
        // Into the sub-folder, and back up.
        h.get_by_label("sub/").click_accesskit();
        frames(&mut h);
        assert_eq!(field(&h), format!("{}{sep}", dir.join("sub").display()));
        frames(&mut h);
        h.get_by_label("b.taut");
        h.get_by_label("Parent folder").click_accesskit();
        frames(&mut h);
        assert_eq!(field(&h), format!("{}{sep}", dir.display()));
        frames(&mut h);
        // A click puts the file in the field; OK opens it.
        h.get_by_label("a.taut").click_accesskit();
        frames(&mut h);
        assert_eq!(field(&h), dir.join("a.taut").display().to_string());
        h.get_by_label("OK").click_accesskit();
        frames(&mut h);
        frames(&mut h);
        assert_eq!(h.state().editor.document.path(), Some(dir.join("a.taut").as_path()), "opened");
        // Save As onto a listed file asks before replacing it (the document named elsewhere
        // again, so that its title is not one more "a.taut").
        h.state_mut().editor.save_as(&elsewhere.join("current.taut"));
        h.state_mut().ui.path_dialog = Some((PathPurpose::SaveAs, format!("{}{sep}", dir.display())));
        frames(&mut h);
        h.get_by_label("a.taut").click_accesskit();
        frames(&mut h);
        h.get_by_label("OK").click_accesskit();
        frames(&mut h);
        assert_eq!(h.state().ui.replace.as_deref(), Some(dir.join("a.taut").as_path()), "Replace it? is asked");
        let _ = std::fs::remove_dir_all(dir);
        let _ = std::fs::remove_dir_all(elsewhere);
    }
}
