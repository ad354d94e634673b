//! The curve mesh as a document's fourth scheme: its edits saved and reopened bit for bit, the
//! core edits validated (a refused one changes nothing), hostile files refused with one line, the
//! edits following cage moves and topology edits, and the surface seam's incremental updates
//! equal to fresh builds bit for bit, whatever the thread count.

use glam::DQuat;
use std::path::Path;
use taut_core::gregory::CurveMesh;
use taut_core::mesh::edit::delete_vertices;
use taut_core::surface::{self, SchemeKind};
use taut_core::{DVec3, Document, EdgeId, Edit, PolyMesh, VertexId};

fn cube() -> PolyMesh {
    let p = (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    PolyMesh::from_polygons(p, &[[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]])
        .unwrap()
}

/// A triangular prism: two triangles and three quads (its curve mesh is built on one
/// Catmull–Clark step of it).
fn prism() -> PolyMesh {
    let p = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.5, 0.9, 0.0),
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(0.5, 0.9, 1.0),
    ];
    PolyMesh::from_polygons(p, &[vec![0, 2, 1], vec![3, 4, 5], vec![0, 1, 4, 3], vec![1, 2, 5, 4], vec![2, 0, 3, 5]])
        .unwrap()
}

fn bits(points: impl IntoIterator<Item = DVec3>) -> Vec<[u64; 3]> {
    points.into_iter().map(|p| p.to_array().map(f64::to_bits)).collect()
}

fn patch_bits(m: &CurveMesh) -> Vec<[u64; 3]> {
    bits(m.patches().iter().flat_map(|p| p.control_points()))
}

fn surface_bits(doc: &Document) -> (Vec<[u64; 3]>, Vec<[u64; 3]>) {
    let s = surface::build(doc).unwrap();
    (bits(s.mesh().positions().iter().copied()), bits(s.normals().unwrap().iter().copied()))
}

/// A cube document in the curve-mesh scheme with every kind of curve-mesh edit applied.
fn edited_cube() -> Document {
    let mut doc = Document::new(cube()).with_scheme(SchemeKind::CurveMesh);
    let (m, _) = doc.curve_mesh().unwrap();
    let (p0, p3) = (m.vertex_position(VertexId(0)), m.vertex_position(VertexId(3)));
    let n5 = m.vertex_normal(VertexId(5));
    let e = m.topology().outgoing(VertexId(6)).next().unwrap().edge();
    let q = m.inner_point(e, VertexId(6)).unwrap();
    let edits = [
        Edit::MoveCurveMeshVertices(vec![
            (VertexId(0), p0 + DVec3::new(-0.1, 0.05, 0.02)),
            (VertexId(3), p3 + DVec3::new(0.0, 0.1, 0.1)),
        ]),
        Edit::SetCurveMeshNormal(VertexId(5), (n5 + DVec3::new(0.2, 0.0, -0.1)).normalize()),
        Edit::RotateCurveMeshNormal(VertexId(3), DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.2)),
        Edit::MoveCurveMeshInnerPoint { curve: e, end: VertexId(6), position: q + DVec3::new(0.03, -0.04, 0.05) },
    ];
    for edit in edits {
        assert!(doc.apply(edit).unwrap(), "every edit changes the curve mesh");
    }
    doc
}

