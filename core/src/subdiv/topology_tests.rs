//! The split against its face lists, the walks it saves and the index functions.

use super::*;
use crate::DVec3;
use crate::nusd::surface::hierarchy::LevelTopology;

fn pyramid_with_pentagon() -> PolyMesh {
    // A pentagonal pyramid with a quad cut: one pentagon, five triangles; plus an open quad
    // strip so boundaries are exercised.
    let mut p: Vec<DVec3> = (0..5)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 5.0;
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    p.push(DVec3::new(0.1, 0.0, 1.0));
    let mut faces: Vec<Vec<u32>> = vec![(0..5).rev().collect()];
    for k in 0..5 {
        faces.push(vec![k, (k + 1) % 5, 5]);
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

fn open_mixed() -> PolyMesh {
    let p = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.3),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 1.0, 0.2),
        DVec3::new(2.0, 1.2, 0.0),
        DVec3::new(3.0, 0.5, 0.0),
    ];
    PolyMesh::from_polygons(p, &[vec![0, 1, 4, 3], vec![1, 2, 5, 4], vec![2, 6, 5]]).unwrap()
}

#[test]
fn mixed_rule_gives_exactly_the_nusd_hierarchy() {
    // Each step from the same parent: NUSD numbers a level's edges by matching its face list,
    // the split by the parent's halfedges, so edge points are numbered alike only one step
    // at a time.
    for cage in [pyramid_with_pentagon(), open_mixed()] {
        let mut nusd = LevelTopology::cage(&cage);
        for _ in 0..3 {
            let split = SplitTopology::split(&nusd.mesh, SplitRule::Mixed).unwrap();
            nusd = nusd.refine().unwrap();
            assert_eq!(split.mesh.polygons(), nusd.mesh.polygons());
            assert_eq!(split.mesh.positions(), nusd.mesh.positions());
        }
    }
}

#[test]
fn counts_euler_origins_and_halves() {
    let cage = pyramid_with_pentagon();
    for (rule, faces) in [(SplitRule::Quads, 5 + 5 * 3), (SplitRule::Mixed, 5 + 5 * 4)] {
        let s = SplitTopology::split(&cage, rule).unwrap();
        s.mesh.validate().unwrap();
        assert_eq!(s.mesh.face_count(), faces);
        assert_eq!(s.mesh.euler_characteristic(), cage.euler_characteristic());
        for v in s.mesh.vertices() {
            let expected = match s.origin(v) {
                VertexOrigin::Vertex(p) => cage.position(p),
                VertexOrigin::Edge(e) => {
                    let (a, b) = cage.edge_vertices(e);
                    0.5 * (cage.position(a) + cage.position(b))
                }
                VertexOrigin::Face(f) => {
                    assert_eq!(s.face_point(f), Some(v));
                    cage.face_vertices(f).map(|u| cage.position(u)).sum::<DVec3>() / cage.face_valence(f) as f64
                }
            };
            assert!((s.mesh.position(v) - expected).length() < 1e-15);
        }
        for e in cage.edges() {
            let (a, b) = cage.edge_vertices(e);
            let m = s.edge_point(e);
            let [ca, cb] = s.edge_children(e);
            let ends = |c: EdgeId| {
                let (x, y) = s.mesh.edge_vertices(c);
                [x.min(y), x.max(y)]
            };
            assert_eq!(ends(ca), [a.min(m), a.max(m)]);
            assert_eq!(ends(cb), [b.min(m), b.max(m)]);
            assert_eq!((s.edge_parent(ca), s.edge_parent(cb)), (Some(e), Some(e)));
        }
        let halves = s.mesh.edges().filter(|&c| s.edge_parent(c).is_some()).count();
        assert_eq!(halves, 2 * cage.edge_count());
        for f in s.mesh.faces() {
            let parent = s.face_parent(f);
            // Every child face's parent-vertex corners are corners of its parent face.
            for v in s.mesh.face_vertices(f).filter(|v| v.index() < cage.vertex_count()) {
                assert!(cage.face_vertices(parent).any(|u| u == v));
            }
        }
    }
}

