//! What the editor keeps on disk besides the designer's own files: the recent-files list, and
//! an autosave for crash recovery.
//!
//! Both live in the user's folders (`dirs::config_dir()/taut/recent.json`,
//! `dirs::data_local_dir()/taut/autosave.taut`); their constructors also take a folder, so tests
//! run in a temporary one. Neither may ever stop the editor: an unreadable or garbled file reads
//! as "nothing there", and writes go through `write_atomic`, so a crash mid-write leaves the
//! previous file intact.
//!
//! The autosave is a plain `.taut` document; a small sidecar JSON beside it records which file
//! it belongs to and when it was written, with a hash of the autosave so a sidecar left from an
//! older autosave is never believed. One autosave slot is shared by every running editor.

use crate::editor::document::EditorDocument;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};
use taut_core::Document;
use taut_core::io::write_atomic;

/// Most recent files remembered.
pub const MAX_RECENT_FILES: usize = 10;

/// How long unsaved changes may wait before they are autosaved.
pub const AUTOSAVE_INTERVAL: Duration = Duration::from_secs(30);

const RECENT_FILE_NAME: &str = "recent.json";
const AUTOSAVE_FILE_NAME: &str = "autosave.taut";
const SIDECAR_FILE_NAME: &str = "autosave.json";

/// The user's folder for Taut's settings (`config_dir()/taut`), if the platform has one.
pub fn config_folder() -> Option<PathBuf> {
    dirs::config_dir().map(|d| d.join("taut"))
}

/// The user's folder for Taut's local data (`data_local_dir()/taut`), if the platform has one.
pub fn data_folder() -> Option<PathBuf> {
    dirs::data_local_dir().map(|d| d.join("taut"))
}

/// The files opened or saved lately, most recent first, without duplicates.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RecentFiles {
    /// Where the list is kept; `None` keeps it in memory only.
    file: Option<PathBuf>,
    paths: Vec<PathBuf>,
}

impl RecentFiles {
    /// The list kept in `folder/recent.json`; empty when that file is missing or unreadable.
    pub fn in_folder(folder: &Path) -> Self {
        let file = folder.join(RECENT_FILE_NAME);
        let paths = std::fs::read(&file)
            .ok()
            .and_then(|bytes| serde_json::from_slice::<Vec<PathBuf>>(&bytes).ok())
            .unwrap_or_default();
        let mut recent = RecentFiles { file: Some(file), paths: Vec::new() };
        // Add oldest first so the list comes out deduplicated and cut to length.
        for path in paths.iter().rev() {
            recent.remember(path);
        }
        recent
    }

    /// The user's list (in [`config_folder`]); kept in memory only when there is no such folder.
    pub fn load() -> Self {
        config_folder().map_or_else(Self::default, |folder| Self::in_folder(&folder))
    }

    /// The files, most recent first.
    pub fn paths(&self) -> &[PathBuf] {
        &self.paths
    }

    /// Puts a file first (moving it up if already listed), forgets the oldest beyond
    /// [`MAX_RECENT_FILES`], and writes the list. The list changes even when writing fails.
    pub fn add(&mut self, path: &Path) -> Result<(), String> {
        self.remember(path);
        self.save()
    }

    /// Forgets a file (one that could not be opened any more) and writes the list.
    pub fn remove(&mut self, path: &Path) -> Result<(), String> {
        let path = absolute(path);
        self.paths.retain(|p| *p != path);
        self.save()
    }

    /// Forgets every file and writes the empty list.
    pub fn clear(&mut self) -> Result<(), String> {
        self.paths.clear();
        self.save()
    }

    fn remember(&mut self, path: &Path) {
        let path = absolute(path);
        self.paths.retain(|p| *p != path);
        self.paths.insert(0, path);
        self.paths.truncate(MAX_RECENT_FILES);
    }

