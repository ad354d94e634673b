//! Starting cages the editor offers beyond the cube and prism: a UV sphere, an icosphere, a torus
//! and a quad grid.
//!
//! Each is centred on the origin with Z up (the editor's convention) and every face is
//! counter-clockwise seen from outside (the grid's faces look up, +Z). The UV sphere is quads
//! between its rings with triangle fans at the poles (as Blender's, so the poles are valence
//! `segments` vertices, which subdivision surfaces smooth less evenly than quad caps would). The
//! icosphere is a regular icosahedron whose triangles are split 4-to-1 `subdivisions` times with
//! the new vertices pushed onto the sphere, so its triangles are nearly equal. Counts outside the
//! allowed ranges and radii that are not positive are refused with a message.

use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};
use std::f64::consts::{PI, TAU};

/// Most segments or rings along one direction of a primitive.
pub const MAX_SEGMENTS: u32 = 1024;
/// Most subdivisions of an icosphere (7 gives 327 680 triangles).
pub const MAX_ICOSPHERE_SUBDIVISIONS: u32 = 7;

fn check_count(what: &str, n: u32, min: u32, max: u32) -> Result<()> {
    if (min..=max).contains(&n) {
        Ok(())
    } else {
        Err(Error::Input(format!("{what} must be from {min} to {max}, not {n}")))
    }
}

fn check_length(what: &str, x: f64) -> Result<()> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(Error::Input(format!("{what} must be a finite length greater than 0, not {x:?}")))
    }
}

/// A sphere of `segments` (≥ 3) around and `rings` (≥ 2) from pole to pole: quads, with a fan of
/// triangles at each pole.
pub fn uv_sphere(segments: u32, rings: u32, radius: f64) -> Result<PolyMesh> {
    check_count("UV sphere segments", segments, 3, MAX_SEGMENTS)?;
    check_count("UV sphere rings", rings, 2, MAX_SEGMENTS)?;
    check_length("the sphere's radius", radius)?;
    let (n, m) = (segments, rings);
    let mut positions = vec![DVec3::new(0.0, 0.0, radius)];
    for j in 1..m {
        let theta = PI * f64::from(j) / f64::from(m);
        for k in 0..n {
            let phi = TAU * f64::from(k) / f64::from(n);
            positions.push(radius * DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()));
        }
    }
    positions.push(DVec3::new(0.0, 0.0, -radius));
    let south = (positions.len() - 1) as u32;
    let at = |j: u32, k: u32| 1 + (j - 1) * n + k % n;
    let mut faces: Vec<Vec<u32>> = Vec::with_capacity((n * m) as usize);
    faces.extend((0..n).map(|k| vec![0, at(1, k), at(1, k + 1)]));
    for j in 1..m - 1 {
        faces.extend((0..n).map(|k| vec![at(j, k), at(j + 1, k), at(j + 1, k + 1), at(j, k + 1)]));
    }
    faces.extend((0..n).map(|k| vec![south, at(m - 1, k + 1), at(m - 1, k)]));
    PolyMesh::from_polygons(positions, &faces)
}

/// An icosphere: the icosahedron split 4-to-1 `subdivisions` times (0 to
/// [`MAX_ICOSPHERE_SUBDIVISIONS`]), every vertex on the sphere.
pub fn icosphere(subdivisions: u32, radius: f64) -> Result<PolyMesh> {
    check_count("icosphere subdivisions", subdivisions, 0, MAX_ICOSPHERE_SUBDIVISIONS)?;
    check_length("the sphere's radius", radius)?;
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let corners = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ];
    let mut positions: Vec<DVec3> = corners.iter().map(|&c| radius * DVec3::from_array(c).normalize()).collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mesh = PolyMesh::from_polygons(positions.clone(), &faces)?;
        let first = positions.len() as u32;
        for e in mesh.edges() {
            let (a, b) = mesh.edge_vertices(e);
            positions.push(radius * (mesh.position(a) + mesh.position(b)).normalize());
        }
        let mid = |a: u32, b: u32| {
            let h = mesh.find_halfedge(crate::VertexId(a), crate::VertexId(b)).expect("a triangle's side is an edge");
            first + h.edge().0
        };
        faces = faces
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    PolyMesh::from_polygons(positions, &faces)
}

