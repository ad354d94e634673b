//! The NUSD warm start after a topology edit (issue 22): the levels of the edited cage start
//! from the solved levels of the cage before, through the edit's provenance, and are re-solved
//! around the edit. References: cold solves of the edited document (the fixed point run to
//! 1e-12, and the default solve), and the old solve itself for the vertices the edit leaves.

#[path = "common/warm.rs"]
mod warm;

use std::collections::HashMap;
use taut_core::document::modelling::MeshEdit;
use taut_core::mesh::primitives::torus;
use taut_core::nusd::surface::SurfaceSolver;
use taut_core::{DVec3, Document, Edit, PolyMesh, VertexId};
use warm::{assert_warm_cheaper, exact, key, max_distance, solved};

/// A torus cage of 40 × 12 quads made uneven (a bulge and a twist), so no symmetry helps.
fn uneven_torus() -> PolyMesh {
    let mut cage = torus(40, 12, 1.0, 0.35).unwrap();
    for v in 0..cage.vertex_count() as u32 {
        let p = cage.position(VertexId(v));
        let bulge = 1.0 + 0.2 * (3.0 * p.y.atan2(p.x)).sin();
        cage.set_position(VertexId(v), DVec3::new(p.x * bulge, p.y, p.z * (1.0 + 0.3 * p.x)));
    }
    cage
}

fn base() -> Document {
    let mut doc = Document::new(uneven_torus());
    doc.settings.levels = 3;
    doc
}

/// The edits of the issue, each local to a part of the cage: extrude a face, cut a loop round
/// the tube, delete a vertex (which opens a hole: the new boundary is solved as a polyline).
fn local_edits(doc: &Document) -> Vec<(&'static str, MeshEdit)> {
    let across = doc.cage.find_halfedge(VertexId(0), VertexId(12)).unwrap().edge();
    vec![
        ("extrude", MeshEdit::ExtrudeFaces { faces: vec![100], distance: 0.05 }),
        ("loop cut round the tube", MeshEdit::LoopCut { edge: across.0, fraction: 0.5 }),
        ("delete", MeshEdit::DeleteVertices { vertices: vec![40] }),
    ]
}

/// The local edits and a loop cut round the hole, whose neighbourhood is most of this cage (the
/// levels are then re-solved whole from the warm start).
fn edits(doc: &Document) -> Vec<(&'static str, MeshEdit)> {
    let along = doc.cage.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge();
    let mut all = local_edits(doc);
    all.push(("loop cut round the hole", MeshEdit::LoopCut { edge: along.0, fraction: 0.3 }));
    all
}

fn edited(doc: &Document, op: &MeshEdit) -> Document {
    let mut after = doc.clone();
    assert!(after.apply(Edit::Mesh(op.clone())).unwrap());
    assert!(after.lineage().is_some(), "a modelling edit keeps its provenance with the document");
    after
}

