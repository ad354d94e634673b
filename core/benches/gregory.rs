//! Curve-mesh speed, reported as ratios against references measured in the same run.
//!
//! - Construction of the curve mesh of a ~2 000-face cage (curved torus), against the
//!   Catmull–Clark refinement to level 2 it starts from (topology, stencils, limit stencils and
//!   their evaluation): how much the fitting, the tangent-plane correction, the patches and the
//!   closeness figure add.
//! - The rebuild after moving one vertex, for cages of about 100, 2 000 and 20 000 faces: the
//!   edit itself and the edit plus the tessellation update of the changed patches at 16 × 16,
//!   against building the changed patches alone. Must not grow with the cage size.
//! - Tessellation throughput at 16 × 16 (patches per second, over the whole 2 000-face mesh), as
//!   a ratio to a streaming pass writing the same bytes of positions and normals.
//!
//! - Evaluation of position and first derivatives on one thread, against a bicubic Bézier patch.
//! - The editor's work per frame while a curve-mesh vertex of the default scene is dragged: the
//!   document edit (checked on a copy of the curve mesh), the surface seam's update (the changed
//!   patches re-tessellated at 16 × 16) and the continuity measurement of the overlay, against
//!   moving one cage point of the same scene in the Catmull–Clark scheme (document edit and
//!   limit-surface update).
//!
//! Run with `cargo bench -p taut-core --bench gregory`. `TAUT_BENCH_QUICK=1` runs fewer repeats.

use rayon::prelude::*;
use std::hint::black_box;
use std::time::{Duration, Instant};
use taut_core::gregory::bezier::{bernstein3, bernstein3_d1};
use taut_core::gregory::{CurveMesh, Tessellation, gregory_patch};
use taut_core::subdiv::{RefinedPositions, Refinement, Scheme};
use taut_core::{DVec3, PolyMesh, VertexId};

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

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn construction(cage: &PolyMesh, repeats: usize) {
    let build = median(repeats, || {
        black_box(CurveMesh::from_cage(cage).unwrap());
    });
    let refine = median(repeats, || {
        let r = Refinement::new(cage, Scheme::CatmullClark, &[], 2).unwrap();
        let mut out = RefinedPositions::default();
        r.evaluate(cage.positions(), &mut out).unwrap();
        black_box(out);
    });
    println!(
        "construction, {}-face cage: {:.1} ms; Catmull–Clark to level 2 with limit points and normals {:.1} ms; ratio {:.2}x",
        cage.face_count(),
        ms(build),
        ms(refine),
        build.as_secs_f64() / refine.as_secs_f64()
    );
}

fn edit(label: &str, cage: &PolyMesh, repeats: usize) -> f64 {
    let (mut mesh, _) = CurveMesh::from_cage(cage).unwrap();
    let mut tess = Tessellation::new(&mesh, 16).unwrap();
    let v = VertexId(cage.vertex_count() as u32 / 2);
    let home = mesh.vertex_position(v);
    let step = 0.01 * cage.bounding_diagonal();
    let mut k = 0usize;
    let mut changed_patches = 0;
    let moves = 200;
    let edit_only = median(repeats, || {
        for _ in 0..moves {
            k += 1;
            let offset = DVec3::new(step * (k % 7) as f64 / 7.0, -step * (k % 3) as f64 / 3.0, 0.5 * step);
            let changed = mesh.move_vertex(v, home + offset).unwrap();
            changed_patches = changed.patches.len();
            black_box(&changed);
        }
    }) / moves;
    let with_tessellation = median(repeats, || {
        for _ in 0..moves {
            k += 1;
            let offset = DVec3::new(step * (k % 5) as f64 / 5.0, step * (k % 3) as f64 / 3.0, -0.5 * step);
            let changed = mesh.move_vertex(v, home + offset).unwrap();
            tess.update(&mesh, &changed).unwrap();
        }
    }) / moves;
    // Reference: building the changed patches from their boundaries, nothing else.
    let faces: Vec<_> = mesh.topology().outgoing(v).map(|h| mesh.topology().face(h)).collect();
    let boundaries: Vec<_> = faces.iter().map(|&f| mesh.patch_boundary(f)).collect();
    let patches_only = median(repeats, || {
        for _ in 0..moves {
            for b in &boundaries {
                black_box(gregory_patch(black_box(b)));
            }
        }
    }) / moves;
    println!(
        "{label}: move one vertex ({changed_patches} patches rebuilt) {:.2} µs = {:.2}x building those patches alone ({:.2} µs); with the 16 × 16 tessellation update {:.1} µs",
        edit_only.as_secs_f64() * 1e6,
        edit_only.as_secs_f64() / patches_only.as_secs_f64(),
        patches_only.as_secs_f64() * 1e6,
        with_tessellation.as_secs_f64() * 1e6
    );
    edit_only.as_secs_f64()
}

