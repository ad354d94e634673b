//! Tests of [`super`]: modelling operations as edits, and scripts of them.

use super::*;
use crate::mesh::edit::fixtures;
use crate::mesh::edit::{Axis, MirrorPlane};

fn cube_doc() -> Document {
    Document::new(fixtures::cube()).with_scheme(SchemeKind::CatmullClark)
}

#[test]
fn an_operation_applied_as_an_edit_is_the_core_operation_with_the_properties_carried() {
    let mut doc = cube_doc();
    doc.apply(Edit::SetCrease(vec![EdgeId(0)], 2.5)).unwrap();
    let by_hand =
        doc.with_edited_cage(edit::extrude_faces(&doc.cage, &[FaceId(1)], FaceGrouping::Region, 0.3).unwrap());
    let mut applied = doc.clone();
    assert!(applied.apply(Edit::Mesh(MeshEdit::ExtrudeFaces { faces: vec![1], distance: 0.3 })).unwrap());
    assert_eq!(applied, by_hand.unwrap());
    assert_eq!(applied.cage.face_count(), 6 + 4);
    assert!(applied.crease.contains(&2.5), "the crease is carried to the new cage");
}

#[test]
fn a_refused_operation_changes_nothing_and_says_why_in_one_line() {
    let doc = cube_doc();
    let cases = [
        MeshEdit::ExtrudeFaces { faces: vec![99], distance: 0.3 },
        MeshEdit::ExtrudeFaces { faces: vec![1], distance: f64::NAN },
        MeshEdit::LoopCut { edge: 0, fraction: f64::INFINITY },
        MeshEdit::Connect { a: 0, b: 0 },
        MeshEdit::MergeAtCentre { vertices: vec![] },
        MeshEdit::ApplyMirror,
    ];
    for op in cases {
        let mut after = doc.clone();
        let message = after.apply(Edit::Mesh(op.clone())).unwrap_err().to_string();
        assert_eq!(after, doc, "{op:?} changed the document");
        assert!(!message.is_empty() && !message.contains('\n'), "{op:?}: {message:?}");
        assert!(doc.check_edit(&Edit::Mesh(op.clone())).is_err(), "{op:?} passes the check");
    }
}

#[test]
fn every_edit_has_an_undo_name() {
    assert_eq!(Edit::Mesh(MeshEdit::ExtrudeFaces { faces: vec![], distance: 0.0 }).name(), "Extrude");
    assert_eq!(Edit::Mesh(MeshEdit::LoopCut { edge: 0, fraction: 0.5 }).name(), "Loop Cut");
    assert_eq!(Edit::MoveVertices(vec![]).name(), "Move");
    assert_eq!(Edit::SetCrease(vec![], 1.0).name(), "Set Crease");
}

/// A session of every kind of scripted step.
fn session() -> Vec<Edit> {
    vec![
        Edit::Mesh(MeshEdit::ExtrudeFaces { faces: vec![1], distance: 0.25 }),
        Edit::MoveVertices(vec![(VertexId(8), DVec3::new(0.1, 1.7, -0.2))]),
        Edit::Mesh(MeshEdit::LoopCut { edge: 3, fraction: 0.3 }),
        Edit::SetCrease(vec![EdgeId(2), EdgeId(5)], f64::INFINITY),
        Edit::SetCorner(vec![VertexId(0)], 1.5),
        Edit::Mesh(MeshEdit::Inset { faces: vec![0], distance: 0.1 }),
        Edit::Mesh(MeshEdit::SplitEdges { edges: vec![4], fraction: 0.25 }),
        Edit::Mesh(MeshEdit::Triangulate { faces: Some(vec![2]) }),
        Edit::Mesh(MeshEdit::JoinTriangles { edges: None }),
        Edit::SetScheme(SchemeKind::Nusd),
        Edit::SetFixed(vec![VertexId(3)], false),
        Edit::SetVertexTension(vec![VertexId(1)], 0.5),
        Edit::SetEdgeTension(vec![EdgeId(1)], 0.25),
        Edit::SetMirror(Some(MirrorPlane::new(Axis::X, 0.0))),
        Edit::SetMirror(None),
        Edit::SetUnits(crate::document::LengthUnit::Inch),
        Edit::SetSubdivSettings(crate::document::SubdivSettings { levels: 2 }),
        Edit::SetSettings(crate::nusd::SolverSettings { levels: 2, ..Default::default() }),
    ]
}

#[test]
fn a_script_written_and_read_back_replays_to_the_same_document_bit_for_bit() {
    let mut by_hand = cube_doc();
    let mut steps = Vec::new();
    for edit in session() {
        steps.push(ScriptStep::of(&edit).expect("scripted"));
        by_hand.apply(edit).unwrap();
    }
    let script = Script { taut_edit_script: 1, edits: steps };
    let text = script.to_json();
    let read = Script::from_json(&text).unwrap();
    assert_eq!(read, script);
    assert!(text.contains("\"op\":\"extrude_faces\"") && text.contains("\"sharpness\":\"inf\""), "{text}");
    let mut replayed = cube_doc();
    read.replay(&mut replayed).unwrap();
    assert_eq!(replayed, by_hand);
    assert_eq!(replayed.to_json(), by_hand.to_json());
}

#[test]
fn a_bad_script_is_refused_with_the_step_that_failed() {
    for (text, said) in [
        ("{\"taut_edit_script\": 2, \"edits\": []}", "version 2"),
        ("{\"taut_edit_script\": 1, \"edits\": [{\"op\": \"explode\"}]}", "cannot be read"),
        ("[1, 2", "cannot be read"),
        (
            "{\"taut_edit_script\": 1, \"edits\": [{\"op\": \"set_crease\", \"edges\": [0], \"sharpness\": \"big\"}]}",
            "edit 1",
        ),
    ] {
        let refused = Script::from_json(text).and_then(|s| s.replay(&mut cube_doc()));
        let message = refused.unwrap_err().to_string();
        assert!(message.contains(said) && !message.contains('\n'), "{text}: {message}");
    }
    // The second step refers to a face the first did not make: the first stays applied.
    let script = Script::from_json(
        "{\"taut_edit_script\": 1, \"edits\": [{\"op\": \"delete_faces\", \"faces\": [0]}, \
         {\"op\": \"inset\", \"faces\": [5], \"distance\": 0.1}]}",
    )
    .unwrap();
    let mut doc = cube_doc();
    let message = script.replay(&mut doc).unwrap_err().to_string();
    assert!(message.starts_with("edit 2 of the script:"), "{message}");
    assert_eq!(doc.cage.face_count(), 5);
}
