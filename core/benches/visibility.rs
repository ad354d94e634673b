//! What the eye sees of a cage ([`visibility_from`], the editor's X-ray-off picking and dimming),
//! timed on quad tori of 2,048, 8,192 and 32,768 faces seen from a three-quarter view, against
//! a reference measured in the same run: indexing the faces and casting one ray per vertex only
//! (the least any visibility by rays can do); and with the index kept, as while only the eye moves. The editor recomputes it when the cage or the eye moves, so at
//! 30 frames a second a cage orbits smoothly while this stays under about 10 ms. Run with
//! `cargo bench -p taut-core --bench visibility`; `TAUT_BENCH_QUICK=1` runs fewer repeats.

mod common;

use common::{best, torus};
use std::hint::black_box;
use taut_core::DVec3;
use taut_core::cage_fit::surface_index::SurfaceIndex;
use taut_core::mesh::visibility::visibility_from;

fn main() {
    let repeats = if std::env::var_os("TAUT_BENCH_QUICK").is_some() { 3 } else { 10 };
    let eye = DVec3::new(2.5, -3.0, 2.0);
    for (nu, nv) in [(64, 32), (128, 64), (256, 128)] {
        let cage = torus(nu, nv);
        let seen = visibility_from(&cage, eye);
        let time = best(repeats, || {
            black_box(visibility_from(&cage, eye));
        });
        let occluder = taut_core::mesh::visibility::Occluder::new(&cage);
        let orbit = best(repeats, || {
            black_box(occluder.visibility(&cage, eye));
        });
        let reference = best(repeats, || {
            let index = SurfaceIndex::new(cage.positions(), &cage.triangles()).unwrap();
            let hits: usize = cage
                .positions()
                .iter()
                .filter(|&&p| {
                    let d = p - eye;
                    index.cast(eye, d.normalize(), d.length() * 0.999).is_some()
                })
                .count();
            black_box(hits);
        });
        println!(
            "{} faces: visibility {:.1} ms, while only the eye moves {:.1} ms ({} of {} vertices seen), {:.1}× one index and one ray per vertex ({:.1} ms)",
            cage.face_count(),
            time.as_secs_f64() * 1e3,
            orbit.as_secs_f64() * 1e3,
            seen.vertices.iter().filter(|&&s| s).count(),
            cage.vertex_count(),
            time.as_secs_f64() / reference.as_secs_f64(),
            reference.as_secs_f64() * 1e3
        );
    }
}
