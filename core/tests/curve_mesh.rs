//! Curve meshes with G1 Gregory patches (`taut_core::gregory`): the properties of
//! `shared/spec/curve-mesh-gregory.md` §7 on every bundled cage and on small cages built here,
//! against references computed independently (the subdivision module's own limit points, the
//! uniform B-spline written out here, patch evaluation at the tessellation's parameters).

use std::path::{Path, PathBuf};
use taut_core::gregory::closeness::closest_point;
use taut_core::gregory::continuity::side_point;
use taut_core::gregory::curve_mesh::{CurveEdit, CurveMeshEdits};
use taut_core::gregory::{CurveMesh, GregoryPatch, SurfacePatch, Tessellation, fit_edge_curves};
use taut_core::subdiv::{RefinedPositions, Refinement, Scheme, catmull_clark_limit};
use taut_core::{DVec3, Document, EdgeId, FaceId, PolyMesh, VertexId, io};

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets")
}

/// Every bundled cage: `assets/*.obj` and the default scene.
fn bundled() -> Vec<(String, PolyMesh)> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(assets())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    names.sort();
    let mut out: Vec<(String, PolyMesh)> = names
        .iter()
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), io::import_mesh(p).unwrap().0))
        .collect();
    assert!(out.len() >= 6, "the bundled cages are missing: {:?}", names);
    out.push(("default.taut".into(), Document::load(&assets().join("default.taut")).unwrap().cage));
    out
}

/// A closed cage with vertices of valence 3, 4, 5 and 6, triangles and a pentagon: a pentagonal
/// prism with a pyramid on top, two neighbouring side quads split into triangles at the same
/// top vertex, every vertex nudged off the symmetric positions.
fn mixed_cage() -> PolyMesh {
    let mut p = Vec::new();
    for (z, r) in [(0.0, 30.0), (28.0, 24.0)] {
        for k in 0..5 {
            let a = std::f64::consts::TAU * k as f64 / 5.0;
            let nudge = DVec3::new((1.7 * k as f64).sin(), (2.3 * k as f64 + z).cos(), 0.8 * (k as f64 + z).sin());
            p.push(DVec3::new(r * a.cos(), r * a.sin(), z) + nudge);
        }
    }
    p.push(DVec3::new(1.5, -0.7, 44.0));
    let (b, t, apex) = (|k: u32| k % 5, |k: u32| 5 + k % 5, 10);
    let mut faces: Vec<Vec<u32>> = vec![(0..5).rev().collect()];
    for k in 0..5 {
        match k {
            // Quads (b0, b1, t1, t0) and (b1, b2, t2, t1) split along the diagonals to t1.
            0 => faces.extend([vec![b(0), b(1), t(1)], vec![b(0), t(1), t(0)]]),
            1 => faces.extend([vec![b(1), b(2), t(1)], vec![b(2), t(2), t(1)]]),
            _ => faces.push(vec![b(k), b(k + 1), t(k + 1), t(k)]),
        }
        faces.push(vec![t(k), t(k + 1), apex]);
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// The all-quad mesh the curve mesh lives on: the cage, or its first Catmull–Clark level.
fn quad_mesh(cage: &PolyMesh) -> PolyMesh {
    if cage.faces().all(|f| cage.face_valence(f) == 4) {
        return cage.clone();
    }
    let r = Refinement::new(cage, Scheme::CatmullClark, &[], 1).unwrap();
    let mut out = RefinedPositions::default();
    r.evaluate_levels(cage.positions(), &mut out).unwrap();
    r.surface(out.finest())
}

fn largest_edge(mesh: &PolyMesh) -> f64 {
    mesh.edges().map(|e| mesh.edge_length(e)).fold(0.0, f64::max)
}

fn same_patch(a: &GregoryPatch, b: &GregoryPatch) -> bool {
    a.control_points()
        .iter()
        .zip(b.control_points().iter())
        .all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits))
}