#[test]
fn curve_mesh_edits_save_and_reopen_bit_for_bit() {
    let doc = edited_cube();
    assert_eq!(doc.curve_mesh.vertices.len(), 3, "vertices 0, 3 and 5 edited");
    assert_eq!(doc.curve_mesh.curves.len(), 10, "the three curves at each of them, and the one at 6");
    let text = doc.to_json();
    assert!(text.contains("\"curve_mesh\""));
    let reopened = Document::from_json(&text, Path::new("edited.taut")).unwrap();
    assert_eq!(reopened, doc);
    assert_eq!(reopened.to_json(), text, "written again, the same text");
    assert_eq!(patch_bits(&reopened.curve_mesh().unwrap().0), patch_bits(&doc.curve_mesh().unwrap().0));
    // A fresh build on the reopened cage with the saved edits: an independent path to the patches.
    let (mut fresh, _) = CurveMesh::from_cage(&reopened.cage).unwrap();
    fresh.set_edits(&reopened.curve_mesh).unwrap();
    assert_eq!(patch_bits(&fresh), patch_bits(&doc.curve_mesh().unwrap().0));
    assert_eq!(surface_bits(&reopened), surface_bits(&doc), "the same surface, bit for bit");
    // Unedited, the key is not written, and files without it open with no edits.
    let plain = Document::new(cube()).with_scheme(SchemeKind::CurveMesh);
    assert!(!plain.to_json().contains("curve_mesh"));
    assert!(Document::from_json(&plain.to_json(), Path::new("p.taut")).unwrap().curve_mesh.is_empty());
    // Rebuild from cage discards every edit.
    let mut rebuilt = doc.clone();
    assert!(rebuilt.apply(Edit::RebuildCurveMesh).unwrap());
    assert!(rebuilt.curve_mesh.is_empty());
    assert_eq!(patch_bits(&rebuilt.curve_mesh().unwrap().0), patch_bits(&CurveMesh::from_cage(&cube()).unwrap().0));
}

#[test]
fn refused_curve_mesh_edits_change_nothing_and_say_why() {
    let doc = edited_cube();
    let (m, _) = doc.curve_mesh().unwrap();
    let e = m.topology().outgoing(VertexId(6)).next().unwrap().edge();
    let far = (0..8).map(VertexId).find(|&v| m.inner_point(e, v).is_none()).unwrap();
    let bad = [
        Edit::MoveCurveMeshVertices(vec![(VertexId(1), DVec3::new(f64::NAN, 0.0, 0.0))]),
        Edit::MoveCurveMeshVertices(vec![(VertexId(0), DVec3::ZERO), (VertexId(99), DVec3::ZERO)]),
        Edit::SetCurveMeshNormal(VertexId(2), DVec3::ZERO),
        Edit::SetCurveMeshNormal(VertexId(2), -m.vertex_normal(VertexId(2))),
        Edit::RotateCurveMeshNormal(VertexId(2), DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0)),
        Edit::MoveCurveMeshInnerPoint { curve: EdgeId(500), end: VertexId(0), position: DVec3::ZERO },
        Edit::MoveCurveMeshInnerPoint { curve: e, end: far, position: DVec3::ZERO },
        Edit::MoveCurveMeshInnerPoint { curve: e, end: VertexId(6), position: DVec3::splat(f64::INFINITY) },
    ];
    for edit in bad {
        let mut after = doc.clone();
        let message = after.apply(edit.clone()).expect_err(&format!("{edit:?} is refused")).to_string();
        assert_eq!(message.lines().count(), 1, "{message}");
        assert_eq!(after, doc, "{edit:?} changed the document");
        assert_eq!(after.to_json(), doc.to_json());
    }
    // The several-at-once move with one bad vertex moved none of them.
    assert_eq!(patch_bits(&doc.curve_mesh().unwrap().0), patch_bits(&m));
}

