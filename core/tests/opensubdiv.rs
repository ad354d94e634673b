//! Agreement with an independent implementation of Pixar's rules: the `opensubdiv-rs` crate (a
//! Rust port of OpenSubdiv's Sdc/Vtr/Far layers).
//!
//! The same cage, scheme, levels and creases go to both; vertices are matched through the
//! refinement's own bookkeeping (not by position): level-0 vertices are the same, and at every
//! level the child of a parent vertex, edge or face on one side is matched with the child of the
//! matched parent vertex, edge (found by its matched end vertices) or face (found by its matched
//! corner set) on the other. Every level's positions and the finest level's limit positions are
//! compared.
//!
//! The crate stores every mask weight as an `f32` (its `Primvar::add_with_weight` takes an `f32`
//! weight even for `f64` data), so it is exact only where all weights are dyadic rationals: the
//! refinement of quad grids of valence-4 vertices, boundaries, creases, sharpness in halves.
//! Those levels are held to 1e-9 of the cage size (they agree to about 1e-16). Limit masks
//! (1/36, 1/6, …) and cages with other valences (weights like 1/9, cos 2π/5) are held to 1e-6,
//! the crate's `f32` precision (measured: a few 1e-8).
//!
//! Limit positions are compared everywhere except at darts of an infinitely sharp edge, where
//! OpenSubdiv takes the smooth limit mask and Taut the exact one (`subdiv::eigen_masks`); there the test checks instead that
//! Taut's limit is the nearer one (measured 4 to 450 times nearer) to the vertex after three more
//! levels of the (agreeing) rules.

use opensubdiv_rs::far::{PrimvarRefiner, TopologyDescriptor, TopologyRefiner, TopologyRefinerFactory, UniformOptions};
use opensubdiv_rs::sdc::{self, SchemeType, VtxBoundaryInterpolation};
use std::collections::HashMap;
use taut_core::mesh::edit::Triangulation;
use taut_core::subdiv::{RefinedPositions, Refinement, Rule, Scheme, VertexOrigin};
use taut_core::{DVec3, PolyMesh, VertexId};

/// Every face cut into triangles (the cage-editing triangulation; vertices kept).
fn triangulate(mesh: &PolyMesh, how: Triangulation) -> taut_core::Result<PolyMesh> {
    Ok(taut_core::mesh::edit::triangulate(mesh, None, how)?.mesh)
}

/// Their refiner for `cage` with edge and vertex sharpness (their creases and corner
/// vertices), refined uniformly to `levels`.
fn theirs_with_corners(
    cage: &PolyMesh,
    scheme: Scheme,
    sharpness: &[f64],
    corners: &[f64],
    levels: u32,
) -> TopologyRefiner {
    let sizes: Vec<usize> = cage.faces().map(|f| cage.face_valence(f)).collect();
    let indices: Vec<u32> = cage.polygons().concat();
    let mut pairs = Vec::new();
    let mut weights = Vec::new();
    for e in cage.edges() {
        let s = sharpness.get(e.index()).copied().unwrap_or(0.0);
        if s > 0.0 {
            let (a, b) = cage.edge_vertices(e);
            pairs.push([a.0, b.0]);
            // OpenSubdiv's infinite sharpness is 10.
            weights.push(if s.is_infinite() { 10.0 } else { s as f32 });
        }
    }
    let (mut corner_vertices, mut corner_weights) = (Vec::new(), Vec::new());
    for (v, &s) in corners.iter().enumerate().filter(|(_, s)| **s > 0.0) {
        corner_vertices.push(v as u32);
        corner_weights.push(if s.is_infinite() { 10.0 } else { s as f32 });
    }
    let descriptor = TopologyDescriptor::new(cage.vertex_count(), &sizes, &indices)
        .with_creases(&pairs, &weights)
        .with_corners(&corner_vertices, &corner_weights);
    let scheme = match scheme {
        Scheme::CatmullClark => SchemeType::Catmark,
        Scheme::Loop => SchemeType::Loop,
    };
    let options = sdc::Options::default().with_vtx_boundary_interpolation(VtxBoundaryInterpolation::EdgeOnly);
    let mut refiner =
        TopologyRefinerFactory::create(descriptor, scheme, options).expect("their refiner accepts the cage");
    refiner.refine_uniform(UniformOptions::new(levels as usize));
    refiner
}

