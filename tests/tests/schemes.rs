//! The surface seam: every scheme behind one interface, the document that chooses it (format
//! version 2, version 1 still opening), and the one edit validator.

use std::path::Path;
use taut_core::document::FORMAT_VERSION;
use taut_core::surface::{self, Budget, ColourBy, Phase, SchemeKind, SubdivSettings};
use taut_core::{DVec3, Document, EdgeId, Edit, VertexId};
use taut_tests::{cube, grid, prism};

fn bundled(name: &str) -> Document {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name);
    Document::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn bundled_version_one_files_open_as_nusd_documents() {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/default.taut")).unwrap();
    assert!(text.contains("\"version\": 1"), "the bundled default scene is a version-1 file");
    let doc = bundled("default.taut");
    assert_eq!(doc.scheme, SchemeKind::Nusd);
    assert!(doc.crease.iter().all(|&s| s == 0.0));
    assert_eq!(doc.subdiv, SubdivSettings::default());
    // Saved again it is version 2 and reads back the same.
    let again = Document::from_json(&doc.to_json(), Path::new("again.taut")).unwrap();
    assert_eq!(again, doc);
    assert!(doc.to_json().contains(&format!("\"version\": {FORMAT_VERSION}")));
}

#[test]
fn version_two_keeps_the_scheme_creases_and_levels_exactly() {
    let mut doc = Document::new(prism(5, 1.0, 1.0)).with_scheme(SchemeKind::CatmullClark);
    doc.set_crease(VertexId(0), VertexId(1), 1.5).unwrap();
    doc.set_crease(VertexId(5), VertexId(6), f64::INFINITY).unwrap();
    doc.subdiv.levels = 2;
    let text = doc.to_json();
    assert!(text.contains("\"scheme\": \"catmull-clark\"") && text.contains("\"inf\""), "{text}");
    let back = Document::from_json(&text, Path::new("x.taut")).unwrap();
    assert_eq!(back, doc);
    assert_eq!(back.to_json(), text);
    // Bad keys and values are refused, naming what is wrong.
    for (bad, expected) in [
        (text.replace("\"inf\"", "\"sharpish\""), "is not a sharpness"),
        (text.replace("1.5", "-1.5"), "must be a number ≥ 0"),
        (text.replace("catmull-clark", "bezier"), "not a valid .taut file"),
        (text.replace("\"levels\": 2", "\"levels\": 0"), "subdivision levels must be 1"),
        (text.replace("\"version\": 2", "\"version\": 1"), "a version-1 file has no scheme"),
    ] {
        let err = Document::from_json(&bad, Path::new("bad.taut")).unwrap_err().to_string();
        assert!(err.contains(expected), "expected '{expected}' in: {err}");
    }
}

#[test]
fn one_validator_refuses_what_no_scheme_can_take() {
    let mut doc = Document::new(cube());
    let before = doc.clone();
    let refusals = [
        (Edit::SetCrease(vec![EdgeId(0)], -1.0), "≥ 0"),
        (Edit::SetCrease(vec![EdgeId(99)], 1.0), "the cage has 12 edges"),
        (Edit::SetScheme(SchemeKind::Loop), "triangulate the cage first"),
        (Edit::SetSubdivSettings(SubdivSettings { levels: 11 }), "subdivision levels must be 1 to"),
        (Edit::SetFixed((0..8).map(VertexId).collect(), false), "fix at least 4 of vertices"),
        (Edit::MoveVertices(vec![(VertexId(0), DVec3::new(f64::NAN, 0.0, 0.0))]), "finite"),
    ];
    for (edit, expected) in refusals {
        let err = doc.apply(edit).unwrap_err().to_string();
        assert!(err.contains(expected), "expected '{expected}' in: {err}");
        assert_eq!(doc, before, "a refused edit changed the document");
    }
    // Unfixing every vertex is fine under Catmull–Clark (fixed flags are NUSD's), but switching
    // that document back to NUSD is refused: its surface would shrink away.
    doc.apply(Edit::SetScheme(SchemeKind::CatmullClark)).unwrap();
    doc.apply(Edit::SetFixed((0..8).map(VertexId).collect(), false)).unwrap();
    let err = doc.apply(Edit::SetScheme(SchemeKind::Nusd)).unwrap_err().to_string();
    assert!(err.contains("has no fixed vertex"), "{err}");
    assert_eq!(doc.scheme, SchemeKind::CatmullClark);
    // An edit that sets what is there changes nothing and says so.
    assert!(!doc.apply(Edit::SetScheme(SchemeKind::CatmullClark)).unwrap());
}

