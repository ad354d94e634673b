//! Control-cage fitting speed: every step on a ~100 k and a ~1 M triangle closed scan-like
//! surface (a bumpy torus), and the sparse solve on cages of ~1 k, ~10 k and ~100 k vertices.
//!
//! References measured in the same run: a streaming pass over the input's index and position
//! buffers (the least any simplifier must do), against which the simplification is a ratio; and
//! one application of the limit matrix, against which the factorisation and solve are a ratio
//! (a near-linear solve keeps that ratio about flat from 1 k to 100 k vertices).
//! Targets (issue 10): 1 M triangles → 2,000-face fitted cage in under 5 s on 2 cores;
//! simplification at least 1 M triangles/s. Peer (issue 22): MeshLab's quadric edge collapse
//! alone (pymeshlab, optimal placement, topology kept) on the same mesh to the same face count, in
//! the same run, when the Python of `tests/run-all.sh` (`.venv-cad`, or `TAUT_CAD_PYTHON`) is
//! there; the target is Taut's whole import-and-fit at least 10× faster. Both are timed three
//! times, each run in a fresh process, in turn; their medians are compared.
//!
//! Run with `cargo bench -p taut-core --bench cage_fit`. `TAUT_BENCH_QUICK=1` skips the 1 M input.

use std::hint::black_box;
use std::time::Instant;
use taut_core::DVec3;
use taut_core::cage_fit::simplify::simplify;
use taut_core::cage_fit::solve::Factorised;
use taut_core::cage_fit::{CageFitParams, CageSize, DenseMesh, Silent, fit_cage};
use taut_core::io::import_triangles;
use taut_core::subdiv::loop_limit_matrix;

/// A closed bumpy torus of `n × n` quads split into triangles.
fn bumpy_torus(n: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut p = Vec::with_capacity((n * n) as usize);
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        for j in 0..n {
            let b = std::f64::consts::TAU * j as f64 / n as f64;
            let r = 0.35 * (1.0 + 0.2 * (5.0 * a).sin() * (3.0 * b).cos());
            let big = 1.0 + r * b.cos();
            p.push(DVec3::new(big * a.cos(), big * a.sin(), r * b.sin()));
        }
    }
    let mut t = Vec::with_capacity(2 * (n * n) as usize);
    for i in 0..n {
        for j in 0..n {
            let (i1, j1) = ((i + 1) % n, (j + 1) % n);
            let (v00, v10, v11, v01) = (i * n + j, i1 * n + j, i1 * n + j1, i * n + j1);
            t.push([v00, v10, v11]);
            t.push([v00, v11, v01]);
        }
    }
    (p, t)
}

