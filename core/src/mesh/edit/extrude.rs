//! Extrusion: faces lifted along their normal with walls along their border, and open-boundary
//! edges pushed outward with a strip of new quads.
//!
//! Face extrusion is the lift of [`super::lift`] followed by a translation: in a region, every
//! vertex of a connected piece of the selection (copies and the vertices inside it) moves by
//! `distance` along the piece's area-weighted mean normal, as Blender's "extrude region" does;
//! individually, each face moves along its own normal. Weak where a piece curls round (a band
//! around a cylinder): its mean normal is short or zero, and the extrusion is refused with a
//! message suggesting individual faces.
//!
//! Boundary-edge extrusion copies the vertices of the selected boundary edges once each (a
//! boundary vertex lies on one boundary, so runs of selected edges share their copies) and joins
//! each edge to its copy with a quad. Copies move by `distance` outward in the tangent plane of
//! the face along each edge: perpendicular to the edge, away from the face, mitred at a corner
//! between two selected edges so both new edges stay `distance` away from the old ones (the
//! mitre is capped at [`MAX_MITRE`] times `distance` at very sharp corners).

use super::draft::{Draft, edge_mask, face_normal};
use super::lift::lift;
use super::provenance::{FaceOrigin, VertexOrigin};
use super::{Edited, FaceGrouping};
use crate::mesh::{EdgeId, FaceId, PolyMesh};
use crate::{DVec3, Error, Result};

/// The longest mitre at a corner, in multiples of the offset distance.
pub const MAX_MITRE: f64 = 4.0;

/// Extrudes faces by `distance` (negative: inward) along their normals, as one region or
/// individually; the lifted faces keep their identity ([`FaceOrigin::Same`]) and each
/// wall is [`FaceOrigin::SweptFrom`] the border edge it stands on.
pub fn extrude_faces(mesh: &PolyMesh, faces: &[FaceId], grouping: FaceGrouping, distance: f64) -> Result<Edited> {
    const OP: &str = "extrude faces";
    check_distance(OP, distance)?;
    let mut lift = lift(mesh, faces, grouping, OP)?;
    if let Some(f) = mesh.faces().find(|&f| lift.mask[f.index()] && face_normal(mesh, f).is_none()) {
        return Err(Error::Topology(format!("{OP}: face {} has no area, so no normal to extrude along", f.0)));
    }
    let mut area = vec![DVec3::ZERO; lift.region_count];
    let mut total = vec![0.0; lift.region_count];
    let mut first_face = vec![FaceId::INVALID; lift.region_count];
    for f in mesh.faces() {
        let r = lift.region_of_face[f.index()];
        if r != u32::MAX {
            let a = mesh.face_area_vector(f);
            area[r as usize] += a;
            total[r as usize] += a.length();
            if !first_face[r as usize].is_valid() {
                first_face[r as usize] = f;
            }
        }
    }
    let mut normal = Vec::with_capacity(lift.region_count);
    for r in 0..lift.region_count {
        let f = first_face[r];
        if area[r].length() <= 1e-6 * total[r] || total[r] == 0.0 {
            return Err(Error::Topology(format!(
                "{OP}: the selected faces around face {} face opposite ways (or have no area), so they have \
                 no common normal to extrude along; extrude them individually",
                f.0
            )));
        }
        normal.push(area[r].normalize());
    }
    for c in &lift.copies {
        lift.draft.positions[c.vertex as usize] += distance * normal[c.region as usize];
    }
    for &(v, r) in &lift.interior {
        lift.draft.positions[v as usize] += distance * normal[r as usize];
    }
    lift.draft.finish()
}