#[test]
fn triangles_rule_refuses_other_faces_and_splits_triangles_in_four() {
    let err = SplitTopology::split(&open_mixed(), SplitRule::Triangles).unwrap_err().to_string();
    assert!(err.contains("face 0 has 4 sides") && err.contains("triangulate"), "{err}");
    let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    let tet = PolyMesh::from_polygons(p, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]).unwrap();
    let s = SplitTopology::split(&tet, SplitRule::Triangles).unwrap();
    assert_eq!((s.mesh.vertex_count(), s.mesh.face_count()), (10, 16));
    assert!(s.mesh.faces().all(|f| s.mesh.face_valence(f) == 3));
    assert_eq!(s.mesh.euler_characteristic(), 2);
    assert!(tet.faces().all(|f| s.face_point(f).is_none()));
}

#[test]
fn quad_halfedges_are_the_index_functions() {
    // The per-parent-halfedge fill of a split into quads gives every child halfedge the
    // values the index functions give: pentagon, triangles, open boundaries, an isolated
    // vertex, and meshes large enough to be cut into several tasks.
    let isolated = {
        let strip = open_mixed();
        let mut p = strip.positions().to_vec();
        p.push(DVec3::splat(7.0));
        PolyMesh::from_polygons(p, &strip.polygons()).unwrap()
    };
    // 90 × 70 quads with a hole: over 12,000 parent halfedges, several tasks.
    let grid = grid_with_hole(91, 71, 40..45, 30..33);
    for cage in [pyramid_with_pentagon(), open_mixed(), isolated, grid] {
        let first = SplitTopology::split(&cage, SplitRule::Quads).unwrap();
        for parent in [&cage, &first.mesh] {
            let plan = Plan::new(parent, SplitRule::Quads, None);
            let nh = plan.halves as usize + 2 * plan.interior_count();
            let (fast, slow) = (plan.quad_halfedges(nh), plan.halfedges(nh));
            assert_eq!(fast.to, slow.to);
            assert_eq!(fast.next, slow.next);
            assert_eq!(fast.prev, slow.prev);
            assert_eq!(fast.face, slow.face);
        }
    }
}

#[test]
fn a_split_again_plans_what_walking_the_faces_plans() {
    // Below a split into quads, the plan read from the halfedges' indices must be the plan walked
    // round the faces, closed (torus) or open (grid with a hole, a mixed cage), and the children
    // the same.
    let torus = crate::mesh::primitives::torus(6, 5, 2.0, 0.7).unwrap();
    let grid = grid_with_hole(9, 7, 4..5, 3..4);
    for cage in [torus, grid, pyramid_with_pentagon(), open_mixed()] {
        let mut above = SplitTopology::split(&cage, SplitRule::Quads).unwrap();
        for _ in 0..2 {
            for rule in [SplitRule::Quads, SplitRule::Mixed] {
                let walked = Plan::new(&above.mesh, rule, None);
                let read = Plan::new(&above.mesh, rule, Some(4 * above.parent_edges));
                let np = above.mesh.halfedge_count() as u32;
                let faced = |h: &u32| above.mesh.face(HalfedgeId(*h)).is_valid();
                let corners = |plan: &Plan| (0..np).filter(faced).map(|h| plan.corner(h)).collect::<Vec<_>>();
                assert_eq!(corners(&read), corners(&walked));
                let slots = |plan: &Plan| (0..np).map(|h| plan.slot(h)).collect::<Vec<_>>();
                assert_eq!(slots(&read), slots(&walked));
                assert_eq!(read.interior_count(), walked.interior_count());
                let interiors = |plan: &Plan| {
                    (0..plan.interior_count() as u32).map(|s| plan.interior_halfedge(s)).collect::<Vec<_>>()
                };
                assert_eq!(interiors(&read), interiors(&walked));
                let nf = above.mesh.face_count();
                let firsts = |plan: &Plan| (0..=nf).map(|f| plan.first_child(f)).collect::<Vec<_>>();
                assert_eq!(firsts(&read), firsts(&walked));
                assert_eq!(read.face_point, walked.face_point);
                assert_eq!(read.face_point_face, walked.face_point_face);
                let (again, once) = (
                    SplitTopology::split_again(&above, rule).unwrap(),
                    SplitTopology::split(&above.mesh, rule).unwrap(),
                );
                assert_same_mesh(&again.mesh, &once.mesh);
                assert_eq!(again.face_parent, once.face_parent);
            }
            above = SplitTopology::split_again(&above, SplitRule::Quads).unwrap();
        }
    }
}

