//! Tests of [`super`].

use super::*;

fn tetra() -> Document {
    let p = vec![DVec3::new(0.1, 0.2, 0.3), DVec3::new(1.0 / 3.0, 0.0, 0.0), DVec3::Y, DVec3::new(0.0, 0.0, 1e-17)];
    let cage = PolyMesh::from_polygons(p, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]).unwrap();
    Document::new(cage)
}

#[test]
fn json_round_trip_is_exact() {
    let mut doc = tetra();
    doc.fixed[2] = false;
    doc.vertex_tension[1] = 0.1 + 0.2;
    doc.set_edge_tension(VertexId(3), VertexId(1), std::f64::consts::PI).unwrap();
    doc.settings.levels = 2;
    doc.settings.spacing = crate::nusd::Spacing::Centripetal;
    let text = doc.to_json();
    let back = Document::from_json(&text, Path::new("mem.taut")).unwrap();
    assert_eq!(back, doc);
    assert_eq!(back.to_json(), text);
}

#[test]
fn corners_round_trip_are_carried_by_an_edit_and_bad_ones_are_named() {
    let mut doc = tetra();
    doc.set_corner(VertexId(1), 2.5).unwrap();
    doc.set_corner(VertexId(3), f64::INFINITY).unwrap();
    let text = doc.to_json();
    assert!(text.contains("\"corner\""), "{text}");
    let back = Document::from_json(&text, Path::new("mem.taut")).unwrap();
    assert_eq!(back.corner, vec![0.0, 2.5, 0.0, f64::INFINITY]);
    assert_eq!(back.to_json(), text);
    assert!(!tetra().to_json().contains("corner"), "no key without corners");
    // An edge split at its middle: the old vertices keep their sharpness, the new one is
    // smooth.
    let split = crate::mesh::edit::split_edges(&doc.cage, &[EdgeId(0)], 0.5).unwrap();
    let edited = doc.with_edited_cage(split).unwrap();
    assert_eq!(edited.corner, vec![0.0, 2.5, 0.0, f64::INFINITY, 0.0]);
    let bad = [
        (text.replace("2.5", "-1.0"), "vertex 1"),
        (text.replace("\"inf\"", "\"sharp\""), "'sharp' is not a sharpness"),
    ];
    for (text, expected) in bad {
        let err = Document::from_json(&text, Path::new("x.taut")).unwrap_err().to_string();
        assert!(err.contains(expected), "expected '{expected}' in: {err}");
    }
    assert!(doc.set_corner(VertexId(9), 1.0).unwrap_err().to_string().contains("4 vertices"));
}

/// `text` with the JSON array under `key` replaced by `with`.
fn replace_array(text: &str, key: &str, with: &str) -> String {
    let start = text.find(&format!("\"{key}\": [")).unwrap() + key.len() + 4;
    let end = start + text[start..].find(']').unwrap() + 1;
    format!("{}{with}{}", &text[..start], &text[end..])
}

#[test]
fn missing_lists_mean_defaults() {
    let text = r#"{"format": "taut-cage", "version": 1, "positions": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,2]]}"#;
    let doc = Document::from_json(text, Path::new("bare.taut")).unwrap();
    assert_eq!(doc.fixed, vec![true; 3]);
    assert_eq!(doc.vertex_tension, vec![0.0; 3]);
}

#[test]
fn bad_documents_are_explained() {
    let good = tetra().to_json();
    let cases = [
        (good.replace("taut-cage", "other"), "expected 'taut-cage'"),
        (good.replace("\"version\": 2", "\"version\": 9"), "not supported"),
        (good[..good.len() / 2].to_string(), "not a valid .taut file"),
        (good.replace("\"settings\"", "\"bogus\": 1, \"settings\""), "unknown field"),
        (good.replace("\"lambda\": 0.6", "\"lambda\": 1.5"), "lambda"),
        (good.replace("\"edge_tension\": []", "\"edge_tension\": [[0, 9, 1.0]]"), "does not exist"),
        (good.replace("\"edge_tension\": []", "\"edge_tension\": [[0, 1, -1.0]]"), "tension"),
        (replace_array(&good, "fixed", "[]"), "4 vertices but 0 fixed flags"),
        (replace_array(&good, "fixed", "[true]"), "4 vertices but 1 fixed flags"),
        (replace_array(&good, "vertex_tension", "[]"), "0 vertex tensions"),
    ];
    for (text, expected) in cases {
        let err = Document::from_json(&text, Path::new("x.taut")).unwrap_err().to_string();
        assert!(err.contains(expected), "expected '{expected}' in: {err}");
    }
}
