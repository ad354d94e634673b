//! The open document of the editor: the cage [`Document`], the file it lives in, undo and
//! redo, and whether it has unsaved changes.
//!
//! Every change a designer makes arrives as one [`Edit`] (the core's, shared with the command
//! line) through [`EditorDocument::apply`], which checks it completely before touching anything,
//! so a refused edit changes nothing.
//! Undo keeps whole snapshots of the document (cages are small), at most
//! [`MAX_UNDO_STEPS`] of them; a drag or a slider movement is bracketed by
//! [`EditorDocument::begin_gesture`] and [`EditorDocument::end_gesture`] and becomes a single
//! step, as egui's `Undoer` does.
//!
//! Two counters tell the rest of the editor what changed. [`EditorDocument::revision`] is
//! bumped by every change (and is unique across documents, so opening another file is a change
//! too): the solver restarts when it differs. Dirty state compares the current state with the
//! saved one by identity, so undoing back to the saved state makes the document clean again.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
pub use taut_core::Edit;
use taut_core::document::modelling::{DocumentStep, MeshEdit, Script, ScriptStep};
use taut_core::gregory::carry::CarryReport;
use taut_core::io::{self, ImportReport, UpAxis};
use taut_core::mesh::edit::Provenance;
use taut_core::{Document, PolyMesh};

/// Most undo steps kept; older ones are forgotten first.
pub const MAX_UNDO_STEPS: usize = 200;

/// Source of revisions, shared by all documents so that a newly opened document never repeats
/// the revision of the one it replaces.
static NEXT_REVISION: AtomicU64 = AtomicU64::new(1);

fn fresh_revision() -> u64 {
    NEXT_REVISION.fetch_add(1, Ordering::Relaxed)
}

/// A state the document can go back or forward to.
#[derive(Clone, Debug)]
struct Snapshot {
    doc: Document,
    state: u64,
    /// The step between this state and the current one, as undo or redo names it.
    name: &'static str,
    /// How many steps of the session's journal led to this state.
    journal_len: usize,
    /// The files the document belonged to, for a step that changed them ([`EditorDocument::adopt`]);
    /// `None` for every other step, which leaves the files as they are.
    files: Option<Files>,
}

/// Which files a document belongs to.
#[derive(Clone, Debug)]
struct Files {
    path: Option<PathBuf>,
    source: Option<PathBuf>,
    import_report: Option<ImportReport>,
}

/// An open gesture: the state before it began.
#[derive(Debug)]
struct Gesture {
    before: Snapshot,
    changed: bool,
}

/// One step of the session's journal: its scripted form, or the name of an edit a script cannot
/// say.
type JournalEntry = Result<ScriptStep, &'static str>;

/// The document open in the editor, with its file, undo history and dirty state.
#[derive(Debug)]
pub struct EditorDocument {
    doc: Document,
    /// Where Save writes: a `.taut` file, or none yet.
    path: Option<PathBuf>,
    /// The file the document was read from or last saved to (an imported mesh included).
    source: Option<PathBuf>,
    import_report: Option<ImportReport>,
    undo: VecDeque<Snapshot>,
    redo: Vec<Snapshot>,
    gesture: Option<Gesture>,
    /// Identity of the current content: a fresh number per change, restored by undo and redo.
    state: u64,
    next_state: u64,
    /// The state last saved or loaded; `None` when no saved state matches any (recovered work).
    saved_state: Option<u64>,
    revision: u64,
    /// Highest cage generation seen, so restored snapshots are bumped past it (see `restore`).
    generation_floor: u64,
    /// Every edit applied since the document was opened, in order (the first `journal_len` lead
    /// to the current state; the rest are undone steps redo can bring back).
    journal: Vec<JournalEntry>,
    journal_len: usize,
}

impl EditorDocument {
    /// A document held in the editor; `path` is the `.taut` file Save writes, if any. It starts
    /// clean, with an empty history.
    pub fn new(doc: Document, path: Option<PathBuf>) -> Self {
        let generation_floor = doc.cage.generation();
        EditorDocument {
            doc,
            source: path.clone(),
            path,
            import_report: None,
            undo: VecDeque::new(),
            redo: Vec::new(),
            gesture: None,
            state: 0,
            next_state: 1,
            saved_state: Some(0),
            revision: fresh_revision(),
            generation_floor,
            journal: Vec::new(),
            journal_len: 0,
        }
    }

    /// Opens a file: a `.taut` document, or a mesh (`.obj`, `.gltf`, `.glb`) imported as a cage
    /// with every vertex fixed. An imported mesh has no [`path`](Self::path) (Save asks for a
    /// `.taut` file); [`source`](Self::source) names it and [`import_report`](Self::import_report)
    /// says what the import repaired.
    pub fn open(path: &Path) -> Result<Self, String> {
        Self::open_with(path, UpAxis::default())
    }

