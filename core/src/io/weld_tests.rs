//! Tests of the weld (kept apart from it so each file holds one idea).

use super::*;

/// The unit cube with every face on its own four vertices, as exporters write it with hard
/// edges: 24 vertices, each corner appearing three times.
fn split_cube() -> (Vec<DVec3>, Vec<[u32; 4]>) {
    let corner = |i: u32| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64);
    let shared = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for face in shared {
        let base = positions.len() as u32;
        positions.extend(face.iter().map(|&i| corner(i)));
        faces.push([base, base + 1, base + 2, base + 3]);
    }
    (positions, faces)
}

#[test]
fn split_cube_welds_to_eight_corners_in_first_appearance_order() {
    let (positions, faces) = split_cube();
    let w = weld(&positions, &faces).unwrap();
    assert_eq!(w.report.welded, 16);
    assert_eq!(w.positions.len(), 8);
    // Independent reference: the distinct positions in order of first appearance.
    let mut expected: Vec<DVec3> = Vec::new();
    for p in &positions {
        if !expected.contains(p) {
            expected.push(*p);
        }
    }
    assert_eq!(w.positions, expected);
    for (face, original) in w.faces.iter().zip(&faces) {
        let a: Vec<DVec3> = face.iter().map(|&v| w.positions[v as usize]).collect();
        let b: Vec<DVec3> = original.iter().map(|&v| positions[v as usize]).collect();
        assert_eq!(a, b);
    }
    let mesh = PolyMesh::from_polygons(w.positions, &w.faces.to_vecs()).unwrap();
    assert!(mesh.is_closed());
    assert_eq!(mesh.euler_characteristic(), 2);
    assert_eq!(w.report.to_string(), "welded 16 vertices");
}

#[test]
fn distinct_positions_keep_their_numbering() {
    let positions = vec![DVec3::Y, DVec3::ZERO, DVec3::X, DVec3::ONE];
    let faces = [[2, 1, 0], [3, 2, 0]];
    let w = weld(&positions, &faces).unwrap();
    assert_eq!(w.positions, positions);
    assert_eq!(w.faces.to_vecs(), vec![vec![2, 1, 0], vec![3, 2, 0]]);
    assert!(w.report.is_clean());
    assert_eq!(w.report.to_string(), "nothing welded or repaired");
}

#[test]
fn negative_zero_welds_with_zero() {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(-0.0, 0.0, -0.0)];
    let w = weld(&positions, &[[0, 1, 2], [3, 2, 1]]).unwrap();
    assert_eq!(w.report.welded, 1);
    assert_eq!(w.positions.len(), 3);
    // The second face became [0, 2, 1]: the first facing the other way.
    assert_eq!((w.report.dropped_faces, w.report.duplicate_faces), (1, 1));
    assert_eq!(w.faces.to_vecs(), vec![vec![0, 1, 2]]);
}

#[test]
fn collapsed_edges_are_removed_cyclically() {
    // Vertex 4 sits on vertex 0: the pentagon's closing edge has length zero.
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::ONE, DVec3::Y, DVec3::ZERO];
    let w = weld(&positions, &[[0, 1, 2, 3, 4]]).unwrap();
    assert_eq!(w.faces.to_vecs(), vec![vec![0, 1, 2, 3]]);
    assert_eq!((w.report.welded, w.report.repaired_faces, w.report.dropped_faces), (1, 1, 0));
    assert!(w.report.warnings[0].contains("repaired face 0"), "{:?}", w.report.warnings);
}

#[test]
fn faces_left_with_two_vertices_are_dropped() {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::X, DVec3::ONE];
    // Face 1 collapses (vertex 3 is vertex 1); face 2 survives, renumbered to [1, 3, 2].
    let faces = vec![vec![0, 1, 2], vec![1, 3, 2], vec![1, 4, 2]];
    let w = weld(&positions, &faces).unwrap();
    assert_eq!(w.faces.to_vecs(), vec![vec![0, 1, 2], vec![1, 3, 2]]);
    assert_eq!(w.report.dropped_faces, 1);
    assert_eq!(
        w.report.to_string(),
        "welded 1 vertex, dropped 1 degenerate face; dropped face 1: fewer than 3 distinct vertices are left once repeats are removed"
    );
}

#[test]
fn a_pinched_face_is_refused_by_number() {
    // Vertex 3 lands on vertex 1, which is not next to it in face 1.
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::X, DVec3::ONE, DVec3::Z];
    let faces = vec![vec![0, 1, 2], vec![1, 4, 3, 5]];
    let err = weld(&positions, &faces).unwrap_err().to_string();
    assert!(err.contains("face 1 passes through vertex 1 twice once vertices"), "{err}");
}

#[test]
fn duplicate_faces_are_dropped_and_listed() {
    let (positions, faces) = split_cube();
    let mut faces = faces.to_vec();
    faces.push(faces[2]);
    faces.push([faces[3][1], faces[3][2], faces[3][3], faces[3][0]]);
    let w = weld(&positions, &faces).unwrap();
    assert_eq!(w.faces.len(), 6);
    assert_eq!((w.report.dropped_faces, w.report.duplicate_faces), (2, 2));
    assert_eq!(
        w.report.to_string(),
        "welded 16 vertices, dropped 2 duplicate faces; dropped face 6: it repeats face 2; dropped face 7: it repeats face 3"
    );
    assert_eq!(w.report.warnings, vec!["dropped face 6: it repeats face 2", "dropped face 7: it repeats face 3"]);
}

#[test]
fn out_of_range_indices_are_an_error_not_a_panic() {
    let err = weld(&[DVec3::ZERO], &[[0, 1, 2]]).unwrap_err().to_string();
    assert!(err.contains("only 1 vertices"), "{err}");
}