fn binary_stl(p: &[DVec3], t: &[[u32; 3]]) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes.extend((t.len() as u32).to_le_bytes());
    for tri in t {
        bytes.extend([0u8; 12]);
        for &i in tri {
            bytes.extend(p[i as usize].as_vec3().to_array().iter().flat_map(|c| c.to_le_bytes()));
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

fn seconds(f: impl FnOnce()) -> f64 {
    let t = Instant::now();
    f();
    t.elapsed().as_secs_f64()
}

fn pipeline(label: &str, n: u32) {
    let (p, t) = bumpy_torus(n);
    let path = std::env::temp_dir().join(format!("taut-bench-cage-{}-{label}.stl", std::process::id()));
    std::fs::write(&path, binary_stl(&p, &t)).unwrap();
    let mut imported = None;
    let import = seconds(|| imported = Some(import_triangles(&path, &Default::default()).unwrap()));
    let (positions, triangles, _) = imported.unwrap();
    let mut dense = None;
    let prepare = seconds(|| dense = Some(DenseMesh::from_triangles(positions, &triangles).unwrap()));
    let dense = dense.unwrap();
    // Reference: one streaming pass over the indices and the corners' positions.
    let stream = seconds(|| {
        let s: f64 = dense.triangles().iter().map(|t| dense.positions()[t[0] as usize].x).sum();
        black_box(s);
    });

    let mut fit = None;
    let total = seconds(|| {
        let params = CageFitParams::new(CageSize::Faces(2000), taut_core::cage_fit::DEFAULT_ROUNDS);
        fit = Some(fit_cage(&dense, &params, &mut Silent).unwrap().unwrap())
    });
    let fit = fit.unwrap();
    let r = &fit.report;
    // The fit simplifies while it indexes the original on the other core: the simplification's
    // own rate is measured alone.
    let simplify_s = seconds(|| {
        black_box(simplify(&dense, 2000).unwrap());
    });
    println!(
        "{label}: {} triangles → {} faces; import {import:.2} s, prepare {prepare:.2} s, fit {total:.2} s (target < 5 s at 1 M)",
        r.input_triangles, r.cage_faces
    );
    for s in &r.steps {
        println!("  {:<22} {:>8.3} s", s.step, s.seconds);
    }
    println!(
        "  simplification alone {:.2} M triangles/s (target ≥ 1), {:.0}× a streaming pass over the mesh ({:.1} ms)",
        r.input_triangles as f64 / simplify_s / 1e6,
        simplify_s / stream,
        stream * 1e3
    );
    // The comparison: Taut's whole import, preparation and fit, each run in a fresh process as
    // `taut cage` runs (cold memory), against MeshLab's quadric edge collapse alone, each run
    // in a fresh Python; the medians of `RUNS` each, taken in turn.
    println!("  in this process: import, preparation and fit {:.2} s", import + prepare + total);
    let (mut ours, mut peers) = (Vec::new(), Vec::new());
    for _ in 0..RUNS {
        ours.push(child_seconds(&path));
        match meshlab_seconds(label, dense.positions(), dense.triangles(), 2000) {
            Some(peer) => peers.push(peer),
            None => break,
        }
    }
    let _ = std::fs::remove_file(&path);
    let list = |v: &[f64]| v.iter().map(|x| format!("{x:.2}")).collect::<Vec<_>>().join(", ");
    println!("  Taut's import, preparation and fit, fresh processes: {} s (median {:.2})", list(&ours), median(&ours));
    if peers.is_empty() {
        println!("  MeshLab's QEM alone: not measured (no Python with pymeshlab; run tests/run-all.sh once)");
    } else {
        println!(
            "  MeshLab's QEM alone: {} s (median {:.2}); Taut {:.1}× faster (target ≥ 10; each run's ratio: {})",
            list(&peers),
            median(&peers),
            median(&peers) / median(&ours),
            ours.iter().zip(&peers).map(|(a, b)| format!("{:.1}×", b / a)).collect::<Vec<_>>().join(", ")
        );
    }
    let fitted = r.fitted().unwrap();
    println!(
        "  QEM volume change {:.3e}, fitted {:.3e}; Hausdorff {:.3e} vs {:.3e}; mean {:.3e} vs {:.3e}; {}",
        r.qem.volume_change.unwrap_or(f64::NAN),
        fitted.volume_change.unwrap_or(f64::NAN),
        r.qem.hausdorff,
        fitted.hausdorff,
        r.qem.mean,
        fitted.mean,
        r.verdict
    );
}

/// Seconds MeshLab's quadric edge collapse alone takes to bring the mesh to `faces`, measured by
/// `tests/cad/meshlab_cage.py` (loading and saving excluded); `None` without pymeshlab.
fn meshlab_seconds(label: &str, p: &[DVec3], t: &[[u32; 3]], faces: usize) -> Option<f64> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let python = std::env::var_os("TAUT_CAD_PYTHON")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| root.join(".venv-cad/bin/python"));
    if !python.exists() {
        return None;
    }
    let dir = std::env::temp_dir();
    let input = dir.join(format!("taut-bench-cage-{}-{label}.ply", std::process::id()));
    let output = dir.join(format!("taut-bench-cage-{}-{label}-meshlab.obj", std::process::id()));
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        p.len(),
        t.len()
    )
    .into_bytes();
    for q in p {
        bytes.extend(q.as_vec3().to_array().iter().flat_map(|c| c.to_le_bytes()));
    }
    for tri in t {
        bytes.push(3);
        bytes.extend(tri.iter().flat_map(|&i| (i as i32).to_le_bytes()));
    }
    std::fs::write(&input, bytes).ok()?;
    let out = std::process::Command::new(python)
        .arg(root.join("tests/cad/meshlab_cage.py"))
        .args(["decimate", input.to_str()?, output.to_str()?, &faces.to_string()])
        .output()
        .ok();
    let _ = std::fs::remove_file(&input);
    let _ = std::fs::remove_file(&output);
    let out = out?;
    let text = String::from_utf8_lossy(&out.stdout);
    let json: serde_json::Value = serde_json::from_str(text.trim().lines().last()?).ok()?;
    json[0]["seconds"].as_f64()
}

