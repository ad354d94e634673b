//! The NUSD warm start after a topology edit with the mirror option on: the designer edits one
//! half, the solver sees the mirrored whole (`MirroredWhole`), and the whole made after the edit
//! carries its lineage from the whole before (composed through the half's edit), so its levels
//! start from the old ones on both halves and are re-solved around the edit and its image, as
//! without the mirror (`nusd_topology_warm.rs`). References: cold solves of the new whole (the
//! fixed point run to 1e-12, and the default solve), and the old solve for what the edit leaves.

#[path = "common/warm.rs"]
mod warm;

use std::collections::HashMap;
use taut_core::document::modelling::MeshEdit;
use taut_core::document::symmetry::{MirrorHalves, MirroredWhole};
use taut_core::mesh::edit::{Axis, MirrorPlane, delete_vertices};
use taut_core::mesh::primitives::torus;
use taut_core::nusd::surface::SurfaceSolver;
use taut_core::{DVec3, Document, EdgeId, Edit, VertexId};
use warm::{assert_warm_cheaper, exact, key, max_distance, solved};

/// The half x ≥ 0 of a torus of `nu` × `nv` quads about the z axis (its two cut rings lie in the
/// plane x = 0, the seam), with the mirror on across that plane; `uneven` bulges and shears it
/// (kept symmetric by the mirror, but with no other symmetry).
fn half_torus(nu: u32, nv: u32, major: f64, minor: f64, uneven: bool) -> Document {
    let mut cage = torus(nu, nv, major, minor).unwrap();
    if uneven {
        for v in 0..cage.vertex_count() as u32 {
            let p = cage.position(VertexId(v));
            let bulge = 1.0 + 0.2 * (3.0 * p.y.atan2(p.x)).sin();
            cage.set_position(VertexId(v), DVec3::new(p.x * bulge, p.y, p.z * (1.0 + 0.3 * p.x)));
        }
    }
    let other_side: Vec<VertexId> = cage.vertices().filter(|&v| cage.position(v).x < -1e-9).collect();
    let mut doc = Document::new(delete_vertices(&cage, &other_side).unwrap().mesh);
    doc.apply(Edit::SetMirror(Some(MirrorPlane::new(Axis::X, 0.0)))).unwrap();
    assert_eq!(doc.mirror_halves(), Some(MirrorHalves::OneHalf));
    doc
}

fn base() -> Document {
    let mut doc = half_torus(40, 12, 1.0, 0.35, true);
    doc.settings.levels = 3;
    doc
}

/// The half's vertex nearest `p`.
fn nearest(doc: &Document, p: DVec3) -> VertexId {
    doc.cage
        .vertices()
        .min_by(|&a, &b| doc.cage.position(a).distance(p).total_cmp(&doc.cage.position(b).distance(p)))
        .unwrap()
}

fn edge(doc: &Document, a: VertexId, b: VertexId) -> EdgeId {
    doc.cage.find_halfedge(a, b).unwrap().edge()
}

/// On the half, away from the seam: the edges of the outermost vertex at angle 0 round the hole
/// (`along`, to its neighbour round the tube) and round the tube (`across`, to the next ring).
fn edges_at_angle_zero(doc: &Document) -> (EdgeId, EdgeId) {
    let v = nearest(doc, DVec3::new(10.0, 0.0, 0.0));
    let p = doc.cage.position(v);
    let ring = |w: VertexId| (doc.cage.position(w).y.atan2(doc.cage.position(w).x) - p.y.atan2(p.x)).abs() < 1e-9;
    let neighbours: Vec<VertexId> = doc.cage.outgoing(v).map(|h| doc.cage.to_vertex(h)).collect();
    let along = *neighbours.iter().find(|&&w| ring(w)).unwrap();
    let across = *neighbours.iter().find(|&&w| !ring(w)).unwrap();
    (edge(doc, v, along), edge(doc, v, across))
}