    fn save(&self) -> Result<(), String> {
        let Some(file) = &self.file else { return Ok(()) };
        // JSON strings hold only Unicode; a path that is not is remembered for this session only.
        let paths: Vec<&str> = self.paths.iter().filter_map(|p| p.to_str()).collect();
        let json = serde_json::to_string_pretty(&paths).map_err(|e| e.to_string())?;
        write_creating_folder(file, json.as_bytes()).map_err(|e| format!("could not remember recent files: {e}"))
    }
}

/// The path made absolute (without touching the file system), so one file is listed once
/// whichever folder it was opened from.
fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

fn write_creating_folder(file: &Path, bytes: &[u8]) -> Result<(), String> {
    if let Some(folder) = file.parent().filter(|f| !f.as_os_str().is_empty()) {
        std::fs::create_dir_all(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
    }
    write_atomic(file, bytes).map_err(|e| e.to_string())
}

/// True when unsaved changes have waited [`AUTOSAVE_INTERVAL`] since the last autosave.
pub fn should_autosave(last: Instant, now: Instant, dirty: bool) -> bool {
    dirty && now.saturating_duration_since(last) >= AUTOSAVE_INTERVAL
}

/// An autosave found at startup: the editor did not exit cleanly with unsaved changes.
#[derive(Clone, Debug, PartialEq)]
pub struct Recovery {
    /// The autosaved `.taut` document.
    pub autosave: PathBuf,
    /// The `.taut` file the work belongs to; `None` for an untitled document or an imported
    /// mesh (or when the record beside the autosave is missing).
    pub original: Option<PathBuf>,
    /// The file the work was read from when that is not a `.taut` file (an imported mesh).
    pub source: Option<PathBuf>,
    /// When the autosave was written.
    pub saved_at: SystemTime,
}

/// The autosave slot: one `.taut` document and its sidecar record in a folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Autosave {
    /// The folder holding the autosave.
    pub dir: PathBuf,
}

/// The sidecar record beside the autosave.
#[derive(Serialize, Deserialize)]
struct AutosaveRecord {
    original: Option<PathBuf>,
    source: Option<PathBuf>,
    saved_at_unix_ms: u64,
    /// FNV-1a hash of the autosave's bytes, as hex: the record describes only that autosave.
    autosave_hash: String,
}

impl Autosave {
    /// The autosave slot in `dir`.
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Autosave { dir: dir.into() }
    }

    /// The user's autosave slot (in [`data_folder`]), if the platform has such a folder.
    pub fn in_data_folder() -> Option<Self> {
        data_folder().map(Self::new)
    }

    /// The autosaved document's path.
    pub fn autosave_path(&self) -> PathBuf {
        self.dir.join(AUTOSAVE_FILE_NAME)
    }

    fn sidecar_path(&self) -> PathBuf {
        self.dir.join(SIDECAR_FILE_NAME)
    }

    /// Writes the document to the autosave slot, atomically, with a record of its file.
    pub fn write(&self, doc: &EditorDocument) -> Result<(), String> {
        let bytes = doc.doc().to_json().into_bytes();
        let autosave = self.autosave_path();
        write_creating_folder(&autosave, &bytes).map_err(|e| format!("autosave failed: {e}"))?;
        let unicode = |p: Option<&Path>| p.filter(|p| p.to_str().is_some()).map(Path::to_path_buf);
        let original = unicode(doc.path());
        let source = unicode(doc.source()).filter(|s| Some(s) != original.as_ref());
        let saved_at_unix_ms = SystemTime::now()
            .duration_since(SystemTime::UNIX_EPOCH)
            .map_or(0, |d| d.as_millis().try_into().unwrap_or(u64::MAX));
        let record = AutosaveRecord { original, source, saved_at_unix_ms, autosave_hash: hash_hex(&bytes) };
        let json = serde_json::to_string_pretty(&record).map_err(|e| e.to_string())?;
        write_atomic(&self.sidecar_path(), json.as_bytes()).map_err(|e| format!("autosave failed: {e}"))
    }

    /// The autosave left by an editor that did not exit cleanly, if there is one.
    pub fn pending(&self) -> Option<Recovery> {
        let autosave = self.autosave_path();
        let bytes = std::fs::read(&autosave).ok()?;
        let record = std::fs::read(self.sidecar_path())
            .ok()
            .and_then(|json| serde_json::from_slice::<AutosaveRecord>(&json).ok())
            .filter(|r| r.autosave_hash == hash_hex(&bytes));
        let saved_at = match &record {
            Some(r) => SystemTime::UNIX_EPOCH + Duration::from_millis(r.saved_at_unix_ms),
            None => std::fs::metadata(&autosave).and_then(|m| m.modified()).unwrap_or(SystemTime::UNIX_EPOCH),
        };
        let (original, source) = record.map_or((None, None), |r| (r.original, r.source));
        Some(Recovery { autosave, original, source, saved_at })
    }

    /// Reads the autosave back as a document with unsaved changes, belonging to its original
    /// file. The autosave stays until [`clear`](Self::clear).
    pub fn recover(&self) -> Result<EditorDocument, String> {
        let pending = self.pending().ok_or_else(|| "there is no autosave to recover".to_string())?;
        let doc = Document::load(&pending.autosave).map_err(|e| format!("the autosave cannot be read: {e}"))?;
        Ok(EditorDocument::recovered(doc, pending.original, pending.source))
    }

    /// Removes the autosave: on a clean exit, after a successful save, or when the designer
    /// declines recovery. Removing what is not there is not an error.
    pub fn clear(&self) -> Result<(), String> {
        for path in [self.autosave_path(), self.sidecar_path()] {
            match std::fs::remove_file(&path) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => return Err(format!("{}: {e}", path.display())),
            }
        }
        Ok(())
    }
}

