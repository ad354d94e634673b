//! Editing a curve mesh (`taut_core::gregory::curve_mesh`) and tessellating it: locality bit
//! for bit, the edit state through JSON and back, undo, refused edits, G1 after arbitrary
//! edits, crack-free tessellation and its exact update, one and two threads.

mod common;

use common::{faces_around, mixed_cage, same_patch};
use taut_core::gregory::continuity::side_point;
use taut_core::gregory::curve_mesh::{CurveEdit, CurveMeshEdits};
use taut_core::gregory::{CurveMesh, SurfacePatch, Tessellation};
use taut_core::{DVec3, EdgeId, FaceId, VertexId};

#[test]
fn an_edit_changes_only_the_patches_that_touch_it_bit_for_bit() {
    let cage = mixed_cage();
    let (fresh, _) = CurveMesh::from_cage(&cage).unwrap();
    let mut mesh = fresh.clone();
    let t = fresh.topology().clone();
    let size = cage.bounding_diagonal();
    // Vertices of valence 3, 5 and 6 and one made by the Catmull–Clark step.
    let apex = VertexId(10);
    let picks: Vec<VertexId> = [VertexId(3), apex, VertexId(6), VertexId(20)].into_iter().collect();
    assert_eq!(picks.iter().map(|&v| t.valence(v)).take(3).collect::<Vec<_>>(), vec![3, 5, 6]);
    let mut states = Vec::new();
    for (k, &v) in picks.iter().enumerate() {
        let before = mesh.patches().to_vec();
        let target = mesh.vertex_position(v) + 0.03 * size * DVec3::new(1.0, -0.5, 0.7 - k as f64 * 0.3);
        let changed = mesh.move_vertex(v, target).unwrap();
        let around = faces_around(&t, v);
        assert_eq!(changed.patches, around, "vertex {v:?}");
        assert_eq!(changed.vertices, vec![v]);
        for f in t.faces() {
            let same = same_patch(&before[f.index()], mesh.patch(f));
            assert_eq!(same, !around.contains(&f), "patch {f:?} after moving {v:?}");
        }
        assert_eq!(mesh.vertex_position(v), target);
        // The tangent plane moved with the vertex: its legs are still in it.
        for h in t.outgoing(v) {
            let leg = mesh.curve_along(h).points[1] - target;
            assert!(leg.dot(mesh.vertex_normal(v)).abs() < 1e-12 * size);
        }
        states.push((mesh.edits(), mesh.patches().to_vec()));
    }
    // Turn a tangent plane and drag an inner point: again only their patches change.
    let before = mesh.patches().to_vec();
    let v = VertexId(1);
    let changed =
        mesh.rotate_tangent_plane(v, glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.2)).unwrap();
    assert_eq!(changed.patches, faces_around(&t, v));
    let h = t.outgoing(v).next().unwrap();
    let e = h.edge();
    let target = mesh.curve_along(h).points[1] + DVec3::new(0.5, 0.5, 0.5);
    let changed_curve = mesh.move_inner_point(e, v, target).unwrap();
    let mut on_curve: Vec<FaceId> = (0..2).map(|s| t.face(e.halfedge(s))).collect();
    on_curve.sort();
    assert_eq!(changed_curve.patches, on_curve);
    assert_eq!(changed_curve.curves, vec![e]);
    let leg = mesh.curve_along(h).points[1] - mesh.vertex_position(v);
    assert!(leg.dot(mesh.vertex_normal(v)).abs() < 1e-12 * size, "the dragged point left the tangent plane");
    for f in t.faces() {
        let touched = changed.patches.contains(&f) || on_curve.contains(&f);
        assert_eq!(same_patch(&before[f.index()], mesh.patch(f)), !touched, "{f:?}");
    }
    // G1 holds after every kind of edit.
    assert!(mesh.continuity(32).1.max_normal_angle <= 1e-6);

    // The edit state survives JSON and rebuilds the same patches on a fresh build.
    let json = serde_json::to_string(&mesh.edits()).unwrap();
    let back: CurveMeshEdits = serde_json::from_str(&json).unwrap();
    let mut reopened = CurveMesh::from_cage(&cage).unwrap().0;
    reopened.set_edits(&back).unwrap();
    for f in t.faces() {
        assert!(same_patch(reopened.patch(f), mesh.patch(f)), "reopened patch {f:?}");
    }
    assert_eq!(reopened.edits(), mesh.edits());
    // Only the edited entities are stored.
    assert_eq!(back.vertices.len(), picks.len() + 1);
    // Undo to each earlier state, then to none, by setting the state.
    for (edits, patches) in states.iter().rev() {
        reopened.set_edits(edits).unwrap();
        assert!(t.faces().all(|f| same_patch(reopened.patch(f), &patches[f.index()])));
    }
    let changed = reopened.set_edits(&CurveMeshEdits { shape: back.shape, ..Default::default() }).unwrap();
    assert!(!changed.patches.is_empty());
    assert!(t.faces().all(|f| same_patch(reopened.patch(f), fresh.patch(f))));
}

