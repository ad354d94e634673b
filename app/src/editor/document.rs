//! The open document of the editor: the cage [`Document`], the file it lives in, undo and
//! redo, and whether it has unsaved changes.
//!
//! Every change a designer makes arrives as one [`Edit`] through [`EditorDocument::apply`],
//! which checks it completely before touching anything, so a refused edit changes nothing.
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
use taut_core::io::{self, ImportReport};
use taut_core::nusd::SolverSettings;
use taut_core::{DVec3, Document, EdgeId, PolyMesh, VertexId};

/// Most undo steps kept; older ones are forgotten first.
pub const MAX_UNDO_STEPS: usize = 200;

/// Source of revisions, shared by all documents so that a newly opened document never repeats
/// the revision of the one it replaces.
static NEXT_REVISION: AtomicU64 = AtomicU64::new(1);

fn fresh_revision() -> u64 {
    NEXT_REVISION.fetch_add(1, Ordering::Relaxed)
}

/// One change to the document, as the UI sends it.
#[derive(Clone, Debug)]
pub enum Edit {
    /// Moves cage vertices to absolute positions.
    MoveVertices(Vec<(VertexId, DVec3)>),
    /// Marks vertices fixed (the surface passes through them) or moving.
    SetFixed(Vec<VertexId>, bool),
    /// Sets the tension τ of vertices.
    SetVertexTension(Vec<VertexId>, f64),
    /// Sets the tension τ of cage edges.
    SetEdgeTension(Vec<EdgeId>, f64),
    /// Sets the tension of the given vertices and edges back to 0.
    ResetTension {
        /// Vertices whose tension becomes 0.
        vertices: Vec<VertexId>,
        /// Edges whose tension becomes 0.
        edges: Vec<EdgeId>,
    },
    /// Replaces the solver settings.
    SetSettings(SolverSettings),
    /// Replaces the whole document (a new cage); the file path stays. Boxed: a document is
    /// far larger than the other edits.
    // The editor opens new documents as new `EditorDocument`s; kept for scripted edits.
    #[cfg_attr(not(test), allow(dead_code))]
    Replace(Box<Document>),
}

/// A state the document can go back or forward to.
#[derive(Clone, Debug)]
struct Snapshot {
    doc: Document,
    state: u64,
}

