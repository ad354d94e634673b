//! The fresh path (topology derived level by level, positions and limits by the rules applied
//! directly) against the stencils a drag builds lazily, on every kind of vertex the rules tell
//! apart: the levels equal to rounding (the direct rules read each face point once made, the
//! stencils expand it into the face's corners), the limits to the bit; a drag gives the bits of
//! a fresh evaluation; one thread gives the bits of several.

use super::*;
use crate::mesh::primitives::torus;

/// A pentagon and five triangles (a pyramid), creased: semi-sharp, sharp and running-out edges,
/// a semi-sharp corner and a sharp one.
fn pyramid() -> (PolyMesh, Vec<f64>, Vec<f64>) {
    let mut p: Vec<DVec3> = (0..5)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 5.0;
            DVec3::new(a.cos(), a.sin(), 0.1 * k as f64)
        })
        .collect();
    p.push(DVec3::new(0.1, 0.0, 1.0));
    let mut faces: Vec<Vec<u32>> = vec![(0..5).rev().collect()];
    faces.extend((0..5).map(|k| vec![k, (k + 1) % 5, 5]));
    let cage = PolyMesh::from_polygons(p, &faces).unwrap();
    let sharpness = (0..cage.edge_count()).map(|e| [0.0, 0.5, 1.5, f64::INFINITY, 2.25][e % 5]).collect();
    let mut corners = vec![0.0; cage.vertex_count()];
    corners[5] = 1.5;
    corners[2] = f64::INFINITY;
    (cage, sharpness, corners)
}

/// An open strip of two quads and a triangle (boundaries, a boundary corner of valence 2).
fn open_strip() -> PolyMesh {
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

/// Two quads glued along all four edges: every vertex interior of valence 2.
fn pillow() -> PolyMesh {
    let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.2), DVec3::Y];
    PolyMesh::from_polygons(p, &[[0, 1, 2, 3], [3, 2, 1, 0]]).unwrap()
}

/// A torus large enough that every level is evaluated in several parallel chunks, with a sharp
/// ring and a semi-sharp one.
fn creased_torus() -> (PolyMesh, Vec<f64>) {
    let cage = torus(16, 12, 2.0, 0.7).unwrap();
    let sharpness = cage
        .edges()
        .map(|e| {
            let (a, b) = cage.edge_vertices(e);
            match (a.0 % 12, b.0 % 12) {
                (0, 0) => f64::INFINITY,
                (6, 6) => 1.5,
                _ => 0.0,
            }
        })
        .collect();
    (cage, sharpness)
}

/// A cone of twenty triangles on a twenty-sided base: the apex and the base's face point have
/// more spokes than the fast path of the limit takes.
fn cone() -> PolyMesh {
    let mut p: Vec<DVec3> = (0..20)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 20.0;
            DVec3::new(a.cos(), a.sin(), 0.05 * (k % 3) as f64)
        })
        .collect();
    p.push(DVec3::new(0.1, 0.0, 1.0));
    let mut faces: Vec<Vec<u32>> = vec![(0..20).rev().collect()];
    faces.extend((0..20).map(|k| vec![k, (k + 1) % 20, 20]));
    PolyMesh::from_polygons(p, &faces).unwrap()
}

fn triangulated(cage: &PolyMesh) -> PolyMesh {
    crate::mesh::edit::triangulate(cage, None, crate::mesh::edit::Triangulation::Fan).unwrap().mesh
}