#[test]
fn hostile_curve_mesh_keys_are_refused_with_one_line() {
    let doc = edited_cube();
    let text = doc.to_json();
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    type Spoil = Box<dyn Fn(&mut serde_json::Value)>;
    let variants: Vec<(&str, Spoil)> = vec![
        ("wrong counts", Box::new(|v| v["curve_mesh"]["shape"][0] = 9.into())),
        ("vertex out of range", Box::new(|v| v["curve_mesh"]["vertices"][0]["vertex"] = 8.into())),
        ("vertex listed twice", Box::new(|v| v["curve_mesh"]["vertices"][1]["vertex"] = 0.into())),
        ("a normal not of unit length", Box::new(|v| v["curve_mesh"]["vertices"][0]["normal"][0] = 5.0.into())),
        ("curve out of range", Box::new(|v| v["curve_mesh"]["curves"][0]["curve"] = 12.into())),
        ("inner point off its plane", Box::new(|v| v["curve_mesh"]["curves"][0]["inner"][0][2] = 40.0.into())),
        ("unknown key", Box::new(|v| v["curve_mesh"]["extra"] = 1.into())),
        ("a string for a number", Box::new(|v| v["curve_mesh"]["vertices"][0]["position"][1] = "x".into())),
        ("version 1 with the key", Box::new(|v| v["version"] = 1.into())),
    ];
    for (what, spoil) in variants {
        let mut v = value.clone();
        spoil(&mut v);
        let result = Document::from_json(&v.to_string(), Path::new("hostile.taut"));
        let message = result.map(|_| ()).expect_err(what).to_string();
        assert_eq!(message.lines().count(), 1, "{what}: {message}");
        assert!(message.contains("hostile.taut"), "{what}: names the file: {message}");
    }
}

#[test]
fn moving_cage_points_keeps_the_curve_mesh_edits() {
    let doc = edited_cube();
    let mut moved = doc.clone();
    let corner = moved.cage.position(VertexId(7));
    assert!(moved.apply(Edit::MoveVertices(vec![(VertexId(7), corner + DVec3::new(0.3, 0.2, 0.4))])).unwrap());
    // Every edited vertex keeps its position and tangent plane exactly (the designer put it there).
    assert_eq!(moved.curve_mesh.vertices, doc.curve_mesh.vertices);
    let (m, _) = moved.curve_mesh().unwrap();
    assert_ne!(
        bits([m.vertex_position(VertexId(7))]),
        bits([doc.curve_mesh().unwrap().0.vertex_position(VertexId(7))])
    );
    // The cached curve mesh the move built equals a fresh build with the carried edits.
    let (mut fresh, _) = CurveMesh::from_cage(&moved.cage).unwrap();
    fresh.set_edits(&moved.curve_mesh).unwrap();
    assert_eq!(patch_bits(&fresh), patch_bits(&m));
    // And undo is the document before: the edit state with the cage.
    assert_eq!(surface_bits(&Document::from_json(&doc.to_json(), Path::new("d.taut")).unwrap()), surface_bits(&doc));
}

#[test]
fn a_topology_edit_carries_what_continues_and_reports_what_is_dropped() {
    let doc = edited_cube();
    let edited_0 = doc.curve_mesh.vertices.iter().find(|e| e.vertex == 0).copied().unwrap();
    // Deleting cage vertex 5 (an edited corner) opens the cube; vertices 0 and 3 continue.
    let edited = delete_vertices(&doc.cage, &[VertexId(5)]).unwrap();
    let (after, report) = doc.with_edited_cage_reported(edited).unwrap();
    assert_eq!(report.dropped_vertices, 1, "{report:?}");
    assert_eq!(report.kept_vertices, 2, "{report:?}");
    assert!(report.message().unwrap().contains("dropped"));
    let kept = after.curve_mesh.vertices.iter().find(|e| e.position == edited_0.position).expect("vertex 0's edit");
    assert_eq!(kept.normal, edited_0.normal, "kept exactly");
    // The carried state is one the new cage's curve mesh takes, and it reopens as it is.
    let reopened = Document::from_json(&after.to_json(), Path::new("open.taut")).unwrap();
    assert_eq!(patch_bits(&reopened.curve_mesh().unwrap().0), patch_bits(&after.curve_mesh().unwrap().0));
}