#[test]
fn hostile_edits_are_refused_and_change_nothing() {
    let (mut mesh, _) = CurveMesh::from_cage(&mixed_cage()).unwrap();
    let original = mesh.patches().to_vec();
    let v = VertexId(2);
    let e = mesh.topology().outgoing(v).next().unwrap().edge();
    let other = mesh.topology().edges().find(|&c| {
        let (a, b) = mesh.topology().edge_vertices(c);
        a != v && b != v
    });
    let errors = [
        mesh.clone().move_vertex(v, DVec3::new(f64::NAN, 0.0, 0.0)).unwrap_err(),
        mesh.clone().move_vertex(VertexId(9999), DVec3::ZERO).unwrap_err(),
        mesh.clone().rotate_tangent_plane(v, glam::DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0)).unwrap_err(),
        mesh.clone().set_vertex_normal(v, -mesh.vertex_normal(v)).unwrap_err(),
        mesh.clone().set_vertex_normal(v, DVec3::ZERO).unwrap_err(),
        mesh.clone().move_inner_point(other.unwrap(), v, DVec3::ZERO).unwrap_err(),
        mesh.clone().move_inner_point(e, v, mesh.vertex_position(v) + 1e-30 * mesh.vertex_normal(v)).unwrap_err(),
        mesh.clone().move_inner_point(EdgeId(99999), v, DVec3::ZERO).unwrap_err(),
    ];
    for err in &errors {
        let text = err.to_string();
        assert!(!text.is_empty() && !text.contains('\n'), "{text}");
    }
    // A state for another mesh, a point off its tangent plane, a normal that is not unit.
    let mut state = mesh.edits();
    state.shape[0] += 1;
    assert!(mesh.set_edits(&state).unwrap_err().to_string().contains("rebuild from the cage"));
    let inner = mesh.curve(e).points;
    let off =
        CurveEdit { curve: e.0, inner: [(inner[1] + 5.0 * mesh.vertex_normal(v)).to_array(), inner[2].to_array()] };
    let state = CurveMeshEdits { shape: mesh.edits().shape, vertices: vec![], curves: vec![off] };
    let mut swapped = state.clone();
    swapped.curves[0].inner = [inner[2].to_array(), inner[1].to_array()];
    for bad in [state, swapped] {
        assert!(mesh.set_edits(&bad).is_err());
    }
    let mut bad_normal = mesh.clone();
    bad_normal.move_vertex(v, mesh.vertex_position(v) + DVec3::X).unwrap();
    let mut s = bad_normal.edits();
    s.vertices[0].normal = [0.0, 0.0, 2.0];
    assert!(mesh.set_edits(&s).is_err());
    assert!(mesh.topology().faces().all(|f| same_patch(mesh.patch(f), &original[f.index()])));
    assert!(mesh.edits().vertices.is_empty() && mesh.edits().curves.is_empty());
}

