//! NUSD at scale (issue 13): multigrid against the plain iteration and a sparse direct solve,
//! as ratios measured in the same run.
//!
//! - Work per level: sweeps of each level 1–5 of the default scene (and with its 16 waist
//!   vertices unfixed), plain against multigrid, and the time of each.
//! - After a drag of one cage vertex by 1 % of the diagonal: the time to re-converge the finest
//!   level of a curved torus cage at level 3 (2 048 faces → 131 k vertices) and at level 5
//!   (1 024 faces → 1 M vertices), re-solved locally (the default, `nusd::surface::local`) and
//!   with every level re-solved whole, as a ratio to one plain iteration of that level and to a
//!   sparse LU solve (faer) of the same level's linear system (the fixed point without tension
//!   is linear in P and R: assembled here, factorised and solved for x, y and z), whose answer is
//!   checked against the local one.
//!
//! Run with `cargo bench -p taut-core --bench nusd_scale`. `TAUT_BENCH_QUICK=1` runs fewer
//! repeats; `TAUT_BENCH_NO_1M=1` skips the million-vertex case.

use faer::prelude::*;
use faer::sparse::{SparseColMat, Triplet};
use std::path::Path;
use std::time::{Duration, Instant};
use taut_core::nusd::surface::SurfaceSolver;
use taut_core::nusd::surface::hierarchy::LevelTopology;
use taut_core::nusd::surface::kernel::{self, State};
use taut_core::nusd::surface::operator::{Controls, Operator, Role};
use taut_core::{DVec3, Document, PolyMesh, VertexId};

/// A closed, curved genus-1 cage of `nu × nv` quads with uneven radii.
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

fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn levels_bench(label: &str, doc: &Document) {
    println!("work per level, {label}, levels 1-5 (sweeps of the level; ms):");
    for multigrid in [false, true] {
        let mut solver = SurfaceSolver::new(doc).unwrap();
        solver.set_multigrid(multigrid);
        let start = Instant::now();
        solver.solve().unwrap();
        let total = start.elapsed();
        let t = solver.timings();
        println!(
            "  {:<10} sweeps {:?}, work in sweeps of each level {:?}, ms {:?}, total {:.1} ms",
            if multigrid { "multigrid" } else { "plain" },
            t.iter().skip(1).map(|t| t.sweeps).collect::<Vec<_>>(),
            t.iter().skip(1).map(|t| t.work.round() as usize).collect::<Vec<_>>(),
            t.iter().skip(1).map(|t| (t.seconds * 1e4).round() / 10.0).collect::<Vec<_>>(),
            ms(total)
        );
    }
}

/// The finest level of `doc` built directly: connectivity, domain and operator.
fn finest_level(doc: &Document) -> (LevelTopology, Vec<DVec3>, Operator) {
    let mut level = LevelTopology::cage(&doc.cage);
    for _ in 0..doc.settings.levels {
        level = level.refine().unwrap();
    }
    let domain = level.mesh.positions().to_vec();
    let controls = Controls {
        fixed: &doc.fixed,
        vertex_tension: &doc.vertex_tension,
        edge_tension: &doc.edge_tension,
        spacing: doc.settings.spacing,
    };
    let op = Operator::build(&level, &domain, &doc.cage, &controls);
    (level, domain, op)
}

/// The level's fixed point without tension as a sparse linear system: per moving vertex `i` the
/// unknowns `P_i`, `R_i` and the equations `ΔR_i = 0`, `ΔP_i − K_i R_i = 0`, with fixed vertices'
/// `R_j = ΔP_j / K_j` substituted; solved by sparse LU for the three coordinates.
fn direct_solve(op: &Operator, positions: &[DVec3]) -> (Vec<DVec3>, Duration, usize) {
    let n = op.role.len();
    let mut unknown = vec![u32::MAX; n];
    let mut m = 0usize;
    for i in 0..n {
        if op.role[i] == Role::Moving {
            unknown[i] = m as u32;
            m += 1;
        }
    }
    let start = Instant::now();
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(m * 30);
    let mut rhs = Mat::<f64>::zeros(2 * m, 3);
    let add_rhs = |rhs: &mut Mat<f64>, row: usize, value: DVec3| {
        for c in 0..3 {
            rhs[(row, c)] += value[c];
        }
    };
    let slots = |i: usize| op.offsets[i] as usize..op.offsets[i + 1] as usize;
    for i in 0..n {
        if unknown[i] == u32::MAX {
            continue;
        }
        let (rr, pr) = (2 * unknown[i] as usize, 2 * unknown[i] as usize + 1);
        // R equation: Σ w_r R_j − R_i = 0.
        triplets.push(Triplet::new(rr, rr, -1.0));
        for s in slots(i) {
            let (j, w) = (op.neighbors[s] as usize, op.weight_r[s]);
            if w == 0.0 {
                continue;
            }
            if unknown[j] != u32::MAX {
                triplets.push(Triplet::new(rr, 2 * unknown[j] as usize, w));
            } else {
                // R_j = (Σ w_p P_k − P_j) / K_j at a fixed neighbour.
                let scale = w / op.k[j];
                add_rhs(&mut rhs, rr, scale * positions[j]);
                for t in slots(j) {
                    let (k, wk) = (op.neighbors[t] as usize, op.weight_p[t]);
                    if unknown[k] != u32::MAX {
                        triplets.push(Triplet::new(rr, 2 * unknown[k] as usize + 1, scale * wk));
                    } else {
                        add_rhs(&mut rhs, rr, -scale * wk * positions[k]);
                    }
                }
            }
        }
        // P equation: Σ w_p P_j − P_i − K_i R_i = 0.
        triplets.push(Triplet::new(pr, pr, -1.0));
        triplets.push(Triplet::new(pr, rr, -op.k[i]));
        for s in slots(i) {
            let (j, w) = (op.neighbors[s] as usize, op.weight_p[s]);
            if unknown[j] != u32::MAX {
                triplets.push(Triplet::new(pr, 2 * unknown[j] as usize + 1, w));
            } else {
                add_rhs(&mut rhs, pr, -w * positions[j]);
            }
        }
    }
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(2 * m, 2 * m, &triplets).unwrap();
    let lu = a.sp_lu().expect("the level's system is regular");
    lu.solve_in_place(rhs.as_mut());
    let time = start.elapsed();
    let mut p = positions.to_vec();
    for i in 0..n {
        if unknown[i] != u32::MAX {
            let row = 2 * unknown[i] as usize + 1;
            p[i] = DVec3::new(rhs[(row, 0)], rhs[(row, 1)], rhs[(row, 2)]);
        }
    }
    (p, time, 2 * m)
}

