//! Closed surfaces and patches tessellated here for the curvature tests: UV spheres,
//! icospheres (optionally jittered), cube spheres, cylinders and tori with a grading, each with
//! known curvature everywhere.

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};
use taut_core::{DVec3, PolyMesh};

/// Deterministic pseudo-random numbers in [-1, 1) (splitmix64), so meshes are the same every run.
#[derive(Debug)]
pub struct Jitter(pub u64);

impl Jitter {
    pub fn draw(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A UV sphere: `rings` bands of latitude, `segments` around; quads with triangle fans at the poles.
pub fn uv_sphere(r: f64, rings: u32, segments: u32) -> PolyMesh {
    let mut p = vec![DVec3::new(0.0, 0.0, -r)];
    for i in 1..rings {
        let theta = PI * i as f64 / rings as f64 - PI / 2.0;
        for j in 0..segments {
            let phi = TAU * j as f64 / segments as f64;
            p.push(r * DVec3::new(theta.cos() * phi.cos(), theta.cos() * phi.sin(), theta.sin()));
        }
    }
    p.push(DVec3::new(0.0, 0.0, r));
    let top = p.len() as u32 - 1;
    let at = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for j in 0..segments {
        faces.push(vec![0, at(1, j + 1), at(1, j)]);
        faces.push(vec![top, at(rings - 1, j), at(rings - 1, j + 1)]);
        for i in 1..rings - 1 {
            faces.push(vec![at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
        }
    }
    PolyMesh::from_polygons(p, &faces).expect("valid UV sphere")
}

/// An icosahedron subdivided `levels` times onto the sphere of radius `r`, then every vertex
/// moved along the sphere by up to `jitter` times the local edge length in a random direction.
pub fn icosphere(r: f64, levels: u32, jitter: f64, seed: u64) -> PolyMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
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
    for _ in 0..levels {
        let mut mid = HashMap::new();
        let mut midpoint = |a: u32, b: u32, p: &mut Vec<DVec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                p.push((p[a as usize] + p[b as usize]).normalize());
                p.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let (ab, bc, ca) = (midpoint(a, b, &mut p), midpoint(b, c, &mut p), midpoint(c, a, &mut p));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let edge = 1.1 / (1u32 << levels) as f64;
    let mut rng = Jitter(seed);
    for q in &mut p {
        let (u, v) = q.any_orthonormal_pair();
        *q = (*q + jitter * edge * (rng.draw() * u + rng.draw() * v)).normalize();
    }
    let p = p.into_iter().map(|q| r * q).collect();
    PolyMesh::from_polygons(p, &faces).expect("valid icosphere")
}

/// A cube of `n × n` quads per side pushed onto the sphere of radius `r`; the quads of the `+z`
/// side are split into triangles (alternating diagonals), so the mesh is quad-dominant.
pub fn cube_sphere(r: f64, n: u32) -> PolyMesh {
    let mut index = HashMap::new();
    let mut p = Vec::new();
    let mut vertex = |g: [i64; 3]| {
        *index.entry(g).or_insert_with(|| {
            let c = DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64) / n as f64 * 2.0 - DVec3::ONE;
            p.push(r * c.normalize());
            p.len() as u32 - 1
        })
    };
    let n = n as i64;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for axis in 0..3 {
        for side in [0, n] {
            let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: i64, dj: i64| {
                        let mut g = [0; 3];
                        g[axis] = side;
                        g[a1] = i + di;
                        g[a2] = j + dj;
                        g
                    };
                    let mut quad =
                        vec![vertex(corner(0, 0)), vertex(corner(1, 0)), vertex(corner(1, 1)), vertex(corner(0, 1))];
                    if side == 0 {
                        quad.reverse();
                    }
                    if axis == 2 && side == n {
                        if (i + j) % 2 == 0 {
                            faces.push(vec![quad[0], quad[1], quad[2]]);
                            faces.push(vec![quad[0], quad[2], quad[3]]);
                        } else {
                            faces.push(vec![quad[0], quad[1], quad[3]]);
                            faces.push(vec![quad[1], quad[2], quad[3]]);
                        }
                    } else {
                        faces.push(quad);
                    }
                }
            }
        }
    }
    PolyMesh::from_polygons(p, &faces).expect("valid cube sphere")
}

/// An open cylinder of radius `r` around the z axis, `segments` around, `rows` along `[0, h]`.
/// With `triangles`, every quad is split along a random diagonal and every vertex off the ends is
/// moved on the cylinder by up to `jitter` times the spacing.
pub fn cylinder(r: f64, h: f64, segments: u32, rows: u32, triangles: bool, jitter: f64) -> PolyMesh {
    let mut rng = Jitter(7);
    let (da, dz) = (TAU / segments as f64, h / rows as f64);
    let mut p = Vec::new();
    for i in 0..=rows {
        for j in 0..segments {
            let inner = i > 0 && i < rows;
            let (ja, jz) = if inner { (jitter * rng.draw(), jitter * rng.draw()) } else { (0.0, 0.0) };
            let a = (j as f64 + ja) * da;
            p.push(DVec3::new(r * a.cos(), r * a.sin(), (i as f64 + jz) * dz));
        }
    }
    let at = |i: u32, j: u32| i * segments + j % segments;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for i in 0..rows {
        for j in 0..segments {
            let q = [at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)];
            if !triangles {
                faces.push(q.to_vec());
            } else if rng.draw() > 0.0 {
                faces.push(vec![q[0], q[1], q[2]]);
                faces.push(vec![q[0], q[2], q[3]]);
            } else {
                faces.push(vec![q[0], q[1], q[3]]);
                faces.push(vec![q[1], q[2], q[3]]);
            }
        }
    }
    PolyMesh::from_polygons(p, &faces).expect("valid cylinder")
}

/// A torus around the z axis (ring radius `big`, tube radius `small`): `nu` quads around the
/// ring, `nv` around the tube. Returns the mesh and each vertex's tube angle `v` (0 outside).
/// `grading` in [0, 1) bunches the rows around the tube unevenly (0: even).
pub fn torus(big: f64, small: f64, nu: u32, nv: u32, grading: f64) -> (PolyMesh, Vec<f64>) {
    let mut p = Vec::new();
    let mut angle = Vec::new();
    for i in 0..nu {
        let u = TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let s = TAU * j as f64 / nv as f64;
            let v = s + grading * s.sin();
            let rho = big + small * v.cos();
            p.push(DVec3::new(rho * u.cos(), rho * u.sin(), small * v.sin()));
            angle.push(v);
        }
    }
    let at = |i: u32, j: u32| (i % nu) * nv + j % nv;
    let mut faces = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            faces.push([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    (PolyMesh::from_polygons(p, &faces).expect("valid torus"), angle)
}
