//! Properties of the subdivision schemes (`taut_core::subdiv`), each against an independent
//! reference: hand-computed values, uniform B-splines and box-spline masks evaluated here, many
//! further subdivision steps, transformed copies, a second thread count.

use taut_core::mesh::edit::Triangulation;
use taut_core::subdiv::{
    RefinedPositions, Refinement, Scheme, catmull_clark_limit, loop_limit_matrix, sharpness_from_pairs,
};
use taut_core::{DVec3, HalfedgeId, PolyMesh, VertexId};
use taut_tests::subdiv::{bicubic, bumpy_grid, closed_bspline, refine, triangulate};
use taut_tests::{cube, grid, prism, transformed};

fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// The boundary loop of a cage starting at boundary halfedge `h`: its halfedges in order.
fn boundary_loop(m: &PolyMesh, start: HalfedgeId) -> Vec<HalfedgeId> {
    let mut out = vec![start];
    let mut h = m.next(start);
    while h != start {
        out.push(h);
        h = m.next(h);
    }
    out
}

#[test]
fn catmull_clark_first_level_of_a_cube_by_hand() {
    let cage = cube();
    let (r, out) = refine(&cage, Scheme::CatmullClark, &[], 1);
    let level = &out.levels[1];
    let split = r.split(1);
    // Face point: the centroid; face 0 is z = −1/2.
    assert!(
        (level[split.face_point(taut_core::FaceId(0)).unwrap().index()] - DVec3::new(0.0, 0.0, -0.5)).length() < 1e-15
    );
    // Edge point of the edge from (−½,−½,−½) to (½,−½,−½): the mean of its ends and the face points
    // (0,0,−½) and (0,−½,0): (0, −3/8, −3/8).
    let e = cage.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge();
    assert!((level[split.edge_point(e).index()] - DVec3::new(0.0, -0.375, -0.375)).length() < 1e-15);
    // Vertex point of valence 3: v/3 + Σe/9 + ΣF/9 = (5/9)·v on a cube centred at the origin.
    for v in cage.vertices() {
        assert!((level[v.index()] - 5.0 / 9.0 * cage.position(v)).length() < 1e-15);
    }
    assert_eq!(r.mesh(1).face_count(), 24);
    assert!(r.mesh(1).faces().all(|f| r.mesh(1).face_valence(f) == 4));
}

#[test]
fn catmull_clark_regular_interior_is_the_bicubic_bspline() {
    let n = 8;
    let cage = bumpy_grid(n);
    let levels = 2;
    let (r, out) = refine(&cage, Scheme::CatmullClark, &[], levels);
    let params = r.mesh(levels).positions(); // the bilinear prolongation: x, y are the parameters
    let mut checked = 0;
    for v in r.mesh(levels).vertices() {
        let (u, w) = (params[v.index()].x, params[v.index()].y);
        if !(2.0..=n as f64 - 2.0).contains(&u) || !(2.0..=n as f64 - 2.0).contains(&w) {
            continue;
        }
        let (s, su, sv) = bicubic(cage.positions(), n as usize, u, w);
        assert!((out.limit[v.index()] - s).length() < 1e-12, "limit at ({u}, {w})");
        let a = angle(out.normals[v.index()], su.cross(sv));
        assert!(
            a < 1e-12,
            "normal at ({u}, {w}): {a:e} rad, {:?} vs {:?}",
            out.normals[v.index()],
            su.cross(sv).normalize()
        );
        checked += 1;
    }
    assert_eq!(checked, 17 * 17);
}