/// The edits of `nusd_topology_warm.rs` on the half, away from the seam (their images are edited
/// too): extrude a face, cut a loop round the tube, delete a vertex (a hole on each half).
fn local_edits(doc: &Document) -> Vec<(&'static str, Edit)> {
    let top = nearest(doc, DVec3::new(0.35, 0.95, 0.4));
    let face = doc.cage.outgoing(top).map(|h| doc.cage.face(h)).find(|f| f.is_valid()).unwrap();
    let (_, across) = edges_at_angle_zero(doc);
    let gone = nearest(doc, DVec3::new(0.8, 0.4, 0.3));
    vec![
        ("extrude", Edit::Mesh(MeshEdit::ExtrudeFaces { faces: vec![face.0], distance: 0.05 })),
        ("loop cut round the tube", Edit::Mesh(MeshEdit::LoopCut { edge: across.0, fraction: 0.5 })),
        ("delete", Edit::Mesh(MeshEdit::DeleteVertices { vertices: vec![gone.0] })),
    ]
}

/// The local edits and a loop cut round the hole (it runs from seam to seam: new vertices on the
/// seam's edges, in the plane).
fn edits(doc: &Document) -> Vec<(&'static str, Edit)> {
    let (along, _) = edges_at_angle_zero(doc);
    let mut all = local_edits(doc);
    all.push(("loop cut round the hole", Edit::Mesh(MeshEdit::LoopCut { edge: along.0, fraction: 0.3 })));
    all
}

/// The half edited, and its mirrored whole from `cache` (which made the whole before the edit).
fn edited(doc: &Document, edit: &Edit, cache: &mut MirroredWhole) -> (Document, Document) {
    let mut after = doc.clone();
    assert!(after.apply(edit.clone()).unwrap());
    assert_eq!(after.mirror_halves(), Some(MirrorHalves::OneHalf));
    let whole = cache.whole(&after).unwrap().expect("one half: a mirrored whole");
    assert!(whole.lineage().is_some(), "{edit:?}: the new whole keeps its lineage from the whole before");
    (after, whole)
}

/// A half, the cache that made its whole, and the whole.
fn mirrored(doc: &Document) -> (MirroredWhole, Document) {
    let mut cache = MirroredWhole::default();
    let whole = cache.whole(doc).unwrap().expect("one half: a mirrored whole");
    (cache, whole)
}

#[test]
fn warm_and_cold_solves_of_an_edited_half_land_on_the_same_fixed_point() {
    let doc = base();
    let (cache, whole) = mirrored(&doc);
    let before = solved(&whole);
    for (name, edit) in edits(&doc) {
        let (_, after) = edited(&doc, &edit, &mut cache.clone());
        let mut warm = before.clone();
        warm.update(&after).unwrap();
        assert_eq!(warm.inherited_levels(), 4, "{name}: the warm start took every level");
        check_against_cold(name, &mut warm, &after);
    }
}

/// Solves `warm` on, and checks it lands where cold solves of `after` do (within the threshold).
fn check_against_cold(name: &str, warm: &mut SurfaceSolver, after: &Document) {
    warm.solve().unwrap();
    let cold = solved(after);
    let status = warm.status();
    assert!(status.converged(warm.reports()), "{name}: {:?}", warm.reports());
    assert!(status.remaining < status.threshold, "{name}: {status:?}");
    let reference = exact(after);
    let (warm_error, cold_error) =
        (max_distance(warm.surface_positions(), &reference), max_distance(cold.surface_positions(), &reference));
    assert!(
        warm_error < status.threshold,
        "{name}: warm start {warm_error:e} from the fixed point (threshold {:e}; cold {cold_error:e})",
        status.threshold
    );
    assert!(
        max_distance(warm.surface_positions(), cold.surface_positions()) < status.threshold,
        "{name}: warm and cold solves differ by more than the threshold"
    );
}