    /// [`open`](Self::open), reading OBJ files with the given up axis. The file is read as the
    /// command line reads it (`Document::open`); an imported mesh is then shown at
    /// [`display_levels`] rather than the command line's default, so a large cage stays live.
    pub fn open_with(path: &Path, obj_up: UpAxis) -> Result<Self, String> {
        let (mut doc, report) = Document::open(path, &io::ImportOptions { obj_up }).map_err(|e| e.to_string())?;
        let Some(report) = report else {
            return Ok(Self::new(doc, Some(path.to_path_buf())));
        };
        doc.settings.levels = display_levels(doc.cage.face_count());
        let settings = doc.settings;
        let mut opened = Self::new(doc, None);
        // The session's script starts with that choice, so replayed on the mesh it gives this
        // document (a mesh opened by `taut edit` has the default levels).
        opened.journal.push(Ok(ScriptStep::Document(DocumentStep::SetSolverSettings { settings })));
        opened.journal_len = 1;
        opened.source = Some(path.to_path_buf());
        opened.import_report = Some(report);
        Ok(opened)
    }

    /// A document restored from an autosave: it has unsaved changes by definition.
    pub(crate) fn recovered(doc: Document, path: Option<PathBuf>, source: Option<PathBuf>) -> Self {
        let mut recovered = Self::new(doc, path);
        recovered.source = source.or_else(|| recovered.path.clone());
        recovered.saved_state = None;
        recovered
    }

    /// The document as it is now.
    pub fn doc(&self) -> &Document {
        &self.doc
    }

    /// Sets what the Curves workspace shows, saved with the file: no change of the design, so
    /// neither an undo step nor unsaved work.
    pub fn set_curves_view(&mut self, view: taut_core::curve::CurvesView) {
        self.doc.curves.view = view;
    }

    /// The `.taut` file Save writes; `None` for a new document or an imported mesh.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The file the document was read from or last saved to, an imported mesh included.
    pub fn source(&self) -> Option<&Path> {
        self.source.as_deref()
    }

    /// What importing a mesh file merged, repaired or skipped; `None` unless imported.
    pub fn import_report(&self) -> Option<&ImportReport> {
        self.import_report.as_ref()
    }

    /// The window title: the file name (or "untitled"), with `*` when there are unsaved changes.
    pub fn title(&self) -> String {
        let name = self
            .path
            .as_deref()
            .or(self.source.as_deref())
            .and_then(|p| p.file_name())
            .map_or_else(|| "untitled".to_string(), |n| n.to_string_lossy().into_owned());
        if self.is_dirty() { format!("{name}*") } else { name }
    }

    /// Changes with every edit, undo, redo and opened document; never repeats.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Identity of the current content: a fresh number per change, the same again after undo or
    /// redo returns to it (it counts from zero in each document).
    pub fn state(&self) -> u64 {
        self.state
    }

    /// The states undo and redo can reach, and the current one.
    pub fn history_states(&self) -> Vec<u64> {
        let mut states: Vec<u64> = self.undo.iter().chain(&self.redo).map(|s| s.state).collect();
        states.extend(self.gesture.as_ref().map(|g| g.before.state));
        states.push(self.state);
        states
    }

    /// True when the document differs from the state last saved or loaded.
    pub fn is_dirty(&self) -> bool {
        self.saved_state != Some(self.state)
    }

    /// Checks and applies one edit. A refused edit leaves the document and its history as they
    /// were and says why; an edit that changes nothing records nothing.
    pub fn apply(&mut self, edit: Edit) -> Result<(), String> {
        let (name, step) = (edit.name(), ScriptStep::of(&edit).ok_or(edit.name()));
        // The one validator of the core: ranges, indices, and a NUSD surface kept anchored.
        let after = match edit {
            // A new cage is checked as it is: no copy of the current document to overwrite.
            Edit::Replace(new) => match self.doc.checked_replacement(new).map_err(|e| e.to_string())? {
                Some(after) => after,
                None => return Ok(()),
            },
            edit => {
                let mut after = self.doc.clone();
                if !after.apply(edit).map_err(|e| e.to_string())? {
                    return Ok(());
                }
                after
            }
        };
        self.record(after, name, step);
        Ok(())
    }

    /// Performs a modelling operation ([`MeshEdit`]) as one named step (checked as any new cage
    /// is); returns where the new cage's elements came from and what became of the curve-mesh
    /// edits, or `None` when the operation changed nothing.
    pub fn apply_mesh(&mut self, op: MeshEdit) -> Result<Option<(Option<Provenance>, CarryReport)>, String> {
        let done = op.run(&self.doc).map_err(|e| e.to_string())?;
        let Some(after) = self.doc.checked_replacement(Box::new(done.doc)).map_err(|e| e.to_string())? else {
            return Ok(None);
        };
        let name = op.name();
        self.record(after, name, Ok(ScriptStep::Mesh(op)));
        Ok(Some((done.provenance, done.carried)))
    }

