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

fn reference(path: &str) -> ReferenceImage {
    ReferenceImage {
        path: path.into(),
        plane: ReferencePlane::Side,
        centre: DVec3::new(0.1, -2.0, 1.0 / 3.0),
        width: 12.5,
        rotation: -30.0,
        opacity: 0.35,
        in_front: true,
        visible: false,
    }
}

#[test]
fn reference_images_round_trip_and_old_files_have_none() {
    let plain = tetra().to_json();
    assert!(!plain.contains("reference_images"), "no key without images");
    assert!(Document::from_json(&plain, Path::new("old.taut")).unwrap().reference_images.is_empty());
    let mut doc = tetra();
    doc.apply(Edit::AddReferenceImage(reference("pics/side view.jpg"))).unwrap();
    doc.apply(Edit::AddReferenceImage(ReferenceImage::new("front.png", ReferencePlane::View, 2.0))).unwrap();
    let text = doc.to_json();
    let back = Document::from_json(&text, Path::new("mem.taut")).unwrap();
    assert_eq!(back.reference_images, doc.reference_images);
    assert_eq!(back.to_json(), text);
    // The optional values may be left out of a hand-written file.
    let short = r#"{"format": "taut-cage", "version": 2, "positions": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,2]],
        "reference_images": [{"path": "a.png", "plane": "top", "centre": [0, 0, 0], "width": 3}]}"#;
    let image = &Document::from_json(short, Path::new("short.taut")).unwrap().reference_images[0];
    assert_eq!((image.opacity, image.visible, image.in_front, image.rotation), (1.0, true, false, 0.0));
}

#[test]
fn hostile_reference_images_are_refused_in_one_line() {
    let mut doc = tetra();
    doc.reference_images.push(reference("a.png"));
    let good = doc.to_json();
    let cases = [
        (good.replace("12.5", "-1.0"), "width must be a finite number > 0"),
        (good.replace("12.5", "0.0"), "width must be a finite number > 0"),
        (good.replace("0.35", "1.5"), "opacity must be between 0 and 1"),
        (good.replace("0.35", "-0.1"), "opacity must be between 0 and 1"),
        (good.replace("12.5", "1e999"), "not a valid .taut file"),
        (good.replace("12.5", "NaN"), "not a valid .taut file"),
        (good.replace("\"side\"", "\"diagonal\""), "unknown variant"),
        (good.replace("\"a.png\"", "\"\""), "needs the path of a file"),
        (good.replace("\"visible\"", "\"bogus\": 1, \"visible\""), "unknown field"),
    ];
    for (text, expected) in cases {
        let err = Document::from_json(&text, Path::new("x.taut")).unwrap_err().to_string();
        assert!(err.contains(expected) && !err.contains('\n'), "expected '{expected}' in: {err}");
    }
    // A path that leaves the folder is kept (the designer sees and removes it) but never resolves.
    for path in ["../outside.png", "/etc/passwd"] {
        let text = good.replace("\"a.png\"", &format!("{path:?}"));
        let opened = Document::from_json(&text, Path::new("x.taut")).unwrap();
        assert_eq!(opened.reference_images[0].path, path);
        assert!(opened.reference_images[0].resolve(Path::new(".")).is_err());
    }
}

#[test]
fn reference_image_edits_are_checked_and_undoable_values() {
    let mut doc = tetra();
    let before = doc.clone();
    for bad in ["../up.png", "/abs.png", "a/../../b.png"] {
        let err = doc.apply(Edit::AddReferenceImage(reference(bad))).unwrap_err().to_string();
        assert!(err.contains("not read"), "{bad}: {err}");
    }
    let mut nan = reference("a.png");
    nan.centre.x = f64::NAN;
    assert!(doc.apply(Edit::AddReferenceImage(nan)).unwrap_err().to_string().contains("centre"));
    assert_eq!(doc, before, "a refused edit changes nothing");
    assert!(doc.apply(Edit::AddReferenceImage(reference("a.png"))).unwrap());
    let mut faded = reference("a.png");
    faded.opacity = 0.9;
    assert!(doc.apply(Edit::SetReferenceImage(0, faded.clone())).unwrap());
    assert!(!doc.apply(Edit::SetReferenceImage(0, faded)).unwrap(), "the same values change nothing");
    assert!(doc.apply(Edit::SetReferenceImage(3, reference("a.png"))).unwrap_err().to_string().contains("has 1"));
    // An image a file brought in from outside can still be changed, but not given a new bad path.
    doc.reference_images[0].path = "../outside.png".into();
    let mut hidden = doc.reference_images[0].clone();
    hidden.visible = true;
    assert!(doc.apply(Edit::SetReferenceImage(0, hidden.clone())).unwrap());
    hidden.path = "../other.png".into();
    assert!(doc.apply(Edit::SetReferenceImage(0, hidden)).is_err());
    assert!(doc.apply(Edit::RemoveReferenceImage(0)).unwrap());
    assert!(doc.reference_images.is_empty());
}

#[test]
fn units_round_trip_default_to_millimetres_and_bad_ones_are_named() {
    let mut doc = tetra();
    let text = doc.to_json();
    assert!(!text.contains("\"units\""), "millimetres, the default, are not written");
    assert_eq!(Document::from_json(&text, Path::new("mem.taut")).unwrap().units, LengthUnit::Millimetre);
    doc.apply(Edit::SetUnits(LengthUnit::Inch)).unwrap();
    let text = doc.to_json();
    assert!(text.contains("\"units\": \"in\""), "{text}");
    let back = Document::from_json(&text, Path::new("mem.taut")).unwrap();
    assert_eq!(back.units, LengthUnit::Inch);
    assert!(back == doc, "the unit is part of the document");
    let bad = text.replace("\"units\": \"in\"", "\"units\": \"furlong\"");
    let error = Document::from_json(&bad, Path::new("mem.taut")).unwrap_err().to_string();
    assert!(error.contains("furlong") && !error.contains('\n'), "{error}");
}
