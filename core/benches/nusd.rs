//! NUSD speed, reported as ratios against references measured in the same run.
//!
//! - One iteration on ~100 k and ~1 M vertices, as vertex updates per second and as a ratio to
//!   a plain streaming pass (read and write) over the same number of bytes with the same threads:
//!   how close the iteration is to the memory-bandwidth limit (target: within 4× at 1 M).
//! - Full 3-level solves from scratch: the default scene, a ~500-face cage (target: < 33 ms,
//!   live dragging) and a ~2 000-face cage (curved tori), with the share spent building levels.
//!
//! Run with `cargo bench -p taut-core` (release profile). `TAUT_BENCH_QUICK=1` runs fewer repeats.

use rayon::prelude::*;
use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};
use taut_core::nusd::surface::hierarchy::LevelTopology;
use taut_core::nusd::surface::kernel::{self, State};
use taut_core::nusd::surface::operator::{Controls, Operator};
use taut_core::nusd::surface::{LevelReport, SurfaceSolver};
use taut_core::{DVec3, Document, PolyMesh};

fn grid(n: u32) -> PolyMesh {
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            p.push(DVec3::new(x, y, 0.2 * (3.0 * x).sin() * (2.0 * y).cos()));
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

/// A closed, curved genus-1 cage of `nu × nv` quads with uneven radii (a designer-like load:
/// curvature everywhere, no flat regions that converge at once).
fn torus(nu: u32, nv: u32) -> PolyMesh {
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

/// Median wall time of `f` over `repeats` runs.
fn median(repeats: usize, mut f: impl FnMut()) -> Duration {
    let mut times: Vec<Duration> = (0..repeats)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .collect();
    times.sort();
    times[times.len() / 2]
}

fn iteration_bench(label: &str, cage_cells: u32, repeats: usize) {
    let cage = grid(cage_cells);
    let mut level = LevelTopology::cage(&cage);
    for _ in 0..3 {
        level = level.refine().unwrap();
    }
    let n = level.vertex_count();
    let domain = level.mesh.positions().to_vec();
    let fixed = vec![true; cage.vertex_count()];
    let zeros = vec![0.0; cage.vertex_count()];
    let edge_zeros = vec![0.0; cage.edge_count()];
    let controls =
        Controls { fixed: &fixed, vertex_tension: &zeros, edge_tension: &edge_zeros, spacing: Default::default() };
    let op = Operator::build(&level, &domain, &cage, &controls);
    let mut state = State::new(domain.clone(), vec![DVec3::ZERO; n]);
    kernel::iterate(&op, &level.mesh, &mut state, 0.6);
    let iteration = median(repeats, || {
        black_box(kernel::iterate(&op, &level.mesh, &mut state, 0.6));
    });

    // The same bytes as one iteration: reads of P, R (own and gathered once), offsets, K,
    // role, neighbour indices and both weight arrays; writes of P and R.
    let slots = op.neighbors.len();
    let read_bytes = n * (2 * 24 + 4 + 8 + 1) + slots * (4 + 8 + 8);
    let write_bytes = n * 2 * 24;
    let source = vec![1.0f64; read_bytes / 8];
    let mut sink = vec![0.0f64; write_bytes / 8];
    let stream = median(repeats, || {
        let total: f64 = source.par_chunks(1 << 14).map(|c| c.iter().sum::<f64>()).sum();
        sink.par_chunks_mut(1 << 14).for_each(|c| c.fill(total));
        black_box(&sink);
    });
    let updates_per_s = n as f64 / iteration.as_secs_f64();
    println!(
        "{label}: {n} vertices, one iteration {:.2} ms = {:.1} M vertex updates/s; streaming pass over the same {:.0} MB {:.2} ms; ratio {:.2}x",
        iteration.as_secs_f64() * 1e3,
        updates_per_s / 1e6,
        (read_bytes + write_bytes) as f64 / 1e6,
        stream.as_secs_f64() * 1e3,
        iteration.as_secs_f64() / stream.as_secs_f64()
    );
}

fn solve_bench(label: &str, doc: &Document, repeats: usize) {
    let mut reports: Vec<LevelReport> = Vec::new();
    let mut finest = 0usize;
    let time = median(repeats, || {
        let mut solver = SurfaceSolver::new(doc).unwrap();
        reports = solver.solve().unwrap();
        finest = solver.surface_positions().len();
    });
    // Reference: one iteration of the finest level, measured now.
    let mut solver = SurfaceSolver::new(doc).unwrap();
    solver.solve().unwrap();
    let mut doc1 = doc.clone();
    doc1.settings.max_iterations = 1;
    let one = median(repeats, || {
        let mut s = SurfaceSolver::new(&doc1).unwrap();
        s.solve().unwrap();
    });
    // A drag step: move one cage vertex by 1 % of the diagonal and re-solve warm.
    let mut dragged = doc.clone();
    let mut step = 0usize;
    let mut warm_iterations = 0usize;
    let warm = median(repeats, || {
        step += 1;
        let offset = 0.01 * doc.cage.bounding_diagonal() * if step.is_multiple_of(2) { 1.0 } else { -1.0 };
        let v = taut_core::VertexId(0);
        dragged.cage.set_position(v, doc.cage.position(v) + DVec3::new(offset, 0.5 * offset, 0.0));
        solver.update(&dragged).unwrap();
        solver.solve().unwrap();
        warm_iterations = solver.status().total_iterations;
    });
    println!(
        "{label}: drag step (1 % of the diagonal) re-solved warm in {:.1} ms, {warm_iterations} iterations = {:.0}% of a solve from scratch",
        warm.as_secs_f64() * 1e3,
        100.0 * warm.as_secs_f64() / time.as_secs_f64()
    );
    let counts: Vec<usize> = reports.iter().map(|r| r.iterations).collect();
    println!(
        "{label}: {} cage faces → {} faces, {} vertices at level {}; full solve {:.1} ms; iterations per level {:?}; \
         setup (building the levels, one iteration each) {:.2} ms = {:.0}% of the solve",
        doc.cage.face_count(),
        solver.surface_topology().face_count(),
        finest,
        doc.settings.levels,
        time.as_secs_f64() * 1e3,
        counts,
        one.as_secs_f64() * 1e3,
        100.0 * one.as_secs_f64() / time.as_secs_f64(),
    );
}

fn main() {
    let quick = std::env::var_os("TAUT_BENCH_QUICK").is_some();
    let repeats = if quick { 3 } else { 11 };
    println!("threads: {}", rayon::current_num_threads());
    iteration_bench("iteration ~100k", 40, repeats);
    iteration_bench("iteration ~1M", 125, repeats.min(7));

    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
    let default = Document::load(&assets.join("default.taut")).unwrap();
    solve_bench("default scene", &default, repeats);
    solve_bench("~500-face torus cage", &Document::new(torus(32, 16)), repeats);
    solve_bench("~2000-face torus cage", &Document::new(torus(64, 32)), repeats.min(5));
}
