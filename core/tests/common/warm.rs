//! What the NUSD warm-start tests share (`nusd_topology_warm.rs`, `nusd_topology_warm_mirror.rs`):
//! solves, the tight fixed point, distances and the sweep comparison of a warm and a cold solve.

#![allow(dead_code)] // each test file uses its own share

use taut_core::nusd::surface::{LevelTiming, SurfaceSolver};
use taut_core::{DVec3, Document};

pub fn solved(doc: &Document) -> SurfaceSolver {
    let mut solver = SurfaceSolver::new(doc).unwrap();
    solver.solve().unwrap();
    solver
}

/// The surface solved to 1e-12: the fixed point both solves approach.
pub fn exact(doc: &Document) -> Vec<DVec3> {
    let mut tight = doc.clone();
    tight.settings.tol = 1e-12;
    tight.settings.max_iterations = 400_000;
    solved(&tight).surface_positions().to_vec()
}

pub fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max)
}

/// Bit patterns of a position, for matching domain points exactly.
pub fn key(p: DVec3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

/// Asserts the warm solve's work is under `bound` times the cold one's, and that at the finest
/// level it takes under twice that share of the work and at most one cycle more. Sweeps as the
/// solver counts them: `work` weighs a sweep of a region by its share of the level, `sweeps`
/// counts each once. (The finest level's sweeps were once bounded by the cold solve's; since a
/// cold solve relaxes whole levels by Gauss–Seidel in 4-sweep cycles it takes 2–3 of them, and a
/// local solve of the region round a delete took 3, 12 sweeps against 8, at a twentieth of the
/// work.)
pub fn assert_warm_cheaper(name: &str, warm: &SurfaceSolver, cold: &SurfaceSolver, bound: f64) {
    let (w, c) = (warm.timings(), cold.timings());
    let total = |t: &[LevelTiming]| t.iter().map(|l| l.work).sum::<f64>();
    let sweeps = |t: &[LevelTiming]| t.iter().map(|l| l.sweeps).collect::<Vec<_>>();
    eprintln!("{name}: warm {:.1} level sweeps {:?}, cold {:.1} {:?}", total(w), sweeps(w), total(c), sweeps(c));
    assert!(total(w) < bound * total(c), "{name}: warm {w:?} against cold {c:?}");
    let last = w.len() - 1;
    assert!(
        w[last].cycles <= c[last].cycles + 1 && w[last].work < 2.0 * bound * c[last].work,
        "{name}: {:?} {:?}",
        w[last],
        c[last]
    );
}
