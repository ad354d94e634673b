//! Tests of [`super`]: the fit of a patch network.

use super::*;
use crate::mesh::PolyMesh;

/// One open quad patch sampled from `surface`.
fn single_patch(m: usize, grade: u32, surface: impl Fn(f64, f64) -> DVec3) -> PatchNetwork {
    let layout = PolyMesh::from_polygons(
        vec![surface(0.0, 0.0), surface(1.0, 0.0), surface(1.0, 1.0), surface(0.0, 1.0)],
        &[[0u32, 1, 2, 3]],
    )
    .unwrap();
    let grid = (0..=m)
        .flat_map(|j| (0..=m).map(move |i| (i, j)))
        .map(|(i, j)| surface(i as f64 / m as f64, j as f64 / m as f64))
        .collect();
    PatchNetwork {
        layout,
        m,
        grids: vec![grid],
        normals: None,
        sharp: vec![false; 4],
        corner: vec![false; 4],
        grade: vec![grade; 4],
        singular_corners: false,
    }
}

#[test]
fn a_bicubic_patch_is_reproduced_with_and_without_graded_knots() {
    let s = |u: f64, v: f64| DVec3::new(u + 0.1 * v * v, v - 0.2 * u * u * u, u * u * v + 0.3 * v * v * v * u * u * u);
    for grade in [0, 2] {
        let net = single_patch(16, grade, s);
        let (model, report) = fit(&net, 1e-6).unwrap();
        assert!(report.max_distance < 1e-12, "grade {grade}: {report:?}");
        assert_eq!(report.spans, vec![1]);
        assert_eq!(model.faces[0].surface.knots_u.len(), if grade == 0 { 2 } else { 5 });
    }
}