    /// Makes a checked document current: one undo step named `name` (or part of the open
    /// gesture), and one step of the journal.
    fn record(&mut self, after: Document, name: &'static str, step: JournalEntry) {
        self.journal.truncate(self.journal_len);
        let journal_len = self.journal_len;
        self.journal.push(step);
        self.journal_len += 1;
        // The document before the edit is the undo snapshot (no second copy of it).
        let before = std::mem::replace(&mut self.doc, after);
        match &mut self.gesture {
            Some(gesture) => {
                if !gesture.changed {
                    gesture.changed = true;
                    gesture.before.name = name;
                    self.redo.clear();
                }
            }
            None => {
                let before = Snapshot { doc: before, state: self.state, name, journal_len, files: None };
                self.push_undo(before);
                self.redo.clear();
            }
        }
        self.state = self.take_state();
        self.touch();
    }

    /// What Undo would undo ("Extrude"), if anything.
    pub fn undo_name(&self) -> Option<&'static str> {
        match &self.gesture {
            Some(gesture) if gesture.changed => Some(gesture.before.name),
            _ => self.undo.back().map(|s| s.name),
        }
    }

    /// What Redo would redo, if anything.
    pub fn redo_name(&self) -> Option<&'static str> {
        self.redo.last().map(|s| s.name)
    }

    /// The edits that led from the document as opened to the current one, as a script
    /// (`taut edit --script` replays it on the opened file); an error naming the first edit a
    /// script cannot say (a new cage from a fit, a curve edit, a curve-mesh edit).
    pub fn script(&self) -> Result<Script, String> {
        let edits = self.journal[..self.journal_len]
            .iter()
            .map(|entry| {
                entry.clone().map_err(|name| {
                    format!("this session holds \"{name}\", which an edit script cannot say; save the document instead")
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        Ok(Script { taut_edit_script: 1, edits })
    }

    /// Starts a gesture (a drag, one slider movement): the edits applied until
    /// [`end_gesture`](Self::end_gesture) become one undo step. Starting a gesture while one is
    /// open continues the open one.
    pub fn begin_gesture(&mut self) {
        if self.gesture.is_none() {
            let (name, journal_len) = ("Edit", self.journal_len);
            let before = Snapshot { doc: self.doc.clone(), state: self.state, name, journal_len, files: None };
            self.gesture = Some(Gesture { before, changed: false });
        }
    }

    /// Ends the open gesture, recording one undo step if it changed the document. A gesture
    /// that ends where it began (dragged and put back) records nothing and keeps the document's
    /// saved state. Does nothing when no gesture is open.
    pub fn end_gesture(&mut self) {
        let Some(gesture) = self.gesture.take() else { return };
        if !gesture.changed {
            return;
        }
        if self.doc == gesture.before.doc {
            // Nothing happened, in the journal either (a cancelled tool puts the document back).
            self.state = gesture.before.state;
            self.journal_len = gesture.before.journal_len;
            self.journal.truncate(self.journal_len);
        } else {
            self.push_undo(gesture.before);
        }
    }

    /// True while a gesture is open.
    pub fn in_gesture(&self) -> bool {
        self.gesture.is_some()
    }

    /// True when there is a step to undo (an open gesture that changed something counts).
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty() || self.gesture.as_ref().is_some_and(|g| g.changed)
    }

    /// True when there is an undone step to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Undoes the last step (ending an open gesture first); false when there is none.
    pub fn undo(&mut self) -> bool {
        self.end_gesture();
        let Some(previous) = self.undo.pop_back() else { return false };
        let current = self.restore(previous);
        self.redo.push(current);
        true
    }

    /// Redoes the last undone step; false when there is none.
    pub fn redo(&mut self) -> bool {
        self.end_gesture();
        let Some(next) = self.redo.pop() else { return false };
        let current = self.restore(next);
        self.push_undo(current);
        true
    }

    /// Saves to the document's `.taut` file; an error when it has none yet (use
    /// [`save_as`](Self::save_as)).
    pub fn save(&mut self) -> Result<(), String> {
        let path = self
            .path
            .clone()
            .ok_or_else(|| "this document has no .taut file yet: use Save As to choose where to save it".to_string())?;
        self.save_as(&path)
    }

    /// Saves to a `.taut` file (atomically: a failed save never damages the previous file),
    /// which then becomes the document's file; the document is clean afterwards.
    pub fn save_as(&mut self, path: &Path) -> Result<(), String> {
        if !is_taut(path) {
            return Err(format!(
                "{}: a cage with its fixed points and tensions is saved as a .taut file; \
                 use Export to write the smoothed surface as .obj or .glb",
                path.display()
            ));
        }
        self.doc.save(path).map_err(|e| e.to_string())?;
        self.path = Some(path.to_path_buf());
        self.source = Some(path.to_path_buf());
        self.import_report = None;
        self.saved_state = Some(self.state);
        Ok(())
    }

    /// Writes a smoothed surface as `.obj` or `.glb` (by extension, atomically).
    pub fn export_surface(
        &self,
        surface: &PolyMesh,
        normals: Option<&[taut_core::DVec3]>,
        path: &Path,
        obj_up: UpAxis,
    ) -> Result<(), String> {
        if is_taut(path) {
            return Err(format!(
                "{}: export writes the smoothed surface as .obj or .glb; use Save As for a .taut cage",
                path.display()
            ));
        }
        if let Some(source) = self.source.as_deref().filter(|s| io::file::same_file(s, path)) {
            return Err(format!(
                "{} is the file this cage was opened from: exporting the surface there would replace it; \
                 choose another name",
                source.display()
            ));
        }
        let options = io::ExportOptions { normals, obj_up };
        io::export_mesh_with(surface, path, &options).map_err(|e| e.to_string())
    }

    /// Makes `doc` the document as one undo step that also leaves the current file: Save then asks
    /// for a `.taut` file, and `source` names where the content came from (a cage fitted to a
    /// mesh). Undo goes back to the previous document and its file, with nothing lost; a gesture
    /// in progress is ended first.
    pub fn adopt(&mut self, doc: Document, source: Option<PathBuf>) -> Result<(), String> {
        doc.validate().map_err(|e| e.to_string())?;
        self.end_gesture();
        let files = self.swap_files(Files { path: None, source, import_report: None });
        let (name, journal_len) = ("Replace Document", self.journal_len);
        self.journal.truncate(self.journal_len);
        self.journal.push(Err(name));
        self.journal_len += 1;
        let doc = std::mem::replace(&mut self.doc, doc);
        let before = Snapshot { doc, state: self.state, name, journal_len, files: Some(files) };
        self.push_undo(before);
        self.redo.clear();
        self.state = self.take_state();
        self.touch();
        Ok(())
    }

    /// Puts `files` in place and returns the ones they replace.
    fn swap_files(&mut self, files: Files) -> Files {
        Files {
            path: std::mem::replace(&mut self.path, files.path),
            source: std::mem::replace(&mut self.source, files.source),
            import_report: std::mem::replace(&mut self.import_report, files.import_report),
        }
    }

    fn take_state(&mut self) -> u64 {
        let state = self.next_state;
        self.next_state += 1;
        state
    }

    /// Records a change: a new revision, and the cage generation noted.
    fn touch(&mut self) {
        self.revision = fresh_revision();
        self.generation_floor = self.generation_floor.max(self.doc.cage.generation());
    }

    fn push_undo(&mut self, snapshot: Snapshot) {
        if self.undo.len() == MAX_UNDO_STEPS {
            self.undo.pop_front();
        }
        self.undo.push_back(snapshot);
    }

    /// Makes a snapshot current and returns the state it replaced.
    fn restore(&mut self, snapshot: Snapshot) -> Snapshot {
        let files = snapshot.files.map(|files| self.swap_files(files));
        let doc = std::mem::replace(&mut self.doc, snapshot.doc);
        let (name, journal_len) = (snapshot.name, self.journal_len);
        let current = Snapshot { doc, state: self.state, name, journal_len, files };
        self.state = snapshot.state;
        self.journal_len = snapshot.journal_len;
        // A snapshot carries the cage generation it had when taken, which later edits have
        // already counted past; a cache keyed on the generation would take the restored cage for
        // one it saw since. Counting on from the highest generation seen keeps it unambiguous.
        while self.doc.cage.generation() <= self.generation_floor {
            self.doc.cage.positions_mut();
        }
        self.touch();
        current
    }
}

fn is_taut(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("taut"))
}

/// The NUSD levels an imported cage is shown at: 4, where zebra stripes on the default scene stop
/// looking faceted (at level 3 the facets show), or fewer for a larger cage so that the finest
/// level stays under 80,000 faces (the default scene at level 5 has 42,000) and a drag stays
/// live. Each level multiplies the faces by about four; a cage is shown at one level at least.
pub fn display_levels(cage_faces: usize) -> u32 {
    const FINEST_FACES: usize = 80_000;
    (1..=4u32).rev().find(|&l| cage_faces.max(1).saturating_mul(4usize.pow(l)) <= FINEST_FACES).unwrap_or(1)
}

#[cfg(test)]
#[path = "document_tests.rs"]
pub(crate) mod tests;