/// For every level, our vertex `v` ↦ their vertex index.
fn correspondence(ours: &Refinement, refiner: &TopologyRefiner) -> Vec<Vec<u32>> {
    let mut maps = vec![(0..ours.mesh(0).vertex_count() as u32).collect::<Vec<u32>>()];
    for l in 1..=ours.level_count() {
        let parent = ours.mesh(l - 1);
        let their_parent = refiner.level(l as usize - 1);
        let refinement = refiner.refinement(l as usize);
        let map = &maps[l as usize - 1];
        let mut faces = HashMap::new();
        for f in 0..their_parent.num_faces() {
            let mut key = their_parent.face_vertices(f).to_vec();
            key.sort();
            faces.insert(key, f);
        }
        let split = ours.split(l);
        let child: Vec<u32> = split
            .mesh
            .vertices()
            .map(|v| match split.origin(v) {
                VertexOrigin::Vertex(p) => refinement.vertex_child_vertex(map[p.index()] as usize),
                VertexOrigin::Edge(e) => {
                    let (a, b) = parent.edge_vertices(e);
                    let edge = their_parent.find_edge(map[a.index()], map[b.index()]).expect("matched edge");
                    refinement.edge_child_vertex(edge as usize)
                }
                VertexOrigin::Face(f) => {
                    let mut key: Vec<u32> = parent.face_vertices(f).map(|u| map[u.index()]).collect();
                    key.sort();
                    refinement.face_child_vertex(faces[&key])
                }
            })
            .collect();
        maps.push(child);
    }
    maps
}

/// The largest distance, relative to the cage size, between our vertices and theirs over all
/// levels, and between the limit positions of the finest level.
fn disagreement(cage: &PolyMesh, scheme: Scheme, sharpness: &[f64], levels: u32) -> (f64, f64) {
    disagreement_with(cage, scheme, sharpness, sharpness, levels)
}

/// Like [`disagreement`], with their creases given apart (to show that creases matter).
fn disagreement_with(
    cage: &PolyMesh,
    scheme: Scheme,
    sharpness: &[f64],
    their_sharpness: &[f64],
    levels: u32,
) -> (f64, f64) {
    disagreement_of_corners(cage, scheme, sharpness, (&[], &[]), their_sharpness, levels)
}

/// Like [`disagreement_with`], with vertex sharpness: ours and theirs (given apart).
fn disagreement_of_corners(
    cage: &PolyMesh,
    scheme: Scheme,
    sharpness: &[f64],
    (corners, their_corners): (&[f64], &[f64]),
    their_sharpness: &[f64],
    levels: u32,
) -> (f64, f64) {
    let ours = Refinement::with_corners(cage, scheme, sharpness, corners, levels).unwrap();
    let mut out = RefinedPositions::default();
    ours.evaluate(cage.positions(), &mut out).unwrap();
    let refiner = theirs_with_corners(cage, scheme, their_sharpness, their_corners, levels);
    let maps = correspondence(&ours, &refiner);
    let primvar = PrimvarRefiner::new(&refiner);
    let mut theirs: Vec<[f64; 3]> = cage.positions().iter().map(|p| p.to_array()).collect();
    let size = cage.bounding_diagonal();
    let mut level_error = 0.0f64;
    for l in 1..=levels as usize {
        let mut next = vec![[0.0; 3]; refiner.level(l).num_vertices()];
        primvar.interpolate(l, &theirs, &mut next);
        theirs = next;
        assert_eq!(theirs.len(), out.levels[l].len(), "vertex counts at level {l}");
        for (v, &t) in maps[l].iter().enumerate() {
            level_error = level_error.max((out.levels[l][v] - DVec3::from_array(theirs[t as usize])).length() / size);
        }
    }
    let mut limit = theirs.clone();
    primvar.limit(&theirs, &mut limit);
    let map = maps.last().unwrap();
    let finest = ours.level_count();
    let sharp = ours.sharpness(finest);
    let infinite_dart = |v: usize| {
        let v = VertexId(v as u32);
        let mesh = ours.mesh(finest);
        ours.vertex_rule(finest, v) == Rule::Dart && mesh.outgoing(v).any(|h| sharp[h.edge().index()] == f64::INFINITY)
    };
    let darts: Vec<usize> = (0..out.limit.len()).filter(|&v| infinite_dart(v)).collect();
    let limit_error = (0..out.limit.len())
        .filter(|v| !darts.contains(v))
        .map(|v| (out.limit[v] - DVec3::from_array(limit[map[v] as usize])).length() / size)
        .fold(0.0, f64::max);
    if !darts.is_empty() {
        let deeper = Refinement::with_corners(cage, scheme, sharpness, corners, levels + 3).unwrap();
        let mut deep = RefinedPositions::default();
        deeper.evaluate_levels(cage.positions(), &mut deep).unwrap();
        for &v in &darts {
            let target = deep.finest()[v];
            let (mine, their) =
                ((out.limit[v] - target).length(), (DVec3::from_array(limit[map[v] as usize]) - target).length());
            assert!(mine < 0.5 * their, "dart {v}: ours {mine:.2e} from the deep vertex, theirs {their:.2e}");
        }
    }
    (level_error, limit_error)
}

