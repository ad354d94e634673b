//! Starting cages for File ▸ New: a cube, a prism, an open patch and an open tube.
//!
//! Each is a [`Document`] with every vertex fixed and no tension, centred on the origin with Z
//! up (the editor's camera convention), about 1 to 2 units across, and every face
//! counter-clockwise seen from outside. Counts outside the sensible range are clamped (at least
//! a triangle, at most [`MAX_DIVISIONS`]), so any slider value gives a valid cage.

use std::f64::consts::TAU;
use taut_core::{DVec3, Document, PolyMesh};

/// Most sides, rings or grid cells along one direction of a primitive.
pub const MAX_DIVISIONS: u32 = 64;

/// A cube of side 1: 8 vertices, 6 quads, closed.
pub fn cube() -> Document {
    let positions = [-0.5, 0.5]
        .into_iter()
        .flat_map(|z| [-0.5, 0.5].into_iter().flat_map(move |y| [-0.5, 0.5].map(|x| DVec3::new(x, y, z))))
        .collect();
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    document(positions, &faces)
}

/// A prism with regular `sides`-gon caps (at least 3), circumradius 1 and height 1: closed,
/// with two n-gons and `sides` quads.
pub fn prism(sides: u32) -> Document {
    let n = sides.clamp(3, MAX_DIVISIONS);
    let positions = [-0.5, 0.5].into_iter().flat_map(|z| ring(n, 1.0, z)).collect();
    let mut faces: Vec<Vec<u32>> = vec![(0..n).rev().collect(), (n..2 * n).collect()];
    faces.extend(band(n, 0).map(|quad| quad.to_vec()));
    document(positions, &faces)
}

/// An open patch of `nx` × `ny` quads (each at least 1), 2 units along its longer side, bulging
/// up by 0.3 in the middle so that smoothing has a curve to show. Its faces look up (+Z).
pub fn grid_patch(nx: u32, ny: u32) -> Document {
    let (nx, ny) = (nx.clamp(1, MAX_DIVISIONS), ny.clamp(1, MAX_DIVISIONS));
    let cell = 2.0 / f64::from(nx.max(ny));
    let mut positions = Vec::with_capacity(((nx + 1) * (ny + 1)) as usize);
    for j in 0..=ny {
        for i in 0..=nx {
            let (u, v) = (f64::from(i) / f64::from(nx), f64::from(j) / f64::from(ny));
            let bulge = 0.3 * (u * std::f64::consts::PI).sin() * (v * std::f64::consts::PI).sin();
            let x = (f64::from(i) - f64::from(nx) / 2.0) * cell;
            let y = (f64::from(j) - f64::from(ny) / 2.0) * cell;
            positions.push(DVec3::new(x, y, bulge));
        }
    }
    let mut faces = Vec::with_capacity((nx * ny) as usize);
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            faces.push([a, a + 1, a + nx + 2, a + nx + 1]);
        }
    }
    document(positions, &faces)
}

/// An open tube around Z: `sides` (at least 3) around, `rings` bands of quads (at least 1)
/// along, radius 0.75 and height 1.5. Its faces look outward.
pub fn cylinder(sides: u32, rings: u32) -> Document {
    let (n, rings) = (sides.clamp(3, MAX_DIVISIONS), rings.clamp(1, MAX_DIVISIONS));
    let positions = (0..=rings).flat_map(|j| ring(n, 0.75, -0.75 + 1.5 * f64::from(j) / f64::from(rings))).collect();
    let faces: Vec<[u32; 4]> = (0..rings).flat_map(|j| band(n, j * n)).collect();
    document(positions, &faces)
}

/// `n` points on a circle around Z at height `z`, counter-clockwise seen from above.
fn ring(n: u32, radius: f64, z: f64) -> impl Iterator<Item = DVec3> {
    (0..n).map(move |k| {
        let angle = TAU * f64::from(k) / f64::from(n);
        DVec3::new(radius * angle.cos(), radius * angle.sin(), z)
    })
}

/// The outward quads joining the ring starting at vertex `first` to the ring above it.
fn band(n: u32, first: u32) -> impl Iterator<Item = [u32; 4]> {
    (0..n).map(move |k| {
        let (a, b) = (first + k, first + (k + 1) % n);
        [a, b, b + n, a + n]
    })
}