#[test]
fn the_mixed_cage_has_what_it_claims() {
    let cage = mixed_cage();
    let valences: std::collections::BTreeSet<usize> = cage.vertices().map(|v| cage.valence(v)).collect();
    assert!([3, 4, 5, 6].iter().all(|n| valences.contains(n)), "{valences:?}");
    let sides: std::collections::BTreeSet<usize> = cage.faces().map(|f| cage.face_valence(f)).collect();
    assert!(sides.contains(&3) && sides.contains(&5) && sides.contains(&4), "{sides:?}");
    assert!(cage.is_closed() && cage.euler_characteristic() == 2);
}

#[test]
fn every_shared_boundary_is_g1_on_every_bundled_cage_and_the_mixed_cage() {
    let mut cages = bundled();
    cages.push(("mixed cage".into(), mixed_cage()));
    for (name, cage) in cages {
        let (mesh, report) = CurveMesh::from_cage(&cage).unwrap_or_else(|e| panic!("{name}: {e}"));
        let quads = quad_mesh(&cage);
        assert_eq!(report.subdivided_first, quads.face_count() != cage.face_count(), "{name}");
        assert_eq!(
            (mesh.vertex_count(), mesh.curve_count(), mesh.patch_count()),
            (quads.vertex_count(), quads.edge_count(), quads.face_count())
        );
        let (shared, continuity) = mesh.continuity(32);
        let interior_edges = quads.edges().filter(|&e| !quads.is_boundary_edge(e)).count();
        assert_eq!(shared.len(), interior_edges, "{name}");
        assert!(continuity.max_normal_angle <= 1e-6, "{name}: normal angle {} rad", continuity.max_normal_angle);
        assert_eq!(continuity.degenerate_samples, 0, "{name}");
        assert!(
            report.fit.alpha_guards.is_empty() && report.fit.fallback_normals.is_empty(),
            "{name}: {:?}",
            report.fit
        );

        let size = cage.bounding_diagonal();
        for v in quads.vertices() {
            // Vertices on the limit surface with its tangent plane, by the subdivision module's
            // own per-vertex evaluation (not the stencils the build used).
            let (limit, normal) = catmull_clark_limit(&quads, v).unwrap();
            assert!(mesh.vertex_position(v).distance(limit) <= 1e-12 * size, "{name}: vertex {v:?}");
            assert!(mesh.vertex_normal(v).cross(normal).length() <= 1e-9, "{name}: normal at {v:?}");
            // Every curve leaves the vertex inside that plane.
            for h in quads.outgoing(v) {
                let leg = mesh.curve_along(h).points[1] - mesh.vertex_position(v);
                assert!(
                    leg.dot(mesh.vertex_normal(v)).abs() <= 1e-12 * size,
                    "{name}: a leg at {v:?} leaves the plane"
                );
                assert!(leg.length() > 0.0);
            }
        }
        // The patches' rims are the curves themselves.
        for f in quads.faces() {
            let boundary = mesh.patch_boundary(f);
            let rims = mesh.patch(f).boundary_curves();
            let expect =
                [boundary.sides[0], boundary.sides[1], boundary.sides[2].reversed(), boundary.sides[3].reversed()];
            assert_eq!(rims, expect, "{name}: patch {f:?}");
        }
    }
}

#[test]
fn curves_and_patches_stay_close_to_the_limit_surface() {
    for (name, cage) in bundled().into_iter().chain([("mixed cage".to_string(), mixed_cage())]) {
        let (mesh, report) = CurveMesh::from_cage(&cage).unwrap();
        let edge = largest_edge(&quad_mesh(&cage));
        // Curves through the five limit points of their edge within 2 % of the longest edge,
        // patches within 6 % (the cube, all valence 3 with nothing subdivided, is the worst).
        assert!(report.fit.max_limit_to_curve <= 0.02 * edge, "{name}: {} of {edge}", report.fit.max_limit_to_curve);
        assert!(report.closeness.max_distance <= 0.06 * edge, "{name}: {} of {edge}", report.closeness.max_distance);
        assert!(report.closeness.max_distance > 0.0 && report.closeness.points == 9 * mesh.patch_count(), "{name}");
        assert!(
            report.fit.max_residual >= report.fit.max_limit_to_curve,
            "{name}: a closest point farther than the parametric one"
        );
    }
}

