//! Tests of the mirror option: exact reflections, plane vertices kept on the plane, partner
//! properties, the mirrored whole's surfaces checked for symmetry by brute-force nearest points
//! (independent of the partner finder), the file key, and refused requests.

use super::*;
use crate::mesh::PolyMesh;
use crate::mesh::primitives::uv_sphere;
use crate::surface::{SchemeKind, solve};
use crate::{DVec3, FaceId};
use glam::DQuat;
use std::path::Path;

fn plane_x() -> MirrorPlane {
    MirrorPlane::new(Axis::X, 0.0)
}

/// The half x ≥ 0 of a UV sphere, with one vertex pushed so no other symmetry hides a mistake.
fn half_sphere() -> PolyMesh {
    let sphere = uv_sphere(8, 6, 1.0).unwrap();
    let left: Vec<FaceId> = sphere
        .faces()
        .filter(|&f| {
            let c: DVec3 = sphere.face_vertices(f).map(|v| sphere.position(v)).sum();
            c.x < 0.0
        })
        .collect();
    let mut half = crate::mesh::edit::delete_faces(&sphere, &left).unwrap().mesh;
    let v = half.vertices().max_by(|&a, &b| half.position(a).x.total_cmp(&half.position(b).x)).unwrap();
    let p = half.position(v);
    half.set_position(v, p + DVec3::new(0.4, 0.1, 0.25));
    half
}

fn half_doc(scheme: SchemeKind) -> Document {
    let mut doc = Document::new(half_sphere()).with_scheme(scheme);
    doc.settings.levels = 2;
    doc.settings.tol = 1e-13;
    doc.settings.max_iterations = 20_000;
    doc.subdiv.levels = 2;
    doc.apply(Edit::SetMirror(Some(plane_x()))).unwrap();
    doc
}

/// A symmetric document: the half sphere made whole.
fn whole_doc() -> Document {
    half_doc(SchemeKind::Nusd).with_mirror_applied().unwrap()
}