/// Extrudes edges of the open boundary by `distance` outward in the surface's tangent plane,
/// adding a quad per edge ([`FaceOrigin::SweptFrom`] it); the new outer edges are copies of the
/// old ones and the new vertices copies of theirs.
pub fn extrude_boundary_edges(mesh: &PolyMesh, edges: &[EdgeId], distance: f64) -> Result<Edited> {
    const OP: &str = "extrude edges";
    check_distance(OP, distance)?;
    let mask = edge_mask(OP, mesh, edges)?;
    let mut draft = Draft::new(mesh, OP);
    let mut copy = vec![u32::MAX; mesh.vertex_count()];
    let mut outward: Vec<Vec<DVec3>> = Vec::new();
    let mut boundary = Vec::new();
    for e in mesh.edges().filter(|e| mask[e.index()]) {
        let Some(h) = [e.halfedge(0), e.halfedge(1)].into_iter().find(|&h| mesh.is_boundary_halfedge(h)) else {
            let (a, b) = mesh.edge_vertices(e);
            return Err(Error::Topology(format!(
                "{OP}: edge {} (vertices {}-{}) has faces on both sides; only edges of an open boundary \
                 can be extruded (extrude faces instead)",
                e.0, a.0, b.0
            )));
        };
        let f = mesh.face(h.twin());
        let n = face_normal(mesh, f).ok_or_else(|| {
            Error::Topology(format!("{OP}: face {} next to edge {} has no area, so no outward direction", f.0, e.0))
        })?;
        let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
        let out = n.cross(mesh.position(b) - mesh.position(a)).normalize_or_zero();
        for v in [a, b] {
            if copy[v.index()] == u32::MAX {
                copy[v.index()] = draft.add_vertex(mesh.position(v), VertexOrigin::CopyOf(v));
                outward.push(Vec::new());
            }
            let k = copy[v.index()] as usize - mesh.vertex_count();
            outward[k].push(out);
        }
        boundary.push(h);
    }
    for (k, dirs) in outward.iter().enumerate() {
        let sum: DVec3 = dirs.iter().copied().sum();
        let dir = sum.normalize_or_zero();
        let cos = dirs[0].dot(dir);
        if dir == DVec3::ZERO || cos <= 0.0 {
            let v = draft.vertex_origin[mesh.vertex_count() + k].source().map_or(0, |v| v.0);
            return Err(Error::Topology(format!(
                "{OP}: the selected edges at vertex {v} fold back onto each other, so there is no outward \
                 direction there; extrude them separately"
            )));
        }
        draft.positions[mesh.vertex_count() + k] += distance * (1.0 / cos).min(MAX_MITRE) * dir;
    }
    for f in mesh.faces() {
        draft.keep_face(f);
    }
    for h in boundary {
        let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
        draft.push_face([a.0, b.0, copy[b.index()], copy[a.index()]], FaceOrigin::SweptFrom(h.edge()));
    }
    draft.finish()
}