/// A tetrahedron on four vertices of its own, with apex `apex` and the rest below it.
fn tetrahedron(base: u32, apex: DVec3, scale: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let p = vec![
        apex,
        apex + scale * DVec3::new(1.0, 0.0, -1.0),
        apex + scale * DVec3::new(-0.5, 0.8, -1.0),
        apex + scale * DVec3::new(-0.5, -0.8, -1.0),
    ];
    let f = [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]].map(|t| t.map(|i| base + i));
    (p, f.to_vec())
}

#[test]
fn parts_that_touch_at_a_point_stay_two_parts() {
    // Two closed tetrahedra, each on its own vertices, apex to apex at the origin (as the
    // monkey's eyes touch its head): welding the apexes would pinch the surface there.
    let (mut positions, mut faces) = tetrahedron(0, DVec3::ZERO, 1.0);
    let (p2, f2) = tetrahedron(4, DVec3::ZERO, -1.0);
    positions.extend(p2);
    faces.extend(f2);
    let w = weld(&positions, &faces).unwrap();
    assert_eq!(w.positions.len(), 8);
    assert_eq!((w.report.welded, w.report.kept_apart), (0, 1));
    assert!(
        w.report.warnings.iter().any(|m| m.contains("parts only touch at [0.0, 0.0, 0.0]: each keeps")),
        "{:?}",
        w.report.warnings
    );
    let mesh = PolyMesh::from_polygons(w.positions, &w.faces.to_vecs()).unwrap();
    mesh.validate().unwrap();
    assert_eq!(mesh.euler_characteristic(), 4, "two spheres");
}

#[test]
fn split_vertices_of_one_part_are_still_welded_next_to_a_touching_part() {
    // The split cube welds to 8 corners while a tetrahedron touching one corner stays apart.
    let (mut positions, faces) = split_cube();
    let mut faces: Vec<Vec<u32>> = faces.iter().map(|f| f.to_vec()).collect();
    let (p2, f2) = tetrahedron(positions.len() as u32, DVec3::ZERO, -0.5);
    positions.extend(p2);
    faces.extend(f2.iter().map(|f| f.to_vec()));
    let w = weld(&positions, &faces).unwrap();
    assert_eq!(w.positions.len(), 8 + 4);
    assert_eq!((w.report.welded, w.report.kept_apart), (16, 1));
    let mesh = PolyMesh::from_polygons(w.positions, &w.faces.to_vecs()).unwrap();
    assert_eq!(mesh.euler_characteristic(), 4);
    assert!(mesh.is_closed());
}

#[test]
fn parts_that_share_an_edge_position_stay_apart_along_it() {
    // Two quads folded along x = 0 on their own vertices and a third on the same edge: three
    // faces on one edge would be non-manifold, so that edge is not welded at all.
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let positions = vec![
        p(0.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(1.0, 1.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 0.0, 0.0),
        p(-1.0, 0.0, 0.0),
        p(-1.0, 1.0, 0.0),
        p(0.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 1.0, 1.0),
        p(0.0, 0.0, 1.0),
    ];
    let faces = [[0, 1, 2, 3], [4, 5, 6, 7], [8, 9, 10, 11]];
    let w = weld(&positions, &faces).unwrap();
    // The edge from (0,0,0) to (0,1,0) is used a → b twice and b → a once: nothing is glued.
    assert_eq!(w.positions.len(), 12);
    assert_eq!(w.report.kept_apart, 4);
    PolyMesh::from_polygons(w.positions, &w.faces.to_vecs()).unwrap().validate().unwrap();
}

#[test]
fn a_file_that_is_non_manifold_by_itself_is_not_repaired_by_splitting() {
    // One file vertex shared by two separate fans stays one vertex: the mesh refuses it.
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y];
    let w = weld(&positions, &[[0, 1, 2], [0, 3, 4]]).unwrap();
    assert_eq!(w.positions.len(), 5);
    assert_eq!(w.report.kept_apart, 0);
    let err = PolyMesh::from_polygons(w.positions, &w.faces.to_vecs()).unwrap_err().to_string();
    assert!(err.contains("non-manifold vertex 0"), "{err}");
}

#[test]
fn each_vertex_finds_the_first_at_its_position_as_a_full_sort_would() {
    // 30,000 vertices on 2,000 positions, −0.0 and 0.0 mixed, in scrambled order: the bucketed
    // grouping must give each vertex the lowest index at its bit-equal position.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let places: Vec<DVec3> = (0..2_000)
        .map(|i| {
            DVec3::new((i % 13) as f64 * 0.1, if i % 7 == 0 { 0.0 } else { (i / 13) as f64 }, 1.0 / (i + 1) as f64)
        })
        .collect();
    let positions: Vec<DVec3> = (0..30_000)
        .map(|_| {
            let p = places[(next() % 2_000) as usize];
            if p.y == 0.0 && next() % 2 == 0 { DVec3::new(p.x, -0.0, p.z) } else { p }
        })
        .collect();
    let key = |p: DVec3| (p + DVec3::ZERO).to_array().map(f64::to_bits);
    let mut expected = vec![0u32; positions.len()];
    for (v, &p) in positions.iter().enumerate() {
        expected[v] = positions.iter().position(|&q| key(q) == key(p)).unwrap() as u32;
    }
    assert_eq!(first_at_same_position(&positions), expected);
    // Buckets sorted once they hold more distinct positions than are searched one by one.
    for linear in [0, 1, 2] {
        assert_eq!(first_at_same_position_searching(&positions, linear), expected, "{linear}");
    }
    assert!(first_at_same_position(&[]).is_empty());
    assert_eq!(first_at_same_position(&[DVec3::ONE]), vec![0]);
}