/// The uniform bicubic B-spline of a 4 × 4 block of control points at `(u, v)`.
fn bspline(p: &[[DVec3; 4]; 4], u: f64, v: f64) -> DVec3 {
    let b = |t: f64| {
        [
            (1.0 - t).powi(3) / 6.0,
            (3.0 * t.powi(3) - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t.powi(3) / 6.0,
        ]
    };
    let (bu, bv) = (b(u), b(v));
    let mut s = DVec3::ZERO;
    for i in 0..4 {
        for j in 0..4 {
            s += bu[i] * bv[j] * p[i][j];
        }
    }
    s
}

#[test]
fn on_a_regular_torus_curves_are_exact_and_closeness_is_bounded_by_the_bspline() {
    // All valence 4: the limit surface is the uniform bicubic B-spline of the cage, whose
    // restriction to an edge is a cubic, so the fitted curves are exact.
    let (nu, nv) = (8u32, 6u32);
    let mut p = Vec::new();
    for i in 0..nu {
        let a = std::f64::consts::TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let b = std::f64::consts::TAU * j as f64 / nv as f64;
            let r = 10.0 + 2.0 * (3.0 * a).sin();
            p.push(DVec3::new(
                (40.0 + r * b.cos()) * a.cos(),
                (40.0 + r * b.cos()) * a.sin(),
                r * b.sin() + 3.0 * (2.0 * a).cos(),
            ));
        }
    }
    let index = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    let faces: Vec<[u32; 4]> = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| [index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)]))
        .collect();
    let cage = PolyMesh::from_polygons(p.clone(), &faces).unwrap();
    let (mesh, report) = CurveMesh::from_cage(&cage).unwrap();
    assert!(report.fit.max_limit_to_curve <= 1e-10 * cage.bounding_diagonal(), "{}", report.fit.max_limit_to_curve);
    // Each curve is the B-spline's edge curve: compare at several parameters.
    let block = |i: u32, j: u32| -> [[DVec3; 4]; 4] {
        std::array::from_fn(|a| {
            std::array::from_fn(|b| p[index(i + nu - 1 + a as u32, j + nv - 1 + b as u32) as usize])
        })
    };
    let mut parametric: f64 = 0.0;
    for (f, face) in faces.iter().enumerate() {
        let (i, j) = (face[0] / nv, face[0] % nv);
        let net = block(i, j);
        // The face's first halfedge runs from (i, j) to (i + 1, j): u along i, v along j.
        let h0 = cage.face_halfedge(FaceId(f as u32));
        assert_eq!(cage.from_vertex(h0).0, face[0]);
        let curve = mesh.curve_along(h0);
        for k in 0..=8 {
            let t = k as f64 / 8.0;
            assert!(curve.point(t).distance(bspline(&net, t, 0.0)) <= 1e-9, "face {f} t {t}");
        }
        let patch = mesh.patch(FaceId(f as u32));
        for a in 1..4 {
            for b in 1..4 {
                let (u, v) = (a as f64 / 4.0, b as f64 / 4.0);
                parametric = parametric.max(patch.point(u, v).distance(bspline(&net, u, v)));
            }
        }
    }
    // The reported closest-point distance can only be smaller than the parametric distance to
    // the same limit points, and it is not zero (Chiyokura–Kimura cross derivatives are not the
    // B-spline's).
    assert!(report.closeness.max_distance <= parametric + 1e-9, "{} > {parametric}", report.closeness.max_distance);
    assert!(report.closeness.max_distance > 0.05 * parametric, "{} vs {parametric}", report.closeness.max_distance);
}

