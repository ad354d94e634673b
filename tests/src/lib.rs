//! Shared fixtures for Taut's cross-crate tests: small cages built in code, so every test states
//! exactly what it runs on.

pub mod files;
pub mod golden;
pub mod shapes;
pub mod subdiv;

use taut_core::{DVec3, Document, PolyMesh};

/// The unit cube centred at the origin, outward quads.
pub fn cube() -> PolyMesh {
    let p = (0..8)
        .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64) - DVec3::splat(0.5))
        .collect();
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    PolyMesh::from_polygons(p, &faces).expect("the cube is valid")
}

/// An open `nx × ny` grid of quads on `[0, nx·h] × [0, ny·h]`, with heights from `z(x, y)`.
pub fn grid(nx: u32, ny: u32, h: f64, z: impl Fn(f64, f64) -> f64) -> PolyMesh {
    let mut p = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64 * h, j as f64 * h);
            p.push(DVec3::new(x, y, z(x, y)));
        }
    }
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let v = j * (nx + 1) + i;
            faces.push([v, v + 1, v + nx + 2, v + nx + 1]);
        }
    }
    PolyMesh::from_polygons(p, &faces).expect("the grid is valid")
}

/// A prism over a regular `n`-gon of circumradius `r` and height `h`: n-gon caps, quad sides.
pub fn prism(n: u32, r: f64, h: f64) -> PolyMesh {
    let mut p = Vec::new();
    for z in [0.0, h] {
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            p.push(DVec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    let mut faces: Vec<Vec<u32>> = vec![(0..n).rev().collect(), (n..2 * n).collect()];
    for k in 0..n {
        let k1 = (k + 1) % n;
        faces.push(vec![k, k1, n + k1, n + k]);
    }
    PolyMesh::from_polygons(p, &faces).expect("the prism is valid")
}

/// A document over `cage` with default settings and the given number of levels and tolerance.
pub fn document(cage: PolyMesh, levels: u32, tol: f64) -> Document {
    let mut doc = Document::new(cage);
    doc.settings.levels = levels;
    doc.settings.tol = tol;
    doc
}

/// Applies `f` to every position of a mesh.
pub fn transformed(mesh: &PolyMesh, f: impl Fn(DVec3) -> DVec3) -> PolyMesh {
    let mut out = mesh.clone();
    for p in out.positions_mut() {
        *p = f(*p);
    }
    out
}