fn grid(n: u32) -> PolyMesh {
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64, j as f64);
            p.push(DVec3::new(x, y, (0.9 * x).sin() * (0.6 * y).cos() + 0.05 * x * y));
        }
    }
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            faces.push([v, v + 1, v + n + 2, v + n + 1]);
        }
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

fn cube() -> PolyMesh {
    let p = (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64) - 0.5).collect();
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// A pentagonal prism, stretched and sheared so nothing is symmetric.
fn prism() -> PolyMesh {
    let mut p = Vec::new();
    for z in [0.0, 1.3] {
        for k in 0..5 {
            let a = std::f64::consts::TAU * k as f64 / 5.0;
            p.push(DVec3::new(1.4 * a.cos() + 0.3 * z, a.sin(), z + 0.1 * k as f64));
        }
    }
    let mut faces: Vec<Vec<u32>> = vec![(0..5).rev().collect(), (5..10).collect()];
    for k in 0..5 {
        faces.push(vec![k, (k + 1) % 5, 5 + (k + 1) % 5, 5 + k]);
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// Sharpness for `creases` given as `(a, b, s)`.
fn creases(cage: &PolyMesh, creases: &[(u32, u32, f64)]) -> Vec<f64> {
    let pairs: Vec<_> = creases.iter().map(|&(a, b, s)| (VertexId(a), VertexId(b), s)).collect();
    taut_core::subdiv::sharpness_from_pairs(cage, &pairs).unwrap()
}

#[test]
fn catmull_clark_levels_of_dyadic_cages_agree_to_1e9() {
    let g = grid(5);
    // A sharp line, a semi-sharp line that runs out (1.5 and 0.5), a dart, a corner where the
    // sharp line meets the boundary, and a crease vertex whose edges run out unequally.
    let s = creases(
        &g,
        &[
            (7, 8, f64::INFINITY),
            (8, 9, f64::INFINITY),
            (9, 10, f64::INFINITY),
            (14, 20, 1.5),
            (20, 26, 0.5),
            (21, 22, 2.0),
        ],
    );
    for sharpness in [vec![], s.clone()] {
        let (level, limit) = disagreement(&g, Scheme::CatmullClark, &sharpness, 3);
        assert!(level < 1e-9 && limit < 1e-6, "level {level:.2e}, limit {limit:.2e}");
    }
    // The creases matter on both sides: against their smooth surface ours differs.
    let (level, _) = disagreement_with(&g, Scheme::CatmullClark, &s, &[], 3);
    assert!(level > 1e-3, "{level}");
}

#[test]
fn catmull_clark_on_irregular_cages_agrees_to_f32_precision() {
    let c = cube();
    let p = prism();
    let cases = [
        (c.clone(), vec![], 3),
        (c.clone(), creases(&c, &[(4, 5, f64::INFINITY), (5, 7, f64::INFINITY), (7, 6, 1.5), (6, 4, 0.5)]), 3),
        (c.clone(), creases(&c, &[(0, 1, f64::INFINITY), (0, 2, f64::INFINITY), (0, 4, 2.5)]), 4),
        // Sharpness still left at the finest level (4.5 − 3): the limit takes it as a crease.
        (c.clone(), creases(&c, &[(0, 1, 4.5), (1, 3, 4.5), (3, 2, 4.5), (2, 0, 4.5), (4, 5, 3.25)]), 3),
        (p.clone(), vec![], 3),
        (p.clone(), creases(&p, &[(0, 1, 1.0), (1, 2, 3.0), (1, 6, 0.7), (7, 8, f64::INFINITY)]), 3),
    ];
    for (cage, sharpness, levels) in cases {
        let (level, limit) = disagreement(&cage, Scheme::CatmullClark, &sharpness, levels);
        assert!(level < 1e-6 && limit < 1e-6, "{} faces: level {level:.2e}, limit {limit:.2e}", cage.face_count());
        if !sharpness.is_empty() {
            assert!(disagreement_with(&cage, Scheme::CatmullClark, &sharpness, &[], levels).0 > 1e-3);
        }
    }
}

#[test]
fn loop_agrees_to_f32_precision() {
    let g = triangulate(&grid(4), Triangulation::Fan).unwrap();
    let p = triangulate(&prism(), Triangulation::ShortestDiagonal).unwrap();
    let cases = [
        (g.clone(), vec![], 3),
        (g.clone(), creases(&g, &[(6, 7, f64::INFINITY), (7, 8, 1.5), (8, 13, 0.5), (12, 13, 2.0)]), 3),
        (p.clone(), vec![], 3),
        (p.clone(), creases(&p, &[(0, 1, 1.0), (1, 2, 3.0), (1, 6, 0.7), (7, 8, f64::INFINITY)]), 3),
    ];
    for (cage, sharpness, levels) in cases {
        let (level, limit) = disagreement(&cage, Scheme::Loop, &sharpness, levels);
        assert!(level < 1e-6 && limit < 1e-6, "{} faces: level {level:.2e}, limit {limit:.2e}", cage.face_count());
        if !sharpness.is_empty() {
            assert!(disagreement_with(&cage, Scheme::Loop, &sharpness, &[], levels).0 > 1e-3);
        }
    }
}

/// Vertex sharpness for `corners` given as `(v, s)`.
fn corners(cage: &PolyMesh, corners: &[(u32, f64)]) -> Vec<f64> {
    let pairs: Vec<_> = corners.iter().map(|&(v, s)| (VertexId(v), s)).collect();
    taut_core::subdiv::corners_from_pairs(cage, &pairs).unwrap()
}

/// Corners (vertex sharpness: sharp, semi-sharp running out at each level, with and without
/// creases through them, on the boundary and inside) agree with OpenSubdiv's in both schemes.
#[test]
fn corners_agree_with_opensubdiv_in_both_schemes() {
    let c = cube();
    let g = grid(4);
    let p = prism();
    let t = triangulate(&grid(4), Triangulation::Fan).unwrap();
    let tp = triangulate(&prism(), Triangulation::ShortestDiagonal).unwrap();
    let cases = [
        (Scheme::CatmullClark, c.clone(), vec![], corners(&c, &[(0, f64::INFINITY), (7, 1.5), (5, 0.5)]), 3),
        (
            Scheme::CatmullClark,
            c.clone(),
            creases(&c, &[(4, 5, f64::INFINITY), (5, 7, 2.0)]),
            corners(&c, &[(5, 2.5), (2, 1.0), (6, f64::INFINITY)]),
            4,
        ),
        // Interior corners of a flat grid, one semi-sharp still left at the finest level.
        (Scheme::CatmullClark, g.clone(), vec![], corners(&g, &[(6, f64::INFINITY), (12, 0.7), (18, 3.5)]), 3),
        (Scheme::CatmullClark, p.clone(), vec![], corners(&p, &[(0, 2.0), (9, f64::INFINITY)]), 3),
        (Scheme::Loop, t.clone(), vec![], corners(&t, &[(6, f64::INFINITY), (12, 1.5), (0, 0.5)]), 3),
        (
            Scheme::Loop,
            tp.clone(),
            creases(&tp, &[(0, 1, 1.0), (7, 8, f64::INFINITY)]),
            corners(&tp, &[(1, f64::INFINITY), (8, 0.4)]),
            3,
        ),
    ];
    for (scheme, cage, sharpness, vertex, levels) in cases {
        let (level, limit) = disagreement_of_corners(&cage, scheme, &sharpness, (&vertex, &vertex), &sharpness, levels);
        assert!(
            level < 1e-6 && limit < 1e-6,
            "{scheme:?}, {} faces: level {level:.2e}, limit {limit:.2e}",
            cage.face_count()
        );
        // The corners matter: against their surface without them ours differs.
        let (without, _) = disagreement_of_corners(&cage, scheme, &sharpness, (&vertex, &[]), &sharpness, levels);
        assert!(without > 1e-3, "{scheme:?}: {without}");
    }
    // A sharp corner stays where it is at every level and in the limit.
    let ours = Refinement::with_corners(&c, Scheme::CatmullClark, &[], &corners(&c, &[(0, f64::INFINITY)]), 3).unwrap();
    let mut out = RefinedPositions::default();
    ours.evaluate(c.positions(), &mut out).unwrap();
    assert_eq!(out.limit[0], c.position(VertexId(0)));
    assert!(out.normals[0].length() > 0.99);
}
