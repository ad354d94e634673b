//! Merging regular regions: the merged faces are the same surface (checked against the unmerged
//! fit at every patch's own parameters), the B-rep stays one closed, consistently oriented shell,
//! and a face that is not C² with its neighbours stays alone.

use super::*;
use crate::cad::fit;
use crate::cad::network::PatchNetwork;
use crate::document::Document;
use crate::mesh::primitives;
use crate::surface::SchemeKind;

fn torus_network() -> PatchNetwork {
    let cage = primitives::torus(8, 6, 2.0, 0.7).unwrap();
    let doc = Document::new(cage).with_scheme(SchemeKind::CatmullClark);
    crate::cad::catmull_clark_network(&doc, 0, 3).unwrap()
}

fn fitted(net: &PatchNetwork) -> BrepModel {
    fit::fit(net, 1e-4 * diagonal(net.layout.positions())).unwrap().0
}

/// Largest distance between the unmerged faces and the merged ones at each patch's own (u, v).
fn moved(before: &BrepModel, after: &BrepModel, placements: &[Placement]) -> f64 {
    let mut worst: f64 = 0.0;
    for (f, place) in placements.iter().enumerate() {
        let own = &before.faces[f].surface;
        let merged = &after.faces[place.face].surface;
        for p in 0..=8 {
            for q in 0..=8 {
                let (u, v) = (p as f64 / 8.0, q as f64 / 8.0);
                let (mu, mv) = place.map(u, v);
                worst = worst.max((evaluate(own, u, v) - evaluate(merged, mu, mv)).length());
            }
        }
    }
    worst
}

fn evaluate(s: &BSplineSurface, u: f64, v: f64) -> DVec3 {
    let knots = |k: &[f64]| Knots::from_breaks(k.to_vec());
    bspline::surface_point(&knots(&s.knots_u), &knots(&s.knots_v), &s.points, u, v).0
}

/// Every edge used by exactly two face sides running opposite ways, and every loop closed.
fn assert_closed_and_oriented(model: &BrepModel) {
    let mut uses = vec![(0, 0); model.edges.len()];
    for face in &model.faces {
        for (k, &(e, forward)) in face.outer.iter().enumerate() {
            if forward {
                uses[e].0 += 1
            } else {
                uses[e].1 += 1
            }
            let end = |(e, forward): (usize, bool)| if forward { model.edges[e].end } else { model.edges[e].start };
            let start = |(e, forward): (usize, bool)| if forward { model.edges[e].start } else { model.edges[e].end };
            let next = face.outer[(k + 1) % face.outer.len()];
            assert_eq!(end((e, forward)), start(next), "the loop is a chain");
        }
    }
    assert!(uses.iter().all(|&u| u == (1, 1)), "every edge once each way: {uses:?}");
    let referenced = model.edges.iter().flat_map(|e| [e.start, e.end]).collect::<std::collections::BTreeSet<_>>();
    assert_eq!(referenced.len(), model.vertices.len(), "no vertex left without an edge");
    assert_edges_lie_where_their_faces_say(model);
}

/// Every edge curve starts and ends at its vertices and is, with its own parameter, the face's
/// surface along the straight line `outer_uv` gives (the `PCURVE` the file carries).
fn assert_edges_lie_where_their_faces_say(model: &BrepModel) {
    let size = diagonal(&model.vertices);
    for (f, face) in model.faces.iter().enumerate() {
        assert_eq!(face.outer_uv.len(), face.outer.len(), "face {f}: every edge placed");
        for (&(e, _), &[a, b]) in face.outer.iter().zip(&face.outer_uv) {
            let edge = &model.edges[e];
            let knots = Knots::from_breaks(edge.curve.knots.clone());
            let points = &edge.curve.points;
            assert!(points[0].distance(model.vertices[edge.start]) <= 1e-12 * size);
            assert!(points[points.len() - 1].distance(model.vertices[edge.end]) <= 1e-12 * size);
            let (first, last) = (edge.curve.knots[0], edge.curve.knots[edge.curve.knots.len() - 1]);
            for k in 0..=16 {
                let s = k as f64 / 16.0;
                let on_curve = bspline::curve_point(&knots, points, first + s * (last - first));
                let (u, v) = (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]));
                let on_face = evaluate(&face.surface, u, v);
                let apart = on_curve.distance(on_face);
                assert!(apart <= 1e-9 * size, "face {f}, edge {e} at {s}: {apart} off the face");
            }
        }
    }
}

