//! Which parts of a polygon mesh an eye sees: the cage's vertices, edges and faces that no other
//! face of the same mesh hides. The editor draws the hidden ones dimmer and does not pick them
//! unless X-ray is on, as Blender's edit mode does (its edit cage hides what lies behind it).
//!
//! Each element is tested by rays from the eye to sample points on it, cast against the mesh's
//! polygons taken as fans of triangles from their first corner (the triangles the renderer and
//! the face picker use): a vertex by itself, an edge by three points along it (seen when any is
//! seen), a face by the centre of its corners. A sample is hidden when the first triangle the
//! ray meets before it, by more than [`VISIBILITY_TOLERANCE`] of the ray's length, belongs to a
//! face that does not hold the sample (the faces round a vertex or edge, or the face itself, do
//! not hide their own corner, edge or centre). A hit on such a face short of the sample (a warped
//! polygon's fan, a grazing ray) is stepped past and the ray cast on, a bounded number of times.
//!
//! The answer is exact for the fans; a warped polygon hides by its fan, as it is drawn. Rays
//! are independent, so the work runs in parallel and the answer does not depend on the number
//! of threads. The cost is one bounding-volume hierarchy over the fans and about
//! `V + 3E + F` ray casts of logarithmic cost: a few milliseconds for a cage of thousands of
//! faces.

use super::{EdgeId, FaceId, PolyMesh, VertexId};
use crate::DVec3;
use crate::cage_fit::surface_index::SurfaceIndex;
use rayon::prelude::*;

/// A hit closer than `(1 − VISIBILITY_TOLERANCE)` times the distance to the sample hides it; a
/// hit at the sample itself (up to rounding) does not.
pub const VISIBILITY_TOLERANCE: f64 = 1e-7;

/// Most faces holding the sample that a ray steps past before it counts the sample as seen.
const MAX_STEPS_PAST: usize = 8;

/// What an eye sees of a mesh: one flag per vertex, edge and face (true when seen).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Visibility {
    pub vertices: Vec<bool>,
    pub edges: Vec<bool>,
    pub faces: Vec<bool>,
}

impl Visibility {
    /// Everything seen (X-ray, or a mesh the rays cannot be cast against).
    pub fn all(mesh: &PolyMesh) -> Self {
        Visibility {
            vertices: vec![true; mesh.vertex_count()],
            edges: vec![true; mesh.edge_count()],
            faces: vec![true; mesh.face_count()],
        }
    }

    pub fn vertex(&self, v: VertexId) -> bool {
        self.vertices.get(v.index()).copied().unwrap_or(true)
    }

    pub fn edge(&self, e: EdgeId) -> bool {
        self.edges.get(e.index()).copied().unwrap_or(true)
    }

    pub fn face(&self, f: FaceId) -> bool {
        self.faces.get(f.index()).copied().unwrap_or(true)
    }
}

/// What `eye` sees of `mesh` (see the module documentation). An eye or a mesh with a non-finite
/// coordinate, or a mesh without faces, hides nothing.
pub fn visibility_from(mesh: &PolyMesh, eye: DVec3) -> Visibility {
    Occluder::new(mesh).visibility(mesh, eye)
}

/// A mesh's faces indexed for the rays of [`visibility_from`]: built once for a cage's shape and
/// kept while only the eye moves (an orbit then costs the rays alone, about half the time).
pub struct Occluder {
    /// `None` for a mesh that hides nothing (no faces, or a non-finite coordinate).
    index: Option<SurfaceIndex>,
    triangle_face: Vec<FaceId>,
}

impl std::fmt::Debug for Occluder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Occluder({} triangles)", self.triangle_face.len())
    }
}

impl Occluder {
    /// Indexes the fans of `mesh`'s faces.
    pub fn new(mesh: &PolyMesh) -> Self {
        let mut triangles = Vec::new();
        let mut triangle_face = Vec::new();
        for f in mesh.faces() {
            let ring: Vec<u32> = mesh.face_vertices(f).map(|v| v.0).collect();
            for k in 1..ring.len().saturating_sub(1) {
                triangles.push([ring[0], ring[k], ring[k + 1]]);
                triangle_face.push(f);
            }
        }
        let finite = mesh.positions().iter().all(|p| p.is_finite());
        let index =
            (finite && !triangles.is_empty()).then(|| SurfaceIndex::new(mesh.positions(), &triangles).ok()).flatten();
        Occluder { index, triangle_face }
    }

