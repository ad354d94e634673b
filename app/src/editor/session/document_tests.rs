//! Tests of `document.rs`, kept apart from the code they check.

use super::*;
use taut_core::io::UpAxis;
use taut_core::nusd::SolverSettings;
use taut_core::nusd::Spacing;
use taut_core::{DVec3, EdgeId, VertexId};

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
        Edit::MoveVertices(vec![(VertexId(1), DVec3::new(1.5, -0.25, 0.0)), (VertexId(6), DVec3::new(0.0, 1.0, 2.0))]),
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
            other => panic!("{other:?} is not among the edits this test makes"),
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
    let writer = EditorDocument::new(cube.clone(), None);
    writer.export_surface(&cube.cage, None, &obj, UpAxis::Y).unwrap();
    assert!(writer.export_surface(&cube.cage, None, &dir.join("x.taut"), UpAxis::Y).is_err());
    let mut ed = EditorDocument::open(&obj).unwrap();
    // Exporting the surface over the mesh the cage came from is refused: it would replace it.
    let err = ed.export_surface(&cube.cage, None, &obj, UpAxis::Y).unwrap_err();
    assert!(err.contains("the file this cage was opened from"), "{err}");
    assert_eq!(ed.doc().cage.positions(), cube.cage.positions());
    assert!(ed.path().is_none());
    assert_eq!(ed.source(), Some(obj.as_path()));
    assert!(ed.import_report().is_some_and(|r| r.is_clean()));
    assert_eq!(ed.title(), "cube.obj");
    assert_eq!(ed.doc().settings.levels, 4, "a small imported cage is shown at level 4");
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

#[test]
fn larger_imported_cages_are_shown_at_fewer_levels() {
    // The default scene's 41 faces and a cube at 4; Blender's monkey (500 faces) at 3, its
    // finest level 32,000 faces; a scan's million faces at one level.
    assert_eq!(display_levels(6), 4);
    assert_eq!(display_levels(41), 4);
    assert_eq!(display_levels(500), 3);
    assert_eq!(display_levels(4_000), 2);
    assert_eq!(display_levels(1_000_000), 1);
    assert_eq!(display_levels(0), 4);
}

/// Adopting a new document (a cage made from a mesh) is one undo step that leaves the file:
/// Save then asks for one, undo brings back the document and its file, redo the adopted one.
#[test]
fn adopting_a_document_is_one_undo_step_that_leaves_the_file() {
    let dir = temp_dir("adopt");
    let file = dir.join("work.taut");
    let mut ed = EditorDocument::new(cube_doc(), None);
    ed.save_as(&file).unwrap();
    ed.apply(Edit::MoveVertices(vec![(VertexId(7), DVec3::splat(1.5))])).unwrap();
    let work = ed.doc().clone();
    let mut other = cube_doc();
    other.cage.positions_mut()[0] = DVec3::splat(-0.5);
    let mesh = dir.join("scan.stl");
    ed.adopt(other.clone(), Some(mesh.clone())).unwrap();
    assert_eq!(ed.doc(), &other);
    assert_eq!((ed.path(), ed.source()), (None, Some(mesh.as_path())));
    assert!(ed.is_dirty() && ed.save().is_err(), "Save asks for a file");
    assert_eq!(ed.title(), "scan.stl*");
    assert!(ed.undo());
    assert_eq!(ed.doc(), &work, "the unsaved move comes back");
    assert_eq!((ed.path(), ed.source()), (Some(file.as_path()), Some(file.as_path())));
    assert!(ed.is_dirty());
    assert!(ed.redo());
    assert_eq!((ed.doc(), ed.path()), (&other, None));
    // A refused document changes nothing.
    let mut broken = cube_doc();
    broken.fixed.pop();
    assert!(ed.adopt(broken, None).is_err());
    assert_eq!((ed.doc(), ed.source()), (&other, Some(mesh.as_path())));
    let _ = std::fs::remove_dir_all(dir);
}
