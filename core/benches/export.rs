//! Writing speed of the mesh formats, as ratios against a reference measured in the same run.
//!
//! The surface is level 3 of a 64 × 32 quad torus under Catmull–Clark (2,048 cage faces, 131 k
//! refined faces: the subdivision benchmark's load) with its vertex normals given, as
//! `taut subdivide --limit` writes it. Measured, each the shortest of several runs:
//! - OBJ text ([`obj_text`]) and GLB bytes ([`glb_bytes`]) made in memory, in MB/s of output;
//! - the reference: one pass copying the same number of bytes (read and write, one thread), the
//!   most a single-threaded encoder could do;
//! - the whole export to a file ([`export_obj_with`], [`export::export_glb_with`]: encode, write
//!   and flush to disk, then rename);
//! - the subdivision itself (topology, stencils and evaluation, [`Refinement::new`] and
//!   [`Refinement::evaluate`]), to which the OBJ encoding is compared.
//!
//! Targets on 2 cores: OBJ at least 200 MB/s, GLB at least 1 GB/s, and the OBJ encoding of
//! the torus under twice its subdivision time. Run with `cargo bench -p taut-core --bench export`;
//! `TAUT_BENCH_QUICK=1` runs fewer repeats.

mod common;

use common::{best, torus};
use std::hint::black_box;
use std::time::Duration;
use taut_core::io::glb::{export_glb_with, glb_bytes};
use taut_core::io::obj::obj_text;
use taut_core::io::{UpAxis, export_obj_with};
use taut_core::subdiv::{RefinedPositions, Refinement, Scheme};

fn mb_per_s(bytes: usize, d: Duration) -> f64 {
    bytes as f64 / d.as_secs_f64() / 1e6
}

fn main() {
    let quick = std::env::var_os("TAUT_BENCH_QUICK").is_some();
    let repeats = if quick { 3 } else { 15 };
    let cage = torus(64, 32);
    let levels = 3;

    let subdivision = best(repeats, || {
        let r = Refinement::new(&cage, Scheme::CatmullClark, &[], levels).unwrap();
        let mut out = RefinedPositions::default();
        r.evaluate(cage.positions(), &mut out).unwrap();
        black_box(out);
    });
    let r = Refinement::new(&cage, Scheme::CatmullClark, &[], levels).unwrap();
    let mut refined = RefinedPositions::default();
    r.evaluate(cage.positions(), &mut refined).unwrap();
    let mut surface = r.mesh(levels).clone();
    surface.positions_mut().copy_from_slice(&refined.limit);
    let normals = refined.normals.clone();
    println!(
        "export of a {}-face Catmull–Clark torus at level {levels}: {} vertices, {} faces (subdivision {:.1} ms)",
        cage.face_count(),
        surface.vertex_count(),
        surface.face_count(),
        subdivision.as_secs_f64() * 1e3
    );

    let obj_len = obj_text(&surface, Some(&normals), UpAxis::Y).len();
    let obj = best(repeats, || {
        black_box(obj_text(&surface, Some(&normals), UpAxis::Y));
    });
    let glb_len = glb_bytes(&surface, Some(&normals)).unwrap().len();
    let glb = best(repeats, || {
        black_box(glb_bytes(&surface, Some(&normals)).unwrap());
    });
    let copy = |bytes: usize| {
        let source = vec![1u8; bytes];
        let mut sink = vec![0u8; bytes];
        best(repeats, || {
            sink.copy_from_slice(black_box(&source));
            black_box(&sink);
        })
    };
    let (obj_copy, glb_copy) = (copy(obj_len), copy(glb_len));

    let dir = std::env::temp_dir().join(format!("taut-bench-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (obj_path, glb_path) = (dir.join("torus.obj"), dir.join("torus.glb"));
    let obj_file = best(repeats, || export_obj_with(&surface, &obj_path, Some(&normals), UpAxis::Y).unwrap());
    let glb_file = best(repeats, || export_glb_with(&surface, &glb_path, Some(&normals)).unwrap());
    let _ = std::fs::remove_dir_all(&dir);

    let row = |name: &str, bytes: usize, encode: Duration, reference: Duration, file: Duration| {
        println!(
            "{name}: {:.1} MB, encoded in {:.1} ms = {:.0} MB/s ({:.1}× the time of copying as many bytes, \
             {:.0} MB/s); to a file, flushed: {:.1} ms = {:.0} MB/s",
            bytes as f64 / 1e6,
            encode.as_secs_f64() * 1e3,
            mb_per_s(bytes, encode),
            encode.as_secs_f64() / reference.as_secs_f64(),
            mb_per_s(bytes, reference),
            file.as_secs_f64() * 1e3,
            mb_per_s(bytes, file)
        );
    };
    row("OBJ", obj_len, obj, obj_copy, obj_file);
    row("GLB", glb_len, glb, glb_copy, glb_file);
    println!(
        "OBJ encoding over subdivision time: {:.2} (target under 2); targets OBJ >= 200 MB/s ({}), GLB >= 1000 MB/s ({})",
        obj.as_secs_f64() / subdivision.as_secs_f64(),
        if mb_per_s(obj_len, obj) >= 200.0 { "met" } else { "missed" },
        if mb_per_s(glb_len, glb) >= 1000.0 { "met" } else { "missed" },
    );
}