#[test]
fn catmull_clark_open_boundary_is_the_cubic_bspline_of_the_boundary_polygon() {
    let cage = bumpy_grid(5);
    let levels = 3;
    let (r, out) = refine(&cage, Scheme::CatmullClark, &[], levels);
    let start = cage.edges().map(|e| e.halfedge(0)).chain(cage.edges().map(|e| e.halfedge(1)));
    let start = start.into_iter().find(|&h| cage.is_boundary_halfedge(h)).unwrap();
    let hs = boundary_loop(&cage, start);
    let polygon: Vec<DVec3> = hs.iter().map(|&h| cage.position(cage.from_vertex(h))).collect();
    let steps = 1 << levels;
    for (i, &h) in hs.iter().enumerate() {
        let mut chain = r.cage_edge_chain(h.edge(), levels).unwrap();
        if chain[0] != cage.from_vertex(h) {
            chain.reverse();
        }
        assert_eq!(chain.len(), steps + 1);
        for (k, v) in chain.iter().enumerate() {
            let expected = closed_bspline(&polygon, i, k as f64 / steps as f64);
            assert!((out.limit[v.index()] - expected).length() < 1e-12, "span {i}, point {k}");
        }
    }
}

/// The level-`levels` positions after `extra` more levels, per vertex of level `levels`.
fn deeper(cage: &PolyMesh, scheme: Scheme, sharpness: &[f64], levels: u32, extra: u32) -> (Vec<DVec3>, Vec<DVec3>) {
    let (r, out) = refine(cage, scheme, sharpness, levels + extra);
    let n = r.mesh(levels).vertex_count();
    let normals = r.surface(out.finest()).vertex_normals();
    (out.finest()[..n].to_vec(), normals[..n].to_vec())
}

#[test]
fn catmull_clark_limit_points_and_normals_match_deep_subdivision() {
    let cages = [cube(), prism(5, 1.0, 1.5), bumpy_grid(3)];
    for cage in &cages {
        let size = cage.bounding_diagonal();
        let (r, out) = refine(cage, Scheme::CatmullClark, &[], 1);
        let (near, _) = deeper(cage, Scheme::CatmullClark, &[], 1, 4);
        let (deep, deep_normals) = deeper(cage, Scheme::CatmullClark, &[], 1, 6);
        let n = r.mesh(1).vertex_count();
        let (mut distance, mut nearer, mut normal) = (0.0f64, 0.0f64, 0.0f64);
        for v in 0..n {
            distance = distance.max((out.limit[v] - deep[v]).length() / size);
            nearer = nearer.max((out.limit[v] - near[v]).length() / size);
            if !r.mesh(1).is_boundary_vertex(VertexId(v as u32)) {
                normal = normal.max(angle(out.normals[v], deep_normals[v]));
            }
        }
        // Two more levels bring the vertices at least 3 times closer to the limit points.
        let faces = cage.face_count();
        assert!(
            distance < 1e-4 && 3.0 * distance < nearer,
            "{faces} faces: {distance:.2e} after 6, {nearer:.2e} after 4"
        );
        assert!(normal < 1e-4, "{faces} faces: normals {normal:.2e} rad from the deep mesh's");
    }
}

#[test]
fn catmull_clark_reproduces_affine_maps_and_is_similarity_invariant() {
    let cage = prism(6, 1.0, 0.8);
    let (_, out) = refine(&cage, Scheme::CatmullClark, &[], 2);
    let affine = |p: DVec3| DVec3::new(2.0 * p.x - p.z + 1.0, 0.5 * p.y + 0.3 * p.x, p.z - 2.0);
    let (_, moved) = refine(&transformed(&cage, affine), Scheme::CatmullClark, &[], 2);
    for (a, b) in out.levels[2].iter().zip(&moved.levels[2]).chain(out.limit.iter().zip(&moved.limit)) {
        assert!((affine(*a) - *b).length() < 1e-12);
    }
    let rotation = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
    let similar = |p: DVec3| 3.0 * (rotation * p) + DVec3::new(0.2, -1.0, 4.0);
    let triangles = triangulate(&cage, Triangulation::ShortestDiagonal).unwrap();
    for (scheme, cage) in [(Scheme::CatmullClark, &cage), (Scheme::Loop, &triangles)] {
        let (_, base) = refine(cage, scheme, &[], 2);
        let (_, sim) = refine(&transformed(cage, similar), scheme, &[], 2);
        for ((a, b), (p, q)) in base.normals.iter().zip(&sim.normals).zip(base.limit.iter().zip(&sim.limit)) {
            assert!(((rotation * *a) - *b).length() < 1e-12, "{scheme:?}");
            assert!((similar(*p) - *q).length() < 1e-12, "{scheme:?}");
        }
    }
    // Outward normals on a closed convex cage.
    let centre = cage.positions().iter().sum::<DVec3>() / cage.vertex_count() as f64;
    for (p, n) in out.limit.iter().zip(&out.normals) {
        assert!((*p - centre).dot(*n) > 0.0);
    }
}