#[test]
fn the_papers_pentagonal_prism() {
    // Circumradius 30, height 30 (the paper's figures fit this size, not the 300 its text says).
    let (cage, _) = io::import_mesh(&assets().join("prism30.obj")).unwrap();
    let own = fit_edge_curves(&cage).unwrap().report;
    // The paper's §3.2: largest level-2-vertex-to-limit distance 0.835, longest edge 35.2.
    assert!((own.longest_edge - 35.27).abs() < 0.01, "{}", own.longest_edge);
    assert!((own.max_chain_to_limit - 0.835).abs() < 0.02 * 0.835, "{}", own.max_chain_to_limit);
    // The paper's §3.3 gives 0.108 after the tangent-plane correction. The cubics with in-plane
    // end tangents cannot come that close at the valence-3 corners (see the report): ours stay
    // within 0.4, and the unconstrained fit on the pentagon edges gives the paper's figure.
    assert!(own.max_limit_to_curve > 0.3 && own.max_limit_to_curve < 0.4, "{}", own.max_limit_to_curve);
    let r = Refinement::new(&cage, Scheme::CatmullClark, &[], 2).unwrap();
    let mut levels = RefinedPositions::default();
    r.evaluate(cage.positions(), &mut levels).unwrap();
    let bottom = cage.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge();
    let chain: Vec<DVec3> = r.cage_edge_chain(bottom, 2).unwrap().iter().map(|w| levels.limit[w.index()]).collect();
    let free =
        taut_core::gregory::bezier::fit_with_fixed_ends(chain[0], chain[4], &chain[1..4], &[0.25, 0.5, 0.75]).unwrap();
    let free_error = chain[1..4].iter().map(|&p| free.distance_to(p).1).fold(0.0, f64::max);
    assert!((free_error - 0.108).abs() < 0.1 * 0.108, "{free_error}");
    // The curve mesh itself is built after one Catmull–Clark step (pentagons): closer still.
    let (mesh, report) = CurveMesh::from_cage(&cage).unwrap();
    assert!(report.subdivided_first && mesh.patch_count() == 30);
    assert!(report.fit.max_limit_to_curve < 0.12, "{}", report.fit.max_limit_to_curve);
    assert!(report.closeness.max_distance < 0.2, "{}", report.closeness.max_distance);
    assert!(mesh.continuity(16).1.max_normal_angle <= 1e-6);
}

/// The faces around a vertex, ascending.
fn faces_around(mesh: &PolyMesh, v: VertexId) -> Vec<FaceId> {
    let mut f: Vec<FaceId> = mesh.outgoing(v).map(|h| mesh.face(h)).filter(|f| f.is_valid()).collect();
    f.sort();
    f
}

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

#[test]
fn similar_cages_give_similar_curve_meshes() {
    // Rotating, scaling and moving the cage moves the curve mesh the same way.
    let cage = mixed_cage();
    let q = glam::DQuat::from_euler(glam::EulerRot::ZXY, 0.4, -0.9, 1.3);
    let map = |p: DVec3| q * (3.5 * p) + DVec3::new(-20.0, 7.0, 110.0);
    let mut moved = cage.clone();
    for p in moved.positions_mut() {
        *p = map(*p);
    }
    let (a, ra) = CurveMesh::from_cage(&cage).unwrap();
    let (b, rb) = CurveMesh::from_cage(&moved).unwrap();
    let tol = 1e-10 * moved.bounding_diagonal();
    for (pa, pb) in a.patches().iter().zip(b.patches()) {
        for (x, y) in pa.control_points().iter().zip(pb.control_points().iter()) {
            assert!(map(*x).distance(*y) <= tol);
        }
    }
    assert!((3.5 * ra.fit.max_limit_to_curve - rb.fit.max_limit_to_curve).abs() <= tol);
    assert!((3.5 * ra.closeness.max_distance - rb.closeness.max_distance).abs() <= 1e-6 * rb.closeness.max_distance);
}