fn tessellation(cage: &PolyMesh, repeats: usize) {
    let (mesh, _) = CurveMesh::from_cage(cage).unwrap();
    let k = 16;
    let fresh = median(repeats, || {
        black_box(Tessellation::new(&mesh, k).unwrap());
    });
    let mut tess = Tessellation::new(&mesh, k).unwrap();
    let all = taut_core::gregory::Changed {
        vertices: mesh.topology().vertices().collect(),
        curves: mesh.topology().edges().collect(),
        patches: mesh.topology().faces().collect(),
    };
    let evaluate = median(repeats, || {
        tess.update(&mesh, &all).unwrap();
    });
    // Reference: writing the same bytes (position and normal per vertex) in parallel.
    let vertices = tess.mesh().vertex_count();
    let mut sink = vec![0.0f64; 6 * vertices];
    let stream = median(repeats, || {
        sink.par_chunks_mut(1 << 14).enumerate().for_each(|(i, c)| c.fill(i as f64));
        black_box(&sink);
    });
    let patches = mesh.patch_count() as f64;
    println!(
        "tessellation at {k} × {k}, {} patches: evaluating every sample {:.1} ms = {:.0} k patches/s ({:.1}x a streaming write of the same {:.1} MB, {:.2} ms); \
         with building the polygon mesh {:.1} ms = {:.0} k patches/s",
        mesh.patch_count(),
        ms(evaluate),
        patches / evaluate.as_secs_f64() / 1e3,
        evaluate.as_secs_f64() / stream.as_secs_f64(),
        48.0 * vertices as f64 / 1e6,
        ms(stream),
        ms(fresh),
        patches / fresh.as_secs_f64() / 1e3
    );
}

