//! Loop cut: a new edge loop across a ring of quads.
//!
//! The ring of an edge is walked from quad to quad across opposite edges, both ways, until it
//! closes on itself (a band round a cylinder or torus) or leaves the cage through the open
//! boundary (a strip across a grid). Every ring edge gets a vertex at the same fraction, measured
//! from the same side of the ring (the side of the starting edge's first vertex, carried across
//! each quad to the corner next to it), and every quad of the ring is cut in two between them.
//! A ring that runs into a triangle or an n-gon is refused naming that face, as is a ring that
//! crosses one quad twice (through both pairs of its opposite edges), since one loop cannot cut
//! it. Linear in the length of the ring plus one rebuild.

use super::Edited;
use super::draft::{Draft, check_fraction};
use super::provenance::{FaceOrigin, VertexOrigin};
use crate::mesh::{EdgeId, HalfedgeId, PolyMesh};
use crate::{Error, Result};

/// Inserts an edge loop across the ring of quads through `edge`, at `fraction` (strictly between
/// 0 and 1) along each ring edge from the side of `edge`'s first vertex.
pub fn loop_cut(mesh: &PolyMesh, edge: EdgeId, fraction: f64) -> Result<Edited> {
    const OP: &str = "loop cut";
    check_fraction(OP, fraction)?;
    if edge.index() >= mesh.edge_count() {
        return Err(Error::Input(format!(
            "{OP}: edge {} does not exist (the cage has {} edges, numbered from 0)",
            edge.0,
            mesh.edge_count()
        )));
    }
    // Ring halfedges, each oriented so that its first vertex is on the measured side, with the
    // fraction measured from that vertex.
    let start = edge.halfedge(0);
    let mut cut: Vec<(HalfedgeId, f64)> = vec![(start, fraction)];
    let mut entering: Vec<HalfedgeId> = Vec::new();
    let mut in_ring = vec![false; mesh.face_count()];
    let mut closed = false;
    for (first, t) in [(start, fraction), (start.twin(), 1.0 - fraction)] {
        let mut g = first;
        loop {
            let f = mesh.face(g);
            if !f.is_valid() {
                break;
            }
            let sides = mesh.face_valence(f);
            if sides != 4 {
                return Err(Error::Topology(format!(
                    "{OP}: the ring across edge {} runs into face {}, which has {sides} sides; a loop cut needs \
                     a ring of quads (cut up to it with split edges and connect vertices instead)",
                    edge.0, f.0
                )));
            }
            if in_ring[f.index()] {
                return Err(Error::Topology(format!(
                    "{OP}: the ring across edge {} crosses face {} twice, so one loop cannot cut it",
                    edge.0, f.0
                )));
            }
            in_ring[f.index()] = true;
            entering.push(g);
            let next = mesh.next(mesh.next(g)).twin();
            if next == start {
                closed = true;
                break;
            }
            cut.push((next, t));
            g = next;
        }
        if closed {
            break;
        }
    }

    let mut draft = Draft::new(mesh, OP);
    let mut middle = vec![u32::MAX; mesh.edge_count()];
    for &(g, t) in &cut {
        let (a, b) = (mesh.from_vertex(g), mesh.to_vertex(g));
        let e = g.edge();
        let t_first = if mesh.edge_vertices(e).0 == a { t } else { 1.0 - t };
        let at = mesh.position(a).lerp(mesh.position(b), t);
        middle[e.index()] = draft.add_vertex(at, VertexOrigin::OnEdge { edge: e, t: t_first });
    }
    let mut entered = vec![HalfedgeId::INVALID; mesh.face_count()];
    for &g in &entering {
        entered[mesh.face(g).index()] = g;
    }
    for f in mesh.faces() {
        let g = entered[f.index()];
        if !g.is_valid() {
            draft.keep_face(f);
            continue;
        }
        let opposite = mesh.next(mesh.next(g));
        let [a, b, c, d] = [g, mesh.next(g), opposite, mesh.prev(g)].map(|h| mesh.from_vertex(h).0);
        let (m1, m2) = (middle[g.edge().index()], middle[opposite.edge().index()]);
        draft.push_face([a, m1, m2, d], FaceOrigin::SplitFrom(f));
        draft.push_face([m1, b, c, m2], FaceOrigin::SplitFrom(f));
    }
    draft.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::VertexId;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid, house, prism, torus};
    use crate::mesh::edit::{EdgeOrigin, FaceOrigin, VertexOrigin};

    fn edge(m: &PolyMesh, a: u32, b: u32) -> EdgeId {
        m.find_halfedge(VertexId(a), VertexId(b)).unwrap().edge()
    }

    #[test]
    fn a_closed_ring_round_a_cube() {
        let cube = cube();
        let e = edge(&cube, 0, 4); // vertical: the ring runs round the four sides
        let edited = loop_cut(&cube, e, 0.25).unwrap();
        check(&cube, &edited);
        let m = &edited.mesh;
        assert_eq!(counts(m), (12, 20, 10));
        assert!(m.is_closed());
        // Every new vertex is a quarter of the way up from the side of vertex 0 (z = 0).
        for v in m.vertices().skip(8) {
            assert_eq!(m.position(v).z, 0.25);
        }
        let split = edited.provenance.faces.iter().filter(|o| matches!(o, FaceOrigin::SplitFrom(_))).count();
        assert_eq!(split, 8);
        let across = edited.provenance.edges.iter().filter(|o| matches!(o, EdgeOrigin::InFace(_))).count();
        assert_eq!(across, 4);
    }

    #[test]
    fn the_fraction_is_measured_from_the_first_vertex_of_the_edge() {
        let cube = cube();
        let e = edge(&cube, 4, 0);
        let (first, _) = cube.edge_vertices(e);
        let edited = loop_cut(&cube, e, 0.1).unwrap();
        let z = edited.mesh.position(VertexId(8)).z;
        assert!((z - if cube.position(first).z == 0.0 { 0.1 } else { 0.9 }).abs() < 1e-15);
        let VertexOrigin::OnEdge { t, .. } = edited.provenance.vertices[8] else { panic!() };
        assert!(t == 0.1 || t == 0.9);
    }

    #[test]
    fn open_rings_run_to_the_boundary_both_ways() {
        let g = grid(3);
        // An interior edge in the middle row: the ring runs up and down to both boundary rows.
        let e = edge(&g, 5, 6);
        let edited = loop_cut(&g, e, 0.5).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (20, 31, 12));
        assert_eq!(edited.mesh.euler_characteristic(), 1);
        let xs: Vec<f64> = edited.mesh.positions()[16..].iter().map(|p| p.x).collect();
        assert!(xs.iter().all(|&x| x == 1.5));
        let mut ys: Vec<f64> = edited.mesh.positions()[16..].iter().map(|p| p.y).collect();
        ys.sort_by(f64::total_cmp);
        assert_eq!(ys, vec![0.0, 1.0, 2.0, 3.0]);
    }

    #[test]
    fn rings_on_a_torus_and_a_prism_close() {
        let t = torus();
        for (a, b, new) in [(0, 1, 8), (0, 6, 6)] {
            let edited = loop_cut(&t, edge(&t, a, b), 0.5).unwrap();
            check(&t, &edited);
            assert_eq!(counts(&edited.mesh), (48 + new, 96 + 2 * new, 48 + new));
            assert_eq!(edited.mesh.euler_characteristic(), 0);
        }
        let p = prism(5);
        let edited = loop_cut(&p, edge(&p, 0, 5), 0.5).unwrap();
        check(&p, &edited);
        assert_eq!(counts(&edited.mesh), (15, 25, 12));
        // The house's walls form a ring below the roof.
        let h = house();
        let edited = loop_cut(&h, edge(&h, 0, 4), 0.5).unwrap();
        check(&h, &edited);
        assert_eq!(counts(&edited.mesh), (13, 24, 13));
        assert!(edited.mesh.positions()[9..].iter().all(|p| p.z == 0.5));
    }

    #[test]
    fn a_ring_into_a_triangle_or_an_ngon_names_the_face() {
        let (h, p) = (house(), prism(5));
        let before = h.polygons();
        let err = loop_cut(&h, edge(&h, 4, 5), 0.5).unwrap_err().to_string();
        assert!(err.contains("which has 3 sides") && err.contains("face "), "{err}");
        assert_eq!(h.polygons(), before);
        let err = loop_cut(&p, edge(&p, 0, 1), 0.5).unwrap_err().to_string();
        assert!(err.contains("which has 5 sides"), "{err}");
        for t in [0.0, 1.0, -0.5, f64::NAN] {
            assert!(loop_cut(&p, edge(&p, 0, 5), t).unwrap_err().to_string().contains("between 0 and 1"));
        }
        assert!(loop_cut(&p, EdgeId(99), 0.5).unwrap_err().to_string().contains("edge 99 does not exist"));
    }
}
