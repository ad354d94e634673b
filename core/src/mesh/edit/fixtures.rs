//! Fixture cages for the edit tests: a cube, an open grid, a prism with n-gon caps, a torus and
//! a mixed triangle/quad cage, each with every face counter-clockwise seen from outside.

use super::{EdgeOrigin, Edited, FaceOrigin, VertexOrigin};
use crate::mesh::primitives;
use crate::{DVec3, EdgeId, PolyMesh, VertexId};

/// Unit cube at [0, 1]³: 8 vertices, 12 edges, 6 quads.
pub fn cube() -> PolyMesh {
    let p = (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// An open `n` × `n` grid of unit quads in z = 0 (vertex `j (n + 1) + i` at (i, j)), looking up.
pub fn grid(n: u32) -> PolyMesh {
    let mut m = primitives::quad_grid(n, n, f64::from(n), f64::from(n)).unwrap();
    let half = f64::from(n) / 2.0;
    for p in m.positions_mut() {
        *p += DVec3::new(half, half, 0.0);
    }
    m
}

/// A prism with regular `n`-gon caps of circumradius 1 at z = 0 and z = 1.
pub fn prism(n: u32) -> PolyMesh {
    let mut p = Vec::new();
    for z in [0.0, 1.0] {
        for k in 0..n {
            let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
            p.push(DVec3::new(a.cos(), a.sin(), z));
        }
    }
    let mut faces: Vec<Vec<u32>> = vec![(0..n).rev().collect(), (n..2 * n).collect()];
    for k in 0..n {
        let k1 = (k + 1) % n;
        faces.push(vec![k, k1, k1 + n, k + n]);
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// A torus of 8 × 6 quads.
pub fn torus() -> PolyMesh {
    primitives::torus(8, 6, 2.0, 0.5).unwrap()
}

/// A house: the unit cube's walls and floor with a four-triangle pyramid roof (apex vertex 8).
pub fn house() -> PolyMesh {
    let mut p: Vec<DVec3> =
        (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    p.push(DVec3::new(0.5, 0.5, 1.6));
    let faces: Vec<Vec<u32>> = vec![
        vec![0, 2, 3, 1],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
        vec![4, 5, 8],
        vec![5, 7, 8],
        vec![7, 6, 8],
        vec![6, 4, 8],
    ];
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// Every fixture with its name.
pub fn all() -> Vec<(&'static str, PolyMesh)> {
    vec![("cube", cube()), ("grid", grid(3)), ("prism", prism(5)), ("torus", torus()), ("house", house())]
}

/// Vertex, edge and face counts.
pub fn counts(m: &PolyMesh) -> (usize, usize, usize) {
    (m.vertex_count(), m.edge_count(), m.face_count())
}

/// Validates an edit and checks every provenance claim against the old cage: sizes, vertices
/// on edges where they say, edges between the vertices their origin implies, face pieces made of
/// their old face's corners.
pub fn check(old: &PolyMesh, edited: &Edited) {
    let (m, p) = (&edited.mesh, &edited.provenance);
    m.validate().unwrap();
    assert_eq!((p.vertices.len(), p.edges.len(), p.faces.len()), counts(m));
    assert_eq!(p.old_counts, counts(old));
    let source = |v: VertexId| p.vertices[v.index()].source();
    for v in m.vertices() {
        match p.vertices[v.index()] {
            VertexOrigin::OnEdge { edge, t } => {
                assert!(t > 0.0 && t < 1.0, "{v:?} at {t}");
                let (a, b) = old.edge_vertices(edge);
                let expected = old.position(a).lerp(old.position(b), t);
                assert!((m.position(v) - expected).length() <= 1e-12 * (1.0 + expected.length()), "{v:?}");
            }
            o => assert!(o.source().unwrap().index() < old.vertex_count()),
        }
    }
    // An old vertex a new corner stands for: its source, or the ends of the edge it lies on.
    let stands_for = |v: VertexId| -> Vec<VertexId> {
        match p.vertices[v.index()] {
            VertexOrigin::OnEdge { edge, .. } => {
                let (a, b) = old.edge_vertices(edge);
                vec![a, b]
            }
            o => vec![o.source().unwrap()],
        }
    };
    for e in m.edges() {
        let (a, b) = m.edge_vertices(e);
        let merged = |v: VertexId| matches!(p.vertices[v.index()], VertexOrigin::Merged(_));
        let same_ends = |oe: EdgeId| {
            let (x, y) = old.edge_vertices(oe);
            let (sa, sb) = (source(a), source(b));
            (sa == Some(x) && sb == Some(y)) || (sa == Some(y) && sb == Some(x))
        };
        match p.edges[e.index()] {
            EdgeOrigin::Same(oe) | EdgeOrigin::CopyOf(oe) | EdgeOrigin::MirrorOf(oe) => {
                assert!(merged(a) || merged(b) || same_ends(oe), "{e:?} claims {:?}", p.edges[e.index()]);
            }
            EdgeOrigin::SplitFrom(oe) => {
                let on = |v: VertexId| matches!(p.vertices[v.index()], VertexOrigin::OnEdge { edge, .. } if edge == oe);
                let (x, y) = old.edge_vertices(oe);
                let end = |v: VertexId| source(v) == Some(x) || source(v) == Some(y);
                assert!((on(a) && end(b)) || (on(b) && end(a)), "{e:?} claims SplitFrom({oe:?})");
            }
            EdgeOrigin::Merged(oe) => assert!(oe.index() < old.edge_count()),
            EdgeOrigin::SweptFrom(v) => {
                let kinds = [a, b].map(|w| p.vertices[w.index()]);
                assert!(
                    kinds.contains(&VertexOrigin::Same(v)) && kinds.contains(&VertexOrigin::CopyOf(v)),
                    "{e:?} claims SweptFrom({v:?}) but joins {kinds:?}"
                );
            }
            EdgeOrigin::InFace(f) => {
                let corners: Vec<VertexId> = old.face_vertices(f).collect();
                for w in [a, b] {
                    assert!(stands_for(w).iter().all(|c| corners.contains(c)), "{e:?} claims InFace({f:?})");
                }
            }
            EdgeOrigin::New => {}
        }
    }
    for f in m.faces() {
        match p.faces[f.index()] {
            FaceOrigin::SplitFrom(of) => {
                let corners: Vec<VertexId> = old.face_vertices(of).collect();
                for v in m.face_vertices(f) {
                    assert!(stands_for(v).iter().all(|c| corners.contains(c)), "{f:?} claims SplitFrom({of:?})");
                }
            }
            FaceOrigin::MirrorOf(of) => {
                let mut want: Vec<VertexId> = old.face_vertices(of).collect();
                let mut have: Vec<VertexId> = m.face_vertices(f).map(|v| source(v).unwrap()).collect();
                want.sort();
                have.sort();
                assert_eq!(want, have, "{f:?} claims MirrorOf({of:?})");
            }
            FaceOrigin::SweptFrom(oe) => {
                let (x, y) = old.edge_vertices(oe);
                let sources: Vec<Option<VertexId>> = m.face_vertices(f).map(source).collect();
                assert!(sources.contains(&Some(x)) && sources.contains(&Some(y)), "{f:?} claims SweptFrom({oe:?})");
            }
            o => {
                let (FaceOrigin::Same(of) | FaceOrigin::Merged(of)) = o else {
                    assert_eq!(o, FaceOrigin::New);
                    continue;
                };
                assert!(of.index() < old.face_count());
            }
        }
    }
}