#[test]
fn a_vertex_dragged_onto_the_plane_warm_starts_the_whole_it_reconnects() {
    // A hole beside the seam (a vertex of the ring next to it deleted), then a vertex of its rim
    // dragged across the plane: it stops on the plane (clipping) and is glued to the seam there, so
    // the whole's connectivity changes while the half's does not.
    let doc = base();
    let (mut cache, whole) = mirrored(&doc);
    let gone = nearest(&doc, DVec3::new(0.17, 1.33, 0.0));
    let (holed, holed_whole) =
        edited(&doc, &Edit::Mesh(MeshEdit::DeleteVertices { vertices: vec![gone.0] }), &mut cache);
    let mut solver = solved(&whole);
    solver.update(&holed_whole).unwrap();
    solver.solve().unwrap();
    let on_plane = |v: VertexId| holed.cage.position(v).x.abs() < 1e-9;
    let rim = holed
        .cage
        .vertices()
        .find(|&v| {
            !on_plane(v)
                && holed
                    .cage
                    .outgoing(v)
                    .any(|h| holed.cage.is_boundary_edge(h.edge()) && on_plane(holed.cage.to_vertex(h)))
        })
        .unwrap();
    let p = holed.cage.position(rim);
    let drag = Edit::MoveVertices(vec![(rim, DVec3::new(-0.1, p.y, p.z))]);
    let (dragged, after) = edited(&holed, &drag, &mut cache);
    assert_eq!(dragged.cage.topology_generation(), holed.cage.topology_generation());
    assert_eq!(dragged.cage.position(rim).x, 0.0, "clipped to the plane");
    assert_eq!(after.cage.vertex_count() + 1, holed_whole.cage.vertex_count(), "its image is gone");
    let mut warm = solver.clone();
    warm.update(&after).unwrap();
    assert_eq!(warm.inherited_levels(), 4);
    check_against_cold("a vertex dragged onto the plane", &mut warm, &after);
}

#[test]
fn the_warm_start_takes_far_fewer_sweeps_than_a_cold_solve() {
    // The load of `nusd_topology_warm.rs` and `benches/topology_edit.rs`, made of two halves: a
    // 2,048-face torus at level 2.
    let mut doc = half_torus(64, 32, 2.0, 0.7, false);
    doc.settings.levels = 2;
    let (cache, whole) = mirrored(&doc);
    assert_eq!(whole.cage.face_count(), 2048);
    let before = solved(&whole);
    let (along, _) = edges_at_angle_zero(&doc);
    // Where face 100 and vertex 40 of the whole torus are in `nusd_topology_warm.rs`.
    let corner = nearest(&doc, DVec3::new(2.39, 0.73, 0.49));
    let face = doc.cage.outgoing(corner).map(|h| doc.cage.face(h)).find(|f| f.is_valid()).unwrap();
    let gone = nearest(&doc, DVec3::new(1.99, 0.2, 0.7));
    for (name, op, bound) in [
        ("extrude", MeshEdit::ExtrudeFaces { faces: vec![face.0], distance: 0.05 }, 0.1),
        // The cut runs round the hole, from seam to seam and on round the image: a band of the
        // whole torus.
        ("loop cut", MeshEdit::LoopCut { edge: along.0, fraction: 0.5 }, 0.4),
        ("delete", MeshEdit::DeleteVertices { vertices: vec![gone.0] }, 0.1),
    ] {
        let (_, after) = edited(&doc, &Edit::Mesh(op), &mut cache.clone());
        let mut warm = before.clone();
        warm.update(&after).unwrap();
        warm.solve().unwrap();
        let cold = solved(&after);
        assert_warm_cheaper(name, &warm, &cold, bound);
    }
}

