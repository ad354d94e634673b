//! Fixtures shared by the curve-mesh tests: the bundled cages, a mixed-valence cage built here,
//! and small helpers.

#![allow(dead_code)] // each test file uses its own share

use std::path::{Path, PathBuf};
use taut_core::gregory::GregoryPatch;
use taut_core::subdiv::{RefinedPositions, Refinement, Scheme};
use taut_core::{DVec3, Document, FaceId, PolyMesh, VertexId, io};

pub fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets")
}

/// Every bundled cage: `assets/*.obj` and the default scene.
pub fn bundled() -> Vec<(String, PolyMesh)> {
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
pub fn mixed_cage() -> PolyMesh {
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
pub fn quad_mesh(cage: &PolyMesh) -> PolyMesh {
    if cage.faces().all(|f| cage.face_valence(f) == 4) {
        return cage.clone();
    }
    let r = Refinement::new(cage, Scheme::CatmullClark, &[], 1).unwrap();
    let mut out = RefinedPositions::default();
    r.evaluate_levels(cage.positions(), &mut out).unwrap();
    r.surface(out.finest())
}

pub fn largest_edge(mesh: &PolyMesh) -> f64 {
    mesh.edges().map(|e| mesh.edge_length(e)).fold(0.0, f64::max)
}

pub fn same_patch(a: &GregoryPatch, b: &GregoryPatch) -> bool {
    a.control_points()
        .iter()
        .zip(b.control_points().iter())
        .all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits))
}

/// The faces around a vertex, ascending.
pub fn faces_around(mesh: &PolyMesh, v: VertexId) -> Vec<FaceId> {
    let mut f: Vec<FaceId> = mesh.outgoing(v).map(|h| mesh.face(h)).filter(|f| f.is_valid()).collect();
    f.sort();
    f
}

/// A cube of side 100 with one corner pulled out along its diagonal by half its distance from
/// the centre (every vertex of valence 3, nothing subdivided first: the coarsest curve mesh).
pub fn pulled_cube() -> PolyMesh {
    let corners = [(-1, -1, 1), (1, -1, 1), (-1, -1, -1), (1, -1, -1), (-1, 1, 1), (1, 1, 1), (-1, 1, -1), (1, 1, -1)];
    let mut p: Vec<DVec3> = corners.iter().map(|&(x, y, z)| 50.0 * DVec3::new(x as f64, y as f64, z as f64)).collect();
    p[5] *= 1.5;
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    PolyMesh::from_polygons(p, &faces.map(|f| f.to_vec())).unwrap()
}