#[test]
fn warm_and_cold_solves_of_an_edited_cage_land_on_the_same_fixed_point() {
    let doc = base();
    let before = solved(&doc);
    for (name, op) in edits(&doc) {
        let after = edited(&doc, &op);
        let mut warm = before.clone();
        warm.update(&after).unwrap();
        assert_eq!(warm.inherited_levels(), 4, "{name}: the warm start took every level");
        warm.solve().unwrap();
        let cold = solved(&after);
        let status = warm.status();
        assert!(status.converged(warm.reports()), "{name}: {:?}", warm.reports());
        assert!(status.remaining < status.threshold, "{name}: {status:?}");
        let reference = exact(&after);
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
}

#[test]
fn the_warm_start_takes_far_fewer_sweeps_than_a_cold_solve() {
    // The load of the issue and of `benches/topology_edit.rs`: a 2,048-face torus at level 2.
    let mut doc = Document::new(torus(64, 32, 2.0, 0.7).unwrap());
    doc.settings.levels = 2;
    let before = solved(&doc);
    let edge = doc.cage.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge();
    for (name, op, bound) in [
        ("extrude", MeshEdit::ExtrudeFaces { faces: vec![100], distance: 0.05 }, 0.1),
        // The cut runs round the hole: its neighbourhood is a band of the whole torus.
        ("loop cut", MeshEdit::LoopCut { edge: edge.0, fraction: 0.5 }, 0.4),
        ("delete", MeshEdit::DeleteVertices { vertices: vec![40] }, 0.1),
    ] {
        let after = edited(&doc, &op);
        let mut warm = before.clone();
        warm.update(&after).unwrap();
        warm.solve().unwrap();
        let cold = solved(&after);
        assert_warm_cheaper(name, &warm, &cold, bound);
    }
}

#[test]
fn vertices_far_from_the_edit_start_exactly_where_they_were_solved() {
    let doc = base();
    let before = solved(&doc);
    let diagonal = doc.cage.bounding_diagonal();
    for (name, op) in local_edits(&doc) {
        let after = edited(&doc, &op);
        // Where the cage changed: new cage vertices that are not old ones at the same place, and
        // old ones that are gone.
        let old_points: HashMap<[u64; 3], ()> = doc.cage.positions().iter().map(|&p| (key(p), ())).collect();
        let new_points: HashMap<[u64; 3], ()> = after.cage.positions().iter().map(|&p| (key(p), ())).collect();
        let mut edit_points: Vec<DVec3> =
            after.cage.positions().iter().copied().filter(|&p| !old_points.contains_key(&key(p))).collect();
        edit_points.extend(doc.cage.positions().iter().copied().filter(|&p| !new_points.contains_key(&key(p))));
        assert!(!edit_points.is_empty());
        let far = |p: DVec3| edit_points.iter().all(|&q| (p - q).length() > 0.25 * diagonal);
        let mut warm = before.clone();
        warm.update(&after).unwrap();
        for level in 1..=3 {
            // A vertex is matched to its old self by its domain point (the refined cage, unsmoothed),
            // independently of how the solver names survivors.
            let old_domain = before.level_topology(level).unwrap().mesh.positions();
            let old_index: HashMap<[u64; 3], usize> =
                old_domain.iter().enumerate().map(|(i, &p)| (key(p), i)).collect();
            let old_solved = before.level_surface(level).unwrap();
            let start = warm.level_surface(level).unwrap();
            let new_domain = warm.level_topology(level).unwrap().mesh.positions();
            let (mut checked, mut total) = (0, 0);
            for (v, &d) in new_domain.iter().enumerate() {
                total += 1;
                let Some(&o) = old_index.get(&key(d)) else { continue };
                if !far(d) {
                    continue;
                }
                checked += 1;
                let (now, was) = (start.positions()[v], old_solved.positions()[o]);
                assert_eq!(key(now), key(was), "{name}, level {level}: vertex {v} (old {o}) starts at {now} not {was}");
            }
            assert!(checked * 2 > total, "{name}, level {level}: only {checked} of {total} vertices checked");
        }
    }
}

#[test]
fn the_warm_start_gives_the_same_bits_on_any_number_of_threads() {
    let doc = base();
    let before = solved(&doc);
    let (_, op) = local_edits(&doc).swap_remove(1);
    let after = edited(&doc, &op);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut warm = before.clone();
            warm.update(&after).unwrap();
            warm.solve().unwrap();
            warm.surface_positions().iter().map(|&p| key(p)).collect::<Vec<_>>()
        })
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn an_edit_of_another_cage_or_an_unfinished_solve_is_handled_honestly() {
    let doc = base();
    let (_, op) = local_edits(&doc).swap_remove(0);
    let after = edited(&doc, &op);
    // A solver of another cage (same connectivity, built separately) has nothing to carry: cold.
    let mut stranger = solved(&base());
    stranger.update(&after).unwrap();
    assert_eq!(stranger.inherited_levels(), 0);
    // An unfinished solve is carried but solved whole, and still lands on the fixed point.
    let mut partial = SurfaceSolver::new(&doc).unwrap();
    partial.advance(taut_core::nusd::surface::Budget::iterations(40));
    partial.update(&after).unwrap();
    assert!(partial.inherited_levels() >= 1);
    partial.solve().unwrap();
    let threshold = partial.status().threshold;
    let error = max_distance(partial.surface_positions(), &exact(&after));
    assert!(error < threshold, "{error:e} from the fixed point (threshold {threshold:e})");
}

#[test]
fn the_surface_seam_the_editor_uses_warm_starts_after_a_modelling_edit() {
    use taut_core::surface::nusd::NusdSurface;
    use taut_core::surface::{Budget, SurfaceScheme};
    // As the editor's frame loop does it: the document takes the edit, the shown surface takes
    // the new document (`SurfaceScheme::update`) and advances.
    let mut doc = base();
    let mut surface = NusdSurface::new(&doc).unwrap();
    surface.advance(Budget::UNLIMITED);
    let (_, op) = local_edits(&doc).swap_remove(0);
    let before = doc.clone();
    doc.apply(Edit::Mesh(op)).unwrap();
    surface.update(&doc).unwrap();
    assert_eq!(surface.solver().inherited_levels(), 4);
    assert!(surface.advance(Budget::UNLIMITED).converged);
    // Undo (the document before, whose cage the solver no longer has): a cold start, not a
    // wrong warm one.
    surface.update(&before).unwrap();
    assert_eq!(surface.solver().inherited_levels(), 0);
}