#[test]
fn vertices_far_from_the_edit_start_exactly_where_they_were_solved_on_both_halves() {
    let doc = base();
    let (cache, whole) = mirrored(&doc);
    let before = solved(&whole);
    let diagonal = whole.cage.bounding_diagonal();
    for (name, edit) in local_edits(&doc) {
        let (_, after) = edited(&doc, &edit, &mut cache.clone());
        // Where the whole changed (the edit and its image): new cage points that are not old ones,
        // and old ones that are gone.
        let old_points: HashMap<[u64; 3], ()> = whole.cage.positions().iter().map(|&p| (key(p), ())).collect();
        let new_points: HashMap<[u64; 3], ()> = after.cage.positions().iter().map(|&p| (key(p), ())).collect();
        let mut edit_points: Vec<DVec3> =
            after.cage.positions().iter().copied().filter(|&p| !old_points.contains_key(&key(p))).collect();
        edit_points.extend(whole.cage.positions().iter().copied().filter(|&p| !new_points.contains_key(&key(p))));
        assert!(edit_points.iter().any(|p| p.x > 0.0) && edit_points.iter().any(|p| p.x < 0.0));
        let far = |p: DVec3| edit_points.iter().all(|&q| (p - q).length() > 0.25 * diagonal);
        let mut warm = before.clone();
        warm.update(&after).unwrap();
        for level in 1..=3 {
            // A vertex is matched to its old self by its domain point (the refined cage, unsmoothed),
            // independently of how the lineage names survivors.
            let old_domain = before.level_topology(level).unwrap().mesh.positions();
            let old_index: HashMap<[u64; 3], usize> =
                old_domain.iter().enumerate().map(|(i, &p)| (key(p), i)).collect();
            let old_solved = before.level_surface(level).unwrap();
            let start = warm.level_surface(level).unwrap();
            let new_domain = warm.level_topology(level).unwrap().mesh.positions();
            // Per half (x > 0, x < 0): vertices checked, and all.
            let (mut checked, mut total) = ([0; 2], [0; 2]);
            for (v, &d) in new_domain.iter().enumerate() {
                if d.x == 0.0 {
                    continue; // on the seam: neither half's alone
                }
                let side = usize::from(d.x < 0.0);
                total[side] += 1;
                let Some(&o) = old_index.get(&key(d)) else { continue };
                if !far(d) {
                    continue;
                }
                checked[side] += 1;
                let (now, was) = (start.positions()[v], old_solved.positions()[o]);
                assert_eq!(key(now), key(was), "{name}, level {level}: vertex {v} (old {o}) starts at {now} not {was}");
            }
            // Twice the edits of `nusd_topology_warm.rs` on a torus of the same size: a fifth of
            // each half is far from both.
            for side in 0..2 {
                assert!(
                    checked[side] * 5 > total[side],
                    "{name}, level {level}, side {side}: only {} of {} vertices checked",
                    checked[side],
                    total[side]
                );
            }
        }
    }
}

#[test]
fn the_warm_start_gives_the_same_bits_on_any_number_of_threads() {
    let doc = base();
    let (cache, whole) = mirrored(&doc);
    let before = solved(&whole);
    let (_, edit) = local_edits(&doc).swap_remove(1);
    let (_, after) = edited(&doc, &edit, &mut cache.clone());
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut warm = before.clone();
            warm.update(&after).unwrap();
            assert_eq!(warm.inherited_levels(), 4);
            warm.solve().unwrap();
            warm.surface_positions().iter().map(|&p| key(p)).collect::<Vec<_>>()
        })
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn the_surface_seam_the_editor_uses_warm_starts_and_an_undo_starts_cold() {
    use taut_core::surface::nusd::NusdSurface;
    use taut_core::surface::{Budget, SurfaceScheme};
    // As the editor's frame loop does it: the half takes the edit, the mirrored whole is made of
    // it by the one cache the editor keeps, and the shown surface takes the whole and advances.
    let mut doc = base();
    let mut cache = MirroredWhole::default();
    let mut surface = NusdSurface::new(&cache.whole(&doc).unwrap().unwrap()).unwrap();
    surface.advance(Budget::UNLIMITED);
    let before = doc.clone();
    for (name, edit) in local_edits(&before) {
        doc.apply(edit).unwrap();
        surface.update(&cache.whole(&doc).unwrap().unwrap()).unwrap();
        assert_eq!(surface.solver().inherited_levels(), 4, "{name}");
        assert!(surface.advance(Budget::UNLIMITED).converged, "{name}");
        // Undo (the half before, whose whole the solver no longer has): a cold start, not a wrong
        // warm one; and the redo after it warm again, from the undone whole.
        let edited = std::mem::replace(&mut doc, before.clone());
        surface.update(&cache.whole(&doc).unwrap().unwrap()).unwrap();
        assert_eq!(surface.solver().inherited_levels(), 0, "{name}: undo");
        assert!(surface.advance(Budget::UNLIMITED).converged, "{name}");
        surface.update(&cache.whole(&edited).unwrap().unwrap()).unwrap();
        assert_eq!(surface.solver().inherited_levels(), 4, "{name}: redo");
        assert!(surface.advance(Budget::UNLIMITED).converged, "{name}");
        // Back to the half before, for the next edit.
        surface.update(&cache.whole(&doc).unwrap().unwrap()).unwrap();
        surface.advance(Budget::UNLIMITED);
    }
}