#[test]
fn bad_cages_get_clear_answers() {
    let one_line = |e: taut_core::Error| {
        let t = e.to_string();
        assert!(!t.contains('\n') && !t.is_empty());
        t
    };
    // A zero-length cage edge: refused, naming it.
    let mut p: Vec<DVec3> =
        (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    let cube_faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    p[1] = p[0];
    let collapsed = PolyMesh::from_polygons(p, &cube_faces).unwrap();
    assert!(one_line(CurveMesh::from_cage(&collapsed).unwrap_err()).contains("zero length"));
    // Non-finite positions.
    let mut nan = mixed_cage();
    nan.positions_mut()[3].y = f64::NAN;
    one_line(CurveMesh::from_cage(&nan).unwrap_err());
    // No faces.
    let empty = PolyMesh::from_polygons::<[u32; 3]>(vec![DVec3::ZERO], &[]).unwrap();
    assert!(one_line(CurveMesh::from_cage(&empty).unwrap_err()).contains("no faces"));

    // An isolated vertex is kept and left alone.
    let mut q: Vec<DVec3> =
        (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    q.push(DVec3::splat(5.0));
    let with_isolated = PolyMesh::from_polygons(q, &cube_faces).unwrap();
    let (mut mesh, _) = CurveMesh::from_cage(&with_isolated).unwrap();
    assert_eq!(mesh.vertex_count(), 9);
    assert_eq!(mesh.vertex_position(VertexId(8)), DVec3::splat(5.0));
    assert!(mesh.move_vertex(VertexId(8), DVec3::ZERO).is_err());
    let tess = Tessellation::new(&mesh, 4).unwrap();
    assert!(tess.mesh().is_isolated(VertexId(8)));
    assert!(mesh.continuity(16).1.max_normal_angle <= 1e-6);

    // A valence-2 vertex (a cube edge split in two; its faces become pentagons): built, G1
    // wherever the normals exist; the two patch corners there are flat (180°).
    let mut r: Vec<DVec3> =
        (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    r.push(DVec3::new(0.5, 0.0, 0.0));
    let split: Vec<Vec<u32>> = vec![
        vec![0, 2, 3, 1, 8],
        vec![4, 5, 7, 6],
        vec![0, 8, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
    ];
    let valence2 = PolyMesh::from_polygons(r, &split).unwrap();
    assert_eq!(valence2.valence(VertexId(8)), 2);
    let (mesh, report) = CurveMesh::from_cage(&valence2).unwrap();
    assert!(mesh.vertex_normal(VertexId(8)).is_finite());
    let (_, c) = mesh.continuity(16);
    assert!(c.max_normal_angle <= 1e-6, "{}", c.max_normal_angle);
    assert!(report.closeness.max_distance.is_finite());
    let tess = Tessellation::new(&mesh, 8).unwrap();
    assert!(tess.normals().iter().all(|n| (n.length() - 1.0).abs() < 1e-12));

    // A degenerate (zero-area) face: whatever is accepted is a valid curve mesh.
    let mut s: Vec<DVec3> =
        (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    s.push(DVec3::new(0.25, 0.0, 0.0));
    s.push(DVec3::new(0.75, 0.0, 0.0));
    // Face 0-8-9-1 on the bottom edge has its four vertices on one line.
    let sliver: Vec<Vec<u32>> = vec![
        vec![0, 2, 3, 1, 9, 8],
        vec![0, 8, 9, 1],
        vec![4, 5, 7, 6],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
    ];
    match PolyMesh::from_polygons(s, &sliver) {
        Err(e) => {
            one_line(e);
        }
        Ok(cage) => match CurveMesh::from_cage(&cage) {
            Err(e) => {
                one_line(e);
            }
            Ok((mesh, _)) => {
                assert!(mesh.patches().iter().all(|p| p.control_points().iter().all(|q| q.is_finite())));
                assert!(mesh.topology().vertices().all(|v| (mesh.vertex_normal(v).length() - 1.0).abs() < 1e-12));
            }
        },
    }
}

#[test]
fn closest_point_agrees_with_a_brute_force_search() {
    let (mesh, _) = CurveMesh::from_cage(&mixed_cage()).unwrap();
    let patch = mesh.patch(FaceId(3));
    let target = patch.point(0.37, 0.61) + 0.3 * patch.normal(0.37, 0.61).unwrap();
    let (_, _, d) = closest_point(patch, target, (0.5, 0.5));
    let n = 200;
    let brute = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| (i, j)))
        .map(|(i, j)| patch.point(i as f64 / n as f64, j as f64 / n as f64).distance(target))
        .fold(f64::INFINITY, f64::min);
    assert!(d <= brute + 1e-12 && d > brute - 1e-3, "{d} vs {brute}");
}
