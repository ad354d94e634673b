//! Catmull–Clark STEP export (issue 21): faces next to extraordinary vertices keep tangent
//! continuity within 0.1° right up to the vertex, on every bundled cage, within the tolerance.
//! (`app/tests/cli_step.rs` checks the written files with OpenCascade at 16 points an edge,
//! which step over the innermost rings; this checks them densely, on Taut's own evaluation.)

mod common;

use common::bundled;
use std::time::Instant;
use taut_core::Document;
use taut_core::cad::fit_document;
use taut_core::surface::SchemeKind;

#[test]
fn catmull_clark_faces_at_extraordinary_vertices_meet_within_a_tenth_of_a_degree() {
    for (name, cage) in bundled() {
        let doc = Document::new(cage).with_scheme(SchemeKind::CatmullClark);
        let t = Instant::now();
        let fitted = fit_document(&doc, None).unwrap();
        let r = &fitted.report;
        eprintln!(
            "{name}: sampled {} per side, within the two innermost rings {:.4}°, elsewhere {:.4}°, {:.3} of the \
             tolerance, {} faces, {:.2} s",
            fitted.samples,
            r.max_star_angle_degrees,
            r.max_angle_degrees,
            r.max_distance / fitted.tolerance,
            fitted.model.faces.len(),
            t.elapsed().as_secs_f64()
        );
        assert!(r.max_star_angle_degrees <= 0.1, "{name}: {r:?}");
        assert!(r.max_angle_degrees <= 0.1, "{name}: {r:?}");
        assert!(r.max_distance <= fitted.tolerance, "{name}: {r:?}");
    }
}