#[test]
fn nusd_edges_meet_their_vertices_and_lie_on_their_faces() {
    // A pentagonal prism: patches of level 1, whose corners move as the levels are solved.
    let ring = |y: f64| (0..5).map(move |k| DVec3::new((k as f64 * 1.2566).cos(), y, (k as f64 * 1.2566).sin()));
    let polygons: Vec<Vec<u32>> = [vec![4, 3, 2, 1, 0], vec![5, 6, 7, 8, 9]]
        .into_iter()
        .chain((0..5).map(|k| vec![k, (k + 1) % 5, (k + 1) % 5 + 5, k + 5]))
        .collect();
    let cage = crate::mesh::PolyMesh::from_polygons(ring(0.0).chain(ring(1.0)).collect(), &polygons).unwrap();
    let doc = Document::new(cage).with_scheme(SchemeKind::Nusd);
    let (net, _) = crate::cad::nusd_network(&doc, 1, 4).unwrap();
    assert_edges_lie_where_their_faces_say(&fitted(&net));
}

#[test]
fn a_regular_torus_becomes_a_few_large_faces_of_the_same_surface() {
    let net = torus_network();
    let before = fitted(&net);
    assert_eq!(before.faces.len(), 48);
    let (after, placements) = merge_regular(before.clone(), &net.layout, &net.sharp);
    // A ring of the torus may not close on itself: at most 7 × 5 patches a face.
    assert!(after.faces.len() < 10, "{} faces", after.faces.len());
    assert!(after.faces.iter().any(|f| f.surface.knots_u.len() > 2), "some face spans several patches");
    assert!(moved(&before, &after, &placements) <= EXACT * 10.0, "the surface moved");
    assert_closed_and_oriented(&after);
    assert_eq!(after.shells.len(), 1);
    assert_eq!(after.shells[0].faces, (0..after.faces.len()).collect::<Vec<_>>());
    // The merged faces keep the simple knots of a C² B-spline, one span a patch.
    for face in &after.faces {
        let s = &face.surface;
        assert!(s.multiplicities_u[1..s.multiplicities_u.len() - 1].iter().all(|&m| m == 1));
        assert_eq!(s.points.len(), s.knots_u.len() + 2);
        assert_eq!(s.points[0].len(), s.knots_v.len() + 2);
    }
}

#[test]
fn a_face_that_is_not_c2_with_its_neighbours_stays_alone() {
    let net = torus_network();
    let mut before = fitted(&net);
    // Move one inner control point of face 9 off the common spline: still one span, no longer C².
    before.faces[9].surface.points[1][2] += DVec3::new(0.0, 0.0, 1e-6);
    let (after, placements) = merge_regular(before.clone(), &net.layout, &net.sharp);
    assert_eq!(placements[9], Placement::alone(placements[9].face));
    assert!(placements.iter().filter(|p| p.face == placements[9].face).count() == 1);
    assert!(moved(&before, &after, &placements) <= EXACT * 10.0, "the surface moved");
    assert_closed_and_oriented(&after);
}

#[test]
fn faces_at_extraordinary_vertices_and_the_turned_solid_are_kept_as_they_are() {
    // A cube: every corner extraordinary, every face graded, nothing to merge.
    let doc = Document::new(crate::mesh::edit::fixtures::cube()).with_scheme(SchemeKind::CatmullClark);
    let net = crate::cad::catmull_clark_network(&doc, 0, 3).unwrap();
    let before = fitted(&net);
    let (after, placements) = merge_regular(before.clone(), &net.layout, &net.sharp);
    assert_eq!(after, before);
    assert!(placements.iter().enumerate().all(|(f, p)| *p == Placement::alone(f)));
    // A torus turned inside out: the merged loops run the other way with their faces.
    let net = torus_network();
    let mut before = fitted(&net);
    for face in &mut before.faces {
        face.same_sense = false;
        face.outer.reverse();
        face.outer_uv.reverse();
        for entry in &mut face.outer {
            entry.1 = !entry.1;
        }
    }
    let (after, _) = merge_regular(before, &net.layout, &net.sharp);
    assert!(after.faces.len() < 10 && after.faces.iter().all(|f| !f.same_sense));
    assert_closed_and_oriented(&after);
}
