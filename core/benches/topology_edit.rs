//! The surface complete again after a topology edit, on a 2,048-face cage (a 64 × 32 torus, the
//! load of the speed issue): extrude one face, cut one loop, delete one vertex, each applied as a
//! document edit (`Edit::Mesh`, checked and carried as the editor applies it), then the surface
//! built from the new document and run to the end, Catmull–Clark at levels 2 (what the editor
//! shows a cage of this size at) and 3, NUSD at level 2.
//!
//! Reported against the targets (Catmull–Clark within 50 ms; NUSD within three 16 ms frames)
//! and as a ratio to the same surface built for the unedited cage in the same run (the cost of a
//! fresh build). NUSD is measured both ways in the same run: *cold* (the surface built for the
//! edited document and solved from nothing, what an edit paid before issue 22) and *warm* (the
//! solved surface of the unedited cage taking the edited document, as the editor does: its levels
//! start from the old ones through the edit's provenance and are re-solved around the edit); the
//! target applies to the warm figure.
//!
//! Run with `cargo bench -p taut-core --bench topology_edit`; `TAUT_BENCH_QUICK=1` runs fewer
//! repeats.

/// The allocator the `taut` binary uses (`app/src/main.rs`), so the times are the editor's.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::time::{Duration, Instant};
use taut_core::document::modelling::MeshEdit;
use taut_core::mesh::primitives::torus;
use taut_core::surface::{self, Budget, SchemeKind};
use taut_core::{Document, Edit, VertexId};

/// Shortest wall time of `f` over `repeats` runs.
fn best(repeats: usize, mut f: impl FnMut()) -> Duration {
    (0..repeats)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .min()
        .unwrap()
}

/// Shortest wall time of `f` over `repeats` runs, each on a fresh `setup()` (not timed).
fn best_on<T>(repeats: usize, mut setup: impl FnMut() -> T, mut f: impl FnMut(&mut T)) -> Duration {
    (0..repeats)
        .map(|_| {
            let mut input = setup();
            let t = Instant::now();
            f(&mut input);
            t.elapsed()
        })
        .min()
        .unwrap()
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Builds the document's surface and runs it to the end.
fn complete(doc: &Document) {
    let mut s = surface::build(doc).unwrap();
    s.advance(Budget::UNLIMITED);
    std::hint::black_box(s.mesh().vertex_count());
}

fn main() {
    let quick = std::env::var_os("TAUT_BENCH_QUICK").is_some();
    let repeats = if quick { 2 } else { 7 };
    let cage = torus(64, 32, 2.0, 0.7).unwrap();
    let edge = cage.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge();
    let edits = [
        ("extrude one face", MeshEdit::ExtrudeFaces { faces: vec![100], distance: 0.05 }),
        ("loop cut", MeshEdit::LoopCut { edge: edge.0, fraction: 0.5 }),
        ("delete one vertex", MeshEdit::DeleteVertices { vertices: vec![40] }),
    ];
    println!("threads: {}; cage {} faces", rayon::current_num_threads(), cage.face_count());
    for (scheme, levels, target_ms) in
        [(SchemeKind::CatmullClark, 2, 50.0), (SchemeKind::CatmullClark, 3, 50.0), (SchemeKind::Nusd, 2, 48.0)]
    {
        let mut base = Document::new(cage.clone()).with_scheme(scheme);
        base.settings.levels = levels;
        base.subdiv.levels = levels;
        let fresh = best(repeats, || complete(&base));
        println!("{} level {levels}: unedited cage built in {:.1} ms", scheme.display_name(), ms(fresh));
        for (name, op) in &edits {
            let mut edited = base.clone();
            let apply = best(repeats, || {
                edited = base.clone();
                edited.apply(Edit::Mesh(op.clone())).unwrap();
            });
            let rebuild = best(repeats, || complete(&edited));
            let total = apply + rebuild;
            if scheme != SchemeKind::Nusd {
                println!(
                    "  {name}: edit {:.2} ms + surface {:.1} ms = {:.1} ms ({}, target {target_ms:.0} ms; {:.2}x the unedited build)",
                    ms(apply),
                    ms(rebuild),
                    ms(total),
                    if ms(total) <= target_ms { "met" } else { "NOT met" },
                    rebuild.as_secs_f64() / fresh.as_secs_f64()
                );
                continue;
            }
            // The editor's path: the solved surface of the unedited cage takes the edited document.
            let solved_base = || {
                let mut s = surface::build(&base).unwrap();
                s.advance(Budget::UNLIMITED);
                s
            };
            let mut update = Duration::MAX;
            let warm = best_on(repeats, solved_base, |s| {
                let t = Instant::now();
                s.update(&edited).unwrap();
                update = update.min(t.elapsed());
                s.advance(Budget::UNLIMITED);
                std::hint::black_box(s.mesh().vertex_count());
            });
            let warm_total = apply + warm;
            println!(
                "  {name}: edit {:.2} ms + surface warm {:.1} ms (levels made and started {:.1}) = {:.1} ms ({}, target {target_ms:.0} ms); cold {:.1} ms = {:.1} ms ({:.2}x the unedited build)",
                ms(apply),
                ms(warm),
                ms(update),
                ms(warm_total),
                if ms(warm_total) <= target_ms { "met" } else { "NOT met" },
                ms(rebuild),
                ms(total),
                rebuild.as_secs_f64() / fresh.as_secs_f64()
            );
        }
    }
}