fn check_distance(op: &str, distance: f64) -> Result<()> {
    if distance.is_finite() && distance != 0.0 {
        Ok(())
    } else {
        Err(Error::Input(format!(
            "{op}: the distance must be a finite non-zero number (negative extrudes inward), not {distance:?}"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::VertexId;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid, prism, torus};
    use crate::mesh::edit::provenance::{CarryRule, carry_edge_property};
    use crate::mesh::edit::{EdgeOrigin, VertexOrigin};

    fn top(m: &PolyMesh) -> FaceId {
        m.faces().find(|&f| m.face_area_vector(f).z > 0.5).unwrap()
    }

    #[test]
    fn extruding_the_top_of_a_cube_gives_ten_faces_and_twelve_vertices() {
        let cube = cube();
        let edited = extrude_faces(&cube, &[top(&cube)], FaceGrouping::Region, 0.5).unwrap();
        check(&cube, &edited);
        let m = &edited.mesh;
        assert_eq!(counts(m), (12, 20, 10));
        assert_eq!(m.euler_characteristic(), 2);
        assert!(m.is_closed());
        // The cap moved up by 0.5, the old top corners stayed.
        let cap = m.faces().find(|&f| edited.provenance.faces[f.index()] == FaceOrigin::Same(top(&cube))).unwrap();
        assert!(m.face_vertices(cap).all(|v| m.position(v).z == 1.5));
        assert_eq!(m.positions()[..8], cube.positions()[..]);
        // Signed volume grows by the extruded box (1 × 1 × 0.5).
        assert!((volume(m) - 1.5).abs() < 1e-12);
    }

    pub(crate) fn volume(m: &PolyMesh) -> f64 {
        m.triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| m.position(crate::VertexId(v)));
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn a_region_gets_walls_only_on_its_border() {
        let cube = cube();
        let (top, front) = (FaceId(1), FaceId(2)); // z = 1 and y = 0, sharing edge 4-5
        let edited = extrude_faces(&cube, &[top, front], FaceGrouping::Region, 0.25).unwrap();
        check(&cube, &edited);
        // Six border edges (the outline), so six walls; the shared edge moves with the region.
        assert_eq!(counts(&edited.mesh), (14, 24, 12));
        assert!(edited.mesh.is_closed());
        let walls = edited.provenance.faces.iter().filter(|o| matches!(o, FaceOrigin::SweptFrom(_))).count();
        assert_eq!(walls, 6);
        // Individually the two faces get four walls each, and the shared edge gets two.
        let edited = extrude_faces(&cube, &[top, front], FaceGrouping::Individual, 0.25).unwrap();
        check(&cube, &edited);
        assert_eq!(counts(&edited.mesh), (16, 28, 14));
        assert!(edited.mesh.is_closed());
    }

    #[test]
    fn regions_touching_at_a_vertex_get_a_copy_each() {
        // Faces (0,0) and (1,1) of a grid share only vertex 5.
        let g = grid(3);
        let edited = extrude_faces(&g, &[FaceId(0), FaceId(4)], FaceGrouping::Region, 1.0).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (16 + 8, 24 + 16, 9 + 8));
        assert_eq!(edited.mesh.euler_characteristic(), 1);
        let copies_of_5 =
            edited.provenance.vertices.iter().filter(|&&o| o == VertexOrigin::CopyOf(VertexId(5))).count();
        assert_eq!(copies_of_5, 2);
    }

    #[test]
    fn inside_vertices_of_a_region_move_with_it() {
        let g = grid(3);
        let all: Vec<FaceId> = g.faces().collect();
        let edited = extrude_faces(&g, &all, FaceGrouping::Region, -2.0).unwrap();
        check(&g, &edited);
        // 12 border vertices copied, 4 inside moved; 12 walls.
        assert_eq!(counts(&edited.mesh), (28, 48, 21));
        for v in [5u32, 6, 9, 10] {
            assert_eq!(edited.mesh.position(VertexId(v)).z, -2.0);
            assert_eq!(edited.provenance.vertices[v as usize], VertexOrigin::Same(VertexId(v)));
        }
    }

    #[test]
    fn extruded_edges_take_the_tension_of_the_edge_they_came_from() {
        let cube = cube();
        let tension: Vec<f64> = cube.edges().map(|e| 1.0 + e.0 as f64).collect();
        let by_ends = |m: &PolyMesh, a: DVec3, b: DVec3| {
            m.edges().find(|&e| {
                let (x, y) = m.edge_vertices(e);
                let (x, y) = (m.position(x), m.position(y));
                (x == a && y == b) || (x == b && y == a)
            })
        };
        let lift = DVec3::new(0.0, 0.0, 0.5);
        let edited = extrude_faces(&cube, &[top(&cube)], FaceGrouping::Region, 0.5).unwrap();
        let carried = carry_edge_property(&tension, &edited.provenance, &CarryRule::new_elements(0.0)).unwrap();
        let m = &edited.mesh;
        for e in cube.edges() {
            let (a, b) = cube.edge_vertices(e);
            let (pa, pb) = (cube.position(a), cube.position(b));
            // The edge stays where it was, and if it bordered the top face its copy is lifted.
            let stay = by_ends(m, pa, pb).expect("old edges stay");
            assert_eq!(carried[stay.index()], tension[e.index()]);
            if pa.z == 1.0 && pb.z == 1.0 {
                let copy = by_ends(m, pa + lift, pb + lift).expect("the cap has a copy of each top edge");
                assert_eq!(carried[copy.index()], tension[e.index()]);
            }
        }
        // The side edges are new: no tension.
        for e in m.edges() {
            let (a, b) = m.edge_vertices(e);
            if (m.position(a) - m.position(b)).z.abs() == 0.5 && m.position(a).z.min(m.position(b).z) == 1.0 {
                assert_eq!(carried[e.index()], 0.0);
                assert!(matches!(edited.provenance.edges[e.index()], EdgeOrigin::SweptFrom(_)));
            }
        }
    }

    #[test]
    fn boundary_edges_extrude_outward_in_the_plane() {
        let g = grid(3);
        // The three edges along y = 0.
        let edges: Vec<EdgeId> = g
            .edges()
            .filter(|&e| {
                let (a, b) = g.edge_vertices(e);
                g.position(a).y == 0.0 && g.position(b).y == 0.0
            })
            .collect();
        assert_eq!(edges.len(), 3);
        let edited = extrude_boundary_edges(&g, &edges, 0.5).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (20, 31, 12));
        assert_eq!(edited.mesh.euler_characteristic(), 1);
        for v in edited.mesh.vertices().skip(16) {
            let VertexOrigin::CopyOf(s) = edited.provenance.vertices[v.index()] else { panic!() };
            assert!((edited.mesh.position(v) - (g.position(s) - DVec3::new(0.0, 0.5, 0.0))).length() < 1e-15);
        }
        // The whole boundary loop: corners mitred so both new edges stay 0.5 out.
        let boundary: Vec<EdgeId> = g.edges().filter(|&e| g.is_boundary_edge(e)).collect();
        let edited = extrude_boundary_edges(&g, &boundary, 0.5).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (28, 48, 21));
        let (lo, hi) = edited.mesh.bounding_box().unwrap();
        assert!(
            (lo - DVec3::new(-0.5, -0.5, 0.0)).length() < 1e-12 && (hi - DVec3::new(3.5, 3.5, 0.0)).length() < 1e-12
        );
    }

    #[test]
    fn bad_extrusions_are_refused_with_a_message() {
        let (cube, t) = (cube(), torus());
        let band: Vec<FaceId> = (0..6).map(FaceId).collect(); // faces i = 0 around the tube
        let sides = [FaceId(2), FaceId(3), FaceId(4), FaceId(5)]; // their normals cancel
        let all: Vec<FaceId> = cube.faces().collect();
        let cases = [
            (extrude_faces(&cube, &[], FaceGrouping::Region, 1.0).err(), "nothing selected"),
            (extrude_faces(&cube, &[FaceId(6)], FaceGrouping::Region, 1.0).err(), "face 6 does not exist"),
            (extrude_faces(&cube, &[FaceId(0)], FaceGrouping::Region, f64::NAN).err(), "finite non-zero"),
            (extrude_faces(&cube, &[FaceId(0)], FaceGrouping::Region, 0.0).err(), "finite non-zero"),
            (extrude_faces(&cube, &all, FaceGrouping::Region, 1.0).err(), "close on themselves"),
            (extrude_faces(&cube, &sides, FaceGrouping::Region, 1.0).err(), "opposite ways"),
            (extrude_boundary_edges(&cube, &[EdgeId(0)], 1.0).err(), "faces on both sides"),
            (extrude_boundary_edges(&prism(4), &[], 1.0).err(), "nothing selected"),
        ];
        for (err, expected) in cases {
            let err = err.expect("refused").to_string();
            assert!(err.contains(expected) && !err.contains('\n'), "expected '{expected}' in: {err}");
        }
        // The band extrudes face by face.
        let edited = extrude_faces(&t, &band, FaceGrouping::Individual, 0.1).unwrap();
        check(&t, &edited);
        assert_eq!(counts(&edited.mesh), (48 + 24, 96 + 48, 48 + 24));
    }
}