#[test]
fn random_edits_keep_every_shared_boundary_g1() {
    let (mut mesh, _) = CurveMesh::from_cage(&mixed_cage()).unwrap();
    let size = mesh.topology().bounding_diagonal();
    let mut seed = 0x2545f4914f6cdd1du64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut accepted, mut refused) = (0, 0);
    for _ in 0..60 {
        let v = VertexId((next() * mesh.vertex_count() as f64) as u32);
        let d = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
        let result = match (next() * 3.0) as u32 {
            0 => mesh.move_vertex(v, mesh.vertex_position(v) + 0.05 * size * d),
            1 => mesh
                .rotate_tangent_plane(v, glam::DQuat::from_axis_angle(d.normalize_or(DVec3::X), 0.6 * (next() - 0.5))),
            _ => {
                let h = mesh.topology().outgoing(v).nth((next() * 3.0) as usize % mesh.topology().valence(v)).unwrap();
                let target = mesh.curve_along(h).points[1] + 0.1 * size * d;
                mesh.move_inner_point(h.edge(), v, target)
            }
        };
        match result {
            Ok(changed) => {
                accepted += 1;
                for f in &changed.patches {
                    assert!(mesh.patch(*f).control_points().iter().all(|p| p.is_finite()));
                }
            }
            Err(e) => {
                refused += 1;
                assert!(!e.to_string().contains('\n'));
            }
        }
    }
    assert!(accepted > 50, "{accepted} accepted, {refused} refused");
    // Edits this large can fold a patch over (an inner point dragged past its vertex turns that
    // corner inside out): the two normals are then opposite, but the tangent planes still agree
    // on every shared boundary, which is what the construction promises.
    let (_, boundaries) = mesh.shared_boundaries();
    let mut worst: f64 = 0.0;
    for b in &boundaries {
        for s in 0..=16 {
            let t = s as f64 / 16.0;
            let (ua, va) = side_point(b.first.side, t);
            let (ub, vb) = side_point(b.second.side, 1.0 - t);
            let na = mesh.patches()[b.first.patch].evaluate(ua, va).unit_normal();
            let nb = mesh.patches()[b.second.patch].evaluate(ub, vb).unit_normal();
            if let (Some(na), Some(nb)) = (na, nb) {
                worst = worst.max(na.cross(nb).length());
            }
        }
    }
    assert!(worst <= 1e-6, "tangent planes {worst} apart");
}

#[test]
fn moderate_edits_keep_every_shared_boundary_g1_with_its_orientation() {
    let (mut mesh, _) = CurveMesh::from_cage(&mixed_cage()).unwrap();
    let size = mesh.topology().bounding_diagonal();
    for v in mesh.topology().vertices().collect::<Vec<_>>() {
        let k = v.0 as f64;
        let p = mesh.vertex_position(v) + 0.01 * size * DVec3::new(k.sin(), (1.3 * k).cos(), (0.7 * k).sin());
        mesh.move_vertex(v, p).unwrap();
        mesh.rotate_tangent_plane(v, glam::DQuat::from_axis_angle(DVec3::new(k.cos(), 1.0, k.sin()).normalize(), 0.05))
            .unwrap();
        let h = mesh.topology().outgoing(v).next().unwrap();
        let leg = mesh.curve_along(h).points[1] - p;
        mesh.move_inner_point(
            h.edge(),
            v,
            p + 1.2 * leg + 0.1 * leg.length() * mesh.vertex_normal(v).any_orthonormal_vector(),
        )
        .unwrap();
    }
    let (_, report) = mesh.continuity(16);
    assert!(report.max_normal_angle <= 1e-6, "{}", report.max_normal_angle);
    assert_eq!(report.degenerate_samples, 0);
}