fn solves(n: u32) {
    let (p, t) = bumpy_torus(n);
    let dense = DenseMesh::from_triangles(p, &t).unwrap();
    for faces in [2_000, 20_000, 200_000] {
        let cage = simplify(&dense, faces).unwrap().cage;
        let m = loop_limit_matrix(&cage).unwrap();
        let rhs = m.apply(cage.positions());
        let apply = seconds(|| {
            black_box(m.apply(cage.positions()));
        });
        let mut factorised = None;
        let factor = seconds(|| factorised = Some(Factorised::new(&m).unwrap()));
        let factorised = factorised.unwrap();
        let solve = seconds(|| {
            black_box(factorised.solve(&rhs, 1e-6).unwrap());
        });
        let v = cage.vertex_count();
        println!(
            "  cage of {v} vertices: factorise {:.2} ms, solve (3 coordinates) {:.2} ms; {:.2} µs per vertex; \
             {:.0}× one matrix application ({:.3} ms)",
            factor * 1e3,
            solve * 1e3,
            (factor + solve) / v as f64 * 1e6,
            (factor + solve) / apply,
            apply * 1e3
        );
    }
}

/// Runs of Taut's whole pipeline and of MeshLab's simplification compared, each in a process of
/// its own; the medians are compared.
const RUNS: usize = 3;

/// The median of a few times.
fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Set in a child process of this benchmark: the binary STL whose import, preparation and fit
/// it times and prints.
const CHILD: &str = "TAUT_BENCH_CAGE_CHILD";

/// Seconds a fresh process of this benchmark takes to import, prepare and fit the STL at `path`.
fn child_seconds(path: &std::path::Path) -> f64 {
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .env(CHILD, path)
        .output()
        .expect("the benchmark runs itself");
    assert!(out.status.success(), "the child run failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).trim().parse().expect("the child prints its seconds")
}

/// The child's run: what `taut cage` does with the file, timed.
fn child(path: &std::path::Path) {
    let whole = seconds(|| {
        let (positions, triangles, _) = import_triangles(path, &Default::default()).unwrap();
        let dense = DenseMesh::from_triangles(positions, &triangles).unwrap();
        let params = CageFitParams::new(CageSize::Faces(2000), taut_core::cage_fit::DEFAULT_ROUNDS);
        black_box(fit_cage(&dense, &params, &mut Silent).unwrap().unwrap());
    });
    println!("{whole}");
}

fn main() {
    // The allocator settings of the `taut` binary, so the times are the editor's.
    taut_core::memory::keep_freed_memory();
    if let Some(path) = std::env::var_os(CHILD) {
        child(std::path::Path::new(&path));
        return;
    }
    let quick = std::env::var_os("TAUT_BENCH_QUICK").is_some();
    println!("threads: {}", rayon::current_num_threads());
    pipeline("100k", 224);
    if !quick {
        pipeline("1M", 708);
    }
    println!("sparse solve by cage size:");
    solves(if quick { 400 } else { 708 });
}
