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
//! A last block does the NUSD edits with the mirror option on: the half x ≥ 0 of the same torus
//! is edited, and the surface is made on the mirrored whole (the same 2,048 faces), as the editor
//! makes it (`MirroredWhole`, whose whole after the edit carries its lineage from the whole before).
//! The edit's time includes making the new whole; warm and cold as above.
//!
//! Run with `cargo bench -p taut-core --bench topology_edit`; `TAUT_BENCH_QUICK=1` runs fewer
//! repeats.

use std::time::{Duration, Instant};
use taut_core::document::modelling::MeshEdit;
use taut_core::document::symmetry::MirroredWhole;
use taut_core::mesh::edit::{Axis, MirrorPlane, delete_vertices};
use taut_core::mesh::primitives::torus;
use taut_core::surface::{self, Budget, SchemeKind};
use taut_core::{DVec3, Document, Edit, FaceId, VertexId};

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
    // The allocator settings of the `taut` binary, so the times are the editor's.
    taut_core::memory::keep_freed_memory();
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
    mirrored(&cage, repeats);
}

/// The half's vertex nearest `p`.
fn nearest(doc: &Document, p: DVec3) -> VertexId {
    let d = |v: VertexId| doc.cage.position(v).distance(p);
    doc.cage.vertices().min_by(|&a, &b| d(a).total_cmp(&d(b))).unwrap()
}

/// NUSD level 2 with the mirror on: the half x ≥ 0 of `cage` edited where the edits above edit
/// the whole (face 100, the loop through vertices 0 and 1, vertex 40), the surface made on the
/// mirrored whole.
fn mirrored(cage: &taut_core::PolyMesh, repeats: usize) {
    let other_side: Vec<VertexId> = cage.vertices().filter(|&v| cage.position(v).x < -1e-9).collect();
    let mut half = Document::new(delete_vertices(cage, &other_side).unwrap().mesh);
    half.settings.levels = 2;
    half.apply(Edit::SetMirror(Some(MirrorPlane::new(Axis::X, 0.0)))).unwrap();
    let mut cache = MirroredWhole::default();
    let whole = cache.whole(&half).unwrap().unwrap();
    let fresh = best(repeats, || complete(&whole));
    println!(
        "NUSD level 2, mirror on (half of {} faces): unedited whole built in {:.1} ms",
        half.cage.face_count(),
        ms(fresh)
    );
    let centre = |m: &taut_core::PolyMesh, f: FaceId| {
        m.face_vertices(f).map(|v| m.position(v)).sum::<DVec3>() / m.face_valence(f) as f64
    };
    let target = centre(cage, FaceId(100));
    let face = half
        .cage
        .faces()
        .min_by(|&f, &g| centre(&half.cage, f).distance(target).total_cmp(&centre(&half.cage, g).distance(target)));
    let face = face.unwrap();
    let (a, b) = (nearest(&half, cage.position(VertexId(0))), nearest(&half, cage.position(VertexId(1))));
    let edge = half.cage.find_halfedge(a, b).unwrap().edge();
    let edits = [
        ("extrude one face", MeshEdit::ExtrudeFaces { faces: vec![face.0], distance: 0.05 }),
        ("loop cut", MeshEdit::LoopCut { edge: edge.0, fraction: 0.5 }),
        (
            "delete one vertex",
            MeshEdit::DeleteVertices { vertices: vec![nearest(&half, cage.position(VertexId(40))).0] },
        ),
    ];
    for (name, op) in &edits {
        // The edit of the half and the new whole made of it, from the cache that made the old.
        let mut edited = half.clone();
        let mut edited_whole = whole.clone();
        let apply = best(repeats, || {
            edited = half.clone();
            edited.apply(Edit::Mesh(op.clone())).unwrap();
            edited_whole = cache.clone().whole(&edited).unwrap().unwrap();
        });
        assert!(edited_whole.lineage().is_some());
        let cold = best(repeats, || complete(&edited_whole));
        let solved_whole = || {
            let mut s = surface::build(&whole).unwrap();
            s.advance(Budget::UNLIMITED);
            s
        };
        let mut update = Duration::MAX;
        let warm = best_on(repeats, solved_whole, |s| {
            let t = Instant::now();
            s.update(&edited_whole).unwrap();
            update = update.min(t.elapsed());
            s.advance(Budget::UNLIMITED);
            std::hint::black_box(s.mesh().vertex_count());
        });
        println!(
            "  {name}: edit and whole {:.2} ms + surface warm {:.1} ms (levels made and started {:.1}) = {:.1} ms ({}, target 48 ms); cold {:.1} ms = {:.1} ms",
            ms(apply),
            ms(warm),
            ms(update),
            ms(apply + warm),
            if ms(apply + warm) <= 48.0 { "met" } else { "NOT met" },
            ms(cold),
            ms(apply + cold)
        );
    }
}