/// A torus around Z: `major_segments` (≥ 3) around the axis, `minor_segments` (≥ 3) around the
/// tube, tube radius `minor_radius` smaller than `major_radius`; closed, all quads.
pub fn torus(major_segments: u32, minor_segments: u32, major_radius: f64, minor_radius: f64) -> Result<PolyMesh> {
    check_count("torus segments around the axis", major_segments, 3, MAX_SEGMENTS)?;
    check_count("torus segments around the tube", minor_segments, 3, MAX_SEGMENTS)?;
    check_length("the torus's radius", major_radius)?;
    check_length("the torus's tube radius", minor_radius)?;
    if minor_radius >= major_radius {
        return Err(Error::Input(format!(
            "the torus's tube radius ({minor_radius:?}) must be smaller than its radius ({major_radius:?}), or the \
             tube would pass through itself"
        )));
    }
    let (nu, nv) = (major_segments, minor_segments);
    let mut positions = Vec::with_capacity((nu * nv) as usize);
    for i in 0..nu {
        let u = TAU * f64::from(i) / f64::from(nu);
        for j in 0..nv {
            let v = TAU * f64::from(j) / f64::from(nv);
            let r = major_radius + minor_radius * v.cos();
            positions.push(DVec3::new(r * u.cos(), r * u.sin(), minor_radius * v.sin()));
        }
    }
    let mut faces = Vec::with_capacity((nu * nv) as usize);
    for i in 0..nu {
        for j in 0..nv {
            let (i1, j1) = ((i + 1) % nu, (j + 1) % nv);
            faces.push([i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1]);
        }
    }
    PolyMesh::from_polygons(positions, &faces)
}