/// An open gesture: the state before it began.
#[derive(Debug)]
struct Gesture {
    before: Snapshot,
    changed: bool,
}

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
        }
    }

    /// Opens a file: a `.taut` document, or a mesh (`.obj`, `.gltf`, `.glb`) imported as a cage
    /// with every vertex fixed. An imported mesh has no [`path`](Self::path) (Save asks for a
    /// `.taut` file); [`source`](Self::source) names it and [`import_report`](Self::import_report)
    /// says what the import repaired.
    pub fn open(path: &Path) -> Result<Self, String> {
        if is_taut(path) {
            let doc = Document::load(path).map_err(|e| e.to_string())?;
            return Ok(Self::new(doc, Some(path.to_path_buf())));
        }
        let (mesh, report) = io::import_mesh(path).map_err(|e| e.to_string())?;
        let doc = Document::new(mesh);
        doc.validate().map_err(|e| format!("{}: {e}", path.display()))?;
        let mut opened = Self::new(doc, None);
        opened.source = Some(path.to_path_buf());
        opened.import_report = Some(report);
        Ok(opened)
    }

    /// A document restored from an autosave: it has unsaved changes by definition.
    pub(super) fn recovered(doc: Document, path: Option<PathBuf>, source: Option<PathBuf>) -> Self {
        let mut recovered = Self::new(doc, path);
        recovered.source = source.or_else(|| recovered.path.clone());
        recovered.saved_state = None;
        recovered
    }

    /// The document as it is now.
    pub fn doc(&self) -> &Document {
        &self.doc
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

    /// True when the document differs from the state last saved or loaded.
    pub fn is_dirty(&self) -> bool {
        self.saved_state != Some(self.state)
    }

    /// Checks and applies one edit. A refused edit leaves the document and its history as they
    /// were and says why; an edit that changes nothing records nothing.
    pub fn apply(&mut self, edit: Edit) -> Result<(), String> {
        check(&self.doc, &edit)?;
        if !changes(&self.doc, &edit) {
            return Ok(());
        }
        match &mut self.gesture {
            Some(gesture) => {
                if !gesture.changed {
                    gesture.changed = true;
                    self.redo.clear();
                }
            }
            None => {
                let before = Snapshot { doc: self.doc.clone(), state: self.state };
                self.push_undo(before);
                self.redo.clear();
            }
        }
        perform(&mut self.doc, edit);
        self.state = self.take_state();
        self.touch();
        Ok(())
    }

    /// Starts a gesture (a drag, one slider movement): the edits applied until
    /// [`end_gesture`](Self::end_gesture) become one undo step. Starting a gesture while one is
    /// open continues the open one.
    pub fn begin_gesture(&mut self) {
        if self.gesture.is_none() {
            let before = Snapshot { doc: self.doc.clone(), state: self.state };
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
            self.state = gesture.before.state;
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
    pub fn export_surface(surface: &PolyMesh, path: &Path) -> Result<(), String> {
        if is_taut(path) {
            return Err(format!(
                "{}: export writes the smoothed surface as .obj or .glb; use Save As for a .taut cage",
                path.display()
            ));
        }
        io::export_mesh(surface, path).map_err(|e| e.to_string())
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
        let current = Snapshot { doc: std::mem::replace(&mut self.doc, snapshot.doc), state: self.state };
        self.state = snapshot.state;
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

/// Checks an edit against the document without changing it.
fn check(doc: &Document, edit: &Edit) -> Result<(), String> {
    match edit {
        Edit::MoveVertices(moves) => {
            for &(v, p) in moves {
                check_vertex(doc, v, "move")?;
                if !p.is_finite() {
                    return Err(format!(
                        "cannot move vertex {} to ({}, {}, {}): coordinates must be finite numbers",
                        v.0, p.x, p.y, p.z
                    ));
                }
            }
            Ok(())
        }
        Edit::SetFixed(vertices, _) => vertices.iter().try_for_each(|&v| check_vertex(doc, v, "fix or free")),
        Edit::SetVertexTension(vertices, tau) => {
            check_tension(*tau)?;
            vertices.iter().try_for_each(|&v| check_vertex(doc, v, "set the tension of"))
        }
        Edit::SetEdgeTension(edges, tau) => {
            check_tension(*tau)?;
            edges.iter().try_for_each(|&e| check_edge(doc, e, "set the tension of"))
        }
        Edit::ResetTension { vertices, edges } => {
            vertices.iter().try_for_each(|&v| check_vertex(doc, v, "reset the tension of"))?;
            edges.iter().try_for_each(|&e| check_edge(doc, e, "reset the tension of"))
        }
        Edit::SetSettings(settings) => settings.validate().map_err(|e| format!("solver settings: {e}")),
        Edit::Replace(new) => {
            new.cage.validate().map_err(|e| format!("cannot use the new cage: {e}"))?;
            new.validate().map_err(|e| format!("cannot use the new cage: {e}"))
        }
    }
}

fn check_vertex(doc: &Document, v: VertexId, action: &str) -> Result<(), String> {
    let n = doc.cage.vertex_count();
    if v.index() < n {
        Ok(())
    } else {
        Err(format!("cannot {action} vertex {}: the cage has {n} vertices, numbered from 0", v.0))
    }
}

fn check_edge(doc: &Document, e: EdgeId, action: &str) -> Result<(), String> {
    let n = doc.cage.edge_count();
    if e.index() < n {
        Ok(())
    } else {
        Err(format!("cannot {action} edge {}: the cage has {n} edges, numbered from 0", e.0))
    }
}

fn check_tension(tau: f64) -> Result<(), String> {
    if tau.is_finite() && tau >= 0.0 {
        Ok(())
    } else {
        Err(format!("tension must be a finite number ≥ 0, not {tau}"))
    }
}

/// True when a checked edit would change the document.
fn changes(doc: &Document, edit: &Edit) -> bool {
    match edit {
        Edit::MoveVertices(moves) => moves.iter().any(|&(v, p)| doc.cage.position(v) != p),
        Edit::SetFixed(vertices, fixed) => vertices.iter().any(|v| doc.fixed[v.index()] != *fixed),
        Edit::SetVertexTension(vertices, tau) => vertices.iter().any(|v| doc.vertex_tension[v.index()] != *tau),
        Edit::SetEdgeTension(edges, tau) => edges.iter().any(|e| doc.edge_tension[e.index()] != *tau),
        Edit::ResetTension { vertices, edges } => {
            vertices.iter().any(|v| doc.vertex_tension[v.index()] != 0.0)
                || edges.iter().any(|e| doc.edge_tension[e.index()] != 0.0)
        }
        Edit::SetSettings(settings) => doc.settings != *settings,
        Edit::Replace(new) => *doc != **new,
    }
}

/// Applies a checked edit.
fn perform(doc: &mut Document, edit: Edit) {
    match edit {
        Edit::MoveVertices(moves) => {
            let positions = doc.cage.positions_mut();
            for (v, p) in moves {
                positions[v.index()] = p;
            }
        }
        Edit::SetFixed(vertices, fixed) => vertices.iter().for_each(|v| doc.fixed[v.index()] = fixed),
        Edit::SetVertexTension(vertices, tau) => vertices.iter().for_each(|v| doc.vertex_tension[v.index()] = tau),
        Edit::SetEdgeTension(edges, tau) => edges.iter().for_each(|e| doc.edge_tension[e.index()] = tau),
        Edit::ResetTension { vertices, edges } => {
            vertices.iter().for_each(|v| doc.vertex_tension[v.index()] = 0.0);
            edges.iter().for_each(|e| doc.edge_tension[e.index()] = 0.0);
        }
        Edit::SetSettings(settings) => doc.settings = settings,
        Edit::Replace(new) => *doc = *new,
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use taut_core::nusd::Spacing;

    /// A unique, empty folder under the system's temp folder.
    pub(in crate::editor) fn temp_dir(name: &str) -> PathBuf {
        static COUNT: AtomicU64 = AtomicU64::new(0);
        let dir = std::env::temp_dir().join(format!(
            "taut-editor-{name}-{}-{}",
            std::process::id(),
            COUNT.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A unit cube cage, every vertex fixed, no tension.
    pub(in crate::editor) fn cube_doc() -> Document {
        let p = [
            [0., 0., 0.],
            [1., 0., 0.],
            [0., 1., 0.],
            [1., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [0., 1., 1.],
            [1., 1., 1.],
        ]
        .map(DVec3::from_array)
        .to_vec();
        let f = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        Document::new(PolyMesh::from_polygons(p, &f).unwrap())
    }

    fn editor() -> EditorDocument {
        EditorDocument::new(cube_doc(), None)
    }

    #[test]
    fn every_edit_applies_and_undoes_exactly() {
        let mut settings = SolverSettings { levels: 2, lambda: 0.4, ..SolverSettings::default() };
        settings.spacing = Spacing::Centripetal;
        let mut other = cube_doc();
        other.cage.positions_mut()[7] = DVec3::splat(2.0);
        other.fixed[0] = false;
        let edits = [
            Edit::MoveVertices(vec![
                (VertexId(1), DVec3::new(1.5, -0.25, 0.0)),
                (VertexId(6), DVec3::new(0.0, 1.0, 2.0)),
            ]),
            Edit::SetFixed(vec![VertexId(0), VertexId(3)], false),
            Edit::SetVertexTension(vec![VertexId(2), VertexId(5)], 2.5),
            Edit::SetEdgeTension(vec![EdgeId(0), EdgeId(11)], 0.75),
            Edit::SetSettings(settings),
            Edit::Replace(Box::new(other.clone())),
        ];
        for edit in edits {
            let mut ed = editor();
            let before = ed.doc().clone();
            ed.apply(edit.clone()).unwrap();
            assert_ne!(*ed.doc(), before, "{edit:?} changed nothing");
            let after = ed.doc().clone();
            match &edit {
                Edit::MoveVertices(m) => assert!(m.iter().all(|&(v, p)| after.cage.position(v) == p)),
                Edit::SetFixed(vs, f) => assert!(vs.iter().all(|v| after.fixed[v.index()] == *f)),
                Edit::SetVertexTension(vs, t) => assert!(vs.iter().all(|v| after.vertex_tension[v.index()] == *t)),
                Edit::SetEdgeTension(es, t) => assert!(es.iter().all(|e| after.edge_tension[e.index()] == *t)),
                Edit::SetSettings(s) => assert_eq!(after.settings, *s),
                Edit::Replace(d) => assert_eq!(after, **d),
                Edit::ResetTension { .. } => unreachable!(),
            }
            assert!(ed.can_undo() && !ed.can_redo());
            assert!(ed.undo());
            assert_eq!(*ed.doc(), before, "undo of {edit:?}");
            assert!(!ed.is_dirty());
            assert!(ed.redo());
            assert_eq!(*ed.doc(), after, "redo of {edit:?}");
            assert!(!ed.redo() && ed.undo() && !ed.undo());
            assert_eq!(*ed.doc(), before);
        }
    }

    #[test]
    fn reset_tension_undoes_exactly() {
        let mut doc = cube_doc();
        doc.vertex_tension[4] = 3.0;
        doc.edge_tension[2] = 1.5;
        doc.edge_tension[5] = 0.5;
        let mut ed = EditorDocument::new(doc.clone(), None);
        ed.apply(Edit::ResetTension { vertices: vec![VertexId(4)], edges: vec![EdgeId(2)] }).unwrap();
        assert_eq!(ed.doc().vertex_tension[4], 0.0);
        assert_eq!(ed.doc().edge_tension[2], 0.0);
        assert_eq!(ed.doc().edge_tension[5], 0.5, "edges not named keep their tension");
        assert!(ed.undo());
        assert_eq!(*ed.doc(), doc);
    }

    #[test]
    fn a_gesture_is_one_undo_step() {
        let mut ed = editor();
        let before = ed.doc().clone();
        ed.apply(Edit::SetFixed(vec![VertexId(2)], false)).unwrap();
        let after_fix = ed.doc().clone();
        ed.begin_gesture();
        let mut revisions = vec![ed.revision()];
        for i in 1..=50 {
            let p = DVec3::new(1.0 + 0.01 * i as f64, 1.0, 1.0);
            ed.apply(Edit::MoveVertices(vec![(VertexId(7), p)])).unwrap();
            revisions.push(ed.revision());
        }
        ed.end_gesture();
        assert!(revisions.windows(2).all(|w| w[1] > w[0]), "every move is a new revision for the solver");
        assert_eq!(ed.doc().cage.position(VertexId(7)), DVec3::new(1.5, 1.0, 1.0));
        assert!(ed.undo());
        assert_eq!(*ed.doc(), after_fix, "the whole drag is undone at once");
        assert!(ed.undo());
        assert_eq!(*ed.doc(), before);
        assert!(!ed.undo());
    }

    #[test]
    fn empty_and_returning_gestures_add_no_step() {
        let mut ed = editor();
        ed.begin_gesture();
        ed.end_gesture();
        assert!(!ed.can_undo());
        // Dragged and put back exactly: no step, still clean.
        let home = ed.doc().cage.position(VertexId(3));
        ed.begin_gesture();
        ed.apply(Edit::MoveVertices(vec![(VertexId(3), home + DVec3::X)])).unwrap();
        assert!(ed.is_dirty() && ed.can_undo());
        ed.apply(Edit::MoveVertices(vec![(VertexId(3), home)])).unwrap();
        ed.end_gesture();
        assert!(!ed.can_undo() && !ed.is_dirty());
        // An edit that changes nothing records nothing.
        let revision = ed.revision();
        ed.apply(Edit::SetFixed(vec![VertexId(0)], true)).unwrap();
        assert!(!ed.can_undo() && !ed.is_dirty());
        assert_eq!(ed.revision(), revision);
    }

    #[test]
    fn undo_during_a_gesture_ends_it_first() {
        let mut ed = editor();
        let before = ed.doc().clone();
        ed.begin_gesture();
        ed.apply(Edit::MoveVertices(vec![(VertexId(0), DVec3::splat(-1.0))])).unwrap();
        assert!(ed.can_undo());
        assert!(ed.undo());
        assert!(!ed.in_gesture());
        assert_eq!(*ed.doc(), before);
    }

    #[test]
    fn a_new_edit_clears_redo() {
        let mut ed = editor();
        ed.apply(Edit::SetVertexTension(vec![VertexId(1)], 1.0)).unwrap();
        ed.apply(Edit::SetVertexTension(vec![VertexId(1)], 2.0)).unwrap();
        assert!(ed.undo());
        assert!(ed.can_redo());
        ed.apply(Edit::SetVertexTension(vec![VertexId(1)], 3.0)).unwrap();
        assert!(!ed.can_redo() && !ed.redo());
        assert_eq!(ed.doc().vertex_tension[1], 3.0);
        assert!(ed.undo());
        assert_eq!(ed.doc().vertex_tension[1], 1.0);
        // The first change of a gesture clears redo too.
        assert!(ed.can_redo());
        ed.begin_gesture();
        ed.apply(Edit::SetVertexTension(vec![VertexId(1)], 4.0)).unwrap();
        assert!(!ed.can_redo());
        ed.end_gesture();
    }

    #[test]
    fn undo_memory_is_bounded() {
        let mut ed = editor();
        for i in 0..MAX_UNDO_STEPS + 50 {
            ed.apply(Edit::SetVertexTension(vec![VertexId(0)], i as f64 + 1.0)).unwrap();
        }
        let mut steps = 0;
        while ed.undo() {
            steps += 1;
        }
        assert_eq!(steps, MAX_UNDO_STEPS);
        assert_eq!(ed.doc().vertex_tension[0], 50.0, "the oldest steps are forgotten first");
    }

    #[test]
    fn refused_edits_change_nothing_and_say_why() {
        let mut ed = editor();
        ed.apply(Edit::SetVertexTension(vec![VertexId(1)], 1.0)).unwrap();
        assert!(ed.undo());
        let bad_settings = SolverSettings { lambda: 1.5, ..SolverSettings::default() };
        let mut broken = cube_doc();
        broken.fixed.pop();
        let cases = [
            (Edit::MoveVertices(vec![(VertexId(0), DVec3::ONE), (VertexId(999), DVec3::ZERO)]), "vertex 999"),
            (Edit::MoveVertices(vec![(VertexId(1), DVec3::new(f64::NAN, 0.0, 0.0))]), "finite"),
            (Edit::MoveVertices(vec![(VertexId(1), DVec3::new(0.0, f64::INFINITY, 0.0))]), "finite"),
            (Edit::SetFixed(vec![VertexId(999)], false), "the cage has 8 vertices"),
            (Edit::SetVertexTension(vec![VertexId(0)], -1.0), "≥ 0"),
            (Edit::SetVertexTension(vec![VertexId(0)], f64::NAN), "finite"),
            (Edit::SetEdgeTension(vec![EdgeId(0)], -0.5), "≥ 0"),
            (Edit::SetEdgeTension(vec![EdgeId(12)], 1.0), "edge 12: the cage has 12 edges"),
            (Edit::ResetTension { vertices: vec![VertexId(0)], edges: vec![EdgeId(40)] }, "edge 40"),
            (Edit::SetSettings(bad_settings), "lambda"),
            (Edit::Replace(Box::new(broken)), "fixed flags"),
        ];
        for (edit, expected) in cases {
            let doc = ed.doc().clone();
            let revision = ed.revision();
            let err = ed.apply(edit.clone()).unwrap_err();
            assert!(err.contains(expected), "expected '{expected}' in: {err}");
            assert_eq!(*ed.doc(), doc, "{edit:?} changed the document");
            assert_eq!(ed.revision(), revision);
            assert!(!ed.can_undo() && ed.can_redo(), "{edit:?} touched the history");
            assert!(!ed.is_dirty());
        }
    }

    #[test]
    fn dirty_follows_the_saved_state() {
        let dir = temp_dir("dirty");
        let path = dir.join("cube.taut");
        let mut ed = editor();
        assert!(!ed.is_dirty());
        assert_eq!(ed.title(), "untitled");
        ed.apply(Edit::SetFixed(vec![VertexId(0)], false)).unwrap();
        assert!(ed.is_dirty());
        assert_eq!(ed.title(), "untitled*");
        assert!(ed.save().unwrap_err().contains("Save As"));
        ed.save_as(&path).unwrap();
        assert!(!ed.is_dirty());
        assert_eq!(ed.title(), "cube.taut");
        ed.apply(Edit::SetFixed(vec![VertexId(1)], false)).unwrap();
        assert!(ed.is_dirty());
        assert_eq!(ed.title(), "cube.taut*");
        assert!(ed.undo());
        assert!(!ed.is_dirty(), "undoing back to the saved state is clean");
        assert!(ed.undo());
        assert!(ed.is_dirty(), "undoing past the saved state is dirty");
        assert!(ed.redo());
        assert!(!ed.is_dirty());
        assert!(ed.redo());
        assert!(ed.is_dirty());
        ed.save().unwrap();
        assert!(!ed.is_dirty());
        assert!(ed.undo());
        ed.apply(Edit::SetFixed(vec![VertexId(5)], false)).unwrap();
        assert!(ed.is_dirty(), "a different branch is never the saved state");
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn revisions_change_with_every_change_and_never_repeat() {
        let mut ed = editor();
        let other = editor();
        assert_ne!(ed.revision(), other.revision());
        let r0 = ed.revision();
        ed.apply(Edit::SetVertexTension(vec![VertexId(0)], 1.0)).unwrap();
        let r1 = ed.revision();
        ed.undo();
        let r2 = ed.revision();
        ed.redo();
        let r3 = ed.revision();
        assert!(r0 < r1 && r1 < r2 && r2 < r3);
    }

    #[test]
    fn cage_generation_never_repeats_across_undo() {
        let mut ed = editor();
        let mut seen = vec![(ed.doc().cage.generation(), ed.doc().cage.positions().to_vec())];
        let moves = [DVec3::X, DVec3::Y, DVec3::Z];
        for m in moves {
            ed.apply(Edit::MoveVertices(vec![(VertexId(0), m * 3.0)])).unwrap();
            seen.push((ed.doc().cage.generation(), ed.doc().cage.positions().to_vec()));
            ed.undo();
            seen.push((ed.doc().cage.generation(), ed.doc().cage.positions().to_vec()));
        }
        for (i, a) in seen.iter().enumerate() {
            for b in &seen[i + 1..] {
                assert!(a.0 != b.0 || a.1 == b.1, "generation {} names two different cages", a.0);
            }
        }
    }

    #[test]
    fn save_as_and_open_round_trip() {
        let dir = temp_dir("roundtrip");
        let path = dir.join("shape.taut");
        let mut ed = editor();
        ed.apply(Edit::SetEdgeTension(vec![EdgeId(3)], 0.1 + 0.2)).unwrap();
        ed.apply(Edit::MoveVertices(vec![(VertexId(5), DVec3::new(1.0 / 3.0, 0.0, 1.0))])).unwrap();
        assert!(ed.save_as(&dir.join("shape.obj")).unwrap_err().contains(".taut"));
        assert!(ed.path().is_none());
        ed.save_as(&path).unwrap();
        assert_eq!(ed.path(), Some(path.as_path()));
        let opened = EditorDocument::open(&path).unwrap();
        assert_eq!(opened.doc(), ed.doc());
        assert_eq!(opened.path(), Some(path.as_path()));
        assert!(!opened.is_dirty() && !opened.can_undo());
        assert_ne!(opened.revision(), ed.revision());
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn an_imported_mesh_asks_for_a_taut_file() {
        let dir = temp_dir("import");
        let obj = dir.join("cube.obj");
        let cube = cube_doc();
        EditorDocument::export_surface(&cube.cage, &obj).unwrap();
        assert!(EditorDocument::export_surface(&cube.cage, &dir.join("x.taut")).is_err());
        let mut ed = EditorDocument::open(&obj).unwrap();
        assert_eq!(ed.doc().cage.positions(), cube.cage.positions());
        assert!(ed.path().is_none());
        assert_eq!(ed.source(), Some(obj.as_path()));
        assert!(ed.import_report().is_some_and(|r| r.is_clean()));
        assert_eq!(ed.title(), "cube.obj");
        assert!(ed.save().is_err());
        let taut = dir.join("cube.taut");
        ed.save_as(&taut).unwrap();
        assert_eq!(ed.path(), Some(taut.as_path()));
        assert_eq!(EditorDocument::open(&taut).unwrap().doc(), ed.doc());
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn garbage_files_are_errors() {
        let dir = temp_dir("garbage");
        let cases: [(&str, &[u8]); 5] = [
            ("bad.taut", b"{ this is not json"),
            ("empty.taut", b""),
            ("bad.obj", b"v 0 0 0\nf 1 2 3 4 5\nnonsense\n"),
            ("bad.glb", &[0xff, 0x00, 0x13, 0x37, 1, 2, 3]),
            ("bad.txt", b"hello"),
        ];
        for (name, bytes) in cases {
            let path = dir.join(name);
            std::fs::write(&path, bytes).unwrap();
            let err = EditorDocument::open(&path).unwrap_err();
            assert!(!err.is_empty(), "{name}");
        }
        assert!(EditorDocument::open(&dir.join("missing.taut")).is_err());
        let _ = std::fs::remove_dir_all(dir);
    }
}