/// One thread: `(S, S_u, S_v)` of a Gregory patch per sample, against the same of the bicubic
/// Bézier patch with its rim and the averages of its inner pairs (the same 16-point sums without
/// the four rational blends).
fn evaluation(cage: &PolyMesh, repeats: usize) {
    let (mesh, _) = CurveMesh::from_cage(cage).unwrap();
    let k = 16;
    let grid: Vec<(f64, f64)> =
        (0..=k).flat_map(|j| (0..=k).map(move |i| (i as f64 / k as f64, j as f64 / k as f64))).collect();
    let patches = &mesh.patches()[..256.min(mesh.patch_count())];
    let samples = (patches.len() * grid.len()) as f64;
    let gregory = median(repeats, || {
        for p in patches {
            for &(u, v) in &grid {
                black_box(p.first_derivatives(black_box(u), v));
            }
        }
    });
    let bezier = median(repeats, || {
        for p in patches {
            let net = &p.rim;
            for &(u, v) in &grid {
                let (bu, bv) = (bernstein3(black_box(u)), bernstein3(v));
                let (du, dv) = (bernstein3_d1(u), bernstein3_d1(v));
                let (mut s, mut su, mut sv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
                for i in 0..4 {
                    for j in 0..4 {
                        s += (bu[i] * bv[j]) * net[i][j];
                        su += (du[i] * bv[j]) * net[i][j];
                        sv += (bu[i] * dv[j]) * net[i][j];
                    }
                }
                black_box((s, su, sv));
            }
        }
    });
    println!(
        "evaluation on one thread: Gregory patch {:.0} ns per sample (position and first derivatives) = {:.2}x a bicubic Bézier patch ({:.0} ns)",
        gregory.as_secs_f64() / samples * 1e9,
        gregory.as_secs_f64() / bezier.as_secs_f64(),
        bezier.as_secs_f64() / samples * 1e9
    );
}

fn main() {
    let quick = std::env::var_os("TAUT_BENCH_QUICK").is_some();
    let repeats = if quick { 3 } else { 9 };
    println!("threads: {}", rayon::current_num_threads());
    let (small, medium, large) = (torus(10, 10), torus(64, 32), torus(200, 100));
    construction(&medium, repeats);
    let times = [
        edit("~100-face cage", &small, repeats),
        edit("~2 000-face cage", &medium, repeats),
        edit("~20 000-face cage", &large, repeats),
    ];
    println!(
        "edit time relative to the ~100-face cage: {:.2}x at ~2 000 faces, {:.2}x at ~20 000 faces",
        times[1] / times[0],
        times[2] / times[0]
    );
    tessellation(&medium, repeats);
    evaluation(&medium, repeats);
    editor_drag(repeats);
}

/// One drag step in the editor on the default scene: the document edit, the seam update and the
/// continuity overlay's measurement, against a cage-point drag step in Catmull–Clark.
fn editor_drag(repeats: usize) {
    use taut_core::surface::{self, SchemeKind};
    use taut_core::{Document, Edit};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/default.taut");
    let scene = Document::load(&path).unwrap();
    let steps = 20;
    let run = |scheme: SchemeKind, continuity: bool| {
        let mut doc = scene.clone().with_scheme(scheme);
        let mut seam = surface::build(&doc).unwrap();
        let v = VertexId(3);
        let home = match scheme {
            SchemeKind::CurveMesh => doc.curve_mesh().unwrap().0.vertex_position(v),
            _ => doc.cage.position(v),
        };
        let mut k = 0usize;
        median(repeats, || {
            for _ in 0..steps {
                k += 1;
                let p = home + DVec3::new(0.05 * (k % 7) as f64, -0.03 * (k % 5) as f64, 0.02 * (k % 3) as f64);
                let edit = match scheme {
                    SchemeKind::CurveMesh => Edit::MoveCurveMeshVertices(vec![(v, p)]),
                    _ => Edit::MoveVertices(vec![(v, p)]),
                };
                // The editor tries every edit on a copy of the document, as here.
                let mut after = doc.clone();
                after.apply(edit).unwrap();
                doc = after;
                seam.update(&doc).unwrap();
                if continuity && let Some(cm) = seam.as_curve_mesh() {
                    black_box(cm.curve_mesh().continuity(16));
                }
            }
        }) / steps as u32
    };
    let curve_mesh = run(SchemeKind::CurveMesh, false);
    let with_continuity = run(SchemeKind::CurveMesh, true);
    let catmull_clark = run(SchemeKind::CatmullClark, false);
    let patches = scene.clone().with_scheme(SchemeKind::CurveMesh).curve_mesh().unwrap().0.patch_count();
    println!(
        "editor drag step on the default scene ({patches} patches): curve-mesh vertex {:.2} ms, with the continuity overlay {:.2} ms; \
         a cage point in Catmull–Clark {:.2} ms; ratios {:.2}x and {:.2}x",
        ms(curve_mesh),
        ms(with_continuity),
        ms(catmull_clark),
        curve_mesh.as_secs_f64() / catmull_clark.as_secs_f64(),
        with_continuity.as_secs_f64() / catmull_clark.as_secs_f64()
    );
}