    /// What `eye` sees of `mesh`, the mesh this occluder was built for.
    pub fn visibility(&self, mesh: &PolyMesh, eye: DVec3) -> Visibility {
        match &self.index {
            Some(index) if eye.is_finite() => visible(mesh, index, &self.triangle_face, eye),
            _ => Visibility::all(mesh),
        }
    }
}

fn visible(mesh: &PolyMesh, index: &SurfaceIndex, triangle_face: &[FaceId], eye: DVec3) -> Visibility {
    let seen = |sample: DVec3, holds: &dyn Fn(FaceId) -> bool| -> bool {
        let to = sample - eye;
        let distance = to.length();
        if distance.is_nan() || distance <= 0.0 {
            return true;
        }
        let direction = to / distance;
        let limit = distance * (1.0 - VISIBILITY_TOLERANCE);
        let mut start = 0.0;
        for _ in 0..MAX_STEPS_PAST {
            let origin = eye + direction * start;
            let Some((t, triangle)) = index.cast_to_triangle(origin, direction, limit - start) else { return true };
            if !holds(triangle_face[triangle]) {
                return false;
            }
            // Past a face that holds the sample, a little further on.
            start += t + distance * VISIBILITY_TOLERANCE;
            if start >= limit {
                return true;
            }
        }
        true
    };

    let vertices = mesh
        .vertices()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&v| {
            if mesh.is_isolated(v) {
                return seen(mesh.position(v), &|_| false);
            }
            let faces: Vec<FaceId> =
                mesh.outgoing(v).filter(|&h| !mesh.is_boundary_halfedge(h)).map(|h| mesh.face(h)).collect();
            seen(mesh.position(v), &|f| faces.contains(&f))
        })
        .collect();
    let edges = mesh
        .edges()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&e| {
            let faces: Vec<FaceId> = [e.halfedge(0), e.halfedge(1)]
                .into_iter()
                .filter(|&h| !mesh.is_boundary_halfedge(h))
                .map(|h| mesh.face(h))
                .collect();
            let (a, b) = mesh.edge_vertices(e);
            let (pa, pb) = (mesh.position(a), mesh.position(b));
            [0.5, 0.25, 0.75].iter().any(|&s| seen(pa.lerp(pb, s), &|f| faces.contains(&f)))
        })
        .collect();
    let faces = mesh
        .faces()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&f| {
            let ring: Vec<DVec3> = mesh.face_vertices(f).map(|v| mesh.position(v)).collect();
            let centre = ring.iter().copied().sum::<DVec3>() / ring.len().max(1) as f64;
            seen(centre, &|g| g == f)
        })
        .collect();
    Visibility { vertices, edges, faces }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives;

    /// The cube [-1, 1]³, faces counter-clockwise seen from outside.
    fn cube() -> PolyMesh {
        let p = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64) * 2.0 - DVec3::ONE)
            .collect();
        let faces = [[0u32, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    /// The corners of the cube that face `eye`'s side: a corner is seen from a point outside
    /// the cube exactly when the eye lies beyond one of the three faces it is on (closed form
    /// for a convex solid seen from outside).
    fn expected_corner(p: DVec3, eye: DVec3) -> bool {
        (0..3).any(|k| p[k].signum() == eye[k].signum() && eye[k].abs() > p[k].abs())
    }

    #[test]
    fn a_cube_hides_its_far_corner_edges_and_faces() {
        let mesh = cube();
        let eye = DVec3::new(3.0, 2.5, 4.0);
        let seen = visibility_from(&mesh, eye);
        for v in mesh.vertices() {
            assert_eq!(seen.vertex(v), expected_corner(mesh.position(v), eye), "corner {v:?}");
        }
        // Seen from a generic direction off every axis: three faces, seven corners, nine edges.
        assert_eq!(seen.vertices.iter().filter(|&&s| s).count(), 7);
        assert_eq!(seen.faces.iter().filter(|&&s| s).count(), 3);
        assert_eq!(seen.edges.iter().filter(|&&s| s).count(), 9);
        for f in mesh.faces() {
            let normal = mesh.face_area_vector(f);
            let centre = mesh.face_vertices(f).map(|v| mesh.position(v)).sum::<DVec3>() / 4.0;
            assert_eq!(seen.face(f), normal.dot(eye - centre) > 0.0, "face {f:?}");
        }
    }

    #[test]
    fn the_answer_holds_under_a_similarity_and_for_an_open_sheet() {
        let mesh = cube();
        let eye = DVec3::new(-2.0, 3.0, 2.5);
        let reference = visibility_from(&mesh, eye);
        let (scale, shift) = (7.5e3, DVec3::new(1e4, -3e3, 42.0));
        let rotate = |p: DVec3| DVec3::new(p.y, -p.x, p.z);
        let mut moved = mesh.clone();
        for p in moved.positions_mut() {
            *p = rotate(*p) * scale + shift;
        }
        assert_eq!(visibility_from(&moved, rotate(eye) * scale + shift), reference);

        // One open quad hides nothing of itself, from either side.
        let quad = PolyMesh::from_polygons(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
            &[[0u32, 1, 2, 3]],
        )
        .unwrap();
        for eye in [DVec3::new(0.3, 0.2, 5.0), DVec3::new(0.3, 0.2, -5.0), DVec3::new(3.0, 3.0, 0.01)] {
            assert_eq!(visibility_from(&quad, eye), Visibility::all(&quad), "eye {eye}");
        }
    }

    #[test]
    fn a_sheet_in_front_hides_the_one_behind_and_nan_hides_nothing() {
        // Two parallel squares, one above the other; the eye above sees only the upper one.
        let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let positions = vec![
            p(0., 0., 0.),
            p(1., 0., 0.),
            p(1., 1., 0.),
            p(0., 1., 0.),
            p(-1., -1., 1.),
            p(2., -1., 1.),
            p(2., 2., 1.),
            p(-1., 2., 1.),
        ];
        let mesh = PolyMesh::from_polygons(positions, &[[0u32, 1, 2, 3], [4, 5, 6, 7]]).unwrap();
        let seen = visibility_from(&mesh, p(0.5, 0.5, 10.0));
        assert_eq!(seen.vertices, [false, false, false, false, true, true, true, true]);
        assert_eq!(seen.faces, [false, true]);
        assert!(mesh.edges().all(|e| seen.edge(e) == (mesh.edge_vertices(e).0.index() >= 4)));
        // From below, the other way round.
        let below = visibility_from(&mesh, p(0.5, 0.5, -10.0));
        assert_eq!(below.vertices, [true, true, true, true, true, true, true, true]);
        // The lower square hides the upper one's centre, not its corners or edges.
        assert_eq!(below.faces, [true, false]);
        assert!(below.edges.iter().all(|&s| s));
        assert_eq!(visibility_from(&mesh, p(f64::NAN, 0.0, 1.0)), Visibility::all(&mesh));
    }

    #[test]
    fn the_answer_does_not_depend_on_the_thread_count() {
        let mut mesh = primitives::uv_sphere(24, 12, 1.0).unwrap();
        for (i, p) in mesh.positions_mut().iter_mut().enumerate() {
            *p *= 1.0 + 0.2 * ((i * 7919 % 13) as f64 / 13.0);
        }
        let eye = DVec3::new(2.0, 1.5, 3.0);
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let many = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
        let a = one.install(|| visibility_from(&mesh, eye));
        let b = many.install(|| visibility_from(&mesh, eye));
        assert_eq!(a, b);
        let shown = a.vertices.iter().filter(|&&s| s).count();
        assert!(shown > 0 && shown < mesh.vertex_count(), "{shown} of {}", mesh.vertex_count());
    }
}
