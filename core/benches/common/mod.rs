//! What the export and visibility benchmarks share: the quad torus they measure on and the
//! shortest-of-n timer.

use std::time::{Duration, Instant};
use taut_core::{DVec3, PolyMesh};

/// A closed, curved genus-1 cage of `nu × nv` quads with uneven radii (the subdivision
/// benchmark's load).
pub fn torus(nu: u32, nv: u32) -> PolyMesh {
    let mut p = Vec::new();
    for i in 0..nu {
        let a = std::f64::consts::TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let b = std::f64::consts::TAU * j as f64 / nv as f64;
            let r = 0.3 * (1.0 + 0.25 * (3.0 * a).sin());
            let big = 1.0 + 0.1 * (2.0 * b).cos();
            p.push(DVec3::new((big + r * b.cos()) * a.cos(), (big + r * b.cos()) * a.sin(), r * b.sin()));
        }
    }
    let mut faces = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (i1, j1) = ((i + 1) % nu, (j + 1) % nv);
            faces.push([i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1]);
        }
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// The shortest wall time of `f` over `repeats` runs: the least disturbed run is the best
/// estimate of the work itself.
pub fn best(repeats: usize, mut f: impl FnMut()) -> Duration {
    (0..repeats)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .min()
        .expect("at least one run")
}