#[test]
fn the_tessellation_shares_boundary_vertices_and_updates_exactly() {
    let cage = mixed_cage();
    let (mut mesh, _) = CurveMesh::from_cage(&cage).unwrap();
    let k = 6;
    let mut tess = Tessellation::new(&mesh, k).unwrap();
    let surface = tess.mesh();
    surface.validate().unwrap();
    // Closed like the cage, the same sphere: shared samples are single vertices.
    assert!(surface.is_closed());
    assert_eq!(surface.euler_characteristic(), cage.euler_characteristic());
    assert_eq!(surface.face_count(), mesh.patch_count() * k * k);
    for f in mesh.topology().faces() {
        let patch = mesh.patch(f);
        for j in 0..=k {
            for i in 0..=k {
                let (u, v) = (i as f64 / k as f64, j as f64 / k as f64);
                let w = tess.grid_vertex(&mesh, f, i, j);
                let p = surface.position(w);
                assert!(p.distance(patch.point(u, v)) <= 1e-12 * cage.bounding_diagonal(), "{f:?} ({i}, {j})");
                // The analytic normal of the patch (at corners the tangent plane's).
                let n = patch.normal(u, v).unwrap();
                assert!(tess.normals()[w.index()].dot(n) > 1.0 - 1e-12, "{f:?} ({i}, {j})");
            }
        }
        for q in tess.patch_faces(f) {
            let corners: Vec<VertexId> = surface.face_vertices(FaceId(q as u32)).collect();
            assert_eq!(corners[0], tess.grid_vertex(&mesh, f, (q % (k * k)) % k, (q % (k * k)) / k));
        }
    }
    // Boundary samples are the curve points themselves.
    for e in mesh.topology().edges() {
        let h = e.halfedge(0);
        let f = mesh.topology().face(h);
        let side = mesh.topology().face_halfedges(f).position(|x| x == h).unwrap();
        let curve = mesh.curve(e);
        let grid = |s: usize| match side {
            0 => (s, 0),
            1 => (k, s),
            2 => (k - s, k),
            _ => (0, k - s),
        };
        for s in 0..=k {
            let (i, j) = grid(s);
            assert_eq!(
                surface.position(tess.grid_vertex(&mesh, f, i, j)),
                curve.point(s as f64 / k as f64).to_array().into()
            );
        }
    }
    // After an edit, updating gives exactly a fresh tessellation.
    let changed =
        mesh.move_vertex(VertexId(6), mesh.vertex_position(VertexId(6)) + DVec3::new(2.0, 1.0, -1.5)).unwrap();
    let (stale, stale_normals) = (tess.mesh().positions().to_vec(), tess.normals().to_vec());
    let ranges = tess.update(&mesh, &changed).unwrap();
    let again = Tessellation::new(&mesh, k).unwrap();
    assert_eq!(tess.mesh().positions(), again.mesh().positions());
    assert_eq!(tess.normals(), again.normals());
    assert_ne!(stale, tess.mesh().positions());
    // Every vertex that changed is in a returned range (what an editor re-uploads), and the
    // ranges cover only the changed patches' vertices.
    let inside = |i: usize| ranges.iter().any(|r| r.contains(&i));
    for i in 0..stale.len() {
        if stale[i] != tess.mesh().positions()[i] || stale_normals[i] != tess.normals()[i] {
            assert!(inside(i), "vertex {i} changed outside the returned ranges");
        }
    }
    let covered: usize = ranges.iter().map(|r| r.len()).sum();
    assert!(covered <= changed.patches.len() * (k + 1) * (k + 1), "{covered}");
}

#[test]
fn results_are_bit_identical_for_one_and_two_threads() {
    let cage = mixed_cage();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| {
            let (mesh, report) = CurveMesh::from_cage(&cage).unwrap();
            let tess = Tessellation::new(&mesh, 8).unwrap();
            let (_, continuity) = mesh.continuity(16);
            let points: Vec<[u64; 3]> = mesh
                .patches()
                .iter()
                .flat_map(|p| p.control_points())
                .map(|p| p.to_array().map(f64::to_bits))
                .collect();
            (points, tess.mesh().positions().to_vec(), tess.normals().to_vec(), report, continuity)
        })
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.0, b.0);
    assert_eq!(a.1, b.1);
    assert_eq!(a.2, b.2);
    assert_eq!(a.3, b.3);
    assert_eq!(a.4, b.4);
}