#[test]
fn a_cage_of_triangles_and_quads_carries_its_edits_across_a_move() {
    let mut doc = Document::new(prism()).with_scheme(SchemeKind::CurveMesh);
    let (m, report) = doc.curve_mesh().unwrap();
    assert!(report.subdivided_first);
    // Curve-mesh vertex 2 stands for cage vertex 2; the last ones for the face points.
    let w = VertexId(m.vertex_count() as u32 - 1);
    let (p2, pw) = (m.vertex_position(VertexId(2)), m.vertex_position(w));
    doc.apply(Edit::MoveCurveMeshVertices(vec![(VertexId(2), p2 + DVec3::Z * 0.1), (w, pw - DVec3::X * 0.05)]))
        .unwrap();
    let before = doc.curve_mesh.clone();
    assert!(doc.apply(Edit::MoveVertices(vec![(VertexId(4), DVec3::new(1.2, -0.1, 1.1))])).unwrap());
    assert_eq!(doc.curve_mesh.vertices, before.vertices, "the edited vertex and face point stay");
    let reopened = Document::from_json(&doc.to_json(), Path::new("prism.taut")).unwrap();
    assert_eq!(surface_bits(&reopened), surface_bits(&doc));
}

#[test]
fn the_surface_updates_incrementally_to_the_fresh_build_bit_for_bit_on_any_thread_count() {
    let plain = Document::new(cube()).with_scheme(SchemeKind::CurveMesh);
    let edited = edited_cube();
    let mut cage_moved = edited.clone();
    cage_moved.apply(Edit::MoveVertices(vec![(VertexId(1), DVec3::new(1.2, -0.1, 0.0))])).unwrap();
    let mut surface = surface::build(&plain).unwrap();
    for target in [&edited, &cage_moved, &plain] {
        surface.update(target).unwrap();
        let got = (bits(surface.mesh().positions().iter().copied()), bits(surface.normals().unwrap().iter().copied()));
        assert_eq!(got, surface_bits(target), "an update gives the fresh build's values");
    }
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| surface_bits(&Document::from_json(&edited.to_json(), Path::new("t.taut")).unwrap()))
    };
    assert_eq!(on(1), on(2), "the same surface on one and two threads");
}

/// What zebra stripes show across a curve: the drawn normal at every tessellation vertex on a
/// curve is each neighbouring patch's own exact normal there (evaluated here from the patch's
/// derivatives), so the stripes cannot break at patch boundaries. On the default scene, built and
/// after an edit.
#[test]
fn the_drawn_normals_on_every_curve_are_both_patches_normals() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/default.taut");
    let mut doc = Document::load(&path).unwrap().with_scheme(SchemeKind::CurveMesh);
    let (m, _) = doc.curve_mesh().unwrap();
    let v = VertexId(3);
    doc.apply(Edit::MoveCurveMeshVertices(vec![(v, m.vertex_position(v) + m.vertex_normal(v) * 4.0)])).unwrap();
    doc.apply(Edit::RotateCurveMeshNormal(v, DQuat::from_rotation_x(0.15))).unwrap();
    for doc in [Document::load(&path).unwrap().with_scheme(SchemeKind::CurveMesh), doc] {
        let (m, _) = doc.curve_mesh().unwrap();
        let t = taut_core::gregory::Tessellation::new(&m, 8).unwrap();
        let k = t.samples();
        let (mut checked, mut worst) = (0, 0.0f64);
        for f in m.topology().faces() {
            let patch = m.patch(f);
            for i in 0..=k {
                for j in 0..=k {
                    if i != 0 && i != k && j != 0 && j != k {
                        continue;
                    }
                    let (_, du, dv) = patch.first_derivatives(i as f64 / k as f64, j as f64 / k as f64);
                    let n = du.cross(dv);
                    if n.length() < 1e-12 {
                        continue;
                    }
                    let drawn = t.normals()[t.grid_vertex(&m, f, i, j).index()];
                    worst = worst.max(drawn.angle_between(n));
                    checked += 1;
                }
            }
        }
        assert!(checked > 3 * k * m.patch_count(), "{checked} boundary samples");
        assert!(worst <= 1e-6, "a drawn normal on a curve is {worst} rad off a neighbouring patch's");
    }
}