/// A flat grid of `nx` × `ny` quads (each at least 1) in the plane z = 0, `width` along X and
/// `depth` along Y, faces looking up (+Z).
pub fn quad_grid(nx: u32, ny: u32, width: f64, depth: f64) -> Result<PolyMesh> {
    check_count("grid segments along X", nx, 1, MAX_SEGMENTS)?;
    check_count("grid segments along Y", ny, 1, MAX_SEGMENTS)?;
    check_length("the grid's width", width)?;
    check_length("the grid's depth", depth)?;
    let mut positions = Vec::with_capacity(((nx + 1) * (ny + 1)) as usize);
    for j in 0..=ny {
        for i in 0..=nx {
            let x = width * (f64::from(i) / f64::from(nx) - 0.5);
            let y = depth * (f64::from(j) / f64::from(ny) - 0.5);
            positions.push(DVec3::new(x, y, 0.0));
        }
    }
    let mut faces = Vec::with_capacity((nx * ny) as usize);
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            faces.push([a, a + 1, a + nx + 2, a + nx + 1]);
        }
    }
    PolyMesh::from_polygons(positions, &faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FaceId;

    /// Volume enclosed by a closed mesh (divergence theorem over a fan of each face).
    fn volume(m: &PolyMesh) -> f64 {
        m.triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| m.position(crate::VertexId(v)));
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn centroid(m: &PolyMesh, f: FaceId) -> DVec3 {
        m.face_vertices(f).map(|v| m.position(v)).sum::<DVec3>() / m.face_valence(f) as f64
    }

    #[test]
    fn uv_sphere_counts_orientation_and_volume() {
        let (n, r) = (12u32, 12u32);
        let m = uv_sphere(n, r, 2.0).unwrap();
        m.validate().unwrap();
        assert!(m.is_closed());
        assert_eq!(m.vertex_count() as u32, n * (r - 1) + 2);
        assert_eq!(m.face_count() as u32, n * r);
        assert_eq!(m.faces().filter(|&f| m.face_valence(f) == 3).count() as u32, 2 * n);
        assert_eq!(m.euler_characteristic(), 2);
        for f in m.faces() {
            assert!(m.face_area_vector(f).dot(centroid(&m, f)) > 0.0, "face {f:?} looks inward");
        }
        for &p in m.positions() {
            assert!((p.length() - 2.0).abs() < 1e-12);
        }
        // The inscribed polyhedron: below the sphere's volume, and close to it.
        let sphere = 4.0 / 3.0 * PI * 8.0;
        let v = volume(&m);
        assert!(v < sphere && v > 0.9 * sphere, "{v} vs {sphere}");
    }

    #[test]
    fn icosphere_is_regular_on_the_sphere() {
        for s in 0..=3u32 {
            let m = icosphere(s, 1.5).unwrap();
            m.validate().unwrap();
            assert!(m.is_closed());
            let faces = 20 * 4usize.pow(s);
            assert_eq!(m.face_count(), faces);
            assert_eq!(m.edge_count(), faces * 3 / 2);
            assert_eq!(m.vertex_count(), faces / 2 + 2);
            for f in m.faces() {
                assert_eq!(m.face_valence(f), 3);
                assert!(m.face_area_vector(f).dot(centroid(&m, f)) > 0.0);
            }
            for &p in m.positions() {
                assert!((p.length() - 1.5).abs() < 1e-12);
            }
            // Edge lengths within 25 % of each other at every level.
            let lengths: Vec<f64> = m.edges().map(|e| m.edge_length(e)).collect();
            let (lo, hi) = lengths.iter().fold((f64::MAX, 0f64), |(lo, hi), &l| (lo.min(l), hi.max(l)));
            assert!(hi / lo < 1.25, "level {s}: {lo}..{hi}");
        }
        // Level 0 is the regular icosahedron: every edge has the closed-form length.
        let m = icosphere(0, 1.0).unwrap();
        let edge = 4.0 / (10.0 + 2.0 * 5f64.sqrt()).sqrt();
        assert!(m.edges().all(|e| (m.edge_length(e) - edge).abs() < 1e-12));
    }

    #[test]
    fn torus_is_genus_one_with_its_closed_form_volume() {
        let m = torus(48, 32, 2.0, 0.5).unwrap();
        m.validate().unwrap();
        assert!(m.is_closed());
        assert_eq!((m.vertex_count(), m.face_count()), (48 * 32, 48 * 32));
        assert_eq!(m.euler_characteristic(), 0);
        for f in m.faces() {
            // Outward: away from the tube's core circle.
            let c = centroid(&m, f);
            let core = 2.0 * DVec3::new(c.x, c.y, 0.0).normalize();
            assert!(m.face_area_vector(f).dot(c - core) > 0.0);
        }
        let exact = 2.0 * PI * PI * 2.0 * 0.25;
        assert!((volume(&m) - exact).abs() < 0.02 * exact, "{} vs {exact}", volume(&m));
    }

    #[test]
    fn quad_grid_is_flat_and_looks_up() {
        let m = quad_grid(5, 3, 2.0, 1.0).unwrap();
        m.validate().unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (24, 38, 15));
        assert_eq!(m.euler_characteristic(), 1);
        let total: DVec3 = m.faces().map(|f| m.face_area_vector(f)).sum();
        assert!((total - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-12);
        assert_eq!(m.bounding_box().unwrap(), (DVec3::new(-1.0, -0.5, 0.0), DVec3::new(1.0, 0.5, 0.0)));
    }

    #[test]
    fn bad_sizes_are_refused() {
        let cases = [
            (uv_sphere(2, 8, 1.0).err(), "segments must be from 3"),
            (uv_sphere(8, 1, 1.0).err(), "rings must be from 2"),
            (uv_sphere(8, 8, f64::NAN).err(), "radius"),
            (icosphere(9, 1.0).err(), "subdivisions"),
            (torus(8, 8, 1.0, 1.0).err(), "pass through itself"),
            (torus(8, 8, 1.0, -0.1).err(), "tube radius"),
            (quad_grid(0, 4, 1.0, 1.0).err(), "along X"),
            (quad_grid(4, 4, 1.0, 0.0).err(), "depth"),
        ];
        for (err, expected) in cases {
            let err = err.expect("refused").to_string();
            assert!(err.contains(expected), "expected '{expected}' in: {err}");
        }
    }
}