#[test]
fn every_scheme_draws_through_the_seam() {
    let mut doc = Document::new(prism(6, 1.0, 1.5));
    for scheme in SchemeKind::ALL {
        if scheme == SchemeKind::Loop {
            let triangles = taut_core::mesh::edit::triangulate(
                &doc.cage,
                None,
                taut_core::mesh::edit::Triangulation::ShortestDiagonal,
            )
            .unwrap();
            doc = doc.with_edited_cage(triangles).unwrap();
        }
        doc.scheme = scheme;
        let s = surface::solve(&doc).unwrap();
        let progress = s.progress();
        assert_eq!(progress.phase, Phase::Done, "{scheme:?}");
        assert!(progress.converged && progress.summary.contains(scheme.display_name()), "{}", progress.summary);
        let mesh = s.mesh();
        mesh.validate().unwrap();
        assert_eq!(s.curves().len(), doc.cage.edge_count(), "one curve per cage edge");
        match scheme {
            // NUSD interpolates the fixed cage: vertex i of the surface is cage vertex i.
            SchemeKind::Nusd => {
                assert!(s.normals().is_none());
                for v in doc.cage.vertices() {
                    assert_eq!(mesh.position(v), doc.cage.position(v));
                }
                let r = ColourBy::parse("r", scheme).unwrap().values(s.as_ref()).unwrap();
                assert_eq!(r.len(), mesh.vertex_count());
            }
            // A subdivision surface has exact unit normals and no NUSD field.
            _ => {
                let normals = s.normals().expect("limit normals");
                assert_eq!(normals.len(), mesh.vertex_count());
                assert!(normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-9));
                assert!(ColourBy::parse("r", scheme).is_err());
            }
        }
        // Each curve runs between its cage edge's two surface points.
        for (e, curve) in doc.cage.edges().zip(s.curves()) {
            let (a, b) = doc.cage.edge_vertices(e);
            assert!((curve[0] - mesh.position(a)).length() < 1e-12, "{scheme:?} edge {e:?}");
            assert!((*curve.last().unwrap() - mesh.position(b)).length() < 1e-12, "{scheme:?} edge {e:?}");
        }
    }
}

/// A drag re-evaluates a subdivision surface through its stencils: the same bits as a fresh
/// build, and its topology kept (no rebuild).
#[test]
fn a_drag_updates_a_subdivision_surface_to_the_fresh_result() {
    let mut doc = Document::new(grid(4, 3, 1.0, |x, y| 0.2 * x * y)).with_scheme(SchemeKind::CatmullClark);
    doc.set_crease(VertexId(6), VertexId(7), 2.0).unwrap();
    let mut live = surface::build(&doc).unwrap();
    let topology = live.mesh().topology_generation();
    doc.apply(Edit::MoveVertices(vec![(VertexId(7), DVec3::new(2.1, 1.2, 0.9))])).unwrap();
    live.update(&doc).unwrap();
    live.advance(Budget::UNLIMITED);
    assert_eq!(live.mesh().topology_generation(), topology, "a drag rebuilt the topology");
    let fresh = surface::solve(&doc).unwrap();
    let bits = |p: &[DVec3]| p.iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(live.mesh().positions()), bits(fresh.mesh().positions()));
    assert_eq!(bits(live.normals().unwrap()), bits(fresh.normals().unwrap()));
    // A crease change rebuilds and matches a fresh build too.
    doc.apply(Edit::SetCrease(vec![doc.edge_between(VertexId(6), VertexId(7)).unwrap()], 0.0)).unwrap();
    live.update(&doc).unwrap();
    assert_eq!(bits(live.mesh().positions()), bits(surface::solve(&doc).unwrap().mesh().positions()));
}
