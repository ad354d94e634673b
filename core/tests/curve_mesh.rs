//! Curve meshes built from cages (`taut_core::gregory`): the properties of
//! `docs/curve-mesh-gregory.md` §7 on every bundled cage and on small cages built here,
//! against references computed independently (the subdivision module's own per-vertex limit
//! points, the uniform B-spline written out here, a brute-force closest point, the paper's
//! figures).

mod common;

use common::{assets, bundled, largest_edge, mixed_cage, quad_mesh};
use taut_core::gregory::closeness::closest_point;
use taut_core::gregory::{CurveMesh, SurfacePatch, Tessellation, fit_edge_curves};
use taut_core::subdiv::{RefinedPositions, Refinement, Scheme, catmull_clark_limit};
use taut_core::{DVec3, FaceId, PolyMesh, VertexId, io};

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
        // patches within 6 % (a loose bound; `curve_mesh_closeness.rs` bounds each cage).
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

/// The cross-boundary field turning through the limit surface at each curve's middle (its normal,
/// and the length fitted to its cross derivatives) brings the patches closer to the Catmull–Clark
/// limit surface than the linear field of Chiyokura and Kimura (measured with the linear field:
/// torus 0.158 %, knob 0.232 %, patch 0.126 %, prism 0.138 % of the diagonal; with the middle
/// normals alone 0.113 %, 0.224 %, 0.092 %, 0.129 %; with the fitted lengths too see
/// `curve_mesh_closeness.rs`), keeps G1 across every shared curve, and an edited curve falls back
/// to the linear field (its patches are then those of a mesh built without middles).
#[test]
fn middle_normals_bring_the_patches_closer_and_keep_g1() {
    for (name, bound) in [("torus.obj", 0.0012), ("knob.obj", 0.00229), ("patch.obj", 0.0010), ("prism.obj", 0.00133)] {
        let (cage, _) = io::import_mesh(&assets().join(name)).unwrap();
        let (mesh, report) = CurveMesh::from_cage(&cage).unwrap();
        let share = report.closeness.max_distance / cage.bounding_diagonal();
        assert!(
            share < bound,
            "{name}: interior limit points {:.4} % of the diagonal from their patches",
            100.0 * share
        );
        let (_, continuity) = mesh.continuity(16);
        assert!(continuity.max_normal_angle < 1e-9, "{name}: {}", continuity.max_normal_angle);
    }
    // An edited curve falls back to the linear field; the other curves of its patches keep their
    // middle normals, and G1 holds.
    let (cage, _) = io::import_mesh(&assets().join("torus.obj")).unwrap();
    let (mut mesh, _) = CurveMesh::from_cage(&cage).unwrap();
    let e = taut_core::EdgeId(5);
    let sides = |mesh: &CurveMesh| -> Vec<(bool, bool)> {
        (0..2)
            .map(|side| {
                let h = e.halfedge(side);
                let f = mesh.topology().face(h);
                let k = mesh.topology().face_halfedges(f).position(|x| x == h).unwrap();
                let boundary = mesh.patch_boundary(f);
                (boundary.mids[k].is_some(), boundary.mids[(k + 2) % 4].is_some())
            })
            .collect()
    };
    assert_eq!(sides(&mesh), vec![(true, true), (true, true)]);
    let before = mesh.patch(mesh.topology().face(e.halfedge(0))).point(0.5, 0.5);
    let (a, _) = mesh.topology().edge_vertices(e);
    let p = mesh.inner_point(e, a).unwrap();
    mesh.move_inner_point(e, a, p).unwrap();
    assert_eq!(sides(&mesh), vec![(false, true), (false, true)]);
    let after = mesh.patch(mesh.topology().face(e.halfedge(0))).point(0.5, 0.5);
    assert!(before != after, "the patch is rebuilt with the linear field on the edited curve");
    let (_, continuity) = mesh.continuity(16);
    assert!(continuity.max_normal_angle < 1e-9);
}
