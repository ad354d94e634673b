//! Distances between two surfaces, for the editor's compare view: how far each vertex of one
//! scheme's surface lies from the other scheme's surface (closest points through a BVH,
//! [`SurfaceIndex`]). Each vertex is measured on its own, in parallel, so the result does not
//! depend on the thread count.

use crate::cage_fit::surface_index::SurfaceIndex;
use crate::mesh::PolyMesh;
use rayon::prelude::*;

/// Per vertex of `from`: its distance to the surface of `to` (every face fan-triangulated).
/// Zeros when `to` has no faces.
pub fn distances_to(from: &PolyMesh, to: &PolyMesh) -> Vec<f64> {
    let triangles = to.triangles();
    let Ok(index) = SurfaceIndex::new(to.positions(), &triangles) else {
        return vec![0.0; from.vertex_count()];
    };
    distances_from(from.positions(), &index)
}

/// Per point: its distance to the surface `index` holds (the editor's distance to the original
/// of a fitted cage, whose index is built once).
pub fn distances_from(points: &[crate::DVec3], index: &SurfaceIndex) -> Vec<f64> {
    points.par_iter().with_min_len(1024).map(|&p| index.distance(p)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DVec3;

    #[test]
    fn distances_to_a_plane_are_the_heights() {
        let plane = PolyMesh::from_polygons(
            vec![
                DVec3::new(-5.0, -5.0, 0.0),
                DVec3::new(5.0, -5.0, 0.0),
                DVec3::new(5.0, 5.0, 0.0),
                DVec3::new(-5.0, 5.0, 0.0),
            ],
            &[[0, 1, 2, 3]],
        )
        .unwrap();
        let lifted = PolyMesh::from_polygons(
            vec![DVec3::new(0.0, 0.0, 1.5), DVec3::new(1.0, 0.0, -0.25), DVec3::new(0.0, 1.0, 2.0)],
            &[[0, 1, 2]],
        )
        .unwrap();
        let d = distances_to(&lifted, &plane);
        for (got, want) in d.iter().zip([1.5, 0.25, 2.0]) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }
}