/// FNV-1a, 64 bits: enough to tell one autosave from another, not a security measure.
fn hash_hex(bytes: &[u8]) -> String {
    let hash =
        bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3));
    format!("{hash:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::document::Edit;
    use crate::editor::document::tests::{cube_doc, temp_dir};
    use taut_core::{DVec3, VertexId};

    #[test]
    fn recent_files_are_ordered_deduplicated_and_limited() {
        let dir = temp_dir("recent");
        let mut recent = RecentFiles::in_folder(&dir);
        assert!(recent.paths().is_empty());
        let file = |i: usize| dir.join(format!("cage{i}.taut"));
        recent.add(&file(1)).unwrap();
        recent.add(&file(2)).unwrap();
        recent.add(&file(1)).unwrap();
        assert_eq!(recent.paths(), [file(1), file(2)]);
        for i in 3..=14 {
            recent.add(&file(i)).unwrap();
        }
        let expected: Vec<PathBuf> = (5..=14).rev().map(file).collect();
        assert_eq!(recent.paths(), expected);
        assert_eq!(RecentFiles::in_folder(&dir).paths(), expected, "the list persists");
        recent.remove(&file(10)).unwrap();
        assert!(!RecentFiles::in_folder(&dir).paths().contains(&file(10)));
        recent.clear().unwrap();
        assert!(RecentFiles::in_folder(&dir).paths().is_empty());
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn relative_paths_are_made_absolute() {
        let dir = temp_dir("recent-relative");
        let mut recent = RecentFiles::in_folder(&dir);
        recent.add(Path::new("some.taut")).unwrap();
        let absolute = std::env::current_dir().unwrap().join("some.taut");
        recent.add(&absolute).unwrap();
        assert_eq!(recent.paths(), [absolute]);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn a_garbled_recent_list_reads_as_empty() {
        let dir = temp_dir("recent-garbage");
        for garbage in [&b"\xff\xfe not json"[..], b"{\"a\": 1}", b"[1, 2, 3]", b""] {
            std::fs::write(dir.join(RECENT_FILE_NAME), garbage).unwrap();
            let mut recent = RecentFiles::in_folder(&dir);
            assert!(recent.paths().is_empty());
            recent.add(Path::new("/tmp/x.taut")).unwrap();
            assert_eq!(RecentFiles::in_folder(&dir).paths(), [PathBuf::from("/tmp/x.taut")]);
        }
        // A missing folder reads as empty and is created on the first write.
        let nested = dir.join("not").join("yet");
        let mut recent = RecentFiles::in_folder(&nested);
        recent.add(Path::new("/tmp/y.taut")).unwrap();
        assert_eq!(RecentFiles::in_folder(&nested).paths().len(), 1);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn autosave_write_pending_recover_clear() {
        let dir = temp_dir("autosave");
        let autosave = Autosave::new(dir.join("slot"));
        assert!(autosave.pending().is_none());
        assert!(autosave.recover().is_err());

        let original = dir.join("work.taut");
        let mut ed = EditorDocument::new(cube_doc(), None);
        ed.save_as(&original).unwrap();
        ed.apply(Edit::MoveVertices(vec![(VertexId(7), DVec3::splat(1.25))])).unwrap();
        let started = SystemTime::now() - Duration::from_secs(1);
        autosave.write(&ed).unwrap();
        let pending = autosave.pending().unwrap();
        assert_eq!(pending.autosave, autosave.autosave_path());
        assert_eq!(pending.original.as_deref(), Some(original.as_path()));
        assert_eq!(pending.source, None);
        assert!(pending.saved_at >= started && pending.saved_at <= SystemTime::now() + Duration::from_secs(1));

        let recovered = autosave.recover().unwrap();
        assert_eq!(recovered.doc(), ed.doc());
        assert_eq!(recovered.path(), Some(original.as_path()));
        assert!(recovered.is_dirty() && !recovered.can_undo());
        assert_eq!(recovered.title(), "work.taut*");
        assert!(autosave.pending().is_some(), "recovering keeps the autosave until it is cleared");

        autosave.clear().unwrap();
        assert!(autosave.pending().is_none());
        autosave.clear().unwrap();
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn an_untitled_autosave_recovers_untitled() {
        let dir = temp_dir("autosave-untitled");
        let autosave = Autosave::new(&dir);
        let ed = EditorDocument::new(cube_doc(), None);
        autosave.write(&ed).unwrap();
        let pending = autosave.pending().unwrap();
        assert_eq!((pending.original, pending.source), (None, None));
        let recovered = autosave.recover().unwrap();
        assert!(recovered.path().is_none() && recovered.is_dirty());
        assert_eq!(recovered.title(), "untitled*");
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn a_stale_or_broken_sidecar_is_not_believed() {
        let dir = temp_dir("autosave-stale");
        let autosave = Autosave::new(&dir);
        let ed = EditorDocument::new(cube_doc(), Some(dir.join("a.taut")));
        autosave.write(&ed).unwrap();
        // A newer autosave written without its record (a crash in between).
        let mut other = cube_doc();
        other.fixed[0] = false;
        other.save(&autosave.autosave_path()).unwrap();
        let pending = autosave.pending().unwrap();
        assert_eq!(pending.original, None, "the record belongs to an older autosave");
        assert_eq!(autosave.recover().unwrap().doc(), &other);
        std::fs::write(dir.join(SIDECAR_FILE_NAME), b"garbage").unwrap();
        assert_eq!(autosave.pending().unwrap().original, None);
        // A garbled autosave is reported, never a panic.
        std::fs::write(autosave.autosave_path(), b"{ not a cage").unwrap();
        assert!(autosave.pending().is_some());
        assert!(autosave.recover().unwrap_err().contains("autosave"));
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn autosave_waits_for_the_interval_and_for_changes() {
        let last = Instant::now();
        let later = last + AUTOSAVE_INTERVAL;
        assert!(should_autosave(last, later, true));
        assert!(!should_autosave(last, later, false));
        assert!(!should_autosave(last, last + Duration::from_secs(29), true));
        assert!(!should_autosave(later, last, true), "a clock going backwards waits");
    }
}