/// A limit point and normal do not depend on the level they are computed from: vertex `v` of
/// level 1 is vertex `v` of level 3, and its limit from level 1 (through
/// `limit_stencils_at(1)`) must equal its limit from level 3. This holds only if every mask,
/// crease and boundary tangents included, is an exact left eigenvector of the subdivision.
#[test]
fn limits_do_not_depend_on_the_level_they_are_taken_at() {
    let l = l_shape();
    let c = cube();
    let sharp = |m: &PolyMesh, pairs: &[(u32, u32)]| {
        let p: Vec<_> = pairs.iter().map(|&(a, b)| (VertexId(a), VertexId(b), f64::INFINITY)).collect();
        sharpness_from_pairs(m, &p).unwrap()
    };
    let t = triangulate(&prism(5, 1.0, 1.2), Triangulation::ShortestDiagonal).unwrap();
    let cases = [
        (Scheme::CatmullClark, prism(5, 1.0, 1.2), vec![]),
        (Scheme::CatmullClark, l.clone(), vec![]),
        (Scheme::CatmullClark, c.clone(), sharp(&c, &[(4, 5), (5, 7), (7, 6), (0, 1), (0, 2), (0, 4)])),
        (Scheme::Loop, t.clone(), sharp(&t, &[(0, 1), (1, 2), (2, 3)])),
        (Scheme::Loop, triangulate(&l, Triangulation::Fan).unwrap(), vec![]),
    ];
    for (scheme, cage, sharpness) in cases {
        let (r, out) = refine(&cage, scheme, &sharpness, 3);
        let at1 = r.limit_stencils_at(1).unwrap();
        let (mut limit, mut normals) = (Vec::new(), Vec::new());
        at1.evaluate(&out.levels[1], &mut limit, &mut normals);
        for v in 0..r.mesh(1).vertex_count() {
            let d = (limit[v] - out.limit[v]).length();
            assert!(d < 1e-12, "{scheme:?} {} faces: vertex {v} limit {d:.2e} apart", cage.face_count());
            let a = angle(normals[v], out.normals[v]);
            assert!(a < 1e-9, "{scheme:?} {} faces: vertex {v} normal {a:.2e} rad apart", cage.face_count());
        }
    }
}

#[test]
fn refinement_keeps_euler_characteristic_and_cage_numbering() {
    for cage in [cube(), prism(5, 1.0, 1.0), bumpy_grid(3)] {
        let (r, _) = refine(&cage, Scheme::CatmullClark, &[], 3);
        for l in 0..=3 {
            r.mesh(l).validate().unwrap();
            assert_eq!(r.mesh(l).euler_characteristic(), cage.euler_characteristic());
        }
        for e in cage.edges() {
            let chain = r.cage_edge_chain(e, 3).unwrap();
            let (a, b) = cage.edge_vertices(e);
            assert_eq!((chain.len(), chain[0], chain[8]), (9, a, b));
            for w in chain.windows(2) {
                assert!(r.mesh(3).find_halfedge(w[0], w[1]).is_some());
            }
        }
    }
}

#[test]
fn bit_identical_for_one_and_two_threads() {
    for (scheme, cage) in [(Scheme::CatmullClark, bumpy_grid(16)), (Scheme::Loop, triangle_grid(16))] {
        let mut sharpness = vec![0.0; cage.edge_count()];
        sharpness[40] = 1.5;
        sharpness[41] = f64::INFINITY;
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let (r, out) = refine(&cage, scheme, &sharpness, 3);
                (r.stencils(3).clone(), r.limit_stencils().clone(), out.levels, out.limit, out.normals)
            })
        };
        assert!(run(1) == run(2), "{scheme:?}");
    }
}