/// A cage the test refines: name, cage, scheme, edge sharpness, vertex sharpness, levels.
type Case = (&'static str, PolyMesh, Scheme, Vec<f64>, Vec<f64>, u32);

/// Every cage the test refines.
fn cages() -> Vec<Case> {
    let (pyramid, sharpness, corners) = pyramid();
    let (torus, torus_sharpness) = creased_torus();
    let loop_pyramid = triangulated(&pyramid);
    let loop_sharpness = (0..loop_pyramid.edge_count()).map(|e| [0.0, 0.75, f64::INFINITY, 1.0][e % 4]).collect();
    let semi_sharp = torus_sharpness.iter().map(|&s| if s.is_finite() { s } else { 0.0 }).collect();
    let mut semi_corners = vec![0.0; torus.vertex_count()];
    semi_corners[3] = 1.25;
    let mut loop_corners = vec![0.0; loop_pyramid.vertex_count()];
    loop_corners[1] = 0.5;
    vec![
        ("creased pyramid", pyramid, Scheme::CatmullClark, sharpness, corners, 3),
        ("open strip", open_strip(), Scheme::CatmullClark, vec![], vec![], 3),
        ("pillow", pillow(), Scheme::CatmullClark, vec![], vec![], 3),
        ("cone", cone(), Scheme::CatmullClark, vec![], vec![], 3),
        ("cone, one level", cone(), Scheme::CatmullClark, vec![], vec![], 1),
        ("creased torus", torus.clone(), Scheme::CatmullClark, torus_sharpness.clone(), vec![], 3),
        // Semi-sharp only: smooth from level 2 on, where the direct rules read no sharpness.
        ("semi-sharp torus", torus.clone(), Scheme::CatmullClark, semi_sharp, semi_corners, 3),
        ("Loop pyramid", loop_pyramid, Scheme::Loop, loop_sharpness, loop_corners, 3),
        ("Loop open strip", triangulated(&open_strip()), Scheme::Loop, vec![], vec![], 3),
        ("Loop torus", triangulated(&torus), Scheme::Loop, vec![], vec![], 2),
    ]
}

fn bits(points: &[DVec3]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
}

#[test]
fn direct_rules_agree_with_the_lazy_stencils_and_a_drag_with_a_fresh_evaluation() {
    for (name, cage, scheme, sharpness, corners, levels) in cages() {
        let r = Refinement::with_corners(&cage, scheme, &sharpness, &corners, levels).unwrap();
        let mut out = RefinedPositions::default();
        r.evaluate(cage.positions(), &mut out).unwrap();
        assert_eq!(
            r.memory_bytes(),
            Refinement::with_corners(&cage, scheme, &sharpness, &corners, levels).unwrap().memory_bytes(),
            "{name}: nothing lazy is built by a fresh evaluation"
        );
        for l in 1..=levels {
            let stencil = r.stencils(l).apply(&out.levels[l as usize - 1]);
            for (v, (a, b)) in stencil.iter().zip(&out.levels[l as usize]).enumerate() {
                // A few roundings of coordinates of size about 1: far below 1e-12.
                assert!(
                    (*a - *b).length() <= 1e-13 * (1.0 + b.length()),
                    "{name}: level {l} vertex {v}: {a} against {b}"
                );
            }
        }
        let (mut limit, mut normals) = (Vec::new(), Vec::new());
        r.limit_stencils().evaluate(out.finest(), &mut limit, &mut normals);
        assert_eq!(bits(&limit), bits(&out.limit), "{name}: limit positions");
        assert_eq!(bits(&normals), bits(&out.normals), "{name}: limit normals");
        assert!(out.normals.iter().any(|n| n.length() > 0.5), "{name}: normals were computed");

        // A drag through the stencils, then the same positions fresh.
        let mut moved = cage.positions().to_vec();
        moved[1] += DVec3::new(0.01, -0.02, 0.03);
        r.update(&moved, &mut out).unwrap();
        let mut fresh = RefinedPositions::default();
        r.evaluate(&moved, &mut fresh).unwrap();
        for l in 0..=levels as usize {
            assert_eq!(bits(&out.levels[l]), bits(&fresh.levels[l]), "{name}: level {l} after a drag");
        }
        assert_eq!(bits(&out.limit), bits(&fresh.limit), "{name}: limit after a drag");
        assert_eq!(bits(&out.normals), bits(&fresh.normals), "{name}: normals after a drag");
    }
}

#[test]
fn a_fresh_evaluation_collected_into_new_buffers_is_the_one_made_in_place() {
    // Into empty buffers every point is collected once; into buffers of the right size it is
    // written in place. Both paths (levels, limit positions, normals) must give the same bits.
    for (name, cage, scheme, sharpness, corners, levels) in cages() {
        let r = Refinement::with_corners(&cage, scheme, &sharpness, &corners, levels).unwrap();
        let mut moved = cage.positions().to_vec();
        moved[0] += DVec3::new(-0.02, 0.01, 0.05);
        let mut fresh = RefinedPositions::default();
        r.evaluate(&moved, &mut fresh).unwrap();
        let mut reused = RefinedPositions::default();
        r.evaluate(cage.positions(), &mut reused).unwrap();
        let sizes: Vec<usize> = reused.levels.iter().map(Vec::len).collect();
        r.evaluate(&moved, &mut reused).unwrap();
        assert_eq!(sizes, reused.levels.iter().map(Vec::len).collect::<Vec<_>>(), "{name}: reused in place");
        for l in 0..=levels as usize {
            assert_eq!(bits(&reused.levels[l]), bits(&fresh.levels[l]), "{name}: level {l}");
        }
        assert_eq!(bits(&reused.limit), bits(&fresh.limit), "{name}: limit positions");
        assert_eq!(bits(&reused.normals), bits(&fresh.normals), "{name}: limit normals");
        assert_eq!(fresh.limit.len(), r.mesh(levels).vertex_count(), "{name}: every finest vertex");
        assert!(fresh.normals.iter().any(|n| n.length() > 0.5), "{name}: normals were computed");
    }
}

#[test]
fn every_level_carries_the_sharpness_down_whether_its_tables_are_made_at_once_or_on_first_use() {
    for (name, cage, scheme, sharpness, corners, levels) in cages() {
        let r = Refinement::with_corners(&cage, scheme, &sharpness, &corners, levels).unwrap();
        for l in 1..=levels {
            let (parent_edges, parent_corners) = (r.sharpness(l - 1).to_vec(), r.corners(l - 1).to_vec());
            let (mesh, split) = (r.mesh(l), r.split(l));
            // A half of a parent edge carries its sharpness less 1; an edge inside a face is smooth.
            let edges = r.sharpness(l);
            assert_eq!(edges.len(), mesh.edge_count(), "{name}: level {l} edge table");
            for e in mesh.edges() {
                let want = split.edge_parent(e).map_or(0.0, |p| child_sharpness(parent_edges[p.index()]));
                assert_eq!(edges[e.index()], want, "{name}: level {l} edge {}", e.0);
            }
            // A parent vertex carries its sharpness less 1; edge and face points are smooth.
            let vertices = r.corners(l);
            assert_eq!(vertices.len(), mesh.vertex_count(), "{name}: level {l} vertex table");
            for (v, &s) in vertices.iter().enumerate() {
                let want = parent_corners.get(v).map_or(0.0, |&c| child_sharpness(c));
                assert_eq!(s, want, "{name}: level {l} vertex {v}");
            }
        }
    }
    // A smooth closed cage's levels make their (all-zero) tables only when asked.
    let cage = pillow();
    let r = Refinement::new(&cage, Scheme::CatmullClark, &[], 2).unwrap();
    let before = r.memory_bytes();
    assert!(r.sharpness(2).iter().chain(r.corners(2)).all(|&s| s == 0.0));
    assert_eq!(
        r.memory_bytes(),
        before + 8 * (r.mesh(2).edge_count() + r.mesh(2).vertex_count()),
        "the smooth level's tables were made before they were asked for"
    );
}

#[test]
fn topology_and_positions_do_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            cages()
                .into_iter()
                .map(|(_, cage, scheme, sharpness, corners, levels)| {
                    let r = Refinement::with_corners(&cage, scheme, &sharpness, &corners, levels).unwrap();
                    let mut out = RefinedPositions::default();
                    r.evaluate(cage.positions(), &mut out).unwrap();
                    let polygons: Vec<_> = (0..=levels).map(|l| r.mesh(l).polygons()).collect();
                    let stencils: Vec<_> = (1..=levels).map(|l| r.stencils(l).clone()).collect();
                    let levels: Vec<_> = out.levels.iter().map(|l| bits(l)).collect();
                    (polygons, levels, bits(&out.limit), bits(&out.normals), stencils, r.limit_stencils().clone())
                })
                .collect::<Vec<_>>()
        })
    };
    let one = run(1);
    assert!(one == run(3), "three threads gave other results than one");
}