/// The largest distance from a point of `mesh` to the nearest point of `mesh` reflected in the
/// plane, found by brute force.
fn asymmetry(mesh: &PolyMesh, plane: MirrorPlane) -> f64 {
    let points = mesh.positions();
    points
        .iter()
        .map(|&p| {
            let q = plane.reflect(p);
            points.iter().map(|&r| r.distance(q)).fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

fn reflected_bits(plane: MirrorPlane, p: DVec3) -> [u64; 3] {
    // Written out here rather than with `MirrorPlane::reflect`: x' = 2·offset − x.
    let mut q = p.to_array();
    let k = match plane.axis {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    };
    q[k] = 2.0 * plane.offset - q[k];
    q.map(f64::to_bits)
}

#[test]
fn edits_of_one_half_mirror_exactly_to_the_other() {
    let mut doc = whole_doc();
    let partners = doc.mirror_partners().unwrap().unwrap();
    let (v, w) = partners
        .iter()
        .enumerate()
        .find_map(|(i, p)| match p {
            MirrorPartner::Partner(w) => Some((VertexId(i as u32), *w)),
            _ => None,
        })
        .unwrap();
    let target = DVec3::new(0.731, -0.2137, 0.4441);
    doc.apply(Edit::MoveVertices(vec![(v, target)])).unwrap();
    assert_eq!(doc.cage.position(v), target);
    assert_eq!(doc.cage.position(w).to_array().map(f64::to_bits), reflected_bits(plane_x(), target));
    // Fixed flags, vertex tension, edge tension and creases reach the partner elements.
    doc.apply(Edit::SetFixed(vec![v], false)).unwrap();
    doc.apply(Edit::SetVertexTension(vec![v], 0.75)).unwrap();
    assert!(!doc.fixed[w.index()] && doc.vertex_tension[w.index()] == 0.75);
    let e = doc.cage.outgoing(v).next().unwrap().edge();
    let (a, b) = doc.cage.edge_vertices(e);
    let image = |x: VertexId| match partners[x.index()] {
        MirrorPartner::Partner(y) => y,
        _ => x,
    };
    let e2 = doc.cage.find_halfedge(image(a), image(b)).unwrap().edge();
    assert_ne!(e, e2);
    doc.apply(Edit::SetEdgeTension(vec![e], 1.5)).unwrap();
    doc.apply(Edit::SetCrease(vec![e], 2.0)).unwrap();
    assert_eq!((doc.edge_tension[e2.index()], doc.crease[e2.index()]), (1.5, 2.0));
    doc.apply(Edit::ResetTension { vertices: vec![w], edges: vec![e2] }).unwrap();
    assert_eq!((doc.vertex_tension[v.index()], doc.edge_tension[e.index()]), (0.0, 0.0));
}

#[test]
fn plane_vertices_stay_on_the_plane_under_moves_rotations_and_scales() {
    for mut doc in [whole_doc(), half_doc(SchemeKind::CatmullClark)] {
        let plane = plane_x();
        let all: Vec<VertexId> = doc.cage.vertices().collect();
        let centre = doc.cage.positions().iter().sum::<DVec3>() / all.len() as f64 + DVec3::new(0.3, 0.1, 0.0);
        let turn = DQuat::from_axis_angle(DVec3::new(0.3, 1.0, 0.2).normalize(), 0.7);
        // G, R and S as the editor sends them: the new positions of the selection.
        let steps: [&dyn Fn(DVec3) -> DVec3; 3] =
            [&|p| p + DVec3::new(0.37, 0.11, -0.2), &|p| centre + turn * (p - centre), &|p| {
                centre + (p - centre) * DVec3::new(1.3, 0.8, 1.1)
            }];
        for step in steps {
            let before = doc.clone();
            let moves = all.iter().map(|&v| (v, step(doc.cage.position(v)))).collect();
            doc.apply(Edit::MoveVertices(moves)).unwrap();
            let partners = before.mirror_partners().unwrap().unwrap();
            for v in doc.cage.vertices() {
                match partners[v.index()] {
                    MirrorPartner::OnPlane => assert_eq!(doc.cage.position(v).x, 0.0, "{v:?} left the plane"),
                    MirrorPartner::Partner(w) => {
                        assert_eq!(doc.cage.position(w), plane.reflect(doc.cage.position(v)), "{v:?} and {w:?}")
                    }
                    MirrorPartner::Unpaired => assert!(doc.cage.position(v).x >= 0.0, "{v:?} crossed the plane"),
                }
            }
        }
        assert!(doc.mirror_halves().is_some());
    }
}

#[test]
fn a_half_moved_across_the_plane_stops_on_it() {
    let mut doc = half_doc(SchemeKind::CatmullClark);
    let v = doc.cage.vertices().find(|&v| doc.cage.position(v).x > 0.5).unwrap();
    let p = doc.cage.position(v);
    doc.apply(Edit::MoveVertices(vec![(v, DVec3::new(-2.0, p.y, p.z))])).unwrap();
    assert_eq!(doc.cage.position(v), DVec3::new(0.0, p.y, p.z));
    assert_eq!(doc.mirror_halves(), Some(MirrorHalves::OneHalf));
}

#[test]
fn surfaces_of_a_mirrored_half_are_symmetric() {
    for scheme in [SchemeKind::Nusd, SchemeKind::CatmullClark] {
        let mut doc = half_doc(scheme);
        // Some moving vertices, tension and a crease, so the surface is not just the cage's.
        let vs: Vec<VertexId> = doc.cage.vertices().filter(|v| v.0 % 3 == 1).collect();
        doc.apply(Edit::SetFixed(vs.clone(), false)).unwrap();
        doc.apply(Edit::SetVertexTension(vs, 0.5)).unwrap();
        doc.apply(Edit::SetCrease(vec![EdgeId(4), EdgeId(9)], 1.5)).unwrap();
        let whole = MirroredWhole::default().whole(&doc).unwrap().expect("one half: a mirrored whole");
        assert_eq!((doc.cage.vertex_count(), whole.cage.vertex_count()), (27, 42), "the 12 plane vertices are shared");
        assert!(whole.cage.is_closed());
        let surface = solve(&whole).unwrap();
        let mesh = surface.mesh();
        let size = mesh.bounding_diagonal();
        let off = asymmetry(mesh, plane_x());
        assert!(off <= 1e-9 * size, "{scheme:?}: the surface is off symmetric by {off:e} of {size}");
        // The whole's first vertices are the half's.
        for v in doc.cage.vertices().filter(|&v| doc.cage.position(v).x > 1e-3) {
            assert_eq!(whole.cage.position(v), doc.cage.position(v));
        }
    }
}

#[test]
fn the_mirrored_whole_keeps_its_connectivity_through_a_drag() {
    let mut doc = half_doc(SchemeKind::Nusd);
    let mut cache = MirroredWhole::default();
    let first = cache.whole(&doc).unwrap().unwrap();
    let v = doc.cage.vertices().find(|&v| doc.cage.position(v).x > 0.5).unwrap();
    doc.apply(Edit::MoveVertices(vec![(v, doc.cage.position(v) + DVec3::Y * 0.1)])).unwrap();
    let moved = cache.whole(&doc).unwrap().unwrap();
    assert_eq!(moved.cage.topology_generation(), first.cage.topology_generation());
    assert_ne!(moved.cage.positions(), first.cage.positions());
    let fresh = MirroredWhole::default().whole(&doc).unwrap().unwrap();
    assert_eq!(moved.cage.positions(), fresh.cage.positions());
    assert_eq!(moved.cage.polygons(), fresh.cage.polygons());
    // A cage with both halves, the curve mesh, or the option off: the document itself.
    assert!(cache.whole(&whole_doc()).unwrap().is_none());
    doc.apply(Edit::SetMirror(None)).unwrap();
    assert!(cache.whole(&doc).unwrap().is_none());
}

#[test]
fn applying_the_mirror_makes_the_half_real() {
    let half = half_doc(SchemeKind::Nusd);
    let mut doc = half.clone();
    let v = VertexId(5);
    doc.apply(Edit::SetVertexTension(vec![v], 0.6)).unwrap();
    let whole = doc.with_mirror_applied().unwrap();
    assert_eq!(whole.mirror, Some(plane_x()));
    assert_eq!(whole.mirror_halves(), Some(MirrorHalves::BothHalves));
    assert!(whole.cage.is_closed());
    assert_eq!(whole.cage.euler_characteristic(), 2);
    let partners = whole.mirror_partners().unwrap().unwrap();
    assert!(partners.iter().all(|p| !matches!(p, MirrorPartner::Unpaired)));
    if let MirrorPartner::Partner(w) = partners[v.index()] {
        assert_eq!(whole.vertex_tension[w.index()], 0.6);
    }
    // Refused: the option off, or a cage with vertices on both sides (a face would cross the plane).
    let cases = [
        (Document::new(half.cage.clone()).with_mirror_applied().err(), "mirror is off"),
        (whole.with_mirror_applied().err(), "both sides"),
    ];
    for (err, expected) in cases {
        let err = err.expect("refused").to_string();
        assert!(err.contains(expected) && !err.contains('\n'), "expected '{expected}' in: {err}");
    }
}

#[test]
fn the_mirror_is_saved_only_when_on() {
    let mut doc = Document::new(half_sphere());
    let plain = doc.to_json();
    assert!(!plain.contains("mirror"));
    doc.apply(Edit::SetMirror(Some(MirrorPlane::new(Axis::Z, 0.1 + 0.2)))).unwrap();
    let text = doc.to_json();
    assert!(text.contains("\"mirror\""), "{text}");
    let back = Document::from_json(&text, Path::new("m.taut")).unwrap();
    assert_eq!(back.mirror.unwrap().offset.to_bits(), (0.1f64 + 0.2).to_bits());
    assert_eq!(back, doc);
    assert_eq!(Document::from_json(&plain, Path::new("p.taut")).unwrap().mirror, None);
    let cases = [
        (text.replace("\"z\"", "\"w\""), "unknown variant"),
        (text.replace("\"offset\"", "\"bogus\": 1, \"offset\""), "unknown field"),
    ];
    for (bad, expected) in cases {
        let err = Document::from_json(&bad, Path::new("bad.taut")).unwrap_err().to_string();
        assert!(err.contains(expected), "expected '{expected}' in: {err}");
    }
    let before = doc.clone();
    let err = doc.apply(Edit::SetMirror(Some(MirrorPlane::new(Axis::X, f64::NAN)))).unwrap_err().to_string();
    assert!(err.contains("finite"), "{err}");
    assert_eq!(doc, before);
}

#[test]
fn unpaired_vertices_of_a_symmetric_cage_are_named() {
    let mut doc = whole_doc();
    let v = doc.cage.vertices().find(|&v| doc.cage.position(v).x > 0.5).unwrap();
    // Moved off its partner's reflection by hand (the option off for a moment).
    doc.apply(Edit::SetMirror(None)).unwrap();
    doc.apply(Edit::MoveVertices(vec![(v, doc.cage.position(v) + DVec3::Z * 0.05)])).unwrap();
    doc.apply(Edit::SetMirror(Some(plane_x()))).unwrap();
    let unpaired = doc.unpaired_vertices(&doc.cage.vertices().collect::<Vec<_>>()).unwrap();
    assert_eq!(unpaired.len(), 2, "{unpaired:?}");
    assert!(unpaired.contains(&v));
    assert!(half_doc(SchemeKind::Nusd).unpaired_vertices(&[VertexId(0)]).unwrap().is_empty());
}

#[test]
fn cached_partners_are_the_ones_found_afresh() {
    let plane = plane_x();
    let mut doc = whole_doc();
    let fresh = |d: &Document| mirror_partners(&d.cage, plane, DEFAULT_MIRROR_TOLERANCE).unwrap();
    for k in 0..4u32 {
        let v = VertexId(3 + 5 * k);
        doc.apply(Edit::MoveVertices(vec![(v, doc.cage.position(v) * 1.1 + DVec3::Y * 0.01)])).unwrap();
        assert_eq!(doc.mirror_partners().unwrap().unwrap(), fresh(&doc), "after move {k}");
    }
    // A half: a vertex clipped onto the plane becomes a plane vertex in the cached answer too.
    let mut half = half_doc(SchemeKind::Nusd);
    let before = half.mirror_partners().unwrap().unwrap();
    let v = half.cage.vertices().find(|&v| half.cage.position(v).x > 0.5).unwrap();
    half.apply(Edit::MoveVertices(vec![(v, DVec3::new(-1.0, 0.0, 0.0))])).unwrap();
    let after = half.mirror_partners().unwrap().unwrap();
    assert_eq!((before[v.index()], after[v.index()]), (MirrorPartner::Unpaired, MirrorPartner::OnPlane));
    assert_eq!(after, fresh(&half));
}

#[test]
fn apply_mirror_as_a_replacement_is_checked_like_apply() {
    let half = half_doc(SchemeKind::Nusd);
    let whole = half.with_mirror_applied().unwrap();
    let mut applied = half.clone();
    assert!(applied.apply(Edit::Replace(Box::new(whole.clone()))).unwrap());
    assert_eq!(half.checked_replacement(Box::new(whole.clone())).unwrap(), Some(applied));
    assert_eq!(half.checked_replacement(Box::new(half.clone())).unwrap(), None, "no change");
    // A NUSD whole with nothing fixed would collapse: refused, as `apply` refuses it.
    let mut loose = whole;
    loose.fixed.iter_mut().for_each(|f| *f = false);
    let err = half.checked_replacement(Box::new(loose.clone())).unwrap_err().to_string();
    assert!(err.starts_with("refused") && !err.contains('\n'), "{err}");
    assert_eq!(half.clone().apply(Edit::Replace(Box::new(loose))).unwrap_err().to_string(), err);
}