fn drag_bench(label: &str, doc: &Document, repeats: usize, direct: bool) {
    let diagonal = doc.cage.bounding_diagonal();
    let mut solver = SurfaceSolver::new(doc).unwrap();
    let start = Instant::now();
    solver.solve().unwrap();
    let fresh = start.elapsed();
    let top = doc.settings.levels as usize;
    let fresh_sweeps = solver.timings()[top].sweeps;
    let vertices = solver.surface_positions().len();

    // One plain iteration of the finest level, measured now.
    let (level, _, op) = finest_level(doc);
    let mut state = State::new(solver.surface_positions().to_vec(), solver.surface_second_derivatives().to_vec());
    let one = median(
        (0..repeats.max(3))
            .map(|_| {
                let t = Instant::now();
                std::hint::black_box(kernel::iterate(&op, &level.mesh, &mut state, 0.6));
                t.elapsed()
            })
            .collect(),
    );

    // Drags: one cage vertex back and forth by 1 % of the diagonal, re-converged warm: locally
    // (the default) and, for comparison, re-solving every level whole.
    let drags = |solver: &mut SurfaceSolver| {
        let mut dragged = doc.clone();
        let mut times = Vec::new();
        let mut sweeps = Vec::new();
        let mut work = Vec::new();
        for k in 0..repeats {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            let v = VertexId(0);
            dragged.cage.set_position(v, doc.cage.position(v) + sign * 0.01 * diagonal * DVec3::new(0.6, 0.0, 0.8));
            let t = Instant::now();
            solver.update(&dragged).unwrap();
            solver.solve().unwrap();
            times.push(t.elapsed());
            sweeps.push(solver.timings()[top].sweeps);
            work.push((solver.timings()[top].work * 10.0).round() / 10.0);
        }
        (median(times), sweeps, work, dragged)
    };
    let mut whole_solver = solver.clone();
    whole_solver.set_local(false);
    let (whole, whole_sweeps, _, _) = drags(&mut whole_solver);
    let (warm, sweeps, work, dragged) = drags(&mut solver);
    let whole_difference = whole_solver
        .surface_positions()
        .iter()
        .zip(solver.surface_positions())
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f64::max)
        / diagonal;
    println!(
        "{label}: {vertices} vertices at level {top}; fresh multigrid solve {:.0} ms ({fresh_sweeps} sweeps of level {top}); \
         one plain iteration {:.2} ms",
        ms(fresh),
        ms(one),
    );
    println!(
        "{label}: after a 1 % drag, re-converged locally in {:.1} ms = {:.1} plain iterations (sweeps of level {top} per \
         drag {sweeps:?}, work in sweeps of the whole level {work:?}); re-solving every level whole {:.1} ms = {:.1} plain \
         iterations (sweeps {whole_sweeps:?}): local is {:.1}x faster, {whole_difference:.1e} of the diagonal apart",
        ms(warm),
        warm.as_secs_f64() / one.as_secs_f64(),
        ms(whole),
        whole.as_secs_f64() / one.as_secs_f64(),
        whole.as_secs_f64() / warm.as_secs_f64(),
    );
    if direct {
        let (_, _, op) = finest_level(&dragged);
        let (p, lu, unknowns) = direct_solve(&op, &finest_level(&dragged).1);
        let difference =
            p.iter().zip(solver.surface_positions()).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max) / diagonal;
        println!(
            "{label}: sparse LU (faer) of the level's system, {unknowns} unknowns, 3 right-hand sides: {:.0} ms = {:.1}x the \
             multigrid re-converge; its answer is {difference:.1e} of the diagonal from multigrid's (tolerance {:e})",
            ms(lu),
            lu.as_secs_f64() / warm.as_secs_f64(),
            doc.settings.tol
        );
    }
}

fn main() {
    let quick = std::env::var_os("TAUT_BENCH_QUICK").is_some();
    let repeats = if quick { 3 } else { 7 };
    println!("threads: {}", rayon::current_num_threads());
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
    let mut scene = Document::load(&assets.join("default.taut")).unwrap();
    scene.settings.levels = 5;
    levels_bench("default scene", &scene);
    // Issue 22's second target: the 16 waist vertices (the rings at heights 38 and 58) unfixed.
    (16..32).for_each(|v| scene.fixed[v] = false);
    levels_bench("default scene, waist unfixed", &scene);

    let mut mid = Document::new(torus(64, 32));
    mid.settings.levels = 3;
    drag_bench("2 048-face torus", &mid, repeats, true);
    if std::env::var_os("TAUT_BENCH_NO_1M").is_none() {
        let mut big = Document::new(torus(32, 32));
        big.settings.levels = 5;
        drag_bench("1 024-face torus", &big, repeats.min(5), true);
    }
}