#[test]
fn derived_levels_are_valid_meshes_with_the_face_lists_of_the_rules() {
    for (name, cage, scheme, sharpness, corners, levels) in cages() {
        let r = Refinement::with_corners(&cage, scheme, &sharpness, &corners, levels).unwrap();
        for l in 1..=levels {
            let (parent, mesh) = (r.mesh(l - 1), r.mesh(l));
            assert_eq!(mesh.validate(), Ok(()), "{name}: level {l}");
            // The same faces, built by matching halfedges from the face list.
            let matched = PolyMesh::from_polygons(mesh.positions().to_vec(), &mesh.polygons()).unwrap();
            assert_eq!(
                (matched.edge_count(), matched.euler_characteristic()),
                (mesh.edge_count(), parent.euler_characteristic())
            );
            for v in mesh.vertices() {
                let mut ours: Vec<u32> = mesh.vertex_neighbors(v).map(|u| u.0).collect();
                let mut theirs: Vec<u32> = matched.vertex_neighbors(v).map(|u| u.0).collect();
                ours.sort_unstable();
                theirs.sort_unstable();
                assert_eq!(ours, theirs, "{name}: level {l} vertex {}", v.0);
                assert_eq!(mesh.is_boundary_vertex(v), matched.is_boundary_vertex(v));
            }
            let split = r.split(l);
            for e in parent.edges() {
                let (a, b) = parent.edge_vertices(e);
                let m = split.edge_point(e);
                for (half, end) in split.edge_children(e).into_iter().zip([a, b]) {
                    let (x, y) = mesh.edge_vertices(half);
                    assert_eq!((x.min(y), x.max(y)), (end.min(m), end.max(m)), "{name}: halves of {e:?}");
                    assert_eq!(split.edge_parent(half), Some(e));
                }
            }
        }
    }
}