fn document<F: AsRef<[u32]>>(positions: Vec<DVec3>, faces: &[F]) -> Document {
    let cage = PolyMesh::from_polygons(positions, faces).expect("primitive cages are valid by construction");
    Document::new(cage)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks a primitive: valid, of the expected topology, about 1 to 2 units across.
    fn check(doc: &Document, closed: bool, euler: i64) {
        doc.cage.validate().unwrap();
        doc.validate().unwrap();
        assert_eq!(doc.cage.is_closed(), closed);
        assert_eq!(doc.cage.euler_characteristic(), euler);
        assert!(doc.cage.vertices().all(|v| !doc.cage.is_isolated(v)));
        let diagonal = doc.cage.bounding_diagonal();
        assert!((1.0..=3.5).contains(&diagonal), "diagonal {diagonal}");
        assert!(doc.fixed.iter().all(|&f| f));
        assert!(doc.cage.faces().all(|f| doc.cage.face_area_vector(f).length() > 1e-6), "a degenerate face");
    }

    /// Volume by the divergence theorem; positive when the faces look outward.
    fn signed_volume(cage: &PolyMesh) -> f64 {
        cage.faces()
            .map(|f| {
                let centroid =
                    cage.face_vertices(f).map(|v| cage.position(v)).sum::<DVec3>() / cage.face_valence(f) as f64;
                centroid.dot(cage.face_area_vector(f)) / 3.0
            })
            .sum()
    }

    #[test]
    fn cube_is_a_closed_unit_cube() {
        let doc = cube();
        check(&doc, true, 2);
        assert_eq!((doc.cage.vertex_count(), doc.cage.face_count()), (8, 6));
        assert!((signed_volume(&doc.cage) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn prisms_are_closed_and_outward() {
        for sides in [0, 3, 5, 8, 64, 1000] {
            let doc = prism(sides);
            let n = sides.clamp(3, MAX_DIVISIONS) as usize;
            check(&doc, true, 2);
            assert_eq!((doc.cage.vertex_count(), doc.cage.face_count()), (2 * n, n + 2));
            // A regular n-gon of circumradius 1 has area n/2 · sin(2π/n); the height is 1.
            let volume = n as f64 / 2.0 * (TAU / n as f64).sin();
            assert!((signed_volume(&doc.cage) - volume).abs() < 1e-12, "sides {sides}");
            assert!(doc.cage.faces().any(|f| doc.cage.face_valence(f) == n));
        }
    }

    #[test]
    fn grid_patches_are_open_disks_looking_up() {
        for (nx, ny) in [(1, 1), (4, 3), (2, 7), (0, 100)] {
            let doc = grid_patch(nx, ny);
            let (nx, ny) = (nx.clamp(1, MAX_DIVISIONS) as usize, ny.clamp(1, MAX_DIVISIONS) as usize);
            check(&doc, false, 1);
            assert_eq!((doc.cage.vertex_count(), doc.cage.face_count()), ((nx + 1) * (ny + 1), nx * ny));
            assert!(doc.cage.faces().all(|f| doc.cage.face_area_vector(f).z > 0.0));
        }
        let curved = grid_patch(4, 4);
        assert!(curved.cage.positions().iter().any(|p| p.z > 0.2), "the patch is curved");
    }

    #[test]
    fn cylinders_are_open_tubes_looking_out() {
        for (sides, rings) in [(3, 1), (8, 3), (2, 0), (12, 5)] {
            let doc = cylinder(sides, rings);
            let (n, r) = (sides.clamp(3, MAX_DIVISIONS) as usize, rings.clamp(1, MAX_DIVISIONS) as usize);
            check(&doc, false, 0);
            assert_eq!((doc.cage.vertex_count(), doc.cage.face_count()), (n * (r + 1), n * r));
            assert!(doc.cage.faces().all(|f| doc.cage.face_valence(f) == 4));
            for f in doc.cage.faces() {
                let centroid = doc.cage.face_vertices(f).map(|v| doc.cage.position(v)).sum::<DVec3>() / 4.0;
                let radial = DVec3::new(centroid.x, centroid.y, 0.0);
                assert!(doc.cage.face_area_vector(f).dot(radial) > 0.0, "face {f:?} looks inward");
            }
        }
    }
}