#[test]
fn a_drag_update_is_bit_identical_to_a_full_evaluation() {
    for (scheme, cage) in [(Scheme::CatmullClark, bumpy_grid(12)), (Scheme::Loop, triangle_grid(12))] {
        let mut sharpness = vec![0.0; cage.edge_count()];
        sharpness[30] = 1.5;
        sharpness[31] = f64::INFINITY;
        let (r, mut dragged) = refine(&cage, scheme, &sharpness, 3);
        let mut positions = cage.positions().to_vec();
        let total = r.update(&positions, &mut dragged).unwrap();
        assert_eq!(total, 0, "nothing moved");
        for (step, v) in [40usize, 41, 0, 168].into_iter().enumerate() {
            positions[v] += DVec3::new(0.01, -0.02, 0.03 * step as f64);
            let recomputed = r.update(&positions, &mut dragged).unwrap();
            let mut fresh = RefinedPositions::default();
            r.evaluate(&positions, &mut fresh).unwrap();
            assert!(dragged.levels == fresh.levels && dragged.limit == fresh.limit && dragged.normals == fresh.normals);
            // A moved cage vertex reaches a small part of the surface only (about a 4 × 4 patch
            // of the 12 × 12 cage's faces).
            let rows: usize = (1..=3).map(|l| r.mesh(l).vertex_count()).sum::<usize>() + r.mesh(3).vertex_count();
            assert!(recomputed > 0 && recomputed < rows / 8, "{recomputed} of {rows}");
        }
        // Moving everything falls back to a full evaluation, with the same result; so do
        // positions whose limit was left behind or that another refinement filled.
        for p in &mut positions {
            *p = 2.0 * *p;
        }
        r.update(&positions, &mut dragged).unwrap();
        let mut fresh = RefinedPositions::default();
        r.evaluate(&positions, &mut fresh).unwrap();
        assert!(dragged.levels == fresh.levels && dragged.limit == fresh.limit && dragged.normals == fresh.normals);
        positions[7].x += 0.5;
        r.evaluate_levels(&positions, &mut dragged).unwrap();
        r.update(&positions, &mut dragged).unwrap();
        let other = Refinement::new(&cage, scheme, &sharpness, 3).unwrap();
        let mut foreign = RefinedPositions::default();
        other.evaluate(cage.positions(), &mut foreign).unwrap();
        r.update(&positions, &mut foreign).unwrap();
        r.evaluate(&positions, &mut fresh).unwrap();
        for out in [&dragged, &foreign] {
            assert!(out.levels == fresh.levels && out.limit == fresh.limit && out.normals == fresh.normals);
        }
    }
}

#[test]
fn catmull_clark_limit_helper_agrees_with_the_refinement() {
    let cage = prism(5, 1.0, 1.0);
    let (r, out) = refine(&cage, Scheme::CatmullClark, &[], 1);
    let level = r.surface(&out.levels[1]);
    for v in level.vertices() {
        let (p, n) = catmull_clark_limit(&level, v).unwrap();
        assert!((p - out.limit[v.index()]).length() < 1e-15);
        assert!((n - out.normals[v.index()]).length() < 1e-15);
    }
    let err = catmull_clark_limit(&cage, VertexId(0)).unwrap_err().to_string();
    assert!(err.contains("5 sides") && err.contains("subdivide once"), "{err}");
}