fn assert_same_mesh(a: &PolyMesh, b: &PolyMesh) {
    assert_eq!(a.positions(), b.positions());
    assert_eq!(a.halfedge_count(), b.halfedge_count());
    for h in (0..a.halfedge_count() as u32).map(HalfedgeId) {
        assert_eq!(
            (a.to_vertex(h), a.next(h), a.prev(h), a.face(h)),
            (b.to_vertex(h), b.next(h), b.prev(h), b.face(h))
        );
    }
    assert!(a.vertices().all(|v| a.vertex_halfedge(v) == b.vertex_halfedge(v)));
    assert!(a.faces().all(|f| a.face_halfedge(f) == b.face_halfedge(f)));
}

/// A flat grid of `(nx − 1) × (ny − 1)` quads without the quads at columns `holes_x` of rows
/// `holes_y`.
fn grid_with_hole(nx: u32, ny: u32, holes_x: std::ops::Range<u32>, holes_y: std::ops::Range<u32>) -> PolyMesh {
    let p = (0..nx * ny).map(|k| DVec3::new((k % nx) as f64, (k / nx) as f64, 0.0)).collect();
    let faces: Vec<[u32; 4]> = (0..ny - 1)
        .flat_map(|j| (0..nx - 1).map(move |i| (i, j)))
        .filter(|&(i, j)| !holes_x.contains(&i) || !holes_y.contains(&j))
        .map(|(i, j)| [j * nx + i, j * nx + i + 1, (j + 1) * nx + i + 1, (j + 1) * nx + i])
        .collect();
    PolyMesh::from_polygons(p, &faces).unwrap()
}

#[test]
fn quad_spokes_are_the_child_walk() {
    // A pentagon, triangles, an open quad strip, an isolated vertex, and a second level of
    // quads; every child vertex's spokes must be its outgoing walk, in the same order.
    let isolated = {
        let strip = open_mixed();
        let mut p = strip.positions().to_vec();
        p.push(DVec3::splat(7.0));
        PolyMesh::from_polygons(p, &strip.polygons()).unwrap()
    };
    for cage in [pyramid_with_pentagon(), isolated] {
        let first = SplitTopology::split(&cage, SplitRule::Quads).unwrap();
        let second = SplitTopology::split(&first.mesh, SplitRule::Quads).unwrap();
        for (parent, s) in [(&cage, &first), (&first.mesh, &second)] {
            let child = &s.mesh;
            for v in child.vertices() {
                let mut derived = Vec::new();
                let interior = s.quad_spokes(parent, v, |e, to, across| derived.push((e, to, across)));
                let walked: Vec<_> = child
                    .outgoing(v)
                    .map(|h| {
                        let e = s.edge_parent(h.edge()).map(|_| h.edge());
                        (e, child.to_vertex(h).0, child.to_vertex(child.next(h)).0)
                    })
                    .collect();
                if child.is_isolated(v) || child.is_boundary_vertex(v) {
                    assert!(!interior && derived.is_empty(), "vertex {}", v.0);
                } else {
                    assert!(interior, "vertex {}", v.0);
                    assert_eq!(derived, walked, "vertex {}", v.0);
                }
            }
        }
    }
}

#[test]
fn isolated_vertices_are_kept_in_place() {
    let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(5.0, 5.0, 5.0)];
    let m = PolyMesh::from_polygons(p, &[[0, 1, 2]]).unwrap();
    let s = SplitTopology::split(&m, SplitRule::Quads).unwrap();
    assert!(s.mesh.is_isolated(VertexId(3)));
    assert_eq!(s.mesh.position(VertexId(3)), DVec3::splat(5.0));
}