/// A regular tetrahedron centred at the origin, outward triangles.
fn tetrahedron() -> PolyMesh {
    let p = vec![
        DVec3::new(1.0, 1.0, 1.0),
        DVec3::new(1.0, -1.0, -1.0),
        DVec3::new(-1.0, 1.0, -1.0),
        DVec3::new(-1.0, -1.0, 1.0),
    ];
    PolyMesh::from_polygons(p, &[[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]).unwrap()
}

/// A triangulated bumpy grid whose interior vertices all have valence 6.
fn triangle_grid(n: u32) -> PolyMesh {
    triangulate(&bumpy_grid(n), Triangulation::Fan).unwrap()
}

#[test]
fn loop_first_level_of_a_tetrahedron_by_hand() {
    let cage = tetrahedron();
    assert!(cage.vertex_normals()[0].dot(DVec3::ONE) > 0.0, "the fixture is outward");
    let (r, out) = refine(&cage, Scheme::Loop, &[], 1);
    // Valence 3: β = (5/8 − (3/8 − 1/8)²)/3 = 3/16, so v' = 7/16 v + 3/16 Σ e = v/4 (Σ e = −v).
    for v in cage.vertices() {
        assert!((out.levels[1][v.index()] - 0.25 * cage.position(v)).length() < 1e-15);
    }
    // Edge point 3/8 (a + b) + 1/8 (c + d) = (a + b)/4, since c + d = −(a + b).
    for e in cage.edges() {
        let (a, b) = cage.edge_vertices(e);
        let expected = 0.25 * (cage.position(a) + cage.position(b));
        assert!((out.levels[1][r.split(1).edge_point(e).index()] - expected).length() < 1e-15);
    }
    assert_eq!((r.mesh(1).vertex_count(), r.mesh(1).face_count()), (10, 16));
    assert!(r.mesh(1).faces().all(|f| r.mesh(1).face_valence(f) == 3));
}

#[test]
fn loop_regular_limit_mask_is_one_half_and_one_twelfth() {
    let cage = triangle_grid(6);
    let (r, _) = refine(&cage, Scheme::Loop, &[], 1);
    let level = r.mesh(1);
    let rows = r.limit_stencils().position_rows();
    let mut regular = 0;
    for v in level.vertices().filter(|&v| !level.is_boundary_vertex(v) && level.valence(v) == 6) {
        for (c, w) in rows.row(v.index()) {
            let expected = if c == v.0 { 0.5 } else { 1.0 / 12.0 };
            assert!((w - expected).abs() < 1e-15, "vertex {v:?}: weight {w} on {c}");
        }
        regular += 1;
    }
    assert!(regular > 50);
}

#[test]
fn loop_limit_points_and_normals_match_deep_subdivision() {
    let cages =
        [tetrahedron(), triangulate(&prism(5, 1.0, 1.5), Triangulation::ShortestDiagonal).unwrap(), triangle_grid(3)];
    for cage in &cages {
        let size = cage.bounding_diagonal();
        let (r, out) = refine(cage, Scheme::Loop, &[], 1);
        let (near, _) = deeper(cage, Scheme::Loop, &[], 1, 4);
        let (deep, deep_normals) = deeper(cage, Scheme::Loop, &[], 1, 6);
        let (mut distance, mut nearer, mut normal) = (0.0f64, 0.0f64, 0.0f64);
        for v in 0..r.mesh(1).vertex_count() {
            distance = distance.max((out.limit[v] - deep[v]).length() / size);
            nearer = nearer.max((out.limit[v] - near[v]).length() / size);
            if !r.mesh(1).is_boundary_vertex(VertexId(v as u32)) {
                normal = normal.max(angle(out.normals[v], deep_normals[v]));
            }
        }
        let faces = cage.face_count();
        assert!(
            distance < 1e-4 && 3.0 * distance < nearer,
            "{faces} faces: {distance:.2e} after 6, {nearer:.2e} after 4"
        );
        assert!(normal < 1e-4, "{faces} faces: normals {normal:.2e} rad from the deep mesh's");
    }
}

#[test]
fn loop_limit_of_the_cage_equals_the_limit_matrix() {
    for cage in [tetrahedron(), triangle_grid(3)] {
        let (_, out) = refine(&cage, Scheme::Loop, &[], 0);
        let m = loop_limit_matrix(&cage).unwrap().apply(cage.positions());
        for (a, b) in out.limit.iter().zip(&m) {
            assert!((*a - *b).length() < 1e-15);
        }
    }
}

#[test]
fn loop_open_boundary_is_the_cubic_bspline_and_affine_maps_are_reproduced() {
    let cage = triangle_grid(4);
    let levels = 3;
    let (r, out) = refine(&cage, Scheme::Loop, &[], levels);
    let start = cage.edges().map(|e| e.halfedge(0)).chain(cage.edges().map(|e| e.halfedge(1)));
    let start = start.into_iter().find(|&h| cage.is_boundary_halfedge(h)).unwrap();
    let hs = boundary_loop(&cage, start);
    let polygon: Vec<DVec3> = hs.iter().map(|&h| cage.position(cage.from_vertex(h))).collect();
    for (i, &h) in hs.iter().enumerate() {
        let mut chain = r.cage_edge_chain(h.edge(), levels).unwrap();
        if chain[0] != cage.from_vertex(h) {
            chain.reverse();
        }
        for (k, v) in chain.iter().enumerate() {
            let expected = closed_bspline(&polygon, i, k as f64 / 8.0);
            assert!((out.limit[v.index()] - expected).length() < 1e-12, "span {i}, point {k}");
        }
    }
    let affine = |p: DVec3| DVec3::new(p.x - 2.0 * p.y, 0.5 * p.z + p.x, 3.0 * p.y + 1.0);
    let (_, moved) = refine(&transformed(&cage, affine), Scheme::Loop, &[], levels);
    for (a, b) in out.finest().iter().zip(moved.finest()).chain(out.limit.iter().zip(&moved.limit)) {
        assert!((affine(*a) - *b).length() < 1e-12);
    }
    for l in 0..=levels {
        assert_eq!(r.mesh(l).euler_characteristic(), cage.euler_characteristic());
    }
}

#[test]
fn loop_refuses_quads_with_a_hint_to_triangulate() {
    for levels in [0, 2] {
        let err = Refinement::new(&cube(), Scheme::Loop, &[], levels).unwrap_err().to_string();
        assert!(err.contains("face 0 has 4 sides") && err.contains("triangulate"), "{err}");
    }
}

/// An L of three quads: its inner corner is a boundary vertex with three faces.
fn l_shape() -> PolyMesh {
    let g = grid(2, 2, 1.0, |x, y| 0.3 * x * x - 0.2 * x * y + 0.1 * y);
    let polygons: Vec<Vec<u32>> = g.polygons().into_iter().take(3).collect();
    PolyMesh::from_polygons(g.positions().to_vec(), &polygons).unwrap()
}

/// At every boundary cage vertex with an interior edge, the plane through its limit point and the
/// limit points of its three neighbours at level `l` (along the boundary both ways, and into the
/// surface along the interior edge) tends to the limit tangent plane as `l` grows: the angle to
/// the limit normal must shrink geometrically.
#[test]
fn boundary_limit_normals_are_the_tangent_planes_of_deep_levels() {
    let cases = [
        (Scheme::CatmullClark, bumpy_grid(3)),
        (Scheme::CatmullClark, l_shape()),
        (Scheme::Loop, triangle_grid(3)),
        (Scheme::Loop, triangulate(&l_shape(), Triangulation::Fan).unwrap()),
    ];
    for (scheme, cage) in cases {
        let (_, base) = refine(&cage, scheme, &[], 0);
        let deep: Vec<(Refinement, RefinedPositions)> = (3..=7).map(|l| refine(&cage, scheme, &[], l)).collect();
        for v in cage.vertices().filter(|&v| cage.is_boundary_vertex(v)) {
            let out = cage.vertex_halfedge(v);
            let (next, prev) = (out.edge(), cage.prev(out).edge());
            let Some(inner) = cage.outgoing(v).find(|h| !cage.is_boundary_edge(h.edge())) else { continue };
            let angles: Vec<f64> = deep
                .iter()
                .map(|(r, o)| {
                    let near = |e| {
                        let c = r.cage_edge_chain(e, r.level_count()).unwrap();
                        o.limit[if c[0] == v { c[1] } else { c[c.len() - 2] }.index()]
                    };
                    let plane = (near(prev) - near(next)).cross(near(inner.edge()) - o.limit[v.index()]);
                    angle(plane, base.normals[v.index()])
                })
                .collect();
            let faces = cage.valence(v) - 1;
            for w in angles.windows(2) {
                assert!(w[1] < 0.8 * w[0], "{scheme:?}, vertex {} with {faces} faces: angles {angles:?}", v.0);
            }
        }
    }
}
